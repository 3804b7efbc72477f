//! `hsv-run config`: the embedded sample-vehicle TOML (or a parsed user config) to start from,
//! and `hsv-run config --check FILE` to validate a config without running anything.

use std::path::Path;

use anyhow::Result;
use hsv_core::config::{LoadedConfig, SAMPLE_CONFIG_TOML};
use hsv_core::registry::Registry;

use crate::vehicle::assemble;
use crate::vehicle::rigid::{RigidVehicle, rigid_needs};
use crate::{out, outln};

/// Prints the embedded config verbatim (with its comments), or a user config as parsed.
pub fn print_config(path: Option<&Path>, json: bool) -> Result<()> {
    let loaded = LoadedConfig::load(path)?;
    if json {
        outln!("{}", serde_json::to_string_pretty(&loaded.config)?)?;
    } else if path.is_none() {
        out!("{SAMPLE_CONFIG_TOML}")?;
    } else {
        out!("{}", toml::to_string_pretty(&loaded.config)?)?;
    }
    Ok(())
}

/// Validates the config at `path` as every command would before running (parse, finite values,
/// reference values, plugins, vehicle geometry, region model names and roles), then builds the
/// rigid vehicle's models with their settings as `trim` would (the body's and surfaces' aero,
/// structure and friction models and the engine: a negative mass, a zero modulus or a count the
/// model refuses fails here, not inside a job), and says OK; the first problem is the error.
/// The conduction models are not built: `pod` would train its basis.
pub fn check_config(path: &Path, registry: &Registry, json: bool) -> Result<()> {
    let (loaded, registry) = super::load_config(Some(path), registry)?;
    let sets = assemble(&loaded, &registry, &rigid_needs("config --check"))?;
    RigidVehicle::new(sets)?;
    if json {
        let summary = serde_json::json!({"config": loaded.file, "valid": true});
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
    } else {
        outln!("{}: OK", loaded.file)?;
    }
    Ok(())
}
