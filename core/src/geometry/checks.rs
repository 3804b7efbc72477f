//! Why a vehicle geometry is refused, and the range checks every part of it uses.

use crate::mesh::MeshError;

/// Why the vehicle geometry could not be read or built.
#[derive(Debug, thiserror::Error)]
pub enum VehicleError {
    /// A config value is out of range or inconsistent with another.
    #[error("[{table}] {key} = {value}: {message}")]
    Invalid {
        table: &'static str,
        key: &'static str,
        value: String,
        message: String,
    },
    /// The config text could not be parsed.
    #[error("{origin}: {message}")]
    Parse { origin: String, message: String },
    /// The generated mesh failed validation (a bug or an extreme config).
    #[error("{what} mesh: {source}")]
    Mesh {
        what: &'static str,
        source: MeshError,
    },
}

pub(crate) fn invalid(
    table: &'static str,
    key: &'static str,
    value: impl ToString,
    message: impl Into<String>,
) -> VehicleError {
    VehicleError::Invalid {
        table,
        key,
        value: value.to_string(),
        message: message.into(),
    }
}

/// Checks that `v` is finite and inside (lo, hi) (open) or [lo, hi] (closed).
pub(crate) fn check_range(
    table: &'static str,
    key: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    closed: bool,
) -> Result<(), VehicleError> {
    let inside = if closed {
        v >= lo && v <= hi
    } else {
        v > lo && v < hi
    };
    if v.is_finite() && inside {
        Ok(())
    } else {
        let (l, r) = if closed { ("[", "]") } else { ("(", ")") };
        Err(invalid(
            table,
            key,
            v,
            format!("must be finite and in {l}{lo}, {hi}{r}"),
        ))
    }
}

/// Checks a panel count is in [min, 10000].
pub(crate) fn check_count(
    table: &'static str,
    key: &'static str,
    n: usize,
    min: usize,
) -> Result<(), VehicleError> {
    if (min..=10_000).contains(&n) {
        Ok(())
    } else {
        Err(invalid(
            table,
            key,
            n,
            format!("must be between {min} and 10000"),
        ))
    }
}
