//! Fixtures the vehicle-level tests share: the sample vehicle with a coarse lifting-surface
//! structure (three lowest modes, the highest near 60 Hz, so explicit steps of a few ms are
//! stable) and a flexible vehicle trimmed at the sample's Mach 6, 26 km.

// Each test crate uses some of these.
#![allow(dead_code)]

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
