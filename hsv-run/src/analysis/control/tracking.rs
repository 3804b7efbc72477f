//! `tracking`: altitude and airspeed hold with integral action, the linear-quadratic servo
//! Groves, Sigthorsson, Serrani, Yurkovich, Bolender & Doman designed for the linearized
//! air-breathing hypersonic vehicle ("Reference Command Tracking for a Linearized Model of an
//! Air-breathing Hypersonic Vehicle", AIAA 2005-6144): the rigid longitudinal design model
//! (airspeed, α, q, θ, h; elevon and φ; [`super::design`]) augmented with the integrals of the
//! altitude and airspeed errors, one LQR on the whole (weights by Bryson's rule, as `lqr`);
//! the lateral axis, whose open loop diverges, is held at trim by `lqr`'s lateral regulator.
//!
//! Sampled every `sample_interval_s`: ξ ← ξ + Δt (y − y_c) for y = (h, V), and
//! u = u_trim − K_x (x − x_ref) − K_ξ ξ, x_ref the trim with h and V at their commands. The
//! commands are `[control.commands]` tables of offsets from trim by time (`altitude_m`,
//! `airspeed_m_s`; linear between rows, held beyond), the paper's doublet is not flown. An
//! error is integrated only while it is small (conditional integration), and an integral that
//! would drive φ further past [0, 1] is held (clamping anti-windup; both Åström & Hägglund,
//! "Advanced PID Control", 2006, §3.5), so a large step is flown on the proportional law.

use hsv_core::ModelError;
use hsv_core::control::{ControlCommands, Controller, MeasuredOutputs, StateFeedback};
use hsv_core::registry::ControlContext;
use hsv_core::registry::{Constructor, ModelDescriptor};
use nalgebra::DMatrix;

use super::lqr::{Regulator, bryson_lqr, design, regulator};
use crate::analysis::inputs::InputTable;
use hsv_core::control::matrix_rows;

/// `[models.tracking]`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrackingSettings {
    pub sample_interval_s: f64,
    pub max_airspeed_m_s: f64,
    pub max_alpha_deg: f64,
    pub max_q_deg_s: f64,
    pub max_pitch_deg: f64,
    pub max_altitude_m: f64,
    pub max_altitude_integral_m_s: f64,
    pub max_airspeed_integral_m: f64,
    pub max_elevon_deg: f64,
    pub max_phi: f64,
    pub max_beta_deg: f64,
    pub max_p_deg_s: f64,
    pub max_r_deg_s: f64,
    pub max_roll_deg: f64,
    pub max_differential_elevon_deg: f64,
    /// Conditional integration: each error is integrated only while it is smaller than this,
    /// so a large step is flown on the proportional law and the integral trims the rest.
    pub integrate_within_m: f64,
    pub integrate_within_m_s: f64,
    /// Feed back the inertial flight-path angle γ and θ in place of the air-data α
    /// (`inertial_flight_path_law`).
    pub inertial_flight_path: bool,
}

impl Default for TrackingSettings {
    fn default() -> Self {
        Self {
            sample_interval_s: 0.01,
            max_airspeed_m_s: 5.0,
            max_alpha_deg: 0.5,
            max_q_deg_s: 2.0,
            max_pitch_deg: 1.0,
            max_altitude_m: 20.0,
            max_altitude_integral_m_s: 100.0,
            max_airspeed_integral_m: 50.0,
            max_elevon_deg: 5.0,
            max_phi: 0.1,
            max_beta_deg: 0.5,
            max_p_deg_s: 5.0,
            max_r_deg_s: 2.0,
            max_roll_deg: 2.0,
            max_differential_elevon_deg: 5.0,
            integrate_within_m: 20.0,
            integrate_within_m_s: 2.0,
            inertial_flight_path: true,
        }
    }
}

const SETTINGS_DOC: &str = "sample_interval_s = 0.01  # s between samples (held in between)
max_airspeed_m_s = 5.0  # Bryson's rule: Q = 1/max^2 on each design state
max_alpha_deg = 0.5
max_q_deg_s = 2.0
max_pitch_deg = 1.0
max_altitude_m = 20.0
max_altitude_integral_m_s = 100.0  # on the integral of the altitude error
max_airspeed_integral_m = 50.0  # on the integral of the airspeed error
max_elevon_deg = 5.0  # R = 1/max^2 on each input
max_phi = 0.1
max_beta_deg = 0.5  # the lateral regulator (as lqr's): beta, p, r, roll; differential elevon
max_p_deg_s = 5.0
max_r_deg_s = 2.0
max_roll_deg = 2.0
max_differential_elevon_deg = 5.0
integrate_within_m = 20.0  # conditional integration: the altitude error is integrated only below this
integrate_within_m_s = 2.0  # and the airspeed error only below this
inertial_flight_path = true  # feed back the inertial flight-path angle and pitch where the design has alpha (alpha = theta - gamma in still air: the same law, but a gust's alpha does not drive the elevon)
# commands: [control.commands] altitude_m / airspeed_m_s = { time_s = [...], value = [...] } (offsets from trim)";

/// The law u = −K z re-expressed to read the inertial flight-path angle γ where it read the
/// air-data α: in still, symmetric flight α = θ − γ, so −K_α α − K_θ θ = K_α γ − (K_α + K_θ) θ
/// is the same law on the linear model, but a gust's α no longer drives the elevon (it still
/// acts through the q, θ, h and V it causes). Without α or θ among `names` the law is kept.
fn inertial_flight_path_law(names: &[String], k: DMatrix<f64>) -> (Vec<String>, DMatrix<f64>) {
    let at = |wanted: &str| names.iter().position(|n| n == wanted);
    let (Some(alpha), Some(pitch)) = (at("alpha_rad"), at("pitch_rad")) else {
        return (names.to_vec(), k);
    };
    let mut law = k;
    for i in 0..law.nrows() {
        let k_alpha = law[(i, alpha)];
        law[(i, alpha)] = -k_alpha;
        law[(i, pitch)] += k_alpha;
    }
    let mut states = names.to_vec();
    states[alpha] = "flight_path_rad".to_owned();
    (states, law)
}

/// `[control.commands]`.
#[derive(Debug, Clone, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CommandTables {
    altitude_m: Option<InputTable>,
    airspeed_m_s: Option<InputTable>,
}

/// Indices of altitude and airspeed in the design model's states and in `MeasuredOutputs`.
const TRACKED: [&str; 2] = ["altitude_m", "airspeed_m_s"];

pub struct Tracking {
    interval_s: f64,
    trim_outputs: [f64; 16],
    trim: ControlCommands,
    /// The proportional law −K_x (x − x_ref) on the longitudinal design states.
    longitudinal: Regulator,
    /// Indices into `MeasuredOutputs::values()` of the tracked outputs.
    tracked: [usize; 2],
    /// Errors are integrated only below these (altitude m, airspeed m/s).
    integrate_within: [f64; 2],
    /// Which design input is φ (the one with a hard range, [0, 1]).
    phi_input: Option<usize>,
    /// Gains on the two integrals.
    k_xi: DMatrix<f64>,
    commands: [InputTable; 2],
    /// The lateral axis held at trim (its open loop diverges: a spiral/roll root).
    lateral: Regulator,
    report: serde_json::Value,
}

impl Tracking {
    /// u = u_trim − K_x (x − x_ref) − K_ξ ξ, as the command triple.
    fn law(&self, y: &[f64; 16], reference: &[f64; 16], xi: &[f64]) -> [f64; 3] {
        let mut u = self.trim.values();
        self.longitudinal.apply(y, reference, &mut u);
        for (i, &ui) in self.longitudinal.inputs.iter().enumerate() {
            u[ui] -= (0..xi.len())
                .map(|j| self.k_xi[(i, j)] * xi[j])
                .sum::<f64>();
        }
        self.lateral.apply(y, &self.trim_outputs, &mut u);
        u
    }
}

impl Controller for Tracking {
    fn name(&self) -> &str {
        "tracking"
    }

    fn sample_interval_s(&self) -> Option<f64> {
        Some(self.interval_s)
    }

    fn state_len(&self) -> usize {
        2
    }

    fn update(
        &mut self,
        outputs: &MeasuredOutputs,
        state: &mut [f64],
        commands: &mut ControlCommands,
    ) -> Result<(), ModelError> {
        let y = outputs.values();
        let mut reference = self.trim_outputs;
        for (c, table) in self.tracked.iter().zip(&self.commands) {
            reference[*c] += table.at(outputs.time_s);
        }
        let previous = [state[0], state[1]];
        for ((xi, &c), within) in state
            .iter_mut()
            .zip(&self.tracked)
            .zip(self.integrate_within)
        {
            let error = y[c] - reference[c];
            if error.abs() < within {
                *xi += self.interval_s * error;
            }
        }
        let mut u = self.law(&y, &reference, state);
        // Clamping anti-windup (Åström & Hägglund, "Advanced PID Control", 2006, §3.5): an
        // integral whose step pushes φ further past [0, 1] keeps its previous value.
        if let Some(i) = self.phi_input {
            let phi = u[self.longitudinal.inputs[i]];
            let excess = if phi > 1.0 {
                phi - 1.0
            } else if phi < 0.0 {
                phi
            } else {
                0.0
            };
            if excess != 0.0 {
                let mut held = false;
                for j in 0..2 {
                    let push = -self.k_xi[(i, j)] * (state[j] - previous[j]);
                    if push * excess > 0.0 {
                        state[j] = previous[j];
                        held = true;
                    }
                }
                if held {
                    u = self.law(&y, &reference, state);
                }
            }
        }
        *commands = ControlCommands::from_values(u);
        Ok(())
    }

    fn design_report(&self) -> serde_json::Value {
        self.report.clone()
    }

    fn state_feedback(&self) -> Vec<StateFeedback> {
        // The proportional parts; the integrals are the controller's own state.
        vec![
            self.longitudinal.feedback.clone(),
            self.lateral.feedback.clone(),
        ]
    }
}

fn position(names: &[&str], name: &str) -> Option<usize> {
    names.iter().position(|n| *n == name)
}

fn build(ctx: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    let s: TrackingSettings = ctx.parse_settings()?;
    let positive = [
        ("sample_interval_s", s.sample_interval_s),
        ("max_airspeed_m_s", s.max_airspeed_m_s),
        ("max_alpha_deg", s.max_alpha_deg),
        ("max_q_deg_s", s.max_q_deg_s),
        ("max_pitch_deg", s.max_pitch_deg),
        ("max_altitude_m", s.max_altitude_m),
        ("max_altitude_integral_m_s", s.max_altitude_integral_m_s),
        ("max_airspeed_integral_m", s.max_airspeed_integral_m),
        ("max_elevon_deg", s.max_elevon_deg),
        ("max_phi", s.max_phi),
        ("max_beta_deg", s.max_beta_deg),
        ("max_p_deg_s", s.max_p_deg_s),
        ("max_r_deg_s", s.max_r_deg_s),
        ("max_roll_deg", s.max_roll_deg),
        ("max_differential_elevon_deg", s.max_differential_elevon_deg),
        ("integrate_within_m", s.integrate_within_m),
        ("integrate_within_m_s", s.integrate_within_m_s),
    ];
    if let Some((key, v)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
        return Err(ctx.settings_error(key, format!("is {v}; expected a number > 0")));
    }
    let tables: CommandTables =
        hsv_core::config::parse_table(ctx.commands, ctx.file, "control.commands")
            .map_err(ModelError::from)?;
    let commands = [
        tables
            .altitude_m
            .unwrap_or_else(|| InputTable::constant(0.0)),
        tables
            .airspeed_m_s
            .unwrap_or_else(|| InputTable::constant(0.0)),
    ];
    for (table, key) in commands.iter().zip([
        "control.commands.altitude_m",
        "control.commands.airspeed_m_s",
    ]) {
        table.check(key).map_err(|e| ModelError::Settings {
            file: ctx.file.to_owned(),
            key_path: e.key.clone(),
            message: e.message,
        })?;
    }

    let model = ctx.design.longitudinal()?;
    let names: Vec<&str> = model.state_names.iter().map(String::as_str).collect();
    let d = f64::to_radians;
    let state_max: Vec<f64> = names
        .iter()
        .map(|n| match *n {
            "airspeed_m_s" => Ok(s.max_airspeed_m_s),
            "alpha_rad" => Ok(d(s.max_alpha_deg)),
            "q_rad_s" => Ok(d(s.max_q_deg_s)),
            "pitch_rad" => Ok(d(s.max_pitch_deg)),
            "altitude_m" => Ok(s.max_altitude_m),
            other => Err(ctx.settings_error("", format!("design state `{other}` has no weight"))),
        })
        .collect::<Result<_, _>>()?;
    let input_max: Vec<f64> = model
        .input_names
        .iter()
        .map(|n| match n.as_str() {
            "symmetric_elevon_rad" => Ok(d(s.max_elevon_deg)),
            "fuel_equivalence_ratio" => Ok(s.max_phi),
            other => Err(ctx.settings_error("", format!("design input `{other}` has no weight"))),
        })
        .collect::<Result<_, _>>()?;
    let tracked_in_states = TRACKED.map(|t| position(&names, t));
    let [Some(h), Some(v)] = tracked_in_states else {
        return Err(ctx.settings_error(
            "",
            "the longitudinal design model lacks altitude_m or airspeed_m_s".to_owned(),
        ));
    };
    // The servo: ż = [A 0; C 0] z + [B; 0] u with C picking h and V (Groves et al. 2005).
    let (n, m) = (names.len(), model.input_names.len());
    let mut a = DMatrix::zeros(n + 2, n + 2);
    a.view_mut((0, 0), (n, n)).copy_from(&model.a);
    a[(n, h)] = 1.0;
    a[(n + 1, v)] = 1.0;
    let mut b = DMatrix::zeros(n + 2, m);
    b.view_mut((0, 0), (n, m)).copy_from(&model.b);
    let servo_max: Vec<f64> = state_max
        .iter()
        .copied()
        .chain([s.max_altitude_integral_m_s, s.max_airspeed_integral_m])
        .collect();
    let (care, poles) = bryson_lqr(ctx, "tracking", &a, &b, &servo_max, &input_max)?;
    let servo_states: Vec<&str> = names
        .iter()
        .copied()
        .chain(["altitude_error_integral_m_s", "airspeed_error_integral_m"])
        .collect();
    let (law_states, law_k) = if s.inertial_flight_path {
        inertial_flight_path_law(&model.state_names, care.k.columns(0, n).into_owned())
    } else {
        (model.state_names.clone(), care.k.columns(0, n).into_owned())
    };
    let longitudinal = regulator(
        ctx,
        &law_states,
        &model.input_names,
        law_k,
        serde_json::Value::Null,
    )?;
    let tracked = [longitudinal.states[h], longitudinal.states[v]];
    let lateral = design(
        ctx,
        "lateral",
        &ctx.design.lateral()?,
        &[
            d(s.max_beta_deg),
            d(s.max_p_deg_s),
            d(s.max_r_deg_s),
            d(s.max_roll_deg),
        ],
        &[d(s.max_differential_elevon_deg)],
    )?;
    let report = serde_json::json!({ "lateral": lateral.report, "longitudinal servo": {
        "design": "LQ servo with integral action on altitude and airspeed (Groves et al., AIAA 2005-6144)",
        "states": servo_states,
        "inputs": model.input_names,
        "gain_k": matrix_rows(&care.k),
        "care_relative_residual": care.relative_residual,
        "closed_loop_poles": poles,
    }});
    Ok(Box::new(Tracking {
        interval_s: s.sample_interval_s,
        trim_outputs: ctx.trim_outputs.values(),
        trim: *ctx.trim_commands,
        tracked,
        integrate_within: [s.integrate_within_m, s.integrate_within_m_s],
        phi_input: model
            .input_names
            .iter()
            .position(|n| n == "fuel_equivalence_ratio"),
        k_xi: care.k.columns(n, 2).into_owned(),
        longitudinal,
        commands,
        lateral,
        report,
    }))
}

hsv_core::register_model!(ModelDescriptor {
    name: "tracking",
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "altitude and airspeed hold with integral action (LQ servo on the residualized rigid longitudinal model; elevon and phi; lateral held by lqr's regulator), commands from [control.commands]",
    settings_doc: SETTINGS_DOC,
    constructor: Constructor::Control(build),
});
