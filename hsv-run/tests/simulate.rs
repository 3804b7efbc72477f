//! Time simulation of the partitioned vehicle from trim (paper §IV.C): a trimmed state stays
//! put, the elevon doublet's altitude response is non-minimum phase (paper Fig. 11), and input
//! tables are checked; restarts are bit-identical and a glide conserves energy with its loads
//! (one file: the checks share the trimmed vehicles and the flight helpers below).

use hsv_run::analysis::simulate::{InputTable, Inputs, Integrator, RunSettings, Sample, simulate};
use hsv_run::vehicle::partitioned::{FlightControls, PartitionedVehicle};
use hsv_run::vehicle::region_rate::RegionLoadRate;

mod common;

/// The coarse sample vehicle (partitioned, unheated), trimmed.
fn trimmed() -> (
    PartitionedVehicle,
    hsv_run::dynamics::VehicleState,
    FlightControls,
) {
    common::trimmed(
        &common::parse(&common::coarse_text()),
        hsv_run::vehicle::partitioned::SurfaceModel::Partitioned,
        false,
    )
}

/// The heated partitioned vehicle (coarse surfaces, full-order conduction) trimmed, heating at
/// coarse rates (10 ms conduction, 20 ms heat flux, 50 ms stiffness) from 293 K.
fn heated_trimmed() -> (
    PartitionedVehicle,
    hsv_run::dynamics::VehicleState,
    FlightControls,
) {
    use hsv_run::vehicle::partitioned::{HeatingRates, SurfaceModel};
    let loaded = common::parse(
        &common::coarse_text().replace("conduction = \"pod\"", "conduction = \"full-order\""),
    );
    let (mut vehicle, state, controls) = common::trimmed(&loaded, SurfaceModel::Partitioned, true);
    vehicle
        .start_heating(&HeatingRates {
            conduction_s: 0.01,
            heat_flux_s: 0.02,
            stiffness_s: 0.05,
            initial_k: 293.0,
        })
        .expect("heating");
    (vehicle, state, controls)
}

fn fly(duration_s: f64, inputs: &Inputs) -> Vec<Sample> {
    fly_with(duration_s, 0.002, inputs)
}

fn fly_with(duration_s: f64, dt_s: f64, inputs: &Inputs) -> Vec<Sample> {
    fly_at_rate(duration_s, dt_s, RegionLoadRate::default(), inputs)
}

fn fly_at_rate(duration_s: f64, dt_s: f64, rate: RegionLoadRate, inputs: &Inputs) -> Vec<Sample> {
    fly_full(duration_s, dt_s, rate, Integrator::default(), inputs).expect("flies")
}

fn fly_full(
    duration_s: f64,
    dt_s: f64,
    rate: RegionLoadRate,
    integrator: Integrator,
    inputs: &Inputs,
) -> Result<Vec<Sample>, hsv_run::analysis::simulate::SimulationError> {
    let (mut vehicle, mut state, controls) = trimmed();
    vehicle.set_body_load_rate(rate).expect("rate");
    let mut samples = Vec::new();
    let settings = RunSettings {
        dt_s,
        integrator,
        duration_s,
        record_every: 5,
        start_step: 0,
    };
    simulate(
        &mut vehicle,
        &mut state,
        &mut hsv_run::control::ControlLoop::schedule(inputs.clone(), &controls, settings.dt_s)
            .expect("schedule"),
        &settings,
        |s, _, _| {
            samples.push(s.clone());
            true
        },
    )?;
    Ok(samples)
}

#[test]
fn a_trimmed_state_stays_put_for_a_tenth_of_a_second() {
    let still = Inputs {
        symmetric_elevon_deg: InputTable::constant(0.0),
        ..Inputs::paper_doublet()
    };
    let samples = fly(0.1, &still);
    let (first, last) = (&samples[0], samples.last().expect("samples"));
    assert!((last.time_s - 0.1).abs() < 1e-12);
    // Trim residuals of 1e-3 m/s² and 1e-4 rad/s² move the state by at most ½ a t² over 0.1 s:
    // 5e-6 m and 2.9e-5 deg; the bounds leave a factor of ten.
    assert!(
        (last.altitude_m - first.altitude_m).abs() < 5e-5,
        "{last:?}"
    );
    assert!((last.alpha_deg - first.alpha_deg).abs() < 3e-4, "{last:?}");
    assert!(last.q_deg_s.abs() < 1e-2, "{last:?}");
}

#[test]
fn the_elevon_doublet_altitude_response_is_non_minimum_phase() {
    // Paper Fig. 11: a nose-up elevon first pushes the tail surfaces' lift down, so the vehicle
    // sinks before the pitch-up makes it climb.
    let samples = fly(1.8, &Inputs::paper_doublet());
    let h0 = samples[0].altitude_m;
    let lowest = samples
        .iter()
        .min_by(|a, b| a.altitude_m.total_cmp(&b.altitude_m))
        .expect("samples");
    let last = samples.last().expect("samples");
    assert!(lowest.altitude_m < h0 - 1e-3, "no initial sink: {lowest:?}");
    assert!(lowest.time_s > 0.5, "sank before the input: {lowest:?}");
    assert!(last.altitude_m > h0, "no climb after the sink: {last:?}");
    assert!(
        last.pitch_deg > samples[0].pitch_deg,
        "no pitch-up: {last:?}"
    );
}

#[test]
fn input_tables_with_unsorted_or_non_finite_rows_are_refused_with_their_key() {
    let unsorted = InputTable {
        time_s: vec![0.0, 1.0, 0.5],
        value: vec![0.0, 1.0, 2.0],
    };
    let err = unsorted
        .check("simulation.inputs.symmetric_elevon_deg")
        .unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("simulation.inputs.symmetric_elevon_deg") && text.contains("row 2"),
        "{text}"
    );
    let nan = InputTable {
        time_s: vec![0.0, f64::NAN],
        value: vec![0.0, 1.0],
    };
    assert!(
        nan.check("x")
            .unwrap_err()
            .to_string()
            .contains("not finite")
    );
    // Between rows the table is linear, beyond them it holds.
    let ramp = InputTable {
        time_s: vec![1.0, 2.0],
        value: vec![0.0, 4.0],
    };
    assert_eq!(ramp.at(0.0), 0.0);
    assert_eq!(ramp.at(1.25), 1.0);
    assert_eq!(ramp.at(9.0), 4.0);
}

#[test]
fn halving_the_aeroelastic_step_leaves_the_doublet_response_unchanged() {
    // Classical Runge-Kutta is fourth order: halving a 2 ms step changes the state by about
    // 1/16 of its (tiny) error; the pitch and altitude 0.4 s into the doublet agree to 1e-4 deg
    // and 1e-4 m (our bound: a hundredth of the response's own 1e-2 scale).
    let coarse = fly_with(0.9, 0.002, &Inputs::paper_doublet());
    let fine = fly_with(0.9, 0.001, &Inputs::paper_doublet());
    let (a, b) = (coarse.last().expect("coarse"), fine.last().expect("fine"));
    assert!((a.time_s - b.time_s).abs() < 1e-12);
    assert!((a.pitch_deg - b.pitch_deg).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!((a.altitude_m - b.altitude_m).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!(
        a.pitch_deg - coarse[0].pitch_deg > 1e-3,
        "the doublet moved nothing: {a:?}"
    );
}

#[test]
fn the_body_region_at_a_coarser_rate_than_the_stages_leaves_the_doublet_response_unchanged() {
    // The body's loads published every 4 ms (two 2 ms steps, eight Runge-Kutta stages) and
    // extrapolated linearly in between (second order, Farhat & Lesoinne 2000), its skin friction
    // evaluated every 10 ms among them (the default) and the surfaces' friction held over each
    // step, against every region and friction law evaluated at every stage: the same bound as
    // the step-halving test above (a hundredth of the response's 1e-2 scale), fixed before
    // running it.
    let doublet = Inputs::paper_doublet();
    let every_stage = fly_at_rate(0.9, 0.002, RegionLoadRate::EveryStage, &doublet);
    let published = fly_at_rate(0.9, 0.002, RegionLoadRate::Interval(0.004), &doublet);
    let (a, b) = (
        every_stage.last().expect("every stage"),
        published.last().expect("published"),
    );
    assert!((a.time_s - b.time_s).abs() < 1e-12);
    assert!((a.pitch_deg - b.pitch_deg).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!((a.q_deg_s - b.q_deg_s).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!((a.altitude_m - b.altitude_m).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!(
        a.pitch_deg - every_stage[0].pitch_deg > 1e-3,
        "the doublet moved nothing: {a:?}"
    );
}

#[test]
fn the_surfaces_at_the_aeroelastic_rate_leave_the_doublet_response_unchanged() {
    // The paper's exchange (§III.C: "the OML pressure distribution is recalculated at discrete
    // aeroelastic time steps"): each surface evaluated once per 1 ms step at the accepted state
    // and extrapolated linearly over the stages (`surface_loads_dt_s = 0.001`), against every
    // stage. The rigid response keeps the step-halving test's bound (a hundredth of the
    // response's 1e-2 scale); the surfaces' first mode amplitude, which the mean loads drive,
    // agrees to 1e-3 of its value. The bounds are the earlier tests'; the 2 s doublet of the
    // sample vehicle had been flown both ways first (pitch, α and q within 3e-5 of their range).
    let doublet = Inputs::paper_doublet();
    let fly = |rate: RegionLoadRate| {
        let (mut vehicle, mut state, controls) = trimmed();
        vehicle.set_surface_load_rate(rate).expect("rate");
        let settings = RunSettings {
            dt_s: 0.001,
            integrator: Integrator::default(),
            duration_s: 0.9,
            record_every: 5,
            start_step: 0,
        };
        let mut last = None;
        simulate(
            &mut vehicle,
            &mut state,
            &mut hsv_run::control::ControlLoop::schedule(doublet.clone(), &controls, 0.001)
                .expect("schedule"),
            &settings,
            |s, _, _| {
                last = Some(s.clone());
                true
            },
        )
        .expect("flies");
        (last.expect("samples"), state.surface_modes[0].q[0])
    };
    let ((a, first_mode_every_stage), (b, first_mode_published)) = (
        fly(RegionLoadRate::EveryStage),
        fly(RegionLoadRate::Interval(0.001)),
    );
    assert!((a.time_s - b.time_s).abs() < 1e-12);
    assert!((a.pitch_deg - b.pitch_deg).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!((a.q_deg_s - b.q_deg_s).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!((a.altitude_m - b.altitude_m).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!(
        (first_mode_published - first_mode_every_stage).abs()
            <= 1e-3 * first_mode_every_stage.abs(),
        "first mode {first_mode_published} against {first_mode_every_stage}"
    );
    assert!(first_mode_every_stage.abs() > 0.0);
}

#[test]
fn the_exponential_integrator_past_the_runge_kutta_limit_matches_a_fine_runge_kutta_run() {
    // The surfaces' structure integrated exactly (ETDRK4, Cox & Matthews 2002) at a step where
    // classical RK4 is unstable on the coarse surfaces' stiffest Ritz vector, against classical
    // RK4 at a quarter of that step: the same bound as the step-halving test (a hundredth of
    // the response's 1e-2 scale), fixed before running it.
    let doublet = Inputs::paper_doublet();
    let rate = RegionLoadRate::default();
    // The step at which the coarse surfaces' stiffest Ritz vector sits where the sample's does
    // at the paper's 1 ms: ω_max Δt = 3.3 (RK4's limit is 2.83). The Ritz basis is M- and
    // K-orthogonal, so ω_i² is the diagonal of M⁻¹K.
    let (vehicle, _, _) = trimmed();
    let layout = vehicle
        .dynamics()
        .layout(hsv_run::dynamics::AttitudeCoordinates::Quaternion);
    let omega_max = vehicle
        .dynamics()
        .surface_linear_blocks(&layout)
        .iter()
        .flat_map(|b| {
            let n = b.generator.nrows() / 2;
            (0..n).map(move |i| (-b.generator[(n + i, i)]).sqrt())
        })
        .fold(0.0, f64::max);
    let coarse_step = 3.3 / omega_max;
    let exponential = fly_full(0.9, coarse_step, rate, Integrator::ExponentialRk4, &doublet)
        .expect("the exponential integrator is stable");
    let fine = fly_full(0.9, coarse_step / 4.0, rate, Integrator::Rk4, &doublet).expect("flies");
    let (a, b) = (exponential.last().expect("exp"), fine.last().expect("fine"));
    assert!((a.time_s - b.time_s).abs() < 1e-12);
    assert!((a.pitch_deg - b.pitch_deg).abs() < 1e-4, "{a:?} vs {b:?}");
    assert!((a.altitude_m - b.altitude_m).abs() < 1e-4, "{a:?} vs {b:?}");
    let unstable = match fly_full(0.9, coarse_step, rate, Integrator::Rk4, &doublet) {
        Err(_) => true,
        Ok(s) => s
            .last()
            .is_none_or(|l| (l.pitch_deg - b.pitch_deg).abs() > 1.0),
    };
    assert!(
        unstable,
        "classical RK4 at {coarse_step} s should be unstable here"
    );
}

#[test]
fn a_duration_that_is_not_a_whole_number_of_steps_ends_exactly_at_it() {
    // 0.205 s at 2 ms: 102 full steps and a last one of 1 ms, never a silent 0.206 s.
    let still = Inputs {
        symmetric_elevon_deg: InputTable::constant(0.0),
        ..Inputs::paper_doublet()
    };
    let samples = fly_with(0.205, 0.002, &still);
    let last = samples.last().expect("samples");
    assert!((last.time_s - 0.205).abs() < 1e-12, "{last:?}");
}

#[test]
fn a_run_resumed_from_its_restart_file_continues_bit_for_bit() {
    // The body region runs every other step, so the restart falls between two of its
    // evaluations and the resumed run must extrapolate from the saved ones; then the surfaces
    // too (`surface_loads_dt_s`), whose publications the restart file carries as well.
    resumes_bit_for_bit(RegionLoadRate::EveryStage);
    resumes_bit_for_bit(RegionLoadRate::Interval(0.004));
}

#[test]
fn every_derivative_reads_the_regions_loads_from_the_data_manager() {
    // Issue 25: a trim's or linearization's derivative (outside a step) evaluates every region,
    // which publishes its loads as its topic's iterate for the coupling to read at once. Then a
    // step's start publishes the body converged (its own rate), and the surfaces, run at every
    // stage, stay iterates the predictor never reads. A check of the exchange's protocol (which
    // topic, when, converged or not), not of physics.
    let (mut vehicle, state, controls) = trimmed();
    let mut out = vehicle.dynamics().zero_derivative();
    vehicle
        .derivative(&state, &controls, &mut out)
        .expect("derivative");
    let published = vehicle.region_publications();
    let topics: Vec<&str> = published.iter().map(|p| p.topic.as_str()).collect();
    assert_eq!(
        topics,
        [
            "main_body/loads",
            "left_surface/loads",
            "right_surface/loads"
        ]
    );
    assert!(
        published
            .iter()
            .all(|p| p.time_s == Some(0.0) && !p.converged),
        "{published:?}"
    );

    let step = vehicle.begin_step(&state, &controls, 0.0).expect("opens");
    let published = vehicle.region_publications();
    assert!(published[0].converged, "{published:?}");
    assert!(published[1..].iter().all(|p| !p.converged), "{published:?}");
    vehicle.commit_step(step, &state, 0.0).expect("commits");
}

#[test]
fn a_restart_of_another_vehicle_is_refused_and_changes_nothing() {
    // Issue 25: the vehicle's own state is one value, checked whole before any of it is taken,
    // so a refused restart leaves the vehicle as it was (nothing half restored).
    let (mut vehicle, _, _) = heated_trimmed();
    let before = vehicle.restart();
    let mut foreign = before.clone();
    foreign.memory.time_s = 1.0;
    foreign.memory.q_ddot[0] = nalgebra::DVector::zeros(foreign.memory.q_ddot[0].len() + 1);
    let err = vehicle
        .restore(&foreign)
        .expect_err("a surface with one mode more");
    assert!(
        err.to_string().contains("modal accelerations for `"),
        "{err}"
    );
    let mut cold = before.clone();
    cold.memory.time_s = 1.0;
    cold.thermal[0] = None;
    let err = vehicle.restore(&cold).expect_err("one surface unheated");
    assert!(
        err.to_string()
            .contains("heats in one run and not in the other"),
        "{err}"
    );
    assert_eq!(vehicle.restart(), before);
}

/// The heated partitioned vehicle (coarse surfaces), trimmed and flown for 0.2 s in one go, and
/// again stopped at 0.102 s, written to JSON, read back into a freshly built vehicle and
/// resumed: the final states must be identical to the last bit.
fn resumes_bit_for_bit(surface_rate: RegionLoadRate) {
    use hsv_run::vehicle::partitioned::VehicleRestart;
    let start = || {
        let (mut vehicle, state, controls) = heated_trimmed();
        vehicle
            .set_body_load_rate(RegionLoadRate::Interval(0.004))
            .expect("rate");
        vehicle.set_surface_load_rate(surface_rate).expect("rate");
        (vehicle, state, controls)
    };
    let inputs = Inputs {
        symmetric_elevon_deg: InputTable {
            time_s: vec![0.0, 0.05, 0.2],
            value: vec![0.0, 1.0, 1.0],
        },
        ..Inputs::paper_doublet()
    };
    let settings = |start_step: usize| RunSettings {
        dt_s: 0.002,
        integrator: hsv_run::analysis::simulate::Integrator::default(),
        duration_s: 0.2,
        record_every: 1,
        start_step,
    };
    let (mut whole, mut whole_state, controls) = start();
    simulate(
        &mut whole,
        &mut whole_state,
        &mut hsv_run::control::ControlLoop::schedule(inputs.clone(), &controls, settings(0).dt_s)
            .expect("schedule"),
        &settings(0),
        |_, _, _| true,
    )
    .expect("whole run");

    let (mut first, mut state, _) = start();
    let mut restart: Option<(String, String)> = None;
    simulate(
        &mut first,
        &mut state,
        &mut hsv_run::control::ControlLoop::schedule(inputs.clone(), &controls, settings(0).dt_s)
            .expect("schedule"),
        &settings(0),
        |s, state, v| {
            if (s.time_s - 0.102).abs() < 1e-12 {
                let vehicle = serde_json::to_string(&v.restart()).expect("vehicle json");
                let state = serde_json::to_string(state).expect("state json");
                restart = Some((vehicle, state));
                return false;
            }
            true
        },
    )
    .expect("first half");
    let (vehicle_json, state_json) = restart.expect("stopped at 0.102 s");
    let (mut resumed, _, _) = start();
    let saved: VehicleRestart = serde_json::from_str(&vehicle_json).expect("vehicle back");
    resumed.restore(&saved).expect("restores");
    let mut resumed_state: hsv_run::dynamics::VehicleState =
        serde_json::from_str(&state_json).expect("state back");
    simulate(
        &mut resumed,
        &mut resumed_state,
        &mut hsv_run::control::ControlLoop::schedule(inputs.clone(), &controls, settings(0).dt_s)
            .expect("schedule"),
        &settings(51),
        |_, _, _| true,
    )
    .expect("second half");
    assert_eq!(
        resumed_state, whole_state,
        "{surface_rate:?}: resumed run drifted from the whole run"
    );
    assert_eq!(resumed.restart(), whole.restart());
    assert!(
        whole.surface_temperatures()[0].1.max_k > 293.0,
        "the surfaces did not heat"
    );
}

#[test]
fn a_gliding_rigid_vehicle_loses_kinetic_and_potential_energy_to_the_work_of_its_loads() {
    use hsv_run::vehicle::partitioned::SurfaceModel;
    // Energy theorem of a rigid body: E = ½ m V² + ½ ωᵀ J ω + m ∫g dh changes by the work of
    // every non-gravitational load, dE/dt = F·V + M·ω (body axes, about the centre of mass).
    // Structures stiffened a hundredfold make the vehicle nearly rigid (their frequencies, up to
    // 270 Hz, still within the explicit step's reach); with the fuel cut (φ = 0) it glides. The
    // loads' power is integrated by the trapezoidal rule over 0.5 ms steps.
    let loaded = common::parse(&common::stiffer_beam(&common::coarse_text(), 2));
    let (mut vehicle, mut state, controls) = common::trimmed(
        &loaded,
        SurfaceModel::Monolithic { lumped_mass: true },
        false,
    );
    let trim_phi = controls.fuel_equivalence_ratio;
    let glide = Inputs {
        symmetric_elevon_deg: InputTable::constant(0.0),
        differential_elevon_deg: InputTable::constant(0.0),
        fuel_equivalence_ratio: InputTable::constant(-trim_phi),
    };
    let mass = *vehicle.mass_properties();
    let (m, j) = (mass.mass_kg, mass.inertia_kg_m2);
    let energy = |s: &hsv_run::dynamics::VehicleState| {
        let r = &s.rigid;
        let v = r.velocity_body_m_s;
        let w = r.angular_velocity_body_rad_s;
        // Potential energy of inverse-square gravity g = g0 (R / (R + h))² (USSA-1976 eq. 17):
        // ∫₀ʰ m g dx = m g0 R h / (R + h).
        let (g0, re) = (
            hsv_core::atmosphere::STANDARD_GRAVITY_M_S2,
            hsv_core::atmosphere::EARTH_RADIUS_M,
        );
        let h = r.altitude_m();
        0.5 * m * v.norm_squared() + 0.5 * w.dot(&(j * w)) + m * g0 * re * h / (re + h)
    };
    let e0 = energy(&state);
    let mut work = 0.0;
    let mut last_power: Option<f64> = None;
    let mut last_e = e0;
    let settings = RunSettings {
        dt_s: 0.0005,
        integrator: hsv_run::analysis::simulate::Integrator::default(),
        duration_s: 0.2,
        record_every: 1,
        start_step: 0,
    };
    simulate(
        &mut vehicle,
        &mut state,
        &mut hsv_run::control::ControlLoop::schedule(glide.clone(), &controls, settings.dt_s)
            .expect("schedule"),
        &settings,
        |_, s, v| {
            let loads = v.body_loads();
            let power = loads.force_n.dot(&s.rigid.velocity_body_m_s)
                + loads.moment_nm.dot(&s.rigid.angular_velocity_body_rad_s);
            if let Some(p0) = last_power {
                work += 0.5 * (p0 + power) * 0.0005;
            }
            last_power = Some(power);
            last_e = energy(s);
            true
        },
    )
    .expect("glides");
    let lost = last_e - e0;
    assert!(lost < 0.0, "a glide without thrust loses energy: {lost} J");
    // 1 %: the loads are those of the last Runge-Kutta stage of each step, the trapezoid works
    // on 0.5 ms steps, and the stiffened structures still store a little elastic energy; all
    // are far smaller than this bound.
    assert!(
        (lost - work).abs() < 0.01 * lost.abs(),
        "energy change {lost} J vs work of the loads {work} J"
    );
}

#[test]
fn the_heat_flux_comes_from_the_accepted_state_not_the_last_stage() {
    use hsv_core::coupling::ElevonCommand;
    // Issue 25: the in-flight heating read the surface aero the last Runge-Kutta stage left
    // (the predictor at t + dt), not a state the flight passes through. Two heated vehicles
    // open the same step from the same accepted state; one then evaluates a stage far from it
    // (the elevon 10 degrees off), the other none; both commit the same end state. The step's
    // conduction must see the same heat flux: the surfaces' temperatures agree to the last bit.
    let start = heated_trimmed;
    let (mut staged, state, controls) = start();
    let (mut unstaged, _, _) = start();
    let opened = [&mut staged, &mut unstaged]
        .map(|vehicle| vehicle.begin_step(&state, &controls, 0.0).expect("opens"));
    let far_stage = FlightControls {
        elevon: ElevonCommand {
            symmetric_rad: controls.elevon.symmetric_rad + 10f64.to_radians(),
            differential_rad: 0.0,
        },
        ..controls
    };
    let mut derivative = staged.dynamics().zero_derivative();
    staged
        .stage_derivative(&opened[0], 0.01, &state, &far_stage, &mut derivative)
        .expect("stage");
    for (vehicle, open) in [&mut staged, &mut unstaged].into_iter().zip(opened) {
        vehicle.commit_step(open, &state, 0.01).expect("commits");
    }
    let (heated, reference) = (
        staged.surface_temperatures(),
        unstaged.surface_temperatures(),
    );
    assert!(heated[0].1.max_k > 293.0, "the surfaces did not heat");
    assert_eq!(heated, reference, "the heating read the last stage's aero");
}

#[global_allocator]
static GLOBAL: hsv_core::testing::CountingAllocator = hsv_core::testing::CountingAllocator;

#[test]
fn the_time_loop_allocates_nothing_once_its_buffers_exist() {
    use hsv_run::vehicle::partitioned::{HeatingRates, SurfaceModel};
    // The heated partitioned vehicle (coarse surfaces) with the body at its 1 ms rate, the
    // surfaces heating, their stiffness updated every 20 ms and a sample recorded every step:
    // after the first steps have sized every buffer, the loop must not touch the heap. (A
    // topic's buffers exist once it holds its two values: the structure temperatures, published
    // at each stiffness update, by step 20.) One rayon thread, so every allocation happens on
    // the thread the counter watches.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    pool.install(|| {
        // Both coupling schemes: the implicit stage fixed point and the staggered step; and
        // the surfaces published once per step through the data manager.
        let staggered = hsv_run::vehicle::staggered::StaggeredSettings {
            residual_tolerance_m: 1e-5,
            max_sub_iterations: 30,
        };
        for (staggered, surface_rate) in [
            (None, RegionLoadRate::EveryStage),
            (Some(staggered), RegionLoadRate::EveryStage),
            (None, RegionLoadRate::Interval(0.002)),
        ] {
            let loaded = common::parse(&common::coarse_text());
            let (mut vehicle, mut state, controls) =
                common::trimmed(&loaded, SurfaceModel::Partitioned, true);
            vehicle.set_staggered(staggered);
            vehicle
                .set_surface_load_rate(surface_rate)
                .expect("surface rate");
            vehicle
                .start_heating(&HeatingRates {
                    conduction_s: 0.01,
                    heat_flux_s: 0.02,
                    stiffness_s: 0.02,
                    initial_k: 293.0,
                })
                .expect("heating");
            let settings = RunSettings {
                dt_s: 0.002,
                integrator: hsv_run::analysis::simulate::Integrator::default(),
                duration_s: 0.2,
                record_every: 1,
                start_step: 0,
            };
            let mut counts = vec![0_usize; 200];
            let mut n = 0;
            simulate(
                &mut vehicle,
                &mut state,
                &mut hsv_run::control::ControlLoop::schedule(
                    Inputs::paper_doublet(),
                    &controls,
                    settings.dt_s,
                )
                .expect("schedule"),
                &settings,
                |_, _, _| {
                    if n < counts.len() {
                        counts[n] = hsv_core::testing::allocations();
                    }
                    n += 1;
                    true
                },
            )
            .expect("flies");
            assert_eq!(n, 101, "one sample per step and the initial one");
            let steady = counts[100] - counts[20];
            assert_eq!(
                steady, 0,
                "{staggered:?}, surfaces {surface_rate:?}: {steady} allocations in steps 20 to \
                 100"
            );
        }
    });
}

/// Galilean invariance, the closed form a wind field must obey: in a uniform vertical gust w_g
/// (body axes) the vehicle's accelerations are those of the same vehicle in still air with its
/// body velocity less the gust, at zero body rates (level trim, where ω × v vanishes). Every
/// region (body, engine, both surfaces at their pivots) must see the gust for this to hold.
#[test]
fn a_uniform_gust_is_a_change_of_relative_wind() {
    use hsv_run::disturbance::{Disturbances, GustSettings};
    let (mut vehicle, state, controls) = trimmed();
    // Both derivatives close the body-surface interface to its tolerance: tighten it so the
    // comparison below reads the invariance, not the fixed point's stopping error.
    vehicle.set_coupling_settings(hsv_run::vehicle::partitioned::CouplingSettings {
        tolerance: hsv_run::vehicle::partitioned::LINEARIZATION_TOLERANCE,
        max_iterations: 400,
    });
    let w_g = 8.0;
    let airspeed = state.rigid.air_data(&nalgebra::Vector3::zeros()).0;
    // A 1-cosine gust 10 000 km long, read at its peak: uniform over the vehicle to 1e-12.
    let half_length_m = 1e7;
    vehicle.set_disturbances(Disturbances {
        dryden: None,
        gusts: vec![GustSettings {
            start_s: 0.0,
            amplitude_m_s: [0.0, 0.0, w_g],
            half_length_m,
        }],
        airspeed_m_s: airspeed,
    });
    let mut gusty = vehicle.dynamics().zero_derivative();
    vehicle
        .derivative_at(half_length_m / airspeed, &state, &controls, &mut gusty)
        .expect("derivative in the gust");
    assert!((vehicle.gust_body_m_s().z - w_g).abs() < 1e-9);

    vehicle.set_disturbances(Disturbances::default());
    let mut relative = state.clone();
    relative.rigid.velocity_body_m_s.z -= w_g;
    let mut calm = vehicle.dynamics().zero_derivative();
    vehicle
        .derivative(&relative, &controls, &mut calm)
        .expect("derivative in still air");

    let close = |a: f64, b: f64, scale: f64, what: &str| {
        assert!((a - b).abs() <= 1e-9 * scale, "{what}: {a} vs {b}");
    };
    let (a, b) = (&gusty.rigid, &calm.rigid);
    for k in 0..3 {
        close(
            a.acceleration_body_m_s2[k],
            b.acceleration_body_m_s2[k],
            10.0,
            "acceleration",
        );
        close(
            a.angular_acceleration_body_rad_s2[k],
            b.angular_acceleration_body_rad_s2[k],
            1.0,
            "angular acceleration",
        );
    }
    // The gust moved the vehicle's loads (8 m/s at 1800 m/s is 0.25 degree of incidence).
    let mut still_d = vehicle.dynamics().zero_derivative();
    vehicle
        .derivative(&state, &controls, &mut still_d)
        .expect("derivative at trim");
    assert!(
        (a.acceleration_body_m_s2.z - still_d.rigid.acceleration_body_m_s2.z).abs() > 0.1,
        "the gust changed nothing"
    );
    for (s_gust, s_calm) in gusty.surface_modes.iter().zip(&calm.surface_modes) {
        for (x, y) in s_gust.q_ddot.iter().zip(s_calm.q_ddot.iter()) {
            close(*x, *y, y.abs().max(1.0), "surface modal acceleration");
        }
    }
    for (x, y) in gusty
        .body_modes
        .q_ddot
        .iter()
        .zip(calm.body_modes.q_ddot.iter())
    {
        close(*x, *y, y.abs().max(1.0), "body modal acceleration");
    }
}

/// The staggered scheme (paper §III, Table 3: regions exchange once per aeroelastic step,
/// sub-iterated to R_tol) converges to the implicit scheme (the fixed point closed in every
/// stage) as its tolerance shrinks: at the fixed point both solve the same stage equations, so
/// the difference must vanish with R_tol (a limit, not a band: each tenfold tighter tolerance
/// must bring the runs closer, and the tightest within 1e-9 m of interface displacement and
/// 1e-9 deg of pitch). The flight: the coarse vehicle with a 2 deg elevon step over 20 ms,
/// which rings the surfaces' and the body's bending, for 0.2 s at 2 ms steps. The observed
/// order of the difference in R_tol is printed (it is reported, not asserted).
#[test]
fn the_staggered_scheme_converges_to_the_implicit_one_as_its_tolerance_shrinks() {
    use hsv_run::vehicle::staggered::StaggeredSettings;
    let inputs = Inputs {
        symmetric_elevon_deg: InputTable {
            time_s: vec![0.0, 0.02],
            value: vec![0.0, 2.0],
        },
        ..Inputs::paper_doublet()
    };
    let settings = RunSettings {
        dt_s: 0.002,
        integrator: Integrator::default(),
        duration_s: 0.2,
        record_every: 1,
        start_step: 0,
    };
    let fly = |staggered: Option<StaggeredSettings>| {
        let (mut vehicle, mut state, controls) = trimmed();
        vehicle.set_staggered(staggered);
        let mut states = Vec::new();
        let mut iterations = 0;
        simulate(
            &mut vehicle,
            &mut state,
            &mut hsv_run::control::ControlLoop::schedule(inputs.clone(), &controls, settings.dt_s)
                .expect("schedule"),
            &settings,
            |s, state, _| {
                states.push((s.pitch_deg, state.clone()));
                iterations += s.coupling_iterations;
                true
            },
        )
        .expect("flies");
        (vehicle, states, iterations as f64 / 100.0)
    };
    let (reference_vehicle, implicit, _) = fly(None);
    let mut previous = f64::INFINITY;
    let mut last = (0.0, 0.0);
    for exponent in 4..=11 {
        let tolerance = 10f64.powi(-exponent);
        let (_, staggered, mean_sub_iterations) = fly(Some(StaggeredSettings {
            residual_tolerance_m: tolerance,
            max_sub_iterations: 60,
        }));
        let (mut displacement, mut pitch) = (0.0_f64, 0.0_f64);
        for ((p_s, s), (p_i, i)) in staggered.iter().zip(&implicit) {
            displacement =
                displacement.max(reference_vehicle.interface_displacement_change_m(s, i));
            pitch = pitch.max((p_s - p_i).abs());
        }
        let order = (previous / displacement).log10();
        println!(
            "R_tol {tolerance:.0e} m: {mean_sub_iterations:.2} sub-iterations per step, interface \
             {displacement:.3e} m, pitch {pitch:.3e} deg from the implicit run (order {order:.2})"
        );
        assert!(
            displacement <= previous,
            "R_tol {tolerance:e}: {displacement:e} m"
        );
        previous = displacement;
        last = (displacement, pitch);
    }
    assert!(last.0 < 1e-9 && last.1 < 1e-9, "tightest: {last:?}");
}
