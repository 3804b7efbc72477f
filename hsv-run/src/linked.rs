//! The one place that names every built-in model crate, so their `inventory` entries are linked.
//!
//! A crate that is only listed in Cargo.toml is never linked and its registrations vanish; each
//! `use ... as _;` below keeps one in. Add a line here when you add a model crate.

use hsv_core::registry::{Registry, RegistryError};

use hsv_model_conduction as _;
use hsv_model_convolution_rom as _;
use hsv_model_eckert as _;
use hsv_model_free_free_beam as _;
use hsv_model_kriging as _;
use hsv_model_newtonian as _;
use hsv_model_piston_theory as _;
use hsv_model_ritz_plate as _;
use hsv_model_scramjet as _;
use hsv_model_shock_expansion as _;

/// Every built-in model of this binary.
pub fn registry() -> Result<Registry, RegistryError> {
    Registry::builtin()
}

/// [`registry`] built once per process and shared: for tests, benches and anything else that
/// asks for the built-in models many times.
pub fn shared_registry() -> Result<&'static Registry, RegistryError> {
    static REGISTRY: std::sync::OnceLock<Result<Registry, RegistryError>> =
        std::sync::OnceLock::new();
    REGISTRY
        .get_or_init(registry)
        .as_ref()
        .map_err(Clone::clone)
}
