//! The `kriging-stanton` heat-flux model: a kriging (Gaussian-process) surrogate of the Stanton
//! number, trained on a Latin hypercube of another heat-flux model or on user data.
//!
//! After Crowell & McNamara's kriging ROM of the Stanton number (the paper's Ref. 16): the
//! surrogate maps five inputs (freestream Mach number, local surface inclination, wall over
//! adiabatic-wall temperature T_w/T_aw, log10 of the running length, altitude) to log10 St, with
//! St = q_conv / (ρ_e u_e c_p (T_aw − T_w)) and T_aw = T_e (1 + r (γ−1)/2 M_e²) the recovery
//! temperature of the panel's edge state (r = Pr^(1/2) laminar, Pr^(1/3) turbulent; Anderson,
//! Hypersonic and High-Temperature Gas Dynamics, 2nd ed., §6.7). Referencing St to T_aw, as
//! Eckert's method does, makes St positive and smooth through T_w = T_aw, so a wall hotter than
//! its recovery temperature is cooled (q < 0), as the base model says.
//!
//! **Transition.** The laminar and turbulent boundary layers get separate surrogates, each
//! trained with the base model forced into that regime; online a panel is turbulent where its
//! edge Reynolds number ρ_e u_e x / μ_e reaches `transition_reynolds` (the rule of `eckert`'s
//! transitional regime). One surrogate across transition would have to fit a jump in St (a
//! turbulent St several times the laminar one at the same point) with a smooth
//! squared-exponential correlation: it would blur the jump over a correlation length and its
//! hold-out error would mix the two. Separate smooth surrogates switched exactly where the base
//! model switches keep each fit smooth and each reported error honest.
//!
//! Training runs the base heat-flux model (default `eckert`, with its emissivity forced to 0 so
//! only convection is learned, and its `regime` and `prandtl_number` set to the surrogate's) on
//! one-panel flat plates whose edge state comes from a registered aero model (default
//! `shock-expansion`), so the surrogate learns exactly what the vehicle run would have computed.
//! Kriging itself is egobox-gp (constant mean, squared-exponential correlation, hyperparameters
//! by maximum likelihood).
//!
//! **Default box.** Mach 3-16, altitude 10-35 km, T_w/T_aw 0.02-1.2, running length 0.02-5 m,
//! inclination −5° to 15°: it covers the paper's flutter case (a 293 K surface at 10 km up to
//! Mach 16: T_w/T_aw ≈ 0.03 at Mach 16, 0.6 at Mach 3) and its 26 km cruise, and walls above
//! their recovery temperature.
//!
//! Online, q_net = St ρ_e u_e c_p (T_aw − T_w) − ε σ T_w⁴. A panel whose inputs fall outside the
//! training box is an error naming the input and the box (or, with `extrapolate = true`, its
//! inputs are clamped to the box). Training is saved to `training_file` (JSON) and reloaded when
//! its fingerprint (settings and base-model settings) matches, so runs do not retrain.

use std::path::Path;

use egobox_doe::{Lhs, SamplingMethod};
use egobox_gp::correlation_models::SquaredExponentialCorr;
use egobox_gp::mean_models::ConstantMean;
use egobox_gp::{GaussianProcess, Kriging};
use hsv_core::aero::{AeroModel, AeroSolution, EdgeState, PanelMotion};
use hsv_core::atmosphere::sutherland_viscosity;
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::material::Material;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Strip, Surface};
use hsv_core::registry::{Constructor, ModelCheck, ModelContext, ModelDescriptor, Role};
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

/// Version of the saved-training format (2: St referenced to T_aw, one surrogate per regime).
const FORMAT: u32 = 2;

/// Header of a user training CSV.
pub const CSV_HEADER: &str =
    "mach,inclination_deg,wall_temperature_ratio,running_length_m,altitude_m,turbulent,stanton";

/// Which boundary-layer state the online model applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    Laminar,
    Turbulent,
    /// Laminar below `transition_reynolds` (edge Reynolds number on the running length),
    /// turbulent from there on.
    Transitional,
}

impl Regime {
    /// The regimes that need a surrogate: (laminar, turbulent).
    fn needs(self) -> (bool, bool) {
        match self {
            Regime::Laminar => (true, false),
            Regime::Turbulent => (false, true),
            Regime::Transitional => (true, true),
        }
    }
}

pub use hsv_core::thermal::recovery_factor;

/// T_aw at an edge state, K ([`hsv_core::thermal::recovery_temperature_k`]).
pub fn recovery_temperature_k(edge: &EdgeState, gamma: f64, r: f64) -> f64 {
    hsv_core::thermal::recovery_temperature_k(edge.temperature_k, edge.mach, gamma, r)
}

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

const SETTINGS_DOC: &str = "\
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

hsv_core::register_model!(ModelDescriptor {
    name: NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 2,
    summary: "kriging surrogates (laminar, turbulent) of the Stanton number referenced to the adiabatic wall, over Mach, inclination, wall temperature, running length and altitude, trained on another heat-flux model or user data",
    settings_doc: SETTINGS_DOC,
    constructor: Constructor::HeatFlux(construct),
});

fn construct(context: &ModelContext<'_>) -> Result<Box<dyn HeatFluxModel>, ModelError> {
    let settings: Settings = context.parse_settings()?;
    Ok(Box::new(KrigingStanton::new(settings, context)?))
}

/// `config --check` of `kriging-stanton`: its settings and its base model as the region sees
/// it, without sampling or training the surrogate.
fn check(context: &ModelContext<'_>) -> Result<(), ModelError> {
    let settings: Settings = context.parse_settings()?;
    check_settings(&settings, context)?;
    if settings.training_csv.is_empty() {
        context
            .check(
                Role::HeatFlux,
                &settings.base_model,
                &context.settings_for(&settings.base_model),
            )
            .map_err(|e| context.base_model_error("base_model", e))?;
    }
    Ok(())
}

hsv_core::register_model_check!(ModelCheck { name: NAME, check });

type StantonGp = GaussianProcess<f64, ConstantMean, SquaredExponentialCorr>;

/// The surrogate of one boundary-layer regime with its measured error.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct RegimeSurrogate {
    /// RMS relative error of St on the held-out samples (fit without them).
    pub holdout_rms_relative_error: f64,
    /// Largest relative error of St on the held-out samples.
    pub holdout_max_relative_error: f64,
    /// Number of training samples in the final fit.
    pub samples: usize,
    gp: StantonGp,
}

/// The trained surrogates with their box; what `training_file` holds.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Surrogate {
    format: u32,
    /// Settings and base-model settings it was trained with; a mismatch forces retraining.
    fingerprint: String,
    /// Training box, in the order of [`INPUTS`].
    pub lower: [f64; 5],
    pub upper: [f64; 5],
    /// Laminar surrogate (absent if the regime setting or the CSV has no laminar part).
    pub laminar: Option<RegimeSurrogate>,
    /// Turbulent surrogate (absent if the regime setting or the CSV has no turbulent part).
    pub turbulent: Option<RegimeSurrogate>,
}

impl Surrogate {
    /// The surrogate of one regime, or an error saying it was not trained.
    pub fn regime(&self, turbulent: bool) -> Result<&RegimeSurrogate, ModelError> {
        let (part, name) = if turbulent {
            (&self.turbulent, "turbulent")
        } else {
            (&self.laminar, "laminar")
        };
        part.as_ref().ok_or_else(|| {
            ModelError::inconsistent(
                NAME,
                format!(
                    "a {name} panel, but no {name} surrogate was trained (regime setting or \
                     training CSV without {name} rows)"
                ),
            )
        })
    }

    /// The larger hold-out RMS relative error of the trained regimes.
    pub fn holdout_rms_relative_error(&self) -> f64 {
        [&self.laminar, &self.turbulent]
            .into_iter()
            .flatten()
            .map(|r| r.holdout_rms_relative_error)
            .fold(0.0, f64::max)
    }
}

/// Inputs and log10 St of the training samples of one regime.
struct TrainingSet {
    inputs: Array2<f64>,
    log_stanton: Array1<f64>,
}

/// Scratch of one regime during an evaluation: input rows and the panels they belong to.
#[derive(Default)]
struct Batch {
    rows: Vec<f64>,
    panels: Vec<usize>,
    recovery_k: Vec<f64>,
}

impl Batch {
    fn clear(&mut self) {
        self.rows.clear();
        self.panels.clear();
        self.recovery_k.clear();
    }
}

/// The `kriging-stanton` model: trained surrogates plus scratch buffers.
pub struct KrigingStanton {
    settings: Settings,
    surrogate: Surrogate,
    running_length_m: Vec<f64>,
    /// Laminar and turbulent batches.
    batches: [Batch; 2],
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
                let (needs_laminar, needs_turbulent) = settings.regime.needs();
                let data = if settings.training_csv.is_empty() {
                    let sample = |needed: bool, regime: Regime| {
                        needed
                            .then(|| sample_base_model(&settings, context, regime))
                            .transpose()
                    };
                    [
                        sample(needs_laminar, Regime::Laminar)?,
                        sample(needs_turbulent, Regime::Turbulent)?,
                    ]
                } else {
                    read_csv(Path::new(&settings.training_csv))?
                };
                let surrogate = train(data, &settings, fingerprint)?;
                if settings.training_file.is_empty() {
                    surrogate
                } else {
                    save(Path::new(&settings.training_file), &surrogate)?
                }
            }
        };
        Ok(Self {
            settings,
            surrogate,
            running_length_m: Vec::new(),
            batches: Default::default(),
        })
    }

    /// The trained surrogates (box, hold-out errors, sample counts).
    pub fn surrogate(&self) -> &Surrogate {
        &self.surrogate
    }

    /// St = q / (ρ_e u_e c_p (T_aw − T_w)) at one point of the input space (order of
    /// [`INPUTS`], running length in m, wall temperature over T_aw) in one regime.
    pub fn stanton(&self, inputs: [f64; 5], turbulent: bool) -> Result<f64, ModelError> {
        let mut x = inputs;
        x[3] = x[3].log10();
        let x = self.checked(x, None)?;
        let prediction = self
            .surrogate
            .regime(turbulent)?
            .gp
            .predict(&Array2::from_shape_vec((1, 5), x.to_vec()).map_err(shape_error)?)
            .map_err(|e| ModelError::inconsistent(NAME, format!("kriging prediction: {e}")))?;
        Ok(10f64.powf(prediction[0]))
    }

    /// Whether a panel's boundary layer is turbulent: the regime setting, or in the
    /// transitional regime the edge Reynolds number ρ_e u_e x / μ_e against
    /// `transition_reynolds` (as `eckert` decides).
    pub fn is_turbulent(&self, edge: &EdgeState, running_length_m: f64) -> bool {
        match self.settings.regime {
            Regime::Laminar => false,
            Regime::Turbulent => true,
            Regime::Transitional => {
                edge.density_kg_m3 * edge.velocity_m_s * running_length_m
                    / sutherland_viscosity(edge.temperature_k)
                    >= self.settings.transition_reynolds
            }
        }
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
fn config_model_settings(context: &ModelContext<'_>, name: &str) -> toml::Table {
    context.settings_for(name).table
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

/// The saved training at `path` if its seal matches and it was built from `fingerprint`; a
/// damaged file is reported and retrained.
fn load(path: &Path, fingerprint: &str) -> Option<Surrogate> {
    match hsv_core::cache::load::<Surrogate>(path) {
        Ok(surrogate) => (surrogate.format == FORMAT && surrogate.fingerprint == fingerprint)
            .then_some(surrogate),
        Err(e) => {
            if e.is_damaged() {
                hsv_core::cache::warn_rebuilding(&e);
            }
            None
        }
    }
}

/// Writes the training as a sealed cache, atomically, and returns it as the file holds it, so
/// this run predicts exactly what a reloading run will.
fn save(path: &Path, surrogate: &Surrogate) -> Result<Surrogate, ModelError> {
    let fail = |e: hsv_core::cache::CacheError| {
        ModelError::inconsistent(NAME, format!("saving the training: {e}"))
    };
    hsv_core::cache::save(path, surrogate).map_err(fail)?;
    hsv_core::cache::load(path).map_err(fail)
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

/// Latin hypercube of the base model, forced into `regime`, on training plates.
fn sample_base_model(
    settings: &Settings,
    context: &ModelContext<'_>,
    regime: Regime,
) -> Result<TrainingSet, ModelError> {
    let mut base_settings = context.settings_for(&settings.base_model);
    // Convection only, over the whole box: re-radiation and the wall-temperature limit are
    // applied online, so a box corner hotter than the melting point still trains.
    let table = &mut base_settings.table;
    table.insert("emissivity".to_owned(), toml::Value::Float(0.0));
    table.insert("melting_point_k".to_owned(), toml::Value::Float(f64::MAX));
    force_regime(table, settings, regime);
    let mut base = context
        .build::<dyn HeatFluxModel>(&settings.base_model, &base_settings)
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
    let aero_settings = context.settings_for(&settings.training_aero_model);
    let mut aero = context
        .build::<dyn AeroModel>(&settings.training_aero_model, &aero_settings)
        .map_err(|e| settings_error(context, "training_aero_model", e.to_string()))?;
    let gas = context.region.gas;

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
        let edge = solution.edge[0];
        let turbulent = regime == Regime::Turbulent;
        let recovery_k = recovery_temperature_k(
            &edge,
            gas.gamma,
            recovery_factor(settings.prandtl_number, turbulent),
        );
        let wall_k = x[2] * recovery_k;
        let mut q = [0.0];
        base.heat_flux(&plate, &flight, &solution, &[wall_k], &mut q)?;
        let stanton = stanton_number(q[0], &edge, &gas, recovery_k, wall_k);
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

/// The base model's settings for training in one regime: `regime` and `prandtl_number` are
/// the surrogate's, so its recovery temperature is the one St is referenced to.
fn force_regime(base_settings: &mut toml::Table, settings: &Settings, regime: Regime) {
    let name = match regime {
        Regime::Laminar => "laminar",
        Regime::Turbulent => "turbulent",
        Regime::Transitional => "transitional",
    };
    base_settings.insert("regime".to_owned(), toml::Value::String(name.to_owned()));
    base_settings.insert(
        "prandtl_number".to_owned(),
        toml::Value::Float(settings.prandtl_number),
    );
}

/// St = q / (ρ_e u_e c_p (T_aw − T_w)).
fn stanton_number(
    heat_flux_w_m2: f64,
    edge: &EdgeState,
    gas: &PerfectGas,
    recovery_temperature_k: f64,
    wall_temperature_k: f64,
) -> f64 {
    heat_flux_w_m2
        / (edge.density_kg_m3
            * edge.velocity_m_s
            * gas.cp()
            * (recovery_temperature_k - wall_temperature_k))
}

/// Reads user training data (header [`CSV_HEADER`]) into (laminar, turbulent) sets.
fn read_csv(path: &Path) -> Result<[Option<TrainingSet>; 2], ModelError> {
    let shown = path.display().to_string();
    let fail = |message: String| ModelError::inconsistent(NAME, format!("{shown}: {message}"));
    let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let expected = CSV_HEADER;
    match lines.next() {
        Some((_, header)) if header.replace(' ', "") == expected => {}
        _ => return Err(fail(format!("the first line must be `{expected}`"))),
    }
    let mut inputs = [Vec::new(), Vec::new()];
    let mut log_stanton = [Vec::new(), Vec::new()];
    for (number, line) in lines {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| fail(format!("line {}: {e}", number + 1)))?;
        if values.len() != 7 {
            return Err(fail(format!(
                "line {}: {} values, expected 7",
                number + 1,
                values.len()
            )));
        }
        if !(values[3] > 0.0 && values[6] > 0.0 && values.iter().all(|v| v.is_finite())) {
            return Err(fail(format!(
                "line {}: running length and Stanton number must be finite and > 0",
                number + 1
            )));
        }
        let regime = match values[5] {
            0.0 => 0,
            1.0 => 1,
            other => {
                return Err(fail(format!(
                    "line {}: turbulent = {other}, expected 0 (laminar) or 1 (turbulent)",
                    number + 1
                )));
            }
        };
        inputs[regime].extend_from_slice(&[
            values[0],
            values[1],
            values[2],
            values[3].log10(),
            values[4],
        ]);
        log_stanton[regime].push(values[6].log10());
    }
    let total = log_stanton[0].len() + log_stanton[1].len();
    let mut sets = [None, None];
    for (k, (inputs, log_stanton)) in inputs.into_iter().zip(log_stanton).enumerate() {
        if log_stanton.is_empty() {
            continue;
        }
        if log_stanton.len() < 10 {
            return Err(fail(format!(
                "{} {} samples; a 5-input surrogate needs at least 10",
                log_stanton.len(),
                ["laminar", "turbulent"][k]
            )));
        }
        sets[k] = Some(TrainingSet {
            inputs: Array2::from_shape_vec((log_stanton.len(), 5), inputs).map_err(shape_error)?,
            log_stanton: Array1::from(log_stanton),
        });
    }
    if total == 0 {
        return Err(fail("no samples".to_owned()));
    }
    Ok(sets)
}

fn fit(inputs: Array2<f64>, log_stanton: Array1<f64>) -> Result<StantonGp, ModelError> {
    Kriging::params()
        .fit(&Dataset::new(inputs, log_stanton))
        .map_err(|e| ModelError::inconsistent(NAME, format!("kriging fit: {e}")))
}

/// Fits each regime's set, with the box the sets span (or the sampled box).
fn train(
    data: [Option<TrainingSet>; 2],
    settings: &Settings,
    fingerprint: String,
) -> Result<Surrogate, ModelError> {
    let mut lower = [f64::INFINITY; 5];
    let mut upper = [f64::NEG_INFINITY; 5];
    for set in data.iter().flatten() {
        for row in set.inputs.rows() {
            for k in 0..5 {
                lower[k] = lower[k].min(row[k]);
                upper[k] = upper[k].max(row[k]);
            }
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
    let [laminar, turbulent] = data;
    Ok(Surrogate {
        format: FORMAT,
        fingerprint,
        lower,
        upper,
        laminar: laminar
            .map(|set| train_regime(&set, settings))
            .transpose()?,
        turbulent: turbulent
            .map(|set| train_regime(&set, settings))
            .transpose()?,
    })
}

/// Fits without the held-out tail to measure the error, then on everything.
fn train_regime(data: &TrainingSet, settings: &Settings) -> Result<RegimeSurrogate, ModelError> {
    let n = data.log_stanton.len();
    let held_out = ((n as f64) * settings.holdout_fraction).round() as usize;
    let (holdout_rms_relative_error, holdout_max_relative_error) = if held_out > 0 {
        let split = n - held_out;
        let partial = fit(
            data.inputs.slice(ndarray::s![..split, ..]).to_owned(),
            data.log_stanton.slice(ndarray::s![..split]).to_owned(),
        )?;
        let predicted = partial
            .predict(&data.inputs.slice(ndarray::s![split.., ..]))
            .map_err(|e| ModelError::inconsistent(NAME, format!("kriging prediction: {e}")))?;
        let errors: Vec<f64> = predicted
            .iter()
            .zip(data.log_stanton.slice(ndarray::s![split..]))
            .map(|(p, t)| (10f64.powf(*p - *t) - 1.0).abs())
            .collect();
        let sum_sq: f64 = errors.iter().map(|e| e * e).sum();
        (
            (sum_sq / held_out as f64).sqrt(),
            errors.iter().copied().fold(0.0, f64::max),
        )
    } else {
        (f64::NAN, f64::NAN)
    };
    Ok(RegimeSurrogate {
        holdout_rms_relative_error,
        holdout_max_relative_error,
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
        let velocity = flight.velocity_body_m_s();
        let direction = velocity / velocity.norm();
        let mut running = std::mem::take(&mut self.running_length_m);
        mesh.strip_running_lengths_m(
            &velocity,
            self.settings.default_running_length_m,
            &mut running,
        );
        self.running_length_m = running;

        for batch in &mut self.batches {
            batch.clear();
        }
        for (i, panel) in mesh.panels.iter().enumerate() {
            let wall_k = wall_temperature_k[i];
            check_wall_temperature(NAME, wall_k, self.settings.melting_point_k, Some(i))?;
            out_w_m2[i] = -self.settings.emissivity * STEFAN_BOLTZMANN_W_M2_K4 * wall_k.powi(4);
            let edge = &aero.edge[i];
            if edge.pressure_pa <= 0.0 || edge.density_kg_m3 <= 0.0 || edge.velocity_m_s <= 0.0 {
                continue;
            }
            let running_length_m = self.running_length_m[i];
            let turbulent = self.is_turbulent(edge, running_length_m);
            let recovery_k = recovery_temperature_k(
                edge,
                gas.gamma,
                recovery_factor(self.settings.prandtl_number, turbulent),
            );
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
                    wall_k / recovery_k,
                    running_length_m.log10(),
                    freestream.altitude_m,
                ],
                Some(i),
            )?;
            let batch = &mut self.batches[usize::from(turbulent)];
            batch.rows.extend_from_slice(&x);
            batch.panels.push(i);
            batch.recovery_k.push(recovery_k);
        }
        for (k, batch) in self.batches.iter_mut().enumerate() {
            if batch.panels.is_empty() {
                continue;
            }
            let gp = &self.surrogate.regime(k == 1)?.gp;
            let inputs =
                Array2::from_shape_vec((batch.panels.len(), 5), std::mem::take(&mut batch.rows))
                    .map_err(shape_error)?;
            let log_stanton = gp
                .predict(&inputs)
                .map_err(|e| ModelError::inconsistent(NAME, format!("kriging prediction: {e}")))?;
            batch.rows = inputs.into_raw_vec_and_offset().0;
            for ((&i, log_st), &recovery_k) in batch
                .panels
                .iter()
                .zip(log_stanton.iter())
                .zip(&batch.recovery_k)
            {
                let edge = &aero.edge[i];
                let q_conv = 10f64.powf(*log_st)
                    * edge.density_kg_m3
                    * edge.velocity_m_s
                    * gas.cp()
                    * (recovery_k - wall_temperature_k[i]);
                out_w_m2[i] += q_conv;
                if !out_w_m2[i].is_finite() {
                    return Err(ModelError::non_finite_at_panel(NAME, "heat flux", i));
                }
            }
        }
        Ok(())
    }
}
