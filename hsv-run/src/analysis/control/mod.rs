//! The control loop: the sample-and-hold loop the time simulation runs a controller in (the
//! measured outputs it samples, the command held between samples, the actuator positions across
//! each step, the state a restart file keeps), built from `[control]` in [`build`].
//!
//! Around it: the built-in controllers (`schedule`, `lqr`, `tracking`), the design models they
//! are built from (rigid longitudinal and lateral models residualized from `linearize`), the
//! actuators (position and rate limits, first-order lag) and the sensors.

pub mod actuators;
pub mod build;
pub mod design;
pub mod lqr;
pub mod schedule;
pub mod sensors;
pub mod tracking;

use hsv_core::control::{ControlCommands, Controller, MeasuredOutputs};
use nalgebra::Vector3;

use crate::dynamics::VehicleState;
use crate::vehicle::partitioned::{ElevonCommand, FlightControls, VehicleError};

pub use actuators::{ActuatorSettings, Actuators, Saturation};
pub use build::{
    DesignFrom, DesignRecord, build_control_loop, control_settings, loop_dynamics, sensor_settings,
};
pub use sensors::{SensorSettings, Sensors};

/// The measured outputs of `state` with the actuators at `positions`, at time `time_s`, in a
/// gust `gust_body_m_s` at the centre of mass (body axes): air data relative to the air.
pub fn measure(
    state: &VehicleState,
    positions: &ControlCommands,
    time_s: f64,
    gust_body_m_s: &Vector3<f64>,
) -> MeasuredOutputs {
    let rigid = &state.rigid;
    let (airspeed, alpha, beta) = rigid.air_data(&(rigid.attitude * gust_body_m_s));
    let (roll, pitch, yaw) = rigid.euler_angles();
    let w = rigid.angular_velocity_body_rad_s;
    let v_ned = rigid.velocity_ned_m_s();
    let speed = v_ned.norm();
    let altitude = rigid.altitude_m();
    let mach = hsv_core::atmosphere::us_standard_atmosphere_1976(altitude)
        .map_or(f64::NAN, |atm| airspeed / atm.speed_of_sound_m_s);
    MeasuredOutputs {
        time_s,
        p_rad_s: w.x,
        q_rad_s: w.y,
        r_rad_s: w.z,
        alpha_rad: alpha,
        beta_rad: beta,
        airspeed_m_s: airspeed,
        mach,
        altitude_m: altitude,
        roll_rad: roll,
        pitch_rad: pitch,
        yaw_rad: yaw,
        flight_path_rad: if speed > 0.0 {
            (-v_ned.z / speed).clamp(-1.0, 1.0).asin()
        } else {
            0.0
        },
        symmetric_elevon_rad: positions.symmetric_elevon_rad,
        differential_elevon_rad: positions.differential_elevon_rad,
        fuel_equivalence_ratio: positions.fuel_equivalence_ratio,
    }
}

/// The vehicle's controls from commands (or actuator positions).
pub fn flight_controls(c: &ControlCommands) -> FlightControls {
    FlightControls {
        elevon: ElevonCommand {
            symmetric_rad: c.symmetric_elevon_rad,
            differential_rad: c.differential_elevon_rad,
        },
        fuel_equivalence_ratio: c.fuel_equivalence_ratio,
    }
}

/// Commands from the vehicle's controls.
pub fn commands_of(c: &FlightControls) -> ControlCommands {
    ControlCommands {
        symmetric_elevon_rad: c.elevon.symmetric_rad,
        differential_elevon_rad: c.elevon.differential_rad,
        fuel_equivalence_ratio: c.fuel_equivalence_ratio,
    }
}

/// Everything the control loop remembers between steps: simulation state, written into restart
/// files.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct ControlState {
    /// The controller's own state ([`Controller::state_len`] values).
    pub controller: Vec<f64>,
    /// The step at which the controller samples next.
    pub next_sample_step: usize,
    /// The command held since the last sample.
    pub command: ControlCommands,
    /// Actuator positions at the start and the end of the current step.
    pub position_start: ControlCommands,
    pub position_end: ControlCommands,
    /// Which limits the actuators met over the current step.
    pub saturation: Saturation,
    /// The true outputs of the last steps, oldest first: the sensors' delay line (empty
    /// without a delay).
    #[serde(default)]
    pub sensor_history: std::collections::VecDeque<MeasuredOutputs>,
}

/// A controller, its actuators and their state, sampled in the time loop.
pub struct ControlLoop {
    controller: Box<dyn Controller>,
    actuators: Option<Actuators>,
    /// What stands between the vehicle and the controller (None: the true outputs).
    sensors: Option<Sensors>,
    /// Steps between samples (None: a law of time, evaluated at every instant).
    sample_steps: Option<usize>,
    pub state: ControlState,
    /// The start and length of the current step, s.
    step_start_s: f64,
    step_dt_s: f64,
}

impl ControlLoop {
    /// The loop at trim: actuators at the trim commands, the controller at its initial state.
    pub fn new(
        controller: Box<dyn Controller>,
        actuators: Option<Actuators>,
        trim: &FlightControls,
        dt_s: f64,
    ) -> Result<Self, VehicleError> {
        let sample_steps = match controller.sample_interval_s() {
            None => {
                if controller.state_len() != 0 {
                    return Err(VehicleError::Input(format!(
                        "controller `{}` keeps state but names no sample interval",
                        controller.name()
                    )));
                }
                None
            }
            Some(interval) if interval.is_finite() && interval > 0.0 => {
                Some(((interval / dt_s).round() as usize).max(1))
            }
            Some(interval) => {
                return Err(VehicleError::Input(format!(
                    "controller `{}`: sample interval {interval} s must be finite and > 0",
                    controller.name()
                )));
            }
        };
        let trim = commands_of(trim);
        let mut state = ControlState {
            controller: vec![0.0; controller.state_len()],
            next_sample_step: 0,
            command: trim,
            position_start: trim,
            position_end: trim,
            saturation: Saturation::default(),
            sensor_history: std::collections::VecDeque::new(),
        };
        controller.initial_state(&mut state.controller);
        Ok(Self {
            controller,
            actuators,
            sensors: None,
            sample_steps,
            state,
            step_start_s: 0.0,
            step_dt_s: dt_s,
        })
    }

    /// The open-loop `schedule` of `inputs` around `trim`, without actuators (the run the
    /// input tables always flew).
    pub fn schedule(
        inputs: crate::analysis::inputs::Inputs,
        trim: &FlightControls,
        dt_s: f64,
    ) -> Result<Self, VehicleError> {
        Self::new(
            Box::new(schedule::Schedule::new(inputs, commands_of(trim))),
            None,
            trim,
            dt_s,
        )
    }

    /// The host program's commands (Python, an FMU): [`ControlState::command`], set by the
    /// host between steps and held over each step, from the trim commands at the start.
    pub fn external(
        actuators: Option<Actuators>,
        trim: &FlightControls,
        dt_s: f64,
    ) -> Result<Self, VehicleError> {
        Self::new(Box::new(HostCommands), actuators, trim, dt_s)
    }

    /// Puts `sensors` between the vehicle and the controller from the next sample on.
    pub fn set_sensors(&mut self, sensors: Option<Sensors>) {
        if let Some(s) = &sensors {
            // The delay line's room, taken here and not in the time loop.
            self.state.sensor_history.reserve(s.delay_steps + 1);
        }
        self.sensors = sensors;
    }

    pub fn controller(&self) -> &dyn Controller {
        self.controller.as_ref()
    }

    /// True when the commands pass through actuators (lags and limits) before they act.
    pub fn has_actuators(&self) -> bool {
        self.actuators.is_some()
    }

    /// Continues from a restart file's control state.
    pub fn restore(&mut self, state: ControlState) -> Result<(), VehicleError> {
        if state.controller.len() != self.controller.state_len() {
            return Err(VehicleError::Input(format!(
                "the restart file holds {} values of controller state, `{}` keeps {}",
                state.controller.len(),
                self.controller.name(),
                self.controller.state_len()
            )));
        }
        self.state = state;
        Ok(())
    }

    fn model_error(&self, e: hsv_core::ModelError) -> VehicleError {
        VehicleError::Input(format!("controller `{}`: {e}", self.controller.name()))
    }

    /// The start of step `step` at `t` (length `dt`) from the accepted `vehicle` state in the
    /// gust `gust_body_m_s` at its centre of mass: the controller samples if due, the actuators
    /// move towards the held command.
    pub fn begin_step(
        &mut self,
        step: usize,
        t: f64,
        dt: f64,
        vehicle: &VehicleState,
        gust_body_m_s: &Vector3<f64>,
    ) -> Result<(), VehicleError> {
        self.step_start_s = t;
        self.step_dt_s = dt;
        self.state.position_start = self.state.position_end;
        // A law of time without actuators is evaluated at each stage instead (`controls_at`);
        // with actuators it drives them from the step's start. A sampled law runs when due.
        let due = match self.sample_steps {
            None => self.actuators.is_some(),
            Some(every) => {
                let due = step >= self.state.next_sample_step;
                if due {
                    self.state.next_sample_step = step + every;
                }
                due
            }
        };
        let delay = self.sensors.as_ref().map_or(0, |s| s.delay_steps);
        if delay > 0 {
            // The delay line holds the true outputs of this step and the `delay` before it.
            let history = &mut self.state.sensor_history;
            history.push_back(measure(
                vehicle,
                &self.state.position_start,
                t,
                gust_body_m_s,
            ));
            while history.len() > delay + 1 {
                history.pop_front();
            }
        }
        if due {
            let truth = match self.state.sensor_history.front() {
                Some(oldest) if delay > 0 => *oldest,
                _ => measure(vehicle, &self.state.position_start, t, gust_body_m_s),
            };
            let outputs = match &self.sensors {
                Some(s) => s.read(step, t, &truth),
                None => truth,
            };
            self.controller
                .update(
                    &outputs,
                    &mut self.state.controller,
                    &mut self.state.command,
                )
                .map_err(|e| self.model_error(e))?;
        }
        let command = self.state.command;
        if !command.values().iter().all(|v| v.is_finite()) {
            return Err(VehicleError::Input(format!(
                "controller `{}` commanded non-finite values at t = {t} s: {command:?}",
                self.controller.name()
            )));
        }
        match &self.actuators {
            Some(act) => {
                let (end, saturation) = act.advance(&self.state.position_start, &command, dt);
                self.state.position_end = end;
                self.state.saturation = saturation;
            }
            None => {
                self.state.position_end = command;
                self.state.saturation = Saturation::default();
            }
        }
        Ok(())
    }

    /// The controls at `time` inside the current step: a law of time without actuators at that
    /// instant (it reads the time alone: [`Controller::sample_interval_s`]), else the actuator
    /// positions, linear across the step.
    pub fn controls_at(&mut self, time: f64) -> Result<FlightControls, VehicleError> {
        if self.sample_steps.is_none() && self.actuators.is_none() {
            let outputs = MeasuredOutputs {
                time_s: time,
                ..MeasuredOutputs::default()
            };
            let mut command = ControlCommands::default();
            self.controller
                .update(&outputs, &mut [], &mut command)
                .map_err(|e| self.model_error(e))?;
            return Ok(flight_controls(&command));
        }
        let w = if self.step_dt_s > 0.0 {
            ((time - self.step_start_s) / self.step_dt_s).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let (a, b) = (
            self.state.position_start.values(),
            self.state.position_end.values(),
        );
        Ok(flight_controls(&ControlCommands::from_values(
            std::array::from_fn(|i| a[i] * (1.0 - w) + b[i] * w),
        )))
    }
}

/// The name a flight under the host's commands reports as its controller.
pub const EXTERNAL_CONTROLLER: &str = "external";

/// The host program's commands: sampled at every step, it leaves the held command as the host
/// set it (not registered: a flight built without a controller uses it).
struct HostCommands;

impl Controller for HostCommands {
    fn name(&self) -> &str {
        EXTERNAL_CONTROLLER
    }

    /// Every step: the loop rounds any interval shorter than a step up to one step.
    fn sample_interval_s(&self) -> Option<f64> {
        Some(f64::MIN_POSITIVE)
    }

    fn update(
        &mut self,
        _outputs: &MeasuredOutputs,
        _state: &mut [f64],
        _commands: &mut ControlCommands,
    ) -> Result<(), hsv_core::ModelError> {
        Ok(())
    }
}

/// What a history sample records of the loop.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ControlRecord {
    /// The controller's command (held since its last sample).
    pub command: ControlCommands,
    /// The actuator positions the vehicle flies with.
    pub position: ControlCommands,
    pub saturation: Saturation,
}

impl ControlLoop {
    /// The loop at `time`, the end of the last step (or the start of the run).
    pub fn record(&mut self, time: f64) -> Result<ControlRecord, VehicleError> {
        if self.sample_steps.is_none() && self.actuators.is_none() {
            let c = commands_of(&self.controls_at(time)?);
            return Ok(ControlRecord {
                command: c,
                position: c,
                saturation: Saturation::default(),
            });
        }
        Ok(ControlRecord {
            command: self.state.command,
            position: self.state.position_end,
            saturation: self.state.saturation,
        })
    }
}
