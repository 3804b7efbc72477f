//! `schedule`: the open-loop `[simulation.inputs]` tables (offsets from trim, linear between
//! rows, held beyond; default the paper's elevon doublet) as a controller: a law of time alone,
//! evaluated at every instant the dynamics ask, so a run under it is the open-loop run.

use hsv_core::ModelError;
use hsv_core::control::{ControlCommands, Controller, MeasuredOutputs};
use hsv_core::registry::ControlContext;
use hsv_core::registry::{Constructor, ModelDescriptor};

use crate::analysis::inputs::Inputs;

/// The schedule around the trim commands.
pub struct Schedule {
    inputs: Inputs,
    trim: ControlCommands,
}

impl Schedule {
    pub fn new(inputs: Inputs, trim: ControlCommands) -> Self {
        Self { inputs, trim }
    }
}

impl Controller for Schedule {
    fn name(&self) -> &str {
        "schedule"
    }

    fn sample_interval_s(&self) -> Option<f64> {
        None
    }

    fn update(
        &mut self,
        outputs: &MeasuredOutputs,
        _state: &mut [f64],
        commands: &mut ControlCommands,
    ) -> Result<(), ModelError> {
        let trim = super::flight_controls(&self.trim);
        *commands = super::commands_of(&self.inputs.controls(&trim, outputs.time_s));
        Ok(())
    }
}

/// The `[simulation.inputs]` schedule of `ctx`.
pub fn schedule_inputs(ctx: &ControlContext<'_>) -> Result<Inputs, ModelError> {
    Inputs::from_table(ctx.schedule, ctx.file, "simulation.inputs").map_err(|e| {
        ModelError::Settings {
            file: ctx.file.to_owned(),
            key_path: e.key.clone(),
            message: e.message,
        }
    })
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ScheduleSettings {}

fn build(ctx: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    let _: ScheduleSettings = ctx.parse_settings()?;
    Ok(Box::new(Schedule::new(
        schedule_inputs(ctx)?,
        *ctx.trim_commands,
    )))
}

hsv_core::register_model!(ModelDescriptor {
    name: "schedule",
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 0,
    summary: "open loop: the [simulation.inputs] time tables (default the paper's elevon doublet) around trim",
    settings_doc: "(none: the tables are [simulation.inputs] symmetric_elevon_deg, differential_elevon_deg, fuel_equivalence_ratio)",
    constructor: Constructor::Control(build),
});
