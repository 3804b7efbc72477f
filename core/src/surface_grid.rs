//! The structural grid of a lifting surface: a structured quadrilateral grid over the planform's
//! mid-plane, with the section thickness at each node, element connectivity, nodal areas and
//! volumes, the root (torque-tube) node set, and maps from aero/thermal mesh points to grid nodes
//! (one file: one type, [`SurfaceGrid`], whose construction, maps and tests share the node
//! numbering below).
//!
//! **Layout.** Nodes sit at chord fractions `u_i` (i = 0 leading edge … `elements_chordwise`
//! trailing edge; the double wedge's ridge is always a station when `elements_chordwise ≥ 2`,
//! the elements split over the two wedges by length) and span fractions `η_j = j /
//! elements_spanwise` (j = 0 root … tip). Node (i, j) has index `j · nodes_chordwise + i`;
//! element (i, j) spans nodes (i..i+1, j..j+1) and has index `j · elements_chordwise + i`.
//! Element nodes are listed counter-clockwise in the body x-y plane (positive signed area with
//! x and y as drawn), whichever side.
//!
//! **Frame.** Body axes, the same as [`crate::geometry::lifting_surface_mesh`]: the mid-plane is
//! the plane z = `pivot_z_m`, the root at |y| = `root_y_m`, the left surface the mirror image
//! (y < 0) of the right. Thickness at a node is the double-wedge thickness
//! t = (t/c) c(η) shape(u), zero at the leading and trailing edges.
//!
//! **Rectangular plate** ([`SurfaceGrid::rectangular`]): uniform thickness, x from 0 (leading
//! edge) to −chord, y from 0 (root edge, the clamped set) to span, z = 0; for checks against
//! plate theory.
//!
//! **Maps.** [`SurfaceGrid::locate`] projects a point onto the mid-plane and returns the grid
//! element containing it with the four bilinear weights; [`SurfaceGrid::map_panels`] does so for
//! every panel centroid of a mesh (pressure → nodal force: F_node += w F_panel; node
//! temperature → panel wall temperature: T_panel = Σ w T_node, [`SurfaceGrid::interpolate`]).

use nalgebra::Point3;

use crate::geometry::{LiftingSurfaceConfig, Side};
use crate::mesh::PanelMesh;

/// Why a grid could not be built or a point mapped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// A dimension or count out of range.
    #[error("structural grid: {quantity} = {value}: {message}")]
    Invalid {
        quantity: String,
        value: f64,
        message: String,
    },
    /// A mesh point does not lie over the grid's planform.
    #[error(
        "structural grid: {what} {index} at ({x:.4}, {y:.4}, {z:.4}) m is {distance_m:.3e} m \
         outside the planform (tolerance {tolerance_m:.1e} m); is it the other side's mesh?"
    )]
    OutsidePlanform {
        what: &'static str,
        index: usize,
        x: f64,
        y: f64,
        z: f64,
        distance_m: f64,
        tolerance_m: f64,
    },
}

/// One of the four edges of the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GridEdge {
    /// η = 0: the root (torque tube / clamped edge).
    Root,
    /// η = 1.
    Tip,
    /// u = 0.
    LeadingEdge,
    /// u = 1.
    TrailingEdge,
}

/// A point located on the grid: its element, the element's nodes and bilinear weights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridPoint {
    /// Element index.
    pub element: usize,
    /// The element's nodes, in the order of `weights`.
    pub nodes: [usize; 4],
    /// Bilinear shape-function weights (sum to 1, all in [0, 1]).
    pub weights: [f64; 4],
    /// Distance in the mid-plane from the point to the planform (0 inside), m.
    pub distance_outside_m: f64,
}

/// Planform geometry behind the grid, as a parametric map (u, η) → (x, y), bilinear per cell.
#[derive(Debug, Clone, PartialEq)]
enum Shape {
    /// Trapezoid: x = −(le_s + η b tanΛ + u c(η)), y = sign (root_y + η b).
    Trapezoid {
        root_chord_m: f64,
        tip_chord_m: f64,
        span_m: f64,
        tan_sweep: f64,
        root_le_s_m: f64,
        root_y_m: f64,
        sign: f64,
    },
    /// Rectangle: x = −u chord, y = η span.
    Rectangle { chord_m: f64, span_m: f64 },
}

impl Shape {
    fn chord_and_le(&self, eta: f64) -> (f64, f64) {
        match *self {
            Shape::Trapezoid {
                root_chord_m,
                tip_chord_m,
                span_m,
                tan_sweep,
                root_le_s_m,
                ..
            } => (
                root_chord_m + (tip_chord_m - root_chord_m) * eta,
                root_le_s_m + eta * span_m * tan_sweep,
            ),
            Shape::Rectangle { chord_m, .. } => (chord_m, 0.0),
        }
    }

    /// (x, y) of parametric point (u, η), m.
    fn xy(&self, u: f64, eta: f64) -> (f64, f64) {
        let (c, le) = self.chord_and_le(eta);
        let y = match *self {
            Shape::Trapezoid {
                span_m,
                root_y_m,
                sign,
                ..
            } => sign * (root_y_m + eta * span_m),
            Shape::Rectangle { span_m, .. } => eta * span_m,
        };
        (-(le + u * c), y)
    }

    /// Unclamped (u, η) of a mid-plane point (x, y).
    fn parametric(&self, x: f64, y: f64) -> (f64, f64) {
        let eta = match *self {
            Shape::Trapezoid {
                span_m,
                root_y_m,
                sign,
                ..
            } => (sign * y - root_y_m) / span_m,
            Shape::Rectangle { span_m, .. } => y / span_m,
        };
        let (c, le) = self.chord_and_le(eta);
        ((-x - le) / c, eta)
    }
}

/// The structural grid of one lifting surface (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceGrid {
    /// Elements along the chord.
    pub elements_chordwise: usize,
    /// Elements along the span.
    pub elements_spanwise: usize,
    /// Chord fraction of each node column, 0 (leading edge) to 1 (trailing edge).
    pub chord_fractions: Vec<f64>,
    /// Span fraction of each node row, 0 (root) to 1 (tip).
    pub span_fractions: Vec<f64>,
    /// Mid-plane node positions, body axes, m.
    pub positions_m: Vec<Point3<f64>>,
    /// Section thickness at each node, m (zero at sharp edges).
    pub thickness_m: Vec<f64>,
    /// Element connectivity, counter-clockwise in the x-y plane.
    pub elements: Vec<[usize; 4]>,
    /// ∫ N_i dA: the planform area each node carries, m² (sums to the planform area).
    pub node_areas_m2: Vec<f64>,
    /// ∫ N_i t dA with t interpolated bilinearly: the volume each node carries, m³.
    pub node_volumes_m3: Vec<f64>,
    /// Nodes on the root edge: clamped to (or driven by) the torque tube.
    pub root_nodes: Vec<usize>,
    /// Root end of the torque tube (pivot axis parallel to y), m.
    pub pivot_m: Point3<f64>,
    /// Which side; the rectangular plate reports `Right` (y ≥ 0).
    pub side: Side,
    shape: Shape,
}

fn invalid(quantity: &str, value: f64, message: impl Into<String>) -> GridError {
    GridError::Invalid {
        quantity: quantity.to_owned(),
        value,
        message: message.into(),
    }
}

fn check_positive(quantity: &str, value: f64, max: f64) -> Result<(), GridError> {
    if value.is_finite() && value > 0.0 && value <= max {
        Ok(())
    } else {
        Err(invalid(
            quantity,
            value,
            format!("must be finite and in (0, {max}]"),
        ))
    }
}

fn check_count(quantity: &str, n: usize, min: usize) -> Result<(), GridError> {
    if (min..=2000).contains(&n) {
        Ok(())
    } else {
        Err(invalid(
            quantity,
            n as f64,
            format!("must be between {min} and 2000"),
        ))
    }
}

/// Chord fractions 0..1 with the ridge as a station: `n` elements split over the two wedges by
/// length (each wedge at least one element when n ≥ 2).
fn chord_fractions(n: usize, ridge: f64) -> Vec<f64> {
    if n < 2 {
        return vec![0.0, 1.0];
    }
    let front = ((n as f64 * ridge).round() as usize).clamp(1, n - 1);
    let back = n - front;
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..front {
        out.push(ridge * i as f64 / front as f64);
    }
    for i in 0..back {
        out.push(ridge + (1.0 - ridge) * i as f64 / back as f64);
    }
    out.push(1.0);
    out
}

/// Bilinear shape functions at natural coordinates (s, t) ∈ [-1, 1]², nodes
/// (−,−), (+,−), (+,+), (−,+).
fn bilinear(s: f64, t: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - s) * (1.0 - t),
        0.25 * (1.0 + s) * (1.0 - t),
        0.25 * (1.0 + s) * (1.0 + t),
        0.25 * (1.0 - s) * (1.0 + t),
    ]
}

impl SurfaceGrid {
    /// The grid of one lifting surface of `cfg` on `side`: `elements_chordwise` (≥ 2, so the
    /// ridge is a node line) by `elements_spanwise` (≥ 1) elements.
    pub fn lifting_surface(
        cfg: &LiftingSurfaceConfig,
        side: Side,
        elements_chordwise: usize,
        elements_spanwise: usize,
    ) -> Result<Self, GridError> {
        check_positive("lifting_surface.root_chord_m", cfg.root_chord_m, 1e4)?;
        check_positive("lifting_surface.tip_chord_m", cfg.tip_chord_m, 1e4)?;
        check_positive("lifting_surface.span_m", cfg.span_m, 1e4)?;
        check_positive(
            "lifting_surface.thickness_to_chord",
            cfg.thickness_to_chord,
            0.5,
        )?;
        let ridge = cfg.max_thickness_chord_fraction;
        if !(ridge.is_finite() && ridge > 0.0 && ridge < 1.0) {
            return Err(invalid(
                "lifting_surface.max_thickness_chord_fraction",
                ridge,
                "must be in (0, 1)",
            ));
        }
        let sweep = cfg.leading_edge_sweep_deg;
        if !(sweep.is_finite() && sweep.abs() <= 80.0) {
            return Err(invalid(
                "lifting_surface.leading_edge_sweep_deg",
                sweep,
                "must be in [-80, 80]",
            ));
        }
        for (q, v) in [
            (
                "lifting_surface.pivot_aft_of_nose_m",
                cfg.pivot_aft_of_nose_m,
            ),
            (
                "lifting_surface.pivot_root_chord_fraction",
                cfg.pivot_root_chord_fraction,
            ),
            ("lifting_surface.pivot_z_m", cfg.pivot_z_m),
            ("lifting_surface.root_y_m", cfg.root_y_m),
        ] {
            if !v.is_finite() {
                return Err(invalid(q, v, "must be finite"));
            }
        }
        check_count("elements_chordwise", elements_chordwise, 2)?;
        check_count("elements_spanwise", elements_spanwise, 1)?;
        let shape = Shape::Trapezoid {
            root_chord_m: cfg.root_chord_m,
            tip_chord_m: cfg.tip_chord_m,
            span_m: cfg.span_m,
            tan_sweep: sweep.to_radians().tan(),
            root_le_s_m: cfg.pivot_aft_of_nose_m - cfg.pivot_root_chord_fraction * cfg.root_chord_m,
            root_y_m: cfg.root_y_m,
            sign: side.sign(),
        };
        let us = chord_fractions(elements_chordwise, ridge);
        let tc = cfg.thickness_to_chord;
        let thickness = move |u: f64, c: f64| {
            let shape = if u <= ridge {
                u / ridge
            } else {
                (1.0 - u) / (1.0 - ridge)
            };
            tc * c * shape.max(0.0)
        };
        let pivot = crate::geometry::pivot_point(cfg, side);
        Ok(Self::build(
            shape,
            us,
            elements_spanwise,
            cfg.pivot_z_m,
            pivot,
            side,
            thickness,
        ))
    }

    /// A uniform rectangular plate (module docs): `chord_m` along −x, `span_m` along +y,
    /// thickness `thickness_m`, root edge (y = 0) the clamped set.
    pub fn rectangular(
        chord_m: f64,
        span_m: f64,
        thickness_m: f64,
        elements_chordwise: usize,
        elements_spanwise: usize,
    ) -> Result<Self, GridError> {
        check_positive("chord_m", chord_m, 1e4)?;
        check_positive("span_m", span_m, 1e4)?;
        check_positive("thickness_m", thickness_m, chord_m.min(span_m))?;
        check_count("elements_chordwise", elements_chordwise, 1)?;
        check_count("elements_spanwise", elements_spanwise, 1)?;
        let us = (0..=elements_chordwise)
            .map(|i| i as f64 / elements_chordwise as f64)
            .collect();
        Ok(Self::build(
            Shape::Rectangle { chord_m, span_m },
            us,
            elements_spanwise,
            0.0,
            Point3::origin(),
            Side::Right,
            move |_, _| thickness_m,
        ))
    }

    fn build(
        shape: Shape,
        us: Vec<f64>,
        elements_spanwise: usize,
        z_m: f64,
        pivot_m: Point3<f64>,
        side: Side,
        thickness: impl Fn(f64, f64) -> f64,
    ) -> Self {
        let nc = us.len();
        let etas: Vec<f64> = (0..=elements_spanwise)
            .map(|j| j as f64 / elements_spanwise as f64)
            .collect();
        let mut positions_m = Vec::with_capacity(nc * etas.len());
        let mut thickness_m = Vec::with_capacity(nc * etas.len());
        for &eta in &etas {
            let (c, _) = shape.chord_and_le(eta);
            for &u in &us {
                let (x, y) = shape.xy(u, eta);
                positions_m.push(Point3::new(x, y, z_m));
                thickness_m.push(thickness(u, c));
            }
        }
        let ec = nc - 1;
        let mut elements = Vec::with_capacity(ec * elements_spanwise);
        for j in 0..elements_spanwise {
            for i in 0..ec {
                let n = [
                    j * nc + i,
                    j * nc + i + 1,
                    (j + 1) * nc + i + 1,
                    (j + 1) * nc + i,
                ];
                let p = |k: usize| positions_m[n[k]];
                let twice_area =
                    (p(2).x - p(0).x) * (p(3).y - p(1).y) - (p(3).x - p(1).x) * (p(2).y - p(0).y);
                elements.push(if twice_area > 0.0 {
                    n
                } else {
                    [n[0], n[3], n[2], n[1]]
                });
            }
        }
        let root_nodes = (0..nc).collect();
        let mut grid = Self {
            elements_chordwise: ec,
            elements_spanwise,
            chord_fractions: us,
            span_fractions: etas,
            positions_m,
            thickness_m,
            elements,
            node_areas_m2: Vec::new(),
            node_volumes_m3: Vec::new(),
            root_nodes,
            pivot_m,
            side,
            shape,
        };
        grid.integrate_node_measures();
        grid
    }

    /// Node areas ∫ N_i dA and volumes ∫ N_i t dA by 2×2 Gauss quadrature (exact for the
    /// bilinear geometry).
    fn integrate_node_measures(&mut self) {
        let n = self.positions_m.len();
        let mut areas = vec![0.0; n];
        let mut volumes = vec![0.0; n];
        let g = 1.0 / 3f64.sqrt();
        for e in 0..self.elements.len() {
            let nodes = self.elements[e];
            for (s, t) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
                let w = bilinear(s, t);
                let det = self.jacobian_det(e, s, t);
                let thick: f64 = (0..4).map(|k| w[k] * self.thickness_m[nodes[k]]).sum();
                for k in 0..4 {
                    areas[nodes[k]] += w[k] * det;
                    volumes[nodes[k]] += w[k] * thick * det;
                }
            }
        }
        self.node_areas_m2 = areas;
        self.node_volumes_m3 = volumes;
    }

    /// det ∂(x, y)/∂(s, t) of element `e` at natural coordinates (s, t), m² (> 0: CCW).
    pub fn jacobian_det(&self, e: usize, s: f64, t: f64) -> f64 {
        let p = self.elements[e].map(|n| self.positions_m[n]);
        let ds = [-(1.0 - t), 1.0 - t, 1.0 + t, -(1.0 + t)];
        let dt = [-(1.0 - s), -(1.0 + s), 1.0 + s, 1.0 - s];
        let (mut xs, mut ys, mut xt, mut yt) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..4 {
            xs += 0.25 * ds[k] * p[k].x;
            ys += 0.25 * ds[k] * p[k].y;
            xt += 0.25 * dt[k] * p[k].x;
            yt += 0.25 * dt[k] * p[k].y;
        }
        xs * yt - xt * ys
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.positions_m.len()
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Nodes per chordwise line (`elements_chordwise + 1`).
    pub fn nodes_chordwise(&self) -> usize {
        self.elements_chordwise + 1
    }

    /// Nodes per spanwise line (`elements_spanwise + 1`).
    pub fn nodes_spanwise(&self) -> usize {
        self.elements_spanwise + 1
    }

    /// Index of node (i chordwise, j spanwise).
    pub fn node_index(&self, i: usize, j: usize) -> usize {
        j * self.nodes_chordwise() + i
    }

    /// Index of element (i chordwise, j spanwise).
    pub fn element_index(&self, i: usize, j: usize) -> usize {
        j * self.elements_chordwise + i
    }

    /// Nodes on `edge`, in order along it.
    pub fn edge_nodes(&self, edge: GridEdge) -> Vec<usize> {
        let (nc, ns) = (self.nodes_chordwise(), self.nodes_spanwise());
        match edge {
            GridEdge::Root => (0..nc).map(|i| self.node_index(i, 0)).collect(),
            GridEdge::Tip => (0..nc).map(|i| self.node_index(i, ns - 1)).collect(),
            GridEdge::LeadingEdge => (0..ns).map(|j| self.node_index(0, j)).collect(),
            GridEdge::TrailingEdge => (0..ns).map(|j| self.node_index(nc - 1, j)).collect(),
        }
    }

    /// Every node on the outer boundary (each once, ascending).
    pub fn boundary_nodes(&self) -> Vec<usize> {
        let mut all: Vec<usize> = [
            GridEdge::Root,
            GridEdge::Tip,
            GridEdge::LeadingEdge,
            GridEdge::TrailingEdge,
        ]
        .iter()
        .flat_map(|&e| self.edge_nodes(e))
        .collect();
        all.sort_unstable();
        all.dedup();
        all
    }

    /// Planform area, m².
    pub fn planform_area_m2(&self) -> f64 {
        self.node_areas_m2.iter().sum()
    }

    /// Area of element `e`, m².
    pub fn element_area_m2(&self, e: usize) -> f64 {
        let g = 1.0 / 3f64.sqrt();
        [(-g, -g), (g, -g), (g, g), (-g, g)]
            .iter()
            .map(|&(s, t)| self.jacobian_det(e, s, t))
            .sum()
    }

    /// Mid-plane z of the grid, m.
    pub fn mid_plane_z_m(&self) -> f64 {
        self.positions_m.first().map_or(0.0, |p| p.z)
    }

    /// Planform size used for mapping tolerances, m.
    fn size_m(&self) -> f64 {
        let (mut lo, mut hi) = (self.positions_m[0], self.positions_m[0]);
        for p in &self.positions_m {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (hi - lo).norm()
    }

    /// The grid element over `point` (projected along z onto the mid-plane) and its bilinear
    /// weights; points beyond the planform are clamped to its nearest edge (the distance is
    /// reported).
    pub fn locate(&self, point: &Point3<f64>) -> GridPoint {
        let (u, eta) = self.shape.parametric(point.x, point.y);
        let (uc, ec) = (u.clamp(0.0, 1.0), eta.clamp(0.0, 1.0));
        let (xc, yc) = self.shape.xy(uc, ec);
        let distance_outside_m = ((point.x - xc).powi(2) + (point.y - yc).powi(2)).sqrt();
        let cell = |stations: &[f64], v: f64| {
            let k = stations.partition_point(|&s| s <= v);
            k.clamp(1, stations.len() - 1) - 1
        };
        let i = cell(&self.chord_fractions, uc);
        let j = cell(&self.span_fractions, ec);
        let (u0, u1) = (self.chord_fractions[i], self.chord_fractions[i + 1]);
        let (e0, e1) = (self.span_fractions[j], self.span_fractions[j + 1]);
        // The map is bilinear in (u, η) per cell, so natural coordinates are linear in them.
        let s = (2.0 * (uc - u0) / (u1 - u0) - 1.0).clamp(-1.0, 1.0);
        let t = (2.0 * (ec - e0) / (e1 - e0) - 1.0).clamp(-1.0, 1.0);
        let nc = self.nodes_chordwise();
        GridPoint {
            element: self.element_index(i, j),
            nodes: [
                j * nc + i,
                j * nc + i + 1,
                (j + 1) * nc + i + 1,
                (j + 1) * nc + i,
            ],
            weights: bilinear(s, t),
            distance_outside_m,
        }
    }

    /// [`SurfaceGrid::locate`] for each point, failing on points farther than 1e-6 × the
    /// planform size outside it.
    pub fn map_points(
        &self,
        points: &[Point3<f64>],
        what: &'static str,
    ) -> Result<Vec<GridPoint>, GridError> {
        let tolerance_m = 1e-6 * self.size_m();
        points
            .iter()
            .enumerate()
            .map(|(index, p)| {
                let g = self.locate(p);
                if g.distance_outside_m.is_nan() || g.distance_outside_m > tolerance_m {
                    Err(GridError::OutsidePlanform {
                        what,
                        index,
                        x: p.x,
                        y: p.y,
                        z: p.z,
                        distance_m: g.distance_outside_m,
                        tolerance_m,
                    })
                } else {
                    Ok(g)
                }
            })
            .collect()
    }

    /// Grid location of every panel centroid of `mesh` (a lifting-surface mesh of the same
    /// side, undeformed): the pressure → nodal force and node → panel temperature map.
    pub fn map_panels(&self, mesh: &PanelMesh) -> Result<Vec<GridPoint>, GridError> {
        let centroids: Vec<Point3<f64>> = mesh.panels.iter().map(|p| p.centroid).collect();
        self.map_points(&centroids, "panel centroid")
    }

    /// Grid location of every vertex of `mesh` (for mode shapes on the mesh).
    pub fn map_vertices(&self, mesh: &PanelMesh) -> Result<Vec<GridPoint>, GridError> {
        self.map_points(&mesh.vertices, "vertex")
    }

    /// `out[k] = Σ w node_values[node]` over `map[k]` (node temperature → panel temperature).
    /// Lengths must agree (`out.len() == map.len()`, nodes within `node_values`).
    pub fn interpolate(map: &[GridPoint], node_values: &[f64], out: &mut [f64]) {
        for (o, g) in out.iter_mut().zip(map) {
            *o = (0..4).map(|k| g.weights[k] * node_values[g.nodes[k]]).sum();
        }
    }

    /// Node values of this grid resampled at the nodes of `target` (bilinear in each cell of this
    /// grid, clamped to its planform): a temperature field handed from one grid to another.
    pub fn resample(&self, node_values: &[f64], target: &SurfaceGrid) -> Vec<f64> {
        let map: Vec<GridPoint> = target.positions_m.iter().map(|p| self.locate(p)).collect();
        let mut out = vec![0.0; map.len()];
        Self::interpolate(&map, node_values, &mut out);
        out
    }

    /// Consistent nodal loads from point loads: `node_loads[n] += w f` for each located force
    /// (panel pressure force → grid node force). `node_loads` has one entry per node.
    pub fn scatter(map: &[GridPoint], values: &[f64], node_loads: &mut [f64]) {
        for (g, &v) in map.iter().zip(values) {
            for k in 0..4 {
                node_loads[g.nodes[k]] += g.weights[k] * v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::lifting_surface_mesh;
    use crate::mesh::RegionKind;
    use approx::assert_relative_eq;

    fn sample() -> LiftingSurfaceConfig {
        crate::config::LoadedConfig::sample()
            .expect("sample")
            .config
            .lifting_surface
    }

    #[test]
    fn trapezoid_grid_has_the_planform_area_volume_and_ridge_thickness() {
        let l = sample();
        for side in [Side::Left, Side::Right] {
            let g = SurfaceGrid::lifting_surface(&l, side, 10, 8).expect("grid");
            assert_eq!(g.n_nodes(), 11 * 9);
            assert_eq!(g.n_elements(), 80);
            // Planform area (c_r + c_t)/2 b; volume of the double wedge (t/c)/2 b (c_r² + c_r
            // c_t + c_t²)/3 (bilinear thickness is exact: t is linear in u and η per cell
            // except the c(η) u product, which is bilinear).
            let (cr, ct, b) = (l.root_chord_m, l.tip_chord_m, l.span_m);
            assert_relative_eq!(
                g.planform_area_m2(),
                0.5 * (cr + ct) * b,
                max_relative = 1e-12
            );
            let v = 0.5 * l.thickness_to_chord * b * (cr * cr + cr * ct + ct * ct) / 3.0;
            let vol: f64 = g.node_volumes_m3.iter().sum();
            assert_relative_eq!(vol, v, max_relative = 1e-10);
            // Ridge at mid-chord: root node 5 has t = (t/c) c_r.
            assert!(g.chord_fractions.contains(&0.5));
            assert_relative_eq!(
                g.thickness_m[5],
                l.thickness_to_chord * cr,
                max_relative = 1e-12
            );
            assert_eq!(g.thickness_m[0], 0.0);
            for e in 0..g.n_elements() {
                assert!(g.jacobian_det(e, 0.0, 0.0) > 0.0, "element {e} is CCW");
            }
            assert_eq!(g.root_nodes, g.edge_nodes(GridEdge::Root));
            for &n in &g.root_nodes {
                assert_relative_eq!(g.positions_m[n].y.abs(), l.root_y_m, epsilon = 1e-12);
                assert_relative_eq!(g.positions_m[n].z, l.pivot_z_m, epsilon = 1e-12);
            }
            assert_eq!(g.pivot_m, crate::geometry::pivot_point(&l, side));
        }
    }

    /// On this planform x(u, η) and y(η) are bilinear in the grid's parametric coordinates, so
    /// a field linear in x and y is bilinear there and resampling reproduces it exactly.
    #[test]
    fn resampling_reproduces_a_linear_field_exactly() {
        let l = sample();
        let coarse = SurfaceGrid::lifting_surface(&l, Side::Right, 16, 8).expect("grid");
        let fine = SurfaceGrid::lifting_surface(&l, Side::Right, 24, 18).expect("grid");
        let field = |p: &Point3<f64>| 400.0 + 30.0 * p.x - 20.0 * p.y;
        let values: Vec<f64> = coarse.positions_m.iter().map(field).collect();
        let resampled = coarse.resample(&values, &fine);
        assert_eq!(resampled.len(), fine.n_nodes());
        for (p, v) in fine.positions_m.iter().zip(&resampled) {
            assert_relative_eq!(*v, field(p), max_relative = 1e-10);
        }
    }

    #[test]
    fn every_aero_panel_and_vertex_maps_onto_the_grid_of_its_side() {
        let l = sample();
        for side in [Side::Left, Side::Right] {
            let mesh = lifting_surface_mesh(&l, side).expect("mesh");
            let g = SurfaceGrid::lifting_surface(&l, side, 12, 6).expect("grid");
            let panels = g.map_panels(&mesh).expect("panels");
            let verts = g.map_vertices(&mesh).expect("vertices");
            assert_eq!(panels.len(), mesh.panels.len());
            // Weights reproduce positions (bilinear interpolation of the grid's x, y).
            for (gp, v) in verts.iter().zip(&mesh.vertices) {
                let x: f64 = (0..4)
                    .map(|k| gp.weights[k] * g.positions_m[gp.nodes[k]].x)
                    .sum();
                let y: f64 = (0..4)
                    .map(|k| gp.weights[k] * g.positions_m[gp.nodes[k]].y)
                    .sum();
                assert_relative_eq!(x, v.x, epsilon = 1e-9);
                assert_relative_eq!(y, v.y, epsilon = 1e-9);
                assert_relative_eq!(gp.weights.iter().sum::<f64>(), 1.0, epsilon = 1e-12);
            }
            // Uniform node temperature → the same panel temperature; pressure loads scatter
            // with their total conserved.
            let t_nodes = vec![500.0; g.n_nodes()];
            let mut t_panels = vec![0.0; panels.len()];
            SurfaceGrid::interpolate(&panels, &t_nodes, &mut t_panels);
            assert!(t_panels.iter().all(|&t| (t - 500.0).abs() < 1e-9));
            let upper: Vec<usize> = mesh.panels_in_region(RegionKind::LiftingSurface).collect();
            let forces: Vec<f64> = upper.iter().map(|&p| mesh.panels[p].area_m2).collect();
            let sub: Vec<GridPoint> = upper.iter().map(|&p| panels[p]).collect();
            let mut nodal = vec![0.0; g.n_nodes()];
            SurfaceGrid::scatter(&sub, &forces, &mut nodal);
            assert_relative_eq!(
                nodal.iter().sum::<f64>(),
                forces.iter().sum::<f64>(),
                max_relative = 1e-12
            );
            // The other side's mesh does not fit.
            let other = lifting_surface_mesh(
                &l,
                if side == Side::Left {
                    Side::Right
                } else {
                    Side::Left
                },
            )
            .expect("mesh");
            let err = g.map_panels(&other).unwrap_err().to_string();
            assert!(err.contains("outside the planform"), "{err}");
        }
    }

    #[test]
    fn rectangular_plate_has_uniform_thickness_and_edges() {
        let g = SurfaceGrid::rectangular(2.0, 1.0, 0.01, 4, 2).expect("grid");
        assert_eq!(g.n_nodes(), 15);
        assert_relative_eq!(g.planform_area_m2(), 2.0, max_relative = 1e-12);
        assert!(g.thickness_m.iter().all(|&t| t == 0.01));
        assert_eq!(g.edge_nodes(GridEdge::Root), vec![0, 1, 2, 3, 4]);
        assert_eq!(g.edge_nodes(GridEdge::Tip), vec![10, 11, 12, 13, 14]);
        assert_eq!(g.edge_nodes(GridEdge::LeadingEdge), vec![0, 5, 10]);
        assert_eq!(g.boundary_nodes().len(), 12);
        // Corner node areas: a quarter element, 0.5 × 0.5 / 4.
        assert_relative_eq!(g.node_areas_m2[0], 0.0625, max_relative = 1e-12);
        let p = g.locate(&Point3::new(-0.25, 0.25, 0.0));
        assert_eq!(p.element, 0);
        assert!(p.weights.iter().all(|&w| (w - 0.25).abs() < 1e-12));
    }

    #[test]
    fn bad_dimensions_and_counts_are_errors_naming_the_quantity() {
        let err = SurfaceGrid::rectangular(-1.0, 1.0, 0.01, 4, 4)
            .unwrap_err()
            .to_string();
        assert!(err.contains("chord_m"), "{err}");
        let err = SurfaceGrid::rectangular(1.0, 1.0, 0.01, 0, 4)
            .unwrap_err()
            .to_string();
        assert!(err.contains("elements_chordwise"), "{err}");
        let err = SurfaceGrid::lifting_surface(&sample(), Side::Left, 1, 4)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("elements_chordwise") && err.contains("between 2"),
            "{err}"
        );
        let bad = LiftingSurfaceConfig {
            span_m: f64::NAN,
            ..sample()
        };
        let err = SurfaceGrid::lifting_surface(&bad, Side::Left, 4, 4)
            .unwrap_err()
            .to_string();
        assert!(err.contains("span_m"), "{err}");
    }
}
