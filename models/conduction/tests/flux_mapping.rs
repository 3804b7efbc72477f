//! Where the wetted panels' heat enters the conduction grid, checked against two principles
//! that hold whatever the discretization:
//!
//! - **Mirror symmetry.** The sample's double-wedge section is symmetric about its mid-plane.
//!   Under a heat flux that is the same on each upper panel and its mirror image on the lower
//!   face (zero incidence), and on the tip face, which the mid-plane cuts in half, the
//!   temperature field is mirror symmetric (the heat equation commutes with the reflection),
//!   so the through-thickness difference is zero at every node, the tip included (Carslaw &
//!   Jaeger, Conduction of Heat in Solids, 2nd ed., 1959, §1.6: the symmetry plane of a
//!   symmetric problem is adiabatic). Tolerance: 1e-6 K, chosen before running (rounding of
//!   double-precision solves over ~10² steps is ~1e-10 K; the mapping error this guards
//!   against gave tens of K).
//! - **Energy conservation.** Every watt of Σ q_i A_i over the wetted panels enters the grid
//!   and nothing else does: the nodal loads sum to it (first law; tolerance 1e-12 relative,
//!   rounding of a few hundred additions).

mod common;

use std::sync::OnceLock;

use common::{convective, full_order, lifting, mesh, running_lengths};
use hsv_core::mesh::{PanelMesh, RegionKind};
use hsv_core::surface_grid::GridEdge;
use hsv_core::thermal::ConductionModel;
use hsv_model_conduction::{FullOrderSettings, Pod, PodBasis, PodSettings, collect_snapshots};
use nalgebra::DVector;

const DT: f64 = 0.5;
/// A priori bound on a through-thickness difference that symmetry makes zero, K.
const SYMMETRY_TOLERANCE_K: f64 = 1e-6;

/// Indices of the panels whose normal lies in the mid-plane (the tip face).
fn side_panels(mesh: &PanelMesh) -> Vec<usize> {
    (0..mesh.panels.len())
        .filter(|&i| {
            let p = &mesh.panels[i];
            p.normal.z.abs() < 0.5
                && mesh.surfaces[usize::from(p.surface)].region == RegionKind::LiftingSurface
        })
        .collect()
}

/// Largest |lower − upper| of the structure over all nodes, K, and its node.
fn largest_difference(model: &dyn ConductionModel, state: &DVector<f64>) -> (f64, usize) {
    let mut d = vec![0.0; model.n_nodes()];
    model.node_temperature_differences(state, &mut d);
    d.iter()
        .enumerate()
        .map(|(i, v)| (v.abs(), i))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
}

/// The largest |difference| at the tip nodes of the model's grid, K.
fn tip_difference(model: &dyn ConductionModel, state: &DVector<f64>) -> f64 {
    let grid = model.node_grid().expect("conduction grid");
    let mut d = vec![0.0; model.n_nodes()];
    model.node_temperature_differences(state, &mut d);
    grid.edge_nodes(GridEdge::Tip)
        .iter()
        .map(|&n| d[n].abs())
        .fold(0.0, f64::max)
}

/// Nodal loads of a symmetric flux are mirror symmetric level by level, and the tip face's
/// share of the heat is large enough that sending it to one face would show.
#[test]
fn a_symmetric_flux_loads_the_grid_symmetrically() {
    let cfg = lifting();
    let mesh = mesh();
    let model = full_order();
    let x = running_lengths(&mesh, &cfg);
    let wall = vec![293.0; mesh.panels.len()];
    let mut q = vec![0.0; mesh.panels.len()];
    convective(&x, 900.0, 120.0)(&wall, &mut q);
    for (u, l) in hsv_core::testing::mirror_panel_pairs(&mesh) {
        assert!(
            (q[u] - q[l]).abs() <= 1e-10 * q[u].abs(),
            "{} vs {}",
            q[u],
            q[l]
        );
    }
    let tip = side_panels(&mesh);
    assert_eq!(tip.len(), cfg.panels_chordwise);
    let tip_power: f64 = tip.iter().map(|&i| q[i] * mesh.panels[i].area_m2).sum();
    let mut load = vec![0.0; model.n_states()];
    model.panel_loads(&q, &mut load);
    let total: f64 = load.iter().sum();
    println!(
        "tip face carries {:.3} % of the heat",
        100.0 * tip_power / total
    );
    assert!(tip_power > 1e-3 * total);
    let grid = model.thermal_grid();
    let top = grid.n_levels - 1;
    let largest = load.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    for node in 0..grid.n_plate_nodes {
        for level in 0..grid.n_levels {
            let (a, b) = (
                load[grid.dof(node, level)],
                load[grid.dof(node, top - level)],
            );
            assert!(
                (a - b).abs() <= 1e-12 * largest,
                "node {node} level {level}: {a} W vs its mirror {b} W"
            );
        }
    }
}

/// `full-order`: 10 s of symmetric convective heating leave no through-thickness difference,
/// at the tip or anywhere, and the whole field is mirror symmetric.
#[test]
fn full_order_keeps_a_symmetric_surface_symmetric() {
    let cfg = lifting();
    let mesh = mesh();
    let x = running_lengths(&mesh, &cfg);
    let mut model = full_order();
    let mut flux = convective(&x, 900.0, 120.0);
    let mut state = model.uniform_state(293.0).unwrap();
    let n = mesh.panels.len();
    let (mut wall, mut q) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..20 {
        model.surface_temperatures(&state, &mut wall);
        flux(&wall, &mut q);
        model.step(&mut state, &q, DT).unwrap();
    }
    let rise = state.max() - 293.0;
    let (worst, node) = largest_difference(&model, &state);
    let tip = tip_difference(&model, &state);
    println!("rise {rise:.1} K, largest |dT| {worst:.3e} K at node {node}, tip {tip:.3e} K");
    assert!(rise > 100.0, "rise {rise} K");
    assert!(worst < SYMMETRY_TOLERANCE_K, "{worst} K at node {node}");
    let grid = model.thermal_grid();
    let top = grid.n_levels - 1;
    for node in 0..grid.n_plate_nodes {
        for level in 0..grid.n_levels {
            let (a, b) = (
                state[grid.dof(node, level)],
                state[grid.dof(node, top - level)],
            );
            assert!(
                (a - b).abs() < SYMMETRY_TOLERANCE_K,
                "node {node}: {a} K vs {b} K"
            );
        }
    }
    for (u, l) in hsv_core::testing::mirror_panel_pairs(&mesh) {
        assert!((wall[u] - wall[l]).abs() < SYMMETRY_TOLERANCE_K);
    }
}

/// Snapshots of three symmetric heating conditions, 20 s each.
fn snapshots() -> &'static Vec<DVector<f64>> {
    static SNAPSHOTS: OnceLock<Vec<DVector<f64>>> = OnceLock::new();
    SNAPSHOTS.get_or_init(|| {
        let cfg = lifting();
        let x = running_lengths(&mesh(), &cfg);
        let mut model = full_order();
        let mut all = Vec::new();
        for (t_aw, h_ref) in [(900.0, 50.0), (700.0, 120.0), (800.0, 80.0)] {
            let mut flux = convective(&x, t_aw, h_ref);
            all.extend(
                collect_snapshots(&mut model, 293.0, DT, 40, 1, |w, q| {
                    flux(w, q);
                    Ok(())
                })
                .unwrap(),
            );
        }
        all
    })
}

/// `pod` (32 modes from symmetric full-order snapshots) under a fourth symmetric condition:
/// no through-thickness difference, at the tip or anywhere.
#[test]
fn pod_keeps_a_symmetric_surface_symmetric() {
    let cfg = lifting();
    let mesh = mesh();
    let x = running_lengths(&mesh, &cfg);
    let full = full_order();
    let basis = PodBasis::from_snapshots(snapshots(), 32, FullOrderSettings::default()).unwrap();
    let mut pod = Pod::new(&full, basis, PodSettings::default()).unwrap();
    let mut flux = convective(&x, 850.0, 65.0);
    let mut a = pod.uniform_state(293.0).unwrap();
    let n = mesh.panels.len();
    let (mut wall, mut q) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..20 {
        pod.surface_temperatures(&a, &mut wall);
        flux(&wall, &mut q);
        pod.step(&mut a, &q, DT).unwrap();
    }
    let mut nodes = vec![0.0; pod.n_nodes()];
    pod.node_temperatures(&a, &mut nodes);
    let rise = nodes.iter().fold(0.0_f64, |m, t| m.max(t - 293.0));
    let (worst, node) = largest_difference(&pod, &a);
    let tip = tip_difference(&pod, &a);
    println!("rise {rise:.1} K, largest |dT| {worst:.3e} K at node {node}, tip {tip:.3e} K");
    assert!(rise > 100.0, "rise {rise} K");
    assert!(worst < SYMMETRY_TOLERANCE_K, "{worst} K at node {node}");
    for (u, l) in hsv_core::testing::mirror_panel_pairs(&mesh) {
        assert!((wall[u] - wall[l]).abs() < SYMMETRY_TOLERANCE_K);
    }
}

/// First law at the grid's boundary: the nodal loads sum to Σ q_i A_i over the wetted panels
/// (upper, lower and tip faces) for a flux that differs on every panel, and the root cap
/// against the body, which is not wetted, adds nothing.
#[test]
fn the_heat_entering_the_grid_is_the_wetted_panels_heat() {
    let mesh = mesh();
    let model = full_order();
    let q: Vec<f64> = (0..mesh.panels.len())
        .map(|i| 1.0e4 * (1.0 + (i % 7) as f64) + 37.0 * i as f64)
        .collect();
    let wetted: f64 = mesh
        .panels
        .iter()
        .zip(&q)
        .filter(|(p, _)| mesh.surfaces[usize::from(p.surface)].region == RegionKind::LiftingSurface)
        .map(|(p, q)| q * p.area_m2)
        .sum();
    let all: f64 = mesh.panels.iter().zip(&q).map(|(p, q)| q * p.area_m2).sum();
    assert!(
        all > wetted,
        "the root cap is in the mesh and takes a flux here"
    );
    let mut load = vec![0.0; model.n_states()];
    model.panel_loads(&q, &mut load);
    let total: f64 = load.iter().sum();
    println!("sum of nodal loads {total:.6e} W, sum q A over wetted panels {wetted:.6e} W");
    assert!((total - wetted).abs() <= 1e-12 * wetted);
    // Panel by panel: a unit flux on one panel puts exactly its area into the grid.
    for i in side_panels(&mesh)
        .into_iter()
        .chain([0, mesh.panels.len() / 2])
    {
        let mut one = vec![0.0; mesh.panels.len()];
        one[i] = 1.0;
        model.panel_loads(&one, &mut load);
        let area = mesh.panels[i].area_m2;
        assert!(
            (load.iter().sum::<f64>() - area).abs() <= 1e-12 * area,
            "panel {i}"
        );
        assert!(
            load.iter().all(|&f| f >= 0.0),
            "panel {i}: no negative nodal load"
        );
    }
}
