//! The staggered coupling scheme (paper §III and Table 3; preCICE's "serial implicit" coupling):
//! the body and the lifting surfaces exchange their interface data once per aeroelastic step.
//!
//! Within a step each region marches its own equations through the step's Runge-Kutta stages
//! with the other side's interface data of the previous sub-iteration at the same stage: the
//! surfaces' modal accelerations q̈ (their root loads on the body) and the body's modal
//! accelerations η̈ (the pivots' elastic motion driving the surfaces). No stage solves the
//! body-surface fixed point; the step is sub-iterated instead, each sub-iteration's interface
//! accelerated as `[coupling] acceleration` says (Aitken's Δ² by default), until the interface
//! displacements at the step's end (the body's elastic translation at each pivot, each
//! surface's deflection at its vertices) change by less than `residual_tolerance_m`. The
//! paper's tolerance is R_tol = 1e-5 m. One sub-iteration is the explicit (loosely coupled)
//! staggered scheme; as the tolerance shrinks the step converges to the fixed point the
//! implicit scheme solves in every stage, so the two agree in the limit.
//!
//! The scheme's first guess at each step is the last converged interface, held over the step.

use hsv_core::acceleration::Acceleration;

use crate::dynamics::VehicleState;

/// Runge-Kutta stages per step at which the interface is exchanged (the fourth-order methods
/// of [`crate::dynamics::integrate`] evaluate the derivative four times).
pub const STAGES: usize = 4;

/// The staggered scheme's settings (`[coupling]` of the config).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaggeredSettings {
    /// Interface displacement change below which a step has converged, m.
    pub residual_tolerance_m: f64,
    pub max_sub_iterations: usize,
}

/// The interface of one step at every stage, for the sub-iterations: the guess the regions
/// read, what they produced, and the acceleration of the sub-iterations (the config's, as the
/// implicit scheme's). Buffers sized once (the loop allocates nothing).
#[derive(Debug)]
pub struct StaggeredInterface {
    pub settings: StaggeredSettings,
    n: usize,
    guess: Vec<f64>,
    produced: Vec<f64>,
    acceleration: Box<dyn Acceleration>,
    /// The step's end state of the last two sub-iterations (the residual compares them).
    pub end: [VehicleState; 2],
}

impl StaggeredInterface {
    /// Buffers for an interface of `n` entries ([`super::partitioned::PartitionedVehicle::interface_len`])
    /// and states shaped like `state`.
    pub fn new(
        settings: StaggeredSettings,
        n: usize,
        state: &VehicleState,
        acceleration: Box<dyn Acceleration>,
    ) -> Self {
        Self {
            settings,
            n,
            guess: vec![0.0; STAGES * n],
            produced: vec![0.0; STAGES * n],
            acceleration,
            end: [state.clone(), state.clone()],
        }
    }

    /// Starts a step from the converged interface `last` at every stage.
    pub fn begin(&mut self, last: &[f64]) {
        for stage in self.guess.chunks_mut(self.n.max(1)) {
            stage.copy_from_slice(&last[..stage.len()]);
        }
        self.acceleration.reset();
    }

    /// The guess and the produced buffer of `stage`, or None beyond the last stage.
    pub fn stage(&mut self, stage: usize) -> Option<(&[f64], &mut [f64])> {
        (stage < STAGES).then(|| {
            let range = stage * self.n..(stage + 1) * self.n;
            (&self.guess[range.clone()], &mut self.produced[range])
        })
    }

    /// The next sub-iteration's guess: the produced interface, accelerated.
    pub fn relax(&mut self) {
        self.acceleration.update(&mut self.guess, &self.produced);
    }

    /// The interface the regions produced at the step's last stage (the next step's start).
    pub fn last_produced(&self) -> &[f64] {
        &self.produced[(STAGES - 1) * self.n..]
    }
}
