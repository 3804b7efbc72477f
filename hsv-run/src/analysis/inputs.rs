//! The control input time tables: `[simulation.inputs]` as (time, value) tables of the elevon
//! and fuel equivalence ratio offsets from trim, their checks, parsing (over the paper's elevon
//! doublet, Fig. 10) and evaluation at a time.

use crate::vehicle::partitioned::{ElevonCommand, FlightControls};

/// A control input as a table of (time s, value) pairs, linear between them and held beyond.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputTable {
    pub time_s: Vec<f64>,
    pub value: Vec<f64>,
}

/// Why an input table is refused: its key path and the problem.
#[derive(Debug, thiserror::Error)]
#[error("input `{key}`: {message}")]
pub struct InputError {
    pub key: String,
    pub message: String,
}

impl InputTable {
    /// A constant input.
    pub fn constant(value: f64) -> Self {
        Self {
            time_s: vec![0.0],
            value: vec![value],
        }
    }

    /// Checks the table: equal lengths, at least one row, finite, times strictly increasing.
    pub fn check(&self, key: &str) -> Result<(), InputError> {
        let fail = |message: String| InputError {
            key: key.to_owned(),
            message,
        };
        if self.time_s.is_empty() || self.time_s.len() != self.value.len() {
            return Err(fail(format!(
                "needs as many values as times, at least one ({} times, {} values)",
                self.time_s.len(),
                self.value.len()
            )));
        }
        if let Some(i) = (0..self.time_s.len())
            .find(|&i| !self.time_s[i].is_finite() || !self.value[i].is_finite())
        {
            return Err(fail(format!(
                "row {i} is not finite (time {} s, value {})",
                self.time_s[i], self.value[i]
            )));
        }
        if let Some(i) = (1..self.time_s.len()).find(|&i| self.time_s[i] <= self.time_s[i - 1]) {
            return Err(fail(format!(
                "times must increase: row {i} ({} s) is not after row {} ({} s)",
                self.time_s[i],
                i - 1,
                self.time_s[i - 1]
            )));
        }
        Ok(())
    }

    /// The input at `t`: linear between rows, the first or last value outside them.
    pub fn at(&self, t: f64) -> f64 {
        let n = self.time_s.len();
        if n == 0 {
            return 0.0;
        }
        let k = self.time_s.partition_point(|&ti| ti <= t);
        if k == 0 {
            return self.value[0];
        }
        if k == n {
            return self.value[n - 1];
        }
        let (t0, t1) = (self.time_s[k - 1], self.time_s[k]);
        let w = (t - t0) / (t1 - t0);
        self.value[k - 1] * (1.0 - w) + self.value[k] * w
    }
}

/// The control inputs as offsets from trim.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Inputs {
    /// Symmetric elevon added to the trim elevon, deg.
    pub symmetric_elevon_deg: InputTable,
    /// Differential elevon (left = +, right = −), deg.
    pub differential_elevon_deg: InputTable,
    /// Fuel equivalence ratio added to the trim φ.
    pub fuel_equivalence_ratio: InputTable,
}

impl Inputs {
    /// The paper's elevon doublet (Fig. 10): +1° ramped in from 0.5 s to 1.0 s, held to 1.5 s,
    /// then ramped back to trim by 2.0 s (our choice of the return: the paper says only that the
    /// elevons return to trim).
    pub fn paper_doublet() -> Self {
        Self {
            symmetric_elevon_deg: InputTable {
                time_s: vec![0.0, 0.5, 1.0, 1.5, 2.0],
                value: vec![0.0, 0.0, 1.0, 1.0, 0.0],
            },
            differential_elevon_deg: InputTable::constant(0.0),
            fuel_equivalence_ratio: InputTable::constant(0.0),
        }
    }

    /// The paper's doublet overlaid by the tables of `table` (a `[simulation.inputs]` table at
    /// `key` in `file`).
    pub fn from_table(table: &toml::Table, file: &str, key: &str) -> Result<Self, InputError> {
        let mut merged = Inputs::paper_doublet();
        for (name, value) in table {
            let path = format!("{key}.{name}");
            let fail = |message: String| InputError {
                key: path.clone(),
                message: format!("{file}: {message}"),
            };
            let t: InputTable = hsv_core::config::parse_table(
                value
                    .as_table()
                    .ok_or_else(|| fail("must be a table".to_owned()))?,
                file,
                &path,
            )
            .map_err(|e| fail(e.to_string()))?;
            match name.as_str() {
                "symmetric_elevon_deg" => merged.symmetric_elevon_deg = t,
                "differential_elevon_deg" => merged.differential_elevon_deg = t,
                "fuel_equivalence_ratio" => merged.fuel_equivalence_ratio = t,
                _ => {
                    return Err(fail(
                        "unknown; expected symmetric_elevon_deg, differential_elevon_deg or \
                         fuel_equivalence_ratio"
                            .to_owned(),
                    ));
                }
            }
        }
        merged.check(key)?;
        Ok(merged)
    }

    pub fn check(&self, key: &str) -> Result<(), InputError> {
        self.symmetric_elevon_deg
            .check(&format!("{key}.symmetric_elevon_deg"))?;
        self.differential_elevon_deg
            .check(&format!("{key}.differential_elevon_deg"))?;
        self.fuel_equivalence_ratio
            .check(&format!("{key}.fuel_equivalence_ratio"))
    }

    /// The controls at `t` around the trim controls.
    pub fn controls(&self, trim: &FlightControls, t: f64) -> FlightControls {
        FlightControls {
            elevon: ElevonCommand {
                symmetric_rad: trim.elevon.symmetric_rad
                    + self.symmetric_elevon_deg.at(t).to_radians(),
                differential_rad: trim.elevon.differential_rad
                    + self.differential_elevon_deg.at(t).to_radians(),
            },
            fuel_equivalence_ratio: trim.fuel_equivalence_ratio + self.fuel_equivalence_ratio.at(t),
        }
    }
}
