//! Cost of one heat-flux evaluation on the sample lifting surface: `eckert` (reference
//! temperature, per panel) against `kriging-stanton` (one batched Gaussian-process prediction),
//! on shock-expansion edge states at Mach 6, 26 km and a 600 K wall.
//!
//! `cargo bench -p hsv-benches --bench heat_flux`. The surrogate is trained in the setup (default
//! settings: 150 Latin-hypercube samples of `eckert` per regime, laminar and turbulent).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hsv_core::aero::{AeroSolution, PanelMotion};
use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::geometry::{Side, lifting_surface_mesh};
use hsv_core::registry::ModelContext;

fn heat_flux(c: &mut Criterion) {
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let registry = hsv_run::registry().expect("registry builds");
    let context = |name: &'static str, key: &'static str| ModelContext {
        settings: loaded.model_settings(name),
        key_path: key,
        file: &loaded.file,
        region: hsv_core::testing::sample_region("right_surface"),
        registry: hsv_core::testing::builtin_registry(),
    };
    let mesh = lifting_surface_mesh(&loaded.config.lifting_surface, Side::Right).expect("mesh");
    let freestream = Freestream::standard(6.0, 26_000.0, loaded.config.gas).expect("freestream");
    let flight = FlightCondition::steady(freestream, 0.0, 0.0);
    let mut aero = AeroSolution::default();
    registry
        .create::<dyn hsv_core::aero::AeroModel>(
            "shock-expansion",
            &context("shock-expansion", "models.shock-expansion"),
        )
        .expect("aero")
        .evaluate(&mesh, &flight, &PanelMotion::default(), &mut aero)
        .expect("aero evaluates");
    let n = mesh.panels.len();
    let wall = vec![600.0; n];
    let mut q = vec![0.0; n];

    let mut group = c.benchmark_group("heat-flux/lifting-surface");
    group.throughput(Throughput::Elements(n as u64));
    for (name, key) in [
        ("eckert", "models.eckert"),
        ("kriging-stanton", "models.kriging-stanton"),
    ] {
        let mut model = registry
            .create::<dyn hsv_core::thermal::HeatFluxModel>(name, &context(name, key))
            .expect("heat-flux model");
        group.bench_function(name, |b| {
            b.iter(|| {
                model
                    .heat_flux(&mesh, &flight, &aero, &wall, &mut q)
                    .expect("heat flux");
                black_box(&q);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, heat_flux);
criterion_main!(benches);
