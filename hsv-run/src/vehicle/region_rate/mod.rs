//! Regions evaluated at the aeroelastic rate rather than at every Runge-Kutta stage: a region's
//! loads are published at an accepted state every interval (default 1 ms: every step at the
//! paper's 1 ms) and read by every stage in between by linear extrapolation in time from the
//! last two publications.
//!
//! This is the paper's partitioned exchange of region data at the aeroelastic rate (Klock &
//! Cesnik §III.A, Table 3: 1 ms; §III.C: "the OML pressure distribution is recalculated at
//! discrete aeroelastic time steps"). The extrapolation is the second-order Adams-Bashforth-type
//! predictor of explicit partitioned schemes (Farhat & Lesoinne 2000, Comput. Methods Appl.
//! Mech. Engrg. 182: the "predictor" of the conventional serial staggered procedure), so the
//! scheme stays second order in the region's loads; over the first step, with one publication,
//! the loads are held. The publications go through the data manager ([`RegionExchange`] in
//! [`exchange`]: one predicted topic per region, [`hsv_core::data`]), whose checkpoint a
//! restart file carries; this file owns the rate rule ([`RegionLoadRate`]).
//!
//! The topic is the only way a region's loads reach the coupling. A region evaluated at a
//! derivative (at every stage, or outside a step: trim, linearization, in-vacuo modes) publishes
//! its loads as the topic's iterate, which the coupling reads at once and the predictor never
//! sees; at an accepted state where it falls due it publishes them converged, which the stages
//! until its next evaluation read extrapolated.
//!
//! - **The main body** (`[simulation] body_loads_dt_s`, default 1 ms): aero and skin friction
//!   on the deformed OML, the engine, and the monolithic model's surfaces. Its evaluation is
//!   expensive and its dynamics slow (rigid body, beam modes up to 27 Hz): three of the four body
//!   evaluations of a Runge-Kutta step are spared.
//! - **The lifting surfaces** (`[simulation] surface_loads_dt_s`, default 0: at every stage, the
//!   reference): each surface's applied aero and friction loads about its pivot in its own frame
//!   and its aero generalized forces. Their Ritz vectors reach hundreds of Hz, so a held or
//!   extrapolated pressure lags their fastest motion (ω Δt = 1.9 for a 300 Hz vector at 1 ms);
//!   the rigid flight, which the elevon and the surfaces' mean loads drive, keeps its accuracy
//!   (test in `hsv-run/tests/simulate.rs`). The elevon's rotation and the thermal generalized
//!   forces are taken at each stage.
//!
//! The body's skin friction, which comes from the aerothermal model (Eckert's reference
//! temperature), is evaluated again only every `body_friction_dt_s` among these publications
//! (default the paper's aerothermal rate, Table 3: 10 ms) and extrapolated linearly from its last
//! two evaluations in between, the same predictor: it is a small,
//! slowly varying part of the body's load (its edge states follow α and the dynamic pressure, on
//! the flight's time scale), and on the 1304-panel body it cost as much as the engine.

pub mod exchange;
pub mod published;

use serde::{Deserialize, Serialize};

pub use exchange::{LoadsPublication, Publication, RegionExchange};
pub use published::{PublishedFriction, PublishedLoads, PublishedTemperatures};

/// The body's skin friction rate by default, s: the paper's aerothermal step (Table 3).
pub const DEFAULT_BODY_FRICTION_DT_S: f64 = 0.01;

/// How often a region (the main body, the lifting surfaces) is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum RegionLoadRate {
    /// At every state derivative (every Runge-Kutta stage): the reference.
    EveryStage,
    /// At the accepted state of the first step at least this long (s) after the last
    /// evaluation, and at most once per step; extrapolated in between (module docs).
    Interval(f64),
}

impl Default for RegionLoadRate {
    /// The paper's aeroelastic rate (Table 3: 1 ms).
    fn default() -> Self {
        Self::Interval(1e-3)
    }
}

impl RegionLoadRate {
    /// The rate of a `[simulation]` interval (`body_loads_dt_s`, `surface_loads_dt_s`): 0 for
    /// every stage, else the interval, s.
    pub fn from_interval_s(interval_s: f64) -> Option<Self> {
        if interval_s == 0.0 {
            Some(Self::EveryStage)
        } else if interval_s.is_finite() && interval_s > 0.0 {
            Some(Self::Interval(interval_s))
        } else {
            None
        }
    }

    /// Whether a step starting at `time_s` evaluates the region, the last evaluation having
    /// been at `last_s` (none: always).
    pub fn is_due(&self, time_s: f64, last_s: Option<f64>) -> bool {
        match (self, last_s) {
            (Self::EveryStage, _) | (_, None) => true,
            // The relative slack absorbs the rounding of step start times k·Δt.
            (Self::Interval(interval), Some(last)) => time_s - last >= interval * (1.0 - 1e-9),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::RegionLoadRate;

    #[test]
    fn an_interval_of_two_steps_evaluates_every_other_step() {
        let rate = RegionLoadRate::Interval(1e-3);
        let dt = 5e-4;
        let mut last = None;
        let due: Vec<bool> = (0..6)
            .map(|k| {
                let t = k as f64 * dt;
                let d = rate.is_due(t, last);
                if d {
                    last = Some(t);
                }
                d
            })
            .collect();
        assert_eq!(due, [true, false, true, false, true, false]);
        assert_eq!(
            RegionLoadRate::from_interval_s(0.0),
            Some(RegionLoadRate::EveryStage)
        );
        assert_eq!(RegionLoadRate::from_interval_s(-1.0), None);
        assert_eq!(RegionLoadRate::from_interval_s(f64::NAN), None);
    }
}
