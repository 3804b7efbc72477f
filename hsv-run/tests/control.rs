//! The `lqr` controller on the (coarse) sample vehicle: its design, its linear closed loop and a
//! short nonlinear closed-loop flight with the paper's doublet.

mod common;

use hsv_run::analysis::simulate::{Integrator, RunSettings, simulate};
use hsv_run::control::{ControlLoop, build_control_loop};

fn design_and_loop(
    dt_s: f64,
) -> (
    hsv_run::vehicle::partitioned::PartitionedVehicle,
    hsv_run::dynamics::VehicleState,
    ControlLoop,
    hsv_run::control::DesignRecord,
    hsv_run::vehicle::partitioned::FlightControls,
) {
    let loaded = common::parse(&common::coarse_text());
    let (mut vehicle, state, controls) = common::trimmed(
        &loaded,
        hsv_run::vehicle::partitioned::SurfaceModel::Partitioned,
        false,
    );
    let registry = hsv_run::registry().expect("registry");
    let (control, design) = build_control_loop(
        &loaded,
        &registry,
        "lqr",
        Some(hsv_run::control::Actuators::new(Default::default(), "control.actuators").unwrap()),
        &mut vehicle,
        &state,
        &controls,
        dt_s,
        hsv_run::control::DesignFrom::Vehicle,
    )
    .expect("lqr designs");
    (vehicle, state, control, design, controls)
}

/// The design: the CARE residual below 1e-9 relative on both axes (the bound), the
/// residualized longitudinal model keeps the unstable short-period root (full model: +1.83 /s
/// from `hsv-run linearize`; the band [1.3, 2.3] /s was chosen after seeing that value), and
/// the rigid closed loop A − B K has every pole in the left half-plane (LQR guarantees it for a
/// stabilizing CARE solution; Anderson & Moore 1990, ch. 3).
#[test]
fn lqr_design_residual_and_closed_loop_poles() {
    let (_, _, control, design, _) = design_and_loop(0.002);
    let report = control.controller().design_report();
    for axis in ["longitudinal", "lateral"] {
        let r = &report[axis];
        let residual = r["care_relative_residual"].as_f64().unwrap();
        assert!(residual < 1e-9, "{axis}: CARE residual {residual}");
        for pole in r["closed_loop_poles"].as_array().unwrap() {
            let re = pole[0].as_f64().unwrap();
            assert!(re < 0.0, "{axis}: closed-loop pole {pole}");
        }
    }
    let a = &design.longitudinal.as_ref().unwrap().a;
    let eig = hsv_core::linalg::general_eigen(a).unwrap();
    let largest = eig.values.iter().map(|c| c.re).fold(f64::MIN, f64::max);
    assert!((1.3..2.3).contains(&largest), "short-period root {largest}");
}

/// 3 s of nonlinear closed-loop flight with the paper's doublet (+1° elevon, 0.5-2 s) added to
/// the LQR commands. Open loop the short period (+1.8 /s) diverges; closed loop α stays within
/// 1° of trim and q within 5 °/s throughout, and by 3 s α is back within 0.1° and q within
/// 0.1 °/s. The throughout-bounds were written before the run; the settling bounds after a
/// CLI run of the full vehicle ended at 0.02° and 0.002 °/s.
#[test]
fn lqr_flies_the_doublet_and_settles() {
    let dt_s = 0.002;
    let (mut vehicle, mut state, mut control, design, _) = design_and_loop(dt_s);
    let trim_alpha = design.trim_outputs.alpha_rad.to_degrees();
    let settings = RunSettings {
        dt_s,
        integrator: Integrator::default(),
        duration_s: 3.0,
        record_every: 5,
        start_step: 0,
    };
    let mut samples = Vec::new();
    simulate(
        &mut vehicle,
        &mut state,
        &mut control,
        &settings,
        |s, _, _| {
            samples.push(s.clone());
            true
        },
    )
    .expect("flies");
    for s in &samples {
        assert!((s.alpha_deg - trim_alpha).abs() < 1.0, "{s:?}");
        assert!(s.q_deg_s.abs() < 5.0, "{s:?}");
        assert!((0.0..=1.0).contains(&s.fuel_equivalence_ratio), "{s:?}");
    }
    // The doublet moved the commands.
    assert!(
        samples
            .iter()
            .any(|s| (s.command_elevon_deg - samples[0].command_elevon_deg).abs() > 0.1)
    );
    let last = samples.last().unwrap();
    assert!((last.time_s - 3.0).abs() < 1e-9);
    assert!((last.alpha_deg - trim_alpha).abs() < 0.1, "{last:?}");
    assert!(last.q_deg_s.abs() < 0.1, "{last:?}");
}

/// `text` (a config) flown by `controller` for `duration_s` from its trim (unheated, 2 ms steps),
/// every `record_every`-th step recorded: the outcome and the samples up to its end.
fn fly_unheated(
    registry: &hsv_core::registry::Registry,
    text: &str,
    controller: &str,
    duration_s: f64,
    record_every: usize,
) -> (
    Result<(), hsv_run::analysis::simulate::SimulationError>,
    Vec<hsv_run::analysis::simulate::Sample>,
) {
    use hsv_run::analysis::flight::{Flight, FlightOptions};
    let loaded = common::parse(text);
    let options = FlightOptions {
        heated: false,
        controller: Some(controller.to_owned()),
        dt_s: 0.002,
        ..FlightOptions::default()
    };
    let mut flight = Flight::trimmed(&loaded, registry, &options, |_| {}).expect("trims");
    let mut samples = Vec::new();
    let outcome = flight.fly(duration_s, record_every, |s, _, _| {
        samples.push(s.clone());
        true
    });
    (outcome.map(|_| ()), samples)
}

/// The `tracking` servo on the coarse sample vehicle at Mach 6, 26 km (unheated, 2 ms steps,
/// default actuators): a +100 m altitude step flown 30 s and, separately, a +20 m/s airspeed
/// step flown 80 s, each ramped in over 1 s from t = 1 s. Bands: the commanded output within
/// 5 % of its step at the end and the other within 10 m or 1 m/s of trim; φ inside [0, 1]
/// throughout; no actuator limit active after 10 s. (The 5 % settling band is the usual one
/// and was written before the airspeed step was flown; the airspeed step's 80 s is physics:
/// at φ = 1 the sample vehicle accelerates at about 0.39 m/s², so +20 m/s takes at least 51 s.
/// The design was iterated on these runs: a lateral regulator, conditional integration.)
#[test]
fn tracking_settles_altitude_and_airspeed_steps() {
    let registry = hsv_run::registry().expect("registry");
    for (table, command, step, duration_s) in [
        ("altitude_m", "altitude_m", 100.0, 30.0),
        ("airspeed_m_s", "airspeed_m_s", 20.0, 80.0),
    ] {
        let text = format!(
            "{}\n[control]\ncontroller = \"tracking\"\n\n[control.commands]\n{table} = {{ time_s = [1.0, 2.0], value = [0.0, {step}] }}\n",
            common::coarse_text()
        );
        let (outcome, samples) = fly_unheated(&registry, &text, "tracking", duration_s, 50);
        outcome.expect("flies");
        let first = samples[0].clone();
        let last = samples.last().expect("samples").clone();
        let dh = last.altitude_m - first.altitude_m;
        let dv = last.airspeed_m_s - first.airspeed_m_s;
        let (tracked, other, other_band) = if command == "altitude_m" {
            (dh, dv, 1.0)
        } else {
            (dv, dh, 10.0)
        };
        assert!(
            (tracked - step).abs() < 0.05 * step,
            "{command}: {tracked} after {duration_s} s for a step of {step}"
        );
        assert!(
            other.abs() < other_band,
            "{command} step moved the other output by {other}"
        );
        for s in &samples {
            assert!(
                (0.0..=1.0).contains(&s.fuel_equivalence_ratio),
                "phi {} at {} s",
                s.fuel_equivalence_ratio,
                s.time_s
            );
            if s.time_s > 10.0 {
                assert!(
                    !(s.elevon_position_saturated
                        || s.elevon_rate_saturated
                        || s.phi_position_saturated
                        || s.phi_rate_saturated),
                    "{command}: an actuator limit is active at {} s",
                    s.time_s
                );
            }
        }
    }
}

/// The full flexible linear model closed by `lqr` (coarse sample, unheated), through the loop
/// the nonlinear runs fly: the default actuators (elevon servo τ = 0.02 s, φ τ = 0.1 s) and
/// the 10 ms hold's average delay of 5 ms (first-order Padé). Every pole is in the closed left
/// half-plane (up to 1e-6 /s: the exactly neutral north, east and heading states). Closed by
/// the ideal continuous law instead (no lag, no delay), the first body bending mode (about
/// 9.4 Hz) goes unstable: q and α measured on the bending body feed the mode back in phase.
/// That is the aeroservoelastic reason the loop dynamics belong in the analysis.
#[test]
fn lqr_closed_loop_with_its_actuators_is_stable_and_without_them_is_not() {
    use hsv_run::control::design::{LoopDynamics, closed_loop_eigenvalues};
    let (mut vehicle, state, control, _, controls) = design_and_loop(0.002);
    let lin = hsv_run::analysis::linearize::linearize(
        &mut vehicle,
        &state,
        &controls,
        &hsv_run::dynamics::PerturbationRule::default(),
    )
    .expect("linearizes");
    let laws = control.controller().state_feedback();
    let flown = LoopDynamics {
        elevon_time_constant_s: 0.02,
        phi_time_constant_s: 0.1,
        delay_s: 0.005,
    };
    let with_loop = closed_loop_eigenvalues(&lin.model, &laws, &flown).expect("closes");
    assert!(
        with_loop[0][0] < 1e-6,
        "largest closed-loop pole {:?}",
        with_loop[0]
    );
    let ideal =
        closed_loop_eigenvalues(&lin.model, &laws, &LoopDynamics::default()).expect("closes");
    let unstable: Vec<_> = ideal.iter().filter(|v| v[0] > 1e-6).collect();
    assert!(
        unstable.iter().any(|v| (2.0 * std::f64::consts::PI * 5.0
            ..2.0 * std::f64::consts::PI * 15.0)
            .contains(&v[1].abs())),
        "no unstable bending mode in the ideal loop: {unstable:?}"
    );
}

/// The example plugin controller (`plugins/pole-placement`, loaded from its cdylib) flies the
/// coarse sample vehicle through a vertical 1-cosine gust of 5 m/s (0.2 s start, 400 m half
/// length). Bands from the closed forms, not from a run: the gust's quasi-steady incidence is
/// w/V = 0.16° and a short period placed at ζ = 0.7 overshoots by 5 %, so |Δα| stays below
/// 1.5 w/V; the placed envelope e^(−ζωt) = e^(−2.8 t) has fallen below 1 % 1.7 s after the
/// gust ends (0.65 s), so from 2.5 s |Δα| < 0.01° and |q| < 0.02 °/s (the uncontrolled
/// phugoid drifts more slowly than that).
#[test]
fn pole_placement_plugin_rides_out_a_gust() {
    let mut registry = hsv_run::registry().expect("registry");
    registry
        .load_plugin(&hsv_core::testing::plugin_path("hsv_plugin_pole_placement"))
        .expect("the plugin loads");
    let text = format!(
        "{}\n[[disturbances.gusts]]\nstart_s = 0.2\namplitude_m_s = [0.0, 0.0, 5.0]\nhalf_length_m = 400.0\n",
        common::coarse_text()
    );
    let (outcome, samples) = fly_unheated(&registry, &text, "pole-placement", 4.0, 5);
    outcome.expect("flies");
    let trim_alpha = samples[0].alpha_deg;
    let quasi_steady_deg = (5.0 / samples[0].airspeed_m_s).to_degrees();
    assert!(samples.iter().any(|s| s.gust_w_m_s > 4.9), "no gust flown");
    for s in &samples {
        let d_alpha = (s.alpha_deg - trim_alpha).abs();
        assert!(
            d_alpha < 1.5 * quasi_steady_deg,
            "Δα {d_alpha}° at {} s",
            s.time_s
        );
        if s.time_s >= 2.5 {
            assert!(d_alpha < 0.01, "Δα {d_alpha}° at {} s", s.time_s);
            assert!(
                s.q_deg_s.abs() < 0.02,
                "q {} °/s at {} s",
                s.q_deg_s,
                s.time_s
            );
        }
    }
}

/// `tracking` holding trim through severe Dryden turbulence (seed 1) for 10 s on the coarse
/// vehicle (unheated, 2 ms). Reading the inertial flight-path angle where its design has α (the
/// default), the gust's α does not drive the elevon and the flight holds (altitude within 20 m);
/// reading the air-data α, the same flight departs before 10 s. Observed, and the band set after
/// seeing it: the coarse vehicle holds within 7.9 m and 7.4° of α, its differential elevon often
/// at its rate limit (it departs at 5.8 s on air data); the full sample vehicle holds 30 s within
/// 0.92 m and 0.27° with no limit reached (and departs at 6.6 s on air data).
#[test]
fn tracking_holds_trim_through_severe_turbulence_reading_the_flight_path() {
    let registry = hsv_run::registry().expect("registry");
    let fly = |inertial: bool| {
        let text = format!(
            "{}\n[control]\ncontroller = \"tracking\"\n\n[models.tracking]\ninertial_flight_path = {inertial}\n\n[disturbances.dryden]\nseverity = \"severe\"\nseed = 1\n",
            common::coarse_text()
        );
        fly_unheated(&registry, &text, "tracking", 10.0, 25)
    };
    let (outcome, samples) = fly(true);
    outcome.expect("holds trim on the flight path");
    let first = &samples[0];
    for s in &samples {
        assert!(
            (s.altitude_m - first.altitude_m).abs() < 20.0,
            "altitude at {} s",
            s.time_s
        );
    }
    assert!(
        samples.iter().any(|s| s.gust_w_m_s.abs() > 1.0),
        "no turbulence flown"
    );
    let (outcome, samples) = fly(false);
    assert!(
        outcome.is_err(),
        "on air data the flight held to {} s",
        samples.last().map_or(0.0, |s| s.time_s)
    );
}

/// Issue 25 item 2, state as data: a heated flight flown 0.1 s, its `RunState` taken and sent
/// through JSON, flown on to 0.2 s; restored to the saved state (the heated structure assembled
/// again) it flies the same 0.1 s again to the last bit, the whole run state included; a state
/// of another vehicle's shape is refused, and a reset returns to t = 0.
#[test]
fn a_flight_restored_to_its_run_state_repeats_its_steps_bit_for_bit() {
    use hsv_run::analysis::flight::{Flight, FlightOptions, RunState};
    let registry = hsv_run::registry().expect("registry");
    let text = common::coarse_text().replace("conduction = \"pod\"", "conduction = \"full-order\"")
        + "\n[simulation]\nheat_transfer_dt_s = 0.01\naerothermal_dt_s = 0.02\nstiffness_interval_s = 0.05\n";
    let loaded = common::parse(&text);
    let options = FlightOptions {
        dt_s: 0.002,
        ..FlightOptions::default()
    };
    let mut flight = Flight::trimmed(&loaded, &registry, &options, |_| {}).expect("trims");
    flight.advance(50).expect("to 0.1 s");
    let json = serde_json::to_string(&flight.run_state()).expect("to json");
    let saved: RunState = serde_json::from_str(&json).expect("from json");
    flight.advance(50).expect("to 0.2 s");
    let end = flight.run_state();
    assert!(
        flight.vehicle.stiffness_heated(),
        "the stiffness was heated by 0.2 s"
    );
    flight.restore(&saved).expect("restores");
    assert_eq!(flight.steps_taken(), 50);
    flight.advance(50).expect("to 0.2 s again");
    assert_eq!(flight.run_state(), end, "the repeated steps drifted");

    let mut foreign = saved.clone();
    foreign.state.body_modes.q = nalgebra::DVector::zeros(1);
    let err = flight.restore(&foreign).expect_err("wrong shape");
    assert!(err.to_string().contains("modal coordinates"), "{err}");
    flight.reset().expect("resets");
    assert_eq!(flight.steps_taken(), 0);
}
