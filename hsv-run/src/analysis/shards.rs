//! Sweeps past one machine: a study's independent cases split into deterministic shards, each
//! shard's output (the study and its cases), and the merge that joins shard outputs into what
//! one unsharded run gives. Trade studies ([`super::trade`], a case per model combination) and
//! flutter maps ([`FlutterMapSpec`], a case per Mach column of the grid) both use it.
//!
//! Case `i` belongs to shard `i mod N`, so shards are independent; a merge takes every shard of
//! one study exactly once (equal specs, equal shard counts) and every case exactly once.
//!
//! A flutter map shards by Mach column rather than by single (Mach, time) point: the surface
//! heats from 293 K at each Mach number, and the march to the last time passes through every
//! earlier one, so splitting a column would repeat its heating. The merge runs the flutter
//! boundary (bracketing on the merged grid, Brent's method between) exactly as the unsharded
//! map does ([`map_from_marches`]), so the two give the same map.

use std::path::PathBuf;
use std::str::FromStr;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::flutter::stability::FlutterRoot;
use super::flutter::sweep::{
    FlutterMap, FlutterModels, FlutterPoint, FlutterSetup, map_from_marches, march,
};
use super::flutter::{DerivativeMethod, SurfaceOptions};
use super::heating::HeatingSteps;

/// FNV-1a 64 of `text`, as 16 hex digits (stable across builds, unlike `DefaultHasher`).
pub fn fingerprint(text: &str) -> String {
    format!("{:016x}", hsv_core::cache::fnv1a(text.bytes()))
}

/// The fingerprint of a loaded config's TOML, so shards of different configs never merge.
pub fn config_fingerprint(loaded: &LoadedConfig) -> String {
    fingerprint(&toml::to_string(&loaded.raw).unwrap_or_default())
}

/// A deterministic share of the cases: case `i` belongs to shard `i mod count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 0-based (Slurm's `SLURM_ARRAY_TASK_ID`).
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The whole study.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// The share a `--shard K/N` flag names, or the whole study without one.
    pub fn from_flag(flag: Option<&str>) -> Result<Self> {
        Ok(flag.map(str::parse).transpose()?.unwrap_or(Self::ALL))
    }

    /// The cases of this shard among `cases`.
    pub fn cases(self, cases: usize) -> Vec<usize> {
        (self.index..cases).step_by(self.count).collect()
    }
}

impl FromStr for Shard {
    type Err = anyhow::Error;

    /// `K/N`, 0 ≤ K < N.
    fn from_str(text: &str) -> Result<Self> {
        let parsed = text
            .split_once('/')
            .and_then(|(k, n)| Some((k.trim().parse().ok()?, n.trim().parse().ok()?)));
        match parsed {
            Some((index, count))
                if count >= 1 && index < count && count <= crate::limits::MAX_SHARDS =>
            {
                Ok(Self { index, count })
            }
            _ => bail!(
                "--shard `{text}`: expected K/N with 0 <= K < N <= {}, e.g. 0/4",
                crate::limits::MAX_SHARDS
            ),
        }
    }
}

/// What defines a sharded study: shards merge only when theirs are equal.
pub trait ShardedStudy: Clone + PartialEq {
    /// What the study is, for messages (`trade study`, `flutter map`).
    const KIND: &'static str;
    /// Number of independent cases.
    fn case_count(&self) -> usize;
}

/// One case's result, numbered within its study.
pub trait ShardedCase: Clone {
    fn index(&self) -> usize;
}

/// The cases of one shard (or of the whole study), as a shard writes them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardOutput<S, C> {
    pub spec: S,
    pub shard: Shard,
    pub cases: Vec<C>,
}

/// Joins shard outputs (named for messages): same study, same shard count, every shard once,
/// every case exactly once; the cases come back in index order.
pub fn merge_shards<S: ShardedStudy, C: ShardedCase>(
    parts: Vec<(String, ShardOutput<S, C>)>,
) -> Result<(S, Vec<C>)> {
    let Some((first_name, first)) = parts.first() else {
        bail!("nothing to merge: give the shard output folders");
    };
    let spec = first.spec.clone();
    let count = first.shard.count;
    let mut seen_shards = vec![None::<String>; count];
    let mut cases: Vec<Option<C>> = vec![None; spec.case_count()];
    for (name, part) in &parts {
        if part.spec != spec {
            bail!(
                "{name} is a different {} from {first_name} (its settings, grid or config \
                 differ); shards merge only within one {}",
                S::KIND,
                S::KIND
            );
        }
        if part.shard.count != count {
            bail!(
                "{name} is shard {}/{} but {first_name} is one of {count} shards",
                part.shard.index,
                part.shard.count
            );
        }
        let seen = seen_shards.get_mut(part.shard.index).with_context(|| {
            format!("{name}: shard {}/{count} is out of range", part.shard.index)
        })?;
        if let Some(other) = seen {
            bail!(
                "shard {}/{count} is given twice: {other} and {name}",
                part.shard.index
            );
        }
        *seen = Some(name.clone());
        for case in &part.cases {
            let slot = cases.get_mut(case.index()).with_context(|| {
                format!(
                    "{name}: case {} is outside the {}'s {} cases",
                    case.index(),
                    S::KIND,
                    spec.case_count()
                )
            })?;
            if slot.is_some() {
                bail!("{name}: case {} appears twice", case.index());
            }
            *slot = Some(case.clone());
        }
    }
    let missing: Vec<String> = seen_shards
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(k, _)| format!("{k}/{count}"))
        .collect();
    if !missing.is_empty() {
        bail!("shards missing from the merge: {}", missing.join(", "));
    }
    let mut complete = Vec::with_capacity(cases.len());
    for (index, case) in cases.into_iter().enumerate() {
        complete.push(case.with_context(|| format!("case {index} is in no shard output"))?);
    }
    Ok((spec, complete))
}

/// Everything that defines a flutter map besides the vehicle config, which it names and
/// fingerprints: the merge rebuilds the analysis from it to run the root finding.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlutterMapSpec {
    /// The analysed lifting-surface region.
    pub region: String,
    pub models: FlutterModels,
    pub altitude_m: f64,
    pub alpha_rad: f64,
    pub heating_dt_s: f64,
    pub flux_every: usize,
    pub initial_temperature_k: f64,
    pub method: DerivativeMethod,
    pub compare_methods: bool,
    /// The Mach grid; case `m` is the column at `machs[m]`.
    pub machs: Vec<f64>,
    pub times_s: Vec<f64>,
    /// The config file (absolute), or `None` for the embedded sample vehicle.
    pub config: Option<PathBuf>,
    pub config_fingerprint: String,
}

impl ShardedStudy for FlutterMapSpec {
    const KIND: &'static str = "flutter map";

    fn case_count(&self) -> usize {
        self.machs.len()
    }
}

impl FlutterMapSpec {
    /// The spec of the map `setup` gives over `machs` × `times_s`, on `loaded` (read from
    /// `config`, absolute, or the sample when `None`).
    pub fn new(
        setup: &FlutterSetup,
        machs: &[f64],
        times_s: &[f64],
        config: Option<PathBuf>,
        loaded: &LoadedConfig,
    ) -> Result<Self> {
        // The surface options have no command-line form; shards run the defaults.
        if setup.options != SurfaceOptions::default() {
            bail!("flutter shards run with the default surface options only");
        }
        Ok(Self {
            region: setup.region.name.clone(),
            models: setup.models.clone(),
            altitude_m: setup.altitude_m,
            alpha_rad: setup.alpha_rad,
            heating_dt_s: setup.heating.dt_s,
            flux_every: setup.heating.flux_every,
            initial_temperature_k: setup.heating.initial_k,
            method: setup.method,
            compare_methods: setup.compare_methods,
            machs: machs.to_vec(),
            times_s: times_s.to_vec(),
            config,
            config_fingerprint: config_fingerprint(loaded),
        })
    }

    /// The analysis on `loaded`, which must be the config the shards ran on.
    pub fn setup(&self, loaded: &LoadedConfig) -> Result<FlutterSetup> {
        if config_fingerprint(loaded) != self.config_fingerprint {
            bail!(
                "{} has changed since the flutter shards ran on it (fingerprint {} now, {} \
                 then); rerun the shards or restore the config",
                loaded.file,
                config_fingerprint(loaded),
                self.config_fingerprint
            );
        }
        Ok(FlutterSetup {
            region: loaded.region(&self.region)?,
            models: self.models.clone(),
            altitude_m: self.altitude_m,
            alpha_rad: self.alpha_rad,
            heating: HeatingSteps {
                dt_s: self.heating_dt_s,
                flux_every: self.flux_every,
                initial_k: self.initial_temperature_k,
            },
            method: self.method,
            compare_methods: self.compare_methods,
            options: SurfaceOptions::default(),
        })
    }
}

/// One marched Mach column of a flutter map: a point per time, with each point's roots (which
/// [`FlutterPoint`] does not serialize) kept beside it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FlutterColumn {
    /// Index in the spec's Mach grid.
    pub index: usize,
    pub mach: f64,
    pub points: Vec<FlutterPoint>,
    pub roots: Vec<Vec<FlutterRoot>>,
}

impl ShardedCase for FlutterColumn {
    fn index(&self) -> usize {
        self.index
    }
}

impl FlutterColumn {
    fn new(index: usize, mach: f64, points: Vec<FlutterPoint>) -> Self {
        let roots = points.iter().map(|p| p.roots.clone()).collect();
        Self {
            index,
            mach,
            points,
            roots,
        }
    }

    /// The points with their roots back in place.
    fn into_points(self) -> Vec<FlutterPoint> {
        self.points
            .into_iter()
            .zip(self.roots)
            .map(|(mut p, roots)| {
                p.roots = roots;
                p
            })
            .collect()
    }
}

/// A flutter shard's output ([`FLUTTER_CASES_FILE`]).
pub type FlutterShard = ShardOutput<FlutterMapSpec, FlutterColumn>;

/// Name of the per-column results file ([`FlutterShard`]) of a flutter shard: what
/// `hsv-run merge` joins.
pub const FLUTTER_CASES_FILE: &str = "flutter-cases.json";

/// Marches the Mach columns of `shard` (on all cores): its share of the map's points.
pub fn march_shard(
    spec: &FlutterMapSpec,
    setup: &FlutterSetup,
    registry: &Registry,
    shard: Shard,
) -> Result<FlutterShard> {
    let cases = shard
        .cases(spec.case_count())
        .into_par_iter()
        .map(|m| {
            let mach = spec.machs[m];
            march(setup, registry, mach, &spec.times_s)
                .map(|points| FlutterColumn::new(m, mach, points))
                .with_context(|| format!("flutter march at Mach {mach}"))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(ShardOutput {
        spec: spec.clone(),
        shard,
        cases,
    })
}

/// The map of merged columns (every column once, in grid order): the flutter boundary at each
/// time and the tracked modes, as the unsharded map finds them.
pub fn map_from_columns(
    spec: &FlutterMapSpec,
    setup: &FlutterSetup,
    registry: &Registry,
    columns: Vec<FlutterColumn>,
) -> Result<FlutterMap> {
    let start = Instant::now();
    let by_mach: Vec<Vec<FlutterPoint>> = columns
        .into_iter()
        .map(FlutterColumn::into_points)
        .collect();
    Ok(map_from_marches(
        setup,
        registry,
        &spec.machs,
        &spec.times_s,
        by_mach,
        &|| {},
        start,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Clone, PartialEq)]
    struct Study(usize);

    impl ShardedStudy for Study {
        const KIND: &'static str = "test study";
        fn case_count(&self) -> usize {
            self.0
        }
    }

    impl ShardedCase for usize {
        fn index(&self) -> usize {
            *self
        }
    }

    fn part(k: usize, n: usize, cases: usize) -> (String, ShardOutput<Study, usize>) {
        let shard = Shard { index: k, count: n };
        (
            format!("shard-{k}"),
            ShardOutput {
                spec: Study(cases),
                shard,
                cases: shard.cases(cases),
            },
        )
    }

    #[test]
    fn shards_partition_the_cases() {
        let mut all: Vec<usize> = (0..3)
            .flat_map(|k| Shard { index: k, count: 3 }.cases(7))
            .collect();
        all.sort_unstable();
        assert_eq!(all, (0..7).collect::<Vec<_>>());
        assert!("3/3".parse::<Shard>().is_err());
        assert!("1/0".parse::<Shard>().is_err());
        assert_eq!(
            "1/4".parse::<Shard>().unwrap(),
            Shard { index: 1, count: 4 }
        );
    }

    #[test]
    fn merge_takes_every_shard_once_in_any_order() {
        let (_, cases) = merge_shards(vec![part(2, 3, 7), part(0, 3, 7), part(1, 3, 7)]).unwrap();
        assert_eq!(cases, (0..7).collect::<Vec<_>>());
        let missing = merge_shards(vec![part(0, 3, 7), part(2, 3, 7)]).unwrap_err();
        assert!(missing.to_string().contains("1/3"), "{missing}");
        let twice = merge_shards(vec![part(0, 2, 4), part(0, 2, 4), part(1, 2, 4)]).unwrap_err();
        assert!(twice.to_string().contains("twice"), "{twice}");
        let other = merge_shards(vec![part(0, 2, 4), part(1, 2, 5)]).unwrap_err();
        assert!(
            other.to_string().contains("different test study"),
            "{other}"
        );
        let counts = merge_shards(vec![part(0, 2, 4), part(1, 3, 4)]).unwrap_err();
        assert!(counts.to_string().contains("one of 2 shards"), "{counts}");
    }
}
