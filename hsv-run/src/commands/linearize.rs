//! `hsv-run linearize`: A, B, C, D of the trimmed flexible vehicle by central differences, with
//! its eigenvalues named (short period, phugoid, roll, Dutch roll, spiral, structural modes),
//! written as JSON and CSV to a run folder.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use hsv_core::registry::Registry;

use super::{ConfigArg, JsonFlag, load_config};
use crate::analysis::linearize::linearize_configured;
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
    /// Run folder (default: runs/linearize-<UTC time>).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write into a non-empty --out folder.
    #[arg(long)]
    pub force: bool,
    /// Also close the loop with this controller (`lqr`) and print the closed-loop eigenvalues
    /// of the full flexible linear model.
    #[arg(long, value_name = "NAME")]
    pub controller: Option<String>,
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

/// Trims, linearizes and writes the run folder.
pub fn run(args: LinearizeArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let rule = PerturbationRule {
        relative: args.relative,
        absolute: args.absolute,
    };
    rule.steps(&nalgebra::DVector::zeros(1))?;
    let (mut vehicle, trimmed, lin) = linearize_configured(&loaded, &registry, &rule)?;
    let (t, controls, state) = (&trimmed.result.trim, &trimmed.controls, &trimmed.state);
    let closed = match &args.controller {
        None => None,
        Some(name) => {
            let (control, _) = crate::control::build_control_loop(
                &loaded,
                &registry,
                name,
                None,
                &mut vehicle,
                state,
                controls,
                1e-3,
                crate::control::DesignFrom::Linear(lin.model.clone()),
            )?;
            let laws = control.controller().state_feedback();
            if laws.is_empty() {
                anyhow::bail!("controller `{name}` is no linear state feedback: no closed loop");
            }
            let values = crate::control::design::closed_loop_eigenvalues(&lin.model, &laws)
                .map_err(|e| anyhow::anyhow!("closing the loop with `{name}`: {e}"))?;
            Some((name.clone(), values, control.controller().design_report()))
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
        "mach": loaded.config.flight.mach,
        "altitude_m": loaded.config.flight.altitude_m,
        "trim": {
            "alpha_deg": t.alpha_deg,
            "elevon_deg": t.elevon_deg,
            "fuel_equivalence_ratio": t.fuel_equivalence_ratio,
        },
        "states": m.state_names.len(),
        "inputs": m.input_names,
        "outputs": m.output_names,
        "modes": lin.modes,
        "closed_loop": closed.as_ref().map(|(name, values, design)| serde_json::json!({
            "controller": name,
            "eigenvalues_re_im": values,
            "design": design,
        })),
    });
    let written = folder.write_summary(summary, &RunStatus::Completed)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
        return Ok(());
    }
    outln!(
        "linearized at trim alpha {:.4} deg, elevon {:.4} deg, phi {:.4}: {} states, {} inputs, {} outputs",
        t.alpha_deg,
        t.elevon_deg,
        t.fuel_equivalence_ratio,
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
    if let Some((name, values, design)) = &closed {
        super::simulate::print_gains(design)?;
        outln!(
            "closed loop under `{name}` (full flexible model), eigenvalues by real part, largest \
             first:"
        )?;
        for v in values {
            outln!("  {:>13.5e} {:>+13.5e} i", v[0], v[1])?;
        }
    }
    outln!("outputs in {}", folder.path.display())?;
    Ok(())
}
