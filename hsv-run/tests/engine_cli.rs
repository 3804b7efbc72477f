//! `hsv-run engine`: both scramjet models at the paper's condition (Mach 6, 26 km, φ 0.13;
//! paper Table 2) give positive net thrust, `--json` has the documented keys, the sweeps land
//! in the run folder, and bad input is one clear error line.

use std::path::PathBuf;
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
    let dir = std::env::temp_dir().join(format!("hsv-engine-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn defaults_give_positive_net_thrust_for_both_models_with_json_keys() {
    let out = scratch_dir("defaults");
    let output = hsv_run(&["engine", "--json", "--out", out.to_str().expect("utf-8")]);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_str(&stdout(&output)).expect("JSON");
    assert_eq!(summary["mach"], 6.0);
    assert_eq!(summary["altitude_m"], 26000.0);
    assert_eq!(summary["alpha_deg"], 0.0);
    assert_eq!(summary["phi"], 0.13);
    let models = summary["models"].as_array().expect("models");
    let names: Vec<&str> = models
        .iter()
        .map(|m| m["model"].as_str().expect("model name"))
        .collect();
    assert!(
        names.contains(&"scramjet-1d") && names.contains(&"scramjet-q1d"),
        "{names:?}"
    );
    for m in models {
        for key in [
            "model",
            "thrust_n",
            "lift_n",
            "pitching_moment_nm",
            "mass_flow_kg_s",
            "status",
            "stations",
        ] {
            assert!(m.get(key).is_some(), "{key} missing in {m}");
        }
        let thrust = m["thrust_n"].as_f64().expect("thrust");
        assert!(thrust > 0.0, "{}: thrust {thrust}", m["model"]);
        assert!(m["mass_flow_kg_s"].as_f64().expect("mass flow") > 0.0);
        assert!(m["lift_n"].as_f64().expect("lift").is_finite());
        assert!(
            m["pitching_moment_nm"]
                .as_f64()
                .expect("moment")
                .is_finite()
        );
        let status = m["status"].as_str().expect("status");
        assert!(
            ["ok", "spillage", "thermal-choking", "unstart"].contains(&status),
            "{status}"
        );
        let stations = m["stations"].as_array().expect("stations");
        let station_names: Vec<&str> = stations
            .iter()
            .map(|s| s["station"].as_str().expect("station"))
            .collect();
        assert_eq!(
            station_names,
            ["inlet", "combustor-entry", "combustor-exit", "nozzle-exit"]
        );
        for s in stations {
            for key in ["mach", "pressure_pa", "temperature_k"] {
                assert!(s[key].as_f64().expect(key) > 0.0, "{key} in {s}");
            }
        }
    }
    for file in [
        "thrust_vs_phi_alpha.png",
        "thrust_vs_phi.csv",
        "thrust_vs_alpha.csv",
        "summary.json",
    ] {
        assert!(out.join(file).is_file(), "{file} not written");
    }
    let csv = std::fs::read_to_string(out.join("thrust_vs_phi.csv")).expect("csv");
    assert!(
        csv.starts_with("phi,scramjet-1d_thrust_n,scramjet-q1d_thrust_n"),
        "{csv}"
    );
}

#[test]
fn table_lists_each_model_and_the_station_states() {
    let out = scratch_dir("table");
    let output = hsv_run(&[
        "engine",
        "--model",
        "scramjet-1d",
        "--mach",
        "7",
        "--altitude-m",
        "28000",
        "--alpha-deg",
        "1.5",
        "--phi",
        "0.2",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    for needle in [
        "Mach 7",
        "28000 m",
        "alpha 1.5 deg",
        "phi 0.2",
        "scramjet-1d",
        "thrust [N]",
        "combustor-exit",
        "nozzle-exit",
    ] {
        assert!(text.contains(needle), "`{needle}` not in:\n{text}");
    }
    assert!(!text.contains("scramjet-q1d"), "{text}");
}

#[test]
fn negative_phi_is_one_error_line_naming_phi() {
    let out = scratch_dir("phi");
    let output = hsv_run(&[
        "engine",
        "--phi",
        "-0.1",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let err = stderr(&output);
    assert!(!output.status.success(), "{}", stdout(&output));
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.starts_with("error:"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("--phi") && err.contains("-0.1"), "{err}");
}

#[test]
fn unknown_model_is_one_error_line_with_the_known_names() {
    let out = scratch_dir("unknown");
    let output = hsv_run(&[
        "engine",
        "--model",
        "scramjet-2d",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let err = stderr(&output);
    assert!(!output.status.success());
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("scramjet-2d") && err.contains("scramjet-1d"),
        "{err}"
    );
}
