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

/// The sample config with its commented "built-up variant" lines switched on (the 4 % wedge, the
/// built-up table, the skins and TPS layer of the conduction model, their carried mass).
fn built_up_variant() -> String {
    // The single commented lines the variant switches on, and the commented table after its
    // header, row by row.
    const VARIANT_LINES: [&str; 4] = [
        "# thickness_to_chord = 0.04",
        "# skin_thickness_m = 0.0025        # built-up",
        "# non_structural_mass_kg_m2 = 3.16",
        "# layers = [{ thickness_m = 0.002",
    ];
    const TABLE_HEADER: &str = "# [models.ritz-plate.built_up]";
    let sample = String::from_utf8(hsv_run(&["config"]).stdout).expect("utf-8");
    let mut out = String::new();
    let mut in_table = false;
    for line in sample.lines() {
        let uncommented = line.strip_prefix("# ").unwrap_or(line);
        let header = line.starts_with(TABLE_HEADER);
        let table_row = in_table && line.starts_with("# ") && uncommented.contains(" = ");
        in_table = header || table_row;
        if line.starts_with("thickness_to_chord = 0.028") || line.starts_with("layers = []") {
            continue;
        }
        let switch_on = header || table_row || VARIANT_LINES.iter().any(|p| line.starts_with(p));
        out.push_str(if switch_on { uncommented } else { line });
        out.push('\n');
    }
    out
}

/// The built-up variant's surface mass against its closed form: over the trapezoid of root and
/// tip chords c_r, c_t and span b, skins 2 ρ t_s S, webs ρ w ∫h dA with ∫h dA the double
/// wedge's volume (τ/2) b (c_r² + c_r c_t + c_t²)/3, and the TPS m_ns S; within the strips at
/// the sharp edges where the depth is below two skins the section is solid (ρ h instead of
/// ρ (2 t_s + w h)): 1 % (band set before the run; the strips are resolved by the Gauss points
/// of the 24-element chord only roughly). A consistency check of the variant's documented mass.
#[test]
fn the_built_up_variant_weighs_its_skins_webs_and_tps() {
    let path = std::env::temp_dir().join(format!("hsv-built-up-{}.toml", std::process::id()));
    std::fs::write(&path, built_up_variant()).expect("write");
    let v = json(&[
        "vehicle",
        "--json",
        "--config",
        path.to_str().expect("path"),
    ]);
    let _ = std::fs::remove_file(&path);
    let mass = v["regions"][1]["mass_properties"]["mass_kg"]
        .as_f64()
        .expect("mass");
    let rho = hsv_core::material::Material::ti_6al_4v().density_kg_m3;
    let (cr, ct, b, tau) = (4.0, 1.6, 3.0, 0.04);
    let (t_s, w, m_ns) = (0.0025, 2.0 * 0.0015 / 0.5, 3.16);
    let area = 0.5 * (cr + ct) * b;
    let volume = 0.5 * tau * b * (cr * cr + cr * ct + ct * ct) / 3.0;
    // Edge strips: the depth grows at 2τ per unit chord from each sharp edge, so it reaches 2 t_s
    // a distance e = t_s/τ in; per unit span each strip holds ρ (e h̄) of solid, h̄ = t_s, in
    // place of ρ (2 t_s e + w t_s e).
    let e = t_s / tau;
    let strips = 2.0 * b * rho * (t_s * e - (2.0 * t_s * e + w * t_s * e));
    let expected = rho * (2.0 * t_s * area + w * volume) + m_ns * area + strips;
    eprintln!("built-up surface: {mass:.2} kg, closed form {expected:.2} kg");
    assert!(
        (mass - expected).abs() < 0.01 * expected,
        "{mass} vs {expected}"
    );
}
