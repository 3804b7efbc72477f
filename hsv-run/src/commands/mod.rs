//! The `hsv-run` commands, one module each: clap arguments plus a `run` function.

pub mod aero;
pub mod catalog;
pub mod config;
pub mod engine;
pub mod heat;
pub mod modes;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;

/// `--json`, shared by every command.
#[derive(Args, Debug, Clone, Copy)]
pub struct JsonFlag {
    /// Print a machine-readable JSON summary instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// `--config FILE`, shared by every command that needs a vehicle.
#[derive(Args, Debug, Clone)]
pub struct ConfigArg {
    /// Vehicle config TOML (default: the embedded sample vehicle; `hsv-run config` prints it).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

/// Loads the config at `path` (or the embedded sample) and returns it with `registry` extended by
/// the plugins the config lists (paths relative to the config file).
pub fn load_config(path: Option<&Path>, registry: &Registry) -> Result<(LoadedConfig, Registry)> {
    let loaded = LoadedConfig::load(path)?;
    let mut registry = registry.clone();
    let base = path
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .unwrap_or_default();
    for plugin in &loaded.config.plugins {
        registry
            .load_plugin(&base.join(plugin))
            .with_context(|| format!("{}: key `plugins`", loaded.file))?;
    }
    Ok((loaded, registry))
}
