//! `hsv-run config`: the embedded sample-vehicle TOML (or a parsed user config) to start from,
//! and `hsv-run config --check FILE` to validate a config without running anything.

use std::path::Path;

use anyhow::Result;
use hsv_core::config::{LoadedConfig, SAMPLE_CONFIG_TOML};
use hsv_core::registry::Registry;

use crate::vehicle::assemble;
use crate::vehicle::check::check_models;
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
/// reference values, plugins, vehicle geometry, region model names and roles), then checks
/// every model a job could build with its settings in its region (`pod` and the other models
/// with costly constructors check their settings and base models without training), and the
/// rigid vehicle `trim` assembles. Every problem is printed, each on its own `error:` line, and
/// the command fails with their count; a sound config says OK.
pub fn check_config(path: &Path, registry: &Registry, json: bool) -> Result<()> {
    let (loaded, registry) = super::load_config_unchecked(Some(path), registry)?;
    let mut problems: Vec<String> = (loaded.model_name_problems(&registry).iter())
        .map(ToString::to_string)
        .collect();
    match loaded.vehicle() {
        // Without the vehicle's geometry no region can be built.
        Err(e) => problems.push(e.to_string()),
        Ok(_) => problems.extend(
            check_models(&loaded, &registry)
                .iter()
                .map(ToString::to_string),
        ),
    }
    if problems.is_empty() {
        // What the models cannot see alone: the vehicle they make together.
        let rigid = assemble(&loaded, &registry, &rigid_needs("config --check"))
            .map_err(anyhow::Error::from)
            .and_then(|sets| Ok(RigidVehicle::new(sets)?));
        if let Err(e) = rigid {
            problems.push(crate::error_line::error_line(&e));
        }
    }
    if json {
        let summary = serde_json::json!({
            "config": loaded.file,
            "valid": problems.is_empty(),
            "problems": problems,
        });
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
    } else if problems.is_empty() {
        outln!("{}: OK", loaded.file)?;
    } else {
        for problem in &problems {
            eprintln!("error: {problem}");
        }
    }
    match problems.len() {
        0 => Ok(()),
        n => anyhow::bail!(
            "{}: {n} problem{} found",
            loaded.file,
            if n == 1 { "" } else { "s" }
        ),
    }
}
