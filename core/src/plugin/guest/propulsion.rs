//! The propulsion role behind the plugin ABI: engine inputs in, loads and named stations out.

use super::*;

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
pub(super) fn station_name(name: &str) -> [u8; STATION_NAME_BYTES] {
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
