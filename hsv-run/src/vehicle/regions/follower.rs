//! The surfaces that follow the body: the monolithic model's lifting surfaces (rotated by the
//! elevon) and the fixed vertical fin of either model. Each is OML moved by the body's beam modes
//! whose aero and friction loads go straight to the body and to its generalized forces; they are
//! evaluated with the body and published with it on `main_body/loads`; each reads the body's
//! modal state and the elevon.

use hsv_core::ModelError;
use hsv_core::aero::{AeroModel, AeroSolution, Loads, PanelMotion, integrate_pressure};
use hsv_core::coupling::{
    ElevonCommand, deflect_lifting_surface, elevon_rotation_angle_rad, generalized_forces,
    pivot_axis, rotation_about_axis,
};
use hsv_core::flow::FlightCondition;
use hsv_core::geometry::{LiftingSurfaceConfig, Side};
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use nalgebra::{Point3, Vector3};

use crate::dynamics::ModalState;
use crate::vehicle::error::{VehicleError, model_error};
use crate::vehicle::friction::RegionFriction;

/// OML that follows the body's modes and whose loads the body takes: a lifting surface of the
/// monolithic model, and the fixed vertical fin of either model.
pub(in crate::vehicle) struct FollowerSurface {
    pub(in crate::vehicle) name: String,
    pub(in crate::vehicle) base: PanelMesh,
    pub(in crate::vehicle) deformed: PanelMesh,
    pub(in crate::vehicle) deflected: PanelMesh,
    /// The body's beam modes on this surface's vertices.
    pub(in crate::vehicle) shapes: ModeShapes,
    pub(in crate::vehicle) aero: Box<dyn AeroModel>,
    pub(in crate::vehicle) friction: Option<RegionFriction>,
    /// The planform and side the elevon rotates an all-movable surface by; `None` for the fin.
    pub(in crate::vehicle) elevon: Option<(LiftingSurfaceConfig, Side)>,
    pub(in crate::vehicle) velocities: Vec<Vector3<f64>>,
    pub(in crate::vehicle) solution: AeroSolution,
    pub(in crate::vehicle) generalized: Vec<f64>,
    /// Its aero loads (pressure and friction) about the centre of mass at the last evaluation.
    pub(in crate::vehicle) loads: Loads,
}

impl FollowerSurface {
    /// The OML its aero last flew: deflected by the elevon, or for the fixed fin as the body's
    /// modes deformed it.
    pub(in crate::vehicle) fn flown_mesh(&self) -> &PanelMesh {
        if self.elevon.is_some() {
            &self.deflected
        } else {
            &self.deformed
        }
    }
}

/// One follower's aero and friction loads about the centre of mass `cg` and its generalized
/// forces on the body's modes, on its OML moved by the body's modal state `body_modes` (and
/// rotated by the elevon for an all-movable surface), into its own buffers.
pub(in crate::vehicle) fn follower_loads(
    f: &mut FollowerSurface,
    body_modes: &ModalState,
    elevon: &ElevonCommand,
    flight: &FlightCondition,
    cg: &Point3<f64>,
) -> Result<(), VehicleError> {
    let p_inf = flight.freestream.pressure_pa;
    let surface = |r: RegionKind| r == RegionKind::LiftingSurface;
    let err = model_error(&f.name);
    f.shapes.deform(&f.base, &body_modes.q, &mut f.deformed);
    f.shapes
        .panel_velocities(&f.base, &body_modes.q_dot, &mut f.velocities);
    if let Some((planform, side)) = &f.elevon {
        let deflection = elevon.deflection_rad(*side);
        deflect_lifting_surface(&f.deformed, planform, *side, deflection, &mut f.deflected)
            .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
        let rotation = rotation_about_axis(&pivot_axis(), elevon_rotation_angle_rad(deflection))
            .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
        for v in &mut f.velocities {
            *v = rotation * *v;
        }
    }
    // The fixed fin flies its deformed OML as it is (`FollowerSurface::flown_mesh`).
    let mesh = if f.elevon.is_some() {
        &f.deflected
    } else {
        &f.deformed
    };
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&f.velocities),
    };
    f.aero
        .evaluate(mesh, flight, &motion, &mut f.solution)
        .map_err(&err)?;
    let mut loads = integrate_pressure(mesh, &f.solution.pressure_pa, p_inf, cg, surface);
    if let Some(friction) = &mut f.friction {
        loads = loads
            + friction
                .loads(mesh, flight, &f.solution, &motion, cg, surface)
                .map_err(&err)?;
    }
    generalized_forces(
        mesh,
        &f.shapes,
        &f.solution.pressure_pa,
        p_inf,
        surface,
        &mut f.generalized,
    )
    .map_err(|e| err(ModelError::inconsistent("coupling", e.to_string())))?;
    f.loads = loads;
    Ok(())
}
