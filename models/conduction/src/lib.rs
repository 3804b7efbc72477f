//! The conduction models of the lifting surface: `full-order` finite-element transient heat
//! conduction and `pod`, its proper-orthogonal-decomposition Galerkin reduced-order model.
//!
//! Both build the structural grid of their region's lifting surface (core `surface_grid.rs`)
//! and take the heat flux of every panel of the region's wetted mesh, in mesh order.

pub mod full_order;
pub mod grid;
pub mod pod;

use hsv_core::error::ModelError;
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::ConductionModel;

pub use full_order::{FullOrder, Settings as FullOrderSettings};
pub use pod::{Pod, PodBasis, Settings as PodSettings, collect_snapshots};

/// The settings error for `key` under the model's table.
fn settings_error(ctx: &ModelContext<'_>, key: &str, value: f64, allowed: &str) -> ModelError {
    ctx.settings_error(
        key,
        format!("{value} is outside the allowed range ({allowed})"),
    )
}

/// The structural grid of the region's lifting surface at the settings' resolution, and the
/// region's wetted mesh.
pub fn lifting_surface_geometry(
    ctx: &ModelContext<'_>,
    settings: &FullOrderSettings,
    model: &str,
) -> Result<(SurfaceGrid, PanelMesh), ModelError> {
    let (planform, side) = ctx.region.lifting_surface(model)?;
    let grid = SurfaceGrid::lifting_surface(
        planform,
        side,
        settings.elements_chordwise,
        settings.elements_spanwise,
    )
    .map_err(|e| ModelError::inconsistent(model, e.to_string()))?;
    Ok((grid, ctx.region.mesh.clone()))
}

/// Parses and range-checks `[models.full-order]`-style settings from `ctx`.
fn full_order_settings(ctx: &ModelContext<'_>) -> Result<FullOrderSettings, ModelError> {
    let settings: FullOrderSettings = ctx.parse_settings()?;
    if let Some((key, value, allowed)) = settings.first_invalid() {
        return Err(settings_error(ctx, &key, value, allowed));
    }
    Ok(settings)
}

fn construct_full_order(ctx: &ModelContext<'_>) -> Result<Box<dyn ConductionModel>, ModelError> {
    let settings = full_order_settings(ctx)?;
    let (grid, mesh) = lifting_surface_geometry(ctx, &settings, full_order::NAME)?;
    Ok(Box::new(FullOrder::new(&grid, &mesh, settings)?))
}

/// The full-order model `pod` projects, built from `[models.full-order]` as this region sees it.
pub fn full_order_for(ctx: &ModelContext<'_>) -> Result<FullOrder, ModelError> {
    let full = ctx.settings_for(full_order::NAME);
    let full_ctx = ModelContext::new(ctx.region, ctx.registry, &full);
    let full_settings = full_order_settings(&full_ctx)?;
    let (grid, mesh) = lifting_surface_geometry(&full_ctx, &full_settings, pod::NAME)?;
    FullOrder::new(&grid, &mesh, full_settings)
}

fn construct_pod(ctx: &ModelContext<'_>) -> Result<Box<dyn ConductionModel>, ModelError> {
    let settings: PodSettings = ctx.parse_settings()?;
    let full = full_order_for(ctx)?;
    let path = std::path::Path::new(&settings.basis_file);
    if !path.exists() {
        return Err(ctx.settings_error(
            "basis_file",
            format!(
                "POD basis file `{}` does not exist; build one from full-order snapshots \
                 (`hsv-run heat` does, or hsv_model_conduction::collect_snapshots, \
                 PodBasis::from_snapshots and PodBasis::save)",
                settings.basis_file
            ),
        ));
    }
    let basis = PodBasis::load(path)?;
    Ok(Box::new(Pod::new(&full, basis, settings)?))
}

hsv_core::register_model!(ModelDescriptor {
    name: full_order::NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 2,
    summary: "finite-element transient conduction in the lifting surface (hexahedra through \
              the thickness, optional TPS layers, T-dependent k and c_p, backward Euler + Picard)",
    settings_doc: full_order::SETTINGS_DOC,
    constructor: Constructor::Conduction(construct_full_order),
});

hsv_core::register_model!(ModelDescriptor {
    name: pod::NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "POD Galerkin reduced-order conduction (mode 0 uniform + snapshot modes; paper: \
              32), properties linear in T, online cost independent of the grid",
    settings_doc: pod::SETTINGS_DOC,
    constructor: Constructor::Conduction(construct_pod),
});
