//! Validation of `newtonian-scalar` and `newtonian-vector` against closed-form Newtonian results.
//!
//! References:
//! - Anderson, J. D., Hypersonic and High-Temperature Gas Dynamics, 2nd ed., AIAA 2006, ch. 3:
//!   modified Newtonian C_p = C_p,max sin²θ (eqs. 3.15-3.16), flat plate at α
//!   C_N = C_p,max sin²α, C_L = C_N cos α, C_D = C_N sin α (the Newtonian flat-plate results with
//!   2 replaced by C_p,max), and C_p,max → 1.839 for γ = 1.4 as M∞ → ∞.
//! - NACA Report 1135 (Ames Research Staff, 1953), eq. 100 (Rayleigh pitot formula) and its
//!   normal-shock table: p02/p1 = 5.640 at M1 = 2, γ = 1.4 (same value in Anderson, Modern
//!   Compressible Flow, table A.2).
//! - Sharp cone and wedge at zero incidence: every face sees the same inclination, so
//!   C_D (base / frontal area) = C_p,max sin²δ — closed form of the same law.

use approx::assert_relative_eq;
use hsv_core::aero::{
    AeroModel, AeroSolution, Coefficients, PanelMotion, ReferenceValues, integrate_pressure,
};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::{PerfectGas, newtonian_cp_max};
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Surface};
use hsv_model_newtonian::{Form, Newtonian, Settings};
use nalgebra::{Point3, Vector3};

const GAMMA: f64 = 1.4;
const CHORD_M: f64 = 2.0;
const SPAN_M: f64 = 1.0;

/// A wedge of half-angle `delta` (0: a flat plate) with its leading edge along y at
/// x = `leading_edge_x`, chord `CHORD_M` aft, `n` panels per face. Surface 0 is the lower face
/// (normal (sin δ, 0, cos δ)), surface 1 the upper face (normal (sin δ, 0, -cos δ)).
fn wedge(delta: f64, n: usize, leading_edge_x: f64) -> PanelMesh {
    let slope = delta.tan();
    let mut vertices = Vec::new();
    for side in [1.0, -1.0] {
        for y in [0.0, SPAN_M] {
            for i in 0..=n {
                let s = CHORD_M * i as f64 / n as f64;
                vertices.push(Point3::new(leading_edge_x - s, y, side * slope * s));
            }
        }
    }
    let row = n + 1;
    let index = |face: usize, far: usize, i: usize| face * 2 * row + far * row + i;
    let mut panels = Vec::new();
    for i in 0..n {
        panels.push(PanelSpec::quad(
            index(0, 0, i),
            index(0, 1, i),
            index(0, 1, i + 1),
            index(0, 0, i + 1),
            0,
        ));
    }
    for i in 0..n {
        panels.push(PanelSpec::quad(
            index(1, 0, i),
            index(1, 0, i + 1),
            index(1, 1, i + 1),
            index(1, 1, i),
            1,
        ));
    }
    let surfaces = vec![
        Surface::new("lower", RegionKind::LiftingSurface),
        Surface::new("upper", RegionKind::LiftingSurface),
    ];
    let mesh = PanelMesh::new(vertices, &panels, Vec::new(), surfaces).unwrap();
    for panel in &mesh.panels {
        let side = if panel.surface == 0 { 1.0 } else { -1.0 };
        let expected = Vector3::new(delta.sin(), 0.0, side * delta.cos());
        assert_relative_eq!(panel.normal, expected, epsilon = 1e-12);
    }
    mesh
}

/// A sharp cone pointing forward (apex at the origin, base at x = -length) of half-angle
/// `delta`, as `n` triangles; returns the mesh and the base radius.
fn cone(delta: f64, length: f64, n: usize) -> (PanelMesh, f64) {
    let radius = length * delta.tan();
    let mut vertices = vec![Point3::origin()];
    for k in 0..n {
        let phi = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        vertices.push(Point3::new(-length, radius * phi.cos(), radius * phi.sin()));
    }
    let triangles: Vec<[usize; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
    let mesh = PanelMesh::from_triangles(
        vertices,
        &triangles,
        Surface::new("cone", RegionKind::MainBody),
    )
    .unwrap();
    for panel in &mesh.panels {
        let radial = Vector3::new(0.0, panel.centroid.y, panel.centroid.z);
        assert!(panel.normal.x > 0.0 && panel.normal.dot(&radial) > 0.0);
    }
    (mesh, radius)
}

/// One panel facing straight forward (normal +x).
fn forward_facing_panel() -> PanelMesh {
    let vertices = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(0.0, 1.0, 1.0),
        Point3::new(0.0, 0.0, 1.0),
    ];
    let surfaces = vec![Surface::new("face", RegionKind::MainBody)];
    let mesh = PanelMesh::new(
        vertices,
        &[PanelSpec::quad(0, 1, 2, 3, 0)],
        Vec::new(),
        surfaces,
    )
    .unwrap();
    assert_relative_eq!(mesh.panels[0].normal, Vector3::x(), epsilon = 1e-14);
    mesh
}

fn freestream(mach: f64) -> Freestream {
    Freestream::standard(mach, 26_000.0, PerfectGas::AIR).unwrap()
}

fn model(form: Form) -> Newtonian {
    Newtonian::new(form, Settings::default())
}

fn evaluate(
    form: Form,
    mesh: &PanelMesh,
    flight: &FlightCondition,
    motion: &PanelMotion<'_>,
) -> AeroSolution {
    let mut out = AeroSolution::default();
    model(form)
        .evaluate(mesh, flight, motion, &mut out)
        .unwrap();
    out
}

fn coefficients(
    mesh: &PanelMesh,
    out: &AeroSolution,
    flight: &FlightCondition,
    area_m2: f64,
) -> Coefficients {
    let fs = &flight.freestream;
    let loads = integrate_pressure(
        mesh,
        &out.pressure_pa,
        fs.pressure_pa,
        &Point3::origin(),
        |_| true,
    );
    let reference = ReferenceValues {
        area_m2,
        chord_m: CHORD_M,
        span_m: SPAN_M,
        moment_point_m: [0.0; 3],
    };
    Coefficients::from_loads(&loads, flight, &reference)
}

/// Flat plate at α (Anderson ch. 3): C_N = C_p,max sin²α, C_L = C_p,max sin²α cos α,
/// C_D = C_p,max sin³α; leeward side shadowed at p∞. Same law, so round-off tolerance (1e-10).
#[test]
fn flat_plate_coefficients_match_anderson() {
    let n = 4;
    let mesh = wedge(0.0, n, 0.0);
    for form in [Form::Scalar, Form::Vector] {
        for mach in [5.0_f64, 8.0, 15.0] {
            let fs = freestream(mach);
            let cp_max = newtonian_cp_max(mach, GAMMA).unwrap();
            for alpha_deg in [2.0_f64, 10.0, 30.0, 60.0] {
                let alpha = alpha_deg.to_radians();
                let flight = FlightCondition::steady(fs, alpha, 0.0);
                let out = evaluate(form, &mesh, &flight, &PanelMotion::default());
                let c = coefficients(&mesh, &out, &flight, CHORD_M * SPAN_M);
                let (s, co) = alpha.sin_cos();
                assert_relative_eq!(c.cl, cp_max * s * s * co, max_relative = 1e-10);
                assert_relative_eq!(c.cd, cp_max * s.powi(3), max_relative = 1e-10);
                assert_relative_eq!(c.cl * co + c.cd * s, cp_max * s * s, max_relative = 1e-10);
                assert_eq!(out.diagnostics.shadowed_panels, n);
                for (i, panel) in mesh.panels.iter().enumerate() {
                    if panel.surface == 1 {
                        assert_eq!(out.pressure_pa[i], fs.pressure_pa);
                        assert_eq!(out.edge[i].mach, fs.mach);
                        assert_eq!(out.edge[i].temperature_k, fs.temperature_k);
                    }
                }
            }
        }
    }
}

/// Sharp cone at α = 0: C_D on the base area = C_p,max sin²δ (closed form). The faceted cone of
/// n triangles is an inscribed pyramid: facet inclination tan θ_f = tan δ cos(π/n), frontal area
/// (n/2) R² sin(2π/n); the model must match that to round-off and the smooth cone to O((π/n)²)
/// (tolerance 1e-3 at n = 256).
#[test]
fn sharp_cone_drag_is_cp_max_sin_squared_delta() {
    let n = 256;
    let fs = freestream(8.0);
    let flight = FlightCondition::steady(fs, 0.0, 0.0);
    let cp_max = newtonian_cp_max(fs.mach, GAMMA).unwrap();
    for delta_deg in [5.0_f64, 10.0, 20.0] {
        let delta = delta_deg.to_radians();
        let (mesh, radius) = cone(delta, 3.0, n);
        let base = std::f64::consts::PI * radius * radius;
        for form in [Form::Scalar, Form::Vector] {
            let out = evaluate(form, &mesh, &flight, &PanelMotion::default());
            assert_eq!(out.diagnostics.shadowed_panels, 0);
            let c = coefficients(&mesh, &out, &flight, base);
            let step = std::f64::consts::PI / n as f64;
            let facet = (delta.tan() * step.cos()).atan();
            let frontal = 0.5 * n as f64 * radius * radius * (2.0 * step).sin();
            assert_relative_eq!(
                c.cd,
                cp_max * facet.sin().powi(2) * frontal / base,
                max_relative = 1e-10
            );
            assert_relative_eq!(c.cd, cp_max * delta.sin().powi(2), max_relative = 1e-3);
            assert!(c.cl.abs() < 1e-12 && c.cy.abs() < 1e-12);
        }
    }
}

/// Wedge of half-angle δ at α: the faces are inclined δ + α (lower) and δ - α (upper), so per
/// unit planform area C_L = [C_p,l cos(δ+α) - C_p,u cos(δ-α)]/cos δ and
/// C_D = [C_p,l sin(δ+α) + C_p,u sin(δ-α)]/cos δ with C_p = C_p,max sin²(inclination), and
/// C_p,u = 0 once α > δ (shadowed). At α = 0: C_D = 2 C_p,max sin²δ tan δ. Round-off tolerance.
#[test]
fn wedge_faces_follow_their_inclination() {
    let n = 3;
    let delta = 10_f64.to_radians();
    let mesh = wedge(delta, n, 0.0);
    let fs = freestream(7.0);
    let cp_max = newtonian_cp_max(fs.mach, GAMMA).unwrap();
    for alpha_deg in [0.0_f64, 4.0, 15.0] {
        let alpha = alpha_deg.to_radians();
        let flight = FlightCondition::steady(fs, alpha, 0.0);
        let out = evaluate(Form::Scalar, &mesh, &flight, &PanelMotion::default());
        let c = coefficients(&mesh, &out, &flight, CHORD_M * SPAN_M);
        let cp_l = cp_max * (delta + alpha).sin().powi(2);
        let cp_u = if alpha < delta {
            cp_max * (delta - alpha).sin().powi(2)
        } else {
            0.0
        };
        let cl = (cp_l * (delta + alpha).cos() - cp_u * (delta - alpha).cos()) / delta.cos();
        let cd = (cp_l * (delta + alpha).sin() + cp_u * (delta - alpha).sin()) / delta.cos();
        assert_relative_eq!(c.cl, cl, epsilon = 1e-12, max_relative = 1e-10);
        assert_relative_eq!(c.cd, cd, max_relative = 1e-10);
        assert_eq!(
            out.diagnostics.shadowed_panels,
            if alpha < delta { 0 } else { n }
        );
        if alpha == 0.0 {
            assert_relative_eq!(
                c.cd,
                2.0 * cp_max * delta.sin().powi(2) * delta.tan(),
                max_relative = 1e-10
            );
        }
    }
}

/// C_p,max → (4/(γ+1)) [(γ+1)²/(4γ)]^(γ/(γ-1)) = 1.8394 as M → ∞, "1.839 for γ = 1.4" (Anderson
/// ch. 3): a forward-facing panel at M = 1000 gives it within 5e-4 of 1.839 (1e-6 of the closed
/// form). At M = 2 its pressure is the pitot pressure of NACA 1135's table, p02/p1 = 5.640
/// (4 figures: 1e-3 relative). Its edge state is stagnation: M_e = 0, T_e = T0.
#[test]
fn stagnation_pressure_is_the_rayleigh_pitot_value() {
    let mesh = forward_facing_panel();
    for form in [Form::Scalar, Form::Vector] {
        let fs = freestream(1000.0);
        let flight = FlightCondition::steady(fs, 0.0, 0.0);
        let out = evaluate(form, &mesh, &flight, &PanelMotion::default());
        let cp = (out.pressure_pa[0] - fs.pressure_pa) / fs.dynamic_pressure_pa;
        let limit = 4.0 / (GAMMA + 1.0)
            * ((GAMMA + 1.0).powi(2) / (4.0 * GAMMA)).powf(GAMMA / (GAMMA - 1.0));
        assert_relative_eq!(cp, limit, max_relative = 1e-6);
        assert!((cp - 1.839).abs() < 5e-4, "{cp}");

        let fs = freestream(2.0);
        let flight = FlightCondition::steady(fs, 0.0, 0.0);
        let out = evaluate(form, &mesh, &flight, &PanelMotion::default());
        assert_relative_eq!(
            out.pressure_pa[0] / fs.pressure_pa,
            5.640,
            max_relative = 1e-3
        );
        let edge = out.edge[0];
        assert!(edge.mach.abs() < 1e-6, "{}", edge.mach);
        assert_relative_eq!(
            edge.temperature_k,
            fs.total_temperature_k(),
            max_relative = 1e-10
        );
        assert_eq!(out.diagnostics.shadowed_panels, 0);
    }
}

/// Windward edge state: isentropic from the normal-shock total state, so T0 is conserved
/// (cp T + V²/2 = cp T0) and p02/p = (1 + (γ-1)/2 M_e²)^(γ/(γ-1)) (NACA 1135 eqs. 43-44).
#[test]
fn windward_edge_state_expands_from_the_pitot_state() {
    let fs = freestream(6.0);
    let (mesh, _) = cone(12_f64.to_radians(), 3.0, 32);
    let flight = FlightCondition::steady(fs, 8_f64.to_radians(), 0.0);
    let out = evaluate(Form::Scalar, &mesh, &flight, &PanelMotion::default());
    let gas = fs.gas;
    let p02 = fs.pressure_pa
        * (1.0 + newtonian_cp_max(fs.mach, GAMMA).unwrap() * 0.5 * GAMMA * fs.mach * fs.mach);
    for (edge, &p) in out.edge.iter().zip(&out.pressure_pa) {
        if p == fs.pressure_pa {
            continue;
        }
        let enthalpy = gas.cp() * edge.temperature_k + 0.5 * edge.velocity_m_s.powi(2);
        assert_relative_eq!(
            enthalpy,
            gas.cp() * fs.total_temperature_k(),
            max_relative = 1e-12
        );
        let ratio = (1.0 + 0.5 * (GAMMA - 1.0) * edge.mach.powi(2)).powf(GAMMA / (GAMMA - 1.0));
        assert_relative_eq!(ratio, p02 / p, max_relative = 1e-10);
        assert_relative_eq!(
            edge.density_kg_m3,
            p / (gas.gas_constant_j_kg_k * edge.temperature_k),
            max_relative = 1e-12
        );
    }
}

/// Without rotation or elastic motion every panel's velocity is the vehicle's, so the vector form
/// must reproduce the scalar form (round-off).
#[test]
fn vector_equals_scalar_without_motion() {
    let (mesh, _) = cone(10_f64.to_radians(), 3.0, 48);
    let flight = FlightCondition::steady(freestream(6.0), 15_f64.to_radians(), 2_f64.to_radians());
    let scalar = evaluate(Form::Scalar, &mesh, &flight, &PanelMotion::default());
    let vector = evaluate(Form::Vector, &mesh, &flight, &PanelMotion::default());
    assert_eq!(scalar.diagnostics, vector.diagnostics);
    assert!(scalar.diagnostics.shadowed_panels > 0);
    for (s, v) in scalar.edge.iter().zip(&vector.edge) {
        assert_relative_eq!(s.pressure_pa, v.pressure_pa, max_relative = 1e-12);
        assert_relative_eq!(s.mach, v.mach, epsilon = 1e-9, max_relative = 1e-9);
        assert_relative_eq!(s.temperature_k, v.temperature_k, max_relative = 1e-12);
    }
}

/// Pitch rate q about the plate centre: each panel moves at V_p = V + ω × r, so the vector form
/// gives p = p∞ + ½ ρ∞ (n·V_p)² C_p,max(|V_p|/a∞), lower pressure ahead of the centre and higher
/// behind it, hence a nose-down (damping) moment; the scalar form ignores q. An elastic velocity
/// adds to V_p the same way. Round-off tolerance.
#[test]
fn pitch_rate_and_elastic_motion_change_windward_pressures_as_the_vector_law_says() {
    let n = 8;
    let mesh = wedge(0.0, n, 0.5 * CHORD_M);
    let fs = freestream(8.0);
    let steady = FlightCondition::steady(fs, 10_f64.to_radians(), 0.0);
    let mut pitching = steady;
    pitching.angular_velocity_rad_s = Vector3::new(0.0, 20.0, 0.0);
    let mut elastic = vec![Vector3::zeros(); mesh.panels.len()];
    elastic[2] = Vector3::new(0.0, 0.0, 15.0);
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&elastic),
    };
    let base = evaluate(Form::Vector, &mesh, &steady, &PanelMotion::default());
    let moving = evaluate(Form::Vector, &mesh, &pitching, &motion);
    let scalar = evaluate(Form::Scalar, &mesh, &pitching, &motion);
    assert_eq!(
        scalar.pressure_pa,
        evaluate(Form::Scalar, &mesh, &steady, &PanelMotion::default()).pressure_pa
    );
    for (i, panel) in mesh.panels.iter().enumerate() {
        let r = panel.centroid - pitching.rotation_center_m;
        let v =
            pitching.velocity_body_m_s() + pitching.angular_velocity_rad_s.cross(&r) + elastic[i];
        let normal_velocity = panel.normal.dot(&v);
        let expected = if normal_velocity > 0.0 {
            let cp_max = newtonian_cp_max(v.norm() / fs.speed_of_sound_m_s, GAMMA).unwrap();
            fs.pressure_pa + 0.5 * fs.density_kg_m3 * normal_velocity.powi(2) * cp_max
        } else {
            fs.pressure_pa
        };
        assert_relative_eq!(moving.pressure_pa[i], expected, max_relative = 1e-12);
        if panel.surface == 0 && i != 2 {
            let ahead = panel.centroid.x > 0.0;
            assert_eq!(
                moving.pressure_pa[i] < base.pressure_pa[i],
                ahead,
                "panel {i}"
            );
        }
    }
    assert!(moving.pressure_pa[2] > base.pressure_pa[2]);
    let cm = |out: &AeroSolution, flight: &FlightCondition| {
        coefficients(&mesh, out, flight, CHORD_M * SPAN_M).cm
    };
    let rate_only = evaluate(Form::Vector, &mesh, &pitching, &PanelMotion::default());
    assert!(
        cm(&rate_only, &pitching) < cm(&base, &steady),
        "pitch rate must damp"
    );
}

#[test]
fn subsonic_freestream_and_non_finite_motion_are_errors() {
    let mesh = forward_facing_panel();
    let mut out = AeroSolution::default();
    for form in [Form::Scalar, Form::Vector] {
        let subsonic = FlightCondition::steady(freestream(0.9), 0.0, 0.0);
        let err = model(form)
            .evaluate(&mesh, &subsonic, &PanelMotion::default(), &mut out)
            .unwrap_err();
        assert!(matches!(err, ModelError::OutOfRange { .. }), "{err}");
        assert!(err.to_string().contains("Mach number"), "{err}");
        let mut bad = FlightCondition::steady(freestream(6.0), 0.0, 0.0);
        bad.angular_velocity_rad_s.y = f64::INFINITY;
        assert!(
            model(form)
                .evaluate(&mesh, &bad, &PanelMotion::default(), &mut out)
                .is_err()
        );
    }
    let flight = FlightCondition::steady(freestream(6.0), 0.0, 0.0);
    let elastic = [Vector3::new(f64::NAN, 0.0, 0.0)];
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&elastic),
    };
    let err = model(Form::Vector)
        .evaluate(&mesh, &flight, &motion, &mut out)
        .unwrap_err();
    assert!(matches!(err, ModelError::NonFinite { .. }), "{err}");
    assert!(err.to_string().contains("panel 0"), "{err}");
    let wrong = [Vector3::zeros(); 2];
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&wrong),
    };
    let err = model(Form::Vector)
        .evaluate(&mesh, &flight, &motion, &mut out)
        .unwrap_err();
    assert!(matches!(err, ModelError::Inconsistent { .. }), "{err}");
}
