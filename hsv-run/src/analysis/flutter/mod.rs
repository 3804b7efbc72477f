//! Flutter of a lifting surface (paper §IV.D, Eqs. 4-8, Figs. 14-16): the surface alone in the
//! flow with its root fixed, a linear state matrix identified around its equilibrium, its
//! eigenvalues, and versus time in the flow as the surface heats the flutter Mach number (an
//! oscillatory pair crosses zero real part) and, apart from it, the divergence Mach number (a
//! real root crosses: static divergence or thermal buckling in the flow).
//!
//! - [`surface`]: the Ritz equations M q̈ + C q̇ + K q = Q_aero(q, q̇) + Q_T of one surface with
//!   the aero of a named model on the deformed mesh, its static equilibrium and the identified
//!   state matrix A (central differences, Eqs. 6-7) from the direct state derivative or from the
//!   paper's sixth-order forward difference over 7 steps of the surface simulation.
//! - [`stability`](mod@stability): eigenvalues and eigenvectors of A with frequency and damping per root, mode
//!   tracking by eigenvector correlation (MAC), and Brent's root finder for the crossing.
//! - [`sweep`]: the heated surface (from 293 K, heated by the flow at each Mach number for the
//!   requested time) analysed over a Mach grid and times.
//! - [`boundary`]: the flutter and divergence Mach numbers per time from the swept grid
//!   (bracketing on the grid, Brent's method between) and the mode tracking across it.
//! - [`panel`]: the classical check of the same path, a simply supported rectangular panel
//!   under first-order piston theory without aerodynamic damping (Dowell's λ).

pub mod boundary;
pub mod panel;
pub mod stability;
pub mod surface;
pub mod sweep;

use hsv_core::ModelError;
use hsv_core::coupling::CouplingError;
use hsv_core::linalg::EigenError;

use crate::dynamics::DynamicsError;
use crate::vehicle::{AssemblyError, RegionError};

pub use stability::{FlutterRoot, Instability, Stability, brent_root, mac, stability};
pub use surface::{DerivativeMethod, Equilibrium, Identification, SurfaceDynamics, SurfaceOptions};

/// Why a flutter point could not be computed; each names the quantity and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum FlutterError {
    #[error("{quantity} = {value} is outside its range ({allowed})")]
    InvalidInput {
        quantity: String,
        value: f64,
        allowed: &'static str,
    },
    #[error("`{model}`: {source}")]
    Model {
        model: String,
        #[source]
        source: ModelError,
    },
    /// The structure lost positive-definite stiffness (thermal buckling).
    #[error("buckled: {0}")]
    Buckled(String),
    /// The surface's wall passed its melting point while heating.
    #[error("melting: {0}")]
    Melting(String),
    #[error(
        "no static equilibrium after {iterations} Newton iterations (residual {residual:.3e} of \
         the load scale {scale:.3e}): the surface may have diverged"
    )]
    NoEquilibrium {
        iterations: usize,
        residual: f64,
        scale: f64,
    },
    #[error("{0}")]
    Inconsistent(String),
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
    #[error(transparent)]
    Coupling(#[from] CouplingError),
    #[error("eigen-analysis of the state matrix: {0}")]
    Eigen(#[from] EigenError),
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Region(#[from] RegionError),
    #[error(transparent)]
    Config(#[from] hsv_core::config::ConfigError),
}

impl FlutterError {
    /// A model's error, named.
    pub fn model(model: &str, source: ModelError) -> Self {
        FlutterError::Model {
            model: model.to_owned(),
            source,
        }
    }

    /// Whether this is a physical end of the analysis (buckled or melted surface) rather than
    /// bad input or a numerical failure.
    pub fn is_physical_limit(&self) -> bool {
        matches!(self, FlutterError::Buckled(_) | FlutterError::Melting(_))
    }
}

/// `value` finite and > 0, else an error naming `quantity`.
pub(crate) fn check_positive(quantity: &str, value: f64) -> Result<(), FlutterError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FlutterError::InvalidInput {
            quantity: quantity.to_owned(),
            value,
            allowed: "finite and > 0",
        })
    }
}
