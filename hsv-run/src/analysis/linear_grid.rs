//! Linear models over a Mach × altitude grid, for gain scheduling and LPV design: each point
//! trimmed and linearized as `linearize` does it ([`linearize_at`]), points side by side,
//! sharded like flutter maps ([`super::shards`]), and the grid as one `.npz` of named arrays.
//!
//! A point that does not trim (outside the engine's or the atmosphere's range) stays in the
//! grid with its error and NaN matrices, so the grid keeps its shape; a grid where no point
//! trims is an error.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::linearize::linearize_at;
use super::shards::{Shard, ShardOutput, ShardedCase, ShardedStudy, config_fingerprint};
use crate::dynamics::PerturbationRule;
use crate::npz::{NpyArray, NpyData, write_npz};

/// Most points of a linear-model grid (each is a flexible trim and a linearization, seconds).
pub const MAX_GRID_POINTS: usize = 10_000;

/// Everything that defines a grid besides the vehicle config, which it names and fingerprints.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearGridSpec {
    pub machs: Vec<f64>,
    pub altitudes_m: Vec<f64>,
    pub rule: PerturbationRule,
    /// The config file (absolute), or `None` for the embedded sample.
    pub config: Option<PathBuf>,
    pub config_fingerprint: String,
}

impl LinearGridSpec {
    /// The grid of `machs` × `altitudes_m` (each finite, Mach above 1) on `loaded`.
    pub fn new(
        machs: &[f64],
        altitudes_m: &[f64],
        rule: PerturbationRule,
        config: Option<PathBuf>,
        loaded: &LoadedConfig,
    ) -> Result<Self> {
        if machs.is_empty() || altitudes_m.is_empty() {
            bail!("a linear-model grid needs at least one Mach number and one altitude");
        }
        if let Some(m) = machs.iter().find(|m| !(m.is_finite() && **m > 1.0)) {
            bail!("grid Mach numbers must be finite and above 1, got {m}");
        }
        if let Some(h) = altitudes_m.iter().find(|h| !h.is_finite()) {
            bail!("grid altitudes must be finite, got {h}");
        }
        let points = machs.len().saturating_mul(altitudes_m.len());
        crate::limits::check_count("grid points (Mach × altitude)", points, 1, MAX_GRID_POINTS)?;
        rule.steps(&nalgebra::DVector::zeros(1))?;
        Ok(Self {
            machs: machs.to_vec(),
            altitudes_m: altitudes_m.to_vec(),
            rule,
            config,
            config_fingerprint: config_fingerprint(loaded),
        })
    }

    /// (Mach, altitude) of point `index`: Mach-major, as the arrays are laid out.
    pub fn point(&self, index: usize) -> (f64, f64) {
        let n = self.altitudes_m.len();
        (self.machs[index / n], self.altitudes_m[index % n])
    }
}

impl ShardedStudy for LinearGridSpec {
    const KIND: &'static str = "linear-model grid";
    fn case_count(&self) -> usize {
        self.machs.len() * self.altitudes_m.len()
    }
}

/// The linear model at one grid point, row-major matrices.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointModel {
    pub trim_alpha_deg: f64,
    pub trim_elevon_deg: f64,
    pub trim_fuel_equivalence_ratio: f64,
    pub state_names: Vec<String>,
    pub input_names: Vec<String>,
    pub output_names: Vec<String>,
    pub x0: Vec<f64>,
    pub u0: Vec<f64>,
    pub a: Vec<f64>,
    pub b: Vec<f64>,
    pub c: Vec<f64>,
    pub d: Vec<f64>,
}

/// One grid point: its model, or why it has none.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridPoint {
    pub index: usize,
    pub mach: f64,
    pub altitude_m: f64,
    pub model: Option<PointModel>,
    pub error: Option<String>,
}

impl ShardedCase for GridPoint {
    fn index(&self) -> usize {
        self.index
    }
}

/// A shard's points as written to [`GRID_CASES_FILE`].
pub type LinearGridShard = ShardOutput<LinearGridSpec, GridPoint>;

/// Name of the per-point results file ([`LinearGridShard`]) of a linear-model grid: what
/// `hsv-run merge` joins.
pub const GRID_CASES_FILE: &str = "linear-grid-cases.json";
/// Name of a whole grid's numpy archive ([`write_grid_npz`]).
pub const GRID_NPZ_FILE: &str = "linear_models.npz";

/// A matrix's entries row by row.
fn row_major(m: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

/// Trims and linearizes grid point `index`.
fn linearize_point(
    spec: &LinearGridSpec,
    loaded: &LoadedConfig,
    registry: &Registry,
    index: usize,
) -> GridPoint {
    let (mach, altitude_m) = spec.point(index);
    let outcome = linearize_at(loaded, registry, &spec.rule, mach, altitude_m);
    let (model, error) = match outcome {
        Ok((_, trim, lin)) => {
            let t = &trim.result.trim;
            let m = lin.model;
            let model = PointModel {
                trim_alpha_deg: t.alpha_deg,
                trim_elevon_deg: t.elevon_deg,
                trim_fuel_equivalence_ratio: t.fuel_equivalence_ratio,
                x0: m.x0.as_slice().to_vec(),
                u0: m.u0.as_slice().to_vec(),
                a: row_major(&m.a),
                b: row_major(&m.b),
                c: row_major(&m.c),
                d: row_major(&m.d),
                state_names: m.state_names,
                input_names: m.input_names,
                output_names: m.output_names,
            };
            (Some(model), None)
        }
        Err(e) => (None, Some(crate::error_line::error_line(&e))),
    };
    GridPoint {
        index,
        mach,
        altitude_m,
        model,
        error,
    }
}

/// The points of `shard`, side by side on rayon's pool; `progress` hears each one done.
pub fn linearize_shard(
    spec: &LinearGridSpec,
    loaded: &LoadedConfig,
    registry: &Registry,
    shard: Shard,
    progress: impl Fn(&GridPoint) + Sync,
) -> LinearGridShard {
    let cases: Vec<GridPoint> = shard
        .cases(spec.case_count())
        .into_par_iter()
        .map(|index| {
            let point = linearize_point(spec, loaded, registry, index);
            progress(&point);
            point
        })
        .collect();
    ShardOutput {
        spec: spec.clone(),
        shard,
        cases,
    }
}

/// The whole grid's points (in index order) as `.npz` arrays: axes `mach` and `altitude_m`;
/// `A`, `B`, `C`, `D` of shape (Mach, altitude, rows, columns), `x0`, `u0`, the trim values and
/// `ok` on the (Mach, altitude) grid (NaN and false where a point failed); the state, input and
/// output names.
pub fn grid_arrays(spec: &LinearGridSpec, points: &[GridPoint]) -> Result<Vec<NpyArray>> {
    let Some(first) = points.iter().find_map(|p| p.model.as_ref()) else {
        let why = points.iter().find_map(|p| p.error.as_deref()).unwrap_or("");
        bail!("no point of the grid trims; the first error: {why}");
    };
    let (nx, nu, ny) = (
        first.state_names.len(),
        first.input_names.len(),
        first.output_names.len(),
    );
    let grid = [spec.machs.len(), spec.altitudes_m.len()];
    let mut arrays = vec![
        NpyArray::new("mach", &grid[..1], NpyData::F64(spec.machs.clone())),
        NpyArray::new(
            "altitude_m",
            &grid[1..],
            NpyData::F64(spec.altitudes_m.clone()),
        ),
    ];
    type Field = fn(&PointModel) -> &[f64];
    let blocks: [(&str, Vec<usize>, Field); 6] = [
        ("A", vec![nx, nx], |m| &m.a),
        ("B", vec![nx, nu], |m| &m.b),
        ("C", vec![ny, nx], |m| &m.c),
        ("D", vec![ny, nu], |m| &m.d),
        ("x0", vec![nx], |m| &m.x0),
        ("u0", vec![nu], |m| &m.u0),
    ];
    for (name, dims, field) in blocks {
        let size: usize = dims.iter().product();
        let mut data = Vec::with_capacity(points.len() * size);
        for point in points {
            match &point.model {
                Some(m) if field(m).len() == size => data.extend_from_slice(field(m)),
                Some(_) => bail!(
                    "grid point {} (Mach {}, {} m) has a model of another size",
                    point.index,
                    point.mach,
                    point.altitude_m
                ),
                None => data.extend(std::iter::repeat_n(f64::NAN, size)),
            }
        }
        let shape: Vec<usize> = grid.iter().chain(&dims).copied().collect();
        arrays.push(NpyArray::new(name, &shape, NpyData::F64(data)));
    }
    type Scalar = fn(&PointModel) -> f64;
    let scalars: [(&str, Scalar); 3] = [
        ("trim_alpha_deg", |m| m.trim_alpha_deg),
        ("trim_elevon_deg", |m| m.trim_elevon_deg),
        ("trim_fuel_equivalence_ratio", |m| {
            m.trim_fuel_equivalence_ratio
        }),
    ];
    for (name, value) in scalars {
        let data = points
            .iter()
            .map(|p| p.model.as_ref().map_or(f64::NAN, value))
            .collect();
        arrays.push(NpyArray::new(name, &grid, NpyData::F64(data)));
    }
    let ok = points.iter().map(|p| p.model.is_some()).collect();
    arrays.push(NpyArray::new("ok", &grid, NpyData::Bool(ok)));
    for (name, names) in [
        ("state_names", &first.state_names),
        ("input_names", &first.input_names),
        ("output_names", &first.output_names),
    ] {
        arrays.push(NpyArray::new(
            name,
            &[names.len()],
            NpyData::Str(names.clone()),
        ));
    }
    Ok(arrays)
}

/// Writes the whole grid's `.npz` to `path`.
pub fn write_grid_npz(path: &Path, spec: &LinearGridSpec, points: &[GridPoint]) -> Result<()> {
    write_npz(path, &grid_arrays(spec, points)?)
}
