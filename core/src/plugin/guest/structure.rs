//! The structure role behind the plugin ABI: modal model, mode shapes, root loads and the
//! optional thermal-stiffness capability.

use super::*;

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

pub(super) fn missing(capability: &str) -> String {
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
