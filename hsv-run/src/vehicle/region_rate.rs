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
//! the loads are held.
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

use hsv_core::aero::Loads;
use nalgebra::{DVector, Vector3};
use serde::{Deserialize, Serialize};

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

/// One publication of a region (the body's, or a lifting surface's with its applied loads about
/// the pivot in the surface's frame as the total and no separate aero part): plain data, part
/// of a restart file.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PublishedLoads {
    pub time_s: f64,
    /// The body: aero, skin friction, engine (and the monolithic model's surfaces) about the
    /// centre of mass, body axes; a surface: its pressure and friction about its pivot in its
    /// own frame. N and N m.
    pub force_n: Vector3<f64>,
    pub moment_nm: Vector3<f64>,
    /// The body's aero (pressure and friction) part alone, N and N m (zero for a surface).
    pub aero_force_n: Vector3<f64>,
    pub aero_moment_nm: Vector3<f64>,
    /// Generalized forces of the region's modes (a surface's: the aero part), N (per unit
    /// modal coordinate).
    pub generalized: DVector<f64>,
}

/// The body's skin friction at its last evaluation: plain data, part of a restart file.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PublishedFriction {
    pub time_s: f64,
    /// About the centre of mass, body axes, N and N m.
    pub force_n: Vector3<f64>,
    pub moment_nm: Vector3<f64>,
}

impl PublishedFriction {
    pub fn new(time_s: f64, loads: &Loads) -> Self {
        Self {
            time_s,
            force_n: loads.force_n,
            moment_nm: loads.moment_nm,
        }
    }

    pub fn loads(&self) -> Loads {
        Loads {
            force_n: self.force_n,
            moment_nm: self.moment_nm,
        }
    }
}

/// The last two publications of a region, and the body's held skin friction.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RegionLoadHistory {
    pub latest: Option<PublishedLoads>,
    pub before: Option<PublishedLoads>,
    /// The last two evaluations of the body's skin friction (absent in restart files written
    /// before the friction had its own rate).
    #[serde(default)]
    pub friction: Option<PublishedFriction>,
    #[serde(default)]
    pub friction_before: Option<PublishedFriction>,
}

impl RegionLoadHistory {
    /// The time of the latest publication, s.
    pub fn latest_time_s(&self) -> Option<f64> {
        self.latest.as_ref().map(|l| l.time_s)
    }

    /// Forgets every publication (a new run).
    pub fn clear(&mut self) {
        self.latest = None;
        self.before = None;
        self.forget_friction();
    }

    /// Forgets the skin friction's evaluations.
    pub fn forget_friction(&mut self) {
        self.friction = None;
        self.friction_before = None;
    }

    /// Publishes the body's skin friction evaluated at `time_s`.
    pub fn publish_friction(&mut self, time_s: f64, loads: &Loads) {
        self.friction_before = self.friction.take();
        self.friction = Some(PublishedFriction::new(time_s, loads));
    }

    /// The skin friction at `time_s`, extrapolated linearly from its last two evaluations (held
    /// with one), when `rate` says it is not due; None when it is.
    pub fn friction_at(&self, time_s: f64, rate: &RegionLoadRate) -> Option<Loads> {
        let f1 = self
            .friction
            .filter(|f| !rate.is_due(time_s, Some(f.time_s)))?;
        let Some(f0) = self.friction_before.filter(|f0| f1.time_s > f0.time_s) else {
            return Some(f1.loads());
        };
        let w = predictor_weight(time_s, f0.time_s, f1.time_s);
        Some(Loads {
            force_n: predict(&f0.force_n, &f1.force_n, w),
            moment_nm: predict(&f0.moment_nm, &f1.moment_nm, w),
        })
    }

    /// Publishes the loads at `time_s`; the latest becomes the one before. Reuses the buffers
    /// of the oldest publication, so after two publications nothing is allocated.
    pub fn publish(&mut self, time_s: f64, total: &Loads, aero: &Loads, generalized: &[f64]) {
        std::mem::swap(&mut self.latest, &mut self.before);
        let slot = self.latest.get_or_insert_with(PublishedLoads::default);
        slot.time_s = time_s;
        slot.force_n = total.force_n;
        slot.moment_nm = total.moment_nm;
        slot.aero_force_n = aero.force_n;
        slot.aero_moment_nm = aero.moment_nm;
        if slot.generalized.len() == generalized.len() {
            slot.generalized.copy_from_slice(generalized);
        } else {
            slot.generalized = DVector::from_column_slice(generalized);
        }
    }

    /// The loads at `time_s` into the outputs: L₁ + (t − t₁)(L₁ − L₀)/(t₁ − t₀) from the last
    /// two publications, or L₁ with one. False (outputs untouched) with none.
    pub fn read(
        &self,
        time_s: f64,
        total: &mut Loads,
        aero: &mut Loads,
        generalized: &mut [f64],
    ) -> bool {
        let Some(l1) = self
            .latest
            .as_ref()
            .filter(|l| l.generalized.len() == generalized.len())
        else {
            return false;
        };
        let w = match &self.before {
            Some(l0) if l1.time_s > l0.time_s && l0.generalized.len() == l1.generalized.len() => {
                predictor_weight(time_s, l0.time_s, l1.time_s)
            }
            _ => 0.0,
        };
        let l0 = self.before.as_ref().filter(|_| w != 0.0).unwrap_or(l1);
        total.force_n = predict(&l0.force_n, &l1.force_n, w);
        total.moment_nm = predict(&l0.moment_nm, &l1.moment_nm, w);
        aero.force_n = predict(&l0.aero_force_n, &l1.aero_force_n, w);
        aero.moment_nm = predict(&l0.aero_moment_nm, &l1.aero_moment_nm, w);
        for ((q, a), b) in generalized
            .iter_mut()
            .zip(l0.generalized.iter())
            .zip(l1.generalized.iter())
        {
            *q = b + (b - a) * w;
        }
        true
    }
}

/// w = (t − t₁)/(t₁ − t₀): how far past the latest of two publications at t₀ < t₁ time `t` is,
/// in units of their spacing.
fn predictor_weight(time_s: f64, t0: f64, t1: f64) -> f64 {
    (time_s - t1) / (t1 - t0)
}

/// L₁ + w (L₁ − L₀): the linear predictor of the module docs from L₀ = `a`, L₁ = `b`.
fn predict(a: &Vector3<f64>, b: &Vector3<f64>, w: f64) -> Vector3<f64> {
    b + (b - a) * w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loads(x: f64) -> Loads {
        Loads {
            force_n: Vector3::new(x, 2.0 * x, 0.0),
            moment_nm: Vector3::new(0.0, 0.0, -x),
        }
    }

    /// A load linear in time is reproduced exactly at any stage time: the predictor is exact
    /// for polynomials of degree one (second-order local error).
    #[test]
    fn a_load_linear_in_time_is_extrapolated_exactly() {
        let mut h = RegionLoadHistory::default();
        let f = |t: f64| 3.0 - 7.0 * t;
        for t in [0.0, 1e-3] {
            h.publish(t, &loads(f(t)), &loads(0.5 * f(t)), &[f(t); 2]);
        }
        let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [0.0; 2]);
        for t in [1e-3, 1.5e-3, 2e-3] {
            assert!(h.read(t, &mut total, &mut aero, &mut q));
            assert!((total.force_n.x - f(t)).abs() < 1e-12);
            assert!((total.force_n.y - 2.0 * f(t)).abs() < 1e-12);
            assert!((aero.moment_nm.z + 0.5 * f(t)).abs() < 1e-12);
            assert!((q[1] - f(t)).abs() < 1e-12);
        }
    }

    /// The friction predictor is exact for a friction linear in time, and steps aside (None)
    /// when the friction is due again.
    #[test]
    fn friction_linear_in_time_is_extrapolated_until_it_is_due() {
        let mut h = RegionLoadHistory::default();
        let rate = RegionLoadRate::Interval(0.01);
        let f = |t: f64| 2.0 + 5.0 * t;
        assert!(h.friction_at(0.0, &rate).is_none(), "nothing published");
        h.publish_friction(0.0, &loads(f(0.0)));
        assert_eq!(
            h.friction_at(0.004, &rate),
            Some(loads(f(0.0))),
            "one: held"
        );
        h.publish_friction(0.01, &loads(f(0.01)));
        for t in [0.011, 0.015, 0.019] {
            let read = h.friction_at(t, &rate).expect("not due");
            assert!((read.force_n.x - f(t)).abs() < 1e-12);
            assert!((read.moment_nm.z + f(t)).abs() < 1e-12);
        }
        assert!(h.friction_at(0.02, &rate).is_none(), "due at 10 ms");
    }

    #[test]
    fn one_publication_is_held_and_none_is_refused() {
        let mut h = RegionLoadHistory::default();
        let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [0.0; 1]);
        assert!(!h.read(0.0, &mut total, &mut aero, &mut q));
        h.publish(0.0, &loads(4.0), &loads(1.0), &[4.0]);
        assert!(h.read(5e-4, &mut total, &mut aero, &mut q));
        assert_eq!(total.force_n.x, 4.0);
        assert_eq!(q[0], 4.0);
        h.clear();
        assert!(!h.read(0.0, &mut total, &mut aero, &mut q));
    }
}

#[cfg(test)]
mod rate_tests {
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
