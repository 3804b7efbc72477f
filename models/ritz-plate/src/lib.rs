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
//! **Temperature update** ([`StructureModel::set_temperatures`]): each element takes the mean
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

fn default_modes() -> usize {
    10
}
fn default_static() -> usize {
    5
}
fn default_chordwise() -> usize {
    24
}
fn default_spanwise() -> usize {
    18
}
fn default_damping() -> f64 {
    0.02
}

/// Which planform the plate covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlanformChoice {
    /// The `[lifting_surface]` trapezoid with its double-wedge thickness.
    #[default]
    Vehicle,
    /// A uniform rectangular plate (`[models.ritz-plate.rectangular]`), for plate-theory checks.
    Rectangular,
}

/// How the root edge is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RootChoice {
    /// Every root node clamped to the (rigid) torque tube.
    #[default]
    Clamped,
    /// All four edges of the rectangular planform simply supported (w and the rotation along
    /// the edge held, Kirchhoff's w = ∂w/∂s = 0) and immovable in-plane: the classical panel
    /// of panel-flutter theory (Dowell, Aeroelasticity of Plates and Shells, 1975). Only with
    /// `planform = "rectangular"`.
    SimplySupported,
}

/// Supports of [`RootChoice::SimplySupported`]: every edge of `grid` simply supported and
/// held in-plane.
pub fn simply_supported_edges(grid: &SurfaceGrid) -> Supports {
    let mut supports = Supports::free(grid.n_nodes());
    for edge in [
        GridEdge::Root,
        GridEdge::Tip,
        GridEdge::LeadingEdge,
        GridEdge::TrailingEdge,
    ] {
        supports = supports
            .simply_support(grid, edge)
            .restrain_in_plane(&grid.edge_nodes(edge));
    }
    supports
}

/// Dimensions of the rectangular plate: chord along −x from the leading edge, span along +y
/// from the clamped root edge.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RectangularSettings {
    pub chord_m: f64,
    pub span_m: f64,
    pub thickness_m: f64,
}

/// `[models.ritz-plate.built_up]`: the surface built up of two face skins with spars and ribs
/// between them ([`fe::BuiltUp`]) instead of solid material face to face.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuiltUpSettings {
    /// Thickness of each face skin, m.
    pub skin_thickness_m: f64,
    /// Thickness of the spar and rib webs, m.
    pub web_thickness_m: f64,
    /// Chordwise distance between spars (spanwise webs), m.
    pub spar_pitch_m: f64,
    /// Spanwise distance between ribs (chordwise webs), m.
    pub rib_pitch_m: f64,
}

impl BuiltUpSettings {
    /// The element section, or the first setting out of range (key, value).
    pub fn section(&self) -> Result<fe::Section, (&'static str, f64)> {
        for (key, v) in [
            ("skin_thickness_m", self.skin_thickness_m),
            ("web_thickness_m", self.web_thickness_m),
            ("spar_pitch_m", self.spar_pitch_m),
            ("rib_pitch_m", self.rib_pitch_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err((key, v));
            }
        }
        Ok(fe::Section::BuiltUp(fe::BuiltUp {
            skin_m: self.skin_thickness_m,
            spar_web_ratio: self.web_thickness_m / self.spar_pitch_m,
            rib_web_ratio: self.web_thickness_m / self.rib_pitch_m,
        }))
    }
}

/// `[models.ritz-plate]`.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Free-vibration modes in the basis (paper: 10).
    #[serde(default = "default_modes")]
    pub free_vibration_modes: usize,
    /// Static load shapes in the basis, 0-5 in the order of [`STATIC_SHAPES`] (paper: 5).
    #[serde(default = "default_static")]
    pub static_shapes: usize,
    /// Structural grid elements along the chord (≥ 2).
    #[serde(default = "default_chordwise")]
    pub elements_chordwise: usize,
    /// Structural grid elements along the span.
    #[serde(default = "default_spanwise")]
    pub elements_spanwise: usize,
    /// A built-in material name or a full table.
    #[serde(default)]
    pub material: MaterialSetting,
    /// Modal damping ratio of every mode, in [0, 1).
    #[serde(default = "default_damping")]
    pub damping_ratio: f64,
    /// `vehicle` (default) or `rectangular`.
    #[serde(default)]
    pub planform: PlanformChoice,
    /// Required with `planform = "rectangular"`.
    #[serde(default)]
    pub rectangular: Option<RectangularSettings>,
    /// Root condition: `clamped` (default), or `simply-supported` (all four edges of a
    /// rectangular plate).
    #[serde(default)]
    pub root: RootChoice,
    /// Adds one more static shape, the deflection under a uniform thermal moment (a uniform
    /// through-thickness temperature difference), so a thermal bending load is reproduced
    /// exactly; off by default (the paper's basis has the five load shapes).
    #[serde(default)]
    pub thermal_moment_shape: bool,
    /// Non-structural mass per unit planform area the plate carries, kg/m² (≥ 0): thermal
    /// protection layers of the conduction model, 2 Σ ρ_l t_l for layers on both faces. Added
    /// to the mass matrices (no rotary inertia), the rigid-body mass and the mass properties;
    /// stiffness is the structure's alone.
    #[serde(default)]
    pub non_structural_mass_kg_m2: f64,
    /// A built-up section (skins, spars, ribs); absent: solid face to face.
    #[serde(default)]
    pub built_up: Option<BuiltUpSettings>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            free_vibration_modes: default_modes(),
            static_shapes: default_static(),
            elements_chordwise: default_chordwise(),
            elements_spanwise: default_spanwise(),
            material: MaterialSetting::default(),
            damping_ratio: default_damping(),
            planform: PlanformChoice::Vehicle,
            rectangular: None,
            root: RootChoice::Clamped,
            thermal_moment_shape: false,
            non_structural_mass_kg_m2: 0.0,
            built_up: None,
        }
    }
}

fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn StructureModel>, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    let material = settings
        .material
        .resolve()
        .map_err(|e| ctx.settings_error("material", e.to_string()))?;
    // The plate's reference modulus (a thermal-only insulator such as `vdi-l1400` has none).
    material
        .youngs_modulus_pa(hsv_core::material::SECANT_REFERENCE_TEMPERATURE_K)
        .map_err(|e| ctx.settings_error("material", e.to_string()))?;
    let (grid, side) = structural_grid(&settings, ctx)?;
    let model = match settings.root {
        RootChoice::Clamped => RitzPlate::new(grid, material, &settings)?,
        RootChoice::SimplySupported => {
            if settings.planform != PlanformChoice::Rectangular {
                return Err(ctx.settings_error(
                    "root",
                    "root = \"simply-supported\" (all four edges) needs planform = \"rectangular\"",
                ));
            }
            let supports = simply_supported_edges(&grid);
            RitzPlate::with_supports(grid, material, supports, &settings)?
        }
    };
    Ok(Box::new(model.with_side(side)))
}

/// The structural grid `settings` describe (node order of `set_temperatures`) and the side of
/// the region's surface, without building the model: what a temperature field for this
/// structure must be sampled on. The grid is the right surface's; the left mirrors it.
pub fn structural_grid(
    settings: &Settings,
    ctx: &ModelContext<'_>,
) -> Result<(SurfaceGrid, Side), ModelError> {
    match settings.planform {
        PlanformChoice::Vehicle => {
            let (surface, side) = ctx.region.lifting_surface(NAME)?;
            SurfaceGrid::lifting_surface(
                surface,
                Side::Right,
                settings.elements_chordwise,
                settings.elements_spanwise,
            )
            .map(|grid| (grid, side))
        }
        PlanformChoice::Rectangular => {
            let r = settings.rectangular.ok_or_else(|| {
                ctx.settings_error(
                    "rectangular",
                    "planform = \"rectangular\" needs a [rectangular] table with chord_m, span_m, \
                     thickness_m",
                )
            })?;
            SurfaceGrid::rectangular(
                r.chord_m,
                r.span_m,
                r.thickness_m,
                settings.elements_chordwise,
                settings.elements_spanwise,
            )
            .map(|grid| (grid, Side::Right))
        }
    }
    .map_err(|e| ctx.settings_error("planform", e.to_string()))
}

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

/// Converts a 12-row element block of generalized forces at held root dofs into the load on
/// the tube (force, moment about `pivot`): w rows give −f ẑ at the node, βx rows −f about y,
/// βy rows +f about x (βy = −θx).
fn root_load_rows(
    plate: &PlateModel,
    e: usize,
    forces: &DMatrix<f64>,
    pivot: &Point3<f64>,
) -> DMatrix<f64> {
    let mut out = DMatrix::<f64>::zeros(6, forces.ncols());
    let nodes = plate.grid.elements[e];
    for (k, &n) in nodes.iter().enumerate() {
        let held = plate.supports.bending[n];
        let r = plate.grid.positions_m[n] - pivot;
        for c in 0..forces.ncols() {
            if held[0] {
                let f = Vector3::new(0.0, 0.0, -forces[(3 * k, c)]);
                let m = r.cross(&f);
                out[(2, c)] += f.z;
                out[(3, c)] += m.x;
                out[(4, c)] += m.y;
                out[(5, c)] += m.z;
            }
            if held[1] {
                out[(4, c)] -= forces[(3 * k + 1, c)];
            }
            if held[2] {
                out[(3, c)] += forces[(3 * k + 2, c)];
            }
        }
    }
    out
}

/// The tube's six rigid motions on element `e`'s bending dofs (12 × 6, columns x, y, z
/// translation and rotation about x, y, z through the pivot): w = 1 for z; roll w = y − y_p,
/// βy = −1; pitch w = −(x − x_p), βx = 1; the in-plane motions (x, y, yaw) move no bending dof.
/// Rᵀ g is then the force and moment about the pivot of nodal bending forces g (virtual work).
fn tube_rigid_motions(plate: &PlateModel, e: usize) -> DMatrix<f64> {
    let pivot = plate.grid.pivot_m;
    let mut r = DMatrix::<f64>::zeros(12, 6);
    for (k, &n) in plate.grid.elements[e].iter().enumerate() {
        let p = plate.grid.positions_m[n];
        r[(3 * k, 2)] = 1.0;
        r[(3 * k, 3)] = p.y - pivot.y;
        r[(3 * k + 2, 3)] = -1.0;
        r[(3 * k, 4)] = -(p.x - pivot.x);
        r[(3 * k + 1, 4)] = 1.0;
    }
    r
}

/// The mirror image in y of a load about a point: a polar force flips y, an axial moment flips
/// x and z.
fn mirror_in_y(mut loads: Loads) -> Loads {
    loads.force_n.y = -loads.force_n.y;
    loads.moment_nm.x = -loads.moment_nm.x;
    loads.moment_nm.z = -loads.moment_nm.z;
    loads
}

/// Checks that each modal vector has `r` entries, naming the one that does not.
fn check_modal_lengths(r: usize, vectors: [(&str, &DVector<f64>); 3]) -> Result<(), ModelError> {
    for (what, v) in vectors {
        if v.len() != r {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} {what} given, the model has {r} Ritz coordinates",
                    v.len()
                ),
            ));
        }
    }
    Ok(())
}

/// A root load with a non-finite component is an error, not NaN.
fn finite_root_load(loads: Loads) -> Result<Loads, ModelError> {
    if loads
        .force_n
        .iter()
        .chain(loads.moment_nm.iter())
        .any(|v| !v.is_finite())
    {
        return Err(ModelError::NonFinite {
            model: NAME.to_owned(),
            quantity: "root load".to_owned(),
            location: String::new(),
        });
    }
    Ok(loads)
}

/// Names free-vibration mode shapes by their dominant content along the span: mean deflection
/// (bending), linear chordwise slope (torsion) or the remainder (chordwise bending), numbered
/// by order of appearance of each kind.
fn classify_modes(plate: &PlateModel, modes: &DMatrix<f64>) -> Vec<String> {
    let g = &plate.grid;
    let (nc, ns) = (g.nodes_chordwise(), g.nodes_spanwise());
    let mut counts = [0usize; 3];
    let kinds = ["bending", "torsion", "chordwise bending"];
    (0..modes.ncols())
        .map(|c| {
            let v: Vec<f64> = modes.column(c).iter().copied().collect();
            let mut energy = [0.0; 3];
            for j in 0..ns {
                let pts: Vec<(f64, f64)> = (0..nc)
                    .map(|i| {
                        let n = g.node_index(i, j);
                        (g.positions_m[n].x, plate.nodal_value(&v, n)[0])
                    })
                    .collect();
                let k = pts.len() as f64;
                let mx = pts.iter().map(|p| p.0).sum::<f64>() / k;
                let mw = pts.iter().map(|p| p.1).sum::<f64>() / k;
                let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
                let sxw: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - mw)).sum();
                let slope = if sxx > 0.0 { sxw / sxx } else { 0.0 };
                energy[0] += k * mw * mw;
                energy[1] += slope * slope * sxx;
                energy[2] += pts
                    .iter()
                    .map(|p| (p.1 - mw - slope * (p.0 - mx)).powi(2))
                    .sum::<f64>();
            }
            let kind = (0..3)
                .max_by(|&a, &b| energy[a].total_cmp(&energy[b]))
                .unwrap_or(0);
            counts[kind] += 1;
            format!("{} {}", kinds[kind], counts[kind])
        })
        .collect()
}

impl RitzPlate {
    /// Builds the full-order plate on `grid` (root nodes clamped), its Ritz basis at 293 K and
    /// the reduced element contributions.
    pub fn new(
        grid: SurfaceGrid,
        material: Material,
        settings: &Settings,
    ) -> Result<Self, ModelError> {
        let supports = Supports::free(grid.n_nodes()).clamp(&grid.root_nodes);
        Self::with_supports(grid, material, supports, settings)
    }

    /// [`RitzPlate::new`] with any supports (plate-theory checks: simply supported edges,
    /// statically determinate in-plane supports for free thermal expansion, ...). Root loads
    /// are then the reactions at every held bending dof.
    pub fn with_supports(
        grid: SurfaceGrid,
        material: Material,
        supports: Supports,
        settings: &Settings,
    ) -> Result<Self, ModelError> {
        let n_modes = settings.free_vibration_modes;
        if !(1..=50).contains(&n_modes) {
            return Err(ModelError::out_of_range(
                NAME,
                "free_vibration_modes",
                n_modes as f64,
                "1 to 50",
            ));
        }
        if settings.static_shapes > STATIC_SHAPES.len() {
            return Err(ModelError::out_of_range(
                NAME,
                "static_shapes",
                settings.static_shapes as f64,
                "0 to 5",
            ));
        }
        let zeta = settings.damping_ratio;
        if !(zeta.is_finite() && (0.0..1.0).contains(&zeta)) {
            return Err(ModelError::out_of_range(
                NAME,
                "damping_ratio",
                zeta,
                "[0, 1)",
            ));
        }
        let added = settings.non_structural_mass_kg_m2;
        if !(added.is_finite() && added >= 0.0) {
            return Err(ModelError::out_of_range(
                NAME,
                "non_structural_mass_kg_m2",
                added,
                "finite and >= 0 kg/m²",
            ));
        }
        let section = match &settings.built_up {
            None => fe::Section::Solid,
            Some(b) => b.section().map_err(|(key, v)| {
                ModelError::out_of_range(NAME, &format!("built_up.{key}"), v, "finite and > 0 m")
            })?,
        };
        let plate = PlateModel::with_section(grid, material, supports, section)
            .map_err(model_error)?
            .with_non_structural_mass(added);
        let requested =
            n_modes + settings.static_shapes + usize::from(settings.thermal_moment_shape);
        if requested > plate.bending_map.n_equations / 4 {
            return Err(model_error(PlateError::TooFewDofs {
                requested,
                available: plate.bending_map.n_equations,
            }));
        }
        let (_, modes) = plate.modes(None, n_modes).map_err(model_error)?;
        let mut names = classify_modes(&plate, &modes);
        let (basis, eigenvalues, static_names) = Self::augment(
            &plate,
            modes,
            settings.static_shapes,
            settings.thermal_moment_shape,
        )?;
        names.extend(static_names);
        let mut model = Self::from_basis(plate, basis, eigenvalues, names, zeta);
        model.reset_reference()?;
        Ok(model)
    }

    /// Adds the static load shapes (and, with `thermal_shape`, the uniform thermal-moment
    /// shape): K⁻¹ f, M-orthogonalized (twice, modified Gram-Schmidt) against the modes and
    /// each other, then rotated so the static block of K_r is diagonal.
    fn augment(
        plate: &PlateModel,
        modes: DMatrix<f64>,
        n_static: usize,
        thermal_shape: bool,
    ) -> Result<AugmentedBasis, ModelError> {
        if n_static == 0 && !thermal_shape {
            let (b, eigenvalues) = Self::rayleigh_ritz(plate, modes)?;
            return Ok((b, eigenvalues, Vec::new()));
        }
        let g = &plate.grid;
        let (nc, ns) = (g.nodes_chordwise(), g.nodes_spanwise());
        let tip = g.edge_nodes(GridEdge::Tip);
        let tip_mid_x = 0.5 * (g.positions_m[tip[0]].x + g.positions_m[tip[nc - 1]].x);
        let mut loads: Vec<Vec<f64>> = (0..n_static)
            .map(|k| {
                plate.to_equations(|n| {
                    let (i, j) = (n % nc, n / nc);
                    let a = g.node_areas_m2[n];
                    let u = g.chord_fractions[i];
                    let eta = g.span_fractions[j];
                    let w = match k {
                        0 => a,
                        1 => f64::from(u8::from(j == ns - 1)),
                        2 => {
                            if j == ns - 1 {
                                g.positions_m[n].x - tip_mid_x
                            } else {
                                0.0
                            }
                        }
                        3 => a * (u - 0.5),
                        _ => a * eta,
                    };
                    [w, 0.0, 0.0]
                })
            })
            .collect();
        if thermal_shape {
            let uniform = ElementState {
                thermal_strain_difference: 1e-3,
                ..ElementState::REFERENCE
            };
            loads.push(plate.thermal_moment_load(&vec![uniform; plate.n_elements()]));
        }
        let f = DMatrix::from_fn(plate.bending_map.n_equations, loads.len(), |r, c| {
            loads[c][r]
        });
        let shapes = plate.static_solve(&f).map_err(model_error)?;
        let m = plate.assemble_mass();
        let m_times = |v: &[f64]| {
            let mut out = vec![0.0; v.len()];
            m.mul_vec(v, &mut out);
            out
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut basis: Vec<Vec<f64>> = modes
            .column_iter()
            .map(|c| c.iter().copied().collect())
            .collect();
        let n_modes = basis.len();
        for col in shapes.column_iter() {
            let mut v: Vec<f64> = col.iter().copied().collect();
            let norm0 = dot(&v, &m_times(&v)).sqrt();
            for _ in 0..2 {
                for b in &basis {
                    let c = dot(b, &m_times(&v));
                    v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
                }
            }
            let norm = dot(&v, &m_times(&v)).sqrt();
            // A shape already (numerically) in the span adds nothing; skip it.
            if norm.is_nan() || norm <= 1e-8 * norm0 {
                continue;
            }
            v.iter_mut().for_each(|x| *x /= norm);
            basis.push(v);
        }
        let n_eq = plate.bending_map.n_equations;
        let b = DMatrix::from_fn(n_eq, basis.len(), |r, c| basis[c][r]);
        let n_s = basis.len() - n_modes;
        // A final Rayleigh-Ritz on the whole basis makes it exactly M-orthonormal and
        // K-orthogonal (the modes from subspace iteration carry ~1e-6 vector errors); the
        // first n_modes Ritz values are the modes' own eigenvalues.
        let (b, eigenvalues) = Self::rayleigh_ritz(plate, b)?;
        let names = (0..n_s)
            .map(|i| format!("static-shape Ritz vector {}", i + 1))
            .collect();
        Ok((b, eigenvalues, names))
    }

    /// Rotates `basis` to the eigenvectors of (Bᵀ K B, Bᵀ M B) at 293 K: M-orthonormal,
    /// K-diagonal, ascending Ritz values.
    fn rayleigh_ritz(
        plate: &PlateModel,
        basis: DMatrix<f64>,
    ) -> Result<(DMatrix<f64>, Vec<f64>), ModelError> {
        let (k, m) = (plate.assemble_stiffness(None), plate.assemble_mass());
        let n = basis.nrows();
        let mut kb = DMatrix::<f64>::zeros(n, basis.ncols());
        let mut mb = DMatrix::<f64>::zeros(n, basis.ncols());
        let mut out = vec![0.0; n];
        for (c, col) in basis.column_iter().enumerate() {
            let v: Vec<f64> = col.iter().copied().collect();
            k.mul_vec(&v, &mut out);
            kb.column_mut(c).copy_from_slice(&out);
            m.mul_vec(&v, &mut out);
            mb.column_mut(c).copy_from_slice(&out);
        }
        let ritz = generalized_symmetric_eigen(
            &(basis.transpose() * kb),
            &(basis.transpose() * mb),
            basis.ncols(),
        )
        .map_err(|_| ModelError::inconsistent(NAME, "the Ritz basis is linearly dependent"))?;
        Ok((basis * ritz.vectors, ritz.values))
    }

    /// Precomputes the reduced element matrices, root-load and rigid-body couplings.
    fn from_basis(
        plate: PlateModel,
        basis: DMatrix<f64>,
        eigenvalues: Vec<f64>,
        names: Vec<String>,
        damping_ratio: f64,
    ) -> Self {
        let r = basis.ncols();
        let n_e = plate.n_elements();
        let mut stiffness = vec![0.0; n_e * r * r];
        let mut geometric = vec![0.0; 3 * n_e * r * r];
        let mut root_elements = Vec::new();
        let mut root_mass = DMatrix::<f64>::zeros(6, r);
        let pivot = plate.grid.pivot_m;
        let mut rigid_coupling = DMatrix::<f64>::zeros(r, 4);
        let mut rigid_mass = Matrix3::<f64>::zeros();
        let mut thermal = vec![0.0; n_e * r];
        let mut root_inertia = DMatrix::<f64>::zeros(6, r);
        for e in 0..n_e {
            let be = plate.element_rows(&basis, e);
            let ke = DMatrix::from_fn(12, 12, |a, b| plate.bending_stiffness[e][(a, b)]);
            let kr = be.transpose() * &ke * &be;
            stiffness[e * r * r..(e + 1) * r * r].copy_from_slice(kr.as_slice());
            let mut ge = [
                DMatrix::<f64>::zeros(12, 12),
                DMatrix::zeros(12, 12),
                DMatrix::zeros(12, 12),
            ];
            for (c, g) in ge.iter_mut().enumerate() {
                for i in 0..4 {
                    for j in 0..4 {
                        g[(3 * i, 3 * j)] = plate.geometric[e][c][(i, j)];
                    }
                }
                let gr = be.transpose() * &*g * &be;
                let start = (3 * e + c) * r * r;
                geometric[start..start + r * r].copy_from_slice(gr.as_slice());
            }
            let me = DMatrix::from_fn(12, 12, |a, b| plate.bending_mass[e][(a, b)]);
            let nodes = plate.grid.elements[e];
            if nodes
                .iter()
                .any(|&n| plate.supports.bending[n].iter().any(|&h| h))
            {
                let stiff = root_load_rows(&plate, e, &(&ke * &be), &pivot);
                let geo = [0, 1, 2].map(|c| root_load_rows(&plate, e, &(&ge[c] * &be), &pivot));
                root_mass += root_load_rows(&plate, e, &(&me * &be), &pivot);
                root_elements.push(RootElement {
                    element: e,
                    stiffness: stiff,
                    geometric: geo,
                });
            }
            // Rigid motions of the tube on the element's nodes: z translation (w = 1) and pitch
            // about the pivot axis (w = −(x − x_p), βx = 1); x translation is in-plane.
            let mut rz = DMatrix::<f64>::zeros(12, 3);
            for (k, &n) in nodes.iter().enumerate() {
                let x = plate.grid.positions_m[n].x;
                rz[(3 * k, 1)] = 1.0;
                rz[(3 * k, 2)] = -(x - pivot.x);
                rz[(3 * k + 1, 2)] = 1.0;
            }
            // The coupling's columns: x, z, roll and pitch of the tube (the order of
            // `rigid_dofs`); roll is column 3 of the six tube motions.
            let tube = tube_rigid_motions(&plate, e);
            let mut coupling = DMatrix::<f64>::zeros(12, 4);
            coupling.column_mut(0).copy_from(&rz.column(0));
            coupling.column_mut(1).copy_from(&rz.column(1));
            coupling.column_mut(2).copy_from(&tube.column(3));
            coupling.column_mut(3).copy_from(&rz.column(2));
            rigid_coupling += be.transpose() * &me * &coupling;
            root_inertia += tube.transpose() * &me * &be;
            let fe = DVector::from_column_slice(plate.bending_thermal[e].as_slice());
            thermal[e * r..(e + 1) * r].copy_from_slice((be.transpose() * fe).as_slice());
            let mrr = rz.transpose() * &me * &rz;
            for a in 1..3 {
                for b in 1..3 {
                    rigid_mass[(a, b)] += mrr[(a, b)];
                }
            }
            let mm = &plate.membrane_mass[e];
            // Σ_ij M_m[u_i, u_j]: the element's mass in x translation.
            rigid_mass[(0, 0)] += (0..4)
                .flat_map(|i| (0..4).map(move |j| (i, j)))
                .map(|(i, j)| mm[(2 * i, 2 * j)])
                .sum::<f64>();
        }
        let n_eq_m = plate.membrane_map.n_equations;
        let modal = ModalModel {
            names,
            mass: DMatrix::identity(r, r),
            damping: DMatrix::zeros(r, r),
            stiffness: DMatrix::from_diagonal(&DVector::from_vec(eigenvalues.clone())),
        };
        Self {
            membrane_k: plate.membrane_matrix(),
            membrane_rhs: vec![0.0; n_eq_m],
            states: vec![ElementState::REFERENCE; n_e],
            resultants: vec![[0.0; 3]; n_e],
            side: plate.grid.side,
            plate,
            damping_ratio,
            basis,
            reference_eigenvalues: eigenvalues.clone(),
            reduced: Reduced {
                size: r,
                stiffness,
                geometric,
                thermal,
            },
            root_elements,
            root_mass,
            root_stiffness: DMatrix::zeros(6, r),
            root_inertia,
            thermal_forces: DVector::zeros(r),
            rigid_coupling,
            rigid_mass,
            modal,
            eigenvalues,
            eigenvectors: DMatrix::identity(r, r),
            symmetric_eigen: SymmetricEigenSolver::new(r),
        }
    }

    /// The reference (293 K, stress-free) state: K_r from the reduced element sums.
    fn reset_reference(&mut self) -> Result<(), ModelError> {
        for s in &mut self.states {
            *s = ElementState::REFERENCE;
        }
        self.resultants.iter_mut().for_each(|r| *r = [0.0; 3]);
        self.update_reduced()
    }

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

    /// Updates stiffness and the thermal-moment load from mid-plane node temperatures (K) and
    /// node through-thickness differences ΔT = T(lower face, z = +t/2) − T(upper face) (K,
    /// linear in z; node order of [`RitzPlate::grid`]). [`StructureModel::set_temperatures`] is
    /// this with ΔT = 0. Allocation-free.
    pub fn set_temperature_field(
        &mut self,
        mean_k: &[f64],
        difference_k: &[f64],
    ) -> Result<(), ModelError> {
        self.update_temperatures(mean_k, Some(difference_k))
    }

    /// Generalized thermal-moment force Q_T = Φᵀ f_T of the latest temperature field (one per
    /// Ritz coordinate; N m per unit modal coordinate): add it to the applied generalized forces,
    /// M_r q̈ + C_r q̇ + K_r q = Q_applied + Q_T. Zero without a through-thickness difference.
    pub fn thermal_generalized_forces(&self) -> &DVector<f64> {
        &self.thermal_forces
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

    /// Checks nodal bending loads: one (F_z N, moment conjugate to βx N m, to βy N m) per grid
    /// node, all finite.
    fn check_nodal_loads(&self, nodal_loads: &[[f64; 3]]) -> Result<(), ModelError> {
        let n = self.plate.grid.n_nodes();
        if nodal_loads.len() != n {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} nodal loads given, the structural grid has {n} nodes",
                    nodal_loads.len()
                ),
            ));
        }
        if let Some(i) = nodal_loads
            .iter()
            .position(|f| f.iter().any(|v| !v.is_finite()))
        {
            return Err(ModelError::NonFinite {
                model: NAME.to_owned(),
                quantity: "nodal load".to_owned(),
                location: format!(" at structural node {i}"),
            });
        }
        Ok(())
    }

    /// Generalized forces Q = Φᵀ f of nodal bending loads on the structural grid (this grid's
    /// side; per node F_z along body z in N, then the moments conjugate to βx and βy in N m;
    /// loads on held dofs go straight to the support and do not enter).
    pub fn generalized_forces(&self, nodal_loads: &[[f64; 3]]) -> Result<DVector<f64>, ModelError> {
        self.check_nodal_loads(nodal_loads)?;
        let f = self.plate.to_equations(|n| nodal_loads[n]);
        Ok(self.basis.tr_mul(&DVector::from_vec(f)))
    }

    /// Resultant about [`RitzPlate::root_reference_m`] of nodal bending loads on the structural
    /// grid (as [`RitzPlate::generalized_forces`]), every node included: F_z = Σ F, M_x =
    /// Σ (y − y_p) F − m_βy, M_y = Σ −(x − x_p) F + m_βx; the applied load for
    /// [`RitzPlate::root_loads_by_force_summation`] when the loads are nodal.
    pub fn nodal_load_resultant(&self, nodal_loads: &[[f64; 3]]) -> Result<Loads, ModelError> {
        self.check_nodal_loads(nodal_loads)?;
        let g = &self.plate.grid;
        let mut l = Loads::default();
        for (p, f) in g.positions_m.iter().zip(nodal_loads) {
            l.force_n.z += f[0];
            l.moment_nm.x += (p.y - g.pivot_m.y) * f[0] - f[2];
            l.moment_nm.y += -(p.x - g.pivot_m.x) * f[0] + f[1];
        }
        finite_root_load(self.on_model_side(l))
    }

    /// The load the surface exerts on the tube by force summation (module docs): the applied
    /// load minus the inertia of the elastic motion, L = F_applied − Rᵀ M Φ q̈, force (N) and
    /// moment about [`RitzPlate::root_reference_m`] (N m), body axes of the selected side.
    /// `applied` is the resultant of every external load on the surface about that point (the
    /// root row's included: e.g. `integrate_pressure` over the surface's panels, or
    /// [`RitzPlate::nodal_load_resultant`]). Velocities enter no term (damping is internal)
    /// but are checked like the rest. The tube's own rigid acceleration is the coordinator's
    /// ([`RitzPlate::rigid_body_mass`], [`RitzPlate::rigid_body_coupling`]).
    pub fn root_loads_by_force_summation(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
        applied: &Loads,
    ) -> Result<Loads, ModelError> {
        check_modal_lengths(
            self.basis.ncols(),
            [
                ("modal coordinates", modal_coordinates),
                ("modal velocities", modal_velocities),
                ("modal accelerations", modal_accelerations),
            ],
        )?;
        let mut inertia = Loads::default();
        for c in 0..self.basis.ncols() {
            let a = modal_accelerations[c];
            for k in 0..3 {
                inertia.force_n[k] += self.root_inertia[(k, c)] * a;
                inertia.moment_nm[k] += self.root_inertia[(k + 3, c)] * a;
            }
        }
        let inertia = self.on_model_side(inertia);
        finite_root_load(Loads {
            force_n: applied.force_n - inertia.force_n,
            moment_nm: applied.moment_nm - inertia.moment_nm,
        })
    }

    /// A load computed on the grid's side, as seen on the selected side.
    fn on_model_side(&self, loads: Loads) -> Loads {
        if self.side == self.plate.grid.side {
            loads
        } else {
            mirror_in_y(loads)
        }
    }

    /// Element states, membrane solve and reduced update for a temperature field.
    fn update_temperatures(
        &mut self,
        mean_k: &[f64],
        difference_k: Option<&[f64]>,
    ) -> Result<(), ModelError> {
        self.plate
            .element_states(mean_k, difference_k, &mut self.states)
            .map_err(model_error)?;
        self.plate
            .membrane_resultants_into(
                &self.states,
                &mut self.membrane_k,
                &mut self.membrane_rhs,
                &mut self.resultants,
            )
            .map_err(model_error)?;
        if let Some(e) = self
            .resultants
            .iter()
            .position(|n| n.iter().any(|v| !v.is_finite()))
        {
            return Err(ModelError::NonFinite {
                model: NAME.to_owned(),
                quantity: "membrane stress resultant".to_owned(),
                location: format!(" in element {e}"),
            });
        }
        self.update_reduced()
    }

    /// Recomputes K_r, root-load matrices, eigen-decomposition and damping from the current
    /// element states and resultants (allocation-free).
    fn update_reduced(&mut self) -> Result<(), ModelError> {
        let r = self.reduced.size;
        let rr = r * r;
        let k = self.modal.stiffness.as_mut_slice();
        k.iter_mut().for_each(|v| *v = 0.0);
        for (e, state) in self.states.iter().enumerate() {
            let s = state.stiffness_scale;
            let ke = &self.reduced.stiffness[e * rr..(e + 1) * rr];
            let n = self.resultants[e];
            let g = &self.reduced.geometric[3 * e * rr..(3 * e + 3) * rr];
            for idx in 0..rr {
                k[idx] += s * ke[idx] + n[0] * g[idx] + n[1] * g[rr + idx] + n[2] * g[2 * rr + idx];
            }
        }
        // Exact symmetry for the eigen-solver.
        for i in 0..r {
            for j in (i + 1)..r {
                let avg = 0.5 * (k[i * r + j] + k[j * r + i]);
                k[i * r + j] = avg;
                k[j * r + i] = avg;
            }
        }
        self.root_stiffness.fill(0.0);
        for re in &self.root_elements {
            let s = self.states[re.element].stiffness_scale;
            let n = self.resultants[re.element];
            for idx in 0..6 * r {
                self.root_stiffness.as_mut_slice()[idx] += s * re.stiffness.as_slice()[idx]
                    + n[0] * re.geometric[0].as_slice()[idx]
                    + n[1] * re.geometric[1].as_slice()[idx]
                    + n[2] * re.geometric[2].as_slice()[idx];
            }
        }
        self.thermal_forces.fill(0.0);
        for (e, state) in self.states.iter().enumerate() {
            let scale = state.stiffness_scale * state.thermal_strain_difference;
            if scale != 0.0 {
                let fe = &self.reduced.thermal[e * r..(e + 1) * r];
                for (q, f) in self.thermal_forces.iter_mut().zip(fe) {
                    *q += scale * f;
                }
            }
        }
        self.symmetric_eigen
            .decompose(
                &self.modal.stiffness,
                &mut self.eigenvalues,
                &mut self.eigenvectors,
            )
            .map_err(|e| ModelError::inconsistent(NAME, format!("reduced stiffness: {e}")))?;
        // C = Ψ diag(2 ζ ω) Ψᵀ (M_r = I); a buckled (λ < 0) mode gets none.
        let c = &mut self.modal.damping;
        c.fill(0.0);
        for m in 0..r {
            let lam = self.eigenvalues[m];
            if lam <= 0.0 {
                continue;
            }
            let coef = 2.0 * self.damping_ratio * lam.sqrt();
            for i in 0..r {
                let pi = self.eigenvectors[(i, m)] * coef;
                for j in 0..r {
                    c[(i, j)] += pi * self.eigenvectors[(j, m)];
                }
            }
        }
        Ok(())
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

impl ThermalStiffness for RitzPlate {
    fn temperature_nodes(&self) -> usize {
        self.plate.grid.n_nodes()
    }

    fn set_temperatures(&mut self, node_temperatures_k: &[f64]) -> Result<(), ModelError> {
        self.update_temperatures(node_temperatures_k, None)
    }

    fn set_temperature_field(
        &mut self,
        mean_k: &[f64],
        difference_k: &[f64],
    ) -> Result<(), ModelError> {
        RitzPlate::set_temperature_field(self, mean_k, difference_k)
    }

    fn thermal_generalized_forces(&self) -> Option<&DVector<f64>> {
        Some(RitzPlate::thermal_generalized_forces(self))
    }

    /// The structural grid; the right surface's, so the left surface's temperatures are taken
    /// in the same node order (the mirror image).
    fn temperature_grid(&self) -> Option<&SurfaceGrid> {
        Some(&self.plate.grid)
    }
}

impl RootLoads for RitzPlate {
    fn root_reference_m(&self) -> Point3<f64> {
        RitzPlate::root_reference_m(self)
    }

    fn root_loads(
        &self,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        modal_accelerations: &DVector<f64>,
        applied: &Loads,
    ) -> Result<Loads, ModelError> {
        self.root_loads_by_force_summation(
            modal_coordinates,
            modal_velocities,
            modal_accelerations,
            applied,
        )
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

impl MassDistribution for RitzPlate {
    /// Node masses ([`PlateModel::node_masses_kg`]: ρ ∫ N_i m dA + m_ns ∫ N_i dA) at the
    /// mid-plane nodes (exact mass and first moment for the bilinear thickness of a solid
    /// section; inertia of the lumped masses, omitting each section's own rotary inertia),
    /// mirrored for the left surface.
    fn mass_properties(&self) -> MassProperties {
        let grid = &self.plate.grid;
        let mirror = if self.side == grid.side { 1.0 } else { -1.0 };
        let at = |p: &Point3<f64>| Point3::new(p.x, mirror * p.y, p.z);
        let node_masses = self.plate.node_masses_kg();
        let masses = node_masses.iter().copied();
        let mass_kg: f64 = masses.clone().sum();
        let first: Vector3<f64> = masses
            .clone()
            .zip(&grid.positions_m)
            .map(|(m, p)| at(p).coords * m)
            .sum();
        let center = Point3::from(first / mass_kg);
        let mut inertia = Matrix3::zeros();
        for (m, p) in masses.zip(&grid.positions_m) {
            let d = at(p) - center;
            inertia += m * (Matrix3::identity() * d.norm_squared() - d * d.transpose());
        }
        MassProperties {
            mass_kg,
            center_of_mass_m: center,
            inertia_kg_m2: inertia,
        }
    }
}

impl RigidBodyCoupling for RitzPlate {
    fn rigid_dofs(&self) -> &[RigidDof] {
        &[
            RigidDof::TranslationX,
            RigidDof::TranslationZ,
            RigidDof::RotationX,
            RigidDof::RotationY,
        ]
    }

    fn rigid_reference_point_m(&self) -> Point3<f64> {
        let p = self.plate.grid.pivot_m;
        let mirror = if self.side == self.plate.grid.side {
            1.0
        } else {
            -1.0
        };
        Point3::new(p.x, mirror * p.y, p.z)
    }

    fn rigid_coupling(&self) -> &DMatrix<f64> {
        &self.rigid_coupling
    }
}
