//! The dylib plugin ABI: a C header with role-tagged function tables over plain numeric buffers,
//! the host that loads and checks it, and safe adapters that make plugin models normal trait
//! objects.
//!
//! Rust trait objects have no stable ABI and `inventory` does not cross a dylib boundary, so a
//! plugin exports one `extern "C"` function, [`PLUGIN_ENTRY_SYMBOL`], returning a
//! [`PluginHeader`]: magic bytes, ABI version, plugin-API semver and a table of models. The
//! header layout is the same in every ABI version, so the host reads `abi_version` before it
//! decides what `models` points at:
//!
//! * **ABI 2** ([`PluginModel`], module [`abi`]): any number of models of the six roles (aero,
//!   heat flux, conduction, structure, propulsion and, since API 2.1, control). Each entry has a role code, descriptor
//!   strings, `create` (settings as JSON plus the region's name, kind, side, mesh, reference
//!   values, gas and parametric geometry as plain data), `destroy`, `last_error`,
//!   `capabilities`, and a pointer to its role's function table ([`AeroFunctions`],
//!   [`HeatFluxFunctions`], [`ConductionFunctions`], [`StructureFunctions`],
//!   [`PropulsionFunctions`], [`ControlFunctions`]) carrying what coupling needs: panel geometry and elastic panel
//!   velocities in and pressures and edge states out (aero); edge states and wall temperatures
//!   in, heat flux or wall shear out (heat flux); state, surface heat flux and the three
//!   temperature read-outs (conduction); modal matrices, mode names, frequencies, mode shapes on
//!   a mesh's vertices, temperature updates, thermal generalized forces, root loads, mass
//!   properties and rigid-body coupling (structure); engine loads, mass flow, status, owned-panel
//!   pressures and station states (propulsion); the trim point, the linear design models on
//!   request, measured outputs, the host-owned state and commands (control).
//! * **ABI 1** ([`v1`]): one or more aero models over panel geometry; still loaded.
//!
//! The host checks magic, ABI and API versions before calling anything else, never unloads the
//! library, wraps each model in an adapter implementing the same role trait as built-in models
//! (module [`host`]) that checks buffer sizes before each call and rejects non-finite outputs
//! after it, and turns every mismatch into an error. Plugin authors write an ordinary model and
//! constructor (as for [`crate::register_model!`]) and export it with [`crate::export_plugin!`],
//! whose glue (module [`guest`]) catches panics at the boundary, so a bug in a plugin is an error
//! in the host, never an abort.

pub mod abi;
mod convert;
pub mod guest;
pub mod host;
pub mod v1;

use std::ffi::c_void;
use std::path::Path;
use std::sync::Arc;

pub use abi::*;
pub use host::{
    AeroAdapter, ConductionAdapter, ControllerAdapter, HeatFluxAdapter, PropulsionAdapter,
    StructureAdapter,
};
/// The ABI-1 plugin-side trait and views, kept so v1 plugin sources compile.
pub use v1::{PluginAero, PluginAeroInput, PluginAeroOutput};

use crate::aero::AeroModel;
use crate::control::Controller;
use crate::propulsion::PropulsionModel;
use crate::registry::{Factory, Origin, Registry, RegistryEntry, RegistryError};
use crate::structure::StructureModel;
use crate::thermal::{ConductionModel, HeatFluxModel};

/// First bytes of every [`PluginHeader`].
pub const PLUGIN_MAGIC: [u8; 8] = *b"HSVPLUG\0";
/// Layout version of the tables this hsv-core writes ([`PluginModel`]); it also reads
/// version 1 ([`v1`]).
pub const PLUGIN_ABI_VERSION: u32 = 2;
/// Semver of the ABI-2 plugin API (the meaning of the fields): the host accepts the same major
/// and a minor up to its own.
/// 2.1 added the control role ([`PLUGIN_ROLE_CONTROL`], [`ControlFunctions`]).
pub const PLUGIN_API_VERSION: (u32, u32, u32) = (2, 1, 0);
/// Name of the entry point a plugin exports: `extern "C" fn() -> *const PluginHeader`.
pub const PLUGIN_ENTRY_SYMBOL: &str = "hsv_plugin_entry";

/// What a plugin's entry point returns; must live for the life of the process. The layout is
/// the same in every ABI version; `models` points at `model_count` tables of the version's type.
#[repr(C)]
pub struct PluginHeader {
    pub magic: [u8; 8],
    pub abi_version: u32,
    pub api_version: [u32; 3],
    pub model_count: u32,
    /// `*const PluginModel` (ABI 2) or `*const v1::PluginModelTable` (ABI 1).
    pub models: *const c_void,
}

// SAFETY: the header is immutable static data.
unsafe impl Sync for PluginHeader {}

impl PluginHeader {
    /// An ABI-2 header over `models` (what [`crate::plugin_header!`] builds).
    pub const fn v2(models: &'static [PluginModel]) -> Self {
        Self {
            magic: PLUGIN_MAGIC,
            abi_version: PLUGIN_ABI_VERSION,
            api_version: [
                PLUGIN_API_VERSION.0,
                PLUGIN_API_VERSION.1,
                PLUGIN_API_VERSION.2,
            ],
            model_count: models.len() as u32,
            models: models.as_ptr() as *const c_void,
        }
    }
}

/// Why a plugin could not be loaded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PluginError {
    #[error("plugin {path}: cannot load the library: {message}")]
    Load { path: String, message: String },
    #[error(
        "plugin {path}: no `{PLUGIN_ENTRY_SYMBOL}` entry point; is it an hsv plugin? ({message})"
    )]
    NoEntry { path: String, message: String },
    #[error("plugin {path}: {message}")]
    BadHeader { path: String, message: String },
    /// A model name the plugin registers is taken or malformed.
    #[error(transparent)]
    Register(#[from] RegistryError),
}

fn bad_header(origin: &str, message: impl Into<String>) -> PluginError {
    PluginError::BadHeader {
        path: origin.to_owned(),
        message: message.into(),
    }
}

impl Registry {
    /// Loads the dylib plugin at `path` and registers its models; returns how many.
    pub fn load_plugin(&mut self, path: &Path) -> Result<usize, PluginError> {
        let entries = load_plugin(path)?;
        self.insert_plugin_entries(entries)
    }

    /// Registers the models of a plugin header that is already in this process (a plugin
    /// linked statically, or a table built in a test); `origin` names it in messages.
    ///
    /// # Safety
    /// `header` must satisfy the plugin ABI: its tables and functions are trusted as a loaded
    /// plugin's would be.
    pub unsafe fn register_plugin_header(
        &mut self,
        header: &'static PluginHeader,
        origin: &str,
    ) -> Result<usize, PluginError> {
        // SAFETY: forwarded contract.
        let entries = unsafe { plugin_entries(header, origin)? };
        self.insert_plugin_entries(entries)
    }

    /// Inserts all of `entries` or none (a duplicate name leaves the registry unchanged).
    fn insert_plugin_entries(&mut self, entries: Vec<RegistryEntry>) -> Result<usize, PluginError> {
        let mut staged = self.clone();
        let count = entries.len();
        for entry in entries {
            staged.insert(entry)?;
        }
        *self = staged;
        Ok(count)
    }
}

/// The loader's error with its cause: libloading says only "dlopen failed" and keeps the
/// system's reason (`dlerror`: no such file, invalid ELF header, missing symbol) as the source.
fn loader_message(error: &libloading::Error) -> String {
    match std::error::Error::source(error) {
        Some(cause) => format!("{error}: {cause}"),
        None => error.to_string(),
    }
}

/// `path` as a file path: a bare name (`libmy_plugin.so`) gets a `./` prefix, because the
/// dynamic loader searches the system library path for names without a directory, so a bare
/// name would load whatever library of that name the system has, not the file here.
fn local_path(path: &Path) -> std::path::PathBuf {
    let mut components = path.components();
    match (components.next(), components.next()) {
        (Some(std::path::Component::Normal(_)), None) => Path::new(".").join(path),
        _ => path.to_path_buf(),
    }
}

/// Loads the plugin at `path`, checks its header and returns one registry entry per model.
///
/// The library is never unloaded: plugin code may be referenced by models for the rest of the run.
pub fn load_plugin(path: &Path) -> Result<Vec<RegistryEntry>, PluginError> {
    let path = &local_path(path);
    let shown = path.display().to_string();
    // SAFETY: loading a library runs its initialisers; that is the trust a user gives a plugin.
    let library = unsafe { libloading::Library::new(path) }.map_err(|e| PluginError::Load {
        path: shown.clone(),
        message: loader_message(&e),
    })?;
    let library: &'static libloading::Library = Box::leak(Box::new(library));
    // SAFETY: the symbol's type is fixed by the ABI; checked through the header below.
    let entry: libloading::Symbol<'static, unsafe extern "C" fn() -> *const PluginHeader> =
        unsafe { library.get(PLUGIN_ENTRY_SYMBOL.as_bytes()) }.map_err(|e| {
            PluginError::NoEntry {
                path: shown.clone(),
                message: loader_message(&e),
            }
        })?;
    // SAFETY: calling the entry point the plugin exported for this purpose.
    let header = unsafe { entry() };
    // SAFETY: null or, by contract, a static header; checked field by field before use.
    let header = unsafe { header.as_ref() }
        .ok_or_else(|| bad_header(&shown, "entry point returned null"))?;
    // SAFETY: the header came from the plugin's own entry point.
    unsafe { plugin_entries(header, &shown) }
}

/// Checks `header` (magic, ABI version, API version, model table) and returns one registry
/// entry per model.
///
/// # Safety
/// `header` must point at static plugin data that follows the ABI its `abi_version` names.
pub unsafe fn plugin_entries(
    header: &'static PluginHeader,
    origin: &str,
) -> Result<Vec<RegistryEntry>, PluginError> {
    if header.magic != PLUGIN_MAGIC {
        return Err(bad_header(origin, "wrong magic bytes: not an hsv plugin"));
    }
    let [major, minor, patch] = header.api_version;
    let (host_major, host_minor, host_patch) = match header.abi_version {
        v1::ABI_VERSION => v1::API_VERSION,
        PLUGIN_ABI_VERSION => PLUGIN_API_VERSION,
        other => {
            return Err(bad_header(
                origin,
                format!(
                    "ABI version {other}, but this hsv-run reads versions 1 and {PLUGIN_ABI_VERSION}; rebuild the plugin against this hsv-core"
                ),
            ));
        }
    };
    if major != host_major || minor > host_minor {
        return Err(bad_header(
            origin,
            format!(
                "plugin API {major}.{minor}.{patch} is incompatible with {host_major}.{host_minor}.{host_patch} (ABI {}): rebuild the plugin against this hsv-core",
                header.abi_version
            ),
        ));
    }
    if header.model_count == 0 || header.models.is_null() {
        return Err(bad_header(origin, "declares no models"));
    }
    let count = header.model_count as usize;
    if header.abi_version == v1::ABI_VERSION {
        // SAFETY: an ABI-1 header points at `model_count` v1 tables.
        let tables: &'static [v1::PluginModelTable] = unsafe {
            std::slice::from_raw_parts(header.models as *const v1::PluginModelTable, count)
        };
        return tables
            .iter()
            .map(|table| unsafe { v1::entry(table, origin) })
            .collect();
    }
    // SAFETY: an ABI-2 header points at `model_count` model entries.
    let models: &'static [PluginModel] =
        unsafe { std::slice::from_raw_parts(header.models as *const PluginModel, count) };
    models
        .iter()
        .map(|model| unsafe { entry(model, origin) })
        .collect()
}

/// Reads a plugin string.
///
/// # Safety
/// `text` must be valid for its length for the life of the process.
unsafe fn plugin_string(text: StrAbi, what: &str, origin: &str) -> Result<String, PluginError> {
    // SAFETY: per the contract above.
    unsafe { convert::str_from(text, what) }
        .map(str::to_owned)
        .map_err(|message| bad_header(origin, message))
}

/// The registry entry of one ABI-2 model.
///
/// # Safety
/// `model` must follow ABI 2.
unsafe fn entry(model: &'static PluginModel, origin: &str) -> Result<RegistryEntry, PluginError> {
    // SAFETY: per the contract above.
    let name = unsafe { plugin_string(model.name, "model name", origin)? };
    let summary = unsafe { plugin_string(model.summary, "summary", origin)? };
    let settings_doc = unsafe { plugin_string(model.settings_doc, "settings doc", origin)? };
    let fidelity = u8::try_from(model.fidelity).map_err(|_| {
        bad_header(
            origin,
            format!("model `{name}` has fidelity {} (0-255)", model.fidelity),
        )
    })?;
    if model.functions.is_null() {
        return Err(bad_header(
            origin,
            format!("model `{name}` has no function table"),
        ));
    }
    let functions = model.functions;
    let model_name = name.clone();
    // SAFETY (each arm): the role code fixes the table type behind `functions`.
    let factory = match model.role {
        PLUGIN_ROLE_AERO => {
            let f: &'static AeroFunctions = unsafe { &*(functions as *const AeroFunctions) };
            Factory::Aero(Arc::new(move |context| {
                AeroAdapter::create(model, f, &model_name, context)
                    .map(|m| Box::new(m) as Box<dyn AeroModel>)
            }))
        }
        PLUGIN_ROLE_HEAT_FLUX => {
            let f: &'static HeatFluxFunctions =
                unsafe { &*(functions as *const HeatFluxFunctions) };
            Factory::HeatFlux(Arc::new(move |context| {
                HeatFluxAdapter::create(model, f, &model_name, context)
                    .map(|m| Box::new(m) as Box<dyn HeatFluxModel>)
            }))
        }
        PLUGIN_ROLE_CONDUCTION => {
            let f: &'static ConductionFunctions =
                unsafe { &*(functions as *const ConductionFunctions) };
            Factory::Conduction(Arc::new(move |context| {
                ConductionAdapter::create(model, f, &model_name, context)
                    .map(|m| Box::new(m) as Box<dyn ConductionModel>)
            }))
        }
        PLUGIN_ROLE_STRUCTURE => {
            let f: &'static StructureFunctions =
                unsafe { &*(functions as *const StructureFunctions) };
            Factory::Structure(Arc::new(move |context| {
                StructureAdapter::create(model, f, &model_name, context)
                    .map(|m| Box::new(m) as Box<dyn StructureModel>)
            }))
        }
        PLUGIN_ROLE_PROPULSION => {
            let f: &'static PropulsionFunctions =
                unsafe { &*(functions as *const PropulsionFunctions) };
            Factory::Propulsion(Arc::new(move |context| {
                PropulsionAdapter::create(model, f, &model_name, context)
                    .map(|m| Box::new(m) as Box<dyn PropulsionModel>)
            }))
        }
        PLUGIN_ROLE_CONTROL => {
            let f: &'static ControlFunctions = unsafe { &*(functions as *const ControlFunctions) };
            Factory::Control(Arc::new(move |context| {
                ControllerAdapter::create(model, f, &model_name, context)
                    .map(|m| Box::new(m) as Box<dyn Controller>)
            }))
        }
        other => {
            return Err(bad_header(
                origin,
                format!(
                    "model `{name}` has role code {other}; ABI {PLUGIN_ABI_VERSION} knows 0 aero, 1 heat flux, 2 conduction, 3 structure, 4 propulsion, 5 control"
                ),
            ));
        }
    };
    Ok(RegistryEntry {
        name,
        fidelity,
        summary,
        settings_doc,
        origin: Origin::Plugin(origin.to_owned()),
        factory,
    })
}
