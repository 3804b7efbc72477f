//! `hsv-run config`: the embedded sample-vehicle TOML (or a parsed user config) to start from.

use std::path::Path;

use anyhow::Result;
use hsv_core::config::{LoadedConfig, SAMPLE_CONFIG_TOML};

/// Prints the embedded config verbatim (with its comments), or a user config as parsed.
pub fn print_config(path: Option<&Path>, json: bool) -> Result<()> {
    let loaded = LoadedConfig::load(path)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&loaded.config)?);
    } else if path.is_none() {
        print!("{SAMPLE_CONFIG_TOML}");
    } else {
        print!("{}", toml::to_string_pretty(&loaded.config)?);
    }
    Ok(())
}
