//! The vertical fin: the `[vertical_fin]` table and the fin's closed panel mesh, standing on the
//! body's upper centreline in the x-z plane.
//!
//! The fin is a fixed trapezoidal surface with the lifting surfaces' double-wedge section. Its
//! mesh is the lifting surfaces' right-side mesh (module `lifting_surface`) rotated by -90° about
//! x, so that its span points up (-z) and its thickness across the centreline (±y): surfaces
//! `fin-left` (y < 0), `fin-right`, `fin-tip` (lifting surface) and `fin-root` (other: the cap
//! against the body). Strips run leading edge to trailing edge at each height, so a sideslip
//! angle β is to the fin what the angle of attack is to a horizontal surface.

use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::mesh::PanelMesh;

use super::checks::{VehicleError, check_range};
use super::lifting_surface::{Planform, WingShape, closed_surface_mesh};

/// The `[vertical_fin]` table: one trapezoidal fin with a double-wedge section on the upper
/// centreline. Distances in m, angles in degrees.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VerticalFinConfig {
    /// Chord at the root, m.
    pub root_chord_m: f64,
    /// Chord at the tip, m.
    pub tip_chord_m: f64,
    /// Root to tip, m.
    pub height_m: f64,
    /// Leading-edge sweep, deg (positive: tip aft).
    pub leading_edge_sweep_deg: f64,
    /// Maximum thickness over chord, same at every station.
    pub thickness_to_chord: f64,
    /// Chordwise position of the maximum thickness (ridge of the double wedge) over chord.
    pub max_thickness_chord_fraction: f64,
    /// Nose to the root chord's leading edge, m.
    pub root_leading_edge_aft_of_nose_m: f64,
    /// z of the root chord below the nose line, m (negative: above it, on the upper surface).
    pub root_z_m: f64,
    /// Panels along the chord on each side (≥ 2, split over the two wedges by length).
    pub panels_chordwise: usize,
    /// Panels along the height.
    pub panels_spanwise: usize,
}

impl VerticalFinConfig {
    /// The fin's planform, checked; errors name the `[vertical_fin]` key.
    fn planform(&self) -> Result<Planform, VehicleError> {
        const T: &str = "vertical_fin";
        let root_le = self.root_leading_edge_aft_of_nose_m;
        check_range(
            T,
            "root_leading_edge_aft_of_nose_m",
            root_le,
            -1e4,
            1e4,
            true,
        )?;
        check_range(T, "root_z_m", self.root_z_m, -1e4, 1e4, true)?;
        let shape = WingShape {
            table: T,
            span_key: "height_m",
            root_chord_m: self.root_chord_m,
            tip_chord_m: self.tip_chord_m,
            span_m: self.height_m,
            leading_edge_sweep_deg: self.leading_edge_sweep_deg,
            thickness_to_chord: self.thickness_to_chord,
            max_thickness_chord_fraction: self.max_thickness_chord_fraction,
            panels_chordwise: self.panels_chordwise,
            panels_spanwise: self.panels_spanwise,
        };
        Planform::checked(&shape, (root_le, 0.0, 0.0))
    }

    /// The fin's planform area, m²: (c_root + c_tip) h / 2.
    pub fn area_m2(&self) -> f64 {
        0.5 * (self.root_chord_m + self.tip_chord_m) * self.height_m
    }
}

/// Closed mesh of the vertical fin (module docs), body frame, m.
pub fn vertical_fin_mesh(cfg: &VerticalFinConfig) -> Result<PanelMesh, VehicleError> {
    let pf = cfg.planform()?;
    let root_z = cfg.root_z_m;
    // -90° about x: the right-side surface's span (+y) goes up (-z), its upper side (-z) left.
    closed_surface_mesh(
        &pf,
        (cfg.panels_chordwise, cfg.panels_spanwise),
        [
            "fin-left".to_owned(),
            "fin-right".to_owned(),
            "fin-tip".to_owned(),
            "fin-root".to_owned(),
        ],
        &|p| Point3::new(p.x, p.z, root_z - p.y),
        &|v| Vector3::new(v.x, v.z, -v.y),
        "vertical fin",
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::RegionKind;

    /// The sample config's fin (its commented block; root chord 4 m, height 3 m).
    fn fin() -> VerticalFinConfig {
        crate::testing::sample_vertical_fin()
    }

    /// The mesh stands in the x-z plane above its root, and its loaded panels' projected area
    /// on the centreline plane is twice the trapezoid's (c_r + c_t) h / 2 (both sides), each
    /// side's outward normal pointing away from the centreline.
    #[test]
    fn fin_mesh_stands_on_the_centreline() {
        let cfg = fin();
        let mesh = vertical_fin_mesh(&cfg).expect("fin mesh");
        let (lo, hi) = crate::mesh::bounding_box_of(&mesh.vertices);
        assert!((lo.z - (cfg.root_z_m - cfg.height_m)).abs() < 1e-12, "{lo}");
        assert!((hi.z - cfg.root_z_m).abs() < 1e-12, "{hi}");
        let half_t = 0.5 * cfg.thickness_to_chord * cfg.root_chord_m;
        assert!((hi.y - half_t).abs() < 1e-12 && (lo.y + half_t).abs() < 1e-12);
        let mut projected = 0.0;
        for (k, panel) in mesh.panels.iter().enumerate() {
            let surface = &mesh.surfaces[panel.surface as usize];
            if surface.region != RegionKind::LiftingSurface || surface.name == "fin-tip" {
                continue;
            }
            let n = panel.normal;
            let side = if surface.name == "fin-left" {
                -1.0
            } else {
                1.0
            };
            assert!(n.y * side > 0.0, "{} panel {k}: normal {n}", surface.name);
            projected += panel.area_m2 * n.y.abs();
        }
        assert!(
            (projected - 2.0 * cfg.area_m2()).abs() < 1e-9 * cfg.area_m2(),
            "{projected} vs {}",
            2.0 * cfg.area_m2()
        );
    }

    #[test]
    fn bad_fin_key_is_named() {
        let mut cfg = fin();
        cfg.height_m = -1.0;
        let err = vertical_fin_mesh(&cfg)
            .expect_err("negative height")
            .to_string();
        assert!(
            err.contains("vertical_fin") && err.contains("height_m"),
            "{err}"
        );
    }
}
