//! The all-movable lifting surfaces: the `[lifting_surface]` table, the planform and the closed
//! panel mesh of each side.
//!
//! **Lifting surfaces** (after Falkiewicz & Cesnik): trapezoidal, double-wedge section, mounted
//! on the body sides with the torque tube (pivot axis) parallel to y. Each mesh is closed:
//! `<side>-surface-upper`, `<side>-surface-lower`, `<side>-surface-tip` (lifting surface) and
//! `<side>-surface-root` (other: the root cap against the body). Strips run leading edge to
//! trailing edge along the chord at each spanwise station, on the upper and lower surfaces.

use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::mesh::{PanelMesh, RegionKind};

use super::checks::{VehicleError, check_count, check_range};
use super::polygon_mesh::{Builder, distribute, lerp};

/// The `[lifting_surface]` table: one trapezoidal all-movable surface with a double-wedge
/// section (after Falkiewicz & Cesnik), mirrored to the left side. Distances in m, angles in
/// degrees.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LiftingSurfaceConfig {
    /// Chord at the root, m.
    pub root_chord_m: f64,
    /// Chord at the tip, m.
    pub tip_chord_m: f64,
    /// Root to tip of one surface, m.
    pub span_m: f64,
    /// Leading-edge sweep, deg (positive: tip aft).
    pub leading_edge_sweep_deg: f64,
    /// Maximum thickness over chord, same at every station.
    pub thickness_to_chord: f64,
    /// Chordwise position of the maximum thickness (ridge of the double wedge) over chord.
    pub max_thickness_chord_fraction: f64,
    /// Nose to the pivot (torque tube) axis, m.
    pub pivot_aft_of_nose_m: f64,
    /// Pivot position along the root chord from the root leading edge, over root chord.
    pub pivot_root_chord_fraction: f64,
    /// z of the pivot axis (and the surface's mid-plane) below the nose line, m.
    pub pivot_z_m: f64,
    /// Distance of the root from the centerline, m (the body's half width when mounted on its
    /// sides).
    pub root_y_m: f64,
    /// Panels along the chord on each of the upper and lower surfaces (≥ 2, split over the two
    /// wedges by length).
    pub panels_chordwise: usize,
    /// Panels along the span.
    pub panels_spanwise: usize,
}

/// Which lifting surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// y < 0.
    Left,
    /// y > 0.
    Right,
}

impl Side {
    /// "left" or "right".
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }

    /// -1 for left, +1 for right.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => -1.0,
            Side::Right => 1.0,
        }
    }
}

/// Validated planform quantities of a trapezoidal double-wedge surface (the lifting surfaces
/// and the vertical fin).
pub(super) struct Planform {
    pub(super) root_chord: f64,
    pub(super) tip_chord: f64,
    pub(super) span: f64,
    pub(super) tan_sweep: f64,
    pub(super) tc: f64,
    pub(super) ridge: f64,
    /// Nose to the root leading edge, m.
    pub(super) root_le_s: f64,
    pub(super) root_y: f64,
    pub(super) pivot_z: f64,
}

/// The trapezoidal, double-wedge shape the lifting surfaces and the vertical fin share, as
/// their config tables give it, and the table and span key its errors name.
pub(super) struct WingShape {
    pub table: &'static str,
    pub span_key: &'static str,
    pub root_chord_m: f64,
    pub tip_chord_m: f64,
    pub span_m: f64,
    pub leading_edge_sweep_deg: f64,
    pub thickness_to_chord: f64,
    pub max_thickness_chord_fraction: f64,
    pub panels_chordwise: usize,
    pub panels_spanwise: usize,
}

impl Planform {
    /// `shape` checked (errors name its table and key) and placed with its root leading edge
    /// `root_le_s` aft of the nose, its root at `root_y`, its pivot plane at `pivot_z`, m.
    pub(super) fn checked(
        shape: &WingShape,
        (root_le_s, root_y, pivot_z): (f64, f64, f64),
    ) -> Result<Self, VehicleError> {
        let t = shape.table;
        check_range(t, "root_chord_m", shape.root_chord_m, 0.0, 1e4, false)?;
        check_range(t, "tip_chord_m", shape.tip_chord_m, 0.0, 1e4, false)?;
        check_range(t, shape.span_key, shape.span_m, 0.0, 1e4, false)?;
        let sweep = shape.leading_edge_sweep_deg;
        check_range(t, "leading_edge_sweep_deg", sweep, -80.0, 80.0, true)?;
        let tc = shape.thickness_to_chord;
        check_range(t, "thickness_to_chord", tc, 0.0, 0.5, false)?;
        let ridge = shape.max_thickness_chord_fraction;
        check_range(t, "max_thickness_chord_fraction", ridge, 0.0, 1.0, false)?;
        check_count(t, "panels_chordwise", shape.panels_chordwise, 2)?;
        check_count(t, "panels_spanwise", shape.panels_spanwise, 1)?;
        Ok(Self {
            root_chord: shape.root_chord_m,
            tip_chord: shape.tip_chord_m,
            span: shape.span_m,
            tan_sweep: sweep.to_radians().tan(),
            tc,
            ridge,
            root_le_s,
            root_y,
            pivot_z,
        })
    }

    fn new(c: &LiftingSurfaceConfig) -> Result<Self, VehicleError> {
        const T: &str = "lifting_surface";
        let pivot_aft = c.pivot_aft_of_nose_m;
        check_range(T, "pivot_aft_of_nose_m", pivot_aft, -1e4, 1e4, true)?;
        let pivot_fraction = c.pivot_root_chord_fraction;
        check_range(
            T,
            "pivot_root_chord_fraction",
            pivot_fraction,
            0.0,
            1.0,
            true,
        )?;
        check_range(T, "pivot_z_m", c.pivot_z_m, -1e4, 1e4, true)?;
        check_range(T, "root_y_m", c.root_y_m, 0.0, 1e4, true)?;
        let shape = WingShape {
            table: T,
            span_key: "span_m",
            root_chord_m: c.root_chord_m,
            tip_chord_m: c.tip_chord_m,
            span_m: c.span_m,
            leading_edge_sweep_deg: c.leading_edge_sweep_deg,
            thickness_to_chord: c.thickness_to_chord,
            max_thickness_chord_fraction: c.max_thickness_chord_fraction,
            panels_chordwise: c.panels_chordwise,
            panels_spanwise: c.panels_spanwise,
        };
        let root_le_s = pivot_aft - pivot_fraction * c.root_chord_m;
        Self::checked(&shape, (root_le_s, c.root_y_m, c.pivot_z_m))
    }

    /// Point at chord fraction u, span fraction eta, on the upper (true) or lower surface, for
    /// the right side (y > 0), m.
    fn point(&self, u: f64, eta: f64, upper: bool) -> Point3<f64> {
        let chord = lerp(self.root_chord, self.tip_chord, eta);
        let le_s = self.root_le_s + eta * self.span * self.tan_sweep;
        let shape = if u <= self.ridge {
            u / self.ridge
        } else {
            (1.0 - u) / (1.0 - self.ridge)
        };
        let half_t = 0.5 * self.tc * chord * shape;
        let z = if upper {
            self.pivot_z - half_t
        } else {
            self.pivot_z + half_t
        };
        Point3::new(-(le_s + u * chord), self.root_y + eta * self.span, z)
    }
}

/// Chord fractions 0..1 with the ridge included; `n` panels split over the two wedges by length.
fn chord_stations(n: usize, ridge: f64) -> Vec<f64> {
    let counts = distribute(n, &[ridge, 1.0 - ridge]);
    let mut out = vec![0.0];
    for (k, &(a, b)) in [(0.0, ridge), (ridge, 1.0)].iter().enumerate() {
        let c = counts[k];
        for i in 1..=c {
            out.push(if i == c {
                b
            } else {
                lerp(a, b, i as f64 / c as f64)
            });
        }
    }
    out
}

/// Closed mesh of one lifting surface at zero deflection (surfaces and strips in the module
/// docs), tagged [`RegionKind::LiftingSurface`] except the root cap ([`RegionKind::Other`]).
pub fn lifting_surface_mesh(
    cfg: &LiftingSurfaceConfig,
    side: Side,
) -> Result<PanelMesh, VehicleError> {
    let pf = Planform::new(cfg)?;
    let sign = side.sign();
    let name = side.name();
    closed_surface_mesh(
        &pf,
        (cfg.panels_chordwise, cfg.panels_spanwise),
        [
            format!("{name}-surface-upper"),
            format!("{name}-surface-lower"),
            format!("{name}-surface-tip"),
            format!("{name}-surface-root"),
        ],
        &|p| Point3::new(p.x, sign * p.y, p.z),
        &|v| Vector3::new(v.x, sign * v.y, v.z),
        match side {
            Side::Left => "left lifting-surface",
            Side::Right => "right lifting-surface",
        },
    )
}

/// The closed mesh of `pf` built on the right side (span along +y, upper surface towards -z),
/// then placed by `place` (points) and `orient` (the outward directions): `names` are the upper,
/// lower, tip and root surfaces; the root cap is [`RegionKind::Other`].
pub(super) fn closed_surface_mesh(
    pf: &Planform,
    (panels_chordwise, panels_spanwise): (usize, usize),
    names: [String; 4],
    place: &dyn Fn(Point3<f64>) -> Point3<f64>,
    orient: &dyn Fn(Vector3<f64>) -> Vector3<f64>,
    what: &'static str,
) -> Result<PanelMesh, VehicleError> {
    let us = chord_stations(panels_chordwise, pf.ridge);
    let ns = panels_spanwise;
    let etas: Vec<f64> = (0..=ns).map(|j| j as f64 / ns as f64).collect();
    let [upper_name, lower_name, tip_name, root_name] = names;

    let mut b = Builder::default();
    let upper = b.surface(upper_name, RegionKind::LiftingSurface);
    let lower = b.surface(lower_name, RegionKind::LiftingSurface);
    let tip = b.surface(tip_name, RegionKind::LiftingSurface);
    let root = b.surface(root_name, RegionKind::Other);

    for (is_upper, surface, outward) in [(true, upper, -Vector3::z()), (false, lower, Vector3::z())]
    {
        let nodes: Vec<Vec<Point3<f64>>> = us
            .iter()
            .map(|&u| {
                etas.iter()
                    .map(|&eta| place(pf.point(u, eta, is_upper)))
                    .collect()
            })
            .collect();
        b.grid(&nodes, |_| surface, orient(outward), true);
    }
    let outboard = Vector3::y();
    for (eta, surface, outward) in [(1.0, tip, outboard), (0.0, root, -outboard)] {
        let nodes: Vec<Vec<Point3<f64>>> = us
            .iter()
            .map(|&u| {
                vec![
                    place(pf.point(u, eta, true)),
                    place(pf.point(u, eta, false)),
                ]
            })
            .collect();
        b.grid(&nodes, |_| surface, orient(outward), false);
    }
    b.finish(what)
}

/// Root end of the torque tube of `side`, m.
pub fn pivot_point(cfg: &LiftingSurfaceConfig, side: Side) -> Point3<f64> {
    Point3::new(
        -cfg.pivot_aft_of_nose_m,
        side.sign() * cfg.root_y_m,
        cfg.pivot_z_m,
    )
}
