//! The main-body region: aero and skin friction on the beam-deformed OML beside the engine on
//! its underside (`engine`), and the body's generalized forces; the surfaces that follow the
//! body are `follower`'s. Publishes `main_body/loads` (its loads about the centre of mass with
//! its engine's and followers', and its generalized forces: at its rate, default 1 ms, or at
//! every stage) and `main_body/skin_friction` (at the aerothermal rate, 10 ms); reads the
//! body's modal state and the controls.
//!
//! Without an engine (no propulsion region: a glide) the body's aero model also loads the
//! engine's ramp and nozzle, as outer surfaces of the flow it computes there; the duct is
//! flow-through and its inner forces are not modelled (the inlet face and nozzle exit are caps
//! that carry no load, as with an engine).

use hsv_core::ModelError;
use hsv_core::aero::{AeroModel, AeroSolution, Loads, PanelMotion, integrate_pressure};
use hsv_core::coupling::generalized_forces;
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use nalgebra::{Point3, Vector3};

use super::engine::{Engine, engine_region_loads};
use super::{FlightControls, join};
use crate::dynamics::VehicleState;
use crate::vehicle::error::{VehicleError, model_error};
use crate::vehicle::friction::RegionFriction;

pub(in crate::vehicle) struct Body {
    pub(in crate::vehicle) friction: Option<RegionFriction>,
    /// Skin friction about the centre of mass of the last body evaluation, and the value the
    /// next evaluation takes instead of evaluating the friction law (set by `begin_step` between
    /// the friction's evaluations: module [`super::region_rate`]), as the surfaces' `held_friction`.
    pub(in crate::vehicle) friction_loads: Loads,
    pub(in crate::vehicle) held_friction: Option<Loads>,
    pub(in crate::vehicle) base: PanelMesh,
    pub(in crate::vehicle) mesh: PanelMesh,
    pub(in crate::vehicle) shapes: ModeShapes,
    pub(in crate::vehicle) aero: Box<dyn AeroModel>,
    pub(in crate::vehicle) velocities: Vec<Vector3<f64>>,
    pub(in crate::vehicle) solution: AeroSolution,
    pub(in crate::vehicle) generalized: Vec<f64>,
    /// The region's generalized forces as published: the body's, its engine's and its
    /// followers' summed (scratch).
    pub(in crate::vehicle) published_generalized: Vec<f64>,
}

/// The main body's aero (pressure and friction) and engine loads about the centre of mass, and
/// its generalized forces, on the OML deformed by the beam modes; without an engine the aero
/// takes the engine's panels and the engine loads are zero.
#[allow(clippy::too_many_arguments)]
pub(in crate::vehicle) fn body_region_loads(
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
