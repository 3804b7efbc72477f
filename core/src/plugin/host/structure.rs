//! The host's structure adapter: modal model, mode shapes and the optional capabilities (thermal
//! stiffness, root loads, mass distribution, rigid-body coupling).

use super::*;

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

pub(super) fn rigid_dof(code: u32) -> Option<RigidDof> {
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
