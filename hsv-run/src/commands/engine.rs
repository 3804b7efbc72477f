//! `hsv-run engine`: thrust, lift, pitching moment, captured mass flow, status and station
//! states of the vehicle's engine per propulsion model, with thrust versus φ and α written to
//! the run folder (CSV and PNG).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::geometry::build_vehicle;
use hsv_core::mesh::PanelMesh;
use hsv_core::propulsion::{EngineInputs, EngineStatus, PropulsionModel, PropulsionSolution};
use hsv_core::registry::{ModelContext, Registry, Role};

use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::output::{self, LinePlot, RunFolder, RunStatus, Series};
use crate::{out, outln};

/// Paper Table 2: trimmed fuel equivalence ratio at Mach 6, 26 km (0.126 to 0.139).
pub const DEFAULT_PHI: f64 = 0.13;

/// φ values of the thrust-versus-φ sweep: 0 to 1 in steps of 0.025.
fn phi_sweep() -> Vec<f64> {
    (0..=40).map(|k| 0.025 * f64::from(k)).collect()
}

/// α values of the thrust-versus-α sweep, deg: -4 to 8 in steps of 0.25.
fn alpha_sweep_deg() -> Vec<f64> {
    (0..=48).map(|k| -4.0 + 0.25 * f64::from(k)).collect()
}

/// Arguments of `hsv-run engine`.
#[derive(Args, Debug, Clone)]
pub struct EngineArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Propulsion model to evaluate (repeatable); default: every registered propulsion model.
    #[arg(long = "model", value_name = "NAME")]
    pub models: Vec<String>,
    /// Freestream Mach number (default: the config's, 6 for the sample).
    #[arg(long, allow_negative_numbers = true)]
    pub mach: Option<f64>,
    /// Geometric altitude, m, 0 to 86000 (default: the config's, 26000 for the sample).
    #[arg(long = "altitude-m", allow_negative_numbers = true)]
    pub altitude_m: Option<f64>,
    /// Angle of attack, deg (default: the config's, 0 for the sample).
    #[arg(long = "alpha-deg", allow_negative_numbers = true)]
    pub alpha_deg: Option<f64>,
    /// Fuel equivalence ratio φ >= 0 (paper Table 2: about 0.13 at trim).
    #[arg(long, allow_negative_numbers = true, default_value_t = DEFAULT_PHI)]
    pub phi: f64,
    /// Run folder for the sweep CSVs, plot and summary.json.
    #[command(flatten)]
    pub output: OutArgs,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// One model's result at the requested condition.
#[derive(Debug, Clone)]
pub struct EngineRow {
    pub model: String,
    pub solution: PropulsionSolution,
    /// Wall time of the evaluation, s.
    pub evaluation_time_s: f64,
}

/// What to evaluate: flight condition, fuel equivalence ratio and models.
#[derive(Debug, Clone)]
pub struct EngineRequest {
    pub mach: f64,
    pub altitude_m: f64,
    pub alpha_deg: f64,
    /// Fuel equivalence ratio φ ≥ 0.
    pub phi: f64,
    /// Registered propulsion model names; empty: every registered one.
    pub models: Vec<String>,
}

impl EngineRequest {
    /// The config's flight condition overridden by the command-line values given.
    fn from_args(args: &EngineArgs, loaded: &LoadedConfig) -> Self {
        let flight = loaded.config.flight;
        Self {
            mach: args.mach.unwrap_or(flight.mach),
            altitude_m: args.altitude_m.unwrap_or(flight.altitude_m),
            alpha_deg: args.alpha_deg.unwrap_or(flight.alpha_deg),
            phi: args.phi,
            models: args.models.clone(),
        }
    }
}

/// The engine job: every requested model evaluated at the request's condition (no files); a
/// non-finite result is an error naming the model and quantity.
pub fn run_engine(
    loaded: &LoadedConfig,
    registry: &Registry,
    request: &EngineRequest,
) -> Result<Vec<EngineRow>> {
    Ok(evaluate_models(loaded, registry, request)?.0)
}

type Evaluated<'a> = (Vec<EngineRow>, Vec<Box<dyn PropulsionModel>>, Setup<'a>);

fn evaluate_models<'a>(
    loaded: &'a LoadedConfig,
    registry: &Registry,
    request: &EngineRequest,
) -> Result<Evaluated<'a>> {
    for (name, value) in [
        ("--mach", request.mach),
        ("--altitude-m", request.altitude_m),
        ("--alpha-deg", request.alpha_deg),
    ] {
        if !value.is_finite() {
            bail!("{name} must be a finite number, got {value}");
        }
    }
    if !(request.phi.is_finite() && request.phi >= 0.0) {
        bail!(
            "--phi must be a finite fuel equivalence ratio >= 0, got {}",
            request.phi
        );
    }
    let models: Vec<String> = if request.models.is_empty() {
        registry
            .names(Role::Propulsion)
            .into_iter()
            .map(str::to_owned)
            .collect()
    } else {
        request.models.clone()
    };
    if models.is_empty() {
        bail!("no propulsion model is registered; load a plugin or name one with --model");
    }
    let body = build_vehicle(&loaded.config.geometry, &loaded.config.lifting_surface)
        .with_context(|| format!("{}: building the vehicle geometry", loaded.file))?
        .body;
    let setup = Setup {
        loaded,
        body,
        mach: request.mach,
        altitude_m: request.altitude_m,
    };
    setup.flight(request.alpha_deg)?;
    let mut rows = Vec::with_capacity(models.len());
    let mut built = Vec::with_capacity(models.len());
    for name in &models {
        let mut model = setup.model(registry, name)?;
        let mut solution = PropulsionSolution::default();
        let start = Instant::now();
        setup
            .evaluate(
                model.as_mut(),
                request.alpha_deg,
                request.phi,
                &mut solution,
            )
            .with_context(|| format!("propulsion model `{name}`"))?;
        check_finite(name, &solution)?;
        rows.push(EngineRow {
            model: name.clone(),
            solution,
            evaluation_time_s: start.elapsed().as_secs_f64(),
        });
        built.push(model);
    }
    Ok((rows, built, setup))
}

/// A model that returns NaN or infinity has failed, whatever it says.
fn check_finite(name: &str, s: &PropulsionSolution) -> Result<()> {
    let (f, m) = (s.loads.force_n, s.loads.moment_nm);
    let values = [
        ("thrust", f.x),
        ("side force", f.y),
        ("normal force", f.z),
        ("rolling moment", m.x),
        ("pitching moment", m.y),
        ("yawing moment", m.z),
        ("mass flow", s.mass_flow_kg_s),
    ];
    if let Some((what, value)) = values.iter().find(|(_, v)| !v.is_finite()) {
        bail!("propulsion model `{name}` returned a non-finite {what} ({value})");
    }
    Ok(())
}

/// The engine problem: vehicle body, config and a flight condition builder.
struct Setup<'a> {
    loaded: &'a LoadedConfig,
    body: PanelMesh,
    mach: f64,
    altitude_m: f64,
}

impl Setup<'_> {
    fn flight(&self, alpha_deg: f64) -> Result<FlightCondition> {
        let freestream = Freestream::standard(self.mach, self.altitude_m, self.loaded.config.gas)?;
        let mut flight = FlightCondition::steady(freestream, alpha_deg.to_radians(), 0.0);
        flight.rotation_center_m = self.loaded.config.reference.moment_point();
        Ok(flight)
    }

    fn model(&self, registry: &Registry, name: &str) -> Result<Box<dyn PropulsionModel>> {
        let region = self.loaded.region("propulsion")?;
        let settings = region.model_settings(name);
        let context = ModelContext::new(&region, registry, &settings);
        Ok(registry.create::<dyn PropulsionModel>(name, &context)?)
    }

    fn evaluate(
        &self,
        model: &mut dyn PropulsionModel,
        alpha_deg: f64,
        phi: f64,
        out: &mut PropulsionSolution,
    ) -> Result<()> {
        let flight = self.flight(alpha_deg)?;
        model.evaluate(
            &EngineInputs {
                flight: &flight,
                body: &self.body,
                fuel_equivalence_ratio: phi,
            },
            out,
        )?;
        Ok(())
    }

    /// Thrust at each point of a sweep; NaN where the model reports an error (skipped in plots).
    /// Thrust, N, and engine status at each (α deg, φ) point (NaN where the model fails).
    fn thrust_sweep(
        &self,
        model: &mut dyn PropulsionModel,
        points: impl Iterator<Item = (f64, f64)>,
    ) -> Sweep {
        let mut out = PropulsionSolution::default();
        let mut sweep = Sweep::default();
        for (alpha_deg, phi) in points {
            match self.evaluate(model, alpha_deg, phi, &mut out) {
                Ok(()) => {
                    sweep.thrust_n.push(out.loads.force_n.x);
                    sweep.status.push(out.status);
                }
                Err(_) => {
                    sweep.thrust_n.push(f64::NAN);
                    sweep.status.push(EngineStatus::Ok);
                }
            }
        }
        sweep
    }
}

/// One model's thrust sweep with the engine status of each point.
#[derive(Debug, Clone, Default)]
struct Sweep {
    thrust_n: Vec<f64>,
    status: Vec<EngineStatus>,
}

fn status_name(solution: &PropulsionSolution) -> String {
    serde_json::to_value(solution.status)
        .ok()
        .and_then(|v| v.as_str().map(str::to_owned))
        .unwrap_or_default()
}

/// Evaluates the requested propulsion models, prints one row per model and writes the sweeps.
pub fn run(args: EngineArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let request = EngineRequest::from_args(&args, &loaded);
    let (rows, mut built, setup) = evaluate_models(&loaded, &registry, &request)?;
    let models: Vec<String> = rows.iter().map(|r| r.model.clone()).collect();
    let (alpha_deg, phi) = (request.alpha_deg, request.phi);
    let reference = loaded.config.reference.moment_point_m;
    // Validity: the combustor models burn at most the stoichiometric fuel (phi = 1); a richer
    // mixture releases no more heat in them, so its thrust is an extrapolation.
    let mut warnings = Vec::new();
    if phi > 1.0 {
        warnings.push(format!(
            "phi {phi} is above stoichiometric (1): the engine models do not represent a \
             fuel-rich combustor"
        ));
    }
    for r in &rows {
        if matches!(
            r.solution.status,
            EngineStatus::ThermalChoking | EngineStatus::Unstart
        ) {
            warnings.push(format!(
                "{}: the engine is {} at this point; its model trusts unchoked, started flow only",
                r.model,
                status_name(&r.solution)
            ));
        }
    }
    for w in &warnings {
        let _ = writeln!(std::io::stderr(), "warning: {w}");
    }
    let summary = || {
        serde_json::json!({
            "warnings": warnings,
            "vehicle": loaded.file,
            "mach": request.mach,
            "altitude_m": request.altitude_m,
            "alpha_deg": alpha_deg,
            "phi": phi,
            "moment_point_m": reference,
            "models": rows.iter().map(row_json).collect::<Vec<_>>(),
        })
    };
    let mut run = RunFolder::create("engine", args.output.out.as_deref(), args.output.force)?;
    let plot = run.run(
        |run| write_sweeps(run, &setup, &models, &mut built, alpha_deg, phi),
        summary,
    )?;
    let mut completed = summary();
    completed["plot"] = plot.display().to_string().into();
    let completed = run.write_summary(completed, &RunStatus::Completed)?;

    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&completed)?)?;
        return Ok(());
    }
    print_table(&rows, &request, reference, &run.path)
}

fn row_json(r: &EngineRow) -> serde_json::Value {
    let s = &r.solution;
    let f = s.loads.force_n;
    let m = s.loads.moment_nm;
    serde_json::json!({
        "model": r.model,
        "thrust_n": f.x,
        "lift_n": -f.z,
        "pitching_moment_nm": m.y,
        "mass_flow_kg_s": s.mass_flow_kg_s,
        "status": status_name(s),
        "stations": s.stations,
        "force_body_n": [f.x, f.y, f.z],
        "moment_body_nm": [m.x, m.y, m.z],
        "evaluation_time_s": r.evaluation_time_s,
    })
}

/// Thrust versus φ (at the requested α) and versus α (at the requested φ), one line per model:
/// CSVs and one PNG in `folder`; returns the PNG path.
fn write_sweeps(
    run: &mut RunFolder,
    setup: &Setup<'_>,
    models: &[String],
    built: &mut [Box<dyn PropulsionModel>],
    alpha_deg: f64,
    phi: f64,
) -> Result<PathBuf> {
    let phis = phi_sweep();
    let alphas = alpha_sweep_deg();
    let mut by_phi = Vec::with_capacity(models.len());
    let mut by_alpha = Vec::with_capacity(models.len());
    for model in built.iter_mut() {
        by_phi.push(setup.thrust_sweep(model.as_mut(), phis.iter().map(|&p| (alpha_deg, p))));
        by_alpha.push(setup.thrust_sweep(model.as_mut(), alphas.iter().map(|&a| (a, phi))));
    }
    let headers: Vec<String> = models.iter().map(|m| format!("{m}_thrust_n")).collect();
    let mut write = |file: &str, x_header: &str, x: &[f64], ys: &[Sweep]| -> Result<()> {
        let mut h: Vec<&str> = vec![x_header];
        h.extend(headers.iter().map(String::as_str));
        let mut columns: Vec<&[f64]> = vec![x];
        columns.extend(ys.iter().map(|s| s.thrust_n.as_slice()));
        let path = run.join(file);
        output::write_csv(&path, &h, &columns)?;
        run.record(path);
        Ok(())
    };
    write("thrust_vs_phi.csv", "phi", &phis, &by_phi)?;
    write("thrust_vs_alpha.csv", "alpha_deg", &alphas, &by_alpha)?;
    let kn = |v: &[f64]| v.iter().map(|t| t / 1e3).collect::<Vec<_>>();
    // One line per model (its own colour and dash), and the points where that model's engine
    // chokes thermally or unstarts marked with circles of the same colour.
    let series = |x: &[f64], ys: &[Sweep]| -> (Vec<Series>, Vec<output::LineStyle>) {
        let mut series = Vec::new();
        let mut styles = Vec::new();
        for (k, (m, sweep)) in models.iter().zip(ys).enumerate() {
            series.push(Series {
                label: m.clone(),
                x: x.to_vec(),
                y: kn(&sweep.thrust_n),
            });
            styles.push(output::LineStyle {
                colour: k,
                dash: output::Dash::nth(k),
                markers_only: false,
            });
            for (status, what) in [
                (EngineStatus::ThermalChoking, "thermally choked"),
                (EngineStatus::Unstart, "unstarted"),
            ] {
                let (cx, cy): (Vec<f64>, Vec<f64>) = x
                    .iter()
                    .zip(&sweep.thrust_n)
                    .zip(&sweep.status)
                    .filter(|(_, s)| **s == status)
                    .map(|((&x, &t), _)| (x, t / 1e3))
                    .unzip();
                if !cx.is_empty() {
                    series.push(Series {
                        label: format!("{m} {what}"),
                        x: cx,
                        y: cy,
                    });
                    styles.push(output::LineStyle {
                        colour: k,
                        dash: output::Dash::Solid,
                        markers_only: true,
                    });
                }
            }
        }
        (series, styles)
    };
    let (phi_series, phi_styles) = series(&phis, &by_phi);
    let (alpha_series, alpha_styles) = series(&alphas, &by_alpha);
    let temperature_k = setup
        .flight(alpha_deg)
        .map(|f| f.freestream.temperature_k)
        .unwrap_or(f64::NAN);
    let plots = [
        output::StyledPlot {
            plot: LinePlot {
                title: format!(
                    "Thrust vs phi: Mach {}, {} m (T {temperature_k:.0} K), alpha {alpha_deg} deg",
                    setup.mach, setup.altitude_m
                ),
                x_label: "fuel equivalence ratio phi".to_owned(),
                y_label: "thrust (body x) [kN]".to_owned(),
                series: phi_series,
            },
            styles: phi_styles,
        },
        output::StyledPlot {
            plot: LinePlot {
                title: format!(
                    "Thrust vs alpha: Mach {}, {} m (T {temperature_k:.0} K), phi {phi}",
                    setup.mach, setup.altitude_m
                ),
                x_label: "angle of attack [deg]".to_owned(),
                y_label: "thrust (body x) [kN]".to_owned(),
                series: alpha_series,
            },
            styles: alpha_styles,
        },
    ];
    let path = run.join("thrust_vs_phi_alpha.png");
    output::write_styled_plots_png(&path, &plots, 2, (1600, 560))?;
    run.record(path.clone());
    Ok(path)
}

fn print_table(
    rows: &[EngineRow],
    request: &EngineRequest,
    reference: [f64; 3],
    folder: &Path,
) -> Result<()> {
    let EngineRequest {
        mach,
        altitude_m,
        alpha_deg,
        phi,
        ..
    } = request;
    outln!("engine at Mach {mach}, {altitude_m} m, alpha {alpha_deg} deg, phi {phi}")?;
    outln!(
        "loads on the vehicle: thrust = body Fx (forward), lift = -Fz (up), pitching moment My about ({:.3}, {:.3}, {:.3}) m (nose up +)",
        reference[0],
        reference[1],
        reference[2]
    )?;
    outln!(
        "{:<16} {:>12} {:>12} {:>13} {:>12} {:>16} {:>9}",
        "model",
        "thrust [N]",
        "lift [N]",
        "My [N m]",
        "mdot [kg/s]",
        "status",
        "time"
    )?;
    for r in rows {
        let s = &r.solution;
        outln!(
            "{:<16} {:>12.4e} {:>12.4e} {:>13.4e} {:>12.3} {:>16} {:>7.0}us",
            r.model,
            s.loads.force_n.x,
            -s.loads.force_n.z,
            s.loads.moment_nm.y,
            s.mass_flow_kg_s,
            status_name(s),
            r.evaluation_time_s * 1e6
        )?;
    }
    outln!()?;
    outln!("station states (middle spanwise section):")?;
    out!("{:<16}", "station")?;
    for r in rows {
        out!(" {:>36}", r.model)?;
    }
    outln!()?;
    out!("{:<16}", "")?;
    for _ in rows {
        out!(" {:>8} {:>13} {:>13}", "Mach", "p [Pa]", "T [K]")?;
    }
    outln!()?;
    let names: Vec<&str> = rows
        .iter()
        .max_by_key(|r| r.solution.stations.len())
        .map(|r| {
            r.solution
                .stations
                .iter()
                .map(|s| s.station.as_str())
                .collect()
        })
        .unwrap_or_default();
    for name in names {
        out!("{name:<16}")?;
        for r in rows {
            match r.solution.stations.iter().find(|s| s.station == name) {
                Some(s) => out!(
                    " {:>8.3} {:>13.4e} {:>13.1}",
                    s.mach,
                    s.pressure_pa,
                    s.temperature_k
                )?,
                None => out!(" {:>8} {:>13} {:>13}", "-", "-", "-")?,
            }
        }
        outln!()?;
    }
    outln!()?;
    outln!(
        "thrust versus phi and alpha: {}",
        folder.join("thrust_vs_phi_alpha.png").display()
    )?;
    Ok(())
}
