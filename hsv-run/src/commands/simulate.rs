//! `hsv-run simulate`: the partitioned flexible vehicle flown from its trim (paper §IV.C) under
//! the control inputs (default: the paper's elevon doublet), written to a run folder: CSV
//! history with units in the header, JSON summary, PNG plots of the paper's Figs. 11-13 (one file:
//! the flags, the restart file and the outputs all serve the one `run`; the flight itself is
//! [`crate::analysis::flight`]'s).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::registry::Registry;

use super::steps::time_steps;
use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::analysis::flight::{
    Flight, FlightOptions, FlightSettings, RunState, flight_vehicle, rate_seconds,
};
use crate::analysis::simulate::{RunSettings, Sample, simulate};
use crate::analysis::trim::Balance;
use crate::outln;
use crate::output::{
    LinePlot, RunFolder, RunStatus, Series, write_csv, write_line_plots_png, write_pvd,
    write_vtk_mesh,
};
use crate::progress::Progress;
use crate::vehicle::partitioned::{FlightControls, SurfaceModel};

/// Arguments of `hsv-run simulate`.
#[derive(Args, Debug, Clone)]
#[command(
    after_help = "INPUTS: a `[simulation.inputs]` table in the config overrides the \
    doublet, each entry a time table of offsets from trim: `symmetric_elevon_deg = { time_s = \
    [...], value = [...] }`, `differential_elevon_deg`, `fuel_equivalence_ratio`; linear \
    between rows, held beyond them."
)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Flight time, s (paper: 2).
    #[arg(
        long = "duration-s",
        default_value_t = 2.0,
        allow_negative_numbers = true
    )]
    pub duration_s: f64,
    /// Aeroelastic step, s (paper Table 3: 0.001). The default integrator propagates the
    /// surfaces' structure exactly, so any Ritz vector is stable (a 5 % surface's 525 Hz has
    /// ω Δt = 3.3 at 1 ms); `[simulation] integrator = "rk4"` needs ω Δt < 2.83 on the
    /// stiffest one (the sample's is 297 Hz: Δt < 1.5 ms).
    #[arg(long = "dt-s", default_value_t = 0.001, allow_negative_numbers = true)]
    pub dt_s: f64,
    /// Steps between recorded samples.
    #[arg(long = "record-every", default_value_t = 5)]
    pub record_every: usize,
    #[command(flatten)]
    pub output: OutArgs,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Continue the run that wrote this `restart.json` (same config and --dt-s; a longer
    /// --duration-s), bit for bit.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Interval between VTK frames of the deformed, heated vehicle, s (0: none).
    #[arg(
        long = "vtk-interval-s",
        default_value_t = 0.1,
        allow_negative_numbers = true
    )]
    pub vtk_interval_s: f64,
    /// Keep the lifting surfaces at their initial temperature (no in-flight heating).
    #[arg(long = "no-heating")]
    pub no_heating: bool,
    /// Fly the monolithic comparison model (paper §IV): surfaces as OML following the body's
    /// modes, not heated.
    #[arg(long)]
    pub monolithic: bool,
    /// With --monolithic, lump the surfaces' mass and inertia into the body (the paper's
    /// proposed correction).
    #[arg(long = "lumped-surface-mass", requires = "monolithic")]
    pub lumped_surface_mass: bool,
    /// The controller flying the vehicle (`hsv-run models`, role control; overrides
    /// `[control] controller`; default `schedule`: the `[simulation.inputs]` tables).
    #[arg(long, value_name = "NAME")]
    pub controller: Option<String>,
    #[command(flatten)]
    pub disturbances: DisturbanceArgs,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// `--turbulence` and `--gust`: disturbances on top of the config's `[disturbances]`.
#[derive(Args, Debug, Clone, Default)]
pub struct DisturbanceArgs {
    /// Dryden turbulence of MIL-F-8785C severity light, moderate or severe (probability of
    /// exceedance 1e-2, 1e-3, 1e-5; intensity from its Fig. 7 at the flight's altitude: above
    /// 65 000 ft only `severe` is not zero), in place of `[disturbances.dryden]`.
    #[arg(long, value_name = "SEVERITY")]
    pub turbulence: Option<crate::disturbance::Severity>,
    /// Seed of the turbulence (the same seed, the same run).
    #[arg(long = "turbulence-seed", value_name = "N", requires = "turbulence")]
    pub turbulence_seed: Option<u64>,
    /// A vertical 1-cosine gust `W_M_S[,START_S[,HALF_LENGTH_M]]` (w down positive; default
    /// from 0.5 s, rising over 533.4 m = the 1750 ft Dryden scale), added to `[disturbances]`.
    #[arg(long, value_name = "W[,START[,D]]")]
    pub gust: Option<String>,
}

impl DisturbanceArgs {
    /// The config's `[disturbances]` with these flags applied, or None without flags.
    pub fn settings(
        &self,
        loaded: &hsv_core::config::LoadedConfig,
    ) -> Result<Option<crate::disturbance::DisturbanceSettings>> {
        use crate::disturbance::{DisturbanceSettings, DrydenSettings, GustSettings};
        if self.turbulence.is_none() && self.gust.is_none() {
            return Ok(None);
        }
        let mut settings = DisturbanceSettings::from_config(loaded)?;
        if let Some(severity) = self.turbulence {
            settings.dryden = Some(DrydenSettings {
                severity: Some(severity),
                sigma_m_s: None,
                scale_m: crate::disturbance::HIGH_ALTITUDE_SCALE_M,
                seed: self.turbulence_seed.unwrap_or_default(),
            });
        }
        if let Some(text) = &self.gust {
            let numbers = text
                .split(',')
                .map(|p| p.trim().parse::<f64>())
                .collect::<Result<Vec<_>, _>>()
                .ok()
                .filter(|v| (1..=3).contains(&v.len()))
                .with_context(|| {
                    format!("--gust {text}: expected W_M_S[,START_S[,HALF_LENGTH_M]], numbers")
                })?;
            settings.gusts.push(GustSettings {
                amplitude_m_s: [0.0, 0.0, numbers[0]],
                start_s: numbers.get(1).copied().unwrap_or(0.5),
                half_length_m: numbers
                    .get(2)
                    .copied()
                    .unwrap_or(crate::disturbance::HIGH_ALTITUDE_SCALE_M),
            });
        }
        settings
            .check()
            .map_err(|(key, why)| anyhow::anyhow!("--turbulence/--gust: {key}: {why}"))?;
        Ok(Some(settings))
    }
}

/// Tag of the restart file format.
const RESTART_FORMAT: &str = "hsv-restart-3";

/// What `--resume` continues from: written as `restart.json` at the end of every run. Its
/// `step`, `state`, `vehicle` and `control` are the run's [`RunState`] (flattened: the same keys
/// at the top level), the rest says what flew.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct RestartFile {
    format: String,
    dt_s: f64,
    time_s: f64,
    trim_alpha_deg: f64,
    /// The trim's flight-path angle, deg (a glide's; 0 in level flight).
    #[serde(default)]
    trim_flight_path_angle_deg: f64,
    controls: FlightControls,
    #[serde(flatten)]
    run: RunState,
    /// The controller and the design it was built from.
    controller: String,
    #[serde(default)]
    design: Option<crate::analysis::control::DesignRecord>,
}

impl RestartFile {
    fn read(path: &std::path::Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("{}: cannot read the restart file", path.display()))?;
        let file: Self = serde_json::from_str(&text)
            .with_context(|| format!("{}: not an hsv restart file", path.display()))?;
        if file.format != RESTART_FORMAT {
            bail!(
                "{}: restart format `{}`, this hsv-run reads `{RESTART_FORMAT}`",
                path.display(),
                file.format
            );
        }
        Ok(file)
    }
}

/// Trims, flies and writes the run folder.
pub fn run(args: SimulateArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    // Refused up front: a non-positive step or an absurd number of steps.
    let plan = time_steps(args.duration_s, args.dt_s).map_err(|e| {
        anyhow::anyhow!(
            "--duration-s {} with --dt-s {}: {e}",
            args.duration_s,
            args.dt_s
        )
    })?;
    let mach = loaded.config.flight.mach;
    let altitude_m = loaded.config.flight.altitude_m;
    let model = if args.monolithic {
        SurfaceModel::Monolithic {
            lumped_mass: args.lumped_surface_mass,
        }
    } else {
        SurfaceModel::Partitioned
    };
    let options = FlightOptions {
        model,
        heated: !args.no_heating,
        controller: Some(
            crate::analysis::control::control_settings(&loaded, args.controller.as_deref())?.0,
        ),
        dt_s: args.dt_s,
        disturbances: args.disturbances.settings(&loaded)?,
    };
    // From trim, or from where a restart file left off (bit for bit).
    let (
        mut vehicle,
        trim_point,
        trim_controls,
        mut state,
        start_step,
        mut control,
        design,
        settings,
    ) = match &args.resume {
        None => {
            let flight = Flight::trimmed(&loaded, &registry, &options, |line| {
                if !args.quiet {
                    eprintln!("simulate: {line}");
                }
            })?;
            let t = &flight.trim.result.trim;
            let point = (
                t.alpha_deg,
                t.elevon_deg,
                t.fuel_equivalence_ratio,
                t.modal_amplitudes.clone(),
                t.flight_path_angle_deg,
            );
            (
                flight.vehicle,
                point,
                flight.trim.controls,
                flight.state,
                0,
                flight.control,
                flight.design,
                flight.settings,
            )
        }
        Some(path) => {
            let restart = RestartFile::read(path)?;
            if restart.dt_s.to_bits() != args.dt_s.to_bits() {
                bail!(
                    "{}: the run used --dt-s {}, not {}; resume with the same step",
                    path.display(),
                    restart.dt_s,
                    args.dt_s
                );
            }
            if restart.run.step > plan.steps
                || (plan.start_s(restart.run.step) - restart.time_s).abs() > 1e-9 * args.dt_s
            {
                bail!(
                    "{}: the run stopped at t = {} s (step {}), which --duration-s {} does not \
                     continue (give a longer duration, a whole number of steps)",
                    path.display(),
                    restart.time_s,
                    restart.run.step,
                    args.duration_s
                );
            }
            let settings = FlightSettings::from_config(&loaded)?;
            let (controller_name, actuators) =
                crate::analysis::control::control_settings(&loaded, args.controller.as_deref())?;
            let mut vehicle = flight_vehicle(&loaded, &registry, &options, &settings)?;
            vehicle.set_disturbances(crate::analysis::flight::flight_disturbances(
                &loaded, &options,
            )?);
            let stored_name = restart.controller.as_str();
            if stored_name != controller_name {
                bail!(
                    "{}: the run was flown by controller `{stored_name}`, not \
                     `{controller_name}`; resume with the same controller",
                    path.display()
                );
            }
            let (mut control, design) = crate::analysis::control::build_control_loop(
                &loaded,
                &registry,
                &controller_name,
                actuators,
                &mut vehicle,
                &restart.run.state,
                &restart.controls,
                args.dt_s,
                restart.design.clone().map_or(
                    crate::analysis::control::DesignFrom::Vehicle,
                    crate::analysis::control::DesignFrom::Restart,
                ),
            )?;
            control.restore(restart.run.control.clone())?;
            vehicle.restore(&restart.run.vehicle)?;
            let point = (
                restart.trim_alpha_deg,
                restart.controls.elevon.symmetric_rad.to_degrees(),
                restart.controls.fuel_equivalence_ratio,
                Vec::new(),
                restart.trim_flight_path_angle_deg,
            );
            (
                vehicle,
                point,
                restart.controls,
                restart.run.state,
                restart.run.step,
                control,
                design,
                settings,
            )
        }
    };
    let controller_name = options.controller.clone().unwrap_or_default();
    let integrator = settings.integrator;
    let earth = settings.earth;
    let (body_rate, friction_rate, surface_rate) = (
        settings.body_loads,
        settings.body_friction,
        settings.surface_loads,
    );
    let design_report = control.controller().design_report();
    let mut folder = RunFolder::create("simulate", args.output.out.as_deref(), args.output.force)?;
    let run_settings = RunSettings {
        dt_s: args.dt_s,
        integrator,
        duration_s: args.duration_s,
        record_every: args.record_every.max(1),
        start_step,
    };
    let n_steps = plan.steps;
    let mut samples: Vec<Sample> = Vec::with_capacity(n_steps / run_settings.record_every + 2);
    let mut body_modes: Vec<Vec<f64>> = Vec::with_capacity(samples.capacity());
    // Each coupling interface's residual per sample (issue 25: recorded per interface).
    let interface_names = vehicle.interface_names();
    let mut interface_residuals: Vec<Vec<f64>> = Vec::with_capacity(samples.capacity());
    let mut progress = (!args.quiet).then(|| Progress::new("simulate", n_steps));
    let start = Instant::now();
    let mut frames: Vec<(f64, String)> = Vec::new();
    let mut frame_error: Option<anyhow::Error> = None;
    let mut next_frame_s = 0.0;
    let vtk_every = args.vtk_interval_s;
    let folder_path = folder.path.clone();
    let outcome = simulate(
        &mut vehicle,
        &mut state,
        &mut control,
        &run_settings,
        |sample, state, vehicle| {
            samples.push(sample.clone());
            body_modes.push(state.body_modes.q.iter().copied().collect());
            interface_residuals.push(vehicle.interface_residuals().to_vec());
            if vtk_every > 0.0 && sample.time_s >= next_frame_s - 1e-9 && frame_error.is_none() {
                let name = format!("vehicle_{:04}.vtk", frames.len());
                let (mesh, pressure, wall) = vehicle.oml_snapshot();
                match write_vtk_mesh(
                    &folder_path.join(&name),
                    &mesh,
                    &[],
                    &[("pressure_pa", &pressure), ("wall_temperature_k", &wall)],
                ) {
                    Ok(()) => frames.push((sample.time_s, name)),
                    Err(e) => frame_error = Some(e),
                }
                next_frame_s += vtk_every;
            }
            if let Some(p) = progress.as_mut() {
                p.update((sample.time_s / args.dt_s).round() as usize);
            }
            true
        },
    );
    if let Some(p) = progress.as_mut() {
        p.finish();
    }
    let wall_time_s = start.elapsed().as_secs_f64();
    if let Some(e) = frame_error {
        return Err(e.context("writing the VTK frames"));
    }
    for (_, name) in &frames {
        folder.record(folder.join(name));
    }
    if !frames.is_empty() {
        let entries: Vec<(f64, &str)> = frames.iter().map(|(t, f)| (*t, f.as_str())).collect();
        let pvd = folder.join("vehicle.pvd");
        write_pvd(&pvd, &entries)?;
        folder.record(pvd);
    }
    // Where the aero models stood outside their range at the last evaluation.
    let final_flight = vehicle.flight(&state)?;
    let warnings: Vec<String> = vehicle
        .aero_diagnostics()
        .iter()
        .flat_map(|(region, model, d)| {
            crate::aero_job::validity_warnings(model, &final_flight, d)
                .into_iter()
                .map(move |w| format!("{region}: {w}"))
        })
        .collect();
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    // The restart file: the last accepted state and everything the next step depends on.
    let reached = match &outcome {
        Ok(done) => *done,
        Err(_) => samples
            .last()
            .map_or(start_step, |s| (s.time_s / args.dt_s).round() as usize),
    };
    let restart = RestartFile {
        format: RESTART_FORMAT.to_owned(),
        dt_s: args.dt_s,
        time_s: plan.start_s(reached.min(plan.steps)).min(plan.duration_s),
        trim_alpha_deg: trim_point.0,
        trim_flight_path_angle_deg: trim_point.4,
        controls: trim_controls,
        run: RunState {
            step: reached,
            state: state.clone(),
            vehicle: vehicle.restart(),
            control: control.state.clone(),
        },
        controller: controller_name.clone(),
        design: Some(design),
    };
    if !design_report.is_null() {
        let path = folder.join("controller.json");
        crate::output::write_file(&path, serde_json::to_string_pretty(&design_report)?)?;
        folder.record(path);
    }
    let restart_path = folder.join("restart.json");
    crate::output::write_file(&restart_path, serde_json::to_string(&restart)?)?;
    folder.record(restart_path);
    let status = match &outcome {
        Ok(_) => RunStatus::Completed,
        Err(e) => RunStatus::Failed(e.to_string()),
    };
    write_history(
        &mut folder,
        &samples,
        &body_modes,
        (&interface_names, &interface_residuals),
    )?;
    let summary = serde_json::json!({
        "mach": mach,
        "altitude_m": altitude_m,
        "trim": {
            "alpha_deg": trim_point.0,
            "elevon_deg": trim_point.1,
            "fuel_equivalence_ratio": trim_point.2,
            "flight_path_angle_deg": trim_point.4,
            "body_modal_amplitudes": trim_point.3,
        },
        "resumed_from": args.resume.as_ref().map(|p| p.display().to_string()),
        "dt_s": args.dt_s,
        "duration_s": args.duration_s,
        "final_time_s": samples.last().map(|s| s.time_s),
        "final_altitude_m": samples.last().map(|s| s.altitude_m),
        "min_altitude_m": samples.iter().map(|s| s.altitude_m).fold(f64::INFINITY, f64::min),
        "max_coupling_iterations": samples.iter().map(|s| s.coupling_iterations).max(),
        "wall_time_s": wall_time_s,
        "threads": rayon::current_num_threads(),
        "integrator": integrator.name(),
        "earth": earth.name(),
        "body_loads_dt_s": rate_seconds(body_rate),
        "body_friction_dt_s": rate_seconds(friction_rate),
        "surface_loads_dt_s": rate_seconds(surface_rate),
        "warnings": warnings,
        // Which regions flew, with their aero models (a glide has no propulsion region, a
        // vehicle with a fin one more).
        "aero_models": vehicle
            .aero_diagnostics()
            .iter()
            .map(|(region, model, _)| (region.clone(), model.clone()))
            .collect::<std::collections::BTreeMap<_, _>>(),
        "controller": controller_name,
        "controller_design": design_report,
        "saturated_samples": samples.iter().filter(|s| s.elevon_position_saturated
            || s.elevon_rate_saturated || s.phi_position_saturated || s.phi_rate_saturated).count(),
    });
    let written = folder.write_summary(summary, &status)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
    } else {
        let last = samples.last().cloned().unwrap_or_default();
        // Level flight balances the drag with thrust (φ), a glide with its descent (γ).
        let third = match Balance::of(&vehicle) {
            Balance::Thrust => Balance::Thrust.named(trim_point.2),
            Balance::Glide => Balance::Glide.named(trim_point.4),
        };
        outln!(
            "trim: alpha {:.4} deg, elevon {:.4} deg, {third}; flew {:.3} s in {:.2} s of wall \
             time",
            trim_point.0,
            trim_point.1,
            last.time_s,
            wall_time_s
        )?;
        outln!(
            "final: altitude {:.2} m, airspeed {:.2} m/s, alpha {:.4} deg, pitch {:.4} deg, q {:.4} \
             deg/s",
            last.altitude_m,
            last.airspeed_m_s,
            last.alpha_deg,
            last.pitch_deg,
            last.q_deg_s
        )?;
        super::print_gains(&design_report)?;
        outln!("outputs in {}", folder.path.display())?;
    }
    outcome.map(|_| ()).map_err(|e| {
        anyhow::anyhow!(
            "{e} (outputs up to that time are in {})",
            folder.path.display()
        )
    })
}

/// The CSV history and the PNG figures.
fn write_history(
    folder: &mut RunFolder,
    samples: &[Sample],
    body_modes: &[Vec<f64>],
    (interfaces, residuals): (&[String], &[Vec<f64>]),
) -> Result<()> {
    let column = |f: fn(&Sample) -> f64| samples.iter().map(f).collect::<Vec<f64>>();
    let time = column(|s| s.time_s);
    let columns: Vec<(&str, Vec<f64>)> = Sample::COLUMNS
        .iter()
        .enumerate()
        .map(|(i, name)| (*name, samples.iter().map(|s| s.values()[i]).collect()))
        .collect();
    let n_modes = body_modes.first().map_or(0, Vec::len);
    let mode_names: Vec<String> = (0..n_modes)
        .map(|k| format!("body_mode_{}_q", k + 1))
        .collect();
    let mode_columns: Vec<Vec<f64>> = (0..n_modes)
        .map(|k| body_modes.iter().map(|q| q[k]).collect())
        .collect();
    let mut headers: Vec<&str> = columns.iter().map(|(h, _)| *h).collect();
    headers.extend(mode_names.iter().map(String::as_str));
    let mut data: Vec<&[f64]> = columns.iter().map(|(_, c)| c.as_slice()).collect();
    data.extend(mode_columns.iter().map(Vec::as_slice));
    let csv = folder.join("history.csv");
    write_csv(&csv, &headers, &data)?;
    folder.record(csv);
    // The coupling residual of each interface, beside the history (whose columns are also the
    // Python and FMU outputs): `coupling_residual` there is their largest.
    let residual_names: Vec<String> = std::iter::once("time_s".to_owned())
        .chain(interfaces.iter().map(|name| format!("{name}_residual")))
        .collect();
    let residual_columns: Vec<Vec<f64>> = (0..interfaces.len())
        .map(|k| {
            residuals
                .iter()
                .map(|r| r.get(k).copied().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let mut data: Vec<&[f64]> = vec![time.as_slice()];
    data.extend(residual_columns.iter().map(Vec::as_slice));
    let names: Vec<&str> = residual_names.iter().map(String::as_str).collect();
    let csv = folder.join("coupling_residuals.csv");
    write_csv(&csv, &names, &data)?;
    folder.record(csv);
    // A panel of labelled series against time, and of the one partitioned series.
    let lines = |title: &str, y_label: &str, series: Vec<(&str, Vec<f64>)>| LinePlot {
        title: title.to_owned(),
        x_label: "time (s)".to_owned(),
        y_label: y_label.to_owned(),
        series: series
            .into_iter()
            .map(|(label, y)| Series {
                label: label.to_owned(),
                x: time.clone(),
                y,
            })
            .collect(),
    };
    let plot =
        |title: &str, y_label: &str, y: Vec<f64>| lines(title, y_label, vec![("partitioned", y)]);
    let figures = [
        plot(
            "Altitude (paper Fig. 11)",
            "altitude (m)",
            column(|s| s.altitude_m),
        ),
        plot("Airspeed", "airspeed (m/s)", column(|s| s.airspeed_m_s)),
        plot(
            "Pitch angle (Fig. 12)",
            "pitch (deg)",
            column(|s| s.pitch_deg),
        ),
        plot("Pitch rate (Fig. 12)", "q (deg/s)", column(|s| s.q_deg_s)),
        plot(
            "Angle of attack (Fig. 13)",
            "alpha (deg)",
            column(|s| s.alpha_deg),
        ),
        plot("Elevon (Fig. 10)", "elevon (deg)", column(|s| s.elevon_deg)),
        lines(
            "Lifting-surface structure temperature (Fig. 14)",
            "temperature (K)",
            vec![
                ("max", column(|s| s.surface_max_temperature_k)),
                ("mean", column(|s| s.surface_mean_temperature_k)),
                ("min", column(|s| s.surface_min_temperature_k)),
            ],
        ),
    ];
    let png = folder.join("history.png");
    write_line_plots_png(&png, &figures, 2, (1200, 1400))?;
    folder.record(png);
    // What the controller asked for against what the actuators did, and the air it flew in.
    let commands = [
        lines(
            "Symmetric elevon",
            "elevon (deg)",
            vec![
                ("command", column(|s| s.command_elevon_deg)),
                ("position", column(|s| s.elevon_deg)),
            ],
        ),
        lines(
            "Differential elevon",
            "differential elevon (deg)",
            vec![
                ("command", column(|s| s.command_differential_elevon_deg)),
                ("position", column(|s| s.differential_elevon_deg)),
            ],
        ),
        lines(
            "Fuel equivalence ratio",
            "phi",
            vec![
                ("command", column(|s| s.command_fuel_equivalence_ratio)),
                ("position", column(|s| s.fuel_equivalence_ratio)),
            ],
        ),
        lines(
            "Gust at the centre of mass (body axes)",
            "gust (m/s)",
            vec![
                ("u", column(|s| s.gust_u_m_s)),
                ("v", column(|s| s.gust_v_m_s)),
                ("w", column(|s| s.gust_w_m_s)),
            ],
        ),
    ];
    let png = folder.join("commands.png");
    write_line_plots_png(&png, &commands, 2, (1200, 800))?;
    folder.record(png);
    Ok(())
}
