//! The `kriging-stanton` heat-flux model: a kriging (Gaussian-process) surrogate of the Stanton
//! number, trained on a Latin hypercube of another heat-flux model or on user data.
//!
//! After Crowell & McNamara's kriging ROM of the Stanton number (the paper's Ref. 16): the
//! surrogate maps five inputs (freestream Mach number, local surface inclination, wall-to-total
//! temperature ratio, log10 of the running length, altitude) to log10 St, with
//! St = q_conv / (ρ_e u_e c_p (T_0 − T_w)), T_0 the freestream total temperature. Using T_0 rather
//! than a recovery temperature keeps St independent of any one model's recovery factor. Training
//! runs the base heat-flux model (default `eckert`, with its emissivity forced to 0 so only
//! convection is learned) on one-panel flat plates whose edge state comes from a registered aero
//! model (default `shock-expansion`), so the surrogate learns exactly what the vehicle run would
//! have computed. Kriging itself is egobox-gp (constant mean, squared-exponential correlation,
//! hyperparameters by maximum likelihood).
//!
//! Online, q_net = St ρ_e u_e c_p (T_0 − T_w) − ε σ T_w⁴. A panel whose inputs fall outside the
//! training box is an error naming the input and the box (or, with `extrapolate = true`, its
//! inputs are clamped to the box). Training is saved to `training_file` (JSON) and reloaded when
//! its fingerprint (settings and base-model settings) matches, so runs do not retrain.

use std::path::Path;

use egobox_doe::{Lhs, SamplingMethod};
use egobox_gp::correlation_models::SquaredExponentialCorr;
use egobox_gp::mean_models::ConstantMean;
use egobox_gp::{GaussianProcess, Kriging};
use hsv_core::aero::{AeroSolution, PanelMotion};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::material::Material;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Strip, Surface};
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor, Registry};
use hsv_core::thermal::{
    HeatFluxModel, STEFAN_BOLTZMANN_W_M2_K4, check_heat_flux_inputs, check_wall_temperature,
};
use linfa::prelude::{Dataset, Fit};
use nalgebra::{Point3, Vector3};
use ndarray::{Array1, Array2};
use rand_xoshiro::Xoshiro256Plus;
use rand_xoshiro::rand_core::SeedableRng;

/// Registered name.
pub const NAME: &str = "kriging-stanton";

/// The surrogate's inputs, in column order.
pub const INPUTS: [&str; 5] = [
    "mach",
    "inclination_deg",
    "wall_temperature_ratio",
    "log10_running_length_m",
    "altitude_m",
];

/// Version of the saved-training format.
const FORMAT: u32 = 1;

/// The `[models.kriging-stanton]` table.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Heat-flux model sampled for training (needs an `emissivity` setting, forced to 0).
    pub base_model: String,
    /// Aero model that gives the training plates their edge state.
    pub training_aero_model: String,
    /// Latin-hypercube size.
    pub samples: usize,
    /// Share of the samples held out to measure the surrogate's error before the final fit.
    pub holdout_fraction: f64,
    /// Seed of the Latin hypercube.
    pub seed: u64,
    /// Training box: freestream Mach number.
    pub mach: [f64; 2],
    /// Training box: surface inclination to the freestream, deg (> 0 windward).
    pub inclination_deg: [f64; 2],
    /// Training box: wall temperature over freestream total temperature.
    pub wall_temperature_ratio: [f64; 2],
    /// Training box: running length from the leading edge, m (sampled in log10).
    pub running_length_m: [f64; 2],
    /// Training box: geometric altitude, m.
    pub altitude_m: [f64; 2],
    /// Wall emissivity for re-radiation, 0 to 1.
    pub emissivity: f64,
    /// Wall temperature above which the structure has melted, K.
    pub melting_point_k: f64,
    /// JSON file the training is saved to and reloaded from; empty: train in memory every run.
    pub training_file: String,
    /// User training data instead of a base model: CSV with header
    /// `mach,inclination_deg,wall_temperature_ratio,running_length_m,altitude_m,stanton`.
    pub training_csv: String,
    /// Clamp inputs outside the training box instead of failing.
    pub extrapolate: bool,
    /// Running length of panels in no strip, m.
    pub default_running_length_m: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            base_model: "eckert".to_owned(),
            training_aero_model: "shock-expansion".to_owned(),
            samples: 80,
            holdout_fraction: 0.2,
            seed: 2026,
            mach: [3.0, 10.0],
            inclination_deg: [-5.0, 15.0],
            wall_temperature_ratio: [0.15, 0.85],
            running_length_m: [0.02, 5.0],
            altitude_m: [10_000.0, 35_000.0],
            emissivity: 0.8,
            melting_point_k: Material::ti_6al_4v().melting_point_k,
            training_file: String::new(),
            training_csv: String::new(),
            extrapolate: false,
            default_running_length_m: 1.0,
        }
    }
}

const SETTINGS_DOC: &str = "\
base_model = \"eckert\"                 # heat-flux model sampled for training (emissivity forced to 0)
training_aero_model = \"shock-expansion\"  # aero model giving the training plates their edge state
samples = 80                          # Latin-hypercube size
holdout_fraction = 0.2                # share held out to measure the error before the final fit
seed = 2026                           # Latin-hypercube seed
mach = [3.0, 10.0]                    # training box: freestream Mach number
inclination_deg = [-5.0, 15.0]        # training box: surface inclination, deg (> 0 windward)
wall_temperature_ratio = [0.15, 0.85] # training box: T_wall / T_total
running_length_m = [0.02, 5.0]        # training box: running length, m (log-sampled)
altitude_m = [10000.0, 35000.0]       # training box: altitude, m
emissivity = 0.8                      # wall emissivity for re-radiation
melting_point_k = 1877.0              # wall temperature limit (Ti-6Al-4V solidus), K
training_file = \"\"                    # JSON save/reload of the training; empty: train every run
training_csv = \"\"                     # user data instead (header mach,inclination_deg,wall_temperature_ratio,running_length_m,altitude_m,stanton)
extrapolate = false                   # clamp inputs outside the box instead of failing
default_running_length_m = 1.0        # running length of panels in no strip, m";

hsv_core::register_model!(ModelDescriptor {
    name: NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 2,
    summary: "kriging surrogate of the Stanton number over Mach, inclination, wall temperature, running length and altitude, trained on another heat-flux model or user data",
    settings_doc: SETTINGS_DOC,
    constructor: Constructor::HeatFlux(construct),
});

fn construct(context: &ModelContext<'_>) -> Result<Box<dyn HeatFluxModel>, ModelError> {
    let settings: Settings = context.parse_settings()?;
    Ok(Box::new(KrigingStanton::new(settings, context)?))
}

type StantonGp = GaussianProcess<f64, ConstantMean, SquaredExponentialCorr>;

/// A trained surrogate with its box and measured error; what `training_file` holds.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Surrogate {
    format: u32,
    /// Settings and base-model settings it was trained with; a mismatch forces retraining.
    fingerprint: String,
    /// Training box, in the order of [`INPUTS`].
    pub lower: [f64; 5],
    pub upper: [f64; 5],
    /// RMS relative error of St on the held-out samples (fit without them).
    pub holdout_rms_relative_error: f64,
    /// Number of training samples in the final fit.
    pub samples: usize,
    gp: StantonGp,
}

/// Inputs and log10 St of the training samples.
struct TrainingSet {
    inputs: Array2<f64>,
    log_stanton: Array1<f64>,
}

/// The `kriging-stanton` model: a trained surrogate plus scratch buffers.
pub struct KrigingStanton {
    settings: Settings,
    surrogate: Surrogate,
    running_length_m: Vec<f64>,
    rows: Vec<f64>,
    convecting: Vec<usize>,
}

impl KrigingStanton {
    /// Loads the saved training if it matches, else trains (from the CSV or the base model).
    pub fn new(settings: Settings, context: &ModelContext<'_>) -> Result<Self, ModelError> {
        check_settings(&settings, context)?;
        let fingerprint = fingerprint(&settings, context)?;
        let saved = (!settings.training_file.is_empty())
            .then(|| load(Path::new(&settings.training_file), &fingerprint))
            .flatten();
        let surrogate = match saved {
            Some(surrogate) => surrogate,
            None => {
                let data = if settings.training_csv.is_empty() {
                    sample_base_model(&settings, context)?
                } else {
                    read_csv(Path::new(&settings.training_csv))?
                };
                let surrogate = train(&data, &settings, fingerprint)?;
                if !settings.training_file.is_empty() {
                    save(Path::new(&settings.training_file), &surrogate)?;
                }
                surrogate
            }
        };
        Ok(Self {
            settings,
            surrogate,
            running_length_m: Vec::new(),
            rows: Vec::new(),
            convecting: Vec::new(),
        })
    }

    /// The trained surrogate (box, hold-out error, sample count).
    pub fn surrogate(&self) -> &Surrogate {
        &self.surrogate
    }

    /// St at one point of the input space (order of [`INPUTS`], running length in m).
    pub fn stanton(&self, inputs: [f64; 5]) -> Result<f64, ModelError> {
        let mut x = inputs;
        x[3] = x[3].log10();
        let x = self.checked(x, None)?;
        let prediction = self
            .surrogate
            .gp
            .predict(&Array2::from_shape_vec((1, 5), x.to_vec()).map_err(shape_error)?)
            .map_err(|e| ModelError::inconsistent(NAME, format!("kriging prediction: {e}")))?;
        Ok(10f64.powf(prediction[0]))
    }

    /// Inputs inside the box, clamped if extrapolation is allowed, else an error naming the box.
    fn checked(&self, mut x: [f64; 5], panel: Option<usize>) -> Result<[f64; 5], ModelError> {
        let s = &self.surrogate;
        for (k, value) in x.iter_mut().enumerate() {
            if !value.is_finite() {
                return Err(ModelError::out_of_range(
                    NAME,
                    INPUTS[k],
                    *value,
                    "a finite number",
                ));
            }
            let margin = 1e-9 * (s.upper[k] - s.lower[k]).abs().max(1.0);
            if *value < s.lower[k] - margin || *value > s.upper[k] + margin {
                if self.settings.extrapolate {
                    *value = value.clamp(s.lower[k], s.upper[k]);
                } else {
                    let at = panel.map_or_else(String::new, |p| format!(" on panel {p}"));
                    return Err(ModelError::out_of_range(
                        NAME,
                        &format!("{}{at}", INPUTS[k]),
                        *value,
                        format!(
                            "the training box [{}, {}]; retrain with a wider box or set extrapolate = true",
                            s.lower[k], s.upper[k]
                        ),
                    ));
                }
            }
        }
        Ok(x)
    }
}

fn shape_error(e: ndarray::ShapeError) -> ModelError {
    ModelError::inconsistent(NAME, format!("input matrix: {e}"))
}

fn settings_error(context: &ModelContext<'_>, key: &str, message: String) -> ModelError {
    ModelError::Settings {
        file: context.file.to_owned(),
        key_path: format!("{}.{key}", context.key_path),
        message,
    }
}

fn check_settings(settings: &Settings, context: &ModelContext<'_>) -> Result<(), ModelError> {
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
    if settings.wall_temperature_ratio[1] >= 1.0 {
        return Err(settings_error(
            context,
            "wall_temperature_ratio",
            "the upper bound must be below 1: St is defined with T_0 - T_w".to_owned(),
        ));
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

/// Settings of a model as the config gives them (`[models.<name>]`), empty if absent.
fn config_model_settings(context: &ModelContext<'_>, name: &str) -> toml::Table {
    context
        .config
        .get("models")
        .and_then(|m| m.get(name))
        .and_then(|v| v.as_table())
        .cloned()
        .unwrap_or_default()
}

/// What a saved training must match: our settings (minus the file names and the online-only
/// keys) and the base and aero models' settings.
fn fingerprint(settings: &Settings, context: &ModelContext<'_>) -> Result<String, ModelError> {
    let mut relevant = settings.clone();
    relevant.training_file.clear();
    relevant.extrapolate = false;
    relevant.emissivity = 0.0;
    relevant.melting_point_k = 0.0;
    relevant.default_running_length_m = 0.0;
    let csv = if settings.training_csv.is_empty() {
        String::new()
    } else {
        std::fs::read_to_string(&settings.training_csv).unwrap_or_default()
    };
    serde_json::to_string(&(
        relevant,
        config_model_settings(context, &settings.base_model),
        config_model_settings(context, &settings.training_aero_model),
        csv,
    ))
    .map_err(|e| ModelError::inconsistent(NAME, format!("fingerprint: {e}")))
}

fn load(path: &Path, fingerprint: &str) -> Option<Surrogate> {
    let text = std::fs::read_to_string(path).ok()?;
    let surrogate: Surrogate = serde_json::from_str(&text).ok()?;
    (surrogate.format == FORMAT && surrogate.fingerprint == fingerprint).then_some(surrogate)
}

fn save(path: &Path, surrogate: &Surrogate) -> Result<(), ModelError> {
    let text = serde_json::to_string(surrogate)
        .map_err(|e| ModelError::inconsistent(NAME, format!("saving the training: {e}")))?;
    std::fs::write(path, text).map_err(|e| {
        ModelError::inconsistent(NAME, format!("cannot write {}: {e}", path.display()))
    })
}

/// One flat-plate panel of length 2x (so its running length is x) inclined by θ to a freestream
/// along +x: normal n = (sin θ, 0, cos θ), so asin(n · V̂) = θ.
fn training_plate(inclination_rad: f64, running_length_m: f64) -> Result<PanelMesh, ModelError> {
    let (s, c) = inclination_rad.sin_cos();
    let tangent = Vector3::new(-c, 0.0, s) * (2.0 * running_length_m);
    let a = Point3::new(0.0, -0.5, 0.0);
    let b = Point3::new(0.0, 0.5, 0.0);
    PanelMesh::new(
        vec![a, b, b + tangent, a + tangent],
        &[PanelSpec::quad(0, 1, 2, 3, 0)],
        vec![Strip { panels: vec![0] }],
        vec![Surface::new("training-plate", RegionKind::Other)],
    )
    .map_err(|e| ModelError::inconsistent(NAME, format!("training plate: {e}")))
}

/// Latin hypercube of the base model on training plates.
fn sample_base_model(
    settings: &Settings,
    context: &ModelContext<'_>,
) -> Result<TrainingSet, ModelError> {
    let registry =
        Registry::builtin().map_err(|e| ModelError::inconsistent(NAME, e.to_string()))?;
    let mut base_settings = config_model_settings(context, &settings.base_model);
    // Convection only, over the whole box: re-radiation and the wall-temperature limit are
    // applied online, so a box corner hotter than the melting point still trains.
    base_settings.insert("emissivity".to_owned(), toml::Value::Float(0.0));
    base_settings.insert("melting_point_k".to_owned(), toml::Value::Float(f64::MAX));
    let base_path = format!("models.{}", settings.base_model);
    let mut base = registry
        .create_heat_flux(
            &settings.base_model,
            &ModelContext {
                settings: &base_settings,
                key_path: &base_path,
                file: context.file,
                config: context.config,
            },
        )
        .map_err(|e| {
            settings_error(
                context,
                "base_model",
                format!(
                    "cannot build the training model (it needs `emissivity` and \
                     `melting_point_k` settings): {e}"
                ),
            )
        })?;
    let aero_settings = config_model_settings(context, &settings.training_aero_model);
    let aero_path = format!("models.{}", settings.training_aero_model);
    let mut aero = registry
        .create_aero(
            &settings.training_aero_model,
            &ModelContext {
                settings: &aero_settings,
                key_path: &aero_path,
                file: context.file,
                config: context.config,
            },
        )
        .map_err(|e| settings_error(context, "training_aero_model", e.to_string()))?;
    let gas = context
        .parse_config_table::<PerfectGas>("gas")
        .unwrap_or(PerfectGas::AIR);

    let limits = ndarray::arr2(&[
        settings.mach,
        settings.inclination_deg,
        settings.wall_temperature_ratio,
        settings.running_length_m.map(f64::log10),
        settings.altitude_m,
    ]);
    let points = Lhs::new(&limits)
        .with_rng(Xoshiro256Plus::seed_from_u64(settings.seed))
        .sample(settings.samples);
    let mut log_stanton = Array1::zeros(points.nrows());
    let mut solution = AeroSolution::default();
    for (i, x) in points.rows().into_iter().enumerate() {
        let running_length_m = 10f64.powf(x[3]);
        let plate = training_plate(x[1].to_radians(), running_length_m)?;
        let freestream = Freestream::standard(x[0], x[4], gas)?;
        let flight = FlightCondition::steady(freestream, 0.0, 0.0);
        aero.evaluate(&plate, &flight, &PanelMotion::default(), &mut solution)?;
        let total_temperature_k = freestream.total_temperature_k();
        let wall_k = x[2] * total_temperature_k;
        let mut q = [0.0];
        base.heat_flux(&plate, &flight, &solution, &[wall_k], &mut q)?;
        let stanton = stanton_number(q[0], &solution.edge[0], &gas, total_temperature_k, wall_k);
        if !(stanton.is_finite() && stanton > 0.0) {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "training sample {i} ({} = {:?}) gave St = {stanton}; narrow the training box",
                    INPUTS.join(", "),
                    x.to_vec()
                ),
            ));
        }
        log_stanton[i] = stanton.log10();
    }
    Ok(TrainingSet {
        inputs: points,
        log_stanton,
    })
}

/// St = q / (ρ_e u_e c_p (T_0 − T_w)).
fn stanton_number(
    heat_flux_w_m2: f64,
    edge: &hsv_core::aero::EdgeState,
    gas: &PerfectGas,
    total_temperature_k: f64,
    wall_temperature_k: f64,
) -> f64 {
    heat_flux_w_m2
        / (edge.density_kg_m3
            * edge.velocity_m_s
            * gas.cp()
            * (total_temperature_k - wall_temperature_k))
}

/// Reads user training data: header `mach,inclination_deg,wall_temperature_ratio,running_length_m,altitude_m,stanton`.
fn read_csv(path: &Path) -> Result<TrainingSet, ModelError> {
    let shown = path.display().to_string();
    let fail = |message: String| ModelError::inconsistent(NAME, format!("{shown}: {message}"));
    let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let expected =
        "mach,inclination_deg,wall_temperature_ratio,running_length_m,altitude_m,stanton";
    match lines.next() {
        Some((_, header)) if header.replace(' ', "") == expected => {}
        _ => return Err(fail(format!("the first line must be `{expected}`"))),
    }
    let mut inputs = Vec::new();
    let mut log_stanton = Vec::new();
    for (number, line) in lines {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| fail(format!("line {}: {e}", number + 1)))?;
        if values.len() != 6 {
            return Err(fail(format!(
                "line {}: {} values, expected 6",
                number + 1,
                values.len()
            )));
        }
        if !(values[3] > 0.0 && values[5] > 0.0 && values.iter().all(|v| v.is_finite())) {
            return Err(fail(format!(
                "line {}: running length and Stanton number must be finite and > 0",
                number + 1
            )));
        }
        inputs.extend_from_slice(&[
            values[0],
            values[1],
            values[2],
            values[3].log10(),
            values[4],
        ]);
        log_stanton.push(values[5].log10());
    }
    if log_stanton.len() < 10 {
        return Err(fail(format!(
            "{} samples; a 5-input surrogate needs at least 10",
            log_stanton.len()
        )));
    }
    Ok(TrainingSet {
        inputs: Array2::from_shape_vec((log_stanton.len(), 5), inputs).map_err(shape_error)?,
        log_stanton: Array1::from(log_stanton),
    })
}

fn fit(inputs: Array2<f64>, log_stanton: Array1<f64>) -> Result<StantonGp, ModelError> {
    Kriging::params()
        .fit(&Dataset::new(inputs, log_stanton))
        .map_err(|e| ModelError::inconsistent(NAME, format!("kriging fit: {e}")))
}

/// Fits without the held-out tail to measure the error, then on everything.
fn train(
    data: &TrainingSet,
    settings: &Settings,
    fingerprint: String,
) -> Result<Surrogate, ModelError> {
    let n = data.log_stanton.len();
    let held_out = ((n as f64) * settings.holdout_fraction).round() as usize;
    let holdout_rms_relative_error = if held_out > 0 {
        let split = n - held_out;
        let partial = fit(
            data.inputs.slice(ndarray::s![..split, ..]).to_owned(),
            data.log_stanton.slice(ndarray::s![..split]).to_owned(),
        )?;
        let predicted = partial
            .predict(&data.inputs.slice(ndarray::s![split.., ..]))
            .map_err(|e| ModelError::inconsistent(NAME, format!("kriging prediction: {e}")))?;
        let sum_sq: f64 = predicted
            .iter()
            .zip(data.log_stanton.slice(ndarray::s![split..]))
            .map(|(p, t)| (10f64.powf(*p - *t) - 1.0).powi(2))
            .sum();
        (sum_sq / held_out as f64).sqrt()
    } else {
        f64::NAN
    };
    let mut lower = [f64::INFINITY; 5];
    let mut upper = [f64::NEG_INFINITY; 5];
    for row in data.inputs.rows() {
        for k in 0..5 {
            lower[k] = lower[k].min(row[k]);
            upper[k] = upper[k].max(row[k]);
        }
    }
    if settings.training_csv.is_empty() {
        // A Latin hypercube does not reach the corners; the box is the one sampled over.
        let boxes = [
            settings.mach,
            settings.inclination_deg,
            settings.wall_temperature_ratio,
            settings.running_length_m.map(f64::log10),
            settings.altitude_m,
        ];
        for (k, [lo, hi]) in boxes.into_iter().enumerate() {
            lower[k] = lo;
            upper[k] = hi;
        }
    }
    Ok(Surrogate {
        format: FORMAT,
        fingerprint,
        lower,
        upper,
        holdout_rms_relative_error,
        samples: n,
        gp: fit(data.inputs.clone(), data.log_stanton.clone())?,
    })
}

impl HeatFluxModel for KrigingStanton {
    fn name(&self) -> &str {
        NAME
    }

    fn heat_flux(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
        out_w_m2: &mut [f64],
    ) -> Result<(), ModelError> {
        check_heat_flux_inputs(NAME, mesh, flight, aero, wall_temperature_k, out_w_m2)?;
        let freestream = &flight.freestream;
        let gas = freestream.gas;
        let total_temperature_k = freestream.total_temperature_k();
        let velocity = flight.velocity_body_m_s();
        let direction = velocity / velocity.norm();
        let mut running = std::mem::take(&mut self.running_length_m);
        mesh.strip_running_lengths_m(
            &velocity,
            self.settings.default_running_length_m,
            &mut running,
        );
        self.running_length_m = running;

        self.rows.clear();
        self.convecting.clear();
        for (i, panel) in mesh.panels.iter().enumerate() {
            let wall_k = wall_temperature_k[i];
            check_wall_temperature(NAME, wall_k, self.settings.melting_point_k, Some(i))?;
            out_w_m2[i] = -self.settings.emissivity * STEFAN_BOLTZMANN_W_M2_K4 * wall_k.powi(4);
            let edge = &aero.edge[i];
            if edge.pressure_pa <= 0.0 || edge.density_kg_m3 <= 0.0 || edge.velocity_m_s <= 0.0 {
                continue;
            }
            let inclination_deg = panel
                .normal
                .dot(&direction)
                .clamp(-1.0, 1.0)
                .asin()
                .to_degrees();
            let x = self.checked(
                [
                    freestream.mach,
                    inclination_deg,
                    wall_k / total_temperature_k,
                    self.running_length_m[i].log10(),
                    freestream.altitude_m,
                ],
                Some(i),
            )?;
            self.rows.extend_from_slice(&x);
            self.convecting.push(i);
        }
        if self.convecting.is_empty() {
            return Ok(());
        }
        let inputs =
            Array2::from_shape_vec((self.convecting.len(), 5), std::mem::take(&mut self.rows))
                .map_err(shape_error)?;
        let log_stanton = self
            .surrogate
            .gp
            .predict(&inputs)
            .map_err(|e| ModelError::inconsistent(NAME, format!("kriging prediction: {e}")))?;
        self.rows = inputs.into_raw_vec_and_offset().0;
        for (&i, log_st) in self.convecting.iter().zip(log_stanton.iter()) {
            let edge = &aero.edge[i];
            let stanton = 10f64.powf(*log_st);
            let q_conv = stanton
                * edge.density_kg_m3
                * edge.velocity_m_s
                * gas.cp()
                * (total_temperature_k - wall_temperature_k[i]);
            out_w_m2[i] += q_conv;
            if !out_w_m2[i].is_finite() {
                return Err(ModelError::non_finite_at_panel(NAME, "heat flux", i));
            }
        }
        Ok(())
    }
}
