//! The data manager with time: interpolated reads of converged history, iterates, rates checked
//! at assembly, and checkpoints that restore bit-identical state (DESIGN.md §3 "Data manager"; one
//! file: the checks share the topic builders and the multi-topic exchange fixture below).

use hsv_core::data::{
    DataCheckpoint, DataError, DataManager, DataManagerBuilder, Interpolation, Publisher,
    Subscriber, SubscriptionSpec,
};
use nalgebra::{DVector, Vector3};
use serde::{Deserialize, Serialize};

/// x(t) = 3 t + 1, the linear signal of the interpolation tests.
fn linear_signal(t_s: f64) -> f64 {
    3.0 * t_s + 1.0
}

fn one_topic_f64(
    publisher_period_s: f64,
    spec: SubscriptionSpec,
) -> (DataManager, Publisher<f64>, Subscriber<f64>) {
    let mut builder = DataManagerBuilder::new();
    let publisher = builder
        .publish_interpolated::<f64>("aerothermal", "wall-heat-flux", publisher_period_s)
        .unwrap();
    let subscriber = builder
        .subscribe_with::<f64>("thermal", "wall-heat-flux", spec)
        .unwrap();
    (builder.build().unwrap(), publisher, subscriber)
}

fn publish_converged(data: &mut DataManager, publisher: Publisher<f64>, t_s: f64) {
    data.publish(publisher, t_s, linear_signal(t_s)).unwrap();
    assert!(data.mark_converged(publisher).unwrap());
}

/// Closed form: linear interpolation reproduces a signal linear in time exactly, so a 1 ms
/// reader of x(t) = 3 t + 1 published every 10 ms gets 3 t + 1 at every millisecond (up to
/// rounding, 1e-12).
#[test]
fn linear_read_of_10ms_publisher_every_1ms_is_exact_on_linear_signal() {
    let (mut data, publisher, reader) = one_topic_f64(0.01, SubscriptionSpec::every(0.001));
    for k in 0..3 {
        publish_converged(&mut data, publisher, f64::from(k) * 0.01);
    }
    let mut x = f64::NAN;
    for ms in 0..=20 {
        let t_s = f64::from(ms) * 0.001;
        let bracket = data.read_at(reader, t_s, &mut x).unwrap();
        assert!((x - linear_signal(t_s)).abs() <= 1e-12, "t = {t_s}: {x}");
        assert!(bracket.earlier_time_s <= t_s && t_s <= bracket.later_time_s);
    }
    let bracket = data.read_at(reader, 0.015, &mut x).unwrap();
    assert_eq!((bracket.earlier_version, bracket.later_version), (2, 3));
    assert!((bracket.weight - 0.5).abs() <= 1e-12);
}

/// Closed form: the predictor x₁ + (t − t₁)(x₁ − x₀)/(t₁ − t₀) reproduces a signal linear in
/// time exactly past the newest value (Farhat & Lesoinne 2000's second-order predictor), so the
/// stages of a 1 ms step read 3 t + 1 from values at 0 and 1 ms (to rounding, 1e-12); inside the
/// history it interpolates, at the newest value it returns that value bit for bit, and with one
/// value it holds it.
#[test]
fn a_predicted_topic_extrapolates_a_linear_signal_exactly_past_its_newest_value() {
    let mut builder = DataManagerBuilder::new();
    let publisher = builder
        .publish_predicted::<f64>("main-body", "loads", 0.001)
        .unwrap();
    let reader = builder.subscribe::<f64>("vehicle", "loads").unwrap();
    let mut data = builder.build().unwrap();
    let mut x = f64::NAN;
    publish_converged(&mut data, publisher, 0.0);
    data.read_at(reader, 0.0005, &mut x).unwrap();
    assert_eq!(x, linear_signal(0.0), "one value: held");
    publish_converged(&mut data, publisher, 0.001);
    for t_s in [0.001, 0.0015, 0.002, 0.0035] {
        let bracket = data.read_at(reader, t_s, &mut x).unwrap();
        assert!((x - linear_signal(t_s)).abs() <= 1e-12, "t = {t_s}: {x}");
        assert_eq!(bracket.later_time_s, 0.001);
    }
    data.read_at(reader, 0.001, &mut x).unwrap();
    assert_eq!(x.to_bits(), linear_signal(0.001).to_bits());
    data.read_at(reader, 0.0004, &mut x).unwrap();
    assert!((x - linear_signal(0.0004)).abs() <= 1e-12, "inside: {x}");
    let info = data.topics().next().unwrap();
    assert_eq!(info.interpolation, Interpolation::Predicted);
}

#[test]
fn read_beyond_newest_value_holds_it() {
    let (mut data, publisher, reader) = one_topic_f64(0.01, SubscriptionSpec::every(0.001));
    publish_converged(&mut data, publisher, 0.0);
    publish_converged(&mut data, publisher, 0.01);
    let mut x = f64::NAN;
    for t_s in [0.01, 0.0125, 0.019, 5.0] {
        let bracket = data.read_at(reader, t_s, &mut x).unwrap();
        assert_eq!(x.to_bits(), linear_signal(0.01).to_bits(), "t = {t_s}");
        assert_eq!(bracket.earlier_version, bracket.later_version);
        assert_eq!(bracket.weight, 0.0);
    }
}

#[test]
fn read_older_than_history_names_topic_reader_and_times() {
    // A 1 ms reader of a 10 ms publisher keeps ⌈0.001 / 0.01⌉ + 2 = 3 values.
    let (mut data, publisher, reader) = one_topic_f64(0.01, SubscriptionSpec::every(0.001));
    assert_eq!(data.topics().next().unwrap().history_depth, 3);
    for k in 0..5 {
        publish_converged(&mut data, publisher, f64::from(k) * 0.01);
    }
    let mut x = 0.0;
    data.read_at(reader, 0.02, &mut x).unwrap();
    let err = data.read_at(reader, 0.015, &mut x).unwrap_err();
    assert!(matches!(err, DataError::ReadBeforeHistory { .. }));
    let message = err.to_string();
    for needle in ["wall-heat-flux", "thermal", "0.015", "0.02"] {
        assert!(message.contains(needle), "`{needle}` missing in: {message}");
    }
}

#[test]
fn iterates_are_invisible_to_read_at_until_converged() {
    let (mut data, publisher, reader) = one_topic_f64(0.001, SubscriptionSpec::every(0.001));
    let mut x = 0.0;
    data.publish(publisher, 0.0, 10.0).unwrap();
    assert!(matches!(
        data.read_at(reader, 0.0, &mut x),
        Err(DataError::NothingConverged { .. })
    ));
    data.commit(0.0).unwrap();
    for (iteration, iterate) in [11.0, 12.0, 13.0].into_iter().enumerate() {
        data.publish(publisher, 0.001, iterate).unwrap();
        let latest = data.read(reader).unwrap();
        assert_eq!((*latest.value, latest.converged), (iterate, false));
        assert_eq!(latest.version, 2 + iteration as u64);
        data.read_at(reader, 0.001, &mut x).unwrap();
        assert_eq!(x, 10.0, "iterate {iterate} leaked into the history");
        assert_eq!(data.read_converged(reader).unwrap().time_s, 0.0);
    }
    assert_eq!(data.commit(0.001).unwrap(), 1);
    data.read_at(reader, 0.001, &mut x).unwrap();
    assert_eq!(x, 13.0);
    assert!(data.read(reader).unwrap().converged);
    assert_eq!(data.commit(0.001).unwrap(), 0, "nothing left to commit");
}

#[test]
fn commit_up_to_a_time_leaves_later_iterates_pending() {
    let mut builder = DataManagerBuilder::new();
    let fast = builder
        .publish_interpolated::<f64>("main-body", "root-motion", 0.001)
        .unwrap();
    let slow = builder
        .publish_interpolated::<f64>("aerothermal", "heat-flux", 0.01)
        .unwrap();
    let mut data = builder.build().unwrap();
    data.publish(fast, 0.001, 1.0).unwrap();
    data.publish(slow, 0.01, 2.0).unwrap();
    assert_eq!(data.commit(0.001).unwrap(), 1);
    assert!(data.mark_converged(slow).unwrap());
    assert!(!data.mark_converged(fast).unwrap());
}

#[test]
fn recommitting_at_the_newest_time_replaces_that_value() {
    let (mut data, publisher, reader) = one_topic_f64(0.01, SubscriptionSpec::every(0.01));
    publish_converged(&mut data, publisher, 0.0);
    data.publish(publisher, 0.0, 7.0).unwrap();
    data.commit(0.0).unwrap();
    assert_eq!(data.history(reader).unwrap().count(), 1);
    assert_eq!(*data.read_converged(reader).unwrap().value, 7.0);
}

#[test]
fn commit_sooner_than_the_declared_period_is_refused_with_times() {
    let (mut data, publisher, _) = one_topic_f64(0.01, SubscriptionSpec::every(0.001));
    publish_converged(&mut data, publisher, 0.0);
    data.publish(publisher, 0.004, 1.0).unwrap();
    let err = data.mark_converged(publisher).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, DataError::CommitTooSoon { .. }));
    for needle in ["wall-heat-flux", "aerothermal", "0.004", "0.01"] {
        assert!(message.contains(needle), "`{needle}` missing in: {message}");
    }
    let late = data.publish(publisher, -0.001, 1.0).unwrap_err();
    assert!(matches!(late, DataError::PublishedBeforeHistory { .. }));
    let nan = data.publish(publisher, f64::NAN, 1.0).unwrap_err();
    assert!(matches!(nan, DataError::NonFiniteTime { .. }));
}

/// Plain data carried with hold semantics: not interpolable.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
struct EngineStatus {
    mode: String,
    thrust_n: f64,
    unstarted: bool,
}

fn status(mode: &str, thrust_n: f64) -> EngineStatus {
    EngineStatus {
        mode: mode.to_owned(),
        thrust_n,
        unstarted: false,
    }
}

#[test]
fn held_topic_carries_structs_and_reads_the_earlier_value_between_commits() {
    let mut builder = DataManagerBuilder::new();
    let publisher = builder
        .publish_with_rate::<EngineStatus>("propulsion", "engine-status", 0.01)
        .unwrap();
    let reader = builder
        .subscribe_with::<EngineStatus>(
            "main-body",
            "engine-status",
            SubscriptionSpec::every(0.001),
        )
        .unwrap();
    let mut data = builder.build().unwrap();
    assert_eq!(
        data.topics().next().unwrap().interpolation,
        Interpolation::Hold
    );
    data.publish(publisher, 0.0, status("ramjet", 1.0e5))
        .unwrap();
    data.commit(0.0).unwrap();
    data.publish(publisher, 0.01, status("scramjet", 2.0e5))
        .unwrap();
    data.commit(0.01).unwrap();
    let mut out = EngineStatus::default();
    data.read_at(reader, 0.009, &mut out).unwrap();
    assert_eq!(out, status("ramjet", 1.0e5));
    data.read_at(reader, 0.01, &mut out).unwrap();
    assert_eq!(out, status("scramjet", 2.0e5));
}

#[test]
fn nalgebra_and_nested_values_interpolate_and_shape_changes_are_reported() {
    let mut builder = DataManagerBuilder::new();
    let forces = builder
        .publish_interpolated::<DVector<f64>>("surface", "generalized-forces", 0.01)
        .unwrap();
    let velocity = builder
        .publish_interpolated::<Vector3<f64>>("main-body", "velocity", 0.01)
        .unwrap();
    let nodes = builder
        .publish_interpolated::<Vec<[f64; 3]>>("main-body", "oml-nodes", 0.01)
        .unwrap();
    let spec = SubscriptionSpec::every(0.001);
    let forces_in = builder
        .subscribe_with::<DVector<f64>>("body", "generalized-forces", spec)
        .unwrap();
    let velocity_in = builder
        .subscribe_with::<Vector3<f64>>("surface", "velocity", spec)
        .unwrap();
    let nodes_in = builder
        .subscribe_with::<Vec<[f64; 3]>>("surface", "oml-nodes", spec)
        .unwrap();
    let mut data = builder.build().unwrap();
    for (k, t_s) in [0.0, 0.01].into_iter().enumerate() {
        let x = linear_signal(t_s);
        data.publish(forces, t_s, DVector::from_element(4, x))
            .unwrap();
        data.publish(velocity, t_s, Vector3::new(x, -x, 2.0 * x))
            .unwrap();
        data.publish(nodes, t_s, vec![[x, 0.0, -x]; 2 + k]).unwrap();
        assert_eq!(data.commit(t_s).unwrap(), 3);
    }
    let t_s = 0.0037;
    let x = linear_signal(t_s);
    let mut f = DVector::zeros(0);
    data.read_at(forces_in, t_s, &mut f).unwrap();
    assert!(f.iter().all(|fi| (fi - x).abs() <= 1e-12));
    let mut v = Vector3::zeros();
    data.read_at(velocity_in, t_s, &mut v).unwrap();
    assert!((v - Vector3::new(x, -x, 2.0 * x)).norm() <= 1e-12);
    let mut n = Vec::new();
    let err = data.read_at(nodes_in, t_s, &mut n).unwrap_err();
    assert!(matches!(
        err,
        DataError::ShapeChanged {
            earlier: (2, 1),
            later: (3, 1),
            ..
        }
    ));
    assert!(err.to_string().contains("oml-nodes"));
}

#[test]
fn ring_keeps_the_slowest_readers_step_and_history() {
    // Rule 5: a 10 ms reader with 50 ms of history of a 1 ms publisher keeps
    // ⌈(0.05 + 0.01) / 0.001⌉ + 2 = 62 values.
    let spec = SubscriptionSpec::every(0.01).with_history(0.05);
    let (mut data, publisher, reader) = one_topic_f64(0.001, spec);
    assert_eq!(data.topics().next().unwrap().history_depth, 62);
    let mut t_s = 0.0;
    for _ in 0..200 {
        publish_converged(&mut data, publisher, t_s);
        t_s += 0.001; // accumulated rounding must pass the period check
    }
    let newest_s = data.read_converged(reader).unwrap().time_s;
    let mut x = 0.0;
    data.read_at(reader, newest_s - 0.06, &mut x).unwrap();
    assert!((x - linear_signal(newest_s - 0.06)).abs() <= 1e-12);
    assert!(data.read_at(reader, newest_s - 0.0625, &mut x).is_err());
}

#[test]
fn assembly_refuses_a_missing_publisher_naming_topic_and_regions() {
    let mut builder = DataManagerBuilder::new();
    builder
        .publish_with_rate::<f64>("main-body", "flight-condition", 0.001)
        .unwrap();
    builder
        .subscribe_with::<f64>("propulsion", "body-oml", SubscriptionSpec::every(0.001))
        .unwrap();
    let message = builder.build().unwrap_err().to_string();
    for needle in ["body-oml", "propulsion", "flight-condition"] {
        assert!(message.contains(needle), "`{needle}` missing in: {message}");
    }
}

fn build_error(publisher_period_s: f64, spec: SubscriptionSpec) -> (DataError, String) {
    let mut builder = DataManagerBuilder::new();
    builder
        .publish_interpolated::<f64>("aerothermal", "wall-heat-flux", publisher_period_s)
        .unwrap();
    builder
        .subscribe_with::<f64>("thermal", "wall-heat-flux", spec)
        .unwrap();
    let err = builder.build().unwrap_err();
    let message = err.to_string();
    (err, message)
}

#[test]
fn assembly_refuses_bad_rates_naming_topic_region_and_value() {
    let cases = [
        (
            0.0,
            SubscriptionSpec::every(0.001),
            "aerothermal",
            "period_s = 0",
        ),
        (
            -0.01,
            SubscriptionSpec::every(0.001),
            "aerothermal",
            "period_s = -0.01",
        ),
        (
            0.01,
            SubscriptionSpec::every(f64::NAN),
            "thermal",
            "period_s = NaN",
        ),
        (
            0.01,
            SubscriptionSpec::every(0.001).with_history(-1.0),
            "thermal",
            "history_s = -1",
        ),
        (
            0.01,
            SubscriptionSpec::every(f64::INFINITY),
            "thermal",
            "period_s = inf",
        ),
    ];
    for (publisher_period_s, spec, region, value) in cases {
        let (err, message) = build_error(publisher_period_s, spec);
        assert!(matches!(err, DataError::InvalidRate { .. }), "{message}");
        for needle in ["wall-heat-flux", region, value] {
            assert!(message.contains(needle), "`{needle}` missing in: {message}");
        }
    }
}

#[test]
fn assembly_refuses_history_it_cannot_keep_naming_both_periods() {
    let (err, message) = build_error(0.001, SubscriptionSpec::every(0.01).with_history(100.0));
    assert!(matches!(err, DataError::HistoryTooLong { .. }));
    for needle in [
        "wall-heat-flux",
        "aerothermal",
        "thermal",
        "0.001",
        "0.01",
        "100",
    ] {
        assert!(message.contains(needle), "`{needle}` missing in: {message}");
    }
}

#[test]
fn assembly_refuses_a_rated_reader_of_an_unrated_publisher() {
    let mut builder = DataManagerBuilder::new();
    builder.publish::<f64>("main-body", "mach").unwrap();
    builder
        .subscribe_with::<f64>("propulsion", "mach", SubscriptionSpec::every(0.001))
        .unwrap();
    let err = builder.build().unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, DataError::UnratedPublisher { .. }));
    for needle in ["mach", "main-body", "propulsion", "0.001"] {
        assert!(message.contains(needle), "`{needle}` missing in: {message}");
    }
}

// ---------------------------------------------------------------------------------------------
// Checkpoints
// ---------------------------------------------------------------------------------------------

struct Exchange {
    data: DataManager,
    root_motion: Publisher<[f64; 6]>,
    heat_flux: Publisher<Vec<f64>>,
    forces: Publisher<DVector<f64>>,
    engine: Publisher<EngineStatus>,
    mach: Publisher<f64>,
    root_motion_in: Subscriber<[f64; 6]>,
    heat_flux_in: Subscriber<Vec<f64>>,
    forces_in: Subscriber<DVector<f64>>,
    engine_in: Subscriber<EngineStatus>,
    mach_in: Subscriber<f64>,
}

/// The sample vehicle's exchange in miniature: 1 ms aeroelastic topics, a 10 ms heat flux, a
/// held struct and an unrated scalar.
fn exchange() -> Exchange {
    let mut b = DataManagerBuilder::new();
    let every_ms = SubscriptionSpec::every(0.001);
    let root_motion = b
        .publish_interpolated("main-body", "root-motion", 0.001)
        .unwrap();
    let heat_flux = b
        .publish_interpolated("aerothermal", "heat-flux", 0.01)
        .unwrap();
    let forces = b
        .publish_interpolated("left-surface", "generalized-forces", 0.001)
        .unwrap();
    let engine = b
        .publish_with_rate("propulsion", "engine-status", 0.001)
        .unwrap();
    let mach = b.publish("main-body", "mach").unwrap();
    Exchange {
        root_motion_in: b
            .subscribe_with("left-surface", "root-motion", every_ms)
            .unwrap(),
        heat_flux_in: b.subscribe_with("thermal", "heat-flux", every_ms).unwrap(),
        forces_in: b
            .subscribe_with(
                "main-body",
                "generalized-forces",
                every_ms.with_history(0.005),
            )
            .unwrap(),
        engine_in: b.subscribe("main-body", "engine-status").unwrap(),
        mach_in: b.subscribe("propulsion", "mach").unwrap(),
        data: b.build().unwrap(),
        root_motion,
        heat_flux,
        forces,
        engine,
        mach,
    }
}

/// Values whose decimal forms need 17 digits, so any rounding would show in the bits.
fn awkward(k: u32, i: u32) -> f64 {
    (f64::from(k) * 0.7 + f64::from(i)).sin() / 3.0 + 0.1
}

impl Exchange {
    /// Steps `k` of 1 ms: three fixed-point iterates per topic, committed; heat flux every 10 ms.
    fn run(&mut self, steps: std::ops::Range<u32>) {
        for k in steps {
            let t_s = f64::from(k) * 0.001;
            for i in 0..3 {
                let x = awkward(k, i);
                let d = &mut self.data;
                d.publish(self.root_motion, t_s, [x, -x, x * x, 1.0 / x, x.exp(), 0.0])
                    .unwrap();
                d.publish_with(self.forces, t_s, |f| {
                    *f = DVector::from_fn(5, |row, _| x * row as f64)
                })
                .unwrap();
                d.publish(
                    self.engine,
                    t_s,
                    status(if x > 0.1 { "on" } else { "off" }, x),
                )
                .unwrap();
                d.publish(self.mach, t_s, 6.0 + x).unwrap();
                if k % 10 == 0 {
                    d.publish_with(self.heat_flux, t_s, |q| {
                        q.clear();
                        q.extend((0..7).map(|j| x * f64::from(j)));
                    })
                    .unwrap();
                }
            }
            self.data.commit(t_s).unwrap();
        }
    }

    /// A pending iterate at `t_s` on every 1 ms topic, not committed.
    fn iterate(&mut self, t_s: f64) {
        let x = awkward(999, 1);
        let d = &mut self.data;
        d.publish(self.root_motion, t_s, [x; 6]).unwrap();
        d.publish(self.forces, t_s, DVector::from_element(5, x))
            .unwrap();
        d.publish(self.mach, t_s, x).unwrap();
    }

    /// Every stamp and every value bit the exchange shows: latest reads, histories and reads
    /// at every 0.5 ms (an error counts as a marker).
    fn fingerprint(&self) -> Vec<u64> {
        let mut out = Vec::new();
        let d = &self.data;
        stamp(
            &mut out,
            d.read(self.root_motion_in)
                .map(|s| (s.time_s, s.version, s.converged, s.value.to_vec())),
        );
        stamp(
            &mut out,
            d.read(self.heat_flux_in)
                .map(|s| (s.time_s, s.version, s.converged, s.value.clone())),
        );
        stamp(
            &mut out,
            d.read(self.forces_in).map(|s| {
                (
                    s.time_s,
                    s.version,
                    s.converged,
                    s.value.as_slice().to_vec(),
                )
            }),
        );
        stamp(
            &mut out,
            d.read(self.engine_in)
                .map(|s| (s.time_s, s.version, s.converged, vec![s.value.thrust_n])),
        );
        stamp(
            &mut out,
            d.read(self.mach_in)
                .map(|s| (s.time_s, s.version, s.converged, vec![*s.value])),
        );
        for s in d.history(self.forces_in).unwrap() {
            stamp(
                &mut out,
                Ok((
                    s.time_s,
                    s.version,
                    s.converged,
                    s.value.as_slice().to_vec(),
                )),
            );
        }
        for s in d.history(self.engine_in).unwrap() {
            out.push(s.value.mode.len() as u64);
            stamp(
                &mut out,
                Ok((s.time_s, s.version, s.converged, vec![s.value.thrust_n])),
            );
        }
        let (mut motion, mut flux, mut forces) = ([0.0; 6], Vec::new(), DVector::zeros(0));
        let mut mach = 0.0;
        for half_ms in 0..160 {
            let t_s = f64::from(half_ms) * 0.0005;
            let reads = [
                d.read_at(self.root_motion_in, t_s, &mut motion)
                    .map(|_| motion.to_vec()),
                d.read_at(self.heat_flux_in, t_s, &mut flux)
                    .map(|_| flux.clone()),
                d.read_at(self.forces_in, t_s, &mut forces)
                    .map(|_| forces.as_slice().to_vec()),
                d.read_at(self.mach_in, t_s, &mut mach).map(|_| vec![mach]),
            ];
            for read in reads {
                match read {
                    Ok(values) => out.extend(values.iter().map(|x| x.to_bits())),
                    Err(_) => out.push(u64::MAX),
                }
            }
        }
        out
    }
}

fn stamp(out: &mut Vec<u64>, read: Result<(f64, u64, bool, Vec<f64>), DataError>) {
    match read {
        Ok((time_s, version, converged, values)) => {
            out.extend([time_s.to_bits(), version, u64::from(converged)]);
            out.extend(values.iter().map(|x| x.to_bits()));
        }
        Err(_) => out.push(u64::MAX),
    }
}

#[test]
fn restore_returns_bit_identical_state_and_replays_identically() {
    let mut exchange = exchange();
    exchange.run(0..20);
    exchange.iterate(0.020);
    let before = exchange.fingerprint();
    let checkpoint = exchange.data.checkpoint();

    exchange.run(20..70); // wraps every ring
    let ahead = exchange.fingerprint();
    assert_ne!(ahead, before);

    exchange.data.restore(&checkpoint).unwrap();
    assert_eq!(exchange.fingerprint(), before);
    exchange.run(20..70);
    assert_eq!(
        exchange.fingerprint(),
        ahead,
        "replay after restore differs"
    );

    let mut reused = checkpoint.clone();
    exchange.data.checkpoint_into(&mut reused);
    exchange.data.restore(&checkpoint).unwrap();
    exchange.data.restore(&reused).unwrap();
    assert_eq!(exchange.fingerprint(), ahead);
}

#[test]
fn checkpoint_json_round_trip_restores_bit_identical_state() {
    let mut exchange = exchange();
    exchange.run(0..33);
    exchange.iterate(0.033);
    let before = exchange.fingerprint();
    let json = serde_json::to_string(&exchange.data.checkpoint()).unwrap();

    let from_file: DataCheckpoint = serde_json::from_str(&json).unwrap();
    assert_eq!(serde_json::to_string(&from_file).unwrap(), json);
    let mut fresh = self::exchange();
    fresh.data.restore(&from_file).unwrap();
    assert_eq!(fresh.fingerprint(), before);

    exchange.run(33..80);
    exchange.data.restore(&from_file).unwrap();
    assert_eq!(exchange.fingerprint(), before);
}

#[test]
fn restore_refuses_a_checkpoint_of_another_topic_table() {
    let mut exchange = exchange();
    exchange.run(0..3);
    let (mut other, _, _) = one_topic_f64(0.01, SubscriptionSpec::every(0.001));
    let err = other.restore(&exchange.data.checkpoint()).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, DataError::CheckpointTopics { .. }));
    assert!(message.contains("wall-heat-flux") && message.contains("root-motion"));

    let json = serde_json::to_string(&exchange.data.checkpoint()).unwrap();
    let tampered = json.replace("\"engine-status\"", "\"mach-number\"");
    let tampered: DataCheckpoint = serde_json::from_str(&tampered).unwrap();
    let before = exchange.fingerprint();
    assert!(exchange.data.restore(&tampered).is_err());
    assert_eq!(
        exchange.fingerprint(),
        before,
        "a refused restore changed state"
    );
}
