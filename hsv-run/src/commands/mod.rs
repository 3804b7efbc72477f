//! The `hsv-run` commands, one module each: clap arguments plus a `run` function.

pub mod aero;
pub mod catalog;
pub mod compare;
pub mod config;
pub mod engine;
pub mod flutter;
pub mod fmu;
pub mod heat;
pub mod linearize;
pub mod merge;
pub mod modes;
pub mod rom;
pub mod shard;
pub mod simulate;
pub mod trade;
pub mod trim;

/// The step rule every timed command uses (kept at this path for the commands).
pub use crate::steps;
pub mod vehicle;

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

/// `--out DIR` and `--force`, shared by every command that writes a run folder.
#[derive(Args, Debug, Clone, Default)]
pub struct OutArgs {
    /// Run folder (default: a new runs/<command>-<UTC time>-<ms>); refused when it already
    /// holds files, unless --force.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write into a non-empty --out folder (files of the same name are replaced).
    #[arg(long, requires = "out")]
    pub force: bool,
}

/// Loads the config at `path` (or the embedded sample) and returns it with `registry` extended by
/// the plugins the config lists (paths relative to the config file), after checking everything
/// a command relies on ([`validate_config`]), so a bad config fails before any work starts.
pub fn load_config(path: Option<&Path>, registry: &Registry) -> Result<(LoadedConfig, Registry)> {
    let (loaded, registry) = load_config_unchecked(path, registry)?;
    validate_config(&loaded, &registry)?;
    Ok((loaded, registry))
}

/// Checks a loaded config beyond parsing (which already checked keys, types, finite numbers and
/// reference values): the vehicle geometry builds, and every `[regions.*]` model name is a
/// registered model of the role its key names.
pub fn validate_config(loaded: &LoadedConfig, registry: &Registry) -> Result<()> {
    loaded.check_models(registry)?;
    loaded.vehicle()?;
    Ok(())
}

/// A command's arguments parsed from `flags` (no program or command name) exactly as the CLI
/// parses them, checks and defaults included: how Python's `hsv.aero` and `hsv.flutter` take
/// the commands' flags.
pub fn parse_flags<A: clap::Args + clap::FromArgMatches>(
    command: &'static str,
    flags: &[String],
) -> Result<A> {
    let cli = A::augment_args(clap::Command::new(command).no_binary_name(true));
    let matches = cli
        .try_get_matches_from(flags)
        .map_err(|e| anyhow::anyhow!("{command}: {}", e.render().to_string().trim_end()))?;
    Ok(A::from_arg_matches(&matches)?)
}

/// [`load_config`] without [`validate_config`].
pub(crate) fn load_config_unchecked(
    path: Option<&Path>,
    registry: &Registry,
) -> Result<(LoadedConfig, Registry)> {
    let loaded = LoadedConfig::load(path)?;
    let base = path
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let registry = with_plugins(&loaded, &base, registry)?;
    Ok((loaded, registry))
}

/// `registry` extended by the plugins `loaded` lists (paths relative to `base`).
fn with_plugins(loaded: &LoadedConfig, base: &Path, registry: &Registry) -> Result<Registry> {
    let mut registry = registry.clone();
    for plugin in &loaded.config.plugins {
        registry
            .load_plugin(&base.join(plugin))
            .with_context(|| format!("{}: key `plugins`", loaded.file))?;
    }
    Ok(registry)
}

/// [`load_config`] of a config's TOML `text` (named `file` in messages; plugin paths relative
/// to the working directory): for hosts that build configs in memory (Python dicts).
pub fn load_config_text(
    text: &str,
    file: &str,
    registry: &Registry,
) -> Result<(LoadedConfig, Registry)> {
    let loaded = hsv_core::config::parse_config(text, file)?;
    let registry = with_plugins(&loaded, Path::new(""), registry)?;
    validate_config(&loaded, &registry)?;
    Ok((loaded, registry))
}
