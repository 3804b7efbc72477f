//! Fixtures the ritz-plate tests share: the registered model built from a settings table, and
//! the free thermal bending of a plate held at three corners.

// Each test crate uses some of these.
#![allow(dead_code)]

use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};
use hsv_core::structure::StructureModel;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_model_ritz_plate::NAME;
use hsv_model_ritz_plate::plate::{ElementState, PlateModel, Supports};

/// The registered model from settings TOML (a `[models.ritz-plate]` body) over the sample
/// config's right surface.
pub fn build(settings_toml: &str) -> Result<Box<dyn StructureModel>, hsv_core::ModelError> {
    let settings: toml::Table = toml::from_str(settings_toml).expect("toml");
    let ctx = ModelContext {
        settings: &settings,
        key_path: "models.ritz-plate",
        file: "test.toml",
        region: hsv_core::testing::sample_region("right_surface"),
        registry: hsv_core::testing::empty_registry(),
    };
    match descriptor().constructor {
        Constructor::Structure(f) => f(&ctx),
        _ => panic!("ritz-plate must be a structure model"),
    }
}

pub fn descriptor() -> &'static ModelDescriptor {
    hsv_core::inventory::iter::<ModelDescriptor>
        .into_iter()
        .find(|d| d.name == NAME)
        .expect("ritz-plate is registered")
}

/// w held at three corners of a rectangular grid only: free to bend, statically determinate.
pub fn three_corner_supports(grid: &SurfaceGrid) -> Supports {
    let (nc, ns) = (grid.nodes_chordwise(), grid.nodes_spanwise());
    let mut supports = Supports::free(grid.n_nodes());
    for n in [
        grid.node_index(0, 0),
        grid.node_index(nc - 1, 0),
        grid.node_index(0, ns - 1),
    ] {
        supports.bending[n][0] = true;
    }
    supports
}

/// How a three-corner-held rectangular plate (chord `c`, span `s`) bends under node mean
/// temperatures and through-thickness differences: the worst relative error of its curvatures
/// (nodal second differences of w) and of its rotation gradients (βx,x, βy,y) against a
/// spherical κ over the interior nodes, and the net transverse thermal load over its total
/// magnitude (zero for a self-equilibrated load).
pub struct FreeBending {
    pub worst_curvature: f64,
    pub worst_rotation_gradient: f64,
    pub net_load_ratio: f64,
}

/// The thermal moment load f_T of the field (node means `mean_k`, face differences
/// `difference_k`) and the full-order displacements u of K u = f_T at the reference stiffness.
pub fn thermal_moment_displacements(
    plate: &PlateModel,
    mean_k: &[f64],
    difference_k: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let mut states = vec![ElementState::REFERENCE; plate.n_elements()];
    plate
        .element_states(mean_k, Some(difference_k), &mut states)
        .expect("states");
    let f = plate.thermal_moment_load(&states);
    let u = plate
        .static_solve(&nalgebra::DMatrix::from_column_slice(f.len(), 1, &f))
        .expect("solve");
    let u = u.column(0).iter().copied().collect();
    (f, u)
}

pub fn free_thermal_bending(
    plate: &PlateModel,
    mean_k: &[f64],
    difference_k: &[f64],
    kappa: f64,
    (c, s): (f64, f64),
) -> FreeBending {
    let (f, u) = thermal_moment_displacements(plate, mean_k, difference_k);
    let g = &plate.grid;
    let (nc, ns) = (g.nodes_chordwise(), g.nodes_spanwise());
    let w = |i: usize, j: usize| plate.nodal_value(&u, g.node_index(i, j));
    let (dx, dy) = (c / (nc - 1) as f64, s / (ns - 1) as f64);
    let error = |k: f64| (k / kappa - 1.0).abs();
    let (mut worst_curvature, mut worst_rotation_gradient): (f64, f64) = (0.0, 0.0);
    for j in 1..ns - 1 {
        for i in 1..nc - 1 {
            let kxx = -(w(i + 1, j)[0] - 2.0 * w(i, j)[0] + w(i - 1, j)[0]) / (dx * dx);
            let kyy = -(w(i, j + 1)[0] - 2.0 * w(i, j)[0] + w(i, j - 1)[0]) / (dy * dy);
            // βx,x and βy,y: x runs along −u, so x_{i+1} − x_i = −dx.
            let bxx = (w(i + 1, j)[1] - w(i - 1, j)[1]) / (-2.0 * dx);
            let byy = (w(i, j + 1)[2] - w(i, j - 1)[2]) / (2.0 * dy);
            worst_curvature = worst_curvature.max(error(kxx)).max(error(kyy));
            worst_rotation_gradient = worst_rotation_gradient.max(error(bxx)).max(error(byy));
        }
    }
    let fz: f64 = (0..g.n_nodes()).map(|n| plate.nodal_value(&f, n)[0]).sum();
    let scale: f64 = f.iter().map(|v| v.abs()).sum();
    FreeBending {
        worst_curvature,
        worst_rotation_gradient,
        net_load_ratio: fz.abs() / scale,
    }
}
