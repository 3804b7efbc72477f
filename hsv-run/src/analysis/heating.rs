//! A lifting surface heating in steady flow: the aerothermal half of a lifting-surface region
//! run on its own (paper §IV.D heats the surface at 10 km for up to 100 s before flutter).
//!
//! The surface is rigid and undeflected, so one aero evaluation gives the edge states for the
//! whole run; the heat flux is re-evaluated from the current wall temperatures every
//! `flux_every` conduction steps (paper Table 3: aerothermal 10 ms, heat transfer 1 ms) and the
//! conduction model advances its state, which stays plain data owned here.

use std::time::Instant;

use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::data::{DataError, DataManager, DataManagerBuilder, Publisher};
use hsv_core::flow::FlightCondition;
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry};
use hsv_core::thermal::{ConductionModel, HeatFluxModel};
use nalgebra::DVector;

use crate::vehicle::regions::thermal::SurfaceThermal;
use crate::vehicle::{AssemblyError, Region, RegionDiagnostics, RegionError};

/// The models of a heating run, by registered name.
#[derive(Debug, Clone, PartialEq)]
pub struct HeatingModels {
    pub aero: String,
    pub heat_flux: String,
    pub conduction: String,
}

/// Time stepping of a heating run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatingSteps {
    /// Conduction step, s.
    pub dt_s: f64,
    /// Conduction steps between heat-flux updates (≥ 1).
    pub flux_every: usize,
    /// Uniform initial temperature, K.
    pub initial_k: f64,
}

/// One lifting surface heating in a steady flow (module docs): the surface thermal region the
/// flight heats its surfaces with ([`SurfaceThermal`]), driven by one steady flow.
pub struct SurfaceHeating {
    region: RegionInfo,
    models: HeatingModels,
    flight: FlightCondition,
    edge: AeroSolution,
    thermal: SurfaceThermal,
    steps: HeatingSteps,
    step: usize,
    temperatures: Option<Publisher<Vec<f64>>>,
    diagnostics: RegionDiagnostics,
}

/// Builds model `name` of role `M` for `region`, naming the region on failure.
fn build<M: ?Sized + hsv_core::registry::RoleModel>(
    region: &RegionInfo,
    registry: &Registry,
    name: &str,
) -> Result<Box<M>, AssemblyError> {
    let settings = region.model_settings(name);
    registry
        .create::<M>(name, &ModelContext::new(region, registry, &settings))
        .map_err(|e| AssemblyError::Model {
            file: region.file.clone(),
            region: region.name.clone(),
            cause: Box::new(e),
        })
}

impl SurfaceHeating {
    /// Builds the models by name for `region`, evaluates the edge states once and starts from a
    /// uniform temperature.
    pub fn new(
        region: RegionInfo,
        registry: &Registry,
        models: HeatingModels,
        flight: FlightCondition,
        steps: HeatingSteps,
    ) -> Result<Self, AssemblyError> {
        let mut aero: Box<dyn AeroModel> = build(&region, registry, &models.aero)?;
        let heat_flux: Box<dyn HeatFluxModel> = build(&region, registry, &models.heat_flux)?;
        let conduction: Box<dyn ConductionModel> = build(&region, registry, &models.conduction)?;
        let model_error = |e: hsv_core::ModelError| AssemblyError::Model {
            file: region.file.clone(),
            region: region.name.clone(),
            cause: Box::new(e),
        };
        let n_panels = region.mesh.panels.len();
        let mut thermal =
            SurfaceThermal::new(heat_flux, conduction, n_panels).map_err(model_error)?;
        let mut edge = AeroSolution::default();
        aero.evaluate(&region.mesh, &flight, &PanelMotion::default(), &mut edge)
            .map_err(model_error)?;
        thermal.start(steps.initial_k).map_err(model_error)?;
        Ok(Self {
            region,
            models,
            flight,
            edge,
            thermal,
            steps: HeatingSteps {
                flux_every: steps.flux_every.max(1),
                ..steps
            },
            step: 0,
            temperatures: None,
            diagnostics: RegionDiagnostics::default(),
        })
    }

    /// Advances one conduction step of `dt_s` (the run's step, or a shorter last one),
    /// updating the heat flux first when it is due. On failure the state is the last good one.
    pub fn advance(&mut self, dt_s: f64) -> Result<(), RegionError> {
        let start = Instant::now();
        if self.step.is_multiple_of(self.steps.flux_every) {
            self.thermal
                .update_heat_flux(&self.region.mesh, &self.flight, &self.edge)
                .map_err(|e| self.error(&self.models.heat_flux, e))?;
            self.diagnostics.evaluations += 1;
        }
        self.thermal
            .step(dt_s, None)
            .map_err(|e| self.error(&self.models.conduction, e))?;
        self.step += 1;
        self.diagnostics.steps += 1;
        self.diagnostics.wall_time_s += start.elapsed().as_secs_f64();
        Ok(())
    }

    fn error(&self, model: &str, e: hsv_core::ModelError) -> RegionError {
        RegionError {
            region: self.region.name.clone(),
            time_s: self.thermal.time_s(),
            message: format!("`{model}`: {e}"),
        }
    }

    /// Time in the flow, s.
    pub fn time_s(&self) -> f64 {
        self.thermal.time_s()
    }

    /// The region this run heats.
    pub fn region(&self) -> &RegionInfo {
        &self.region
    }

    pub fn flight(&self) -> &FlightCondition {
        &self.flight
    }

    /// The conduction model (its size, grid).
    pub fn conduction(&self) -> &dyn ConductionModel {
        self.thermal.conduction()
    }

    /// The conduction state.
    pub fn state(&self) -> &DVector<f64> {
        self.thermal.state()
    }

    /// Structure node temperatures of the current state, K.
    pub fn node_temperatures_k(&mut self) -> &[f64] {
        self.thermal.node_temperatures_k()
    }

    /// Wall temperature of each panel of the current state, K.
    pub fn wall_temperatures_k(&mut self) -> &[f64] {
        self.thermal.wall_temperatures_k()
    }

    /// Where the one aero evaluation of the edge states left its model's range (counts).
    pub fn aero_diagnostics(&self) -> &hsv_core::aero::AeroDiagnostics {
        &self.edge.diagnostics
    }

    /// The heat flux of the latest update, W/m² per panel.
    pub fn heat_flux_w_m2(&self) -> &[f64] {
        self.thermal.heat_flux_w_m2()
    }
}

impl Region for SurfaceHeating {
    fn name(&self) -> &str {
        &self.region.name
    }

    /// Publishes the structure node temperatures every conduction step.
    fn declare(&mut self, data: &mut DataManagerBuilder) -> Result<(), DataError> {
        let topic = format!("{}.structure_temperatures_k", self.region.name);
        self.temperatures =
            Some(data.publish_with_rate(&self.region.name, &topic, self.steps.dt_s)?);
        Ok(())
    }

    fn step_to(&mut self, time_s: f64, data: &mut DataManager) -> Result<(), RegionError> {
        // Steps end exactly at `time_s`: the last one is shortened when needed.
        while time_s - self.time_s() > 1e-9 * self.steps.dt_s {
            let dt = self.steps.dt_s.min(time_s - self.time_s());
            self.advance(dt)?;
        }
        if let Some(topic) = self.temperatures {
            let time_s = self.thermal.time_s();
            let node_k = self.thermal.node_temperatures_k();
            data.publish_with(topic, time_s, |v: &mut Vec<f64>| {
                v.clear();
                v.extend_from_slice(node_k);
            })
            .and_then(|_| data.mark_converged(topic).map(|_| ()))
            .map_err(|e| RegionError {
                region: self.region.name.clone(),
                time_s,
                message: e.to_string(),
            })?;
        }
        Ok(())
    }

    fn diagnostics(&self) -> RegionDiagnostics {
        self.diagnostics.clone()
    }
}
