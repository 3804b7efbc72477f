//! Cost of whole jobs on the sample vehicle (Mach 6, 26 km, the embedded config's models): one
//! state derivative of the partitioned flexible vehicle at its trim (body–surface coupling
//! converged), one rigid and one flexible trim (Nelder–Mead, the Newton polish and the restart
//! check, as `hsv-run trim`), 0.1 s of flight from trim under the paper's elevon doublet (100
//! steps of 1 ms), the 2 s doublet as `hsv-run simulate` flies it (heated partitioned vehicle;
//! issue 24's target 0.3 s on one core) with the implicit and the staggered coupling and with the
//! surfaces evaluated once per step, and one
//! lifting surface's POD training from a cold cache (nine full-order runs side by side). `RAYON_NUM_THREADS=1` for the one-core figures.
//!
//! `cargo bench -p hsv-benches --bench jobs -- --measurement-time 3 --warm-up-time 1`. The
//! flexible trim that gives the derivative's and the flight's starting state runs once in the
//! setup. One flutter point is in the `flutter` bench.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::config::LoadedConfig;
use hsv_core::registry::ModelContext;
use hsv_model_conduction::PodTraining;
use hsv_run::analysis::flight::{Flight, FlightOptions};
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

    group.bench_function("flexible trim", |b| {
        b.iter(|| black_box(trim(&mut vehicle, black_box(&request)).expect("trims")))
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
    let options = FlightOptions::default();
    group.bench_function(
        "simulate 2 s (heated partitioned, the paper's doublet)",
        |b| {
            b.iter_batched(
                || Flight::trimmed(&loaded, &registry, &options, |_| {}).expect("trims"),
                |mut flight| {
                    let steps = flight.fly(2.0, 5, |_, _, _| true).expect("flies");
                    black_box(steps)
                },
                criterion::BatchSize::PerIteration,
            )
        },
    );

    // The same flight with the surfaces' aero recalculated once per 1 ms aeroelastic step and
    // extrapolated over the stages (`[simulation] surface_loads_dt_s = 0.001`), evaluated
    // beside the body.
    let mut surfaces_per_step = loaded.clone();
    surfaces_per_step.config.simulation.surface_loads_dt_s = Some(0.001);
    group.bench_function(
        "simulate 2 s (heated partitioned, surfaces once per step)",
        |b| {
            b.iter_batched(
                || Flight::trimmed(&surfaces_per_step, &registry, &options, |_| {}).expect("trims"),
                |mut flight| {
                    let steps = flight.fly(2.0, 5, |_, _, _| true).expect("flies");
                    black_box(steps)
                },
                criterion::BatchSize::PerIteration,
            )
        },
    );

    // The same flight with the paper's staggered coupling (R_tol = 1e-5 m): each sub-iteration
    // evaluates every region again, against the implicit scheme's cheap stage iterations.
    let mut staggered = loaded.clone();
    staggered.config.coupling.scheme = hsv_core::config::CouplingSchemeName::Staggered;
    group.bench_function(
        "simulate 2 s (heated partitioned, staggered coupling)",
        |b| {
            b.iter_batched(
                || Flight::trimmed(&staggered, &registry, &options, |_| {}).expect("trims"),
                |mut flight| {
                    let steps = flight.fly(2.0, 5, |_, _, _| true).expect("flies");
                    black_box(steps)
                },
                criterion::BatchSize::PerIteration,
            )
        },
    );

    let region = hsv_core::testing::sample_region("left_surface");
    let pod_settings = region.model_settings("pod");
    let ctx = ModelContext::new(region, &registry, &pod_settings);
    let training: PodTraining = pod_settings
        .table
        .get("training")
        .cloned()
        .map(|t| {
            t.try_into::<PodTraining>()
                .expect("the sample's [models.pod.training]")
        })
        .unwrap_or_default();
    let mut full = hsv_model_conduction::full_order_for(&ctx).expect("full-order model");
    group.bench_function("pod training, one surface (cold cache)", |b| {
        b.iter(|| {
            black_box(
                hsv_model_conduction::training::train_basis(&ctx, &training, &mut full, 32)
                    .expect("trains"),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, jobs);
criterion_main!(benches);
