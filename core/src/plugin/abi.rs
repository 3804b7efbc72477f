//! The `#[repr(C)]` structs of plugin ABI version 2: one model entry per model, a function table
//! per role, and the plain-data inputs and outputs each function reads and writes.
//!
//! Conventions: every array is a pointer plus the count named beside it; 3-vectors are `x, y, z`
//! interleaved, body axes, SI units; matrices are column-major; strings are UTF-8 pointer and
//! length ([`StrAbi`]), no NUL. Functions return 0 on success and a non-zero status on error,
//! after which the model's `last_error` holds the message. A function is only called with the
//! sizes the host read from the model (`n_modes`, `sizes`) and with output buffers of exactly the
//! stated lengths.

use std::ffi::c_void;

/// Role code of an aero model ([`PluginModel::role`]).
pub const PLUGIN_ROLE_AERO: u32 = 0;
/// Role code of a heat-flux model.
pub const PLUGIN_ROLE_HEAT_FLUX: u32 = 1;
/// Role code of a conduction model.
pub const PLUGIN_ROLE_CONDUCTION: u32 = 2;
/// Role code of a structure model.
pub const PLUGIN_ROLE_STRUCTURE: u32 = 3;
/// Role code of a propulsion model.
pub const PLUGIN_ROLE_PROPULSION: u32 = 4;
/// Role code of a controller (plugin API 2.1).
pub const PLUGIN_ROLE_CONTROL: u32 = 5;

/// Status a function returns when the model lacks the optional output asked for (not an error).
pub const PLUGIN_STATUS_NONE: i32 = -1;

/// Capability bit of a heat-flux model: `wall_shear` works (skin friction).
pub const CAPABILITY_SKIN_FRICTION: u32 = 1;
/// Capability bit of a structure model: temperature-dependent stiffness.
pub const CAPABILITY_THERMAL_STIFFNESS: u32 = 1;
/// Capability bit of a structure model: root loads.
pub const CAPABILITY_ROOT_LOADS: u32 = 2;
/// Capability bit of a structure model: mass properties.
pub const CAPABILITY_MASS_PROPERTIES: u32 = 4;
/// Capability bit of a structure model: rigid-body coupling.
pub const CAPABILITY_RIGID_BODY_COUPLING: u32 = 8;

/// Region kind codes ([`crate::mesh::RegionKind`]): main body, lifting surface, propulsion, other.
pub const REGION_MAIN_BODY: u32 = 0;
pub const REGION_LIFTING_SURFACE: u32 = 1;
pub const REGION_PROPULSION: u32 = 2;
pub const REGION_OTHER: u32 = 3;
/// Side codes of a region: none, left (y < 0), right (y > 0).
pub const SIDE_NONE: u32 = 0;
pub const SIDE_LEFT: u32 = 1;
pub const SIDE_RIGHT: u32 = 2;

/// Engine status codes ([`crate::propulsion::EngineStatus`]).
pub const ENGINE_OK: u32 = 0;
pub const ENGINE_SPILLAGE: u32 = 1;
pub const ENGINE_THERMAL_CHOKING: u32 = 2;
pub const ENGINE_UNSTART: u32 = 3;

/// Longest station name an engine can report, bytes of UTF-8.
pub const STATION_NAME_BYTES: usize = 32;

/// A borrowed UTF-8 string: pointer and length in bytes (no NUL).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct StrAbi {
    pub ptr: *const u8,
    pub len: usize,
}

impl StrAbi {
    /// A view of `text` valid while `text` lives.
    pub const fn new(text: &str) -> Self {
        Self {
            ptr: text.as_ptr(),
            len: text.len(),
        }
    }
}

/// Creates a model; the arguments of every role's `create`.
pub type CreateFn = unsafe extern "C" fn(args: *const CreateArgs) -> *mut c_void;
/// Destroys a model handle.
pub type DestroyFn = unsafe extern "C" fn(handle: *mut c_void);
/// Copies the last error message of `handle` (of the last failed `create` when null) into
/// `buffer` (at most `capacity` bytes, UTF-8, no NUL); returns the message's full length.
pub type LastErrorFn =
    unsafe extern "C" fn(handle: *mut c_void, buffer: *mut u8, capacity: usize) -> usize;
/// The role's capability bits of a created model (`CAPABILITY_*`), read once after `create`.
pub type CapabilitiesFn = unsafe extern "C" fn(handle: *mut c_void) -> u32;

/// One model of an ABI-2 plugin: descriptor, common functions and its role's function table.
#[repr(C)]
pub struct PluginModel {
    /// `PLUGIN_ROLE_*`; fixes the type `functions` points at.
    pub role: u32,
    /// Fidelity rank within the role (0-255).
    pub fidelity: u32,
    /// Registered name, kebab-case.
    pub name: StrAbi,
    pub summary: StrAbi,
    /// `key = default  # meaning` per line.
    pub settings_doc: StrAbi,
    /// Builds a model; null on error (then `last_error(null)`).
    pub create: CreateFn,
    pub destroy: DestroyFn,
    pub last_error: LastErrorFn,
    pub capabilities: CapabilitiesFn,
    /// `&AeroFunctions`, `&HeatFluxFunctions`, `&ConductionFunctions`, `&StructureFunctions`,
    /// `&PropulsionFunctions` or `&ControlFunctions` by `role`; static.
    pub functions: *const c_void,
}

// SAFETY: model entries are immutable static data; the pointers are to static strings and tables.
unsafe impl Sync for PluginModel {}
unsafe impl Send for PluginModel {}

/// What `create` gets: the model's settings, where they come from, and its region. A
/// controller belongs to no region: its `region` is named `control`, of kind
/// [`REGION_OTHER`], with an empty mesh and zero reference and gas values; it gets the
/// operating point from [`ControlFunctions::start`].
#[repr(C)]
pub struct CreateArgs {
    /// `[models.<name>]` overlaid by the region's override, as JSON.
    pub settings_json: StrAbi,
    /// Dotted key path of the settings in the config file, for messages.
    pub key_path: StrAbi,
    /// The config file, for messages.
    pub file: StrAbi,
    pub region: RegionAbi,
}

/// The region a model is built for ([`crate::region::RegionInfo`]) as plain data.
#[repr(C)]
pub struct RegionAbi {
    /// `main_body`, `left_surface`, `right_surface`, `propulsion`, ...
    pub name: StrAbi,
    /// `REGION_*` code.
    pub kind: u32,
    /// `SIDE_*` code.
    pub side: u32,
    /// The region's undeformed wetted mesh.
    pub mesh: MeshAbi,
    /// Reference area m², chord m, span m, moment point x, y, z m.
    pub reference: [f64; 6],
    pub gamma: f64,
    pub gas_constant_j_kg_k: f64,
    /// The parametric geometry as JSON: `{"body": <[geometry] table>}`,
    /// `{"lifting_surface": <[lifting_surface] table>, "side": "left"|"right"}` or `"mesh"`.
    pub geometry_json: StrAbi,
}

/// A panel mesh ([`crate::mesh::PanelMesh`]) as flat arrays.
#[repr(C)]
pub struct MeshAbi {
    pub n_vertices: usize,
    /// `3 n_vertices`, m.
    pub vertices_m: *const f64,
    pub n_panels: usize,
    /// `4 n_panels` vertex indices, counter-clockwise seen from outside (a triangle repeats its
    /// third vertex).
    pub panel_vertices: *const usize,
    /// `n_panels`: 3 or 4.
    pub panel_vertex_count: *const u8,
    /// `n_panels` surface indices.
    pub panel_surface: *const u32,
    /// `3 n_panels`, m.
    pub centroid_m: *const f64,
    /// `3 n_panels` outward unit normals.
    pub normal: *const f64,
    /// `n_panels`, m².
    pub area_m2: *const f64,
    pub n_strips: usize,
    /// `n_strips + 1`: strip `s` is `strip_panels[strip_offsets[s]..strip_offsets[s + 1]]`,
    /// upstream first.
    pub strip_offsets: *const usize,
    pub strip_panels: *const usize,
    pub n_surfaces: usize,
    /// `n_surfaces` `REGION_*` codes.
    pub surface_kind: *const u32,
    /// `n_surfaces + 1` byte offsets into `surface_names` (UTF-8, concatenated).
    pub surface_name_offsets: *const usize,
    pub surface_names: *const u8,
}

/// Freestream and vehicle motion ([`crate::flow::FlightCondition`]), SI units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightAbi {
    pub mach: f64,
    pub altitude_m: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
    pub velocity_m_s: f64,
    pub dynamic_viscosity_pa_s: f64,
    pub dynamic_pressure_pa: f64,
    pub gamma: f64,
    pub gas_constant_j_kg_k: f64,
    pub alpha_rad: f64,
    pub beta_rad: f64,
    /// Body rates (p, q, r) relative to the air, rad/s.
    pub angular_velocity_rad_s: [f64; 3],
    /// Point the body rotates about, m.
    pub rotation_center_m: [f64; 3],
}

/// Input of an aero evaluation.
#[repr(C)]
pub struct AeroInputAbi {
    pub flight: FlightAbi,
    /// The (deformed) mesh to evaluate.
    pub mesh: MeshAbi,
    /// `3 n_panels` elastic velocity of each panel centroid, m/s, or null (none). A panel moves
    /// relative to the air at V + ω × (r − r_c) + elastic.
    pub elastic_velocity_m_s: *const f64,
}

/// Output of an aero evaluation, buffers sized by the host.
#[repr(C)]
pub struct AeroOutputAbi {
    /// `n_panels` absolute pressures, Pa.
    pub pressure_pa: *mut f64,
    /// `5 n_panels` edge states: Mach, pressure Pa, temperature K, density kg/m³, velocity m/s.
    pub edge: *mut f64,
    /// Shadowed panels, detached shocks, piston-theory violations, vacuum expansions.
    pub diagnostics: [u64; 4],
}

/// Aero functions.
#[repr(C)]
pub struct AeroFunctions {
    pub evaluate: unsafe extern "C" fn(
        handle: *mut c_void,
        input: *const AeroInputAbi,
        output: *mut AeroOutputAbi,
    ) -> i32,
}

/// Input of a heat-flux or wall-shear evaluation: the aero state at the wall.
#[repr(C)]
pub struct WallInputAbi {
    pub flight: FlightAbi,
    pub mesh: MeshAbi,
    /// `n_panels` absolute pressures of the aero evaluation, Pa.
    pub pressure_pa: *const f64,
    /// `5 n_panels` edge states, as in [`AeroOutputAbi::edge`].
    pub edge: *const f64,
    /// `n_panels` wall temperatures, K.
    pub wall_temperature_k: *const f64,
}

/// Heat-flux functions; `wall_shear` only when the model has [`CAPABILITY_SKIN_FRICTION`].
#[repr(C)]
pub struct HeatFluxFunctions {
    /// Net heat flux into the wall, `n_panels` W/m².
    pub heat_flux: unsafe extern "C" fn(
        handle: *mut c_void,
        input: *const WallInputAbi,
        out_w_m2: *mut f64,
    ) -> i32,
    /// Wall shear, `n_panels` Pa.
    pub wall_shear: unsafe extern "C" fn(
        handle: *mut c_void,
        input: *const WallInputAbi,
        out_pa: *mut f64,
    ) -> i32,
}

/// Conduction functions. The thermal state is the host's `n_states` numbers.
#[repr(C)]
pub struct ConductionFunctions {
    /// Writes `[n_states, n_nodes, n_surface_panels]`; fixed for a model's life.
    pub sizes: unsafe extern "C" fn(handle: *mut c_void, out: *mut usize) -> i32,
    /// State of a structure at a uniform temperature (K), `n_states`.
    pub uniform_state: unsafe extern "C" fn(
        handle: *mut c_void,
        temperature_k: f64,
        state: *mut f64,
        n_states: usize,
    ) -> i32,
    /// Advances `state` by `dt_s` under `n_surface_panels` heat fluxes (W/m²).
    pub step: unsafe extern "C" fn(
        handle: *mut c_void,
        state: *mut f64,
        n_states: usize,
        heat_flux_w_m2: *const f64,
        n_surface_panels: usize,
        dt_s: f64,
    ) -> i32,
    /// Wall temperature of each wetted panel, `n_surface_panels` K.
    pub surface_temperatures: ReadStateFn,
    /// Temperature of each structural node, `n_nodes` K.
    pub node_temperatures: ReadStateFn,
    /// Lower-face minus upper-face temperature at each node, `n_nodes` K.
    pub node_temperature_differences: ReadStateFn,
}

/// Reads a quantity of `n_out` values out of a conduction state.
pub type ReadStateFn = unsafe extern "C" fn(
    handle: *mut c_void,
    state: *const f64,
    n_states: usize,
    out: *mut f64,
    n_out: usize,
) -> i32;

/// Structure functions. Capability functions are only called when the bit is set.
#[repr(C)]
pub struct StructureFunctions {
    /// Number of modes; fixed for a model's life.
    pub n_modes: unsafe extern "C" fn(handle: *mut c_void) -> usize,
    /// Copies mode `index`'s name (UTF-8, at most `capacity` bytes); returns its full length.
    pub mode_name: unsafe extern "C" fn(
        handle: *mut c_void,
        index: usize,
        buffer: *mut u8,
        capacity: usize,
    ) -> usize,
    /// Generalized mass kg, damping kg/s and stiffness N/m, each `n_modes²` column-major.
    pub modal_matrices: unsafe extern "C" fn(
        handle: *mut c_void,
        mass: *mut f64,
        damping: *mut f64,
        stiffness: *mut f64,
        n_modes: usize,
    ) -> i32,
    /// `n_modes` natural frequencies, Hz.
    pub natural_frequencies_hz:
        unsafe extern "C" fn(handle: *mut c_void, out: *mut f64, n_modes: usize) -> i32,
    /// Mode shapes at the mesh's vertices: `3 n_vertices × n_modes` column-major, m.
    pub mode_shapes_on: unsafe extern "C" fn(
        handle: *mut c_void,
        mesh: *const MeshAbi,
        out: *mut f64,
        n_modes: usize,
    ) -> i32,
    /// Number of node temperatures the stiffness takes.
    pub temperature_nodes: unsafe extern "C" fn(handle: *mut c_void) -> usize,
    /// Sets node temperatures (K) and, when `difference_k` is not null, through-thickness
    /// differences (lower minus upper face, K), `n_nodes` each.
    pub set_temperature_field: unsafe extern "C" fn(
        handle: *mut c_void,
        mean_k: *const f64,
        difference_k: *const f64,
        n_nodes: usize,
    ) -> i32,
    /// Generalized thermal-moment forces, `n_modes`; [`PLUGIN_STATUS_NONE`] when the model has
    /// none.
    pub thermal_generalized_forces:
        unsafe extern "C" fn(handle: *mut c_void, out: *mut f64, n_modes: usize) -> i32,
    /// The root reference point, m (3).
    pub root_reference_m: unsafe extern "C" fn(handle: *mut c_void, out: *mut f64) -> i32,
    /// Root force N and moment N m (6) from `n_modes` modal coordinates, velocities and
    /// accelerations and the applied loads (force then moment, 6).
    pub root_loads: unsafe extern "C" fn(
        handle: *mut c_void,
        q: *const f64,
        q_dot: *const f64,
        q_ddot: *const f64,
        n_modes: usize,
        applied: *const f64,
        out: *mut f64,
    ) -> i32,
    /// Mass kg, centre of mass m (3), inertia about it kg m² (9, column-major): 13 values.
    pub mass_properties: unsafe extern "C" fn(handle: *mut c_void, out: *mut f64) -> i32,
    /// Rigid degrees of freedom (`dofs`, up to 6 codes 0-5: translation x, y, z, rotation x, y,
    /// z) and their reference point (3, m); returns the count (> 6 or on error: 0 and
    /// `last_error`).
    pub rigid_dofs:
        unsafe extern "C" fn(handle: *mut c_void, dofs: *mut u32, reference_m: *mut f64) -> usize,
    /// Rigid coupling C = Φᵀ M R, `n_modes × n_dofs` column-major.
    pub rigid_coupling: unsafe extern "C" fn(
        handle: *mut c_void,
        out: *mut f64,
        n_modes: usize,
        n_dofs: usize,
    ) -> i32,
}

/// Input of an engine evaluation.
#[repr(C)]
pub struct EngineInputAbi {
    pub flight: FlightAbi,
    /// The (deformed) body mesh; the engine reads the panels of `REGION_PROPULSION` surfaces.
    pub body: MeshAbi,
    /// Fuel equivalence ratio φ.
    pub fuel_equivalence_ratio: f64,
}

/// One engine station.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StationAbi {
    /// UTF-8, NUL-padded.
    pub name: [u8; STATION_NAME_BYTES],
    pub mach: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
}

/// Output of an engine evaluation.
#[repr(C)]
pub struct EngineOutputAbi {
    /// Force N (3) then moment N m (3) about the body reference point, body axes.
    pub loads: [f64; 6],
    pub mass_flow_kg_s: f64,
    /// `ENGINE_*` code.
    pub status: u32,
    /// `n_panels` of the body mesh, Pa.
    pub panel_pressure_pa: *mut f64,
    /// Room for `station_capacity` stations; the plugin writes `n_stations`.
    pub stations: *mut StationAbi,
    pub station_capacity: usize,
    pub n_stations: usize,
}

/// Propulsion functions.
#[repr(C)]
pub struct PropulsionFunctions {
    pub evaluate: unsafe extern "C" fn(
        handle: *mut c_void,
        input: *const EngineInputAbi,
        output: *mut EngineOutputAbi,
    ) -> i32,
}

/// Where a controller asks the host for its linear design model during
/// [`ControlFunctions::start`]: the host linearizes the trimmed vehicle on the first request.
#[repr(C)]
pub struct DesignSourceAbi {
    /// The host's context, passed back to `model`.
    pub context: *mut c_void,
    /// Points `out` at the design model `which` ([`DESIGN_LONGITUDINAL`] or
    /// [`DESIGN_LATERAL`]) as JSON (`{"state_names": [..], "input_names": [..], "a": [[row],
    /// ..], "b": [[row], ..], "reduction": ".."}`, rows of `a` and `b` by state), valid until
    /// `start` returns; on a non-zero status `out` holds the host's error message instead.
    pub model: unsafe extern "C" fn(context: *mut c_void, which: u32, out: *mut StrAbi) -> i32,
}

/// [`DesignSourceAbi::model`]: the rigid longitudinal design model (inputs symmetric elevon, φ).
pub const DESIGN_LONGITUDINAL: u32 = 0;
/// [`DesignSourceAbi::model`]: the rigid lateral design model (input differential elevon).
pub const DESIGN_LATERAL: u32 = 1;

/// Number of measured outputs a controller reads ([`crate::control::MeasuredOutputs::NAMES`]).
pub const CONTROL_OUTPUTS: usize = 16;
/// Number of commands a controller writes ([`crate::control::ControlCommands::NAMES`]).
pub const CONTROL_COMMANDS: usize = 3;

/// What a controller's `start` gets: the operating point it is designed about.
#[repr(C)]
pub struct ControlStartAbi {
    /// Measured outputs at trim, in the order of `MeasuredOutputs::NAMES`.
    pub trim_outputs: [f64; CONTROL_OUTPUTS],
    /// Trim commands: symmetric elevon rad, differential elevon rad, φ.
    pub trim_commands: [f64; CONTROL_COMMANDS],
    /// `[simulation.inputs]` as JSON (`{}` when the config has none).
    pub schedule_json: StrAbi,
    /// `[control.commands]` as JSON (`{}` when the config has none).
    pub commands_json: StrAbi,
    pub design: DesignSourceAbi,
}

/// Controller functions. `start` is called once, after `create` and before any other; the
/// controller's state is the host's `n_state` numbers (written into restart files).
#[repr(C)]
pub struct ControlFunctions {
    /// Designs the controller about the operating point.
    pub start: unsafe extern "C" fn(handle: *mut c_void, args: *const ControlStartAbi) -> i32,
    /// Interval between samples, s; 0 for a stateless law of time evaluated at every instant.
    pub sample_interval_s: unsafe extern "C" fn(handle: *mut c_void) -> f64,
    /// Length of the controller's state; fixed after `start`.
    pub state_len: unsafe extern "C" fn(handle: *mut c_void) -> usize,
    /// The state at trim, `n_state` values.
    pub initial_state:
        unsafe extern "C" fn(handle: *mut c_void, state: *mut f64, n_state: usize) -> i32,
    /// One sample: [`CONTROL_OUTPUTS`] measured outputs in, the state advanced in place,
    /// [`CONTROL_COMMANDS`] absolute commands out.
    pub update: unsafe extern "C" fn(
        handle: *mut c_void,
        outputs: *const f64,
        state: *mut f64,
        n_state: usize,
        commands: *mut f64,
    ) -> i32,
    /// Copies the design report (JSON; `null` for none) into `buffer` (at most `capacity`
    /// bytes); returns its full length.
    pub design_report:
        unsafe extern "C" fn(handle: *mut c_void, buffer: *mut u8, capacity: usize) -> usize,
    /// Copies the static state-feedback laws u = −K z as JSON (`[{"state_names": [..],
    /// "input_names": [..], "k": [[row], ..]}, ..]`, rows of `k` by input; `[]` for none)
    /// into `buffer`; returns its full length.
    pub state_feedback:
        unsafe extern "C" fn(handle: *mut c_void, buffer: *mut u8, capacity: usize) -> usize,
}
