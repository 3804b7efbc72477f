//! End to end, the flutter study's heating case on the sample right surface: Mach 5, 10 km,
//! zero incidence, `shock-expansion` edge states and `eckert` heat flux, 10 s from 293 K.
//!
//! Principle: mirror symmetry. The double-wedge section is symmetric about its mid-plane and at
//! zero incidence the flow is too, so the heat flux on each upper panel equals that on its
//! mirror image (checked here to 1e-10 relative, the precondition) and the temperature field is
//! mirror symmetric (the heat equation commutes with the reflection; Carslaw & Jaeger,
//! Conduction of Heat in Solids, 2nd ed., 1959, §1.6): the structure's through-thickness
//! difference is zero at every node, the tip included, for `full-order` and `pod`. Tolerance
//! 1e-6 K, chosen before running (rounding over 100 steps is ~1e-10 K; sending the tip face's
//! heat to the lower face gave a difference of several K at the tip).

mod common;

use hsv_core::surface_grid::GridEdge;

const TOLERANCE_K: f64 = 1e-6;

/// |v_upper − v_lower| ≤ `relative` |v_upper| on every mirror pair.
fn assert_mirror_symmetric(v: &[f64], pairs: &[(usize, usize)], relative: f64, what: &str) {
    for &(u, l) in pairs {
        assert!(
            (v[u] - v[l]).abs() <= relative * v[u].abs(),
            "{what}: {} vs {} on mirror panels {u}, {l}",
            v[u],
            v[l]
        );
    }
}

/// The sample right surface with the POD basis trained in `dir` from 10 s full-order runs
/// at Mach 4, 4.5 and 5 (the `heat` command's default snapshot conditions) at zero incidence.
fn region(dir: &std::path::Path) -> hsv_core::region::RegionInfo {
    common::surface_with_pod_training(dir, &[4.0, 4.5, 5.0], 10.0, &[0.0])
}

/// Heats for 10 s with `conduction` and checks the symmetry; returns the largest rise, K.
fn heat_symmetrically(region: &hsv_core::region::RegionInfo, conduction: &str) -> f64 {
    let mut heating = common::surface_heating(region, conduction, 5.0, 0.0);
    // The input: on the uniform initial wall the flux is mirror symmetric.
    let pairs = hsv_core::testing::mirror_panel_pairs(&region.mesh);
    heating.advance(0.1).expect("heating step");
    assert_mirror_symmetric(heating.heat_flux_w_m2(), &pairs, 1e-10, conduction);
    for _ in 1..100 {
        heating.advance(0.1).expect("heating step");
    }
    let conduction_model = heating.conduction();
    let mut difference = vec![0.0; conduction_model.n_nodes()];
    conduction_model.node_temperature_differences(heating.state(), &mut difference);
    let grid = conduction_model.node_grid().expect("node grid");
    let tip = grid.edge_nodes(GridEdge::Tip);
    let worst_tip = tip.iter().map(|&n| difference[n].abs()).fold(0.0, f64::max);
    let (worst, node) = difference
        .iter()
        .enumerate()
        .map(|(i, d)| (d.abs(), i))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
    let rise = heating
        .node_temperatures_k()
        .iter()
        .fold(0.0_f64, |m, t| m.max(t - 293.0));
    println!(
        "{conduction}: rise {rise:.1} K, largest |dT| {worst:.3e} K (node {node}), tip {worst_tip:.3e} K"
    );
    assert!(
        worst < TOLERANCE_K,
        "{conduction}: {worst} K at node {node}"
    );
    assert_mirror_symmetric(heating.heat_flux_w_m2(), &pairs, 1e-10, conduction);
    let wall = heating.wall_temperatures_k();
    for &(u, l) in &pairs {
        assert!((wall[u] - wall[l]).abs() < TOLERANCE_K, "{conduction}");
    }
    rise
}

#[test]
fn zero_incidence_heating_leaves_no_through_thickness_difference() {
    let dir = std::env::temp_dir().join(format!("hsv-symmetric-heating-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let region = region(&dir);
    for conduction in ["full-order", "pod"] {
        let rise = heat_symmetrically(&region, conduction);
        assert!(rise > 100.0, "{conduction}: rise {rise} K");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
