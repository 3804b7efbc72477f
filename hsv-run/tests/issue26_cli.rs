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

/// An angle of attack inside one turn but far outside the panel methods' validity runs, and
/// the JSON `warnings` say which model left its range on how many panels, and why.
#[test]
fn angle_of_attack_near_ninety_degrees_warns_by_model_and_quantity() {
    let output = hsv_run(&["aero", "--alpha-deg", "89.9", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).expect("valid JSON");
    let warnings = summary["warnings"].to_string();
    assert!(
        warnings.contains("panels turn the flow beyond the largest oblique-shock deflection")
            && warnings.contains("angle of attack or deflection beyond the model's range"),
        "{warnings}"
    );
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
    // Mach 25 at 20 km: q = 0.7 p M^2 = 2419 kPa and T0 = T (1 + 0.2 M^2) = 27300 K.
    let output = hsv_run(&[
        "trim",
        "--rigid",
        "--mach",
        "25",
        "--altitude-m",
        "20000",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let hot: serde_json::Value = serde_json::from_slice(&output.stdout).expect("valid JSON");
    assert_eq!(hot["trim_status"], "converged-with-warnings", "{hot}");
    let notes = hot["notes"].to_string();
    assert!(
        notes.contains("outside the air-breathing corridor")
            && notes.contains("stagnation temperature 27298 K is above 2500 K"),
        "{notes}"
    );
}

// ---- item 1: `config --check` checks every model with its settings ---------------------

/// A material table for `key = { ... }`, with one property of the first row or of the
/// material replaced by the caller.
fn material_table(density: f64, poisson: f64, modulus: f64, conductivity: f64) -> String {
    format!(
        "{{ name = \"edited\", density_kg_m3 = {density}, poisson_ratio = {poisson}, \
         melting_point_k = 1877.0, table = [ \
         {{ temperature_k = 250.0, youngs_modulus_pa = {modulus}, thermal_expansion_per_k = 9e-6, \
         conductivity_w_m_k = {conductivity}, specific_heat_j_kg_k = 500.0 }}, \
         {{ temperature_k = 1300.0, youngs_modulus_pa = 0.7e11, thermal_expansion_per_k = 11e-6, \
         conductivity_w_m_k = 20.0, specific_heat_j_kg_k = 700.0 }} ] }} #"
    )
}

/// Every config class of issue 26 item 1 used to pass `config --check` (or fail only inside a
/// job). Each now fails the check, naming the key path (and the value and allowed range where
/// there is one), with no panic; the sample config passes.
#[test]
fn config_check_rejects_every_class_with_its_key_path() {
    let sample = common::cli::stdout(&hsv_run(&["config"]));
    let dir = scratch_dir("config-check");
    let plate_material = "material = \"ti-6al-4v\"             # DESIGN";
    let conduction_material = "structure_material = \"ti-6al-4v\"";
    let cases: Vec<(&str, &str, String, &str)> = vec![
        (
            "negative mass",
            "forebody_mass_per_length_kg_m = 838.0",
            "forebody_mass_per_length_kg_m = -838.0".into(),
            "key `models.free-free-beam.forebody_mass_per_length_kg_m`",
        ),
        (
            "zero density (zero plate mass)",
            plate_material,
            format!("material = {}", material_table(0.0, 0.3, 1.1e11, 7.0)),
            "key `models.ritz-plate.material`: material edited: density_kg_m3 = 0",
        ),
        (
            "negative density",
            plate_material,
            format!("material = {}", material_table(-4430.0, 0.3, 1.1e11, 7.0)),
            "density_kg_m3 = -4430",
        ),
        (
            "zero stiffness",
            "vertical_bending_stiffness_n_m2 = 6.32e9",
            "vertical_bending_stiffness_n_m2 = 0.0".into(),
            "key `models.free-free-beam.vertical_bending_stiffness_n_m2`",
        ),
        (
            "zero modulus",
            plate_material,
            format!("material = {}", material_table(4430.0, 0.3, 0.0, 7.0)),
            "table[0].youngs_modulus_pa = 0",
        ),
        (
            "negative modulus",
            plate_material,
            format!("material = {}", material_table(4430.0, 0.3, -1e9, 7.0)),
            "table[0].youngs_modulus_pa = -1000000000",
        ),
        (
            "Poisson ratio 0.5",
            plate_material,
            format!("material = {}", material_table(4430.0, 0.5, 1.1e11, 7.0)),
            "poisson_ratio = 0.5: must be in (-1, 0.5)",
        ),
        (
            "zero conductivity (conduction model, not built before)",
            conduction_material,
            format!(
                "structure_material = {}",
                material_table(4430.0, 0.3, 1.1e11, 0.0)
            ),
            "key `models.full-order.structure_material`: material edited: \
             table[0].conductivity_w_m_k = 0",
        ),
        (
            "negative emissivity",
            "emissivity = 0.8 ",
            "emissivity = -0.8 ".into(),
            "key `models.eckert.emissivity`: -0.8 is outside the allowed range (0 to 1)",
        ),
        (
            "negative damping",
            "damping_ratio = 0.02               # our choice",
            "damping_ratio = -0.02 #".into(),
            "key `models.ritz-plate.damping_ratio`: -0.02 is outside the allowed range ([0, 1))",
        ),
        (
            "zero strips (the engine no region names)",
            "spanwise_strips = 5                    # our choice\n",
            "spanwise_strips = 0\n".into(),
            "region `propulsion`: key `models.scramjet-q1d.spanwise_strips`: 0 is out of range; allowed: 3 to 101",
        ),
        (
            "zero structural modes",
            "free_vibration_modes = 10 ",
            "free_vibration_modes = 0 ".into(),
            "key `models.ritz-plate.free_vibration_modes`: 0 is outside the allowed range (1 to 50)",
        ),
        (
            "zero POD modes (conduction model, not built before)",
            "modes = 32 ",
            "modes = 0 ".into(),
            "key `models.pod.modes`: 0 is outside the allowed range (1 to 1000)",
        ),
        (
            "unknown key inside a model's table",
            "[models.eckert]\n",
            "[models.eckert]\nbogus_key = 1\n".into(),
            "models.eckert.bogus_key",
        ),
        (
            "a region override naming an unknown model",
            "[regions.propulsion]",
            "[regions.left_surface]\naero = \"no-such-model\"\n\n[regions.propulsion]".into(),
            "key `regions.left_surface.aero`: unknown hsv model `no-such-model`",
        ),
        (
            "a missing role",
            "aero = \"shock-expansion-piston\"    # paper §II.B",
            "#".into(),
            "region `main_body`: no aero model, which the aerothermoelastic simulation needs \
             (set `regions.main_body.aero`)",
        ),
        (
            "a model in the wrong role",
            "propulsion = \"scramjet-1d\" ",
            "propulsion = \"eckert\" ".into(),
            "key `regions.propulsion.propulsion`: `eckert` is a heat-flux model, but this key \
             names a propulsion model",
        ),
    ];
    for (k, (class, from, to, needle)) in cases.iter().enumerate() {
        assert!(sample.contains(from), "{class}: `{from}` not in the sample");
        let path = dir.join(format!("bad-{k}.toml"));
        std::fs::write(&path, sample.replacen(from, to, 1)).unwrap();
        let output = hsv_run(&["config", "--check", path.to_str().unwrap()]);
        let err = stderr(&output);
        assert!(!output.status.success(), "{class}: passed the check");
        assert!(!err.contains("panicked"), "{class}: {err}");
        assert!(
            err.starts_with("error:") && err.contains(needle),
            "{class}: `{needle}` not in: {err}"
        );
        assert_eq!(err.matches(needle).count(), 1, "{class}: said twice: {err}");
    }
    // In a folder without caches: the check trains no POD basis (it would write hsv-cache/).
    let fresh = scratch_dir("config-check-fresh");
    let good = fresh.join("sample.toml");
    std::fs::write(&good, &sample).unwrap();
    let output = hsv_run_in(Some(&fresh), &["config", "--check", "sample.toml"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        !fresh.join("hsv-cache").exists(),
        "the check trained a model"
    );
}

/// Problems in different models and model names are reported together, one `error:` line
/// each, with the count; a setting both surfaces share is one problem naming both regions; `--json` lists them.
#[test]
fn config_check_reports_every_problem_at_once() {
    let sample = common::cli::stdout(&hsv_run(&["config"]));
    let edits = [
        (
            "forebody_mass_per_length_kg_m = 838.0",
            "forebody_mass_per_length_kg_m = -838.0",
        ),
        ("modes = 32 ", "modes = 0 "),
        (
            "spanwise_strips = 5                    # our choice\n",
            "spanwise_strips = 0\n",
        ),
        (
            "damping_ratio = 0.02               # our choice",
            "damping_ratio = -0.02 #",
        ),
        (
            "[regions.propulsion]",
            "[regions.left_surface]\naero = \"no-such-model\"\n\n[regions.propulsion]",
        ),
    ];
    let mut text = sample.clone();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    let path = scratch_dir("config-check-all").join("four.toml");
    std::fs::write(&path, &text).unwrap();
    let output = hsv_run(&["config", "--check", path.to_str().unwrap()]);
    let err = stderr(&output);
    assert!(!output.status.success());
    let lines: Vec<&str> = err.trim_end().lines().collect();
    assert_eq!(lines.len(), 6, "{err}");
    assert!(lines.iter().all(|l| l.starts_with("error:")), "{err}");
    for needle in [
        "region `main_body`: key `models.free-free-beam.forebody_mass_per_length_kg_m`",
        "regions `left_surface`, `right_surface`: key `models.pod.modes`",
        "region `propulsion`: key `models.scramjet-q1d.spanwise_strips`",
        "regions `left_surface`, `right_surface`: key `models.ritz-plate.damping_ratio`",
        "key `regions.left_surface.aero`: unknown hsv model `no-such-model`",
        "5 problems found",
    ] {
        assert_eq!(err.matches(needle).count(), 1, "`{needle}`: {err}");
    }
    let output = hsv_run(&["config", "--json", "--check", path.to_str().unwrap()]);
    let json: serde_json::Value =
        serde_json::from_str(&common::cli::stdout(&output)).expect("JSON");
    assert_eq!(json["valid"], false);
    assert_eq!(json["problems"].as_array().map(Vec::len), Some(5), "{json}");
}
