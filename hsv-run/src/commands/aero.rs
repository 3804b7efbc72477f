//! `hsv-run aero`: forces, moments and coefficients of the vehicle or an STL mesh, per aero model.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;

use super::{ConfigArg, JsonFlag, load_config};
use crate::aero_job::{self, AeroMesh, AeroRequest, FrictionRequest};
use crate::{outln, output};

/// Arguments of `hsv-run aero`.
#[derive(Args, Debug, Clone)]
pub struct AeroArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Evaluate this closed STL mesh (ASCII or binary, metres, body axes) instead of the
    /// vehicle. It must be watertight with consistently oriented facets; one facing inward
    /// throughout is turned outward with a warning.
    #[arg(long, value_name = "FILE.stl")]
    pub mesh: Option<PathBuf>,
    /// Evaluate an open or inconsistently oriented --mesh anyway (loads on an open surface are
    /// not those of a closed body).
    #[arg(long, requires = "mesh")]
    pub allow_open: bool,
    /// Moment reference point, body axes, m, as X,Y,Z (default: the config's
    /// [reference] moment_point_m for the vehicle; the centre of the mesh's bounding box for
    /// --mesh).
    #[arg(long = "moment-point-m", value_name = "X,Y,Z", value_parser = parse_point, allow_hyphen_values = true)]
    pub moment_point_m: Option<[f64; 3]>,
    /// Aero model to evaluate (repeatable); default: the main body's model from the config.
    #[arg(long = "model", value_name = "NAME", conflicts_with = "all")]
    pub models: Vec<String>,
    /// Evaluate every registered aero model.
    #[arg(long)]
    pub all: bool,
    /// Freestream Mach number (default: the config's, 6 for the sample).
    #[arg(long, allow_negative_numbers = true)]
    pub mach: Option<f64>,
    /// Geometric altitude, m, 0 to 86000 (default: the config's, 26000 for the sample).
    #[arg(long = "altitude-m", allow_negative_numbers = true)]
    pub altitude_m: Option<f64>,
    /// Angle of attack, deg.
    #[arg(long = "alpha-deg", allow_negative_numbers = true)]
    pub alpha_deg: Option<f64>,
    /// Sideslip angle, deg.
    #[arg(long = "beta-deg", allow_negative_numbers = true)]
    pub beta_deg: Option<f64>,
    /// Reference area, m² (default: config, or the planform area of an STL mesh).
    #[arg(long = "sref-m2", allow_negative_numbers = true)]
    sref_m2: Option<f64>,
    /// Reference length for the pitching moment, m (default: config, or the STL mesh length).
    #[arg(long = "lref-m", allow_negative_numbers = true)]
    pub lref_m: Option<f64>,
    /// Reference span for the rolling and yawing moments, m (default: config, or the STL mesh
    /// width).
    #[arg(long = "bref-m", allow_negative_numbers = true)]
    pub bref_m: Option<f64>,
    /// Also integrate the surfaces the engine model owns (inlet ramp, external nozzle) with the
    /// aero model, as an unpowered vehicle.
    #[arg(long)]
    pub include_engine_surfaces: bool,
    /// Add skin friction: the wall shear of the main body's heat-flux model
    /// ([regions.main_body] heat_flux, else `eckert`) on the aero model's edge states, reported
    /// separately and in the total.
    #[arg(long)]
    pub friction: bool,
    /// Wall temperature for --friction, K (one value on every panel; default 300, a cold
    /// structure; radiative equilibrium is not computed here).
    #[arg(
        long = "wall-temperature-k",
        default_value_t = 300.0,
        requires = "friction",
        allow_negative_numbers = true
    )]
    pub wall_temperature_k: f64,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// What `aero` computed: the mesh, the request, a row per model, and the warnings.
pub struct AeroReport {
    pub mesh: AeroMesh,
    pub request: AeroRequest,
    pub rows: Vec<aero_job::AeroRow>,
    pub warnings: Vec<String>,
    pub flight_condition: hsv_core::flow::FlightCondition,
}

/// Evaluates the requested aero models and prints one row per model (the summary with
/// `--json`).
pub fn run(args: AeroArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let report = evaluate(&args, &loaded, &registry)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&summary(&report))?)?;
        return Ok(());
    }
    print_rows(&report)
}

/// Evaluates the aero models `args` asks for on `loaded`'s vehicle (or `--mesh`; `args.config`
/// is not read), warnings on stderr as they arise: what `run` prints and Python's `hsv.aero`
/// returns.
pub fn evaluate(args: &AeroArgs, loaded: &LoadedConfig, registry: &Registry) -> Result<AeroReport> {
    let flight = loaded.config.flight;
    let mut warnings = Vec::new();
    let mesh = match &args.mesh {
        None => aero_job::vehicle_mesh(loaded)?,
        Some(path) => AeroMesh {
            mesh: read_closed_mesh(path, args.allow_open, &mut warnings)?,
            source: path.display().to_string(),
            has_engine_surfaces: false,
        },
    };
    for warning in &warnings {
        let _ = writeln!(std::io::stderr(), "warning: {warning}");
    }
    let mut reference = match &args.mesh {
        None => loaded.config.reference,
        Some(_) => aero_job::mesh_reference(&mesh.mesh),
    };
    if let Some(s) = args.sref_m2 {
        if !(s.is_finite() && s > 0.0) {
            bail!("--sref-m2 must be a positive number of square metres, got {s}");
        }
        reference.area_m2 = s;
    }
    if let Some(l) = args.lref_m {
        if !(l.is_finite() && l > 0.0) {
            bail!("--lref-m must be a positive length in metres, got {l}");
        }
        reference.chord_m = l;
    }
    if let Some(b) = args.bref_m {
        if !(b.is_finite() && b > 0.0) {
            bail!("--bref-m must be a positive length in metres, got {b}");
        }
        reference.span_m = b;
    }
    if let Some(point) = args.moment_point_m {
        reference.moment_point_m = point;
    }
    check_reference(&reference, args.mesh.is_some())?;
    let models = if args.all {
        aero_job::all_aero_models(registry)
    } else if !args.models.is_empty() {
        args.models.clone()
    } else {
        vec![loaded.config.regions.main_body.aero.clone().context(
            "the config names no main-body aero model (regions.main_body.aero); pass --model NAME",
        )?]
    };
    let request = AeroRequest {
        mach: args.mach.unwrap_or(flight.mach),
        altitude_m: args.altitude_m.unwrap_or(flight.altitude_m),
        alpha_deg: args.alpha_deg.unwrap_or(flight.alpha_deg),
        beta_deg: args.beta_deg.unwrap_or(flight.beta_deg),
        models,
        reference,
        include_engine_surfaces: args.include_engine_surfaces,
    };
    let friction = args.friction.then(|| {
        let t = args.wall_temperature_k;
        if t.is_finite() && t > 0.0 {
            Ok(FrictionRequest::from_config(loaded, t))
        } else {
            Err(anyhow::anyhow!(
                "--wall-temperature-k must be a positive number of kelvin, got {t}"
            ))
        }
    });
    let friction = friction.transpose()?;
    let rows =
        aero_job::run_aero_with_friction(loaded, registry, &mesh, &request, friction.as_ref())?;
    let flight_condition = aero_job::flight_condition(loaded, &request)?;
    for r in &rows {
        for warning in
            crate::aero_job::validity_warnings(&r.model, &flight_condition, &r.diagnostics)
        {
            let _ = writeln!(std::io::stderr(), "warning: {warning}");
            warnings.push(warning);
        }
    }
    Ok(AeroReport {
        mesh,
        request,
        rows,
        warnings,
        flight_condition,
    })
}

/// The `--json` summary of a report.
pub fn summary(report: &AeroReport) -> serde_json::Value {
    let AeroReport {
        mesh,
        request,
        rows,
        warnings,
        flight_condition,
    } = report;
    let models: Vec<_> = rows
        .iter()
        .map(|r| {
            let mut row = serde_json::json!({
                "model": r.model,
                "force_body_n": [r.loads.force_n.x, r.loads.force_n.y, r.loads.force_n.z],
                "moment_body_nm": [r.loads.moment_nm.x, r.loads.moment_nm.y, r.loads.moment_nm.z],
                "cl": r.coefficients.cl,
                "cd": r.coefficients.cd,
                "cy": r.coefficients.cy,
                "cm": r.coefficients.cm,
                "croll": r.coefficients.croll,
                "cn": r.coefficients.cn,
                "diagnostics": r.diagnostics,
                "evaluation_time_s": r.evaluation_time_s,
            });
            if let Some(f) = &r.friction {
                add_friction_json(&mut row, r, f, flight_condition);
            }
            row
        })
        .collect();
    serde_json::json!({
        "mesh": mesh.source,
        "panels": mesh.mesh.panels.len(),
        "mach": request.mach,
        "altitude_m": request.altitude_m,
        "alpha_deg": request.alpha_deg,
        "beta_deg": request.beta_deg,
        "sref_m2": request.reference.area_m2,
        "lref_m": request.reference.chord_m,
        "bref_m": request.reference.span_m,
        "moment_point_m": request.reference.moment_point_m,
        "engine_surfaces_included": request.include_engine_surfaces || !mesh.has_engine_surfaces,
        "models": models,
        "warnings": warnings,
        "status": output::RunStatus::Completed.to_json(),
        "files": Vec::<String>::new(),
    })
}

/// The table of a report.
fn print_rows(report: &AeroReport) -> Result<()> {
    let AeroReport {
        mesh,
        request,
        rows,
        flight_condition,
        ..
    } = report;
    let reference = request.reference;
    outln!(
        "{} ({} panels) at Mach {}, {} m, alpha {} deg, beta {} deg",
        mesh.source,
        mesh.mesh.panels.len(),
        request.mach,
        request.altitude_m,
        request.alpha_deg,
        request.beta_deg
    )?;
    outln!(
        "reference: S = {:.3} m^2, l = {:.3} m, b = {:.3} m, moments about ({:.3}, {:.3}, {:.3}) m (body axes: x fwd, y right, z down)",
        reference.area_m2,
        reference.chord_m,
        reference.span_m,
        reference.moment_point_m[0],
        reference.moment_point_m[1],
        reference.moment_point_m[2]
    )?;
    if mesh.has_engine_surfaces && !request.include_engine_surfaces {
        outln!(
            "engine-owned surfaces (inlet ramp, external nozzle) excluded: the propulsion model owns them (--include-engine-surfaces to add)"
        )?;
    }
    outln!(
        "{:<24} {:>12} {:>12} {:>12} {:>13} {:>13} {:>13} {:>9} {:>9} {:>9} {:>9}",
        "model",
        "Fx [N]",
        "Fy [N]",
        "Fz [N]",
        "Mx [N m]",
        "My [N m]",
        "Mz [N m]",
        "CL",
        "CD",
        "Cm",
        "time"
    )?;
    for r in rows {
        let f = r.loads.force_n;
        let m = r.loads.moment_nm;
        outln!(
            "{:<24} {:>12.4e} {:>12.4e} {:>12.4e} {:>13.4e} {:>13.4e} {:>13.4e} {:>9.5} {:>9.5} {:>9.5} {:>7.0}us",
            r.model,
            f.x,
            f.y,
            f.z,
            m.x,
            m.y,
            m.z,
            r.coefficients.cl,
            r.coefficients.cd,
            r.coefficients.cm,
            r.evaluation_time_s * 1e6
        )?;
        let d = r.diagnostics;
        let notes: Vec<String> = [
            (d.detached_shocks, "detached shocks (pitot pressure)"),
            (
                d.piston_theory_violations,
                "panels beyond piston-theory validity (|w| >= a)",
            ),
            (d.vacuum_expansions, "vacuum expansions (base, lee faces)"),
        ]
        .iter()
        .filter(|(count, _)| *count > 0)
        .map(|(count, what)| format!("{count} {what}"))
        .collect();
        if !notes.is_empty() {
            outln!("{:<24} note: {}", "", notes.join(", "))?;
        }
        if let Some(f) = &r.friction {
            print_friction_rows(r, f, flight_condition)?;
        }
    }
    Ok(())
}

/// `X,Y,Z` in metres.
fn parse_point(text: &str) -> Result<[f64; 3], String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("`{text}` is not three numbers X,Y,Z in metres: {e}"))?;
    match values[..] {
        [x, y, z] if values.iter().all(|v| v.is_finite()) => Ok([x, y, z]),
        [_, _, _] => Err(format!("`{text}`: coordinates must be finite")),
        _ => Err(format!(
            "`{text}` has {} values; give three, X,Y,Z in metres",
            values.len()
        )),
    }
}

/// Reads an STL and checks it is the closed, outward-facing surface of a solid: a mesh facing
/// inward throughout is turned outward (a warning says so); an open or inconsistently oriented
/// one is refused unless `allow_open` (then a warning).
pub fn read_closed_mesh(
    path: &Path,
    allow_open: bool,
    warnings: &mut Vec<String>,
) -> Result<hsv_core::mesh::PanelMesh> {
    let mut mesh = hsv_core::stl::read_stl(path)?;
    let closure = mesh.closure();
    let shown = path.display();
    if closure.is_closed_inward() {
        mesh.reverse_orientation();
        warnings.push(format!(
            "{shown}: every facet faced into the solid (enclosed volume {:.6e} m³); turned them outward",
            closure.enclosed_volume_m3
        ));
    } else if !closure.is_closed_outward() {
        let problems = closure.problems().join(", ");
        if !allow_open {
            bail!(
                "{shown}: not the closed, consistently oriented surface of a solid ({problems}); fix the mesh or pass --allow-open to evaluate it as it is"
            );
        }
        warnings.push(format!(
            "{shown}: evaluated as it is with --allow-open ({problems})"
        ));
    }
    Ok(mesh)
}

/// Reference values must be positive (they divide the coefficients) and the moment point finite.
fn check_reference(reference: &hsv_core::aero::ReferenceValues, from_mesh: bool) -> Result<()> {
    let source = if from_mesh {
        "from the mesh's extent"
    } else {
        "from the config"
    };
    for (what, flag, value) in [
        ("reference area", "--sref-m2", reference.area_m2),
        ("reference length", "--lref-m", reference.chord_m),
        ("reference span", "--bref-m", reference.span_m),
    ] {
        if !(value.is_finite() && value > 0.0) {
            bail!(
                "the {what} {source} is {value}; it must be positive (it divides the coefficients): set it with {flag}"
            );
        }
    }
    Ok(())
}

/// Friction keys of one model's JSON row: friction force, moment, drag and drag coefficient,
/// the pressure drag, and the pressure + friction totals.
fn add_friction_json(
    row: &mut serde_json::Value,
    r: &aero_job::AeroRow,
    f: &aero_job::FrictionLoads,
    flight: &hsv_core::flow::FlightCondition,
) {
    let total = r.total_loads();
    let pressure_drag_n = aero_job::drag_n(&r.loads, flight);
    let (fl, tf, tm) = (f.loads.force_n, total.force_n, total.moment_nm);
    let extra = serde_json::json!({
        "friction_heat_flux_model": f.heat_flux_model,
        "friction_wall_temperature_k": f.wall_temperature_k,
        "friction_force_body_n": [fl.x, fl.y, fl.z],
        "friction_moment_body_nm": [f.loads.moment_nm.x, f.loads.moment_nm.y, f.loads.moment_nm.z],
        "friction_drag_n": f.drag_n,
        "friction_drag_coefficient": f.coefficients.cd,
        "pressure_drag_n": pressure_drag_n,
        "total_force_body_n": [tf.x, tf.y, tf.z],
        "total_moment_body_nm": [tm.x, tm.y, tm.z],
        "total_drag_n": pressure_drag_n + f.drag_n,
        "total_cd": r.coefficients.cd + f.coefficients.cd,
        "total_cl": r.coefficients.cl + f.coefficients.cl,
        "total_cm": r.coefficients.cm + f.coefficients.cm,
    });
    if let (Some(row), serde_json::Value::Object(extra)) = (row.as_object_mut(), extra) {
        row.extend(extra);
    }
}

/// The friction and total lines under one model's row of the table.
fn print_friction_rows(
    r: &aero_job::AeroRow,
    f: &aero_job::FrictionLoads,
    flight: &hsv_core::flow::FlightCondition,
) -> Result<()> {
    let total = r.total_loads();
    for (label, loads, cl, cd, cm) in [
        (
            format!("  friction ({})", f.heat_flux_model),
            f.loads,
            f.coefficients.cl,
            f.coefficients.cd,
            f.coefficients.cm,
        ),
        (
            "  pressure + friction".to_owned(),
            total,
            r.coefficients.cl + f.coefficients.cl,
            r.coefficients.cd + f.coefficients.cd,
            r.coefficients.cm + f.coefficients.cm,
        ),
    ] {
        let (fo, m) = (loads.force_n, loads.moment_nm);
        outln!(
            "{label:<24} {:>12.4e} {:>12.4e} {:>12.4e} {:>13.4e} {:>13.4e} {:>13.4e} {cl:>9.5} {cd:>9.5} {cm:>9.5}",
            fo.x,
            fo.y,
            fo.z,
            m.x,
            m.y,
            m.z
        )?;
    }
    outln!(
        "{:<24} drag: pressure {:.4e} N, friction {:.4e} N (wall at {} K), total {:.4e} N",
        "",
        aero_job::drag_n(&r.loads, flight),
        f.drag_n,
        f.wall_temperature_k,
        aero_job::drag_n(&total, flight)
    )?;
    Ok(())
}
