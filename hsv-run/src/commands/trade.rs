//! `hsv-run trade`: a fidelity trade study — every combination of the varied region models run
//! through one job on all cores, each compared with the highest-fidelity combination, with its
//! cost; a shard of it (`--shard K/N`), or a Slurm job array that runs the shards
//! (`--emit-slurm N`). Writes `trade.csv`, `trade.json`, `trade.png` (error against cost, the
//! Pareto front) and `trade-cases.json` (what `hsv-run merge` joins).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;
use rayon::prelude::*;

use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::analysis::simulate::Inputs;
use crate::analysis::trade::{
    CaseResult, FlightSpec, Shard, StudySpec, TradeCases, TradeJob, TradeTable, Variation, compare,
    fingerprint, read_costs, run_case,
};
use crate::outln;
use crate::output::{
    LinePlot, LineStyle, RunFolder, RunStatus, Series, StyledPlot, write_file,
    write_styled_plots_png,
};

/// Name of the per-case results file in every trade or shard folder.
pub const CASES_FILE: &str = "trade-cases.json";

/// Arguments of `hsv-run trade`.
#[derive(Args, Debug, Clone)]
#[command(
    after_help = "CONFIG: a `[trade]` table gives the same: `job = \"trim\"`, \
    `duration_s`, `dt_s`, `record_every`, `costs = \"costs.csv\"` and `[trade.vary]` with \
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
    /// Geometric altitude, m (default: the config's).
    #[arg(long = "altitude-m", allow_negative_numbers = true)]
    pub altitude_m: Option<f64>,
    /// Flight time of a simulate study, s (default 2).
    #[arg(long = "duration-s", allow_negative_numbers = true)]
    pub duration_s: Option<f64>,
    /// Aeroelastic step of a simulate study, s (default 0.0005, as `hsv-run simulate`).
    #[arg(long = "dt-s", allow_negative_numbers = true)]
    pub dt_s: Option<f64>,
    /// Steps between recorded samples of a simulate study (default 5).
    #[arg(long = "record-every")]
    pub record_every: Option<usize>,
    /// Per-model cost CSV `model,seconds` (scripts/criterion_costs.py writes it from the
    /// benches): a case's cost is the sum over its varied models (default: its wall time,
    /// which varies from run to run).
    #[arg(long, value_name = "FILE")]
    pub costs: Option<PathBuf>,
    /// Run only shard K of N (0-based; case i belongs to shard i mod N); join the shard folders
    /// with `hsv-run merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Worker threads (default: all cores); 1 gives uncontended wall times.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Write a Slurm job-array script running N shards (and submit.sh, which also queues the
    /// merge) instead of running.
    #[arg(long = "emit-slurm", value_name = "N", conflicts_with = "shard")]
    pub emit_slurm: Option<usize>,
    /// `#SBATCH --cpus-per-task` of each shard.
    #[arg(long = "slurm-cpus", default_value_t = 8)]
    pub slurm_cpus: usize,
    /// `#SBATCH --time` of each shard.
    #[arg(long = "slurm-time", default_value = "02:00:00")]
    pub slurm_time: String,
    /// `#SBATCH --partition` (default: the cluster's).
    #[arg(long = "slurm-partition")]
    pub slurm_partition: Option<String>,
    /// The hsv-run the cluster runs (default: this executable).
    #[arg(long = "hsv-run", value_name = "PATH")]
    pub hsv_run: Option<PathBuf>,
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
    let altitude_m = args.altitude_m.unwrap_or(loaded.config.flight.altitude_m);
    for (flag, value) in [("--mach", mach), ("--altitude-m", altitude_m)] {
        if !value.is_finite() {
            bail!("{flag} must be a finite number, got {value}");
        }
    }
    let flight = match job {
        TradeJob::Trim => None,
        TradeJob::Simulate => {
            let duration_s = args.duration_s.or(settings.duration_s).unwrap_or(2.0);
            let dt_s = args.dt_s.or(settings.dt_s).unwrap_or(0.0005);
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
    let config_text = toml::to_string(&loaded.raw).unwrap_or_default();
    let mut spec = StudySpec {
        job,
        variations,
        mach,
        altitude_m,
        flight,
        config_file: loaded.file.clone(),
        config_fingerprint: fingerprint(&config_text),
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

/// Runs the study (or its shard, or writes the Slurm scripts).
pub fn run(args: TradeArgs, registry: &Registry) -> Result<()> {
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
    if let Some(shards) = args.emit_slurm {
        return emit_slurm(&args, &spec, costs_path.as_deref(), shards, &mut folder);
    }
    let shard = args
        .shard
        .as_deref()
        .map(str::parse)
        .transpose()?
        .unwrap_or(Shard::ALL);
    let inputs = match spec.job {
        TradeJob::Simulate => super::simulate::inputs(&loaded)?,
        TradeJob::Trim => Inputs::paper_doublet(),
    };
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
                let case = run_case(&spec, &loaded, &registry, &inputs, i);
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

/// Writes `trade.csv`, `trade.json`, `trade.png` and `summary.json`, and prints the table (or
/// the summary with `json`). Shared with `hsv-run merge`.
pub fn write_table(folder: &mut RunFolder, table: &TradeTable, json: bool) -> Result<()> {
    let csv = folder.join("trade.csv");
    write_file(&csv, table_csv(table))?;
    folder.record(csv);
    let path = folder.join("trade.json");
    write_file(&path, serde_json::to_string_pretty(&table_json(table))?)?;
    folder.record(path);
    let png = folder.join("trade.png");
    write_pareto_png(&png, table)?;
    folder.record(png);
    let failed = table
        .rows
        .iter()
        .filter(|r| r.case.failure.is_some())
        .count();
    let summary = serde_json::json!({
        "job": table.spec.job.as_str(),
        "cases": table.rows.len(),
        "failed_cases": failed,
        "reference_case": table.reference_case,
        "pareto_cases": table.rows.iter().filter(|r| r.pareto).map(|r| r.case.index).collect::<Vec<_>>(),
    });
    let status = if failed == table.rows.len() {
        RunStatus::Failed("every case failed".to_owned())
    } else {
        RunStatus::Completed
    };
    let written = folder.write_summary(summary, &status)?;
    if json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
    } else {
        print_table(table)?;
        outln!("outputs in {}", folder.path.display())?;
    }
    Ok(())
}

/// Names of the value columns: every value any case reports, sorted.
fn value_names(table: &TradeTable) -> Vec<String> {
    let mut names: Vec<String> = table
        .rows
        .iter()
        .flat_map(|r| r.case.values.keys().cloned())
        .collect();
    names.sort();
    names.dedup();
    names
}

/// Names of the deviation columns.
fn deviation_names(table: &TradeTable) -> Vec<String> {
    let mut names: Vec<String> = table
        .rows
        .iter()
        .flat_map(|r| r.deviations.keys().cloned())
        .collect();
    names.sort();
    names.dedup();
    names
}

fn number(value: Option<f64>) -> String {
    value.map_or_else(String::new, |v| format!("{v:.9e}"))
}

/// The table as CSV: one row per case; units in the headers; failures leave cells empty.
pub fn table_csv(table: &TradeTable) -> String {
    let values = value_names(table);
    let deviations = deviation_names(table);
    let deviation_label = match table.spec.job {
        TradeJob::Trim => "abs_deviation",
        TradeJob::Simulate => "rms_deviation",
    };
    let mut text = String::from(
        "case,combination,reference,pareto,fidelity_sum,wall_time_s,model_cost_s,error",
    );
    for v in &values {
        let _ = write!(text, ",{v}");
    }
    for d in &deviations {
        let _ = write!(text, ",{deviation_label}_{d}");
    }
    text.push_str(",failure\n");
    for row in &table.rows {
        let fidelity: u32 = row.fidelity.iter().map(|&f| u32::from(f)).sum();
        let _ = write!(
            text,
            "{},\"{}\",{},{},{fidelity},{:.6e},{},{}",
            row.case.index,
            row.label,
            row.reference,
            row.pareto,
            row.case.wall_time_s,
            number(row.model_cost_s),
            number(row.error)
        );
        for v in &values {
            let _ = write!(text, ",{}", number(row.case.values.get(v).copied()));
        }
        for d in &deviations {
            let _ = write!(text, ",{}", number(row.deviations.get(d).copied()));
        }
        let failure = row.case.failure.as_deref().unwrap_or("").replace('"', "'");
        let _ = writeln!(text, ",\"{failure}\"");
    }
    text
}

/// The table as JSON (histories left out: they are in `trade-cases.json`).
pub fn table_json(table: &TradeTable) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = table
        .rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "case": r.case.index,
                "combination": r.label,
                "models": r.case.models,
                "fidelity": r.fidelity,
                "reference": r.reference,
                "pareto": r.pareto,
                "wall_time_s": r.case.wall_time_s,
                "model_cost_s": r.model_cost_s,
                "error": r.error,
                "values": r.case.values,
                "deviations": r.deviations,
                "failure": r.case.failure,
            })
        })
        .collect();
    serde_json::json!({
        "job": table.spec.job.as_str(),
        "study": table.spec,
        "reference_case": table.reference_case,
        "error_definition": match table.spec.job {
            TradeJob::Trim => "max over alpha, elevon, phi of |value - reference| / |reference|",
            TradeJob::Simulate => "max over altitude, airspeed, alpha, pitch, q of RMS(history - reference) / max(RMS(reference), peak-to-peak(reference), floor); floors 0.01 m, 0.01 m/s, 0.001 deg, 0.001 deg, 0.001 deg/s",
        },
        "rows": rows,
    })
}

/// Error against cost: every case as a marker, the Pareto front as a line; cost on a log10 axis.
fn write_pareto_png(path: &Path, table: &TradeTable) -> Result<()> {
    let point =
        |r: &crate::analysis::trade::TradeRow| (r.cost_s().log10(), r.error.unwrap_or(f64::NAN));
    let (x, y): (Vec<f64>, Vec<f64>) = table.rows.iter().map(point).unzip();
    let mut front: Vec<(f64, f64)> = table.rows.iter().filter(|r| r.pareto).map(point).collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    // A staircase: each front point's error holds until the next, cheaper-to-better step.
    let mut stairs: Vec<(f64, f64)> = Vec::with_capacity(2 * front.len());
    for (i, p) in front.iter().enumerate() {
        if i > 0 {
            stairs.push((p.0, front[i - 1].1));
        }
        stairs.push(*p);
    }
    let (fx, fy): (Vec<f64>, Vec<f64>) = stairs.into_iter().unzip();
    let cost = if table.rows.iter().any(|r| r.model_cost_s.is_some()) {
        "log10 model cost (s)"
    } else {
        "log10 wall time (s)"
    };
    let plot = StyledPlot {
        plot: LinePlot {
            title: format!(
                "Fidelity trade ({}): error against cost",
                table.spec.job.as_str()
            ),
            x_label: cost.to_owned(),
            y_label: "error vs highest fidelity (-)".to_owned(),
            series: vec![
                Series {
                    label: "cases".to_owned(),
                    x,
                    y,
                },
                Series {
                    label: "Pareto front".to_owned(),
                    x: fx,
                    y: fy,
                },
            ],
        },
        styles: vec![
            LineStyle {
                colour: 0,
                markers_only: true,
                ..LineStyle::default()
            },
            LineStyle {
                colour: 1,
                ..LineStyle::default()
            },
        ],
    };
    write_styled_plots_png(path, &[plot], 1, (900, 600))
}

/// The table on standard output.
fn print_table(table: &TradeTable) -> Result<()> {
    let spec = &table.spec;
    outln!(
        "Fidelity trade study: {} at Mach {}, {} m; {} cases, reference (highest fidelity) case {}",
        spec.job.as_str(),
        spec.mach,
        spec.altitude_m,
        table.rows.len(),
        table.reference_case
    )?;
    let shown: Vec<(&str, &str)> = match spec.job {
        TradeJob::Trim => vec![
            ("alpha_deg", "alpha (deg)"),
            ("elevon_deg", "elevon (deg)"),
            ("fuel_equivalence_ratio", "phi"),
        ],
        TradeJob::Simulate => vec![
            ("trim_alpha_deg", "trim alpha"),
            ("final_altitude_m", "final alt (m)"),
            ("final_alpha_deg", "final alpha"),
        ],
    };
    let mut header = format!(
        "{:>4} {:>3} {:>8} {:>11} {:>11}",
        "case", "fid", "mark", "wall (s)", "cost (s)"
    );
    let _ = write!(header, " {:>11}", "error");
    for (_, title) in &shown {
        let _ = write!(header, " {title:>14}");
    }
    header.push_str("  combination");
    outln!("{header}")?;
    for row in &table.rows {
        let fidelity: u32 = row.fidelity.iter().map(|&f| u32::from(f)).sum();
        let mark = match (row.reference, row.pareto) {
            (true, true) => "ref,pf",
            (true, false) => "ref",
            (false, true) => "pf",
            _ => "",
        };
        let cell = |v: Option<f64>, w: usize| {
            v.map_or_else(|| format!("{:>w$}", "-"), |v| format!("{v:>w$.4e}"))
        };
        let mut line = format!(
            "{:>4} {fidelity:>3} {mark:>8} {:>11.4} {}",
            row.case.index,
            row.case.wall_time_s,
            cell(row.model_cost_s, 11)
        );
        let _ = write!(line, " {}", cell(row.error, 11));
        for (key, _) in &shown {
            let v = row.case.values.get(*key).copied();
            let _ = write!(
                line,
                " {}",
                v.map_or_else(|| format!("{:>14}", "-"), |v| format!("{v:>14.6}"))
            );
        }
        let _ = write!(line, "  {}", row.label);
        if let Some(f) = &row.case.failure {
            let _ = write!(line, "  FAILED: {f}");
        }
        outln!("{line}")?;
    }
    outln!(
        "error: {}; pf = on the Pareto front of (cost, error)",
        match spec.job {
            TradeJob::Trim => "largest relative deviation of alpha, elevon, phi from the reference",
            TradeJob::Simulate =>
                "largest RMS deviation of altitude, airspeed, alpha, pitch, q relative to the reference's size (max of its RMS and peak-to-peak)",
        }
    )?;
    Ok(())
}

/// `'text'` for a POSIX shell.
fn shell_quote(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=,:+".contains(c));
    if plain {
        text.to_owned()
    } else {
        format!("'{}'", text.replace('\'', "'\\''"))
    }
}

/// An absolute form of `path` for a script that runs elsewhere.
fn absolute(path: &Path) -> Result<PathBuf> {
    std::path::absolute(path).with_context(|| format!("cannot resolve the path {}", path.display()))
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
    if let Some(costs) = costs {
        line.extend(["--costs".to_owned(), absolute(costs)?.display().to_string()]);
    }
    Ok(line)
}

/// The Slurm job-array script of `shards` shards and the submit script that queues it and the
/// dependent merge.
pub fn slurm_scripts(
    program: &str,
    arguments: &[String],
    merge_arguments: &[String],
    shards: usize,
    cpus: usize,
    time: &str,
    partition: Option<&str>,
) -> (String, String) {
    let command = std::iter::once(program.to_owned())
        .chain(arguments.iter().cloned())
        .map(|a| shell_quote(&a))
        .collect::<Vec<_>>()
        .join(" ");
    let mut array = String::new();
    let _ = writeln!(array, "#!/bin/bash");
    let _ = writeln!(
        array,
        "# Generated by `hsv-run trade --emit-slurm {shards}`: one trade-study shard per array task."
    );
    let _ = writeln!(
        array,
        "# Submit with `bash submit.sh` (queues this array and the dependent merge)."
    );
    let _ = writeln!(array, "#SBATCH --job-name=hsv-trade");
    let _ = writeln!(array, "#SBATCH --array=0-{}", shards - 1);
    let _ = writeln!(array, "#SBATCH --ntasks=1");
    let _ = writeln!(array, "#SBATCH --cpus-per-task={cpus}");
    let _ = writeln!(array, "#SBATCH --time={time}");
    if let Some(p) = partition {
        let _ = writeln!(array, "#SBATCH --partition={p}");
    }
    let _ = writeln!(array, "#SBATCH --output=slurm-%A_%a.out");
    let _ = writeln!(array, "set -euo pipefail");
    let _ = writeln!(
        array,
        "{command} --threads \"${{SLURM_CPUS_PER_TASK:-{cpus}}}\" --quiet \\\n    --shard \"${{SLURM_ARRAY_TASK_ID}}/{shards}\" --out \"shard-${{SLURM_ARRAY_TASK_ID}}\" --force"
    );
    let shard_dirs = (0..shards)
        .map(|k| format!("shard-{k}"))
        .collect::<Vec<_>>()
        .join(" ");
    let merge = std::iter::once(shell_quote(program))
        .chain([
            "merge".to_owned(),
            shard_dirs,
            "--out merged --force".to_owned(),
        ])
        .chain(merge_arguments.iter().map(|a| shell_quote(a)))
        .collect::<Vec<_>>()
        .join(" ");
    let mut submit = String::new();
    let _ = writeln!(submit, "#!/bin/bash");
    let _ = writeln!(
        submit,
        "# Generated by `hsv-run trade --emit-slurm {shards}`: queues the {shards}-shard array, then the merge once every shard succeeded."
    );
    let _ = writeln!(submit, "set -euo pipefail");
    let _ = writeln!(submit, "cd \"$(dirname \"$0\")\"");
    let _ = writeln!(submit, "array_job=$(sbatch --parsable trade-array.sbatch)");
    let _ = writeln!(
        submit,
        "merge_job=$(sbatch --parsable --dependency=afterok:${{array_job}} --job-name=hsv-trade-merge \\\n    --ntasks=1 --cpus-per-task=1 --time=00:30:00{} --output=slurm-merge-%j.out \\\n    --wrap {})",
        partition
            .map(|p| format!(" --partition={p}"))
            .unwrap_or_default(),
        shell_quote(&merge)
    );
    let _ = writeln!(
        submit,
        "echo \"queued shards as job ${{array_job}}, merge as job ${{merge_job}}; results in $(pwd)/merged\""
    );
    (array, submit)
}

/// Writes `trade-array.sbatch` and `submit.sh` into the run folder.
fn emit_slurm(
    args: &TradeArgs,
    spec: &StudySpec,
    costs: Option<&Path>,
    shards: usize,
    folder: &mut RunFolder,
) -> Result<()> {
    if shards == 0 {
        bail!("--emit-slurm must be at least 1 shard, got 0");
    }
    let cases = spec.case_count();
    if shards > cases {
        bail!(
            "--emit-slurm {shards}: the study has only {cases} cases; use at most {cases} shards"
        );
    }
    let program = match &args.hsv_run {
        Some(p) => absolute(p)?,
        None => std::env::current_exe().context("cannot find this executable's path")?,
    };
    let arguments = shard_arguments(args, spec, costs)?;
    // The merge computes the table, so it needs the same cost file.
    let merge_arguments = match costs {
        Some(c) => vec!["--costs".to_owned(), absolute(c)?.display().to_string()],
        None => Vec::new(),
    };
    let (array, submit) = slurm_scripts(
        &program.display().to_string(),
        &arguments,
        &merge_arguments,
        shards,
        args.slurm_cpus.max(1),
        &args.slurm_time,
        args.slurm_partition.as_deref(),
    );
    let array_path = folder.join("trade-array.sbatch");
    write_file(&array_path, &array)?;
    folder.record(array_path.clone());
    let submit_path = folder.join("submit.sh");
    write_file(&submit_path, &submit)?;
    folder.record(submit_path.clone());
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let _ = std::fs::set_permissions(&submit_path, std::fs::Permissions::from_mode(0o755));
    }
    let summary = serde_json::json!({
        "job": spec.job.as_str(),
        "cases": cases,
        "shards": shards,
        "array_script": array_path.display().to_string(),
        "submit_script": submit_path.display().to_string(),
    });
    let written = folder.write_summary(summary, &RunStatus::Completed)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
    } else {
        outln!("{array}")?;
        outln!(
            "wrote {} and {} ({cases} cases in {shards} shards); on the cluster run `bash {}`",
            array_path.display(),
            submit_path.display(),
            submit_path.display()
        )?;
    }
    Ok(())
}
