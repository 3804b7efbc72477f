//! The paper's Table 2 (Klock & Cesnik, §IV.B): the Table 2 vehicle (`configs/table2-hsv.toml`:
//! the sample with built-up surfaces and the paper's unknowns calibrated) trimmed for steady
//! level flight at Mach 6, 26 km by `hsv-run trim`, rigid and flexible, as a user runs it.
//!
//! This is a calibration test (issue 22, item 6), not a validation: the paper leaves the
//! vehicle's width, profile aft of the forebody, surface structure and engine constants
//! unspecified, and the config chooses them (each commented "calibrated" with this target) so
//! that the rigid partitioned trim lands here; the flexible trim was not tuned. The bands are
//! issue 22's, written before the calibration: α ± 0.5°, δe ± 1.0°, φ ± 0.03 about the paper's
//! values.

mod common;

use common::cli::{hsv_run, json, stderr};

/// Issue 22, item 2: the bands about each Table 2 value.
const ALPHA_BAND_DEG: f64 = 0.5;
const ELEVON_BAND_DEG: f64 = 1.0;
const PHI_BAND: f64 = 0.03;

/// Paper Table 2, partitioned solution: (α deg, δe deg, φ).
const PAPER_RIGID: (f64, f64, f64) = (-0.64, 1.49, 0.126);
const PAPER_FLEXIBLE: (f64, f64, f64) = (-0.66, 2.06, 0.139);

/// `hsv-run trim --json` with `model_flag` on the Table 2 vehicle from the default start:
/// (α, δe, φ), the trim converged (cost at its floor, the restart agreeing).
fn trimmed(model_flag: &str) -> (f64, f64, f64) {
    let config = concat!(env!("CARGO_MANIFEST_DIR"), "/../configs/table2-hsv.toml");
    let output = hsv_run(&["trim", model_flag, "--json", "--config", config]);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary = json(&output);
    assert_eq!(summary["trim_status"], "converged", "{summary}");
    let t = &summary["trim"];
    let value = |key: &str| {
        t[key]
            .as_f64()
            .unwrap_or_else(|| panic!("{key}: {summary}"))
    };
    (
        value("alpha_deg"),
        value("elevon_deg"),
        value("fuel_equivalence_ratio"),
    )
}

fn assert_in_bands(what: &str, got: (f64, f64, f64), paper: (f64, f64, f64)) {
    let within = (got.0 - paper.0).abs() <= ALPHA_BAND_DEG
        && (got.1 - paper.1).abs() <= ELEVON_BAND_DEG
        && (got.2 - paper.2).abs() <= PHI_BAND;
    assert!(
        within,
        "{what} trim: alpha {:.3} deg, elevon {:.3} deg, phi {:.4}; paper Table 2: {:.2} deg, \
         {:.2} deg, {:.3} (bands {ALPHA_BAND_DEG} deg, {ELEVON_BAND_DEG} deg, {PHI_BAND})",
        got.0, got.1, got.2, paper.0, paper.1, paper.2
    );
}

#[test]
fn the_rigid_trim_is_within_the_bands_of_table_2() {
    assert_in_bands("rigid", trimmed("--rigid"), PAPER_RIGID);
}

#[test]
fn the_flexible_trim_is_within_the_bands_of_table_2() {
    assert_in_bands("flexible", trimmed("--flexible"), PAPER_FLEXIBLE);
}

/// The first Table 2 point the calibration found (width 16.5 m, boat tail −3.22° with its
/// nozzle closure, inlet 0.9 m, internal nozzle area ratio 1.8): its aero loads stiffen the
/// beam so strongly (λ(K⁻¹ ∂F/∂q) < −1) that the plain static-equilibrium iteration
/// q ← K⁻¹ F(q) overshoots, bends the ramp until its flow expands to vacuum, and the flexible
/// trim of `simulate` failed. The under-relaxed retry of `settle` finds the equilibrium: the
/// flight starts from a trim in the bands of Table 2.
#[test]
fn a_strongly_aero_stiffened_vehicle_still_settles_to_its_elastic_equilibrium() {
    let shipped = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../configs/table2-hsv.toml"
    ))
    .expect("the Table 2 config");
    let mut text = shipped.clone();
    for (from, to) in [
        ("width_m = 15.5", "width_m = 16.5"),
        ("span_m = 15.5", "span_m = 16.5"),
        ("area_m2 = 471.2", "area_m2 = 501.6"),
        ("root_y_m = 7.75", "root_y_m = 8.25"),
        (
            "upper_aftbody_angle_deg = -1.884",
            "upper_aftbody_angle_deg = -3.22",
        ),
        ("nozzle_angle_deg = 10.426", "nozzle_angle_deg = 8.446"),
        ("inlet_height_m = 1.07", "inlet_height_m = 0.9"),
        ("combustor_height_m = 1.07", "combustor_height_m = 0.9"),
        (
            "internal_nozzle_area_ratio = 1.4",
            "internal_nozzle_area_ratio = 1.8",
        ),
    ] {
        assert_eq!(text.matches(from).count(), 1, "`{from}` in the config");
        text = text.replace(from, to);
    }
    let dir = common::cli::scratch_dir("table2-stiffened");
    let path = dir.join("stiffened.toml");
    std::fs::write(&path, text).expect("writes the config");
    // `simulate`'s trim: the vehicle as a flight assembles it (the config's coupling
    // acceleration), trimmed and put in level flight, then one step flown.
    let out = dir.join("run");
    let output = hsv_run(&[
        "simulate",
        "--no-heating",
        "--duration-s",
        "0.002",
        "--json",
        "--config",
        path.to_str().expect("utf-8 path"),
        "--out",
        out.to_str().expect("utf-8 path"),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary = json(&output);
    let t = &summary["trim"];
    let got = (
        t["alpha_deg"].as_f64().expect("alpha"),
        t["elevon_deg"].as_f64().expect("elevon"),
        t["fuel_equivalence_ratio"].as_f64().expect("phi"),
    );
    assert_in_bands("flexible (stiffened)", got, PAPER_FLEXIBLE);
    std::fs::remove_dir_all(&dir).ok();
}
