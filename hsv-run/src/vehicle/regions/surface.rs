//! The lifting-surface regions: each surface's aero on its Ritz-deformed, elevon-rotated mesh
//! (moved at its root by the body's modes), its aero generalized forces and its applied load
//! about the pivot, the surfaces evaluated side by side. Each publishes `<surface>/loads` (its
//! applied load in its own frame and its aero generalized forces: at every stage by default,
//! or at `surface_loads_dt_s`); reads its own and the body's modal states, the elevon, its
//! flight condition and (a model with memory) its modal history. Its heating is `heated`'s.

use hsv_core::ModelError;
use hsv_core::aero::{
    AeroModel, AeroSolution, Loads, ModalHistory, PanelMotion, integrate_pressure,
};
use hsv_core::coupling::{
    ElevonCommand, ModalProjection, deflect_lifting_surface, elevon_rotation_angle_rad, pivot_axis,
    rotate_points, rotation_about_axis,
};
use hsv_core::flow::FlightCondition;
use hsv_core::geometry::{LiftingSurfaceConfig, Side, pivot_point};
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use hsv_core::structure::StructureModel;
use nalgebra::{DVector, Point3, Vector3};
use rayon::prelude::*;

use super::heated::HeatedSurface;
use super::side_by_side;
use crate::dynamics::VehicleState;
use crate::dynamics::equations_of_motion::pivot_motion;
use crate::vehicle::error::{VehicleError, model_error};
use crate::vehicle::friction::RegionFriction;

pub(in crate::vehicle) struct Surface {
    pub(in crate::vehicle) thermal: Option<HeatedSurface>,
    pub(in crate::vehicle) friction: Option<RegionFriction>,
    /// Skin friction about the pivot (body frame) evaluated at the open step's first stage, the
    /// accepted state, and held by its other stages (see [`surface_region_loads`]).
    pub(in crate::vehicle) held_friction: Option<Loads>,
    /// Pressure and friction loads about the pivot in the surface's own (undeflected) frame, from
    /// the last region evaluation: what it publishes with its aero generalized forces.
    pub(in crate::vehicle) applied_surface_frame: Loads,
    pub(in crate::vehicle) name: String,
    pub(in crate::vehicle) base: PanelMesh,
    /// The base vertices displaced by the modes, before the elevon's rotation, m.
    pub(in crate::vehicle) displaced_m: Vec<Point3<f64>>,
    pub(in crate::vehicle) deflected: PanelMesh,
    pub(in crate::vehicle) shapes: ModeShapes,
    pub(in crate::vehicle) projection: ModalProjection,
    pub(in crate::vehicle) structure: Box<dyn StructureModel>,
    pub(in crate::vehicle) aero: Box<dyn AeroModel>,
    pub(in crate::vehicle) planform: LiftingSurfaceConfig,
    pub(in crate::vehicle) side: Side,
    pub(in crate::vehicle) pivot_m: Point3<f64>,
    /// The base mesh rotated rigidly by the elevon (what a model with memory evaluates on).
    pub(in crate::vehicle) rigid: PanelMesh,
    pub(in crate::vehicle) velocities: Vec<Vector3<f64>>,
    pub(in crate::vehicle) solution: AeroSolution,
    pub(in crate::vehicle) generalized: Vec<f64>,
    /// The body's mode shapes at the pivot (6 × n_body: translation m, section rotation rad).
    pub(in crate::vehicle) body_modes_at_pivot: nalgebra::DMatrix<f64>,
}

/// One lifting surface's aero on its Ritz-deformed mesh rotated by its elevon (the mesh moves
/// with its own modes and the body's at the pivot, the modal states given): the panel solution
/// and, for a model with memory (convolution ROM), the generalized forces from its modal
/// history (`true`). Returns the elevon's rotation.
pub(in crate::vehicle) fn surface_aero(
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
pub(in crate::vehicle) fn surface_region_loads(
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
pub(in crate::vehicle) fn add_thermal_generalized_forces(s: &Surface, out: &mut DVector<f64>) {
    let thermal = s
        .structure
        .thermal_stiffness()
        .and_then(|t| t.thermal_generalized_forces());
    for (k, q) in out.iter_mut().enumerate() {
        *q += thermal.map_or(0.0, |t| t[k]);
    }
}

/// The elevon's rotation of a surface about its torque tube for a deflection, rad.
pub(in crate::vehicle) fn elevon_rotation(
    surface: &str,
    deflection_rad: f64,
) -> Result<nalgebra::Rotation3<f64>, VehicleError> {
    rotation_about_axis(&pivot_axis(), elevon_rotation_angle_rad(deflection_rad))
        .map_err(|e| model_error(surface)(ModelError::inconsistent("elevon", e.to_string())))
}

/// Every lifting surface's region loads, side by side (rayon).
/// Each surface's loads in its own flight condition (`flights`, one per surface: the wind
/// where it flies).
pub(in crate::vehicle) fn surfaces_loads(
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
