//! The `ritz-plate` settings: planform and root choices, the rectangular and built-up variants,
//! their defaults, the constructor the registry calls and the structural grid it builds.

use super::*;

pub(super) fn default_modes() -> usize {
    10
}

pub(super) fn default_static() -> usize {
    5
}

pub(super) fn default_chordwise() -> usize {
    24
}

pub(super) fn default_spanwise() -> usize {
    18
}

pub(super) fn default_damping() -> f64 {
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

pub(super) fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn StructureModel>, ModelError> {
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
    if let Some(model) = built_before(&settings, &grid, &material) {
        return Ok(Box::new(model.with_side(side)));
    }
    let key = (settings.clone(), grid.clone(), material.clone());
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
    remember_built(key, &model);
    Ok(Box::new(model.with_side(side)))
}

/// What a plate is built from (settings, grid, material) and the plate, before its side.
type BuiltPlate = ((Settings, SurfaceGrid, Material), RitzPlate);

/// The last plate built in this process. The left and right surfaces are built from the same
/// grid (the right's: `with_side` mirrors it), so the second is a copy of the first instead of
/// a second Ritz solve (64 ms on the sample surface); the copy is the same to the bit, the
/// construction being a deterministic function of these inputs.
static LAST_BUILT: std::sync::Mutex<Option<BuiltPlate>> = std::sync::Mutex::new(None);

/// A copy of the last plate built, when it was built from these inputs.
fn built_before(settings: &Settings, grid: &SurfaceGrid, material: &Material) -> Option<RitzPlate> {
    // A poisoned lock (a panic elsewhere while it was held) is a miss: the plate is built again.
    let last = LAST_BUILT.lock().ok()?;
    let ((s, g, m), plate) = last.as_ref()?;
    (s == settings && g == grid && m == material).then(|| plate.clone())
}

/// Forgets the last plate built, so the next construction solves for its Ritz basis again
/// (what a benchmark of the construction measures).
pub fn forget_built_plates() {
    if let Ok(mut last) = LAST_BUILT.lock() {
        *last = None;
    }
}

/// Keeps `plate`, built from `key`, for the next construction.
fn remember_built(key: (Settings, SurfaceGrid, Material), plate: &RitzPlate) {
    if let Ok(mut last) = LAST_BUILT.lock() {
        *last = Some((key, plate.clone()));
    }
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
