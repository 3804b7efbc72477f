//! Validation of `piston-theory` against closed-form piston-theory and simple-wave results.
//!
//! References:
//! - Lighthill, M. J., "Oscillating airfoils at high Mach number", J. Aeronaut. Sci. 20(6), 1953:
//!   simple-wave piston pressure p/p∞ = (1 + (γ-1)/2 w/a)^(2γ/(γ-1)) and its acoustic (linear)
//!   limit p - p∞ = ρ∞ a∞ w.
//! - Ashley, H. & Zartarian, G., "Piston theory — a new aerodynamic tool for the
//!   aeroelastician", J. Aeronaut. Sci. 23(12), 1956: the third-order expansion and the flat-plate
//!   normal force C_N = (4 sin α / M)(1 + (γ+1)/12 M² sin²α).
//! - Ackeret (1925) linear supersonic lift slope c_l = 4α/√(M²-1), whose M → ∞ limit 4α/M is the
//!   piston-theory result (Ashley & Zartarian).

use approx::assert_relative_eq;
use hsv_core::aero::{
    AeroModel, AeroSolution, Coefficients, EdgeState, PanelMotion, ReferenceValues,
    integrate_pressure,
};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::{PerfectGas, piston_pressure_ratio_exact, piston_pressure_ratio_third_order};
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Surface};
use hsv_model_piston_theory::{PistonTheory, Settings};
use nalgebra::{Point3, Vector3};

const GAMMA: f64 = 1.4;
const CHORD_M: f64 = 2.0;
const SPAN_M: f64 = 1.0;
const N_CHORD: usize = 4;

/// A zero-thickness flat plate in the body x-y plane (leading edge at x = 0, trailing edge at
/// x = -c), with `N_CHORD` lower panels (surface 0, normal +z) and `N_CHORD` upper panels
/// (surface 1, normal -z).
fn flat_plate() -> PanelMesh {
    let n = N_CHORD;
    let mut vertices = Vec::new();
    for y in [0.0, SPAN_M] {
        for i in 0..=n {
            vertices.push(Point3::new(-CHORD_M * i as f64 / n as f64, y, 0.0));
        }
    }
    let top = |i: usize| n + 1 + i;
    let mut panels = Vec::new();
    for i in 0..n {
        panels.push(PanelSpec::quad(i, top(i), top(i + 1), i + 1, 0));
    }
    for i in 0..n {
        panels.push(PanelSpec::quad(i, i + 1, top(i + 1), top(i), 1));
    }
    let surfaces = vec![
        Surface::new("lower", RegionKind::LiftingSurface),
        Surface::new("upper", RegionKind::LiftingSurface),
    ];
    let mesh = PanelMesh::new(vertices, &panels, Vec::new(), surfaces).unwrap();
    for panel in &mesh.panels {
        let expected = if panel.surface == 0 { 1.0 } else { -1.0 };
        assert_relative_eq!(panel.normal.z, expected, epsilon = 1e-14);
    }
    mesh
}

fn is_lower(mesh: &PanelMesh, i: usize) -> bool {
    mesh.panels[i].surface == 0
}

fn freestream(mach: f64) -> Freestream {
    Freestream::standard(mach, 26_000.0, PerfectGas::AIR).unwrap()
}

fn evaluate(mesh: &PanelMesh, flight: &FlightCondition, motion: &PanelMotion<'_>) -> AeroSolution {
    let mut out = AeroSolution::default();
    PistonTheory::new(Settings::default())
        .evaluate(mesh, flight, motion, &mut out)
        .unwrap();
    out
}

fn plate_reference() -> ReferenceValues {
    ReferenceValues {
        area_m2: CHORD_M * SPAN_M,
        chord_m: CHORD_M,
        span_m: SPAN_M,
        moment_point_m: [0.0; 3],
    }
}

/// Flat plate at α: each side sees w/a = ±M sin α, so p/p∞ = P3(±M sin α) exactly; against
/// Lighthill's exact simple wave the error is the truncated fourth-order term
/// γ(γ+1)(3-γ)/96 (w/a)⁴ (binomial series of the exact relation), so it scales with (w/a)⁴.
#[test]
fn flat_plate_matches_third_order_and_exact_simple_wave_to_fourth_order() {
    let mesh = flat_plate();
    let fs = freestream(6.0);
    let c4 = GAMMA * (GAMMA + 1.0) * (3.0 - GAMMA) / 96.0;
    let mut errors = Vec::new();
    for alpha_deg in [0.25_f64, 0.5, 1.0, 2.0] {
        let flight = FlightCondition::steady(fs, alpha_deg.to_radians(), 0.0);
        let out = evaluate(&mesh, &flight, &PanelMotion::default());
        let x = fs.mach * alpha_deg.to_radians().sin();
        for (i, &p) in out.pressure_pa.iter().enumerate() {
            let w = if is_lower(&mesh, i) { x } else { -x };
            let ratio = p / fs.pressure_pa;
            // Definition of the model: tolerance is round-off.
            assert_relative_eq!(
                ratio,
                piston_pressure_ratio_third_order(w, GAMMA),
                max_relative = 1e-13
            );
            let error = piston_pressure_ratio_exact(w, GAMMA).unwrap() - ratio;
            // Leading truncation coefficient; the next term is c4 (4-2γ)/10 w⁵, so 3% at w <= 0.21.
            assert_relative_eq!(error / w.powi(4), c4, max_relative = 0.03);
        }
        assert_eq!(out.diagnostics.piston_theory_violations, 0);
        errors.push((
            x,
            piston_pressure_ratio_exact(x, GAMMA).unwrap() - out.pressure_pa[0] / fs.pressure_pa,
        ));
    }
    for pair in errors.windows(2) {
        let order = (pair[1].1 / pair[0].1).ln() / (pair[1].0 / pair[0].0).ln();
        assert!(
            (order - 4.0).abs() < 0.05,
            "observed truncation order {order}"
        );
    }
}

/// Flat-plate normal force of third-order piston theory, C_N = (4 sin α/M)(1 + (γ+1)/12 M² sin²α)
/// (Ashley & Zartarian 1956; the even terms cancel between the two sides), to round-off; its
/// linear part is Ackeret's 4α/√(M²-1) in the M → ∞ limit: c_l M/(4α) → 1 within 0.2% at
/// α = 0.2°, and c_l/c_l,Ackeret - 1 = O(1/(2M²)).
#[test]
fn flat_plate_lift_slope_is_ackeret_in_the_piston_limit() {
    let mesh = flat_plate();
    let alpha = 0.2_f64.to_radians();
    for mach in [5.0_f64, 10.0, 20.0] {
        let fs = freestream(mach);
        let flight = FlightCondition::steady(fs, alpha, 0.0);
        let out = evaluate(&mesh, &flight, &PanelMotion::default());
        let loads = integrate_pressure(
            &mesh,
            &out.pressure_pa,
            fs.pressure_pa,
            &Point3::origin(),
            |_| true,
        );
        let coefficients = Coefficients::from_loads(&loads, &flight, &plate_reference());
        let (s, c) = alpha.sin_cos();
        let cn = 4.0 * s / mach * (1.0 + (GAMMA + 1.0) / 12.0 * mach * mach * s * s);
        assert_relative_eq!(coefficients.cl, cn * c, max_relative = 1e-10);
        assert_relative_eq!(coefficients.cd, cn * s, max_relative = 1e-10);
        let piston_limit = 4.0 * alpha / mach;
        assert_relative_eq!(coefficients.cl, piston_limit, max_relative = 2e-3);
        let ackeret = 4.0 * alpha / (mach * mach - 1.0).sqrt();
        let difference = (coefficients.cl / ackeret - 1.0).abs();
        assert!(difference < 1.0 / (mach * mach), "M = {mach}: {difference}");
    }
}

/// A plate plunging as h = h0 sin ωt at α = 0: the lower side sees w = ḣ, the upper w = -ḣ, so
/// p = p∞ P3(±ḣ/a∞); for small ḣ the pressure is Lighthill's acoustic piston p - p∞ = ρ∞ a∞ ḣ to
/// O(ḣ/a) (tolerance (γ+1)/4 · |ḣ/a| from the quadratic term).
#[test]
fn plunging_plate_pressure_follows_the_plunge_velocity() {
    let mesh = flat_plate();
    let fs = freestream(6.0);
    let flight = FlightCondition::steady(fs, 0.0, 0.0);
    let (h0, omega) = (0.05, 2.0 * std::f64::consts::PI * 20.0);
    let mut elastic = vec![Vector3::zeros(); mesh.panels.len()];
    for step in 0..8 {
        let t = step as f64 / 8.0 / 20.0;
        let h_dot = h0 * omega * (omega * t).cos();
        elastic.fill(Vector3::new(0.0, 0.0, h_dot));
        let motion = PanelMotion {
            elastic_velocity_m_s: Some(&elastic),
        };
        let out = evaluate(&mesh, &flight, &motion);
        let x = h_dot / fs.speed_of_sound_m_s;
        for (i, &p) in out.pressure_pa.iter().enumerate() {
            let w = if is_lower(&mesh, i) { x } else { -x };
            assert_relative_eq!(
                p / fs.pressure_pa,
                piston_pressure_ratio_third_order(w, GAMMA),
                max_relative = 1e-13
            );
            if w.abs() > 1e-6 {
                let acoustic = fs.density_kg_m3 * fs.speed_of_sound_m_s * w * fs.speed_of_sound_m_s;
                let relative = ((p - fs.pressure_pa) / acoustic - 1.0).abs();
                assert!(
                    relative <= (GAMMA + 1.0) / 4.0 * w.abs() * 1.01 + 1e-9,
                    "{relative}"
                );
            }
        }
    }
}

/// |w|/a >= 1 is outside piston theory: every such panel is counted; a cubic that goes negative
/// is clipped at p = 0 with a zero (no-gas) edge state and counted as a vacuum expansion.
#[test]
fn sonic_normal_velocities_are_counted_and_vacuum_is_clipped() {
    let mesh = flat_plate();
    let fs = freestream(6.0);
    let flight = FlightCondition::steady(fs, 0.0, 0.0);
    let n = mesh.panels.len();
    let mut elastic = vec![Vector3::zeros(); n];
    let cases = [(0.5, 0, 0), (1.2, n, 0), (2.0, n, N_CHORD)];
    for (w_over_a, violations, vacuum) in cases {
        elastic.fill(Vector3::new(0.0, 0.0, w_over_a * fs.speed_of_sound_m_s));
        let motion = PanelMotion {
            elastic_velocity_m_s: Some(&elastic),
        };
        let out = evaluate(&mesh, &flight, &motion);
        assert_eq!(
            out.diagnostics.piston_theory_violations, violations,
            "w/a = {w_over_a}"
        );
        assert_eq!(
            out.diagnostics.vacuum_expansions, vacuum,
            "w/a = {w_over_a}"
        );
        for (i, &p) in out.pressure_pa.iter().enumerate() {
            assert!(p.is_finite() && p >= 0.0);
            if vacuum > 0 && !is_lower(&mesh, i) {
                assert_eq!(p, 0.0);
                assert_eq!(out.edge[i], EdgeState::default());
            }
        }
    }
}

/// Edge state: the freestream itself at w = 0; otherwise isentropic from the freestream,
/// T/T∞ = (p/p∞)^((γ-1)/γ), with the total enthalpy cp T + V²/2 = cp T0 conserved and ρ = p/(RT)
/// (NACA Report 1135 eqs. 43-44), to round-off.
#[test]
fn edge_state_is_an_isentropic_simple_wave_from_the_freestream() {
    let mesh = flat_plate();
    let fs = freestream(6.0);
    let gas = fs.gas;
    let out = evaluate(
        &mesh,
        &FlightCondition::steady(fs, 0.0, 0.0),
        &PanelMotion::default(),
    );
    for edge in &out.edge {
        assert_relative_eq!(edge.mach, fs.mach, max_relative = 1e-12);
        assert_relative_eq!(edge.temperature_k, fs.temperature_k, max_relative = 1e-12);
        assert_relative_eq!(edge.density_kg_m3, fs.density_kg_m3, max_relative = 1e-12);
        assert_relative_eq!(edge.velocity_m_s, fs.velocity_m_s, max_relative = 1e-12);
    }
    let flight = FlightCondition::steady(fs, 5_f64.to_radians(), 0.0);
    let out = evaluate(&mesh, &flight, &PanelMotion::default());
    let total_enthalpy = gas.cp() * fs.total_temperature_k();
    for (edge, &p) in out.edge.iter().zip(&out.pressure_pa) {
        assert_eq!(edge.pressure_pa, p);
        let isentropic = fs.temperature_k * (p / fs.pressure_pa).powf((GAMMA - 1.0) / GAMMA);
        assert_relative_eq!(edge.temperature_k, isentropic, max_relative = 1e-12);
        let enthalpy = gas.cp() * edge.temperature_k + 0.5 * edge.velocity_m_s.powi(2);
        assert_relative_eq!(enthalpy, total_enthalpy, max_relative = 1e-12);
        assert_relative_eq!(
            edge.density_kg_m3,
            p / (gas.gas_constant_j_kg_k * edge.temperature_k),
            max_relative = 1e-12
        );
    }
}

#[test]
fn subsonic_freestream_and_bad_motion_are_errors() {
    let mesh = flat_plate();
    let mut model = PistonTheory::new(Settings::default());
    let mut out = AeroSolution::default();
    let subsonic = FlightCondition::steady(freestream(0.8), 0.0, 0.0);
    let err = model
        .evaluate(&mesh, &subsonic, &PanelMotion::default(), &mut out)
        .unwrap_err();
    assert!(matches!(err, ModelError::OutOfRange { .. }), "{err}");
    assert!(err.to_string().contains("Mach number"), "{err}");

    let flight = FlightCondition::steady(freestream(6.0), 0.0, 0.0);
    let mut elastic = vec![Vector3::zeros(); mesh.panels.len()];
    elastic[3].z = f64::NAN;
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&elastic),
    };
    let err = model
        .evaluate(&mesh, &flight, &motion, &mut out)
        .unwrap_err();
    assert!(matches!(err, ModelError::NonFinite { .. }), "{err}");
    assert!(err.to_string().contains("panel 3"), "{err}");

    let short = vec![Vector3::zeros(); 2];
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&short),
    };
    let err = model
        .evaluate(&mesh, &flight, &motion, &mut out)
        .unwrap_err();
    assert!(matches!(err, ModelError::Inconsistent { .. }), "{err}");

    let mut bad = flight;
    bad.alpha_rad = f64::NAN;
    assert!(
        model
            .evaluate(&mesh, &bad, &PanelMotion::default(), &mut out)
            .is_err()
    );
}
