//! One time step of the partitioned vehicle: the step's protocol (begin, the stages'
//! derivatives, commit), the regions' rates and publications, the flight condition each region
//! flies in, and the regions' loads at a stage.

use super::*;

impl PartitionedVehicle {
    pub fn dynamics(&self) -> &VehicleDynamics {
        &self.dynamics
    }

    pub fn mass_properties(&self) -> &MassProperties {
        &self.mass
    }

    /// Commits the accepted `step` ending at `time_s` with `state`: the surfaces' modal
    /// histories (aero models with memory; nothing for the others) and the heating.
    pub fn commit_step(
        &mut self,
        step: OpenStep,
        state: &VehicleState,
        time_s: f64,
    ) -> Result<(), VehicleError> {
        if time_s.is_nan() || time_s < step.start_s {
            return Err(VehicleError::Input(format!(
                "a step opened at t = {} s cannot end at t = {time_s} s",
                step.start_s
            )));
        }
        self.memory.time_s = time_s;
        // Only an aero model with memory commits anything at the step's end (in the flight
        // condition each surface then flies in); for the others this is no work at all.
        if self.memory.histories.iter().any(Option::is_some) {
            let flight = self.flight(state)?;
            self.update_surface_flights(state, &flight)?;
        }
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            if let (Some(rom), Some(history)) =
                (s.aero.modal_history(), self.memory.histories[i].as_mut())
            {
                let dt = time_s - history.time_s;
                let modes = &state.surface_modes[i];
                rom.commit(
                    history,
                    &self.surface_flights[i],
                    dt,
                    &modes.q,
                    &modes.q_dot,
                )
                .map_err(model_error(&s.name))?;
            }
        }
        self.advance_heating(time_s)?;
        self.stage_one = None;
        Ok(())
    }

    /// The Earth the vehicle flies over (`[simulation] earth`; flat by default).
    pub fn set_earth(&mut self, earth: crate::dynamics::EarthModel) {
        self.dynamics.set_earth(earth);
    }

    /// How often the body region is evaluated within a time step ([`RegionLoadRate`]); forgets
    /// the regions' publications.
    pub fn set_body_load_rate(&mut self, rate: RegionLoadRate) -> Result<(), VehicleError> {
        self.body_rate = rate;
        self.rebuild_exchange()
    }

    pub fn body_load_rate(&self) -> RegionLoadRate {
        self.body_rate
    }

    /// How often, among the body region's publications, its skin friction is evaluated again
    /// (`EveryStage`: at every publication); default the aerothermal rate
    /// [`DEFAULT_BODY_FRICTION_DT_S`].
    pub fn set_body_friction_rate(&mut self, rate: RegionLoadRate) -> Result<(), VehicleError> {
        self.body_friction_rate = rate;
        self.rebuild_exchange()
    }

    /// How often the lifting surfaces are evaluated within a time step ([`RegionLoadRate`];
    /// `EveryStage` by default).
    pub fn set_surface_load_rate(&mut self, rate: RegionLoadRate) -> Result<(), VehicleError> {
        self.surface_rate = rate;
        self.rebuild_exchange()
    }

    /// The regions' exchange declared again for the current rates, nothing published.
    pub(super) fn rebuild_exchange(&mut self) -> Result<(), VehicleError> {
        let names: Vec<String> = self.surfaces.iter().map(|s| s.name.clone()).collect();
        self.exchange = RegionExchange::new(
            &names,
            self.body_rate,
            self.body_friction_rate,
            self.surface_rate,
            self.heating.heat_flux_s,
        )?;
        Ok(())
    }

    pub fn surface_load_rate(&self) -> RegionLoadRate {
        self.surface_rate
    }

    /// Forgets the regions' publications (a run starting afresh).
    pub fn forget_region_loads(&mut self) -> Result<(), VehicleError> {
        Ok(self.exchange.clear()?)
    }

    /// Opens the step starting at `time_s` from the accepted `state`: the heat flux where due;
    /// then each region that runs at its own rate (the body by default, the surfaces with
    /// `surface_loads_dt_s`) is evaluated and published here when due. The step's stage
    /// derivatives ([`Self::stage_derivative`] with the returned [`OpenStep`]) read its
    /// publications (extrapolated) until [`Self::commit_step`] takes the step back.
    pub fn begin_step(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        time_s: f64,
    ) -> Result<OpenStep, VehicleError> {
        self.stage_one = None;
        // The field a step reads (its stages and every region ahead of the centre of mass).
        self.disturbances
            .extend_to(time_s + DISTURBANCE_LOOKAHEAD_S, self.region_lead_max_m());
        if self.body_rate == RegionLoadRate::EveryStage
            && self.surface_rate == RegionLoadRate::EveryStage
        {
            self.refresh_heat_fluxes(state, controls, time_s, false)?;
            return Ok(OpenStep {
                start_s: time_s,
                reads_publications: false,
            });
        }
        for s in &mut self.surfaces {
            s.held_friction = None;
        }
        let body_due = self.body_rate != RegionLoadRate::EveryStage
            && self.body_rate.is_due(time_s, self.exchange.body_time_s());
        let surfaces_due = self.surface_rate != RegionLoadRate::EveryStage
            && !self.surfaces.is_empty()
            && self
                .surface_rate
                .is_due(time_s, self.exchange.surfaces_time_s());
        // Surfaces evaluated at every stage meet the body here on the first stage's state, so
        // two threads take them side by side; that stage then reads what they gave
        // (`stage_one_surfaces`). The staggered scheme moves their roots between sub-iterations.
        let surfaces_beside_body = body_due
            && !surfaces_due
            && self.surface_rate == RegionLoadRate::EveryStage
            && self.staggered.is_none()
            && !self.surfaces.is_empty();
        let surfaces_evaluated = surfaces_due || surfaces_beside_body;
        if body_due || surfaces_due {
            self.publish_regions(state, controls, time_s, body_due, surfaces_evaluated)?;
            if surfaces_beside_body {
                self.stage_one_state.clone_from(state);
                self.stage_one = Some((time_s, *controls));
            }
        }
        // The heat flux where due, from the surfaces' aero at this state (just evaluated, or
        // evaluated for it).
        self.refresh_heat_fluxes(state, controls, time_s, surfaces_evaluated)?;
        Ok(OpenStep {
            start_s: time_s,
            reads_publications: true,
        })
    }

    /// The body (when due) and the surfaces (when wanted) at the step starting at `time_s`,
    /// evaluated at the accepted `state` side by side; the body, and the surfaces when they run
    /// at their own rate, published (module [`crate::vehicle::region_rate`]).
    pub(super) fn publish_regions(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        time_s: f64,
        body_due: bool,
        surfaces: bool,
    ) -> Result<(), VehicleError> {
        let flight = self.flight(state)?;
        self.memory.time_s = time_s;
        if surfaces {
            self.update_surface_flights(state, &flight)?;
        }
        if body_due {
            self.body.held_friction = self
                .exchange
                .friction_at(time_s, &self.body_friction_rate)?;
        }
        let (body_loads, surfaces_done) = self.regions_side_by_side(
            state,
            controls,
            &flight,
            RegionsWanted {
                body: body_due,
                surfaces,
                hold_friction: true,
            },
        );
        let held = self.body.held_friction.take();
        if let Some(done) = surfaces_done {
            done?;
            // Due at their own rate: converged. Evaluated beside the body for the first stage:
            // the iterate that stage reads.
            let publication = if self.surface_rate == RegionLoadRate::EveryStage {
                Publication::Iterate
            } else {
                Publication::Converged
            };
            self.publish_surfaces((time_s, publication))?;
        }
        if let Some(loads) = body_loads {
            self.publish_body_region(
                loads?,
                (state, controls, &flight),
                (time_s, Publication::Converged),
            )?;
            if held.is_none() && self.body.friction.is_some() {
                self.exchange
                    .publish_friction(time_s, &self.body.friction_loads)?;
            }
        }
        Ok(())
    }

    /// Each region's loads topic in the data manager with its latest publication: the
    /// regions' loads reach the coupling only through these (module docs of
    /// [`crate::vehicle::region_rate`]).
    pub fn region_publications(&self) -> Vec<crate::vehicle::region_rate::LoadsPublication> {
        self.exchange.loads_publications()
    }

    /// The last derivative's coupling iterations and residual.
    pub fn coupling_report(&self) -> CouplingReport {
        self.memory.coupling
    }

    /// The interfaces of the body-surface coupling, in [`Self::interface_residuals`]' order:
    /// each lifting surface's root, then the main body's modes.
    pub fn interface_names(&self) -> Vec<String> {
        self.surfaces
            .iter()
            .map(|s| s.name.clone())
            .chain(std::iter::once("main_body".to_owned()))
            .collect()
    }

    /// Each interface's residual at the last derivative's final fixed-point iteration (the
    /// implicit scheme): a surface's relative root-force change, the body's relative η̈
    /// change; [`CouplingReport::residual`] is the largest.
    pub fn interface_residuals(&self) -> &[f64] {
        &self.interface_residuals
    }

    /// The flight condition of a rigid state at the centre of mass: airspeed, α, β relative
    /// to the air (the disturbances' wind there) and rates about it.
    pub fn flight(&self, state: &VehicleState) -> Result<FlightCondition, VehicleError> {
        self.flight_at(state, 0.0)
    }

    /// Sets the wind field the regions fly through from the next evaluation on.
    pub fn set_disturbances(&mut self, disturbances: Disturbances) {
        self.disturbances = disturbances;
    }

    pub fn disturbances(&self) -> &Disturbances {
        &self.disturbances
    }

    /// The gust velocity at the centre of mass now, body axes, m/s.
    pub fn gust_body_m_s(&self) -> Vector3<f64> {
        if self.disturbances.is_calm() {
            return Vector3::zeros();
        }
        self.disturbances.velocity_at(self.memory.time_s, 0.0)
    }

    /// How far ahead of the centre of mass the foremost region flies, m (at least zero).
    pub(super) fn region_lead_max_m(&self) -> f64 {
        let cg_x = self.mass.center_of_mass_m.x;
        self.surfaces
            .iter()
            .map(|s| s.pivot_m.x - cg_x)
            .fold(0.0, f64::max)
    }

    /// The flight condition `lead_m` ahead of the centre of mass along the body x axis: the
    /// airspeed and wind angles of the centre of mass's velocity relative to the gust there.
    pub(super) fn flight_at(
        &self,
        state: &VehicleState,
        lead_m: f64,
    ) -> Result<FlightCondition, VehicleError> {
        let rigid = &state.rigid;
        let wind_ned = if self.disturbances.is_calm() {
            Vector3::zeros()
        } else {
            rigid.attitude * self.disturbances.velocity_at(self.memory.time_s, lead_m)
        };
        let (airspeed, alpha, beta) = rigid.air_data(&wind_ned);
        let altitude = rigid.altitude_m();
        let freestream = Freestream::at_airspeed(airspeed, altitude, self.gas)
            .map_err(model_error("main_body"))?;
        let mut flight = FlightCondition::steady(freestream, alpha, beta);
        flight.angular_velocity_rad_s = rigid.angular_velocity_body_rad_s;
        flight.rotation_center_m = self.mass.center_of_mass_m;
        Ok(flight)
    }

    /// Loads of every region except the root loads' inertia term (which waits for q̈), read by
    /// the coupling from the regions' loads topics (the data manager, [`RegionExchange`]). A
    /// region evaluated here (the main body with its engine and followers, each lifting
    /// surface, run side by side) publishes the iterate read at once. With `reads_publications`
    /// (a stage of an open step) a region that runs at its own rate is not evaluated: its
    /// publications are read extrapolated to the stage; and the first stage reads the surfaces
    /// `begin_step` evaluated and published at its state.
    pub(super) fn region_loads(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        flight: &FlightCondition,
        reads_publications: bool,
    ) -> Result<(), VehicleError> {
        let time_s = self.memory.time_s;
        let surfaces_predicted =
            reads_publications && self.read_surface_loads(&controls.elevon, Some(time_s))?;
        let surfaces_published =
            surfaces_predicted || (reads_publications && self.stage_one_surfaces(state, controls));
        let body_predicted = reads_publications
            && self.exchange.read_body(
                time_s,
                &mut self.loads.body,
                &mut self.aero_loads,
                self.loads.body_generalized_force.as_mut_slice(),
            )?;
        if !surfaces_published {
            self.update_surface_flights(state, flight)?;
        }
        let (body_loads, surfaces_done) = self.regions_side_by_side(
            state,
            controls,
            flight,
            RegionsWanted {
                body: !body_predicted,
                surfaces: !surfaces_published,
                hold_friction: reads_publications,
            },
        );
        if let Some(done) = surfaces_done {
            done?;
            self.publish_surfaces((time_s, Publication::Iterate))?;
        }
        if !surfaces_predicted {
            self.read_surface_loads(&controls.elevon, None)?;
        }
        if let Some(loads) = body_loads {
            self.publish_body_region(
                loads?,
                (state, controls, flight),
                (time_s, Publication::Iterate),
            )?;
            self.exchange.read_body_latest(
                &mut self.loads.body,
                &mut self.aero_loads,
                self.loads.body_generalized_force.as_mut_slice(),
            )?;
        }
        Ok(())
    }

    /// The wanted regions evaluated side by side at `state` (the body: its aero and engine
    /// loads; the surfaces: into their own buffers and the generalized forces), at the vehicle's
    /// time; `None` for a region not wanted.
    fn regions_side_by_side(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        flight: &FlightCondition,
        wanted: RegionsWanted,
    ) -> RegionResults {
        let cg = self.mass.center_of_mass_m;
        let reference_point_m = self.reference_point_m;
        let time_s = self.memory.time_s;
        let histories = &self.memory.histories;
        let body = &mut self.body;
        let engine = self.engine.as_mut();
        let surfaces = &mut self.surfaces;
        let surface_flights = &self.surface_flights;
        join(
            || {
                wanted.body.then(|| {
                    body_region_loads(
                        body,
                        engine,
                        state,
                        controls,
                        flight,
                        &cg,
                        &reference_point_m,
                    )
                })
            },
            || {
                wanted.surfaces.then(|| {
                    surfaces_loads(
                        surfaces,
                        state,
                        &controls.elevon,
                        surface_flights,
                        (time_s, histories),
                        wanted.hold_friction,
                    )
                })
            },
        )
    }

    /// Whether the surfaces' loads `begin_step` evaluated at the accepted state serve this
    /// derivative: the step's first stage, at the same time, state and controls (once).
    fn stage_one_surfaces(&mut self, state: &VehicleState, controls: &FlightControls) -> bool {
        self.stage_one.take().is_some_and(|(time_s, at)| {
            time_s == self.memory.time_s && at == *controls && *state == self.stage_one_state
        })
    }

    /// Whether any surface's stiffness has been updated from its temperature field.
    pub fn stiffness_heated(&self) -> bool {
        self.surfaces
            .iter()
            .filter_map(|s| s.thermal.as_ref())
            .any(|t| t.stiffness_time_s > 0.0)
    }

    /// Force (N) and moment about the centre of mass (N m) of every load but gravity at the
    /// latest derivative evaluation: aero, engine and the surfaces' root loads, body axes.
    pub fn body_loads(&self) -> Loads {
        self.loads.body
    }

    /// The aero loads (pressure and friction, N and N m about the centre of mass, body axes) of
    /// each region that follows the body (the vertical fin; the monolithic model's lifting
    /// surfaces) at its latest evaluation, by region name.
    pub fn follower_loads(&self) -> Vec<(String, Loads)> {
        self.followers
            .iter()
            .map(|f| (f.name.clone(), f.loads))
            .collect()
    }

    /// Each region's aero model and the validity diagnostics of its latest evaluation.
    pub fn aero_diagnostics(&self) -> Vec<(String, String, hsv_core::aero::AeroDiagnostics)> {
        let mut out = vec![(
            "main_body".to_owned(),
            self.body.aero.name().to_owned(),
            self.body.solution.diagnostics,
        )];
        for s in &self.surfaces {
            out.push((
                s.name.clone(),
                s.aero.name().to_owned(),
                s.solution.diagnostics,
            ));
        }
        for f in &self.followers {
            out.push((
                f.name.clone(),
                f.aero.name().to_owned(),
                f.solution.diagnostics,
            ));
        }
        out
    }

    /// How the surfaces are modelled.
    pub fn surface_model(&self) -> SurfaceModel {
        self.surface_model
    }
}

/// The body's (aero, engine) loads and the surfaces' completion, each when wanted.
type RegionResults = (
    Option<Result<(Loads, Loads), VehicleError>>,
    Option<Result<(), VehicleError>>,
);

/// Which regions [`PartitionedVehicle::regions_side_by_side`] evaluates, and whether the
/// surfaces hold their skin friction over the open step.
#[derive(Debug, Clone, Copy)]
struct RegionsWanted {
    body: bool,
    surfaces: bool,
    hold_friction: bool,
}
