//! The shared aftbody (external nozzle) model of both engines (issue 10, item 8): a
//! quasi-one-dimensional plume between the aftbody and a pressure-matched shear layer.
//!
//! Sources: Anderson, Modern Compressible Flow (3rd ed.), §4.13 (free boundary: equal pressure
//! on both sides), eq. 4.17 (θ-β-M) and eq. 4.44 (Prandtl-Meyer); NACA Report 1135, eq. 44
//! (isentropic p0/p) and eq. 80 (area-Mach relation).

use approx::assert_relative_eq;
use hsv_core::config::LoadedConfig;
use hsv_core::flow::Freestream;
use hsv_core::gas::{self, FlowBranch, PerfectGas, ShockBranch};
use hsv_model_scramjet::{
    Checker, FlowState, NOZZLE_EXIT, OneDSettings, QuasiOneDSettings, SectionConditions,
    SectionGeometry, SectionSolution, shear_layer_angle_rad,
};
use nalgebra::{Point2, Vector2};

const GAMMA: f64 = 1.4;

/// The shear-layer angle δ balances the plume expanded by δ (Prandtl-Meyer, Anderson MCF eq.
/// 4.44) against the external flow compressed by δ (weak oblique shock, eq. 4.17): equal
/// pressures across the free boundary (§4.13), to 1e-8, for the sample's Mach 6, 26 km external
/// flow and exhausts from the engine's φ = 0.13 and 0.45 exit states. Not under-expanded: δ = 0.
#[test]
fn shear_layer_angle_matches_pressure_across_the_free_boundary() {
    let gas = PerfectGas::AIR;
    let f = Freestream::standard(6.0, 26_000.0, gas).unwrap();
    let external = FlowState {
        mach: f.mach,
        pressure_pa: f.pressure_pa,
        temperature_k: f.temperature_k,
    };
    for (mach, pressure) in [(2.769, 16.611e3), (1.130, 69.869e3), (1.0, 80.757e3)] {
        let exhaust = FlowState {
            mach,
            pressure_pa: pressure,
            temperature_k: 900.0,
        };
        let delta = shear_layer_angle_rad(&exhaust, &external, &gas);
        assert!(delta > 0.0);
        let plume = gas::prandtl_meyer_expansion(mach, delta, GAMMA).unwrap();
        let shock = gas::oblique_shock(f.mach, delta, GAMMA, ShockBranch::Weak).unwrap();
        assert_relative_eq!(
            pressure * plume.pressure_ratio,
            f.pressure_pa * shock.pressure_ratio,
            max_relative = 1e-8
        );
    }
    let over = FlowState {
        mach: 3.0,
        pressure_pa: 0.5 * f.pressure_pa,
        temperature_k: 900.0,
    };
    assert_eq!(shear_layer_angle_rad(&over, &external, &gas), 0.0);
}

/// Both engines' aftbody pressures follow the area-Mach relation of the plume stream tube
/// (NACA 1135 eq. 80, supersonic branch, with p0 and T0 of the nozzle exit kept, eq. 44):
/// A/A_e = (h_e + r + ξ tan δ)/h_e at each segment midpoint (r the wall's rise above the
/// exhaust direction, ξ the distance downstream of the exit), but not below p∞ (the external
/// pressure under a level cowl at α = 0). Recomputed here from the section geometry with
/// `gas::mach_from_area_ratio`; 1e-9. Mach 6, 26 km, φ = 0.13 and 0.45.
#[test]
fn aftbody_pressure_is_the_quasi_one_dimensional_plume_expansion() {
    let loaded = LoadedConfig::sample().expect("embedded config");
    let geometry = loaded.config.geometry;
    let profile = hsv_core::geometry::body_profile(&geometry).expect("profile");
    let section = SectionGeometry::from_profile(&profile, 0.0, 29, 12, 19);
    let check = Checker {
        file: "test",
        key_path: "models.x",
    };
    let gas = PerfectGas::AIR;
    let f = Freestream::standard(6.0, 26_000.0, gas).unwrap();
    let (one, _) = OneDSettings::default().engine(&geometry, &check).unwrap();
    let (q, _) = QuasiOneDSettings::default()
        .engine(&geometry, &check)
        .unwrap();
    for phi in [0.13, 0.45] {
        let conditions = SectionConditions {
            freestream: &f,
            alpha_rad: 0.0,
            fuel_equivalence_ratio: phi,
            reference_m: Point2::new(-15.2, 0.0),
        };
        let mut a = SectionSolution::default();
        one.solve(&section, &conditions, &mut a).unwrap();
        let mut b = SectionSolution::default();
        q.solve(&section, &conditions, &mut b).unwrap();
        for out in [a, b] {
            let exit = out.station(NOZZLE_EXIT).expect("started");
            let (state, h_e) = (exit.state, exit.area_m2_per_m);
            let external = FlowState {
                mach: f.mach,
                pressure_pa: f.pressure_pa,
                temperature_k: f.temperature_k,
            };
            let delta = shear_layer_angle_rad(&state, &external, &gas);
            let n = section.cowl_m.len();
            let e = (section.cowl_m[n - 1] - section.cowl_m[n - 2]).normalize();
            let up = Vector2::new(-e.y, e.x);
            let a_star = h_e / gas::area_mach_ratio(state.mach, GAMMA);
            let p0 = state.pressure_pa * gas::total_pressure_ratio(state.mach, GAMMA);
            let mut rising = true;
            for (w, p) in section.nozzle_m.windows(2).zip(&out.nozzle_pressure_pa) {
                let mid = Point2::from((w[0].coords + w[1].coords) * 0.5);
                let r = mid - section.nozzle_start();
                let h = h_e + r.dot(&up) + r.dot(&e).max(0.0) * delta.tan();
                let mach =
                    gas::mach_from_area_ratio(h / a_star, GAMMA, FlowBranch::Supersonic).unwrap();
                let expected = (p0 / gas::total_pressure_ratio(mach, GAMMA)).max(f.pressure_pa);
                assert_relative_eq!(*p, expected, max_relative = 1e-9);
                rising &= h >= h_e;
            }
            assert!(rising, "the aftbody diverges from the exhaust direction");
            // Under-expanded exhaust: the aftbody pushes forward (thrust) and up (lift).
            assert!(state.pressure_pa > f.pressure_pa);
        }
    }
}
