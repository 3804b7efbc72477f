//! The trimmed vehicle in flight: the `[simulation]` settings a flight reads, the one
//! trim-then-fly setup (`simulate`, `compare`, the Python `Simulation`), and a flight a host
//! program (Python, an FMU) advances one aeroelastic step at a time with its own commands,
//! marching exactly as [`super::simulate::simulate`] does (one file: the settings, the
//! trim and the stepped flight are the one path from a config to a flying vehicle that every flying
//! command and host shares).

use anyhow::{Context, Result, bail};
use hsv_core::config::LoadedConfig;
use hsv_core::control::ControlCommands;
use hsv_core::registry::Registry;

use super::level_trim::{LevelTrim, earth, trim_level_flight};
use super::simulate::{
    Inputs, Integrator, RunSettings, Sample, SimulationError, Stepper, record_sample, simulate,
};
use crate::analysis::control::{ControlLoop, DesignFrom, DesignRecord, EXTERNAL_CONTROLLER};
use crate::disturbance::{DisturbanceSettings, Disturbances};
use crate::dynamics::EarthModel;
use crate::dynamics::VehicleState;
use crate::vehicle::flexible_vehicle_with;
use crate::vehicle::partitioned::{HeatingRates, PartitionedVehicle, SurfaceModel, VehicleError};
use crate::vehicle::region_rate::{DEFAULT_BODY_FRICTION_DT_S, RegionLoadRate};

/// The heating rates: `[simulation]` keys `heat_transfer_dt_s`, `aerothermal_dt_s`,
/// `stiffness_interval_s`, `initial_temperature_k` over the paper's Table 3 defaults.
pub fn heating_rates(loaded: &LoadedConfig) -> Result<HeatingRates> {
    let simulation = &loaded.config.simulation;
    let mut rates = HeatingRates::default();
    for (key, value, slot) in [
        (
            "heat_transfer_dt_s",
            simulation.heat_transfer_dt_s,
            &mut rates.conduction_s,
        ),
        (
            "aerothermal_dt_s",
            simulation.aerothermal_dt_s,
            &mut rates.heat_flux_s,
        ),
        (
            "stiffness_interval_s",
            simulation.stiffness_interval_s,
            &mut rates.stiffness_s,
        ),
        (
            "initial_temperature_k",
            simulation.initial_temperature_k,
            &mut rates.initial_k,
        ),
    ] {
        match value {
            None => {}
            Some(v) if v.is_finite() && v > 0.0 => *slot = v,
            Some(v) => bail!(
                "{}: key `simulation.{key}` must be a positive number, got {v}",
                loaded.file
            ),
        }
    }
    Ok(rates)
}

/// How often the main body region is evaluated: `[simulation] body_loads_dt_s` (s; default
/// the paper's 1 ms aeroelastic rate; 0 evaluates it at every Runge-Kutta stage).
pub fn body_load_rate(loaded: &LoadedConfig) -> Result<RegionLoadRate> {
    rate_setting(
        loaded,
        "body_loads_dt_s",
        loaded.config.simulation.body_loads_dt_s,
        RegionLoadRate::default(),
        "0: at every Runge-Kutta stage",
    )
}

/// How often the lifting surfaces' aero is evaluated: `[simulation] surface_loads_dt_s` (s;
/// default 0, at every Runge-Kutta stage; the paper's 1 ms recalculates it once per aeroelastic
/// step and extrapolates in between: module [`crate::vehicle::region_rate`]).
pub fn surface_load_rate(loaded: &LoadedConfig) -> Result<RegionLoadRate> {
    rate_setting(
        loaded,
        "surface_loads_dt_s",
        loaded.config.simulation.surface_loads_dt_s,
        RegionLoadRate::EveryStage,
        "0: at every Runge-Kutta stage",
    )
}

/// How often the body's skin friction is evaluated again: `[simulation] body_friction_dt_s`
/// (s; default the paper's 10 ms aerothermal rate; 0 at every body evaluation).
pub fn body_friction_rate(loaded: &LoadedConfig) -> Result<RegionLoadRate> {
    rate_setting(
        loaded,
        "body_friction_dt_s",
        loaded.config.simulation.body_friction_dt_s,
        RegionLoadRate::Interval(DEFAULT_BODY_FRICTION_DT_S),
        "0: at every evaluation of the body",
    )
}

/// A `[simulation]` interval `key` of `value` seconds (0 meaning every evaluation), or
/// `default`.
fn rate_setting(
    loaded: &LoadedConfig,
    key: &str,
    value: Option<f64>,
    default: RegionLoadRate,
    zero_means: &str,
) -> Result<RegionLoadRate> {
    let Some(value) = value else {
        return Ok(default);
    };
    RegionLoadRate::from_interval_s(value).with_context(|| {
        format!(
            "{}: key `simulation.{key}` is {value}; expected a number of seconds >= 0 \
             ({zero_means})",
            loaded.file
        )
    })
}

/// A rate as the `[simulation]` key writes it: seconds, 0 for every evaluation.
pub fn rate_seconds(rate: RegionLoadRate) -> f64 {
    match rate {
        RegionLoadRate::EveryStage => 0.0,
        RegionLoadRate::Interval(s) => s,
    }
}

/// The integrator: `[simulation] integrator` (`exponential-rk4`, the default, or `rk4`).
pub fn integrator(loaded: &LoadedConfig) -> Result<Integrator> {
    let Some(name) = &loaded.config.simulation.integrator else {
        return Ok(Integrator::default());
    };
    Integrator::from_name(name).with_context(|| {
        format!(
            "{}: key `simulation.integrator` is \"{name}\"; expected one of {}",
            loaded.file,
            Integrator::NAMES.map(|n| format!("\"{n}\"")).join(", ")
        )
    })
}

/// The inputs: `[simulation.inputs]` of the config over the paper's doublet (also what a
/// simulate trade study flies).
pub fn inputs(loaded: &LoadedConfig) -> Result<Inputs> {
    let Some(table) = &loaded.config.simulation.inputs else {
        return Ok(Inputs::paper_doublet());
    };
    if table.contains_key("fuel_equivalence_ratio") && !loaded.config.regions.has("propulsion") {
        bail!(
            "{}: key `simulation.inputs.fuel_equivalence_ratio`: the vehicle has no engine (no \
             `[regions.propulsion]` table), so there is no fuel to command; remove the table or \
             add the region",
            loaded.file
        );
    }
    Ok(Inputs::from_table(
        table,
        &loaded.file,
        "simulation.inputs",
    )?)
}

/// Everything `[simulation]` says about how a flight runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightSettings {
    pub rates: HeatingRates,
    pub body_loads: RegionLoadRate,
    pub body_friction: RegionLoadRate,
    pub surface_loads: RegionLoadRate,
    pub integrator: Integrator,
    pub earth: EarthModel,
}

impl FlightSettings {
    /// The settings of `[simulation]`, its inputs table checked too (so a bad table fails before
    /// the trim).
    pub fn from_config(loaded: &LoadedConfig) -> Result<Self> {
        inputs(loaded)?;
        Ok(Self {
            rates: heating_rates(loaded)?,
            body_loads: body_load_rate(loaded)?,
            body_friction: body_friction_rate(loaded)?,
            surface_loads: surface_load_rate(loaded)?,
            integrator: integrator(loaded)?,
            earth: earth(loaded)?,
        })
    }
}

/// Which vehicle flies and who commands it.
#[derive(Debug, Clone, PartialEq)]
pub struct FlightOptions {
    /// Partitioned (paper §III) or the monolithic comparison model.
    pub model: SurfaceModel,
    /// The partitioned surfaces heat in flight.
    pub heated: bool,
    /// A registered controller (`schedule`, `lqr`, ...), or `None` for the host's commands
    /// ([`Flight::command`]), held from the trim commands until the host sets others.
    pub controller: Option<String>,
    /// Aeroelastic step, s (paper Table 3: 1 ms).
    pub dt_s: f64,
    /// What the flight flies through, in place of the config's `[disturbances]` (None: the
    /// config's).
    pub disturbances: Option<DisturbanceSettings>,
}

impl Default for FlightOptions {
    fn default() -> Self {
        Self {
            model: SurfaceModel::Partitioned,
            heated: true,
            controller: Some("schedule".to_owned()),
            dt_s: 1e-3,
            disturbances: None,
        }
    }
}

/// The vehicle of a flight: `options`' model, heated if asked and partitioned, its body
/// evaluated at the `[simulation]` rates.
pub fn flight_vehicle(
    loaded: &LoadedConfig,
    registry: &Registry,
    options: &FlightOptions,
    settings: &FlightSettings,
) -> Result<PartitionedVehicle> {
    let heated = options.heated && options.model == SurfaceModel::Partitioned;
    let mut vehicle = flexible_vehicle_with(
        loaded,
        registry,
        options.model,
        heated,
        "the time simulation",
    )?;
    vehicle.set_body_load_rate(settings.body_loads)?;
    vehicle.set_body_friction_rate(settings.body_friction)?;
    vehicle.set_surface_load_rate(settings.surface_loads)?;
    vehicle.set_earth(settings.earth);
    Ok(vehicle)
}

/// The wind field a flight of `loaded` flies through: `options`' disturbances or the config's
/// `[disturbances]`, frozen in the air mass at the airspeed of the config's flight condition.
pub fn flight_disturbances(loaded: &LoadedConfig, options: &FlightOptions) -> Result<Disturbances> {
    let settings = match &options.disturbances {
        Some(d) => {
            d.check()
                .map_err(|(key, why)| anyhow::anyhow!("disturbances.{key}: {why}"))?;
            d.clone()
        }
        None => DisturbanceSettings::from_config(loaded)?,
    };
    let flight = &loaded.config.flight;
    let airspeed_m_s =
        hsv_core::flow::Freestream::standard(flight.mach, flight.altitude_m, loaded.config.gas)
            .map_err(|e| anyhow::anyhow!("{}: [flight]: {e}", loaded.file))?
            .velocity_m_s;
    settings
        .field(flight.altitude_m, airspeed_m_s, options.dt_s)
        .map_err(|e| anyhow::anyhow!("{}: key `disturbances`: {e}", loaded.file))
}

/// A trimmed vehicle in flight under a controller: the vehicle, its state and its control loop,
/// advanced one aeroelastic step at a time.
pub struct Flight {
    pub vehicle: PartitionedVehicle,
    pub state: VehicleState,
    pub control: ControlLoop,
    /// The design the controller was built from (restart files carry it).
    pub design: DesignRecord,
    /// The controller's name (`external` for the host's commands).
    pub controller_name: String,
    pub trim: LevelTrim,
    pub settings: FlightSettings,
    pub dt_s: f64,
    /// Steps taken.
    step: usize,
    /// Built at the first step (after any restore of the state).
    stepper: Option<Stepper>,
    /// The flight at t = 0, for [`Flight::reset`].
    initial: RunState,
    /// The wind field from t = 0 (a vehicle assembled again flies it again; the field is a
    /// function of its seed and time, so one serves any restored time).
    disturbances: Disturbances,
    /// What the vehicle was assembled from: a reset after the heated stiffness has been applied
    /// assembles it again (the structure models keep no cold copy of their matrices).
    source: (LoadedConfig, Registry, FlightOptions),
}

/// Everything the next step of a flight depends on, as plain data (serde; floats round-trip
/// JSON exactly): the steps taken, the integrated state, the vehicle's own state (coupling
/// guesses, thermal states, ROM histories, the regions' publications in the data manager) and
/// the control loop's. A flight restored to it continues bit for bit ([`Flight::restore`]);
/// `simulate`'s `restart.json` holds the same parts.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunState {
    /// Steps taken (the next step's index); the time is steps × Δt.
    pub step: usize,
    pub state: VehicleState,
    pub vehicle: crate::vehicle::partitioned::VehicleRestart,
    pub control: crate::analysis::control::ControlState,
}

impl Flight {
    /// Assembles the configured vehicle, trims it at the config's flight condition, designs the
    /// controller on the trimmed vehicle before it heats, and starts the heating: the state at
    /// t = 0 of every run. `log` hears what is happening (the trim takes seconds).
    pub fn trimmed(
        loaded: &LoadedConfig,
        registry: &Registry,
        options: &FlightOptions,
        mut log: impl FnMut(&str),
    ) -> Result<Self> {
        if !(options.dt_s.is_finite() && options.dt_s > 0.0) {
            bail!(
                "the time step must be a positive number of seconds, got {}",
                options.dt_s
            );
        }
        let settings = FlightSettings::from_config(loaded)?;
        let disturbances = flight_disturbances(loaded, options)?;
        let (controller_name, actuators) =
            crate::analysis::control::control_settings(loaded, options.controller.as_deref())?;
        let mut vehicle = flight_vehicle(loaded, registry, options, &settings)?;
        let (mach, altitude_m) = (loaded.config.flight.mach, loaded.config.flight.altitude_m);
        log(&format!(
            "trimming the flexible vehicle at Mach {mach}, {altitude_m} m"
        ));
        let trim = trim_level_flight(&mut vehicle, mach, altitude_m)?;
        for note in &trim.result.notes {
            log(&format!("warning: {note}"));
        }
        let (control, design, controller_name) = match &options.controller {
            None => (
                ControlLoop::external(actuators, &trim.controls, options.dt_s)?,
                DesignRecord::default(),
                EXTERNAL_CONTROLLER.to_owned(),
            ),
            Some(_) => {
                // Designed on the trimmed vehicle before it heats.
                let (control, design) = crate::analysis::control::build_control_loop(
                    loaded,
                    registry,
                    &controller_name,
                    actuators,
                    &mut vehicle,
                    &trim.state,
                    &trim.controls,
                    options.dt_s,
                    DesignFrom::Vehicle,
                )?;
                (control, design, controller_name)
            }
        };
        vehicle.set_disturbances(disturbances);
        vehicle.start_heating(&settings.rates)?;
        vehicle.forget_region_loads()?;
        let initial = RunState {
            step: 0,
            state: trim.state.clone(),
            vehicle: vehicle.restart(),
            control: control.state.clone(),
        };
        let disturbances = vehicle.disturbances().clone();
        Ok(Self {
            vehicle,
            state: trim.state.clone(),
            control,
            design,
            controller_name,
            trim,
            settings,
            dt_s: options.dt_s,
            step: 0,
            stepper: None,
            initial,
            disturbances,
            source: (loaded.clone(), registry.clone(), options.clone()),
        })
    }

    /// Back to the trimmed flight at t = 0 (the vehicle's models, heating and control loop as
    /// they were), without trimming again: a run after a reset repeats the first bit for bit.
    pub fn reset(&mut self) -> Result<(), VehicleError> {
        let initial = self.initial.clone();
        self.restore(&initial)
    }

    /// The flight's state now, as data ([`RunState`]): what [`Self::restore`] returns to.
    pub fn run_state(&self) -> RunState {
        RunState {
            step: self.step,
            state: self.state.clone(),
            vehicle: self.vehicle.restart(),
            control: self.control.state.clone(),
        }
    }

    /// Returns the flight to `run` (taken from this flight, or one built from the same config
    /// and options): the steps after it repeat those after it was taken, bit for bit. A vehicle
    /// whose stiffness has been heated is assembled again first (its structure models keep no
    /// cold matrices).
    pub fn restore(&mut self, run: &RunState) -> Result<(), VehicleError> {
        let shape = |s: &VehicleState| {
            let modes = |m: &crate::dynamics::ModalState| (m.q.len(), m.q_dot.len());
            let surfaces: Vec<_> = s.surface_modes.iter().map(modes).collect();
            (modes(&s.body_modes), surfaces)
        };
        let expected = shape(&self.vehicle.dynamics().zero_state());
        if shape(&run.state) != expected {
            return Err(VehicleError::Input(format!(
                "the run state's modal coordinates (body, surfaces) {:?} do not fit this \
                 vehicle's {expected:?}",
                shape(&run.state)
            )));
        }
        if self.vehicle.stiffness_heated() {
            let (loaded, registry, options) = &self.source;
            self.vehicle = flight_vehicle(loaded, registry, options, &self.settings)
                .map_err(|e| VehicleError::Input(crate::error_line::error_line(&e)))?;
        }
        self.vehicle.set_disturbances(self.disturbances.clone());
        self.vehicle.restore(&run.vehicle)?;
        self.control.restore(run.control.clone())?;
        self.state.clone_from(&run.state);
        self.step = run.step;
        self.stepper = None;
        Ok(())
    }

    /// Flies `duration_s` from the trim as `simulate` flies it (the `[simulation]` integrator,
    /// Δt of the options), `observe` hearing every `record_every`-th sample and the last; the
    /// steps taken, or where the flight went bad.
    pub fn fly(
        &mut self,
        duration_s: f64,
        record_every: usize,
        observe: impl FnMut(&Sample, &VehicleState, &mut PartitionedVehicle) -> bool + Send,
    ) -> Result<usize, SimulationError> {
        let run = RunSettings {
            dt_s: self.dt_s,
            integrator: self.settings.integrator,
            duration_s,
            record_every: record_every.max(1),
            start_step: 0,
        };
        simulate(
            &mut self.vehicle,
            &mut self.state,
            &mut self.control,
            &run,
            observe,
        )
    }

    /// Steps taken since t = 0.
    pub fn steps_taken(&self) -> usize {
        self.step
    }

    /// The flight time, s: steps × Δt.
    pub fn time_s(&self) -> f64 {
        self.step as f64 * self.dt_s
    }

    /// The actuators of the loop (None: commands act at once).
    pub fn has_actuators(&self) -> bool {
        self.control.has_actuators()
    }

    /// Sets the commands the host holds from the next step on (only a flight under the host's
    /// commands takes them: a registered controller commands itself).
    pub fn command(&mut self, commands: ControlCommands) -> Result<(), VehicleError> {
        if self.controller_name != EXTERNAL_CONTROLLER {
            return Err(VehicleError::Input(format!(
                "this flight is commanded by controller `{}`; commands are taken only by a \
                 flight built without a controller (the host's commands)",
                self.controller_name
            )));
        }
        if !commands.values().iter().all(|v| v.is_finite()) {
            return Err(VehicleError::Input(format!(
                "commands must be finite, got {commands:?}"
            )));
        }
        self.control.state.command = commands;
        Ok(())
    }

    /// Advances `n` aeroelastic steps of Δt under the loop's commands.
    pub fn advance(&mut self, n: usize) -> Result<(), SimulationError> {
        let wrap = |time_s: f64| move |source: VehicleError| SimulationError { time_s, source };
        if self.stepper.is_none() {
            self.stepper = Some(
                Stepper::new(&self.vehicle, &self.state, self.settings.integrator)
                    .map_err(wrap(self.time_s()))?,
            );
        }
        let Some(stepper) = self.stepper.as_mut() else {
            return Ok(());
        };
        // On a rayon worker, as `simulate` runs: the regions' side-by-side sections join there.
        let (vehicle, state, control, dt, step) = (
            &mut self.vehicle,
            &mut self.state,
            &mut self.control,
            self.dt_s,
            &mut self.step,
        );
        rayon::scope(|_| {
            for _ in 0..n {
                let k = *step;
                let t = k as f64 * dt;
                stepper
                    .step(vehicle, state, control, k, t, dt, (k + 1) as f64 * dt)
                    .map_err(wrap(t))?;
                *step += 1;
            }
            Ok(())
        })
    }

    /// The recorded quantities now.
    pub fn sample(&mut self) -> Result<Sample, SimulationError> {
        let t = self.time_s();
        record_sample(&mut self.vehicle, &mut self.control, &self.state, t)
            .map_err(|source| SimulationError { time_s: t, source })
    }
}
