//! Cost of one conduction step on the sample lifting surface: `full-order` (finite elements,
//! banded Cholesky per Picard iteration) against `pod` (32 modes, r × r Galerkin system), at the
//! paper's 1 ms heat-transfer step under Eckert heating at Mach 6, 26 km.
//!
//! `cargo bench -p hsv-benches --bench conduction`. The POD basis is built in the setup from
//! full-order snapshots of the same heating (Mach 5, 6 and 7).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::aero::{AeroSolution, PanelMotion};
use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::geometry::{Side, lifting_surface_mesh};
use hsv_core::registry::ModelContext;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::ConductionModel;
use hsv_model_conduction::{
    FullOrder, FullOrderSettings, Pod, PodBasis, PodSettings, collect_snapshots,
};

fn conduction(c: &mut Criterion) {
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let registry = hsv_run::registry().expect("registry builds");
    let settings = FullOrderSettings::default();
    let cfg = &loaded.config.lifting_surface;
    let grid = SurfaceGrid::lifting_surface(
        cfg,
        Side::Right,
        settings.elements_chordwise,
        settings.elements_spanwise,
    )
    .expect("grid");
    let mesh = lifting_surface_mesh(cfg, Side::Right).expect("mesh");
    let mut full = FullOrder::new(&grid, &mesh, settings.clone()).expect("full order");
    let key = "models.eckert".to_owned();
    let context = ModelContext {
        settings: loaded.model_settings("eckert"),
        key_path: &key,
        file: &loaded.file,
        region: hsv_core::testing::sample_region("right_surface"),
        registry: hsv_core::testing::builtin_registry(),
    };
    let mut aero_model = registry
        .create::<dyn hsv_core::aero::AeroModel>(
            "shock-expansion",
            &ModelContext {
                settings: loaded.model_settings("shock-expansion"),
                key_path: "models.shock-expansion",
                file: &loaded.file,
                region: hsv_core::testing::sample_region("right_surface"),
                registry: hsv_core::testing::builtin_registry(),
            },
        )
        .expect("aero");
    let mut heat = registry
        .create::<dyn hsv_core::thermal::HeatFluxModel>("eckert", &context)
        .expect("eckert");
    let flight_at = |mach: f64| {
        let f = Freestream::standard(mach, 26_000.0, loaded.config.gas).expect("freestream");
        FlightCondition::steady(f, 0.0, 0.0)
    };
    let mut snapshots = Vec::new();
    for mach in [5.0, 6.0, 7.0] {
        let flight = flight_at(mach);
        let mut aero = AeroSolution::default();
        aero_model
            .evaluate(&mesh, &flight, &PanelMotion::default(), &mut aero)
            .expect("aero evaluates");
        snapshots.extend(
            collect_snapshots(&mut full, 293.0, 0.1, 100, 1, |wall, q| {
                heat.heat_flux(&mesh, &flight, &aero, wall, q)
            })
            .expect("snapshots"),
        );
    }
    let basis = PodBasis::from_snapshots(&snapshots, 32, settings).expect("basis");
    let mut pod = Pod::new(&full, basis, PodSettings::default()).expect("pod");

    // Heat flux at the state reached after 5 s at Mach 6 (full order), held during the bench.
    let flight = flight_at(6.0);
    let mut aero = AeroSolution::default();
    aero_model
        .evaluate(&mesh, &flight, &PanelMotion::default(), &mut aero)
        .expect("aero evaluates");
    let mut state = full.uniform_state(293.0).expect("state");
    let n = mesh.panels.len();
    let (mut wall, mut q) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..50 {
        full.surface_temperatures(&state, &mut wall);
        heat.heat_flux(&mesh, &flight, &aero, &wall, &mut q)
            .expect("flux");
        full.step(&mut state, &q, 0.1).expect("step");
    }
    let a = pod.project(&state);
    eprintln!(
        "full order: {} temperatures; POD: {} modes",
        full.n_states(),
        pod.n_states()
    );

    let mut group = c.benchmark_group("conduction/step-1ms");
    group.bench_function("full-order", |b| {
        b.iter_batched_ref(
            || state.clone(),
            |s| full.step(black_box(s), black_box(&q), 1e-3).expect("step"),
            criterion::BatchSize::SmallInput,
        )
    });
    group.bench_function("pod", |b| {
        b.iter_batched_ref(
            || a.clone(),
            |s| pod.step(black_box(s), black_box(&q), 1e-3).expect("step"),
            criterion::BatchSize::SmallInput,
        )
    });
    group.finish();
}

criterion_group!(benches, conduction);
criterion_main!(benches);
