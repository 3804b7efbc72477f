//! The flutter and divergence boundaries: from the marched grid points, the Mach number where
//! each kind of instability sets in at each time (bracketed on the grid, Brent between), the
//! mode a flutter crossing grows from, and the modes tracked over the grid (paper §IV.D).
//!
//! **Flutter and divergence Mach numbers** at a time, each on its own ([`Instability`]): the
//! flutter boundary is where an oscillatory pair's largest real part crosses the round-off
//! threshold ([`super::stability`](mod@super::stability)), the divergence boundary where a real
//! root's does. For each, the lowest grid interval whose lower end is stable and upper end unstable
//! in that kind brackets the crossing; Brent's method then finds the zero, each evaluation a fresh
//! heating march at that Mach number to that time, and every point it evaluates is kept
//! ([`FlutterMap::searched`]). A range with no stable point, or no unstable one, is reported as
//! such with the largest real part and least damping found, never as a crossing. A flutter crossing
//! names the mode it grows from: the critical pair is followed back by eigenvector correlation over
//! the grid points below it to the roots of the lowest analysed Mach number. A surface buckled in
//! vacuum is analysed like any other: where the flow does not hold it, its real root in the right
//! half plane is a divergence (thermal buckling) boundary, not flutter. A melting surface (wall
//! past the solidus) or one past its material data takes no part in the bracketing.

use std::time::Instant;

use hsv_core::registry::Registry;
use nalgebra::{Complex, DVector};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::FlutterError;
use super::stability::{FlutterRoot, Instability, brent_root, track};
use super::sweep::{FlutterPoint, FlutterSetup, flutter_point, status_text};

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
    /// `points[t][m]`: time index t, Mach index m.
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

/// The map of grid columns already marched (`by_mach[m]`: [`march`](super::sweep::march) at
/// `machs[m]` over `times_s`): the flutter and divergence boundaries at each time (their root
/// findings run new marches) and the tracked modes; `tick` twice per time.
/// [`flutter_map`](super::sweep::flutter_map) ends with it, and
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

impl FlutterPoint {
    /// The largest σ of the roots of `kind`, with the root, 1/s.
    fn critical_root(&self, kind: Instability) -> Option<(usize, &FlutterRoot)> {
        self.roots
            .iter()
            .enumerate()
            .filter(|(_, r)| kind.admits(r))
            .max_by(|a, b| a.1.real_per_s.total_cmp(&b.1.real_per_s))
    }
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
