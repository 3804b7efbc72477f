//! The conduction models of the lifting surface: `full-order` finite-element transient heat
//! conduction and `pod`, its proper-orthogonal-decomposition Galerkin reduced-order model.
//!
//! Both build the structural grid of their region's lifting surface (core `surface_grid.rs`)
//! and take the heat flux of every panel of the region's wetted mesh, in mesh order.

pub mod full_order;
pub mod grid;
pub mod pod;
mod settings;
pub mod training;

use std::path::PathBuf;

use hsv_core::error::ModelError;
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::{Constructor, ModelCheck, ModelContext, ModelDescriptor, Role};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::ConductionModel;

pub use full_order::{FullOrder, Settings as FullOrderSettings};
pub use pod::{Pod, PodBasis, Settings as PodSettings, collect_snapshots};
pub use training::Training as PodTraining;

/// How far below a material table's lowest temperature, K, a temperature is taken as round-off
/// of the table's floor (a wall at 293 K computed as 292.99999 K) and clamped to it, in every
/// conduction model alike; further below, the table lookup reports the range.
pub const ROUND_OFF_BELOW_TABLE_K: f64 = 0.5;

/// `temperature_k` lifted to the floor of `material`'s thermal table when it lies below it by
/// at most [`ROUND_OFF_BELOW_TABLE_K`]; otherwise unchanged.
pub fn clamp_round_off_k(material: &hsv_core::material::Material, temperature_k: f64) -> f64 {
    let (floor, _) = material.temperature_range_k();
    if temperature_k < floor && temperature_k >= floor - ROUND_OFF_BELOW_TABLE_K {
        floor
    } else {
        temperature_k
    }
}

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
    // Resolved here for the key path of a bad table; the model resolves them again.
    let materials = std::iter::once((
        "structure_material".to_owned(),
        &settings.structure_material,
    ))
    .chain(
        (settings.layers.iter().enumerate())
            .map(|(i, layer)| (format!("layers[{i}].material"), &layer.material)),
    )
    .chain(
        (settings.skin_thickness_m.is_some())
            .then(|| ("interior_material".to_owned(), &settings.interior_material)),
    );
    for (key, material) in materials {
        material
            .resolve()
            .map_err(|e| ctx.settings_error(&key, e.to_string()))?;
    }
    Ok(settings)
}

/// Skins with no room for the interior on `grid`: the settings error naming the key.
fn check_skins_fit(
    ctx: &ModelContext<'_>,
    settings: &FullOrderSettings,
    grid: &SurfaceGrid,
) -> Result<(), ModelError> {
    match settings.skins_misfit(grid) {
        Some((key, value, allowed)) => Err(settings_error(ctx, &key, value, &allowed)),
        None => Ok(()),
    }
}

fn construct_full_order(ctx: &ModelContext<'_>) -> Result<Box<dyn ConductionModel>, ModelError> {
    let settings = full_order_settings(ctx)?;
    let (grid, mesh) = lifting_surface_geometry(ctx, &settings, full_order::NAME)?;
    check_skins_fit(ctx, &settings, &grid)?;
    Ok(Box::new(FullOrder::new(&grid, &mesh, settings)?))
}

/// The full-order model `pod` projects, built from `[models.full-order]` as this region sees it.
pub fn full_order_for(ctx: &ModelContext<'_>) -> Result<FullOrder, ModelError> {
    let full = ctx.settings_for(full_order::NAME);
    let full_ctx = ModelContext::new(ctx.region, ctx.registry, &full);
    let full_settings = full_order_settings(&full_ctx)?;
    let (grid, mesh) = lifting_surface_geometry(&full_ctx, &full_settings, pod::NAME)?;
    check_skins_fit(&full_ctx, &full_settings, &grid)?;
    FullOrder::new(&grid, &mesh, full_settings)
}

/// `[models.pod]` parsed and range-checked, with the basis file it reads: a missing file with
/// no training table to build it from is an error.
fn pod_settings(ctx: &ModelContext<'_>) -> Result<(PodSettings, PathBuf), ModelError> {
    let settings: PodSettings = ctx.parse_settings()?;
    if let Some((key, value, allowed)) = settings.first_invalid() {
        return Err(settings_error(ctx, &key, value, allowed));
    }
    let path = settings.basis_path(&ctx.region.name);
    if settings.training.is_none() && !path.exists() {
        return Err(ctx.settings_error(
            "basis_file",
            format!(
                "POD basis file `{}` does not exist; give a [models.pod.training] table to \
                 train one, or build one from full-order snapshots \
                 (hsv_model_conduction::collect_snapshots, PodBasis::from_snapshots, \
                 PodBasis::save)",
                path.display()
            ),
        ));
    }
    Ok((settings, path))
}

/// `config --check` of `pod`: its settings, the full-order model it projects and the training
/// runs' base models, without training a basis.
fn check_pod(ctx: &ModelContext<'_>) -> Result<(), ModelError> {
    let (settings, _) = pod_settings(ctx)?;
    full_order_for(ctx)?;
    if let Some(training) = &settings.training {
        let bases = [
            ("training.heat_flux", Role::HeatFlux, &training.heat_flux),
            ("training.aero", Role::Aero, &training.aero),
        ];
        for (key, role, name) in bases {
            ctx.check(role, name, &ctx.settings_for(name))
                .map_err(|e| ctx.base_model_error(key, e))?;
        }
    }
    Ok(())
}

/// A basis another region saved from the same fingerprint (the mirror lifting surface's: both
/// train on the same planform, grid and conditions, and their snapshots agree to rounding).
fn sibling_basis(settings: &PodSettings, region: &str, fingerprint: &str) -> Option<PodBasis> {
    settings
        .sibling_basis_paths(region)
        .iter()
        .filter_map(|p| PodBasis::load_cache(p).ok())
        .find(|b| b.fingerprint == fingerprint)
}

fn construct_pod(ctx: &ModelContext<'_>) -> Result<Box<dyn ConductionModel>, ModelError> {
    let (mut settings, path_buf) = pod_settings(ctx)?;
    let mut full = full_order_for(ctx)?;
    let path = path_buf.as_path();
    let mut reused = true;
    let basis = match &settings.training {
        None => PodBasis::load(path)?,
        Some(training) => {
            let fingerprint = training::fingerprint(ctx, training, &full)?;
            let cached = PodBasis::load_cache(path);
            if let Err(e) = &cached
                && e.is_damaged()
            {
                hsv_core::cache::warn_rebuilding(e);
            }
            match cached {
                Ok(basis) if basis.fingerprint == fingerprint => basis,
                // Missing, damaged or built from something else: another region's basis built
                // from the same (the mirror surface: the fingerprint holds the planform and
                // settings, not the side), else train, and save it as this region's.
                _ if let Some(basis) = sibling_basis(&settings, &ctx.region.name, &fingerprint) => {
                    basis.save(path)?;
                    basis
                }
                _ => {
                    reused = false;
                    let mut basis =
                        training::train_basis(ctx, training, &mut full, settings.modes)?;
                    basis.training = Some(training.clone());
                    basis.fingerprint = fingerprint;
                    basis.save(path)?;
                    basis
                }
            }
        }
    };
    // A basis the model trained itself may hold fewer modes than asked when its runs gave fewer
    // snapshots; the run uses what it has and says so. A hand-built basis must hold them all.
    let mut note = None;
    if settings.training.is_some() && settings.modes > basis.n_modes() {
        note = Some(format!(
            "{}.modes = {} but the training runs gave only {} snapshots: using {} modes \
             (lengthen training.duration_s or shorten training.dt_s for more)",
            ctx.key_path,
            settings.modes,
            basis.n_snapshots,
            basis.n_modes()
        ));
        settings.modes = basis.n_modes();
    }
    Ok(Box::new(
        Pod::new(&full, basis, settings)?
            .with_basis_file(path.display().to_string())
            .with_cache_use(hsv_core::thermal::CacheUse {
                path: path_buf.clone(),
                reused,
                note,
            }),
    ))
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

hsv_core::register_model_check!(ModelCheck {
    name: pod::NAME,
    check: check_pod,
});
