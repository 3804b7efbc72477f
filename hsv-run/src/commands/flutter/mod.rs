//! `hsv-run flutter`: flutter of the heated lifting surface versus time in the flow (paper
//! §IV.D, Figs. 14-16), or with `--panel` the classical simply supported panel under piston
//! theory (Dowell's λ). The analysis is [`crate::analysis::flutter`]; this module is its CLI,
//! the map's outputs are [`super::shared::flutter_map`]'s.
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

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use hsv_core::aero::AeroModel;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::{ModelContext, Registry};
use serde_json::json;

use super::shared::flutter_map::{SURFACE_REGION, print_table, write_map};
use super::shared::shard::ShardArgs;
use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::analysis::flutter::panel::{SimplySupportedPanel, panel_flutter};
use crate::analysis::flutter::sweep::{FlutterMap, FlutterModels, FlutterSetup, flutter_map};
use crate::analysis::flutter::{DerivativeMethod, FlutterError, SurfaceOptions};
use crate::analysis::heating::HeatingSteps;
use crate::outln;
use crate::output::RunFolder;

/// Default times in the flow, s: the paper's 0 to 100 s, with the first seconds resolved.
const DEFAULT_TIMES_S: [f64; 14] = [
    0.0, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0,
];

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
    pub shards: ShardArgs,
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
