//! `lqr`: linear-quadratic regulators designed at run start on the rigid longitudinal and
//! lateral design models of the trimmed vehicle ([`super::design`]: structure statically
//! residualized), weights by Bryson's rule (Q_ii = 1/z_max², R_jj = 1/u_max²; Bryson & Ho,
//! "Applied Optimal Control", 1975, §5.4), the CARE solved by the matrix sign function with
//! Newton-Kleinman refinement ([`hsv_core::control::riccati`]). The law, sampled every
//! `sample_interval_s`: u = u_trim + u_pilot(t) − K (z − z_trim), z read from the measured
//! outputs, u_pilot the `[simulation.inputs]` schedule when `pilot_inputs` (the doublet then
//! excites the regulated vehicle).

use hsv_core::ModelError;
use hsv_core::control::riccati::{RiccatiSolution, solve_care};
use hsv_core::control::{
    ControlCommands, Controller, LinearDesignModel, MeasuredOutputs, StateFeedback, matrix_rows,
};
use hsv_core::registry::ControlContext;
use hsv_core::registry::{Constructor, ModelDescriptor};
use nalgebra::DMatrix;

use super::schedule::{Schedule, schedule_inputs};

/// `[models.lqr]`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct LqrSettings {
    pub sample_interval_s: f64,
    pub max_airspeed_m_s: f64,
    pub max_alpha_deg: f64,
    pub max_q_deg_s: f64,
    pub max_pitch_deg: f64,
    pub max_altitude_m: f64,
    pub max_beta_deg: f64,
    pub max_p_deg_s: f64,
    pub max_r_deg_s: f64,
    pub max_roll_deg: f64,
    pub max_elevon_deg: f64,
    pub max_differential_elevon_deg: f64,
    pub max_phi: f64,
    pub lateral: bool,
    pub pilot_inputs: bool,
}

impl Default for LqrSettings {
    fn default() -> Self {
        Self {
            sample_interval_s: 0.01,
            max_airspeed_m_s: 10.0,
            max_alpha_deg: 0.5,
            max_q_deg_s: 2.0,
            max_pitch_deg: 1.0,
            max_altitude_m: 50.0,
            max_beta_deg: 0.5,
            max_p_deg_s: 5.0,
            max_r_deg_s: 2.0,
            max_roll_deg: 2.0,
            max_elevon_deg: 5.0,
            max_differential_elevon_deg: 5.0,
            max_phi: 0.1,
            lateral: true,
            pilot_inputs: true,
        }
    }
}

const SETTINGS_DOC: &str = "sample_interval_s = 0.01  # s between samples (held in between)
max_airspeed_m_s = 10.0  # Bryson's rule: Q = 1/max^2 on each design state
max_alpha_deg = 0.5
max_q_deg_s = 2.0
max_pitch_deg = 1.0
max_altitude_m = 50.0
max_beta_deg = 0.5
max_p_deg_s = 5.0
max_r_deg_s = 2.0
max_roll_deg = 2.0
max_elevon_deg = 5.0  # R = 1/max^2 on each input
max_differential_elevon_deg = 5.0
max_phi = 0.1
lateral = true  # also regulate the lateral axis with differential elevon
pilot_inputs = true  # add the [simulation.inputs] offsets (the doublet) to the commands";

/// One axis's regulator.
#[derive(Debug, Clone)]
pub(crate) struct Regulator {
    /// Indices into `MeasuredOutputs::values()` of the states, and into the command triple.
    pub(crate) states: Vec<usize>,
    pub(crate) inputs: Vec<usize>,
    pub(crate) feedback: StateFeedback,
    pub(crate) report: serde_json::Value,
}

impl Regulator {
    /// Adds −K (z − z_ref) to the commands `u` (z from the measured values `y`, z_ref from
    /// `reference`: the trim, or a tracking controller's commanded state).
    pub(crate) fn apply(&self, y: &[f64; 16], reference: &[f64; 16], u: &mut [f64; 3]) {
        let k = &self.feedback.k;
        for (i, &ui) in self.inputs.iter().enumerate() {
            let mut sum = 0.0;
            for (j, &zj) in self.states.iter().enumerate() {
                sum += k[(i, j)] * (y[zj] - reference[zj]);
            }
            u[ui] -= sum;
        }
    }
}

/// The LQR of ẋ = A x + B u weighted by Bryson's rule (Q_ii = 1/x_max², R_jj = 1/u_max²): the
/// CARE solution and the closed-loop poles of A − B K as (re, im).
pub(crate) fn bryson_lqr(
    ctx: &ControlContext<'_>,
    axis: &str,
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    state_max: &[f64],
    input_max: &[f64],
) -> Result<(RiccatiSolution, Vec<[f64; 2]>), ModelError> {
    let weights = |max: &[f64]| {
        DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(
            max.len(),
            max.iter().map(|m| 1.0 / (m * m)),
        ))
    };
    let s = solve_care(a, b, &weights(state_max), &weights(input_max))
        .map_err(|e| ctx.settings_error("", format!("{axis} LQR design: {e}")))?;
    let poles = hsv_core::linalg::general_eigen(&(a - b * &s.k))
        .map_err(|e| ctx.settings_error("", format!("{axis} closed-loop poles: {e}")))?;
    let poles = poles.values.iter().map(|c| [c.re, c.im]).collect();
    Ok((s, poles))
}

/// The regulator u −= K (z − z_ref) on the named design states (measured outputs) and inputs
/// (commands).
pub(crate) fn regulator(
    ctx: &ControlContext<'_>,
    state_names: &[String],
    input_names: &[String],
    k: DMatrix<f64>,
    report: serde_json::Value,
) -> Result<Regulator, ModelError> {
    let index = |names: &[&str], n: &String, what: &str| {
        names
            .iter()
            .position(|m| m == n)
            .ok_or_else(|| ctx.settings_error("", format!("design {what} `{n}` is unknown")))
    };
    Ok(Regulator {
        states: state_names
            .iter()
            .map(|n| index(&MeasuredOutputs::NAMES, n, "state (measured output)"))
            .collect::<Result<_, _>>()?,
        inputs: input_names
            .iter()
            .map(|n| index(&ControlCommands::NAMES, n, "input (command)"))
            .collect::<Result<_, _>>()?,
        feedback: StateFeedback {
            state_names: state_names.to_vec(),
            input_names: input_names.to_vec(),
            k,
        },
        report,
    })
}

pub(crate) fn design(
    ctx: &ControlContext<'_>,
    axis: &str,
    model: &LinearDesignModel,
    state_max: &[f64],
    input_max: &[f64],
) -> Result<Regulator, ModelError> {
    let (s, poles) = bryson_lqr(ctx, axis, &model.a, &model.b, state_max, input_max)?;
    let report = serde_json::json!({
        "states": model.state_names,
        "inputs": model.input_names,
        "reduction": model.reduction,
        "a": matrix_rows(&model.a),
        "b": matrix_rows(&model.b),
        "gain_k": matrix_rows(&s.k),
        "care_relative_residual": s.relative_residual,
        "sign_iterations": s.sign_iterations,
        "newton_kleinman_steps": s.newton_steps,
        "closed_loop_poles": poles,
    });
    regulator(ctx, &model.state_names, &model.input_names, s.k, report)
}

/// The regulators and the pilot schedule.
pub struct Lqr {
    interval_s: f64,
    trim_outputs: [f64; 16],
    pilot: Option<Schedule>,
    trim: ControlCommands,
    regulators: Vec<Regulator>,
}

impl Controller for Lqr {
    fn name(&self) -> &str {
        "lqr"
    }

    fn sample_interval_s(&self) -> Option<f64> {
        Some(self.interval_s)
    }

    fn update(
        &mut self,
        outputs: &MeasuredOutputs,
        _state: &mut [f64],
        commands: &mut ControlCommands,
    ) -> Result<(), ModelError> {
        let mut base = self.trim;
        if let Some(pilot) = self.pilot.as_mut() {
            pilot.update(outputs, &mut [], &mut base)?;
        }
        let mut u = base.values();
        let y = outputs.values();
        for reg in &self.regulators {
            reg.apply(&y, &self.trim_outputs, &mut u);
        }
        *commands = ControlCommands::from_values(u);
        Ok(())
    }

    fn design_report(&self) -> serde_json::Value {
        let mut axes = serde_json::Map::new();
        for (name, reg) in ["longitudinal", "lateral"].iter().zip(&self.regulators) {
            axes.insert((*name).to_owned(), reg.report.clone());
        }
        serde_json::Value::Object(axes)
    }

    fn state_feedback(&self) -> Vec<StateFeedback> {
        self.regulators.iter().map(|r| r.feedback.clone()).collect()
    }
}

fn build(ctx: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    let s: LqrSettings = ctx.parse_settings()?;
    let positive = [
        ("sample_interval_s", s.sample_interval_s),
        ("max_airspeed_m_s", s.max_airspeed_m_s),
        ("max_alpha_deg", s.max_alpha_deg),
        ("max_q_deg_s", s.max_q_deg_s),
        ("max_pitch_deg", s.max_pitch_deg),
        ("max_altitude_m", s.max_altitude_m),
        ("max_beta_deg", s.max_beta_deg),
        ("max_p_deg_s", s.max_p_deg_s),
        ("max_r_deg_s", s.max_r_deg_s),
        ("max_roll_deg", s.max_roll_deg),
        ("max_elevon_deg", s.max_elevon_deg),
        ("max_differential_elevon_deg", s.max_differential_elevon_deg),
        ("max_phi", s.max_phi),
    ];
    if let Some((key, v)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
        return Err(ctx.settings_error(key, format!("is {v}; expected a number > 0")));
    }
    let d = f64::to_radians;
    let mut regulators = vec![design(
        ctx,
        "longitudinal",
        &ctx.design.longitudinal()?,
        &[
            s.max_airspeed_m_s,
            d(s.max_alpha_deg),
            d(s.max_q_deg_s),
            d(s.max_pitch_deg),
            s.max_altitude_m,
        ],
        &[d(s.max_elevon_deg), s.max_phi],
    )?];
    if s.lateral {
        regulators.push(design(
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
        )?);
    }
    let pilot = if s.pilot_inputs {
        Some(Schedule::new(schedule_inputs(ctx)?, *ctx.trim_commands))
    } else {
        None
    };
    Ok(Box::new(Lqr {
        interval_s: s.sample_interval_s,
        trim_outputs: ctx.trim_outputs.values(),
        pilot,
        trim: *ctx.trim_commands,
        regulators,
    }))
}

hsv_core::register_model!(ModelDescriptor {
    name: "lqr",
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "LQR state feedback on the residualized rigid longitudinal (elevon, phi) and lateral (differential elevon) models of the trimmed vehicle",
    settings_doc: SETTINGS_DOC,
    constructor: Constructor::Control(build),
});
