//! Cost of one evaluation of each aero model on the sample vehicle mesh (body + lifting surfaces).
//!
//! `cargo bench -p hsv-benches --bench aero_models`; per-panel cost = time / panel count, which
//! the bench prints once at start.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hsv_core::aero::{AeroSolution, PanelMotion};
use hsv_core::config::LoadedConfig;
use hsv_core::registry::ModelContext;
use hsv_run::aero_job::{self, AeroRequest};

fn aero_models(c: &mut Criterion) {
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let registry = hsv_run::registry().expect("registry builds");
    let mesh = aero_job::vehicle_mesh(&loaded).expect("sample vehicle builds");
    let models = aero_job::all_aero_models(&registry);
    let request = AeroRequest {
        mach: loaded.config.flight.mach,
        altitude_m: loaded.config.flight.altitude_m,
        alpha_deg: 2.0,
        beta_deg: 0.0,
        models: models.clone(),
        reference: loaded.config.reference,
        include_engine_surfaces: false,
    };
    let flight = aero_job::flight_condition(&loaded, &request).expect("flight condition");
    let panels = mesh.mesh.panels.len();
    eprintln!("sample vehicle mesh: {panels} panels");

    let mut group = c.benchmark_group("aero/sample-vehicle");
    group.throughput(Throughput::Elements(panels as u64));
    for name in &models {
        let key_path = format!("models.{name}");
        let context = ModelContext {
            settings: loaded.model_settings(name),
            key_path: &key_path,
            file: &loaded.file,
            region: hsv_core::testing::sample_region("right_surface"),
            registry: hsv_core::testing::builtin_registry(),
        };
        let mut model = registry
            .create::<dyn hsv_core::aero::AeroModel>(name, &context)
            .expect("model builds");
        let mut solution = AeroSolution::default();
        group.bench_function(name.as_str(), |b| {
            b.iter(|| {
                model
                    .evaluate(
                        black_box(&mesh.mesh),
                        black_box(&flight),
                        &PanelMotion::default(),
                        &mut solution,
                    )
                    .expect("evaluates");
                black_box(&solution.pressure_pa);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, aero_models);
criterion_main!(benches);
