//! The surface thermal region: one heated lifting surface's aerothermal model (the wall heat
//! flux from an aero solution at the current wall temperatures) and its conduction state
//! advanced to a time under a flux (paper §III.B; Table 3: heat transfer 1 ms, aerothermal
//! 10 ms).
//!
//! One component, two drivers: the flight heats each surface with one, its flux computed from
//! the accepted state's aero and published on the surface's `wall_heat_flux` topic
//! ([`super::heated`], [`crate::vehicle::partitioned`]); the standalone heating run on a fixed flow (`hsv-run heat`, the
//! flutter march: [`crate::analysis::heating::SurfaceHeating`]) drives one from its steady edge
//! states. Its state is plain data: the conduction state and the time it has reached.

use hsv_core::ModelError;
use hsv_core::aero::AeroSolution;
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::PanelMesh;
use hsv_core::thermal::{ConductionModel, HeatFluxModel};
use nalgebra::DVector;

/// One surface's heat flux and conduction (module docs).
pub struct SurfaceThermal {
    heat_flux: Box<dyn HeatFluxModel>,
    conduction: Box<dyn ConductionModel>,
    /// The conduction state: simulation state of the region (temperatures or POD
    /// coefficients).
    state: DVector<f64>,
    /// The step's scratch state ([`ConductionModel::advance`]).
    trial: DVector<f64>,
    wall_k: Vec<f64>,
    /// The wall heat flux of the last update, W/m² per panel.
    flux_w_m2: Vec<f64>,
    node_k: Vec<f64>,
    /// Time up to which the conduction has been stepped, s.
    time_s: f64,
}

impl SurfaceThermal {
    /// The models of a surface whose mesh has `n_panels` panels (the conduction model must take
    /// that many), at zero state; [`Self::start`] sets the initial temperature.
    pub fn new(
        heat_flux: Box<dyn HeatFluxModel>,
        conduction: Box<dyn ConductionModel>,
        n_panels: usize,
    ) -> Result<Self, ModelError> {
        if conduction.n_surface_panels() != n_panels {
            return Err(ModelError::inconsistent(
                conduction.name(),
                format!(
                    "takes {} surface panels, the region's mesh has {n_panels}",
                    conduction.n_surface_panels()
                ),
            ));
        }
        let n_states = conduction.n_states();
        let n_nodes = conduction.n_nodes();
        Ok(Self {
            heat_flux,
            conduction,
            state: DVector::zeros(n_states),
            trial: DVector::zeros(n_states),
            wall_k: vec![0.0; n_panels],
            flux_w_m2: vec![0.0; n_panels],
            node_k: vec![0.0; n_nodes],
            time_s: 0.0,
        })
    }

    /// Starts at a uniform `initial_k` (K) at t = 0.
    pub fn start(&mut self, initial_k: f64) -> Result<(), ModelError> {
        self.state = self.conduction.uniform_state(initial_k)?;
        self.trial.clone_from(&self.state);
        self.time_s = 0.0;
        Ok(())
    }

    /// The wall heat flux of `solution` on `mesh` in `flight` at the current wall temperatures,
    /// into the region's flux ([`Self::heat_flux_w_m2`]).
    pub fn update_heat_flux(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        solution: &AeroSolution,
    ) -> Result<(), ModelError> {
        self.conduction
            .surface_temperatures(&self.state, &mut self.wall_k);
        self.heat_flux
            .heat_flux(mesh, flight, solution, &self.wall_k, &mut self.flux_w_m2)
    }

    /// One conduction step of `dt_s` (s) under `flux` (W/m² per panel; the region's own latest
    /// flux when `None`). On failure the state is the last good one.
    pub fn step(&mut self, dt_s: f64, flux: Option<&[f64]>) -> Result<(), ModelError> {
        let flux = flux.unwrap_or(&self.flux_w_m2);
        self.conduction
            .advance(&mut self.state, &mut self.trial, flux, dt_s)?;
        self.time_s += dt_s;
        Ok(())
    }

    /// Conduction steps of `dt_s` (the last one shortened to end exactly there) up to `time_s`
    /// under `flux` (as [`Self::step`]); whether any step was taken.
    pub fn advance_to(
        &mut self,
        time_s: f64,
        dt_s: f64,
        flux: Option<&[f64]>,
    ) -> Result<bool, ModelError> {
        let mut stepped = false;
        while time_s - self.time_s > 1e-9 * dt_s {
            let dt = dt_s.min(time_s - self.time_s);
            self.step(dt, flux)?;
            stepped = true;
        }
        Ok(stepped)
    }

    /// Time up to which the conduction has been stepped, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// The conduction state.
    pub fn state(&self) -> &DVector<f64> {
        &self.state
    }

    /// Continues from a saved `state` reached at `time_s` (a restart); the state must have the
    /// model's size.
    pub fn restore(&mut self, state: &DVector<f64>, time_s: f64) -> Result<(), ModelError> {
        if state.len() != self.state.len() {
            return Err(ModelError::inconsistent(
                self.conduction.name(),
                format!(
                    "a saved state of {} values for a model of {}",
                    state.len(),
                    self.state.len()
                ),
            ));
        }
        self.state.clone_from(state);
        self.time_s = time_s;
        Ok(())
    }

    /// The conduction model (its size, grid, transfers).
    pub fn conduction(&self) -> &dyn ConductionModel {
        self.conduction.as_ref()
    }

    /// The wall heat flux of the last update, W/m² per panel.
    pub fn heat_flux_w_m2(&self) -> &[f64] {
        &self.flux_w_m2
    }

    /// Structure node temperatures of the current state, K.
    pub fn node_temperatures_k(&mut self) -> &[f64] {
        self.conduction
            .node_temperatures(&self.state, &mut self.node_k);
        &self.node_k
    }

    /// Wall temperature of each panel of the current state, K.
    pub fn wall_temperatures_k(&mut self) -> &[f64] {
        self.conduction
            .surface_temperatures(&self.state, &mut self.wall_k);
        &self.wall_k
    }
}
