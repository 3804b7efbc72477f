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
use crate::vehicle::partitioned::{
    ElevonCommand, FlightControls, PartitionedVehicle, VehicleError,
};

/// Input names, with units.
pub const INPUT_NAMES: [&str; 3] = [
    "symmetric_elevon_rad",
    "differential_elevon_rad",
    "fuel_equivalence_ratio",
];

/// Output names, with units.
pub const OUTPUT_NAMES: [&str; 10] = [
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
) -> anyhow::Result<(PartitionedVehicle, super::flight::LevelTrim, Linearization)> {
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
    let trim = super::flight::trim_level_flight(
        &mut vehicle,
        loaded.config.flight.mach,
        loaded.config.flight.altitude_m,
    )?;
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
    let f = |x: &DVector<f64>, u: &DVector<f64>, dx: &mut DVector<f64>| {
        layout.unpack(x, &mut state)?;
        vehicle.derivative(&state, &controls(u), &mut derivative)?;
        layout.pack_derivative(x, &derivative, dx)?;
        Ok::<(), VehicleError>(())
    };
    let mut out_state = trim_state.clone();
    let g = |x: &DVector<f64>, _u: &DVector<f64>, y: &mut DVector<f64>| {
        layout.unpack(x, &mut out_state)?;
        let rigid = &out_state.rigid;
        let (airspeed, alpha, beta) = rigid.air_data(&Vector3::zeros());
        let (roll, pitch, yaw) = rigid.euler_angles();
        let w = rigid.angular_velocity_body_rad_s;
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
        ];
        for (out, v) in y.iter_mut().zip(values) {
            *out = v;
        }
        Ok::<(), VehicleError>(())
    };
    let model = LinearModel::build(
        f,
        g,
        &x0,
        &u0,
        rule,
        layout.names(),
        INPUT_NAMES.iter().map(|s| s.to_string()).collect(),
        OUTPUT_NAMES.iter().map(|s| s.to_string()).collect(),
    )?;
    let scales = match vehicle.dynamics().lowest_natural_frequency_rad_s() {
        Some(w) => ModeScales::new(speed).with_structure(w),
        None => ModeScales::new(speed),
    };
    let modes = flight_modes(&model.a, &layout.roles(), &scales)?;
    Ok(Linearization { model, modes })
}
