//! Cost of one flutter point of the sample lifting surface (paper §IV.D): the heating march
//! from 293 K at Mach 5, 10 km for 10 s (full-order conduction, Eckert heat flux, 0.1 s steps),
//! the temperature transfer onto `ritz-plate`, the equilibrium, the identified 30 × 30 state
//! matrix (direct derivative) and its eigenvalues; and the identification alone with each
//! derivative method on the cold surface.
//!
//! `cargo bench -p hsv-benches --bench flutter`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::aero::AeroModel;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::ModelContext;
use hsv_core::structure::StructureModel;
use hsv_run::analysis::flutter::sweep::{FlutterModels, FlutterSetup, flight_at, flutter_point};
use hsv_run::analysis::flutter::{DerivativeMethod, SurfaceDynamics, SurfaceOptions};
use hsv_run::analysis::heating::HeatingSteps;

fn flutter(c: &mut Criterion) {
    let registry = hsv_run::registry().expect("registry");
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let region = loaded.region("right_surface").expect("region");
    let setup = FlutterSetup {
        region: region.clone(),
        models: FlutterModels {
            aero: "shock-expansion-piston".into(),
            heat_flux: "eckert".into(),
            conduction: "full-order".into(),
            structure: "ritz-plate".into(),
        },
        altitude_m: 10_000.0,
        alpha_rad: 0.0,
        heating: HeatingSteps {
            dt_s: 0.1,
            flux_every: 1,
            initial_k: 293.0,
        },
        method: DerivativeMethod::Direct,
        compare_methods: false,
        options: SurfaceOptions::default(),
    };
    let mut group = c.benchmark_group("flutter/sample-surface");
    group.sample_size(10);
    group.bench_function(
        "one point: heat 10 s at Mach 5 + identify + eigenvalues",
        |b| {
            b.iter(|| {
                let p = flutter_point(&setup, &registry, black_box(5.0), 10.0).expect("point");
                black_box(p.max_real_per_s)
            })
        },
    );
    let settings = region.model_settings("ritz-plate");
    let structure = registry
        .create::<dyn StructureModel>(
            "ritz-plate",
            &ModelContext::new(&region, &registry, &settings),
        )
        .expect("structure");
    let flight = flight_at(&setup, 5.0).expect("flight");
    let aero_settings = region.model_settings("shock-expansion-piston");
    let aero: Box<dyn AeroModel> = registry
        .create(
            "shock-expansion-piston",
            &ModelContext::new(&region, &registry, &aero_settings),
        )
        .expect("aero");
    let mut surface = SurfaceDynamics::new(
        region.mesh.clone(),
        aero,
        structure.as_ref(),
        flight,
        SurfaceOptions::default(),
    )
    .expect("surface");
    let eq = surface.equilibrium().expect("equilibrium").state;
    for (name, method) in [
        ("identify A (direct derivative)", DerivativeMethod::Direct),
        (
            "identify A (forward difference, 7 steps)",
            DerivativeMethod::ForwardDifference,
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| black_box(surface.identify(&eq, method).expect("identify").a[(0, 0)]))
        });
    }
    group.finish();
}

criterion_group!(benches, flutter);
criterion_main!(benches);
