//! The propulsion role: engine forces, moments and the pressures it puts on the body underside.

use crate::aero::Loads;
use crate::error::ModelError;
use crate::flow::FlightCondition;
use crate::mesh::PanelMesh;

/// How the engine is operating; anything but `Ok` is reported to the user with the numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum EngineStatus {
    #[default]
    Ok,
    /// The ramp shock misses the cowl lip: part of the captured stream tube spills.
    Spillage,
    /// Heat addition exceeds what the combustor flow can take at its entry Mach number.
    ThermalChoking,
    /// The inlet cannot swallow its shock system (flow goes subsonic upstream of the isolator).
    Unstart,
}

/// Flow state at a named engine station (inlet, combustor entry/exit, nozzle exit).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StationState {
    pub station: String,
    pub mach: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
}

/// Output of one engine evaluation; buffers are reused between evaluations.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PropulsionSolution {
    /// Engine force and moment on the vehicle (flow path and engine-owned external surfaces),
    /// body axes, moment about the body reference point.
    pub loads: Loads,
    /// Air mass flow captured by the inlet, kg/s.
    pub mass_flow_kg_s: f64,
    pub status: EngineStatus,
    /// Absolute pressure on each panel of the body mesh the engine owns (region
    /// `Propulsion`), Pa; other entries are the freestream pressure.
    pub panel_pressure_pa: Vec<f64>,
    pub stations: Vec<StationState>,
}

/// Inputs to an engine evaluation.
#[derive(Debug, Clone, Copy)]
pub struct EngineInputs<'a> {
    pub flight: &'a FlightCondition,
    /// The (deformed) body mesh; the engine reads its ramp and nozzle geometry from the panels
    /// tagged `Propulsion`.
    pub body: &'a PanelMesh,
    /// Fuel equivalence ratio φ (1 = stoichiometric).
    pub fuel_equivalence_ratio: f64,
}

/// A propulsion model.
pub trait PropulsionModel: Send {
    /// The registered name (`scramjet-1d`, `scramjet-q1d`, ...).
    fn name(&self) -> &str;

    /// Engine loads, captured mass flow, status, station states and owned-surface pressures.
    fn evaluate(
        &mut self,
        inputs: &EngineInputs<'_>,
        out: &mut PropulsionSolution,
    ) -> Result<(), ModelError>;
}
