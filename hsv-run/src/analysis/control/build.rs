//! The control loop's building from `[control]`: the controller by name, its actuators and
//! sensors, and the design model it is built from (the trimmed vehicle linearized on first
//! request, a linear model already computed, or the design a restart file saved).
//!
//! `[control]` of the config: `controller = "schedule"` (default: the `[simulation.inputs]`
//! table, flown exactly as before) or any registered controller (`hsv-run models`, role
//! `control`), `[control.actuators]` ([`super::actuators`]) and `[control.sensors]`
//! ([`super::sensors`]). A controller's own settings are `[models.<name>]`.

use hsv_core::control::{ControlCommands, MeasuredOutputs};
use nalgebra::Vector3;

use super::actuators::{ActuatorSettings, Actuators};
use super::sensors::{SensorSettings, Sensors};
use super::{ControlLoop, commands_of, design, measure};
use crate::dynamics::VehicleState;
use crate::vehicle::partitioned::FlightControls;

/// `[control]` of the config.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ControlTable {
    controller: Option<String>,
    actuators: Option<ActuatorSettings>,
    sensors: Option<SensorSettings>,
    /// Read by the controller that tracks them (`tracking`).
    commands: Option<toml::Table>,
}

/// The sensors of `[control.sensors]` for a loop of step `dt_s` (None without the table).
pub fn sensor_settings(
    loaded: &hsv_core::config::LoadedConfig,
    dt_s: f64,
) -> anyhow::Result<Option<Sensors>> {
    let table: ControlTable =
        hsv_core::config::parse_table(&loaded.config.control, &loaded.file, "control")?;
    table
        .sensors
        .map(|s| Sensors::new(&s, dt_s, "control.sensors"))
        .transpose()
        .map_err(|e| anyhow::anyhow!("{}: {e}", loaded.file))
}

/// The actuator lags and loop delay of controller `name`'s loop as the config sets them, for
/// the linear closed loop (`linearize --controller`).
pub fn loop_dynamics(
    loaded: &hsv_core::config::LoadedConfig,
    name: &str,
    controller: &dyn hsv_core::control::Controller,
) -> anyhow::Result<design::LoopDynamics> {
    let (_, actuators) = control_settings(loaded, Some(name))?;
    let table: ControlTable =
        hsv_core::config::parse_table(&loaded.config.control, &loaded.file, "control")?;
    let sensor_delay_s = table.sensors.map_or(0.0, |s| s.delay_s);
    let hold_delay_s = 0.5 * controller.sample_interval_s().unwrap_or(0.0);
    Ok(match actuators {
        Some(a) => design::LoopDynamics {
            elevon_time_constant_s: a.settings().elevon_time_constant_s,
            phi_time_constant_s: a.settings().phi_time_constant_s,
            delay_s: hold_delay_s + sensor_delay_s,
        },
        None => design::LoopDynamics {
            delay_s: hold_delay_s + sensor_delay_s,
            ..Default::default()
        },
    })
}

/// The design data a run's controller was built from: saved in restart files so a resumed run
/// rebuilds the same controller bit for bit.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct DesignRecord {
    pub trim_outputs: MeasuredOutputs,
    pub trim_commands: ControlCommands,
    pub longitudinal: Option<hsv_core::control::LinearDesignModel>,
    pub lateral: Option<hsv_core::control::LinearDesignModel>,
}

/// What a controller's design model comes from.
pub enum DesignFrom {
    /// Linearize the trimmed vehicle when the controller first asks.
    Vehicle,
    /// The full linear model of the trimmed vehicle, already computed (`linearize`).
    Linear(crate::dynamics::LinearModel),
    /// The design a restart file saved (bit for bit the same controller).
    Restart(DesignRecord),
}

/// Linearizes the trimmed vehicle on the first request.
struct VehicleDesign<'v> {
    vehicle: std::cell::RefCell<&'v mut crate::vehicle::partitioned::PartitionedVehicle>,
    trim_state: &'v VehicleState,
    trim_controls: &'v FlightControls,
    full: std::cell::RefCell<Option<crate::dynamics::LinearModel>>,
    record: std::cell::RefCell<DesignRecord>,
}

impl VehicleDesign<'_> {
    fn axis(
        &self,
        axis: &design::Axis,
        slot: fn(&mut DesignRecord) -> &mut Option<hsv_core::control::LinearDesignModel>,
    ) -> Result<hsv_core::control::LinearDesignModel, hsv_core::ModelError> {
        if let Some(m) = slot(&mut self.record.borrow_mut()).clone() {
            return Ok(m);
        }
        let err = |m: String| hsv_core::ModelError::settings_at("", "control", "", m);
        if self.full.borrow().is_none() {
            let lin = crate::analysis::linearize::linearize(
                &mut self.vehicle.borrow_mut(),
                self.trim_state,
                self.trim_controls,
                &crate::dynamics::PerturbationRule::default(),
            )
            .map_err(|e| {
                err(format!(
                    "linearizing the trimmed vehicle for the design: {e}"
                ))
            })?;
            *self.full.borrow_mut() = Some(lin.model);
        }
        let full = self.full.borrow();
        let model =
            design::design_model(full.as_ref().expect("linearized above"), axis).map_err(err)?;
        *slot(&mut self.record.borrow_mut()) = Some(model.clone());
        Ok(model)
    }
}

impl hsv_core::control::DesignSource for VehicleDesign<'_> {
    fn longitudinal(&self) -> Result<hsv_core::control::LinearDesignModel, hsv_core::ModelError> {
        self.axis(&design::LONGITUDINAL, |r| &mut r.longitudinal)
    }
    fn lateral(&self) -> Result<hsv_core::control::LinearDesignModel, hsv_core::ModelError> {
        self.axis(&design::LATERAL, |r| &mut r.lateral)
    }
}

/// The controller name and actuators of `[control]` (`override_name`, from `--controller`,
/// wins over `[control] controller`; default `schedule`, whose default is no actuators).
pub fn control_settings(
    loaded: &hsv_core::config::LoadedConfig,
    override_name: Option<&str>,
) -> anyhow::Result<(String, Option<Actuators>)> {
    let table: ControlTable =
        hsv_core::config::parse_table(&loaded.config.control, &loaded.file, "control")?;
    let name = override_name
        .map(str::to_owned)
        .or(table.controller)
        .unwrap_or_else(|| "schedule".to_owned());
    let actuators = match table.actuators {
        Some(s) => Some(s),
        None if name == "schedule" => None,
        None => Some(ActuatorSettings::default()),
    };
    let actuators = actuators
        .map(|s| Actuators::new(s, "control.actuators"))
        .transpose()
        .map_err(|e| anyhow::anyhow!("{}: {e}", loaded.file))?;
    Ok((name, actuators))
}

/// Builds controller `name` at the trim (`trim_state`, `trim_controls`) of `vehicle`, its design
/// model from `from`, behind the config's `[control.sensors]`; the loop and the design it used.
#[allow(clippy::too_many_arguments)]
pub fn build_control_loop(
    loaded: &hsv_core::config::LoadedConfig,
    registry: &hsv_core::registry::Registry,
    name: &str,
    actuators: Option<Actuators>,
    vehicle: &mut crate::vehicle::partitioned::PartitionedVehicle,
    trim_state: &VehicleState,
    trim_controls: &FlightControls,
    dt_s: f64,
    from: DesignFrom,
) -> anyhow::Result<(ControlLoop, DesignRecord)> {
    let trim_commands = commands_of(trim_controls);
    let fresh = || DesignRecord {
        trim_outputs: measure(trim_state, &trim_commands, 0.0, &Vector3::zeros()),
        trim_commands,
        longitudinal: None,
        lateral: None,
    };
    let (record, full) = match from {
        DesignFrom::Vehicle => (fresh(), None),
        DesignFrom::Linear(model) => (fresh(), Some(model)),
        DesignFrom::Restart(record) => (record, None),
    };
    let (trim_outputs, trim_commands) = (record.trim_outputs, record.trim_commands);
    let source = VehicleDesign {
        vehicle: std::cell::RefCell::new(vehicle),
        trim_state,
        trim_controls,
        full: std::cell::RefCell::new(full),
        record: std::cell::RefCell::new(record),
    };
    // `[simulation.inputs]` and `[control.commands]` (empty when the config has none).
    let sub_table = |table: &toml::Table, key: &str| {
        table
            .get(key)
            .and_then(|v| v.as_table())
            .cloned()
            .unwrap_or_default()
    };
    let schedule = &loaded.config.simulation.inputs.clone().unwrap_or_default();
    let commands = &sub_table(&loaded.config.control, "commands");
    let key_path = format!("models.{name}");
    let context = hsv_core::registry::ControlContext {
        settings: loaded.model_settings(name),
        key_path: &key_path,
        file: &loaded.file,
        trim_outputs: &trim_outputs,
        trim_commands: &trim_commands,
        design: &source,
        schedule,
        commands,
        registry,
    };
    let controller = registry
        .create_controller(name, &context)
        .map_err(|e| anyhow::anyhow!("{}: controller `{name}`: {e}", loaded.file))?;
    let mut control = ControlLoop::new(controller, actuators, trim_controls, dt_s)?;
    // Sensors stand between the vehicle and every controller that measures it.
    control.set_sensors(sensor_settings(loaded, dt_s)?);
    Ok((control, source.record.into_inner()))
}
