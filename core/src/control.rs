//! The control role: a controller reads the measured outputs of the vehicle and returns the
//! commands (symmetric and differential elevon, fuel equivalence ratio φ) at its own rate.
//!
//! Controllers register by name with [`register_model!`](crate::register_model) like models
//! (`Constructor::Control`), so `hsv-run models` and `describe` list them; their settings are
//! `[models.<name>]`. A controller keeps scratch only: whatever it remembers between samples
//! (an integrator, a filter) lives in the plain `state` slice the runner owns and writes into
//! restart files. Design data (a linear model of the trimmed vehicle, [`LinearDesignModel`]) is
//! plain serializable data too, so a resumed run rebuilds the same controller bit for bit.

pub mod riccati;

use nalgebra::DMatrix;

use crate::error::ModelError;

/// What the controller measures (the true values at the sample instant, or what the runner's
/// sensors make of them: delayed, biased, noisy). SI,
/// angles in radians, body axes x forward, y right, z down.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct MeasuredOutputs {
    /// Time of the sample, s.
    pub time_s: f64,
    /// Body roll, pitch and yaw rates, rad/s.
    pub p_rad_s: f64,
    pub q_rad_s: f64,
    pub r_rad_s: f64,
    /// Angle of attack and sideslip of the centre of mass, rad.
    pub alpha_rad: f64,
    pub beta_rad: f64,
    /// Airspeed of the centre of mass, m/s.
    pub airspeed_m_s: f64,
    /// Flight Mach number (US Standard Atmosphere 1976 speed of sound at the altitude).
    pub mach: f64,
    /// Geometric altitude, m.
    pub altitude_m: f64,
    /// 3-2-1 Euler angles, rad.
    pub roll_rad: f64,
    pub pitch_rad: f64,
    pub yaw_rad: f64,
    /// Flight-path angle γ = asin(−v_down / |v|), rad (positive climbing).
    pub flight_path_rad: f64,
    /// Actuator positions: symmetric and differential elevon (rad), fuel equivalence ratio.
    pub symmetric_elevon_rad: f64,
    pub differential_elevon_rad: f64,
    pub fuel_equivalence_ratio: f64,
}

impl MeasuredOutputs {
    /// The names of [`Self::values`], units in the names.
    pub const NAMES: [&'static str; 16] = [
        "time_s",
        "p_rad_s",
        "q_rad_s",
        "r_rad_s",
        "alpha_rad",
        "beta_rad",
        "airspeed_m_s",
        "mach",
        "altitude_m",
        "roll_rad",
        "pitch_rad",
        "yaw_rad",
        "flight_path_rad",
        "symmetric_elevon_rad",
        "differential_elevon_rad",
        "fuel_equivalence_ratio",
    ];

    /// The outputs in the order of [`Self::NAMES`].
    pub fn values(&self) -> [f64; 16] {
        [
            self.time_s,
            self.p_rad_s,
            self.q_rad_s,
            self.r_rad_s,
            self.alpha_rad,
            self.beta_rad,
            self.airspeed_m_s,
            self.mach,
            self.altitude_m,
            self.roll_rad,
            self.pitch_rad,
            self.yaw_rad,
            self.flight_path_rad,
            self.symmetric_elevon_rad,
            self.differential_elevon_rad,
            self.fuel_equivalence_ratio,
        ]
    }

    /// The outputs from their values in the order of [`Self::NAMES`].
    pub fn from_values(v: [f64; 16]) -> Self {
        Self {
            time_s: v[0],
            p_rad_s: v[1],
            q_rad_s: v[2],
            r_rad_s: v[3],
            alpha_rad: v[4],
            beta_rad: v[5],
            airspeed_m_s: v[6],
            mach: v[7],
            altitude_m: v[8],
            roll_rad: v[9],
            pitch_rad: v[10],
            yaw_rad: v[11],
            flight_path_rad: v[12],
            symmetric_elevon_rad: v[13],
            differential_elevon_rad: v[14],
            fuel_equivalence_ratio: v[15],
        }
    }

    /// The output called `name` (one of [`Self::NAMES`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        Self::NAMES
            .iter()
            .position(|n| *n == name)
            .map(|i| self.values()[i])
    }
}

/// What a controller commands (absolute values, not offsets from trim).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct ControlCommands {
    /// Symmetric elevon, rad (positive: nose-up pitching moment, trailing edge up on the aft
    /// surfaces; DESIGN §4).
    pub symmetric_elevon_rad: f64,
    /// Differential elevon (left = +, right = −), rad.
    pub differential_elevon_rad: f64,
    /// Fuel equivalence ratio φ (1 = stoichiometric).
    pub fuel_equivalence_ratio: f64,
}

impl ControlCommands {
    /// The names of [`Self::values`], units in the names.
    pub const NAMES: [&'static str; 3] = [
        "symmetric_elevon_rad",
        "differential_elevon_rad",
        "fuel_equivalence_ratio",
    ];

    /// The commands in the order of [`Self::NAMES`].
    pub fn values(&self) -> [f64; 3] {
        [
            self.symmetric_elevon_rad,
            self.differential_elevon_rad,
            self.fuel_equivalence_ratio,
        ]
    }

    /// The commands from values in the order of [`Self::NAMES`].
    pub fn from_values(
        [
            symmetric_elevon_rad,
            differential_elevon_rad,
            fuel_equivalence_ratio,
        ]: [f64; 3],
    ) -> Self {
        Self {
            symmetric_elevon_rad,
            differential_elevon_rad,
            fuel_equivalence_ratio,
        }
    }
}

/// A linear design model ẋ = A x + B u of the trimmed vehicle, in deviations from trim.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LinearDesignModel {
    /// State names: each a [`MeasuredOutputs`] name, so a state-feedback law reads its state
    /// from the measurements.
    pub state_names: Vec<String>,
    /// Input names: `symmetric_elevon_rad`, `fuel_equivalence_ratio`, ...
    pub input_names: Vec<String>,
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    /// How the model was reduced from the full linearization, for the printed summary.
    pub reduction: String,
}

/// A controller.
pub trait Controller: Send {
    /// The registered name.
    fn name(&self) -> &str;

    /// Interval between samples, s; `None` for a law of time alone (an open-loop schedule),
    /// which is evaluated at every instant the dynamics ask and so must keep no state.
    fn sample_interval_s(&self) -> Option<f64>;

    /// Length of the controller's state (0: memoryless).
    fn state_len(&self) -> usize {
        0
    }

    /// The state at the start of a run (trim), into `state` of length [`Self::state_len`].
    fn initial_state(&self, state: &mut [f64]) {
        state.fill(0.0);
    }

    /// One sample: the commands from the measurements, advancing `state` by one interval.
    /// Allocates nothing (it runs inside the time loop).
    fn update(
        &mut self,
        outputs: &MeasuredOutputs,
        state: &mut [f64],
        commands: &mut ControlCommands,
    ) -> Result<(), ModelError>;

    /// Lines describing the design (gains, closed-loop poles), printed and saved at run start.
    fn design_report(&self) -> serde_json::Value {
        serde_json::Value::Null
    }

    /// The linear state-feedback laws u = −K z (deviations from trim) the controller applies,
    /// for closed-loop linear analysis; empty for laws that are not static state feedback.
    fn state_feedback(&self) -> Vec<StateFeedback> {
        Vec::new()
    }
}

/// Where a controller gets its linear design model: the runner linearizes the trimmed vehicle
/// on the first request (and remembers it for the restart file); a resumed run answers with
/// the model it saved.
pub trait DesignSource {
    /// The rigid longitudinal design model around trim (states from [`MeasuredOutputs`] names,
    /// inputs symmetric elevon and φ).
    fn longitudinal(&self) -> Result<LinearDesignModel, ModelError>;
    /// The rigid lateral design model (states β, p, r, roll; input differential elevon).
    fn lateral(&self) -> Result<LinearDesignModel, ModelError>;
}

/// A static state-feedback law u = −K z, z and u deviations from trim named by
/// [`MeasuredOutputs`] and [`ControlCommands`] fields.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StateFeedback {
    pub state_names: Vec<String>,
    pub input_names: Vec<String>,
    pub k: DMatrix<f64>,
}

/// A matrix as its rows (`[[a00, a01, ..], ..]`): the JSON form of design reports and of the
/// plugin ABI's design models and gains.
pub fn matrix_rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}
