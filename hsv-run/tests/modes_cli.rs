//! `hsv-run modes`: JSON structure, the main body's frequencies against exact beam solutions,
//! output files, temperature inputs and their errors.
//!
//! Reference frequencies of the sample body (paper Table 1 beam, free-free):
//! - vertical and lateral bending: exact roots of the stepped (838 / 1250 kg/m) Euler-Bernoulli
//!   beam by the transfer-matrix method (Pestel & Leckie, Matrix Methods in Elastomechanics),
//!   computed in models/free-free-beam/tests/validation.rs: 9.510371 Hz and 26.910030 Hz;
//! - torsion (uniform GJ, I_x): f = √(GJ / I_x) / (2L) (Thomson, Theory of Vibration, ch. 9).
//!
//! The finite-element model gives upper bounds (consistent mass, Rayleigh-Ritz) within 2e-4.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn hsv_run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .args(args)
        .output()
        .expect("hsv-run starts")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hsv-modes-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Runs `modes --json --out <dir>/run --force` plus `extra`, expecting success (`--force`:
/// some tests run twice into the same folder).
fn modes_json(dir: &Path, extra: &[&str]) -> serde_json::Value {
    let out = dir.join("run");
    let mut args = vec![
        "modes",
        "--json",
        "--out",
        out.to_str().expect("utf-8 path"),
        "--force",
    ];
    args.extend_from_slice(extra);
    let output = hsv_run(&args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
    serde_json::from_str(&stdout(&output)).expect("valid JSON")
}

/// Runs and expects failure with an `error:` line containing every `needle`, and no panic.
fn expect_error(args: &[&str], needles: &[&str]) {
    let output = hsv_run(args);
    let err = stderr(&output);
    assert!(
        !output.status.success(),
        "{args:?} succeeded: {}",
        stdout(&output)
    );
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(err.starts_with("error:"), "{args:?}: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: `{needle}` not in: {err}");
    }
}

/// (name, frequency) pairs of a JSON mode list.
fn modes_of(list: &serde_json::Value) -> Vec<(String, f64)> {
    list.as_array()
        .expect("a list of modes")
        .iter()
        .map(|m| {
            (
                m["name"].as_str().expect("name").to_owned(),
                m["frequency_hz"].as_f64().expect("frequency_hz"),
            )
        })
        .collect()
}

/// The sample config with `regions.lifting_surfaces` naming `structure` (or none).
fn sample_with_surface_structure(dir: &Path, structure: Option<&str>) -> PathBuf {
    let text = stdout(&hsv_run(&["config"]));
    let mut out = String::new();
    let mut in_surfaces = false;
    for line in text.lines() {
        if line.starts_with('[') {
            in_surfaces = line.trim() == "[regions.lifting_surfaces]";
        }
        if in_surfaces && line.trim_start().starts_with("structure") {
            continue;
        }
        out.push_str(line);
        out.push('\n');
        if line.trim() == "[regions.lifting_surfaces]"
            && let Some(name) = structure
        {
            out.push_str(&format!("structure = \"{name}\"\n"));
        }
    }
    if structure == Some("free-free-beam") {
        // A surface region has no body profile to place a beam axis on: say where it is.
        out.push_str("\n[regions.lifting_surfaces.models.free-free-beam]\naxis_z_m = 0.0\n");
    }
    let path = dir.join("vehicle.toml");
    std::fs::write(&path, out).expect("write config");
    path
}

#[test]
fn body_frequencies_match_the_exact_free_free_beam() {
    let dir = scratch_dir("body");
    let json = modes_json(&dir, &[]);
    assert_eq!(json["body_model"], "free-free-beam");
    let body = modes_of(&json["body"]);
    let torsion_hz = (4.74e9f64 / 3.28e3).sqrt() / (2.0 * 30.4);
    let expected = [
        ("vertical bending 1", 9.510371),
        ("torsion 1", torsion_hz),
        ("lateral bending 1", 26.910030),
    ];
    assert_eq!(body.len(), expected.len(), "{body:?}");
    for ((name, f), (want_name, want_f)) in body.iter().zip(expected) {
        assert_eq!(name, want_name);
        assert!(
            *f >= want_f * (1.0 - 1e-7) && (f / want_f - 1.0) < 2e-4,
            "{name}: {f} Hz vs exact {want_f} Hz"
        );
    }
    assert!(
        body.windows(2).all(|w| w[0].1 < w[1].1),
        "ascending: {body:?}"
    );
    // Surfaces: one list per side, always present.
    for side in ["left", "right"] {
        assert!(
            json["surfaces"][side].is_array(),
            "{side}: {}",
            json["surfaces"]
        );
    }
    if json["surface_model"].is_null() {
        let notes = json["notes"].to_string();
        assert!(
            notes.contains("no lifting-surface structure model configured"),
            "{notes}"
        );
    }
}

#[test]
fn vtk_per_mode_and_png_plots_are_written() {
    let dir = scratch_dir("files");
    let json = modes_json(&dir, &[]);
    let folder = PathBuf::from(json["run_folder"].as_str().expect("run folder"));
    let files: Vec<String> = json["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| f.as_str().expect("path").to_owned())
        .collect();
    for name in [
        "body-undeformed.vtk",
        "body-mode-01-vertical-bending-1.vtk",
        "body-mode-02-torsion-1.vtk",
        "body-mode-03-lateral-bending-1.vtk",
        "body-modes.pvd",
        "body-modes.png",
    ] {
        let path = folder.join(name);
        assert!(files.iter().any(|f| f.ends_with(name)), "{name} not listed");
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        if name.ends_with(".vtk") {
            let text = String::from_utf8_lossy(&bytes);
            assert!(text.starts_with("# vtk DataFile Version"), "{name}");
            if name.contains("-mode-") {
                assert!(text.contains("VECTORS mode_shape double"), "{name}");
            }
        } else if name.ends_with(".png") {
            assert_eq!(&bytes[1..4], b"PNG");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn text_output_lists_the_modes() {
    let dir = scratch_dir("text");
    let out = dir.join("run");
    let output = hsv_run(&["modes", "--out", out.to_str().expect("utf-8")]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    for needle in [
        "main body (free-free-beam)",
        "vertical bending 1",
        "torsion 1",
        "lateral bending 1",
    ] {
        assert!(text.contains(needle), "`{needle}` not in:\n{text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn surfaces_are_reported_per_side_and_mirror_images_share_frequencies() {
    // With the body beam standing in as the surface structure the surface path runs on any
    // build; both sides are mirror images, so their frequencies agree.
    let dir = scratch_dir("surfaces");
    let config = sample_with_surface_structure(&dir, Some("free-free-beam"));
    let json = modes_json(&dir, &["--config", config.to_str().expect("utf-8")]);
    assert_eq!(json["surface_model"], "free-free-beam");
    let (left, right) = (
        modes_of(&json["surfaces"]["left"]),
        modes_of(&json["surfaces"]["right"]),
    );
    assert_eq!(left.len(), 3);
    assert_eq!(left, right);
    assert_eq!(json["surface_status"]["left"]["state"], "ok");
    let files = json["files"].to_string();
    assert!(
        files.contains("left-surface-mode-01") && files.contains("surface-modes.png"),
        "{files}"
    );

    let config = sample_with_surface_structure(&dir, None);
    let json = modes_json(&dir, &["--config", config.to_str().expect("utf-8")]);
    assert!(json["surface_model"].is_null());
    assert_eq!(json["surfaces"]["left"], serde_json::json!([]));
    assert_eq!(json["surface_status"]["right"]["state"], "not configured");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn heating_leaves_the_body_unchanged_and_does_not_stiffen_the_surfaces() {
    // The main body is temperature independent (paper §II.A). A heated surface loses modulus
    // and, clamped at the root, gains compressive thermal stress: every frequency falls (or it
    // buckles, reported as such).
    let dir = scratch_dir("heated");
    let cold = modes_json(&dir, &[]);
    let hot = modes_json(&dir, &["--temperature-k", "600"]);
    assert_eq!(cold["body"], hot["body"]);
    assert_eq!(hot["surface_temperature"]["uniform_k"], 600.0);
    if !cold["surface_model"].is_null() {
        for side in ["left", "right"] {
            if hot["surface_status"][side]["state"] == "buckled" {
                assert!(hot["surface_status"][side]["message"].is_string());
                assert_eq!(hot["surfaces"][side], serde_json::json!([]));
                continue;
            }
            let (c, h) = (
                modes_of(&cold["surfaces"][side]),
                modes_of(&hot["surfaces"][side]),
            );
            assert_eq!(c.len(), h.len());
            for (a, b) in c.iter().zip(&h) {
                assert!(
                    b.1 < a.1,
                    "{side} {}: {} Hz at 600 K vs {} Hz at 293 K",
                    a.0,
                    b.1,
                    a.1
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_temperature_inputs_are_clear_errors() {
    expect_error(
        &["modes", "--temperature-k", "-5"],
        &["--temperature-k", "-5"],
    );
    expect_error(&["modes", "--temperature-k", "nan"], &["--temperature-k"]);
    let output = hsv_run(&[
        "modes",
        "--temperature-k",
        "300",
        "--temperature-field",
        "t.csv",
    ]);
    assert!(!output.status.success());
    assert!(
        stderr(&output).contains("cannot be used with"),
        "{}",
        stderr(&output)
    );

    let dir = scratch_dir("fields");
    let cases = [
        ("header.csv", "node,temp\n0,300\n", "expected the header"),
        (
            "dup.csv",
            "node,temperature_k\n0,300\n1,310\n0,320\n",
            "node 0 appears twice",
        ),
        (
            "gap.csv",
            "node,temperature_k\n0,300\n2,310\n",
            "node 1 has no temperature",
        ),
        ("neg.csv", "node,temperature_k\n0,-3\n", "positive"),
        ("text.csv", "node,temperature_k\n0,hot\n", "not a number"),
        ("empty.csv", "", "empty"),
    ];
    for (name, text, needle) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write csv");
        expect_error(
            &[
                "modes",
                "--temperature-field",
                path.to_str().expect("utf-8"),
            ],
            &[name, needle],
        );
    }
    expect_error(
        &["modes", "--temperature-field", "/nonexistent/t.csv"],
        &["/nonexistent/t.csv", "cannot read"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_structure_models_suggest_the_closest() {
    let dir = scratch_dir("unknown");
    let text = stdout(&hsv_run(&["config"])).replace(
        "structure = \"free-free-beam\"",
        "structure = \"free-free-bem\"",
    );
    let path = dir.join("vehicle.toml");
    std::fs::write(&path, text).expect("write config");
    expect_error(
        &["modes", "--config", path.to_str().expect("utf-8")],
        &["free-free-bem", "did you mean `free-free-beam`"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The assembled vehicle's coupled modes (issue 21: the body's 9.5 Hz bending and the surfaces'
/// first bending interact). Consistency checks, not a validation (that is the monolithic
/// finite-element comparison in tests/tests/elastic_interface_fe.rs): the condensed mass of the
/// partitioned equations is symmetric to 1e-8 (an energy-consistent interface: the surfaces
/// take the body's pivot motion through the same matrices that carry their root loads back),
/// the shares of each mode sum to 1 and the mirror-image surfaces share every mode equally
/// (1e-6); and the modes near 9 Hz carry both body and surface strain energy (over 10 % each),
/// where a one-way interface would leave them pure.
#[test]
fn coupled_modes_mix_the_body_and_the_surfaces() {
    let dir = scratch_dir("coupled");
    let json = modes_json(&dir, &[]);
    let coupled = &json["coupled"];
    assert_eq!(
        coupled["regions"],
        serde_json::json!(["main_body", "left_surface", "right_surface"])
    );
    let asymmetry = coupled["mass_asymmetry"].as_f64().expect("asymmetry");
    assert!(asymmetry < 1e-8, "condensed mass asymmetry {asymmetry}");
    let modes = coupled["modes"].as_array().expect("modes");
    let body_modes = modes_of(&json["body"]).len();
    let surface_modes = modes_of(&json["surfaces"]["right"]).len();
    assert_eq!(modes.len(), body_modes + 2 * surface_modes);
    let mut mixed = 0;
    for mode in modes {
        let f = mode["frequency_hz"].as_f64().expect("frequency");
        let shares: Vec<f64> = mode["strain_energy_shares"]
            .as_array()
            .expect("shares")
            .iter()
            .map(|s| s.as_f64().expect("share"))
            .collect();
        assert!(
            (shares.iter().sum::<f64>() - 1.0).abs() < 1e-9,
            "{f} Hz: {shares:?}"
        );
        assert!((shares[1] - shares[2]).abs() < 1e-6, "{f} Hz: {shares:?}");
        if (8.0..11.0).contains(&f) && shares[0] > 0.1 && shares[1] + shares[2] > 0.1 {
            mixed += 1;
        }
    }
    assert!(mixed >= 2, "modes near 9 Hz: {modes:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
