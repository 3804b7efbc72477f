//! The host side of ABI 2: one safe adapter per role that owns a plugin model handle, implements
//! the same trait as the built-in models, checks every buffer size before a call and every
//! output after it (a NaN from a plugin is an error naming the quantity and panel).

use std::cell::RefCell;
use std::ffi::c_void;

use nalgebra::{DMatrix, DVector, Matrix3, Point3, Vector3};

use super::abi::*;
use super::convert::{
    MeshBuffers, RegionBuffers, control_region, design_model_json, edge_from, flatten_edges,
    flight_abi, state_feedback_from_json,
};
use crate::aero::{AeroModel, AeroSolution, Loads, PanelMotion};
use crate::control::{ControlCommands, Controller, DesignSource, MeasuredOutputs, StateFeedback};
use crate::error::ModelError;
use crate::flow::FlightCondition;
use crate::mesh::{ModeShapes, PanelMesh};
use crate::propulsion::{
    EngineInputs, EngineStatus, PropulsionModel, PropulsionSolution, StationState,
};
use crate::registry::ControlContext;
use crate::registry::ModelContext;
use crate::structure::{
    MassDistribution, MassProperties, ModalModel, RigidBodyCoupling, RigidDof, RootLoads,
    StructureModel, ThermalStiffness,
};
use crate::thermal::{
    ConductionModel, HeatFluxModel, SkinFriction, check_heat_flux_inputs, check_step_inputs,
    check_wall_shear_inputs,
};

mod aero;
mod conduction;
mod control;
mod heat_flux;
mod propulsion;
mod structure;

pub use aero::*;
pub use conduction::*;
pub use control::*;
pub use heat_flux::*;
pub use propulsion::*;
pub use structure::*;

/// Stations an engine may report through the ABI.
const STATION_CAPACITY: usize = 32;

/// A created plugin model: its entry, handle and name; destroyed on drop.
pub(crate) struct Handle {
    entry: &'static PluginModel,
    raw: *mut c_void,
    name: String,
    capabilities: u32,
}

// SAFETY: the plugin contract makes a model handle usable from any one thread at a time, which
// `&mut self` (or the single-threaded `&self` reads) of the owning adapter guarantees.
unsafe impl Send for Handle {}

/// The plugin's message for `raw` (or for the last failed create when null).
pub(crate) fn plugin_message(entry: &PluginModel, raw: *mut c_void) -> String {
    let mut buffer = vec![0u8; 1024];
    // SAFETY: the buffer is valid for `capacity` bytes; the plugin writes at most that many.
    let length = unsafe { (entry.last_error)(raw, buffer.as_mut_ptr(), buffer.len()) };
    buffer.truncate(length.min(buffer.len()));
    String::from_utf8_lossy(&buffer).into_owned()
}

impl Handle {
    /// Creates the model with the context's settings and region.
    pub(crate) fn create(
        entry: &'static PluginModel,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        let region = RegionBuffers::new(context.region);
        let (file, key_path) = (context.file, context.key_path);
        let settings = context.settings;
        Self::create_in(
            entry,
            name,
            settings,
            key_path,
            file,
            region.abi(context.region),
        )
    }

    /// Creates the model with `settings` (`[models.<name>]`, at `key_path` of `file`) for
    /// `region`.
    fn create_in(
        entry: &'static PluginModel,
        name: &str,
        settings: &toml::Table,
        key_path: &str,
        file: &str,
        region: RegionAbi,
    ) -> Result<Self, ModelError> {
        let settings = serde_json::to_string(settings).map_err(|e| {
            ModelError::inconsistent(name, format!("settings as JSON for the plugin: {e}"))
        })?;
        let args = CreateArgs {
            settings_json: StrAbi::new(&settings),
            key_path: StrAbi::new(key_path),
            file: StrAbi::new(file),
            region,
        };
        // SAFETY: `args` and everything it points at live across the call.
        let raw = unsafe { (entry.create)(&args) };
        if raw.is_null() {
            return Err(plugin_failure(name, "create", plugin_message(entry, raw)));
        }
        // SAFETY: a handle fresh from `create`.
        let capabilities = unsafe { (entry.capabilities)(raw) };
        Ok(Self {
            entry,
            raw,
            name: name.to_owned(),
            capabilities,
        })
    }

    fn has(&self, bit: u32) -> bool {
        self.capabilities & bit != 0
    }

    /// An error for a non-zero `status` of function `what`.
    fn check(&self, status: i32, what: &str) -> Result<(), ModelError> {
        if status == 0 {
            return Ok(());
        }
        Err(plugin_failure(
            &self.name,
            what,
            plugin_message(self.entry, self.raw),
        ))
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: the handle came from `create` and is destroyed once.
        unsafe { (self.entry.destroy)(self.raw) };
    }
}

/// The plugin's message under the model's name (without repeating a `name: ` prefix).
fn plugin_failure(name: &str, what: &str, message: String) -> ModelError {
    let message = message
        .strip_prefix(&format!("{name}: "))
        .map(str::to_owned)
        .unwrap_or(message);
    ModelError::inconsistent(name, format!("plugin {what} failed: {message}"))
}

/// The first non-finite value of `values` (grouped `per` to a panel) as an error.
fn check_finite(
    name: &str,
    quantity: &str,
    values: &[f64],
    per: usize,
    unit: &str,
) -> Result<(), ModelError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(ModelError::NonFinite {
            model: name.to_owned(),
            quantity: format!("{quantity} (from the plugin)"),
            location: format!(" at {unit} {}", i / per.max(1)),
        }),
    }
}

fn check_len(name: &str, what: &str, len: usize, expected: usize) -> Result<(), ModelError> {
    if len == expected {
        Ok(())
    } else {
        Err(ModelError::inconsistent(
            name,
            format!("{len} {what}, but the model takes {expected}"),
        ))
    }
}
