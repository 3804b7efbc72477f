//! The vehicle's own state in a restart file and its restoration (`--resume`, bit for bit).

use super::*;

impl PartitionedVehicle {
    /// The vehicle's own state for a restart file ([`VehicleRestart`]).
    pub fn restart(&self) -> VehicleRestart {
        VehicleRestart {
            time_s: self.time_s,
            q_ddot: self.q_ddot.clone(),
            root_force_n: self.surfaces.iter().map(|s| s.root_force_n).collect(),
            thermal: self
                .surfaces
                .iter()
                .map(|s| {
                    s.thermal.as_ref().map(|t| ThermalRestart {
                        state: t.region.state().clone(),
                        structure_k: t.onto_structure.mean_k.clone(),
                        structure_difference_k: t.onto_structure.difference_k.clone(),
                        conduction_time_s: t.region.time_s(),
                        stiffness_time_s: t.stiffness_time_s,
                    })
                })
                .collect(),
            histories: self.surfaces.iter().map(|s| s.history.clone()).collect(),
            heating_conduction_s: self.heating.conduction_s,
            heating_heat_flux_s: self.heating.heat_flux_s,
            heating_stiffness_s: self.heating.stiffness_s,
            heating_initial_k: self.heating.initial_k,
            region_loads: self.exchange.checkpoint(),
            body_q_ddot: self.body_q_ddot.clone(),
            coupling: self.report,
        }
    }

    /// Restores the vehicle's own state from a restart file: the surfaces' stiffness is set from
    /// the saved temperature field again, so the modal matrices are those of the run.
    pub fn restore(&mut self, r: &VehicleRestart) -> Result<(), VehicleError> {
        let n = self.surfaces.len();
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
        for (what, len) in [
            ("coupling accelerations", r.q_ddot.len()),
            ("root forces", r.root_force_n.len()),
            ("thermal states", r.thermal.len()),
            ("modal histories", r.histories.len()),
        ] {
            if len != n {
                return Err(VehicleError::Input(format!(
                    "restart file: {len} {what} for a vehicle of {n} lifting surfaces"
                )));
            }
        }
        let n_body = self.body_q_ddot.len();
        let len = r.body_q_ddot.len();
        if len != 0 && len != n_body {
            return Err(VehicleError::Input(format!(
                "restart file: {len} body modal accelerations for a body of {n_body} modes"
            )));
        }
        self.time_s = r.time_s;
        self.report = r.coupling;
        self.heating = HeatingRates {
            conduction_s: r.heating_conduction_s,
            heat_flux_s: r.heating_heat_flux_s,
            stiffness_s: r.heating_stiffness_s,
            initial_k: r.heating_initial_k,
        };
        // The exchange declares the heat flux's interval: at the run's, then its state.
        self.rebuild_exchange()?;
        self.exchange.restore(&r.region_loads)?;
        self.stage_one = None;
        self.q_ddot.clone_from(&r.q_ddot);
        if r.body_q_ddot.is_empty() {
            self.body_q_ddot.fill(0.0);
        } else {
            self.body_q_ddot.copy_from(&r.body_q_ddot);
        }
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            s.root_force_n = r.root_force_n[i];
            s.history.clone_from(&r.histories[i]);
            match (&mut s.thermal, &r.thermal[i]) {
                (Some(t), Some(saved)) => {
                    if saved.state.len() != t.region.state().len() {
                        return Err(VehicleError::Input(format!(
                            "restart file: {} thermal states for `{}`, whose conduction model has {}",
                            saved.state.len(),
                            s.name,
                            t.region.state().len()
                        )));
                    }
                    t.region
                        .restore(&saved.state, saved.conduction_time_s)
                        .map_err(model_error(&s.name))?;
                    t.onto_structure.mean_k.clone_from(&saved.structure_k);
                    t.onto_structure
                        .difference_k
                        .clone_from(&saved.structure_difference_k);
                    t.stiffness_time_s = saved.stiffness_time_s;
                    if t.stiffness_time_s > 0.0 {
                        if let Some(thermal) = s.structure.thermal_stiffness_mut() {
                            t.onto_structure
                                .apply(thermal)
                                .map_err(model_error(&s.name))?;
                        }
                        self.dynamics
                            .set_surface_matrices(i, s.structure.modal_model())?;
                    }
                }
                (None, None) => {}
                _ => {
                    return Err(VehicleError::Input(format!(
                        "restart file: `{}` heats in one run and not in the other",
                        s.name
                    )));
                }
            }
        }
        Ok(())
    }
}
