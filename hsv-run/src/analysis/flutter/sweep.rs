//! The flutter grid's points: the heated surface over Mach numbers and times in the flow (paper
//! §IV.D, Figs. 14-16), each point's stability, and the map over the grid.
//!
//! At each Mach number of a grid the surface starts uniformly at 293 K and heats in that flow
//! ([`SurfaceHeating`]: heat flux, conduction); at each requested time the conduction model's
//! node temperatures and through-thickness differences are moved onto the structure's grid
//! ([`StructureTemperatures`]) and set on the structure (heat-degraded modulus, thermal-stress geometric
//! stiffness, thermal moment), then the surface's equilibrium, identified state matrix and
//! eigenvalues give the point's stability. The grid marches are independent and run on all
//! cores; the flutter and divergence boundaries and the tracked modes then come from the marched
//! points ([`super::boundary`]).
//!
//! A surface buckled in vacuum (its own stiffness no longer positive definite) is analysed with
//! its aero like any other and flagged. A melting surface (wall past the solidus) or one past
//! its material data is reported at its Mach number and time.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use hsv_core::aero::AeroModel;
use hsv_core::coupling::StructureTemperatures;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry, RoleModel};
use hsv_core::structure::StructureModel;
use nalgebra::Complex;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::stability::{FlutterRoot, Instability, stability};
use super::surface::{DerivativeMethod, SurfaceDynamics, SurfaceOptions};
use super::{FlutterError, check_positive};
use crate::analysis::heating::{HeatingModels, HeatingSteps, SurfaceHeating};
use crate::progress::Progress;
use crate::vehicle::Region;
use crate::vehicle::region_rate::PublishedTemperatures;
use hsv_core::data::{DataError, DataManager, DataManagerBuilder, Publisher, Subscriber};

pub use super::boundary::{
    FlutterBoundary, FlutterMap, GrowsFrom, MACH_TOLERANCE, SearchedPoint, map_from_marches,
};

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

/// The temperature state of a march, moved onto the structure. The surface's thermal region
/// and its structure exchange through a data manager, as in flight: the region advances to a
/// time ([`Region::step_to`], publishing its node temperatures), the field moved onto the
/// structure's nodes is published on `<surface>/structure_temperatures`, and the structure
/// reads its stiffness from that topic.
struct Thermal {
    heating: SurfaceHeating,
    onto_structure: StructureTemperatures,
    data: DataManager,
    to_structure: (
        Publisher<PublishedTemperatures>,
        Subscriber<PublishedTemperatures>,
    ),
}

/// A data-manager error of the march, as the flutter error it is.
fn exchange_error(e: DataError) -> FlutterError {
    FlutterError::Inconsistent(format!("the march's data exchange: {e}"))
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
        let mut heating = heating;
        let name = setup.region.name.clone();
        let topic = format!("{name}/structure_temperatures");
        let mut builder = DataManagerBuilder::new();
        heating.declare(&mut builder).map_err(exchange_error)?;
        let to_structure = (
            builder
                .publish(&format!("{name}/thermal"), &topic)
                .map_err(exchange_error)?,
            builder.subscribe(&name, &topic).map_err(exchange_error)?,
        );
        let data = builder.build().map_err(exchange_error)?;
        Ok(Self {
            heating,
            onto_structure,
            data,
            to_structure,
        })
    }

    /// Heats to `time_s` (steps of the region's dt, the last shortened).
    fn advance_to(&mut self, time_s: f64) -> Result<(), FlutterError> {
        self.heating.step_to(time_s, &mut self.data).map_err(|e| {
            let message = e.to_string();
            // A wall past the solidus (heat flux), or a structure past the end of its
            // material's thermal data, which for Ti-6Al-4V ends at 1869.8 K, 7 K below the
            // solidus: both are the melting surface.
            if message.contains("melted") || message.contains("(k, c_p) data") {
                FlutterError::Melting(message)
            } else {
                FlutterError::Region(e)
            }
        })
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
        let (publisher, reader) = self.to_structure;
        let field = &self.onto_structure;
        self.data
            .publish_with(publisher, self.heating.time_s(), |t| {
                t.mean_k.clone_from(&field.mean_k);
                t.difference_k.clone_from(&field.difference_k);
            })
            .and_then(|_| self.data.mark_converged(publisher))
            .map_err(exchange_error)?;
        let read = self.data.read_converged(reader).map_err(exchange_error)?;
        thermal
            .set_temperature_field(&read.value.mean_k, &read.value.difference_k)
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
        if let Err(e) = thermal.advance_to(time_s) {
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
}

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
