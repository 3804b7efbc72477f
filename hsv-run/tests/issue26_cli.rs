//! Issue 26 (reliability, round 3): every count a user sets is checked against a stated limit
//! before work starts; default commands work on the default config at short horizons and with
//! friction; flow angles beyond one turn are refused and angles beyond a model's range warn.

mod common;

use common::cli::{hsv_run, hsv_run_in, scratch_dir, stderr};

/// Expects failure with one `error:` line containing `needle` and no panic.
fn expect_error(args: &[&str], needle: &str) {
    let output = hsv_run(args);
    let err = stderr(&output);
    assert!(!output.status.success(), "{args:?} succeeded");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(err.starts_with("error:"), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: `{needle}` not in: {err}");
}

// ---- item 2: counts have stated limits, checked before work starts ----------------------

#[test]
fn absurd_counts_are_refused_up_front_with_their_limit() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["flutter", "--times-s", "1e300"],
            "the limit is 100000 steps",
        ),
        (
            &["flutter", "--times-s", "0,1000", "--dt-s", "0.001"],
            "is 1.000e6 heating steps; the limit is 100000 steps",
        ),
        (
            &["flutter", "--mach-step", "1e-9"],
            "the limit is 400 points",
        ),
        (
            &["trade", "--threads", "100000"],
            "--threads (0: all cores) must be from 0 to 1024, got 100000",
        ),
        (&["flutter", "--shard", "0/100000"], "0 <= K < N <= 10000"),
        (
            &["flutter", "--panel", "--panel-modes", "100000"],
            "--panel-modes must be from 1 to 500, got 100000",
        ),
        (
            &["flutter", "--panel", "--panel-elements", "0"],
            "--panel-elements must be from 1 to 200, got 0",
        ),
        (
            &["heat", "--duration-s", "1e300"],
            "more than the 100000000 allowed",
        ),
        (
            &["simulate", "--duration-s", "1e300"],
            "more than the 100000000 allowed",
        ),
    ];
    for (args, needle) in cases {
        expect_error(args, needle);
    }
}

// ---- item 4: flow angles -------------------------------------------------------------------

#[test]
fn flow_angles_beyond_one_turn_are_refused() {
    for (flag, value) in [
        ("--alpha-deg", "720"),
        ("--alpha-deg", "1e300"),
        ("--beta-deg", "-181"),
    ] {
        expect_error(
            &["aero", flag, value],
            &format!("{flag} must be a finite angle from -180 to 180 deg, got"),
        );
    }
    expect_error(
        &["heat", "--alpha-deg", "720"],
        "--alpha-deg must be a finite angle from -180 to 180 deg, got 720",
    );
    expect_error(
        &["flutter", "--alpha-deg", "720"],
        "--alpha-deg must be a finite angle from -180 to 180 deg, got 720",
    );
}

#[test]
fn sideslip_beyond_ninety_degrees_warns_by_model_and_quantity_in_the_json() {
    let output = hsv_run(&["aero", "--beta-deg", "95", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).expect("valid JSON");
    let warnings: Vec<&str> = summary["warnings"]
        .as_array()
        .expect("warnings array")
        .iter()
        .filter_map(|w| w.as_str())
        .collect();
    let model = summary["models"][0]["model"].as_str().expect("model name");
    let expected = format!("{model}: angle of sideslip 95 deg is beyond 90 deg");
    assert!(
        warnings.iter().any(|w| w.starts_with(&expected)),
        "{expected} not in {warnings:?}"
    );
    assert!(stderr(&output).contains(&expected));
}

// ---- item 3: default commands on the default config ------------------------------------

/// Piston theory expands some panels to vacuum (T_e = 0 K at panel 606 on the sample vehicle);
/// Eckert gives those panels no boundary layer instead of failing the run.
#[test]
fn aero_all_with_friction_runs_on_the_default_config() {
    let output = hsv_run(&["aero", "--all", "--friction", "--json"]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    assert!(!err.contains("edge temperature"), "{err}");
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).expect("valid JSON");
    let rows = summary["models"].as_array().expect("models");
    assert!(rows.len() > 1);
    for row in rows {
        let friction = row["friction_drag_n"].as_f64().expect("friction drag");
        assert!(friction > 0.0, "{row}");
    }
    let warnings = summary["warnings"].to_string();
    assert!(
        warnings.contains("piston-theory: ") && warnings.contains("expand to vacuum"),
        "{warnings}"
    );
}

/// One second at 0.1 s gives the three snapshot runs 30 snapshots; `pod` uses 30 modes of its
/// 32 and says so.
#[test]
fn a_one_second_heat_run_trains_pod_on_the_snapshots_it_has_and_says_so() {
    let dir = scratch_dir("heat-1s");
    let output = hsv_run_in(
        Some(&dir),
        &["heat", "--duration-s", "1", "--out", "run", "--json"],
    );
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    let expected =
        "pod: models.pod.modes = 32 but the training runs gave only 30 snapshots: using 30 modes";
    assert!(err.contains(expected), "{err}");
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).expect("valid JSON");
    assert!(
        summary["warnings"].to_string().contains(expected),
        "{summary}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

// ---- item 5: a trim outside the envelope says so -----------------------------------------

/// `trim --altitude-m 0` (Mach 6 at sea level) still finds level flight, but its JSON status is
/// `converged-with-warnings` with the dynamic pressure named, and the warning reaches stderr;
/// the paper's condition is `converged`.
#[test]
fn a_sea_level_trim_converges_with_a_warning() {
    let output = hsv_run(&["trim", "--altitude-m", "0", "--json"]);
    let summary = common::cli::json(&output);
    assert_eq!(
        summary["trim_status"], "converged-with-warnings",
        "{summary}"
    );
    let notes = summary["notes"].to_string();
    assert!(notes.contains("air-breathing corridor"), "{notes}");
    assert!(stderr(&output).contains("warning: trim: dynamic pressure"));
    let paper = common::cli::json(&hsv_run(&["trim", "--json"]));
    assert_eq!(paper["trim_status"], "converged", "{paper}");
}

// ---- item 1 (in part): `config --check` builds the rigid vehicle's models -----------------

/// A config whose models refuse their settings used to pass `config --check` and fail inside a
/// job. The check now builds the models `trim` builds (body and surface aero, structures,
/// friction, engine), so each of these fails there with one line naming the key path and the
/// allowed range; the sample config passes.
#[test]
fn config_check_builds_the_models_and_names_the_bad_setting() {
    let sample = common::cli::stdout(&hsv_run(&["config"]));
    let dir = scratch_dir("config-check");
    let cases = [
        (
            "forebody_mass_per_length_kg_m = 838.0",
            "forebody_mass_per_length_kg_m = -838.0",
            "models.free-free-beam.forebody_mass_per_length_kg_m",
        ),
        (
            "vertical_bending_stiffness_n_m2 = 6.32e9",
            "vertical_bending_stiffness_n_m2 = 0.0",
            "models.free-free-beam.vertical_bending_stiffness_n_m2",
        ),
        (
            "emissivity = 0.8 ",
            "emissivity = -0.8 ",
            "models.eckert.emissivity",
        ),
        (
            "[models.eckert]\n",
            "[models.eckert]\nbogus_key = 1\n",
            "models.eckert.bogus_key",
        ),
        (
            "free_vibration_modes = 10 ",
            "free_vibration_modes = 0 ",
            "free_vibration_modes = 0 is outside the model's range (1 to 50)",
        ),
    ];
    for (k, (from, to, needle)) in cases.iter().enumerate() {
        assert!(sample.contains(from), "{from}");
        let path = dir.join(format!("bad-{k}.toml"));
        std::fs::write(&path, sample.replacen(from, to, 1)).unwrap();
        let output = hsv_run(&["config", "--check", path.to_str().unwrap()]);
        let err = stderr(&output);
        assert!(!output.status.success(), "{to}: passed the check");
        assert!(
            err.starts_with("error:") && err.contains(needle),
            "{to}: {err}"
        );
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert_eq!(err.matches(needle).count(), 1, "said twice: {err}");
    }
    let good = dir.join("sample.toml");
    std::fs::write(&good, &sample).unwrap();
    let output = hsv_run(&["config", "--check", good.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
}
