//! Geometry tests against closed forms (areas, volumes, counts) on the sample vehicle.

use super::body::Profile;
use super::*;
use crate::mesh::{PanelMesh, RegionKind};
use nalgebra::Vector3;

/// The sample vehicle config, read here without the config module (which depends on this one).
const SAMPLE_TOML: &str = include_str!("../../../configs/sample-hsv.toml");
use approx::assert_relative_eq;

/// The error message of `r`, failing the test (without dumping meshes) when it is `Ok`.
fn err_of<T>(r: Result<T, VehicleError>, case: &str) -> String {
    match r {
        Ok(_) => panic!("{case}: expected an error"),
        Err(e) => e.to_string(),
    }
}

fn sample() -> (GeometryConfig, LiftingSurfaceConfig) {
    let doc: toml::Table = toml::from_str(SAMPLE_TOML).expect("valid TOML");
    let g = doc["geometry"].clone().try_into().expect("[geometry]");
    let l = doc["lifting_surface"]
        .clone()
        .try_into()
        .expect("[lifting_surface]");
    (g, l)
}

/// Strips run upstream to downstream: centroid x strictly decreasing (x points forward).
fn assert_strips_downstream(mesh: &PanelMesh) {
    for (s, strip) in mesh.strips.iter().enumerate() {
        for w in strip.panels.windows(2) {
            let (a, b) = (mesh.panels[w[0]].centroid.x, mesh.panels[w[1]].centroid.x);
            assert!(
                b < a,
                "strip {s}: panel {} (x {b}) not aft of {} (x {a})",
                w[1],
                w[0]
            );
        }
    }
}

#[test]
fn sample_tables_parse_from_the_embedded_config() {
    // Other tables live in the same file; pick ours out of the whole document.
    let doc: toml::Table = toml::from_str(SAMPLE_TOML).expect("valid TOML");
    let g: GeometryConfig = doc["geometry"].clone().try_into().expect("[geometry]");
    let l: LiftingSurfaceConfig = doc["lifting_surface"]
        .clone()
        .try_into()
        .expect("[lifting_surface]");
    assert_eq!((g.clone(), l.clone()), sample());
    // Paper Table 1: L_f = L_a = 15.2 m.
    assert_eq!(g.forebody_length_m, 15.2);
    assert_eq!(g.length_m - g.forebody_length_m, 15.2);
    // B&D: tau_1U = 3 deg, tau_1L = 6.2 deg.
    assert_eq!(g.upper_forebody_angle_deg, 3.0);
    assert_eq!(g.lower_forebody_angle_deg, 6.2);
}

#[test]
fn body_is_closed_with_outward_normals_and_analytic_area_and_volume() {
    let (g, _) = sample();
    let body = body_mesh(&g).expect("body");
    let profile = body_profile(&g).expect("profile");
    assert!(body.is_closed(), "body mesh must be watertight");
    assert!(body.is_consistently_oriented());
    // Prismatic body: V = profile area x width, A = perimeter x width + 2 x profile area.
    let volume = profile.area_m2() * g.width_m;
    let area = profile.perimeter_m() * g.width_m + 2.0 * profile.area_m2();
    assert_relative_eq!(body.enclosed_volume_m3(), volume, max_relative = 1e-10);
    assert_relative_eq!(body.total_area_m2(), area, max_relative = 1e-10);
    assert!(
        body.enclosed_volume_m3() > 0.0,
        "outward normals give a positive volume"
    );
    // Profile by hand (B&D, metric): ramp end 14.3 tan 6.2 deg below the nose line, upper
    // surface at the tail 30.4 tan 3 deg above it.
    let z_r = 14.3 * 6.2f64.to_radians().tan();
    assert_relative_eq!(profile.ramp_end_m.y, z_r, epsilon = 1e-12);
    assert_relative_eq!(profile.cowl_lip_m.y, z_r + 1.07, epsilon = 1e-12);
    assert_relative_eq!(
        profile.tail_upper_m.y,
        -30.4 * 3f64.to_radians().tan(),
        epsilon = 1e-12
    );
    let base = profile.tail_lower_m.y - profile.tail_upper_m.y;
    assert!(
        base > 0.0 && base < 0.02,
        "B&D's aftbody nearly closes: base {base} m"
    );
}

#[test]
fn body_panel_count_and_region_tags() {
    let (g, _) = sample();
    let body = body_mesh(&g).expect("body");
    let prof = Profile::new(&g).expect("profile");
    let xs = prof.stations(g.panels_along_x);
    let n = xs.len() - 1;
    assert_eq!(n, g.panels_along_x);
    let n_engine = xs
        .iter()
        .filter(|&&s| s > prof.inlet + 1e-9 && s <= prof.exit + 1e-9)
        .count();
    let (ny, nz, ne) = (
        g.panels_across_width,
        g.panels_per_side,
        g.panels_engine_height,
    );
    // Upper + lower (ramp, cowl, nozzle) + sides + base + two caps.
    let expected = 2 * n * ny + 2 * (n * nz + n_engine * ne) + ny * nz + 2 * ny * ne;
    assert_eq!(body.panels.len(), expected);
    // Every panel has exactly one region; the regions partition the mesh.
    let count = |r| body.panels_in_region(r).count();
    assert_eq!(
        count(RegionKind::MainBody)
            + count(RegionKind::Propulsion)
            + count(RegionKind::Other)
            + count(RegionKind::LiftingSurface),
        body.panels.len()
    );
    assert_eq!(count(RegionKind::LiftingSurface), 0);
    let surf = |name: &str| body.surface_index(name).expect(name);
    let region_of = |name: &str| body.surfaces[usize::from(surf(name))].region;
    assert_eq!(region_of("inlet-ramp"), RegionKind::Propulsion);
    assert_eq!(region_of("nozzle"), RegionKind::Propulsion);
    assert_eq!(region_of("cowl"), RegionKind::MainBody);
    assert_eq!(region_of("inlet-face"), RegionKind::Other);
    assert_eq!(region_of("nozzle-exit"), RegionKind::Other);
    // Propulsion panels are exactly the ramp (nose to inlet) and the nozzle (exit to tail).
    for p in body.panels_in_region(RegionKind::Propulsion) {
        let x = -body.panels[p].centroid.x;
        assert!(x < prof.inlet || x > prof.exit);
    }
    // Outward normals by surface.
    for (name, check) in [
        (
            "upper-forebody",
            (|n: Vector3<f64>| n.z < -0.99) as fn(Vector3<f64>) -> bool,
        ),
        ("upper-aftbody", |n| n.z < -0.99),
        ("inlet-ramp", |n| n.z > 0.99 && n.x > 0.0),
        ("cowl", |n| n.z > 0.999),
        ("nozzle", |n| n.z > 0.9 && n.x < 0.0),
        ("left-side", |n| n.y < -0.999),
        ("right-side", |n| n.y > 0.999),
        ("base", |n| n.x < -0.999),
        ("inlet-face", |n| n.x > 0.999),
        ("nozzle-exit", |n| n.x < -0.999),
    ] {
        let s = surf(name);
        assert!(body.panels_in_surface(s).count() > 0, "{name} has panels");
        for p in body.panels_in_surface(s) {
            assert!(
                check(body.panels[p].normal),
                "{name}: {}",
                body.panels[p].normal
            );
        }
    }
}

#[test]
fn body_strips_run_nose_to_tail_and_cover_the_wetted_surfaces() {
    let (g, _) = sample();
    let body = body_mesh(&g).expect("body");
    assert!(body.is_structured());
    assert_strips_downstream(&body);
    let mut in_strip = vec![0u32; body.panels.len()];
    for s in &body.strips {
        for &p in &s.panels {
            in_strip[p] += 1;
        }
    }
    let name_of = |p: usize| {
        body.surfaces[usize::from(body.panels[p].surface)]
            .name
            .as_str()
    };
    for (p, &c) in in_strip.iter().enumerate() {
        let expect = u32::from(!matches!(name_of(p), "base" | "inlet-face" | "nozzle-exit"));
        assert_eq!(c, expect, "panel {p} on {} is in {c} strips", name_of(p));
    }
    // Upper strips start at the nose and end at the tail.
    let upper = body.surface_index("upper-forebody").expect("upper");
    let first = body
        .strips
        .iter()
        .find(|s| body.panels[s.panels[0]].surface == upper)
        .expect("an upper strip");
    let last = *first.panels.last().expect("non-empty");
    let (lo, _) = body.bounding_box();
    assert!(body.panels[last].centroid.x < lo.x + 0.6);
    assert_eq!(
        body.surfaces[usize::from(body.panels[last].surface)].name,
        "upper-aftbody"
    );
}

#[test]
fn lifting_surfaces_are_closed_mirror_images_with_analytic_volume() {
    let (_, l) = sample();
    let right = lifting_surface_mesh(&l, Side::Right).expect("right");
    let left = lifting_surface_mesh(&l, Side::Left).expect("left");
    for m in [&left, &right] {
        assert!(m.is_closed() && m.is_consistently_oriented());
        assert_strips_downstream(m);
        // Double wedge: section area t c / 2 = (t/c) c² / 2, c linear in span:
        // V = (t/c)/2 b (c_r² + c_r c_t + c_t²)/3.
        let (cr, ct) = (l.root_chord_m, l.tip_chord_m);
        let v = 0.5 * l.thickness_to_chord * l.span_m * (cr * cr + cr * ct + ct * ct) / 3.0;
        assert_relative_eq!(m.enclosed_volume_m3(), v, max_relative = 1e-10);
        // Planform: projected area of the upper surface = (c_r + c_t)/2 b.
        let upper = m.panels_in_region(RegionKind::LiftingSurface).filter(|&p| {
            m.surfaces[usize::from(m.panels[p].surface)]
                .name
                .ends_with("upper")
        });
        let projected: f64 = upper
            .map(|p| -m.panels[p].normal.z * m.panels[p].area_m2)
            .sum();
        assert_relative_eq!(projected, 0.5 * (cr + ct) * l.span_m, max_relative = 1e-10);
        assert_eq!(m.strips.len(), 2 * l.panels_spanwise);
    }
    // Mirror images: same vertices with y negated, same panels, mirrored normals.
    assert_eq!(left.vertices.len(), right.vertices.len());
    for (a, b) in left.vertices.iter().zip(&right.vertices) {
        assert_eq!((a.x, -a.y, a.z), (b.x, b.y, b.z));
    }
    assert_eq!(left.panels.len(), right.panels.len());
    for (a, b) in left.panels.iter().zip(&right.panels) {
        assert_relative_eq!(a.normal.x, b.normal.x, epsilon = 1e-12);
        assert_relative_eq!(a.normal.y, -b.normal.y, epsilon = 1e-12);
        assert_relative_eq!(a.normal.z, b.normal.z, epsilon = 1e-12);
        assert_relative_eq!(a.area_m2, b.area_m2, max_relative = 1e-12);
    }
    assert!(right.bounding_box().0.y >= l.root_y_m - 1e-12);
    assert!(left.bounding_box().1.y <= -l.root_y_m + 1e-12);
}

#[test]
fn sample_vehicle_assembles_with_surfaces_on_the_aftbody_sides() {
    let (g, l) = sample();
    let v = build_vehicle(&g, &l).expect("sample vehicle");
    assert_eq!(v.reference_point_m, Point3::new(-15.2, 0.0, 0.0));
    assert_eq!(v.length_m, 30.4);
    let (lo, hi) = v.body.bounding_box();
    assert_relative_eq!(lo.x, -30.4, epsilon = 1e-12);
    assert_relative_eq!(hi.x, 0.0, epsilon = 1e-12);
    assert_relative_eq!(hi.y - lo.y, 3.0, epsilon = 1e-12);
    // The root section lies inside the body's side profile (between the upper surface and
    // the nozzle), so the surface is attached to the side wall.
    let (g, l) = sample();
    let prof = Profile::new(&g).expect("profile");
    let root = v
        .right_surface
        .surface_index("right-surface-root")
        .expect("root");
    for p in v.right_surface.panels_in_surface(root) {
        for &i in v.right_surface.panels[p].vertex_indices() {
            let q = v.right_surface.vertices[i];
            let s = -q.x;
            assert!(s > 0.0 && s < g.length_m);
            assert!(
                q.z > prof.z_upper(s) && q.z < prof.z_lower(s),
                "root point {q}"
            );
            assert_relative_eq!(q.y, l.root_y_m, epsilon = 1e-12);
        }
    }
    assert_eq!(v.right_pivot_m, Point3::new(-25.0, 1.5, -0.9));
    assert_eq!(v.left_pivot_m, Point3::new(-25.0, -1.5, -0.9));
}

#[test]
fn bad_geometry_is_an_error_naming_the_key() {
    let (g, l) = sample();
    let cases: Vec<(GeometryConfig, &str)> = vec![
        (
            GeometryConfig {
                width_m: -1.0,
                ..g.clone()
            },
            "width_m",
        ),
        (
            GeometryConfig {
                inlet_aft_of_nose_m: 40.0,
                ..g.clone()
            },
            "inlet_aft_of_nose_m",
        ),
        (
            GeometryConfig {
                engine_length_m: 20.0,
                ..g.clone()
            },
            "engine_length_m",
        ),
        (
            GeometryConfig {
                nozzle_angle_deg: 30.0,
                ..g.clone()
            },
            "nozzle_angle_deg",
        ),
        (
            GeometryConfig {
                panels_along_x: 0,
                ..g.clone()
            },
            "panels_along_x",
        ),
        (
            GeometryConfig {
                length_m: f64::NAN,
                ..g.clone()
            },
            "length_m",
        ),
        (
            GeometryConfig {
                upper_forebody_angle_deg: -10.0,
                ..g.clone()
            },
            "upper_forebody_angle_deg",
        ),
    ];
    for (bad, key) in cases {
        let err = err_of(build_vehicle(&bad, &l), key);
        assert!(
            err.contains(key) && err.contains("[geometry]"),
            "{key}: {err}"
        );
    }
    let bad = LiftingSurfaceConfig {
        root_y_m: 1.0,
        ..l.clone()
    };
    let err = err_of(build_vehicle(&g, &bad), "root_y_m");
    assert!(
        err.contains("root_y_m") && err.contains("inside the body"),
        "{err}"
    );
    let bad = LiftingSurfaceConfig {
        panels_chordwise: 1,
        ..l
    };
    let err = err_of(lifting_surface_mesh(&bad, Side::Left), "panels_chordwise");
    assert!(err.contains("panels_chordwise"), "{err}");
}

#[test]
fn sharp_tail_collapses_the_base() {
    let (mut g, _) = sample();
    // Nozzle angle that closes the aftbody exactly at the tail.
    let prof = Profile::new(&g).expect("profile");
    let rise = prof.z_ramp_end - prof.z_upper(g.length_m);
    let tail_len = g.length_m - prof.exit;
    g.nozzle_angle_deg = (rise / tail_len).atan().to_degrees();
    let body = body_mesh(&g).expect("body");
    assert!(body.is_closed() && body.is_consistently_oriented());
    let base = body.surface_index("base").expect("base surface");
    assert!(body.panels_in_surface(base).count() <= g.panels_across_width * g.panels_per_side);
    let profile = body_profile(&g).expect("profile");
    assert_relative_eq!(
        body.enclosed_volume_m3(),
        profile.area_m2() * g.width_m,
        max_relative = 1e-9
    );
}
