//! The structure role: a modal model (generalized mass, damping, stiffness) and its mode shapes.

use nalgebra::{DMatrix, DVector};

use crate::aero::Loads;
use crate::error::ModelError;
use crate::mesh::{ModeShapes, PanelMesh};

/// Generalized (modal) matrices of a structure, in the mode order of [`ModalModel::names`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModalModel {
    /// Mode names, e.g. "vertical bending 1", "torsion 1".
    pub names: Vec<String>,
    /// Generalized mass, kg (1 for mass-normalized modes).
    pub mass: DMatrix<f64>,
    /// Generalized damping, kg/s.
    pub damping: DMatrix<f64>,
    /// Generalized stiffness, N/m.
    pub stiffness: DMatrix<f64>,
}

impl ModalModel {
    pub fn n_modes(&self) -> usize {
        self.names.len()
    }
}

/// A flexible structure reduced to modal coordinates.
pub trait StructureModel: Send {
    /// The registered name (`free-free-beam`, `ritz-plate`, ...).
    fn name(&self) -> &str;

    /// Current generalized matrices (after the latest temperature update, if any).
    fn modal_model(&self) -> &ModalModel;

    /// Natural frequencies of the current modal model, Hz; an error names a buckled (negative
    /// stiffness) mode instead of returning NaN.
    fn natural_frequencies_hz(&self) -> Result<Vec<f64>, ModelError>;

    /// Displacement field of every mode at the vertices of `mesh` (an aero or thermal mesh of the
    /// same component, in the same axes).
    fn mode_shapes_on(&self, mesh: &PanelMesh) -> Result<ModeShapes, ModelError>;

    /// Number of structural node temperatures `set_temperatures` expects (0: no thermal coupling).
    fn temperature_nodes(&self) -> usize {
        0
    }

    /// Updates stiffness from structural node temperatures (K): heat-degraded modulus and thermal
    /// stress. Structures without thermal coupling say so.
    fn set_temperatures(&mut self, node_temperatures_k: &[f64]) -> Result<(), ModelError> {
        let _ = node_temperatures_k;
        Err(ModelError::Unsupported {
            model: self.name().to_owned(),
            capability: "temperature-dependent stiffness".to_owned(),
            needed_by: "an aerothermoelastic lifting surface".to_owned(),
        })
    }

    /// Forces and moments the structure exerts on its support (a lifting surface's torque tube),
    /// from modal coordinates, velocities and accelerations. Free structures have no root.
    fn root_loads(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
    ) -> Result<Loads, ModelError> {
        let _ = (modal_coordinates, modal_velocities, modal_accelerations);
        Err(ModelError::Unsupported {
            model: self.name().to_owned(),
            capability: "root loads".to_owned(),
            needed_by: "a lifting surface attached to the main body".to_owned(),
        })
    }
}
