//! The time march: the partitioned vehicle simulated from trim (paper §IV.C) under its control
//! loop, the coupled state derivative marched by fourth-order (exponential) Runge-Kutta at
//! the aeroelastic step (paper Table 3: 1 ms) with the main body region evaluated at the vehicle's
//! [`RegionLoadRate`](crate::vehicle::region_rate::RegionLoadRate), and a sample of every recorded
//! quantity handed to an observer.
//! The loop allocates nothing per step. The control input time tables are in
//! [`super::inputs`].

use nalgebra::DVector;

use crate::analysis::control::ControlLoop;
use crate::dynamics::{AttitudeCoordinates, ExponentialRk4, VehicleState};
use crate::vehicle::partitioned::{OpenStep, PartitionedVehicle, VehicleError};
use crate::vehicle::staggered::StaggeredInterface;

pub use super::inputs::{InputError, InputTable, Inputs};

/// One recorded instant (SI, angles in degrees as named).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct Sample {
    pub time_s: f64,
    pub north_m: f64,
    pub altitude_m: f64,
    pub u_m_s: f64,
    pub v_m_s: f64,
    pub w_m_s: f64,
    pub airspeed_m_s: f64,
    pub alpha_deg: f64,
    pub beta_deg: f64,
    pub roll_deg: f64,
    pub pitch_deg: f64,
    pub yaw_deg: f64,
    pub p_deg_s: f64,
    pub q_deg_s: f64,
    pub r_deg_s: f64,
    pub elevon_deg: f64,
    pub fuel_equivalence_ratio: f64,
    /// Differential elevon actuator position, deg.
    pub differential_elevon_deg: f64,
    /// The controller's commands (elevon_deg and fuel_equivalence_ratio above are the actuator
    /// positions the vehicle flies with; equal without actuators).
    pub command_elevon_deg: f64,
    pub command_differential_elevon_deg: f64,
    pub command_fuel_equivalence_ratio: f64,
    /// Which actuator limits bit over the step that ended at this sample.
    pub elevon_position_saturated: bool,
    pub elevon_rate_saturated: bool,
    pub phi_position_saturated: bool,
    pub phi_rate_saturated: bool,
    pub coupling_iterations: usize,
    pub coupling_residual: f64,
    /// Lowest, highest and mean structure temperature over the heated surfaces, K (NaN when no
    /// surface heats).
    pub surface_min_temperature_k: f64,
    pub surface_max_temperature_k: f64,
    pub surface_mean_temperature_k: f64,
    /// The gust velocity at the centre of mass (`[disturbances]`), body axes, m/s; α, β and
    /// airspeed above are relative to the air moving with it.
    pub gust_u_m_s: f64,
    pub gust_v_m_s: f64,
    pub gust_w_m_s: f64,
}

impl Sample {
    /// The recorded quantities in `history.csv` order (units in the names; the saturation flags
    /// as 0 or 1): the columns of the history and of the Python `Simulation`'s outputs.
    pub const COLUMNS: [&'static str; 33] = [
        "time_s",
        "north_m",
        "altitude_m",
        "u_m_s",
        "v_m_s",
        "w_m_s",
        "airspeed_m_s",
        "alpha_deg",
        "beta_deg",
        "roll_deg",
        "pitch_deg",
        "yaw_deg",
        "p_deg_s",
        "q_deg_s",
        "r_deg_s",
        "elevon_deg",
        "fuel_equivalence_ratio",
        "coupling_iterations",
        "coupling_residual",
        "differential_elevon_deg",
        "command_elevon_deg",
        "command_differential_elevon_deg",
        "command_fuel_equivalence_ratio",
        "elevon_position_saturated",
        "elevon_rate_saturated",
        "phi_position_saturated",
        "phi_rate_saturated",
        "surface_min_temperature_k",
        "surface_max_temperature_k",
        "surface_mean_temperature_k",
        "gust_u_m_s",
        "gust_v_m_s",
        "gust_w_m_s",
    ];

    /// The values in the order of [`Self::COLUMNS`].
    pub fn values(&self) -> [f64; 33] {
        [
            self.time_s,
            self.north_m,
            self.altitude_m,
            self.u_m_s,
            self.v_m_s,
            self.w_m_s,
            self.airspeed_m_s,
            self.alpha_deg,
            self.beta_deg,
            self.roll_deg,
            self.pitch_deg,
            self.yaw_deg,
            self.p_deg_s,
            self.q_deg_s,
            self.r_deg_s,
            self.elevon_deg,
            self.fuel_equivalence_ratio,
            self.coupling_iterations as f64,
            self.coupling_residual,
            self.differential_elevon_deg,
            self.command_elevon_deg,
            self.command_differential_elevon_deg,
            self.command_fuel_equivalence_ratio,
            f64::from(u8::from(self.elevon_position_saturated)),
            f64::from(u8::from(self.elevon_rate_saturated)),
            f64::from(u8::from(self.phi_position_saturated)),
            f64::from(u8::from(self.phi_rate_saturated)),
            self.surface_min_temperature_k,
            self.surface_max_temperature_k,
            self.surface_mean_temperature_k,
            self.gust_u_m_s,
            self.gust_v_m_s,
            self.gust_w_m_s,
        ]
    }
}

/// How the state is marched over one aeroelastic step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Integrator {
    /// Classical fourth-order Runge-Kutta on the whole state: stable for ω Δt < 2.83, so the
    /// sample surface's 297 Hz Ritz vector needs Δt ≤ 1.5 ms (a 5 % surface's 525 Hz, 0.86 ms).
    Rk4,
    /// Fourth-order exponential time differencing with the lifting surfaces' structural
    /// equations integrated exactly ([`ExponentialRk4`]): stable at the paper's 1 ms.
    #[default]
    ExponentialRk4,
}

impl Integrator {
    /// The `[simulation] integrator` spellings.
    pub const NAMES: [&'static str; 2] = ["exponential-rk4", "rk4"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "exponential-rk4" => Some(Self::ExponentialRk4),
            "rk4" => Some(Self::Rk4),
            _ => None,
        }
    }

    /// The `[simulation] integrator` spelling of this method.
    pub fn name(&self) -> &'static str {
        match self {
            Self::ExponentialRk4 => Self::NAMES[0],
            Self::Rk4 => Self::NAMES[1],
        }
    }
}

/// Step size and length of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// Aeroelastic step, s (paper Table 3: 1 ms).
    pub dt_s: f64,
    pub integrator: Integrator,
    pub duration_s: f64,
    /// Steps between recorded samples.
    pub record_every: usize,
    /// The step to start from: 0, or where a restart file left off.
    pub start_step: usize,
}

/// Why a run stopped.
#[derive(Debug, thiserror::Error)]
#[error("at t = {time_s:.4} s: {source}")]
pub struct SimulationError {
    pub time_s: f64,
    #[source]
    pub source: VehicleError,
}

/// Marches `state` from t = 0 under `inputs` around the trim controls, handing each recorded
/// sample, the state and the vehicle (for snapshots) to `observe`, which may stop the run by
/// returning false.
///
/// The loop runs on a rayon worker thread, so the regions' side-by-side evaluation inside each
/// stage is a cheap `join` on the worker's own deque: called from outside the pool, every stage
/// would hand its work to the pool and sleep on a latch (12 % of the run's time on one core).
pub fn simulate(
    vehicle: &mut PartitionedVehicle,
    state: &mut VehicleState,
    control: &mut ControlLoop,
    settings: &RunSettings,
    observe: impl FnMut(&Sample, &VehicleState, &mut PartitionedVehicle) -> bool + Send,
) -> Result<usize, SimulationError> {
    rayon::scope(|_| march(vehicle, state, control, settings, observe))
}

/// The time loop of [`simulate`], on the calling thread.
fn march(
    vehicle: &mut PartitionedVehicle,
    state: &mut VehicleState,
    control: &mut ControlLoop,
    settings: &RunSettings,
    mut observe: impl FnMut(&Sample, &VehicleState, &mut PartitionedVehicle) -> bool,
) -> Result<usize, SimulationError> {
    let wrap = |time_s: f64| move |source: VehicleError| SimulationError { time_s, source };
    let mut stepper = Stepper::new(vehicle, state, settings.integrator).map_err(wrap(0.0))?;
    // The last step is shortened so the run ends exactly at the duration.
    let plan = crate::steps::time_steps(settings.duration_s, settings.dt_s)
        .map_err(|e| wrap(0.0)(VehicleError::Input(e.to_string())))?;
    let steps = plan.steps;
    let t0 = plan.start_s(settings.start_step.min(steps));
    let first = record_sample(&mut *vehicle, &mut *control, state, t0).map_err(wrap(t0))?;
    if !observe(&first, state, vehicle) {
        return Ok(0);
    }
    if settings.start_step == 0 {
        vehicle.forget_region_loads().map_err(wrap(t0))?;
    }
    for k in settings.start_step.min(steps)..steps {
        let t = plan.start_s(k);
        stepper
            .step(vehicle, state, control, k, t, plan.dt_of(k), plan.end_s(k))
            .map_err(wrap(t))?;
        let done = k + 1;
        if (done % settings.record_every.max(1) == 0 || done == steps) && {
            let sample = record_sample(&mut *vehicle, &mut *control, state, plan.end_s(k))
                .map_err(wrap(t))?;
            !observe(&sample, state, vehicle)
        } {
            return Ok(done);
        }
    }
    Ok(steps)
}

/// One aeroelastic step at a time: the packed state, the integrator and the scratch the state
/// derivative writes into, so a host that commands each step (Python, an FMU) marches exactly
/// as [`simulate`] does. Built at the state it starts from; the loop allocates nothing.
pub struct Stepper {
    layout: crate::dynamics::StateLayout,
    x: DVector<f64>,
    rk4: ExponentialRk4,
    scratch: VehicleState,
    derivative: crate::dynamics::VehicleDerivative,
    /// The staggered scheme's interface buffers and the step's start (None: implicit).
    staggered: Option<(StaggeredInterface, DVector<f64>, Vec<f64>)>,
}

impl Stepper {
    /// The stepper at `state` with `integrator`.
    pub fn new(
        vehicle: &PartitionedVehicle,
        state: &VehicleState,
        integrator: Integrator,
    ) -> Result<Self, VehicleError> {
        let layout = vehicle.dynamics().layout(AttitudeCoordinates::Quaternion);
        let mut x = DVector::zeros(layout.len());
        layout.pack(state, &mut x)?;
        // Classical RK4 is the exponential method without blocks (to rounding).
        let blocks = match integrator {
            Integrator::Rk4 => Vec::new(),
            Integrator::ExponentialRk4 => vehicle.dynamics().surface_linear_blocks(&layout),
        };
        let rk4 = ExponentialRk4::new(layout.len(), blocks)?;
        let staggered = vehicle.staggered().map(|settings| {
            let n = vehicle.interface_len();
            (
                StaggeredInterface::new(settings, n, state, vehicle.new_acceleration()),
                x.clone(),
                vec![0.0; n],
            )
        });
        Ok(Self {
            layout,
            x,
            rk4,
            scratch: state.clone(),
            derivative: vehicle.dynamics().zero_derivative(),
            staggered,
        })
    }

    /// Step `k` from `t` to `end` (length `dt`): the controller samples and the actuators move,
    /// the body region is evaluated at the accepted state, the coupled state is marched, and
    /// the accepted step is committed (models with memory, surface heating); `state` ends at
    /// `end`.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        vehicle: &mut PartitionedVehicle,
        state: &mut VehicleState,
        control: &mut ControlLoop,
        k: usize,
        t: f64,
        dt: f64,
        end: f64,
    ) -> Result<(), VehicleError> {
        // The controller samples (at its rate) and the actuators move over the step.
        control.begin_step(k, t, dt, state, &vehicle.gust_body_m_s())?;
        // The body region at the accepted state, read by the step's stages (its rate).
        let start_controls = control.controls_at(t)?;
        let open = vehicle.begin_step(state, &start_controls, t)?;
        let Self {
            layout,
            x,
            rk4,
            scratch,
            derivative,
            staggered,
        } = self;
        if let Some((interface, start, last)) = staggered {
            staggered_step(
                vehicle, &open, control, layout, rk4, scratch, derivative, interface, start, last,
                x, t, dt,
            )?;
        } else {
            let mut f = |time: f64, x: &DVector<f64>, dx: &mut DVector<f64>| {
                layout.unpack(x, scratch)?;
                let controls = control.controls_at(time)?;
                vehicle.stage_derivative(&open, time, scratch, &controls, derivative)?;
                layout.pack_derivative(x, derivative, dx)?;
                Ok::<(), VehicleError>(())
            };
            rk4.step(&mut f, t, dt, x)?;
            layout.normalize_attitude(x)?;
        }
        layout.unpack(x, state)?;
        // The accepted step: models with memory commit their history, the surfaces heat.
        vehicle.commit_step(open, state, end)
    }
}

/// One step of the staggered scheme (module [`crate::vehicle::staggered`]): the step marched
/// from `start` with the interface of the previous sub-iteration at each stage, sub-iterated
/// until the interface displacements at the step's end settle; `x` ends at the accepted step.
#[allow(clippy::too_many_arguments)]
fn staggered_step(
    vehicle: &mut PartitionedVehicle,
    open: &OpenStep,
    control: &mut ControlLoop,
    layout: &crate::dynamics::StateLayout,
    rk4: &mut ExponentialRk4,
    scratch: &mut VehicleState,
    derivative: &mut crate::dynamics::VehicleDerivative,
    interface: &mut StaggeredInterface,
    start: &mut DVector<f64>,
    last: &mut [f64],
    x: &mut DVector<f64>,
    t: f64,
    dt: f64,
) -> Result<(), VehicleError> {
    let settings = interface.settings;
    start.copy_from(x);
    vehicle.interface_guess(last);
    interface.begin(last);
    let mut residual = f64::INFINITY;
    let mut sub = 0;
    while sub < settings.max_sub_iterations.max(1) {
        sub += 1;
        x.copy_from(start);
        let mut stage = 0;
        let mut f = |time: f64, x: &DVector<f64>, dx: &mut DVector<f64>| {
            layout.unpack(x, scratch)?;
            let controls = control.controls_at(time)?;
            let (guess, produced) = interface.stage(stage).ok_or_else(|| {
                VehicleError::Input(format!(
                    "the staggered scheme exchanges at {} stages; the integrator asked for more",
                    crate::vehicle::staggered::STAGES
                ))
            })?;
            vehicle.staggered_derivative(
                (open, time),
                scratch,
                &controls,
                guess,
                produced,
                derivative,
            )?;
            layout.pack_derivative(x, derivative, dx)?;
            stage += 1;
            Ok::<(), VehicleError>(())
        };
        rk4.step(&mut f, t, dt, x)?;
        layout.normalize_attitude(x)?;
        interface.end.swap(0, 1);
        layout.unpack(x, &mut interface.end[0])?;
        if sub > 1 {
            residual =
                vehicle.interface_displacement_change_m(&interface.end[0], &interface.end[1]);
            if residual <= settings.residual_tolerance_m {
                break;
            }
        }
        interface.relax();
    }
    vehicle.set_staggered_report(sub, residual);
    let settled = residual <= settings.residual_tolerance_m;
    if !settled && settings.max_sub_iterations > 1 {
        return Err(VehicleError::Coupling {
            iterations: sub,
            interfaces: "main body and lifting surfaces (staggered step)".to_owned(),
            residuals: vec![residual],
            tolerance: settings.residual_tolerance_m,
        });
    }
    vehicle.set_interface_guess(interface.last_produced());
    Ok(())
}

/// The sample of `state` at `t`: flight state, the control loop's record, coupling and
/// surface temperatures.
pub fn record_sample(
    vehicle: &mut PartitionedVehicle,
    control: &mut ControlLoop,
    state: &VehicleState,
    t: f64,
) -> Result<Sample, VehicleError> {
    let (lo, hi, mean) = vehicle
        .heated_surface_range()
        .map_or((f64::NAN, f64::NAN, f64::NAN), |t| {
            (t.min_k, t.max_k, t.mean_k)
        });
    let rigid = &state.rigid;
    let gust = vehicle.gust_body_m_s();
    let (airspeed, alpha, beta) = rigid.air_data(&(rigid.attitude * gust));
    let (roll, pitch, yaw) = rigid.euler_angles();
    let c = control.record(t)?;
    let w = rigid.angular_velocity_body_rad_s;
    let v = rigid.velocity_body_m_s;
    let report = vehicle.coupling_report();
    Ok(Sample {
        time_s: t,
        north_m: rigid.position_ned_m.x,
        altitude_m: rigid.altitude_m(),
        u_m_s: v.x,
        v_m_s: v.y,
        w_m_s: v.z,
        airspeed_m_s: airspeed,
        alpha_deg: alpha.to_degrees(),
        beta_deg: beta.to_degrees(),
        roll_deg: roll.to_degrees(),
        pitch_deg: pitch.to_degrees(),
        yaw_deg: yaw.to_degrees(),
        p_deg_s: w.x.to_degrees(),
        q_deg_s: w.y.to_degrees(),
        r_deg_s: w.z.to_degrees(),
        elevon_deg: c.position.symmetric_elevon_rad.to_degrees(),
        fuel_equivalence_ratio: c.position.fuel_equivalence_ratio,
        differential_elevon_deg: c.position.differential_elevon_rad.to_degrees(),
        command_elevon_deg: c.command.symmetric_elevon_rad.to_degrees(),
        command_differential_elevon_deg: c.command.differential_elevon_rad.to_degrees(),
        command_fuel_equivalence_ratio: c.command.fuel_equivalence_ratio,
        elevon_position_saturated: c.saturation.elevon_position,
        elevon_rate_saturated: c.saturation.elevon_rate,
        phi_position_saturated: c.saturation.phi_position,
        phi_rate_saturated: c.saturation.phi_rate,
        coupling_iterations: report.iterations,
        coupling_residual: report.residual,
        surface_min_temperature_k: lo,
        surface_max_temperature_k: hi,
        surface_mean_temperature_k: mean,
        gust_u_m_s: gust.x,
        gust_v_m_s: gust.y,
        gust_w_m_s: gust.z,
    })
}
