//! The conduction role behind the plugin ABI: state, steps and the surface temperatures.

use super::*;

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
