//! The control role behind the plugin ABI: a guest controller designed from the host's trim and
//! linear models (read through `DesignSource`) and stepped on sensor samples.

use super::*;

/// A plugin controller: its settings until `start` designs it, then the controller and the
/// texts the host reads.
pub struct ControlState {
    constructor: Option<ControllerConstructor>,
    settings: toml::Table,
    key_path: String,
    file: String,
    controller: Option<Box<dyn Controller>>,
    report: String,
    feedback: String,
}

impl ControlState {
    fn controller(&mut self) -> Result<&mut Box<dyn Controller>, String> {
        self.controller
            .as_mut()
            .ok_or_else(|| "the controller is used before `start`".to_owned())
    }
}

impl Exportable for dyn Controller {
    type State = ControlState;
    const ROLE: u32 = PLUGIN_ROLE_CONTROL;
    const FUNCTIONS: *const c_void = &ControlFunctions {
        start: control_start,
        sample_interval_s: control_sample_interval,
        state_len: control_state_len,
        initial_state: control_initial_state,
        update: control_update,
        design_report: control_design_report,
        state_feedback: control_state_feedback,
    } as *const ControlFunctions as *const c_void;
    fn state(model: Box<Self>) -> ControlState {
        ControlState {
            constructor: None,
            settings: toml::Table::new(),
            key_path: String::new(),
            file: String::new(),
            report: serde_json::to_string(&model.design_report()).unwrap_or_default(),
            feedback: state_feedback_json(&model.state_feedback()),
            controller: Some(model),
        }
    }
    fn capabilities(_: &mut ControlState) -> u32 {
        0
    }
}

/// Keeps a controller's settings from the host's `args` until `start` builds it with
/// `constructor` about the operating point.
///
/// # Safety
/// `args` must be null or valid per the ABI.
pub unsafe fn create_controller(
    args: *const CreateArgs,
    constructor: ControllerConstructor,
) -> *mut c_void {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: per the contract above.
        let args = unsafe { args.as_ref() }.ok_or("create called without arguments")?;
        let (json, key_path, file) = unsafe {
            (
                str_from(args.settings_json, "settings")?,
                str_from(args.key_path, "settings key path")?,
                str_from(args.file, "config file name")?,
            )
        };
        Ok::<_, String>(ControlState {
            constructor: Some(constructor),
            settings: json_table(json, "settings")?,
            key_path: key_path.to_owned(),
            file: file.to_owned(),
            controller: None,
            report: String::new(),
            feedback: String::new(),
        })
    }));
    let outcome = outcome.unwrap_or_else(|payload| {
        Err(format!(
            "plugin panicked in create: {}",
            panic_message(payload)
        ))
    });
    match outcome {
        Ok(state) => Box::into_raw(Box::new(Instance {
            state,
            last_error: String::new(),
        })) as *mut c_void,
        Err(message) => {
            CREATE_ERROR.with(|e| *e.borrow_mut() = message);
            std::ptr::null_mut()
        }
    }
}

/// A JSON table from the host (empty text: an empty table).
pub(super) fn json_table(json: &str, what: &str) -> Result<toml::Table, String> {
    if json.trim().is_empty() {
        return Ok(toml::Table::new());
    }
    serde_json::from_str(json).map_err(|e| format!("{what} are not a JSON table: {e}"))
}

/// The host's design models, asked for through [`DesignSourceAbi`].
pub(super) struct GuestDesign<'a> {
    abi: &'a DesignSourceAbi,
    name: &'a str,
}

impl GuestDesign<'_> {
    fn model(&self, which: u32) -> Result<LinearDesignModel, ModelError> {
        let mut text = StrAbi::new("");
        // SAFETY: the host's function with its own context, during `start`.
        let status = unsafe { (self.abi.model)(self.abi.context, which, &mut text) };
        // SAFETY: the host keeps the text alive until `start` returns.
        let text = unsafe { str_from(text, "design model") }
            .map_err(|e| ModelError::inconsistent(self.name, e))?;
        if status != 0 {
            return Err(ModelError::inconsistent(
                self.name,
                format!("the host has no design model: {text}"),
            ));
        }
        design_model_from_json(text).map_err(|e| ModelError::inconsistent(self.name, e))
    }
}

impl DesignSource for GuestDesign<'_> {
    fn longitudinal(&self) -> Result<LinearDesignModel, ModelError> {
        self.model(DESIGN_LONGITUDINAL)
    }
    fn lateral(&self) -> Result<LinearDesignModel, ModelError> {
        self.model(DESIGN_LATERAL)
    }
}

unsafe extern "C" fn control_start(handle: *mut c_void, args: *const ControlStartAbi) -> i32 {
    // SAFETY: the host passes a handle from `create` and arguments that follow the ABI.
    unsafe {
        call::<ControlState>(handle, "start", |s| {
            let args = args.as_ref().ok_or("null start arguments")?;
            let constructor = s.constructor.ok_or("the controller is already started")?;
            let schedule = json_table(str_from(args.schedule_json, "schedule")?, "schedule")?;
            let commands = json_table(str_from(args.commands_json, "commands")?, "commands")?;
            let trim_outputs = MeasuredOutputs::from_values(args.trim_outputs);
            let trim_commands = ControlCommands::from_values(args.trim_commands);
            let name = s
                .key_path
                .rsplit('.')
                .next()
                .unwrap_or(&s.key_path)
                .to_owned();
            let design = GuestDesign {
                abi: &args.design,
                name: &name,
            };
            let context = ControlContext {
                settings: &s.settings,
                key_path: &s.key_path,
                file: &s.file,
                trim_outputs: &trim_outputs,
                trim_commands: &trim_commands,
                design: &design,
                schedule: &schedule,
                commands: &commands,
                registry: guest_registry(),
            };
            let controller = constructor(&context).map_err(error_text)?;
            s.report = serde_json::to_string(&controller.design_report())
                .map_err(|e| format!("design report as JSON: {e}"))?;
            s.feedback = state_feedback_json(&controller.state_feedback());
            s.controller = Some(controller);
            s.constructor = None;
            Ok(0)
        })
    }
}

unsafe extern "C" fn control_sample_interval(handle: *mut c_void) -> f64 {
    let mut interval = f64::NAN;
    // SAFETY: the host passes a handle from `create`.
    unsafe {
        call::<ControlState>(handle, "sample interval", |s| {
            interval = s.controller()?.sample_interval_s().unwrap_or(0.0);
            Ok(0)
        })
    };
    interval
}

unsafe extern "C" fn control_state_len(handle: *mut c_void) -> usize {
    // SAFETY: the host passes a handle from `create`.
    unsafe {
        call_count::<ControlState>(handle, "state length", |s| Ok(s.controller()?.state_len()))
    }
}

unsafe extern "C" fn control_initial_state(
    handle: *mut c_void,
    state: *mut f64,
    n_state: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and `n_state` values of room.
    unsafe {
        call::<ControlState>(handle, "initial state", |s| {
            let controller = s.controller()?;
            if n_state != controller.state_len() {
                return Err(format!(
                    "{n_state} state values, but the controller keeps {}",
                    controller.state_len()
                ));
            }
            controller.initial_state(slice_mut(state, n_state, "state")?);
            Ok(0)
        })
    }
}

unsafe extern "C" fn control_update(
    handle: *mut c_void,
    outputs: *const f64,
    state: *mut f64,
    n_state: usize,
    commands: *mut f64,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<ControlState>(handle, "update", |s| {
            let controller = s.controller()?;
            if n_state != controller.state_len() {
                return Err(format!(
                    "{n_state} state values, but the controller keeps {}",
                    controller.state_len()
                ));
            }
            let measured: [f64; CONTROL_OUTPUTS] = slice(outputs, CONTROL_OUTPUTS, "outputs")?
                .try_into()
                .map_err(|_| "outputs")?;
            let out = slice_mut(commands, CONTROL_COMMANDS, "commands")?;
            let mut command = ControlCommands::from_values(out.try_into().map_err(|_| "commands")?);
            controller
                .update(
                    &MeasuredOutputs::from_values(measured),
                    slice_mut(state, n_state, "state")?,
                    &mut command,
                )
                .map_err(error_text)?;
            out.copy_from_slice(&command.values());
            Ok(0)
        })
    }
}

unsafe extern "C" fn control_design_report(
    handle: *mut c_void,
    buffer: *mut u8,
    capacity: usize,
) -> usize {
    // SAFETY: the host passes a handle from `create` and `capacity` bytes of room.
    unsafe {
        call_count::<ControlState>(handle, "design report", |s| {
            Ok(copy_text(&s.report, buffer, capacity))
        })
    }
}

unsafe extern "C" fn control_state_feedback(
    handle: *mut c_void,
    buffer: *mut u8,
    capacity: usize,
) -> usize {
    // SAFETY: the host passes a handle from `create` and `capacity` bytes of room.
    unsafe {
        call_count::<ControlState>(handle, "state feedback", |s| {
            Ok(copy_text(&s.feedback, buffer, capacity))
        })
    }
}
