//! The reduced-order aero capability: an aero model identified from another one (a convolution
//! ROM built from a panel method or CFD step responses) that can say what it was built from,
//! be identified anew, and be checked against its source on prescribed modal motion.
//!
//! A model opts in by returning itself from [`super::AeroModel::reduced_order`] (`None`
//! by default), as structure models expose their capabilities ([`crate::structure`]); commands
//! ask for it with [`require`], so they name the model but never link its crate. A reduced
//! model names its source model in the `source` key of its settings.

use nalgebra::DMatrix;

use super::AeroModel;
use crate::error::ModelError;
use crate::flow::FlightCondition;

/// How a check moves the modes.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CheckOptions {
    /// Periods of each sinusoid (of the lowest frequency for the random motion).
    pub periods: f64,
    /// Time steps per period of the highest frequency in a motion.
    pub steps_per_period: usize,
    /// Amplitude of each mode over the correction table's largest.
    pub amplitude_fraction: f64,
    /// Largest vertex velocity of a motion over the freestream speed of sound (the motion's own
    /// piston Mach number), capping the amplitude of the fast modes; `None`: no cap.
    pub max_velocity_ratio: Option<f64>,
    /// Seed of the random multi-mode motion.
    pub seed: u64,
    /// Time the ROM with its panel pressures (as the partitioned vehicle needs them for loads
    /// and heating); false: generalized forces only.
    pub pressures: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            periods: 2.0,
            steps_per_period: 40,
            // Our choice: inside the correction table, between its last two amplitudes.
            amplitude_fraction: 0.9,
            // Our choice: ż/a∞ ≤ 0.02, where the quadratic term of piston theory,
            // (γ+1)/4 (ż/a∞), is 1.2 % of the linear one (Lighthill 1953): the reduced model's
            // rate response is linear, so faster motion tests the source's nonlinearity in
            // rates, which the correction factor does not claim to capture.
            max_velocity_ratio: Some(0.02),
            seed: 14,
            pressures: true,
        }
    }
}

/// One prescribed motion: the errors, costs and both histories.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MotionReport {
    /// `mode 2 at 14.3 Hz` or `random multi-mode`.
    pub name: String,
    /// ‖Q_ROM − Q_source‖ / ‖Q_source − Q_source(q = 0)‖ over every step and mode (2-norms):
    /// the error relative to the aeroelastic part of the forces.
    pub relative_rms_error: f64,
    /// max |Q_ROM − Q_source| / max |Q_source − Q_source(q = 0)| over steps and modes.
    pub relative_max_error: f64,
    pub steps: usize,
    pub dt_s: f64,
    /// Wall-clock time per step of the source (deform, panel velocities, evaluate, project), s.
    pub source_seconds_per_step: f64,
    /// Wall-clock time per step of the ROM (forces, pressures if asked, commit), s.
    pub rom_seconds_per_step: f64,
    /// Source time over ROM time.
    pub speedup: f64,
    pub time_s: Vec<f64>,
    /// Generalized forces `[step][mode]`, N m per unit modal coordinate.
    pub source_generalized_forces: Vec<Vec<f64>>,
    pub rom_generalized_forces: Vec<Vec<f64>>,
}

/// Every motion of a check.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CheckReport {
    pub mach: f64,
    pub altitude_m: f64,
    pub alpha_deg: f64,
    /// Whether the correction factor was applied.
    pub correction: bool,
    /// Wall-clock time of the ROM's steady value (one source evaluation per flight condition and
    /// rigid position, not counted in the per-step times), s.
    pub steady_value_seconds: f64,
    pub motions: Vec<MotionReport>,
}

impl CheckReport {
    /// The largest relative RMS error of the motions.
    pub fn worst_relative_rms_error(&self) -> f64 {
        self.motions
            .iter()
            .map(|m| m.relative_rms_error)
            .fold(0.0, f64::max)
    }

    /// Total source time over total ROM time.
    pub fn overall_speedup(&self) -> f64 {
        let total = |f: fn(&MotionReport) -> f64| -> f64 {
            self.motions.iter().map(|m| f(m) * m.steps as f64).sum()
        };
        total(|m| m.source_seconds_per_step) / total(|m| m.rom_seconds_per_step)
    }
}

/// What a reduced-order model was identified from, and how.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RomSummary {
    /// The reduced model's registered name.
    pub model: String,
    /// The aero model it was identified from.
    pub source: String,
    /// Where its generalized-force step responses come from: `source` or a CSV path.
    pub force_origin: String,
    pub n_modes: usize,
    pub n_panels: usize,
    /// Identification condition.
    pub mach: f64,
    pub altitude_m: f64,
    pub alpha_deg: f64,
    /// Mach numbers of the nonlinear correction table (empty: none).
    pub correction_mach: Vec<f64>,
    /// Amplitudes of the correction table per mode.
    pub correction_amplitudes: usize,
    /// Samples per step response (1: memoryless source).
    pub response_samples: usize,
    /// Sample interval of the step responses, s (0 for one sample).
    pub response_dt_s: f64,
    /// Natural frequencies of its modes, Hz.
    pub natural_frequencies_hz: Vec<f64>,
    /// The identification cache file, if any.
    pub cache_file: Option<String>,
    /// True when the identification came from the cache; false when it was (re)built.
    pub from_cache: bool,
    /// Wall-clock time of the latest identification, s (0 when it came from the cache).
    pub identification_seconds: f64,
}

/// An aero model identified from a source model (the [`AeroModel::reduced_order`] capability).
pub trait ReducedOrderAero {
    /// What it was built from.
    fn summary(&self) -> RomSummary;

    /// Identifies it anew from its source, even when the cache held a valid identification,
    /// and rewrites the cache.
    fn reidentify(&mut self) -> Result<(), ModelError>;

    /// The identification condition (steady level flight at its Mach, altitude and α).
    fn reference_flight(&self) -> Result<FlightCondition, ModelError>;

    /// Settled generalized aerodynamic stiffness ∂Q/∂q and damping ∂Q/∂q̇ at `flight`
    /// (n_modes × n_modes, row: force, column: mode), before the nonlinear correction.
    fn linear_coefficients(&self, flight: &FlightCondition) -> (DMatrix<f64>, DMatrix<f64>);

    /// Turns its nonlinear correction on or off (off: the linear model alone).
    fn set_correction(&mut self, on: bool);

    /// Runs it and its source side by side on prescribed modal motion at `flight`.
    fn check(
        &mut self,
        flight: &FlightCondition,
        options: &CheckOptions,
    ) -> Result<CheckReport, ModelError>;
}

/// The reduced-order capability of `model`; the error names the model and `needed_by`.
pub fn require<'a>(
    model: &'a mut dyn AeroModel,
    needed_by: &str,
) -> Result<&'a mut dyn ReducedOrderAero, ModelError> {
    let name = model.name().to_owned();
    model.reduced_order().ok_or(ModelError::Unsupported {
        model: name,
        capability: "reduced-order identification (an aero model identified from a source)"
            .to_owned(),
        needed_by: needed_by.to_owned(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aero::{AeroSolution, PanelMotion};
    use crate::mesh::PanelMesh;

    struct Plain;

    impl AeroModel for Plain {
        fn name(&self) -> &str {
            "plain"
        }
        fn evaluate(
            &mut self,
            _: &PanelMesh,
            _: &FlightCondition,
            _: &PanelMotion<'_>,
            _: &mut AeroSolution,
        ) -> Result<(), ModelError> {
            Ok(())
        }
    }

    /// A model without the capability is refused with its name, the capability and the analysis.
    #[test]
    fn require_names_model_and_analysis() {
        let error = require(&mut Plain, "`hsv-run rom check`")
            .err()
            .expect("refused");
        let text = error.to_string();
        assert!(text.contains("`plain`") && text.contains("reduced-order"));
        assert!(text.contains("`hsv-run rom check`"), "{text}");
    }

    /// Speed-up is total source time over total ROM time, weighted by steps.
    #[test]
    fn overall_speedup_weights_motions_by_steps() {
        let motion = |steps: usize, source: f64, rom: f64| MotionReport {
            name: String::new(),
            relative_rms_error: 0.0,
            relative_max_error: 0.0,
            steps,
            dt_s: 0.0,
            source_seconds_per_step: source,
            rom_seconds_per_step: rom,
            speedup: source / rom,
            time_s: vec![],
            source_generalized_forces: vec![],
            rom_generalized_forces: vec![],
        };
        let report = CheckReport {
            mach: 6.0,
            altitude_m: 0.0,
            alpha_deg: 0.0,
            correction: true,
            steady_value_seconds: 0.0,
            motions: vec![motion(10, 2.0, 1.0), motion(30, 1.0, 1.0)],
        };
        // (10·2 + 30·1) / (10 + 30) = 1.25.
        assert!((report.overall_speedup() - 1.25).abs() < 1e-15);
    }
}
