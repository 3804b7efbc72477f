//! Skin friction of one region: the wall shear of its heat-flux model on the aero model's edge
//! states, as force and moment along the local edge flow (`hsv_core::aero::integrate_shear`).

use hsv_core::ModelError;
use hsv_core::aero::{AeroSolution, Loads, PanelMotion, integrate_shear};
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::{PanelMesh, RegionKind};
use hsv_core::thermal::HeatFluxModel;
use nalgebra::Point3;

/// Wall temperature of the friction law, K (our choice: a cold, thermally protected wall, the
/// default of `hsv-run aero --friction`; the heated surfaces' own temperatures are a refinement
/// left to the thermal coupling).
pub const FRICTION_WALL_TEMPERATURE_K: f64 = 300.0;

/// A region's friction model and its buffers.
pub struct RegionFriction {
    model: Box<dyn HeatFluxModel>,
    wall_k: Vec<f64>,
    shear_pa: Vec<f64>,
}

impl RegionFriction {
    /// `model` must have a wall-shear law (checked at assembly).
    pub fn new(model: Box<dyn HeatFluxModel>, n_panels: usize) -> Self {
        Self {
            model,
            wall_k: vec![FRICTION_WALL_TEMPERATURE_K; n_panels],
            shear_pa: vec![0.0; n_panels],
        }
    }

    /// Friction force and moment about `point` on the panels `include` passes. No allocation
    /// once the buffers fit the mesh.
    pub fn loads(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        motion: &PanelMotion<'_>,
        point: &Point3<f64>,
        include: impl Fn(RegionKind) -> bool,
    ) -> Result<Loads, ModelError> {
        let n = mesh.panels.len();
        self.wall_k.resize(n, FRICTION_WALL_TEMPERATURE_K);
        self.shear_pa.resize(n, 0.0);
        let Some(law) = self.model.skin_friction() else {
            return Err(ModelError::inconsistent(
                self.model.name(),
                "no wall-shear law",
            ));
        };
        law.wall_shear(mesh, flight, aero, &self.wall_k, &mut self.shear_pa)?;
        Ok(integrate_shear(
            mesh,
            &self.shear_pa,
            flight,
            motion,
            point,
            include,
        ))
    }
}
