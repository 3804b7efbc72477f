//! Fixtures the conduction tests share: the sample right lifting surface, its default
//! full-order model, and a laminar convective heat flux on it.

// Each test crate uses some of these.
#![allow(dead_code)]

use hsv_core::config::LoadedConfig;
use hsv_core::geometry::{LiftingSurfaceConfig, Side, lifting_surface_mesh};
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Surface};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_model_conduction::{FullOrder, FullOrderSettings};

/// Stefan-Boltzmann constant, W/(m² K⁴).
pub const SIGMA: f64 = 5.670_374_419e-8;

pub fn lifting() -> LiftingSurfaceConfig {
    LoadedConfig::sample().unwrap().config.lifting_surface
}

/// The sample right surface's panel mesh.
pub fn mesh() -> PanelMesh {
    lifting_surface_mesh(&lifting(), Side::Right).unwrap()
}

/// The full-order model of the sample right surface with default settings.
pub fn full_order() -> FullOrder {
    let cfg = lifting();
    let settings = FullOrderSettings::default();
    let grid = SurfaceGrid::lifting_surface(
        &cfg,
        Side::Right,
        settings.elements_chordwise,
        settings.elements_spanwise,
    )
    .unwrap();
    FullOrder::new(&grid, &mesh(), settings).unwrap()
}

/// Running length of each panel centroid from the leading edge, m (at least 1 cm): a function
/// of (x, y) only, so a panel and its mirror image get the same value.
pub fn running_lengths(mesh: &PanelMesh, cfg: &LiftingSurfaceConfig) -> Vec<f64> {
    let tan = cfg.leading_edge_sweep_deg.to_radians().tan();
    let root_le = cfg.pivot_aft_of_nose_m - cfg.pivot_root_chord_fraction * cfg.root_chord_m;
    mesh.panels
        .iter()
        .map(|p| {
            let eta = ((p.centroid.y - cfg.root_y_m) / cfg.span_m).clamp(0.0, 1.0);
            (-p.centroid.x - (root_le + eta * cfg.span_m * tan)).max(0.01)
        })
        .collect()
}

/// Laminar flat-plate convection, q = h_ref (1 m / x)^½ (T_aw − T_w) − 0.8 σ T_w⁴ (Anderson,
/// Hypersonic and High-Temperature Gas Dynamics, §6.9), on every panel alike: symmetric
/// whenever the wall temperatures are.
pub fn convective(x: &[f64], t_aw: f64, h_ref: f64) -> impl FnMut(&[f64], &mut [f64]) + '_ {
    move |wall: &[f64], q: &mut [f64]| {
        for i in 0..q.len() {
            q[i] = h_ref / x[i].sqrt() * (t_aw - wall[i]) - 0.8 * SIGMA * wall[i].powi(4);
        }
    }
}

/// A lifting-surface panel mesh of `vertices` and quads `specs` (surface "plate").
pub fn plate_mesh(vertices: Vec<nalgebra::Point3<f64>>, specs: &[PanelSpec]) -> PanelMesh {
    PanelMesh::new(
        vertices,
        specs,
        Vec::new(),
        vec![Surface::new("plate", RegionKind::LiftingSurface)],
    )
    .unwrap()
}

/// The unit plate's two faces at z = ∓h/2: panel 0 the upper (normal −z), panel 1 the lower
/// (normal +z), each covering the whole face.
pub fn faces(h: f64) -> PanelMesh {
    let v = |x: f64, y: f64, z: f64| nalgebra::Point3::new(x, y, z);
    let vertices = vec![
        v(0.0, 0.0, -h / 2.0),
        v(-1.0, 0.0, -h / 2.0),
        v(-1.0, 1.0, -h / 2.0),
        v(0.0, 1.0, -h / 2.0),
        v(0.0, 0.0, h / 2.0),
        v(-1.0, 0.0, h / 2.0),
        v(-1.0, 1.0, h / 2.0),
        v(0.0, 1.0, h / 2.0),
    ];
    let specs = [
        PanelSpec::quad(0, 1, 2, 3, 0),
        PanelSpec::quad(4, 7, 6, 5, 0),
    ];
    let mesh = plate_mesh(vertices, &specs);
    assert!(mesh.panels[0].normal.z < 0.0 && mesh.panels[1].normal.z > 0.0);
    mesh
}

/// Density, specific heat and conductivity of the constant-property titanium-like material the
/// closed-form tests use (kg/m³, J/(kg K), W/(m K)).
pub const RHO: f64 = 4430.0;
pub const CP: f64 = 560.0;
pub const K: f64 = 7.0;

/// The titanium-like material with [`RHO`], [`CP`], [`K`] at every temperature (1-5000 K).
pub fn constant_material() -> hsv_core::material::MaterialSetting {
    hsv_core::material::MaterialSetting::Table(
        hsv_core::material::Material::constant(
            "constant",
            RHO,
            0.31,
            110e9,
            9e-6,
            K,
            CP,
            (1.0, 5000.0),
        )
        .unwrap(),
    )
}

/// The registry's view of model settings `settings` (at `key_path` of the sample config) on
/// the sample right lifting surface.
pub fn sample_context<'a>(
    settings: &'a toml::Table,
    key_path: &'a str,
) -> hsv_core::registry::ModelContext<'a> {
    hsv_core::registry::ModelContext {
        settings,
        key_path,
        file: "sample-hsv.toml",
        region: hsv_core::testing::sample_region("right_surface"),
        registry: hsv_core::testing::builtin_registry(),
    }
}
