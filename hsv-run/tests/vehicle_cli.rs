//! `hsv-run vehicle` and `hsv-run trim` on the embedded vehicle: mass properties from the
//! structure models against closed forms, and the trim layout.

use std::process::{Command, Output};

fn hsv_run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .args(args)
        .output()
        .expect("hsv-run starts")
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = hsv_run(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON")
}

#[test]
fn vehicle_mass_is_the_beam_of_table_1_plus_two_titanium_double_wedges() {
    let v = json(&["vehicle", "--json"]);
    let regions = v["regions"].as_array().expect("regions");
    let names: Vec<&str> = regions
        .iter()
        .filter_map(|r| r["region"].as_str())
        .collect();
    assert_eq!(
        names,
        ["main_body", "left_surface", "right_surface", "propulsion"]
    );
    // Paper Table 1: μ_f L_f + μ_a L_a = 838·15.2 + 1250·15.2 kg.
    let beam = 838.0 * 15.2 + 1250.0 * 15.2;
    // A double wedge of thickness ratio τ tapering linearly from c_r to c_t over b has volume
    // (τ/2) b (c_r² + c_r c_t + c_t²)/3; sample planform 4.0/1.6/3.0 m, τ = 0.028; Ti-6Al-4V.
    let (cr, ct, b, tau) = (4.0, 1.6, 3.0, 0.028);
    let volume = 0.5 * tau * b * (cr * cr + cr * ct + ct * ct) / 3.0;
    let rho = hsv_core::material::Material::ti_6al_4v().density_kg_m3;
    let surface = rho * volume;
    let mass = |i: usize| {
        regions[i]["mass_properties"]["mass_kg"]
            .as_f64()
            .expect("mass")
    };
    assert!(
        (mass(0) - beam).abs() < 1e-6 * beam,
        "{} vs {beam}",
        mass(0)
    );
    assert!(
        (mass(1) - surface).abs() < 1e-6 * surface,
        "{} vs {surface}",
        mass(1)
    );
    assert!((mass(2) - surface).abs() < 1e-6 * surface);
    let total = v["vehicle_mass_properties"]["mass_kg"]
        .as_f64()
        .expect("total");
    assert!((total - beam - 2.0 * surface).abs() < 1e-6 * total);
    // Mirror images: the vehicle's centre of mass is on the plane of symmetry.
    let y = v["vehicle_mass_properties"]["center_of_mass_m"][1]
        .as_f64()
        .expect("y");
    assert!(y.abs() < 1e-9, "{y}");
}

#[test]
fn trim_prints_the_table_2_layout_and_a_json_summary() {
    let out = hsv_run(&["trim"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for row in [
        "alpha",
        "delta_e",
        "phi",
        "u_dot",
        "w_dot",
        "q_dot",
        "evaluations",
    ] {
        assert!(text.contains(row), "`{row}` missing:\n{text}");
    }
    let v = json(&["trim", "--json"]);
    let phi = v["trim"]["fuel_equivalence_ratio"].as_f64().expect("phi");
    assert!(phi > 0.0 && phi <= 1.0, "{v}");
    assert_eq!(v["restart_agrees_within_1_percent"], true);
    assert_eq!(v["status"]["state"], "completed");
    assert_eq!(v["files"], serde_json::json!([]));
}

#[test]
fn simulate_writes_history_plots_vtk_frames_and_a_summary() {
    let dir = std::env::temp_dir().join(format!("hsv-simulate-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_str().expect("utf-8");
    let v = json(&[
        "simulate",
        "--duration-s",
        "0.01",
        "--vtk-interval-s",
        "0.005",
        "--quiet",
        "--json",
        "--out",
        out,
    ]);
    assert_eq!(v["status"]["state"], "completed", "{v}");
    let files = v["files"].to_string();
    for name in [
        "history.csv",
        "history.png",
        "vehicle.pvd",
        "vehicle_0000.vtk",
        "summary.json",
    ] {
        assert!(files.contains(name), "`{name}` not in {files}");
    }
    let csv = std::fs::read_to_string(dir.join("history.csv")).expect("csv");
    let header = csv.lines().next().expect("header");
    for column in [
        "time_s",
        "altitude_m",
        "alpha_deg",
        "surface_max_temperature_k",
        "body_mode_1_q",
    ] {
        assert!(header.contains(column), "`{column}` not in {header}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
