//! The propulsion region: the engine model on the main body's deformed underside, its loads
//! about the centre of mass and its generalized forces on the body's modes. It runs beside the
//! body's aero (both read the deformed OML and nothing of each other) and is published with the
//! body on `main_body/loads`. A vehicle without a `[regions.propulsion]` table has none (a
//! glide).

use hsv_core::ModelError;
use hsv_core::aero::Loads;
use hsv_core::coupling::generalized_forces;
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use hsv_core::propulsion::{EngineInputs, PropulsionModel, PropulsionSolution};
use nalgebra::Point3;

use super::FlightControls;
use crate::vehicle::error::{VehicleError, model_error};

/// The propulsion region's model and its last evaluation.
pub(in crate::vehicle) struct Engine {
    pub(in crate::vehicle) model: Box<dyn PropulsionModel>,
    pub(in crate::vehicle) solution: PropulsionSolution,
    /// Generalized forces of its panel pressures on the body's modes, N (zero for an engine
    /// model without panel pressures).
    pub(in crate::vehicle) generalized: Vec<f64>,
}

impl Engine {
    pub(in crate::vehicle) fn new(model: Box<dyn PropulsionModel>, n_body_modes: usize) -> Self {
        Self {
            model,
            solution: PropulsionSolution::default(),
            generalized: vec![0.0; n_body_modes],
        }
    }
}

/// The engine's loads about the centre of mass `cg` on the body's deformed `mesh` (its moment
/// comes about `reference_point_m`), and its generalized forces on the body's `shapes`.
pub(in crate::vehicle) fn engine_region_loads(
    engine: &mut Engine,
    (mesh, shapes): (&PanelMesh, &ModeShapes),
    flight: &FlightCondition,
    controls: &FlightControls,
    (cg, reference_point_m): (&Point3<f64>, &Point3<f64>),
) -> Result<Loads, VehicleError> {
    let engine_err = model_error("propulsion");
    let p_inf = flight.freestream.pressure_pa;
    engine
        .model
        .evaluate(
            &EngineInputs {
                flight,
                body: mesh,
                fuel_equivalence_ratio: controls.fuel_equivalence_ratio,
            },
            &mut engine.solution,
        )
        .map_err(&engine_err)?;
    let e = engine.solution.loads;
    if engine.solution.panel_pressure_pa.len() == mesh.panels.len() {
        generalized_forces(
            mesh,
            shapes,
            &engine.solution.panel_pressure_pa,
            p_inf,
            |r| r == RegionKind::Propulsion,
            &mut engine.generalized,
        )
        .map_err(|e| engine_err(ModelError::inconsistent("coupling", e.to_string())))?;
    } else {
        engine.generalized.iter_mut().for_each(|q| *q = 0.0);
    }
    Ok(Loads {
        force_n: e.force_n,
        moment_nm: e.moment_nm + (reference_point_m - cg).cross(&e.force_n),
    })
}
