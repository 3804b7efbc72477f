//! The `full-order` settings: the `[models.full-order]` table (grid resolution, structure,
//! built-up skins and interior, outer layers, quadrature, Picard iteration), its defaults and
//! documented form, and the checks of its ranges and of the skins against the plate.
//!
//! The `pod` model builds on the same table (its basis is fingerprinted by [`Settings::resolved`]).

use hsv_core::material::MaterialSetting;
use hsv_core::surface_grid::SurfaceGrid;

use crate::grid::Quadrature;

/// An outer layer over the structure (a thermal-protection layer), on both faces.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSetting {
    /// Thickness, m.
    pub thickness_m: f64,
    /// A built-in material name or a full material table (core `material.rs`).
    pub material: MaterialSetting,
    /// Elements through the layer.
    #[serde(default = "one")]
    pub sublayers: usize,
}

fn one() -> usize {
    1
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

/// The default interior: still air (core `material/air.rs`).
fn air() -> MaterialSetting {
    MaterialSetting::Name("air".to_owned())
}

fn is_air(m: &MaterialSetting) -> bool {
    *m == air()
}

/// Settings of `[models.full-order]` (the `pod` model builds on the same table).
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Grid elements along the chord (≥ 2; the ridge is a node line).
    pub elements_chordwise: usize,
    /// Grid elements along the span.
    pub elements_spanwise: usize,
    /// Structural material.
    pub structure_material: MaterialSetting,
    /// Elements through the structure's thickness (through each skin when built up).
    pub structure_sublayers: usize,
    /// Smallest structural thickness, m (the double wedge is sharp at its edges); when built
    /// up, the smallest interior thickness.
    pub minimum_thickness_m: f64,
    /// Skin thickness t_s, m. Absent: the structure is solid, the plate's whole thickness.
    /// Given: it is built up, two skins of `structure_material` (`structure_sublayers` elements
    /// each) at the plate's faces with the interior between them (the plate's thickness less
    /// 2 t_s, at least `minimum_thickness_m`); the outer layers stay where they are.
    /// (Serialized only when given, like the two interior keys only when not their defaults,
    /// so a solid configuration's POD basis fingerprint is what it was before these keys.)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skin_thickness_m: Option<f64>,
    /// Material of a built-up structure's interior (unused when solid): a thermal-only table
    /// will do. Default still air (`"air"`). It conducts only: radiation and convection between
    /// the skins are neglected, so an air interior is nearly adiabatic.
    #[serde(skip_serializing_if = "is_air")]
    pub interior_material: MaterialSetting,
    /// Elements through the interior (unused when solid). One element conducts the quasi-steady
    /// k/h exactly; the interior's heat capacity is negligible for air.
    #[serde(skip_serializing_if = "is_one")]
    pub interior_sublayers: usize,
    /// Quadrature of the elements' conduction matrices ([`crate::grid`] module docs):
    /// `"gauss"` (2×2×2 Gauss, the consistent Galerkin matrix) or `"nodal"` (the 8 corners: the
    /// finite-volume stencil, whose non-positive off-diagonals keep the discrete maximum
    /// principle in thin elements). Absent: [`Settings::quadrature`], `gauss` for a solid
    /// structure (as before the key existed) and `nodal` for a built-up one, whose skin and
    /// outer-layer elements are ~100 times wider than thick. (Serialized only when given, so a
    /// solid configuration's POD basis fingerprint is what it was before this key.)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conduction_quadrature: Option<Quadrature>,
    /// Outer layers over the structure on both faces, outermost first.
    pub layers: Vec<LayerSetting>,
    /// Picard iterations stop when no temperature changes by more than this, K.
    pub picard_tolerance_k: f64,
    /// Picard iterations allowed per time step.
    pub max_picard_iterations: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            elements_chordwise: 16,
            elements_spanwise: 8,
            structure_material: MaterialSetting::default(),
            structure_sublayers: 2,
            // Our choice: 2 mm skins at the sharp leading and trailing edges.
            minimum_thickness_m: 0.002,
            skin_thickness_m: None,
            interior_material: air(),
            interior_sublayers: 1,
            conduction_quadrature: None,
            layers: Vec::new(),
            picard_tolerance_k: 1e-3,
            max_picard_iterations: 30,
        }
    }
}

/// What `hsv-run describe full-order` prints.
pub const SETTINGS_DOC: &str = "\
elements_chordwise = 16        # grid elements along the chord (>= 2)
elements_spanwise = 8          # grid elements along the span
structure_material = \"ti-6al-4v\" # structural material (name or full table)
structure_sublayers = 2        # elements through the structure's thickness (each skin when built up)
minimum_thickness_m = 0.002    # smallest structural thickness (sharp edges), m; built up: smallest interior
# skin_thickness_m = 0.0015    # optional: a built-up structure, two skins of this thickness, m, at the
                               #   faces (structure_material) over a hollow interior; absent: solid
interior_material = \"air\"      # built-up interior: still air (k, c_p 100-3000 K, Incropera & DeWitt
                               #   Table A.4) or a table; no radiation or convection between the skins
interior_sublayers = 1         # elements through the interior (built up)
# conduction_quadrature = \"nodal\" # optional: \"gauss\" (2x2x2, consistent) or \"nodal\" (corners: the
                               #   finite-volume stencil, no undershoot in thin elements); absent:
                               #   gauss when solid, nodal when built up (skin_thickness_m given)
layers = []                    # outer (TPS) layers on both faces, outermost first, e.g.
                               #   [{ thickness_m = 0.002, material = \"vdi-l1400\", sublayers = 2 }]
                               #   (built-in thermal-only insulator, k and c_p 293-1673.15 K, VDI
                               #   Heat Atlas) or a material table; k, c_p only: no E is asked of a
                               #   layer. Their mass: ritz-plate non_structural_mass_kg_m2 = 2 Σ ρ t
picard_tolerance_k = 1e-3      # Picard convergence: largest change per iteration, K
max_picard_iterations = 30     # Picard iterations allowed per step";

impl Settings {
    /// The conduction quadrature in effect: `conduction_quadrature` when given, otherwise
    /// `gauss` for a solid structure and `nodal` for a built-up one (its thin skins and layers
    /// would break the maximum principle under Gauss; [`crate::grid`] module docs).
    pub fn quadrature(&self) -> Quadrature {
        self.conduction_quadrature
            .unwrap_or(match self.skin_thickness_m {
                None => Quadrature::Gauss,
                Some(_) => Quadrature::Nodal,
            })
    }

    /// These settings with the quadrature in effect written out, except a solid structure's
    /// default `gauss`, which stays absent: what a POD basis is fingerprinted and checked by, so
    /// a basis serves exactly the runs with its grid matrices (a built-up basis from before the
    /// key existed was built with Gauss and is not reused for the nodal default), and a solid
    /// configuration's fingerprint is what it was before the key.
    pub fn resolved(&self) -> Settings {
        let quadrature = self.quadrature();
        let legacy = self.skin_thickness_m.is_none() && quadrature == Quadrature::Gauss;
        Settings {
            conduction_quadrature: (!legacy).then_some(quadrature),
            ..self.clone()
        }
    }

    /// The first setting out of range: (key, value, allowed).
    pub fn first_invalid(&self) -> Option<(String, f64, &'static str)> {
        let counts = [
            ("elements_chordwise", self.elements_chordwise, 2),
            ("elements_spanwise", self.elements_spanwise, 1),
            ("structure_sublayers", self.structure_sublayers, 1),
            ("interior_sublayers", self.interior_sublayers, 1),
            ("max_picard_iterations", self.max_picard_iterations, 1),
        ];
        for (key, n, min) in counts {
            if !(min..=2000).contains(&n) {
                return Some((
                    key.to_owned(),
                    n as f64,
                    "an integer from the minimum to 2000",
                ));
            }
        }
        let positive = [
            ("minimum_thickness_m", self.minimum_thickness_m),
            ("picard_tolerance_k", self.picard_tolerance_k),
        ];
        let skin = self.skin_thickness_m.map(|t| ("skin_thickness_m", t));
        for (key, v) in positive.into_iter().chain(skin) {
            if !(v.is_finite() && v > 0.0) {
                return Some((key.to_owned(), v, "finite and > 0"));
            }
        }
        for (i, layer) in self.layers.iter().enumerate() {
            if !(layer.thickness_m.is_finite() && layer.thickness_m > 0.0) {
                return Some((
                    format!("layers[{i}].thickness_m"),
                    layer.thickness_m,
                    "finite and > 0",
                ));
            }
            if !(1..=100).contains(&layer.sublayers) {
                return Some((
                    format!("layers[{i}].sublayers"),
                    layer.sublayers as f64,
                    "1 to 100",
                ));
            }
        }
        None
    }

    /// Skins that leave no room for the interior anywhere on `plate` (2 t_s at least its largest
    /// thickness): (key, value, allowed).
    pub fn skins_misfit(&self, plate: &SurfaceGrid) -> Option<(String, f64, String)> {
        let t = self.skin_thickness_m?;
        let thickest = plate.thickness_m.iter().copied().fold(0.0, f64::max);
        (2.0 * t >= thickest).then(|| {
            (
                "skin_thickness_m".to_owned(),
                t,
                format!(
                    "below half the plate's largest thickness, {thickest} m, so that the \
                     interior has room"
                ),
            )
        })
    }
}
