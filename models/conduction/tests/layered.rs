//! `full-order` with an outer (thermal-protection) layer on both faces against steady
//! one-dimensional conduction through a composite wall: in series, the temperature drop across
//! each layer is q t / k and the drops add, ΔT = q Σ tᵢ/kᵢ (Incropera & DeWitt, Fundamentals of
//! Heat and Mass Transfer, §3.1.2 "The composite wall", thermal resistances in series).
//!
//! A 1 m × 1 m plate (one grid element, adiabatic sides) carries the stack lower layer /
//! structure / upper layer; flux q enters through the upper face and leaves through the lower,
//! and one implicit step of 1e9 s reaches the steady state.

mod common;
use approx::assert_relative_eq;
use common::faces;
use hsv_core::material::{Material, MaterialSetting};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::ConductionModel;
use hsv_model_conduction::full_order::LayerSetting;
use hsv_model_conduction::{FullOrder, FullOrderSettings};
use nalgebra::DVector;

/// Structure: a constant-property titanium-like plate (the closed form needs constant k).
const K_STRUCTURE: f64 = 7.0;
/// Protection layer: a constant-property insulator.
const K_LAYER: f64 = 0.1;

fn structure() -> MaterialSetting {
    MaterialSetting::Table(
        Material::constant(
            "structure",
            4430.0,
            0.31,
            110e9,
            9e-6,
            K_STRUCTURE,
            560.0,
            (1.0, 5000.0),
        )
        .unwrap(),
    )
}

fn layer() -> MaterialSetting {
    MaterialSetting::Table(
        Material::constant(
            "insulator",
            300.0,
            0.2,
            1e9,
            1e-6,
            K_LAYER,
            1000.0,
            (1.0, 5000.0),
        )
        .unwrap(),
    )
}

/// A plate of structural thickness `t_structure_m` with a `t_layer_m` layer on each face
/// (`None`: bare).
fn plate(t_structure_m: f64, t_layer_m: Option<f64>) -> FullOrder {
    let grid = SurfaceGrid::rectangular(1.0, 1.0, t_structure_m, 1, 1).unwrap();
    let layers: Vec<LayerSetting> = t_layer_m
        .map(|t| LayerSetting {
            thickness_m: t,
            material: layer(),
            sublayers: 4,
        })
        .into_iter()
        .collect();
    let total = t_structure_m + 2.0 * t_layer_m.unwrap_or(0.0);
    FullOrder::new(
        &grid,
        &faces(total),
        FullOrderSettings {
            structure_material: structure(),
            structure_sublayers: 4,
            minimum_thickness_m: 1e-6,
            picard_tolerance_k: 1e-7,
            layers,
            ..FullOrderSettings::default()
        },
    )
    .unwrap()
}

/// Temperature of `level` (0 = lower face) at plate node 0.
fn at_level(model: &FullOrder, state: &DVector<f64>, level: usize) -> f64 {
    state[model.thermal_grid().dof(0, level)]
}

/// Steady composite wall (Incropera §3.1.2): face-to-face drop q (2 t_l/k_l + t_s/k_s), the
/// structure's own drop q t_s/k_s, each layer's q t_l/k_l; to 1e-6 relative.
#[test]
fn steady_drop_through_a_protected_plate_is_the_series_resistance() {
    let (t_s, t_l, q) = (0.01, 0.005, 2.0e3);
    let mut model = plate(t_s, Some(t_l));
    let mut state = model.uniform_state(400.0).unwrap();
    model.step(&mut state, &[q, -q], 1.0e9).unwrap();
    let top = model.thermal_grid().n_levels - 1;
    let (s_lo, s_hi) = model.thermal_grid().structure_ranges[0];
    let faces_drop = at_level(&model, &state, top) - at_level(&model, &state, 0);
    let structure_drop = at_level(&model, &state, s_hi) - at_level(&model, &state, s_lo);
    let layer_drop = at_level(&model, &state, top) - at_level(&model, &state, s_hi);
    assert_relative_eq!(
        faces_drop,
        q * (2.0 * t_l / K_LAYER + t_s / K_STRUCTURE),
        max_relative = 1e-6
    );
    assert_relative_eq!(structure_drop, q * t_s / K_STRUCTURE, max_relative = 1e-6);
    assert_relative_eq!(layer_drop, q * t_l / K_LAYER, max_relative = 1e-6);
    // Heat in equals heat out: the mean stays at the initial 400 K, so the structure (in the
    // middle of a symmetric stack) averages 400 K.
    let mut nodes = vec![0.0; 4];
    model.node_temperatures(&state, &mut nodes);
    assert_relative_eq!(nodes[0], 400.0, epsilon = 1e-3);
}

/// Transient, one face heated: the structure temperature that the plate model sees
/// (`node_temperatures`, the structure's levels only) rises less under a protection layer than
/// bare, while the stored energy still equals the heat input (first law, to 1e-6).
#[test]
fn a_protection_layer_reduces_the_structure_temperature_rise() {
    let (t_s, t_l, q, dt, steps) = (0.01, 0.005, 2.0e4, 0.2, 100);
    let mut covered = plate(t_s, Some(t_l));
    let mut bare = plate(t_s, None);
    let mut s_cov = covered.uniform_state(300.0).unwrap();
    let mut s_bare = bare.uniform_state(300.0).unwrap();
    for _ in 0..steps {
        covered.step(&mut s_cov, &[q, 0.0], dt).unwrap();
        bare.step(&mut s_bare, &[q, 0.0], dt).unwrap();
    }
    let mut n_cov = vec![0.0; 4];
    let mut n_bare = vec![0.0; 4];
    covered.node_temperatures(&s_cov, &mut n_cov);
    bare.node_temperatures(&s_bare, &mut n_bare);
    // Bare: all the heat is in the structure, mean rise q t / (ρ c_p t_s) (first law; 2 % for
    // the trapezoid average over 4 sub-layers of a profile still curved after 20 s).
    let bare_rise = q * dt * steps as f64 / (4430.0 * 560.0 * t_s);
    assert_relative_eq!(n_bare[0] - 300.0, bare_rise, max_relative = 0.02);
    assert!(
        n_cov[0] - 300.0 < 0.5 * bare_rise,
        "covered {} K vs bare {} K",
        n_cov[0],
        n_bare[0]
    );
    let stored = covered.stored_energy_j(&s_cov, 300.0).unwrap();
    assert_relative_eq!(stored, q * dt * steps as f64, max_relative = 1e-6);
}
