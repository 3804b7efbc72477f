//! `hsv-run trade`: a fidelity trade study — every combination of the varied region models run
//! through one job (trim, simulate, flutter) on all cores, each compared with the
//! highest-fidelity combination, with its cost; a shard of it (`--shard K/N`), or a Slurm job
//! array that runs the shards (`--emit-slurm N`, [`super::shared::shard`]). Writes `trade.csv`,
//! `trade.json`, `trade.png` (error against cost, the Pareto front) and `trade-cases.json`
//! (what `hsv-run merge` joins).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;
use rayon::prelude::*;

use super::shared::shard::{ShardArgs, SlurmJob, absolute, emit_slurm};
use super::shared::trade_table::write_table;
use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::analysis::shards::config_fingerprint;
use crate::analysis::trade::{
    CASES_FILE, CaseResult, FlightSpec, FlutterGrid, StudySpec, TradeCases, TradeJob, Variation,
    compare, flutter_region, read_costs, run_case,
};
use crate::outln;
use crate::output::{RunFolder, RunStatus, write_file};

/// Arguments of `hsv-run trade`.
#[derive(Args, Debug, Clone)]
#[command(
    after_help = "CONFIG: a `[trade]` table gives the same: `job = \"trim\"`, \
    `duration_s`, `dt_s`, `record_every`, `mach_range`, `mach_step`, `times_s`, \
    `costs = \"costs.csv\"` and `[trade.vary]` with \
    `\"main_body.aero\" = [\"newtonian-scalar\", \"shock-expansion\"]`; flags override it. \
    CLUSTER: `--emit-slurm N` writes trade-array.sbatch (a Slurm job array of N shards) and \
    submit.sh (submits it, then `hsv-run merge` as a dependent job) into the run folder."
)]
pub struct TradeArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// A varied model key and its models, `<region>.<key>=<model>,<model>,...` (repeatable);
    /// region: main_body, lifting_surfaces, left_surface, right_surface, propulsion; key: aero,
    /// heat_flux, conduction, structure, propulsion.
    #[arg(long = "vary", value_name = "REGION.KEY=MODELS")]
    pub vary: Vec<String>,
    /// What every combination runs (default: the config's `[trade] job`, else trim).
    #[arg(long, value_enum)]
    pub job: Option<TradeJob>,
    /// Freestream Mach number (default: the config's).
    #[arg(long, allow_negative_numbers = true)]
    pub mach: Option<f64>,
    /// Geometric altitude, m (default: the config's; a flutter study: 10 km, as `hsv-run
    /// flutter`).
    #[arg(long = "altitude-m", allow_negative_numbers = true)]
    pub altitude_m: Option<f64>,
    /// Flight time of a simulate study, s (default 2).
    #[arg(long = "duration-s", allow_negative_numbers = true)]
    pub duration_s: Option<f64>,
    /// Aeroelastic step of a simulate study, s (default 0.001, as `hsv-run simulate`); the
    /// conduction step of a flutter study (default 0.1, as `hsv-run flutter`).
    #[arg(long = "dt-s", allow_negative_numbers = true)]
    pub dt_s: Option<f64>,
    /// Steps between recorded samples of a simulate study (default 5).
    #[arg(long = "record-every")]
    pub record_every: Option<usize>,
    /// Mach range of a flutter study's grid, `A:B` (default 2:20).
    #[arg(long = "mach-range", value_name = "A:B")]
    pub mach_range: Option<String>,
    /// Mach step of a flutter study's grid (default 3: a coarser grid than `hsv-run flutter`'s,
    /// the crossing itself is found by root finding).
    #[arg(long = "mach-step", allow_negative_numbers = true)]
    pub mach_step: Option<f64>,
    /// Times in the flow of a flutter study, s, comma separated (default 0,20).
    #[arg(
        long = "times-s",
        value_name = "LIST",
        value_delimiter = ',',
        num_args = 1..,
        allow_negative_numbers = true
    )]
    pub times_s: Vec<f64>,
    /// Angle of attack of a flutter study, deg (default: the config's).
    #[arg(long = "alpha-deg", allow_negative_numbers = true)]
    pub alpha_deg: Option<f64>,
    /// Per-model cost CSV `model,seconds` (scripts/criterion_costs.py writes it from the
    /// benches): a case's cost is the sum over its varied models (default: its wall time,
    /// which varies from run to run).
    #[arg(long, value_name = "FILE")]
    pub costs: Option<PathBuf>,
    #[command(flatten)]
    pub shards: ShardArgs,
    /// Worker threads (default: all cores); 1 gives uncontended wall times.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    #[command(flatten)]
    pub output: OutArgs,
    /// No per-case progress lines.
    #[arg(long)]
    pub quiet: bool,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// The `[trade]` config table.
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct TradeSettings {
    job: Option<TradeJob>,
    #[serde(default)]
    vary: BTreeMap<String, Vec<String>>,
    duration_s: Option<f64>,
    dt_s: Option<f64>,
    record_every: Option<usize>,
    mach_range: Option<String>,
    mach_step: Option<f64>,
    times_s: Option<Vec<f64>>,
    costs: Option<PathBuf>,
}

/// The study the arguments and the config's `[trade]` table define, ranked by `registry`.
fn study(
    args: &TradeArgs,
    loaded: &LoadedConfig,
    registry: &Registry,
) -> Result<(StudySpec, Option<PathBuf>)> {
    let settings: TradeSettings = if loaded.config.trade.is_empty() {
        TradeSettings::default()
    } else {
        hsv_core::config::parse_table(&loaded.config.trade, &loaded.file, "trade")?
    };
    let variations = if args.vary.is_empty() {
        settings
            .vary
            .iter()
            .map(|(key, models)| {
                Variation::new(key, models.clone())
                    .with_context(|| format!("{}: key `trade.vary`", loaded.file))
            })
            .collect::<Result<Vec<_>>>()?
    } else {
        args.vary
            .iter()
            .map(|v| v.parse())
            .collect::<Result<Vec<Variation>>>()?
    };
    if variations.is_empty() {
        bail!(
            "nothing to vary: give --vary <region>.<key>=<model>,<model> (e.g. \
             main_body.aero=newtonian-scalar,shock-expansion) or a [trade.vary] table"
        );
    }
    if let Some(twice) = variations
        .iter()
        .enumerate()
        .find(|(i, v)| variations[..*i].iter().any(|w| w.key == v.key))
    {
        bail!("trade variation `{}` is given twice", twice.1.key);
    }
    let job = args.job.or(settings.job).unwrap_or(TradeJob::Trim);
    let mach = args.mach.unwrap_or(loaded.config.flight.mach);
    let altitude_m = args.altitude_m.unwrap_or(match job {
        TradeJob::Flutter => FLUTTER_ALTITUDE_M,
        _ => loaded.config.flight.altitude_m,
    });
    for (flag, value) in [("--mach", mach), ("--altitude-m", altitude_m)] {
        if !value.is_finite() {
            bail!("{flag} must be a finite number, got {value}");
        }
    }
    let flight = match job {
        TradeJob::Trim | TradeJob::Flutter => None,
        TradeJob::Simulate => {
            let duration_s = args.duration_s.or(settings.duration_s).unwrap_or(2.0);
            let dt_s = args.dt_s.or(settings.dt_s).unwrap_or(0.001);
            super::steps::time_steps(duration_s, dt_s).map_err(|e| {
                anyhow::anyhow!("trade flight of {duration_s} s with steps of {dt_s} s: {e}")
            })?;
            Some(FlightSpec {
                duration_s,
                dt_s,
                record_every: args
                    .record_every
                    .or(settings.record_every)
                    .unwrap_or(5)
                    .max(1),
            })
        }
    };
    let flutter = match job {
        TradeJob::Flutter => Some(flutter_grid(args, &settings, loaded, &variations)?),
        _ => {
            let given = [
                ("--mach-range", args.mach_range.is_some()),
                ("--mach-step", args.mach_step.is_some()),
                ("--times-s", !args.times_s.is_empty()),
                ("--alpha-deg", args.alpha_deg.is_some()),
            ];
            if let Some((flag, _)) = given.iter().find(|(_, g)| *g) {
                bail!(
                    "{flag} is an option of a flutter study (--job flutter), not of {}",
                    job.as_str()
                );
            }
            None
        }
    };
    let mut spec = StudySpec {
        job,
        variations,
        mach,
        altitude_m,
        flight,
        flutter,
        config_file: loaded.file.clone(),
        config_fingerprint: config_fingerprint(loaded),
    };
    spec.rank(registry)?;
    // Every combination's names and roles are checked before any case runs.
    for index in 0..spec.case_count() {
        spec.config_for(loaded, index)?.check_models(registry)?;
    }
    let costs = args.costs.clone().or_else(|| {
        settings.costs.map(
            |c| match args.config.config.as_deref().and_then(Path::parent) {
                Some(base) => base.join(c),
                None => c,
            },
        )
    });
    Ok((spec, costs))
}

/// The paper's flutter altitude (§IV.D), the default of `hsv-run flutter`.
const FLUTTER_ALTITUDE_M: f64 = 10_000.0;

/// The grid of a flutter study: flags, else the `[trade]` table, else 2:20 in steps of 3 at
/// 0 and 20 s.
fn flutter_grid(
    args: &TradeArgs,
    settings: &TradeSettings,
    loaded: &LoadedConfig,
    variations: &[Variation],
) -> Result<FlutterGrid> {
    let range_text = args
        .mach_range
        .clone()
        .or_else(|| settings.mach_range.clone())
        .unwrap_or_else(|| "2:20".to_owned());
    let range = super::parse_mach_range(&range_text)?;
    let mach_step = args.mach_step.or(settings.mach_step).unwrap_or(3.0);
    let machs = super::flutter_mach_grid(range, mach_step)?;
    let times_s = if args.times_s.is_empty() {
        settings.times_s.clone().unwrap_or_else(|| vec![0.0, 20.0])
    } else {
        args.times_s.clone()
    };
    if times_s.is_empty()
        || times_s.iter().any(|t| !(t.is_finite() && *t >= 0.0))
        || times_s.windows(2).any(|w| w[1] <= w[0])
    {
        bail!("--times-s (or `trade.times_s`) must be ascending, finite and >= 0, got {times_s:?}");
    }
    let dt_s = args.dt_s.or(settings.dt_s).unwrap_or(0.1);
    if !(dt_s.is_finite() && dt_s > 0.0) {
        bail!("--dt-s (or `trade.dt_s`) of a flutter study must be a positive number, got {dt_s}");
    }
    super::check_flutter_times(&times_s, dt_s)?;
    let alpha_deg = args.alpha_deg.unwrap_or(loaded.config.flight.alpha_deg);
    crate::limits::check_flow_angle_deg("--alpha-deg", alpha_deg)?;
    Ok(FlutterGrid {
        region: flutter_region(variations)?,
        mach_range: range,
        mach_step,
        machs,
        times_s,
        dt_s,
        alpha_deg,
    })
}

/// Runs the study (or its shard, or writes the Slurm scripts).
pub fn run(args: TradeArgs, registry: &Registry) -> Result<()> {
    crate::limits::check_count(
        "--threads (0: all cores)",
        args.threads,
        0,
        crate::limits::MAX_THREADS,
    )?;
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let (spec, costs_path) = study(&args, &loaded, &registry)?;
    let costs = costs_path
        .as_deref()
        .map(|path| {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read --costs {}", path.display()))?;
            read_costs(&text, &path.display().to_string())
        })
        .transpose()?;
    let mut folder = RunFolder::create("trade", args.output.out.as_deref(), args.output.force)?;
    if let Some(shards) = args.shards.emit_slurm {
        let path = costs_path.as_deref();
        let job = SlurmJob {
            command: "trade",
            what: "trade-study",
            arguments: shard_arguments(&args, &spec, path)?,
            // The merge computes the table, so it needs the same cost file.
            merge_arguments: match path {
                Some(c) => vec!["--costs".to_owned(), absolute(c)?.display().to_string()],
                None => Vec::new(),
            },
            cases: spec.case_count(),
            merge_computes: false,
        };
        return emit_slurm(&args.shards, &job, shards, &mut folder, args.json.json);
    }
    let shard = args.shards.shard()?;
    if spec.job == TradeJob::Simulate {
        // A bad `[simulation]` table fails here, before any case runs.
        crate::analysis::flight::FlightSettings::from_config(&loaded)?;
    }
    let indices = shard.cases(spec.case_count());
    if !args.quiet {
        eprintln!(
            "trade: {} of {} {} cases (shard {}/{}) on {} threads",
            indices.len(),
            spec.case_count(),
            spec.job.as_str(),
            shard.index,
            shard.count,
            if args.threads == 0 {
                rayon::current_num_threads()
            } else {
                args.threads
            }
        );
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .context("cannot start the worker threads")?;
    let cases: Vec<CaseResult> = pool.install(|| {
        indices
            .par_iter()
            .map(|&i| {
                let case = run_case(&spec, &loaded, &registry, i);
                if !args.quiet {
                    eprintln!(
                        "trade: case {i} {} in {:.2} s{}",
                        spec.label(&case.models),
                        case.wall_time_s,
                        case.failure
                            .as_deref()
                            .map(|f| format!(" FAILED: {f}"))
                            .unwrap_or_default()
                    );
                }
                case
            })
            .collect()
    });
    let record = TradeCases {
        spec: spec.clone(),
        shard,
        cases,
    };
    let path = folder.join(CASES_FILE);
    write_file(&path, serde_json::to_string_pretty(&record)?)?;
    folder.record(path);
    if shard.count > 1 {
        let failed = record.cases.iter().filter(|c| c.failure.is_some()).count();
        let summary = serde_json::json!({
            "job": spec.job.as_str(),
            "shard": format!("{}/{}", shard.index, shard.count),
            "cases": record.cases.iter().map(|c| c.index).collect::<Vec<_>>(),
            "failed_cases": failed,
        });
        let written = folder.write_summary(summary, &RunStatus::Completed)?;
        if args.json.json {
            outln!("{}", serde_json::to_string_pretty(&written)?)?;
        } else {
            outln!(
                "shard {}/{}: {} cases ({failed} failed) in {}; join the shard folders with \
                 `hsv-run merge DIR...`",
                shard.index,
                shard.count,
                record.cases.len(),
                folder.path.display()
            )?;
        }
        return Ok(());
    }
    let table = compare(&spec, record.cases, costs.as_ref())?;
    write_table(&mut folder, &table, args.json.json)
}

/// The `hsv-run trade` arguments every shard runs (the study as resolved here, so the shards
/// agree whatever the config's `[trade]` table says).
fn shard_arguments(
    args: &TradeArgs,
    spec: &StudySpec,
    costs: Option<&Path>,
) -> Result<Vec<String>> {
    let mut line = vec!["trade".to_owned()];
    if let Some(config) = &args.config.config {
        line.extend([
            "--config".to_owned(),
            absolute(config)?.display().to_string(),
        ]);
    }
    line.extend(["--job".to_owned(), spec.job.as_str().to_owned()]);
    for v in &spec.variations {
        line.extend([
            "--vary".to_owned(),
            format!("{}={}", v.key, v.models.join(",")),
        ]);
    }
    line.extend([
        "--mach".to_owned(),
        spec.mach.to_string(),
        "--altitude-m".to_owned(),
        spec.altitude_m.to_string(),
    ]);
    if let Some(f) = spec.flight {
        line.extend([
            "--duration-s".to_owned(),
            f.duration_s.to_string(),
            "--dt-s".to_owned(),
            f.dt_s.to_string(),
            "--record-every".to_owned(),
            f.record_every.to_string(),
        ]);
    }
    if let Some(g) = &spec.flutter {
        let times = g.times_s.iter().map(f64::to_string).collect::<Vec<_>>();
        line.extend([
            "--mach-range".to_owned(),
            format!("{}:{}", g.mach_range.0, g.mach_range.1),
            "--mach-step".to_owned(),
            g.mach_step.to_string(),
            format!("--times-s={}", times.join(",")),
            "--dt-s".to_owned(),
            g.dt_s.to_string(),
            "--alpha-deg".to_owned(),
            g.alpha_deg.to_string(),
        ]);
    }
    if let Some(costs) = costs {
        line.extend(["--costs".to_owned(), absolute(costs)?.display().to_string()]);
    }
    Ok(line)
}
