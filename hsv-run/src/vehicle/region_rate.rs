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
//! the loads are held. The publications go through the data manager ([`RegionExchange`]: one
//! predicted topic per region, [`hsv_core::data`]), whose checkpoint a restart file carries.
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
use hsv_core::data::{
    DataCheckpoint, DataError, DataManager, DataManagerBuilder, Interpolate, Publisher,
    ShapeMismatch, Subscriber,
};
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
/// the pivot in the surface's frame as the total and no separate aero part): the value of the
/// region's loads topic; the data manager stamps it with its time.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PublishedLoads {
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

impl Interpolate for PublishedLoads {
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .lerp_into(&other.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .lerp_into(&other.moment_nm, w, &mut out.moment_nm)?;
        self.aero_force_n
            .lerp_into(&other.aero_force_n, w, &mut out.aero_force_n)?;
        self.aero_moment_nm
            .lerp_into(&other.aero_moment_nm, w, &mut out.aero_moment_nm)?;
        self.generalized
            .lerp_into(&other.generalized, w, &mut out.generalized)
    }

    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .extrapolate_into(&newer.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .extrapolate_into(&newer.moment_nm, w, &mut out.moment_nm)?;
        self.aero_force_n
            .extrapolate_into(&newer.aero_force_n, w, &mut out.aero_force_n)?;
        self.aero_moment_nm
            .extrapolate_into(&newer.aero_moment_nm, w, &mut out.aero_moment_nm)?;
        self.generalized
            .extrapolate_into(&newer.generalized, w, &mut out.generalized)
    }

    fn copy_into(&self, out: &mut Self) {
        out.force_n = self.force_n;
        out.moment_nm = self.moment_nm;
        out.aero_force_n = self.aero_force_n;
        out.aero_moment_nm = self.aero_moment_nm;
        self.generalized.copy_into(&mut out.generalized);
    }
}

/// The body's skin friction at one evaluation, about the centre of mass, body axes, N and N m:
/// the value of its topic.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PublishedFriction {
    pub force_n: Vector3<f64>,
    pub moment_nm: Vector3<f64>,
}

impl Interpolate for PublishedFriction {
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .lerp_into(&other.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .lerp_into(&other.moment_nm, w, &mut out.moment_nm)
    }

    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .extrapolate_into(&newer.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .extrapolate_into(&newer.moment_nm, w, &mut out.moment_nm)
    }
}

/// The reader of every topic: the coupled derivative, which assembles the vehicle's loads.
const READER: &str = "coupling";

/// A publisher and its reader.
type Channel<T> = (Publisher<T>, Subscriber<T>);

/// The regions' publications at their own rates, exchanged through the data manager (paper
/// §III): one predicted topic per region (`main_body/loads`, `<surface>/loads`) and the body's
/// skin friction (`main_body/skin_friction`), each keeping its last two converged values and
/// read at any stage time by the module's predictor; and each lifting surface's wall heat flux
/// (`<surface>/wall_heat_flux`, W/m² per panel), published by the aerothermal step every
/// heat-flux interval (paper Table 3: 10 ms) and held for the conduction steps between (1 ms).
/// Handles are indices: no look-up and, once each topic has its values, no allocation in the
/// time loop.
pub struct RegionExchange {
    data: DataManager,
    /// The exchange with nothing published: what forgetting restores.
    empty: DataCheckpoint,
    body: Channel<PublishedLoads>,
    friction: Channel<PublishedFriction>,
    surfaces: Vec<Channel<PublishedLoads>>,
    heat_fluxes: Vec<Channel<Vec<f64>>>,
    /// The value a read fills before it is copied out (no allocation after the first).
    scratch: PublishedLoads,
}

impl std::fmt::Debug for RegionExchange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RegionExchange")
            .field("data", &self.data)
            .finish_non_exhaustive()
    }
}

/// The period a topic declares for a rate, s: its interval, or (every stage: never published)
/// the shortest one that passes the data manager's check.
fn declared_period_s(rate: RegionLoadRate) -> f64 {
    match rate {
        RegionLoadRate::Interval(interval_s) => interval_s,
        RegionLoadRate::EveryStage => f64::MIN_POSITIVE,
    }
}

impl RegionExchange {
    /// The topics of the body (at `body` rate, its skin friction at `friction`'s among them)
    /// and of each surface named in `surfaces` (at `surface` rate, its wall heat flux every
    /// `heat_flux_period_s`), nothing published.
    pub fn new(
        surface_names: &[String],
        body: RegionLoadRate,
        friction: RegionLoadRate,
        surface: RegionLoadRate,
        heat_flux_period_s: f64,
    ) -> Result<Self, DataError> {
        let mut builder = DataManagerBuilder::new();
        let body_period_s = declared_period_s(body);
        // The friction is published only at the body's publications where it is due.
        let friction_period_s = match friction {
            RegionLoadRate::Interval(interval_s) => interval_s.max(body_period_s),
            RegionLoadRate::EveryStage => body_period_s,
        };
        let body = (
            builder.publish_predicted("main_body", "main_body/loads", body_period_s)?,
            builder.subscribe(READER, "main_body/loads")?,
        );
        let friction = (
            builder.publish_predicted("main_body", "main_body/skin_friction", friction_period_s)?,
            builder.subscribe(READER, "main_body/skin_friction")?,
        );
        let surfaces = surface_names
            .iter()
            .map(|name| {
                let topic = format!("{name}/loads");
                Ok((
                    builder.publish_predicted(name, &topic, declared_period_s(surface))?,
                    builder.subscribe(READER, &topic)?,
                ))
            })
            .collect::<Result<Vec<_>, DataError>>()?;
        let heat_fluxes = surface_names
            .iter()
            .map(|name| {
                let topic = format!("{name}/wall_heat_flux");
                Ok((
                    builder.publish_with_rate(name, &topic, heat_flux_period_s)?,
                    builder.subscribe(READER, &topic)?,
                ))
            })
            .collect::<Result<Vec<_>, DataError>>()?;
        let data = builder.build()?;
        Ok(Self {
            empty: data.checkpoint(),
            data,
            body,
            friction,
            surfaces,
            heat_fluxes,
            scratch: PublishedLoads::default(),
        })
    }

    /// The time of the first surface's latest wall heat flux, s (the heated surfaces' fluxes
    /// are refreshed together).
    pub fn heat_flux_time_s(&self) -> Option<f64> {
        let (_, reader) = self.heat_fluxes.first()?;
        self.data.read_converged(*reader).ok().map(|s| s.time_s)
    }

    /// Publishes surface `index`'s wall heat flux (W/m² per panel) at `time_s`, in place.
    pub fn publish_heat_flux(
        &mut self,
        index: usize,
        time_s: f64,
        flux_w_m2: &[f64],
    ) -> Result<(), DataError> {
        let Some(&(publisher, _)) = self.heat_fluxes.get(index) else {
            return Ok(());
        };
        self.data
            .publish_with(publisher, time_s, |v: &mut Vec<f64>| {
                v.clear();
                v.extend_from_slice(flux_w_m2);
            })?;
        self.data.mark_converged(publisher)?;
        Ok(())
    }

    /// Surface `index`'s latest published wall heat flux, W/m² per panel, read in place (held
    /// until the next refresh, which comes at a step's start before that step's conduction);
    /// None before the first.
    pub fn heat_flux(&self, index: usize) -> Result<Option<&[f64]>, DataError> {
        let Some(&(_, reader)) = self.heat_fluxes.get(index) else {
            return Ok(None);
        };
        match self.data.read_converged(reader) {
            Ok(latest) => Ok(Some(latest.value.as_slice())),
            Err(DataError::NothingConverged { .. }) => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Forgets every publication (a new run).
    pub fn clear(&mut self) -> Result<(), DataError> {
        self.data.restore(&self.empty)
    }

    /// The exchange's state, for a restart file.
    pub fn checkpoint(&self) -> DataCheckpoint {
        self.data.checkpoint()
    }

    /// Restores a state of [`Self::checkpoint`] (of an exchange with the same topics).
    pub fn restore(&mut self, checkpoint: &DataCheckpoint) -> Result<(), DataError> {
        self.data.restore(checkpoint)
    }

    /// The time of the body's latest publication, s.
    pub fn body_time_s(&self) -> Option<f64> {
        self.data.read_converged(self.body.1).ok().map(|s| s.time_s)
    }

    /// The time of the first surface's latest publication, s (the surfaces publish together).
    pub fn surfaces_time_s(&self) -> Option<f64> {
        let (_, reader) = self.surfaces.first()?;
        self.data.read_converged(*reader).ok().map(|s| s.time_s)
    }

    /// Publishes the body's loads at `time_s`.
    pub fn publish_body(
        &mut self,
        time_s: f64,
        total: &Loads,
        aero: &Loads,
        generalized: &[f64],
    ) -> Result<(), DataError> {
        publish_loads(
            &mut self.data,
            self.body.0,
            time_s,
            total,
            aero,
            generalized,
        )
    }

    /// Publishes surface `index`'s applied loads about its pivot and aero generalized forces at
    /// `time_s`.
    pub fn publish_surface(
        &mut self,
        index: usize,
        time_s: f64,
        applied: &Loads,
        generalized: &[f64],
    ) -> Result<(), DataError> {
        let Some(&(publisher, _)) = self.surfaces.get(index) else {
            return Ok(());
        };
        let none = Loads::default();
        publish_loads(
            &mut self.data,
            publisher,
            time_s,
            applied,
            &none,
            generalized,
        )
    }

    /// The body's loads at `time_s` into the outputs (module docs' predictor; held with one
    /// publication); false (outputs untouched) with none.
    pub fn read_body(
        &mut self,
        time_s: f64,
        total: &mut Loads,
        aero: &mut Loads,
        generalized: &mut [f64],
    ) -> Result<bool, DataError> {
        let reader = self.body.1;
        self.read_loads(reader, time_s, total, Some(aero), generalized)
    }

    /// Surface `index`'s applied loads and aero generalized forces at `time_s` (as
    /// [`Self::read_body`]).
    pub fn read_surface(
        &mut self,
        index: usize,
        time_s: f64,
        applied: &mut Loads,
        generalized: &mut [f64],
    ) -> Result<bool, DataError> {
        let Some(&(_, reader)) = self.surfaces.get(index) else {
            return Ok(false);
        };
        self.read_loads(reader, time_s, applied, None, generalized)
    }

    fn read_loads(
        &mut self,
        reader: Subscriber<PublishedLoads>,
        time_s: f64,
        total: &mut Loads,
        aero: Option<&mut Loads>,
        generalized: &mut [f64],
    ) -> Result<bool, DataError> {
        match self.data.read_at(reader, time_s, &mut self.scratch) {
            Err(DataError::NothingConverged { .. }) => return Ok(false),
            Err(e) => return Err(e),
            Ok(_) => {}
        }
        let l = &self.scratch;
        if l.generalized.len() != generalized.len() {
            return Ok(false);
        }
        total.force_n = l.force_n;
        total.moment_nm = l.moment_nm;
        if let Some(aero) = aero {
            aero.force_n = l.aero_force_n;
            aero.moment_nm = l.aero_moment_nm;
        }
        generalized.copy_from_slice(l.generalized.as_slice());
        Ok(true)
    }

    /// Publishes the body's skin friction evaluated at `time_s`.
    pub fn publish_friction(&mut self, time_s: f64, loads: &Loads) -> Result<(), DataError> {
        self.data.publish(
            self.friction.0,
            time_s,
            PublishedFriction {
                force_n: loads.force_n,
                moment_nm: loads.moment_nm,
            },
        )?;
        self.data.mark_converged(self.friction.0)?;
        Ok(())
    }

    /// The skin friction at `time_s`, extrapolated linearly from its last two evaluations (held
    /// with one), when `rate` says it is not due; None when it is.
    pub fn friction_at(
        &self,
        time_s: f64,
        rate: &RegionLoadRate,
    ) -> Result<Option<Loads>, DataError> {
        let reader = self.friction.1;
        let last_s = match self.data.read_converged(reader) {
            Ok(latest) => latest.time_s,
            Err(DataError::NothingConverged { .. }) => return Ok(None),
            Err(e) => return Err(e),
        };
        if rate.is_due(time_s, Some(last_s)) {
            return Ok(None);
        }
        let mut friction = PublishedFriction::default();
        self.data.read_at(reader, time_s, &mut friction)?;
        Ok(Some(Loads {
            force_n: friction.force_n,
            moment_nm: friction.moment_nm,
        }))
    }
}

/// Publishes and commits one region's loads at `time_s`, in place (the head's buffers reused).
fn publish_loads(
    data: &mut DataManager,
    publisher: Publisher<PublishedLoads>,
    time_s: f64,
    total: &Loads,
    aero: &Loads,
    generalized: &[f64],
) -> Result<(), DataError> {
    data.publish_with(publisher, time_s, |slot| {
        slot.force_n = total.force_n;
        slot.moment_nm = total.moment_nm;
        slot.aero_force_n = aero.force_n;
        slot.aero_moment_nm = aero.moment_nm;
        if slot.generalized.len() == generalized.len() {
            slot.generalized.copy_from_slice(generalized);
        } else {
            slot.generalized = DVector::from_column_slice(generalized);
        }
    })?;
    data.mark_converged(publisher)?;
    Ok(())
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

    fn exchange() -> RegionExchange {
        RegionExchange::new(
            &["left_surface".to_owned()],
            RegionLoadRate::Interval(1e-3),
            RegionLoadRate::Interval(0.01),
            RegionLoadRate::Interval(1e-3),
            0.01,
        )
        .expect("exchange")
    }

    /// A load linear in time is reproduced exactly at any stage time: the predictor is exact
    /// for polynomials of degree one (second-order local error).
    #[test]
    fn a_load_linear_in_time_is_extrapolated_exactly() {
        let mut h = exchange();
        let f = |t: f64| 3.0 - 7.0 * t;
        for t in [0.0, 1e-3] {
            h.publish_body(t, &loads(f(t)), &loads(0.5 * f(t)), &[f(t); 2])
                .expect("published");
            h.publish_surface(0, t, &loads(-f(t)), &[f(t); 3])
                .expect("published");
        }
        let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [0.0; 2]);
        let mut q3 = [0.0; 3];
        for t in [1e-3, 1.5e-3, 2e-3] {
            assert!(h.read_body(t, &mut total, &mut aero, &mut q).expect("read"));
            assert!((total.force_n.x - f(t)).abs() < 1e-12);
            assert!((total.force_n.y - 2.0 * f(t)).abs() < 1e-12);
            assert!((aero.moment_nm.z + 0.5 * f(t)).abs() < 1e-12);
            assert!((q[1] - f(t)).abs() < 1e-12);
            assert!(h.read_surface(0, t, &mut total, &mut q3).expect("read"));
            assert!((total.force_n.x + f(t)).abs() < 1e-12);
            assert!((q3[2] - f(t)).abs() < 1e-12);
        }
        assert_eq!(h.body_time_s(), Some(1e-3));
        assert_eq!(h.surfaces_time_s(), Some(1e-3));
    }

    /// The friction predictor is exact for a friction linear in time, and steps aside (None)
    /// when the friction is due again.
    #[test]
    fn friction_linear_in_time_is_extrapolated_until_it_is_due() {
        let mut h = exchange();
        let rate = RegionLoadRate::Interval(0.01);
        let f = |t: f64| 2.0 + 5.0 * t;
        assert!(
            h.friction_at(0.0, &rate).expect("read").is_none(),
            "nothing published"
        );
        h.publish_friction(0.0, &loads(f(0.0))).expect("published");
        assert_eq!(
            h.friction_at(0.004, &rate).expect("read"),
            Some(loads(f(0.0))),
            "one: held"
        );
        h.publish_friction(0.01, &loads(f(0.01)))
            .expect("published");
        for t in [0.011, 0.015, 0.019] {
            let read = h.friction_at(t, &rate).expect("read").expect("not due");
            assert!((read.force_n.x - f(t)).abs() < 1e-12);
            assert!((read.moment_nm.z + f(t)).abs() < 1e-12);
        }
        assert!(
            h.friction_at(0.02, &rate).expect("read").is_none(),
            "due at 10 ms"
        );
    }

    /// The wall heat flux is published every 10 ms and read as published (the latest), and a
    /// refresh sooner than its interval is refused naming the topic.
    #[test]
    fn the_heat_flux_is_held_between_its_refreshes() {
        let mut h = exchange();
        assert_eq!(h.heat_flux(0).expect("read"), None, "none yet");
        assert_eq!(h.heat_flux_time_s(), None);
        h.publish_heat_flux(0, 0.0, &[1.0, 2.0]).expect("published");
        h.publish_heat_flux(0, 0.01, &[3.0, 4.0])
            .expect("published");
        assert_eq!(h.heat_flux(0).expect("read"), Some(&[3.0, 4.0][..]));
        assert_eq!(h.heat_flux_time_s(), Some(0.01));
        let err = h
            .publish_heat_flux(0, 0.015, &[5.0, 6.0])
            .expect_err("sooner than 10 ms");
        assert!(
            err.to_string().contains("left_surface/wall_heat_flux"),
            "{err}"
        );
    }

    /// One publication is held, none reads nothing, a publication sooner than the declared
    /// interval is refused, and clearing forgets everything (a checkpoint round trip restores
    /// it).
    #[test]
    fn one_publication_is_held_none_is_refused_and_clearing_forgets() {
        let mut h = exchange();
        let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [0.0; 1]);
        assert!(
            !h.read_body(0.0, &mut total, &mut aero, &mut q)
                .expect("read")
        );
        h.publish_body(0.0, &loads(4.0), &loads(1.0), &[4.0])
            .expect("published");
        assert!(
            h.read_body(5e-4, &mut total, &mut aero, &mut q)
                .expect("read")
        );
        assert_eq!(total.force_n.x, 4.0);
        assert_eq!(q[0], 4.0);
        let err = h
            .publish_body(5e-4, &loads(4.0), &loads(1.0), &[4.0])
            .expect_err("sooner than 1 ms");
        assert!(err.to_string().contains("main_body/loads"), "{err}");
        let saved = h.checkpoint();
        h.clear().expect("cleared");
        assert!(
            !h.read_body(0.0, &mut total, &mut aero, &mut q)
                .expect("read")
        );
        h.restore(&saved).expect("restored");
        assert!(
            h.read_body(5e-4, &mut total, &mut aero, &mut q)
                .expect("read")
        );
        assert_eq!(h.checkpoint(), saved);
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
