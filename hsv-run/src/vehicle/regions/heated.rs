//! The heated lifting surfaces: each surface's thermal region ([`super::thermal`]: the heat flux
//! from its aero at the accepted state, the conduction under it) and its structure's stiffness
//! from the temperature field (paper §III.B, Table 3). Each publishes `<surface>/wall_heat_flux`
//! (every aerothermal interval, 10 ms) and `<surface>/structure_temperatures` (every stiffness
//! interval); its conduction reads the flux, its structure the temperatures.

use hsv_core::ModelError;
use hsv_core::aero::ModalHistory;
use hsv_core::coupling::ElevonCommand;
use hsv_core::flow::FlightCondition;
use hsv_core::structure::StructureModel;
use nalgebra::DVector;

use super::surface::{Surface, surface_aero};
use crate::vehicle::AssemblyError;
use crate::vehicle::error::{VehicleError, assembly_error, model_error};
use crate::vehicle::region_rate::RegionExchange;

/// Rates of the in-flight heating (paper Table 3). In a restart file its fields are keys of
/// the vehicle's own ([`crate::vehicle::partitioned::VehicleRestart`]), prefixed `heating_`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HeatingRates {
    /// Conduction step, s (paper: heat transfer 1 ms).
    #[serde(rename = "heating_conduction_s")]
    pub conduction_s: f64,
    /// Interval between heat-flux updates, s (paper: aerothermal 10 ms); the flux is refreshed
    /// at the start of the step where it falls due, from the accepted state.
    #[serde(rename = "heating_heat_flux_s")]
    pub heat_flux_s: f64,
    /// Interval between stiffness updates from the temperature field, s (our choice).
    #[serde(rename = "heating_stiffness_s")]
    pub stiffness_s: f64,
    /// Initial uniform temperature, K (paper: 293 K).
    #[serde(rename = "heating_initial_k")]
    pub initial_k: f64,
}

impl Default for HeatingRates {
    fn default() -> Self {
        Self {
            conduction_s: 1e-3,
            heat_flux_s: 1e-2,
            stiffness_s: 0.1,
            initial_k: 293.0,
        }
    }
}

/// One surface heating in flight: its thermal region ([`super::thermal`]: the heat
/// flux from its latest aero solution, published on its `wall_heat_flux` topic, and the
/// conduction under it) and the structure's stiffness updated from the temperature field.
pub(in crate::vehicle) struct HeatedSurface {
    pub(in crate::vehicle) region: crate::vehicle::regions::thermal::SurfaceThermal,
    /// The temperature field moved onto the structure's nodes (last stiffness update).
    pub(in crate::vehicle) onto_structure: hsv_core::coupling::StructureTemperatures,
    /// Time of the last stiffness update, s.
    pub(in crate::vehicle) stiffness_time_s: f64,
    /// Set when the field was moved onto the structure again: it is published on the
    /// surface's `structure_temperatures` topic, the structure reads it into its stiffness and
    /// the vehicle's modal matrices follow.
    pub(in crate::vehicle) stiffness_changed: bool,
}

/// One heated surface's thermal state: its conduction state and the field its structure's
/// stiffness was last updated from.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ThermalRestart {
    pub state: DVector<f64>,
    pub structure_k: Vec<f64>,
    pub structure_difference_k: Vec<f64>,
    pub conduction_time_s: f64,
    pub stiffness_time_s: f64,
}

impl HeatedSurface {
    /// The thermal region's conduction state and the field the structure last read.
    pub(in crate::vehicle) fn saved(&self) -> ThermalRestart {
        ThermalRestart {
            state: self.region.state().clone(),
            structure_k: self.onto_structure.mean_k.clone(),
            structure_difference_k: self.onto_structure.difference_k.clone(),
            conduction_time_s: self.region.time_s(),
            stiffness_time_s: self.stiffness_time_s,
        }
    }

    /// Continues from `saved`; whether the structure's stiffness must be set from its field
    /// again (it had been heated).
    pub(in crate::vehicle) fn restore(
        &mut self,
        saved: &ThermalRestart,
    ) -> Result<bool, ModelError> {
        self.region.restore(&saved.state, saved.conduction_time_s)?;
        self.onto_structure.mean_k.clone_from(&saved.structure_k);
        self.onto_structure
            .difference_k
            .clone_from(&saved.structure_difference_k);
        self.stiffness_time_s = saved.stiffness_time_s;
        Ok(self.stiffness_time_s > 0.0)
    }
}

/// A surface's thermal model, with the transfer of its conduction nodes onto the structure's
/// temperature grid (mirrored when the structure keeps the other side's grid).
pub(in crate::vehicle) fn surface_thermal(
    name: &str,
    heat_flux: Box<dyn hsv_core::thermal::HeatFluxModel>,
    conduction: Box<dyn hsv_core::thermal::ConductionModel>,
    structure: &dyn StructureModel,
    n_panels: usize,
) -> Result<HeatedSurface, AssemblyError> {
    let thermal = structure
        .thermal_stiffness()
        .ok_or_else(|| assembly_error(name, "temperature-dependent stiffness".into()))?;
    let onto_structure =
        hsv_core::coupling::StructureTemperatures::new(conduction.as_ref(), thermal).map_err(
            |e| assembly_error(name, format!("conduction `{}`: {e}", conduction.name())),
        )?;
    let model = conduction.name().to_owned();
    let region =
        crate::vehicle::regions::thermal::SurfaceThermal::new(heat_flux, conduction, n_panels)
            .map_err(|e| assembly_error(name, format!("conduction `{model}`: {e}")))?;
    Ok(HeatedSurface {
        region,
        onto_structure,
        stiffness_time_s: 0.0,
        stiffness_changed: false,
    })
}

/// Whether the heat flux, last published at `last_s` (None: never), is due again at `time_s`
/// (every heat-flux interval).
pub(in crate::vehicle) fn heat_flux_due(
    last_s: Option<f64>,
    time_s: f64,
    rates: &HeatingRates,
) -> bool {
    last_s.is_none_or(|last| time_s - last >= rates.heat_flux_s - 1e-12)
}

/// One heated surface's heat flux at `time_s` from its aero at the accepted state (the
/// surface's modes, the body's, the elevon and its flight condition), into its buffer for the
/// vehicle to publish. The aero is evaluated here unless `aero_current` (the step's start has
/// just evaluated the surface at this state), never read from the last derivative: inside a step
/// that is the last Runge-Kutta stage's predictor, not a state the flight passes through.
pub(in crate::vehicle) fn refresh_heat_flux(
    s: &mut Surface,
    modes: (&crate::dynamics::ModalState, &crate::dynamics::ModalState),
    elevon: &ElevonCommand,
    flight: &FlightCondition,
    (time_s, history, aero_current): (f64, Option<&ModalHistory>, bool),
) -> Result<(), VehicleError> {
    if s.thermal.is_none() {
        return Ok(());
    }
    if !aero_current {
        // The panel solution only: the step's first stage evaluates the loads at this state.
        surface_aero(s, modes, elevon, flight, (time_s, history))?;
    }
    let err = model_error(&s.name);
    let Some(t) = &mut s.thermal else {
        return Ok(());
    };
    t.region
        .update_heat_flux(&s.deflected, flight, &s.solution)
        .map_err(&err)?;
    Ok(())
}

/// Surface `index`'s thermal region up to `time_s`: conduction steps under the heat flux it last
/// published (`exchange`, [`refresh_heat_flux`] at the steps' starts), and at the stiffness
/// rate the temperature field moved onto the structure's nodes (flagged to be published on its
/// `structure_temperatures` topic, which the structure reads: [`read_structure_temperatures`]).
pub(in crate::vehicle) fn heat_surface(
    s: &mut Surface,
    exchange: &RegionExchange,
    index: usize,
    time_s: f64,
    rates: &HeatingRates,
) -> Result<(), VehicleError> {
    let Some(t) = &mut s.thermal else {
        return Ok(());
    };
    let err = model_error(&s.name);
    // Read in place from its topic (before any refresh: the zero flux the region starts with).
    let flux = exchange.heat_flux(index)?;
    let stepped = t
        .region
        .advance_to(time_s, rates.conduction_s, flux)
        .map_err(&err)?;
    if stepped && time_s - t.stiffness_time_s >= rates.stiffness_s - 1e-12 {
        t.onto_structure
            .update(t.region.conduction(), t.region.state())
            .map_err(|e| {
                err(ModelError::inconsistent(
                    "temperature transfer",
                    e.to_string(),
                ))
            })?;
        t.stiffness_changed = true;
        t.stiffness_time_s = time_s;
    }
    Ok(())
}

/// Surface `index`'s structure takes the temperatures its thermal region published
/// (`exchange`), when it published new ones: its temperature-dependent stiffness.
pub(in crate::vehicle) fn read_structure_temperatures(
    s: &mut Surface,
    exchange: &RegionExchange,
    index: usize,
) -> Result<(), VehicleError> {
    let Some(t) = &s.thermal else {
        return Ok(());
    };
    if !t.stiffness_changed {
        return Ok(());
    }
    let err = model_error(&s.name);
    if let (Some((_, temperatures)), Some(thermal)) = (
        exchange.structure_temperatures(index)?,
        s.structure.thermal_stiffness_mut(),
    ) {
        thermal
            .set_temperature_field(&temperatures.mean_k, &temperatures.difference_k)
            .map_err(&err)?;
    }
    Ok(())
}
