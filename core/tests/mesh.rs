//! Panel mesh geometry, validation and modal deformation.
//!
//! Analytic references: surface area and volume of the cube, cylinder (2πRh + 2πR², πR²h) and
//! sphere (4πR², 4πR³/3), e.g. Zwillinger (ed.), *CRC Standard Mathematical Tables and
//! Formulae*, 32nd ed., §4.6 (solids); inscribed regular polygon area n R² sin(2π/n) / 2.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use hsv_core::mesh::{
    MeshError, ModeShapes, PanelMesh, PanelSpec, RegionKind, Strip, Surface, weld_vertices,
};
use nalgebra::{DMatrix, DVector, Point3, Rotation3, Vector3};
use proptest::prelude::*;

/// Unit cube [0,1]³ with outward quads on two surfaces (caps: main body, walls: propulsion) and
/// one strip.
fn unit_cube() -> PanelMesh {
    let v = |x: f64, y: f64, z: f64| Point3::new(x, y, z);
    let vertices = vec![
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(1., 1., 0.),
        v(0., 1., 0.),
        v(0., 0., 1.),
        v(1., 0., 1.),
        v(1., 1., 1.),
        v(0., 1., 1.),
    ];
    let panels = [
        PanelSpec::quad(0, 3, 2, 1, 0), // z = 0, normal -z
        PanelSpec::quad(4, 5, 6, 7, 0), // z = 1, normal +z
        PanelSpec::quad(0, 1, 5, 4, 1), // y = 0, normal -y
        PanelSpec::quad(3, 7, 6, 2, 1), // y = 1, normal +y
        PanelSpec::quad(0, 4, 7, 3, 1), // x = 0, normal -x
        PanelSpec::quad(1, 2, 6, 5, 1), // x = 1, normal +x
    ];
    PanelMesh::new(
        vertices,
        &panels,
        vec![Strip {
            panels: vec![5, 1, 4],
        }],
        vec![
            Surface::new("caps", RegionKind::MainBody),
            Surface::new("walls", RegionKind::Propulsion),
        ],
    )
    .expect("valid cube")
}

/// Closed cylinder of radius r, height h along z: n sectors, m rings, quads on the side and
/// triangle fans on the caps.
fn cylinder(r: f64, h: f64, n: usize, m: usize) -> PanelMesh {
    let mut vertices = Vec::new();
    for k in 0..=m {
        let z = h * k as f64 / m as f64;
        for i in 0..n {
            let t = 2.0 * PI * i as f64 / n as f64;
            vertices.push(Point3::new(r * t.cos(), r * t.sin(), z));
        }
    }
    let bottom = vertices.len();
    vertices.push(Point3::new(0.0, 0.0, 0.0));
    let top = vertices.len();
    vertices.push(Point3::new(0.0, 0.0, h));
    let id = |k: usize, i: usize| k * n + i % n;
    let mut panels = Vec::new();
    for k in 0..m {
        for i in 0..n {
            panels.push(PanelSpec::quad(
                id(k, i),
                id(k, i + 1),
                id(k + 1, i + 1),
                id(k + 1, i),
                0,
            ));
        }
    }
    for i in 0..n {
        panels.push(PanelSpec::triangle(bottom, id(0, i + 1), id(0, i), 0));
        panels.push(PanelSpec::triangle(top, id(m, i), id(m, i + 1), 0));
    }
    PanelMesh::new(
        vertices,
        &panels,
        Vec::new(),
        vec![Surface::new("cylinder", RegionKind::Other)],
    )
    .expect("valid cylinder")
}

/// UV sphere of radius r: n meridian sectors, m latitude bands, triangles at the poles.
fn sphere(r: f64, n: usize, m: usize) -> PanelMesh {
    let mut vertices = vec![Point3::new(0.0, 0.0, -r)];
    for k in 1..m {
        let phi = -PI / 2.0 + PI * k as f64 / m as f64;
        for i in 0..n {
            let t = 2.0 * PI * i as f64 / n as f64;
            vertices.push(Point3::new(
                r * phi.cos() * t.cos(),
                r * phi.cos() * t.sin(),
                r * phi.sin(),
            ));
        }
    }
    let north = vertices.len();
    vertices.push(Point3::new(0.0, 0.0, r));
    let id = |k: usize, i: usize| 1 + (k - 1) * n + i % n;
    let mut panels = Vec::new();
    for i in 0..n {
        panels.push(PanelSpec::triangle(0, id(1, i + 1), id(1, i), 0));
        panels.push(PanelSpec::triangle(
            north,
            id(m - 1, i),
            id(m - 1, i + 1),
            0,
        ));
    }
    for k in 1..m - 1 {
        for i in 0..n {
            panels.push(PanelSpec::quad(
                id(k, i),
                id(k, i + 1),
                id(k + 1, i + 1),
                id(k + 1, i),
                0,
            ));
        }
    }
    PanelMesh::new(
        vertices,
        &panels,
        Vec::new(),
        vec![Surface::new("sphere", RegionKind::Other)],
    )
    .expect("valid sphere")
}

#[test]
fn unit_cube_area_volume_and_closure() {
    let cube = unit_cube();
    assert_relative_eq!(cube.total_area_m2(), 6.0, epsilon = 1e-14);
    assert_relative_eq!(cube.enclosed_volume_m3(), 1.0, epsilon = 1e-14);
    assert!(cube.is_closed());
    assert!(cube.is_consistently_oriented());
    assert!(cube.is_structured());
    // Outward normals: each face normal points away from the centre.
    let centre = Point3::new(0.5, 0.5, 0.5);
    for p in &cube.panels {
        assert_relative_eq!(p.area_m2, 1.0, epsilon = 1e-14);
        let out = p.centroid - centre;
        assert_relative_eq!(p.normal, out * 2.0, epsilon = 1e-14);
    }
    assert_eq!(
        cube.bounding_box(),
        (Point3::new(0., 0., 0.), Point3::new(1., 1., 1.))
    );
    assert_eq!(
        cube.panels_in_region(RegionKind::MainBody)
            .collect::<Vec<_>>(),
        vec![0, 1]
    );
    assert_eq!(cube.panels_in_region(RegionKind::Propulsion).count(), 4);
    assert_eq!(cube.panels_in_region(RegionKind::Other).count(), 0);
}

#[test]
fn open_box_is_not_closed() {
    let cube = unit_cube();
    let specs: Vec<PanelSpec> = cube.panels[1..]
        .iter()
        .map(|p| PanelSpec {
            vertices: p.vertices,
            vertex_count: p.vertex_count,
            surface: p.surface,
        })
        .collect();
    let open = PanelMesh::new(
        cube.vertices.clone(),
        &specs,
        Vec::new(),
        cube.surfaces.clone(),
    )
    .expect("valid open box");
    assert!(!open.is_closed());
    assert!(open.is_consistently_oriented());
}

#[test]
fn reversed_normals_give_negative_volume() {
    let cube = unit_cube();
    let specs: Vec<PanelSpec> = cube
        .panels
        .iter()
        .map(|p| {
            let v = p.vertices;
            PanelSpec::quad(v[3], v[2], v[1], v[0], p.surface)
        })
        .collect();
    let inside_out = PanelMesh::new(
        cube.vertices.clone(),
        &specs,
        Vec::new(),
        cube.surfaces.clone(),
    )
    .expect("valid");
    assert!(inside_out.is_closed());
    assert_relative_eq!(inside_out.enclosed_volume_m3(), -1.0, epsilon = 1e-14);
    // One flipped face breaks the consistent orientation.
    let mut mixed = specs.clone();
    let v = cube.panels[0].vertices;
    mixed[0] = PanelSpec::quad(v[0], v[1], v[2], v[3], 0);
    let mixed =
        PanelMesh::new(cube.vertices.clone(), &mixed, Vec::new(), cube.surfaces).expect("valid");
    assert!(mixed.is_closed());
    assert!(!mixed.is_consistently_oriented());
}

#[test]
fn cylinder_matches_polygonal_and_converges_to_analytic() {
    let (r, h) = (0.7, 2.3);
    // Exact for the inscribed prism: side n (2 r sin(π/n)) h, caps 2 n r² sin(2π/n) / 2.
    let c = cylinder(r, h, 24, 5);
    let n = 24.0;
    let side = n * 2.0 * r * (PI / n).sin() * h;
    let cap = 0.5 * n * r * r * (2.0 * PI / n).sin();
    assert_relative_eq!(c.total_area_m2(), side + 2.0 * cap, max_relative = 1e-12);
    assert_relative_eq!(c.enclosed_volume_m3(), cap * h, max_relative = 1e-12);
    assert!(c.is_closed() && c.is_consistently_oriented());
    // Second-order convergence to 2πRh + 2πR² and πR²h.
    let area = 2.0 * PI * r * h + 2.0 * PI * r * r;
    let volume = PI * r * r * h;
    let mut last = (f64::INFINITY, f64::INFINITY);
    for n in [16, 32, 64, 128] {
        let c = cylinder(r, h, n, 4);
        let ea = (c.total_area_m2() - area).abs() / area;
        let ev = (c.enclosed_volume_m3() - volume).abs() / volume;
        if last.0.is_finite() {
            assert!(ea < last.0 / 3.5 && ev < last.1 / 3.5, "n = {n}: {ea} {ev}");
        }
        last = (ea, ev);
    }
    assert!(last.0 < 1e-3 && last.1 < 1e-3);
}

#[test]
fn sphere_converges_to_analytic_area_and_volume() {
    let r = 1.3;
    let area = 4.0 * PI * r * r;
    let volume = 4.0 / 3.0 * PI * r.powi(3);
    let mut last = (f64::INFINITY, f64::INFINITY);
    for n in [16, 32, 64, 128] {
        let s = sphere(r, n, n / 2);
        assert!(s.is_closed() && s.is_consistently_oriented());
        let ea = (s.total_area_m2() - area).abs() / area;
        let ev = (s.enclosed_volume_m3() - volume).abs() / volume;
        if last.0.is_finite() {
            assert!(ea < last.0 / 3.0 && ev < last.1 / 3.0, "n = {n}: {ea} {ev}");
        }
        last = (ea, ev);
        // Outward normals: along the radius at each centroid.
        for p in &s.panels {
            assert!(p.normal.dot(&p.centroid.coords) > 0.0);
        }
    }
    // Inscribed UV sphere at n = 128: area 5.0e-4 and volume 1.0e-3 low.
    assert!(last.0 < 1e-3 && last.1 < 1.5e-3);
}

#[test]
fn non_planar_quad_uses_the_diagonals() {
    let vertices = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.1),
        Point3::new(1.0, 1.0, 0.0),
        Point3::new(0.0, 1.0, 0.1),
    ];
    let mesh = PanelMesh::new(
        vertices.clone(),
        &[PanelSpec::quad(0, 1, 2, 3, 0)],
        Vec::new(),
        vec![Surface::new("warped", RegionKind::Other)],
    )
    .expect("valid");
    let d = (vertices[2] - vertices[0]).cross(&(vertices[3] - vertices[1]));
    let p = &mesh.panels[0];
    assert_relative_eq!(p.area_m2, d.norm() / 2.0, epsilon = 1e-15);
    assert_relative_eq!(p.normal, d.normalize(), epsilon = 1e-15);
    assert_relative_eq!(p.normal, Vector3::z(), epsilon = 1e-15);
    assert_relative_eq!(p.centroid, Point3::new(0.5, 0.5, 0.05), epsilon = 1e-15);
}

#[test]
fn construction_errors_are_reported() {
    let cube = unit_cube();
    let surf = || vec![Surface::new("s", RegionKind::Other)];
    let v = cube.vertices.clone();
    let tri = |a, b, c| PanelSpec::triangle(a, b, c, 0);
    assert!(matches!(
        PanelMesh::new(v.clone(), &[], Vec::new(), surf()),
        Err(MeshError::Empty)
    ));
    assert!(matches!(
        PanelMesh::new(v.clone(), &[tri(0, 1, 9)], Vec::new(), surf()),
        Err(MeshError::BadVertexIndex { vertex: 9, .. })
    ));
    // Collinear points: zero area.
    let line = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(2.0, 0.0, 0.0),
    ];
    assert!(matches!(
        PanelMesh::new(line, &[tri(0, 1, 2)], Vec::new(), surf()),
        Err(MeshError::DegeneratePanel { panel: 0, .. })
    ));
    assert!(matches!(
        PanelMesh::new(
            v.clone(),
            &[tri(0, 1, 2)],
            vec![Strip { panels: vec![3] }],
            surf()
        ),
        Err(MeshError::BadStripPanel { panel: 3, .. })
    ));
    assert!(matches!(
        PanelMesh::new(v.clone(), &[tri(0, 1, 2)], vec![Strip::default()], surf()),
        Err(MeshError::EmptyStrip { strip: 0 })
    ));
    assert!(matches!(
        PanelMesh::new(
            v.clone(),
            &[PanelSpec::triangle(0, 1, 2, 1)],
            Vec::new(),
            surf()
        ),
        Err(MeshError::BadSurfaceIndex { surface: 1, .. })
    ));
    let mut nan = v.clone();
    nan[2].y = f64::NAN;
    let err = PanelMesh::new(nan, &[tri(0, 1, 2)], Vec::new(), surf()).unwrap_err();
    assert!(matches!(err, MeshError::NonFiniteVertex { vertex: 2, .. }));
    assert!(err.to_string().contains("vertex 2"));
    let bad_count = PanelSpec {
        vertices: [0, 1, 2, 3],
        vertex_count: 5,
        surface: 0,
    };
    assert!(matches!(
        PanelMesh::new(v, &[bad_count], Vec::new(), surf()),
        Err(MeshError::BadVertexCount { count: 5, .. })
    ));
}

#[test]
fn from_triangles_builds_an_unstructured_mesh() {
    // Regular tetrahedron-like corner: volume 1/6, outward winding.
    let vertices = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
    ];
    let tris = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let mesh = PanelMesh::from_triangles(vertices, &tris, Surface::new("tet", RegionKind::Other))
        .expect("valid");
    assert!(!mesh.is_structured());
    assert!(mesh.is_closed() && mesh.is_consistently_oriented());
    assert_relative_eq!(mesh.enclosed_volume_m3(), 1.0 / 6.0, epsilon = 1e-15);
    assert_relative_eq!(
        mesh.total_area_m2(),
        1.5 + 3f64.sqrt() / 2.0,
        epsilon = 1e-14
    );
    assert!(mesh.panels.iter().all(|p| p.vertex_count == 3));
}

#[test]
fn merge_offsets_indices_surfaces_and_strips() {
    let mut a = unit_cube();
    let mut b = unit_cube();
    for v in &mut b.vertices {
        v.x += 3.0;
    }
    b.update_geometry();
    a.merge(&b);
    assert_eq!(a.vertices.len(), 16);
    assert_eq!(a.panels.len(), 12);
    assert_eq!(a.surfaces.len(), 4);
    assert_eq!(a.strips.len(), 2);
    assert_eq!(a.strips[1].panels, vec![11, 7, 10]);
    assert_eq!(a.panels[6].surface, 2);
    assert_eq!(a.panels[6].vertices, [8, 11, 10, 9]);
    assert!(a.is_closed());
    assert_relative_eq!(a.enclosed_volume_m3(), 2.0, epsilon = 1e-13);
    assert_relative_eq!(a.total_area_m2(), 12.0, epsilon = 1e-13);
    assert_eq!(a.panels_in_region(RegionKind::MainBody).count(), 4);
    assert_eq!(a.bounding_box().1, Point3::new(4.0, 1.0, 1.0));
}

#[test]
fn update_geometry_follows_moved_vertices() {
    let mut cube = unit_cube();
    for v in &mut cube.vertices {
        v.z *= 2.0;
    }
    cube.update_geometry();
    assert_relative_eq!(cube.enclosed_volume_m3(), 2.0, epsilon = 1e-14);
    assert_relative_eq!(cube.total_area_m2(), 10.0, epsilon = 1e-14);
    assert_relative_eq!(cube.panels[1].centroid.z, 2.0, epsilon = 1e-14);
}

#[test]
fn weld_merges_points_within_tolerance() {
    let pts = [
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(1e-9, -1e-9, 0.0),
        Point3::new(1.0 + 5e-10, 0.0, 0.0),
        Point3::new(0.5, 0.0, 0.0),
    ];
    let (unique, map) = weld_vertices(&pts, 1e-8);
    assert_eq!(unique.len(), 3);
    assert_eq!(map, vec![0, 1, 0, 1, 2]);
    let (unique, map) = weld_vertices(&pts, 0.0);
    assert_eq!(unique.len(), 5);
    assert_eq!(map, vec![0, 1, 2, 3, 4]);
}

/// Rigid-body mode shapes of `mesh`: translation along `t` and small rotation about `axis`
/// through the origin (δ = axis × r).
fn rigid_modes(mesh: &PanelMesh, t: Vector3<f64>, axis: Vector3<f64>) -> ModeShapes {
    let n = mesh.vertices.len();
    let mut phi = DMatrix::zeros(3 * n, 2);
    for (i, v) in mesh.vertices.iter().enumerate() {
        let rot = axis.cross(&v.coords);
        for a in 0..3 {
            phi[(3 * i + a, 0)] = t[a];
            phi[(3 * i + a, 1)] = rot[a];
        }
    }
    ModeShapes {
        vertex_displacement: phi,
    }
}

#[test]
fn translation_mode_moves_centroids_by_q_and_keeps_normals() {
    let base = sphere(1.0, 24, 12);
    let modes = rigid_modes(&base, Vector3::new(0.0, 1.0, 0.0), Vector3::z());
    assert_eq!(modes.n_modes(), 2);
    modes.check(&base).expect("sizes fit");
    let mut out = PanelMesh::default();
    let q = DVector::from_vec(vec![0.37, 0.0]);
    modes.deform(&base, &q, &mut out);
    for (a, b) in base.panels.iter().zip(&out.panels) {
        assert_relative_eq!(
            b.centroid - a.centroid,
            Vector3::new(0.0, 0.37, 0.0),
            epsilon = 1e-12
        );
        assert_relative_eq!(b.normal, a.normal, epsilon = 1e-12);
        assert_relative_eq!(b.area_m2, a.area_m2, max_relative = 1e-12);
    }
    // Deforming again reuses `out` (same topology) and starts from the base, not from `out`.
    modes.deform(&base, &q, &mut out);
    assert_relative_eq!(
        out.panels[0].centroid - base.panels[0].centroid,
        Vector3::new(0.0, 0.37, 0.0),
        epsilon = 1e-12
    );
    // Velocities: Φ q̇ averaged over each panel's vertices.
    let mut vel = vec![Vector3::zeros(); base.panels.len()];
    modes.panel_velocities(&base, &DVector::from_vec(vec![2.0, 0.0]), &mut vel);
    for v in &vel {
        assert_relative_eq!(*v, Vector3::new(0.0, 2.0, 0.0), epsilon = 1e-12);
    }
}

#[test]
fn rotation_mode_rotates_normals() {
    let base = unit_cube();
    let axis = Vector3::new(0.0, 0.0, 1.0);
    let modes = rigid_modes(&base, Vector3::zeros(), axis);
    let mut out = PanelMesh::default();
    // Linear mode: first-order rotation, dn/dq = axis × n.
    let q = 1e-6;
    modes.deform(&base, &DVector::from_vec(vec![0.0, q]), &mut out);
    for (a, b) in base.panels.iter().zip(&out.panels) {
        let rate = (b.normal - a.normal) / q;
        assert_relative_eq!(rate, axis.cross(&a.normal), epsilon = 1e-5);
    }
    // Finite amplitude: the +x face normal turns by atan(q) about z (a linear rotation mode
    // shears the face, which stays planar).
    let q = 0.2;
    modes.deform(&base, &DVector::from_vec(vec![0.0, q]), &mut out);
    let expect = Rotation3::from_axis_angle(&Vector3::z_axis(), q.atan()) * Vector3::x();
    assert_relative_eq!(out.panels[5].normal, expect, epsilon = 1e-12);
    // Panel velocity of a rotation mode: ω × r at the vertices' mean.
    let mut vel = vec![Vector3::zeros(); base.panels.len()];
    modes.panel_velocities(&base, &DVector::from_vec(vec![0.0, 3.0]), &mut vel);
    for (p, v) in base.panels.iter().zip(&vel) {
        let mean = p
            .vertex_indices()
            .iter()
            .map(|&i| base.vertices[i].coords)
            .sum::<Vector3<f64>>()
            / 4.0;
        assert_relative_eq!(*v, (axis * 3.0).cross(&mean), epsilon = 1e-12);
    }
}

#[test]
fn mode_shape_size_mismatch_is_reported() {
    let base = unit_cube();
    let modes = ModeShapes {
        vertex_displacement: DMatrix::zeros(3 * 7, 1),
    };
    let err = modes.check(&base).unwrap_err();
    assert!(matches!(
        err,
        MeshError::ModeShapeSize {
            rows: 21,
            n_vertices: 8
        }
    ));
}

proptest! {
    /// Rigid motions preserve area, volume and closure; normals rotate with the body.
    #[test]
    fn rigid_motion_preserves_area_and_volume(
        ax in -3.0f64..3.0, ay in -3.0f64..3.0, az in -3.0f64..3.0,
        tx in -10.0f64..10.0, ty in -10.0f64..10.0, tz in -10.0f64..10.0,
    ) {
        let base = cylinder(0.5, 1.5, 12, 3);
        let rot = Rotation3::new(Vector3::new(ax, ay, az));
        let mut moved = base.clone();
        for v in &mut moved.vertices {
            *v = rot * *v + Vector3::new(tx, ty, tz);
        }
        moved.update_geometry();
        prop_assert!(moved.is_closed());
        prop_assert!((moved.total_area_m2() - base.total_area_m2()).abs() < 1e-10);
        prop_assert!((moved.enclosed_volume_m3() - base.enclosed_volume_m3()).abs() < 1e-10);
        for (a, b) in base.panels.iter().zip(&moved.panels) {
            prop_assert!((rot * a.normal - b.normal).norm() < 1e-10);
        }
    }
}
