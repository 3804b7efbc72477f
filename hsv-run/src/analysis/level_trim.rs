//! The trimmed level flight a run, a linearization or a control design starts from, over the
//! configured Earth: the trim ([`super::trim`]) and the vehicle put in that flight.

use anyhow::{Context, Result, bail};
use hsv_core::config::LoadedConfig;

use super::trim::{TrimRequest, TrimResult, TrimStatus, trim};
use crate::dynamics::{EarthModel, VehicleState};
use crate::vehicle::partitioned::{ElevonCommand, FlightControls, PartitionedVehicle};

/// The Earth: `[simulation] earth` (`flat`, the default and the paper's; `spherical`;
/// `spherical-rotating`) starting at `[simulation] latitude_deg` (default 0).
pub fn earth(loaded: &LoadedConfig) -> Result<EarthModel> {
    let simulation = &loaded.config.simulation;
    let latitude_deg = match simulation.latitude_deg {
        None => 0.0,
        Some(value) if (-89.0..=89.0).contains(&value) => value,
        Some(value) => bail!(
            "{}: key `simulation.latitude_deg` is {value}; expected degrees in [-89, 89]",
            loaded.file
        ),
    };
    let Some(name) = &simulation.earth else {
        return Ok(EarthModel::Flat);
    };
    EarthModel::from_name(name, latitude_deg.to_radians()).with_context(|| {
        format!(
            "{}: key `simulation.earth` is \"{name}\"; expected one of {}",
            loaded.file,
            EarthModel::NAMES.map(|n| format!("\"{n}\"")).join(", ")
        )
    })
}

/// The trimmed level flight a run starts from.
#[derive(Debug, Clone)]
pub struct LevelTrim {
    pub result: TrimResult,
    /// The trim controls (no differential elevon).
    pub controls: FlightControls,
    /// The vehicle in level flight at the trim.
    pub state: VehicleState,
}

/// Trims `vehicle` for steady flight at `mach`, `altitude_m` (default search) and puts it in
/// that flight: level, or a glide for a vehicle without an engine.
pub fn trim_level_flight(
    vehicle: &mut PartitionedVehicle,
    mach: f64,
    altitude_m: f64,
) -> Result<LevelTrim> {
    let request = TrimRequest {
        mach,
        altitude_m,
        ..TrimRequest::default()
    };
    let result = trim(vehicle, &request)?;
    if result.status == TrimStatus::Failed {
        bail!(
            "no flight starts from the trim at Mach {mach}, {altitude_m} m: it failed ({})",
            result.notes.join("; ")
        );
    }
    let t = &result.trim;
    let controls = FlightControls {
        elevon: ElevonCommand {
            symmetric_rad: t.elevon_deg.to_radians(),
            differential_rad: 0.0,
        },
        fuel_equivalence_ratio: t.fuel_equivalence_ratio,
    };
    let (state, _) = vehicle.steady_flight_state(
        mach,
        altitude_m,
        t.alpha_deg.to_radians(),
        t.flight_path_angle_deg.to_radians(),
        &controls,
    )?;
    Ok(LevelTrim {
        result,
        controls,
        state,
    })
}
