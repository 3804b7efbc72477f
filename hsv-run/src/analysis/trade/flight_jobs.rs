//! The trim and simulate jobs of a trade study: the rigid vehicle trimmed for level flight, and
//! the partitioned flexible vehicle trimmed and flown as `hsv-run simulate` flies it.

use std::collections::BTreeMap;

use anyhow::{Result, bail};
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;

use super::{CaseResult, HISTORY_CHANNELS, StudySpec};
use crate::analysis::flight::{Flight, FlightOptions};
use crate::analysis::trim::{TrimRequest, trim};
use crate::vehicle::assemble;
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
        ("flight_path_angle_deg".to_owned(), t.flight_path_angle_deg),
        ("thrust_n".to_owned(), t.loads.thrust_n),
        ("drag_n".to_owned(), t.loads.drag_n),
    ]);
    Ok(())
}

/// The partitioned vehicle trimmed and flown as `hsv-run simulate` flies it (one setup,
/// `analysis::flight::Flight`: the config's controller, integrator, body rates and in-flight
/// heating), at the study's Mach and altitude.
pub(super) fn simulate_case(
    spec: &StudySpec,
    loaded: &LoadedConfig,
    registry: &Registry,
    out: &mut CaseResult,
) -> Result<()> {
    let Some(flight_spec) = spec.flight else {
        bail!("a simulate study needs its flight duration and step");
    };
    let mut loaded = loaded.clone();
    loaded.config.flight.mach = spec.mach;
    loaded.config.flight.altitude_m = spec.altitude_m;
    let options = FlightOptions {
        controller: Some(crate::analysis::control::control_settings(&loaded, None)?.0),
        dt_s: flight_spec.dt_s,
        ..FlightOptions::default()
    };
    let mut flight = Flight::trimmed(&loaded, registry, &options, |_| {})?;
    let mut history: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    flight.fly(
        flight_spec.duration_s,
        flight_spec.record_every,
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
    let t = &flight.trim.result.trim;
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
