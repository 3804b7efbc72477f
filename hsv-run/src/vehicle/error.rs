//! Why the coupled vehicle or one of its regions could not go on: the region and the quantity,
//! the exchange, the dynamics or the coupling; shared by the regions and the vehicle that couples
//! them.

use hsv_core::ModelError;

use super::AssemblyError;

/// Why a derivative could not be computed: the region and quantity.
#[derive(Debug, thiserror::Error)]
pub enum VehicleError {
    #[error("region `{region}`: {source}")]
    Model {
        region: String,
        #[source]
        source: ModelError,
    },
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
    /// The regions' exchange through the data manager refused a publication or read.
    #[error("exchanging region data: {0}")]
    Exchange(#[from] hsv_core::data::DataError),
    /// A run's inputs are refused (its steps, its tables).
    #[error("{0}")]
    Input(String),
    #[error(
        "body-surface coupling did not converge in {iterations} iterations at the interfaces \
         {interfaces}: last relative changes {residuals:?} (root forces, body η̈; tolerance \
         {tolerance})"
    )]
    Coupling {
        iterations: usize,
        interfaces: String,
        residuals: Vec<f64>,
        tolerance: f64,
    },
}

pub(in crate::vehicle) fn model_error(region: &str) -> impl Fn(ModelError) -> VehicleError + '_ {
    move |source| VehicleError::Model {
        region: region.to_owned(),
        source,
    }
}

pub(in crate::vehicle) fn assembly_error(region: &str, message: String) -> AssemblyError {
    AssemblyError::Model {
        file: String::new(),
        region: region.to_owned(),
        cause: message.into(),
    }
}
