//! `hsv-run rom identify|check`: a region's reduced-order aero model (default `convolution-rom`
//! on the left lifting surface), identified from a named source model.
//!
//! `identify` builds the model, which loads its cache when it was built from the same inputs
//! and otherwise identifies and writes it (`--rebuild` identifies anew regardless), and prints
//! what it was built from. `check` runs the model and its source side by side on prescribed
//! modal motion (each mode alone at its natural frequency, and a random multi-mode motion) and
//! writes the errors, the speed-up, both generalized-force histories (CSV) and a plot of them.
//! The model is asked for its reduced-order capability by name
//! ([`hsv_core::reduced_order::require`]); no model crate is named here.

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use hsv_core::aero::AeroModel;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::reduced_order::{self, CheckOptions, CheckReport, ReducedOrderAero, RomSummary};
use hsv_core::registry::{ModelContext, Registry};
use serde_json::json;

use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::outln;
use crate::output::{LinePlot, RunFolder, RunStatus, Series, write_file, write_line_plots_png};

/// Arguments of `hsv-run rom`.
#[derive(Args, Debug, Clone)]
pub struct RomArgs {
    #[command(subcommand)]
    pub action: RomAction,
}

/// `identify` or `check`.
#[derive(Subcommand, Debug, Clone)]
pub enum RomAction {
    /// Build the reduced model of a region from its source and write or refresh its cache.
    Identify(IdentifyArgs),
    /// Compare the reduced model with its source on prescribed modal motion: error, speed-up,
    /// CSV and plot of both generalized-force histories.
    Check(CheckArgs),
}

/// Which model of which region, from which source.
#[derive(Args, Debug, Clone)]
pub struct RomTarget {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Region: left_surface, right_surface or main_body.
    #[arg(long, default_value = "left_surface")]
    pub region: String,
    /// Reduced-order aero model (registered name).
    #[arg(long, default_value = "convolution-rom")]
    pub model: String,
    /// Source aero model (default: the region's configured aero model, or the reduced model's
    /// own `source` setting when the region already runs the reduced model).
    #[arg(long, value_name = "NAME")]
    pub source: Option<String>,
}

/// Arguments of `hsv-run rom identify`.
#[derive(Args, Debug, Clone)]
pub struct IdentifyArgs {
    #[command(flatten)]
    pub target: RomTarget,
    /// Identify anew even when the cache holds a valid identification.
    #[arg(long)]
    pub rebuild: bool,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// Arguments of `hsv-run rom check`.
#[derive(Args, Debug, Clone)]
pub struct CheckArgs {
    #[command(flatten)]
    pub target: RomTarget,
    /// Mach number of the check (default: the identification's).
    #[arg(long)]
    pub mach: Option<f64>,
    /// Geometric altitude, m (default: the identification's).
    #[arg(long = "altitude-m", allow_negative_numbers = true)]
    pub altitude_m: Option<f64>,
    /// Angle of attack, deg (default: the identification's).
    #[arg(long = "alpha-deg", allow_negative_numbers = true)]
    pub alpha_deg: Option<f64>,
    /// Periods of each sinusoid (of the lowest frequency for the random motion).
    #[arg(long, default_value_t = CheckOptions::default().periods)]
    pub periods: f64,
    /// Time steps per period of the highest frequency of a motion.
    #[arg(long = "steps-per-period", default_value_t = CheckOptions::default().steps_per_period)]
    pub steps_per_period: usize,
    /// Modal amplitude as a fraction of the correction table's largest.
    #[arg(long = "amplitude-fraction", default_value_t = CheckOptions::default().amplitude_fraction)]
    pub amplitude_fraction: f64,
    /// Largest vertex velocity of a motion over the speed of sound (caps the fast modes'
    /// amplitudes).
    #[arg(
        long = "max-velocity-ratio",
        default_value_t = 0.02,
        conflicts_with = "no_velocity_cap"
    )]
    pub max_velocity_ratio: f64,
    /// Every mode at the amplitude fraction, however fast it moves.
    #[arg(long = "no-velocity-cap")]
    pub no_velocity_cap: bool,
    /// Seed of the random multi-mode motion.
    #[arg(long, default_value_t = CheckOptions::default().seed)]
    pub seed: u64,
    /// The linear convolution alone (no nonlinear correction).
    #[arg(long = "no-correction")]
    pub no_correction: bool,
    /// Time the reduced model's generalized forces only (no panel pressures).
    #[arg(long = "forces-only")]
    pub forces_only: bool,
    #[command(flatten)]
    pub out: OutArgs,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// Runs `hsv-run rom`.
pub fn run(args: RomArgs, registry: &Registry) -> Result<()> {
    match args.action {
        RomAction::Identify(args) => identify(args, registry),
        RomAction::Check(args) => check(args, registry),
    }
}

/// The reduced model of the target region built through the registry, with its source set.
fn build(target: &RomTarget, registry: &Registry) -> Result<Box<dyn AeroModel>> {
    let (loaded, registry) = load_config(target.config.config.as_deref(), registry)?;
    let region = loaded.region(&target.region)?;
    let configured = loaded
        .config
        .regions
        .region(&target.region)
        .and_then(|models| models.aero);
    let source = target
        .source
        .clone()
        .or_else(|| configured.filter(|aero| aero != &target.model));
    let plain = region.model_settings(&target.model);
    let mut settings = plain.clone();
    if let Some(source) = &source {
        registry.get(source).with_context(|| "--source")?;
        settings
            .table
            .insert("source".to_owned(), toml::Value::String(source.clone()));
    }
    let create = |settings| {
        registry.create::<dyn AeroModel>(
            &target.model,
            &ModelContext::new(&region, &registry, settings),
        )
    };
    match create(&settings) {
        Ok(model) => Ok(model),
        Err(error) => {
            // Reduced models name their source in `source`; a model that refused the key and
            // builds without it is no reduced model, which is the error to report.
            if source.is_some()
                && let Ok(mut model) = create(&plain)
            {
                reduced_order::require(model.as_mut(), "`hsv-run rom`")?;
            }
            Err(error).with_context(|| format!("building `{}` for {}", target.model, target.region))
        }
    }
}

fn identify(args: IdentifyArgs, registry: &Registry) -> Result<()> {
    let mut model = build(&args.target, registry)?;
    let rom = reduced_order::require(model.as_mut(), "`hsv-run rom identify`")?;
    if args.rebuild && rom.summary().from_cache {
        rom.reidentify()?;
    }
    let summary = rom.summary();
    let flight = rom.reference_flight()?;
    let (stiffness, damping) = rom.linear_coefficients(&flight);
    if args.json.json {
        let value = json!({
            "command": "rom identify",
            "region": args.target.region,
            "rom": summary,
            "aero_stiffness_norm_n_m": stiffness.norm(),
            "aero_damping_norm_n_m_s": damping.norm(),
            "status": RunStatus::Completed.to_json(),
            "files": summary.cache_file.iter().collect::<Vec<_>>(),
        });
        outln!("{}", serde_json::to_string_pretty(&value)?)?;
        return Ok(());
    }
    print_summary(&args.target.region, &summary)?;
    outln!(
        "generalized aero stiffness |dQ/dq| {:.4e} N m, damping |dQ/dq-dot| {:.4e} N m s \
         (Frobenius, at the identification condition)",
        stiffness.norm(),
        damping.norm()
    )?;
    Ok(())
}

fn print_summary(region: &str, s: &RomSummary) -> Result<()> {
    outln!(
        "{} on {region} from `{}` (forces from {}): {} modes, {} panels",
        s.model,
        s.source,
        s.force_origin,
        s.n_modes,
        s.n_panels
    )?;
    outln!(
        "identified at Mach {}, {} m, alpha {} deg; {} response sample(s){}",
        s.mach,
        s.altitude_m,
        s.alpha_deg,
        s.response_samples,
        if s.response_samples > 1 {
            format!(" every {:.4e} s", s.response_dt_s)
        } else {
            " (memoryless source)".to_owned()
        }
    )?;
    if s.correction_mach.is_empty() {
        outln!("no nonlinear correction")?;
    } else {
        outln!(
            "nonlinear correction over Mach {:?} and {} amplitudes per mode",
            s.correction_mach,
            s.correction_amplitudes
        )?;
    }
    let cache = match (&s.cache_file, s.from_cache) {
        (None, _) => "no cache file".to_owned(),
        (Some(f), true) => format!("cache {f} reused (built from the same inputs)"),
        (Some(f), false) => format!(
            "cache {f} written (identified in {:.3} s)",
            s.identification_seconds
        ),
    };
    outln!("{cache}")?;
    Ok(())
}

/// The check's flight: the identification condition with the given overrides.
fn check_flight(rom: &dyn ReducedOrderAero, args: &CheckArgs) -> Result<FlightCondition> {
    let reference = rom.reference_flight()?;
    let f = &reference.freestream;
    let mach = args.mach.unwrap_or(f.mach);
    let altitude_m = args.altitude_m.unwrap_or(f.altitude_m);
    let alpha_deg = args
        .alpha_deg
        .unwrap_or_else(|| reference.alpha_rad.to_degrees());
    if !(mach.is_finite() && mach >= 1.0) {
        bail!("--mach must be finite and >= 1 (supersonic sources), got {mach}");
    }
    if !(alpha_deg.is_finite() && alpha_deg.abs() < 90.0) {
        bail!("--alpha-deg must be finite with |alpha| < 90, got {alpha_deg}");
    }
    let freestream = Freestream::standard(mach, altitude_m, f.gas).context("--altitude-m")?;
    Ok(FlightCondition::steady(
        freestream,
        alpha_deg.to_radians(),
        0.0,
    ))
}

fn check(args: CheckArgs, registry: &Registry) -> Result<()> {
    use crate::limits::{MAX_CHECK_STEPS, check_count};
    check_count(
        "--steps-per-period",
        args.steps_per_period,
        2,
        MAX_CHECK_STEPS,
    )?;
    let response_steps = args.periods * args.steps_per_period as f64;
    if !(args.periods.is_finite() && args.periods > 0.0 && response_steps <= MAX_CHECK_STEPS as f64)
    {
        anyhow::bail!(
            "--periods {} at --steps-per-period {} is {response_steps:.3e} steps per response; --periods must be positive and the limit is {MAX_CHECK_STEPS} steps",
            args.periods,
            args.steps_per_period
        );
    }
    let mut model = build(&args.target, registry)?;
    let rom = reduced_order::require(model.as_mut(), "`hsv-run rom check`")?;
    let flight = check_flight(rom, &args)?;
    let options = CheckOptions {
        periods: args.periods,
        steps_per_period: args.steps_per_period,
        amplitude_fraction: args.amplitude_fraction,
        max_velocity_ratio: (!args.no_velocity_cap).then_some(args.max_velocity_ratio),
        seed: args.seed,
        pressures: !args.forces_only,
    };
    if args.no_correction {
        rom.set_correction(false);
    }
    let summary = rom.summary();
    let mut folder = RunFolder::create("rom-check", args.out.out.as_deref(), args.out.force)?;
    let partial = json!({"command": "rom check", "region": args.target.region, "rom": summary});
    let report = folder.run(
        |folder| {
            let report = rom.check(&flight, &options)?;
            write_outputs(folder, &report, summary.n_modes)?;
            Ok(report)
        },
        || partial.clone(),
    )?;
    let value = json!({
        "command": "rom check",
        "region": args.target.region,
        "rom": summary,
        "check_options": options,
        "mach": report.mach,
        "altitude_m": report.altitude_m,
        "alpha_deg": report.alpha_deg,
        "correction": report.correction,
        "worst_relative_rms_error": report.worst_relative_rms_error(),
        "overall_speedup": report.overall_speedup(),
        "steady_value_s": report.steady_value_seconds,
        "motions": report.motions.iter().map(|m| json!({
            "name": m.name,
            "relative_rms_error": m.relative_rms_error,
            "relative_max_error": m.relative_max_error,
            "steps": m.steps,
            "dt_s": m.dt_s,
            "source_s_per_step": m.source_seconds_per_step,
            "rom_s_per_step": m.rom_seconds_per_step,
            "speedup": m.speedup,
        })).collect::<Vec<_>>(),
    });
    let written = folder.write_summary(value, &RunStatus::Completed)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
        return Ok(());
    }
    print_summary(&args.target.region, &summary)?;
    print_report(&report)?;
    outln!("outputs in {}", folder.path.display())?;
    Ok(())
}

fn print_report(report: &CheckReport) -> Result<()> {
    outln!(
        "check at Mach {}, {} m, alpha {} deg, correction {}",
        report.mach,
        report.altitude_m,
        report.alpha_deg,
        if report.correction { "on" } else { "off" }
    )?;
    outln!(
        "{:<28} {:>11} {:>11} {:>6} {:>12} {:>12} {:>9}",
        "motion",
        "rel. RMS",
        "rel. max",
        "steps",
        "source s/st",
        "ROM s/step",
        "speed-up"
    )?;
    for m in &report.motions {
        outln!(
            "{:<28} {:>11.3e} {:>11.3e} {:>6} {:>12.3e} {:>12.3e} {:>9.1}",
            m.name,
            m.relative_rms_error,
            m.relative_max_error,
            m.steps,
            m.source_seconds_per_step,
            m.rom_seconds_per_step,
            m.speedup
        )?;
    }
    outln!(
        "worst relative RMS error {:.3e}, overall speed-up {:.1} (steady value once per \
         condition: {:.3e} s)",
        report.worst_relative_rms_error(),
        report.overall_speedup(),
        report.steady_value_seconds
    )?;
    Ok(())
}

/// `rom-check.csv` (both histories of every motion), `rom-check-motions.csv` (errors and
/// costs) and `rom-check.png`.
fn write_outputs(folder: &mut RunFolder, report: &CheckReport, n_modes: usize) -> Result<()> {
    let mut header = vec!["motion".to_owned(), "time_s".to_owned()];
    for who in ["source", "rom"] {
        header.extend((1..=n_modes).map(|k| format!("{who}_generalized_force_{k}_n_m")));
    }
    let mut text = header.join(",") + "\n";
    for (i, m) in report.motions.iter().enumerate() {
        for (step, t) in m.time_s.iter().enumerate() {
            let values = m.source_generalized_forces[step]
                .iter()
                .chain(&m.rom_generalized_forces[step])
                .map(|v| format!("{v:.9e}"));
            let row: Vec<String> = [i.to_string(), format!("{t:.9e}")]
                .into_iter()
                .chain(values)
                .collect();
            text += &(row.join(",") + "\n");
        }
    }
    let path = folder.join("rom-check.csv");
    write_file(&path, text)?;
    folder.record(path);
    let mut table = String::from(
        "motion,name,relative_rms_error,relative_max_error,steps,dt_s,source_s_per_step,rom_s_per_step,speedup\n",
    );
    for (i, m) in report.motions.iter().enumerate() {
        table += &format!(
            "{i},{},{:e},{:e},{},{:e},{:e},{:e},{:e}\n",
            m.name,
            m.relative_rms_error,
            m.relative_max_error,
            m.steps,
            m.dt_s,
            m.source_seconds_per_step,
            m.rom_seconds_per_step,
            m.speedup
        );
    }
    let path = folder.join("rom-check-motions.csv");
    write_file(&path, table)?;
    folder.record(path);
    let plots: Vec<LinePlot> = report.motions.iter().map(motion_plot).collect();
    let columns = 4.min(plots.len()).max(1);
    let rows = plots.len().div_ceil(columns) as u32;
    let path = folder.join("rom-check.png");
    write_line_plots_png(&path, &plots, columns, (500 * columns as u32, 320 * rows))?;
    folder.record(path);
    Ok(())
}

/// One motion's panel: the source's and the ROM's generalized force of the mode whose force
/// moves most.
fn motion_plot(m: &hsv_core::reduced_order::MotionReport) -> LinePlot {
    let n = m.source_generalized_forces.first().map_or(0, Vec::len);
    let swing = |k: usize| {
        let values = m.source_generalized_forces.iter().map(|q| q[k]);
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        hi - lo
    };
    let k = (0..n)
        .max_by(|a, b| swing(*a).total_cmp(&swing(*b)))
        .unwrap_or(0);
    let series = |label: &str, forces: &[Vec<f64>]| Series {
        label: format!("{label} Q{}", k + 1),
        x: m.time_s.clone(),
        y: forces
            .iter()
            .map(|q| q.get(k).copied().unwrap_or(0.0))
            .collect(),
    };
    LinePlot {
        title: format!("{} (RMS err {:.1e})", m.name, m.relative_rms_error),
        x_label: "time (s)".to_owned(),
        y_label: format!("Q{} (N m)", k + 1),
        series: vec![
            series("source", &m.source_generalized_forces),
            series("ROM", &m.rom_generalized_forces),
        ],
    }
}
