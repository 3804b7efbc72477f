//! Modal equations of motion (paper Eq. 1, η rows, and the lifting surfaces' Ritz equations of
//! §III.C): M q̈ + C q̇ + K q = Q − C_rb a_root, with general generalized mass, damping and
//! stiffness from [`hsv_core::structure::ModalModel`].
//!
//! **Free-free body: mean axes.** Free-free modes are M-orthogonal to the six rigid-body
//! motions, so about the mean axes (origin at the instantaneous centre of mass) the elastic and
//! rigid equations decouple (Waszak & Schmidt, J. Aircraft 25(6), 1988): the body's modes take
//! no rigid-acceleration term, and uniform gravity gives them no generalized force
//! (Φᵀ M g = 0). The inertia tensor is taken at the undeformed shape.
//!
//! **Lifting surfaces.** Each surface's Ritz coordinates are elastic motion relative to its
//! torque tube, whose motion is the body's at the pivot. The inertial coupling is
//! −C_rb a_root with C_rb = Φᵀ M R from [`hsv_core::structure::RigidBodyCoupling`], the columns
//! of R being the rigid DOFs the model lists (`ritz-plate`: x and z translation and pitch about
//! the pivot, as the paper). [`RootMotion`] computes all six root accelerations, and the surface
//! takes those its model lists. In a = root acceleration:
//! - the full rigid-body acceleration of the pivot: a_cm + ζ̇ × d + ζ × (ζ × d) (tangential
//!   and centripetal terms of the body's rotation, not just the centre-of-mass acceleration);
//! - gravity, by using the specific force a − g rather than a: gravity's generalized force on
//!   the surface, Φᵀ M g, is C_rb g for the translation DOFs, so a freely falling vehicle's
//!   surfaces do not deform (equivalence principle) and a vehicle in level flight sees its
//!   1-g sag;
//! - when the coordinator gives the body's mode shapes at the pivot
//!   ([`SurfaceAttachment::body_modes_at_pivot`]), the body's elastic motion there: d̈ = Φ_P η̈,
//!   2 ζ × Φ_P η̇, and the elastic offset of the pivot in the rotational terms; the rotation rows
//!   add Φ_θ η̈ to the angular acceleration.
//!
//! Not included: the gyroscopic and centrifugal-stiffness terms of the body's rotation acting on
//! the surface's own elastic displacements (second order in ζ times q), and y-translation, which
//! the paper neglects and `ritz-plate` does not list.

use hsv_core::aero::Loads;
use hsv_core::error::ModelError;
use hsv_core::mesh::PanelMesh;
use hsv_core::structure::{
    MassProperties, ModalModel, RigidBodyCoupling, RigidDof, StructureModel,
};
use nalgebra::{Cholesky, DMatrix, DVector, Dyn, Matrix3, Matrix6, Point3, Vector3, Vector6};
use serde::{Deserialize, Serialize};

use super::rigid_body::{RigidBodyDerivative, RigidBodyState, point_acceleration};
use super::{DynamicsError, check_finite, check_len};

/// Modal coordinates and their rates (the body's flexible modes, or one surface's Ritz
/// coordinates): plain data.
#[derive(Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct ModalState {
    /// Generalized coordinates (units of the mode shapes' normalization).
    pub q: DVector<f64>,
    /// Their time derivatives, 1/s.
    pub q_dot: DVector<f64>,
}

impl Clone for ModalState {
    fn clone(&self) -> Self {
        Self {
            q: self.q.clone(),
            q_dot: self.q_dot.clone(),
        }
    }

    /// Copies into the existing buffers when the lengths agree: the time loop copies states
    /// without allocating.
    fn clone_from(&mut self, source: &Self) {
        copy_vector(&mut self.q, &source.q);
        copy_vector(&mut self.q_dot, &source.q_dot);
    }
}

/// `to ← from`, in place when the lengths agree.
fn copy_vector(to: &mut DVector<f64>, from: &DVector<f64>) {
    if to.len() == from.len() {
        to.copy_from(from);
    } else {
        *to = from.clone();
    }
}

impl ModalState {
    pub fn zeros(n_modes: usize) -> Self {
        Self {
            q: DVector::zeros(n_modes),
            q_dot: DVector::zeros(n_modes),
        }
    }

    pub fn n_modes(&self) -> usize {
        self.q.len()
    }
}

/// The time derivative of a [`ModalState`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModalRate {
    /// q̇ (a copy of the state's rates).
    pub q_dot: DVector<f64>,
    /// q̈ from the modal equations.
    pub q_ddot: DVector<f64>,
}

impl ModalRate {
    pub fn zeros(n_modes: usize) -> Self {
        Self {
            q_dot: DVector::zeros(n_modes),
            q_ddot: DVector::zeros(n_modes),
        }
    }
}

/// The modal equations of one structure: its generalized matrices, the Cholesky factor of the
/// generalized mass (factored once), and a scratch right-hand side.
#[derive(Debug, Clone)]
pub struct ModalDynamics {
    name: String,
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    mass_factor: Cholesky<f64, Dyn>,
    rhs: DVector<f64>,
}

impl ModalDynamics {
    /// From a structure's modal model; `name` (the region) labels errors. The error names a
    /// generalized mass that is not symmetric positive definite or matrices of the wrong size.
    pub fn new(name: &str, model: &ModalModel) -> Result<Self, DynamicsError> {
        let n = model.mass.nrows();
        check_matrices(name, model, n)?;
        let mass_factor = factor_mass(name, &model.mass)?;
        Ok(Self {
            name: name.to_owned(),
            mass: model.mass.clone(),
            damping: model.damping.clone(),
            stiffness: model.stiffness.clone(),
            mass_factor,
            rhs: DVector::zeros(n),
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn n_modes(&self) -> usize {
        self.rhs.len()
    }

    /// Generalized mass, damping and stiffness in use.
    pub fn matrices(&self) -> (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>) {
        (&self.mass, &self.damping, &self.stiffness)
    }

    /// Takes new matrices of the same size (a temperature update changes the stiffness): copies
    /// in place without allocating, and refactors the mass only if it changed.
    pub fn set_matrices(&mut self, model: &ModalModel) -> Result<(), DynamicsError> {
        check_matrices(&self.name, model, self.n_modes())?;
        self.damping.copy_from(&model.damping);
        self.stiffness.copy_from(&model.stiffness);
        if model.mass != self.mass {
            self.mass_factor = factor_mass(&self.name, &model.mass)?;
            self.mass.copy_from(&model.mass);
        }
        Ok(())
    }

    /// The generator of the unforced equations on (q, q̇): [[0, I], [−M⁻¹K, −M⁻¹C]].
    pub fn state_generator(&self) -> DMatrix<f64> {
        let n = self.n_modes();
        let mut l = DMatrix::zeros(2 * n, 2 * n);
        l.view_mut((0, n), (n, n)).fill_with_identity();
        let mut stiffness = -self.stiffness.clone();
        let mut damping = -self.damping.clone();
        if n > 0 {
            self.mass_factor.solve_mut(&mut stiffness);
            self.mass_factor.solve_mut(&mut damping);
        }
        l.view_mut((n, 0), (n, n)).copy_from(&stiffness);
        l.view_mut((n, n), (n, n)).copy_from(&damping);
        l
    }

    /// q̈ from M q̈ = Q − C q̇ − K q − C_rb a (`rigid`: C_rb and a, when the structure is driven
    /// by its support's motion), into `out` together with q̇. No allocation.
    pub fn acceleration(
        &mut self,
        state: &ModalState,
        generalized_force: &DVector<f64>,
        rigid: Option<(&DMatrix<f64>, &DVector<f64>)>,
        out: &mut ModalRate,
    ) -> Result<(), DynamicsError> {
        let n = self.n_modes();
        let name = &self.name;
        check_len(|| format!("{name}: modal coordinates"), n, state.q.len())?;
        check_len(|| format!("{name}: modal velocities"), n, state.q_dot.len())?;
        check_len(
            || format!("{name}: generalized forces"),
            n,
            generalized_force.len(),
        )?;
        check_len(|| format!("{name}: modal rate buffer"), n, out.q_ddot.len())?;
        check_len(|| format!("{name}: modal rate buffer"), n, out.q_dot.len())?;
        self.rhs.copy_from(generalized_force);
        self.rhs.gemv(-1.0, &self.damping, &state.q_dot, 1.0);
        self.rhs.gemv(-1.0, &self.stiffness, &state.q, 1.0);
        if let Some((coupling, root_acceleration)) = rigid {
            check_len(
                || format!("{name}: rigid coupling rows"),
                n,
                coupling.nrows(),
            )?;
            check_len(
                || format!("{name}: root accelerations"),
                coupling.ncols(),
                root_acceleration.len(),
            )?;
            self.rhs.gemv(-1.0, coupling, root_acceleration, 1.0);
        }
        out.q_ddot.copy_from(&self.rhs);
        if n > 0 {
            self.mass_factor.solve_mut(&mut out.q_ddot);
        }
        out.q_dot.copy_from(&state.q_dot);
        Ok(())
    }
}

fn check_matrices(name: &str, model: &ModalModel, n: usize) -> Result<(), DynamicsError> {
    for (what, m) in [
        ("generalized mass", &model.mass),
        ("generalized damping", &model.damping),
        ("generalized stiffness", &model.stiffness),
    ] {
        check_len(|| format!("{name}: {what} rows"), n, m.nrows())?;
        check_len(|| format!("{name}: {what} columns"), n, m.ncols())?;
        check_finite(|| format!("{name}: {what}"), m.iter())?;
    }
    Ok(())
}

fn factor_mass(name: &str, mass: &DMatrix<f64>) -> Result<Cholesky<f64, Dyn>, DynamicsError> {
    let scale = mass.abs().max();
    let symmetric = (mass - mass.transpose()).abs().max() <= 1e-9 * scale;
    Cholesky::new(mass.clone())
        .filter(|_| symmetric)
        .ok_or_else(|| DynamicsError::ModalMassNotPositiveDefinite {
            structure: name.to_owned(),
        })
}

/// How a lifting surface hangs on the body: its pivot, the rigid DOFs of its coupling matrix,
/// the coupling C_rb = Φᵀ M R, and (optionally) the body's mode shapes at the pivot.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceAttachment {
    /// Region name, for messages.
    pub name: String,
    /// Point the rigid rotations are taken about (the torque-tube pivot), structural body
    /// axes, m.
    pub pivot_m: Point3<f64>,
    /// The rigid DOFs of the coupling's columns.
    pub dofs: Vec<RigidDof>,
    /// C_rb (n_modes × dofs.len()).
    pub coupling: DMatrix<f64>,
    /// Motion of the pivot per unit body modal coordinate: rows translation x, y, z (m) and
    /// rotation x, y, z (rad), one column per body mode. Zeros: the pivot moves rigidly with
    /// the body frame.
    pub body_modes_at_pivot: DMatrix<f64>,
    /// The surface's rigid mass matrix about the pivot for (translation, rotation)
    /// accelerations ([`pivot_mass_matrix`]): the inertia the body's elastic motion at the
    /// pivot drives. Zero: a massless attachment.
    pub pivot_mass: Matrix6<f64>,
}

impl SurfaceAttachment {
    /// From a structure's rigid-body coupling capability, with the pivot fixed to the body
    /// frame (no body-mode motion at the pivot; set [`Self::body_modes_at_pivot`] to add it)
    /// and the surface's mass about the pivot.
    pub fn from_coupling(
        name: &str,
        coupling: &dyn RigidBodyCoupling,
        mass: &MassProperties,
        n_body_modes: usize,
    ) -> Self {
        let pivot_m = coupling.rigid_reference_point_m();
        Self {
            name: name.to_owned(),
            pivot_m,
            dofs: coupling.rigid_dofs().to_vec(),
            coupling: coupling.rigid_coupling().clone(),
            body_modes_at_pivot: DMatrix::zeros(6, n_body_modes),
            pivot_mass: pivot_mass_matrix(mass, &pivot_m),
        }
    }
}

/// Step of the central differences across the section in [`pivot_mode_shapes`], m: the beam's
/// field is linear across its section, so any step is exact there.
const SECTION_STEP_M: f64 = 0.01;

/// A structure's mode shapes at a point as rows translation x, y, z (m) and rotation x, y, z
/// (rad), one column per mode: the displacement at the point and the rotation of the body's
/// cross-section there (the plane x = x_P, in which a torque tube's bearing sits), from central
/// differences across the section: θx = ½ (∂u_z/∂y − ∂u_y/∂z), θy = ∂u_x/∂z, θz = −∂u_x/∂y.
/// Across the section, not ½ curl u: a beam's field off its axis has a shear term
/// ½ θx′ (y − y_axis) in the curl that no material line of the section turns by.
pub fn pivot_mode_shapes(
    structure: &dyn StructureModel,
    point_m: &Point3<f64>,
) -> Result<DMatrix<f64>, ModelError> {
    let h = SECTION_STEP_M;
    let offsets = [
        Vector3::zeros(),
        Vector3::new(0.0, h, 0.0),
        Vector3::new(0.0, -h, 0.0),
        Vector3::new(0.0, 0.0, h),
        Vector3::new(0.0, 0.0, -h),
    ];
    let mesh = PanelMesh {
        vertices: offsets.iter().map(|d| point_m + d).collect(),
        panels: Vec::new(),
        strips: Vec::new(),
        surfaces: Vec::new(),
    };
    let shapes = structure.mode_shapes_on(&mesh)?;
    let u = |vertex: usize, k: usize| {
        let d = &shapes.vertex_displacement;
        Vector3::new(
            d[(3 * vertex, k)],
            d[(3 * vertex + 1, k)],
            d[(3 * vertex + 2, k)],
        )
    };
    let n = shapes.n_modes();
    let mut out = DMatrix::zeros(6, n);
    for k in 0..n {
        let du_dy = (u(1, k) - u(2, k)) / (2.0 * h);
        let du_dz = (u(3, k) - u(4, k)) / (2.0 * h);
        let t = u(0, k);
        out[(0, k)] = t.x;
        out[(1, k)] = t.y;
        out[(2, k)] = t.z;
        out[(3, k)] = 0.5 * (du_dy.z - du_dz.y);
        out[(4, k)] = du_dz.x;
        out[(5, k)] = -du_dy.x;
    }
    Ok(out)
}

/// The 6 × 6 rigid mass matrix of a body about a point P for (a_P, α), the acceleration of P
/// and the angular acceleration: force m a_P − m \[c\]× α and moment about P m \[c\]× a_P + I_P α,
/// c = G − P, \[c\]× the cross-product matrix (symmetric because \[c\]× is skew). The
/// velocity-squared terms (m ω × (ω × c)) are left out: at the body's rates they are below
/// 1e-3 g at a pivot's offset from the surface's centre of mass.
pub fn pivot_mass_matrix(mass: &MassProperties, pivot_m: &Point3<f64>) -> Matrix6<f64> {
    let c = mass.center_of_mass_m - pivot_m;
    let skew = c.cross_matrix() * mass.mass_kg;
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(Matrix3::identity() * mass.mass_kg));
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew));
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&skew);
    m.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&mass.inertia_about(pivot_m));
    m
}

/// The wrench (force N, moment about P N m) of a 6 × 6 pivot mass on (a, α).
pub fn pivot_inertia(mass: &Matrix6<f64>, a: &Vector3<f64>, alpha: &Vector3<f64>) -> Loads {
    let w = mass * Vector6::new(a.x, a.y, a.z, alpha.x, alpha.y, alpha.z);
    Loads {
        force_n: Vector3::new(w[0], w[1], w[2]),
        moment_nm: Vector3::new(w[3], w[4], w[5]),
    }
}

/// The motion of a surface's root that drives its modal equations.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct RootMotion {
    /// Inertial acceleration of the pivot minus gravity (the specific force), body axes, m/s².
    pub specific_force_m_s2: Vector3<f64>,
    /// Angular acceleration of the torque tube, body axes, rad/s².
    pub angular_acceleration_rad_s2: Vector3<f64>,
}

impl RootMotion {
    /// The component of a rigid DOF (m/s² for translations, rad/s² for rotations).
    pub fn dof(&self, dof: RigidDof) -> f64 {
        match dof {
            RigidDof::TranslationX => self.specific_force_m_s2.x,
            RigidDof::TranslationY => self.specific_force_m_s2.y,
            RigidDof::TranslationZ => self.specific_force_m_s2.z,
            RigidDof::RotationX => self.angular_acceleration_rad_s2.x,
            RigidDof::RotationY => self.angular_acceleration_rad_s2.y,
            RigidDof::RotationZ => self.angular_acceleration_rad_s2.z,
        }
    }

    /// The root motion of a pivot at `offset_m` from the centre of mass, with the body's
    /// elastic motion there given by `body_modes_at_pivot` (6 × n_body) and the body's modal
    /// state and accelerations. No allocation.
    pub fn at_pivot(
        rigid_state: &RigidBodyState,
        rigid_rate: &RigidBodyDerivative,
        offset_m: &Vector3<f64>,
        body_modes_at_pivot: &DMatrix<f64>,
        body_modes: &ModalState,
        body_q_ddot: &DVector<f64>,
    ) -> Self {
        let mut displacement = Vector3::zeros();
        let mut velocity = Vector3::zeros();
        let mut acceleration = Vector3::zeros();
        let mut rotation_acceleration = Vector3::zeros();
        let n = body_modes_at_pivot
            .ncols()
            .min(body_modes.q.len())
            .min(body_q_ddot.len());
        for k in 0..n {
            let column = body_modes_at_pivot.column(k);
            let translation = Vector3::new(column[0], column[1], column[2]);
            displacement += translation * body_modes.q[k];
            velocity += translation * body_modes.q_dot[k];
            acceleration += translation * body_q_ddot[k];
            rotation_acceleration += Vector3::new(column[3], column[4], column[5]) * body_q_ddot[k];
        }
        let inertial = point_acceleration(
            rigid_state,
            rigid_rate,
            &(offset_m + displacement),
            &velocity,
            &acceleration,
        );
        Self {
            specific_force_m_s2: inertial - rigid_rate.gravity_body_m_s2,
            angular_acceleration_rad_s2: rigid_rate.angular_acceleration_body_rad_s2
                + rotation_acceleration,
        }
    }
}

/// How far a structure's modes are from mean axes: the largest |C_ij| / √(M_ii R_jj), the cosine
/// (in the mass inner product) between mode i and rigid motion j, with C = Φᵀ M R the rigid
/// coupling, M_ii the generalized mass and R_jj = ‖r_j‖²_M the rigid mass of DOF j (the mass for
/// a translation, the inertia about the reference point for a rotation). It lies in [0, 1] by
/// the Cauchy-Schwarz inequality; 0 means the modes are M-orthogonal to rigid motion and the
/// decoupled mean-axes equations are exact. The coordinator checks it at assembly.
pub fn mean_axes_cosine(
    coupling: &dyn RigidBodyCoupling,
    modal_mass: &DMatrix<f64>,
    mass: &MassProperties,
) -> f64 {
    let c = coupling.rigid_coupling();
    let inertia = mass.inertia_about(&coupling.rigid_reference_point_m());
    let rigid_mass = |dof: RigidDof| match dof {
        RigidDof::TranslationX | RigidDof::TranslationY | RigidDof::TranslationZ => mass.mass_kg,
        RigidDof::RotationX => inertia[(0, 0)],
        RigidDof::RotationY => inertia[(1, 1)],
        RigidDof::RotationZ => inertia[(2, 2)],
    };
    let mut worst: f64 = 0.0;
    for (j, &dof) in coupling.rigid_dofs().iter().enumerate().take(c.ncols()) {
        for i in 0..c.nrows().min(modal_mass.nrows()) {
            let norm = (modal_mass[(i, i)] * rigid_mass(dof)).sqrt();
            if norm > 0.0 {
                worst = worst.max(c[(i, j)].abs() / norm);
            }
        }
    }
    worst
}
