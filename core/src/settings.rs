//! Typed values from TOML tables, with errors naming the file and the dotted key path: the
//! one parser behind the config ([`crate::config`]) and every model's settings
//! ([`crate::registry::ModelContext::parse_settings`]), so neither module needs the other.

use serde::de::DeserializeOwned;

use crate::error::ModelError;

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
pub(crate) fn first_line(message: &str) -> String {
    message.lines().next().unwrap_or_default().trim().to_owned()
}
