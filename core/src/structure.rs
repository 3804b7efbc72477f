//! The structure role: a modal model (generalized mass, damping, stiffness) and its mode shapes.

use nalgebra::{DMatrix, DVector, Matrix3, Point3};

use crate::aero::Loads;
use crate::error::ModelError;
use crate::mesh::{ModeShapes, PanelMesh};
use crate::surface_grid::SurfaceGrid;

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
///
/// What a structure can do beyond its modal matrices is a capability: a separate trait the model
/// opts into by returning itself from the matching accessor (`None` by default). Assembly asks
/// for what an analysis needs with [`require`] before t = 0.
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

    /// Temperature-dependent stiffness, if the model has it.
    fn thermal_stiffness(&self) -> Option<&dyn ThermalStiffness> {
        None
    }

    /// Temperature-dependent stiffness, mutable (to set temperatures).
    fn thermal_stiffness_mut(&mut self) -> Option<&mut dyn ThermalStiffness> {
        None
    }

    /// Loads at the support (a lifting surface's torque tube), if the structure has a root.
    fn root_loads(&self) -> Option<&dyn RootLoads> {
        None
    }

    /// Mass, centre of mass and inertia, if the model knows its mass distribution.
    fn mass_properties(&self) -> Option<&dyn MassDistribution> {
        None
    }

    /// Inertial coupling between the modes and rigid-body motion, if the model gives it.
    fn rigid_body_coupling(&self) -> Option<&dyn RigidBodyCoupling> {
        None
    }
}

/// Stiffness that follows a temperature field: heat-degraded modulus and thermal stress.
pub trait ThermalStiffness {
    /// Number of structural node temperatures [`Self::set_temperatures`] expects.
    fn temperature_nodes(&self) -> usize;

    /// Updates stiffness from structural node temperatures (K), uniform through the thickness.
    fn set_temperatures(&mut self, node_temperatures_k: &[f64]) -> Result<(), ModelError>;

    /// Updates stiffness and the thermal-moment load from mean node temperatures and
    /// through-thickness differences (lower face minus upper face, K, linear in z). Models
    /// without bending from a thermal gradient take the mean only.
    fn set_temperature_field(
        &mut self,
        mean_k: &[f64],
        difference_k: &[f64],
    ) -> Result<(), ModelError> {
        let _ = difference_k;
        self.set_temperatures(mean_k)
    }

    /// Generalized force of the thermal moment of the latest temperature field (one per mode),
    /// added to the applied generalized forces; `None` when the model has no thermal moments.
    fn thermal_generalized_forces(&self) -> Option<&DVector<f64>> {
        None
    }

    /// The surface grid whose nodes [`Self::set_temperatures`] takes, if the model has one:
    /// what a conduction model's node temperatures are interpolated onto.
    fn temperature_grid(&self) -> Option<&SurfaceGrid> {
        None
    }
}

/// Forces and moments a structure exerts on its support.
pub trait RootLoads {
    /// The point root moments are taken about (a lifting surface's pivot), body axes, m.
    fn root_reference_m(&self) -> Point3<f64>;

    /// Root force and moment (body axes, about [`Self::root_reference_m`]) by force summation
    /// over the free structure: `applied`, the resultant about the root reference of every
    /// external load on it (aero pressure, for example from `coupling::pressure_loads`), minus
    /// the inertia of the elastic motion. Stiffness and damping forces are internal, so a
    /// truncated modal basis enters only through the accelerations.
    fn root_loads(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
        applied: &Loads,
    ) -> Result<Loads, ModelError>;
}

/// Mass, centre of mass and inertia tensor of a structure, body axes.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MassProperties {
    pub mass_kg: f64,
    /// m, body axes.
    pub center_of_mass_m: Point3<f64>,
    /// Inertia tensor about the centre of mass, body axes, kg m² (products of inertia with the
    /// sign convention I_xy = −∫ x y dm).
    pub inertia_kg_m2: Matrix3<f64>,
}

impl MassProperties {
    /// The inertia tensor about `point` by the parallel-axis theorem, kg m²:
    /// I_P = I_G + m (|d|² 1 − d dᵀ), d = G − P.
    pub fn inertia_about(&self, point: &Point3<f64>) -> Matrix3<f64> {
        let d = self.center_of_mass_m - point;
        self.inertia_kg_m2
            + self.mass_kg * (Matrix3::identity() * d.norm_squared() - d * d.transpose())
    }

    /// The mass properties of two bodies together.
    pub fn combined(&self, other: &MassProperties) -> MassProperties {
        let mass_kg = self.mass_kg + other.mass_kg;
        let center = Point3::from(
            (self.center_of_mass_m.coords * self.mass_kg
                + other.center_of_mass_m.coords * other.mass_kg)
                / mass_kg,
        );
        MassProperties {
            mass_kg,
            center_of_mass_m: center,
            inertia_kg_m2: self.inertia_about(&center) + other.inertia_about(&center),
        }
    }
}

/// A structure's mass distribution.
pub trait MassDistribution {
    fn mass_properties(&self) -> MassProperties;
}

/// A rigid-body degree of freedom of a structure's support or reference point, body axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RigidDof {
    TranslationX,
    TranslationY,
    TranslationZ,
    RotationX,
    RotationY,
    RotationZ,
}

/// Inertial coupling of the elastic modes with rigid-body motion.
pub trait RigidBodyCoupling {
    /// The rigid degrees of freedom of [`Self::rigid_coupling`]'s columns (translations in m,
    /// rotations in rad about axes through [`Self::rigid_reference_point_m`]).
    fn rigid_dofs(&self) -> &[RigidDof];

    /// Point the rotations are taken about (a lifting surface's pivot), body axes, m.
    fn rigid_reference_point_m(&self) -> Point3<f64>;

    /// C = Φᵀ M R (n_modes × n_dofs), R the rigid-body displacement fields of
    /// [`Self::rigid_dofs`]: the modal equations get the generalized force −C a for rigid
    /// accelerations a. Zero for free-free modes about their mean axes.
    fn rigid_coupling(&self) -> &DMatrix<f64>;
}

/// An optional structure capability an analysis may need.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Capability {
    ThermalStiffness,
    RootLoads,
    MassProperties,
    RigidBodyCoupling,
}

impl Capability {
    pub fn as_str(self) -> &'static str {
        match self {
            Capability::ThermalStiffness => "temperature-dependent stiffness",
            Capability::RootLoads => "root loads",
            Capability::MassProperties => "mass properties",
            Capability::RigidBodyCoupling => "rigid-body coupling",
        }
    }

    /// Whether `model` has this capability.
    pub fn of(self, model: &dyn StructureModel) -> bool {
        match self {
            Capability::ThermalStiffness => model.thermal_stiffness().is_some(),
            Capability::RootLoads => model.root_loads().is_some(),
            Capability::MassProperties => model.mass_properties().is_some(),
            Capability::RigidBodyCoupling => model.rigid_body_coupling().is_some(),
        }
    }
}

/// Checks at assembly that `model` has every capability `analysis` needs; the error names the
/// model, the first missing capability and the analysis.
pub fn require(
    model: &dyn StructureModel,
    needs: &[Capability],
    analysis: &str,
) -> Result<(), ModelError> {
    match needs.iter().find(|c| !c.of(model)) {
        None => Ok(()),
        Some(missing) => Err(ModelError::Unsupported {
            model: model.name().to_owned(),
            capability: missing.as_str().to_owned(),
            needed_by: analysis.to_owned(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two point masses: m₁ = 1 kg at (1, 0, 0), m₂ = 3 kg at (−1, 0, 0) combine to 4 kg at
    /// x = −0.5 with I_yy = I_zz = Σ m d² = 1·1.5² + 3·0.5² = 3 kg m² and I_xx = 0.
    #[test]
    fn point_masses_combine_by_the_parallel_axis_theorem() {
        let point = |m: f64, x: f64| MassProperties {
            mass_kg: m,
            center_of_mass_m: Point3::new(x, 0.0, 0.0),
            inertia_kg_m2: Matrix3::zeros(),
        };
        let both = point(1.0, 1.0).combined(&point(3.0, -1.0));
        assert_eq!(both.mass_kg, 4.0);
        assert!((both.center_of_mass_m.x + 0.5).abs() < 1e-15);
        let i = both.inertia_kg_m2;
        assert!((i[(1, 1)] - 3.0).abs() < 1e-12 && (i[(2, 2)] - 3.0).abs() < 1e-12);
        assert!(i[(0, 0)].abs() < 1e-12);
        // About the first mass: I_yy = 3·2² = 12.
        let about = both.inertia_about(&Point3::new(1.0, 0.0, 0.0));
        assert!((about[(1, 1)] - 12.0).abs() < 1e-12);
    }
}
