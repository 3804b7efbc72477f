//! POD training: full-order snapshot runs of the region's lifting surface heated in steady flow,
//! the basis built from them, and the record of what it was built from that decides whether a
//! cached basis file still serves.
//!
//! The heat flux comes from a heat-flux model on the edge states of an aero model, both built by
//! name through the host registry (plugins included), as the region sees their settings.

use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::registry::ModelContext;
use hsv_core::thermal::HeatFluxModel;
use nalgebra::DVector;

use crate::full_order::FullOrder;
use crate::pod::{NAME, PodBasis};

/// `[models.pod.training]`: the flight conditions the snapshot runs heat the surface in.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Training {
    /// Heat-flux model of the snapshot runs (registered name).
    pub heat_flux: String,
    /// Aero model giving the edge states (registered name).
    pub aero: String,
    /// Mach numbers, one snapshot run each.
    pub mach: Vec<f64>,
    /// Geometric altitude, m.
    pub altitude_m: f64,
    /// Angles of attack, deg (a number or a list): one snapshot run per Mach number and angle.
    /// At zero incidence the symmetric section heats symmetrically, so a basis trained there
    /// alone spans only mirror-symmetric fields (no through-thickness difference, no thermal
    /// moment); angles either side of zero give it the asymmetric ones.
    #[serde(deserialize_with = "one_or_many")]
    pub alpha_deg: Vec<f64>,
    /// Time in the flow of each run, s.
    pub duration_s: f64,
    /// Conduction step, s.
    pub dt_s: f64,
    /// Snapshots kept per run, evenly spaced in time.
    pub snapshots_per_run: usize,
    /// Uniform initial temperature, K.
    pub initial_k: f64,
}

impl Default for Training {
    fn default() -> Self {
        Self {
            heat_flux: "eckert".to_owned(),
            aero: "shock-expansion".to_owned(),
            // Our choice: bracket the paper's Mach 6 heating case from below and at it.
            mach: vec![5.0, 5.5, 6.0],
            // Paper §IV.D: the surface heats at 10 km.
            altitude_m: 10_000.0,
            // Our choice: either side of zero, about the trimmed surface's incidence (body
            // α 1.7° with the elevon at -5.6°), and cool enough that 100 s at Mach 6 stays
            // inside the titanium's thermal data.
            alpha_deg: vec![-4.0, 0.0, 4.0],
            // Paper: up to 100 s in the flow.
            duration_s: 100.0,
            dt_s: 0.1,
            snapshots_per_run: 100,
            initial_k: 293.0,
        }
    }
}

/// A number or a list of numbers, as a list.
fn one_or_many<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<Vec<f64>, D::Error> {
    #[derive(serde::Deserialize)]
    #[serde(untagged)]
    enum OneOrMany {
        One(f64),
        Many(Vec<f64>),
    }
    use serde::Deserialize;
    Ok(match OneOrMany::deserialize(deserializer)? {
        OneOrMany::One(a) => vec![a],
        OneOrMany::Many(a) => a,
    })
}

impl Training {
    /// The first setting outside its range: key, value and the allowed range.
    pub fn first_invalid(&self) -> Option<(String, f64, &'static str)> {
        let positive = [
            ("training.duration_s", self.duration_s),
            ("training.dt_s", self.dt_s),
            ("training.initial_k", self.initial_k),
        ];
        for (key, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Some((key.to_owned(), value, "finite and > 0"));
            }
        }
        if let Some((i, &m)) = self
            .mach
            .iter()
            .enumerate()
            .find(|(_, m)| !(m.is_finite() && **m >= 1.0))
        {
            return Some((format!("training.mach[{i}]"), m, "finite and >= 1"));
        }
        if self.mach.is_empty() {
            return Some(("training.mach".to_owned(), 0.0, "at least one Mach number"));
        }
        if !self.altitude_m.is_finite() {
            return Some(("training.altitude_m".to_owned(), self.altitude_m, "finite"));
        }
        if let Some((i, &a)) = self
            .alpha_deg
            .iter()
            .enumerate()
            .find(|(_, a)| !(a.is_finite() && a.abs() < 90.0))
        {
            return Some((
                format!("training.alpha_deg[{i}]"),
                a,
                "finite, |alpha| < 90",
            ));
        }
        if self.alpha_deg.is_empty() {
            return Some((
                "training.alpha_deg".to_owned(),
                0.0,
                "at least one angle of attack",
            ));
        }
        let steps = self.duration_s / self.dt_s;
        if steps > 1e7 {
            return Some(("training.dt_s".to_owned(), self.dt_s, "<= duration_s / 1e7"));
        }
        if self.snapshots_per_run == 0 {
            return Some(("training.snapshots_per_run".to_owned(), 0.0, ">= 1"));
        }
        None
    }

    /// Steps per run: duration over step, the last step ending at the duration (rounded to
    /// the nearest whole step).
    fn steps(&self) -> usize {
        ((self.duration_s / self.dt_s).round() as usize).max(1)
    }
}

/// What a basis was built from, as one string: the training conditions, the revision of the
/// panel-to-grid map, the full-order grid and materials (settings with the quadrature in effect,
/// [`crate::full_order::Settings::resolved`]), the planform and the settings of the base models. A cached basis serves only
/// a run whose fingerprint is the same.
pub fn fingerprint(
    ctx: &ModelContext<'_>,
    training: &Training,
    full: &FullOrder,
) -> Result<String, ModelError> {
    let planform = ctx.region.lifting_surface(NAME)?.0;
    serde_json::to_string(&(
        training,
        crate::full_order::PANEL_MAP_REVISION,
        full.settings().resolved(),
        planform,
        &ctx.settings_for(&training.heat_flux).table,
        &ctx.settings_for(&training.aero).table,
    ))
    .map_err(|e| ModelError::inconsistent(NAME, format!("fingerprint: {e}")))
}

/// Runs `full` at every training condition and builds a basis of `modes` modes from the
/// snapshots (fewer when the runs give fewer snapshots than `modes`). The runs are independent,
/// so they run side by side (rayon, each with its own copy of the full-order model and its own
/// heat-flux and aero models); the snapshots are gathered in the conditions' order, so the basis
/// is the same bit for bit on any number of threads.
pub fn train_basis(
    ctx: &ModelContext<'_>,
    training: &Training,
    full: &mut FullOrder,
    modes: usize,
) -> Result<PodBasis, ModelError> {
    use rayon::prelude::*;
    let steps = training.steps();
    let every = (steps / training.snapshots_per_run).max(1);
    let conditions: Vec<(f64, f64)> = training
        .mach
        .iter()
        .flat_map(|&m| training.alpha_deg.iter().map(move |&a| (m, a)))
        .collect();
    let template: &FullOrder = full;
    let runs: Vec<Vec<DVector<f64>>> = conditions
        .par_iter()
        .map(|&(mach, alpha_deg)| {
            let mut full = template.clone();
            condition_snapshots(ctx, training, &mut full, mach, alpha_deg, steps, every)
        })
        .collect::<Result<_, _>>()?;
    let snapshots: Vec<DVector<f64>> = runs.into_iter().flatten().collect();
    // A short horizon gives fewer snapshots than modes: take the modes they allow (the model
    // says so, see `construct_pod`) rather than refuse a run the full-order model can do.
    let modes = modes.min(snapshots.len()).max(1);
    PodBasis::from_snapshots(&snapshots, modes, full.settings().clone())
}

/// The snapshots of one training run: `full` in the flow at Mach `mach` and `alpha_deg`, the
/// training's heat-flux model on the training's aero edge states.
fn condition_snapshots(
    ctx: &ModelContext<'_>,
    training: &Training,
    full: &mut FullOrder,
    mach: f64,
    alpha_deg: f64,
    steps: usize,
    every: usize,
) -> Result<Vec<DVector<f64>>, ModelError> {
    let build_error = |what: &str, e: hsv_core::registry::RegistryError| {
        ctx.settings_error(&format!("training.{what}"), e.to_string())
    };
    let heat_settings = ctx.settings_for(&training.heat_flux);
    let mut heat = ctx
        .build::<dyn HeatFluxModel>(&training.heat_flux, &heat_settings)
        .map_err(|e| build_error("heat_flux", e))?;
    let aero_settings = ctx.settings_for(&training.aero);
    let mut aero = ctx
        .build::<dyn AeroModel>(&training.aero, &aero_settings)
        .map_err(|e| build_error("aero", e))?;
    let mesh = &ctx.region.mesh;
    let mut edge = AeroSolution::default();
    let freestream = Freestream::standard(mach, training.altitude_m, ctx.region.gas)?;
    let flight = FlightCondition::steady(freestream, alpha_deg.to_radians(), 0.0);
    aero.evaluate(mesh, &flight, &PanelMotion::default(), &mut edge)?;
    crate::pod::collect_snapshots(
        full,
        training.initial_k,
        training.dt_s,
        steps,
        every,
        |wall, q| heat.heat_flux(mesh, &flight, &edge, wall, q),
    )
    .map_err(|e| {
        ModelError::inconsistent(
            NAME,
            format!("full-order snapshot run at Mach {mach}, alpha {alpha_deg} deg: {e}"),
        )
    })
}
