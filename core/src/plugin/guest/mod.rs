//! The plugin side of ABI 2: a model written against the same role traits as a built-in model
//! (with the same constructor signature) behind `extern "C"` functions over plain buffers.
//!
//! Every function rebuilds the core types from the host's buffers (reusing scratch), calls the
//! model inside `catch_unwind`, and copies the results out; an error or a panic becomes the
//! model's last error and a non-zero status, never an unwind across the boundary. Plugin authors
//! use [`crate::export_plugin!`]; this module is its machinery.

use std::cell::RefCell;
use std::ffi::c_void;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::OnceLock;

use nalgebra::{DVector, Vector3};

use super::abi::*;
use super::convert::{
    design_model_from_json, edge_from, flight_from_abi, mesh_from_abi, region_from_abi, slice,
    slice_mut, state_feedback_json, str_from,
};
use crate::aero::{AeroModel, AeroSolution, Loads, PanelMotion};
use crate::control::{
    ControlCommands, Controller, DesignSource, LinearDesignModel, MeasuredOutputs,
};
use crate::error::ModelError;
use crate::mesh::PanelMesh;
use crate::propulsion::{EngineInputs, EngineStatus, PropulsionModel, PropulsionSolution};
use crate::region::ModelSettings;
use crate::registry::{ControlContext, ControllerConstructor};
use crate::registry::{ModelContext, Registry};
use crate::structure::{RigidDof, StructureModel};
use crate::thermal::{ConductionModel, HeatFluxModel};

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

/// A role trait object that can be exported: its role code, function table and plugin-side state.
pub trait Exportable {
    /// The per-instance state behind a handle: the model and its scratch buffers.
    type State: Send + 'static;
    const ROLE: u32;
    /// The role's static function table.
    const FUNCTIONS: *const c_void;
    fn state(model: Box<Self>) -> Self::State;
    fn capabilities(state: &mut Self::State) -> u32;
}

/// What a handle points at.
pub struct Instance<S> {
    state: S,
    last_error: String,
}

thread_local! {
    static CREATE_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
}

fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned())
}

fn error_text(error: ModelError) -> String {
    error.to_string()
}

/// Runs `body` on the instance behind `handle`, catching panics; an error becomes the last error.
///
/// # Safety
/// `handle` must be null or come from `create` of a model whose state is `S`.
unsafe fn call<S>(
    handle: *mut c_void,
    what: &str,
    body: impl FnOnce(&mut S) -> Result<i32, String>,
) -> i32 {
    if handle.is_null() {
        return 1;
    }
    // SAFETY: per the contract above; the host serializes calls on one handle.
    let instance = unsafe { &mut *(handle as *mut Instance<S>) };
    let outcome = catch_unwind(AssertUnwindSafe(|| body(&mut instance.state)));
    match outcome {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            instance.last_error = message;
            2
        }
        Err(payload) => {
            instance.last_error = format!("plugin panicked in {what}: {}", panic_message(payload));
            3
        }
    }
}

/// Like [`call`] for functions that return a count: 0 on error.
unsafe fn call_count<S>(
    handle: *mut c_void,
    what: &str,
    body: impl FnOnce(&mut S) -> Result<usize, String>,
) -> usize {
    let mut count = 0;
    // SAFETY: forwarded contract.
    let status = unsafe {
        call::<S>(handle, what, |s| {
            count = body(s)?;
            Ok(0)
        })
    };
    if status == 0 { count } else { 0 }
}

fn guest_registry() -> &'static Registry {
    static EMPTY: OnceLock<Registry> = OnceLock::new();
    EMPTY.get_or_init(Registry::empty)
}

/// Builds a model from the host's `args` with `constructor`, as the registry would.
///
/// # Safety
/// `args` must be null or valid per the ABI.
pub unsafe fn create<M: ?Sized + Exportable>(
    args: *const CreateArgs,
    constructor: fn(&ModelContext<'_>) -> Result<Box<M>, ModelError>,
) -> *mut c_void {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if args.is_null() {
            return Err("create called without arguments".to_owned());
        }
        // SAFETY: per the contract above.
        let args = unsafe { &*args };
        let (json, key_path, file) = unsafe {
            (
                str_from(args.settings_json, "settings")?,
                str_from(args.key_path, "settings key path")?,
                str_from(args.file, "config file name")?,
            )
        };
        let table: toml::Table = if json.trim().is_empty() {
            toml::Table::new()
        } else {
            serde_json::from_str(json).map_err(|e| format!("settings are not a JSON table: {e}"))?
        };
        let settings = ModelSettings {
            table,
            key_path: key_path.to_owned(),
        };
        let model = key_path.rsplit('.').next().unwrap_or(key_path);
        let region = unsafe { region_from_abi(&args.region, model, settings.clone(), file)? };
        let context = ModelContext::new(&region, guest_registry(), &settings);
        constructor(&context).map_err(error_text)
    }));
    let outcome = match outcome {
        Ok(outcome) => outcome,
        Err(payload) => Err(format!(
            "plugin panicked in create: {}",
            panic_message(payload)
        )),
    };
    match outcome {
        Ok(model) => Box::into_raw(Box::new(Instance {
            state: M::state(model),
            last_error: String::new(),
        })) as *mut c_void,
        Err(message) => {
            CREATE_ERROR.with(|e| *e.borrow_mut() = message);
            std::ptr::null_mut()
        }
    }
}

/// # Safety
/// `handle` must come from `create` for state `S` and not be used afterwards.
pub unsafe extern "C" fn destroy<S>(handle: *mut c_void) {
    if !handle.is_null() {
        // SAFETY: per the contract above.
        let _ = catch_unwind(AssertUnwindSafe(|| unsafe {
            drop(Box::from_raw(handle as *mut Instance<S>))
        }));
    }
}

/// # Safety
/// `buffer` must be valid for `capacity` bytes; `handle` null or from `create` for state `S`.
pub unsafe extern "C" fn last_error<S>(
    handle: *mut c_void,
    buffer: *mut u8,
    capacity: usize,
) -> usize {
    let message = if handle.is_null() {
        CREATE_ERROR.with(|e| e.borrow().clone())
    } else {
        // SAFETY: per the contract above.
        unsafe { (*(handle as *mut Instance<S>)).last_error.clone() }
    };
    copy_text(&message, buffer, capacity)
}

fn copy_text(message: &str, buffer: *mut u8, capacity: usize) -> usize {
    let bytes = message.as_bytes();
    let copied = bytes.len().min(capacity);
    if copied > 0 && !buffer.is_null() {
        // SAFETY: `copied` fits both buffers.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), buffer, copied) };
    }
    bytes.len()
}

/// # Safety
/// `handle` must be null or come from `create` for `M`.
pub unsafe extern "C" fn capabilities<M: ?Sized + Exportable>(handle: *mut c_void) -> u32 {
    let mut bits = 0;
    // SAFETY: forwarded contract.
    unsafe {
        call::<M::State>(handle, "capabilities", |s| {
            bits = M::capabilities(s);
            Ok(0)
        })
    };
    bits
}

/// The model entry of one exported model (used by [`crate::plugin_header!`]).
pub const fn model_entry<M: ?Sized + Exportable>(
    name: &'static str,
    fidelity: u8,
    summary: &'static str,
    settings_doc: &'static str,
    create: CreateFn,
) -> PluginModel {
    PluginModel {
        role: M::ROLE,
        fidelity: fidelity as u32,
        name: StrAbi::new(name),
        summary: StrAbi::new(summary),
        settings_doc: StrAbi::new(settings_doc),
        create,
        destroy: destroy::<M::State>,
        last_error: last_error::<M::State>,
        capabilities: capabilities::<M>,
        functions: M::FUNCTIONS,
    }
}

/// A static [`super::PluginHeader`] over models built by constructors with the built-in signature:
///
/// ```ignore
/// hsv_core::plugin_header! {
///     static HEADER = [
///         heat_flux { name: "my-model", fidelity: 0, summary: "...", settings: "", constructor: construct },
///     ];
/// }
/// ```
/// Roles: `aero`, `heat_flux`, `conduction`, `structure`, `propulsion`, `control` (a
/// [`crate::registry::ControllerConstructor`]). [`crate::export_plugin!`]
/// adds the entry point; this macro alone serves in-process tables (tests).
#[macro_export]
macro_rules! plugin_header {
    ($(#[$meta:meta])* $vis:vis static $header:ident = [ $(
        $role:ident {
            name: $name:expr,
            fidelity: $fidelity:expr,
            summary: $summary:expr,
            settings: $settings:expr,
            constructor: $constructor:expr $(,)?
        }
    ),+ $(,)? ];) => {
        $(#[$meta])*
        $vis static $header: $crate::plugin::PluginHeader = {
            const MODELS: &[$crate::plugin::PluginModel] = &[$(
                $crate::__hsv_plugin_model!($role, $name, $fidelity, $summary, $settings, $constructor)
            ),+];
            $crate::plugin::PluginHeader::v2(MODELS)
        };
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __hsv_plugin_model {
    (aero, $($rest:tt)*) => {
        $crate::__hsv_plugin_model!(@ dyn $crate::aero::AeroModel, $($rest)*)
    };
    (heat_flux, $($rest:tt)*) => {
        $crate::__hsv_plugin_model!(@ dyn $crate::thermal::HeatFluxModel, $($rest)*)
    };
    (conduction, $($rest:tt)*) => {
        $crate::__hsv_plugin_model!(@ dyn $crate::thermal::ConductionModel, $($rest)*)
    };
    (structure, $($rest:tt)*) => {
        $crate::__hsv_plugin_model!(@ dyn $crate::structure::StructureModel, $($rest)*)
    };
    (propulsion, $($rest:tt)*) => {
        $crate::__hsv_plugin_model!(@ dyn $crate::propulsion::PropulsionModel, $($rest)*)
    };
    (control, $name:expr, $fidelity:expr, $summary:expr, $settings:expr, $constructor:expr) => {{
        unsafe extern "C" fn create(
            args: *const $crate::plugin::CreateArgs,
        ) -> *mut ::std::ffi::c_void {
            // SAFETY: the host passes arguments that follow the ABI.
            unsafe { $crate::plugin::guest::create_controller(args, $constructor) }
        }
        $crate::plugin::guest::model_entry::<dyn $crate::control::Controller>(
            $name, $fidelity, $summary, $settings, create,
        )
    }};
    (@ $trait:ty, $name:expr, $fidelity:expr, $summary:expr, $settings:expr, $constructor:expr) => {{
        unsafe extern "C" fn create(
            args: *const $crate::plugin::CreateArgs,
        ) -> *mut ::std::ffi::c_void {
            // SAFETY: the host passes arguments that follow the ABI.
            unsafe { $crate::plugin::guest::create::<$trait>(args, $constructor) }
        }
        $crate::plugin::guest::model_entry::<$trait>($name, $fidelity, $summary, $settings, create)
    }};
}

/// Exports models as an hsv plugin (ABI 2): the [`crate::plugin_header!`] table plus the
/// `hsv_plugin_entry` symbol. Each model is a constructor with the built-in signature
/// (`fn(&ModelContext) -> Result<Box<dyn Role>, ModelError>`), so a plugin model is written
/// exactly like a built-in one:
///
/// ```ignore
/// hsv_core::export_plugin! [
///     heat_flux { name: "my-model", fidelity: 0, summary: "...", settings: "", constructor: construct },
/// ];
/// ```
#[macro_export]
macro_rules! export_plugin {
    ($($models:tt)+) => {
        $crate::plugin_header! {
            static __HSV_PLUGIN_HEADER = [ $($models)+ ];
        }
        /// The hsv plugin entry point.
        #[unsafe(no_mangle)]
        pub extern "C" fn hsv_plugin_entry() -> *const $crate::plugin::PluginHeader {
            &__HSV_PLUGIN_HEADER
        }
    };
}
