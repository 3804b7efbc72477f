//! The heated surface over Mach numbers and times in the flow (paper §IV.D, Figs. 14-16).
//!
//! At each Mach number of a grid the surface starts uniformly at 293 K and heats in that flow
//! ([`SurfaceHeating`]: heat flux, conduction); at each requested time the conduction model's
//! node temperatures and through-thickness differences are moved onto the structure's grid
//! ([`StructureTemperatures`]) and set on the structure (heat-degraded modulus, thermal-stress geometric
//! stiffness, thermal moment), then the surface's equilibrium, identified state matrix and
//! eigenvalues give the point's stability. The grid marches are independent and run on all
//! cores.
//!
//! **Flutter and divergence Mach numbers** at a time, each on its own ([`Instability`]): the
//! flutter boundary is where an oscillatory pair's largest real part crosses the round-off
//! threshold ([`super::stability`]), the divergence boundary where a real root's does. For
//! each, the lowest grid interval whose lower end is stable and upper end unstable in that
//! kind brackets the crossing; Brent's method then finds the zero, each evaluation a fresh
//! heating march at that Mach number to that time, and every point it evaluates is kept
//! ([`FlutterMap::searched`]). A range with no stable point, or no unstable one, is reported
//! as such with the largest real part and least damping found, never as a crossing. A flutter
//! crossing names the mode it grows from: the critical pair is followed back by eigenvector
//! correlation over the grid points below it to the roots of the lowest analysed Mach number.
//! A surface buckled in vacuum (its own stiffness no longer positive definite) is analysed with
//! its aero like any other and flagged; where the flow does not hold it, its real root in the
//! right half plane is a divergence (thermal buckling) boundary, not flutter. A melting
//! surface (wall past the solidus) or one past its material data is reported at its Mach
//! number and time and takes no part in the bracketing.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use hsv_core::aero::AeroModel;
use hsv_core::coupling::StructureTemperatures;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry, RoleModel};
use hsv_core::structure::StructureModel;
use nalgebra::{Complex, DVector};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::stability::{FlutterRoot, Instability, brent_root, stability, track};
use super::surface::{DerivativeMethod, SurfaceDynamics, SurfaceOptions};
use super::{FlutterError, check_positive};
use crate::analysis::heating::{HeatingModels, HeatingSteps, SurfaceHeating};
use crate::progress::Progress;

/// The models of a flutter analysis, by registered name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlutterModels {
    pub aero: String,
    pub heat_flux: String,
    pub conduction: String,
    pub structure: String,
}

/// Everything a flutter point needs besides its Mach number and time.
#[derive(Debug, Clone)]
pub struct FlutterSetup {
    /// The lifting-surface region (its mesh and model settings).
    pub region: RegionInfo,
    pub models: FlutterModels,
    pub altitude_m: f64,
    pub alpha_rad: f64,
    /// Heating march: conduction step, flux updates, initial temperature (293 K).
    pub heating: HeatingSteps,
    pub method: DerivativeMethod,
    /// Also identify A with the other derivative method and report how far they differ.
    pub compare_methods: bool,
    pub options: SurfaceOptions,
}

/// What became of one (Mach, time) point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "state", rename_all = "kebab-case")]
pub enum PointStatus {
    Stable,
    Unstable,
    Buckled { message: String },
    Melting { message: String },
    Failed { message: String },
}

impl PointStatus {
    fn from_error(e: &FlutterError) -> Self {
        match e {
            FlutterError::Buckled(m) => PointStatus::Buckled { message: m.clone() },
            FlutterError::Melting(m) => PointStatus::Melting { message: m.clone() },
            other => PointStatus::Failed {
                message: other.to_string(),
            },
        }
    }

    /// Whether the point has eigenvalues (stable or unstable).
    pub fn is_analysed(&self) -> bool {
        matches!(self, PointStatus::Stable | PointStatus::Unstable)
    }
}

/// How far the two derivative methods' state matrices differ at a point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MethodDifference {
    /// ‖A_fd − A_direct‖_F / ‖A_direct‖_F.
    pub relative_matrix_difference: f64,
    /// |λ_fd − λ_direct| / |λ_direct| of the root with the largest real part.
    pub critical_root_difference: f64,
}

/// One analysed point (deserialized without its roots, which shard outputs keep apart).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FlutterPoint {
    pub mach: f64,
    pub time_s: f64,
    pub status: PointStatus,
    /// Largest real part of the eigenvalues, 1/s.
    pub max_real_per_s: Option<f64>,
    /// Largest real part minus the growth threshold, 1/s (positive: unstable).
    pub growth_margin_per_s: Option<f64>,
    /// The same over the oscillatory roots only (positive: flutter); `None` without any.
    #[serde(default)]
    pub flutter_margin_per_s: Option<f64>,
    /// The same over the real roots only (positive: divergence); `None` without any.
    #[serde(default)]
    pub divergence_margin_per_s: Option<f64>,
    pub least_damping_ratio: Option<f64>,
    #[serde(skip)]
    pub roots: Vec<FlutterRoot>,
    /// Structure node temperatures at the point, K.
    pub min_temperature_k: f64,
    pub max_temperature_k: f64,
    pub mean_temperature_k: f64,
    pub method_difference: Option<MethodDifference>,
    /// Wall time of the identification and eigen-analysis, s.
    pub analysis_wall_time_s: f64,
    /// Why the structure alone is buckled (stiffness not positive definite) at the point, if
    /// it is: the point is analysed with its aero all the same ([`super::surface`]).
    #[serde(default)]
    pub buckled_in_vacuum: Option<String>,
}

/// Builds model `name` of role `M` for `region`.
fn build<M: ?Sized + RoleModel>(
    region: &RegionInfo,
    registry: &Registry,
    name: &str,
) -> Result<Box<M>, FlutterError> {
    let settings = region.model_settings(name);
    registry
        .create::<M>(name, &ModelContext::new(region, registry, &settings))
        .map_err(|e| FlutterError::Inconsistent(format!("model `{name}`: {e}")))
}

/// The steady flight condition at `mach`.
pub fn flight_at(setup: &FlutterSetup, mach: f64) -> Result<FlightCondition, FlutterError> {
    check_positive("Mach number", mach)?;
    let freestream = Freestream::standard(mach, setup.altitude_m, setup.region.gas)
        .map_err(|e| FlutterError::model("freestream", e))?;
    Ok(FlightCondition::steady(freestream, setup.alpha_rad, 0.0))
}

/// The temperature state of a march, moved onto the structure.
struct Thermal {
    heating: SurfaceHeating,
    onto_structure: StructureTemperatures,
}

impl Thermal {
    fn new(
        setup: &FlutterSetup,
        registry: &Registry,
        flight: FlightCondition,
        structure: &dyn StructureModel,
    ) -> Result<Self, FlutterError> {
        let heating = SurfaceHeating::new(
            setup.region.clone(),
            registry,
            HeatingModels {
                aero: setup.models.aero.clone(),
                heat_flux: setup.models.heat_flux.clone(),
                conduction: setup.models.conduction.clone(),
            },
            flight,
            setup.heating,
        )?;
        let Some(thermal) = structure.thermal_stiffness() else {
            return Err(FlutterError::Inconsistent(format!(
                "structure model `{}` has no temperature-dependent stiffness",
                setup.models.structure
            )));
        };
        let onto_structure =
            StructureTemperatures::new(heating.conduction(), thermal).map_err(|e| {
                FlutterError::Inconsistent(format!(
                    "conduction model `{}` onto structure model `{}`: {e}",
                    setup.models.conduction, setup.models.structure
                ))
            })?;
        Ok(Self {
            heating,
            onto_structure,
        })
    }

    /// Heats to `time_s` (steps of the run's dt, the last shortened).
    fn advance_to(&mut self, time_s: f64, dt_s: f64) -> Result<(), FlutterError> {
        while time_s - self.heating.time_s() > 1e-9 * dt_s {
            let dt = dt_s.min(time_s - self.heating.time_s());
            self.heating.advance(dt).map_err(|e| {
                let message = e.to_string();
                // A wall past the solidus (heat flux), or a structure past the end of its
                // material's thermal data, which for Ti-6Al-4V ends at 1869.8 K, 7 K below the
                // solidus: both are the melting surface.
                if message.contains("melted") || message.contains("(k, c_p) data") {
                    FlutterError::Melting(message)
                } else {
                    FlutterError::Region(e)
                }
            })?;
        }
        Ok(())
    }

    /// Sets the current field on the structure; returns (min, max, mean) node temperature, K.
    fn apply(
        &mut self,
        structure: &mut dyn StructureModel,
        name: &str,
    ) -> Result<(f64, f64, f64), FlutterError> {
        self.onto_structure
            .update(self.heating.conduction(), self.heating.state())?;
        let Some(thermal) = structure.thermal_stiffness_mut() else {
            return Err(FlutterError::Inconsistent(format!(
                "structure model `{name}` has no temperature-dependent stiffness"
            )));
        };
        self.onto_structure
            .apply(thermal)
            .map_err(|e| FlutterError::model(name, e))?;
        Ok(temperature_range(self.onto_structure.conduction_node_k()))
    }
}

/// (min, max, mean) of `values`.
fn temperature_range(values: &[f64]) -> (f64, f64, f64) {
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    (min, max, mean)
}

/// Equilibrium, identification and eigenvalues of `structure` in `flight`.
pub fn analyse_structure(
    setup: &FlutterSetup,
    registry: &Registry,
    structure: &dyn StructureModel,
    flight: FlightCondition,
) -> Result<(super::Stability, Option<MethodDifference>), FlutterError> {
    let aero: Box<dyn AeroModel> = build(&setup.region, registry, &setup.models.aero)?;
    let mut surface = SurfaceDynamics::new(
        setup.region.mesh.clone(),
        aero,
        structure,
        flight,
        setup.options,
    )?;
    let equilibrium = surface.equilibrium()?;
    let identified = surface.identify(&equilibrium.state, setup.method)?;
    let result = stability(&identified.a)?;
    let difference = if setup.compare_methods {
        let other = match setup.method {
            DerivativeMethod::Direct => DerivativeMethod::ForwardDifference,
            DerivativeMethod::ForwardDifference => DerivativeMethod::Direct,
        };
        let second = surface.identify(&equilibrium.state, other)?;
        let (direct, fd) = match setup.method {
            DerivativeMethod::Direct => (&identified.a, &second.a),
            DerivativeMethod::ForwardDifference => (&second.a, &identified.a),
        };
        let other_stability = stability(&second.a)?;
        let root = |s: &super::Stability| {
            s.roots.get(s.critical).map_or(Complex::new(0.0, 0.0), |r| {
                Complex::new(r.real_per_s, r.imag_rad_s)
            })
        };
        let (l1, l2) = (root(&result), root(&other_stability));
        Some(MethodDifference {
            relative_matrix_difference: (fd - direct).norm() / direct.norm().max(f64::MIN_POSITIVE),
            critical_root_difference: (l1 - l2).norm() / l1.norm().max(f64::MIN_POSITIVE),
        })
    } else {
        None
    };
    Ok((result, difference))
}

/// A point that could not be analysed.
fn failed_point(mach: f64, time_s: f64, e: &FlutterError, range: (f64, f64, f64)) -> FlutterPoint {
    FlutterPoint {
        mach,
        time_s,
        status: PointStatus::from_error(e),
        max_real_per_s: None,
        growth_margin_per_s: None,
        flutter_margin_per_s: None,
        divergence_margin_per_s: None,
        least_damping_ratio: None,
        roots: Vec::new(),
        min_temperature_k: range.0,
        max_temperature_k: range.1,
        mean_temperature_k: range.2,
        method_difference: None,
        analysis_wall_time_s: 0.0,
        buckled_in_vacuum: None,
    }
}

/// The surface heated at `mach` and analysed at each of `times_s` (ascending, s). A point
/// whose heating failed is reported as such, and so are the later ones of the march.
pub fn march(
    setup: &FlutterSetup,
    registry: &Registry,
    mach: f64,
    times_s: &[f64],
) -> Result<Vec<FlutterPoint>, FlutterError> {
    if let Some(w) = times_s.windows(2).find(|w| w[1] < w[0]) {
        return Err(FlutterError::InvalidInput {
            quantity: "time in flow (s)".to_owned(),
            value: w[1],
            allowed: "ascending",
        });
    }
    let flight = flight_at(setup, mach)?;
    let mut structure: Box<dyn StructureModel> =
        build(&setup.region, registry, &setup.models.structure)?;
    let mut thermal = Thermal::new(setup, registry, flight, structure.as_ref())?;
    let mut points = Vec::with_capacity(times_s.len());
    // The error that ended the march and the temperatures it ended at: later points report
    // both (not the initial field).
    let mut stopped: Option<(FlutterError, (f64, f64, f64))> = None;
    for &time_s in times_s {
        if let Some((e, range)) = &stopped {
            points.push(failed_point(mach, time_s, e, *range));
            continue;
        }
        if let Err(e) = thermal.advance_to(time_s, setup.heating.dt_s) {
            let range = temperature_range(thermal.heating.node_temperatures_k());
            points.push(failed_point(mach, time_s, &e, range));
            stopped = Some((e, range));
            continue;
        }
        let range = match thermal.apply(structure.as_mut(), &setup.models.structure) {
            Ok(range) => range,
            Err(e) => {
                let range = temperature_range(thermal.heating.node_temperatures_k());
                points.push(failed_point(mach, time_s, &e, range));
                continue;
            }
        };
        points.push(analyse_point(
            setup,
            registry,
            structure.as_ref(),
            flight,
            time_s,
            range,
        ));
    }
    Ok(points)
}

fn analyse_point(
    setup: &FlutterSetup,
    registry: &Registry,
    structure: &dyn StructureModel,
    flight: FlightCondition,
    time_s: f64,
    range: (f64, f64, f64),
) -> FlutterPoint {
    let mach = flight.freestream.mach;
    let start = Instant::now();
    match analyse_structure(setup, registry, structure, flight) {
        Ok((s, difference)) => FlutterPoint {
            mach,
            time_s,
            status: if s.is_unstable() {
                PointStatus::Unstable
            } else {
                PointStatus::Stable
            },
            max_real_per_s: Some(s.max_real_per_s),
            growth_margin_per_s: Some(s.growth_margin_per_s()),
            flutter_margin_per_s: s.margin_per_s(Instability::Flutter),
            divergence_margin_per_s: s.margin_per_s(Instability::Divergence),
            least_damping_ratio: Some(s.least_damping_ratio()),
            roots: s.roots,
            min_temperature_k: range.0,
            max_temperature_k: range.1,
            mean_temperature_k: range.2,
            method_difference: difference,
            analysis_wall_time_s: start.elapsed().as_secs_f64(),
            buckled_in_vacuum: structure
                .natural_frequencies_hz()
                .err()
                .map(|e| e.to_string()),
        },
        Err(e) => failed_point(mach, time_s, &e, range),
    }
}

/// One flutter point: the surface heated at `mach` for `time_s`, analysed.
pub fn flutter_point(
    setup: &FlutterSetup,
    registry: &Registry,
    mach: f64,
    time_s: f64,
) -> Result<FlutterPoint, FlutterError> {
    march(setup, registry, mach, &[time_s])?
        .pop()
        .ok_or_else(|| FlutterError::Inconsistent("no point analysed".to_owned()))
}

impl FlutterPoint {
    /// The point's margin in `kind` ([`Instability`]), 1/s: positive when unstable in that
    /// kind; without a root of that kind, the margin a root at σ = 0 would have (negative).
    /// `None` when the point has no eigenvalues.
    pub fn margin_per_s(&self, kind: Instability) -> Option<f64> {
        let own = match kind {
            Instability::Flutter => self.flutter_margin_per_s,
            Instability::Divergence => self.divergence_margin_per_s,
        };
        match (own, self.max_real_per_s, self.growth_margin_per_s) {
            (Some(m), _, _) => Some(m),
            (None, Some(max_real), Some(growth)) => Some(-(max_real - growth)),
            _ => None,
        }
    }

    /// Whether the point is analysed and unstable in `kind`.
    pub fn is_unstable_in(&self, kind: Instability) -> bool {
        self.margin_per_s(kind).is_some_and(|m| m > 0.0)
    }

    /// Whether the point is analysed and stable in `kind`.
    pub fn is_stable_in(&self, kind: Instability) -> bool {
        self.margin_per_s(kind).is_some_and(|m| m <= 0.0)
    }

    /// The largest σ of the roots of `kind`, with the root, 1/s.
    fn critical_root(&self, kind: Instability) -> Option<(usize, &FlutterRoot)> {
        self.roots
            .iter()
            .enumerate()
            .filter(|(_, r)| kind.admits(r))
            .max_by(|a, b| a.1.real_per_s.total_cmp(&b.1.real_per_s))
    }
}

/// A flutter or divergence boundary at one time ([`Instability`] says which).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum FlutterBoundary {
    /// A root of the boundary's kind crosses zero real part at `mach` (Brent), between a
    /// stable and an unstable grid point.
    Crossing {
        mach: f64,
        /// The final bracket, Mach numbers.
        bracket: (f64, f64),
        /// Heating marches of the root finding.
        evaluations: usize,
        /// Frequency of the crossing root at the unstable end of the final bracket, Hz (0 for
        /// a divergence boundary).
        frequency_hz: f64,
        /// The root the crossing one continues at the lowest analysed Mach number of the same
        /// time: its number among that point's roots of the boundary's kind by frequency (1:
        /// the lowest), its frequency (Hz) and that Mach number. `None` when the tracking
        /// lost it.
        #[serde(default)]
        grows_from: Option<GrowsFrom>,
    },
    /// Every analysed point is stable in the boundary's kind.
    StableInRange {
        /// The largest real part of the boundary's kind found and where, 1/s.
        max_real_per_s: f64,
        at_mach: f64,
        least_damping_ratio: f64,
        /// The first grid point above the lowest analysed one that could not be analysed
        /// (buckled, melting, past the material data): the range is stable only up to it.
        limited_by: Option<String>,
    },
    /// Already unstable in the boundary's kind at the lowest analysed Mach number.
    UnstableAtLowest {
        lowest_mach: f64,
        max_real_per_s: f64,
        least_damping_ratio: f64,
    },
    /// No bracket could be resolved (every point buckled, melted or failed, or the root
    /// finding met such a point).
    Unresolved { reason: String },
}

/// The mode a crossing root grows from ([`FlutterBoundary::Crossing`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GrowsFrom {
    /// 1-based, by frequency, among the roots of the boundary's kind at `mach`.
    pub mode: usize,
    pub frequency_hz: f64,
    pub mach: f64,
}

impl FlutterBoundary {
    /// The boundary's Mach number, when there is a crossing.
    pub fn mach(&self) -> Option<f64> {
        match self {
            FlutterBoundary::Crossing { mach, .. } => Some(*mach),
            _ => None,
        }
    }
}

/// A point the root finding of a boundary evaluated.
#[derive(Debug, Clone, Serialize)]
pub struct SearchedPoint {
    /// The boundary whose search evaluated it.
    pub instability: Instability,
    pub point: FlutterPoint,
}

/// The grid of points and the flutter and divergence boundaries at each time.
#[derive(Debug, Clone, Serialize)]
pub struct FlutterMap {
    pub machs: Vec<f64>,
    pub times_s: Vec<f64>,
    /// points[t][m]: time index t, Mach index m.
    pub points: Vec<Vec<FlutterPoint>>,
    /// The flutter boundary (an oscillatory pair crosses) at each time.
    pub boundaries: Vec<FlutterBoundary>,
    /// The divergence boundary (a real root crosses) at each time.
    pub divergence: Vec<FlutterBoundary>,
    /// At each time, every point the two root findings evaluated, in order.
    pub searched: Vec<Vec<SearchedPoint>>,
    /// For each time and Mach, the root index of each tracked mode (reference: the first
    /// analysed point's roots by frequency).
    #[serde(skip)]
    pub tracked: Vec<Vec<Vec<Option<usize>>>>,
    pub wall_time_s: f64,
}

/// Mach tolerance of the root finding.
pub const MACH_TOLERANCE: f64 = 1e-3;

/// Analyses the grid `machs` × `times_s` and finds the flutter and divergence Mach numbers at
/// each time (module docs), on all cores, with a progress line.
pub fn flutter_map(
    setup: &FlutterSetup,
    registry: &Registry,
    machs: &[f64],
    times_s: &[f64],
) -> Result<FlutterMap, FlutterError> {
    let start = Instant::now();
    if machs.is_empty() || times_s.is_empty() {
        return Err(FlutterError::Inconsistent(
            "a flutter map needs at least one Mach number and one time".to_owned(),
        ));
    }
    for &m in machs {
        check_positive("Mach number", m)?;
    }
    let total = machs.len() + 2 * times_s.len();
    let progress = Mutex::new(Progress::new("flutter", total));
    let done = AtomicUsize::new(0);
    let tick = || {
        let d = done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Ok(mut p) = progress.lock() {
            p.update(d);
        }
    };
    let by_mach: Vec<Vec<FlutterPoint>> = machs
        .par_iter()
        .map(|&m| {
            let r = march(setup, registry, m, times_s);
            tick();
            r
        })
        .collect::<Result<_, _>>()?;
    let map = map_from_marches(setup, registry, machs, times_s, by_mach, &tick, start);
    if let Ok(mut p) = progress.lock() {
        p.finish();
    }
    map
}

/// The map of grid columns already marched (`by_mach[m]`: [`march`] at `machs[m]` over
/// `times_s`): the flutter and divergence boundaries at each time (their root findings run new
/// marches) and the tracked modes; `tick` twice per time. [`flutter_map`] ends with it, and
/// `hsv-run merge` joins the columns of flutter shards with it, so both give the same map.
pub fn map_from_marches(
    setup: &FlutterSetup,
    registry: &Registry,
    machs: &[f64],
    times_s: &[f64],
    by_mach: Vec<Vec<FlutterPoint>>,
    tick: &(dyn Fn() + Sync),
    start: Instant,
) -> Result<FlutterMap, FlutterError> {
    if by_mach.len() != machs.len() || by_mach.iter().any(|c| c.len() != times_s.len()) {
        return Err(FlutterError::Inconsistent(format!(
            "{} marched Mach columns for a grid of {} Mach numbers and {} times",
            by_mach.len(),
            machs.len(),
            times_s.len()
        )));
    }
    let points: Vec<Vec<FlutterPoint>> = (0..times_s.len())
        .map(|t| by_mach.iter().map(|row| row[t].clone()).collect())
        .collect();
    let kinds = [Instability::Flutter, Instability::Divergence];
    let jobs: Vec<(usize, Instability)> = (0..times_s.len())
        .flat_map(|t| kinds.map(|k| (t, k)))
        .collect();
    let found: Vec<(FlutterBoundary, Vec<FlutterPoint>)> = jobs
        .par_iter()
        .map(|&(t, kind)| {
            let b = boundary(setup, registry, &points[t], kind);
            tick();
            b
        })
        .collect();
    let mut boundaries = Vec::with_capacity(times_s.len());
    let mut divergence = Vec::with_capacity(times_s.len());
    let mut searched: Vec<Vec<SearchedPoint>> = vec![Vec::new(); times_s.len()];
    for (&(t, instability), (b, evaluated)) in jobs.iter().zip(found) {
        match instability {
            Instability::Flutter => boundaries.push(b),
            Instability::Divergence => divergence.push(b),
        }
        searched[t].extend(
            evaluated
                .into_iter()
                .map(|point| SearchedPoint { instability, point }),
        );
    }
    let tracked = track_modes(&points);
    Ok(FlutterMap {
        machs: machs.to_vec(),
        times_s: times_s.to_vec(),
        points,
        boundaries,
        divergence,
        searched,
        tracked,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

/// The roots of `kind` of `p`, with their indices in `p.roots`.
fn roots_of(p: &FlutterPoint, kind: Instability) -> (Vec<usize>, Vec<FlutterRoot>) {
    p.roots
        .iter()
        .enumerate()
        .filter(|(_, r)| kind.admits(r))
        .map(|(i, r)| (i, r.clone()))
        .unzip()
}

/// The mode of `kind` at the row's lowest analysed point that the critical root of `end`
/// continues: followed by eigenvector correlation over the analysed grid points below
/// `end.mach` (module docs).
fn grows_from(row: &[FlutterPoint], end: &FlutterPoint, kind: Instability) -> Option<GrowsFrom> {
    let (critical, _) = end.critical_root(kind)?;
    let mut below = row
        .iter()
        .filter(|p| p.status.is_analysed() && p.mach < end.mach);
    let first = below.next()?;
    let (_, reference) = roots_of(first, kind);
    let mut shapes: Vec<DVector<Complex<f64>>> =
        reference.iter().map(|r| r.shape.clone()).collect();
    let mut follow = |p: &FlutterPoint| {
        let (indices, roots) = roots_of(p, kind);
        let assigned = track(&shapes, &roots);
        for (shape, a) in shapes.iter_mut().zip(&assigned) {
            if let Some(j) = a {
                *shape = roots[*j].shape.clone();
            }
        }
        assigned
            .iter()
            .map(|a| a.map(|j| indices[j]))
            .collect::<Vec<_>>()
    };
    below.for_each(|p| {
        follow(p);
    });
    let mode = follow(end).iter().position(|a| *a == Some(critical))?;
    Some(GrowsFrom {
        mode: mode + 1,
        frequency_hz: reference[mode].frequency_hz,
        mach: first.mach,
    })
}

/// The boundary of `kind` along one time's row of grid points (module docs), and the points
/// its root finding evaluated.
fn boundary(
    setup: &FlutterSetup,
    registry: &Registry,
    row: &[FlutterPoint],
    kind: Instability,
) -> (FlutterBoundary, Vec<FlutterPoint>) {
    let analysed: Vec<&FlutterPoint> = row.iter().filter(|p| p.status.is_analysed()).collect();
    let Some(first) = analysed.first() else {
        let reasons: Vec<String> = row
            .iter()
            .map(|p| format!("Mach {}: {}", p.mach, status_text(&p.status)))
            .collect();
        let reason = format!("no point could be analysed ({})", reasons.join("; "));
        return (FlutterBoundary::Unresolved { reason }, Vec::new());
    };
    let largest = |p: &FlutterPoint| p.critical_root(kind).map(|(_, r)| r.real_per_s);
    let max_real = analysed
        .iter()
        .filter_map(|p| largest(p).map(|v| (v, p.mach)))
        .fold((f64::NEG_INFINITY, first.mach), |a, b| {
            if b.0 > a.0 { b } else { a }
        });
    let least_damping = analysed
        .iter()
        .filter_map(|p| p.least_damping_ratio)
        .fold(f64::INFINITY, f64::min);
    if first.is_unstable_in(kind) {
        let b = FlutterBoundary::UnstableAtLowest {
            lowest_mach: first.mach,
            max_real_per_s: largest(first).unwrap_or_default(),
            least_damping_ratio: first.least_damping_ratio.unwrap_or_default(),
        };
        return (b, Vec::new());
    }
    let Some(pair) = analysed
        .windows(2)
        .find(|w| w[0].is_stable_in(kind) && w[1].is_unstable_in(kind))
    else {
        let limited_by = row
            .iter()
            .find(|p| p.mach > first.mach && !p.status.is_analysed())
            .map(|p| format!("from Mach {}: {}", p.mach, status_text(&p.status)));
        let b = FlutterBoundary::StableInRange {
            max_real_per_s: max_real.0,
            at_mach: max_real.1,
            least_damping_ratio: least_damping,
            limited_by,
        };
        return (b, Vec::new());
    };
    let (lo, hi) = (pair[0], pair[1]);
    let time_s = lo.time_s;
    // The root finding needs the stability only, not the method comparison.
    let setup = &FlutterSetup {
        compare_methods: false,
        ..setup.clone()
    };
    let margin = |p: &FlutterPoint| p.margin_per_s(kind).unwrap_or(f64::NAN);
    let mut evaluated: Vec<FlutterPoint> = Vec::new();
    let search = brent_root(
        |mach| {
            let p = flutter_point(setup, registry, mach, time_s)?;
            let m = p.margin_per_s(kind).ok_or_else(|| {
                FlutterError::Inconsistent(format!(
                    "the point at Mach {mach:.4}, t = {time_s} s: {}",
                    status_text(&p.status)
                ))
            });
            evaluated.push(p);
            m
        },
        (lo.mach, hi.mach),
        (margin(lo), margin(hi)),
        MACH_TOLERANCE,
        60,
    );
    let b = match search {
        Ok(r) => {
            // The unstable end of the final bracket: the lowest unstable point evaluated.
            let end = evaluated
                .iter()
                .chain(std::iter::once(hi))
                .filter(|p| p.is_unstable_in(kind))
                .min_by(|a, b| a.mach.total_cmp(&b.mach))
                .unwrap_or(hi);
            FlutterBoundary::Crossing {
                mach: r.root,
                bracket: r.bracket,
                evaluations: r.evaluations,
                frequency_hz: end.critical_root(kind).map_or(0.0, |(_, r)| r.frequency_hz),
                grows_from: grows_from(row, end, kind),
            }
        }
        Err(e) => FlutterBoundary::Unresolved {
            reason: format!(
                "{} between Mach {} and {} at t = {time_s} s: {e}",
                kind.name(),
                lo.mach,
                hi.mach
            ),
        },
    };
    (b, evaluated)
}

/// A one-line description of a point's status.
pub fn status_text(status: &PointStatus) -> String {
    match status {
        PointStatus::Stable => "stable".to_owned(),
        PointStatus::Unstable => "unstable".to_owned(),
        PointStatus::Buckled { message } => format!("buckled ({message})"),
        PointStatus::Melting { message } => format!("melting ({message})"),
        PointStatus::Failed { message } => format!("failed ({message})"),
    }
}

/// Mode tracking over the grid (module docs of [`super::stability`]): along Mach at each
/// time, each time starting from the previous time's first analysed point.
fn track_modes(points: &[Vec<FlutterPoint>]) -> Vec<Vec<Vec<Option<usize>>>> {
    let mut reference: Option<Vec<DVector<Complex<f64>>>> = None;
    let mut out = Vec::with_capacity(points.len());
    for row in points {
        let mut row_out = Vec::with_capacity(row.len());
        let mut row_start: Option<Vec<DVector<Complex<f64>>>> = None;
        let mut current = reference.clone();
        for p in row {
            if p.roots.is_empty() {
                row_out.push(Vec::new());
                continue;
            }
            let shapes: Vec<DVector<Complex<f64>>> = match &current {
                None => {
                    // The first analysed point names the modes by frequency.
                    p.roots.iter().map(|r| r.shape.clone()).collect()
                }
                Some(s) => s.clone(),
            };
            let assigned = track(&shapes, &p.roots);
            let next: Vec<DVector<Complex<f64>>> = assigned
                .iter()
                .zip(&shapes)
                .map(|(a, old)| a.map_or_else(|| old.clone(), |j| p.roots[j].shape.clone()))
                .collect();
            if row_start.is_none() {
                row_start = Some(next.clone());
            }
            current = Some(next);
            row_out.push(assigned);
        }
        if row_start.is_some() {
            reference = row_start;
        }
        out.push(row_out);
    }
    out
}
