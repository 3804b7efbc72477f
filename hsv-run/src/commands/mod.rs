//! The `hsv-run` commands, one module each: clap arguments plus a `run` function. What more
//! than one command reads or prints lives here (the shared arguments, the flutter map's, the
//! controller gains) or in [`shared`] (the cluster shards, and the outputs a command and
//! `hsv-run merge` both write); a command imports no other command.

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
pub mod shared;
pub mod simulate;
pub mod trade;
pub mod trim;

/// The step rule every timed command uses (kept at this path for the commands).
pub use crate::steps;
pub mod vehicle;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;

use crate::outln;

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
    /// Run folder (default: a new `runs/<command>-<UTC time>-<ms>`); refused when it already
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

/// The gains of a designed controller (its `controller.json` report): an LQR axis in three
/// lines, any other entry (a plugin's report) as `key: JSON`.
pub(crate) fn print_gains(report: &serde_json::Value) -> Result<()> {
    let Some(axes) = report.as_object() else {
        return Ok(());
    };
    for (axis, r) in axes {
        if r.get("care_relative_residual").is_none() {
            outln!("{axis}: {r}")?;
            continue;
        }
        outln!(
            "{axis} LQR: states {}, inputs {}; CARE relative residual {:.2e}",
            r["states"],
            r["inputs"],
            r["care_relative_residual"].as_f64().unwrap_or(f64::NAN)
        )?;
        outln!("  K = {}", r["gain_k"])?;
        outln!("  closed-loop poles (re, im) = {}", r["closed_loop_poles"])?;
    }
    Ok(())
}

// The flutter map's arguments, shared by `flutter` and `trade --job flutter`.

/// `A:B` with 1 ≤ A < B, finite.
pub(crate) fn parse_mach_range(text: &str) -> Result<(f64, f64)> {
    let Some((a, b)) = text.split_once(':') else {
        bail!("--mach-range must be A:B (e.g. 2:20), got `{text}`");
    };
    let parse = |s: &str| -> Result<f64> {
        s.trim()
            .parse::<f64>()
            .with_context(|| format!("--mach-range: `{s}` is not a number"))
    };
    let (a, b) = (parse(a)?, parse(b)?);
    if !(a.is_finite() && b.is_finite() && a >= 1.0 && b > a) {
        bail!("--mach-range must have 1 <= A < B (supersonic aero models), got {a}:{b}");
    }
    Ok((a, b))
}

/// The Mach grid A, A + step, ..., B.
pub(crate) fn flutter_mach_grid(range: (f64, f64), step: f64) -> Result<Vec<f64>> {
    if !(step.is_finite() && step > 0.0) {
        bail!("--mach-step must be a positive number, got {step}");
    }
    let intervals = ((range.1 - range.0) / step).round();
    let limit = crate::limits::MAX_MACH_POINTS;
    if intervals + 1.0 > limit as f64 {
        bail!("--mach-step {step} gives {intervals:.3e} grid points; the limit is {limit} points");
    }
    let n = intervals as usize;
    Ok(crate::analysis::flutter::panel::mach_grid(
        range.0,
        range.1,
        n.max(1) + 1,
    ))
}

/// The times of a flutter map within their limits: at most
/// [`MAX_FLUTTER_TIMES`](crate::limits::MAX_FLUTTER_TIMES) of them, and the heating to the last
/// at most [`MAX_HEATING_STEPS`](crate::limits::MAX_HEATING_STEPS) conduction steps.
pub(crate) fn check_flutter_times(times_s: &[f64], dt_s: f64) -> Result<()> {
    use crate::limits::{MAX_FLUTTER_TIMES, MAX_HEATING_STEPS, check_count};
    check_count("--times-s (count)", times_s.len(), 1, MAX_FLUTTER_TIMES)?;
    let last_s = times_s.last().copied().unwrap_or(0.0);
    let steps = (last_s / dt_s).ceil();
    if steps.is_nan() || steps > MAX_HEATING_STEPS as f64 {
        bail!(
            "--times-s up to {last_s:e} s at --dt-s {dt_s} is {steps:.3e} heating steps; the limit is {MAX_HEATING_STEPS} steps (shorten the times or lengthen the step)"
        );
    }
    Ok(())
}
