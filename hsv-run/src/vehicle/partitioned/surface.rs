//! The lifting-surface regions: each surface's aero on its Ritz-deformed, elevon-rotated mesh,
//! its generalized forces and applied loads about the pivot, its heat flux and conduction, and
//! the surfaces evaluated side by side.

use super::*;

/// A surface's thermal model, with the transfer of its conduction nodes onto the structure's
/// temperature grid (mirrored when the structure keeps the other side's grid).
pub(super) fn surface_thermal(
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
    let region = crate::vehicle::thermal::SurfaceThermal::new(heat_flux, conduction, n_panels)
        .map_err(|e| assembly_error(name, format!("conduction `{model}`: {e}")))?;
    Ok(HeatedSurface {
        region,
        onto_structure,
        stiffness_time_s: 0.0,
        stiffness_changed: false,
    })
}

/// One lifting surface's aero on its Ritz-deformed mesh rotated by its elevon (the mesh moves
/// with its own modes and the body's at the pivot, the modal states given): the panel solution
/// and, for a model with memory (convolution ROM), the generalized forces from its modal
/// history (`true`). Returns the elevon's rotation.
pub(super) fn surface_aero(
    s: &mut Surface,
    (modes, body_modes): (&crate::dynamics::ModalState, &crate::dynamics::ModalState),
    elevon: &ElevonCommand,
    flight: &FlightCondition,
    (time_s, history): (f64, Option<&ModalHistory>),
) -> Result<(nalgebra::Rotation3<f64>, bool), VehicleError> {
    let err = model_error(&s.name);
    let deflection = elevon.deflection_rad(s.side);
    // Elastic displacement, then the elevon's rotation about the torque tube (what
    // `deflect_lifting_surface` does), with the panel geometry computed once at the end.
    let rotation = elevon_rotation(&s.name, deflection)?;
    s.shapes.displace_with_velocities(
        &s.base,
        &modes.q,
        &modes.q_dot,
        &mut s.displaced_m,
        &mut s.velocities,
    );
    rotate_points(
        &s.displaced_m,
        &pivot_point(&s.planform, s.side),
        &rotation,
        &mut s.deflected.vertices,
    )
    .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
    for v in &mut s.velocities {
        *v = rotation * *v;
    }
    // The body's elastic motion at the pivot carries the root: translation d and the section's
    // small rotation θ, r ← r + d + θ × (r − P), and their rates in the boundary velocity.
    // (Panel velocities: at the panels' centroids.)
    let carried = s.body_modes_at_pivot.ncols() > 0;
    if carried {
        let (d, theta) = pivot_motion(&s.body_modes_at_pivot, &body_modes.q);
        for r in &mut s.deflected.vertices {
            *r += d + theta.cross(&(*r - s.pivot_m));
        }
    }
    s.deflected.update_geometry();
    if carried {
        let (d_dot, theta_dot) = pivot_motion(&s.body_modes_at_pivot, &body_modes.q_dot);
        for (panel, v) in s.deflected.panels.iter().zip(s.velocities.iter_mut()) {
            *v += d_dot + theta_dot.cross(&(panel.centroid - s.pivot_m));
        }
    }
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&s.velocities),
    };
    let dt_since_commit = time_s - history.map_or(0.0, |h| h.time_s);
    match (s.aero.modal_history(), history) {
        // A model with memory (convolution ROM): generalized forces from the modal history on
        // the rigidly deflected mesh.
        (Some(rom), Some(history)) => {
            deflect_lifting_surface(&s.base, &s.planform, s.side, deflection, &mut s.rigid)
                .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
            rom.evaluate_modal(
                &s.rigid,
                flight,
                history,
                dt_since_commit.max(0.0),
                &modes.q,
                &modes.q_dot,
                &mut s.generalized,
                Some(&mut s.solution),
            )
            .map_err(&err)?;
            Ok((rotation, true))
        }
        _ => {
            s.aero
                .evaluate(&s.deflected, flight, &motion, &mut s.solution)
                .map_err(&err)?;
            Ok((rotation, false))
        }
    }
}

/// One lifting surface's aero ([`surface_aero`]), its aero generalized forces, and its applied
/// load (pressure and skin friction about the pivot, in its own frame): what it publishes.
///
/// Inside an open step (`hold_friction`), the skin friction is evaluated at the step's first
/// stage, the accepted state, and held by the others: friction reaches only the root loads, and
/// it changes on the flight's time scale (the elevon ramps over 0.5 s), so holding it over one
/// 1 ms step moves the state by O(Δt · dF/dt) while sparing three of its four evaluations.
/// Outside a step (trim, linearization, flutter) and with `body_loads_dt_s = 0` (the every-stage
/// reference) it is evaluated every time.
pub(super) fn surface_region_loads(
    s: &mut Surface,
    modes: (&crate::dynamics::ModalState, &crate::dynamics::ModalState),
    elevon: &ElevonCommand,
    flight: &FlightCondition,
    clock: (f64, Option<&ModalHistory>),
    hold_friction: bool,
) -> Result<(), VehicleError> {
    let p_inf = flight.freestream.pressure_pa;
    let (rotation, from_history) = surface_aero(s, modes, elevon, flight, clock)?;
    let err = model_error(&s.name);
    if !from_history {
        // The modes turn with the surface, so A n·φ is that of the reference geometry.
        s.projection
            .generalized_forces(&s.solution.pressure_pa, p_inf, &mut s.generalized)
            .map_err(|e| err(ModelError::inconsistent("coupling", e.to_string())))?;
    }
    // Pressure and skin friction on the deflected surface, about the pivot: the applied load of
    // the root loads' force summation, which works in the surface's own frame.
    let friction = match (&mut s.friction, s.held_friction.filter(|_| hold_friction)) {
        (Some(_), Some(held)) => held,
        (Some(f), _) => f
            .loads(
                &s.deflected,
                flight,
                &s.solution,
                &PanelMotion::default(),
                &s.pivot_m,
                |r| r == RegionKind::LiftingSurface,
            )
            .map_err(&err)?,
        (None, _) => Loads::default(),
    };
    s.held_friction = hold_friction.then_some(friction);
    let applied = integrate_pressure(
        &s.deflected,
        &s.solution.pressure_pa,
        p_inf,
        &s.pivot_m,
        |r| r == RegionKind::LiftingSurface,
    ) + friction;
    s.applied_surface_frame = Loads {
        force_n: rotation.inverse_transform_vector(&applied.force_n),
        moment_nm: rotation.inverse_transform_vector(&applied.moment_nm),
    };
    Ok(())
}

/// The surface's generalized forces: the aero ones read from its publication (in `out`) plus
/// the thermal ones of its heated stiffness.
fn add_thermal_generalized_forces(s: &Surface, out: &mut DVector<f64>) {
    let thermal = s
        .structure
        .thermal_stiffness()
        .and_then(|t| t.thermal_generalized_forces());
    for (k, q) in out.iter_mut().enumerate() {
        *q += thermal.map_or(0.0, |t| t[k]);
    }
}

/// The elevon's rotation of a surface about its torque tube for a deflection, rad.
pub(super) fn elevon_rotation(
    surface: &str,
    deflection_rad: f64,
) -> Result<nalgebra::Rotation3<f64>, VehicleError> {
    rotation_about_axis(&pivot_axis(), elevon_rotation_angle_rad(deflection_rad))
        .map_err(|e| model_error(surface)(ModelError::inconsistent("elevon", e.to_string())))
}

/// Whether the heat flux, last published at `last_s` (None: never), is due again at `time_s`
/// (every heat-flux interval).
pub(super) fn heat_flux_due(last_s: Option<f64>, time_s: f64, rates: &HeatingRates) -> bool {
    last_s.is_none_or(|last| time_s - last >= rates.heat_flux_s - 1e-12)
}

/// One heated surface's heat flux at `time_s` from its aero at the accepted state (the
/// surface's modes, the body's, the elevon and its flight condition), into its buffer for the
/// vehicle to publish. The aero is evaluated here unless `aero_current` (the step's start has
/// just evaluated the surface at this state), never read from the last derivative: inside a step
/// that is the last Runge-Kutta stage's predictor, not a state the flight passes through.
pub(super) fn refresh_heat_flux(
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
pub(super) fn heat_surface(
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
pub(super) fn read_structure_temperatures(
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

/// Every lifting surface's region loads, side by side (rayon).
/// Each surface's loads in its own flight condition (`flights`, one per surface: the wind
/// where it flies).
pub(super) fn surfaces_loads(
    surfaces: &mut [Surface],
    state: &VehicleState,
    elevon: &ElevonCommand,
    flights: &[FlightCondition],
    (time_s, histories): (f64, &[Option<ModalHistory>]),
    hold_friction: bool,
) -> Result<(), VehicleError> {
    let each = |(i, s): (usize, &mut Surface)| {
        surface_region_loads(
            s,
            (&state.surface_modes[i], &state.body_modes),
            elevon,
            &flights[i],
            (time_s, histories[i].as_ref()),
            hold_friction,
        )
    };
    if side_by_side() {
        surfaces.par_iter_mut().enumerate().try_for_each(each)
    } else {
        surfaces.iter_mut().enumerate().try_for_each(each)
    }
}

impl PartitionedVehicle {
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

    /// Publishes every surface's evaluation at `time_s` on its loads topic: `converged` at an
    /// accepted state where the surfaces fall due at their own rate, else the iterate one
    /// derivative reads at once.
    pub(super) fn publish_surfaces(
        &mut self,
        time_s: f64,
        converged: bool,
    ) -> Result<(), VehicleError> {
        for (index, s) in self.surfaces.iter().enumerate() {
            let (applied, generalized) = (&s.applied_surface_frame, s.generalized.as_slice());
            if converged {
                self.exchange
                    .publish_surface(index, time_s, applied, generalized)?;
            } else {
                self.exchange
                    .publish_surface_iterate(index, time_s, applied, generalized)?;
            }
        }
        Ok(())
    }
}
