//! Flexible-vehicle equations of motion (paper Eq. 1), the fixed-step integrator and the
//! linearization machinery (paper Eqs. 6-7) the vehicle coordinator calls.
//!
//! Plain data in, plain data out: the coordinator computes the loads (aero, engine,
//! lifting-surface root loads, generalized forces) from a state; this module turns a state and
//! those loads into the state derivative, steps it, and linearizes around a point. Once the
//! workspaces are built nothing here allocates per derivative or per step.
//!
//! - [`rigid_body`]: the 6-DOF rigid motion of the body frame (centre of mass, NED flat earth,
//!   quaternion attitude, altitude-dependent gravity).
//! - [`modal`]: modal equations M q̈ + C q̇ + K q = Q − C_rb a for the free-free body (mean axes)
//!   and for each lifting surface driven by the motion of its root.
//! - [`equations_of_motion`]: the assembled vehicle state, loads and derivative.
//! - [`state_layout`]: the flat state-vector layout (quaternion or 3-2-1 Euler attitude) the
//!   integrator and linearization work on.
//! - [`integrate`]: classical fourth-order Runge-Kutta on a preallocated workspace.
//! - [`linearize`](mod@linearize): A, B, C, D by central differences with the paper's perturbation rule, and
//!   the paper's sixth-order forward difference of a sampled time history.
//! - [`flight_modes`](mod@flight_modes): eigenvalues with frequency and damping, named by eigenvector content
//!   (short period, phugoid, roll, Dutch roll, spiral, structural modes).

pub mod equations_of_motion;
pub mod flight_modes;
pub mod integrate;
pub mod linearize;
pub mod modal;
pub mod rigid_body;
pub mod state_layout;

pub use equations_of_motion::{VehicleDerivative, VehicleDynamics, VehicleLoads, VehicleState};
pub use flight_modes::{FlightMode, ModeName, ModeScales, StateRole, flight_modes};
pub use integrate::{ExponentialRk4, LinearBlock, Rk4};
pub use linearize::{LinearModel, PerturbationRule, linearize, linearize_outputs};
pub use modal::{
    ModalDynamics, ModalRate, ModalState, RootMotion, SurfaceAttachment, mean_axes_cosine,
};
pub use rigid_body::{EarthModel, GravityModel, RigidBody, RigidBodyDerivative, RigidBodyState};
pub use state_layout::{AttitudeCoordinates, StateLayout};

use hsv_core::linalg::EigenError;

/// Why a derivative, a step or a linearization could not be computed. Each names the quantity,
/// its value and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum DynamicsError {
    #[error("{quantity} must be {allowed}, got {value}")]
    InvalidParameter {
        quantity: String,
        value: f64,
        allowed: &'static str,
    },
    #[error("{what}: expected {expected} entries, got {got}")]
    Dimension {
        what: String,
        expected: usize,
        got: usize,
    },
    #[error("{structure}: the generalized mass matrix is not symmetric positive definite")]
    ModalMassNotPositiveDefinite { structure: String },
    #[error(
        "the inertia tensor is not symmetric positive definite (diagonal {diagonal_kg_m2:?} kg m²)"
    )]
    InertiaNotPositiveDefinite { diagonal_kg_m2: [f64; 3] },
    #[error("{quantity} is not finite (entry {index}: {value})")]
    NonFinite {
        quantity: String,
        index: usize,
        value: f64,
    },
    #[error(
        "the 3-2-1 Euler angles are singular at pitch {pitch_deg:.6} deg (gimbal lock); use the quaternion layout"
    )]
    GimbalLock { pitch_deg: f64 },
    #[error("the attitude quaternion has zero or non-finite norm")]
    DegenerateQuaternion,
    #[error("eigen-analysis of the state matrix: {0}")]
    Eigen(#[from] EigenError),
}

/// The first non-finite entry of `values`, as an error naming `quantity`.
pub(crate) fn check_finite<'a>(
    quantity: impl FnOnce() -> String,
    values: impl IntoIterator<Item = &'a f64>,
) -> Result<(), DynamicsError> {
    match values.into_iter().enumerate().find(|(_, v)| !v.is_finite()) {
        None => Ok(()),
        Some((index, &value)) => Err(DynamicsError::NonFinite {
            quantity: quantity(),
            index,
            value,
        }),
    }
}

/// `Ok` when `got == expected`, otherwise a dimension error naming `what`.
pub(crate) fn check_len(
    what: impl FnOnce() -> String,
    expected: usize,
    got: usize,
) -> Result<(), DynamicsError> {
    if expected == got {
        Ok(())
    } else {
        Err(DynamicsError::Dimension {
            what: what(),
            expected,
            got,
        })
    }
}
