//! `hsv-run heat`: one lifting surface, uniformly at 293 K, exposed to steady flow for a while;
//! the heat flux of a heat-flux model on the edge states of an aero model drives each requested
//! conduction model, and the temperature history of the structure is written out.
//!
//! The surface is rigid and undeflected, so one aero evaluation serves the whole run; the heat
//! flux is re-evaluated from the current wall temperatures every `--flux-interval-s` (paper
//! Table 3: 10 ms) and the conduction model advances by `--dt-s` (paper: 1 ms; default 0.1 s
//! here, which the implicit models take without loss of stability).
//!
//! A `pod` model needs its basis file (`[models.pod] basis_file`); when it is missing this
//! command builds it from `full-order` snapshots of the same surface at the Mach numbers of
//! `--snapshot-mach` (default: the run's Mach number and ± 1) at the run's altitude and
//! duration, and saves it there. A basis from other conditions reproduces the mean temperature
//! closely but the sharp leading edge's peak less well (Mach 6, 26 km, 20 s from Mach 5 and 7
//! snapshots: 43 K low at a 533 K peak; from Mach 4, 5, 7, 8: 14 K).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::mesh::PanelMesh;
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::{ConductionModel, HeatFluxModel};
use hsv_core::vehicle::Side;
use hsv_model_conduction::{FullOrderSettings, PodBasis, PodSettings};

use super::{ConfigArg, JsonFlag, load_config};
use crate::output::{self, LinePlot, Series};
use crate::progress::Progress;

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
    /// Run folder (default: runs/heat-<UTC time>).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
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

/// The flight condition, the right lifting surface mesh and its edge states.
struct Setup {
    flight: FlightCondition,
    mesh: PanelMesh,
    aero: AeroSolution,
    heat_flux: String,
    region: RegionInfo,
}

/// The heated lifting surface: the right one (the left is its mirror image).
const HEATED_REGION: &str = "right_surface";

fn check_positive(flag: &str, value: f64) -> Result<()> {
    if !(value.is_finite() && value > 0.0) {
        bail!("{flag} must be a positive number, got {value}");
    }
    Ok(())
}

/// Flight condition at `mach`, and the edge states of the aero model on the surface mesh.
fn setup(loaded: &LoadedConfig, registry: &Registry, args: &HeatArgs, mach: f64) -> Result<Setup> {
    let flight_cfg = loaded.config.flight;
    let altitude_m = args.altitude_m.unwrap_or(10_000.0);
    let alpha_deg = args.alpha_deg.unwrap_or(flight_cfg.alpha_deg);
    if !alpha_deg.is_finite() {
        bail!("--alpha-deg must be a finite number, got {alpha_deg}");
    }
    let freestream = Freestream::standard(mach, altitude_m, loaded.config.gas)?;
    let flight = FlightCondition::steady(freestream, alpha_deg.to_radians(), 0.0);
    let region = loaded.region(HEATED_REGION)?;
    let aero_name = match &args.aero {
        Some(name) => name.clone(),
        None => loaded
            .config
            .regions
            .region(HEATED_REGION)
            .and_then(|r| r.aero)
            .unwrap_or_else(|| "shock-expansion".to_owned()),
    };
    let settings = region.model_settings(&aero_name);
    let mut aero_model = registry
        .create::<dyn AeroModel>(&aero_name, &ModelContext::new(&region, registry, &settings))?;
    let mut aero = AeroSolution::default();
    aero_model
        .evaluate(&region.mesh, &flight, &PanelMotion::default(), &mut aero)
        .with_context(|| format!("aero model `{aero_name}`"))?;
    let heat_flux = match &args.heat_flux {
        Some(name) => name.clone(),
        None => loaded
            .config
            .regions
            .region(HEATED_REGION)
            .and_then(|r| r.heat_flux)
            .unwrap_or_else(|| "eckert".to_owned()),
    };
    Ok(Setup {
        flight,
        mesh: region.mesh.clone(),
        aero,
        heat_flux,
        region,
    })
}

/// Runs `conduction` from a uniform temperature for the run's duration.
fn run_model(
    name: &str,
    conduction: &mut dyn ConductionModel,
    heat: &mut dyn HeatFluxModel,
    s: &Setup,
    args: &HeatArgs,
    samples: usize,
) -> Result<History> {
    let n_panels = s.mesh.panels.len();
    if conduction.n_surface_panels() != n_panels {
        bail!(
            "conduction model `{name}` takes {} surface panels, the lifting surface mesh has {n_panels}",
            conduction.n_surface_panels()
        );
    }
    let steps = (args.duration_s / args.dt_s).round().max(1.0) as usize;
    let flux_every = args
        .flux_interval_s
        .map_or(1, |f| ((f / args.dt_s).round() as usize).max(1));
    let record_every = (steps / samples.max(1)).max(1);
    let frame_every = (steps / 10).max(1);
    let mut state = conduction
        .uniform_state(args.initial_k)
        .with_context(|| format!("conduction model `{name}`"))?;
    let mut wall = vec![0.0; n_panels];
    let mut q = vec![0.0; n_panels];
    let mut nodes = vec![0.0; conduction.n_nodes()];
    let mut history = History {
        model: name.to_owned(),
        time_s: Vec::new(),
        min_k: Vec::new(),
        max_k: Vec::new(),
        mean_k: Vec::new(),
        conduction_wall_time_s: 0.0,
        steps,
        states: conduction.n_states(),
        final_node_temperatures_k: Vec::new(),
        stopped: None,
        surface_frames: Vec::new(),
    };
    record(conduction, 0.0, &state, &mut nodes, &mut history);
    let mut t_end = steps as f64 * args.dt_s;
    let mut progress = Progress::new(format!("heat: {name}"), steps);
    for k in 0..steps {
        let t = k as f64 * args.dt_s;
        if k % flux_every == 0 {
            conduction.surface_temperatures(&state, &mut wall);
            if let Err(e) = heat.heat_flux(&s.mesh, &s.flight, &s.aero, &wall, &mut q) {
                history.stopped = Some(format!("heat flux for `{name}` at t = {t:.3} s: {e}"));
                t_end = t;
                break;
            }
        }
        if k % frame_every == 0 {
            history.surface_frames.push((t, wall.clone(), q.clone()));
        }
        let start = Instant::now();
        let mut trial = state.clone();
        if let Err(e) = conduction.step(&mut trial, &q, args.dt_s) {
            // Keep the last good state: what was computed so far stays in the outputs.
            history.stopped = Some(format!("conduction model `{name}` at t = {t:.3} s: {e}"));
            t_end = t;
            break;
        }
        state = trial;
        progress.update(k + 1);
        history.conduction_wall_time_s += start.elapsed().as_secs_f64();
        if (k + 1) % record_every == 0 || k + 1 == steps {
            record(
                conduction,
                (k + 1) as f64 * args.dt_s,
                &state,
                &mut nodes,
                &mut history,
            );
        }
    }
    if history.stopped.is_some() {
        record(conduction, t_end, &state, &mut nodes, &mut history);
    }
    conduction.surface_temperatures(&state, &mut wall);
    history.surface_frames.push((t_end, wall, q));
    Ok(history)
}

/// Appends the structure's min/max/mean node temperature at time `t` to `h`.
fn record(
    conduction: &dyn ConductionModel,
    t: f64,
    state: &nalgebra::DVector<f64>,
    nodes: &mut [f64],
    h: &mut History,
) {
    conduction.node_temperatures(state, nodes);
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

/// Builds and saves the POD basis from full-order snapshots at the snapshot Mach numbers.
fn build_pod_basis(
    loaded: &LoadedConfig,
    registry: &Registry,
    args: &HeatArgs,
    mach: f64,
    path: &std::path::Path,
    modes: usize,
) -> Result<PodBasis> {
    let full_settings: FullOrderSettings = hsv_core::config::parse_table(
        loaded.model_settings("full-order"),
        &loaded.file,
        "models.full-order",
    )?;
    let machs = if args.snapshot_mach.is_empty() {
        // Bracket the run's heating from below and at it: a snapshot run hotter than the run
        // itself could leave the material data (Mach 7 at 10 km nears the solidus in 100 s).
        vec![(mach - 1.0).max(1.5), (mach - 0.5).max(1.5), mach]
    } else {
        args.snapshot_mach.clone()
    };
    let region = loaded.region(HEATED_REGION)?;
    let pod_settings = region.model_settings("pod");
    let mut full =
        hsv_model_conduction::full_order_for(&ModelContext::new(&region, registry, &pod_settings))?;
    let steps = (args.duration_s / args.dt_s).round().max(1.0) as usize;
    let every = (steps / 100).max(1);
    let mut snapshots = Vec::new();
    for &m in &machs {
        check_positive("--snapshot-mach", m)?;
        let s = setup(loaded, registry, args, m)?;
        let settings = s.region.model_settings(&s.heat_flux);
        let mut heat = registry.create::<dyn HeatFluxModel>(
            &s.heat_flux,
            &ModelContext::new(&s.region, registry, &settings),
        )?;
        let mut progress = Progress::new(format!("POD snapshots at Mach {m}"), steps);
        let mut done = 0;
        let run = hsv_model_conduction::collect_snapshots(
            &mut full,
            args.initial_k,
            args.dt_s,
            steps,
            every,
            |wall, q| {
                done += 1;
                progress.update(done);
                heat.heat_flux(&s.mesh, &s.flight, &s.aero, wall, q)
            },
        )
        .with_context(|| format!("full-order snapshot run at Mach {m}"))?;
        snapshots.extend(run);
    }
    let basis = PodBasis::from_snapshots(&snapshots, modes, full_settings)?;
    basis.save(path)?;
    Ok(basis)
}

/// Runs the heating job and writes the run folder.
pub fn run(args: HeatArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let registry = &registry;
    let mach = args.mach.unwrap_or(loaded.config.flight.mach);
    check_positive("--mach", mach)?;
    check_positive("--duration-s", args.duration_s)?;
    check_positive("--dt-s", args.dt_s)?;
    check_positive("--initial-k", args.initial_k)?;
    if let Some(f) = args.flux_interval_s {
        check_positive("--flux-interval-s", f)?;
    }
    let models = if args.models.is_empty() {
        vec!["full-order".to_owned(), "pod".to_owned()]
    } else {
        args.models.clone()
    };
    let s = setup(&loaded, registry, &args, mach)?;
    let folder = output::run_folder("heat", args.out.as_deref())?;
    let mut notes = Vec::new();
    let mut histories = Vec::new();
    for name in &models {
        if name == "pod" {
            let pod: PodSettings = hsv_core::config::parse_table(
                loaded.model_settings("pod"),
                &loaded.file,
                "models.pod",
            )?;
            let path = PathBuf::from(&pod.basis_file);
            if !path.exists() {
                let basis = build_pod_basis(&loaded, registry, &args, mach, &path, pod.modes)?;
                notes.push(format!(
                    "built POD basis {} ({} modes from {} snapshots, energy fraction {:.9})",
                    path.display(),
                    basis.n_modes(),
                    basis.n_snapshots,
                    basis.energy_fraction
                ));
            }
        }
        let settings = s.region.model_settings(name);
        let mut conduction = registry.create::<dyn ConductionModel>(
            name,
            &ModelContext::new(&s.region, registry, &settings),
        )?;
        let settings = s.region.model_settings(&s.heat_flux);
        let mut heat = registry.create::<dyn HeatFluxModel>(
            &s.heat_flux,
            &ModelContext::new(&s.region, registry, &settings),
        )?;
        histories.push(run_model(
            name,
            conduction.as_mut(),
            heat.as_mut(),
            &s,
            &args,
            200,
        )?);
    }
    let grids = temperature_field_grids(&loaded, registry)?;
    write_outputs(&folder, &s, &histories, grids.as_ref())?;

    if args.json.json {
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
        let summary = serde_json::json!({
            "mach": mach,
            "altitude_m": s.flight.freestream.altitude_m,
            "alpha_deg": s.flight.alpha_rad.to_degrees(),
            "duration_s": args.duration_s,
            "dt_s": args.dt_s,
            "heat_flux_model": s.heat_flux,
            "initial_temperature_k": args.initial_k,
            "run_folder": folder.display().to_string(),
            "notes": notes,
            "models": models,
        });
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return stopped_error(&histories, &folder);
    }
    println!(
        "lifting surface ({} panels) at Mach {mach}, {} m, alpha {:.2} deg for {} s (dt {} s), heat flux `{}`",
        s.mesh.panels.len(),
        s.flight.freestream.altitude_m,
        s.flight.alpha_rad.to_degrees(),
        args.duration_s,
        args.dt_s,
        s.heat_flux
    );
    for note in &notes {
        println!("{note}");
    }
    println!(
        "{:<14} {:>7} {:>9} {:>12} {:>12} {:>12} {:>14}",
        "model", "states", "t (s)", "min T (K)", "max T (K)", "mean T (K)", "wall time (s)"
    );
    for h in &histories {
        println!(
            "{:<14} {:>7} {:>9.2} {:>12.2} {:>12.2} {:>12.2} {:>14.3}",
            h.model,
            h.states,
            h.time_s.last().copied().unwrap_or(0.0),
            h.min_k.last().copied().unwrap_or(f64::NAN),
            h.max_k.last().copied().unwrap_or(f64::NAN),
            h.mean_k.last().copied().unwrap_or(f64::NAN),
            h.conduction_wall_time_s
        );
    }
    println!("outputs in {}", folder.display());
    println!(
        "final fields for `hsv-run modes --temperature-field`: {}",
        folder.join("temperature_field_<model>.csv").display()
    );
    stopped_error(&histories, &folder)
}

/// An error naming every model that stopped early (outputs up to that time are written).
fn stopped_error(histories: &[History], folder: &std::path::Path) -> Result<()> {
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

/// The conduction grid and the lifting-surface structure's grid, when the structure is a
/// `ritz-plate` on the vehicle planform: node temperatures are handed from one to the other.
fn temperature_field_grids(
    loaded: &LoadedConfig,
    registry: &Registry,
) -> Result<Option<(SurfaceGrid, SurfaceGrid)>> {
    let region = loaded.region(HEATED_REGION)?;
    let structure_name = loaded
        .config
        .regions
        .region(HEATED_REGION)
        .and_then(|r| r.structure);
    if structure_name.as_deref() != Some("ritz-plate") {
        return Ok(None);
    }
    let settings = region.model_settings("ritz-plate");
    let context = ModelContext::new(&region, registry, &settings);
    let ritz: hsv_model_ritz_plate::Settings = context.parse_settings()?;
    if ritz.planform != hsv_model_ritz_plate::PlanformChoice::Vehicle {
        return Ok(None);
    }
    let full: FullOrderSettings =
        ModelContext::new(&region, registry, &region.model_settings("full-order"))
            .parse_settings()?;
    // Node order is the same on both sides; resample on the right-hand planform.
    let conduction = SurfaceGrid::lifting_surface(
        &loaded.config.lifting_surface,
        Side::Right,
        full.elements_chordwise,
        full.elements_spanwise,
    )?;
    let (structure, _) = hsv_model_ritz_plate::structural_grid(&ritz, &context)?;
    Ok(Some((conduction, structure)))
}

/// The final structural temperatures as the `node,temperature_k` CSV that
/// `hsv-run modes --temperature-field` reads: resampled from the conduction grid onto the
/// structure's grid when both are known (`grids`), else the conduction model's own nodes.
fn write_temperature_field(
    folder: &std::path::Path,
    h: &History,
    grids: Option<&(SurfaceGrid, SurfaceGrid)>,
) -> Result<()> {
    let path = folder.join(format!("temperature_field_{}.csv", h.model));
    let (values, on) = match grids {
        Some((conduction, structure))
            if conduction.n_nodes() == h.final_node_temperatures_k.len() =>
        {
            (
                conduction.resample(&h.final_node_temperatures_k, structure),
                format!(
                    "the ritz-plate grid ({} x {} elements)",
                    structure.elements_chordwise, structure.elements_spanwise
                ),
            )
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
    std::fs::write(&path, text)
        .with_context(|| format!("cannot write the temperature field {}", path.display()))
}

/// CSV history, temperature-range PNG, VTK surface fields with a PVD, final node field CSV.
fn write_outputs(
    folder: &std::path::Path,
    s: &Setup,
    histories: &[History],
    grids: Option<&(SurfaceGrid, SurfaceGrid)>,
) -> Result<()> {
    let mut plots = Vec::new();
    for h in histories {
        output::write_csv(
            &folder.join(format!("temperature_history_{}.csv", h.model)),
            &[
                "time_s",
                "min_temperature_k",
                "max_temperature_k",
                "mean_temperature_k",
            ],
            &[&h.time_s, &h.min_k, &h.max_k, &h.mean_k],
        )?;
        let series = |label: &str, y: &[f64]| Series {
            label: format!("{} {label}", h.model),
            x: h.time_s.clone(),
            y: y.to_vec(),
        };
        plots.push(series("max", &h.max_k));
        plots.push(series("mean", &h.mean_k));
        plots.push(series("min", &h.min_k));
        let mut pvd = Vec::new();
        for (i, (t, wall, q)) in h.surface_frames.iter().enumerate() {
            let file = format!("surface_{}_{i:03}.vtk", h.model);
            output::write_vtk_mesh(
                &folder.join(&file),
                &s.mesh,
                &[],
                &[("temperature_k", wall), ("heat_flux_w_m2", q)],
            )?;
            pvd.push((*t, file));
        }
        let entries: Vec<(f64, &str)> = pvd.iter().map(|(t, f)| (*t, f.as_str())).collect();
        output::write_pvd(&folder.join(format!("surface_{}.pvd", h.model)), &entries)?;
        write_temperature_field(folder, h, grids)?;
    }
    output::write_line_plots_png(
        &folder.join("temperature_range.png"),
        &[LinePlot {
            title: "Temperature range of the lifting surface structure".to_owned(),
            x_label: "time in flow (s)".to_owned(),
            y_label: "temperature (K)".to_owned(),
            series: plots,
        }],
        1,
        (1000, 650),
    )
}
