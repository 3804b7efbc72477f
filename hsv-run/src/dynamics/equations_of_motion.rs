//! The assembled vehicle's equations of motion: its state, loads and derivative (paper Eq. 1
//! plus each lifting surface's modal equations). The flat state vector the integrator and the
//! linearization work on is laid out in [`super::state_layout`].
//!
//! Order within a derivative: the rigid body first (from the loads the coordinator gives,
//! including the surfaces' root loads of its latest coupling iterate), then the body's modes,
//! then each surface driven by the body's motion at its pivot. The body-surface algebraic loop
//! (root loads depend on the surfaces' accelerations, which depend on the body's at the pivots)
//! is closed by the coordinator's coupling iteration, not here.
//!
//! **The elastic interface** (paper §II.B: the body gives the surfaces their root displacement
//! and velocity, the surfaces give the body root forces and moments). Mass bookkeeping, with no
//! double counting:
//! - the rigid body carries the whole vehicle's mass, the surfaces' rigid mass lumped at their
//!   pivots in [`MassProperties`]; the root loads the coordinator adds are the force-summation
//!   loads L = Rᵀ (f − M Φ q̈) (applied load minus the elastic inertia);
//! - the body's modes are the beam's own free-free modes, mean axes of the beam alone, not of
//!   the assembly: the assembly's modes would need the surfaces' structure inside the body's
//!   model, across regions. The surfaces' rigid mass at the pivots then couples to them
//!   inertially, exactly (up to modal truncation): the body's modal equations take each
//!   surface's wrench at its pivot, Φ_Pᵀ (L − M_P (a_P − g)), with M_P the surface's 6 × 6
//!   rigid mass about the pivot and a_P the pivot's full acceleration (rigid and elastic);
//!   the rigid body takes the reaction of the elastic part, −M_P Φ_P η̈. The assembled mass
//!   matrix is then symmetric: the term Φ_Pᵀ M_P Φ_P is the surfaces' added mass on the
//!   body's modes, Φ_Pᵀ M_P their coupling with the rigid motion.
//! - the body's η̈ in those terms is the coordinator's interface iterate
//!   ([`VehicleLoads::body_modal_acceleration`]), so the loop closes in the same fixed point
//!   as the surfaces' q̈.
//!
//! [`MassProperties`]: hsv_core::structure::MassProperties

use hsv_core::aero::Loads;
use hsv_core::structure::ModalModel;
use nalgebra::{DMatrix, DVector, Vector3};
use serde::{Deserialize, Serialize};

use super::modal::{
    ModalDynamics, ModalRate, ModalState, RootMotion, SurfaceAttachment, pivot_inertia,
};
use super::rigid_body::{RigidBody, RigidBodyDerivative, RigidBodyState};
use super::{DynamicsError, check_finite, check_len};

/// The whole vehicle's dynamic state: plain data.
#[derive(Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct VehicleState {
    pub rigid: RigidBodyState,
    /// The free-free body's modal coordinates (mean axes).
    pub body_modes: ModalState,
    /// Each lifting surface's Ritz coordinates, in the order of the surfaces given to
    /// [`VehicleDynamics::new`].
    pub surface_modes: Vec<ModalState>,
}

impl Clone for VehicleState {
    fn clone(&self) -> Self {
        Self {
            rigid: self.rigid,
            body_modes: self.body_modes.clone(),
            surface_modes: self.surface_modes.clone(),
        }
    }

    /// Copies into the existing buffers when the shapes agree (no allocation in the time loop).
    fn clone_from(&mut self, source: &Self) {
        self.rigid = source.rigid;
        self.body_modes.clone_from(&source.body_modes);
        self.surface_modes.clone_from(&source.surface_modes);
    }
}

/// What the coordinator computes from a state: body-axis loads about the centre of mass
/// (aero on the deformed OML, engine, surface root loads; gravity is added by the dynamics) and
/// generalized forces.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VehicleLoads {
    /// Force (N) and moment about the centre of mass (N m), body axes, gravity excluded.
    pub body: Loads,
    /// Q_η of the body's modes (aero, engine; gravity gives none about mean axes).
    pub body_generalized_force: DVector<f64>,
    /// Each surface's generalized forces (aero, thermal; gravity and root motion are added by
    /// the dynamics).
    pub surface_generalized_forces: Vec<DVector<f64>>,
    /// Each surface's root load on the body (applied load minus the elastic inertia, force N
    /// and moment N m about its pivot, body axes), as included in `body`: what the dynamics
    /// projects onto the body's modes with the surface's rigid inertia.
    pub surface_root_loads: Vec<Loads>,
    /// The body-surface interface's iterate of the body's modal accelerations η̈ (1/s²): the
    /// elastic acceleration of the pivots that drives the surfaces' rigid inertia in the rigid
    /// body's and the body modes' equations. The coordinator's fixed point makes it the η̈
    /// that the derivative returns.
    pub body_modal_acceleration: DVector<f64>,
}

/// The time derivative of a [`VehicleState`], with the root motion each surface saw.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VehicleDerivative {
    pub rigid: RigidBodyDerivative,
    pub body_modes: ModalRate,
    pub surface_modes: Vec<ModalRate>,
    /// The root motion that drove each surface.
    pub surface_root_motion: Vec<RootMotion>,
}

/// One lifting surface's modal equations and attachment, with its root-acceleration scratch.
#[derive(Debug, Clone)]
struct Surface {
    modal: ModalDynamics,
    /// The structural generator at assembly (before any temperature update): what the exponential
    /// integrator propagates exactly, so a resumed run uses the same one.
    reference_generator: DMatrix<f64>,
    attachment: SurfaceAttachment,
    root_acceleration: DVector<f64>,
}

/// The vehicle's equations of motion: the rigid body, the body's modes and each surface's.
#[derive(Debug, Clone)]
pub struct VehicleDynamics {
    rigid: RigidBody,
    body: ModalDynamics,
    surfaces: Vec<Surface>,
    /// Scratch: the body's generalized forces with the surfaces' wrenches on it.
    body_force: DVector<f64>,
}

impl VehicleDynamics {
    /// From the rigid body, the body's modal model (mean axes; an empty model for a rigid
    /// vehicle) and each surface's attachment and modal model.
    pub fn new(
        rigid: RigidBody,
        body_modes: &ModalModel,
        surfaces: Vec<(SurfaceAttachment, &ModalModel)>,
    ) -> Result<Self, DynamicsError> {
        let body = ModalDynamics::new("main body", body_modes)?;
        let surfaces = surfaces
            .into_iter()
            .map(|(attachment, model)| {
                let modal = ModalDynamics::new(&attachment.name, model)?;
                let name = &attachment.name;
                check_len(
                    || format!("{name}: rigid coupling rows (one per Ritz mode)"),
                    modal.n_modes(),
                    attachment.coupling.nrows(),
                )?;
                check_len(
                    || format!("{name}: rigid coupling columns (one per rigid DOF)"),
                    attachment.dofs.len(),
                    attachment.coupling.ncols(),
                )?;
                check_len(
                    || format!("{name}: body mode shapes at the pivot (rows)"),
                    6,
                    attachment.body_modes_at_pivot.nrows(),
                )?;
                check_len(
                    || format!("{name}: body mode shapes at the pivot (columns)"),
                    body.n_modes(),
                    attachment.body_modes_at_pivot.ncols(),
                )?;
                check_finite(
                    || format!("{name}: rigid coupling"),
                    attachment.coupling.iter(),
                )?;
                Ok(Surface {
                    root_acceleration: DVector::zeros(attachment.dofs.len()),
                    reference_generator: modal.state_generator(),
                    modal,
                    attachment,
                })
            })
            .collect::<Result<Vec<_>, DynamicsError>>()?;
        Ok(Self {
            body_force: DVector::zeros(body.n_modes()),
            rigid,
            body,
            surfaces,
        })
    }

    /// The Earth the rigid body flies over ([`RigidBody::set_earth`]).
    pub fn set_earth(&mut self, earth: super::rigid_body::EarthModel) {
        self.rigid.set_earth(earth);
    }

    pub fn rigid_body(&self) -> &RigidBody {
        &self.rigid
    }

    pub fn body_modes(&self) -> &ModalDynamics {
        &self.body
    }

    pub fn n_surfaces(&self) -> usize {
        self.surfaces.len()
    }

    /// A surface's attachment.
    pub fn surface_attachment(&self, surface: usize) -> Option<&SurfaceAttachment> {
        self.surfaces.get(surface).map(|s| &s.attachment)
    }

    /// The lowest natural frequency of the body's and the surfaces' modal models, rad/s:
    /// min √(K_ii / M_ii) (their bases are M- and K-orthogonal); None without modes.
    pub fn lowest_natural_frequency_rad_s(&self) -> Option<f64> {
        std::iter::once(&self.body)
            .chain(self.surfaces.iter().map(|s| &s.modal))
            .flat_map(|m| {
                let (mass, _, stiffness) = m.matrices();
                (0..m.n_modes()).map(move |i| (stiffness[(i, i)] / mass[(i, i)]).sqrt())
            })
            .filter(|w| w.is_finite())
            .reduce(f64::min)
    }

    /// Each surface's modal equations with the structural generator at assembly (before any
    /// temperature update), in order.
    pub fn surface_modal_models(&self) -> impl Iterator<Item = (&ModalDynamics, &DMatrix<f64>)> {
        self.surfaces
            .iter()
            .map(|s| (&s.modal, &s.reference_generator))
    }

    /// Updates a surface's modal matrices in place (temperature-dependent stiffness).
    pub fn set_surface_matrices(
        &mut self,
        surface: usize,
        model: &ModalModel,
    ) -> Result<(), DynamicsError> {
        let n = self.surfaces.len();
        let s = self
            .surfaces
            .get_mut(surface)
            .ok_or_else(|| DynamicsError::Dimension {
                what: format!("lifting surface index {surface}"),
                expected: n,
                got: surface + 1,
            })?;
        s.modal.set_matrices(model)
    }

    /// A state of the right sizes: at rest at the origin, modes undeformed.
    pub fn zero_state(&self) -> VehicleState {
        VehicleState {
            rigid: RigidBodyState::default(),
            body_modes: ModalState::zeros(self.body.n_modes()),
            surface_modes: self
                .surfaces
                .iter()
                .map(|s| ModalState::zeros(s.modal.n_modes()))
                .collect(),
        }
    }

    /// Zero loads of the right sizes.
    pub fn zero_loads(&self) -> VehicleLoads {
        VehicleLoads {
            body: Loads::default(),
            body_generalized_force: DVector::zeros(self.body.n_modes()),
            surface_generalized_forces: self
                .surfaces
                .iter()
                .map(|s| DVector::zeros(s.modal.n_modes()))
                .collect(),
            surface_root_loads: vec![Loads::default(); self.surfaces.len()],
            body_modal_acceleration: DVector::zeros(self.body.n_modes()),
        }
    }

    /// A derivative buffer of the right sizes.
    pub fn zero_derivative(&self) -> VehicleDerivative {
        VehicleDerivative {
            rigid: RigidBodyDerivative::default(),
            body_modes: ModalRate::zeros(self.body.n_modes()),
            surface_modes: self
                .surfaces
                .iter()
                .map(|s| ModalRate::zeros(s.modal.n_modes()))
                .collect(),
            surface_root_motion: vec![RootMotion::default(); self.surfaces.len()],
        }
    }

    /// The state derivative into `out` (buffers from [`Self::zero_derivative`]). No allocation;
    /// a non-finite result is an error naming the quantity.
    pub fn derivative(
        &mut self,
        state: &VehicleState,
        loads: &VehicleLoads,
        out: &mut VehicleDerivative,
    ) -> Result<(), DynamicsError> {
        let n_surfaces = self.surfaces.len();
        check_len(
            || "surface modal states".into(),
            n_surfaces,
            state.surface_modes.len(),
        )?;
        check_len(
            || "surface generalized forces".into(),
            n_surfaces,
            loads.surface_generalized_forces.len(),
        )?;
        check_len(
            || "surface modal rates".into(),
            n_surfaces,
            out.surface_modes.len(),
        )?;
        check_len(
            || "surface root motions".into(),
            n_surfaces,
            out.surface_root_motion.len(),
        )?;
        check_finite(
            || "body loads (force N, moment N m)".into(),
            loads.body.force_n.iter().chain(loads.body.moment_nm.iter()),
        )?;
        check_len(
            || "surface root loads".into(),
            n_surfaces,
            loads.surface_root_loads.len(),
        )?;
        check_len(
            || "body modal acceleration iterate".into(),
            self.body.n_modes(),
            loads.body_modal_acceleration.len(),
        )?;
        // The surfaces' rigid inertia under the body's elastic motion at the pivots (their
        // rigid inertia under the rigid motion is in the rigid body's mass).
        let mut body_loads = loads.body;
        for surface in &self.surfaces {
            let a = &surface.attachment;
            let (d_ddot, theta_ddot) =
                pivot_motion(&a.body_modes_at_pivot, &loads.body_modal_acceleration);
            let w = pivot_inertia(&a.pivot_mass, &d_ddot, &theta_ddot);
            let offset = self.rigid.offset_from_center_of_mass(&a.pivot_m);
            body_loads.force_n -= w.force_n;
            body_loads.moment_nm -= w.moment_nm + offset.cross(&w.force_n);
        }
        out.rigid = self.rigid.derivative(&state.rigid, &body_loads);
        let rigid = &out.rigid;
        check_finite(
            || "rigid-body acceleration (m/s², rad/s²)".into(),
            rigid
                .acceleration_body_m_s2
                .iter()
                .chain(rigid.angular_acceleration_body_rad_s2.iter()),
        )?;
        // Each surface's wrench on the body at its pivot, Φ_Pᵀ (L − M_P a_P): its root load
        // and its rigid inertia at the pivot's specific force (gravity's share included, so a
        // freely falling vehicle stays undeformed).
        self.body_force.copy_from(&loads.body_generalized_force);
        for (i, surface) in self.surfaces.iter().enumerate() {
            let a = &surface.attachment;
            let offset = self.rigid.offset_from_center_of_mass(&a.pivot_m);
            let root = RootMotion::at_pivot(
                &state.rigid,
                &out.rigid,
                &offset,
                &a.body_modes_at_pivot,
                &state.body_modes,
                &loads.body_modal_acceleration,
            );
            let inertia = pivot_inertia(
                &a.pivot_mass,
                &root.specific_force_m_s2,
                &root.angular_acceleration_rad_s2,
            );
            let root_load = &loads.surface_root_loads[i];
            let force = root_load.force_n - inertia.force_n;
            let moment = root_load.moment_nm - inertia.moment_nm;
            for (k, q) in self.body_force.iter_mut().enumerate() {
                let phi = a.body_modes_at_pivot.column(k);
                *q += phi[0] * force.x
                    + phi[1] * force.y
                    + phi[2] * force.z
                    + phi[3] * moment.x
                    + phi[4] * moment.y
                    + phi[5] * moment.z;
            }
        }
        self.body.acceleration(
            &state.body_modes,
            &self.body_force,
            None,
            &mut out.body_modes,
        )?;
        check_finite(
            || "main body modal acceleration".into(),
            out.body_modes.q_ddot.iter(),
        )?;
        for (i, surface) in self.surfaces.iter_mut().enumerate() {
            let attachment = &surface.attachment;
            let offset = self.rigid.offset_from_center_of_mass(&attachment.pivot_m);
            let root = RootMotion::at_pivot(
                &state.rigid,
                &out.rigid,
                &offset,
                &attachment.body_modes_at_pivot,
                &state.body_modes,
                &out.body_modes.q_ddot,
            );
            for (a, &dof) in surface
                .root_acceleration
                .iter_mut()
                .zip(attachment.dofs.iter())
            {
                *a = root.dof(dof);
            }
            out.surface_root_motion[i] = root;
            surface.modal.acceleration(
                &state.surface_modes[i],
                &loads.surface_generalized_forces[i],
                Some((&attachment.coupling, &surface.root_acceleration)),
                &mut out.surface_modes[i],
            )?;
            let name = &attachment.name;
            check_finite(
                || format!("{name}: modal acceleration"),
                out.surface_modes[i].q_ddot.iter(),
            )?;
        }
        Ok(())
    }
}

/// The pivot's elastic translation and rotation (m, rad, or their rates) for modal values
/// `eta`: Φ_P η split into its translation and rotation rows.
pub fn pivot_motion(
    body_modes_at_pivot: &DMatrix<f64>,
    eta: &DVector<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let mut translation = Vector3::zeros();
    let mut rotation = Vector3::zeros();
    for (k, &e) in eta.iter().enumerate().take(body_modes_at_pivot.ncols()) {
        let c = body_modes_at_pivot.column(k);
        translation += Vector3::new(c[0], c[1], c[2]) * e;
        rotation += Vector3::new(c[3], c[4], c[5]) * e;
    }
    (translation, rotation)
}

/// Angular momentum of the rigid body about its centre of mass in NED axes, C_eb J ζ, kg m²/s
/// (constant in torque-free motion).
pub fn angular_momentum_ned(rigid: &RigidBody, state: &RigidBodyState) -> Vector3<f64> {
    state.attitude * (rigid.inertia_kg_m2() * state.angular_velocity_body_rad_s)
}

/// Rotational kinetic energy ½ ζᵀ J ζ, J.
pub fn rotational_energy(rigid: &RigidBody, state: &RigidBodyState) -> f64 {
    let w = &state.angular_velocity_body_rad_s;
    0.5 * w.dot(&(rigid.inertia_kg_m2() * w))
}
