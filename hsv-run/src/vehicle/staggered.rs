//! The staggered coupling scheme (paper §III and Table 3; preCICE's "serial implicit" coupling):
//! the body and the lifting surfaces exchange their interface data once per aeroelastic step.
//!
//! Within a step each region marches its own equations through the step's Runge-Kutta stages
//! with the other side's interface data of the previous sub-iteration at the same stage: the
//! surfaces' modal accelerations q̈ (their root loads on the body) and the body's modal
//! accelerations η̈ (the pivots' elastic motion driving the surfaces). No stage solves the
//! body-surface fixed point; the step is sub-iterated instead, each sub-iteration's interface
//! relaxed by Aitken's Δ² (Küttler & Wall 2008, Comput. Mech. 43, 61-72), until the interface
//! displacements at the step's end (the body's elastic translation at each pivot, each
//! surface's deflection at its vertices) change by less than `residual_tolerance_m`. The
//! paper's tolerance is R_tol = 1e-5 m. One sub-iteration is the explicit (loosely coupled)
//! staggered scheme; as the tolerance shrinks the step converges to the fixed point the
//! implicit scheme solves in every stage, so the two agree in the limit.
//!
//! The scheme's first guess at each step is the last converged interface, held over the step.

use crate::dynamics::VehicleState;

/// Runge-Kutta stages per step at which the interface is exchanged (the fourth-order methods
/// of [`crate::dynamics::integrate`] evaluate the derivative four times).
pub const STAGES: usize = 4;

/// Lower and upper bound of Aitken's relaxation factor (our choice: as the implicit scheme).
const RELAXATION_BOUNDS: (f64, f64) = (0.05, 1.5);

/// The staggered scheme's settings (`[coupling]` of the config).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaggeredSettings {
    /// Interface displacement change below which a step has converged, m.
    pub residual_tolerance_m: f64,
    pub max_sub_iterations: usize,
}

/// The interface of one step at every stage, for the sub-iterations: the guess the regions
/// read, what they produced, and Aitken's state. Buffers sized once (the loop allocates
/// nothing).
#[derive(Debug, Clone)]
pub struct StaggeredInterface {
    pub settings: StaggeredSettings,
    n: usize,
    guess: Vec<f64>,
    produced: Vec<f64>,
    previous_step: Vec<f64>,
    omega: f64,
    /// The step's end state of the last two sub-iterations (the residual compares them).
    pub end: [VehicleState; 2],
}

impl StaggeredInterface {
    /// Buffers for an interface of `n` entries ([`super::partitioned::PartitionedVehicle::interface_len`])
    /// and states shaped like `state`.
    pub fn new(settings: StaggeredSettings, n: usize, state: &VehicleState) -> Self {
        Self {
            settings,
            n,
            guess: vec![0.0; STAGES * n],
            produced: vec![0.0; STAGES * n],
            previous_step: vec![0.0; STAGES * n],
            omega: 1.0,
            end: [state.clone(), state.clone()],
        }
    }

    /// Starts a step from the converged interface `last` at every stage.
    pub fn begin(&mut self, last: &[f64]) {
        for stage in self.guess.chunks_mut(self.n.max(1)) {
            stage.copy_from_slice(&last[..stage.len()]);
        }
        self.previous_step.fill(0.0);
        self.omega = 1.0;
    }

    /// The guess and the produced buffer of `stage`, or None beyond the last stage.
    pub fn stage(&mut self, stage: usize) -> Option<(&[f64], &mut [f64])> {
        (stage < STAGES).then(|| {
            let range = stage * self.n..(stage + 1) * self.n;
            (&self.guess[range.clone()], &mut self.produced[range])
        })
    }

    /// The next sub-iteration's guess: the produced interface relaxed by Aitken's factor
    /// (`sub_iteration` counts from 1).
    pub fn relax(&mut self, sub_iteration: usize) {
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..self.guess.len() {
            let r = self.produced[k] - self.guess[k];
            let dr = r - self.previous_step[k];
            num += self.previous_step[k] * dr;
            den += dr * dr;
            self.previous_step[k] = r;
        }
        if sub_iteration > 1 && den > 0.0 {
            self.omega = (-self.omega * num / den).clamp(RELAXATION_BOUNDS.0, RELAXATION_BOUNDS.1);
        }
        for k in 0..self.guess.len() {
            self.guess[k] += self.omega * self.previous_step[k];
        }
    }

    /// The interface the regions produced at the step's last stage (the next step's start).
    pub fn last_produced(&self) -> &[f64] {
        &self.produced[(STAGES - 1) * self.n..]
    }
}
