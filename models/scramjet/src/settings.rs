//! Settings of `[models.scramjet-1d]` and `[models.scramjet-q1d]`, their defaults and checks.
//!
//! Every key has a default, so a config without the table runs the sample engine; unknown keys
//! are errors naming the key path. Area ratios left out follow the `[geometry]` table.

use hsv_core::error::ModelError;
use hsv_core::geometry::GeometryConfig;

use crate::section::Fuel;

/// Hydrogen-air stoichiometric fuel/air mass ratio (Heiser & Pratt, Hypersonic Airbreathing
/// Propulsion, AIAA 1994: f_st = 0.0291 for H2).
pub const HYDROGEN_STOICHIOMETRIC_FUEL_AIR_RATIO: f64 = 0.0291;
/// Hydrogen lower heating value, J/kg (Heiser & Pratt 1994: h_PR = 119,954 kJ/kg ≈ 120 MJ/kg).
pub const HYDROGEN_HEATING_VALUE_J_KG: f64 = 1.2e8;
/// Our choice: 90 % of the heating value released (the 1-D models have no finite-rate chemistry).
pub const DEFAULT_COMBUSTION_EFFICIENCY: f64 = 0.9;
/// Our choice: five spanwise sections (two more than the quadratic fit needs).
pub const DEFAULT_SPANWISE_STRIPS: usize = 5;

fn default_strips() -> usize {
    DEFAULT_SPANWISE_STRIPS
}
fn default_f_st() -> f64 {
    HYDROGEN_STOICHIOMETRIC_FUEL_AIR_RATIO
}
fn default_heating_value() -> f64 {
    HYDROGEN_HEATING_VALUE_J_KG
}
fn default_efficiency() -> f64 {
    DEFAULT_COMBUSTION_EFFICIENCY
}
fn default_friction() -> f64 {
    0.002
}
fn default_mixing() -> f64 {
    5.0
}
fn default_isolator() -> f64 {
    0.2
}
fn default_combustor() -> f64 {
    0.5
}
fn default_combustor_area_ratio() -> f64 {
    1.0
}
fn default_steps() -> usize {
    200
}

/// `[models.scramjet-1d]`.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct OneDSettings {
    /// Spanwise sections the engine is evaluated on (≥ 3 for the quadratic fit).
    #[serde(default = "default_strips")]
    pub spanwise_strips: usize,
    /// Stoichiometric fuel/air mass ratio.
    #[serde(default = "default_f_st")]
    pub stoichiometric_fuel_air_ratio: f64,
    /// Fuel lower heating value, J/kg.
    #[serde(default = "default_heating_value")]
    pub fuel_heating_value_j_kg: f64,
    /// Fraction of the heating value released, (0, 1].
    #[serde(default = "default_efficiency")]
    pub combustion_efficiency: f64,
    /// Combustor area over inlet face height; default geometry.combustor_height_m /
    /// geometry.inlet_height_m.
    #[serde(default)]
    pub diffuser_area_ratio: Option<f64>,
    /// Internal nozzle exit area over combustor area (≥ 1); default geometry.inlet_height_m /
    /// geometry.combustor_height_m (the body mesh's engine exit is as tall as its inlet).
    #[serde(default)]
    pub internal_nozzle_area_ratio: Option<f64>,
}

impl Default for OneDSettings {
    fn default() -> Self {
        Self {
            spanwise_strips: DEFAULT_SPANWISE_STRIPS,
            stoichiometric_fuel_air_ratio: HYDROGEN_STOICHIOMETRIC_FUEL_AIR_RATIO,
            fuel_heating_value_j_kg: HYDROGEN_HEATING_VALUE_J_KG,
            combustion_efficiency: DEFAULT_COMBUSTION_EFFICIENCY,
            diffuser_area_ratio: None,
            internal_nozzle_area_ratio: None,
        }
    }
}

/// `[models.scramjet-q1d]`.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct QuasiOneDSettings {
    /// Spanwise sections the engine is evaluated on (≥ 3 for the quadratic fit).
    #[serde(default = "default_strips")]
    pub spanwise_strips: usize,
    /// Stoichiometric fuel/air mass ratio.
    #[serde(default = "default_f_st")]
    pub stoichiometric_fuel_air_ratio: f64,
    /// Fuel lower heating value, J/kg.
    #[serde(default = "default_heating_value")]
    pub fuel_heating_value_j_kg: f64,
    /// Fraction of the heating value released once mixed, (0, 1].
    #[serde(default = "default_efficiency")]
    pub combustion_efficiency: f64,
    /// Isolator (combustor entry) area over inlet face height; default
    /// geometry.combustor_height_m / geometry.inlet_height_m.
    #[serde(default)]
    pub diffuser_area_ratio: Option<f64>,
    /// Internal nozzle exit area over combustor exit area (≥ 1); default
    /// geometry.inlet_height_m / (geometry.combustor_height_m × combustor_area_ratio).
    #[serde(default)]
    pub internal_nozzle_area_ratio: Option<f64>,
    /// Combustor exit area over entry area (linear area change), (0, 10].
    #[serde(default = "default_combustor_area_ratio")]
    pub combustor_area_ratio: f64,
    /// Wall skin-friction coefficient c_f in the combustor, [0, 0.05].
    #[serde(default = "default_friction")]
    pub wall_friction_coefficient: f64,
    /// Shape θ of the mixing-efficiency curve η_m(χ) = θχ/(1 + (θ-1)χ), [1, 100].
    #[serde(default = "default_mixing")]
    pub mixing_shape_parameter: f64,
    /// Inlet face to combustor entry over engine length, (0, 1).
    #[serde(default = "default_isolator")]
    pub isolator_length_fraction: f64,
    /// Combustor length over engine length, (0, 1); isolator + combustor < 1.
    #[serde(default = "default_combustor")]
    pub combustor_length_fraction: f64,
    /// Integration steps along the combustor (RK4), [10, 100000].
    #[serde(default = "default_steps")]
    pub combustor_steps: usize,
}

impl Default for QuasiOneDSettings {
    fn default() -> Self {
        Self {
            spanwise_strips: DEFAULT_SPANWISE_STRIPS,
            stoichiometric_fuel_air_ratio: HYDROGEN_STOICHIOMETRIC_FUEL_AIR_RATIO,
            fuel_heating_value_j_kg: HYDROGEN_HEATING_VALUE_J_KG,
            combustion_efficiency: DEFAULT_COMBUSTION_EFFICIENCY,
            diffuser_area_ratio: None,
            internal_nozzle_area_ratio: None,
            combustor_area_ratio: default_combustor_area_ratio(),
            wall_friction_coefficient: default_friction(),
            mixing_shape_parameter: default_mixing(),
            isolator_length_fraction: default_isolator(),
            combustor_length_fraction: default_combustor(),
            combustor_steps: default_steps(),
        }
    }
}

/// Checks settings values, naming `<key_path>.<key>` in `file` on error.
pub struct Checker<'a> {
    pub file: &'a str,
    pub key_path: &'a str,
}

impl Checker<'_> {
    fn error(&self, key: &str, message: String) -> ModelError {
        ModelError::Settings {
            file: self.file.to_owned(),
            key_path: if self.key_path.is_empty() {
                key.to_owned()
            } else {
                format!("{}.{key}", self.key_path)
            },
            message,
        }
    }

    /// `value` finite and in (lo, hi] (`lo_open`) or [lo, hi].
    pub fn range(
        &self,
        key: &str,
        value: f64,
        lo: f64,
        hi: f64,
        lo_open: bool,
    ) -> Result<f64, ModelError> {
        let inside = if lo_open { value > lo } else { value >= lo } && value <= hi;
        if value.is_finite() && inside {
            Ok(value)
        } else {
            let open = if lo_open { "(" } else { "[" };
            Err(self.error(
                key,
                format!("{value} is out of range; allowed: finite and in {open}{lo}, {hi}]"),
            ))
        }
    }

    /// `value` in [lo, hi].
    pub fn count(
        &self,
        key: &str,
        value: usize,
        lo: usize,
        hi: usize,
    ) -> Result<usize, ModelError> {
        if (lo..=hi).contains(&value) {
            Ok(value)
        } else {
            Err(self.error(
                key,
                format!("{value} is out of range; allowed: {lo} to {hi}"),
            ))
        }
    }

    /// Fails with `message` on `key`.
    pub fn fail(&self, key: &str, message: impl Into<String>) -> ModelError {
        self.error(key, message.into())
    }
}

/// The fuel of either model's settings, checked.
pub fn fuel(
    check: &Checker<'_>,
    stoichiometric_fuel_air_ratio: f64,
    heating_value_j_kg: f64,
    combustion_efficiency: f64,
) -> Result<Fuel, ModelError> {
    Ok(Fuel {
        stoichiometric_fuel_air_ratio: check.range(
            "stoichiometric_fuel_air_ratio",
            stoichiometric_fuel_air_ratio,
            0.0,
            1.0,
            true,
        )?,
        heating_value_j_kg: check.range(
            "fuel_heating_value_j_kg",
            heating_value_j_kg,
            0.0,
            1e9,
            true,
        )?,
        combustion_efficiency: check.range(
            "combustion_efficiency",
            combustion_efficiency,
            0.0,
            1.0,
            true,
        )?,
    })
}

/// The diffuser and internal-nozzle area ratios: the settings' values, or from the geometry
/// (combustor height over inlet height; the exit face, as tall as the inlet, over the
/// combustor exit).
pub fn area_ratios(
    check: &Checker<'_>,
    geometry: &GeometryConfig,
    diffuser: Option<f64>,
    nozzle: Option<f64>,
    combustor_area_ratio: f64,
) -> Result<(f64, f64), ModelError> {
    let diffuser = match diffuser {
        Some(d) => check.range("diffuser_area_ratio", d, 0.0, 100.0, true)?,
        None => geometry.combustor_height_m / geometry.inlet_height_m,
    };
    let nozzle = match nozzle {
        Some(n) => check.range("internal_nozzle_area_ratio", n, 1.0, 1000.0, false)?,
        None => {
            let n = geometry.inlet_height_m / (geometry.combustor_height_m * combustor_area_ratio);
            if !(n.is_finite() && n >= 1.0) {
                return Err(check.fail(
                    "internal_nozzle_area_ratio",
                    format!(
                        "not set, and the geometry gives {n} (inlet height / combustor exit height) < 1, \
                         a converging internal nozzle; set it to a value >= 1"
                    ),
                ));
            }
            n
        }
    };
    if !(diffuser.is_finite() && diffuser > 0.0) {
        return Err(check.fail(
            "diffuser_area_ratio",
            format!("not set, and the geometry gives {diffuser}; set a positive value"),
        ));
    }
    Ok((diffuser, nozzle))
}
