//! Plugin ABI version 1 (aero models only), kept so plugins built against it still load and
//! plugin sources written for it still compile.
//!
//! A v1 header has the same layout as a v2 one ([`super::PluginHeader`]); its `models` point at
//! [`PluginModelTable`]s. New plugins use ABI version 2 ([`crate::export_plugin!`]).

use std::ffi::{CStr, c_char, c_void};
use std::sync::Arc;

use nalgebra::Vector3;

use crate::aero::{AeroModel, AeroSolution, EdgeState, PanelMotion};
use crate::error::ModelError;
use crate::flow::FlightCondition;
use crate::mesh::PanelMesh;
use crate::registry::{Factory, Origin, RegistryEntry};

use super::{PluginError, bad_header};

/// ABI version of this module's tables.
pub const ABI_VERSION: u32 = 1;
/// Plugin API version v1 plugins declare.
pub const API_VERSION: (u32, u32, u32) = (1, 0, 0);
/// Role code of an aero model in [`PluginModelTable::role`] (the only role of ABI 1).
pub const PLUGIN_ROLE_AERO: u32 = 0;

/// One model of a plugin: descriptor strings and its functions.
#[repr(C)]
pub struct PluginModelTable {
    pub role: u32,
    /// NUL-terminated UTF-8, static.
    pub name: *const c_char,
    pub summary: *const c_char,
    pub settings_doc: *const c_char,
    pub fidelity: u32,
    /// Builds a model from its settings as JSON bytes; null on error (then `last_error(null)`).
    pub create: unsafe extern "C" fn(settings_json: *const u8, len: usize) -> *mut c_void,
    /// Evaluates an aero model; 0 on success, non-zero on error (then `last_error(handle)`).
    pub evaluate_aero: unsafe extern "C" fn(
        handle: *mut c_void,
        input: *const AeroInputAbi,
        output: *mut AeroOutputAbi,
    ) -> i32,
    pub destroy: unsafe extern "C" fn(handle: *mut c_void),
    /// Copies the last error message (UTF-8, no NUL) of `handle` (or of the last failed
    /// `create` when null) into `buffer`; returns its full length.
    pub last_error:
        unsafe extern "C" fn(handle: *mut c_void, buffer: *mut u8, capacity: usize) -> usize,
}

unsafe impl Sync for PluginModelTable {}

/// Freestream and vehicle motion, SI units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreestreamAbi {
    pub mach: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
    pub velocity_m_s: f64,
    pub gamma: f64,
    pub gas_constant_j_kg_k: f64,
    /// Vehicle velocity relative to the air, body axes, m/s.
    pub vehicle_velocity_body_m_s: [f64; 3],
}

/// Panel geometry and motion as flat arrays (x, y, z interleaved).
#[repr(C)]
pub struct AeroInputAbi {
    pub freestream: FreestreamAbi,
    pub n_panels: usize,
    pub centroid_m: *const f64,
    pub normal: *const f64,
    pub area_m2: *const f64,
    /// Velocity of each panel relative to the air (rigid-body plus elastic), body axes, m/s.
    pub panel_velocity_m_s: *const f64,
    /// Strip `s` holds `strip_panels[strip_offsets[s]..strip_offsets[s + 1]]`, upstream first.
    pub n_strips: usize,
    pub strip_offsets: *const usize,
    pub strip_panels: *const usize,
}

/// Where a plugin writes its results: `n_panels` pressures (Pa) and `5 n_panels` edge values
/// (Mach, pressure Pa, temperature K, density kg/m³, velocity m/s per panel).
#[repr(C)]
pub struct AeroOutputAbi {
    pub pressure_pa: *mut f64,
    pub edge: *mut f64,
}

/// Reads a static C string of a v1 table.
///
/// # Safety
/// `pointer` must be null or a NUL-terminated static string.
unsafe fn plugin_str(
    pointer: *const c_char,
    what: &str,
    origin: &str,
) -> Result<String, PluginError> {
    if pointer.is_null() {
        return Err(bad_header(origin, format!("{what} is null")));
    }
    // SAFETY: per the contract above.
    let text = unsafe { CStr::from_ptr(pointer) };
    text.to_str()
        .map(str::to_owned)
        .map_err(|_| bad_header(origin, format!("{what} is not UTF-8")))
}

/// The registry entry of one ABI-1 model table.
///
/// # Safety
/// `table` must follow ABI 1.
pub(super) unsafe fn entry(
    table: &'static PluginModelTable,
    origin: &str,
) -> Result<RegistryEntry, PluginError> {
    // SAFETY: per the contract above.
    let name = unsafe { plugin_str(table.name, "model name", origin)? };
    if table.role != PLUGIN_ROLE_AERO {
        return Err(bad_header(
            origin,
            format!(
                "model `{name}` has role code {}; ABI version 1 carries aero models (code 0) only",
                table.role
            ),
        ));
    }
    let fidelity = u8::try_from(table.fidelity).unwrap_or(u8::MAX);
    let summary = unsafe { plugin_str(table.summary, "summary", origin)? };
    let settings_doc = unsafe { plugin_str(table.settings_doc, "settings doc", origin)? };
    let model_name = name.clone();
    Ok(RegistryEntry {
        name,
        fidelity,
        summary,
        settings_doc,
        origin: Origin::Plugin(origin.to_owned()),
        factory: Factory::Aero(Arc::new(move |context| {
            let settings = serde_json::to_vec(context.settings).map_err(|e| {
                ModelError::inconsistent(&model_name, format!("settings to JSON: {e}"))
            })?;
            PluginAeroModel::create(table, &model_name, &settings)
                .map(|m| Box::new(m) as Box<dyn AeroModel>)
        })),
    })
}

/// Copies a plugin's last error message.
fn plugin_error(table: &PluginModelTable, handle: *mut c_void) -> String {
    let mut buffer = vec![0u8; 512];
    // SAFETY: the buffer is valid for `capacity` bytes; the plugin writes at most that many.
    let length = unsafe { (table.last_error)(handle, buffer.as_mut_ptr(), buffer.len()) };
    buffer.truncate(length.min(buffer.len()));
    String::from_utf8_lossy(&buffer).into_owned()
}

/// A plugin aero model behind the same trait as the built-in ones.
pub struct PluginAeroModel {
    table: &'static PluginModelTable,
    handle: *mut c_void,
    name: String,
    centroid: Vec<f64>,
    normal: Vec<f64>,
    area: Vec<f64>,
    velocity: Vec<f64>,
    strip_offsets: Vec<usize>,
    strip_panels: Vec<usize>,
    edge: Vec<f64>,
}

// SAFETY: the plugin contract makes a model handle usable from any one thread at a time, which
// `&mut self` on every call guarantees.
unsafe impl Send for PluginAeroModel {}

impl PluginAeroModel {
    pub(super) fn create(
        table: &'static PluginModelTable,
        name: &str,
        settings_json: &[u8],
    ) -> Result<Self, ModelError> {
        // SAFETY: pointer and length describe `settings_json`.
        let handle = unsafe { (table.create)(settings_json.as_ptr(), settings_json.len()) };
        if handle.is_null() {
            return Err(ModelError::inconsistent(
                name,
                format!(
                    "plugin could not create the model: {}",
                    plugin_error(table, handle)
                ),
            ));
        }
        Ok(Self {
            table,
            handle,
            name: name.to_owned(),
            centroid: Vec::new(),
            normal: Vec::new(),
            area: Vec::new(),
            velocity: Vec::new(),
            strip_offsets: Vec::new(),
            strip_panels: Vec::new(),
            edge: Vec::new(),
        })
    }
}

impl Drop for PluginAeroModel {
    fn drop(&mut self) {
        // SAFETY: the handle came from `create` and is destroyed once.
        unsafe { (self.table.destroy)(self.handle) };
    }
}

impl AeroModel for PluginAeroModel {
    fn name(&self) -> &str {
        &self.name
    }

    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        let n = mesh.panels.len();
        self.centroid.clear();
        self.normal.clear();
        self.area.clear();
        self.velocity.clear();
        let panel_velocity = motion.velocity_of_panels(flight, mesh);
        for (i, panel) in mesh.panels.iter().enumerate() {
            self.centroid
                .extend_from_slice(panel.centroid.coords.as_slice());
            self.normal.extend_from_slice(panel.normal.as_slice());
            self.area.push(panel.area_m2);
            let v: Vector3<f64> = panel_velocity(i);
            self.velocity.extend_from_slice(v.as_slice());
        }
        self.strip_offsets.clear();
        self.strip_panels.clear();
        self.strip_offsets.push(0);
        for strip in &mesh.strips {
            self.strip_panels.extend_from_slice(&strip.panels);
            self.strip_offsets.push(self.strip_panels.len());
        }
        let f = &flight.freestream;
        let v = flight.velocity_body_m_s();
        let input = AeroInputAbi {
            freestream: FreestreamAbi {
                mach: f.mach,
                pressure_pa: f.pressure_pa,
                temperature_k: f.temperature_k,
                density_kg_m3: f.density_kg_m3,
                speed_of_sound_m_s: f.speed_of_sound_m_s,
                velocity_m_s: f.velocity_m_s,
                gamma: f.gas.gamma,
                gas_constant_j_kg_k: f.gas.gas_constant_j_kg_k,
                vehicle_velocity_body_m_s: [v.x, v.y, v.z],
            },
            n_panels: n,
            centroid_m: self.centroid.as_ptr(),
            normal: self.normal.as_ptr(),
            area_m2: self.area.as_ptr(),
            panel_velocity_m_s: self.velocity.as_ptr(),
            n_strips: mesh.strips.len(),
            strip_offsets: self.strip_offsets.as_ptr(),
            strip_panels: self.strip_panels.as_ptr(),
        };
        out.reset(n);
        self.edge.clear();
        self.edge.resize(5 * n, 0.0);
        let mut output = AeroOutputAbi {
            pressure_pa: out.pressure_pa.as_mut_ptr(),
            edge: self.edge.as_mut_ptr(),
        };
        // SAFETY: every pointer is valid for the lengths the ABI states for `n` panels.
        let status = unsafe { (self.table.evaluate_aero)(self.handle, &input, &mut output) };
        if status != 0 {
            return Err(ModelError::inconsistent(
                &self.name,
                format!(
                    "plugin evaluation failed: {}",
                    plugin_error(self.table, self.handle)
                ),
            ));
        }
        for (i, edge) in out.edge.iter_mut().enumerate() {
            let e = &self.edge[5 * i..5 * i + 5];
            *edge = EdgeState {
                mach: e[0],
                pressure_pa: e[1],
                temperature_k: e[2],
                density_kg_m3: e[3],
                velocity_m_s: e[4],
            };
        }
        if let Some(bad) = out.pressure_pa.iter().position(|p| !p.is_finite()) {
            return Err(ModelError::NonFinite {
                model: self.name.clone(),
                quantity: "pressure".to_owned(),
                location: format!(" on panel {bad}"),
            });
        }
        Ok(())
    }
}

/// What a plugin aero model sees: safe slices over the host's buffers.
pub struct PluginAeroInput<'a> {
    pub freestream: FreestreamAbi,
    pub centroid_m: &'a [[f64; 3]],
    pub normal: &'a [[f64; 3]],
    pub area_m2: &'a [f64],
    pub panel_velocity_m_s: &'a [[f64; 3]],
    /// Panel indices of each strip, upstream first.
    pub strips: Vec<&'a [usize]>,
}

/// Where a plugin aero model writes: pressure (Pa) and edge state per panel.
pub struct PluginAeroOutput<'a> {
    pub pressure_pa: &'a mut [f64],
    /// Per panel: Mach, pressure Pa, temperature K, density kg/m³, velocity m/s.
    pub edge: &'a mut [[f64; 5]],
}

/// The trait a plugin author implements; [`export_aero_plugin!`](crate::export_aero_plugin) turns it into the C table.
pub trait PluginAero: Sized {
    /// Builds the model from its settings (the `[models.<name>]` table, as JSON).
    fn create(settings: &serde_json::Value) -> Result<Self, String>;
    /// Fills `output` for the panels in `input`.
    fn evaluate(
        &mut self,
        input: &PluginAeroInput<'_>,
        output: &mut PluginAeroOutput<'_>,
    ) -> Result<(), String>;
}

/// Plugin-side glue used by [`export_aero_plugin!`](crate::export_aero_plugin); not for hosts.
#[doc(hidden)]
pub mod export {
    use super::*;
    use std::cell::RefCell;
    use std::panic::{AssertUnwindSafe, catch_unwind};

    thread_local! {
        static CREATE_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
    }

    /// A model instance with its last error.
    pub struct Instance<M> {
        pub model: M,
        pub last_error: String,
    }

    fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
        payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".to_owned())
    }

    /// # Safety
    /// `settings` must be valid for `len` bytes.
    pub unsafe fn create<M: PluginAero>(settings: *const u8, len: usize) -> *mut c_void {
        let result = catch_unwind(AssertUnwindSafe(|| {
            let bytes = if len == 0 {
                &[][..]
            } else {
                // SAFETY: caller guarantees validity.
                unsafe { std::slice::from_raw_parts(settings, len) }
            };
            let value: serde_json::Value = if bytes.is_empty() {
                serde_json::Value::Object(Default::default())
            } else {
                serde_json::from_slice(bytes).map_err(|e| format!("settings are not JSON: {e}"))?
            };
            M::create(&value)
        }));
        let outcome = match result {
            Ok(outcome) => outcome,
            Err(payload) => Err(format!(
                "plugin panicked in create: {}",
                panic_message(payload)
            )),
        };
        match outcome {
            Ok(model) => Box::into_raw(Box::new(Instance {
                model,
                last_error: String::new(),
            })) as *mut c_void,
            Err(message) => {
                CREATE_ERROR.with(|e| *e.borrow_mut() = message);
                std::ptr::null_mut()
            }
        }
    }

    /// # Safety
    /// `handle` must come from [`create`] for `M`; `input`/`output` must follow the ABI.
    pub unsafe fn evaluate<M: PluginAero>(
        handle: *mut c_void,
        input: *const AeroInputAbi,
        output: *mut AeroOutputAbi,
    ) -> i32 {
        if handle.is_null() || input.is_null() || output.is_null() {
            return 1;
        }
        // SAFETY: per the contract above.
        let instance = unsafe { &mut *(handle as *mut Instance<M>) };
        let (input, output) = unsafe { (&*input, &mut *output) };
        let n = input.n_panels;
        // SAFETY: the host passes arrays of the lengths the ABI states.
        let (view, mut out) = unsafe {
            let offsets = std::slice::from_raw_parts(input.strip_offsets, input.n_strips + 1);
            let total = offsets.last().copied().unwrap_or(0);
            let panels = std::slice::from_raw_parts(input.strip_panels, total);
            let strips = offsets.windows(2).map(|w| &panels[w[0]..w[1]]).collect();
            (
                PluginAeroInput {
                    freestream: input.freestream,
                    centroid_m: std::slice::from_raw_parts(input.centroid_m as *const [f64; 3], n),
                    normal: std::slice::from_raw_parts(input.normal as *const [f64; 3], n),
                    area_m2: std::slice::from_raw_parts(input.area_m2, n),
                    panel_velocity_m_s: std::slice::from_raw_parts(
                        input.panel_velocity_m_s as *const [f64; 3],
                        n,
                    ),
                    strips,
                },
                PluginAeroOutput {
                    pressure_pa: std::slice::from_raw_parts_mut(output.pressure_pa, n),
                    edge: std::slice::from_raw_parts_mut(output.edge as *mut [f64; 5], n),
                },
            )
        };
        let result = catch_unwind(AssertUnwindSafe(|| {
            instance.model.evaluate(&view, &mut out)
        }));
        let message = match result {
            Ok(Ok(())) => return 0,
            Ok(Err(message)) => message,
            Err(payload) => format!("plugin panicked in evaluate: {}", panic_message(payload)),
        };
        instance.last_error = message;
        2
    }

    /// # Safety
    /// `handle` must come from [`create`] for `M` and not be used afterwards.
    pub unsafe fn destroy<M: PluginAero>(handle: *mut c_void) {
        if !handle.is_null() {
            // SAFETY: per the contract above.
            let _ = catch_unwind(AssertUnwindSafe(|| unsafe {
                drop(Box::from_raw(handle as *mut Instance<M>))
            }));
        }
    }

    /// # Safety
    /// `buffer` must be valid for `capacity` bytes; `handle` null or from [`create`] for `M`.
    pub unsafe fn last_error<M: PluginAero>(
        handle: *mut c_void,
        buffer: *mut u8,
        capacity: usize,
    ) -> usize {
        let message = if handle.is_null() {
            CREATE_ERROR.with(|e| e.borrow().clone())
        } else {
            // SAFETY: per the contract above.
            unsafe { (*(handle as *mut Instance<M>)).last_error.clone() }
        };
        let bytes = message.as_bytes();
        let copied = bytes.len().min(capacity);
        // SAFETY: `copied` fits both buffers.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), buffer, copied) };
        bytes.len()
    }
}

/// Exports one aero model type implementing [`PluginAero`] as an ABI-1 hsv plugin (kept for
/// existing plugin sources; new plugins use [`crate::export_plugin!`]):
/// `hsv_core::export_aero_plugin!(MyModel, name: "my-model", fidelity: 1, summary: "...", settings: "...");`
#[macro_export]
macro_rules! export_aero_plugin {
    ($model:ty, name: $name:literal, fidelity: $fidelity:literal, summary: $summary:literal, settings: $settings:literal $(,)?) => {
        unsafe extern "C" fn __hsv_create(
            settings: *const u8,
            len: usize,
        ) -> *mut ::std::ffi::c_void {
            unsafe { $crate::plugin::v1::export::create::<$model>(settings, len) }
        }
        unsafe extern "C" fn __hsv_evaluate(
            handle: *mut ::std::ffi::c_void,
            input: *const $crate::plugin::v1::AeroInputAbi,
            output: *mut $crate::plugin::v1::AeroOutputAbi,
        ) -> i32 {
            unsafe { $crate::plugin::v1::export::evaluate::<$model>(handle, input, output) }
        }
        unsafe extern "C" fn __hsv_destroy(handle: *mut ::std::ffi::c_void) {
            unsafe { $crate::plugin::v1::export::destroy::<$model>(handle) }
        }
        unsafe extern "C" fn __hsv_last_error(
            handle: *mut ::std::ffi::c_void,
            buffer: *mut u8,
            capacity: usize,
        ) -> usize {
            unsafe { $crate::plugin::v1::export::last_error::<$model>(handle, buffer, capacity) }
        }
        static __HSV_MODELS: [$crate::plugin::v1::PluginModelTable; 1] =
            [$crate::plugin::v1::PluginModelTable {
                role: $crate::plugin::v1::PLUGIN_ROLE_AERO,
                name: concat!($name, "\0").as_ptr() as *const ::std::ffi::c_char,
                summary: concat!($summary, "\0").as_ptr() as *const ::std::ffi::c_char,
                settings_doc: concat!($settings, "\0").as_ptr() as *const ::std::ffi::c_char,
                fidelity: $fidelity,
                create: __hsv_create,
                evaluate_aero: __hsv_evaluate,
                destroy: __hsv_destroy,
                last_error: __hsv_last_error,
            }];
        static __HSV_HEADER: $crate::plugin::PluginHeader = $crate::plugin::PluginHeader {
            magic: $crate::plugin::PLUGIN_MAGIC,
            abi_version: $crate::plugin::v1::ABI_VERSION,
            api_version: [
                $crate::plugin::v1::API_VERSION.0,
                $crate::plugin::v1::API_VERSION.1,
                $crate::plugin::v1::API_VERSION.2,
            ],
            model_count: 1,
            models: &__HSV_MODELS as *const $crate::plugin::v1::PluginModelTable
                as *const ::std::ffi::c_void,
        };
        /// The hsv plugin entry point.
        #[unsafe(no_mangle)]
        pub extern "C" fn hsv_plugin_entry() -> *const $crate::plugin::PluginHeader {
            &__HSV_HEADER
        }
    };
}
