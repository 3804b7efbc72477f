//! The main-body region: aero and skin friction on the beam-deformed OML beside the engine on
//! its underside (`engine`), and the body's generalized forces; the surfaces that follow the
//! body are `follower`'s.
//!
//! Without an engine (no propulsion region: a glide) the body's aero model also loads the
//! engine's ramp and nozzle, as outer surfaces of the flow it computes there; the duct is
//! flow-through and its inner forces are not modelled (the inlet face and nozzle exit are caps
//! that carry no load, as with an engine).

use super::*;

/// The main body's aero (pressure and friction) and engine loads about the centre of mass, and
/// its generalized forces, on the OML deformed by the beam modes; without an engine the aero
/// takes the engine's panels and the engine loads are zero.
#[allow(clippy::too_many_arguments)]
pub(super) fn body_region_loads(
    b: &mut Body,
    engine: Option<&mut Engine>,
    state: &VehicleState,
    controls: &FlightControls,
    flight: &FlightCondition,
    cg: &Point3<f64>,
    reference_point_m: &Point3<f64>,
) -> Result<(Loads, Loads), VehicleError> {
    let p_inf = flight.freestream.pressure_pa;
    let body_err = model_error("main_body");
    let modes = &state.body_modes;
    b.shapes.displace_with_velocities(
        &b.base,
        &modes.q,
        &modes.q_dot,
        &mut b.mesh.vertices,
        &mut b.velocities,
    );
    b.mesh.update_geometry();
    // The body's aero and its engine both read the deformed OML and nothing of each other:
    // side by side.
    let Body {
        friction,
        friction_loads,
        held_friction,
        mesh,
        shapes,
        aero,
        velocities,
        solution,
        generalized,
        ..
    } = b;
    let (mesh, shapes) = (&*mesh, &*shapes);
    let powered = engine.is_some();
    let (body_aero, engine_loads) = join(
        || -> Result<Loads, VehicleError> {
            let motion = PanelMotion {
                elastic_velocity_m_s: Some(velocities),
            };
            aero.evaluate(mesh, flight, &motion, solution)
                .map_err(&body_err)?;
            let main_body = |r: RegionKind| crate::vehicle::body_aero_loads(r, powered);
            let mut body_aero =
                integrate_pressure(mesh, &solution.pressure_pa, p_inf, cg, main_body);
            if let Some(f) = friction {
                *friction_loads = match held_friction {
                    Some(held) => *held,
                    None => f
                        .loads(mesh, flight, solution, &motion, cg, main_body)
                        .map_err(&body_err)?,
                };
                body_aero = body_aero + *friction_loads;
            }
            generalized_forces(
                mesh,
                shapes,
                &solution.pressure_pa,
                p_inf,
                main_body,
                generalized,
            )
            .map_err(|e| body_err(ModelError::inconsistent("coupling", e.to_string())))?;
            Ok(body_aero)
        },
        || -> Result<Loads, VehicleError> {
            // The propulsion region on the deformed underside (none: a glide).
            match engine {
                Some(engine) => engine_region_loads(
                    engine,
                    (mesh, shapes),
                    flight,
                    controls,
                    (cg, reference_point_m),
                ),
                None => Ok(Loads::default()),
            }
        },
    );
    Ok((body_aero?, engine_loads?))
}

impl PartitionedVehicle {
    /// Publishes the body region's evaluation at `time_s` on its loads topic: its aero and
    /// engine loads (`body_loads`, [`body_region_loads`]) and generalized forces, with those of
    /// the regions that follow the body (evaluated here: the monolithic model's surfaces, the
    /// fin). `converged` at an accepted state where the body falls due (what the predictor
    /// extrapolates), else the iterate one derivative reads at once.
    pub(super) fn publish_body_region(
        &mut self,
        (body_aero, engine_loads): (Loads, Loads),
        (state, controls, flight): (&VehicleState, &FlightControls, &FlightCondition),
        (time_s, converged): (f64, bool),
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
        if converged {
            self.exchange
                .publish_body(time_s, &total, &aero, generalized)?;
        } else {
            self.exchange
                .publish_body_iterate(time_s, &total, &aero, generalized)?;
        }
        Ok(())
    }
}
