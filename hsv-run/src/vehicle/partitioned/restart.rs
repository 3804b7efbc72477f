//! The vehicle's own state in a restart file and its restoration (`--resume`, bit for bit): its
//! memory whole ([`VehicleMemory`]), each heated surface's thermal state, the heating's rates
//! and the data manager's checkpoint.

use super::*;

/// What the vehicle itself carries from one derivative and one step to the next, beyond the
/// integrated [`VehicleState`]: the time, the coupling iteration's guesses (each surface's q̈,
/// the body's η̈) and references (root forces, the last report), and the surfaces' modal
/// histories (aero models with memory). Plain data held as one value by the vehicle, saved and
/// restored whole; the thermal regions and the data manager keep theirs (in
/// [`VehicleRestart`] beside it).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct VehicleMemory {
    /// Simulation time of the next derivative, s (models with memory, the wind field).
    pub time_s: f64,
    /// Surface modal accelerations: the coupling's unknown, kept from the last derivative as
    /// the next guess.
    pub q_ddot: Vec<DVector<f64>>,
    /// Each surface's root force at the last coupling iteration, N (the residual's reference).
    pub root_force_n: Vec<Vector3<f64>>,
    /// The modal history of each surface's aero model with memory (`None` for the others).
    pub histories: Vec<Option<ModalHistory>>,
    /// The last coupling iteration's report (the first sample of a continued run shows it;
    /// absent in older restart files).
    #[serde(default)]
    pub coupling: CouplingReport,
    /// The body's η̈, the interface's other unknown (absent in restart files from before the
    /// two-way interface: zeros).
    #[serde(default)]
    pub body_q_ddot: DVector<f64>,
}

/// Everything of the vehicle, beyond its [`VehicleState`], that the next step depends on: its
/// own memory, the surfaces' thermal states, the heating's rates and the regions' publications
/// in the data manager. With it a run continues bit for bit. Its keys are flat (one JSON object).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct VehicleRestart {
    #[serde(flatten)]
    pub memory: VehicleMemory,
    pub thermal: Vec<Option<ThermalRestart>>,
    #[serde(flatten)]
    pub heating: HeatingRates,
    /// The regions' publications at their own rates: the data manager's checkpoint of the
    /// body's and each surface's loads topics and the body's skin friction.
    pub region_loads: hsv_core::data::DataCheckpoint,
}

impl PartitionedVehicle {
    /// The vehicle's own state for a restart file ([`VehicleRestart`]).
    pub fn restart(&self) -> VehicleRestart {
        VehicleRestart {
            memory: self.memory.clone(),
            thermal: self
                .surfaces
                .iter()
                .map(|s| s.thermal.as_ref().map(HeatedSurface::saved))
                .collect(),
            heating: self.heating,
            region_loads: self.exchange.checkpoint(),
        }
    }

    /// Restores the vehicle's own state from a restart file: the surfaces' stiffness is set from
    /// the saved temperature field again, so the modal matrices are those of the run.
    pub fn restore(&mut self, r: &VehicleRestart) -> Result<(), VehicleError> {
        self.check_restart(r)?;
        let mut memory = r.memory.clone();
        if memory.body_q_ddot.is_empty() {
            // A restart file from before the two-way interface.
            memory.body_q_ddot = DVector::zeros(self.memory.body_q_ddot.len());
        }
        self.memory = memory;
        self.heating = r.heating;
        // The exchange declares the heat flux's interval: at the run's, then its state.
        self.rebuild_exchange()?;
        self.exchange.restore(&r.region_loads)?;
        self.stage_one = None;
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            let (Some(t), Some(saved)) = (&mut s.thermal, &r.thermal[i]) else {
                continue;
            };
            if t.restore(saved).map_err(model_error(&s.name))? {
                if let Some(thermal) = s.structure.thermal_stiffness_mut() {
                    t.onto_structure
                        .apply(thermal)
                        .map_err(model_error(&s.name))?;
                }
                self.dynamics
                    .set_surface_matrices(i, s.structure.modal_model())?;
            }
        }
        Ok(())
    }

    /// Whether `r` fits this vehicle: as many surfaces, modes and thermal states, each surface
    /// heating in both runs or in neither, and no cold state for a heated structure.
    fn check_restart(&self, r: &VehicleRestart) -> Result<(), VehicleError> {
        if self.stiffness_heated()
            && r.thermal
                .iter()
                .flatten()
                .any(|t| t.stiffness_time_s <= 0.0)
        {
            // A heated structure cannot be cooled in place: its models keep no cold matrices.
            return Err(VehicleError::Input(
                "cannot restore a cold-stiffness state into a vehicle whose surfaces' stiffness \
                 has been heated; assemble the vehicle again"
                    .to_owned(),
            ));
        }
        let n = self.surfaces.len();
        let m = &r.memory;
        for (what, len) in [
            ("coupling accelerations", m.q_ddot.len()),
            ("root forces", m.root_force_n.len()),
            ("thermal states", r.thermal.len()),
            ("modal histories", m.histories.len()),
        ] {
            if len != n {
                return Err(VehicleError::Input(format!(
                    "restart file: {len} {what} for a vehicle of {n} lifting surfaces"
                )));
            }
        }
        for (s, (q_ddot, saved)) in self.surfaces.iter().zip(m.q_ddot.iter().zip(&r.thermal)) {
            if q_ddot.len() != s.shapes.n_modes() {
                return Err(VehicleError::Input(format!(
                    "restart file: {} modal accelerations for `{}`, which has {} modes",
                    q_ddot.len(),
                    s.name,
                    s.shapes.n_modes()
                )));
            }
            match (&s.thermal, saved) {
                (Some(t), Some(saved)) if saved.state.len() != t.region.state().len() => {
                    return Err(VehicleError::Input(format!(
                        "restart file: {} thermal states for `{}`, whose conduction model has {}",
                        saved.state.len(),
                        s.name,
                        t.region.state().len()
                    )));
                }
                (Some(_), Some(_)) | (None, None) => {}
                _ => {
                    return Err(VehicleError::Input(format!(
                        "restart file: `{}` heats in one run and not in the other",
                        s.name
                    )));
                }
            }
        }
        let n_body = self.memory.body_q_ddot.len();
        let len = m.body_q_ddot.len();
        if len != 0 && len != n_body {
            return Err(VehicleError::Input(format!(
                "restart file: {len} body modal accelerations for a body of {n_body} modes"
            )));
        }
        Ok(())
    }
}
