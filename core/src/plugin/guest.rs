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
    ControlCommands, ControlContext, Controller, ControllerConstructor, DesignSource,
    LinearDesignModel, MeasuredOutputs,
};
use crate::error::ModelError;
use crate::mesh::PanelMesh;
use crate::propulsion::{EngineInputs, EngineStatus, PropulsionModel, PropulsionSolution};
use crate::region::ModelSettings;
use crate::registry::{ModelContext, Registry};
use crate::structure::{RigidDof, StructureModel};
use crate::thermal::{ConductionModel, HeatFluxModel};

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

/// Model, rebuilt mesh and reused solution of an aero plugin model.
pub struct AeroState {
    model: Box<dyn AeroModel>,
    mesh: PanelMesh,
    elastic: Vec<Vector3<f64>>,
    solution: AeroSolution,
}

impl Exportable for dyn AeroModel {
    type State = AeroState;
    const ROLE: u32 = PLUGIN_ROLE_AERO;
    const FUNCTIONS: *const c_void = &AeroFunctions {
        evaluate: aero_evaluate,
    } as *const AeroFunctions as *const c_void;
    fn state(model: Box<Self>) -> AeroState {
        AeroState {
            model,
            mesh: PanelMesh::default(),
            elastic: Vec::new(),
            solution: AeroSolution::default(),
        }
    }
    fn capabilities(_: &mut AeroState) -> u32 {
        0
    }
}

fn vectors(values: &[f64], out: &mut Vec<Vector3<f64>>) {
    out.clear();
    out.extend(
        values
            .chunks_exact(3)
            .map(|v| Vector3::new(v[0], v[1], v[2])),
    );
}

unsafe extern "C" fn aero_evaluate(
    handle: *mut c_void,
    input: *const AeroInputAbi,
    output: *mut AeroOutputAbi,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<AeroState>(handle, "evaluate", |s| {
            let (input, output) = (
                input.as_ref().ok_or("null input")?,
                output.as_mut().ok_or("null output")?,
            );
            mesh_from_abi(&input.mesh, &mut s.mesh)?;
            let n = s.mesh.panels.len();
            let flight = flight_from_abi(&input.flight);
            let motion = if input.elastic_velocity_m_s.is_null() {
                PanelMotion::default()
            } else {
                vectors(
                    slice(input.elastic_velocity_m_s, 3 * n, "elastic velocities")?,
                    &mut s.elastic,
                );
                PanelMotion {
                    elastic_velocity_m_s: Some(&s.elastic),
                }
            };
            s.model
                .evaluate(&s.mesh, &flight, &motion, &mut s.solution)
                .map_err(error_text)?;
            let pressure = slice_mut(output.pressure_pa, n, "pressure output")?;
            let edge = slice_mut(output.edge, 5 * n, "edge output")?;
            if s.solution.pressure_pa.len() != n || s.solution.edge.len() != n {
                return Err(format!(
                    "model returned {} pressures and {} edge states for {n} panels",
                    s.solution.pressure_pa.len(),
                    s.solution.edge.len()
                ));
            }
            pressure.copy_from_slice(&s.solution.pressure_pa);
            for (out, e) in edge.chunks_exact_mut(5).zip(&s.solution.edge) {
                out.copy_from_slice(&[
                    e.mach,
                    e.pressure_pa,
                    e.temperature_k,
                    e.density_kg_m3,
                    e.velocity_m_s,
                ]);
            }
            let d = &s.solution.diagnostics;
            output.diagnostics = [
                d.shadowed_panels as u64,
                d.detached_shocks as u64,
                d.piston_theory_violations as u64,
                d.vacuum_expansions as u64,
            ];
            Ok(0)
        })
    }
}

/// Model, rebuilt mesh and aero state of a heat-flux plugin model.
pub struct HeatFluxState {
    model: Box<dyn HeatFluxModel>,
    mesh: PanelMesh,
    aero: AeroSolution,
}

impl Exportable for dyn HeatFluxModel {
    type State = HeatFluxState;
    const ROLE: u32 = PLUGIN_ROLE_HEAT_FLUX;
    const FUNCTIONS: *const c_void = &HeatFluxFunctions {
        heat_flux: heat_flux_evaluate,
        wall_shear: heat_flux_wall_shear,
    } as *const HeatFluxFunctions as *const c_void;
    fn state(model: Box<Self>) -> HeatFluxState {
        HeatFluxState {
            model,
            mesh: PanelMesh::default(),
            aero: AeroSolution::default(),
        }
    }
    fn capabilities(state: &mut HeatFluxState) -> u32 {
        if state.model.skin_friction().is_some() {
            CAPABILITY_SKIN_FRICTION
        } else {
            0
        }
    }
}

/// Rebuilds the wall inputs into `s`; returns the wall temperatures.
///
/// # Safety
/// `input` must follow the ABI.
unsafe fn wall_inputs<'a>(
    s: &mut HeatFluxState,
    input: *const WallInputAbi,
) -> Result<(&'a [f64], crate::flow::FlightCondition, usize), String> {
    // SAFETY: per the contract above.
    let input = unsafe { input.as_ref().ok_or("null input")? };
    unsafe { mesh_from_abi(&input.mesh, &mut s.mesh)? };
    let n = s.mesh.panels.len();
    let (pressure, edge, wall) = unsafe {
        (
            slice(input.pressure_pa, n, "pressures")?,
            slice(input.edge, 5 * n, "edge states")?,
            slice(input.wall_temperature_k, n, "wall temperatures")?,
        )
    };
    s.aero.reset(n);
    s.aero.pressure_pa.copy_from_slice(pressure);
    for (out, e) in s.aero.edge.iter_mut().zip(edge.chunks_exact(5)) {
        *out = edge_from(e);
    }
    Ok((wall, flight_from_abi(&input.flight), n))
}

unsafe extern "C" fn heat_flux_evaluate(
    handle: *mut c_void,
    input: *const WallInputAbi,
    out_w_m2: *mut f64,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<HeatFluxState>(handle, "heat_flux", |s| {
            let (wall, flight, n) = wall_inputs(s, input)?;
            let out = slice_mut(out_w_m2, n, "heat-flux output")?;
            s.model
                .heat_flux(&s.mesh, &flight, &s.aero, wall, out)
                .map_err(error_text)?;
            Ok(0)
        })
    }
}

unsafe extern "C" fn heat_flux_wall_shear(
    handle: *mut c_void,
    input: *const WallInputAbi,
    out_pa: *mut f64,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<HeatFluxState>(handle, "wall_shear", |s| {
            let (wall, flight, n) = wall_inputs(s, input)?;
            let out = slice_mut(out_pa, n, "wall-shear output")?;
            let friction = s
                .model
                .skin_friction()
                .ok_or("the model has no skin-friction law")?;
            friction
                .wall_shear(&s.mesh, &flight, &s.aero, wall, out)
                .map_err(error_text)?;
            Ok(0)
        })
    }
}

/// Model and state scratch of a conduction plugin model.
pub struct ConductionState {
    model: Box<dyn ConductionModel>,
    state: DVector<f64>,
}

impl Exportable for dyn ConductionModel {
    type State = ConductionState;
    const ROLE: u32 = PLUGIN_ROLE_CONDUCTION;
    const FUNCTIONS: *const c_void = &ConductionFunctions {
        sizes: conduction_sizes,
        uniform_state: conduction_uniform_state,
        step: conduction_step,
        surface_temperatures: conduction_surface_temperatures,
        node_temperatures: conduction_node_temperatures,
        node_temperature_differences: conduction_node_temperature_differences,
    } as *const ConductionFunctions as *const c_void;
    fn state(model: Box<Self>) -> ConductionState {
        ConductionState {
            model,
            state: DVector::zeros(0),
        }
    }
    fn capabilities(_: &mut ConductionState) -> u32 {
        0
    }
}

unsafe extern "C" fn conduction_sizes(handle: *mut c_void, out: *mut usize) -> i32 {
    // SAFETY: the host passes a handle from `create` and room for 3 sizes.
    unsafe {
        call::<ConductionState>(handle, "sizes", |s| {
            let out = slice_mut(out, 3, "sizes output")?;
            out.copy_from_slice(&[
                s.model.n_states(),
                s.model.n_nodes(),
                s.model.n_surface_panels(),
            ]);
            Ok(0)
        })
    }
}

unsafe extern "C" fn conduction_uniform_state(
    handle: *mut c_void,
    temperature_k: f64,
    state: *mut f64,
    n_states: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and a state of `n_states`.
    unsafe {
        call::<ConductionState>(handle, "uniform_state", |s| {
            let out = slice_mut(state, n_states, "state output")?;
            let uniform = s.model.uniform_state(temperature_k).map_err(error_text)?;
            if uniform.len() != n_states {
                return Err(format!(
                    "uniform state has {} values, not {n_states}",
                    uniform.len()
                ));
            }
            out.copy_from_slice(uniform.as_slice());
            Ok(0)
        })
    }
}

unsafe extern "C" fn conduction_step(
    handle: *mut c_void,
    state: *mut f64,
    n_states: usize,
    heat_flux_w_m2: *const f64,
    n_surface_panels: usize,
    dt_s: f64,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<ConductionState>(handle, "step", |s| {
            let values = slice_mut(state, n_states, "state")?;
            let flux = slice(heat_flux_w_m2, n_surface_panels, "heat flux")?;
            s.state = DVector::from_column_slice(values);
            s.model.step(&mut s.state, flux, dt_s).map_err(error_text)?;
            if s.state.len() != n_states {
                return Err(format!(
                    "step changed the state length to {}",
                    s.state.len()
                ));
            }
            values.copy_from_slice(s.state.as_slice());
            Ok(0)
        })
    }
}

/// Reads `n_out` values from a state with `read`.
unsafe fn read_state(
    handle: *mut c_void,
    what: &str,
    state: *const f64,
    n_states: usize,
    out: *mut f64,
    n_out: usize,
    read: fn(&dyn ConductionModel, &DVector<f64>, &mut [f64]),
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<ConductionState>(handle, what, |s| {
            let values = slice(state, n_states, "state")?;
            let out = slice_mut(out, n_out, "temperature output")?;
            if s.state.len() == n_states {
                s.state.as_mut_slice().copy_from_slice(values);
            } else {
                s.state = DVector::from_column_slice(values);
            }
            read(s.model.as_ref(), &s.state, out);
            Ok(0)
        })
    }
}

unsafe extern "C" fn conduction_surface_temperatures(
    handle: *mut c_void,
    state: *const f64,
    n_states: usize,
    out: *mut f64,
    n_out: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        read_state(
            handle,
            "surface_temperatures",
            state,
            n_states,
            out,
            n_out,
            |m, s, o| m.surface_temperatures(s, o),
        )
    }
}

unsafe extern "C" fn conduction_node_temperatures(
    handle: *mut c_void,
    state: *const f64,
    n_states: usize,
    out: *mut f64,
    n_out: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        read_state(
            handle,
            "node_temperatures",
            state,
            n_states,
            out,
            n_out,
            |m, s, o| m.node_temperatures(s, o),
        )
    }
}

unsafe extern "C" fn conduction_node_temperature_differences(
    handle: *mut c_void,
    state: *const f64,
    n_states: usize,
    out: *mut f64,
    n_out: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        read_state(
            handle,
            "node_temperature_differences",
            state,
            n_states,
            out,
            n_out,
            |m, s, o| m.node_temperature_differences(s, o),
        )
    }
}

/// Model and rebuilt mesh of a structure plugin model.
pub struct StructureState {
    model: Box<dyn StructureModel>,
    mesh: PanelMesh,
}

impl Exportable for dyn StructureModel {
    type State = StructureState;
    const ROLE: u32 = PLUGIN_ROLE_STRUCTURE;
    const FUNCTIONS: *const c_void = &StructureFunctions {
        n_modes: structure_n_modes,
        mode_name: structure_mode_name,
        modal_matrices: structure_modal_matrices,
        natural_frequencies_hz: structure_natural_frequencies,
        mode_shapes_on: structure_mode_shapes_on,
        temperature_nodes: structure_temperature_nodes,
        set_temperature_field: structure_set_temperature_field,
        thermal_generalized_forces: structure_thermal_forces,
        root_reference_m: structure_root_reference,
        root_loads: structure_root_loads,
        mass_properties: structure_mass_properties,
        rigid_dofs: structure_rigid_dofs,
        rigid_coupling: structure_rigid_coupling,
    } as *const StructureFunctions as *const c_void;
    fn state(model: Box<Self>) -> StructureState {
        StructureState {
            model,
            mesh: PanelMesh::default(),
        }
    }
    fn capabilities(state: &mut StructureState) -> u32 {
        let m = state.model.as_ref();
        let mut bits = 0;
        if m.thermal_stiffness().is_some() {
            bits |= CAPABILITY_THERMAL_STIFFNESS;
        }
        if m.root_loads().is_some() {
            bits |= CAPABILITY_ROOT_LOADS;
        }
        if m.mass_properties().is_some() {
            bits |= CAPABILITY_MASS_PROPERTIES;
        }
        if m.rigid_body_coupling().is_some() {
            bits |= CAPABILITY_RIGID_BODY_COUPLING;
        }
        bits
    }
}

fn missing(capability: &str) -> String {
    format!("the model has no {capability}")
}

unsafe extern "C" fn structure_n_modes(handle: *mut c_void) -> usize {
    // SAFETY: the host passes a handle from `create`.
    unsafe {
        call_count::<StructureState>(handle, "n_modes", |s| Ok(s.model.modal_model().n_modes()))
    }
}

unsafe extern "C" fn structure_mode_name(
    handle: *mut c_void,
    index: usize,
    buffer: *mut u8,
    capacity: usize,
) -> usize {
    // SAFETY: the host passes a handle from `create` and a buffer of `capacity` bytes.
    unsafe {
        call_count::<StructureState>(handle, "mode_name", |s| {
            let name = s
                .model
                .modal_model()
                .names
                .get(index)
                .ok_or_else(|| format!("no mode {index}"))?;
            Ok(copy_text(name, buffer, capacity))
        })
    }
}

unsafe extern "C" fn structure_modal_matrices(
    handle: *mut c_void,
    mass: *mut f64,
    damping: *mut f64,
    stiffness: *mut f64,
    n_modes: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and three n_modes² buffers.
    unsafe {
        call::<StructureState>(handle, "modal_matrices", |s| {
            let modal = s.model.modal_model();
            for (matrix, out, what) in [
                (&modal.mass, mass, "mass"),
                (&modal.damping, damping, "damping"),
                (&modal.stiffness, stiffness, "stiffness"),
            ] {
                if matrix.shape() != (n_modes, n_modes) {
                    return Err(format!(
                        "generalized {what} matrix is {:?}, not {n_modes} x {n_modes}",
                        matrix.shape()
                    ));
                }
                slice_mut(out, n_modes * n_modes, what)?.copy_from_slice(matrix.as_slice());
            }
            Ok(0)
        })
    }
}

unsafe extern "C" fn structure_natural_frequencies(
    handle: *mut c_void,
    out: *mut f64,
    n_modes: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and n_modes values.
    unsafe {
        call::<StructureState>(handle, "natural_frequencies_hz", |s| {
            let frequencies = s.model.natural_frequencies_hz().map_err(error_text)?;
            if frequencies.len() != n_modes {
                return Err(format!(
                    "{} natural frequencies for {n_modes} modes",
                    frequencies.len()
                ));
            }
            slice_mut(out, n_modes, "frequency output")?.copy_from_slice(&frequencies);
            Ok(0)
        })
    }
}

unsafe extern "C" fn structure_mode_shapes_on(
    handle: *mut c_void,
    mesh: *const MeshAbi,
    out: *mut f64,
    n_modes: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create`, a mesh and 3 n_vertices n_modes values.
    unsafe {
        call::<StructureState>(handle, "mode_shapes_on", |s| {
            mesh_from_abi(mesh.as_ref().ok_or("null mesh")?, &mut s.mesh)?;
            let shapes = s.model.mode_shapes_on(&s.mesh).map_err(error_text)?;
            let rows = 3 * s.mesh.vertices.len();
            let displacement = &shapes.vertex_displacement;
            if displacement.shape() != (rows, n_modes) {
                return Err(format!(
                    "mode shapes are {:?}, not {rows} x {n_modes}",
                    displacement.shape()
                ));
            }
            slice_mut(out, rows * n_modes, "mode-shape output")?
                .copy_from_slice(displacement.as_slice());
            Ok(0)
        })
    }
}

unsafe extern "C" fn structure_temperature_nodes(handle: *mut c_void) -> usize {
    // SAFETY: the host passes a handle from `create`.
    unsafe {
        call_count::<StructureState>(handle, "temperature_nodes", |s| {
            let thermal = s
                .model
                .thermal_stiffness()
                .ok_or_else(|| missing("temperature-dependent stiffness"))?;
            Ok(thermal.temperature_nodes())
        })
    }
}

unsafe extern "C" fn structure_set_temperature_field(
    handle: *mut c_void,
    mean_k: *const f64,
    difference_k: *const f64,
    n_nodes: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and n_nodes values per non-null buffer.
    unsafe {
        call::<StructureState>(handle, "set_temperature_field", |s| {
            let mean = slice(mean_k, n_nodes, "node temperatures")?;
            let thermal = s
                .model
                .thermal_stiffness_mut()
                .ok_or_else(|| missing("temperature-dependent stiffness"))?;
            if difference_k.is_null() {
                thermal.set_temperatures(mean).map_err(error_text)?;
            } else {
                let difference = slice(difference_k, n_nodes, "temperature differences")?;
                thermal
                    .set_temperature_field(mean, difference)
                    .map_err(error_text)?;
            }
            Ok(0)
        })
    }
}

unsafe extern "C" fn structure_thermal_forces(
    handle: *mut c_void,
    out: *mut f64,
    n_modes: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and n_modes values.
    unsafe {
        call::<StructureState>(handle, "thermal_generalized_forces", |s| {
            let thermal = s
                .model
                .thermal_stiffness()
                .ok_or_else(|| missing("temperature-dependent stiffness"))?;
            let Some(forces) = thermal.thermal_generalized_forces() else {
                return Ok(PLUGIN_STATUS_NONE);
            };
            if forces.len() != n_modes {
                return Err(format!(
                    "{} thermal generalized forces for {n_modes} modes",
                    forces.len()
                ));
            }
            slice_mut(out, n_modes, "thermal-force output")?.copy_from_slice(forces.as_slice());
            Ok(0)
        })
    }
}

unsafe extern "C" fn structure_root_reference(handle: *mut c_void, out: *mut f64) -> i32 {
    // SAFETY: the host passes a handle from `create` and room for 3 values.
    unsafe {
        call::<StructureState>(handle, "root_reference_m", |s| {
            let root = s.model.root_loads().ok_or_else(|| missing("root loads"))?;
            slice_mut(out, 3, "root reference output")?
                .copy_from_slice(root.root_reference_m().coords.as_slice());
            Ok(0)
        })
    }
}

unsafe extern "C" fn structure_root_loads(
    handle: *mut c_void,
    q: *const f64,
    q_dot: *const f64,
    q_ddot: *const f64,
    n_modes: usize,
    applied: *const f64,
    out: *mut f64,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<StructureState>(handle, "root_loads", |s| {
            let vector = |p: *const f64, what: &str| -> Result<DVector<f64>, String> {
                Ok(DVector::from_column_slice(slice(p, n_modes, what)?))
            };
            let (q, q_dot, q_ddot) = (
                vector(q, "modal coordinates")?,
                vector(q_dot, "modal velocities")?,
                vector(q_ddot, "modal accelerations")?,
            );
            let a = slice(applied, 6, "applied loads")?;
            let applied = Loads {
                force_n: Vector3::new(a[0], a[1], a[2]),
                moment_nm: Vector3::new(a[3], a[4], a[5]),
            };
            let root = s.model.root_loads().ok_or_else(|| missing("root loads"))?;
            let loads = root
                .root_loads(&q, &q_dot, &q_ddot, &applied)
                .map_err(error_text)?;
            let out = slice_mut(out, 6, "root-load output")?;
            out[..3].copy_from_slice(loads.force_n.as_slice());
            out[3..].copy_from_slice(loads.moment_nm.as_slice());
            Ok(0)
        })
    }
}

unsafe extern "C" fn structure_mass_properties(handle: *mut c_void, out: *mut f64) -> i32 {
    // SAFETY: the host passes a handle from `create` and room for 13 values.
    unsafe {
        call::<StructureState>(handle, "mass_properties", |s| {
            let mass = s
                .model
                .mass_properties()
                .ok_or_else(|| missing("mass properties"))?
                .mass_properties();
            let out = slice_mut(out, 13, "mass-property output")?;
            out[0] = mass.mass_kg;
            out[1..4].copy_from_slice(mass.center_of_mass_m.coords.as_slice());
            out[4..].copy_from_slice(mass.inertia_kg_m2.as_slice());
            Ok(0)
        })
    }
}

pub(crate) fn dof_code(dof: RigidDof) -> u32 {
    match dof {
        RigidDof::TranslationX => 0,
        RigidDof::TranslationY => 1,
        RigidDof::TranslationZ => 2,
        RigidDof::RotationX => 3,
        RigidDof::RotationY => 4,
        RigidDof::RotationZ => 5,
    }
}

unsafe extern "C" fn structure_rigid_dofs(
    handle: *mut c_void,
    dofs: *mut u32,
    reference_m: *mut f64,
) -> usize {
    // SAFETY: the host passes a handle from `create`, room for 6 codes and 3 values.
    unsafe {
        call_count::<StructureState>(handle, "rigid_dofs", |s| {
            let rigid = s
                .model
                .rigid_body_coupling()
                .ok_or_else(|| missing("rigid-body coupling"))?;
            let list = rigid.rigid_dofs();
            if list.len() > 6 {
                return Err(format!(
                    "{} rigid degrees of freedom (at most 6)",
                    list.len()
                ));
            }
            let codes = slice_mut(dofs, 6, "rigid-dof output")?;
            for (code, dof) in codes.iter_mut().zip(list) {
                *code = dof_code(*dof);
            }
            slice_mut(reference_m, 3, "reference output")?
                .copy_from_slice(rigid.rigid_reference_point_m().coords.as_slice());
            Ok(list.len())
        })
    }
}

unsafe extern "C" fn structure_rigid_coupling(
    handle: *mut c_void,
    out: *mut f64,
    n_modes: usize,
    n_dofs: usize,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and n_modes n_dofs values.
    unsafe {
        call::<StructureState>(handle, "rigid_coupling", |s| {
            let rigid = s
                .model
                .rigid_body_coupling()
                .ok_or_else(|| missing("rigid-body coupling"))?;
            let coupling = rigid.rigid_coupling();
            if coupling.shape() != (n_modes, n_dofs) {
                return Err(format!(
                    "rigid coupling is {:?}, not {n_modes} x {n_dofs}",
                    coupling.shape()
                ));
            }
            slice_mut(out, n_modes * n_dofs, "rigid-coupling output")?
                .copy_from_slice(coupling.as_slice());
            Ok(0)
        })
    }
}

/// Model, rebuilt body mesh and reused solution of a propulsion plugin model.
pub struct PropulsionState {
    model: Box<dyn PropulsionModel>,
    mesh: PanelMesh,
    solution: PropulsionSolution,
}

impl Exportable for dyn PropulsionModel {
    type State = PropulsionState;
    const ROLE: u32 = PLUGIN_ROLE_PROPULSION;
    const FUNCTIONS: *const c_void = &PropulsionFunctions {
        evaluate: propulsion_evaluate,
    } as *const PropulsionFunctions as *const c_void;
    fn state(model: Box<Self>) -> PropulsionState {
        PropulsionState {
            model,
            mesh: PanelMesh::default(),
            solution: PropulsionSolution::default(),
        }
    }
    fn capabilities(_: &mut PropulsionState) -> u32 {
        0
    }
}

pub(crate) fn status_code(status: EngineStatus) -> u32 {
    match status {
        EngineStatus::Ok => ENGINE_OK,
        EngineStatus::Spillage => ENGINE_SPILLAGE,
        EngineStatus::ThermalChoking => ENGINE_THERMAL_CHOKING,
        EngineStatus::Unstart => ENGINE_UNSTART,
    }
}

/// `name` in a NUL-padded field, cut at a character boundary.
fn station_name(name: &str) -> [u8; STATION_NAME_BYTES] {
    let mut out = [0u8; STATION_NAME_BYTES];
    let mut end = name.len().min(STATION_NAME_BYTES);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    out[..end].copy_from_slice(&name.as_bytes()[..end]);
    out
}

unsafe extern "C" fn propulsion_evaluate(
    handle: *mut c_void,
    input: *const EngineInputAbi,
    output: *mut EngineOutputAbi,
) -> i32 {
    // SAFETY: the host passes a handle from `create` and buffers of the stated sizes.
    unsafe {
        call::<PropulsionState>(handle, "evaluate", |s| {
            let (input, output) = (
                input.as_ref().ok_or("null input")?,
                output.as_mut().ok_or("null output")?,
            );
            mesh_from_abi(&input.body, &mut s.mesh)?;
            let n = s.mesh.panels.len();
            let flight = flight_from_abi(&input.flight);
            let inputs = EngineInputs {
                flight: &flight,
                body: &s.mesh,
                fuel_equivalence_ratio: input.fuel_equivalence_ratio,
            };
            s.model
                .evaluate(&inputs, &mut s.solution)
                .map_err(error_text)?;
            let solution = &s.solution;
            if solution.panel_pressure_pa.len() != n {
                return Err(format!(
                    "{} panel pressures for a body mesh of {n} panels",
                    solution.panel_pressure_pa.len()
                ));
            }
            if solution.stations.len() > output.station_capacity {
                return Err(format!(
                    "{} engine stations, more than the {} the ABI carries",
                    solution.stations.len(),
                    output.station_capacity
                ));
            }
            slice_mut(output.panel_pressure_pa, n, "panel-pressure output")?
                .copy_from_slice(&solution.panel_pressure_pa);
            let stations = slice_mut(output.stations, output.station_capacity, "stations")?;
            for (out, station) in stations.iter_mut().zip(&solution.stations) {
                *out = StationAbi {
                    name: station_name(&station.station),
                    mach: station.mach,
                    pressure_pa: station.pressure_pa,
                    temperature_k: station.temperature_k,
                };
            }
            output.n_stations = solution.stations.len();
            let l = &solution.loads;
            output.loads = [
                l.force_n.x,
                l.force_n.y,
                l.force_n.z,
                l.moment_nm.x,
                l.moment_nm.y,
                l.moment_nm.z,
            ];
            output.mass_flow_kg_s = solution.mass_flow_kg_s;
            output.status = status_code(solution.status);
            Ok(0)
        })
    }
}

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
fn json_table(json: &str, what: &str) -> Result<toml::Table, String> {
    if json.trim().is_empty() {
        return Ok(toml::Table::new());
    }
    serde_json::from_str(json).map_err(|e| format!("{what} are not a JSON table: {e}"))
}

/// The host's design models, asked for through [`DesignSourceAbi`].
struct GuestDesign<'a> {
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
/// [`crate::control::ControllerConstructor`]). [`crate::export_plugin!`]
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
