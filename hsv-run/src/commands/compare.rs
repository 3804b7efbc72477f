//! `hsv-run compare`: the partitioned and the monolithic vehicle side by side (paper §IV, Table 2
//! and Figs. 11-13): their trims (rigid and flexible) in the Table 2 layout, and the time
//! histories of the elevon doublet overlaid; the monolithic model with and without the
//! surfaces' mass lumped into the body (the correction the paper proposes). The partitioned
//! vehicle flies twice, with the body-surface interface closed in every stage (`implicit`) and
//! with the paper's staggered exchange once per step to `[coupling] residual_tolerance_m`
//! (`staggered`); both trim alike (a steady state has nothing to stagger).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use hsv_core::config::CouplingSchemeName;
use hsv_core::registry::Registry;

use super::{ConfigArg, JsonFlag, load_config};
use crate::analysis::flight::{Flight, FlightOptions};
use crate::analysis::simulate::Sample;
use crate::analysis::trim::{Balance, TrimPoint, TrimRequest, trim};
use crate::outln;
use crate::output::{LinePlot, RunFolder, RunStatus, Series, write_csv, write_line_plots_png};
use crate::vehicle::assemble;
use crate::vehicle::partitioned::SurfaceModel;
use crate::vehicle::rigid::{RigidVehicle, rigid_needs};

/// Arguments of `hsv-run compare`.
#[derive(Args, Debug, Clone)]
pub struct CompareArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Flight time of each simulation, s (paper: 2).
    #[arg(
        long = "duration-s",
        default_value_t = 2.0,
        allow_negative_numbers = true
    )]
    pub duration_s: f64,
    /// Aeroelastic step, s (see `simulate --help`).
    #[arg(long = "dt-s", default_value_t = 0.001, allow_negative_numbers = true)]
    pub dt_s: f64,
    /// Run folder (default: `runs/compare-<UTC time>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write into a non-empty --out folder.
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// A plotted quantity: title, axis label and how to read it from a sample.
type Quantity = (&'static str, &'static str, fn(&Sample) -> f64);

/// One model's trim and history.
struct Case {
    label: &'static str,
    trim: TrimPoint,
    samples: Vec<Sample>,
    failure: Option<String>,
}

/// Trims and flies the vehicle of `model` through the one flight setup (`analysis::flight`):
/// unheated, so the partitioned and monolithic vehicles differ in their surfaces' structure and
/// mass only, under the config's `[simulation]` inputs (the paper's doublet by default).
fn fly(
    loaded: &hsv_core::config::LoadedConfig,
    registry: &Registry,
    (model, scheme, label): (SurfaceModel, CouplingSchemeName, &'static str),
    args: &CompareArgs,
) -> Result<Case> {
    let mut loaded = loaded.clone();
    loaded.config.coupling.scheme = scheme;
    let loaded = &loaded;
    let options = FlightOptions {
        model,
        heated: false,
        controller: Some("schedule".to_owned()),
        dt_s: args.dt_s,
        disturbances: None,
    };
    let mut flight = Flight::trimmed(loaded, registry, &options, |_| {})?;
    let mut samples = Vec::new();
    let outcome = flight.fly(args.duration_s, 10, |s, _, _| {
        samples.push(s.clone());
        true
    });
    Ok(Case {
        label,
        trim: flight.trim.result.trim,
        samples,
        failure: outcome.err().map(|e| e.to_string()),
    })
}

/// Trims and flies every model and writes the comparison.
pub fn run(args: CompareArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    for (flag, v) in [("--duration-s", args.duration_s), ("--dt-s", args.dt_s)] {
        if !(v.is_finite() && v > 0.0) {
            bail!("{flag} must be a positive number, got {v}");
        }
    }
    let mut folder = RunFolder::create("compare", args.out.as_deref(), args.force)?;
    let (mach, altitude_m) = (loaded.config.flight.mach, loaded.config.flight.altitude_m);
    let sets = assemble(&loaded, &registry, &rigid_needs("hsv-run compare"))?;
    let rigid = trim(
        &mut RigidVehicle::new(sets)?,
        &TrimRequest {
            mach,
            altitude_m,
            ..TrimRequest::default()
        },
    )?
    .trim;
    let implicit = CouplingSchemeName::Implicit;
    let cases = [
        (SurfaceModel::Partitioned, implicit, "partitioned"),
        (
            SurfaceModel::Partitioned,
            CouplingSchemeName::Staggered,
            "partitioned, staggered",
        ),
        (
            SurfaceModel::Monolithic { lumped_mass: false },
            implicit,
            "monolithic",
        ),
        (
            SurfaceModel::Monolithic { lumped_mass: true },
            implicit,
            "monolithic, surface mass lumped",
        ),
    ]
    .into_iter()
    .map(|case| fly(&loaded, &registry, case, &args))
    .collect::<Result<Vec<Case>>>()?;
    // Table 2 layout.
    let mut rows = vec![("rigid".to_owned(), rigid.clone())];
    rows.extend(cases.iter().map(|c| (c.label.to_owned(), c.trim.clone())));
    // Level flight balances the drag with φ; a vehicle without an engine glides at γ.
    let glide = rigid.balance == Balance::Glide;
    let (flight, third) = if glide {
        ("Steady glide (no propulsion region)", "gamma deg")
    } else {
        ("Steady level flight", "phi")
    };
    outln!(
        "{flight} at Mach {mach}, {altitude_m} m (paper Table 2 layout; rigid = rigid vehicle, \
         the others flexible)"
    )?;
    outln!(
        "{:<34} {:>10} {:>10} {:>9} {:>12} {:>12} {:>11}",
        "model",
        "alpha deg",
        "elevon deg",
        third,
        "thrust N",
        "drag N",
        "J"
    )?;
    for (label, t) in &rows {
        outln!(
            "{:<34} {:>10.4} {:>10.4} {:>9.4} {:>12.1} {:>12.1} {:>11.3e}",
            label,
            t.alpha_deg,
            t.elevon_deg,
            if glide {
                t.flight_path_angle_deg
            } else {
                t.fuel_equivalence_ratio
            },
            t.loads.thrust_n,
            t.loads.drag_n,
            t.cost
        )?;
    }
    // Histories, overlaid.
    let mut plots = Vec::new();
    let quantities: [Quantity; 6] = [
        (
            "Altitude change (paper Fig. 11)",
            "altitude - initial (m)",
            |s| s.altitude_m,
        ),
        ("Airspeed", "airspeed (m/s)", |s| s.airspeed_m_s),
        ("Pitch angle (Fig. 12)", "pitch (deg)", |s| s.pitch_deg),
        ("Pitch rate (Fig. 12)", "q (deg/s)", |s| s.q_deg_s),
        ("Angle of attack (Fig. 13)", "alpha (deg)", |s| s.alpha_deg),
        ("Elevon (Fig. 10)", "elevon (deg)", |s| s.elevon_deg),
    ];
    for (title, y_label, f) in quantities {
        let series = cases
            .iter()
            .map(|c| {
                let first = c.samples.first().map_or(0.0, f);
                let offset = if title.starts_with("Altitude") {
                    first
                } else {
                    0.0
                };
                Series {
                    label: c.label.to_owned(),
                    x: c.samples.iter().map(|s| s.time_s).collect(),
                    y: c.samples.iter().map(|s| f(s) - offset).collect(),
                }
            })
            .collect();
        plots.push(LinePlot {
            title: format!("{title}, Mach {mach}, {altitude_m} m"),
            x_label: "time (s)".to_owned(),
            y_label: y_label.to_owned(),
            series,
        });
    }
    let png = folder.join("compare.png");
    write_line_plots_png(&png, &plots, 2, (1300, 1200))?;
    folder.record(png);
    for c in &cases {
        let name = format!(
            "history_{}.csv",
            c.label.replace([' ', ','], "_").replace("__", "_")
        );
        let col = |f: fn(&Sample) -> f64| c.samples.iter().map(f).collect::<Vec<f64>>();
        let path = folder.join(&name);
        write_csv(
            &path,
            &[
                "time_s",
                "altitude_m",
                "airspeed_m_s",
                "alpha_deg",
                "pitch_deg",
                "q_deg_s",
                "elevon_deg",
                "coupling_iterations",
                "coupling_residual",
            ],
            &[
                &col(|s| s.time_s),
                &col(|s| s.altitude_m),
                &col(|s| s.airspeed_m_s),
                &col(|s| s.alpha_deg),
                &col(|s| s.pitch_deg),
                &col(|s| s.q_deg_s),
                &col(|s| s.elevon_deg),
                &col(|s| s.coupling_iterations as f64),
                &col(|s| s.coupling_residual),
            ],
        )?;
        folder.record(path);
    }
    let summary = serde_json::json!({
        "mach": mach,
        "altitude_m": altitude_m,
        "trims": rows.iter().map(|(label, t)| serde_json::json!({
            "model": label,
            "alpha_deg": t.alpha_deg,
            "elevon_deg": t.elevon_deg,
            "fuel_equivalence_ratio": t.fuel_equivalence_ratio,
            "flight_path_angle_deg": t.flight_path_angle_deg,
            "thrust_n": t.loads.thrust_n,
            "drag_n": t.loads.drag_n,
            "cost": t.cost,
            "body_modal_amplitudes": t.modal_amplitudes,
        })).collect::<Vec<_>>(),
        "simulations": cases.iter().map(|c| serde_json::json!({
            "model": c.label,
            "final_time_s": c.samples.last().map(|s| s.time_s),
            "final_pitch_deg": c.samples.last().map(|s| s.pitch_deg),
            "final_altitude_change_m": c.samples.last().zip(c.samples.first()).map(|(l, f)| l.altitude_m - f.altitude_m),
            "mean_coupling_iterations": c.samples.iter().map(|s| s.coupling_iterations as f64).sum::<f64>() / c.samples.len().max(1) as f64,
            "stopped": c.failure,
        })).collect::<Vec<_>>(),
    });
    let failed: Vec<String> = cases
        .iter()
        .filter_map(|c| c.failure.as_ref().map(|f| format!("{}: {f}", c.label)))
        .collect();
    let status = if failed.is_empty() {
        RunStatus::Completed
    } else {
        RunStatus::Failed(failed.join("; "))
    };
    let written = folder.write_summary(summary, &status)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
    } else {
        outln!("outputs in {}", folder.path.display())?;
    }
    if !failed.is_empty() {
        bail!(
            "{} (outputs are in {})",
            failed.join("; "),
            folder.path.display()
        );
    }
    Ok(())
}
