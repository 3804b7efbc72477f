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
use crate::control::{
    ControlCommands, ControlContext, Controller, DesignSource, MeasuredOutputs, StateFeedback,
};
use crate::error::ModelError;
use crate::flow::FlightCondition;
use crate::mesh::{ModeShapes, PanelMesh};
use crate::propulsion::{
    EngineInputs, EngineStatus, PropulsionModel, PropulsionSolution, StationState,
};
use crate::registry::ModelContext;
use crate::structure::{
    MassDistribution, MassProperties, ModalModel, RigidBodyCoupling, RigidDof, RootLoads,
    StructureModel, ThermalStiffness,
};
use crate::thermal::{
    ConductionModel, HeatFluxModel, SkinFriction, check_heat_flux_inputs, check_step_inputs,
    check_wall_shear_inputs,
};

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

/// An aero plugin model behind [`AeroModel`].
pub struct AeroAdapter {
    handle: Handle,
    functions: &'static AeroFunctions,
    mesh: MeshBuffers,
    elastic: Vec<f64>,
    edge: Vec<f64>,
}

impl AeroAdapter {
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static AeroFunctions,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        Ok(Self {
            handle: Handle::create(entry, name, context)?,
            functions,
            mesh: MeshBuffers::default(),
            elastic: Vec::new(),
            edge: Vec::new(),
        })
    }
}

impl AeroModel for AeroAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        let name = &self.handle.name;
        let n = mesh.panels.len();
        self.mesh.fill(mesh);
        let elastic = match motion.elastic_velocity_m_s {
            Some(velocities) => {
                check_len(name, "elastic panel velocities", velocities.len(), n)?;
                self.elastic.clear();
                for v in velocities {
                    self.elastic.extend_from_slice(v.as_slice());
                }
                self.elastic.as_ptr()
            }
            None => std::ptr::null(),
        };
        let input = AeroInputAbi {
            flight: flight_abi(flight),
            mesh: self.mesh.abi(),
            elastic_velocity_m_s: elastic,
        };
        out.reset(n);
        self.edge.clear();
        self.edge.resize(5 * n, 0.0);
        let mut output = AeroOutputAbi {
            pressure_pa: out.pressure_pa.as_mut_ptr(),
            edge: self.edge.as_mut_ptr(),
            diagnostics: [0; 4],
        };
        // SAFETY: every buffer has the length the ABI states for `n` panels.
        let status = unsafe { (self.functions.evaluate)(self.handle.raw, &input, &mut output) };
        self.handle.check(status, "evaluation")?;
        check_finite(name, "pressure", &out.pressure_pa, 1, "panel")?;
        check_finite(name, "edge state", &self.edge, 5, "panel")?;
        for (edge, values) in out.edge.iter_mut().zip(self.edge.chunks_exact(5)) {
            *edge = edge_from(values);
        }
        let [shadowed, detached, piston, vacuum] = output.diagnostics.map(|c| c as usize);
        let d = &mut out.diagnostics;
        d.shadowed_panels = shadowed;
        d.detached_shocks = detached;
        d.piston_theory_violations = piston;
        d.vacuum_expansions = vacuum;
        Ok(())
    }
}

/// A heat-flux plugin model behind [`HeatFluxModel`] (and [`SkinFriction`] when it has it).
pub struct HeatFluxAdapter {
    handle: Handle,
    functions: &'static HeatFluxFunctions,
    mesh: MeshBuffers,
    edge: Vec<f64>,
}

impl HeatFluxAdapter {
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static HeatFluxFunctions,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        Ok(Self {
            handle: Handle::create(entry, name, context)?,
            functions,
            mesh: MeshBuffers::default(),
            edge: Vec::new(),
        })
    }

    /// Calls `function` on the wall inputs; `out` has one value per panel (checked by the caller).
    fn call_wall(
        &mut self,
        function: unsafe extern "C" fn(*mut c_void, *const WallInputAbi, *mut f64) -> i32,
        what: &str,
        wall: Wall<'_>,
        out: &mut [f64],
    ) -> Result<(), ModelError> {
        self.mesh.fill(wall.mesh);
        flatten_edges(&wall.aero.edge, &mut self.edge);
        let input = WallInputAbi {
            flight: flight_abi(wall.flight),
            mesh: self.mesh.abi(),
            pressure_pa: wall.aero.pressure_pa.as_ptr(),
            edge: self.edge.as_ptr(),
            wall_temperature_k: wall.temperature_k.as_ptr(),
        };
        // SAFETY: the caller checked one pressure, edge state, wall temperature and output per
        // panel.
        let status = unsafe { function(self.handle.raw, &input, out.as_mut_ptr()) };
        self.handle.check(status, what)?;
        check_finite(&self.handle.name, what, out, 1, "panel")
    }
}

/// The inputs of a heat-flux or wall-shear call.
struct Wall<'a> {
    mesh: &'a PanelMesh,
    flight: &'a FlightCondition,
    aero: &'a AeroSolution,
    temperature_k: &'a [f64],
}

impl HeatFluxModel for HeatFluxAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn heat_flux(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
        out_w_m2: &mut [f64],
    ) -> Result<(), ModelError> {
        check_heat_flux_inputs(
            &self.handle.name,
            mesh,
            flight,
            aero,
            wall_temperature_k,
            out_w_m2,
        )?;
        check_len(
            &self.handle.name,
            "pressures",
            aero.pressure_pa.len(),
            mesh.panels.len(),
        )?;
        let function = self.functions.heat_flux;
        self.call_wall(
            function,
            "heat flux",
            Wall {
                mesh,
                flight,
                aero,
                temperature_k: wall_temperature_k,
            },
            out_w_m2,
        )
    }

    fn skin_friction(&mut self) -> Option<&mut dyn SkinFriction> {
        if self.handle.has(CAPABILITY_SKIN_FRICTION) {
            Some(self)
        } else {
            None
        }
    }
}

impl SkinFriction for HeatFluxAdapter {
    fn wall_shear(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
        out_pa: &mut [f64],
    ) -> Result<(), ModelError> {
        check_wall_shear_inputs(
            &self.handle.name,
            mesh,
            flight,
            aero,
            wall_temperature_k,
            out_pa,
        )?;
        check_len(
            &self.handle.name,
            "pressures",
            aero.pressure_pa.len(),
            mesh.panels.len(),
        )?;
        let function = self.functions.wall_shear;
        self.call_wall(
            function,
            "wall shear",
            Wall {
                mesh,
                flight,
                aero,
                temperature_k: wall_temperature_k,
            },
            out_pa,
        )
    }
}

/// A conduction plugin model behind [`ConductionModel`].
///
/// The trait's temperature reads cannot fail; when the plugin's do, the adapter fills the output
/// with NaN (which every consumer's temperature check rejects) and returns the plugin's message
/// from the next `step` or `uniform_state`.
pub struct ConductionAdapter {
    handle: Handle,
    functions: &'static ConductionFunctions,
    /// n_states, n_nodes, n_surface_panels.
    sizes: [usize; 3],
    pending: RefCell<Option<ModelError>>,
}

impl ConductionAdapter {
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static ConductionFunctions,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        let handle = Handle::create(entry, name, context)?;
        let mut sizes = [0usize; 3];
        // SAFETY: room for the 3 sizes.
        let status = unsafe { (functions.sizes)(handle.raw, sizes.as_mut_ptr()) };
        handle.check(status, "sizes")?;
        Ok(Self {
            handle,
            functions,
            sizes,
            pending: RefCell::new(None),
        })
    }

    fn take_pending(&self) -> Result<(), ModelError> {
        match self.pending.borrow_mut().take() {
            Some(error) => Err(error),
            None => Ok(()),
        }
    }

    fn read(
        &self,
        function: ReadStateFn,
        what: &str,
        state: &DVector<f64>,
        out_k: &mut [f64],
        expected: usize,
    ) {
        let name = &self.handle.name;
        let result = check_len(name, "state values", state.len(), self.sizes[0])
            .and_then(|()| check_len(name, &format!("{what} slots"), out_k.len(), expected))
            .and_then(|()| {
                // SAFETY: state and output have the lengths the plugin reported.
                let status = unsafe {
                    function(
                        self.handle.raw,
                        state.as_ptr(),
                        state.len(),
                        out_k.as_mut_ptr(),
                        out_k.len(),
                    )
                };
                self.handle.check(status, what)
            })
            .and_then(|()| check_finite(name, what, out_k, 1, "entry"));
        if let Err(error) = result {
            out_k.fill(f64::NAN);
            self.pending.borrow_mut().get_or_insert(error);
        }
    }
}

impl ConductionModel for ConductionAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn n_states(&self) -> usize {
        self.sizes[0]
    }

    fn n_nodes(&self) -> usize {
        self.sizes[1]
    }

    fn n_surface_panels(&self) -> usize {
        self.sizes[2]
    }

    fn uniform_state(&self, temperature_k: f64) -> Result<DVector<f64>, ModelError> {
        self.take_pending()?;
        let mut state = DVector::zeros(self.sizes[0]);
        // SAFETY: the state has the length the plugin reported.
        let status = unsafe {
            (self.functions.uniform_state)(
                self.handle.raw,
                temperature_k,
                state.as_mut_ptr(),
                state.len(),
            )
        };
        self.handle.check(status, "uniform state")?;
        check_finite(
            &self.handle.name,
            "uniform state",
            state.as_slice(),
            1,
            "state",
        )?;
        Ok(state)
    }

    fn step(
        &mut self,
        state: &mut DVector<f64>,
        surface_heat_flux_w_m2: &[f64],
        dt_s: f64,
    ) -> Result<(), ModelError> {
        self.take_pending()?;
        let name = &self.handle.name;
        check_len(name, "state values", state.len(), self.sizes[0])?;
        check_len(
            name,
            "surface heat fluxes",
            surface_heat_flux_w_m2.len(),
            self.sizes[2],
        )?;
        check_step_inputs(name, surface_heat_flux_w_m2, dt_s)?;
        // SAFETY: state and heat flux have the lengths the plugin reported.
        let status = unsafe {
            (self.functions.step)(
                self.handle.raw,
                state.as_mut_ptr(),
                state.len(),
                surface_heat_flux_w_m2.as_ptr(),
                surface_heat_flux_w_m2.len(),
                dt_s,
            )
        };
        self.handle.check(status, "step")?;
        check_finite(name, "thermal state", state.as_slice(), 1, "state")
    }

    fn surface_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let function = self.functions.surface_temperatures;
        self.read(
            function,
            "surface temperatures",
            state,
            out_k,
            self.sizes[2],
        );
    }

    fn node_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let function = self.functions.node_temperatures;
        self.read(function, "node temperatures", state, out_k, self.sizes[1]);
    }

    fn node_temperature_differences(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let function = self.functions.node_temperature_differences;
        self.read(
            function,
            "node temperature differences",
            state,
            out_k,
            self.sizes[1],
        );
    }
}

/// A structure plugin model behind [`StructureModel`] and the capabilities it declares.
///
/// Modal matrices, mass properties and rigid coupling are read at creation and after every
/// temperature update, so the trait's infallible accessors return checked, cached values.
pub struct StructureAdapter {
    handle: Handle,
    functions: &'static StructureFunctions,
    modal: ModalModel,
    temperature_nodes: usize,
    thermal_forces: Option<DVector<f64>>,
    root_reference: Point3<f64>,
    mass: MassProperties,
    rigid_dofs: Vec<RigidDof>,
    rigid_reference: Point3<f64>,
    rigid_coupling: DMatrix<f64>,
}

fn rigid_dof(code: u32) -> Option<RigidDof> {
    Some(match code {
        0 => RigidDof::TranslationX,
        1 => RigidDof::TranslationY,
        2 => RigidDof::TranslationZ,
        3 => RigidDof::RotationX,
        4 => RigidDof::RotationY,
        5 => RigidDof::RotationZ,
        _ => return None,
    })
}

impl StructureAdapter {
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static StructureFunctions,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        let mut model = Self {
            handle: Handle::create(entry, name, context)?,
            functions,
            modal: ModalModel::default(),
            temperature_nodes: 0,
            thermal_forces: None,
            root_reference: Point3::origin(),
            mass: MassProperties {
                mass_kg: 0.0,
                center_of_mass_m: Point3::origin(),
                inertia_kg_m2: Matrix3::zeros(),
            },
            rigid_dofs: Vec::new(),
            rigid_reference: Point3::origin(),
            rigid_coupling: DMatrix::zeros(0, 0),
        };
        model.refresh()?;
        Ok(model)
    }

    fn raw(&self) -> *mut c_void {
        self.handle.raw
    }

    /// Reads every cached quantity from the plugin.
    fn refresh(&mut self) -> Result<(), ModelError> {
        let f = self.functions;
        // SAFETY: every call below gets buffers of the sizes the plugin reported.
        let n = unsafe { (f.n_modes)(self.raw()) };
        if n == 0 {
            return Err(plugin_failure(
                &self.handle.name,
                "modal model",
                format!(
                    "no modes ({})",
                    plugin_message(self.handle.entry, self.raw())
                ),
            ));
        }
        let mut names = Vec::with_capacity(n);
        let mut buffer = vec![0u8; 256];
        for k in 0..n {
            let len = unsafe { (f.mode_name)(self.raw(), k, buffer.as_mut_ptr(), buffer.len()) };
            names.push(String::from_utf8_lossy(&buffer[..len.min(buffer.len())]).into_owned());
        }
        let (mut mass, mut damping, mut stiffness) = (
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        );
        let status = unsafe {
            (f.modal_matrices)(
                self.raw(),
                mass.as_mut_ptr(),
                damping.as_mut_ptr(),
                stiffness.as_mut_ptr(),
                n,
            )
        };
        self.handle.check(status, "modal matrices")?;
        let name = self.handle.name.clone();
        for (what, matrix) in [
            ("generalized mass", &mass),
            ("generalized damping", &damping),
            ("generalized stiffness", &stiffness),
        ] {
            check_finite(&name, what, matrix.as_slice(), 1, "entry")?;
        }
        self.modal = ModalModel {
            names,
            mass,
            damping,
            stiffness,
        };
        if self.handle.has(CAPABILITY_THERMAL_STIFFNESS) {
            self.temperature_nodes = unsafe { (f.temperature_nodes)(self.raw()) };
            let mut forces = DVector::zeros(n);
            let status =
                unsafe { (f.thermal_generalized_forces)(self.raw(), forces.as_mut_ptr(), n) };
            self.thermal_forces = if status == PLUGIN_STATUS_NONE {
                None
            } else {
                self.handle.check(status, "thermal generalized forces")?;
                check_finite(
                    &name,
                    "thermal generalized force",
                    forces.as_slice(),
                    1,
                    "mode",
                )?;
                Some(forces)
            };
        }
        if self.handle.has(CAPABILITY_ROOT_LOADS) {
            let mut point = [0.0; 3];
            let status = unsafe { (f.root_reference_m)(self.raw(), point.as_mut_ptr()) };
            self.handle.check(status, "root reference")?;
            check_finite(&name, "root reference point", &point, 3, "point")?;
            self.root_reference = Point3::from(point);
        }
        if self.handle.has(CAPABILITY_MASS_PROPERTIES) {
            let mut values = [0.0; 13];
            let status = unsafe { (f.mass_properties)(self.raw(), values.as_mut_ptr()) };
            self.handle.check(status, "mass properties")?;
            check_finite(&name, "mass properties", &values, 13, "entry")?;
            self.mass = MassProperties {
                mass_kg: values[0],
                center_of_mass_m: Point3::new(values[1], values[2], values[3]),
                inertia_kg_m2: Matrix3::from_column_slice(&values[4..]),
            };
        }
        if self.handle.has(CAPABILITY_RIGID_BODY_COUPLING) {
            let (mut codes, mut point) = ([u32::MAX; 6], [0.0; 3]);
            let count =
                unsafe { (f.rigid_dofs)(self.raw(), codes.as_mut_ptr(), point.as_mut_ptr()) };
            if count == 0 || count > 6 {
                return Err(plugin_failure(
                    &name,
                    "rigid degrees of freedom",
                    format!(
                        "{count} degrees of freedom ({})",
                        plugin_message(self.handle.entry, self.raw())
                    ),
                ));
            }
            let dofs: Option<Vec<RigidDof>> =
                codes[..count].iter().map(|&c| rigid_dof(c)).collect();
            self.rigid_dofs = dofs.ok_or_else(|| {
                ModelError::inconsistent(&name, "plugin rigid degree-of-freedom code is not 0-5")
            })?;
            self.rigid_reference = Point3::from(point);
            let mut coupling = DMatrix::zeros(n, count);
            let status = unsafe { (f.rigid_coupling)(self.raw(), coupling.as_mut_ptr(), n, count) };
            self.handle.check(status, "rigid coupling")?;
            check_finite(&name, "rigid coupling", coupling.as_slice(), n, "rigid dof")?;
            self.rigid_coupling = coupling;
        }
        Ok(())
    }

    fn set_field(
        &mut self,
        mean_k: &[f64],
        difference_k: Option<&[f64]>,
    ) -> Result<(), ModelError> {
        let name = &self.handle.name;
        check_len(
            name,
            "node temperatures",
            mean_k.len(),
            self.temperature_nodes,
        )?;
        if let Some(difference) = difference_k {
            check_len(
                name,
                "temperature differences",
                difference.len(),
                self.temperature_nodes,
            )?;
        }
        // SAFETY: both buffers have the node count the plugin reported.
        let status = unsafe {
            (self.functions.set_temperature_field)(
                self.raw(),
                mean_k.as_ptr(),
                difference_k.map_or(std::ptr::null(), <[f64]>::as_ptr),
                mean_k.len(),
            )
        };
        self.handle.check(status, "temperature update")?;
        self.refresh()
    }
}

impl StructureModel for StructureAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn modal_model(&self) -> &ModalModel {
        &self.modal
    }

    fn natural_frequencies_hz(&self) -> Result<Vec<f64>, ModelError> {
        let n = self.modal.n_modes();
        let mut out = vec![0.0; n];
        // SAFETY: room for n frequencies.
        let status =
            unsafe { (self.functions.natural_frequencies_hz)(self.raw(), out.as_mut_ptr(), n) };
        self.handle.check(status, "natural frequencies")?;
        check_finite(&self.handle.name, "natural frequency", &out, 1, "mode")?;
        Ok(out)
    }

    fn mode_shapes_on(&self, mesh: &PanelMesh) -> Result<ModeShapes, ModelError> {
        let n = self.modal.n_modes();
        let mut buffers = MeshBuffers::default();
        buffers.fill(mesh);
        let abi = buffers.abi();
        let mut shapes = DMatrix::zeros(3 * mesh.vertices.len(), n);
        // SAFETY: room for 3 n_vertices × n_modes values.
        let status =
            unsafe { (self.functions.mode_shapes_on)(self.raw(), &abi, shapes.as_mut_ptr(), n) };
        self.handle.check(status, "mode shapes")?;
        check_finite(
            &self.handle.name,
            "mode shape",
            shapes.as_slice(),
            3,
            "vertex (row-major over modes)",
        )?;
        Ok(ModeShapes {
            vertex_displacement: shapes,
        })
    }

    fn thermal_stiffness(&self) -> Option<&dyn ThermalStiffness> {
        self.handle
            .has(CAPABILITY_THERMAL_STIFFNESS)
            .then_some(self as &dyn ThermalStiffness)
    }

    fn thermal_stiffness_mut(&mut self) -> Option<&mut dyn ThermalStiffness> {
        if self.handle.has(CAPABILITY_THERMAL_STIFFNESS) {
            Some(self)
        } else {
            None
        }
    }

    fn root_loads(&self) -> Option<&dyn RootLoads> {
        self.handle
            .has(CAPABILITY_ROOT_LOADS)
            .then_some(self as &dyn RootLoads)
    }

    fn mass_properties(&self) -> Option<&dyn MassDistribution> {
        self.handle
            .has(CAPABILITY_MASS_PROPERTIES)
            .then_some(self as &dyn MassDistribution)
    }

    fn rigid_body_coupling(&self) -> Option<&dyn RigidBodyCoupling> {
        self.handle
            .has(CAPABILITY_RIGID_BODY_COUPLING)
            .then_some(self as &dyn RigidBodyCoupling)
    }
}

impl ThermalStiffness for StructureAdapter {
    fn temperature_nodes(&self) -> usize {
        self.temperature_nodes
    }

    fn set_temperatures(&mut self, node_temperatures_k: &[f64]) -> Result<(), ModelError> {
        self.set_field(node_temperatures_k, None)
    }

    fn set_temperature_field(
        &mut self,
        mean_k: &[f64],
        difference_k: &[f64],
    ) -> Result<(), ModelError> {
        self.set_field(mean_k, Some(difference_k))
    }

    fn thermal_generalized_forces(&self) -> Option<&DVector<f64>> {
        self.thermal_forces.as_ref()
    }
}

impl RootLoads for StructureAdapter {
    fn root_reference_m(&self) -> Point3<f64> {
        self.root_reference
    }

    fn root_loads(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
        applied: &Loads,
    ) -> Result<Loads, ModelError> {
        let name = &self.handle.name;
        let n = self.modal.n_modes();
        check_len(name, "modal coordinates", modal_coordinates.len(), n)?;
        check_len(name, "modal velocities", modal_velocities.len(), n)?;
        check_len(name, "modal accelerations", modal_accelerations.len(), n)?;
        let a = [
            applied.force_n.x,
            applied.force_n.y,
            applied.force_n.z,
            applied.moment_nm.x,
            applied.moment_nm.y,
            applied.moment_nm.z,
        ];
        let mut out = [0.0; 6];
        // SAFETY: n modal values each, 6 applied and 6 output values.
        let status = unsafe {
            (self.functions.root_loads)(
                self.raw(),
                modal_coordinates.as_ptr(),
                modal_velocities.as_ptr(),
                modal_accelerations.as_ptr(),
                n,
                a.as_ptr(),
                out.as_mut_ptr(),
            )
        };
        self.handle.check(status, "root loads")?;
        check_finite(name, "root load", &out, 6, "root")?;
        Ok(Loads {
            force_n: Vector3::new(out[0], out[1], out[2]),
            moment_nm: Vector3::new(out[3], out[4], out[5]),
        })
    }
}

impl MassDistribution for StructureAdapter {
    fn mass_properties(&self) -> MassProperties {
        self.mass
    }
}

impl RigidBodyCoupling for StructureAdapter {
    fn rigid_dofs(&self) -> &[RigidDof] {
        &self.rigid_dofs
    }

    fn rigid_reference_point_m(&self) -> Point3<f64> {
        self.rigid_reference
    }

    fn rigid_coupling(&self) -> &DMatrix<f64> {
        &self.rigid_coupling
    }
}

/// A propulsion plugin model behind [`PropulsionModel`].
pub struct PropulsionAdapter {
    handle: Handle,
    functions: &'static PropulsionFunctions,
    mesh: MeshBuffers,
    stations: Vec<StationAbi>,
}

impl PropulsionAdapter {
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static PropulsionFunctions,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        Ok(Self {
            handle: Handle::create(entry, name, context)?,
            functions,
            mesh: MeshBuffers::default(),
            stations: Vec::new(),
        })
    }
}

fn engine_status(code: u32) -> Option<EngineStatus> {
    Some(match code {
        ENGINE_OK => EngineStatus::Ok,
        ENGINE_SPILLAGE => EngineStatus::Spillage,
        ENGINE_THERMAL_CHOKING => EngineStatus::ThermalChoking,
        ENGINE_UNSTART => EngineStatus::Unstart,
        _ => return None,
    })
}

impl PropulsionModel for PropulsionAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn evaluate(
        &mut self,
        inputs: &EngineInputs<'_>,
        out: &mut PropulsionSolution,
    ) -> Result<(), ModelError> {
        let name = &self.handle.name;
        let n = inputs.body.panels.len();
        self.mesh.fill(inputs.body);
        let input = EngineInputAbi {
            flight: flight_abi(inputs.flight),
            body: self.mesh.abi(),
            fuel_equivalence_ratio: inputs.fuel_equivalence_ratio,
        };
        out.panel_pressure_pa.clear();
        out.panel_pressure_pa.resize(n, 0.0);
        let blank = StationAbi {
            name: [0; STATION_NAME_BYTES],
            mach: 0.0,
            pressure_pa: 0.0,
            temperature_k: 0.0,
        };
        self.stations.clear();
        self.stations.resize(STATION_CAPACITY, blank);
        let mut output = EngineOutputAbi {
            loads: [0.0; 6],
            mass_flow_kg_s: 0.0,
            status: ENGINE_OK,
            panel_pressure_pa: out.panel_pressure_pa.as_mut_ptr(),
            stations: self.stations.as_mut_ptr(),
            station_capacity: STATION_CAPACITY,
            n_stations: 0,
        };
        // SAFETY: n panel pressures and STATION_CAPACITY stations of room.
        let status = unsafe { (self.functions.evaluate)(self.handle.raw, &input, &mut output) };
        self.handle.check(status, "evaluation")?;
        check_finite(name, "engine load", &output.loads, 6, "loads")?;
        check_finite(name, "mass flow", &[output.mass_flow_kg_s], 1, "inlet")?;
        check_finite(name, "panel pressure", &out.panel_pressure_pa, 1, "panel")?;
        if output.n_stations > STATION_CAPACITY {
            return Err(ModelError::inconsistent(
                name,
                format!(
                    "plugin reported {} stations, more than the {STATION_CAPACITY} it had room for",
                    output.n_stations
                ),
            ));
        }
        let l = output.loads;
        out.loads = Loads {
            force_n: Vector3::new(l[0], l[1], l[2]),
            moment_nm: Vector3::new(l[3], l[4], l[5]),
        };
        out.mass_flow_kg_s = output.mass_flow_kg_s;
        out.status = engine_status(output.status).ok_or_else(|| {
            ModelError::inconsistent(
                name,
                format!("plugin engine status code {} is not 0-3", output.status),
            )
        })?;
        out.stations.truncate(output.n_stations);
        for (k, station) in self.stations[..output.n_stations].iter().enumerate() {
            let end = station
                .name
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(STATION_NAME_BYTES);
            let label = String::from_utf8_lossy(&station.name[..end]);
            let values = [station.mach, station.pressure_pa, station.temperature_k];
            check_finite(
                name,
                &format!("station `{label}` state"),
                &values,
                3,
                "station",
            )?;
            // Reuse the slot (and its name's allocation) when the station is the same.
            if out.stations.get(k).is_none_or(|slot| slot.station != label) {
                let state = StationState {
                    station: label.into_owned(),
                    mach: 0.0,
                    pressure_pa: 0.0,
                    temperature_k: 0.0,
                };
                match out.stations.get_mut(k) {
                    Some(slot) => *slot = state,
                    None => out.stations.push(state),
                }
            }
            let slot = &mut out.stations[k];
            slot.mach = station.mach;
            slot.pressure_pa = station.pressure_pa;
            slot.temperature_k = station.temperature_k;
        }
        Ok(())
    }
}

/// Reads a text the plugin copies into a buffer and whose full length it returns.
fn read_text(
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
struct HostDesign<'a> {
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
