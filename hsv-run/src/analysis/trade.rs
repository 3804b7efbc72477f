//! Fidelity trade studies: every combination of named region models run through one job (rigid
//! trim, a flight from trim, or the lifting surface's flutter map), compared with the
//! highest-fidelity combination, with the cost of each; split into deterministic shards
//! ([`super::shards`]) that merge into the same table. The jobs themselves are in
//! `flight_jobs` (trim, simulate) and `flutter_job` (one file: the spec, its cases and the
//! comparison into the table share the case numbering the shards and the merge rely on).
//!
//! A study is a list of [`Variation`]s (`main_body.aero=newtonian-scalar,shock-expansion`), each
//! a `[regions.<region>] <role>` key and the model names it takes. Its cases are the Cartesian
//! product, numbered with the last variation changing fastest. The reference case takes, on every
//! variation, the model of highest registry `fidelity` (the first listed on a tie). Case `i`
//! belongs to shard `i mod N`, so shards are independent and any set of shard outputs that
//! covers every case merges into the table one unsharded run gives.

use std::collections::BTreeMap;
use std::str::FromStr;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use hsv_core::config::{LoadedConfig, parse_config};
use hsv_core::registry::Registry;
use serde::{Deserialize, Serialize};

mod flight_jobs;
mod flutter_job;

use flight_jobs::{simulate_case, trim_case};
pub use flutter_job::{
    FlutterAtTime, FlutterGrid, flutter_mach_key, flutter_region, flutter_setup,
};
use flutter_job::{flutter_case, flutter_deviation};

pub use super::shards::{Shard, fingerprint};
use super::shards::{ShardOutput, ShardedCase, ShardedStudy, merge_shards};

/// Region tables a variation may edit (`lifting_surfaces` sets both surfaces).
pub const REGION_TABLES: [&str; 5] = [
    "main_body",
    "lifting_surfaces",
    "left_surface",
    "right_surface",
    "propulsion",
];

/// Model keys of a region table, one per role.
pub const ROLE_KEYS: [&str; 5] = ["aero", "heat_flux", "conduction", "structure", "propulsion"];

/// Trim values compared between combinations.
pub const TRIM_QUANTITIES: [&str; 3] = ["alpha_deg", "elevon_deg", "fuel_equivalence_ratio"];

/// Trim values compared as 0 where a case has none: a glide's flight-path angle (a vehicle
/// without an engine glides with φ 0; level-flight cases, and files of earlier versions, carry
/// no γ or γ 0).
pub const OPTIONAL_TRIM_QUANTITIES: [&str; 1] = ["flight_path_angle_deg"];

/// Time histories compared between combinations (the flight's response to the inputs).
pub const HISTORY_CHANNELS: [&str; 5] = [
    "altitude_m",
    "airspeed_m_s",
    "alpha_deg",
    "pitch_deg",
    "q_deg_s",
];

/// Smallest scale of each [`HISTORY_CHANNELS`] entry in the simulate error (1 cm, 1 cm/s,
/// 0.001 deg, 0.001 deg, 0.001 deg/s): a channel that stays near zero (q before the doublet)
/// is not divided by its round-off.
pub const HISTORY_FLOORS: [f64; 5] = [1e-2, 1e-2, 1e-3, 1e-3, 1e-3];

/// One varied model key and the names it takes, e.g. `main_body.aero=newtonian-scalar,shock-expansion`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Variation {
    /// `<region>.<role key>`, e.g. `main_body.aero`.
    pub key: String,
    pub models: Vec<String>,
    /// Registry fidelity of each model ([`StudySpec::rank`]), so merging needs no registry.
    #[serde(default)]
    pub fidelity: Vec<u8>,
}

impl Variation {
    /// A checked variation: a known region table and role key, at least one model, no repeats.
    pub fn new(key: &str, models: Vec<String>) -> Result<Self> {
        let Some((region, role)) = key.split_once('.') else {
            bail!("trade variation `{key}`: expected <region>.<model key>, e.g. main_body.aero");
        };
        if !REGION_TABLES.contains(&region) {
            bail!(
                "trade variation `{key}`: unknown region `{region}`; expected one of {}",
                REGION_TABLES.join(", ")
            );
        }
        if !ROLE_KEYS.contains(&role) {
            bail!(
                "trade variation `{key}`: unknown model key `{role}`; expected one of {}",
                ROLE_KEYS.join(", ")
            );
        }
        if models.is_empty() || models.iter().any(String::is_empty) {
            bail!("trade variation `{key}`: give at least one model name, none empty");
        }
        if let Some(twice) = models
            .iter()
            .enumerate()
            .find(|(i, m)| models[..*i].contains(m))
        {
            bail!(
                "trade variation `{key}`: model `{}` is listed twice",
                twice.1
            );
        }
        Ok(Self {
            key: key.to_owned(),
            models,
            fidelity: Vec::new(),
        })
    }

    /// (region table, role key).
    pub fn parts(&self) -> (&str, &str) {
        self.key.split_once('.').unwrap_or((self.key.as_str(), ""))
    }
}

impl FromStr for Variation {
    type Err = anyhow::Error;

    /// `<region>.<key>=<model>,<model>,...`
    fn from_str(text: &str) -> Result<Self> {
        let Some((key, models)) = text.split_once('=') else {
            bail!("trade variation `{text}`: expected <region>.<key>=<model>,<model>,...");
        };
        let models = models
            .split(',')
            .map(|m| m.trim().to_owned())
            .collect::<Vec<_>>();
        Self::new(key.trim(), models)
    }
}

/// What each case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum TradeJob {
    /// Steady level flight of the rigid vehicle: α, δe, φ.
    Trim,
    /// The partitioned flexible vehicle flown from its trim under the config's inputs: time
    /// histories.
    Simulate,
    /// One lifting surface heated in the flow and analysed over a Mach grid (as `hsv-run
    /// flutter`): the flutter Mach number at each time in the flow.
    Flutter,
}

impl TradeJob {
    pub fn as_str(self) -> &'static str {
        match self {
            TradeJob::Trim => "trim",
            TradeJob::Simulate => "simulate",
            TradeJob::Flutter => "flutter",
        }
    }
}

/// Step and length of each flight of a `simulate` study.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlightSpec {
    pub duration_s: f64,
    pub dt_s: f64,
    pub record_every: usize,
}

/// Everything that defines a study: shards merge only when theirs are equal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudySpec {
    pub job: TradeJob,
    pub variations: Vec<Variation>,
    pub mach: f64,
    pub altitude_m: f64,
    /// Present for `simulate` studies.
    pub flight: Option<FlightSpec>,
    /// Present for `flutter` studies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flutter: Option<FlutterGrid>,
    /// The config file the cases edit (for messages).
    pub config_file: String,
    /// FNV-1a 64 of the config's TOML, so shards of different configs never merge.
    pub config_fingerprint: String,
}

impl StudySpec {
    /// Number of cases: the product of the variation lengths.
    pub fn case_count(&self) -> usize {
        self.variations.iter().map(|v| v.models.len()).product()
    }

    /// The models of case `index` (one per variation); the last variation changes fastest.
    pub fn combination(&self, index: usize) -> Vec<String> {
        let mut rest = index;
        let mut models = vec![String::new(); self.variations.len()];
        for (slot, variation) in models.iter_mut().zip(&self.variations).rev() {
            let n = variation.models.len();
            *slot = variation.models[rest % n].clone();
            rest /= n;
        }
        models
    }

    /// `main_body.aero=newtonian-scalar left_surface.heat_flux=eckert`.
    pub fn label(&self, models: &[String]) -> String {
        self.variations
            .iter()
            .zip(models)
            .map(|(v, m)| format!("{}={m}", v.key))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The index of the case with `models`.
    fn index_of(&self, models: &[usize]) -> usize {
        self.variations
            .iter()
            .zip(models)
            .fold(0, |acc, (v, &m)| acc * v.models.len() + m)
    }

    /// Looks up every model's registry fidelity (unknown names are an error naming the key).
    pub fn rank(&mut self, registry: &Registry) -> Result<()> {
        for variation in &mut self.variations {
            variation.fidelity = variation
                .models
                .iter()
                .map(|name| registry.get(name).map(|e| e.fidelity))
                .collect::<Result<_, _>>()
                .with_context(|| format!("trade variation `{}`", variation.key))?;
        }
        Ok(())
    }

    /// Registry fidelity of each model of case `index` (0 where not ranked).
    pub fn fidelity(&self, index: usize) -> Vec<u8> {
        let mut rest = index;
        let mut out = vec![0; self.variations.len()];
        for (slot, v) in out.iter_mut().zip(&self.variations).rev() {
            let n = v.models.len();
            *slot = v.fidelity.get(rest % n).copied().unwrap_or(0);
            rest /= n;
        }
        out
    }

    /// The reference case: on every variation the model of highest fidelity (the first listed
    /// on a tie).
    pub fn reference_case(&self) -> usize {
        let picks: Vec<usize> = self
            .variations
            .iter()
            .map(|v| {
                let mut best = 0;
                for (k, f) in v.fidelity.iter().enumerate() {
                    if *f > v.fidelity[best] {
                        best = k;
                    }
                }
                best
            })
            .collect();
        self.index_of(&picks)
    }

    /// The vehicle config of case `index`: `base` with the case's `[regions.*]` names set.
    pub fn config_for(&self, base: &LoadedConfig, index: usize) -> Result<LoadedConfig> {
        let mut raw = base.raw.clone();
        for (variation, model) in self.variations.iter().zip(self.combination(index)) {
            let (region, role) = variation.parts();
            let regions = raw
                .entry("regions")
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .with_context(|| format!("{}: key `regions` must be a table", base.file))?;
            let table = regions
                .entry(region)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .with_context(|| {
                    format!("{}: key `regions.{region}` must be a table", base.file)
                })?;
            table.insert(role.to_owned(), toml::Value::String(model));
        }
        let text = toml::to_string(&raw)
            .with_context(|| format!("{}: cannot write the edited config", base.file))?;
        let file = format!("{} [{}]", base.file, self.label(&self.combination(index)));
        Ok(parse_config(&text, &file)?)
    }
}

impl ShardedStudy for StudySpec {
    const KIND: &'static str = "trade study";

    fn case_count(&self) -> usize {
        StudySpec::case_count(self)
    }
}

/// What one case gave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    pub index: usize,
    /// One model per variation.
    pub models: Vec<String>,
    /// Wall time of the case (config, assembly and job), s.
    pub wall_time_s: f64,
    /// Named results (trim values; final flight state).
    pub values: BTreeMap<String, f64>,
    /// Recorded time histories (`simulate`): `time_s` and [`HISTORY_CHANNELS`].
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub history: BTreeMap<String, Vec<f64>>,
    /// The flutter boundary at each time (`flutter`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub flutter: Vec<FlutterAtTime>,
    /// Why the case failed, if it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

impl ShardedCase for CaseResult {
    fn index(&self) -> usize {
        self.index
    }
}

/// Runs case `index` of `spec` on `base` (configs and plugins as loaded).
pub fn run_case(
    spec: &StudySpec,
    base: &LoadedConfig,
    registry: &Registry,
    index: usize,
) -> CaseResult {
    let start = Instant::now();
    let mut result = CaseResult {
        index,
        models: spec.combination(index),
        wall_time_s: 0.0,
        values: BTreeMap::new(),
        history: BTreeMap::new(),
        flutter: Vec::new(),
        failure: None,
    };
    let outcome = spec
        .config_for(base, index)
        .and_then(|loaded| match spec.job {
            TradeJob::Trim => trim_case(spec, &loaded, registry, &mut result),
            TradeJob::Simulate => simulate_case(spec, &loaded, registry, &mut result),
            TradeJob::Flutter => flutter_case(spec, &loaded, registry, &mut result),
        });
    if let Err(error) = outcome {
        result.failure = Some(crate::error_line::error_line(&error));
    }
    result.wall_time_s = start.elapsed().as_secs_f64();
    result
}

/// The cases of one shard (or of the whole study), as written to [`CASES_FILE`].
pub type TradeCases = ShardOutput<StudySpec, CaseResult>;

/// Name of the per-case results file ([`TradeCases`]) in every trade or shard folder: what
/// `hsv-run merge` joins.
pub const CASES_FILE: &str = "trade-cases.json";

/// Joins trade shard outputs ([`merge_shards`]).
pub fn merge_cases(parts: Vec<(String, TradeCases)>) -> Result<(StudySpec, Vec<CaseResult>)> {
    merge_shards(parts)
}

/// Per-model cost, s, from a `model,seconds` CSV (header line; extra columns ignored).
pub fn read_costs(text: &str, file: &str) -> Result<BTreeMap<String, f64>> {
    let mut costs = BTreeMap::new();
    for (n, line) in text.lines().enumerate().skip(1) {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut fields = line.split(',');
        let (Some(model), Some(seconds)) = (fields.next(), fields.next()) else {
            bail!("{file}: line {}: expected model,seconds", n + 1);
        };
        let seconds: f64 = seconds
            .trim()
            .parse()
            .ok()
            .filter(|s: &f64| s.is_finite() && *s >= 0.0)
            .with_context(|| {
                format!(
                    "{file}: line {}: seconds `{}` must be a non-negative number",
                    n + 1,
                    seconds.trim()
                )
            })?;
        costs.insert(model.trim().to_owned(), seconds);
    }
    Ok(costs)
}

/// One row of the trade table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TradeRow {
    pub case: CaseResult,
    pub label: String,
    /// Registry fidelity of each varied model.
    pub fidelity: Vec<u8>,
    /// Sum of the varied models' costs from `--costs`, s.
    pub model_cost_s: Option<f64>,
    /// |value − reference| of each trim value, or RMS(history − reference) of each channel.
    pub deviations: BTreeMap<String, f64>,
    /// Trim: the largest relative deviation of α, δe, φ (γ for a glide); simulate: the largest
    /// channel RMS deviation over the reference channel's scale, max(RMS, peak-to-peak, floor)
    /// ([`HISTORY_FLOORS`]); flutter: the largest relative deviation of the flutter Mach number
    /// over the times (`flutter_deviation`). `None` when either failed.
    pub error: Option<f64>,
    pub reference: bool,
    /// On the Pareto front of (cost, error): no other case is both cheaper and more accurate.
    pub pareto: bool,
}

/// The study's table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TradeTable {
    pub spec: StudySpec,
    pub reference_case: usize,
    pub rows: Vec<TradeRow>,
}

impl TradeRow {
    /// The cost on the Pareto plot: model cost when known, else wall time.
    pub fn cost_s(&self) -> f64 {
        self.model_cost_s.unwrap_or(self.case.wall_time_s)
    }
}

/// Compares every case with the reference and marks the Pareto front.
pub fn compare(
    spec: &StudySpec,
    cases: Vec<CaseResult>,
    costs: Option<&BTreeMap<String, f64>>,
) -> Result<TradeTable> {
    let reference_case = spec.reference_case();
    let reference = cases
        .iter()
        .find(|c| c.index == reference_case)
        .filter(|c| c.failure.is_none())
        .cloned();
    let mut rows = Vec::with_capacity(cases.len());
    for case in cases {
        let fidelity = spec.fidelity(case.index);
        let model_cost_s = match costs {
            None => None,
            Some(costs) => Some(case.models.iter().try_fold(0.0, |sum, m| {
                costs
                    .get(m)
                    .map(|s| sum + s)
                    .with_context(|| format!("--costs has no row for model `{m}`"))
            })?),
        };
        let (deviations, error) = match (&reference, case.failure.is_none()) {
            (Some(r), true) => deviation(spec.job, &case, r),
            _ => (BTreeMap::new(), None),
        };
        rows.push(TradeRow {
            label: spec.label(&case.models),
            reference: case.index == reference_case,
            fidelity,
            model_cost_s,
            deviations,
            error,
            pareto: false,
            case,
        });
    }
    rows.sort_by_key(|r| r.case.index);
    mark_pareto(&mut rows);
    Ok(TradeTable {
        spec: spec.clone(),
        reference_case,
        rows,
    })
}

/// Deviations of `case` from `reference` and the scalar error ([`TradeRow::error`]).
fn deviation(
    job: TradeJob,
    case: &CaseResult,
    reference: &CaseResult,
) -> (BTreeMap<String, f64>, Option<f64>) {
    let mut deviations = BTreeMap::new();
    let mut error: f64 = 0.0;
    match job {
        TradeJob::Trim => {
            let optional = OPTIONAL_TRIM_QUANTITIES.into_iter().map(|q| {
                let value = |c: &CaseResult| c.values.get(q).copied().unwrap_or(0.0);
                (q, Some(value(case)), Some(value(reference)))
            });
            let required = TRIM_QUANTITIES.into_iter().map(|q| {
                let value = |c: &CaseResult| c.values.get(q).copied();
                (q, value(case), value(reference))
            });
            for (q, v, r) in required.chain(optional) {
                let (Some(v), Some(r)) = (v, r) else {
                    return (deviations, None);
                };
                let d = (v - r).abs();
                deviations.insert(q.to_owned(), d);
                // Relative to the reference value (absolute when it is zero).
                error = error.max(if r != 0.0 { d / r.abs() } else { d });
            }
        }
        TradeJob::Simulate => {
            for (ch, floor) in HISTORY_CHANNELS.into_iter().zip(HISTORY_FLOORS) {
                let (Some(v), Some(r)) = (case.history.get(ch), reference.history.get(ch)) else {
                    return (deviations, None);
                };
                let n = v.len().min(r.len());
                if n == 0 {
                    return (deviations, None);
                }
                // RMS(x − x_ref) over the common samples (both runs record the same times).
                let rms = (v[..n]
                    .iter()
                    .zip(&r[..n])
                    .map(|(a, b)| (a - b).powi(2))
                    .sum::<f64>()
                    / n as f64)
                    .sqrt();
                deviations.insert(ch.to_owned(), rms);
                error = error.max(rms / history_scale(&r[..n], floor));
            }
        }
        TradeJob::Flutter => return flutter_deviation(case, reference),
    }
    (deviations, error.is_finite().then_some(error))
}

/// Scale of a reference history: max(RMS, peak-to-peak, `floor`), so the error is relative to
/// the signal's size or its excursion, whichever is larger.
fn history_scale(reference: &[f64], floor: f64) -> f64 {
    let n = reference.len().max(1) as f64;
    let rms = (reference.iter().map(|x| x * x).sum::<f64>() / n).sqrt();
    let hi = reference.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let lo = reference.iter().copied().fold(f64::INFINITY, f64::min);
    rms.max(hi - lo).max(floor)
}

/// Marks the non-dominated rows of (cost, error): sorted by cost, each row whose error is below
/// every cheaper row's.
fn mark_pareto(rows: &mut [TradeRow]) {
    let mut order: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].error.is_some())
        .collect();
    order.sort_by(|&a, &b| {
        rows[a].cost_s().total_cmp(&rows[b].cost_s()).then(
            rows[a]
                .error
                .unwrap_or(0.0)
                .total_cmp(&rows[b].error.unwrap_or(0.0)),
        )
    });
    let mut best = f64::INFINITY;
    for i in order {
        let e = rows[i].error.unwrap_or(f64::INFINITY);
        if e < best {
            rows[i].pareto = true;
            best = e;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(variations: &[&str]) -> StudySpec {
        StudySpec {
            job: TradeJob::Trim,
            variations: variations.iter().map(|v| v.parse().unwrap()).collect(),
            mach: 6.0,
            altitude_m: 26_000.0,
            flight: None,
            flutter: None,
            config_file: "test".into(),
            config_fingerprint: fingerprint("test"),
        }
    }

    #[test]
    fn combinations_are_the_cartesian_product_last_fastest() {
        let s = spec(&["main_body.aero=a,b", "left_surface.heat_flux=c,d,e"]);
        assert_eq!(s.case_count(), 6);
        assert_eq!(s.combination(0), ["a", "c"]);
        assert_eq!(s.combination(1), ["a", "d"]);
        assert_eq!(s.combination(5), ["b", "e"]);
        assert_eq!(s.index_of(&[1, 2]), 5);
        let mut ranked = s.clone();
        ranked.variations[0].fidelity = vec![1, 3];
        ranked.variations[1].fidelity = vec![2, 2, 1];
        assert_eq!(ranked.reference_case(), 3);
        assert_eq!(ranked.fidelity(5), [3, 1]);
    }

    fn case(index: usize, values: &[(&str, f64)], history: &[(&str, Vec<f64>)]) -> CaseResult {
        CaseResult {
            index,
            models: Vec::new(),
            wall_time_s: 1.0,
            values: values.iter().map(|(k, v)| ((*k).to_owned(), *v)).collect(),
            history: history
                .iter()
                .map(|(k, v)| ((*k).to_owned(), v.clone()))
                .collect(),
            flutter: Vec::new(),
            failure: None,
        }
    }

    /// Hand-computed: trim error = max |Δ|/|ref| = max(0.5/2, 1/4, 0.01/0.1) = 0.25; a history
    /// offset by a constant 0.3 deg from an alpha of 0 ± 1 deg (RMS 1, peak-to-peak 2) has
    /// RMS deviation 0.3 and error 0.3/2 = 0.15; a q that stays at zero is scaled by its floor.
    #[test]
    fn errors_follow_their_definitions() {
        let reference = case(
            0,
            &[
                ("alpha_deg", 2.0),
                ("elevon_deg", -4.0),
                ("fuel_equivalence_ratio", 0.1),
            ],
            &[],
        );
        let other = case(
            1,
            &[
                ("alpha_deg", 1.5),
                ("elevon_deg", -3.0),
                ("fuel_equivalence_ratio", 0.11),
            ],
            &[],
        );
        let (d, e) = deviation(TradeJob::Trim, &other, &reference);
        assert!((e.unwrap() - 0.25).abs() < 1e-12);
        assert!((d["alpha_deg"] - 0.5).abs() < 1e-12);

        let flat = |v: f64| vec![v; 4];
        let history = |alpha: Vec<f64>, q: f64| {
            vec![
                ("altitude_m", flat(26_000.0)),
                ("airspeed_m_s", flat(1800.0)),
                ("alpha_deg", alpha),
                ("pitch_deg", flat(1.0)),
                ("q_deg_s", flat(q)),
            ]
        };
        let reference = case(0, &[], &history(vec![1.0, -1.0, 1.0, -1.0], 0.0));
        let other = case(1, &[], &history(vec![1.3, -0.7, 1.3, -0.7], 0.0));
        let (d, e) = deviation(TradeJob::Simulate, &other, &reference);
        assert!((d["alpha_deg"] - 0.3).abs() < 1e-12);
        assert!((e.unwrap() - 0.15).abs() < 1e-12);
        let q_off = case(1, &[], &history(vec![1.0, -1.0, 1.0, -1.0], 2e-4));
        let (_, e) = deviation(TradeJob::Simulate, &q_off, &reference);
        assert!(
            (e.unwrap() - 0.2).abs() < 1e-12,
            "2e-4 deg/s over the 1e-3 floor"
        );
    }

    #[test]
    fn bad_variations_are_refused() {
        assert!("wing.aero=a".parse::<Variation>().is_err());
        assert!("main_body.lift=a".parse::<Variation>().is_err());
        assert!("main_body.aero=a,a".parse::<Variation>().is_err());
        assert!("main_body.aero".parse::<Variation>().is_err());
    }
}
