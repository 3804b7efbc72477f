//! `hsv-run aero --friction`: skin friction from the main body's heat-flux model (by name through
//! the registry) next to the pressure loads, with friction drag reported separately and in the
//! total.

use std::process::{Command, Output};

use serde_json::Value;

fn hsv_run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hsv-run"))
        .args(args)
        .output()
        .expect("hsv-run starts")
}

/// The first model row of `aero --json` with `args`.
fn aero_row(args: &[&str]) -> Value {
    let mut all = vec!["aero", "--json"];
    all.extend_from_slice(args);
    let output = hsv_run(&all);
    assert!(
        output.status.success(),
        "{all:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let json: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    json["models"][0].clone()
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

fn vec3(v: &Value, key: &str) -> [f64; 3] {
    let a = v[key]
        .as_array()
        .unwrap_or_else(|| panic!("{key} missing in {v}"));
    [0, 1, 2].map(|i| a[i].as_f64().expect("number"))
}

/// Sample vehicle at Mach 6, 26 km, α = 0 (the config's flight point): the friction drag of
/// `eckert` at a 300 K wall is positive and acts aft, and the total drag and force are the
/// pressure loads plus the friction loads; without `--friction` the pressure row is unchanged
/// and has no friction keys.
#[test]
fn sample_vehicle_friction_drag_is_positive_and_adds_to_the_pressure_drag() {
    let flight = ["--mach", "6", "--altitude-m", "26000", "--alpha-deg", "0"];
    let with: Vec<&str> = flight.iter().copied().chain(["--friction"]).collect();
    let row = aero_row(&with);
    let plain = aero_row(&flight);
    assert!(plain.get("friction_drag_n").is_none(), "{plain}");
    assert_eq!(plain["force_body_n"], row["force_body_n"]);

    let friction = num(&row, "friction_drag_n");
    let pressure = num(&row, "pressure_drag_n");
    let total = num(&row, "total_drag_n");
    println!("drag: pressure {pressure:.1} N, friction {friction:.1} N, total {total:.1} N");
    assert!(friction > 0.0, "friction drag {friction} N");
    assert!((total - (pressure + friction)).abs() <= 1e-9 * total.abs());
    let cd_f = num(&row, "friction_drag_coefficient");
    assert!((num(&row, "total_cd") - (num(&row, "cd") + cd_f)).abs() < 1e-12);
    // Pressure drag agrees with the pressure CD (same q S).
    assert!((pressure / num(&row, "cd") - friction / cd_f).abs() <= 1e-6 * friction / cd_f);

    let f = vec3(&row, "friction_force_body_n");
    let p = vec3(&row, "force_body_n");
    let t = vec3(&row, "total_force_body_n");
    for i in 0..3 {
        assert!((t[i] - (p[i] + f[i])).abs() <= 1e-9 * t[0].abs());
    }
    // At α = β = 0 the drag axis is −x: the friction force points aft and is mostly axial.
    assert!((f[0] + friction).abs() <= 1e-9 * friction);
    assert!(f[2].abs() < 0.1 * friction && f[1].abs() < 1e-6 * friction);
    assert_eq!(row["friction_heat_flux_model"], "eckert");
    assert_eq!(num(&row, "friction_wall_temperature_k"), 300.0);
}

/// The friction model's settings come from the config by name: a laminar `eckert` gives less
/// friction drag than the sample's transitional one (turbulent beyond edge Re_x = 5e5), and a
/// hotter wall less than a cold one (lower ρ* at higher T*: Eckert 1955).
#[test]
fn friction_follows_the_config_and_the_wall_temperature() {
    let sample = hsv_run(&["config"]);
    assert!(sample.status.success());
    let text = String::from_utf8(sample.stdout).unwrap();
    let transitional = "regime = \"transitional\"";
    assert!(text.contains(transitional), "sample eckert regime changed");
    let laminar = text.replacen(transitional, "regime = \"laminar\"", 1);
    let dir = std::env::temp_dir().join(format!("hsv-friction-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("laminar.toml");
    std::fs::write(&path, laminar).unwrap();

    let base = num(&aero_row(&["--friction"]), "friction_drag_n");
    let lam = num(
        &aero_row(&["--friction", "--config", path.to_str().unwrap()]),
        "friction_drag_n",
    );
    let hot = num(
        &aero_row(&["--friction", "--wall-temperature-k", "1000"]),
        "friction_drag_n",
    );
    println!("friction drag: transitional {base:.1} N, laminar {lam:.1} N, 1000 K wall {hot:.1} N");
    assert!(lam > 0.0 && lam < 0.5 * base, "laminar {lam} vs {base}");
    assert!(hot > 0.0 && hot < base, "hot wall {hot} vs {base}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A non-physical wall temperature is one clear error line; the option needs `--friction`.
#[test]
fn bad_wall_temperatures_are_rejected() {
    for bad in ["-5", "0", "NaN"] {
        let output = hsv_run(&["aero", "--friction", "--wall-temperature-k", bad]);
        let err = String::from_utf8_lossy(&output.stderr);
        assert!(
            !output.status.success() && !err.contains("panicked"),
            "{err}"
        );
        assert!(
            err.starts_with("error:") && err.contains("--wall-temperature-k"),
            "{err}"
        );
    }
    let output = hsv_run(&["aero", "--friction", "--wall-temperature-k", "5000"]);
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && err.contains("melt"), "{err}");
    let output = hsv_run(&["aero", "--wall-temperature-k", "400"]);
    assert!(!output.status.success());
}
