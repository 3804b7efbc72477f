//! The error every model returns: what went wrong, in which quantity, with the allowed values.

use crate::atmosphere::AtmosphereError;
use crate::gas::GasError;

/// Why a model could not be built or evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A model's settings table is wrong; `key_path` is the full dotted path in the config file.
    #[error("{file}: key `{key_path}`: {message}")]
    Settings {
        file: String,
        key_path: String,
        message: String,
    },
    /// An input is outside what the model can handle.
    #[error("{model}: {quantity} = {value} is outside the model's range ({allowed})")]
    OutOfRange {
        model: String,
        quantity: String,
        value: f64,
        allowed: String,
    },
    /// A computed quantity became NaN or infinite.
    #[error("{model}: {quantity} became non-finite{location}")]
    NonFinite {
        model: String,
        quantity: String,
        location: String,
    },
    /// The model cannot do what an analysis asked of it.
    #[error("model `{model}` has no {capability}, which {needed_by} needs")]
    Unsupported {
        model: String,
        capability: String,
        needed_by: String,
    },
    /// Inputs do not fit together (buffer lengths, meshes, mode counts).
    #[error("{model}: {message}")]
    Inconsistent { model: String, message: String },
    /// The model was asked to work on a region it is not made for (a plate model on the body).
    #[error("{model}: {message}")]
    WrongRegion { model: String, message: String },
    #[error(transparent)]
    Gas(#[from] GasError),
    #[error(transparent)]
    Atmosphere(#[from] AtmosphereError),
}

impl ModelError {
    /// A settings error at `key` under the table at `table_path` (the table itself when `key`
    /// is empty) of config `file`.
    pub fn settings_at(
        file: &str,
        table_path: &str,
        key: &str,
        message: impl Into<String>,
    ) -> Self {
        Self::Settings {
            file: file.to_owned(),
            key_path: if key.is_empty() {
                table_path.to_owned()
            } else {
                format!("{table_path}.{key}")
            },
            message: message.into(),
        }
    }

    /// Shorthand for [`ModelError::OutOfRange`].
    pub fn out_of_range(
        model: &str,
        quantity: &str,
        value: f64,
        allowed: impl Into<String>,
    ) -> Self {
        Self::OutOfRange {
            model: model.to_owned(),
            quantity: quantity.to_owned(),
            value,
            allowed: allowed.into(),
        }
    }

    /// A quantity that became NaN or infinite on mesh panel `panel`.
    pub fn non_finite_at_panel(model: &str, quantity: &str, panel: usize) -> Self {
        Self::NonFinite {
            model: model.to_owned(),
            quantity: quantity.to_owned(),
            location: format!(" at panel {panel}"),
        }
    }

    /// Shorthand for [`ModelError::Inconsistent`].
    pub fn inconsistent(model: &str, message: impl Into<String>) -> Self {
        Self::Inconsistent {
            model: model.to_owned(),
            message: message.into(),
        }
    }
}
