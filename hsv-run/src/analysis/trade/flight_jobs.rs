//! The trim and simulate jobs of a trade study: the rigid vehicle trimmed for level flight, and
//! the partitioned flexible vehicle trimmed and flown under the config's inputs.

use std::collections::BTreeMap;

use anyhow::{Result, bail};
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;

use super::{CaseResult, HISTORY_CHANNELS, StudySpec};
use crate::analysis::simulate::{Inputs, RunSettings, simulate};
use crate::analysis::trim::{TrimRequest, trim};
use crate::dynamics::GravityModel;
use crate::vehicle::assemble;
use crate::vehicle::partitioned::{
    CouplingSettings, ElevonCommand, FlightControls, PartitionedVehicle, partitioned_needs,
};
use crate::vehicle::rigid::{RigidVehicle, rigid_needs};

fn request(spec: &StudySpec) -> TrimRequest {
    TrimRequest {
        mach: spec.mach,
        altitude_m: spec.altitude_m,
        ..TrimRequest::default()
    }
}

/// Rigid trim: α, δe, φ, thrust and drag.
pub(super) fn trim_case(
    spec: &StudySpec,
    loaded: &LoadedConfig,
    registry: &Registry,
    out: &mut CaseResult,
) -> Result<()> {
    let sets = assemble(loaded, registry, &rigid_needs("trade study trim"))?;
    let mut vehicle = RigidVehicle::new(sets)?;
    let t = trim(&mut vehicle, &request(spec))?.trim;
    out.values = BTreeMap::from([
        ("alpha_deg".to_owned(), t.alpha_deg),
        ("elevon_deg".to_owned(), t.elevon_deg),
        (
            "fuel_equivalence_ratio".to_owned(),
            t.fuel_equivalence_ratio,
        ),
        ("thrust_n".to_owned(), t.loads.thrust_n),
        ("drag_n".to_owned(), t.loads.drag_n),
    ]);
    Ok(())
}

/// The partitioned vehicle trimmed and flown under `inputs`, as `hsv-run simulate` does.
pub(super) fn simulate_case(
    spec: &StudySpec,
    loaded: &LoadedConfig,
    registry: &Registry,
    inputs: &Inputs,
    out: &mut CaseResult,
) -> Result<()> {
    let Some(flight) = spec.flight else {
        bail!("a simulate study needs its flight duration and step");
    };
    let sets = assemble(loaded, registry, &partitioned_needs("trade study flight"))?;
    let mut vehicle =
        PartitionedVehicle::new(sets, GravityModel::default(), CouplingSettings::default())?;
    let t = trim(&mut vehicle, &request(spec))?.trim;
    let controls = FlightControls {
        elevon: ElevonCommand {
            symmetric_rad: t.elevon_deg.to_radians(),
            differential_rad: 0.0,
        },
        fuel_equivalence_ratio: t.fuel_equivalence_ratio,
    };
    let (mut state, _) = vehicle.level_flight_state(
        spec.mach,
        spec.altitude_m,
        t.alpha_deg.to_radians(),
        &controls,
    )?;
    let settings = RunSettings {
        dt_s: flight.dt_s,
        integrator: crate::analysis::simulate::Integrator::default(),
        duration_s: flight.duration_s,
        record_every: flight.record_every.max(1),
        start_step: 0,
    };
    let mut history: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let mut control =
        crate::control::ControlLoop::schedule(inputs.clone(), &controls, flight.dt_s)?;
    simulate(
        &mut vehicle,
        &mut state,
        &mut control,
        &settings,
        |s, _, _| {
            for (name, value) in [
                ("time_s", s.time_s),
                ("altitude_m", s.altitude_m),
                ("airspeed_m_s", s.airspeed_m_s),
                ("alpha_deg", s.alpha_deg),
                ("pitch_deg", s.pitch_deg),
                ("q_deg_s", s.q_deg_s),
            ] {
                history.entry(name.to_owned()).or_default().push(value);
            }
            true
        },
    )?;
    out.values = BTreeMap::from([
        ("trim_alpha_deg".to_owned(), t.alpha_deg),
        ("trim_elevon_deg".to_owned(), t.elevon_deg),
        (
            "trim_fuel_equivalence_ratio".to_owned(),
            t.fuel_equivalence_ratio,
        ),
    ]);
    for channel in HISTORY_CHANNELS {
        if let Some(last) = history.get(channel).and_then(|h| h.last()) {
            out.values.insert(format!("final_{channel}"), *last);
        }
    }
    out.history = history;
    Ok(())
}
