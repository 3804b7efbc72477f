//! Validation of `hsv_core::gas` against published compressible-flow tables and worked examples,
//! plus property tests of the invariants every perfect-gas relation must keep (one file: one test
//! binary for one module, sharing the tolerance helpers below).
//!
//! Tolerances: a tabulated value is matched to half a unit in its last printed digit unless a
//! comment says otherwise. All values are for γ = 1.4 unless stated.
//!
//! Sources:
//! - NACA Report 1135 (Ames Research Staff 1953), Tables I-II and charts.
//! - Bar-Meir, "Fundamentals of Compressible Fluid Mechanics" (Potto project), normal-shock,
//!   oblique-shock (worked examples) and Rayleigh-flow tables (Table 10.1), potto.org.
//! - Munson et al., "Fundamentals of Fluid Mechanics", Table A.1; Farokhi, "Aircraft Propulsion",
//!   2nd ed., Appendix B (isentropic tables).
//! - Çengel & Cimbala, "Fluid Mechanics", oblique-shock example (Ma1 = 2.0, δ = 10°, P1 = 75 kPa).
//! - fluidspad.com oblique-shock calculator, detachment-angle table for air.
//! - Anderson, "Modern Compressible Flow" (MCF), Table A.3 (Rayleigh flow); Anderson,
//!   "Hypersonic and High-Temperature Gas Dynamics", §3.2 (C_p,max → 1.839 for γ = 1.4).

use hsv_core::gas::*;
use proptest::prelude::*;

const G: f64 = GAMMA_AIR;

fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// Asserts |actual - expected| <= tolerance, naming the quantity.
fn assert_close(what: &str, actual: f64, expected: f64, tolerance: f64) {
    assert!(
        (actual - expected).abs() <= tolerance,
        "{what}: got {actual}, expected {expected} ± {tolerance}"
    );
}

/// Half a unit in the last digit of a value printed with `decimals` decimals (plus 1e-12 slack).
fn half_unit(decimals: i32) -> f64 {
    0.5 * 10f64.powi(-decimals) + 1e-12
}

// ---------------------------------------------------------------------------------------------
// Isentropic flow
// ---------------------------------------------------------------------------------------------

#[test]
fn isentropic_ratios_mach_0_5_munson_table_a1() {
    // Munson Table A.1, M = 0.50: p/p0 = 0.8430, ρ/ρ0 = 0.8852, T/T0 = 0.9524, A/A* = 1.3398.
    assert_close(
        "p/p0",
        1.0 / total_pressure_ratio(0.5, G),
        0.8430,
        half_unit(4),
    );
    assert_close(
        "rho/rho0",
        1.0 / total_density_ratio(0.5, G),
        0.8852,
        half_unit(4),
    );
    assert_close(
        "T/T0",
        1.0 / total_temperature_ratio(0.5, G),
        0.9524,
        half_unit(4),
    );
    assert_close("A/A*", area_mach_ratio(0.5, G), 1.3398, half_unit(4));
}

#[test]
fn isentropic_mach_2_naca_1135_table() {
    // NACA 1135 Table I, M = 2.00: p/p0 = 0.1278, T/T0 = 0.5556, A/A* = 1.6875.
    assert_close(
        "p/p0",
        1.0 / total_pressure_ratio(2.0, G),
        0.1278,
        half_unit(4),
    );
    assert_close(
        "T/T0",
        1.0 / total_temperature_ratio(2.0, G),
        0.5556,
        half_unit(4),
    );
    assert_close("A/A*", area_mach_ratio(2.0, G), 1.6875, half_unit(4));
}

#[test]
fn area_mach_ratio_rows_munson_farokhi_naca_1135() {
    // (M, A/A*, decimals): 0.10 -> 5.8218 (Munson A.1, Farokhi App. B); 0.20 -> 2.9635 (Farokhi);
    // 3.00 -> 4.2346 and 5.00 -> 25.000 (NACA 1135 Table I).
    for (mach, expected, decimals) in [
        (0.1, 5.8218, 4),
        (0.2, 2.9635, 4),
        (3.0, 4.2346, 4),
        (5.0, 25.000, 3),
    ] {
        assert_close(
            &format!("A/A* at M = {mach}"),
            area_mach_ratio(mach, G),
            expected,
            half_unit(decimals),
        );
    }
}

#[test]
fn mach_from_area_ratio_inverts_exact_rational_rows() {
    // At γ = 7/5, A/A*(2) = 27/16 and A/A*(1/2) = 2 (7/8)³ exactly (NACA 1135 eq. 80).
    let supersonic = mach_from_area_ratio(27.0 / 16.0, G, FlowBranch::Supersonic).unwrap();
    assert_close("M(27/16, supersonic)", supersonic, 2.0, 1e-13);
    let subsonic = mach_from_area_ratio(2.0 * 0.875f64.powi(3), G, FlowBranch::Subsonic).unwrap();
    assert_close("M(1.3398, subsonic)", subsonic, 0.5, 1e-13);
    assert_eq!(
        mach_from_area_ratio(1.0, G, FlowBranch::Supersonic).unwrap(),
        1.0
    );
    assert!(matches!(
        mach_from_area_ratio(0.9, G, FlowBranch::Subsonic),
        Err(GasError::OutOfRange { .. })
    ));
}

#[test]
fn mach_from_total_pressure_ratio_naca_1135() {
    // NACA 1135 Table I: p/p0 = 0.1278 at M = 2.00 (4 digits => M to about ±2e-4).
    let mach = mach_from_total_pressure_ratio(1.0 / 0.1278, G).unwrap();
    assert_close("M from p0/p", mach, 2.0, 5e-4);
    // Exact inverse of eq. 44 at M = 2: p0/p = 1.8^3.5.
    let exact = mach_from_total_pressure_ratio(1.8f64.powf(3.5), G).unwrap();
    assert_close("M from 1.8^3.5", exact, 2.0, 1e-14);
    assert!(mach_from_total_pressure_ratio(0.5, G).is_err());
}

#[test]
fn mach_angle_at_mach_2_is_30_degrees() {
    // NACA 1135 Table II, M = 2.00: μ = 30.000°.
    assert_close("mu(2)", mach_angle(2.0).unwrap().to_degrees(), 30.0, 1e-12);
    assert!(matches!(mach_angle(0.8), Err(GasError::Subsonic { .. })));
}

// ---------------------------------------------------------------------------------------------
// Normal shock
// ---------------------------------------------------------------------------------------------

#[test]
fn normal_shock_mach_2_potto_and_naca_1135() {
    // Potto GDC normal-shock output at Mx = 2.0: My = 0.57735, Ty/Tx = 1.6875, ρy/ρx = 2.6667,
    // Py/Px = 4.5000, P0y/P0x = 0.72087 (same as NACA 1135 Table II).
    let s = normal_shock(2.0, G).unwrap();
    assert_close("M2", s.mach_downstream, 0.57735, half_unit(5));
    assert_close("T2/T1", s.temperature_ratio, 1.6875, half_unit(4));
    assert_close("rho2/rho1", s.density_ratio, 2.6667, half_unit(4));
    assert_close("p2/p1", s.pressure_ratio, 4.5000, half_unit(4));
    assert_close("p02/p01", s.total_pressure_ratio, 0.72087, half_unit(5));
}

#[test]
fn normal_shock_mach_3_5_potto() {
    // Potto GDC normal-shock output at Mx = 3.5: My = 0.45115, Ty/Tx = 3.3151, ρy/ρx = 4.2609,
    // Py/Px = 14.1250, P0y/P0x = 0.21295.
    let s = normal_shock(3.5, G).unwrap();
    assert_close("M2", s.mach_downstream, 0.45115, half_unit(5));
    assert_close("T2/T1", s.temperature_ratio, 3.3151, half_unit(4));
    assert_close("rho2/rho1", s.density_ratio, 4.2609, half_unit(4));
    assert_close("p2/p1", s.pressure_ratio, 14.1250, half_unit(4));
    assert_close("p02/p01", s.total_pressure_ratio, 0.21295, half_unit(5));
}

#[test]
fn normal_shock_mach_5_and_6_rational_forms_of_naca_1135() {
    // NACA 1135 eqs. 93-99 with γ = 7/5 reduce to p2/p1 = (7M²-1)/6, ρ2/ρ1 = 6M²/(M²+5),
    // M2² = (M²+5)/(7M²-1), p02/p01 = (ρ2/ρ1)^(7/2) (p2/p1)^(-5/2). At M = 5 the table row is
    // p2/p1 = 29.000, ρ2/ρ1 = 5.0000, T2/T1 = 5.8000; at M = 6 the fractions are 251/6, 216/41.
    let s5 = normal_shock(5.0, G).unwrap();
    assert_close("p2/p1 at M = 5", s5.pressure_ratio, 29.0, 1e-12);
    assert_close("rho2/rho1 at M = 5", s5.density_ratio, 5.0, 1e-12);
    assert_close("T2/T1 at M = 5", s5.temperature_ratio, 5.8, 1e-12);

    let s6 = normal_shock(6.0, G).unwrap();
    let p: f64 = 251.0 / 6.0;
    let rho: f64 = 216.0 / 41.0;
    assert_close("p2/p1 at M = 6", s6.pressure_ratio, p, 1e-12);
    assert_close("rho2/rho1 at M = 6", s6.density_ratio, rho, 1e-12);
    assert_close("T2/T1 at M = 6", s6.temperature_ratio, p / rho, 1e-12);
    assert_close(
        "M2 at M = 6",
        s6.mach_downstream,
        (41.0f64 / 251.0).sqrt(),
        1e-14,
    );
    assert_close(
        "p02/p01 at M = 6",
        s6.total_pressure_ratio,
        rho.powf(3.5) * p.powf(-2.5),
        1e-14,
    );
    // Printed check at 4 significant figures: p02/p01(6) = 0.02965 (NACA 1135 Table II).
    assert_close(
        "p02/p01 at M = 6 (table)",
        s6.total_pressure_ratio,
        0.02965,
        half_unit(5),
    );
}

#[test]
fn normal_shock_rejects_subsonic_and_nan() {
    let err = normal_shock(0.8, G).unwrap_err();
    assert!(matches!(err, GasError::Subsonic { mach, .. } if mach == 0.8));
    assert!(err.to_string().contains("0.8 is subsonic"), "{err}");
    assert!(matches!(
        normal_shock(f64::NAN, G),
        Err(GasError::NonFinite { .. })
    ));
    assert!(matches!(
        normal_shock(2.0, 1.0),
        Err(GasError::OutOfRange { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Pitot and Newtonian stagnation pressure
// ---------------------------------------------------------------------------------------------

#[test]
fn rayleigh_pitot_mach_2_naca_1135() {
    // NACA 1135 Table II, M = 2.00: p1/p02 = 0.1773, i.e. p02/p1 = 5.640.
    let pitot = rayleigh_pitot_pressure_ratio(2.0, G).unwrap();
    assert_close("p02/p1 at M = 2", pitot, 5.640, half_unit(3));
}

#[test]
fn rayleigh_pitot_worked_example_calculatoratoz() {
    // calculatoratoz.com "Stagnation pressure behind normal shock by Rayleigh pitot tube formula":
    // P1 = 65.374 Pa, γ = 1.4, M1 = 1.49 -> p02 = 220.6775 Pa.
    let p02 = 65.374 * rayleigh_pitot_pressure_ratio(1.49, G).unwrap();
    assert_close("p02 (Pa)", p02, 220.6775, half_unit(4));
}

#[test]
fn rayleigh_pitot_mach_6_equals_shock_times_isentropic() {
    // Identity behind eq. 100: p02/p1 = (p02/p01)(p01/p1), with the M = 6 shock of the
    // rational-form test above.
    let direct = rayleigh_pitot_pressure_ratio(6.0, G).unwrap();
    let product = normal_shock(6.0, G).unwrap().total_pressure_ratio * total_pressure_ratio(6.0, G);
    assert_close("p02/p1 at M = 6", direct, product, 1e-12 * product);
    // Subsonic: the isentropic p0/p (NACA 1135 eq. 44).
    assert_close(
        "p0/p at M = 0.5",
        rayleigh_pitot_pressure_ratio(0.5, G).unwrap(),
        total_pressure_ratio(0.5, G),
        0.0,
    );
}

#[test]
fn newtonian_cp_max_hypersonic_limit_anderson() {
    // Anderson, Hypersonic and High-Temperature Gas Dynamics §3.2: C_p,max → 1.839 as M → ∞
    // for γ = 1.4 (limit of eq. 3.15 with the Rayleigh pitot formula).
    let cp = newtonian_cp_max(1.0e4, G).unwrap();
    assert_close("Cp,max at M = 1e4", cp, 1.839, half_unit(3));
    // At M = 2 it follows from p02/p1 = 5.640 (NACA 1135): (5.640 - 1) / 2.8 = 1.657.
    assert_close(
        "Cp,max at M = 2",
        newtonian_cp_max(2.0, G).unwrap(),
        1.657,
        half_unit(3),
    );
    assert!(newtonian_cp_max(0.0, G).is_err());
}

// ---------------------------------------------------------------------------------------------
// Oblique shock
// ---------------------------------------------------------------------------------------------

#[test]
fn oblique_shock_mach_2_theta_10_cengel_cimbala() {
    // Çengel & Cimbala example: Ma1 = 2.0, δ = 10°, P1 = 75.0 kPa: β_weak = 39.3°, β_strong = 83.7°,
    // P2 = 128 kPa (weak) and 333 kPa (strong), Ma2 = 1.64 (weak). NACA 1135 chart / θ-β-M table:
    // β_weak = 39.31° (brief value), to ±0.005°.
    let weak = oblique_shock(2.0, deg(10.0), G, ShockBranch::Weak).unwrap();
    let strong = oblique_shock(2.0, deg(10.0), G, ShockBranch::Strong).unwrap();
    assert_close(
        "beta weak (deg)",
        weak.wave_angle_rad.to_degrees(),
        39.31,
        half_unit(2),
    );
    assert_close(
        "beta strong (deg)",
        strong.wave_angle_rad.to_degrees(),
        83.7,
        half_unit(1),
    );
    assert_close(
        "P2 weak (kPa)",
        75.0 * weak.pressure_ratio,
        128.0,
        half_unit(0),
    );
    assert_close(
        "P2 strong (kPa)",
        75.0 * strong.pressure_ratio,
        333.0,
        half_unit(0),
    );
    assert_close("M2 weak", weak.mach_downstream, 1.64, half_unit(2));
    assert!(strong.mach_downstream < 1.0);
}

#[test]
fn oblique_shock_potto_examples() {
    // Potto GDC oblique-shock outputs (Mx, My_strong, My_weak, θ_strong, θ_weak, δ, P0y/P0x_weak):
    // (2.0, 0.58974, 1.7498, 85.7021°, 36.2098°, 7°, 0.99445) and
    // (3.0, 0.48013, 2.7008, 87.8807°, 23.9356°, 6°, 0.99105).
    for (mach, m2_strong, m2_weak, beta_strong, beta_weak, delta, p0_weak) in [
        (2.0, 0.58974, 1.7498, 85.7021, 36.2098, 7.0, 0.99445),
        (3.0, 0.48013, 2.7008, 87.8807, 23.9356, 6.0, 0.99105),
    ] {
        let weak = oblique_shock(mach, deg(delta), G, ShockBranch::Weak).unwrap();
        let strong = oblique_shock(mach, deg(delta), G, ShockBranch::Strong).unwrap();
        let at = format!("M = {mach}, δ = {delta}°");
        assert_close(
            &format!("beta weak {at}"),
            weak.wave_angle_rad.to_degrees(),
            beta_weak,
            half_unit(4),
        );
        assert_close(
            &format!("beta strong {at}"),
            strong.wave_angle_rad.to_degrees(),
            beta_strong,
            half_unit(4),
        );
        assert_close(
            &format!("M2 weak {at}"),
            weak.mach_downstream,
            m2_weak,
            half_unit(4),
        );
        assert_close(
            &format!("M2 strong {at}"),
            strong.mach_downstream,
            m2_strong,
            half_unit(5),
        );
        assert_close(
            &format!("p02/p01 weak {at}"),
            weak.total_pressure_ratio,
            p0_weak,
            half_unit(5),
        );
    }
}

#[test]
fn max_deflection_naca_1135_and_fluidspad() {
    // NACA 1135 chart: θ_max(M = 2) = 22.97°, β = 64.67°. fluidspad.com detachment table (air):
    // M = 3: 34.1° at β = 65.2°; M = 5: 41.1° at β = 66.6°.
    let (theta, beta) = max_deflection(2.0, G).unwrap();
    assert_close(
        "theta_max(2) (deg)",
        theta.to_degrees(),
        22.97,
        half_unit(2),
    );
    assert_close(
        "beta at theta_max(2) (deg)",
        beta.to_degrees(),
        64.67,
        half_unit(2),
    );
    for (mach, theta_table, beta_table) in [(3.0, 34.1, 65.2), (5.0, 41.1, 66.6)] {
        let (theta, beta) = max_deflection(mach, G).unwrap();
        assert_close(
            "theta_max (deg)",
            theta.to_degrees(),
            theta_table,
            half_unit(1),
        );
        assert_close(
            "beta at theta_max (deg)",
            beta.to_degrees(),
            beta_table,
            half_unit(1),
        );
    }
}

#[test]
fn oblique_shock_detaches_beyond_theta_max() {
    let (theta_max, beta_max) = max_deflection(2.0, G).unwrap();
    let err = oblique_shock(2.0, deg(25.0), G, ShockBranch::Weak).unwrap_err();
    assert!(
        matches!(err, GasError::Detached { max_deflection_rad, .. } if max_deflection_rad == theta_max)
    );
    assert!(err.to_string().contains("detaches"), "{err}");
    // At θ_max both branches meet.
    for branch in [ShockBranch::Weak, ShockBranch::Strong] {
        let s = oblique_shock(2.0, theta_max, G, branch).unwrap();
        assert_close("beta at theta_max", s.wave_angle_rad, beta_max, 1e-12);
    }
}

#[test]
fn oblique_shock_input_errors() {
    let err = oblique_shock(0.8, deg(5.0), G, ShockBranch::Weak).unwrap_err();
    assert!(
        err.to_string()
            .contains("Mach number 0.8 is subsonic; an oblique shock needs M >= 1"),
        "{err}"
    );
    assert!(matches!(
        oblique_shock(2.0, f64::NAN, G, ShockBranch::Weak),
        Err(GasError::NonFinite { .. })
    ));
    assert!(oblique_shock(2.0, -0.1, G, ShockBranch::Weak).is_err());
    assert!(oblique_shock_from_wave_angle(2.0, deg(20.0), G).is_err());
    assert!(oblique_shock_from_wave_angle(2.0, deg(95.0), G).is_err());
}

#[test]
fn oblique_shock_from_wave_angle_reproduces_cengel_cimbala() {
    // Çengel & Cimbala: β = 39.3° and 83.7° both give δ ≈ 10° at Ma1 = 2.0 (their values are
    // rounded to 0.1°, so δ agrees to about ±0.1°).
    for beta in [39.3, 83.7] {
        let s = oblique_shock_from_wave_angle(2.0, deg(beta), G).unwrap();
        assert_close("delta (deg)", s.deflection_rad.to_degrees(), 10.0, 0.1);
    }
    // β = 90° is the normal shock.
    let normal = oblique_shock_from_wave_angle(2.0, deg(90.0), G).unwrap();
    assert_close("delta at 90°", normal.deflection_rad, 0.0, 1e-15);
    assert_close("p2/p1 at 90°", normal.pressure_ratio, 4.5, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Prandtl-Meyer
// ---------------------------------------------------------------------------------------------

#[test]
fn prandtl_meyer_naca_1135_table_ii() {
    // NACA 1135 Table II: ν(2.00) = 26.38°, ν(6.00) = 84.96°; ν_max = 130.45° for γ = 1.4.
    assert_close(
        "nu(2)",
        prandtl_meyer(2.0, G).unwrap().to_degrees(),
        26.38,
        half_unit(2),
    );
    assert_close(
        "nu(6)",
        prandtl_meyer(6.0, G).unwrap().to_degrees(),
        84.96,
        half_unit(2),
    );
    assert_close(
        "nu_max",
        max_prandtl_meyer(G).to_degrees(),
        130.45,
        half_unit(2),
    );
    assert_eq!(prandtl_meyer(1.0, G).unwrap(), 0.0);
}

#[test]
fn inverse_prandtl_meyer_naca_1135_table_ii() {
    // Inverting the table: ν = 26.38° -> M = 2.00 and ν = 84.96° -> M = 6.00, to the Mach
    // uncertainty the 0.005° rounding of ν implies (dM = dν / (dν/dM)).
    for (nu_deg, mach) in [(26.38, 2.0), (84.96, 6.0)] {
        let m = inverse_prandtl_meyer(deg(nu_deg), G).unwrap();
        let x = (mach * mach - 1.0f64).sqrt();
        let slope = x / (mach * (1.0 + 0.2 * mach * mach));
        assert_close("M(nu)", m, mach, deg(0.005) / slope + 1e-9);
    }
    assert_eq!(inverse_prandtl_meyer(0.0, G).unwrap(), 1.0);
    assert!(inverse_prandtl_meyer(max_prandtl_meyer(G), G).is_err());
    assert!(inverse_prandtl_meyer(-0.1, G).is_err());
}

#[test]
fn expansion_from_mach_2_to_mach_6_naca_1135() {
    // Turning M = 2 flow by ν(6) - ν(2) = 84.96° - 26.38° (NACA 1135 Table II) gives M = 6 to the
    // table's rounding, and p2/p1 = (p/p0)(6) / (p/p0)(2) with p/p0(2) = 0.1278 (Table I) and
    // p/p0(6) = 8.2^-3.5 (eq. 44).
    let turn = deg(84.96 - 26.38);
    let e = prandtl_meyer_expansion(2.0, turn, G).unwrap();
    assert_close("M2", e.mach_downstream, 6.0, 2e-3);
    let expected_p = 8.2f64.powf(-3.5) / 0.1278;
    assert_close("p2/p1", e.pressure_ratio, expected_p, 2e-3 * expected_p);
}

#[test]
fn expansion_past_nu_max_is_vacuum_error() {
    let err = prandtl_meyer_expansion(2.0, deg(110.0), G).unwrap_err();
    assert!(matches!(err, GasError::VacuumExpansion { .. }), "{err}");
    assert!(prandtl_meyer_expansion(2.0, -0.1, G).is_err());
    let none = prandtl_meyer_expansion(2.0, 0.0, G).unwrap();
    assert_eq!(none.mach_downstream, 2.0);
    assert_eq!(none.pressure_ratio, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Rayleigh flow
// ---------------------------------------------------------------------------------------------

#[test]
fn rayleigh_flow_mach_0_5_potto_table_10_1() {
    // Potto Table 10.1 (k = 1.4), M = 0.50: T/T* = 0.79012, T0/T0* = 0.69136, P/P* = 1.778,
    // P0/P0* = 1.114, ρ*/ρ (= V/V*) = 0.44444.
    let r = rayleigh_flow(0.5, G).unwrap();
    assert_close("T/T*", r.temperature_ratio, 0.79012, half_unit(5));
    assert_close("T0/T0*", r.total_temperature_ratio, 0.69136, half_unit(5));
    assert_close("p/p*", r.pressure_ratio, 1.778, half_unit(3));
    assert_close("p0/p0*", r.total_pressure_ratio, 1.114, half_unit(3));
    assert_close("V/V*", r.velocity_ratio, 0.44444, half_unit(5));
}

#[test]
fn rayleigh_flow_mach_2_and_3_anderson_table_a3() {
    // Rayleigh-flow tables (Anderson MCF Table A.3; NACA 1135 values), γ = 1.4, 4 significant figures:
    // M = 2.0: p/p* = 0.3636, T/T* = 0.5289, p0/p0* = 1.503, T0/T0* = 0.7934;
    // M = 3.0: p/p* = 0.1765, T/T* = 0.2803, p0/p0* = 3.424, T0/T0* = 0.6540.
    // Bar-Meir's Rayleigh table prints T/T*(2.0) = 0.52893.
    for (mach, p, t, p0, t0) in [
        (2.0, 0.3636, 0.5289, 1.503, 0.7934),
        (3.0, 0.1765, 0.2803, 3.424, 0.6540),
    ] {
        let r = rayleigh_flow(mach, G).unwrap();
        assert_close("p/p*", r.pressure_ratio, p, half_unit(4));
        assert_close("T/T*", r.temperature_ratio, t, half_unit(4));
        assert_close("p0/p0*", r.total_pressure_ratio, p0, half_unit(3));
        assert_close("T0/T0*", r.total_temperature_ratio, t0, half_unit(4));
    }
    assert_close(
        "T/T* at 2.0 (Bar-Meir)",
        rayleigh_flow(2.0, G).unwrap().temperature_ratio,
        0.52893,
        half_unit(5),
    );
}

#[test]
fn rayleigh_mach_from_total_temperature_ratio_inverts_table_rows() {
    // Potto Table 10.1: T0/T0* = 0.69136 at M = 0.50 (subsonic); Anderson MCF Table A.3:
    // T0/T0* = 0.7934 at M = 2.0 (supersonic). Rounding of the ratio bounds the Mach error.
    let sub = rayleigh_mach_from_total_temperature_ratio(0.69136, G, FlowBranch::Subsonic).unwrap();
    assert_close("M subsonic", sub, 0.5, 1e-5);
    let sup =
        rayleigh_mach_from_total_temperature_ratio(0.7934, G, FlowBranch::Supersonic).unwrap();
    assert_close("M supersonic", sup, 2.0, 2e-3);
    // Sonic point and choking.
    for branch in [FlowBranch::Subsonic, FlowBranch::Supersonic] {
        let m = rayleigh_mach_from_total_temperature_ratio(1.0, G, branch).unwrap();
        assert_close("M at T0/T0* = 1", m, 1.0, 1e-15);
    }
    assert!(matches!(
        rayleigh_mach_from_total_temperature_ratio(1.2, G, FlowBranch::Subsonic),
        Err(GasError::ThermalChoking { .. })
    ));
    // Supersonic Rayleigh flow cannot reach T0/T0* <= (γ²-1)/γ² = 0.4898.
    assert!(rayleigh_mach_from_total_temperature_ratio(0.4, G, FlowBranch::Supersonic).is_err());
}

// ---------------------------------------------------------------------------------------------
// Piston theory
// ---------------------------------------------------------------------------------------------

#[test]
fn third_order_piston_theory_error_is_fourth_order() {
    // The simple-wave relation (Lighthill 1953) expands as 1 + γ w + γ(γ+1)/4 w² + γ(γ+1)/12 w³
    // + γ(γ+1)(3-γ)/96 w⁴ + O(w⁵); the third-order form (Ashley & Zartarian 1956) keeps the first
    // four terms, so the error / w⁴ tends to γ(γ+1)(3-γ)/96 and halving w divides it by 16.
    let c4 = G * (G + 1.0) * (3.0 - G) / 96.0;
    let error = |w: f64| {
        piston_pressure_ratio_exact(w, G).unwrap() - piston_pressure_ratio_third_order(w, G)
    };
    for w in [0.02, -0.02, 0.01, -0.01] {
        assert_close("error / w^4", error(w) / w.powi(4), c4, 0.05 * c4);
    }
    let ratio = error(0.02) / error(0.01);
    assert_close("error(0.02)/error(0.01)", ratio, 16.0, 0.5);
}

#[test]
fn piston_exact_cavitation_and_isentropic_check() {
    // w/a = -2/(γ-1) = -5 is the escape speed of a simple wave: the pressure reaches zero there
    // and the gas cannot follow a faster piston.
    assert!(matches!(
        piston_pressure_ratio_exact(-5.5, G),
        Err(GasError::Cavitation { .. })
    ));
    let near_vacuum = piston_pressure_ratio_exact(-4.99, G).unwrap();
    assert!(near_vacuum > 0.0 && near_vacuum < 1e-15);
    assert!(piston_pressure_ratio_exact(f64::INFINITY, G).is_err());
    // The simple wave is isentropic: p/p∞ = (a/a∞)^(2γ/(γ-1)) with a/a∞ = 1 + (γ-1)/2 w/a.
    assert_close(
        "p/p_inf at w/a = 1",
        piston_pressure_ratio_exact(1.0, G).unwrap(),
        1.2f64.powi(7),
        1e-12,
    );
}

// ---------------------------------------------------------------------------------------------
// Perfect gas
// ---------------------------------------------------------------------------------------------

#[test]
fn perfect_gas_air_sea_level_sound_speed_ussa_1976() {
    // USSA-1976 Table III: sea-level speed of sound 340.29 m/s at 288.15 K.
    let air = PerfectGas::default();
    assert_eq!(air, PerfectGas::AIR);
    assert_close("a (m/s)", air.speed_of_sound(288.15), 340.29, half_unit(2));
    assert_close("cp - cv", air.cp() - air.cv(), GAS_CONSTANT_AIR, 1e-10);
    assert_close("cp/cv", air.cp() / air.cv(), GAMMA_AIR, 1e-14);
    assert!(PerfectGas::new(1.0, 287.0).is_err());
    assert!(PerfectGas::new(1.4, -1.0).is_err());
    assert!(PerfectGas::new(f64::NAN, 287.0).is_err());
    assert_eq!(PerfectGas::new(1.3, 300.0).unwrap().gamma, 1.3);
}

// ---------------------------------------------------------------------------------------------
// Invariants
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Across a normal shock entropy rises (p02/p01 < 1), the flow becomes subsonic but stays above
    /// the limit √((γ-1)/(2γ)), and p, ρ, T all rise.
    #[test]
    fn normal_shock_invariants(mach in 1.001f64..50.0, gamma in 1.05f64..1.67) {
        let s = normal_shock(mach, gamma).unwrap();
        prop_assert!(s.total_pressure_ratio < 1.0);
        prop_assert!(s.mach_downstream < 1.0);
        prop_assert!(s.mach_downstream > ((gamma - 1.0) / (2.0 * gamma)).sqrt());
        prop_assert!(s.pressure_ratio > 1.0 && s.density_ratio > 1.0 && s.temperature_ratio > 1.0);
        prop_assert!(s.density_ratio < (gamma + 1.0) / (gamma - 1.0));
    }

    /// Oblique shocks: θ-β-M round trip, entropy rise, strong branch subsonic, weak branch slower
    /// than upstream, and weak β between the Mach angle and β at θ_max.
    #[test]
    fn oblique_shock_invariants(
        mach in 1.05f64..25.0,
        fraction in 0.001f64..0.999,
        gamma in 1.1f64..1.67,
    ) {
        let (theta_max, beta_max) = max_deflection(mach, gamma).unwrap();
        let theta = fraction * theta_max;
        let weak = oblique_shock(mach, theta, gamma, ShockBranch::Weak).unwrap();
        let strong = oblique_shock(mach, theta, gamma, ShockBranch::Strong).unwrap();
        for s in [&weak, &strong] {
            let back = deflection_from_wave_angle(mach, s.wave_angle_rad, gamma);
            prop_assert!((back - theta).abs() <= 1e-12, "theta {} back {}", theta, back);
            prop_assert!(s.total_pressure_ratio < 1.0);
            prop_assert!(s.pressure_ratio > 1.0);
        }
        let mu = mach_angle(mach).unwrap();
        prop_assert!(weak.wave_angle_rad > mu && weak.wave_angle_rad <= beta_max);
        prop_assert!(strong.wave_angle_rad >= beta_max && strong.wave_angle_rad <= std::f64::consts::FRAC_PI_2);
        prop_assert!(strong.mach_downstream < 1.0);
        prop_assert!(weak.mach_downstream < mach);
        prop_assert!(weak.total_pressure_ratio >= strong.total_pressure_ratio);
    }

    /// As θ → 0 the weak shock becomes a Mach wave: β → asin(1/M) and p2/p1 → 1 linearly in θ
    /// (linear theory: p2/p1 - 1 ≈ γ M² θ / √(M²-1)).
    #[test]
    fn weak_shock_tends_to_mach_wave(mach in 1.2f64..20.0, theta in 1e-9f64..1e-5) {
        let s = oblique_shock(mach, theta, G, ShockBranch::Weak).unwrap();
        let mu = mach_angle(mach).unwrap();
        // dβ/dθ at θ = 0 from the θ-β-M relation: (γ+1) M² / (4 (M² - 1)).
        let beta_slope = (G + 1.0) * mach * mach / (4.0 * (mach * mach - 1.0));
        prop_assert!((s.wave_angle_rad - mu).abs() <= 2.0 * beta_slope * theta + 1e-12);
        let linear = G * mach * mach * theta / (mach * mach - 1.0).sqrt();
        prop_assert!((s.pressure_ratio - 1.0 - linear).abs() <= 0.05 * linear + 1e-12);
    }

    /// As θ → 0 the strong shock becomes the normal shock: β → π/2, ratios → normal-shock values.
    #[test]
    fn strong_shock_tends_to_normal_shock(mach in 1.2f64..20.0, theta in 1e-9f64..1e-6) {
        let s = oblique_shock(mach, theta, G, ShockBranch::Strong).unwrap();
        let n = normal_shock(mach, G).unwrap();
        prop_assert!((s.wave_angle_rad - std::f64::consts::FRAC_PI_2).abs() <= 1e-4);
        prop_assert!((s.pressure_ratio / n.pressure_ratio - 1.0).abs() <= 1e-7);
        prop_assert!((s.mach_downstream - n.mach_downstream).abs() <= 1e-5);
    }

    /// Prandtl-Meyer inverse round trip to 1e-12 relative.
    #[test]
    fn prandtl_meyer_round_trip(mach in 1.000_001f64..60.0, gamma in 1.1f64..1.67) {
        let nu = prandtl_meyer(mach, gamma).unwrap();
        let back = inverse_prandtl_meyer(nu, gamma).unwrap();
        prop_assert!((back / mach - 1.0).abs() <= 1e-12, "M {} back {}", mach, back);
    }

    /// Expansions are isentropic compositions: turning by a then b equals turning by a + b, and
    /// the pressure falls while the Mach number rises.
    #[test]
    fn expansion_composes(mach in 1.0f64..8.0, a in 0.0f64..0.3, b in 0.0f64..0.3) {
        let one = prandtl_meyer_expansion(mach, a, G).unwrap();
        let two = prandtl_meyer_expansion(one.mach_downstream, b, G).unwrap();
        let both = prandtl_meyer_expansion(mach, a + b, G).unwrap();
        prop_assert!((two.mach_downstream / both.mach_downstream - 1.0).abs() <= 1e-11);
        let composed = one.pressure_ratio * two.pressure_ratio;
        prop_assert!((composed / both.pressure_ratio - 1.0).abs() <= 1e-10);
        prop_assert!(both.mach_downstream >= mach && both.pressure_ratio <= 1.0);
    }

    /// Area-Mach inverse round trip on both branches.
    #[test]
    fn area_ratio_round_trip(mach in 0.01f64..30.0, gamma in 1.1f64..1.67) {
        prop_assume!((mach - 1.0).abs() > 1e-3);
        let branch = if mach < 1.0 { FlowBranch::Subsonic } else { FlowBranch::Supersonic };
        let back = mach_from_area_ratio(area_mach_ratio(mach, gamma), gamma, branch).unwrap();
        prop_assert!((back / mach - 1.0).abs() <= 1e-10, "M {} back {}", mach, back);
    }

    /// Rayleigh T0/T0* inverse round trip on both branches; T0/T0* <= 1 everywhere.
    #[test]
    fn rayleigh_round_trip(mach in 0.01f64..20.0) {
        prop_assume!((mach - 1.0).abs() > 1e-3);
        let r = rayleigh_flow(mach, G).unwrap();
        prop_assert!(r.total_temperature_ratio <= 1.0);
        let branch = if mach < 1.0 { FlowBranch::Subsonic } else { FlowBranch::Supersonic };
        let back =
            rayleigh_mach_from_total_temperature_ratio(r.total_temperature_ratio, G, branch).unwrap();
        prop_assert!((back / mach - 1.0).abs() <= 1e-8, "M {} back {}", mach, back);
    }

    /// Third-order piston theory differs from the exact simple wave by at most C w⁴ for |w| <= 0.3
    /// (C = 0.1, above the leading coefficient γ(γ+1)(3-γ)/96 = 0.056), plus the two
    /// evaluations' rounding: the exact ratio is a 7th power of 1 + (γ-1)w/2 (eight roundings)
    /// and the polynomial four, 16 ε of the ratio between them. (The former 1e-15, about 4.5 ε,
    /// failed at w = 6.7e-5, where w⁴ is 2e-17.)
    #[test]
    fn piston_third_order_within_fourth_order_bound(w in -0.3f64..0.3) {
        let exact = piston_pressure_ratio_exact(w, G).unwrap();
        let third = piston_pressure_ratio_third_order(w, G);
        let rounding = 16.0 * f64::EPSILON * exact.abs();
        prop_assert!((exact - third).abs() <= 0.1 * w.powi(4) + rounding);
    }
}
