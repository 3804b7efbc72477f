//! Cost of each structure model on its sample region: construction (assembly and the modal
//! solve: the free-free beam's finite elements for the main body, the Ritz plate's MITC4 basis
//! for the lifting surface) and the mapping of its modes onto the region's aero mesh, the two
//! things the partitioned vehicle asks of a structure outside the time loop. The per-step
//! stiffness update of `ritz-plate` is in the `ritz_plate` bench.
//!
//! `cargo bench -p hsv-benches --bench structures -- --measurement-time 3 --warm-up-time 1`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::registry::{ModelContext, Role};
use hsv_core::structure::StructureModel;

fn structures(c: &mut Criterion) {
    let registry = hsv_run::registry().expect("registry builds");
    let mut group = c.benchmark_group("structures/sample-region");
    group.sample_size(10);
    for name in registry.names(Role::Structure) {
        // Each model on the region the sample config gives it.
        let region_name = match name {
            "free-free-beam" => "main_body",
            _ => "right_surface",
        };
        let region = hsv_core::testing::sample_region(region_name);
        let settings = region.model_settings(name);
        let context = ModelContext::new(region, &registry, &settings);
        let build = || {
            // The construction itself, not the copy of the mirror surface's plate that
            // `ritz-plate` hands out when built twice from the same inputs.
            hsv_model_ritz_plate::forget_built_plates();
            registry
                .create::<dyn StructureModel>(name, &context)
                .expect("structure builds")
        };
        group.bench_function(format!("{name}/construction"), |b| {
            b.iter(|| black_box(build()))
        });
        let model = build();
        group.bench_function(format!("{name}/mode shapes on the aero mesh"), |b| {
            b.iter(|| black_box(model.mode_shapes_on(&region.mesh).expect("maps")))
        });
    }
    group.finish();
}

criterion_group!(benches, structures);
criterion_main!(benches);
