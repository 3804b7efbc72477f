//! The regions' publications and the coupling's reads: each region's evaluation published on
//! its topic in the data manager (the body with its engine and followers, the surfaces, the
//! heated surfaces' heat flux), read back by the coupling for the derivative (module docs of
//! [`crate::vehicle::region_rate`]), and the flight condition each surface flies in.

use super::*;

impl PartitionedVehicle {
    /// Publishes the body region's evaluation at `time_s` on its loads topic: its aero and
    /// engine loads (`body_loads`, [`body_region_loads`]) and generalized forces, with those of
    /// the regions that follow the body (evaluated here: the monolithic model's surfaces, the
    /// fin), converged or as an iterate ([`Publication`]).
    pub(super) fn publish_body_region(
        &mut self,
        (body_aero, engine_loads): (Loads, Loads),
        (state, controls, flight): (&VehicleState, &FlightControls, &FlightCondition),
        at: (f64, Publication),
    ) -> Result<(), VehicleError> {
        self.evaluate_followers(state, controls, flight)?;
        let mut total = body_aero + engine_loads;
        let mut aero = body_aero;
        let b = &mut self.body;
        for (k, q) in b.published_generalized.iter_mut().enumerate() {
            // Without an engine its generalized forces are zeros, as they were summed before.
            *q = b.generalized[k] + self.engine.as_ref().map_or(0.0, |e| e.generalized[k]);
        }
        for f in &self.followers {
            total = total + f.loads;
            aero = aero + f.loads;
            for (q, g) in b.published_generalized.iter_mut().zip(&f.generalized) {
                *q += g;
            }
        }
        let generalized = b.published_generalized.as_slice();
        Ok(self.exchange.publish_body(at, &total, &aero, generalized)?)
    }

    /// The surfaces that follow the body (the monolithic model's lifting surfaces, rotated by the
    /// elevon, and the fixed vertical fin): OML following the body's modes whose aero loads go
    /// straight to the body and to its generalized forces.
    pub(super) fn evaluate_followers(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        flight: &FlightCondition,
    ) -> Result<(), VehicleError> {
        let cg = self.mass.center_of_mass_m;
        let elevon = controls.elevon;
        for f in &mut self.followers {
            follower_loads(f, &state.body_modes, &elevon, flight, &cg)?;
        }
        Ok(())
    }

    /// The heated surfaces' heat flux, where due, from their aero at the accepted `state`
    /// (each in its own flight condition, side by side).
    pub(super) fn refresh_heat_fluxes(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        time_s: f64,
        aero_current: bool,
    ) -> Result<(), VehicleError> {
        let rates = self.heating;
        // The heated surfaces' fluxes are refreshed together, from t = 0 on.
        let heated = self.surfaces.iter().any(|s| s.thermal.is_some());
        if !heated || !heat_flux_due(self.exchange.heat_flux_time_s(), time_s, &rates) {
            return Ok(());
        }
        if !aero_current {
            let flight = self.flight(state)?;
            self.update_surface_flights(state, &flight)?;
        }
        let elevon = controls.elevon;
        let body_modes = &state.body_modes;
        let refresh = |(((s, modes), flight), history): (
            (
                (&mut Surface, &crate::dynamics::ModalState),
                &FlightCondition,
            ),
            &Option<ModalHistory>,
        )| {
            refresh_heat_flux(
                s,
                (modes, body_modes),
                &elevon,
                flight,
                (time_s, history.as_ref(), aero_current),
            )
        };
        let histories = &self.memory.histories;
        if side_by_side() {
            self.surfaces
                .par_iter_mut()
                .zip(state.surface_modes.par_iter())
                .zip(self.surface_flights.par_iter())
                .zip(histories.par_iter())
                .try_for_each(refresh)?;
        } else {
            self.surfaces
                .iter_mut()
                .zip(state.surface_modes.iter())
                .zip(self.surface_flights.iter())
                .zip(histories.iter())
                .try_for_each(refresh)?;
        }
        for (index, s) in self.surfaces.iter().enumerate() {
            if let Some(t) = &s.thermal {
                self.exchange
                    .publish_heat_flux(index, time_s, t.region.heat_flux_w_m2())?;
            }
        }
        Ok(())
    }

    /// Each surface's flight condition into `surface_flights`: the wind at its pivot, `lead`
    /// ahead of the centre of mass along the body axis (`flight`, the centre of mass's, when the
    /// air is calm).
    pub(super) fn update_surface_flights(
        &mut self,
        state: &VehicleState,
        flight: &FlightCondition,
    ) -> Result<(), VehicleError> {
        self.surface_flights.clear();
        let cg_x = self.mass.center_of_mass_m.x;
        for i in 0..self.surfaces.len() {
            let f = if self.disturbances.is_calm() {
                *flight
            } else {
                self.flight_at(state, self.surfaces[i].pivot_m.x - cg_x)?
            };
            self.surface_flights.push(f);
        }
        Ok(())
    }

    /// Each surface's loads for this derivative, read from its loads topic by the coupling
    /// (into [`SurfaceRead`] and the vehicle's generalized forces), turned by the stage's elevon
    /// rotation and with the thermal generalized forces of its heated stiffness.
    /// `predicted_at` a stage time: the publications at its own rate extrapolated there (module
    /// [`crate::vehicle::region_rate`]), false when the surfaces run at every stage or nothing
    /// is published yet; `None`: the latest publication, the iterate this derivative's
    /// evaluation (or the step's start, for its first stage) has just published.
    pub(super) fn read_surface_loads(
        &mut self,
        elevon: &ElevonCommand,
        predicted_at: Option<f64>,
    ) -> Result<bool, VehicleError> {
        if predicted_at.is_some() && self.surface_rate == RegionLoadRate::EveryStage {
            return Ok(false);
        }
        for (index, ((s, read), out)) in self
            .surfaces
            .iter()
            .zip(self.surface_reads.iter_mut())
            .zip(self.loads.surface_generalized_forces.iter_mut())
            .enumerate()
        {
            let generalized = out.as_mut_slice();
            match predicted_at {
                Some(time_s) => {
                    let applied = &mut read.applied_surface_frame;
                    if !self
                        .exchange
                        .read_surface(index, time_s, applied, generalized)?
                    {
                        return Ok(false);
                    }
                }
                None => self.exchange.read_surface_latest(
                    index,
                    &mut read.applied_surface_frame,
                    generalized,
                )?,
            }
            let rotation = elevon_rotation(&s.name, elevon.deflection_rad(s.side))?;
            read.applied_about_pivot = Loads {
                force_n: rotation * read.applied_surface_frame.force_n,
                moment_nm: rotation * read.applied_surface_frame.moment_nm,
            };
            read.elevon_rotation = rotation;
            add_thermal_generalized_forces(s, out);
        }
        Ok(!self.surfaces.is_empty())
    }

    /// Publishes every surface's evaluation at `time_s` on its loads topic, converged or as an
    /// iterate ([`Publication`]).
    pub(super) fn publish_surfaces(&mut self, at: (f64, Publication)) -> Result<(), VehicleError> {
        for (index, s) in self.surfaces.iter().enumerate() {
            self.exchange
                .publish_surface(index, at, &s.applied_surface_frame, &s.generalized)?;
        }
        Ok(())
    }
}
