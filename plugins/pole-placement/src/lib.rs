//! Example hsv dylib plugin of the control role: `pole-placement`, a short-period stability
//! augmentation whose gains place the poles by Ackermann's formula.
//!
//! It shows what a third-party controller needs: implement [`Controller`] and a
//! [`hsv_core::registry::ControllerConstructor`] exactly as a built-in controller would, and
//! export them with [`hsv_core::export_plugin!`] (plugin API 2.1); build with
//! `cargo build --release -p hsv-plugin-pole-placement` and fly with
//! `hsv-run --plugin target/release/libhsv_plugin_pole_placement.so simulate --controller pole-placement`.
//!
//! The design: the (α, q) block of the host's rigid longitudinal design model with the
//! symmetric elevon is the short-period approximation (Etkin & Reid, "Dynamics of Flight",
//! 3rd ed., §7.3). Its gains K = [0 1] [b Ab]⁻¹ p(A) put the closed-loop poles at the roots of
//! p(s) = s² + 2ζω s + ω² (Ackermann 1972; Ogata, "Modern Control Engineering", 5th ed.,
//! §10-2). The law, sampled every `sample_interval_s`: δe = δe_trim − K (z − z_trim),
//! z = (α, q); φ and the differential elevon stay at trim (the lateral axis is left to the
//! vehicle, so fly it symmetric).

use hsv_core::control::{ControlCommands, Controller, MeasuredOutputs, StateFeedback, matrix_rows};
use hsv_core::error::ModelError;
use hsv_core::registry::ControlContext;
use nalgebra::{DMatrix, DVector};

/// Registered name.
pub const NAME: &str = "pole-placement";

/// `[models.pole-placement]`.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
struct Settings {
    sample_interval_s: f64,
    short_period_frequency_rad_s: f64,
    short_period_damping: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            sample_interval_s: 0.01,
            short_period_frequency_rad_s: 4.0,
            short_period_damping: 0.7,
        }
    }
}

const SETTINGS_DOC: &str = "sample_interval_s = 0.01  # s between samples (held in between)
short_period_frequency_rad_s = 4.0  # placed short-period natural frequency
short_period_damping = 0.7  # placed short-period damping ratio";

/// Coefficients c of the monic polynomial sⁿ + c\[0\] sⁿ⁻¹ + … + c\[n−1\] with roots `poles`
/// (re, im); complex roots must come in conjugate pairs for the result to be real.
pub fn characteristic_coefficients(poles: &[(f64, f64)]) -> Vec<f64> {
    // Multiply out Π (s − p) in complex arithmetic, highest power first.
    let mut c: Vec<(f64, f64)> = vec![(1.0, 0.0)];
    for &(re, im) in poles {
        let mut next = vec![(0.0, 0.0); c.len() + 1];
        for (k, &(a, b)) in c.iter().enumerate() {
            next[k].0 += a;
            next[k].1 += b;
            next[k + 1].0 -= a * re - b * im;
            next[k + 1].1 -= a * im + b * re;
        }
        c = next;
    }
    c[1..].iter().map(|&(a, _)| a).collect()
}

/// Ackermann's formula K = eₙᵀ [b Ab … Aⁿ⁻¹b]⁻¹ p(A) for the single-input pair (A, b):
/// the gains of u = −K x that give A − b K the characteristic polynomial with coefficients
/// `coefficients` (as from [`characteristic_coefficients`]). `None` when (A, b) is not
/// controllable (singular controllability matrix).
pub fn ackermann(a: &DMatrix<f64>, b: &DVector<f64>, coefficients: &[f64]) -> Option<DVector<f64>> {
    let n = a.nrows();
    if a.ncols() != n || b.len() != n || coefficients.len() != n || n == 0 {
        return None;
    }
    let mut controllability = DMatrix::zeros(n, n);
    let mut column = b.clone();
    for k in 0..n {
        controllability.set_column(k, &column);
        column = a * &column;
    }
    // p(A) = Aⁿ + c₀ Aⁿ⁻¹ + … + cₙ₋₁ I by Horner's rule.
    let mut p = DMatrix::identity(n, n);
    for &c in coefficients {
        p = a * p + DMatrix::identity(n, n) * c;
    }
    let inverse = controllability.try_inverse()?;
    let last_row = inverse.row(n - 1);
    Some((last_row * p).transpose())
}

/// The sampled short-period augmentation.
pub struct PolePlacement {
    interval_s: f64,
    /// Indices of α and q in `MeasuredOutputs::values()`, and their trim values.
    states: [usize; 2],
    trim: [f64; 2],
    gains: [f64; 2],
    trim_commands: ControlCommands,
    report: serde_json::Value,
}

impl Controller for PolePlacement {
    fn name(&self) -> &str {
        NAME
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
        let y = outputs.values();
        let feedback: f64 = (0..2)
            .map(|i| self.gains[i] * (y[self.states[i]] - self.trim[i]))
            .sum();
        *commands = self.trim_commands;
        commands.symmetric_elevon_rad -= feedback;
        Ok(())
    }

    fn design_report(&self) -> serde_json::Value {
        self.report.clone()
    }

    fn state_feedback(&self) -> Vec<StateFeedback> {
        vec![StateFeedback {
            state_names: vec!["alpha_rad".into(), "q_rad_s".into()],
            input_names: vec!["symmetric_elevon_rad".into()],
            k: DMatrix::from_row_slice(1, 2, &self.gains),
        }]
    }
}

fn index(names: &[String], wanted: &str, what: &str) -> Result<usize, ModelError> {
    names.iter().position(|n| n == wanted).ok_or_else(|| {
        ModelError::inconsistent(
            NAME,
            format!("the longitudinal design model has no {what} `{wanted}` (it has {names:?})"),
        )
    })
}

/// Designs the augmentation on the host's longitudinal design model.
pub fn construct(ctx: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    if !(settings.sample_interval_s.is_finite() && settings.sample_interval_s > 0.0) {
        return Err(ctx.settings_error("sample_interval_s", "must be > 0 s"));
    }
    let omega = settings.short_period_frequency_rad_s;
    if !(omega.is_finite() && omega > 0.0) {
        return Err(ctx.settings_error("short_period_frequency_rad_s", "must be > 0 rad/s"));
    }
    let zeta = settings.short_period_damping;
    if !(zeta.is_finite() && zeta > 0.0) {
        return Err(ctx.settings_error("short_period_damping", "must be > 0"));
    }
    let model = ctx.design.longitudinal()?;
    let alpha = index(&model.state_names, "alpha_rad", "state")?;
    let q = index(&model.state_names, "q_rad_s", "state")?;
    let elevon = index(&model.input_names, "symmetric_elevon_rad", "input")?;
    let block = [alpha, q];
    let a = DMatrix::from_fn(2, 2, |i, j| model.a[(block[i], block[j])]);
    let b = DVector::from_fn(2, |i, _| model.b[(block[i], elevon)]);
    let coefficients = [2.0 * zeta * omega, omega * omega];
    let k = ackermann(&a, &b, &coefficients).ok_or_else(|| {
        ModelError::inconsistent(
            NAME,
            "the short-period pair (A, b) is not controllable by the symmetric elevon",
        )
    })?;
    let names = MeasuredOutputs::NAMES;
    let states = ["alpha_rad", "q_rad_s"].map(|s| names.iter().position(|n| *n == s).unwrap_or(0));
    let trim_values = ctx.trim_outputs.values();
    let open_loop: Vec<(f64, f64)> = a
        .complex_eigenvalues()
        .iter()
        .map(|e| (e.re, e.im))
        .collect();
    let report = serde_json::json!({
        "short_period_model": {"a": matrix_rows(&a), "b": [b[0], b[1]]},
        "open_loop_poles": open_loop,
        "placed": {"frequency_rad_s": omega, "damping": zeta},
        "gains": {"alpha": k[0], "q_s": k[1]},
    });
    Ok(Box::new(PolePlacement {
        interval_s: settings.sample_interval_s,
        states,
        trim: states.map(|i| trim_values[i]),
        gains: [k[0], k[1]],
        trim_commands: *ctx.trim_commands,
        report,
    }))
}

hsv_core::export_plugin! {
    control {
        name: NAME,
        fidelity: 0,
        summary: "Short-period pole placement (Ackermann's formula on the alpha-q block of the design model); example dylib plugin",
        settings: SETTINGS_DOC,
        constructor: construct,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ogata, "Modern Control Engineering", 5th ed., Example 10-1: A = [0 1 0; 0 0 1; −1 −5 −6],
    /// b = [0 0 1]ᵀ, poles −2 ± 4j and −10 give K = [199 55 8] exactly.
    #[test]
    fn ackermann_reproduces_ogata_example_10_1() {
        let a = DMatrix::from_row_slice(3, 3, &[0.0, 1.0, 0.0, 0.0, 0.0, 1.0, -1.0, -5.0, -6.0]);
        let b = DVector::from_column_slice(&[0.0, 0.0, 1.0]);
        let c = characteristic_coefficients(&[(-2.0, 4.0), (-2.0, -4.0), (-10.0, 0.0)]);
        assert_eq!(c, vec![14.0, 60.0, 200.0]);
        let k = ackermann(&a, &b, &c).expect("controllable");
        for (got, want) in k.iter().zip([199.0, 55.0, 8.0]) {
            assert!((got - want).abs() < 1e-10, "K = {k}");
        }
    }

    #[test]
    fn an_uncontrollable_pair_has_no_gain() {
        let a = DMatrix::from_row_slice(2, 2, &[-1.0, 0.0, 0.0, 2.0]);
        let b = DVector::from_column_slice(&[1.0, 0.0]);
        assert!(ackermann(&a, &b, &[2.0, 1.0]).is_none());
    }
}
