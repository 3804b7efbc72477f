//! Cost of a `ritz-plate` stiffness update from a temperature field on the sample lifting
//! surface: the reduced update (`set_temperatures`: membrane solve + reduced element sums +
//! 15 × 15 eigen-decomposition) against a full rebuild (assemble K(T) + K_G(σ(T)) of the
//! full-order plate and re-solve its 10 lowest modes), and the one-time Ritz-basis build.
//!
//! `cargo bench -p hsv-benches --bench ritz_plate`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::config::LoadedConfig;
use hsv_core::geometry::Side;
use hsv_core::material::Material;
use hsv_core::structure::StructureModel;
use hsv_core::structure::ThermalStiffness;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_model_ritz_plate::{RitzPlate, Settings};

fn ritz_plate(c: &mut Criterion) {
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    // The defaults are the sample config's [models.ritz-plate] table (tested in the crate).
    let settings = Settings::default();
    let surface = &loaded.config.lifting_surface;
    let grid = || {
        SurfaceGrid::lifting_surface(
            surface,
            Side::Right,
            settings.elements_chordwise,
            settings.elements_spanwise,
        )
        .expect("grid")
    };
    let mut model = RitzPlate::new(grid(), Material::ti_6al_4v(), &settings).expect("model");
    let g = grid();
    // A hot leading edge: 700 K at the leading edge falling linearly to 293 K at mid-chord,
    // and 50 K hotter at the tip than at the root.
    let temps: Vec<f64> = (0..g.n_nodes())
        .map(|n| {
            let u = g.chord_fractions[n % g.nodes_chordwise()];
            let eta = g.span_fractions[n / g.nodes_chordwise()];
            293.0 + 407.0 * (1.0 - 2.0 * u).max(0.0) + 50.0 * eta
        })
        .collect();
    eprintln!(
        "ritz-plate sample surface: {} nodes, {} elements, {} free bending dofs, {} Ritz vectors",
        g.n_nodes(),
        g.n_elements(),
        model.plate().bending_map.n_equations,
        model.basis().ncols()
    );
    let mut group = c.benchmark_group("ritz-plate/sample-surface");
    group.bench_function("set_temperatures (reduced update)", |b| {
        b.iter(|| {
            model.set_temperatures(black_box(&temps)).expect("update");
            black_box(model.modal_model().stiffness[(0, 0)])
        })
    });
    group.sample_size(10);
    group.bench_function("full rebuild (assemble K(T) + K_G, 10 modes)", |b| {
        b.iter(|| {
            black_box(
                model
                    .plate()
                    .frequencies_hz(Some(black_box(&temps)), 10)
                    .expect("full"),
            )
        })
    });
    group.bench_function("Ritz basis build (construction)", |b| {
        b.iter(|| {
            black_box(RitzPlate::new(grid(), Material::ti_6al_4v(), &settings).expect("model"))
        })
    });
    group.finish();
}

criterion_group!(benches, ritz_plate);
criterion_main!(benches);
