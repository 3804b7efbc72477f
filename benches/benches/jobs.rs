//! Cost of whole jobs on the sample vehicle (Mach 6, 26 km, the embedded config's models): one
//! state derivative of the partitioned flexible vehicle at its trim (body–surface coupling
//! converged), one rigid trim (Nelder–Mead and its restart check, as `hsv-run trim`), and 0.1 s
//! of flight from trim under the paper's elevon doublet (100 steps of 1 ms, as
//! `hsv-run simulate`).
//!
//! `cargo bench -p hsv-benches --bench jobs -- --measurement-time 3 --warm-up-time 1`. The
//! flexible trim that gives the derivative's and the flight's starting state runs once in the
//! setup. One flutter point is in the `flutter` bench.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::config::LoadedConfig;
use hsv_run::analysis::simulate::{Inputs, RunSettings, simulate};
use hsv_run::analysis::trim::{TrimRequest, trim};
use hsv_run::dynamics::GravityModel;
use hsv_run::vehicle::assemble;
use hsv_run::vehicle::partitioned::{
    CouplingSettings, ElevonCommand, FlightControls, PartitionedVehicle, partitioned_needs,
};
use hsv_run::vehicle::rigid::{RigidVehicle, rigid_needs};

fn partitioned(
    loaded: &LoadedConfig,
    registry: &hsv_core::registry::Registry,
) -> PartitionedVehicle {
    let sets = assemble(loaded, registry, &partitioned_needs("bench")).expect("assembles");
    PartitionedVehicle::new(sets, GravityModel::default(), CouplingSettings::default())
        .expect("partitioned vehicle")
}

fn jobs(c: &mut Criterion) {
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let registry = hsv_run::registry().expect("registry builds");
    let request = TrimRequest {
        mach: loaded.config.flight.mach,
        altitude_m: loaded.config.flight.altitude_m,
        ..TrimRequest::default()
    };

    let mut vehicle = partitioned(&loaded, &registry);
    let t = trim(&mut vehicle, &request).expect("flexible trim").trim;
    let controls = FlightControls {
        elevon: ElevonCommand {
            symmetric_rad: t.elevon_deg.to_radians(),
            differential_rad: 0.0,
        },
        fuel_equivalence_ratio: t.fuel_equivalence_ratio,
    };
    let (trimmed, _) = vehicle
        .level_flight_state(
            request.mach,
            request.altitude_m,
            t.alpha_deg.to_radians(),
            &controls,
        )
        .expect("trimmed state");

    let mut group = c.benchmark_group("jobs/sample-vehicle");
    group.sample_size(10);
    let mut derivative = vehicle.dynamics().zero_derivative();
    group.bench_function("partitioned state derivative", |b| {
        b.iter(|| {
            vehicle
                .derivative(black_box(&trimmed), &controls, &mut derivative)
                .expect("derivative");
            black_box(&derivative);
        })
    });

    let sets = assemble(&loaded, &registry, &rigid_needs("bench")).expect("assembles");
    let mut rigid = RigidVehicle::new(sets).expect("rigid vehicle");
    group.bench_function("rigid trim", |b| {
        b.iter(|| black_box(trim(&mut rigid, black_box(&request)).expect("trims")))
    });

    let inputs = Inputs::paper_doublet();
    let settings = RunSettings {
        dt_s: 0.001,
        integrator: hsv_run::analysis::simulate::Integrator::default(),
        duration_s: 0.1,
        record_every: 20,
        start_step: 0,
    };
    group.bench_function("simulate 0.1 s (partitioned, dt 1 ms)", |b| {
        b.iter_batched(
            || (partitioned(&loaded, &registry), trimmed.clone()),
            |(mut fresh, mut state)| {
                let steps = simulate(
                    &mut fresh,
                    &mut state,
                    &mut hsv_run::control::ControlLoop::schedule(
                        inputs.clone(),
                        &controls,
                        settings.dt_s,
                    )
                    .expect("schedule"),
                    &settings,
                    |_, _, _| true,
                )
                .expect("flies");
                black_box(steps)
            },
            criterion::BatchSize::PerIteration,
        )
    });
    group.finish();
}

criterion_group!(benches, jobs);
criterion_main!(benches);
