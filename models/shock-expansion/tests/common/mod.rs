//! The test meshes' one building block: a two-dimensional polyline extruded over one metre of
//! span into a streamwise strip of quadrilaterals.

use hsv_core::mesh::{PanelSpec, Strip};
use nalgebra::Point3;

/// Appends the polyline `points` (x, z, from leading to trailing edge; body axes, chord along
/// -x) extruded over y in [y0, y0 + 1] m as one strip, its panels counter-clockwise seen from
/// below (normals down, +z: a lower surface) when `facing_down`, else from above (an upper
/// surface).
pub fn push_extruded_strip(
    (vertices, panels, strips): (&mut Vec<Point3<f64>>, &mut Vec<PanelSpec>, &mut Vec<Strip>),
    points: &[(f64, f64)],
    y0: f64,
    facing_down: bool,
) {
    let base = vertices.len();
    for &(x, z) in points {
        vertices.push(Point3::new(x, y0, z));
        vertices.push(Point3::new(x, y0 + 1.0, z));
    }
    let mut strip = Strip::default();
    for i in 0..points.len() - 1 {
        let (a0, a1, b0, b1) = (
            base + 2 * i,
            base + 2 * i + 1,
            base + 2 * i + 2,
            base + 2 * i + 3,
        );
        strip.panels.push(panels.len());
        panels.push(if facing_down {
            PanelSpec::quad(a0, a1, b1, b0, 0)
        } else {
            PanelSpec::quad(a0, b0, b1, a1, 0)
        });
    }
    strips.push(strip);
}
