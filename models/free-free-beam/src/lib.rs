//! The `free-free-beam` main-body structure: a non-uniform Euler-Bernoulli beam along the body x
//! axis, free-free, reduced to its lowest lateral-bending, vertical-bending and torsion modes.
//!
//! Paper (Klock & Cesnik, §III.A and Table 1, after Frendreis & Cesnik): the main body is a
//! free-free Euler-Bernoulli beam with three modes (lateral bending, longitudinal = vertical
//! bending, torsion); forebody and aftbody 15.2 m each with 838 and 1250 kg/m, I_x = 3.28e3
//! kg m²/m, EI_zz = 5.06e10, EI_yy = 6.32e9, GJ = 4.74e9 N m². The beam runs from the nose
//! (x = 0) to the tail (x = −30.4 m) at height `axis_z_m`.
//!
//! Method: finite elements ([`fe`]: Hermite cubic bending in two planes, linear torsion and
//! axial, consistent mass), free-free modes by a shifted Cholesky eigen-solve ([`modes`]), the
//! six rigid-body modes identified by frequency and checked against the analytic rigid motions,
//! elastic modes classified by their kinetic energy per DOF group and the requested number of
//! each kind kept, mass-normalized: generalized mass I, stiffness diag(ω²), damping diag(2ζω).
//! The main body's structure is temperature independent (paper §II.A: thermally protected).
//!
//! Mode shapes on a mesh: each vertex r moves with the cross-section at its station,
//! u = w(x) + θ(x) × (r − r_axis(x)), w and θ interpolated with the element shape functions;
//! vertices beyond the beam ends move rigidly with the end section.
//!
//! The settings, their limits and checks are in `settings.rs` (re-exported here).

pub mod fe;
pub mod modes;
mod settings;

use hsv_core::error::ModelError;
use hsv_core::geometry::{BodyProfile, GeometryConfig, body_profile};
use hsv_core::mesh::{ModeShapes, PanelMesh};
use hsv_core::region::RegionGeometry;
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};
use hsv_core::structure::{
    MassDistribution, MassProperties, ModalModel, RigidBodyCoupling, RigidDof, StructureModel,
};
use nalgebra::{DMatrix, DVector, Matrix3, Point3, Vector3};

pub use fe::{BeamMesh, ModeKind, Section, SectionMotion};
pub use modes::{ElasticModes, RIGID_BODY_MODES};
use settings::SETTINGS_DOC;
pub use settings::{ELEMENTS_PER_HALF_WAVE, MAX_ELEMENTS, MAX_MODES_PER_KIND, Settings};

/// Registered name.
pub const NAME: &str = "free-free-beam";

/// Height of the area centroid of the closed side profile, m below the nose line:
/// z̄ = Σ (z_i + z_{i+1})(x_i z_{i+1} − x_{i+1} z_i) / (6 A_signed) (polygon centroid).
pub fn profile_centroid_z_m(profile: &BodyProfile) -> f64 {
    let o = profile.outline_m();
    let (mut twice_area, mut moment) = (0.0, 0.0);
    for i in 0..o.len() {
        let (a, b) = (o[i], o[(i + 1) % o.len()]);
        let cross = a.x * b.y - b.x * a.y;
        twice_area += cross;
        moment += (a.y + b.y) * cross;
    }
    moment / (3.0 * twice_area)
}

/// The free-free beam with its kept modes.
#[derive(Debug, Clone)]
pub struct FreeFreeBeam {
    settings: Settings,
    axis_z_m: f64,
    mass_properties: MassProperties,
    /// Φᵀ M R of the kept modes with the six rigid motions about the nose station (n × 6).
    rigid_coupling: DMatrix<f64>,
    mesh: BeamMesh,
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    elastic: ElasticModes,
    /// Kept modes: indices into `elastic`, ascending in frequency.
    kept: Vec<usize>,
    /// Kept shapes, one column per kept mode (mass-normalized nodal vectors).
    kept_shapes: DMatrix<f64>,
    modal: ModalModel,
}

impl FreeFreeBeam {
    /// Builds the beam from `settings` with its axis at height `axis_z_m` (m below the nose
    /// line), solves its free-free modes and keeps the requested ones.
    pub fn new(settings: Settings, axis_z_m: f64) -> Result<Self, ModelError> {
        settings
            .check()
            .map_err(|bad| ModelError::out_of_range(NAME, bad.key, bad.value, bad.allowed))?;
        if !axis_z_m.is_finite() {
            return Err(ModelError::out_of_range(
                NAME, "axis_z_m", axis_z_m, "finite",
            ));
        }
        Self::build(settings, axis_z_m)
    }

    /// Builds from a config: settings from `[models.free-free-beam]`, checked against
    /// `[geometry]` (lengths) when present; the axis height from the settings or the profile.
    pub fn from_context(ctx: &ModelContext<'_>) -> Result<Self, ModelError> {
        let settings: Settings = ctx.parse_settings()?;
        let key = |k: &str| format!("{}.{k}", ctx.key_path);
        settings.check().map_err(|bad| ModelError::Settings {
            file: ctx.file.to_owned(),
            key_path: key(bad.key),
            message: format!(
                "{} = {} is outside the allowed range ({})",
                bad.key, bad.value, bad.allowed
            ),
        })?;
        let geometry: Option<&GeometryConfig> = match &ctx.region.geometry {
            RegionGeometry::Body(g) => Some(g),
            _ => None,
        };
        if let Some(g) = &geometry {
            for (ours, theirs, their_key) in [
                (
                    settings.forebody_length_m,
                    g.forebody_length_m,
                    "geometry.forebody_length_m",
                ),
                (settings.length_m(), g.length_m, "geometry.length_m"),
            ] {
                if (ours - theirs).abs() > 1e-6 * theirs.abs().max(1.0) {
                    return Err(ModelError::Settings {
                        file: ctx.file.to_owned(),
                        key_path: key(if their_key.ends_with("forebody_length_m") {
                            "forebody_length_m"
                        } else {
                            "aftbody_length_m"
                        }),
                        message: format!(
                            "the beam ({ours} m) must match `{their_key}` = {theirs} m: the \
                             beam spans the body from nose to tail, joining at the forebody end"
                        ),
                    });
                }
            }
        }
        let axis_z_m = match (settings.axis_z_m, &geometry) {
            (Some(z), _) => z,
            (None, Some(g)) => {
                let profile = body_profile(g).map_err(|e| ModelError::Settings {
                    file: ctx.file.to_owned(),
                    key_path: "geometry".to_owned(),
                    message: e.to_string(),
                })?;
                profile_centroid_z_m(&profile)
            }
            (None, None) => {
                return Err(ModelError::Settings {
                    file: ctx.file.to_owned(),
                    key_path: key("axis_z_m"),
                    message: "no [geometry] table to place the beam axis at the profile \
                              centroid: set axis_z_m"
                        .to_owned(),
                });
            }
        };
        Self::build(settings, axis_z_m)
    }

    fn build(settings: Settings, axis_z_m: f64) -> Result<Self, ModelError> {
        let mesh = settings.beam_mesh();
        let (mass, stiffness) = mesh.assemble();
        let elastic = modes::free_free_modes(
            NAME,
            &mass,
            &stiffness,
            &mesh.rigid_body_modes(),
            &mesh.dof_kinds(),
            ModeKind::ALL.map(|kind| settings.modes_of(kind)),
        )?;
        let mut kept = Vec::new();
        let mut names = Vec::new();
        let mut count = [0usize; 4];
        for (i, kind) in elastic.kinds.iter().enumerate() {
            let c = &mut count[kind.index()];
            if *c < settings.modes_of(*kind) {
                *c += 1;
                kept.push(i);
                names.push(format!("{} {}", kind.label(), *c));
            }
        }
        for kind in ModeKind::ALL {
            let found = count[kind.index()];
            if found < settings.modes_of(kind) {
                return Err(ModelError::out_of_range(
                    NAME,
                    &format!("{} modes", kind.label()),
                    settings.modes_of(kind) as f64,
                    format!(
                        "at most {found} with elements = {} (add elements)",
                        settings.elements
                    ),
                ));
            }
        }
        let omega: Vec<f64> = kept.iter().map(|&i| elastic.omega2[i].sqrt()).collect();
        if let Some(k) = omega.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(ModelError::NonFinite {
                model: NAME.to_owned(),
                quantity: "natural frequency".to_owned(),
                location: format!(" of mode `{}`", names[k]),
            });
        }
        let n = kept.len();
        let zeta = settings.damping_ratio;
        let modal = ModalModel {
            names,
            mass: DMatrix::identity(n, n),
            damping: DMatrix::from_diagonal(&DVector::from_iterator(
                n,
                omega.iter().map(|w| 2.0 * zeta * w),
            )),
            stiffness: DMatrix::from_diagonal(&DVector::from_iterator(
                n,
                kept.iter().map(|&i| elastic.omega2[i]),
            )),
        };
        let kept_shapes = DMatrix::from_fn(mesh.n_dof(), n, |r, c| elastic.shapes[(r, kept[c])]);
        let rigid = mesh.rigid_body_modes();
        let mass_rigid = rigid.transpose() * &mass * &rigid;
        let mass_properties = rigid_mass_properties(&mass_rigid, axis_z_m);
        let rigid_coupling = kept_shapes.transpose() * &mass * &rigid;
        Ok(Self {
            settings,
            axis_z_m,
            mass_properties,
            rigid_coupling,
            mesh,
            mass,
            stiffness,
            elastic,
            kept,
            kept_shapes,
            modal,
        })
    }

    /// The settings it was built with.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Beam axis height below the nose line, m.
    pub fn axis_z_m(&self) -> f64 {
        self.axis_z_m
    }

    /// The finite-element mesh.
    pub fn beam_mesh(&self) -> &BeamMesh {
        &self.mesh
    }

    /// Assembled consistent mass matrix, kg (kg m² on rotations).
    pub fn mass_matrix(&self) -> &DMatrix<f64> {
        &self.mass
    }

    /// Assembled stiffness matrix, N/m (N m/rad on rotations).
    pub fn stiffness_matrix(&self) -> &DMatrix<f64> {
        &self.stiffness
    }

    /// Every elastic mode of the mesh (rigid-body modes removed), ascending.
    pub fn elastic_modes(&self) -> &ElasticModes {
        &self.elastic
    }

    /// Kind of each kept mode, in [`ModalModel::names`] order.
    pub fn kept_kinds(&self) -> Vec<ModeKind> {
        self.kept.iter().map(|&i| self.elastic.kinds[i]).collect()
    }

    /// Mass-normalized nodal shapes of the kept modes (columns).
    pub fn kept_shapes(&self) -> &DMatrix<f64> {
        &self.kept_shapes
    }

    /// Cross-section motion of kept mode `mode` at body station `x_m` (clamped to the beam).
    pub fn section_motion(&self, mode: usize, x_m: f64) -> SectionMotion {
        let col = self.kept_shapes.column(mode);
        self.mesh.section_motion_of(|i| col[i], -x_m)
    }

    /// Displacement of body point `r` (m) in kept mode `mode`: w(x) + θ(x) × (r − r_axis(x)),
    /// the section taken at x clamped to the beam.
    pub fn point_displacement(&self, mode: usize, r: &nalgebra::Point3<f64>) -> Vector3<f64> {
        let x_c = r.x.clamp(-self.mesh.length_m(), 0.0);
        let motion = self.section_motion(mode, r.x);
        let arm = Vector3::new(r.x - x_c, r.y, r.z - self.axis_z_m);
        motion.displacement + motion.rotation.cross(&arm)
    }
}

/// Mass, centre of mass and inertia from the rigid-body mass matrix Rᵀ M R (6 × 6, about the
/// nose station of the beam axis at z = `axis_z_m`): m = (Rᵀ M R)₀₀, the centre of mass from the
/// first moment (Rᵀ M R)₂₄ = ∫ μ s ds, the inertia about the nose station from the rotational
/// block, moved to the centre of mass by the parallel-axis theorem.
fn rigid_mass_properties(mass_rigid: &DMatrix<f64>, axis_z_m: f64) -> MassProperties {
    let mass_kg = mass_rigid[(0, 0)];
    let nose = Point3::new(0.0, 0.0, axis_z_m);
    let center = Point3::new(-mass_rigid[(2, 4)] / mass_kg, 0.0, axis_z_m);
    let about_nose = MassProperties {
        mass_kg,
        center_of_mass_m: center,
        inertia_kg_m2: Matrix3::from_fn(|i, j| mass_rigid[(3 + i, 3 + j)]),
    };
    let d = center - nose;
    MassProperties {
        inertia_kg_m2: about_nose.inertia_kg_m2
            - mass_kg * (Matrix3::identity() * d.norm_squared() - d * d.transpose()),
        ..about_nose
    }
}

impl MassDistribution for FreeFreeBeam {
    fn mass_properties(&self) -> MassProperties {
        self.mass_properties
    }
}

impl RigidBodyCoupling for FreeFreeBeam {
    fn rigid_dofs(&self) -> &[RigidDof] {
        &[
            RigidDof::TranslationX,
            RigidDof::TranslationY,
            RigidDof::TranslationZ,
            RigidDof::RotationX,
            RigidDof::RotationY,
            RigidDof::RotationZ,
        ]
    }

    fn rigid_reference_point_m(&self) -> Point3<f64> {
        Point3::new(0.0, 0.0, self.axis_z_m)
    }

    fn rigid_coupling(&self) -> &DMatrix<f64> {
        &self.rigid_coupling
    }
}

impl StructureModel for FreeFreeBeam {
    fn name(&self) -> &str {
        NAME
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
        (0..self.modal.n_modes())
            .map(|i| {
                let k = self.modal.stiffness[(i, i)];
                if k.is_finite() && k > 0.0 {
                    Ok(k.sqrt() / std::f64::consts::TAU)
                } else {
                    Err(ModelError::out_of_range(
                        NAME,
                        &format!("generalized stiffness of `{}`", self.modal.names[i]),
                        k,
                        "finite and > 0",
                    ))
                }
            })
            .collect()
    }

    fn mode_shapes_on(&self, mesh: &PanelMesh) -> Result<ModeShapes, ModelError> {
        let n_modes = self.modal.n_modes();
        let mut displacement = DMatrix::zeros(3 * mesh.vertices.len(), n_modes);
        for (v, r) in mesh.vertices.iter().enumerate() {
            for k in 0..n_modes {
                let u = self.point_displacement(k, r);
                if !(u.x.is_finite() && u.y.is_finite() && u.z.is_finite()) {
                    return Err(ModelError::NonFinite {
                        model: NAME.to_owned(),
                        quantity: format!("mode shape `{}`", self.modal.names[k]),
                        location: format!(" at vertex {v}"),
                    });
                }
                displacement[(3 * v, k)] = u.x;
                displacement[(3 * v + 1, k)] = u.y;
                displacement[(3 * v + 2, k)] = u.z;
            }
        }
        Ok(ModeShapes {
            vertex_displacement: displacement,
        })
    }
}

fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn StructureModel>, ModelError> {
    Ok(Box::new(FreeFreeBeam::from_context(ctx)?))
}

hsv_core::register_model!(ModelDescriptor {
    name: NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "main body as a free-free non-uniform Euler-Bernoulli beam (finite elements): \
              lateral bending, vertical bending and torsion modes mapped to the OML",
    settings_doc: SETTINGS_DOC,
    constructor: Constructor::Structure(construct),
});
