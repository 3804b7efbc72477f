//! The heat-flux role behind the plugin ABI.

use super::*;

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
