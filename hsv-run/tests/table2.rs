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
