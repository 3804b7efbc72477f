//! `hsv-run heat`: the heated surface hands its final temperature field to `hsv-run modes`
//! (frequencies fall, as heat-degraded stiffness must), a run that leaves the material table
//! stops with the time and quantity and keeps its outputs, and bad input is one clear error.

use std::path::PathBuf;
use std::process::{Command, Output};

fn hsv_run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .args(args)
        .output()
        .expect("hsv-run starts")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hsv-heat-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn first_surface_frequency_hz(modes_json: &serde_json::Value) -> f64 {
    modes_json["surfaces"]["right"][0]["frequency_hz"]
        .as_f64()
        .expect("right surface frequency")
}

#[test]
fn heated_field_lowers_the_lifting_surface_frequencies() {
    let out = scratch_dir("field");
    let heat = hsv_run(&[
        "heat",
        "--model",
        "full-order",
        "--duration-s",
        "3",
        "--json",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(heat.status.success(), "{}", stderr(&heat));
    let summary: serde_json::Value = serde_json::from_slice(&heat.stdout).expect("JSON");
    assert_eq!(summary["altitude_m"], 10000.0);
    let model = &summary["models"][0];
    assert_eq!(model["model"], "full-order");
    assert!(model["final_max_temperature_k"].as_f64().expect("max") > 400.0);
    assert!(model["stopped"].is_null());
    let field = out.join("temperature_field_full-order.csv");
    let text = std::fs::read_to_string(&field).expect("temperature field written");
    // On the ritz-plate grid of the sample config: 25 x 19 nodes.
    assert_eq!(
        text.lines().filter(|l| !l.starts_with('#')).count(),
        1 + 25 * 19
    );

    let cold = hsv_run(&[
        "modes",
        "--json",
        "--out",
        out.join("cold").to_str().unwrap(),
    ]);
    assert!(cold.status.success(), "{}", stderr(&cold));
    let hot = hsv_run(&[
        "modes",
        "--json",
        "--temperature-field",
        field.to_str().unwrap(),
        "--out",
        out.join("hot").to_str().unwrap(),
    ]);
    assert!(hot.status.success(), "{}", stderr(&hot));
    let cold: serde_json::Value = serde_json::from_slice(&cold.stdout).expect("JSON");
    let hot: serde_json::Value = serde_json::from_slice(&hot.stdout).expect("JSON");
    assert!(first_surface_frequency_hz(&hot) < first_surface_frequency_hz(&cold));
    std::fs::remove_dir_all(&out).ok();
}

/// Mach 10 at 10 km (total temperature about 4700 K) overheats the thin leading edge: the run
/// stops naming the time and keeps what it computed.
#[test]
fn a_run_that_overheats_stops_with_the_time_and_keeps_its_outputs() {
    let out = scratch_dir("overheat");
    let output = hsv_run(&[
        "heat",
        "--model",
        "full-order",
        "--mach",
        "10",
        "--duration-s",
        "100",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(!output.status.success());
    let err = stderr(&output);
    assert!(
        err.contains("at t = ") && err.contains("outputs up to that time"),
        "{err}"
    );
    let history = std::fs::read_to_string(out.join("temperature_history_full-order.csv"))
        .expect("history written");
    assert!(history.lines().count() > 2, "{history}");
    assert!(out.join("temperature_range.png").exists());
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn bad_input_is_one_clear_error() {
    let output = hsv_run(&["heat", "--duration-s", "-1"]);
    assert!(!output.status.success());
    let err = stderr(&output);
    assert!(err.contains("--duration-s"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");

    let output = hsv_run(&["heat", "--model", "full-ordre"]);
    assert!(!output.status.success());
    let err = stderr(&output);
    assert!(err.contains("full-order"), "did you mean: {err}");
}
