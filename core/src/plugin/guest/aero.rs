//! The aero role behind the plugin ABI: a guest's `AeroModel` evaluated on the host's mesh and
//! motion buffers.

use super::*;

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

pub(super) fn vectors(values: &[f64], out: &mut Vec<Vector3<f64>>) {
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
