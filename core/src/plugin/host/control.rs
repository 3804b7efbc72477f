//! The host's controller adapter: a plugin controller designed from the host's models (served
//! as JSON through `DesignSourceAbi`) and stepped on sensor samples.

use super::*;

/// Reads a text the plugin copies into a buffer and whose full length it returns.
pub(super) fn read_text(
    raw: *mut c_void,
    copy: unsafe extern "C" fn(*mut c_void, *mut u8, usize) -> usize,
) -> String {
    let mut buffer = vec![0u8; 4096];
    // SAFETY: the buffer is valid for its length; the plugin writes at most that many bytes.
    let length = unsafe { copy(raw, buffer.as_mut_ptr(), buffer.len()) };
    if length > buffer.len() {
        buffer.resize(length, 0);
        // SAFETY: as above, with room for the whole text.
        let again = unsafe { copy(raw, buffer.as_mut_ptr(), buffer.len()) };
        buffer.truncate(again.min(length));
    } else {
        buffer.truncate(length);
    }
    String::from_utf8_lossy(&buffer).into_owned()
}

/// The host's answer to a plugin controller's design-model requests during `start`.
pub(super) struct HostDesign<'a> {
    source: &'a dyn DesignSource,
    /// JSON texts handed out, alive until `start` returns.
    texts: Vec<String>,
}

/// [`DesignSourceAbi::model`] on the host: the design model as JSON, or the error message.
unsafe extern "C" fn host_design_model(context: *mut c_void, which: u32, out: *mut StrAbi) -> i32 {
    if context.is_null() || out.is_null() {
        return 1;
    }
    // SAFETY: `context` is the `HostDesign` of the running `start`, `out` the plugin's slot.
    let (design, out) = unsafe { (&mut *(context as *mut HostDesign<'_>), &mut *out) };
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match which {
        DESIGN_LONGITUDINAL => design.source.longitudinal().map_err(|e| e.to_string()),
        DESIGN_LATERAL => design.source.lateral().map_err(|e| e.to_string()),
        other => Err(format!(
            "design model code {other} is not {DESIGN_LONGITUDINAL} (longitudinal) or {DESIGN_LATERAL} (lateral)"
        )),
    }));
    let (status, text) = match outcome {
        Ok(Ok(model)) => (0, design_model_json(&model)),
        Ok(Err(message)) => (2, message),
        Err(_) => (3, "the host panicked building the design model".to_owned()),
    };
    design.texts.push(text);
    let text = design.texts.last().map_or("", String::as_str);
    *out = StrAbi::new(text);
    status
}

/// A plugin controller behind [`Controller`]; its state is the host's slice.
pub struct ControllerAdapter {
    handle: Handle,
    functions: &'static ControlFunctions,
    sample_interval_s: Option<f64>,
    /// The state at trim, read once at create; its length is the controller's state length.
    initial_state: Vec<f64>,
    report: serde_json::Value,
    feedback: Vec<StateFeedback>,
}

impl ControllerAdapter {
    /// Creates the plugin controller and designs it about the context's operating point.
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static ControlFunctions,
        name: &str,
        context: &ControlContext<'_>,
    ) -> Result<Self, ModelError> {
        let mut empty = MeshBuffers::default();
        empty.fill(&PanelMesh::default());
        let (file, key_path) = (context.file, context.key_path);
        let region = control_region(&empty);
        let handle = Handle::create_in(entry, name, context.settings, key_path, file, region)?;
        let as_json = |table: &toml::Table, what: &str| {
            serde_json::to_string(table).map_err(|e| {
                ModelError::inconsistent(name, format!("{what} as JSON for the plugin: {e}"))
            })
        };
        let schedule = as_json(context.schedule, "[simulation.inputs]")?;
        let commands = as_json(context.commands, "[control.commands]")?;
        let mut design = HostDesign {
            source: context.design,
            texts: Vec::new(),
        };
        let args = ControlStartAbi {
            trim_outputs: context.trim_outputs.values(),
            trim_commands: context.trim_commands.values(),
            schedule_json: StrAbi::new(&schedule),
            commands_json: StrAbi::new(&commands),
            design: DesignSourceAbi {
                context: &mut design as *mut HostDesign<'_> as *mut c_void,
                model: host_design_model,
            },
        };
        // SAFETY: `args`, the strings and `design` live across the call.
        let status = unsafe { (functions.start)(handle.raw, &args) };
        handle.check(status, "start")?;
        // SAFETY: a started handle.
        let interval = unsafe { (functions.sample_interval_s)(handle.raw) };
        let sample_interval_s = match interval {
            0.0 => None,
            dt if dt.is_finite() && dt > 0.0 => Some(dt),
            dt => {
                return Err(ModelError::inconsistent(
                    name,
                    format!("plugin sample interval {dt} s is not > 0 (or 0 for a law of time)"),
                ));
            }
        };
        // SAFETY: a started handle.
        let state_len = unsafe { (functions.state_len)(handle.raw) };
        let mut initial_state = vec![0.0; state_len];
        // SAFETY: `state_len` values of room.
        let status =
            unsafe { (functions.initial_state)(handle.raw, initial_state.as_mut_ptr(), state_len) };
        handle.check(status, "initial state")?;
        check_finite(
            name,
            "initial controller state",
            &initial_state,
            1,
            "state index",
        )?;
        let report_text = read_text(handle.raw, functions.design_report);
        let report = if report_text.trim().is_empty() {
            serde_json::Value::Null
        } else {
            serde_json::from_str(&report_text).map_err(|e| {
                ModelError::inconsistent(name, format!("plugin design report is not JSON: {e}"))
            })?
        };
        let feedback_text = read_text(handle.raw, functions.state_feedback);
        let feedback = if feedback_text.trim().is_empty() {
            Vec::new()
        } else {
            state_feedback_from_json(&feedback_text)
                .map_err(|e| ModelError::inconsistent(name, format!("plugin {e}")))?
        };
        Ok(Self {
            handle,
            functions,
            sample_interval_s,
            initial_state,
            report,
            feedback,
        })
    }
}

impl Controller for ControllerAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn sample_interval_s(&self) -> Option<f64> {
        self.sample_interval_s
    }

    fn state_len(&self) -> usize {
        self.initial_state.len()
    }

    fn initial_state(&self, state: &mut [f64]) {
        // Read once at create, where a failure is an error (this trait method cannot fail).
        if state.len() == self.initial_state.len() {
            state.copy_from_slice(&self.initial_state);
        } else {
            state.fill(0.0);
        }
    }

    fn update(
        &mut self,
        outputs: &MeasuredOutputs,
        state: &mut [f64],
        commands: &mut ControlCommands,
    ) -> Result<(), ModelError> {
        let name = &self.handle.name;
        check_len(
            name,
            "controller state values",
            state.len(),
            self.initial_state.len(),
        )?;
        let measured = outputs.values();
        let mut out = commands.values();
        // SAFETY: CONTROL_OUTPUTS measurements, `state_len` state values and CONTROL_COMMANDS
        // commands of room.
        let status = unsafe {
            (self.functions.update)(
                self.handle.raw,
                measured.as_ptr(),
                state.as_mut_ptr(),
                state.len(),
                out.as_mut_ptr(),
            )
        };
        self.handle.check(status, "update")?;
        check_finite(name, "controller state", state, 1, "state index")?;
        check_finite(name, "command", &out, 1, "command index")?;
        *commands = ControlCommands::from_values(out);
        Ok(())
    }

    fn design_report(&self) -> serde_json::Value {
        self.report.clone()
    }

    fn state_feedback(&self) -> Vec<StateFeedback> {
        self.feedback.clone()
    }
}
