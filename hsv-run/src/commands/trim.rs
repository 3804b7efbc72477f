//! `hsv-run trim`: steady level flight of the rigid vehicle (paper §IV.B), printed in the layout
//! of the paper's Table 2: α, δe, φ, thrust, drag, J and each residual acceleration, with the
//! restart check, evaluations and wall time. A vehicle without a propulsion region trims for a
//! steady glide: γ in place of φ.

use anyhow::{Result, bail};
use clap::Args;
use hsv_core::registry::Registry;

use super::{ConfigArg, JsonFlag, load_config};
use crate::analysis::trim::{Balance, TrimRequest, TrimResult, TrimStatus, trim};
use crate::dynamics::GravityModel;
use crate::outln;
use crate::vehicle::assemble;
use crate::vehicle::partitioned::{CouplingSettings, PartitionedVehicle, partitioned_needs};
use crate::vehicle::rigid::{RigidVehicle, rigid_needs};

/// Arguments of `hsv-run trim`.
#[derive(Args, Debug, Clone)]
pub struct TrimArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Trim the rigid vehicle (the default).
    #[arg(long, conflicts_with = "flexible")]
    pub rigid: bool,
    /// Trim the flexible partitioned vehicle: body and surface modes at static equilibrium
    /// (aero, engine, gravity and inertial relief) at every evaluated point.
    #[arg(long)]
    pub flexible: bool,
    /// Freestream Mach number (default: the config's, 6 for the sample).
    #[arg(long, allow_negative_numbers = true)]
    pub mach: Option<f64>,
    /// Geometric altitude, m (default: the config's, 26000 for the sample).
    #[arg(long = "altitude-m", allow_negative_numbers = true)]
    pub altitude_m: Option<f64>,
    /// Where the search starts: α (deg), δe (deg), φ, e.g. `--start=-0.5,1.5,0.13` (default
    /// 2,0,0.3); for a vehicle without an engine the third is the glide's flight-path angle γ
    /// (deg, default -10). A vehicle may have more than one trim (a low-φ one with the surfaces
    /// lifting and a high-φ one with them pushing down): the start picks the basin.
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        value_name = "ALPHA_DEG,ELEVON_DEG,PHI_OR_GAMMA_DEG"
    )]
    pub start: Option<Vec<f64>>,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// Trims the configured vehicle and prints the result.
pub fn run(args: TrimArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let result = trim_configured(
        &loaded,
        &registry,
        args.flexible,
        args.mach,
        args.altitude_m,
        args.start.as_deref(),
    )?;
    let model = if args.flexible { "flexible" } else { "rigid" };
    if args.json.json {
        outln!(
            "{}",
            serde_json::to_string_pretty(&summary(&result, model))?
        )?;
    } else {
        print_table(&result, model)?;
    }
    for note in &result.notes {
        eprintln!("warning: trim: {note}");
    }
    if result.status == TrimStatus::Failed {
        bail!(
            "the trim at Mach {}, {} m failed: {}",
            result.mach,
            result.altitude_m,
            result.notes.join("; ")
        );
    }
    Ok(())
}

/// Trims the vehicle of `loaded`, rigid or `flexible`, at `mach` and `altitude_m` (default:
/// the config's flight condition), the search starting from `start` (α deg, δe deg, φ; default
/// [`TrimRequest`]'s).
pub fn trim_configured(
    loaded: &hsv_core::config::LoadedConfig,
    registry: &Registry,
    flexible: bool,
    mach: Option<f64>,
    altitude_m: Option<f64>,
    start: Option<&[f64]>,
) -> Result<TrimResult> {
    let mach = mach.unwrap_or(loaded.config.flight.mach);
    let altitude_m = altitude_m.unwrap_or(loaded.config.flight.altitude_m);
    for (flag, value) in [("--mach", mach), ("--altitude-m", altitude_m)] {
        if !value.is_finite() {
            anyhow::bail!("{flag} must be a finite number, got {value}");
        }
    }
    let mut request = TrimRequest {
        mach,
        altitude_m,
        ..TrimRequest::default()
    };
    let glide = !loaded.config.regions.has("propulsion");
    if let Some(start) = start {
        request.start = trim_start(start, glide)?;
        request.glide_start_deg = request.start[2];
    }
    Ok(if flexible {
        let needs = partitioned_needs("trim of the flexible vehicle");
        let sets = assemble(loaded, registry, &needs)?;
        let mut vehicle =
            PartitionedVehicle::new(sets, GravityModel::default(), CouplingSettings::default())?;
        vehicle.set_earth(crate::analysis::level_trim::earth(loaded)?);
        trim(&mut vehicle, &request)?
    } else {
        let earth = crate::analysis::level_trim::earth(loaded)?;
        if earth != crate::dynamics::EarthModel::Flat {
            anyhow::bail!(
                "{}: `simulation.earth = \"{}\"`: the rigid vehicle's trim flies a flat Earth \
                 only; trim the flexible vehicle (--flexible) over a sphere",
                loaded.file,
                earth.name()
            );
        }
        let sets = assemble(loaded, registry, &rigid_needs("trim of the rigid vehicle"))?;
        let mut vehicle = RigidVehicle::new(sets)?;
        trim(&mut vehicle, &request)?
    })
}

/// A search start α (deg), δe (deg), φ checked: three finite numbers, φ in (0, 1]; for a
/// `glide` the third is γ (deg) in (-60, 60).
fn trim_start(start: &[f64], glide: bool) -> Result<[f64; 3]> {
    let &[alpha_deg, elevon_deg, third] = start else {
        bail!(
            "--start takes three numbers (alpha_deg,elevon_deg,{}), got {}",
            if glide { "gamma_deg" } else { "phi" },
            start.len()
        );
    };
    let finite = [alpha_deg, elevon_deg, third].iter().all(|v| v.is_finite());
    let valid = if glide {
        finite && third.abs() < 60.0
    } else {
        finite && third > 0.0 && third <= 1.0
    };
    if !valid && glide {
        bail!(
            "--start {alpha_deg},{elevon_deg},{third}: expected finite angles in degrees, the \
             glide's flight-path angle in (-60, 60) deg (the vehicle has no propulsion region)"
        );
    }
    if !valid {
        bail!(
            "--start {alpha_deg},{elevon_deg},{third}: expected finite angles in degrees and a \
             fuel equivalence ratio in (0, 1]"
        );
    }
    Ok([alpha_deg, elevon_deg, third])
}

/// The JSON summary (what `--json` prints): keys name quantity and unit.
pub fn summary(r: &TrimResult, model: &str) -> serde_json::Value {
    let point = |p: &crate::analysis::trim::TrimPoint| {
        serde_json::json!({
            "alpha_deg": p.alpha_deg,
            "elevon_deg": p.elevon_deg,
            "fuel_equivalence_ratio": p.fuel_equivalence_ratio,
            "flight_path_angle_deg": p.flight_path_angle_deg,
            // thrust (level flight, the engine balances the drag) or glide (the weight does).
            "balance": p.balance,
            "thrust_n": p.loads.thrust_n,
            "drag_n": p.loads.drag_n,
            "friction_drag_n": p.loads.friction_drag_n,
            // Body axes (x forward, z down), moments about the centre of mass: where each
            // region's share of the balance comes from.
            "loads_about_centre_of_mass": {
                "body_aero": p.loads.body_aero,
                "surface_aero": p.loads.surface_aero,
                "engine": p.loads.engine,
            },
            "cost": p.cost,
            "u_dot_m_s2": p.accelerations.u_dot_m_s2,
            "w_dot_m_s2": p.accelerations.w_dot_m_s2,
            "q_dot_rad_s2": p.accelerations.q_dot_rad_s2,
            "engine_status": p.loads.engine_status,
            "evaluations": p.evaluations,
            "body_modal_amplitudes": p.modal_amplitudes,
        })
    };
    serde_json::json!({
        "model": model,
        "mach": r.mach,
        "altitude_m": r.altitude_m,
        "mass_kg": r.mass_kg,
        "trim": point(&r.trim),
        "restart": point(&r.restart),
        "restart_agrees_within_1_percent": r.agreed,
        // converged, converged-with-warnings or failed, and why.
        "trim_status": r.status.name(),
        "notes": r.notes,
        "wall_time_s": r.wall_time_s,
        // Trim prints; it writes no file.
        "status": crate::output::RunStatus::Completed.to_json(),
        "files": Vec::<String>::new(),
    })
}

fn print_table(r: &TrimResult, model: &str) -> Result<()> {
    let t = &r.trim;
    let flight = match t.balance {
        Balance::Thrust => "Steady level flight",
        Balance::Glide => "Steady glide (no propulsion region)",
    };
    outln!(
        "{flight}, {model} vehicle, Mach {}, {} m ({:.0} kg)",
        r.mach,
        r.altitude_m,
        r.mass_kg
    )?;
    outln!(
        "{:<8} {:<40} {:>14} {:>14}",
        "symbol",
        "description",
        "trim",
        "restart"
    )?;
    let row = |symbol: &str, what: &str, a: f64, b: f64| {
        outln!("{symbol:<8} {what:<40} {a:>14.6} {b:>14.6}")
    };
    let e = &r.restart;
    row("alpha", "angle of attack (deg)", t.alpha_deg, e.alpha_deg)?;
    row(
        "delta_e",
        "elevon deflection (deg)",
        t.elevon_deg,
        e.elevon_deg,
    )?;
    match t.balance {
        Balance::Thrust => row(
            "phi",
            "fuel equivalence ratio",
            t.fuel_equivalence_ratio,
            e.fuel_equivalence_ratio,
        )?,
        Balance::Glide => row(
            "gamma",
            "flight-path angle (deg)",
            t.flight_path_angle_deg,
            e.flight_path_angle_deg,
        )?,
    }
    for (k, ((name, a), (_, b))) in t
        .modal_amplitudes
        .iter()
        .zip(&e.modal_amplitudes)
        .enumerate()
    {
        row(
            &format!("eta_{}", k + 1),
            &format!("{name} amplitude"),
            *a,
            *b,
        )?;
    }
    row("T", "thrust (N)", t.loads.thrust_n, e.loads.thrust_n)?;
    row("D", "drag (N)", t.loads.drag_n, e.loads.drag_n)?;
    outln!("minimized parameters")?;
    let sci = |symbol: &str, what: &str, a: f64, b: f64| {
        outln!("{symbol:<8} {what:<40} {a:>14.3e} {b:>14.3e}")
    };
    sci(
        "u_dot",
        "forward acceleration (m/s^2)",
        t.accelerations.u_dot_m_s2,
        e.accelerations.u_dot_m_s2,
    )?;
    sci(
        "w_dot",
        "vertical acceleration (m/s^2)",
        t.accelerations.w_dot_m_s2,
        e.accelerations.w_dot_m_s2,
    )?;
    sci(
        "q_dot",
        "pitch angular acceleration (deg/s^2)",
        t.accelerations.q_dot_rad_s2.to_degrees(),
        e.accelerations.q_dot_rad_s2.to_degrees(),
    )?;
    sci("J", "cost u_dot^2 + w_dot^2 + q_dot^2 (SI)", t.cost, e.cost)?;
    outln!(
        "evaluations {} + {}, wall time {:.2} s; restart from a 10 % perturbation {}",
        t.evaluations,
        e.evaluations,
        r.wall_time_s,
        if r.agreed {
            "agrees within 1 %"
        } else {
            "does NOT agree within 1 % (both minima shown)"
        }
    )?;
    outln!("status {}", r.status.name())?;
    Ok(())
}
