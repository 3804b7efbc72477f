//! Validation of the `full-order` conduction model against closed-form conduction solutions
//! (Carslaw & Jaeger, Conduction of Heat in Solids, 2nd ed., 1959) and energy conservation.
//!
//! One-dimensional cases use a 1 m × 1 m plate (one grid element) with many element layers
//! through its thickness, heated through one upper panel covering the whole top face; the
//! sides are adiabatic, so the conduction is one-dimensional through the thickness.

mod common;
use approx::assert_relative_eq;
use common::{CP, K, RHO, constant_material, faces};
use hsv_core::config::LoadedConfig;
use hsv_core::material::{Material, MaterialSetting};
use hsv_core::mesh::RegionKind;
use hsv_core::registry::Registry;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::ConductionModel;
use hsv_model_conduction::{FullOrder, FullOrderSettings};
use nalgebra::DVector;

fn slab(thickness_m: f64, sublayers: usize, material: MaterialSetting) -> FullOrder {
    let grid = SurfaceGrid::rectangular(1.0, 1.0, thickness_m, 1, 1).unwrap();
    FullOrder::new(
        &grid,
        &faces(thickness_m),
        FullOrderSettings {
            structure_material: material,
            structure_sublayers: sublayers,
            minimum_thickness_m: 1e-6,
            picard_tolerance_k: 1e-7,
            ..FullOrderSettings::default()
        },
    )
    .unwrap()
}

/// Temperature of `level` (0 = lower face) at plate node 0.
fn at_level(model: &FullOrder, state: &DVector<f64>, level: usize) -> f64 {
    state[model.thermal_grid().dof(0, level)]
}

/// erfc(x), x ≥ 0 (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7).
fn erfc(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    poly * (-x * x).exp()
}

/// Semi-infinite solid under a constant surface flux q from t = 0 (Carslaw & Jaeger §2.9):
/// T − T0 = (2q/k) [√(αt/π) exp(−z²/4αt) − (z/2) erfc(z / 2√(αt))], at the surface
/// 2q√(αt/π)/k. A 50 mm slab of 100 layers for 10 s (penetration depth 4√(αt) = 21 mm),
/// Δt = 10 ms; tolerance 1 % of the surface rise.
#[test]
fn semi_infinite_solid_under_constant_flux_matches_carslaw_and_jaeger() {
    let (h, n) = (0.05, 100);
    let mut model = slab(h, n, constant_material());
    let mut state = model.uniform_state(300.0).unwrap();
    let q = 1.0e5;
    let dt = 0.01;
    let steps = 1000;
    for _ in 0..steps {
        model.step(&mut state, &[q, 0.0], dt).unwrap();
    }
    let t = dt * steps as f64;
    let alpha = K / (RHO * CP);
    let exact = |z: f64| {
        let s = (alpha * t).sqrt();
        2.0 * q / K
            * (s / std::f64::consts::PI.sqrt() * (-z * z / (4.0 * s * s)).exp()
                - 0.5 * z * erfc(z / (2.0 * s)))
    };
    let surface = exact(0.0);
    for depth_layers in [0, 4, 10, 20] {
        let z = h * depth_layers as f64 / n as f64;
        let got = at_level(&model, &state, n - depth_layers) - 300.0;
        println!("z = {z:.4} m: {got:.3} K, exact {:.3} K", exact(z));
        assert!(
            (got - exact(z)).abs() < 0.01 * surface,
            "z = {z}: {got} vs {}",
            exact(z)
        );
    }
    // The reported surface temperature of the heated panel is the top face.
    let mut surface_k = [0.0; 2];
    model.surface_temperatures(&state, &mut surface_k);
    assert_relative_eq!(
        surface_k[0],
        at_level(&model, &state, n),
        max_relative = 1e-12
    );
    assert_relative_eq!(
        surface_k[1],
        at_level(&model, &state, 0),
        max_relative = 1e-12
    );
}

/// Slab 0 < x < L, insulated at x = 0, constant flux q into x = L (Carslaw & Jaeger §3.3):
/// T − T0 = q t/(ρ c L) + (q L/k) [(3x² − L²)/(6L²) − (2/π²) Σ (−1)ⁿ/n² e^(−α n² π² t/L²) cos(nπx/L)].
fn slab_with_flux(x: f64, l: f64, q: f64, t: f64) -> f64 {
    let alpha = K / (RHO * CP);
    let pi = std::f64::consts::PI;
    let series: f64 = (1..200)
        .map(|n: usize| {
            let sign = if n.is_multiple_of(2) { 1.0 } else { -1.0 };
            let n = n as f64;
            sign / (n * n) * (-alpha * n * n * pi * pi * t / (l * l)).exp() * (n * pi * x / l).cos()
        })
        .sum();
    q * t / (RHO * CP * l)
        + q * l / K * ((3.0 * x * x - l * l) / (6.0 * l * l) - 2.0 / (pi * pi) * series)
}

/// Unconditional stability: a 10 mm slab (diffusion time L²/α = 35 s) stepped with Δt = 1 ms
/// and with Δt = 125 s > 3 L²/α stays monotone through the thickness and matches the Fourier
/// series at the end (t = 2 s and t = 250 s) within 1 % of the temperature rise.
#[test]
fn implicit_steps_are_stable_far_beyond_the_diffusion_time() {
    let (l, n, q) = (0.01, 20, 2.0e4);
    for (dt, steps) in [(1e-3, 2000), (125.0, 2)] {
        let mut model = slab(l, n, constant_material());
        let mut state = model.uniform_state(300.0).unwrap();
        for _ in 0..steps {
            model.step(&mut state, &[q, 0.0], dt).unwrap();
        }
        let t = dt * steps as f64;
        let rise = slab_with_flux(l, l, q, t);
        for level in 0..=n {
            let x = l * level as f64 / n as f64;
            let got = at_level(&model, &state, level) - 300.0;
            assert!(
                (got - slab_with_flux(x, l, q, t)).abs() < 0.01 * rise,
                "dt {dt}: x = {x}: {got} vs {}",
                slab_with_flux(x, l, q, t)
            );
            if level > 0 {
                assert!(got >= at_level(&model, &state, level - 1) - 300.0 - 1e-9);
            }
        }
    }
}

/// Steady state: flux q in through the top, out through the bottom; one step of Δt = 1e9 s
/// reaches the linear profile T' = q/k (Fourier's law), with the mean temperature unchanged.
#[test]
fn steady_state_is_the_linear_profile() {
    let (l, n, q) = (0.02, 10, 5.0e3);
    let mut model = slab(l, n, constant_material());
    let mut state = model.uniform_state(400.0).unwrap();
    model.step(&mut state, &[q, -q], 1.0e9).unwrap();
    for level in 0..=n {
        let x = l * level as f64 / n as f64;
        let expected = 400.0 + q / K * (x - 0.5 * l);
        assert_relative_eq!(at_level(&model, &state, level), expected, epsilon = 1e-4);
    }
}

/// Energy conservation with temperature-dependent Ti-6Al-4V (core table): Σ ρ V ∫c_p dT equals
/// ∫ q A dt to 1e-6 over 200 steps that heat the surface by about 230 K.
#[test]
fn stored_energy_equals_heat_input_with_temperature_dependent_properties() {
    let mut model = slab(0.01, 8, MaterialSetting::Name("ti-6al-4v".to_owned()));
    let mut state = model.uniform_state(300.0).unwrap();
    let (q, dt, steps) = (2.0e5, 0.1, 200);
    for _ in 0..steps {
        model.step(&mut state, &[q, 0.0], dt).unwrap();
    }
    assert!(model.last_picard_iterations() > 1);
    let top = at_level(&model, &state, 8);
    assert!(top > 450.0 && top < 923.0, "top {top} K");
    let stored = model.stored_energy_j(&state, 300.0).unwrap();
    let input = q * 1.0 * dt * steps as f64;
    assert_relative_eq!(stored, input, max_relative = 1e-6);
}

#[test]
fn bad_inputs_are_clear_errors() {
    let mut model = slab(0.01, 4, MaterialSetting::Name("ti-6al-4v".to_owned()));
    let mut state = model.uniform_state(300.0).unwrap();
    let err = model.step(&mut state, &[1.0], 0.1).unwrap_err().to_string();
    assert!(err.contains("1 heat fluxes for 2 surface panels"), "{err}");
    let err = model
        .step(&mut state, &[1.0, 0.0], -1.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("time step") && err.contains("-1"), "{err}");
    let err = model
        .step(&mut state, &[f64::NAN, 0.0], 0.1)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("heat flux") && err.contains("panel 0"),
        "{err}"
    );
    // Outside the material's property table (Ti-6Al-4V: see the core table for its range).
    let (_, top) = Material::ti_6al_4v().temperature_range_k();
    let err = model.uniform_state(top + 100.0).unwrap_err().to_string();
    assert!(
        err.contains(&top.to_string()) && err.contains(&(top + 100.0).to_string()),
        "{err}"
    );
    let mut hot = model.uniform_state(top - 50.0).unwrap();
    let err = model
        .step(&mut hot, &[5.0e6, 0.0], 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("Ti-6Al-4V") && err.contains(&top.to_string()),
        "{err}"
    );
    // Settings.
    let grid = SurfaceGrid::rectangular(1.0, 1.0, 0.01, 1, 1).unwrap();
    let err = FullOrder::new(
        &grid,
        &faces(0.01),
        FullOrderSettings {
            picard_tolerance_k: 0.0,
            ..FullOrderSettings::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("picard_tolerance_k"), "{err}");
    // A negative conductivity in a layer's material table.
    let mut tps =
        Material::constant("tps", 300.0, 0.2, 1e9, 1e-6, 0.1, 1000.0, (1.0, 3000.0)).unwrap();
    tps.table[0].conductivity_w_m_k = -0.1;
    let err = FullOrder::new(
        &grid,
        &faces(0.01),
        FullOrderSettings {
            layers: vec![hsv_model_conduction::full_order::LayerSetting {
                thickness_m: 0.005,
                material: MaterialSetting::Table(tps),
                sublayers: 1,
            }],
            ..FullOrderSettings::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("conductivity") && err.contains("-0.1"),
        "{err}"
    );
}

/// A thermal-protection layer over the titanium: the layer's low conductivity keeps the
/// structure cooler than the bare plate under the same flux, and energy is still conserved.
#[test]
fn a_protection_layer_shields_the_structure() {
    let grid = SurfaceGrid::rectangular(1.0, 1.0, 0.01, 1, 1).unwrap();
    let tps = Material::constant("tps", 300.0, 0.2, 1e9, 1e-6, 0.1, 1000.0, (1.0, 3000.0)).unwrap();
    let settings = FullOrderSettings {
        layers: vec![hsv_model_conduction::full_order::LayerSetting {
            thickness_m: 0.005,
            material: MaterialSetting::Table(tps),
            sublayers: 2,
        }],
        picard_tolerance_k: 1e-7,
        ..FullOrderSettings::default()
    };
    let mut covered = FullOrder::new(&grid, &faces(0.02), settings).unwrap();
    let mut bare = slab(0.01, 2, MaterialSetting::Name("ti-6al-4v".to_owned()));
    let mut s_cov = covered.uniform_state(300.0).unwrap();
    let mut s_bare = bare.uniform_state(300.0).unwrap();
    for _ in 0..50 {
        covered.step(&mut s_cov, &[2.0e4, 0.0], 0.2).unwrap();
        bare.step(&mut s_bare, &[2.0e4, 0.0], 0.2).unwrap();
    }
    let mut nodes_cov = vec![0.0; 4];
    let mut nodes_bare = vec![0.0; 4];
    covered.node_temperatures(&s_cov, &mut nodes_cov);
    bare.node_temperatures(&s_bare, &mut nodes_bare);
    assert!(
        nodes_cov[0] < nodes_bare[0] - 5.0,
        "{nodes_cov:?} vs {nodes_bare:?}"
    );
    let stored = covered.stored_energy_j(&s_cov, 300.0).unwrap();
    assert_relative_eq!(stored, 2.0e4 * 10.0, max_relative = 1e-6);
    // Outer face is the hottest level.
    let top = covered.thermal_grid().n_levels - 1;
    assert!(
        s_cov[covered.thermal_grid().dof(0, top)] > s_cov[covered.thermal_grid().dof(0, top - 1)]
    );
}

/// The registered model on the sample lifting surface: every wetted panel maps to the grid,
/// a uniform flux raises the stored energy by exactly Σ q A Δt, the root cap takes no heat.
#[test]
fn registered_model_heats_the_sample_lifting_surface() {
    let loaded = LoadedConfig::sample().unwrap();
    let settings = toml::Table::new();
    let registry = Registry::builtin().unwrap();
    let mut model = registry
        .create::<dyn hsv_core::thermal::ConductionModel>(
            "full-order",
            &common::sample_context(&settings, "models.full-order"),
        )
        .unwrap();
    let mut state = model.uniform_state(293.0).unwrap();
    let n = model.n_surface_panels();
    let cfg = &loaded.config.lifting_surface;
    let mesh =
        hsv_core::geometry::lifting_surface_mesh(cfg, hsv_core::geometry::Side::Right).unwrap();
    assert_eq!(n, mesh.panels.len());
    let q = vec![5.0e4; n];
    let dt = 0.5;
    for _ in 0..4 {
        model.step(&mut state, &q, dt).unwrap();
    }
    let wetted: f64 = mesh
        .panels
        .iter()
        .filter(|p| mesh.surfaces[p.surface as usize].region == RegionKind::LiftingSurface)
        .map(|p| p.area_m2)
        .sum();
    // Energy check through a fresh full-order model with the same settings.
    let grid = SurfaceGrid::lifting_surface(cfg, hsv_core::geometry::Side::Right, 16, 8).unwrap();
    let direct = FullOrder::new(&grid, &mesh, FullOrderSettings::default()).unwrap();
    let stored = direct.stored_energy_j(&state, 293.0).unwrap();
    assert_relative_eq!(stored, 5.0e4 * wetted * dt * 4.0, max_relative = 1e-5);
    let mut nodes = vec![0.0; model.n_nodes()];
    model.node_temperatures(&state, &mut nodes);
    assert!(nodes.iter().all(|&t| t > 293.0 && t < 923.0));
    // Thin edges heat faster than the thick ridge.
    let mut surface = vec![0.0; n];
    model.surface_temperatures(&state, &mut surface);
    let max = surface.iter().cloned().fold(f64::MIN, f64::max);
    let min = surface.iter().cloned().fold(f64::MAX, f64::min);
    assert!(max > min + 1.0, "{min} .. {max}");
}
