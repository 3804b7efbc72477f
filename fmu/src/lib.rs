//! `hsv_fmu`: the trimmed flexible vehicle as an FMI 3.0 co-simulation FMU.
//!
//! fmi-export 0.3 generates the FMI C API from [`HsvVehicle`]'s fields (parameters, inputs,
//! outputs); this crate gives it the vehicle: on leaving initialization mode the configured
//! vehicle is trimmed at the parameters' flight condition ([`Flight::trimmed`], as `hsv-run
//! simulate` does), and each `fmi3DoStep` advances it a whole number of aeroelastic steps under
//! the inputs, held over the communication step. `hsv-run fmu` zips this library with its model
//! description ([`hsv_fmu_model_description`]) and the vehicle config (`resources/config.toml`;
//! without one the FMU flies the embedded sample vehicle).

use std::ffi::{CString, c_char};
use std::panic::AssertUnwindSafe;
use std::path::Path;
use std::sync::OnceLock;

use anyhow::{Context as _, Result, bail};
use fmi::fmi3::schema;
use fmi::fmi3::{Fmi3Error, Fmi3Res};
use fmi_export::FmuModel;
use fmi_export::fmi3::{CSDoStepResult, Context, DefaultLoggingCategory, Model, UserModel};
use hsv_core::control::ControlCommands;
use hsv_run::analysis::control::EXTERNAL_CONTROLLER;
use hsv_run::analysis::flight::{Flight, FlightOptions};
use hsv_run::analysis::simulate::Sample;

/// The FMU's model identifier: the library's file name in `binaries/<platform>/`.
pub const MODEL_IDENTIFIER: &str = "hsv_fmu";

/// The config file an FMU carries, under its resources folder.
pub const CONFIG_RESOURCE: &str = "config.toml";

/// The partitioned aerothermoelastic hypersonic vehicle of Klock & Cesnik, trimmed in level
/// flight at Mach `trim_mach`, `trim_altitude_m` and flown from there; inputs are offsets from the trim
/// commands, outputs the columns of `hsv-run simulate`'s history.csv.
#[derive(FmuModel, Default)]
#[model(model_exchange = false, co_simulation = true, user_model = false)]
pub struct HsvVehicle {
    /// Mach number of the trimmed level flight the run starts from (replaces the config's
    /// [flight] mach).
    #[variable(causality = Parameter, variability = Fixed, start = 6.0)]
    trim_mach: f64,
    /// Altitude of the trimmed level flight the run starts from, m (replaces the config's
    /// [flight] altitude_m).
    #[variable(causality = Parameter, variability = Fixed, start = 26000.0)]
    trim_altitude_m: f64,
    /// Aeroelastic step, s (paper Table 3: 1 ms); a communication step is a whole number of
    /// them.
    #[variable(causality = Parameter, variability = Fixed, start = 0.001)]
    dt_s: f64,
    /// Who commands the vehicle: `external` (the inputs), or a registered controller by name
    /// (`schedule`: the config's [simulation.inputs], default the paper's elevon doublet;
    /// `lqr`), which then ignores the inputs.
    #[variable(causality = Parameter, variability = Fixed, start = String::from("external"))]
    controller: String,

    /// Symmetric elevon command added to the trim elevon, deg (positive: nose-up pitching
    /// moment, i.e. trailing edge up on these aft surfaces; DESIGN §4).
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    elevon_offset_deg: f64,
    /// Differential elevon command (left = +, right = -), deg.
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    differential_elevon_command_deg: f64,
    /// Fuel equivalence ratio command added to the trim ratio.
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    fuel_equivalence_ratio_offset: f64,

    /// Trim angle of attack, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    trim_alpha_deg: f64,
    /// Trim symmetric elevon, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    trim_elevon_deg: f64,
    /// Trim fuel equivalence ratio.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    trim_fuel_equivalence_ratio: f64,

    /// Distance flown north (flat Earth), m.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    north_m: f64,
    /// Altitude, m.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    altitude_m: f64,
    /// Body-axis velocity along x, m/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    u_m_s: f64,
    /// Body-axis velocity along y, m/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    v_m_s: f64,
    /// Body-axis velocity along z, m/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    w_m_s: f64,
    /// Airspeed, m/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    airspeed_m_s: f64,
    /// Angle of attack, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    alpha_deg: f64,
    /// Sideslip angle, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    beta_deg: f64,
    /// Roll angle, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    roll_deg: f64,
    /// Pitch angle, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    pitch_deg: f64,
    /// Yaw angle, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    yaw_deg: f64,
    /// Roll rate, deg/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    p_deg_s: f64,
    /// Pitch rate, deg/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    q_deg_s: f64,
    /// Yaw rate, deg/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    r_deg_s: f64,
    /// Symmetric elevon actuator position, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    elevon_deg: f64,
    /// Fuel equivalence ratio the engine burns.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    fuel_equivalence_ratio: f64,
    /// Coupling iterations of the last step.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    coupling_iterations: f64,
    /// Coupling residual of the last step.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    coupling_residual: f64,
    /// Differential elevon actuator position, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    differential_elevon_deg: f64,
    /// Symmetric elevon command, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    command_elevon_deg: f64,
    /// Differential elevon command, deg.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    command_differential_elevon_deg: f64,
    /// Fuel equivalence ratio command.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    command_fuel_equivalence_ratio: f64,
    /// 1 when the elevon position limit bit over the last step, else 0.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    elevon_position_saturated: f64,
    /// 1 when the elevon rate limit bit over the last step, else 0.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    elevon_rate_saturated: f64,
    /// 1 when the fuel equivalence ratio limit bit over the last step, else 0.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    phi_position_saturated: f64,
    /// 1 when the fuel equivalence ratio rate limit bit over the last step, else 0.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    phi_rate_saturated: f64,
    /// Lowest structure temperature over the heated surfaces, K.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    surface_min_temperature_k: f64,
    /// Highest structure temperature over the heated surfaces, K.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    surface_max_temperature_k: f64,
    /// Mean structure temperature over the heated surfaces, K.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    surface_mean_temperature_k: f64,
    /// Gust velocity at the centre of mass along body x ([disturbances] of the config), m/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    gust_u_m_s: f64,
    /// Gust velocity at the centre of mass along body y, m/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    gust_v_m_s: f64,
    /// Gust velocity at the centre of mass along body z (down), m/s.
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    gust_w_m_s: f64,

    /// The trimmed flight (None before initialization and after a failed step).
    #[variable(skip = true)]
    flight: Option<Box<Flight>>,
    /// The parameters `flight` was trimmed for (a reset with the same ones reuses the trim).
    #[variable(skip = true)]
    built_for: Option<Setup>,
    /// Why the flight stopped, for the steps asked of it afterwards.
    #[variable(skip = true)]
    failure: Option<String>,
}

/// The parameters a trim depends on.
#[derive(Debug, Clone, PartialEq)]
struct Setup {
    mach: f64,
    altitude_m: f64,
    dt_s: f64,
    controller: String,
    resources: std::path::PathBuf,
}

impl HsvVehicle {
    fn setup(&self, resources: &Path) -> Setup {
        Setup {
            mach: self.trim_mach,
            altitude_m: self.trim_altitude_m,
            dt_s: self.dt_s,
            controller: self.controller.clone(),
            resources: resources.to_owned(),
        }
    }

    /// Trims the vehicle for `setup` (or returns the one trimmed for it to t = 0), logging what
    /// the trim says.
    fn start(&mut self, setup: Setup, log: &mut dyn FnMut(&str)) -> Result<()> {
        self.failure = None;
        if let (Some(flight), Some(built)) = (self.flight.as_mut(), self.built_for.as_ref())
            && *built == setup
        {
            flight.reset()?;
        } else {
            self.flight = None;
            self.built_for = None;
            let flight = trimmed_flight(&setup, log)?;
            self.flight = Some(Box::new(flight));
            self.built_for = Some(setup);
        }
        self.publish()
    }

    /// Advances the flight from `t_s` by `h_s` under the inputs.
    fn advance(&mut self, t_s: f64, h_s: f64) -> Result<()> {
        if let Some(why) = &self.failure {
            bail!("the flight stopped earlier ({why}); reset the FMU to fly again");
        }
        let commands = self.commands();
        let Some(flight) = self.flight.as_mut() else {
            bail!("the vehicle is not trimmed: leave initialization mode before stepping");
        };
        let dt = flight.dt_s;
        let steps = (h_s / dt).round();
        if !(steps >= 1.0 && (steps * dt - h_s).abs() <= 1e-9 * h_s.max(dt)) {
            bail!(
                "communication step {h_s} s is not a whole number of aeroelastic steps of {dt} s \
                 (parameter dt_s)"
            );
        }
        if (t_s - flight.time_s()).abs() > 1e-3 * dt {
            bail!(
                "asked to step from t = {t_s} s, but the flight is at t = {} s (the FMU cannot \
                 go back or skip ahead)",
                flight.time_s()
            );
        }
        if let Some(commands) = commands {
            flight.command(commands)?;
        }
        flight.advance(steps as usize)?;
        self.publish()
    }

    /// The host's commands (the trim commands plus the input offsets), or None when a
    /// registered controller flies the vehicle.
    fn commands(&self) -> Option<ControlCommands> {
        let flight = self.flight.as_ref()?;
        if flight.controller_name != EXTERNAL_CONTROLLER {
            return None;
        }
        let trim = &flight.trim.controls;
        Some(ControlCommands {
            symmetric_elevon_rad: trim.elevon.symmetric_rad + self.elevon_offset_deg.to_radians(),
            differential_elevon_rad: trim.elevon.differential_rad
                + self.differential_elevon_command_deg.to_radians(),
            fuel_equivalence_ratio: trim.fuel_equivalence_ratio
                + self.fuel_equivalence_ratio_offset,
        })
    }

    /// Copies the flight's sample into the outputs.
    fn publish(&mut self) -> Result<()> {
        let Some(flight) = self.flight.as_mut() else {
            return Ok(());
        };
        let trim = flight.trim.result.trim.clone();
        let s: Sample = flight.sample()?;
        self.trim_alpha_deg = trim.alpha_deg;
        self.trim_elevon_deg = trim.elevon_deg;
        self.trim_fuel_equivalence_ratio = trim.fuel_equivalence_ratio;
        self.north_m = s.north_m;
        self.altitude_m = s.altitude_m;
        self.u_m_s = s.u_m_s;
        self.v_m_s = s.v_m_s;
        self.w_m_s = s.w_m_s;
        self.airspeed_m_s = s.airspeed_m_s;
        self.alpha_deg = s.alpha_deg;
        self.beta_deg = s.beta_deg;
        self.roll_deg = s.roll_deg;
        self.pitch_deg = s.pitch_deg;
        self.yaw_deg = s.yaw_deg;
        self.p_deg_s = s.p_deg_s;
        self.q_deg_s = s.q_deg_s;
        self.r_deg_s = s.r_deg_s;
        self.elevon_deg = s.elevon_deg;
        self.fuel_equivalence_ratio = s.fuel_equivalence_ratio;
        self.coupling_iterations = s.coupling_iterations as f64;
        self.coupling_residual = s.coupling_residual;
        self.differential_elevon_deg = s.differential_elevon_deg;
        self.command_elevon_deg = s.command_elevon_deg;
        self.command_differential_elevon_deg = s.command_differential_elevon_deg;
        self.command_fuel_equivalence_ratio = s.command_fuel_equivalence_ratio;
        self.elevon_position_saturated = f64::from(u8::from(s.elevon_position_saturated));
        self.elevon_rate_saturated = f64::from(u8::from(s.elevon_rate_saturated));
        self.phi_position_saturated = f64::from(u8::from(s.phi_position_saturated));
        self.phi_rate_saturated = f64::from(u8::from(s.phi_rate_saturated));
        self.surface_min_temperature_k = s.surface_min_temperature_k;
        self.surface_max_temperature_k = s.surface_max_temperature_k;
        self.surface_mean_temperature_k = s.surface_mean_temperature_k;
        self.gust_u_m_s = s.gust_u_m_s;
        self.gust_v_m_s = s.gust_v_m_s;
        self.gust_w_m_s = s.gust_w_m_s;
        Ok(())
    }
}

/// The configured vehicle (`resources/config.toml`, else the embedded sample) trimmed at
/// `setup`'s flight condition under its controller.
fn trimmed_flight(setup: &Setup, log: &mut dyn FnMut(&str)) -> Result<Flight> {
    for (name, value) in [
        ("trim_mach", setup.mach),
        ("trim_altitude_m", setup.altitude_m),
    ] {
        if !(value.is_finite() && value > 0.0) {
            bail!("parameter {name} must be a positive number, got {value}");
        }
    }
    let registry = hsv_run::shared_registry()?;
    let config = setup.resources.join(CONFIG_RESOURCE);
    let (mut loaded, registry) =
        hsv_run::commands::load_config(config.exists().then_some(config.as_path()), registry)?;
    loaded.config.flight.mach = setup.mach;
    loaded.config.flight.altitude_m = setup.altitude_m;
    let controller = (setup.controller != EXTERNAL_CONTROLLER).then(|| setup.controller.clone());
    let options = FlightOptions {
        controller,
        dt_s: setup.dt_s,
        ..FlightOptions::default()
    };
    Flight::trimmed(&loaded, &registry, &options, |line| log(line))
        .with_context(|| format!("the vehicle of {}", loaded.file))
}

/// Runs `f`, a panic turned into an error (no panic crosses the FMI boundary).
fn guarded<T>(f: impl FnOnce() -> Result<T>) -> Result<T> {
    match std::panic::catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("(no message)");
            bail!("internal error (a panic in hsv): {message}")
        }
    }
}

/// Logs `error` through the importer's callback (and to stderr, which importers that drop
/// their log do not hide).
fn report(context: &dyn Context<HsvVehicle>, error: &anyhow::Error) {
    let message = hsv_run::error_line::error_line(error);
    eprintln!("hsv_fmu: error: {message}");
    context.log(
        Fmi3Error::Error.into(),
        DefaultLoggingCategory::LogAll,
        format_args!("{message}"),
    );
}

impl UserModel for HsvVehicle {
    type LoggingCategory = DefaultLoggingCategory;

    fn configurate(&mut self, context: &dyn Context<Self>) -> Result<(), Fmi3Error> {
        let setup = self.setup(context.resource_path());
        let mut notes = Vec::new();
        let started = guarded(|| self.start(setup, &mut |line| notes.push(line.to_owned())));
        for note in &notes {
            context.log(
                Fmi3Res::OK.into(),
                DefaultLoggingCategory::LogAll,
                format_args!("{note}"),
            );
        }
        started.map_err(|e| {
            report(context, &e);
            Fmi3Error::Error
        })
    }

    fn do_step(
        &mut self,
        context: &mut dyn Context<Self>,
        current_communication_point: f64,
        communication_step_size: f64,
        _no_set_fmu_state_prior_to_current_point: bool,
    ) -> Result<CSDoStepResult, Fmi3Error> {
        let stepped =
            guarded(|| self.advance(current_communication_point, communication_step_size));
        if let Err(e) = stepped {
            self.failure = Some(hsv_run::error_line::error_line(&e));
            report(context, &e);
            return Err(Fmi3Error::Error);
        }
        let end = current_communication_point + communication_step_size;
        context.set_time(end);
        Ok(CSDoStepResult::completed(end))
    }
}

fmi_export::export_fmu!(HsvVehicle);

/// modelDescription.xml of the FMU (FMI 3.0 co-simulation).
fn model_description() -> Result<String> {
    let variables = model_metadata();
    let description = schema::Fmi3ModelDescription {
        fmi_version: "3.0".to_owned(),
        model_name: "hsv".to_owned(),
        instantiation_token: <HsvVehicle as Model>::INSTANTIATION_TOKEN.to_owned(),
        description: Some(
            "Partitioned aerothermoelastic air-breathing hypersonic vehicle (after Klock & \
             Cesnik), trimmed in level flight at the parameters' Mach number and altitude and \
             flown from there: a flexible main body, two heated all-movable lifting surfaces \
             and a scramjet"
                .to_owned(),
        ),
        version: Some(env!("CARGO_PKG_VERSION").to_owned()),
        license: Some(env!("CARGO_PKG_LICENSE").to_owned()),
        generation_tool: Some(format!("hsv {}", env!("CARGO_PKG_VERSION"))),
        model_variables: variables.model_variables,
        model_structure: variables.model_structure,
        default_experiment: Some(schema::DefaultExperiment {
            start_time: Some(0.0),
            // The paper's elevon doublet (Fig. 10) at its aeroelastic step.
            stop_time: Some(2.0),
            step_size: Some(0.001),
            ..Default::default()
        }),
        co_simulation: Some(schema::Fmi3CoSimulation {
            model_identifier: MODEL_IDENTIFIER.to_owned(),
            can_handle_variable_communication_step_size: Some(true),
            can_get_and_set_fmu_state: Some(false),
            can_serialize_fmu_state: Some(false),
            has_event_mode: Some(false),
            ..Default::default()
        }),
        ..Default::default()
    };
    Ok(fmi::schema::serialize(&description, false)?)
}

/// The FMU's modelDescription.xml for `hsv-run fmu`: a NUL-terminated UTF-8 string that the
/// library owns for as long as it is loaded, or null (with the reason on stderr) when it cannot
/// be written.
#[unsafe(no_mangle)]
pub extern "C" fn hsv_fmu_model_description() -> *const c_char {
    static XML: OnceLock<Option<CString>> = OnceLock::new();
    let xml = XML.get_or_init(
        || match guarded(|| Ok(CString::new(model_description()?)?)) {
            Ok(xml) => Some(xml),
            Err(e) => {
                eprintln!("hsv_fmu: cannot write the model description: {e:#}");
                None
            }
        },
    );
    xml.as_ref().map_or(std::ptr::null(), |x| x.as_ptr())
}
