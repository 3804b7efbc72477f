//! Fixtures the vehicle-level tests share: the sample vehicle with a coarse lifting-surface
//! structure (three lowest modes, the highest near 60 Hz, so explicit steps of a few ms are
//! stable) and a flexible vehicle trimmed at the sample's Mach 6, 26 km.

// Each test crate uses some of these.
#![allow(dead_code)]

pub mod cli;
pub mod strategies;

use hsv_core::config::{LoadedConfig, SAMPLE_CONFIG_TOML, parse_config};
use hsv_run::analysis::trim::{TrimPoint, TrimRequest, trim};
use hsv_run::dynamics::VehicleState;
use hsv_run::vehicle::flexible_vehicle_with;
use hsv_run::vehicle::partitioned::{
    ElevonCommand, FlightControls, PartitionedVehicle, SurfaceModel,
};

/// The sample config text with the coarse lifting-surface structure.
pub fn coarse_text() -> String {
    SAMPLE_CONFIG_TOML
        .replace("free_vibration_modes = 10", "free_vibration_modes = 3")
        .replace("static_shapes = 5", "static_shapes = 0")
        .replace("elements_chordwise = 24", "elements_chordwise = 8")
        .replace("elements_spanwise = 18", "elements_spanwise = 6")
}

/// `text` with the beam's bending and torsion stiffness (paper Table 1) times 10^`exponent`.
pub fn stiffer_beam(text: &str, exponent: i32) -> String {
    let scale = |v: f64| format!("= {:e} ", v * 10f64.powi(exponent));
    text.replace("= 5.06e10", scale(5.06e10).trim_end())
        .replace("= 6.32e9 ", &scale(6.32e9))
        .replace("= 4.74e9 ", &scale(4.74e9))
}

pub fn parse(text: &str) -> LoadedConfig {
    parse_config(text, "test.toml").expect("config")
}

/// The controls of a trim point.
pub fn controls_of(t: &TrimPoint) -> FlightControls {
    FlightControls {
        elevon: ElevonCommand {
            symmetric_rad: t.elevon_deg.to_radians(),
            differential_rad: 0.0,
        },
        fuel_equivalence_ratio: t.fuel_equivalence_ratio,
    }
}

/// The flexible vehicle of `model` from `loaded`, trimmed at Mach 6, 26 km, and its trimmed
/// state (modes at static equilibrium) and controls.
pub fn trimmed(
    loaded: &LoadedConfig,
    model: SurfaceModel,
    heated: bool,
) -> (PartitionedVehicle, VehicleState, FlightControls) {
    let registry = hsv_run::registry().expect("registry");
    let mut vehicle =
        flexible_vehicle_with(loaded, &registry, model, heated, "test").expect("vehicle");
    let t = trim(&mut vehicle, &TrimRequest::default())
        .expect("trims")
        .trim;
    let controls = controls_of(&t);
    let (state, _) = vehicle
        .level_flight_state(6.0, 26_000.0, t.alpha_deg.to_radians(), &controls)
        .expect("equilibrium");
    (vehicle, state, controls)
}

/// The sample right surface with its `pod` basis cached in `dir`, trained from `duration_s`
/// full-order runs at 10 km at the Mach numbers `mach` and the angles `alpha_deg`.
pub fn surface_with_pod_training(
    dir: &std::path::Path,
    mach: &[f64],
    duration_s: f64,
    alpha_deg: &[f64],
) -> hsv_core::region::RegionInfo {
    let mut region = hsv_core::testing::sample_region("right_surface").clone();
    let mut pod = region.model_settings("pod");
    let basis = dir.join("pod-basis-{region}.json");
    pod.table.insert(
        "basis_file".into(),
        toml::Value::String(basis.display().to_string()),
    );
    let mut training = pod
        .table
        .get("training")
        .and_then(|t| t.as_table())
        .cloned()
        .unwrap_or_default();
    let floats = |v: &[f64]| toml::Value::Array(v.iter().map(|&x| toml::Value::Float(x)).collect());
    training.insert("mach".into(), floats(mach));
    training.insert("duration_s".into(), toml::Value::Float(duration_s));
    training.insert("alpha_deg".into(), floats(alpha_deg));
    pod.table
        .insert("training".into(), toml::Value::Table(training));
    region.settings.insert("pod".into(), pod);
    region
}

/// `region` about to heat from 293 K in 0.1 s steps (heat flux every step) with `conduction`,
/// on `shock-expansion` edge states and `eckert` heat flux at Mach `mach`, 10 km, `alpha_deg`.
pub fn surface_heating(
    region: &hsv_core::region::RegionInfo,
    conduction: &str,
    mach: f64,
    alpha_deg: f64,
) -> hsv_run::analysis::heating::SurfaceHeating {
    use hsv_run::analysis::heating::{HeatingModels, HeatingSteps, SurfaceHeating};
    let registry = hsv_run::registry().expect("registry");
    let freestream =
        hsv_core::flow::Freestream::standard(mach, 10_000.0, region.gas).expect("freestream");
    SurfaceHeating::new(
        region.clone(),
        &registry,
        HeatingModels {
            aero: "shock-expansion".to_owned(),
            heat_flux: "eckert".to_owned(),
            conduction: conduction.to_owned(),
        },
        hsv_core::flow::FlightCondition::steady(freestream, alpha_deg.to_radians(), 0.0),
        HeatingSteps {
            dt_s: 0.1,
            flux_every: 1,
            initial_k: 293.0,
        },
    )
    .expect("heating run")
}
