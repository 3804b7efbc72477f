//! Validation of `kriging-stanton`.
//!
//! - Trained on `eckert` (edge states from `shock-expansion`), the surrogate reproduces Eckert's
//!   convective heat flux on points it never saw within the hold-out error it reports (the
//!   kriging check of Crowell & McNamara, J. Aircraft 49(4), 2012, the paper's Ref. 16).
//! - Trained from a user CSV of a closed-form law, the laminar flat-plate Stanton number from the
//!   Blasius skin friction and the Colburn analogy, St = 0.332 Re_x^(-1/2) Pr^(-2/3) (Incropera &
//!   DeWitt, Fundamentals of Heat and Mass Transfer, 6th ed., Eqs. 7.24 and 7.28), it reproduces
//!   the law on held-out points within its reported error.
//! - A saved training reloads to identical predictions; inputs outside the box are errors naming
//!   the box.

use hsv_core::aero::{AeroSolution, PanelMotion};
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Strip, Surface};
use hsv_core::registry::{ModelContext, Registry};
use hsv_core::thermal::HeatFluxModel;
use hsv_model_eckert as _;
use hsv_model_kriging::{
    CSV_HEADER, KrigingStanton, Settings, recovery_factor, recovery_temperature_k,
};
use hsv_model_shock_expansion as _;
use nalgebra::{Point3, Vector3};

const PR: f64 = 0.71;

fn context<'a>(settings: &'a toml::Table, _config: &'a toml::Table) -> ModelContext<'a> {
    ModelContext {
        settings,
        key_path: "models.kriging-stanton",
        file: "vehicle.toml",
        region: hsv_core::testing::sample_region("right_surface"),
        registry: hsv_core::testing::builtin_registry(),
    }
}

fn build(toml_text: &str) -> Result<KrigingStanton, String> {
    build_in(toml_text, "")
}

/// Builds the surrogate from its settings inside a vehicle config (which holds the base model's
/// `[models.eckert]` settings).
fn build_in(toml_text: &str, config_text: &str) -> Result<KrigingStanton, String> {
    let table: toml::Table = toml::from_str(toml_text).map_err(|e| e.to_string())?;
    let settings: Settings = table.clone().try_into().map_err(|e| e.to_string())?;
    let config: toml::Table = toml::from_str(config_text).map_err(|e| e.to_string())?;
    // The region sees the config's [models.*] tables (the base model's settings).
    let mut region = hsv_core::testing::sample_region("right_surface").clone();
    let models = config.get("models").and_then(toml::Value::as_table);
    for (name, value) in models.into_iter().flatten() {
        if let Some(table) = value.as_table() {
            let settings = hsv_core::region::ModelSettings {
                table: table.clone(),
                key_path: format!("models.{name}"),
            };
            region.settings.insert(name.clone(), settings);
        }
    }
    let ctx = ModelContext {
        region: &region,
        ..context(&table, &config)
    };
    KrigingStanton::new(settings, &ctx).map_err(|e| e.to_string())
}

/// Point `i` of the Halton sequence in bases 2, 3, 5, 7, 11, mapped into `lower..upper`: test
/// points spread over the box and independent of the training's Latin hypercube.
fn halton_point(i: usize, lower: [f64; 5], upper: [f64; 5]) -> [f64; 5] {
    let bases = [2, 3, 5, 7, 11];
    let mut x = [0.0; 5];
    for k in 0..5 {
        let (mut f, mut r, mut n) = (1.0, 0.0, i + 1);
        while n > 0 {
            f /= bases[k] as f64;
            r += f * (n % bases[k]) as f64;
            n /= bases[k];
        }
        x[k] = lower[k] + r * (upper[k] - lower[k]);
    }
    x
}

/// One flat panel of length 2x (running length x) inclined by θ to a freestream along +x.
fn plate(inclination_deg: f64, running_length_m: f64) -> PanelMesh {
    let (s, c) = inclination_deg.to_radians().sin_cos();
    let tangent = Vector3::new(-c, 0.0, s) * (2.0 * running_length_m);
    let a = Point3::new(0.0, -0.5, 0.0);
    let b = Point3::new(0.0, 0.5, 0.0);
    PanelMesh::new(
        vec![a, b, b + tangent, a + tangent],
        &[PanelSpec::quad(0, 1, 2, 3, 0)],
        vec![Strip { panels: vec![0] }],
        vec![Surface::new("plate", RegionKind::Other)],
    )
    .unwrap()
}

/// Convective heat flux (W/m²) of `model` on a plate at the given inputs (x[2] = T_w/T_aw with
/// the recovery factor of the regime), edge state from shock-expansion.
fn convective_flux(model: &mut dyn HeatFluxModel, x: [f64; 5], turbulent: bool) -> f64 {
    let registry = Registry::builtin().unwrap();
    let empty = toml::Table::new();
    let mut aero = registry
        .create::<dyn hsv_core::aero::AeroModel>("shock-expansion", &context(&empty, &empty))
        .unwrap();
    let mesh = plate(x[1], x[3]);
    let freestream = Freestream::standard(x[0], x[4], PerfectGas::AIR).unwrap();
    let flight = FlightCondition::steady(freestream, 0.0, 0.0);
    let mut solution = AeroSolution::default();
    aero.evaluate(&mesh, &flight, &PanelMotion::default(), &mut solution)
        .unwrap();
    let wall_k =
        x[2] * recovery_temperature_k(&solution.edge[0], 1.4, recovery_factor(PR, turbulent));
    let mut q = [0.0];
    model
        .heat_flux(&mesh, &flight, &solution, &[wall_k], &mut q)
        .unwrap();
    q[0]
}

fn rms(errors: &[f64]) -> f64 {
    (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt()
}

/// Crowell & McNamara (2012)-style check: the surrogate of Eckert's laminar heating over the
/// default box (100 samples) reproduces Eckert on 40 fresh points within its reported hold-out
/// RMS error, and that error is below 10 % (the hold-out fit has 20 fewer samples than the
/// final one).
#[test]
fn surrogate_reproduces_eckert_on_unseen_points_within_reported_error() {
    let mut surrogate = build_in(
        "emissivity = 0.0\nsamples = 100\nmelting_point_k = 1e9\nregime = \"laminar\"\n",
        "",
    )
    .unwrap();
    let reported = surrogate.surrogate().holdout_rms_relative_error();
    assert!(reported < 0.10, "hold-out RMS error {reported}");

    let registry = Registry::builtin().unwrap();
    let eckert_settings: toml::Table =
        toml::from_str("emissivity = 0.0\nregime = \"laminar\"\nmelting_point_k = 1e9").unwrap();
    let empty = toml::Table::new();
    let mut eckert = registry
        .create::<dyn hsv_core::thermal::HeatFluxModel>(
            "eckert",
            &context(&eckert_settings, &empty),
        )
        .unwrap();

    let defaults = Settings::default();
    let lower = [
        defaults.mach[0],
        defaults.inclination_deg[0],
        defaults.wall_temperature_ratio[0],
        defaults.running_length_m[0],
        defaults.altitude_m[0],
    ];
    let upper = [
        defaults.mach[1],
        defaults.inclination_deg[1],
        defaults.wall_temperature_ratio[1],
        defaults.running_length_m[1],
        defaults.altitude_m[1],
    ];
    let errors: Vec<f64> = (0..40)
        .map(|i| {
            let x = halton_point(i, lower, upper);
            let truth = convective_flux(eckert.as_mut(), x, false);
            convective_flux(&mut surrogate, x, false) / truth - 1.0
        })
        .collect();
    let measured = rms(&errors);
    assert!(
        measured <= reported,
        "RMS error on unseen points {measured}, reported {reported}"
    );
}

/// Blasius + Colburn (Incropera & DeWitt Eqs. 7.24, 7.28) from a user CSV: the surrogate
/// reproduces St = 0.332 Re_x^(-1/2) Pr^(-2/3) on 30 held-out points within 1.5× its reported
/// error, and that error is below 2 %.
#[test]
fn surrogate_trained_from_csv_reproduces_blasius_colburn_law() {
    let lower = [4.0, 0.0, 0.2, 0.1, 15_000.0];
    let upper = [8.0, 10.0, 0.6, 2.0, 30_000.0];
    let law = |x: [f64; 5]| {
        let f = Freestream::standard(x[0], x[4], PerfectGas::AIR).unwrap();
        let re_x = f.density_kg_m3 * f.velocity_m_s * x[3] / f.dynamic_viscosity_pa_s;
        0.332 / re_x.sqrt() * PR.powf(-2.0 / 3.0)
    };
    let mut csv = format!("{CSV_HEADER}\n");
    for i in 0..60 {
        // Training points from a later stretch of the sequence than the test points below.
        let x = halton_point(500 + i, lower, upper);
        csv += &format!(
            "{},{},{},{},{},0,{}\n",
            x[0],
            x[1],
            x[2],
            x[3],
            x[4],
            law(x)
        );
    }
    let path = std::env::temp_dir().join(format!("hsv-kriging-blasius-{}.csv", std::process::id()));
    std::fs::write(&path, csv).unwrap();
    let surrogate = build(&format!("training_csv = {:?}\n", path.to_str().unwrap())).unwrap();
    std::fs::remove_file(&path).ok();
    let reported = surrogate.surrogate().holdout_rms_relative_error();
    assert!(reported < 0.02, "hold-out RMS error {reported}");
    // Laminar rows only: no turbulent surrogate, and asking for one is an error.
    assert!(surrogate.surrogate().turbulent.is_none());
    let err = surrogate
        .stanton([6.0, 5.0, 0.4, 1.0, 20_000.0], true)
        .unwrap_err()
        .to_string();
    assert!(err.contains("no turbulent surrogate"), "{err}");

    // Test points inside the sampled hull: the box shrunk by 10 % on every side.
    let (inner_lower, inner_upper): (Vec<f64>, Vec<f64>) = (0..5)
        .map(|k| {
            let margin = 0.1 * (upper[k] - lower[k]);
            (lower[k] + margin, upper[k] - margin)
        })
        .unzip();
    let inner_lower: [f64; 5] = inner_lower.try_into().unwrap();
    let inner_upper: [f64; 5] = inner_upper.try_into().unwrap();
    let errors: Vec<f64> = (0..30)
        .map(|i| {
            let x = halton_point(i, inner_lower, inner_upper);
            surrogate.stanton(x, false).unwrap() / law(x) - 1.0
        })
        .collect();
    let measured = rms(&errors);
    assert!(
        measured <= 1.5 * reported.max(0.002),
        "RMS error on unseen points {measured}, reported {reported}"
    );
}

/// A saved training reloads to identical predictions; changed settings retrain.
#[test]
fn saved_training_reloads_identically_and_retrains_on_changed_settings() {
    let path = std::env::temp_dir().join(format!("hsv-kriging-{}.json", std::process::id()));
    std::fs::remove_file(&path).ok();
    let settings = format!(
        "samples = 40\ntraining_file = {:?}\n",
        path.to_str().unwrap()
    );
    let first = build(&settings).unwrap();
    assert!(path.exists(), "training not saved to {}", path.display());
    let saved = std::fs::read_to_string(&path).unwrap();
    let second = build(&settings).unwrap();
    let x = [6.0, 5.0, 0.4, 1.0, 26_000.0];
    for turbulent in [false, true] {
        assert_eq!(
            first.stanton(x, turbulent).unwrap(),
            second.stanton(x, turbulent).unwrap()
        );
    }
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        saved,
        "reload must not retrain"
    );

    let third = build(&format!("{settings}seed = 7\n")).unwrap();
    assert_ne!(
        first.stanton(x, false).unwrap(),
        third.stanton(x, false).unwrap()
    );
    std::fs::remove_file(&path).ok();
}

/// Inputs outside the training box are errors naming the input and the box; `extrapolate`
/// clamps them to the box instead.
#[test]
fn inputs_outside_the_box_are_errors_naming_the_box() {
    let surrogate = build("samples = 30\n").unwrap();
    let err = surrogate
        .stanton([17.0, 5.0, 0.4, 1.0, 26_000.0], true)
        .unwrap_err()
        .to_string();
    assert!(err.contains("mach") && err.contains("[3, 16]"), "{err}");

    let clamped = build("samples = 30\nextrapolate = true\n").unwrap();
    assert_eq!(
        clamped
            .stanton([17.0, 5.0, 0.4, 1.0, 26_000.0], true)
            .unwrap(),
        clamped
            .stanton([16.0, 5.0, 0.4, 1.0, 26_000.0], true)
            .unwrap()
    );
}

/// Bad settings and bad CSVs name the file and key.
#[test]
fn bad_settings_and_csv_are_clear_errors() {
    let err = build("mach = [8.0, 4.0]\n").err().unwrap();
    assert!(
        err.contains("vehicle.toml") && err.contains("models.kriging-stanton.mach"),
        "{err}"
    );
    let err = build("samples = 5\n").err().unwrap();
    assert!(err.contains("samples"), "{err}");
    let path = std::env::temp_dir().join(format!("hsv-kriging-bad-{}.csv", std::process::id()));
    std::fs::write(&path, "mach,stanton\n6,0.001\n").unwrap();
    let err = build(&format!("training_csv = {:?}\n", path.to_str().unwrap()))
        .err()
        .unwrap();
    std::fs::remove_file(&path).ok();
    assert!(
        err.contains("hsv-kriging-bad") && err.contains("first line"),
        "{err}"
    );
}

/// A wall above the melting point is an error, not a heat flux.
#[test]
fn wall_above_melting_point_is_an_error() {
    let mut surrogate = build("samples = 30\n").unwrap();
    let mesh = plate(5.0, 1.0);
    let freestream = Freestream::standard(8.0, 10_000.0, PerfectGas::AIR).unwrap();
    let flight = FlightCondition::steady(freestream, 0.0, 0.0);
    let registry = Registry::builtin().unwrap();
    let empty = toml::Table::new();
    let mut solution = AeroSolution::default();
    registry
        .create::<dyn hsv_core::aero::AeroModel>("shock-expansion", &context(&empty, &empty))
        .unwrap()
        .evaluate(&mesh, &flight, &PanelMotion::default(), &mut solution)
        .unwrap();
    let mut q = [0.0];
    let err = surrogate
        .heat_flux(&mesh, &flight, &solution, &[1900.0], &mut q)
        .unwrap_err()
        .to_string();
    assert!(err.contains("melted") && err.contains("1877"), "{err}");
}

/// Eckert's heating of a plate at the given inputs with `settings` (emissivity 0 for
/// convection only).
fn eckert_flux(settings: &str, x: [f64; 5], turbulent: bool) -> f64 {
    let registry = Registry::builtin().unwrap();
    let table: toml::Table = toml::from_str(settings).unwrap();
    let empty = toml::Table::new();
    let mut eckert = registry
        .create::<dyn hsv_core::thermal::HeatFluxModel>("eckert", &context(&table, &empty))
        .unwrap();
    convective_flux(eckert.as_mut(), x, turbulent)
}

/// The paper's flutter case (a 293 K surface at 10 km, Mach up to 16; §IV.B) lies inside the
/// default box: at Mach 8, 10 km, a 293 K plate inclined 5° at 0.5 m (edge Reynolds number
/// ~3e7: turbulent, as the default transitional rule decides) the surrogate reproduces Eckert
/// within the turbulent surrogate's largest hold-out error, and that error is below 10 %.
/// Test-sized training (60 samples per regime); the default 150 is checked in
/// `default_training_reports_percent_level_errors` (ignored: run with `--ignored`).
#[test]
fn cold_wall_at_mach_8_and_10_km_matches_eckert_within_reported_error() {
    let mut surrogate = build("samples = 60\nemissivity = 0.0\nmelting_point_k = 1e9\n").unwrap();
    let freestream = Freestream::standard(8.0, 10_000.0, PerfectGas::AIR).unwrap();
    let mesh = plate(5.0, 0.5);
    let registry = Registry::builtin().unwrap();
    let empty = toml::Table::new();
    let mut solution = AeroSolution::default();
    registry
        .create::<dyn hsv_core::aero::AeroModel>("shock-expansion", &context(&empty, &empty))
        .unwrap()
        .evaluate(
            &mesh,
            &FlightCondition::steady(freestream, 0.0, 0.0),
            &PanelMotion::default(),
            &mut solution,
        )
        .unwrap();
    assert!(surrogate.is_turbulent(&solution.edge[0], 0.5));
    let recovery = recovery_temperature_k(&solution.edge[0], 1.4, recovery_factor(PR, true));
    let x = [8.0, 5.0, 293.0 / recovery, 0.5, 10_000.0];
    let box_ = surrogate.surrogate();
    for k in 0..5 {
        let v = if k == 3 { x[3].log10() } else { x[k] };
        assert!(
            (box_.lower[k]..=box_.upper[k]).contains(&v),
            "input {k} = {v}"
        );
    }
    let reported = box_.turbulent.as_ref().unwrap().holdout_max_relative_error;
    assert!(reported < 0.10, "largest hold-out error {reported}");
    let truth = eckert_flux("emissivity = 0.0\nmelting_point_k = 1e9", x, true);
    let ours = convective_flux(&mut surrogate, x, true);
    assert!(truth > 0.0);
    assert!(
        (ours / truth - 1.0).abs() <= reported,
        "surrogate {ours} W/m2, eckert {truth} W/m2, reported {reported}"
    );
}

/// Eckert: a wall above its adiabatic-wall (recovery) temperature is cooled by the flow,
/// q ∝ T_aw − T_w (Eckert 1955; Anderson, Hypersonic §6.9). With St referenced to T_aw the
/// surrogate gives the same sign at T_w = 1.05 T_aw, laminar and turbulent.
#[test]
fn wall_above_recovery_temperature_is_cooled_like_eckert() {
    let mut surrogate = build("samples = 40\nemissivity = 0.0\nmelting_point_k = 1e9\n").unwrap();
    for (x, turbulent) in [
        ([8.0, 5.0, 1.05, 0.5, 10_000.0], true),
        ([6.0, 5.0, 1.05, 0.02, 35_000.0], false),
    ] {
        let regime = if turbulent { "turbulent" } else { "laminar" };
        let truth = eckert_flux(
            &format!("emissivity = 0.0\nmelting_point_k = 1e9\nregime = {regime:?}"),
            x,
            turbulent,
        );
        let mut forced = build(&format!(
            "samples = 40\nemissivity = 0.0\nmelting_point_k = 1e9\nregime = {regime:?}\n"
        ))
        .unwrap();
        let ours = convective_flux(&mut forced, x, turbulent);
        assert!(
            truth < 0.0 && ours < 0.0,
            "{regime}: eckert {truth}, surrogate {ours}"
        );
    }
    // The transitional default at 10 km, 0.5 m is turbulent and cools too.
    assert!(convective_flux(&mut surrogate, [8.0, 5.0, 1.05, 0.5, 10_000.0], true) < 0.0);
}

/// The default training (150 samples per regime over Mach 3-16, 10-35 km) and its hold-out
/// errors, printed; slow in a debug build, so ignored by default
/// (`cargo test -p hsv-model-kriging --release -- --ignored --nocapture`).
#[test]
#[ignore]
fn default_training_reports_percent_level_errors() {
    let start = std::time::Instant::now();
    let surrogate = build("").unwrap();
    let s = surrogate.surrogate();
    for (name, part) in [("laminar", &s.laminar), ("turbulent", &s.turbulent)] {
        let part = part.as_ref().unwrap();
        println!(
            "{name}: {} samples, hold-out RMS {:.4}, max {:.4}",
            part.samples, part.holdout_rms_relative_error, part.holdout_max_relative_error
        );
        assert!(part.holdout_rms_relative_error < 0.05);
    }
    println!("trained in {:.1} s", start.elapsed().as_secs_f64());
}
