//! `hsv-run heat`: one lifting surface, uniformly at 293 K, exposed to steady flow for a while;
//! the heat flux of a heat-flux model on the edge states of an aero model drives each requested
//! conduction model, and the temperature history of the structure is written out. The loop is
//! [`crate::analysis::heating::SurfaceHeating`]; this module is its CLI and outputs (one file: one
//! command, whose outputs are written from the histories its loop records).
//!
//! The heat flux is re-evaluated from the current wall temperatures every `--flux-interval-s`
//! (paper Table 3: 10 ms) and the conduction model advances by `--dt-s` (paper: 1 ms; default
//! 0.1 s here, which the implicit models take without loss of stability).
//!
//! A `pod` model trains its own basis (`[models.pod.training]`): this command sets the training
//! to the run's altitude, duration, step and models at the Mach numbers of `--snapshot-mach`
//! (default: M − 1, M − 0.5 and M), so the basis file (`[models.pod] basis_file`) is rebuilt
//! whenever it was built from anything else. A basis from other conditions reproduces the mean
//! temperature closely but the sharp leading edge's peak less well (Mach 6, 26 km, 20 s from
//! Mach 5 and 7 snapshots: 43 K low at a 533 K peak; from Mach 4, 5, 7, 8: 14 K).

use std::path::Path;

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::coupling::GridTransfer;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry, Role};
use hsv_core::structure::StructureModel;
use hsv_core::thermal::ConductionModel;

use super::steps::{StepPlan, time_steps};
use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::analysis::heating::{HeatingModels, HeatingSteps, SurfaceHeating};
use crate::outln;
use crate::output::{self, LinePlot, RunFolder, RunStatus, Series};
use crate::progress::Progress;
use crate::vehicle::Region;

/// Arguments of `hsv-run heat`.
#[derive(Args, Debug, Clone)]
pub struct HeatArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Freestream Mach number (default: the config's).
    #[arg(long, allow_negative_numbers = true)]
    pub mach: Option<f64>,
    /// Geometric altitude, m (default: 10000, the paper's heating case).
    #[arg(long = "altitude-m", allow_negative_numbers = true)]
    pub altitude_m: Option<f64>,
    /// Angle of attack, deg (default: the config's).
    #[arg(long = "alpha-deg", allow_negative_numbers = true)]
    pub alpha_deg: Option<f64>,
    /// Time in the flow, s (paper: up to 100 s).
    #[arg(
        long = "duration-s",
        default_value_t = 100.0,
        allow_negative_numbers = true
    )]
    pub duration_s: f64,
    /// Conduction time step, s (paper: 0.001).
    #[arg(long = "dt-s", default_value_t = 0.1, allow_negative_numbers = true)]
    pub dt_s: f64,
    /// Interval between heat-flux updates, s (default: every conduction step; paper: 0.01).
    #[arg(long = "flux-interval-s", allow_negative_numbers = true)]
    pub flux_interval_s: Option<f64>,
    /// Conduction model (repeatable; default: full-order and pod side by side).
    #[arg(long = "model", value_name = "NAME")]
    pub models: Vec<String>,
    /// Heat-flux model (default: the config's lifting-surface heat_flux, else eckert).
    #[arg(long = "heat-flux", value_name = "NAME")]
    pub heat_flux: Option<String>,
    /// Aero model for the edge states (default: the config's lifting-surface aero model).
    #[arg(long = "aero", value_name = "NAME")]
    pub aero: Option<String>,
    /// Mach numbers of the full-order snapshot runs that build a missing POD basis (default:
    /// M − 1, M − 0.5 and M).
    #[arg(long = "snapshot-mach", value_name = "M", num_args = 1.., allow_negative_numbers = true)]
    pub snapshot_mach: Vec<f64>,
    /// Initial uniform temperature, K.
    #[arg(
        long = "initial-k",
        default_value_t = 293.0,
        allow_negative_numbers = true
    )]
    pub initial_k: f64,
    #[command(flatten)]
    pub output: OutArgs,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// Temperature history and cost of one conduction model.
#[derive(Debug, Clone, serde::Serialize)]
struct History {
    model: String,
    time_s: Vec<f64>,
    min_k: Vec<f64>,
    max_k: Vec<f64>,
    mean_k: Vec<f64>,
    /// Wall time spent in the conduction steps, s.
    conduction_wall_time_s: f64,
    steps: usize,
    states: usize,
    final_node_temperatures_k: Vec<f64>,
    /// Why the run stopped before the end (time, model and quantity), if it did.
    stopped: Option<String>,
    /// Panel wall temperatures at the VTK sample times.
    #[serde(skip)]
    surface_frames: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

/// The heated lifting surface: the right one (the left is its mirror image).
const HEATED_REGION: &str = "right_surface";

/// The flight condition, the heated region and the models of the run.
struct Setup {
    flight: FlightCondition,
    region: RegionInfo,
    aero: String,
    heat_flux: String,
    /// The region's structure model, whose grid the final temperature field is written on.
    structure: Option<String>,
}

fn check_positive(flag: &str, value: f64) -> Result<()> {
    if !(value.is_finite() && value > 0.0) {
        bail!("{flag} must be a positive number, got {value}");
    }
    Ok(())
}

/// Flight condition at `mach` and the heated region with its models.
fn setup(loaded: &LoadedConfig, args: &HeatArgs, mach: f64) -> Result<Setup> {
    let flight_cfg = loaded.config.flight;
    let altitude_m = args.altitude_m.unwrap_or(10_000.0);
    let alpha_deg = args.alpha_deg.unwrap_or(flight_cfg.alpha_deg);
    crate::limits::check_flow_angle_deg("--alpha-deg", alpha_deg)?;
    let freestream = Freestream::standard(mach, altitude_m, loaded.config.gas)?;
    let flight = FlightCondition::steady(freestream, alpha_deg.to_radians(), 0.0);
    let region = loaded.region(HEATED_REGION)?;
    let configured = loaded
        .config
        .regions
        .region(HEATED_REGION)
        .unwrap_or_default();
    let aero = args
        .aero
        .clone()
        .or(configured.aero)
        .unwrap_or_else(|| "shock-expansion".to_owned());
    let heat_flux = args
        .heat_flux
        .clone()
        .or(configured.heat_flux)
        .unwrap_or_else(|| "eckert".to_owned());
    Ok(Setup {
        flight,
        region,
        aero,
        heat_flux,
        structure: configured.structure,
    })
}

/// Sets `pod`'s training to this run's conditions (`[models.pod.training]`), so its basis is
/// trained for them, or reused when it already was.
fn train_pod_for_run(s: &mut Setup, args: &HeatArgs, mach: f64) -> Result<()> {
    let machs = if args.snapshot_mach.is_empty() {
        // Bracket the run's heating from below and at it: a snapshot run hotter than the run
        // itself could leave the material data (Mach 7 at 10 km nears the solidus in 100 s).
        vec![(mach - 1.0).max(1.5), (mach - 0.5).max(1.5), mach]
    } else {
        args.snapshot_mach.clone()
    };
    crate::limits::check_count(
        "--snapshot-mach (count of snapshot runs)",
        machs.len(),
        1,
        crate::limits::MAX_SNAPSHOT_RUNS,
    )?;
    for &m in &machs {
        check_positive("--snapshot-mach", m)?;
    }
    let training = serde_json::json!({
        "heat_flux": s.heat_flux,
        "aero": s.aero,
        "mach": machs,
        "altitude_m": s.flight.freestream.altitude_m,
        "alpha_deg": s.flight.alpha_rad.to_degrees(),
        "duration_s": args.duration_s,
        "dt_s": args.dt_s,
        "snapshots_per_run": 100,
        "initial_k": args.initial_k,
    });
    let table: toml::Table = serde_json::from_value(training)?;
    let mut pod = s.region.model_settings("pod");
    pod.table
        .insert("training".to_owned(), toml::Value::Table(table));
    s.region.settings.insert("pod".to_owned(), pod);
    Ok(())
}

/// Runs conduction model `name` from a uniform temperature for the run's duration.
fn run_model(
    name: &str,
    s: &Setup,
    registry: &Registry,
    args: &HeatArgs,
    plan: &Plan,
    samples: usize,
) -> Result<(History, SurfaceHeating)> {
    let steps = plan.steps.steps;
    let mut heating = SurfaceHeating::new(
        s.region.clone(),
        registry,
        HeatingModels {
            aero: s.aero.clone(),
            heat_flux: s.heat_flux.clone(),
            conduction: name.to_owned(),
        },
        s.flight,
        HeatingSteps {
            dt_s: plan.steps.dt_s,
            flux_every: plan.flux_every,
            initial_k: args.initial_k,
        },
    )?;
    let record_every = (steps / samples.max(1)).max(1);
    let frame_every = (steps / 10).max(1);
    let mut history = History {
        model: name.to_owned(),
        time_s: Vec::new(),
        min_k: Vec::new(),
        max_k: Vec::new(),
        mean_k: Vec::new(),
        conduction_wall_time_s: 0.0,
        steps,
        states: heating.conduction().n_states(),
        final_node_temperatures_k: Vec::new(),
        stopped: None,
        surface_frames: Vec::new(),
    };
    record(&mut heating, &mut history);
    let mut progress = Progress::new(format!("heat: {name}"), steps);
    for k in 0..steps {
        if k % frame_every == 0 {
            let wall = heating.wall_temperatures_k().to_vec();
            let q = heating.heat_flux_w_m2().to_vec();
            history.surface_frames.push((heating.time_s(), wall, q));
        }
        if let Err(e) = heating.advance(plan.steps.dt_of(k)) {
            // Keep the last good state: what was computed so far stays in the outputs.
            history.stopped = Some(e.to_string());
            break;
        }
        progress.update(k + 1);
        if (k + 1) % record_every == 0 || k + 1 == steps {
            record(&mut heating, &mut history);
        }
    }
    if history.stopped.is_some() {
        record(&mut heating, &mut history);
    }
    history.conduction_wall_time_s = heating.diagnostics().wall_time_s;
    let wall = heating.wall_temperatures_k().to_vec();
    let q = heating.heat_flux_w_m2().to_vec();
    history.surface_frames.push((heating.time_s(), wall, q));
    Ok((history, heating))
}

/// Appends the structure's min/max/mean node temperature at the current time to `h`.
fn record(heating: &mut SurfaceHeating, h: &mut History) {
    let t = heating.time_s();
    let nodes = heating.node_temperatures_k();
    h.time_s.push(t);
    h.min_k
        .push(nodes.iter().copied().fold(f64::INFINITY, f64::min));
    h.max_k
        .push(nodes.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    h.mean_k
        .push(nodes.iter().sum::<f64>() / nodes.len().max(1) as f64);
    h.final_node_temperatures_k.clear();
    h.final_node_temperatures_k.extend_from_slice(nodes);
}

/// The step plan of a run: the conduction steps (the last one shortened when the duration is
/// not a whole number of them) and the conduction steps between heat-flux updates.
#[derive(Debug, Clone, Copy)]
struct Plan {
    steps: StepPlan,
    flux_every: usize,
}

/// The run's steps by the shared rule ([`time_steps`]); a heat-flux interval must be a whole
/// number of conduction steps, so the flux is never silently updated at another rate.
fn step_plan(args: &HeatArgs) -> Result<Plan> {
    let steps = time_steps(args.duration_s, args.dt_s).map_err(|e| {
        anyhow::anyhow!(
            "--duration-s {} at --dt-s {}: {e}",
            args.duration_s,
            args.dt_s
        )
    })?;
    let flux_every = match args.flux_interval_s {
        None => 1,
        Some(interval) => {
            check_positive("--flux-interval-s", interval)?;
            let per_update = time_steps(interval, steps.dt_s)
                .map_err(|e| anyhow::anyhow!("--flux-interval-s {interval}: {e}"))?;
            if per_update.last_step_shortened() {
                bail!(
                    "--flux-interval-s {interval} is not a whole number of conduction steps of \
                     --dt-s {} s; give a multiple of it",
                    steps.dt_s
                );
            }
            per_update.steps
        }
    };
    Ok(Plan { steps, flux_every })
}

/// Checks that `name` is a registered model of `role` (what `flag` names), so a typo fails
/// before the run folder is created.
fn check_model(registry: &Registry, flag: &str, name: &str, role: Role) -> Result<()> {
    let entry = registry
        .get(name)
        .map_err(|e| anyhow::anyhow!("{flag} {name}: {e}"))?;
    if entry.role() != role {
        bail!(
            "{flag} {name}: `{name}` is a {} model, not a {role} model (known: {})",
            entry.role(),
            registry.names(role).join(", ")
        );
    }
    Ok(())
}

/// Runs the heating job and writes the run folder.
pub fn run(args: HeatArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let registry = &registry;
    // Every input is checked before the run folder exists: a refused run leaves nothing.
    let mach = args.mach.unwrap_or(loaded.config.flight.mach);
    check_positive("--mach", mach)?;
    check_positive("--duration-s", args.duration_s)?;
    check_positive("--dt-s", args.dt_s)?;
    check_positive("--initial-k", args.initial_k)?;
    let plan = step_plan(&args)?;
    let models = if args.models.is_empty() {
        vec!["full-order".to_owned(), "pod".to_owned()]
    } else {
        args.models.clone()
    };
    let mut s = setup(&loaded, &args, mach)?;
    for name in &models {
        check_model(registry, "--model", name, Role::Conduction)?;
    }
    check_model(registry, "--heat-flux", &s.heat_flux, Role::HeatFlux)?;
    check_model(registry, "--aero", &s.aero, Role::Aero)?;
    if models.iter().any(|m| m == "pod") {
        train_pod_for_run(&mut s, &args, mach)?;
    }
    let mut run = RunFolder::create("heat", args.output.out.as_deref(), args.output.force)?;
    let mut notes = Vec::new();
    let mut histories = Vec::new();
    let mut transfers = Vec::new();
    let mut warnings = Vec::new();
    let partial = |histories: &[History], notes: &[String], warnings: &[String]| {
        summary_json(&args, &s, mach, histories, notes, warnings)
    };
    for name in &models {
        let (history, heating) = run.run(
            |_| run_model(name, &s, registry, &args, &plan, 200),
            || partial(&histories, &notes, &warnings),
        )?;
        // A model built from a cache (the POD basis) says where it is and whether it was reused.
        if let Some(cache) = heating.conduction().cache() {
            let how = if cache.reused {
                "reused (built from these conditions)"
            } else {
                "trained from full-order runs at this run's conditions"
            };
            eprintln!("heat: `{name}` cache {}: {how}", cache.path.display());
            notes.push(format!("`{name}` cache {}: {how}", cache.path.display()));
            if let Some(note) = cache.note {
                warnings.push(format!("{name}: {note}"));
            }
        }
        for w in crate::aero_job::validity_warnings(&s.aero, &s.flight, heating.aero_diagnostics())
        {
            let w = format!("{name}: {w}");
            if !warnings.contains(&w) {
                warnings.push(w);
            }
        }
        transfers.push(run.run(
            |_| structure_transfer(&s, registry, heating.conduction()),
            || partial(&histories, &notes, &warnings),
        )?);
        histories.push(history);
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    run.run(
        |run| write_outputs(run, &s, &histories, &transfers),
        || partial(&histories, &notes, &warnings),
    )?;
    let stopped: Vec<&str> = histories
        .iter()
        .filter_map(|h| h.stopped.as_deref())
        .collect();
    let status = if stopped.is_empty() {
        RunStatus::Completed
    } else {
        RunStatus::Failed(stopped.join("; "))
    };
    let summary = run.write_summary(partial(&histories, &notes, &warnings), &status)?;
    let folder = run.path.clone();

    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
        return stopped_error(&histories, &folder);
    }
    outln!(
        "lifting surface ({} panels) at Mach {mach}, {} m, alpha {:.2} deg for {} s (dt {} s), heat flux `{}`",
        s.region.mesh.panels.len(),
        s.flight.freestream.altitude_m,
        s.flight.alpha_rad.to_degrees(),
        args.duration_s,
        args.dt_s,
        s.heat_flux
    )?;
    if plan.steps.last_step_shortened() {
        outln!(
            "{} steps, the last shortened to {} s to end at {} s",
            plan.steps.steps,
            plan.steps.last_dt_s,
            plan.steps.duration_s
        )?;
    }
    for note in &notes {
        outln!("{note}")?;
    }
    outln!(
        "{:<14} {:>7} {:>9} {:>12} {:>12} {:>12} {:>14}",
        "model",
        "states",
        "t (s)",
        "min T (K)",
        "max T (K)",
        "mean T (K)",
        "wall time (s)"
    )?;
    for h in &histories {
        outln!(
            "{:<14} {:>7} {:>9.2} {:>12.2} {:>12.2} {:>12.2} {:>14.3}",
            h.model,
            h.states,
            h.time_s.last().copied().unwrap_or(0.0),
            h.min_k.last().copied().unwrap_or(f64::NAN),
            h.max_k.last().copied().unwrap_or(f64::NAN),
            h.mean_k.last().copied().unwrap_or(f64::NAN),
            h.conduction_wall_time_s
        )?;
    }
    outln!("outputs in {}", folder.display())?;
    outln!(
        "final fields for `hsv-run modes --temperature-field`: {}",
        folder.join("temperature_field_<model>.csv").display()
    )?;
    stopped_error(&histories, &folder)
}

/// The JSON summary of the run so far (keys name quantity and unit).
fn summary_json(
    args: &HeatArgs,
    s: &Setup,
    mach: f64,
    histories: &[History],
    notes: &[String],
    warnings: &[String],
) -> serde_json::Value {
    let models: Vec<_> = histories
        .iter()
        .map(|h| {
            serde_json::json!({
                "model": h.model,
                "states": h.states,
                "steps": h.steps,
                "conduction_wall_time_s": h.conduction_wall_time_s,
                "final_min_temperature_k": h.min_k.last(),
                "final_max_temperature_k": h.max_k.last(),
                "final_mean_temperature_k": h.mean_k.last(),
                "final_time_s": h.time_s.last(),
                "stopped": h.stopped,
            })
        })
        .collect();
    serde_json::json!({
        "mach": mach,
        "altitude_m": s.flight.freestream.altitude_m,
        "alpha_deg": s.flight.alpha_rad.to_degrees(),
        "duration_s": args.duration_s,
        "dt_s": args.dt_s,
        "aero_model": s.aero,
        "heat_flux_model": s.heat_flux,
        "initial_temperature_k": args.initial_k,
        "notes": notes,
        "warnings": warnings,
        "models": models,
    })
}

/// An error naming every model that stopped early (outputs up to that time are written).
fn stopped_error(histories: &[History], folder: &Path) -> Result<()> {
    let stopped: Vec<&str> = histories
        .iter()
        .filter_map(|h| h.stopped.as_deref())
        .collect();
    if stopped.is_empty() {
        return Ok(());
    }
    bail!(
        "{} (outputs up to that time are in {})",
        stopped.join("; "),
        folder.display()
    )
}

/// The transfer of a conduction model's node temperatures onto the temperature nodes of the
/// region's structure model (built by name to ask it), with a description of the target: `None`
/// when the region names no structure or the structure has no temperature-dependent stiffness
/// (the conduction nodes are written as they are), the one conduction-to-structure transfer
/// otherwise ([`GridTransfer::conduction_to_structure`]), whose mismatch is an error.
fn structure_transfer(
    s: &Setup,
    registry: &Registry,
    conduction: &dyn ConductionModel,
) -> Result<Option<(GridTransfer, String)>> {
    let Some(structure_name) = &s.structure else {
        return Ok(None);
    };
    let region = &s.region;
    let settings = region.model_settings(structure_name);
    let structure = registry
        .create::<dyn StructureModel>(
            structure_name,
            &ModelContext::new(region, registry, &settings),
        )
        .with_context(|| {
            format!(
                "structure model `{structure_name}` of region `{}`",
                region.name
            )
        })?;
    let Some(thermal) = structure.thermal_stiffness() else {
        return Ok(None);
    };
    let target = thermal.temperature_grid();
    let transfer = GridTransfer::conduction_to_structure(
        (conduction.node_grid(), conduction.n_nodes()),
        (target, thermal.temperature_nodes()),
    )
    .with_context(|| {
        format!(
            "region `{}`: the temperatures of conduction `{}` onto structure `{structure_name}`",
            region.name,
            conduction.name()
        )
    })?;
    // A transfer exists only between two grids.
    Ok(transfer.zip(target).map(|(transfer, grid)| {
        let on = format!(
            "the {structure_name} grid ({} x {} elements)",
            grid.elements_chordwise, grid.elements_spanwise
        );
        (transfer, on)
    }))
}

/// The final structural temperatures as the `node,temperature_k` CSV that
/// `hsv-run modes --temperature-field` reads: transferred from the conduction grid onto the
/// structure's grid when both are known, else the conduction model's own nodes.
fn write_temperature_field(
    run: &mut RunFolder,
    h: &History,
    transfer: Option<&(GridTransfer, String)>,
) -> Result<()> {
    let path = run.join(&format!("temperature_field_{}.csv", h.model));
    let (values, on) = match transfer {
        Some((transfer, on)) => {
            let mut values = vec![0.0; transfer.n_target()];
            transfer.apply(&h.final_node_temperatures_k, &mut values)?;
            (values, on.clone())
        }
        _ => (
            h.final_node_temperatures_k.clone(),
            "the conduction grid".to_owned(),
        ),
    };
    let mut text = format!(
        "# thickness-averaged structure temperatures of `{}` after {:.3} s in the flow, on {on}\n\
         # input of `hsv-run modes --temperature-field`\nnode,temperature_k\n",
        h.model,
        h.time_s.last().copied().unwrap_or(0.0)
    );
    for (node, t) in values.iter().enumerate() {
        text += &format!("{node},{t}\n");
    }
    output::write_file(&path, text)?;
    run.record(path);
    Ok(())
}

/// CSV history, temperature-range PNG, VTK surface fields with a PVD, final node field CSV,
/// each recorded in the run folder.
fn write_outputs(
    run: &mut RunFolder,
    s: &Setup,
    histories: &[History],
    transfers: &[Option<(GridTransfer, String)>],
) -> Result<()> {
    let mut series = Vec::new();
    for (h, transfer) in histories.iter().zip(transfers) {
        let csv = run.join(&format!("temperature_history_{}.csv", h.model));
        output::write_csv(
            &csv,
            &[
                "time_s",
                "min_temperature_k",
                "max_temperature_k",
                "mean_temperature_k",
            ],
            &[&h.time_s, &h.min_k, &h.max_k, &h.mean_k],
        )?;
        run.record(csv);
        // Labels start with the model: one dash pattern per model, one colour per statistic
        // (output::default_styles).
        let line = |label: &str, y: &[f64]| Series {
            label: format!("{} {label}", h.model),
            x: h.time_s.clone(),
            y: y.to_vec(),
        };
        series.extend([
            line("max", &h.max_k),
            line("mean", &h.mean_k),
            line("min", &h.min_k),
        ]);
        let mut pvd = Vec::new();
        for (i, (t, wall, q)) in h.surface_frames.iter().enumerate() {
            let file = format!("surface_{}_{i:03}.vtk", h.model);
            let path = run.join(&file);
            output::write_vtk_mesh(
                &path,
                &s.region.mesh,
                &[],
                &[("temperature_k", wall), ("heat_flux_w_m2", q)],
            )?;
            run.record(path);
            pvd.push((*t, file));
        }
        let entries: Vec<(f64, &str)> = pvd.iter().map(|(t, f)| (*t, f.as_str())).collect();
        let path = run.join(&format!("surface_{}.pvd", h.model));
        output::write_pvd(&path, &entries)?;
        run.record(path);
        write_temperature_field(run, h, transfer.as_ref())?;
    }
    let f = &s.flight.freestream;
    let png = run.join("temperature_range.png");
    output::write_line_plots_png(
        &png,
        &[LinePlot {
            title: format!(
                "Lifting-surface structure temperature: M {:.2}, {:.0} m, alpha {:.1} deg; \
                 {} on {}",
                f.mach,
                f.altitude_m,
                s.flight.alpha_rad.to_degrees(),
                s.heat_flux,
                s.aero
            ),
            x_label: "time in flow (s)".to_owned(),
            y_label: "temperature (K)".to_owned(),
            series,
        }],
        1,
        (1100, 650),
    )?;
    run.record(png);
    Ok(())
}
