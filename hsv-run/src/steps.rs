//! Time stepping of a run: how many steps a duration takes at a step size, and how long the
//! last one is. The one rule every time-marching job uses, so none silently runs past the
//! requested end or starts a run that cannot finish.
//!
//! The rule: a duration that is a whole number of steps (to a relative 1e-9, so 100 s at 0.1 s
//! is 1000 steps despite round-off) takes that many; otherwise the steps are rounded up and the
//! last one shortened so the run ends exactly at the duration. More than [`MAX_STEPS`] steps is
//! refused up front with the count.

/// Most steps a run may take (10⁸: hours of wall time even for the cheapest model).
pub const MAX_STEPS: u64 = 100_000_000;

/// Relative tolerance for "a whole number of steps".
const WHOLE_STEPS_TOLERANCE: f64 = 1e-9;

/// Why a duration and step cannot make a run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    #[error("the {what} must be a positive number of seconds, got {value}")]
    NotPositive { what: &'static str, value: f64 },
    #[error(
        "a duration of {duration_s} s at a step of {dt_s} s is {steps:.3e} steps, more than the {MAX_STEPS} allowed; lengthen the step or shorten the duration"
    )]
    TooMany {
        duration_s: f64,
        dt_s: f64,
        steps: f64,
    },
}

/// The steps of a run: `steps` of `dt_s`, the last of `last_dt_s` (≤ `dt_s`), ending exactly at
/// `duration_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepPlan {
    pub steps: usize,
    /// Step size, s.
    pub dt_s: f64,
    /// Length of the last step, s: `dt_s` when the duration is a whole number of steps.
    pub last_dt_s: f64,
    /// End time, s.
    pub duration_s: f64,
}

impl StepPlan {
    /// Length of step `k` (0-based), s.
    pub fn dt_of(&self, k: usize) -> f64 {
        if k + 1 == self.steps {
            self.last_dt_s
        } else {
            self.dt_s
        }
    }

    /// Time at the start of step `k`, s: k Δt.
    pub fn start_s(&self, k: usize) -> f64 {
        k as f64 * self.dt_s
    }

    /// Time at the end of step `k`, s: (k + 1) Δt, and exactly the duration after the last.
    pub fn end_s(&self, k: usize) -> f64 {
        if k + 1 >= self.steps {
            self.duration_s
        } else {
            (k + 1) as f64 * self.dt_s
        }
    }

    /// True when the last step is shorter than the others.
    pub fn last_step_shortened(&self) -> bool {
        self.last_dt_s < self.dt_s
    }
}

/// The steps that take a run from 0 to `duration_s` at `dt_s` (module docs for the rule).
pub fn time_steps(duration_s: f64, dt_s: f64) -> Result<StepPlan, StepError> {
    for (what, value) in [("duration", duration_s), ("time step", dt_s)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(StepError::NotPositive { what, value });
        }
    }
    let ratio = duration_s / dt_s;
    // An infinite ratio (a step that underflows against the duration) is too many as well.
    if !ratio.is_finite() || ratio > MAX_STEPS as f64 * (1.0 + WHOLE_STEPS_TOLERANCE) {
        return Err(StepError::TooMany {
            duration_s,
            dt_s,
            steps: ratio.ceil(),
        });
    }
    let whole = ratio.round();
    let is_whole = whole >= 1.0 && (ratio - whole).abs() <= WHOLE_STEPS_TOLERANCE * ratio;
    // At most MAX_STEPS here, so the conversion is exact.
    let steps = (if is_whole { whole } else { ratio.ceil() } as usize).max(1);
    let last_dt_s = if is_whole {
        dt_s
    } else if steps == 1 {
        duration_s
    } else {
        (duration_s - (steps - 1) as f64 * dt_s).min(dt_s)
    };
    Ok(StepPlan {
        steps,
        dt_s: dt_s.min(duration_s),
        last_dt_s,
        duration_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(plan: &StepPlan) -> f64 {
        (0..plan.steps).map(|k| plan.dt_of(k)).sum()
    }

    #[test]
    fn whole_numbers_of_steps_despite_round_off() {
        // 100 / 0.1 = 1000.0000000000001 in floating point: still 1000 steps, none extra.
        let plan = time_steps(100.0, 0.1).expect("plan");
        assert_eq!(plan.steps, 1000);
        assert!(!plan.last_step_shortened());
        assert_eq!(plan.end_s(999), 100.0);
        let plan = time_steps(0.3, 0.1).expect("plan");
        assert_eq!(plan.steps, 3);
        assert!((plan.last_dt_s - 0.1).abs() < 1e-12);
        assert_eq!(plan.end_s(2), 0.3);
    }

    #[test]
    fn a_partial_last_step_ends_exactly_at_the_duration() {
        // 1 s at 0.3 s: 0.3, 0.3, 0.3 and 0.1 (rounding would have run 0.9 s or 1.2 s).
        let plan = time_steps(1.0, 0.3).expect("plan");
        assert_eq!(plan.steps, 4);
        assert!(plan.last_step_shortened());
        assert!((plan.last_dt_s - 0.1).abs() < 1e-12);
        assert!((total(&plan) - 1.0).abs() < 1e-12);
        assert_eq!(plan.end_s(3), 1.0);
        assert!((plan.start_s(3) - 0.9).abs() < 1e-12);
        // 2.5 s at 1 s: 1, 1, 0.5 (rounding to even would have stopped at 2 s).
        let plan = time_steps(2.5, 1.0).expect("plan");
        assert_eq!((plan.steps, plan.last_dt_s), (3, 0.5));
    }

    #[test]
    fn a_step_longer_than_the_duration_is_one_short_step() {
        let plan = time_steps(0.05, 0.1).expect("plan");
        assert_eq!(plan.steps, 1);
        assert_eq!(plan.last_dt_s, 0.05);
        assert_eq!(plan.dt_of(0), 0.05);
        assert_eq!(plan.end_s(0), 0.05);
    }

    #[test]
    fn absurd_step_counts_are_refused_with_the_count() {
        let err = time_steps(1e6, 1e-6).unwrap_err();
        assert!(matches!(err, StepError::TooMany { .. }));
        let text = err.to_string();
        assert!(
            text.contains("1.000e12 steps") && text.contains("100000000"),
            "{text}"
        );
        // Exactly the limit is allowed.
        assert_eq!(time_steps(1e8, 1.0).expect("limit").steps, 100_000_000);
        assert!(time_steps(1e8 + 1.0, 1.0).is_err());
        // Underflow to an infinite ratio is refused too, not wrapped.
        assert!(time_steps(1e300, 1e-300).is_err());
    }

    #[test]
    fn non_positive_or_non_finite_inputs_are_refused() {
        for (d, dt) in [
            (0.0, 0.1),
            (-1.0, 0.1),
            (f64::NAN, 0.1),
            (1.0, 0.0),
            (1.0, f64::INFINITY),
            (f64::INFINITY, 1.0),
        ] {
            let err = time_steps(d, dt).unwrap_err();
            assert!(
                matches!(err, StepError::NotPositive { .. }),
                "{d} {dt}: {err}"
            );
        }
    }
}
