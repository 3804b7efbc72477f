//! Cost of one evaluation of each propulsion model on the sample vehicle body mesh (Mach 6,
//! 26 km, α = 0), at the paper's trim φ = 0.13 (paper Table 2) and past thermal choking
//! (φ = 0.6), where `scramjet-q1d` searches for the largest heat release the combustor takes.
//!
//! `cargo bench -p hsv-benches --bench propulsion`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::geometry::build_vehicle;
use hsv_core::propulsion::{EngineInputs, PropulsionSolution};
use hsv_core::registry::{ModelContext, Role};
use hsv_model_scramjet as _;

fn propulsion_models(c: &mut Criterion) {
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let registry = hsv_run::registry().expect("registry builds");
    let body = build_vehicle(&loaded.config.geometry, &loaded.config.lifting_surface)
        .expect("sample vehicle builds")
        .body;
    let freestream = Freestream::standard(6.0, 26_000.0, loaded.config.gas).expect("atmosphere");
    let mut flight = FlightCondition::steady(freestream, 0.0, 0.0);
    flight.rotation_center_m = loaded.config.reference.moment_point();
    eprintln!("sample body mesh: {} panels", body.panels.len());

    let mut group = c.benchmark_group("propulsion/sample-body");
    for name in registry.names(Role::Propulsion) {
        let key_path = format!("models.{name}");
        let context = ModelContext {
            settings: loaded.model_settings(name),
            key_path: &key_path,
            file: &loaded.file,
            region: hsv_core::testing::sample_region("propulsion"),
            registry: hsv_core::testing::builtin_registry(),
        };
        let mut model = registry
            .create::<dyn hsv_core::propulsion::PropulsionModel>(name, &context)
            .expect("model builds");
        let mut solution = PropulsionSolution::default();
        for (label, phi) in [("phi-0.13", 0.13), ("phi-0.6-choked", 0.6)] {
            let inputs = EngineInputs {
                flight: &flight,
                body: &body,
                fuel_equivalence_ratio: phi,
            };
            group.bench_function(format!("{name}/{label}"), |b| {
                b.iter(|| {
                    model
                        .evaluate(black_box(&inputs), &mut solution)
                        .expect("evaluates");
                    black_box(&solution.loads);
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, propulsion_models);
criterion_main!(benches);
