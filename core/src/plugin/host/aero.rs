//! The host's aero adapter: a plugin's aero model behind the `AeroModel` trait, buffers checked
//! before each call and outputs after it.

use super::*;

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
