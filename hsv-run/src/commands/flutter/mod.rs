//! `hsv-run flutter`: flutter of the heated lifting surface versus time in the flow (paper
//! §IV.D, Figs. 14-16), or with `--panel` the classical simply supported panel under piston
//! theory (Dowell's λ). The analysis is [`crate::analysis::flutter`]; this module is its CLI
//! and outputs.
//!
//! At each Mach number of the grid (`--mach-range A:B` in steps of `--mach-step`) the right
//! lifting surface starts at 293 K and heats in that flow; at each time of `--times-s` its
//! linear state matrix is identified around its equilibrium and its eigenvalues decide
//! stability. At each time the flutter Mach number (an oscillatory pair crosses, reported with
//! its frequency and the mode it grows from) and, apart from it, the divergence Mach number (a
//! real root crosses: static divergence or thermal buckling in the flow) are each found by
//! Brent's method between the grid points that bracket that kind's crossing. Defaults: 10 km,
//! Mach 2 to 40 in steps of 1 (the range holds the sample surface's cold crossing, whose
//! thickness is calibrated to the paper's 16.1: see `configs/sample-hsv.toml`), times 0, 1, 2,
//! 5, 10, 20, ..., 100 s (the boundary falls fastest in the first seconds), full-order
//! conduction (no POD training), the direct state derivative with the paper's forward
//! difference compared at every grid point.

mod shard;

use std::path::Path;

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use hsv_core::aero::AeroModel;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::{ModelContext, Registry};
use serde_json::json;

use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::analysis::flutter::Instability;
use crate::analysis::flutter::panel::{SimplySupportedPanel, panel_flutter};
use crate::analysis::flutter::sweep::{
    FlutterBoundary, FlutterMap, FlutterModels, FlutterPoint, FlutterSetup, PointStatus,
    flutter_map, status_text,
};
use crate::analysis::flutter::{DerivativeMethod, FlutterError, SurfaceOptions};
use crate::analysis::heating::HeatingSteps;
use crate::outln;
use crate::output::{self, LinePlot, RunFolder, RunStatus, Series};

/// Default times in the flow, s: the paper's 0 to 100 s, with the first seconds resolved.
const DEFAULT_TIMES_S: [f64; 14] = [
    0.0, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0,
];

/// The analysed lifting surface: the right one (the left is its mirror image).
const SURFACE_REGION: &str = "right_surface";

/// `--derivative`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DerivativeChoice {
    /// The state derivative from the equations of motion.
    Direct,
    /// The paper's sixth-order forward difference over 7 steps of the surface simulation.
    ForwardDifference,
}

/// Arguments of `hsv-run flutter`.
#[derive(Args, Debug, Clone)]
pub struct FlutterArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Geometric altitude, m (paper: 10 km).
    #[arg(
        long = "altitude-m",
        default_value_t = 10_000.0,
        allow_negative_numbers = true
    )]
    pub altitude_m: f64,
    /// Mach range of the grid, `A:B`.
    #[arg(long = "mach-range", value_name = "A:B", default_value = "2:40")]
    pub mach_range: String,
    /// Mach step of the grid.
    #[arg(
        long = "mach-step",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    pub mach_step: f64,
    /// Times in the flow, s, comma separated (default 0, 1, 2, 5, 10, 20, ..., 100).
    #[arg(
        long = "times-s",
        value_name = "LIST",
        value_delimiter = ',',
        num_args = 1..,
        allow_negative_numbers = true
    )]
    pub times_s: Vec<f64>,
    /// Aero model (default: the config's lifting-surface model, `shock-expansion-piston` in the
    /// sample; `piston-theory` with --panel).
    #[arg(long = "aero", value_name = "NAME")]
    pub aero: Option<String>,
    /// Heat-flux model (default: the config's lifting-surface model, else eckert).
    #[arg(long = "heat-flux", value_name = "NAME")]
    pub heat_flux: Option<String>,
    /// Conduction model (default full-order; `pod` trains or reuses its basis file).
    #[arg(long = "conduction", value_name = "NAME", default_value = "full-order")]
    pub conduction: String,
    /// Conduction time step of the heating, s.
    #[arg(long = "dt-s", default_value_t = 0.1, allow_negative_numbers = true)]
    pub dt_s: f64,
    /// Angle of attack, deg (default: the config's).
    #[arg(long = "alpha-deg", allow_negative_numbers = true)]
    pub alpha_deg: Option<f64>,
    /// State derivative of the identification.
    #[arg(long = "derivative", value_enum, default_value = "direct")]
    pub derivative: DerivativeChoice,
    /// Skip identifying A with the other derivative method at each grid point.
    #[arg(long = "no-compare")]
    pub no_compare: bool,
    /// Classical panel flutter instead: a simply supported rectangular Ti-6Al-4V panel under
    /// piston theory without aerodynamic damping; reports q and λ = 2 q a³ / (β D).
    #[arg(long)]
    pub panel: bool,
    /// Panel chord (streamwise), m.
    #[arg(long = "panel-chord-m", default_value_t = 0.5, requires = "panel")]
    pub panel_chord_m: f64,
    /// Panel span, m.
    #[arg(long = "panel-span-m", default_value_t = 0.5, requires = "panel")]
    pub panel_span_m: f64,
    /// Panel thickness, m.
    #[arg(
        long = "panel-thickness-m",
        default_value_t = 0.002,
        requires = "panel"
    )]
    pub panel_thickness_m: f64,
    /// Panel free-vibration modes in the basis.
    #[arg(long = "panel-modes", default_value_t = 17, requires = "panel")]
    pub panel_modes: usize,
    /// Panel elements each way.
    #[arg(long = "panel-elements", default_value_t = 20, requires = "panel")]
    pub panel_elements: usize,
    #[command(flatten)]
    pub out: OutArgs,
    #[command(flatten)]
    pub json: JsonFlag,
    /// `--shard K/N` (a share of the Mach columns) and `--emit-slurm N`.
    #[command(flatten)]
    pub shards: super::shard::ShardArgs,
}

/// Runs the flutter analysis and writes the run folder.
pub fn run(args: FlutterArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let machs = map_machs(&args)?;
    if args.panel && args.shards.is_sharded() {
        bail!("--shard and --emit-slurm split the flutter map over Mach; --panel is one check");
    }
    if args.panel {
        return run_panel(&args, &loaded, &registry, &machs);
    }
    let (setup, times) = map_setup(&args, &loaded)?;
    if args.shards.is_sharded() {
        return shard::run_shard(&args, &loaded, &registry, &setup, &machs, &times);
    }
    let (folder, map, summary) = map_run(&args, &setup, &registry, &machs, &times)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
        return Ok(());
    }
    print_table(&setup, &map, &folder.path)
}

/// The flutter map `args` asks for on `loaded` (`args.config` is not read), its run folder
/// written: the `--json` summary. What Python's `hsv.flutter` returns; `--panel` and shards
/// are the command's alone.
pub fn map_json(
    args: &FlutterArgs,
    loaded: &LoadedConfig,
    registry: &Registry,
) -> Result<serde_json::Value> {
    if args.panel || args.shards.is_sharded() {
        bail!("--panel, --shard and --emit-slurm are the flutter command's; run it for those");
    }
    let machs = map_machs(args)?;
    let (setup, times) = map_setup(args, loaded)?;
    Ok(map_run(args, &setup, registry, &machs, &times)?.2)
}

/// The Mach grid of `--mach-range` and `--mach-step` (and a finite `--altitude-m`).
fn map_machs(args: &FlutterArgs) -> Result<Vec<f64>> {
    if !(args.altitude_m.is_finite()) {
        bail!(
            "--altitude-m must be a finite number, got {}",
            args.altitude_m
        );
    }
    let range = super::parse_mach_range(&args.mach_range)?;
    super::flutter_mach_grid(range, args.mach_step)
}

/// The analysis of a flutter map and its times in the flow, from the flags and the config.
fn map_setup(args: &FlutterArgs, loaded: &LoadedConfig) -> Result<(FlutterSetup, Vec<f64>)> {
    let times = if args.times_s.is_empty() {
        DEFAULT_TIMES_S.to_vec()
    } else {
        args.times_s.clone()
    };
    if let Some(t) = times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
        bail!("--times-s must be finite and >= 0, got {t}");
    }
    if times.windows(2).any(|w| w[1] <= w[0]) {
        bail!("--times-s must be ascending, got {times:?}");
    }
    if !(args.dt_s.is_finite() && args.dt_s > 0.0) {
        bail!("--dt-s must be a positive number, got {}", args.dt_s);
    }
    super::check_flutter_times(&times, args.dt_s)?;
    let configured = loaded
        .config
        .regions
        .region(SURFACE_REGION)
        .unwrap_or_default();
    let alpha_deg = args.alpha_deg.unwrap_or(loaded.config.flight.alpha_deg);
    crate::limits::check_flow_angle_deg("--alpha-deg", alpha_deg)?;
    let Some(structure) = configured.structure.clone() else {
        bail!(
            "{}: region `{SURFACE_REGION}` has no structure model (set `regions.lifting_surfaces.structure`)",
            loaded.file
        );
    };
    let setup = FlutterSetup {
        region: loaded.region(SURFACE_REGION)?,
        models: FlutterModels {
            aero: args
                .aero
                .clone()
                .or(configured.aero)
                .unwrap_or_else(|| "shock-expansion-piston".to_owned()),
            heat_flux: args
                .heat_flux
                .clone()
                .or(configured.heat_flux)
                .unwrap_or_else(|| "eckert".to_owned()),
            conduction: args.conduction.clone(),
            structure,
        },
        altitude_m: args.altitude_m,
        alpha_rad: alpha_deg.to_radians(),
        heating: HeatingSteps {
            dt_s: args.dt_s,
            flux_every: 1,
            initial_k: 293.0,
        },
        method: match args.derivative {
            DerivativeChoice::Direct => DerivativeMethod::Direct,
            DerivativeChoice::ForwardDifference => DerivativeMethod::ForwardDifference,
        },
        compare_methods: !args.no_compare,
        options: SurfaceOptions::default(),
    };
    Ok((setup, times))
}

/// Computes the map into a new run folder: the folder, the map and its summary.
fn map_run(
    args: &FlutterArgs,
    setup: &FlutterSetup,
    registry: &Registry,
    machs: &[f64],
    times: &[f64],
) -> Result<(RunFolder, FlutterMap, serde_json::Value)> {
    let mut folder = RunFolder::create("flutter", args.out.out.as_deref(), args.out.force)?;
    let map = folder.run(
        |_| flutter_map(setup, registry, machs, times).map_err(anyhow::Error::from),
        || json!({"command": "flutter"}),
    )?;
    let summary = write_map(&mut folder, setup, &map)?;
    Ok((folder, map, summary))
}

/// The map's CSVs, PNGs and summary; the summary as written.
fn write_map(
    folder: &mut RunFolder,
    setup: &FlutterSetup,
    map: &FlutterMap,
) -> Result<serde_json::Value> {
    write_outputs(folder, map)?;
    folder.write_summary(summary(setup, map), &RunStatus::Completed)
}

/// The map's outputs and the table (or the summary with `json`): `hsv-run merge` of flutter
/// shards.
pub(super) fn write_run(
    folder: &mut RunFolder,
    setup: &FlutterSetup,
    map: &FlutterMap,
    json: bool,
) -> Result<()> {
    let summary = write_map(folder, setup, map)?;
    if json {
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
    } else {
        print_table(setup, map, &folder.path)?;
    }
    Ok(())
}

/// The largest of the points' method differences, if any were computed.
fn worst_difference(map: &FlutterMap) -> Option<(f64, f64)> {
    map.points
        .iter()
        .flatten()
        .filter_map(|p| p.method_difference)
        .map(|d| (d.relative_matrix_difference, d.critical_root_difference))
        .reduce(|a, b| (a.0.max(b.0), a.1.max(b.1)))
}

/// The JSON summary: keys name quantity and unit.
fn summary(setup: &FlutterSetup, map: &FlutterMap) -> serde_json::Value {
    let boundaries: Vec<_> = map
        .times_s
        .iter()
        .zip(map.boundaries.iter().zip(&map.divergence))
        .map(|(t, (f, d))| {
            json!({"time_s": t, "flutter_mach": f.mach(), "flutter": f,
                   "divergence_mach": d.mach(), "divergence": d})
        })
        .collect();
    let limits: Vec<_> = map
        .points
        .iter()
        .flatten()
        .filter(|p| !p.status.is_analysed())
        .map(|p| json!({"mach": p.mach, "time_s": p.time_s, "status": p.status}))
        .collect();
    let first = map.boundaries.first().and_then(FlutterBoundary::mach);
    let last = map.boundaries.last().and_then(FlutterBoundary::mach);
    let difference = worst_difference(map);
    json!({
        "command": "flutter",
        "altitude_m": setup.altitude_m,
        "alpha_deg": setup.alpha_rad.to_degrees(),
        "models": setup.models,
        "derivative_method": setup.method,
        "mach_grid": map.machs,
        "times_s": map.times_s,
        "initial_temperature_k": setup.heating.initial_k,
        "conduction_dt_s": setup.heating.dt_s,
        "flutter_mach_first_time": first,
        "flutter_mach_last_time": last,
        "divergence_mach_first_time": map.divergence.first().and_then(FlutterBoundary::mach),
        "divergence_mach_last_time": map.divergence.last().and_then(FlutterBoundary::mach),
        "flutter_margin_loss": match (first, last) {
            (Some(a), Some(b)) if a > 0.0 => Some(1.0 - b / a),
            _ => None,
        },
        "boundaries": boundaries,
        "buckled_melting_or_failed_points": limits,
        "max_relative_matrix_difference_forward_vs_direct": difference.map(|d| d.0),
        "max_critical_root_difference_forward_vs_direct": difference.map(|d| d.1),
        "wall_time_s": map.wall_time_s,
        "paper": {"cold_flutter_mach": 16.1, "flutter_mach_after_100_s": 3.5,
                  "note": "Klock & Cesnik §IV.D, Fig. 16: first-mode flutter of their surface; ours is the sample planform"},
    })
}

/// The table on standard output.
fn print_table(setup: &FlutterSetup, map: &FlutterMap, folder: &Path) -> Result<()> {
    outln!(
        "flutter of `{}` at {} m, alpha {:.2} deg: aero `{}`, heat flux `{}`, conduction `{}`, structure `{}`",
        SURFACE_REGION,
        setup.altitude_m,
        setup.alpha_rad.to_degrees(),
        setup.models.aero,
        setup.models.heat_flux,
        setup.models.conduction,
        setup.models.structure
    )?;
    outln!(
        "Mach grid {:?}, {} times, wall time {:.1} s",
        map.machs,
        map.times_s.len(),
        map.wall_time_s
    )?;
    outln!(
        "{:>8}  {:>12}  {}",
        "t (s)",
        "flutter M",
        "flutter (oscillatory pair) | divergence (real root)"
    )?;
    for ((t, f), d) in map.times_s.iter().zip(&map.boundaries).zip(&map.divergence) {
        outln!(
            "{t:>8.1}  {:>12}  {}",
            f.mach()
                .map_or_else(|| "-".to_owned(), |m| format!("{m:.3}")),
            describe(f, Instability::Flutter)
        )?;
        outln!(
            "{:>8}  {:>12}  {}",
            "",
            d.mach()
                .map_or_else(|| "-".to_owned(), |m| format!("div {m:.3}")),
            describe(d, Instability::Divergence)
        )?;
    }
    for p in map.points.iter().flatten() {
        if !p.status.is_analysed() {
            outln!(
                "  Mach {:.2}, t = {:.1} s: {}",
                p.mach,
                p.time_s,
                status_text(&p.status)
            )?;
        }
    }
    if let Some((m, r)) = worst_difference(map) {
        outln!(
            "forward difference (7 steps) vs direct derivative: A differs by {m:.2e} (Frobenius, relative), the critical root by {r:.2e}"
        )?;
    }
    outln!("outputs in {}", folder.display())?;
    Ok(())
}

/// One line on a flutter or divergence boundary.
pub(super) fn describe(b: &FlutterBoundary, kind: Instability) -> String {
    let what = kind.name();
    match b {
        FlutterBoundary::Crossing {
            mach,
            frequency_hz,
            evaluations,
            grows_from,
            ..
        } => {
            let origin = grows_from.map_or_else(
                || "mode not tracked".to_owned(),
                |g| {
                    format!(
                        "grows from mode {} ({:.2} Hz at Mach {})",
                        g.mode, g.frequency_hz, g.mach
                    )
                },
            );
            match kind {
                Instability::Flutter => format!(
                    "flutter at Mach {mach:.3}: {frequency_hz:.2} Hz, {origin}; {evaluations} Brent evaluations"
                ),
                Instability::Divergence => format!(
                    "divergence at Mach {mach:.3}: a real root crosses, {origin}; {evaluations} Brent evaluations"
                ),
            }
        }
        FlutterBoundary::StableInRange {
            max_real_per_s,
            at_mach,
            least_damping_ratio,
            limited_by,
        } => {
            let limit = limited_by
                .as_ref()
                .map_or_else(String::new, |l| format!("; analysable only below {l}"));
            // A time with no root of this kind (no real root for divergence) leaves the search's
            // maximum at −∞: say so instead of printing the sentinel.
            if max_real_per_s.is_finite() {
                format!(
                    "no {what} in the range (largest real part of its roots {max_real_per_s:.4} /s at Mach {at_mach}, least damping ratio {least_damping_ratio:.4}){limit}"
                )
            } else {
                format!("no {what} in the range (no root of its kind at any Mach analysed){limit}")
            }
        }
        FlutterBoundary::UnstableAtLowest {
            lowest_mach,
            max_real_per_s,
            least_damping_ratio,
        } => format!(
            "{what} already at Mach {lowest_mach} (largest real part {max_real_per_s:.4} /s, damping ratio {least_damping_ratio:.4})"
        ),
        FlutterBoundary::Unresolved { reason } => format!("{what} unresolved: {reason}"),
    }
}

/// The lowest grid Mach number of `row` that could not be analysed (melting, past the
/// material data, failed): above it the row says nothing about flutter.
fn limit_mach(row: &[FlutterPoint]) -> Option<f64> {
    row.iter()
        .filter(|p| !p.status.is_analysed())
        .map(|p| p.mach)
        .reduce(f64::min)
}

/// The crossings of `boundaries` as columns: time (s), Mach number, frequency (Hz), the mode
/// it grows from (0: not tracked) and that mode's frequency (Hz).
fn crossing_columns(times_s: &[f64], boundaries: &[FlutterBoundary]) -> [Vec<f64>; 5] {
    let mut cols: [Vec<f64>; 5] = Default::default();
    for (t, b) in times_s.iter().zip(boundaries) {
        if let FlutterBoundary::Crossing {
            mach,
            frequency_hz,
            grows_from,
            ..
        } = b
        {
            let (mode, from_hz) =
                grows_from.map_or((0.0, 0.0), |g| (g.mode as f64, g.frequency_hz));
            for (c, v) in cols
                .iter_mut()
                .zip([*t, *mach, *frequency_hz, mode, from_hz])
            {
                c.push(v);
            }
        }
    }
    cols
}

/// Fig. 16: the flutter Mach number versus time (flutter_mach.csv), the divergence Mach number
/// apart from it (divergence_mach.csv), the limit of the analysable range versus time
/// (flutter_limits.csv), and all three in flutter_mach.png.
fn write_flutter_mach(folder: &mut RunFolder, map: &FlutterMap) -> Result<()> {
    let flutter = crossing_columns(&map.times_s, &map.boundaries);
    let divergence = crossing_columns(&map.times_s, &map.divergence);
    for (name, kind, cols) in [
        ("flutter_mach.csv", "flutter", &flutter),
        ("divergence_mach.csv", "divergence", &divergence),
    ] {
        let path = folder.join(name);
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        output::write_csv(
            &path,
            &[
                "time_s",
                &format!("{kind}_mach"),
                "frequency_hz",
                "grows_from_mode",
                "grows_from_frequency_hz",
            ],
            &refs,
        )?;
        folder.record(path);
    }
    let (t_l, m_l): (Vec<f64>, Vec<f64>) = map
        .times_s
        .iter()
        .zip(&map.points)
        .filter_map(|(t, row)| limit_mach(row).map(|m| (*t, m)))
        .unzip();
    let path = folder.join("flutter_limits.csv");
    output::write_csv(
        &path,
        &["time_s", "lowest_unanalysable_mach"],
        &[&t_l, &m_l],
    )?;
    folder.record(path);
    let mut series = Vec::new();
    for (label, cols) in [
        ("flutter Mach (oscillatory pair crosses)", &flutter),
        ("divergence Mach (real root crosses)", &divergence),
    ] {
        if !cols[0].is_empty() {
            series.push(Series {
                label: label.to_owned(),
                x: cols[0].clone(),
                y: cols[1].clone(),
            });
        }
    }
    if !t_l.is_empty() {
        series.push(Series {
            label: "lowest Mach melted or past material data".to_owned(),
            x: t_l,
            y: m_l,
        });
    }
    if series.is_empty() {
        return Ok(());
    }
    let path = folder.join("flutter_mach.png");
    output::write_line_plots_png(
        &path,
        &[LinePlot {
            title: "Flutter and divergence Mach numbers versus time in flow".to_owned(),
            x_label: "time in flow (s)".to_owned(),
            y_label: "Mach number".to_owned(),
            series,
        }],
        1,
        (900, 600),
    )?;
    folder.record(path);
    Ok(())
}

/// CSVs and PNGs of Figs. 14-16.
fn write_outputs(folder: &mut RunFolder, map: &FlutterMap) -> Result<()> {
    write_flutter_mach(folder, map)?;
    // Fig. 15: every root of every grid point (with its tracked mode) and of every point the
    // boundary searches evaluated (search 1: flutter, 2: divergence; mode 0: not tracked), the
    // largest-σ root of each point flagged critical.
    let mut cols: [Vec<f64>; 9] = Default::default();
    let mut push_point = |p: &FlutterPoint, search: f64, modes: &[Option<usize>]| {
        let critical = p
            .roots
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.real_per_s.total_cmp(&b.1.real_per_s))
            .map(|(i, _)| i);
        for (j, r) in p.roots.iter().enumerate() {
            let mode = modes
                .iter()
                .position(|m| *m == Some(j))
                .map_or(0.0, |k| (k + 1) as f64);
            for (c, v) in cols.iter_mut().zip([
                p.time_s,
                p.mach,
                search,
                mode,
                if critical == Some(j) { 1.0 } else { 0.0 },
                r.real_per_s,
                r.imag_rad_s,
                r.frequency_hz,
                r.damping_ratio,
            ]) {
                c.push(v);
            }
        }
    };
    let mut loci = Vec::new();
    for (ti, row) in map.points.iter().enumerate() {
        let mut x = Vec::new();
        let mut y = Vec::new();
        for (mi, p) in row.iter().enumerate() {
            let tracked = map
                .tracked
                .get(ti)
                .and_then(|r| r.get(mi))
                .map_or(&[][..], Vec::as_slice);
            push_point(p, 0.0, tracked);
            if let Some(r) = tracked
                .first()
                .copied()
                .flatten()
                .and_then(|j| p.roots.get(j))
            {
                x.push(r.real_per_s);
                y.push(r.frequency_hz);
            }
        }
        for s in map.searched.get(ti).into_iter().flatten() {
            let search = match s.instability {
                Instability::Flutter => 1.0,
                Instability::Divergence => 2.0,
            };
            push_point(&s.point, search, &[]);
        }
        if !x.is_empty() {
            loci.push(Series {
                label: format!("t = {} s", map.times_s[ti]),
                x,
                y,
            });
        }
    }
    let path = folder.join("root_loci.csv");
    let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    output::write_csv(
        &path,
        &[
            "time_s",
            "mach",
            "search",
            "mode",
            "critical",
            "real_per_s",
            "imag_rad_s",
            "frequency_hz",
            "damping_ratio",
        ],
        &refs,
    )?;
    folder.record(path);
    if !loci.is_empty() {
        let path = folder.join("root_loci.png");
        output::write_line_plots_png(
            &path,
            &[LinePlot {
                title: "Root loci of the first free-vibration mode over Mach, by time in flow"
                    .to_owned(),
                x_label: "real part (1/s)".to_owned(),
                y_label: "frequency (Hz)".to_owned(),
                series: loci,
            }],
            1,
            (1000, 700),
        )?;
        folder.record(path);
    }
    // Fig. 14: temperature range of the structure versus time, by Mach number.
    let mut t_cols: [Vec<f64>; 5] = Default::default();
    for p in map.points.iter().flatten() {
        if matches!(p.status, PointStatus::Failed { .. }) && p.min_temperature_k.is_infinite() {
            continue;
        }
        for (c, v) in t_cols.iter_mut().zip([
            p.mach,
            p.time_s,
            p.min_temperature_k,
            p.max_temperature_k,
            p.mean_temperature_k,
        ]) {
            c.push(v);
        }
    }
    let path = folder.join("temperature_range.csv");
    let refs: Vec<&[f64]> = t_cols.iter().map(Vec::as_slice).collect();
    output::write_csv(
        &path,
        &[
            "mach",
            "time_s",
            "min_temperature_k",
            "max_temperature_k",
            "mean_temperature_k",
        ],
        &refs,
    )?;
    folder.record(path);
    let shown: Vec<usize> = {
        let n = map.machs.len();
        let k = n.min(5);
        (0..k).map(|i| i * (n - 1) / (k - 1).max(1)).collect()
    };
    let mut series = Vec::new();
    for &mi in &shown {
        let mut t = Vec::new();
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        for row in &map.points {
            let p = &row[mi];
            if p.min_temperature_k.is_finite() && p.max_temperature_k.is_finite() {
                t.push(p.time_s);
                lo.push(p.min_temperature_k);
                hi.push(p.max_temperature_k);
            }
        }
        if !t.is_empty() {
            let m = map.machs[mi];
            series.push(Series {
                label: format!("Mach {m:.1} max"),
                x: t.clone(),
                y: hi,
            });
            series.push(Series {
                label: format!("Mach {m:.1} min"),
                x: t,
                y: lo,
            });
        }
    }
    if !series.is_empty() {
        let path = folder.join("temperature_range.png");
        output::write_line_plots_png(
            &path,
            &[LinePlot {
                title: "Temperature range of the lifting surface structure".to_owned(),
                x_label: "time in flow (s)".to_owned(),
                y_label: "temperature (K)".to_owned(),
                series,
            }],
            1,
            (1000, 650),
        )?;
        folder.record(path);
    }
    Ok(())
}

/// `--panel`: the classical simply supported panel.
fn run_panel(
    args: &FlutterArgs,
    loaded: &hsv_core::config::LoadedConfig,
    registry: &Registry,
    machs: &[f64],
) -> Result<()> {
    use crate::limits::{MAX_MODES, MAX_PANEL_ELEMENTS, check_count};
    check_count("--panel-modes", args.panel_modes, 1, MAX_MODES)?;
    check_count(
        "--panel-elements",
        args.panel_elements,
        1,
        MAX_PANEL_ELEMENTS,
    )?;
    let panel = SimplySupportedPanel {
        chord_m: args.panel_chord_m,
        span_m: args.panel_span_m,
        thickness_m: args.panel_thickness_m,
        elements: (args.panel_elements, args.panel_elements),
        modes: args.panel_modes,
    };
    let gas = loaded.config.gas;
    let (region, structure) = panel.build(registry, gas)?;
    let aero_name = args
        .aero
        .clone()
        .unwrap_or_else(|| "piston-theory".to_owned());
    let make_aero = || -> Result<Box<dyn AeroModel>, FlutterError> {
        let settings = region.model_settings(&aero_name);
        registry
            .create::<dyn AeroModel>(&aero_name, &ModelContext::new(&region, registry, &settings))
            .map_err(|e| FlutterError::Inconsistent(format!("model `{aero_name}`: {e}")))
    };
    let d = panel.rigidity_n_m()?;
    let start = std::time::Instant::now();
    let result = panel_flutter(
        &region.mesh,
        structure.as_ref(),
        &make_aero,
        gas,
        args.altitude_m,
        machs,
        d,
        panel.chord_m,
    )?;
    let wall = start.elapsed().as_secs_f64();
    let summary = json!({
        "command": "flutter --panel",
        "panel": {"chord_m": panel.chord_m, "span_m": panel.span_m,
                  "thickness_m": panel.thickness_m, "modes": panel.modes,
                  "elements": panel.elements.0, "material": "ti-6al-4v (293 K)",
                  "edges": "simply supported, in-plane immovable"},
        "aero": aero_name,
        "aerodynamic_damping": false,
        "altitude_m": args.altitude_m,
        "rigidity_n_m": d,
        "critical_mach": result.critical_mach,
        "critical_dynamic_pressure_pa": result.critical_dynamic_pressure_pa,
        "lambda": result.lambda,
        "lambda_definition": "2 q a^3 / (beta D), beta = M (piston theory's high-Mach form)",
        "lambda_ackeret": result.lambda_ackeret,
        "flutter_frequency_hz": result.flutter_frequency_hz,
        "boundary": result.boundary,
        "wall_time_s": wall,
    });
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
        return Ok(());
    }
    outln!(
        "simply supported panel {} m x {} m x {} m (Ti-6Al-4V, D = {d:.4} N m) at {} m, aero `{aero_name}` without aerodynamic damping",
        panel.chord_m,
        panel.span_m,
        panel.thickness_m,
        args.altitude_m
    )?;
    match (
        result.critical_mach,
        result.critical_dynamic_pressure_pa,
        result.lambda,
    ) {
        (Some(m), Some(q), Some(l)) => outln!(
            "flutter at Mach {m:.4}: q = {q:.1} Pa, lambda = 2 q a^3/(M D) = {l:.2} (with beta = sqrt(M^2-1): {:.2}), {:.2} Hz",
            result.lambda_ackeret.unwrap_or(l),
            result.flutter_frequency_hz.unwrap_or(0.0)
        )?,
        _ => outln!(
            "no flutter crossing in the Mach range: {}",
            serde_json::to_string(&result.boundary)?
        )?,
    }
    outln!("wall time {wall:.2} s")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A time whose roots are all oscillatory has no real root: the divergence line says so
    /// instead of printing the search's −∞ sentinel.
    #[test]
    fn a_kind_with_no_roots_is_named_not_printed_as_minus_infinity() {
        let none = FlutterBoundary::StableInRange {
            max_real_per_s: f64::NEG_INFINITY,
            at_mach: f64::NAN,
            least_damping_ratio: f64::INFINITY,
            limited_by: None,
        };
        let line = describe(&none, Instability::Divergence);
        assert_eq!(
            line,
            "no divergence in the range (no root of its kind at any Mach analysed)"
        );
        let some = FlutterBoundary::StableInRange {
            max_real_per_s: -2.04,
            at_mach: 5.0,
            least_damping_ratio: 0.01,
            limited_by: None,
        };
        assert!(describe(&some, Instability::Flutter).contains("-2.0400 /s at Mach 5"));
    }
}
