//! The host's heat-flux adapter (heat flux and skin friction).

use super::*;

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
pub(super) struct Wall<'a> {
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
