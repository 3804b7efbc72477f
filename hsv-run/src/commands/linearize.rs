//! `hsv-run linearize`: A, B, C, D of the trimmed flexible vehicle by central differences, with
//! its eigenvalues named (short period, phugoid, roll, Dutch roll, spiral, structural modes),
//! written as JSON and CSV to a run folder.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;

use super::shared::linear_grid::write_grid_folder;
use super::shared::shard::absolute;
use super::{ConfigArg, JsonFlag, load_config};
use crate::analysis::linear_grid::{LinearGridSpec, linearize_shard};
use crate::analysis::linearize::linearize_at;
use crate::analysis::shards::{Shard, ShardedStudy};
use crate::dynamics::PerturbationRule;
use crate::outln;
use crate::output::{RunFolder, RunStatus, write_file};

/// Arguments of `hsv-run linearize`.
#[derive(Args, Debug, Clone)]
pub struct LinearizeArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Perturbation relative to each trim value (paper Eq. 7: 1 %); positions take this fraction
    /// of 100 m (1 m at 1 %), not of their value.
    #[arg(long, default_value_t = 0.01)]
    pub relative: f64,
    /// Perturbation of a trim value that is zero (state units).
    #[arg(long, default_value_t = 1e-6)]
    pub absolute: f64,
    /// Run folder (default: `runs/linearize-<UTC time>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write into a non-empty --out folder.
    #[arg(long)]
    pub force: bool,
    /// Also close the loop with this controller (`lqr`) and print the closed-loop eigenvalues
    /// of the full flexible linear model, with the `[control.actuators]` lags and the sample
    /// hold's and sensors' delay in the loop.
    #[arg(long, value_name = "NAME", conflicts_with = "grid")]
    pub controller: Option<String>,
    /// Flight Mach number(s), comma separated (default: the config's `[flight] mach`); more
    /// than one needs --grid.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub mach: Vec<f64>,
    /// Geometric altitude(s), m, comma separated (default: the config's `[flight]
    /// altitude_m`); more than one needs --grid.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub altitude_m: Vec<f64>,
    /// Linearize at every --mach × --altitude-m point (side by side) and write them all to
    /// `linear_models.npz` (numpy: A, B, C, D of shape (Mach, altitude, rows, columns), trim
    /// values, names) for gain scheduling and LPV design.
    #[arg(long)]
    pub grid: bool,
    /// With --grid: only shard K of N of the points (0-based; point i, Mach-major, belongs to
    /// shard i mod N); join the shard folders with `hsv-run merge`.
    #[arg(long, value_name = "K/N", requires = "grid")]
    pub shard: Option<String>,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// A matrix as CSV rows with a header of column names and a first column of row names.
fn matrix_csv(m: &nalgebra::DMatrix<f64>, rows: &[String], columns: &[String]) -> String {
    let mut text = format!("row,{}\n", columns.join(","));
    for (i, name) in rows.iter().enumerate() {
        let values: Vec<String> = (0..m.ncols()).map(|j| format!("{:e}", m[(i, j)])).collect();
        text += &format!("{name},{}\n", values.join(","));
    }
    text
}

/// Trims, linearizes and writes the run folder (a grid's with --grid).
pub fn run(args: LinearizeArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let rule = PerturbationRule {
        relative: args.relative,
        absolute: args.absolute,
    };
    rule.steps(&nalgebra::DVector::zeros(1))?;
    let flight = &loaded.config.flight;
    let machs = if args.mach.is_empty() {
        vec![flight.mach]
    } else {
        args.mach.clone()
    };
    let altitudes_m = if args.altitude_m.is_empty() {
        vec![flight.altitude_m]
    } else {
        args.altitude_m.clone()
    };
    if args.grid {
        return run_grid(&args, &loaded, &registry, &machs, &altitudes_m, rule);
    }
    let (&[mach], &[altitude_m]) = (machs.as_slice(), altitudes_m.as_slice()) else {
        anyhow::bail!(
            "--mach and --altitude-m take one value each without --grid (got {} and {}); add \
             --grid to linearize over every pair",
            machs.len(),
            altitudes_m.len()
        );
    };
    let (mut vehicle, trimmed, lin) = linearize_at(&loaded, &registry, &rule, mach, altitude_m)?;
    let (t, controls, state) = (&trimmed.result.trim, &trimmed.controls, &trimmed.state);
    let closed = match &args.controller {
        None => None,
        Some(name) => {
            let (control, _) = crate::analysis::control::build_control_loop(
                &loaded,
                &registry,
                name,
                None,
                &mut vehicle,
                state,
                controls,
                1e-3,
                crate::analysis::control::DesignFrom::Linear(lin.model.clone()),
            )?;
            let laws = control.controller().state_feedback();
            if laws.is_empty() {
                anyhow::bail!("controller `{name}` is no linear state feedback: no closed loop");
            }
            let dynamics =
                crate::analysis::control::loop_dynamics(&loaded, name, control.controller())?;
            let values = crate::analysis::control::design::closed_loop_eigenvalues(
                &lin.model, &laws, &dynamics,
            )
            .map_err(|e| anyhow::anyhow!("closing the loop with `{name}`: {e}"))?;
            Some((
                name.clone(),
                values,
                control.controller().design_report(),
                dynamics,
            ))
        }
    };
    let mut folder = RunFolder::create("linearize", args.out.as_deref(), args.force)?;
    let m = &lin.model;
    for (name, matrix, rows, columns) in [
        ("A.csv", &m.a, &m.state_names, &m.state_names),
        ("B.csv", &m.b, &m.state_names, &m.input_names),
        ("C.csv", &m.c, &m.output_names, &m.state_names),
        ("D.csv", &m.d, &m.output_names, &m.input_names),
    ] {
        let path = folder.join(name);
        write_file(&path, matrix_csv(matrix, rows, columns))?;
        folder.record(path);
    }
    let mut modes_csv = String::from(
        "name,real_per_s,imaginary_rad_s,natural_frequency_rad_s,damped_frequency_hz,damping_ratio,time_to_half_or_double_s\n",
    );
    for mode in &lin.modes {
        modes_csv += &format!(
            "{},{:e},{:e},{:e},{:e},{:e},{}\n",
            mode.name,
            mode.real_per_s,
            mode.imaginary_rad_s,
            mode.natural_frequency_rad_s,
            mode.damped_frequency_hz,
            mode.damping_ratio,
            mode.time_to_half_or_double_s
                .map_or_else(String::new, |v| format!("{v:e}"))
        );
    }
    let path = folder.join("modes.csv");
    write_file(&path, modes_csv)?;
    folder.record(path);
    let path = folder.join("linear_model.json");
    write_file(&path, serde_json::to_string_pretty(&lin.model)?)?;
    folder.record(path);
    let summary = serde_json::json!({
        "mach": mach,
        "altitude_m": altitude_m,
        "trim": {
            "alpha_deg": t.alpha_deg,
            "elevon_deg": t.elevon_deg,
            "fuel_equivalence_ratio": t.fuel_equivalence_ratio,
            "flight_path_angle_deg": t.flight_path_angle_deg,
        },
        "states": m.state_names.len(),
        "inputs": m.input_names,
        "outputs": m.output_names,
        "modes": lin.modes,
        "closed_loop": closed.as_ref().map(|(name, values, design, dynamics)| serde_json::json!({
            "controller": name,
            "eigenvalues_re_im": values,
            "design": design,
            "elevon_time_constant_s": dynamics.elevon_time_constant_s,
            "phi_time_constant_s": dynamics.phi_time_constant_s,
            "delay_s": dynamics.delay_s,
        })),
    });
    let written = folder.write_summary(summary, &RunStatus::Completed)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
        return Ok(());
    }
    outln!(
        "linearized at trim alpha {:.4} deg, elevon {:.4} deg, {}: {} states, {} inputs, {} outputs",
        t.alpha_deg,
        t.elevon_deg,
        t.balance_named(),
        m.state_names.len(),
        m.input_names.len(),
        m.output_names.len()
    )?;
    outln!(
        "{:<26} {:>13} {:>13} {:>11} {:>10}",
        "mode",
        "Re (1/s)",
        "Im (rad/s)",
        "f_d (Hz)",
        "zeta"
    )?;
    for mode in &lin.modes {
        outln!(
            "{:<26} {:>13.5e} {:>13.5e} {:>11.4} {:>10.4}",
            mode.name.to_string(),
            mode.real_per_s,
            mode.imaginary_rad_s,
            mode.damped_frequency_hz,
            mode.damping_ratio
        )?;
    }
    if let Some((name, values, design, dynamics)) = &closed {
        super::print_gains(design)?;
        outln!(
            "closed loop under `{name}` (full flexible model; actuator lags {} s elevon, {} s \
             phi; delay {} s as first-order Pade), eigenvalues by real part, largest first:",
            dynamics.elevon_time_constant_s,
            dynamics.phi_time_constant_s,
            dynamics.delay_s
        )?;
        for v in values {
            outln!("  {:>13.5e} {:>+13.5e} i", v[0], v[1])?;
        }
    }
    outln!("outputs in {}", folder.path.display())?;
    Ok(())
}

/// `linearize --grid`: every point trimmed and linearized side by side, the points written to
/// `linear-grid-cases.json` and, for the whole grid (not a shard of it), to
/// `linear_models.npz` ([`write_grid_folder`]).
fn run_grid(
    args: &LinearizeArgs,
    loaded: &LoadedConfig,
    registry: &Registry,
    machs: &[f64],
    altitudes_m: &[f64],
    rule: PerturbationRule,
) -> Result<()> {
    let config = (args.config.config.as_deref()).map(absolute).transpose()?;
    let spec = LinearGridSpec::new(machs, altitudes_m, rule, config, loaded)?;
    let shard = Shard::from_flag(args.shard.as_deref())?;
    let mut folder = RunFolder::create("linearize", args.out.as_deref(), args.force)?;
    let total = shard.cases(spec.case_count()).len();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let output = linearize_shard(&spec, loaded, registry, shard, |point| {
        let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        let how = point
            .error
            .as_deref()
            .map_or_else(|| "linearized".to_owned(), |e| format!("no model: {e}"));
        eprintln!(
            "linearize: point {k}/{total} (Mach {}, {} m): {how}",
            point.mach, point.altitude_m
        );
    });
    write_grid_folder(&mut folder, &output, args.json.json)
}
