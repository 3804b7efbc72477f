//! The `aero` job: forces, moments and coefficients of a mesh at one flight condition, per model.

use std::time::Instant;

use anyhow::{Context, Result, bail};
use hsv_core::aero::{
    AeroDiagnostics, AeroModel, AeroSolution, Coefficients, Loads, PanelMotion, ReferenceValues,
    integrate_pressure,
};
use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::mesh::{PanelMesh, RegionKind};
use hsv_core::registry::{ModelContext, Registry, Role};
use hsv_core::vehicle::build_vehicle;

/// A mesh to evaluate and what it is, for reports.
#[derive(Debug, Clone)]
pub struct AeroMesh {
    pub mesh: PanelMesh,
    /// "sample vehicle" or the STL path.
    pub source: String,
    /// True for the assembled vehicle, whose engine-owned surfaces are left to the engine model.
    pub has_engine_surfaces: bool,
}

/// The sample (or configured) vehicle: body and both lifting surfaces in one mesh.
pub fn vehicle_mesh(loaded: &LoadedConfig) -> Result<AeroMesh> {
    let vehicle = build_vehicle(&loaded.config.geometry, &loaded.config.lifting_surface)
        .with_context(|| format!("{}: building the vehicle geometry", loaded.file))?;
    let mut mesh = vehicle.body;
    mesh.merge(&vehicle.left_surface);
    mesh.merge(&vehicle.right_surface);
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

/// One model's result.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AeroRow {
    pub model: String,
    pub loads: Loads,
    pub coefficients: Coefficients,
    pub diagnostics: AeroDiagnostics,
    /// Wall time of one evaluation as measured here (indicative; benches give the real figures), s.
    pub evaluation_time_s: f64,
}

/// Flight condition of a request in the standard atmosphere.
pub fn flight_condition(loaded: &LoadedConfig, request: &AeroRequest) -> Result<FlightCondition> {
    for (name, value) in [
        ("--mach", request.mach),
        ("--altitude-m", request.altitude_m),
        ("--alpha-deg", request.alpha_deg),
        ("--beta-deg", request.beta_deg),
    ] {
        if !value.is_finite() {
            bail!("{name} must be a finite number, got {value}");
        }
    }
    let freestream = Freestream::standard(request.mach, request.altitude_m, loaded.config.gas)?;
    let mut flight = FlightCondition::steady(
        freestream,
        request.alpha_deg.to_radians(),
        request.beta_deg.to_radians(),
    );
    flight.rotation_center_m = request.reference.moment_point();
    Ok(flight)
}

/// Evaluates every requested model on `mesh` and integrates its loads.
pub fn run_aero(
    loaded: &LoadedConfig,
    registry: &Registry,
    mesh: &AeroMesh,
    request: &AeroRequest,
) -> Result<Vec<AeroRow>> {
    let flight = flight_condition(loaded, request)?;
    let include_engine = request.include_engine_surfaces || !mesh.has_engine_surfaces;
    let include = |region: RegionKind| match region {
        RegionKind::MainBody | RegionKind::LiftingSurface => true,
        RegionKind::Propulsion => include_engine,
        RegionKind::Other => !mesh.has_engine_surfaces,
    };
    let mut solution = AeroSolution::default();
    let mut rows = Vec::with_capacity(request.models.len());
    let region = loaded.mesh_region("vehicle", mesh.mesh.clone());
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
            include,
        );
        rows.push(AeroRow {
            model: name.clone(),
            coefficients: Coefficients::from_loads(&loads, &flight, &request.reference),
            loads,
            diagnostics: solution.diagnostics,
            evaluation_time_s,
        });
    }
    Ok(rows)
}

/// All registered aero model names, sorted.
pub fn all_aero_models(registry: &Registry) -> Vec<String> {
    registry
        .names(Role::Aero)
        .into_iter()
        .map(str::to_owned)
        .collect()
}
