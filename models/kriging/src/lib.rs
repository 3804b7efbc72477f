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

mod settings;
mod training;

pub use settings::*;
use training::*;

/// T_aw at an edge state, K ([`hsv_core::thermal::recovery_temperature_k`]).
pub fn recovery_temperature_k(edge: &EdgeState, gamma: f64, r: f64) -> f64 {
    hsv_core::thermal::recovery_temperature_k(edge.temperature_k, edge.mach, gamma, r)
}

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
