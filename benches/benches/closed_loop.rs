//! Cost of 10 s of closed-loop flight with turbulence on the sample vehicle (issue 23's bench):
//! the trimmed flexible partitioned vehicle, heated, under `lqr` (its pilot inputs: the paper's
//! doublet) through severe MIL-F-8785C Dryden turbulence (seed 1), 1 ms steps, as
//! `hsv-run simulate --controller lqr --turbulence severe --duration-s 10` flies it; the trim
//! and the LQR design run once in the setup, each iteration resets the flight to t = 0.
//!
//! `cargo bench -p hsv-benches --bench closed_loop -- --warm-up-time 1`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::config::LoadedConfig;
use hsv_run::analysis::flight::{Flight, FlightOptions};
use hsv_run::disturbance::{DisturbanceSettings, DrydenSettings, HIGH_ALTITUDE_SCALE_M, Severity};

fn closed_loop(c: &mut Criterion) {
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let registry = hsv_run::registry().expect("registry builds");
    let options = FlightOptions {
        controller: Some("lqr".to_owned()),
        disturbances: Some(DisturbanceSettings {
            dryden: Some(DrydenSettings {
                severity: Some(Severity::Severe),
                sigma_m_s: None,
                scale_m: HIGH_ALTITUDE_SCALE_M,
                seed: 1,
            }),
            gusts: Vec::new(),
        }),
        ..FlightOptions::default()
    };
    let mut flight =
        Flight::trimmed(&loaded, &registry, &options, |_| {}).expect("trims and designs");
    let mut group = c.benchmark_group("closed-loop/sample-vehicle");
    group.sample_size(10);
    group.bench_function("10 s lqr, severe Dryden turbulence, dt 1 ms", |b| {
        b.iter(|| {
            flight.reset().expect("resets");
            let steps = flight.fly(10.0, 100, |_, _, _| true).expect("flies 10 s");
            black_box(steps)
        })
    });
    group.finish();
}

criterion_group!(benches, closed_loop);
criterion_main!(benches);
