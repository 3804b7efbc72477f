//! The `aero` job: forces, moments and coefficients of a mesh at one flight condition, per model.

use std::time::Instant;

use anyhow::{Context, Result, bail};
use hsv_core::aero::{
    AeroDiagnostics, AeroModel, AeroSolution, Coefficients, Loads, PanelMotion, ReferenceValues,
    integrate_pressure, integrate_shear,
};
use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::geometry::{build_vehicle, vertical_fin_mesh};
use hsv_core::mesh::{PanelMesh, RegionKind};
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry, Role};
use hsv_core::thermal::HeatFluxModel;

/// A mesh to evaluate and what it is, for reports.
#[derive(Debug, Clone)]
pub struct AeroMesh {
    pub mesh: PanelMesh,
    /// "sample vehicle" or the STL path.
    pub source: String,
    /// True for the assembled vehicle, whose engine-owned surfaces are left to the engine model.
    pub has_engine_surfaces: bool,
}

/// The sample (or configured) vehicle: body, both lifting surfaces and the vertical fin (when
/// the config has one) in one mesh.
pub fn vehicle_mesh(loaded: &LoadedConfig) -> Result<AeroMesh> {
    let vehicle = build_vehicle(&loaded.config.geometry, &loaded.config.lifting_surface)
        .with_context(|| format!("{}: building the vehicle geometry", loaded.file))?;
    let mut mesh = vehicle.body;
    mesh.merge(&vehicle.left_surface);
    mesh.merge(&vehicle.right_surface);
    if let Some(fin) = &loaded.config.vertical_fin {
        mesh.merge(
            &vertical_fin_mesh(fin)
                .with_context(|| format!("{}: building the vertical fin", loaded.file))?,
        );
    }
    Ok(AeroMesh {
        mesh,
        source: format!("vehicle from {}", loaded.file),
        has_engine_surfaces: true,
    })
}

/// Reference values for an arbitrary mesh: planform area ½ Σ |n_z| A, length and span from the
/// bounding box, moments about the bounding-box centre.
pub fn mesh_reference(mesh: &PanelMesh) -> ReferenceValues {
    let planform: f64 = mesh
        .panels
        .iter()
        .map(|p| p.normal.z.abs() * p.area_m2)
        .sum::<f64>()
        * 0.5;
    let (lo, hi) = mesh.bounding_box();
    let centre = nalgebra::center(&lo, &hi);
    ReferenceValues {
        area_m2: planform,
        chord_m: hi.x - lo.x,
        span_m: hi.y - lo.y,
        moment_point_m: [centre.x, centre.y, centre.z],
    }
}

/// What to evaluate.
#[derive(Debug, Clone)]
pub struct AeroRequest {
    pub mach: f64,
    pub altitude_m: f64,
    pub alpha_deg: f64,
    pub beta_deg: f64,
    /// Registered aero model names, in output order.
    pub models: Vec<String>,
    pub reference: ReferenceValues,
    /// Integrate the engine-owned (propulsion) surfaces too, as an unpowered vehicle.
    pub include_engine_surfaces: bool,
}

/// Skin friction to add to the pressure loads: the wall shear of a heat-flux model's boundary
/// layer on the aero model's edge states.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionRequest {
    /// Registered heat-flux model with a skin-friction law (`eckert`).
    pub heat_flux_model: String,
    /// Wall temperature of every panel, K (the cold-structure default of `aero` is 300 K).
    pub wall_temperature_k: f64,
}

impl FrictionRequest {
    /// The main body's heat-flux model (`[regions.main_body] heat_flux`), else `eckert`, at
    /// `wall_temperature_k`.
    pub fn from_config(loaded: &LoadedConfig, wall_temperature_k: f64) -> Self {
        Self {
            heat_flux_model: loaded
                .config
                .regions
                .main_body
                .heat_flux
                .clone()
                .unwrap_or_else(|| "eckert".to_owned()),
            wall_temperature_k,
        }
    }
}

/// Skin-friction loads of one aero evaluation.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FrictionLoads {
    /// The heat-flux model whose wall shear was integrated.
    pub heat_flux_model: String,
    pub wall_temperature_k: f64,
    /// F = Σ τ A t̂ and its moment about the reference point, body axes.
    pub loads: Loads,
    /// Friction drag, N (the force's component along −V).
    pub drag_n: f64,
    pub coefficients: Coefficients,
}

/// One model's result.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AeroRow {
    pub model: String,
    /// Pressure loads.
    pub loads: Loads,
    pub coefficients: Coefficients,
    pub diagnostics: AeroDiagnostics,
    /// Wall time of one evaluation as measured here (indicative; benches give the real figures), s.
    pub evaluation_time_s: f64,
    /// Skin-friction loads, when requested.
    pub friction: Option<FrictionLoads>,
}

impl AeroRow {
    /// Pressure plus friction loads.
    pub fn total_loads(&self) -> Loads {
        match &self.friction {
            Some(f) => self.loads + f.loads,
            None => self.loads,
        }
    }
}

/// Drag D = −F · V̂, N: the force's component against the flight velocity (the wind-axis drag of
/// [`Coefficients::from_loads`] times q S).
pub fn drag_n(loads: &Loads, flight: &FlightCondition) -> f64 {
    -loads.force_n.dot(&flight.velocity_body_m_s().normalize())
}

/// Flight condition of a request in the standard atmosphere.
pub fn flight_condition(loaded: &LoadedConfig, request: &AeroRequest) -> Result<FlightCondition> {
    for (name, value) in [
        ("--mach", request.mach),
        ("--altitude-m", request.altitude_m),
    ] {
        if !value.is_finite() {
            bail!("{name} must be a finite number, got {value}");
        }
    }
    crate::limits::check_flow_angle_deg("--alpha-deg", request.alpha_deg)?;
    crate::limits::check_flow_angle_deg("--beta-deg", request.beta_deg)?;
    let freestream = Freestream::standard(request.mach, request.altitude_m, loaded.config.gas)?;
    let mut flight = FlightCondition::steady(
        freestream,
        request.alpha_deg.to_radians(),
        request.beta_deg.to_radians(),
    );
    flight.rotation_center_m = request.reference.moment_point();
    Ok(flight)
}

/// Evaluates every requested model on `mesh` and integrates its pressure loads.
pub fn run_aero(
    loaded: &LoadedConfig,
    registry: &Registry,
    mesh: &AeroMesh,
    request: &AeroRequest,
) -> Result<Vec<AeroRow>> {
    run_aero_with_friction(loaded, registry, mesh, request, None)
}

/// Evaluates every requested model on `mesh`, integrates its pressure loads and, with
/// `friction`, the skin friction of the named heat-flux model on the same panels.
pub fn run_aero_with_friction(
    loaded: &LoadedConfig,
    registry: &Registry,
    mesh: &AeroMesh,
    request: &AeroRequest,
    friction: Option<&FrictionRequest>,
) -> Result<Vec<AeroRow>> {
    let flight = flight_condition(loaded, request)?;
    let include = surfaces_filter(mesh, request.include_engine_surfaces);
    let mut solution = AeroSolution::default();
    let mut rows = Vec::with_capacity(request.models.len());
    let region = loaded.mesh_region("vehicle", mesh.mesh.clone());
    let mut shear_model = friction
        .map(|f| friction_model(&region, registry, &f.heat_flux_model))
        .transpose()?;
    let mut shear_pa = vec![0.0; mesh.mesh.panels.len()];
    for name in &request.models {
        let settings = region.model_settings(name);
        let context = ModelContext::new(&region, registry, &settings);
        let mut model = registry.create::<dyn AeroModel>(name, &context)?;
        let start = Instant::now();
        model
            .evaluate(&mesh.mesh, &flight, &PanelMotion::default(), &mut solution)
            .with_context(|| format!("aero model `{name}`"))?;
        let evaluation_time_s = start.elapsed().as_secs_f64();
        if let Some(bad) = solution.pressure_pa.iter().position(|p| !p.is_finite()) {
            bail!("aero model `{name}` returned a non-finite pressure on panel {bad}");
        }
        let loads = integrate_pressure(
            &mesh.mesh,
            &solution.pressure_pa,
            flight.freestream.pressure_pa,
            &request.reference.moment_point(),
            &include,
        );
        let friction = match (friction, shear_model.as_deref_mut()) {
            (Some(f), Some(model)) => {
                let loads =
                    friction_loads(model, mesh, &flight, &solution, f, request, &mut shear_pa)
                        .and_then(|loads| {
                            nonfinite_loads(&loads)
                                .map_or(Ok(loads), |what| Err(anyhow::anyhow!("{what}")))
                        })
                        .with_context(|| {
                            format!(
                                "skin friction of `{}` on the edge states of aero model `{name}`",
                                f.heat_flux_model
                            )
                        })?;
                Some(FrictionLoads {
                    heat_flux_model: f.heat_flux_model.clone(),
                    wall_temperature_k: f.wall_temperature_k,
                    drag_n: drag_n(&loads, &flight),
                    coefficients: Coefficients::from_loads(&loads, &flight, &request.reference),
                    loads,
                })
            }
            _ => None,
        };
        rows.push(AeroRow {
            model: name.clone(),
            coefficients: Coefficients::from_loads(&loads, &flight, &request.reference),
            loads,
            diagnostics: solution.diagnostics,
            evaluation_time_s,
            friction,
        });
    }
    Ok(rows)
}

/// Heat-flux model `name`, built by name with the region's settings, checked to have a
/// skin-friction law.
fn friction_model(
    region: &RegionInfo,
    registry: &Registry,
    name: &str,
) -> Result<Box<dyn HeatFluxModel>> {
    let settings = region.model_settings(name);
    let context = ModelContext::new(region, registry, &settings);
    let mut model = registry
        .create::<dyn HeatFluxModel>(name, &context)
        .with_context(|| format!("building heat-flux model `{name}` for skin friction"))?;
    if model.skin_friction().is_none() {
        bail!(
            "heat-flux model `{name}` has no skin-friction law (a surrogate of the heat flux \
             only); name one that has, e.g. `eckert`, in [regions.main_body] heat_flux"
        );
    }
    Ok(model)
}

/// Wall shear of `model` on every panel at the requested wall temperature, integrated over the
/// panels of the same regions as the pressure.
fn friction_loads(
    model: &mut dyn HeatFluxModel,
    mesh: &AeroMesh,
    flight: &FlightCondition,
    solution: &AeroSolution,
    friction: &FrictionRequest,
    request: &AeroRequest,
    shear_pa: &mut [f64],
) -> Result<Loads> {
    let t = friction.wall_temperature_k;
    if !(t.is_finite() && t > 0.0) {
        bail!("wall temperature must be a finite number of kelvin > 0, got {t}");
    }
    let walls = vec![t; shear_pa.len()];
    let Some(skin) = model.skin_friction() else {
        bail!(
            "heat-flux model `{}` has no skin-friction law",
            model.name()
        );
    };
    skin.wall_shear(&mesh.mesh, flight, solution, &walls, shear_pa)?;
    Ok(integrate_shear(
        &mesh.mesh,
        shear_pa,
        flight,
        &PanelMotion::default(),
        &request.reference.moment_point(),
        surfaces_filter(mesh, request.include_engine_surfaces),
    ))
}

/// The regions whose panels carry aero loads: body and lifting surfaces always; the engine-owned
/// surfaces of an assembled vehicle only when asked (an unpowered vehicle); every surface of an
/// STL mesh.
fn surfaces_filter(
    mesh: &AeroMesh,
    include_engine_surfaces: bool,
) -> impl Fn(RegionKind) -> bool + use<> {
    let include_engine = include_engine_surfaces || !mesh.has_engine_surfaces;
    let has_engine_surfaces = mesh.has_engine_surfaces;
    move |region: RegionKind| match region {
        RegionKind::MainBody | RegionKind::LiftingSurface => true,
        RegionKind::Propulsion => include_engine,
        RegionKind::Other => !has_engine_surfaces,
    }
}

/// Which loads are not finite, if any.
fn nonfinite_loads(loads: &Loads) -> Option<&'static str> {
    if loads.force_n.iter().any(|v| !v.is_finite()) {
        Some("non-finite friction force")
    } else if loads.moment_nm.iter().any(|v| !v.is_finite()) {
        Some("non-finite friction moment")
    } else {
        None
    }
}

/// All registered aero model names, sorted.
pub fn all_aero_models(registry: &Registry) -> Vec<String> {
    registry
        .names(Role::Aero)
        .into_iter()
        .map(str::to_owned)
        .collect()
}

/// Lowest Mach number of each model's stated range: Newtonian impact theory is a hypersonic
/// approximation (Anderson, Hypersonic and High-Temperature Gas Dynamics, 2nd ed., §3.2-3.3:
/// hypersonic roughly above Mach 5), piston theory needs M² ≫ 1 (Ashley & Zartarian, J. Aero.
/// Sci. 23(12), 1956; the `piston-theory` model's own summary: M ≳ 2).
fn lowest_mach(model: &str) -> Option<(f64, &'static str)> {
    match model {
        "newtonian-scalar" | "newtonian-vector" => Some((
            5.0,
            "Newtonian impact theory is a hypersonic approximation (M >~ 5)",
        )),
        "piston-theory" | "shock-expansion-piston" => {
            Some((2.0, "piston theory needs M well above 1 (M >~ 2)"))
        }
        _ => None,
    }
}

/// Where aero model `model` left its range of validity at `flight`: the model's Mach range
/// and the panels its evaluation counted beyond it ([`AeroDiagnostics`]); one sentence each,
/// for stderr and the JSON `warnings`. Shadowed panels are not listed: the shadow rule is part
/// of every panel method's stated model.
pub fn validity_warnings(
    model: &str,
    flight: &hsv_core::flow::FlightCondition,
    d: &AeroDiagnostics,
) -> Vec<String> {
    let mach = flight.freestream.mach;
    let mut warnings = Vec::new();
    if let Some((lowest, why)) = lowest_mach(model)
        && mach < lowest
    {
        warnings.push(format!(
            "{model}: Mach {mach} is below the model's range; {why}"
        ));
    }
    // Beyond 90 deg the flow meets the vehicle from behind: every panel method here measures
    // running lengths and leading edges from the nose, so its numbers mean nothing there.
    for (quantity, angle_rad) in [
        ("angle of attack", flight.alpha_rad),
        ("angle of sideslip", flight.beta_rad),
    ] {
        let angle_deg = angle_rad.to_degrees();
        if angle_deg.abs() > 90.0 {
            warnings.push(format!(
                "{model}: {quantity} {angle_deg} deg is beyond 90 deg (flow from behind the \
                 vehicle), outside the model's range"
            ));
        }
    }
    let counts = [
        (
            d.detached_shocks,
            "turn the flow beyond the largest oblique-shock deflection (detached shock; \
             pressure from the model's post-detachment rule): angle of attack or deflection \
             beyond the model's range",
        ),
        (
            d.piston_theory_violations,
            "move at |w|/a >= 1 normal to themselves, beyond piston theory",
        ),
        (
            d.vacuum_expansions,
            "expand to vacuum (pressure clipped at zero)",
        ),
    ];
    for (count, what) in counts {
        if count > 0 {
            warnings.push(format!("{model}: {count} panels {what}"));
        }
    }
    warnings
}
