//! The `kriging-stanton` settings: their keys and defaults, the documentation the registry shows,
//! and their checks against the region they are built for.

use super::*;

/// The `[models.kriging-stanton]` table.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Heat-flux model sampled for training (needs an `emissivity` setting, forced to 0).
    pub base_model: String,
    /// Aero model that gives the training plates their edge state.
    pub training_aero_model: String,
    /// Latin-hypercube size, per boundary-layer regime.
    pub samples: usize,
    /// Share of the samples held out to measure the surrogate's error before the final fit.
    pub holdout_fraction: f64,
    /// Seed of the Latin hypercube.
    pub seed: u64,
    /// Training box: freestream Mach number.
    pub mach: [f64; 2],
    /// Training box: surface inclination to the freestream, deg (> 0 windward).
    pub inclination_deg: [f64; 2],
    /// Training box: wall temperature over the panel's recovery temperature, T_w/T_aw.
    pub wall_temperature_ratio: [f64; 2],
    /// Training box: running length from the leading edge, m (sampled in log10).
    pub running_length_m: [f64; 2],
    /// Training box: geometric altitude, m.
    pub altitude_m: [f64; 2],
    /// Wall emissivity for re-radiation, 0 to 1.
    pub emissivity: f64,
    /// Wall temperature above which the structure has melted, K.
    pub melting_point_k: f64,
    /// JSON file the training is saved to and reloaded from (default [`DEFAULT_TRAINING_FILE`],
    /// in the cache folder beside the POD basis and the convolution ROM); empty: train in
    /// memory every run.
    pub training_file: String,
    /// User training data instead of a base model: CSV with header [`CSV_HEADER`]
    /// (`turbulent` 0 or 1; St referenced to T_aw − T_w).
    pub training_csv: String,
    /// Clamp inputs outside the training box instead of failing.
    pub extrapolate: bool,
    /// Running length of panels in no strip, m.
    pub default_running_length_m: f64,
    /// Laminar, turbulent or transitional (online; the base model is trained in each).
    pub regime: Regime,
    /// Edge Reynolds number ρ_e u_e x / μ_e where a transitional boundary layer turns turbulent.
    pub transition_reynolds: f64,
    /// Prandtl number of air for the recovery factor; also given to the base model.
    pub prandtl_number: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            base_model: "eckert".to_owned(),
            training_aero_model: "shock-expansion".to_owned(),
            // Our choice: over the default box 150 samples per regime give hold-out RMS errors
            // of 1.1 % (laminar) and 1.2 % (turbulent), largest 2.8 % and 4.2 %, in 6.5 s of
            // training (test `default_training_reports_percent_level_errors`, run with --ignored).
            samples: 150,
            holdout_fraction: 0.2,
            seed: 2026,
            // The paper's flutter sweep reaches Mach 16.1 at 10 km; Mach 3 is its lowest.
            mach: [3.0, 16.0],
            inclination_deg: [-5.0, 15.0],
            // A 293 K wall at Mach 16, 10 km is 0.03 T_aw; above 1, walls hotter than T_aw.
            wall_temperature_ratio: [0.02, 1.2],
            running_length_m: [0.02, 5.0],
            altitude_m: [10_000.0, 35_000.0],
            emissivity: 0.8,
            melting_point_k: Material::ti_6al_4v().melting_point_k,
            training_file: DEFAULT_TRAINING_FILE.to_owned(),
            training_csv: String::new(),
            extrapolate: false,
            default_running_length_m: 1.0,
            // The `eckert` defaults, so the surrogate switches where its base model does.
            regime: Regime::Transitional,
            transition_reynolds: 5.0e5,
            prandtl_number: 0.71,
        }
    }
}

/// Default `training_file`: the cache folder of the working directory.
pub const DEFAULT_TRAINING_FILE: &str = "hsv-cache/kriging-stanton.json";

pub(super) const SETTINGS_DOC: &str = "\
base_model = \"eckert\"                 # heat-flux model sampled for training (emissivity forced to 0)
training_aero_model = \"shock-expansion\"  # aero model giving the training plates their edge state
samples = 150                         # Latin-hypercube size per regime (laminar, turbulent)
holdout_fraction = 0.2                # share held out to measure the error before the final fit
seed = 2026                           # Latin-hypercube seed
mach = [3.0, 16.0]                    # training box: freestream Mach number
inclination_deg = [-5.0, 15.0]        # training box: surface inclination, deg (> 0 windward)
wall_temperature_ratio = [0.02, 1.2]  # training box: T_wall / T_adiabatic_wall (St = q / (rho u c_p (T_aw - T_w)))
running_length_m = [0.02, 5.0]        # training box: running length, m (log-sampled)
altitude_m = [10000.0, 35000.0]       # training box: altitude, m
emissivity = 0.8                      # wall emissivity for re-radiation
melting_point_k = 1877.0              # wall temperature limit (Ti-6Al-4V solidus), K
training_file = \"hsv-cache/kriging-stanton.json\"  # JSON save/reload of the training (folder created when missing); empty: train every run
training_csv = \"\"                     # user data instead (header mach,inclination_deg,wall_temperature_ratio,running_length_m,altitude_m,turbulent,stanton)
extrapolate = false                   # clamp inputs outside the box instead of failing
default_running_length_m = 1.0        # running length of panels in no strip, m
regime = \"transitional\"              # \"laminar\", \"turbulent\" or \"transitional\": one surrogate per regime
transition_reynolds = 5e5             # edge Reynolds number on the running length where transition happens
prandtl_number = 0.71                 # for the recovery factor; also set on the base model";

pub(super) fn settings_error(context: &ModelContext<'_>, key: &str, message: String) -> ModelError {
    ModelError::Settings {
        file: context.file.to_owned(),
        key_path: format!("{}.{key}", context.key_path),
        message,
    }
}

pub(super) fn check_settings(
    settings: &Settings,
    context: &ModelContext<'_>,
) -> Result<(), ModelError> {
    let boxes = [
        ("mach", settings.mach, 1.0),
        ("inclination_deg", settings.inclination_deg, -89.0),
        (
            "wall_temperature_ratio",
            settings.wall_temperature_ratio,
            0.0,
        ),
        ("running_length_m", settings.running_length_m, 0.0),
        ("altitude_m", settings.altitude_m, 0.0),
    ];
    for (key, [lo, hi], floor) in boxes {
        if !(lo.is_finite() && hi.is_finite() && lo < hi && lo >= floor) {
            return Err(settings_error(
                context,
                key,
                format!("[{lo}, {hi}] must be finite, increasing and start at or above {floor}"),
            ));
        }
    }
    for (key, value, ok, allowed) in [
        (
            "transition_reynolds",
            settings.transition_reynolds,
            settings.transition_reynolds > 0.0,
            "finite and > 0",
        ),
        (
            "prandtl_number",
            settings.prandtl_number,
            settings.prandtl_number > 0.0 && settings.prandtl_number <= 10.0,
            "0 < Pr <= 10",
        ),
    ] {
        if !(value.is_finite() && ok) {
            return Err(settings_error(
                context,
                key,
                format!("{value} is outside the allowed range ({allowed})"),
            ));
        }
    }
    if settings.running_length_m[0] <= 0.0 {
        return Err(settings_error(
            context,
            "running_length_m",
            "the lower bound must be > 0 (log-sampled)".to_owned(),
        ));
    }
    if !(0.0..=1.0).contains(&settings.emissivity) {
        return Err(settings_error(
            context,
            "emissivity",
            format!("{} is outside [0, 1]", settings.emissivity),
        ));
    }
    if !(0.0..0.9).contains(&settings.holdout_fraction) {
        return Err(settings_error(
            context,
            "holdout_fraction",
            format!("{} is outside [0, 0.9)", settings.holdout_fraction),
        ));
    }
    let held_out = (settings.samples as f64 * settings.holdout_fraction).round() as usize;
    if settings.training_csv.is_empty() && settings.samples.saturating_sub(held_out) < 10 {
        return Err(settings_error(
            context,
            "samples",
            format!(
                "{} samples leave fewer than 10 to fit a 5-input surrogate",
                settings.samples
            ),
        ));
    }
    if !(settings.melting_point_k.is_finite() && settings.melting_point_k > 0.0) {
        return Err(settings_error(
            context,
            "melting_point_k",
            format!("{} must be > 0", settings.melting_point_k),
        ));
    }
    if !(settings.default_running_length_m.is_finite() && settings.default_running_length_m > 0.0) {
        return Err(settings_error(
            context,
            "default_running_length_m",
            format!("{} must be > 0", settings.default_running_length_m),
        ));
    }
    Ok(())
}

/// Settings of a model as this region sees them, empty if the config has none.
pub(super) fn config_model_settings(context: &ModelContext<'_>, name: &str) -> toml::Table {
    context.settings_for(name).table
}
