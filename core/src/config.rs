//! The vehicle config file: its types, loading, and errors that name the file and key path.
//!
//! Every table is `deny_unknown_fields`, so a misspelt key is an error that names the key path
//! and the allowed keys, never a silently ignored setting.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

use crate::aero::ReferenceValues;
use crate::error::ModelError;
use crate::gas::PerfectGas;
use crate::vehicle::{GeometryConfig, LiftingSurfaceConfig};

/// The sample vehicle config, embedded in every binary.
pub const SAMPLE_CONFIG_TOML: &str = include_str!("../../configs/sample-hsv.toml");

/// Name under which the embedded sample config is reported in messages.
pub const EMBEDDED_CONFIG_NAME: &str = "<embedded configs/sample-hsv.toml>";

/// A config error: where (file and dotted key path) and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {}{message}", if key_path.is_empty() { String::new() } else { format!("key `{key_path}`: ") })]
pub struct ConfigError {
    pub file: String,
    pub key_path: String,
    pub message: String,
}

impl From<ConfigError> for ModelError {
    fn from(error: ConfigError) -> Self {
        ModelError::Settings {
            file: error.file,
            key_path: error.key_path,
            message: error.message,
        }
    }
}

/// The flight condition a command starts from.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlightConfig {
    pub mach: f64,
    /// Geometric altitude, m.
    pub altitude_m: f64,
    #[serde(default)]
    pub alpha_deg: f64,
    #[serde(default)]
    pub beta_deg: f64,
}

/// Model names for one region; absent roles are not modelled in that region.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionModels {
    pub aero: Option<String>,
    pub heat_flux: Option<String>,
    pub conduction: Option<String>,
    pub structure: Option<String>,
    pub propulsion: Option<String>,
}

/// Which models each region of the vehicle runs.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionsConfig {
    #[serde(default)]
    pub main_body: RegionModels,
    #[serde(default)]
    pub lifting_surfaces: RegionModels,
    #[serde(default)]
    pub propulsion: RegionModels,
}

/// The whole vehicle config.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HsvConfig {
    pub flight: FlightConfig,
    pub reference: ReferenceValues,
    #[serde(default)]
    pub gas: PerfectGas,
    pub geometry: GeometryConfig,
    pub lifting_surface: LiftingSurfaceConfig,
    #[serde(default)]
    pub regions: RegionsConfig,
    /// Per-model settings, `[models.<name>]`; checked by each model's constructor.
    #[serde(default)]
    pub models: BTreeMap<String, toml::Table>,
    /// Dylib plugins to load before models are looked up.
    #[serde(default)]
    pub plugins: Vec<PathBuf>,
}

/// A parsed config together with its raw table (for model constructors) and its origin.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedConfig {
    pub config: HsvConfig,
    pub raw: toml::Table,
    /// The file name used in messages.
    pub file: String,
}

impl LoadedConfig {
    /// The embedded sample vehicle.
    pub fn sample() -> Result<Self, ConfigError> {
        parse_config(SAMPLE_CONFIG_TOML, EMBEDDED_CONFIG_NAME)
    }

    /// The config at `path`, or the embedded sample when `path` is `None`.
    pub fn load(path: Option<&Path>) -> Result<Self, ConfigError> {
        match path {
            None => Self::sample(),
            Some(path) => {
                let file = path.display().to_string();
                let text = std::fs::read_to_string(path).map_err(|e| ConfigError {
                    file: file.clone(),
                    key_path: String::new(),
                    message: format!("cannot read: {e}"),
                })?;
                parse_config(&text, &file)
            }
        }
    }

    /// Settings table of model `name` (`[models.<name>]`), empty if absent.
    pub fn model_settings(&self, name: &str) -> &toml::Table {
        static EMPTY: std::sync::OnceLock<toml::Table> = std::sync::OnceLock::new();
        self.config
            .models
            .get(name)
            .unwrap_or_else(|| EMPTY.get_or_init(toml::Table::new))
    }
}

/// Parses config text; `file` names it in errors.
pub fn parse_config(text: &str, file: &str) -> Result<LoadedConfig, ConfigError> {
    let raw: toml::Table = toml::from_str(text).map_err(|e| {
        let place = e.span().map_or_else(String::new, |span| {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
            format!(" at line {line}, column {column}")
        });
        ConfigError {
            file: file.to_owned(),
            key_path: String::new(),
            message: format!("not valid TOML{place}: {}", first_line(e.message())),
        }
    })?;
    let config: HsvConfig = parse_table(&raw, file, "")?;
    Ok(LoadedConfig {
        config,
        raw,
        file: file.to_owned(),
    })
}

/// Deserializes `table` (found at `key_path` in `file`) into `T`, naming the full key path of
/// the first offending key.
pub fn parse_table<T: DeserializeOwned>(
    table: &toml::Table,
    file: &str,
    key_path: &str,
) -> Result<T, ConfigError> {
    let value = toml::Value::Table(table.clone());
    serde_path_to_error::deserialize(value).map_err(|error| {
        let inner = error.path().to_string();
        let path = match (key_path.is_empty(), inner == ".") {
            (true, _) => inner,
            (false, true) => key_path.to_owned(),
            (false, false) => format!("{key_path}.{inner}"),
        };
        ConfigError {
            file: file.to_owned(),
            key_path: path,
            message: first_line(&error.inner().to_string()),
        }
    })
}

/// The first line of a message: deserializer errors append context lines the key path already gives.
fn first_line(message: &str) -> String {
    message.lines().next().unwrap_or_default().trim().to_owned()
}
