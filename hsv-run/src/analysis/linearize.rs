//! Linear models of the trimmed partitioned vehicle for control design (the paper's stated
//! purpose): ẋ = A x + B u, y = C x + D u by central differences (paper Eqs. 6-7 perturbation
//! rule) around a trim, with 3-2-1 Euler attitude so the state is minimal, inputs symmetric and
//! differential elevon and φ, and the usual flight-dynamics outputs; eigenvalues named by
//! content (short period, phugoid, roll, Dutch roll, spiral, structural modes).

use nalgebra::{DVector, Vector3};

use crate::dynamics::{
    AttitudeCoordinates, FlightMode, LinearModel, ModeScales, PerturbationRule, VehicleState,
    flight_modes,
};
use crate::dynamics::{StateLayout, StateRole, VehicleDerivative};
use crate::vehicle::partitioned::{
    CouplingGuess, CouplingSettings, ElevonCommand, FlightControls, PartitionedVehicle,
    VehicleError,
};

/// Input names, with units.
pub const INPUT_NAMES: [&str; 3] = [
    "symmetric_elevon_rad",
    "differential_elevon_rad",
    "fuel_equivalence_ratio",
];

/// Output names, with units.
pub const OUTPUT_NAMES: [&str; 11] = [
    "airspeed_m_s",
    "alpha_rad",
    "beta_rad",
    "p_rad_s",
    "q_rad_s",
    "r_rad_s",
    "roll_rad",
    "pitch_rad",
    "yaw_rad",
    "altitude_m",
    "flight_path_rad",
];

/// A linear model and its named modes.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Linearization {
    pub model: LinearModel,
    pub modes: Vec<FlightMode>,
}

fn controls(u: &DVector<f64>) -> FlightControls {
    FlightControls {
        elevon: ElevonCommand {
            symmetric_rad: u[0],
            differential_rad: u[1],
        },
        fuel_equivalence_ratio: u[2],
    }
}

/// The configured flexible vehicle, trimmed for level flight at the config's flight condition
/// and linearized there by `rule`: the vehicle (for a controller design on it), its trim and
/// the linear model.
pub fn linearize_configured(
    loaded: &hsv_core::config::LoadedConfig,
    registry: &hsv_core::registry::Registry,
    rule: &PerturbationRule,
) -> anyhow::Result<(
    PartitionedVehicle,
    super::level_trim::LevelTrim,
    Linearization,
)> {
    let flight = &loaded.config.flight;
    linearize_at(loaded, registry, rule, flight.mach, flight.altitude_m)
}

/// [`linearize_configured`] at Mach `mach` and geometric altitude `altitude_m` instead of the
/// config's flight condition: one point of a linear-model grid.
pub fn linearize_at(
    loaded: &hsv_core::config::LoadedConfig,
    registry: &hsv_core::registry::Registry,
    rule: &PerturbationRule,
    mach: f64,
    altitude_m: f64,
) -> anyhow::Result<(
    PartitionedVehicle,
    super::level_trim::LevelTrim,
    Linearization,
)> {
    let sets = crate::vehicle::assemble(
        loaded,
        registry,
        &crate::vehicle::partitioned::partitioned_needs("the linearization"),
    )?;
    let mut vehicle = PartitionedVehicle::new(
        sets,
        crate::dynamics::GravityModel::default(),
        crate::vehicle::partitioned::CouplingSettings::default(),
    )?;
    vehicle.set_earth(super::level_trim::earth(loaded)?);
    let trim = super::level_trim::trim_level_flight(&mut vehicle, mach, altitude_m)?;
    let lin = linearize(&mut vehicle, &trim.state, &trim.controls, rule)?;
    Ok((vehicle, trim, lin))
}

/// Linearizes `vehicle` around `trim_state` and `trim_controls`.
pub fn linearize(
    vehicle: &mut PartitionedVehicle,
    trim_state: &VehicleState,
    trim_controls: &FlightControls,
    rule: &PerturbationRule,
) -> Result<Linearization, VehicleError> {
    let layout = vehicle.dynamics().layout(AttitudeCoordinates::Euler321);
    let mut x0 = DVector::zeros(layout.len());
    layout.pack(trim_state, &mut x0)?;
    let u0 = DVector::from_vec(vec![
        trim_controls.elevon.symmetric_rad,
        trim_controls.elevon.differential_rad,
        trim_controls.fuel_equivalence_ratio,
    ]);
    let mut state = trim_state.clone();
    let mut derivative = vehicle.dynamics().zero_derivative();
    let speed = trim_state.rigid.air_data(&Vector3::zeros()).0;
    // Every evaluation starts the coupling iteration from the guess converged at the operating
    // point, and converges it tightly: the derivative is then a function of (x, u) alone, so
    // what the physics leaves out (position over a flat Earth) comes out exactly zero instead of
    // the iteration's residual over the step.
    let flight_settings = vehicle.coupling_settings();
    vehicle.set_coupling_settings(LINEARIZATION_COUPLING);
    let converged = vehicle.derivative(trim_state, trim_controls, &mut derivative);
    let guess = vehicle.coupling_guess();
    let model = converged.and_then(|()| {
        build_model(
            vehicle,
            &guess,
            &layout,
            &x0,
            &u0,
            rule,
            &mut state,
            &mut derivative,
        )
    });
    vehicle.set_coupling_settings(flight_settings);
    vehicle.set_coupling_guess(&guess)?;
    let model = model?;
    let scales = match vehicle.dynamics().lowest_natural_frequency_rad_s() {
        Some(w) => ModeScales::new(speed).with_structure(w),
        None => ModeScales::new(speed),
    };
    let modes = flight_modes(&model.a, &layout.roles(), &scales)?;
    Ok(Linearization { model, modes })
}

/// Coupling convergence inside a linearization: the relative root-load change of an iteration
/// below 1e-12 (the flight's 1e-8 leaves a residual that a 1e-6 perturbation would read as a
/// derivative).
pub const LINEARIZATION_COUPLING: CouplingSettings = CouplingSettings {
    tolerance: crate::vehicle::partitioned::LINEARIZATION_TOLERANCE,
    max_iterations: 400,
};

/// The length scale of a position state, m: 1 m steps under the paper's 1 %, a small fraction of
/// the 6.4 km density scale height at 26 km (USSA-1976) that the altitude acts through.
pub const POSITION_SCALE_M: f64 = 100.0;

/// The central-difference model of `vehicle` around `x0`, `u0`, each evaluation from `guess`.
#[allow(clippy::too_many_arguments)]
fn build_model(
    vehicle: &mut PartitionedVehicle,
    guess: &CouplingGuess,
    layout: &StateLayout,
    x0: &DVector<f64>,
    u0: &DVector<f64>,
    rule: &PerturbationRule,
    state: &mut VehicleState,
    derivative: &mut VehicleDerivative,
) -> Result<LinearModel, VehicleError> {
    let mut out_state = state.clone();
    let f = |x: &DVector<f64>, u: &DVector<f64>, dx: &mut DVector<f64>| {
        vehicle.set_coupling_guess(guess)?;
        layout.unpack(x, state)?;
        vehicle.derivative(state, &controls(u), derivative)?;
        layout.pack_derivative(x, derivative, dx)?;
        Ok::<(), VehicleError>(())
    };
    let g = |x: &DVector<f64>, _u: &DVector<f64>, y: &mut DVector<f64>| {
        layout.unpack(x, &mut out_state)?;
        let rigid = &out_state.rigid;
        let (airspeed, alpha, beta) = rigid.air_data(&Vector3::zeros());
        let (roll, pitch, yaw) = rigid.euler_angles();
        let w = rigid.angular_velocity_body_rad_s;
        let v_ned = rigid.velocity_ned_m_s();
        let flight_path = (-v_ned.z / v_ned.norm()).clamp(-1.0, 1.0).asin();
        let values = [
            airspeed,
            alpha,
            beta,
            w.x,
            w.y,
            w.z,
            roll,
            pitch,
            yaw,
            rigid.altitude_m(),
            flight_path,
        ];
        for (out, v) in y.iter_mut().zip(values) {
            *out = v;
        }
        Ok::<(), VehicleError>(())
    };
    // The paper's rule (a fraction of the operating value) perturbs the altitude by 260 m at
    // 26 km; a position's scale is not its value, so positions take the rule's fraction of
    // POSITION_SCALE_M instead.
    let mut x_steps = rule.steps(x0)?;
    for (step, role) in x_steps.iter_mut().zip(layout.roles()) {
        if matches!(role, StateRole::Position | StateRole::Altitude) {
            *step = (rule.relative * POSITION_SCALE_M).max(rule.absolute);
        }
    }
    let u_steps = rule.steps(u0)?;
    LinearModel::build_with_steps(
        f,
        g,
        x0,
        u0,
        (&x_steps, &u_steps),
        layout.names(),
        INPUT_NAMES.iter().map(|s| s.to_string()).collect(),
        OUTPUT_NAMES.iter().map(|s| s.to_string()).collect(),
    )
}
