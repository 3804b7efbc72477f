//! The `ritz-plate` lifting-surface structure: a finite-element plate on the surface's structural
//! grid reduced to a Ritz basis of free-vibration modes and static load shapes, with
//! heat-degraded modulus and thermal-stress geometric stiffness updated cheaply from a node
//! temperature field.
//!
//! **Full-order model** ([`plate::PlateModel`]): MITC4 Mindlin-Reissner bending elements
//! (Bathe & Dvorkin 1985) with the double-wedge thickness varying over the grid, consistent
//! mass, Q4 membrane elements for the thermal in-plane problem, and the membrane-prestress
//! geometric stiffness K_G on the transverse displacement. The section is symmetric about the
//! mid-plane, so membrane and bending decouple; the dynamic model is the bending block
//! (w, βx, βy), the membrane block only carries thermal stress.
//!
//! **Torque tube.** The root nodes are clamped to the tube; the Ritz coordinates are elastic
//! motion relative to it. The tube's rigid motion (root x and z translation from the main
//! body, pitch about the pivot axis, paper §III.C, and roll, through which the body's torsion
//! bends the surface) is the coordinator's input: its inertial
//! coupling with the Ritz coordinates is [`RitzPlate::rigid_body_coupling`] (generalized force
//! −C a_root) and the surface's rigid mass [`RitzPlate::rigid_body_mass`].
//!
//! **Root loads.** [`RitzPlate::root_loads_by_force_summation`] returns the load the elastic
//! surface exerts on the tube by force summation over the free body of the surface: the
//! applied load (every node, the root row included) minus the inertia of the elastic motion,
//! L = Rᵀ (f − M Φ q̈), as force and moment about the pivot (R: the rigid motions of the tube).
//! Stiffness and damping forces are internal, so a truncated Ritz basis only enters through
//! q̈, which converges much faster than the stresses. [`StructureModel::root_loads`], whose
//! trait signature does not yet pass the applied loads, still gives the mode-displacement
//! reactions r = K_cf Φ q + M_cf Φ q̈ of the full model's root row, which miss the root row's
//! own load and converge slowly for loads outside the basis.
//!
//! **Ritz basis** (paper §III.C: 10 free-vibration modes + 5 static load shapes; after
//! Falkiewicz & Cesnik): the first N clamped-root modes at 293 K plus the deflections under
//! uniform pressure, a tip force, a tip twisting couple, a chordwise-linear and a
//! spanwise-linear pressure, M-orthogonalized against the modes and diagonalized, so at 293 K
//! M_r = I and K_r = diag(ω²) with the N modes reproduced exactly (Rayleigh-Ritz on a subspace
//! that contains them).
//!
//! **Temperature update** ([`ThermalStiffness::set_temperatures`]): each element takes the mean
//! temperature of its nodes; s_e = E(T_e)/E(293 K), ε_e = α_sec(T_e)(T_e − 293 K). A membrane
//! solve (root held in-plane) gives element resultants N_e; then
//! K_r = Σ_e s_e K_r,e + Σ_e Σ_c N_e,c G_r,e,c from reduced element matrices precomputed once,
//! without reassembling or re-solving the bending model. Compressive N lowers the frequencies;
//! when K_r loses positive definiteness [`StructureModel::natural_frequencies_hz`] reports the
//! surface as buckled. Damping: modal, ζ on every current eigenmode.
//!
//! **Thermal moments** ([`RitzPlate::set_temperature_field`]): a through-thickness temperature
//! difference ΔT (lower face minus upper, linear in z) gives the thermal moment
//! M_T = ∫ E α ΔT z/t z dz = E α ΔT t²/12 (Boley & Weiner, Theory of Thermal Stresses, 1960),
//! the equivalent nodal load f_T = Σ_e s_e Δε_e f_e and the generalized thermal force
//! Q_T = Φᵀ f_T ([`RitzPlate::thermal_generalized_forces`]), summed from reduced element vectors
//! like K_r. It is self-equilibrated, so it adds nothing to the root loads.
//!
//! **Side.** The model is built for the right surface (y > 0); [`RitzPlate::with_side`] selects
//! the left. Mode shapes map onto a mesh of either side (the left as the mirror image).

pub mod fe;
pub mod plate;

use hsv_core::aero::Loads;
use hsv_core::error::ModelError;
use hsv_core::geometry::Side;
use hsv_core::linalg::{BandedMatrix, SymmetricEigenSolver, generalized_symmetric_eigen};
use hsv_core::material::{Material, MaterialSetting};
use hsv_core::mesh::{ModeShapes, PanelMesh};
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};
use hsv_core::structure::{
    MassDistribution, MassProperties, ModalModel, RigidBodyCoupling, RigidDof, RootLoads,
    StructureModel, ThermalStiffness,
};
use hsv_core::surface_grid::{GridEdge, GridPoint, SurfaceGrid};
use nalgebra::{DMatrix, DVector, Matrix3, Point3, Vector3};

use crate::plate::{ElementState, PlateError, PlateModel, Supports};

mod basis;
mod loads;
mod settings;
mod thermal;

use loads::*;
pub use settings::*;

/// Registered name.
pub const NAME: &str = "ritz-plate";

/// Names of the static load shapes, in the order they are added.
pub const STATIC_SHAPES: [&str; 5] = [
    "uniform pressure",
    "tip force",
    "tip twisting couple",
    "chordwise-linear pressure",
    "spanwise-linear pressure",
];

hsv_core::register_model!(ModelDescriptor {
    name: NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "lifting-surface MITC4 plate reduced to free-vibration modes + static load shapes \
              (Ritz); E(T) and thermal-stress geometric stiffness from a temperature field",
    settings_doc: "free_vibration_modes = 10   # clamped-root modes in the Ritz basis (paper: 10)\n\
                   static_shapes = 5           # 0-5: uniform pressure, tip force, tip twist, chordwise- and spanwise-linear pressure\n\
                   elements_chordwise = 24     # structural grid (>= 2; the ridge is a node line)\n\
                   elements_spanwise = 18\n\
                   material = \"ti-6al-4v\"      # or a table: name, density_kg_m3, poisson_ratio, melting_point_k, table = [{temperature_k, youngs_modulus_pa, thermal_expansion_per_k, conductivity_w_m_k, specific_heat_j_kg_k}, ...]\n\
                   damping_ratio = 0.02        # modal damping ratio of every mode\n\
                   planform = \"vehicle\"        # or \"rectangular\" with [models.ritz-plate.rectangular] chord_m, span_m, thickness_m\n\
                   root = \"clamped\"            # root nodes clamped to the torque tube; \"simply-supported\": all four edges of a rectangular plate (panel flutter)\n\
                   thermal_moment_shape = false # add the uniform thermal-moment deflection to the basis\n\
                   non_structural_mass_kg_m2 = 0.0 # carried mass per planform area, kg/m² (TPS layers of [models.full-order]: 2 Σ ρ t, e.g. 3.16 for 2 mm of vdi-l1400 on both faces)\n\
                   # [models.ritz-plate.built_up]  # absent: solid face to face; present: two skins with spar and rib webs between\n\
                   # skin_thickness_m = 0.003      # each face skin, m (the conduction model's [models.full-order] skin_thickness_m)\n\
                   # web_thickness_m = 0.0015      # spar and rib webs, m\n\
                   # spar_pitch_m = 0.5            # chordwise distance between spars, m\n\
                   # rib_pitch_m = 0.5             # spanwise distance between ribs, m",
    constructor: Constructor::Structure(construct),
});

fn model_error(e: PlateError) -> ModelError {
    match e {
        PlateError::Material(m) => m.into_model_error(NAME),
        other => ModelError::inconsistent(NAME, other.to_string()),
    }
}

/// A Ritz basis with its Ritz values and the names of the added static-shape vectors.
type AugmentedBasis = (DMatrix<f64>, Vec<f64>, Vec<String>);

/// Reduced element contributions, stored flat for a fast update.
#[derive(Debug, Clone)]
struct Reduced {
    /// r.
    size: usize,
    /// K_r,e at E_ref: element e at `[e r² ..]`, column-major r × r.
    stiffness: Vec<f64>,
    /// G_r,e,c: element e, component c at `[(3e + c) r² ..]`.
    geometric: Vec<f64>,
    /// Φ_eᵀ f_e: generalized thermal-moment force of a unit face strain difference in element
    /// e at E_ref, at `[e r ..]`.
    thermal: Vec<f64>,
}

/// Root-load matrices of one element touching the root: load on the tube (F, M) per Ritz
/// coordinate (6 × r) from its stiffness at E_ref and from each unit resultant.
#[derive(Debug, Clone)]
struct RootElement {
    element: usize,
    stiffness: DMatrix<f64>,
    geometric: [DMatrix<f64>; 3],
}

/// The `ritz-plate` model (module docs).
#[derive(Debug, Clone)]
pub struct RitzPlate {
    plate: PlateModel,
    side: Side,
    damping_ratio: f64,
    /// Ritz vectors over the free bending equations, M-orthonormal (n_eq × r).
    basis: DMatrix<f64>,
    /// Ritz values ω² at 293 K.
    reference_eigenvalues: Vec<f64>,
    reduced: Reduced,
    root_elements: Vec<RootElement>,
    /// Load on the tube per unit q̈ (6 × r): mass rows (temperature-independent).
    root_mass: DMatrix<f64>,
    /// Current load on the tube per unit q (6 × r).
    root_stiffness: DMatrix<f64>,
    /// Resultant about the pivot of the inertia forces M Φ per unit q̈ over every node (6 × r):
    /// Rᵀ M Φ, the force-summation inertia.
    root_inertia: DMatrix<f64>,
    /// Current generalized thermal-moment force Q_T (r).
    thermal_forces: DVector<f64>,
    rigid_coupling: DMatrix<f64>,
    rigid_mass: Matrix3<f64>,
    modal: ModalModel,
    /// Current eigenvalues of K_r (ascending) and eigenvectors.
    eigenvalues: Vec<f64>,
    eigenvectors: DMatrix<f64>,
    // Workspaces of set_temperatures.
    states: Vec<ElementState>,
    resultants: Vec<[f64; 3]>,
    membrane_k: BandedMatrix,
    membrane_rhs: Vec<f64>,
    symmetric_eigen: SymmetricEigenSolver,
}

impl RitzPlate {
    /// The selected side (mode shapes, root loads and the roll coupling mirror for `Left`).
    pub fn with_side(mut self, side: Side) -> Self {
        if side != self.side {
            // The mirror image in y turns a roll of the tube into the opposite roll.
            self.rigid_coupling.column_mut(2).neg_mut();
        }
        self.side = side;
        self
    }

    pub fn side(&self) -> Side {
        self.side
    }

    /// Number of structural grid nodes `set_temperatures` expects (node order of
    /// [`RitzPlate::grid`]).
    pub fn temperature_nodes(&self) -> usize {
        self.plate.grid.n_nodes()
    }

    /// The structural grid (node positions, thickness, maps to aero meshes).
    pub fn grid(&self) -> &SurfaceGrid {
        &self.plate.grid
    }

    /// The full-order plate behind the basis.
    pub fn plate(&self) -> &PlateModel {
        &self.plate
    }

    /// Ritz vectors over the free bending equations (n_eq × r), M-orthonormal.
    pub fn basis(&self) -> &DMatrix<f64> {
        &self.basis
    }

    /// Ritz values ω² (rad²/s²) of the basis at 293 K, ascending within modes and shapes.
    pub fn reference_eigenvalues(&self) -> &[f64] {
        &self.reference_eigenvalues
    }

    /// Element-mean membrane resultants (N/m: xx, yy, xy) of the latest temperature field.
    pub fn membrane_resultants(&self) -> &[[f64; 3]] {
        &self.resultants
    }

    /// Inertial coupling C = Φᵀ M R (r × 4) of the Ritz coordinates with the tube's rigid
    /// accelerations a = (ẍ m/s², z̈ m/s², roll and pitch rad/s² about +x and +y through the
    /// pivot): the Ritz equations get the generalized force −C a. Roll is the body's torsion
    /// or roll at the pivot, which bends the surface (w = y − y_p); the paper's tube motion is
    /// x, z and pitch.
    pub fn rigid_body_coupling(&self) -> &DMatrix<f64> {
        &self.rigid_coupling
    }

    /// Rigid mass matrix Rᵀ M R of the surface for (x, z, pitch) about the pivot: kg, kg m,
    /// kg m².
    pub fn rigid_body_mass(&self) -> &Matrix3<f64> {
        &self.rigid_mass
    }

    /// Reference point of the root loads: the pivot of the torque tube on the selected side,
    /// body axes, m.
    pub fn root_reference_m(&self) -> Point3<f64> {
        let p = self.plate.grid.pivot_m;
        if self.side == self.plate.grid.side {
            p
        } else {
            Point3::new(p.x, -p.y, p.z)
        }
    }

    /// Displacement (m) at a mid-plane offset `z_offset_m` of a Ritz vector at a grid point:
    /// (z βx, z βy, w) interpolated bilinearly.
    fn displacement(&self, column: usize, at: &GridPoint, z_offset_m: f64) -> Vector3<f64> {
        let v = self.basis.column(column);
        let mut d = Vector3::zeros();
        for k in 0..4 {
            let n = at.nodes[k];
            let mut nodal = [0.0; 3];
            for (dof, val) in nodal.iter_mut().enumerate() {
                if let Some(i) = self.plate.bending_map.equation[n * 3 + dof] {
                    *val = v[i];
                }
            }
            d += Vector3::new(z_offset_m * nodal[1], z_offset_m * nodal[2], nodal[0])
                * at.weights[k];
        }
        d
    }
}

impl StructureModel for RitzPlate {
    fn name(&self) -> &str {
        NAME
    }

    fn thermal_stiffness(&self) -> Option<&dyn ThermalStiffness> {
        Some(self)
    }

    fn thermal_stiffness_mut(&mut self) -> Option<&mut dyn ThermalStiffness> {
        Some(self)
    }

    fn root_loads(&self) -> Option<&dyn RootLoads> {
        Some(self)
    }

    fn mass_properties(&self) -> Option<&dyn MassDistribution> {
        Some(self)
    }

    fn rigid_body_coupling(&self) -> Option<&dyn RigidBodyCoupling> {
        Some(self)
    }

    fn modal_model(&self) -> &ModalModel {
        &self.modal
    }

    fn natural_frequencies_hz(&self) -> Result<Vec<f64>, ModelError> {
        if let Some((mode, &lam)) = self
            .eigenvalues
            .iter()
            .enumerate()
            .find(|(_, l)| **l <= 0.0)
        {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "buckled: mode {} of the current stiffness has eigenvalue {lam:.4e} rad²/s² \
                     (≤ 0); compressive thermal stress exceeds the surface's buckling load",
                    mode + 1
                ),
            ));
        }
        let f: Vec<f64> = self
            .eigenvalues
            .iter()
            .map(|l| l.sqrt() / (2.0 * std::f64::consts::PI))
            .collect();
        if let Some(i) = f.iter().position(|v| !v.is_finite()) {
            return Err(ModelError::NonFinite {
                model: NAME.to_owned(),
                quantity: "natural frequency".to_owned(),
                location: format!(" of mode {}", i + 1),
            });
        }
        Ok(f)
    }

    fn mode_shapes_on(&self, mesh: &PanelMesh) -> Result<ModeShapes, ModelError> {
        let grid = &self.plate.grid;
        // A mesh on the other side of y = 0 is the mirror image of this surface's.
        let mean_y =
            mesh.vertices.iter().map(|v| v.y).sum::<f64>() / mesh.vertices.len().max(1) as f64;
        let grid_y = grid.positions_m.iter().map(|p| p.y).sum::<f64>() / grid.n_nodes() as f64;
        let mirror = mean_y * grid_y < 0.0;
        let points: Vec<Point3<f64>> = mesh
            .vertices
            .iter()
            .map(|v| {
                if mirror {
                    Point3::new(v.x, -v.y, v.z)
                } else {
                    *v
                }
            })
            .collect();
        let map = grid
            .map_points(&points, "vertex")
            .map_err(|e| ModelError::inconsistent(NAME, e.to_string()))?;
        let r = self.basis.ncols();
        let z_mid = grid.mid_plane_z_m();
        let mut shapes = DMatrix::<f64>::zeros(3 * points.len(), r);
        for (i, (p, at)) in points.iter().zip(&map).enumerate() {
            for c in 0..r {
                let mut d = self.displacement(c, at, p.z - z_mid);
                if mirror {
                    d.y = -d.y;
                }
                shapes[(3 * i, c)] = d.x;
                shapes[(3 * i + 1, c)] = d.y;
                shapes[(3 * i + 2, c)] = d.z;
            }
        }
        Ok(ModeShapes {
            vertex_displacement: shapes,
        })
    }
}

impl RitzPlate {
    /// Root loads by the mode-displacement method, r = K_cf Φ q + M_cf Φ q̈ at the full model's
    /// root row: misses the root row's own load and converges slowly for loads outside the
    /// basis; kept to compare with [`RootLoads::root_loads`] (force summation).
    pub fn root_loads_by_mode_displacement(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
    ) -> Result<Loads, ModelError> {
        check_modal_lengths(
            self.basis.ncols(),
            [
                ("modal coordinates", modal_coordinates),
                ("modal velocities", modal_velocities),
                ("modal accelerations", modal_accelerations),
            ],
        )?;
        let l = &self.root_stiffness * modal_coordinates + &self.root_mass * modal_accelerations;
        finite_root_load(self.on_model_side(Loads {
            force_n: Vector3::new(l[0], l[1], l[2]),
            moment_nm: Vector3::new(l[3], l[4], l[5]),
        }))
    }
}
