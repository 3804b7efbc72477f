//! The conduction grid: a plate (mid-plane quads with a thickness per node) extruded through
//! its thickness into trilinear hexahedra, layer by layer, with each element's geometric
//! conduction matrix, each node's lumped volume, and the map from wetted panels to face nodes.
//!
//! **Through the thickness.** At every plate node the stack runs from the lower outer face to
//! the upper outer face along the node normal ("up" = the side facing −z, body axes): the outer
//! layers in reverse order (outermost first in the settings), the structure (the plate's own
//! thickness, at least `minimum_thickness_m`), then the outer layers again, outermost last.
//! Each layer is split into equal sub-layers; the levels between them carry the degrees of
//! freedom, numbered `plate_node * n_levels + level` (level 0 on the lower face).
//!
//! **Elements.** Trilinear 8-node hexahedra: geometric conduction matrix
//! G_ab = ∫ ∇N_a · ∇N_b dV and lumped volume V_a = ∫ N_a dV by 2×2×2 Gauss quadrature (Hughes,
//! The Finite Element Method, 1987, §3.5 and §7.3.2; row-sum lumping is positive for the
//! trilinear brick). The conductance of an element is k(T) G; the heat capacity of a node
//! is Σ_materials ρ c_p(T) V.

use nalgebra::{Matrix3, Point3, Vector3};

use hsv_core::surface_grid::SurfaceGrid;

use hsv_core::linalg::reverse_cuthill_mckee;

/// One layer of the through-thickness stack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    /// Thickness, m; `None` for the structure, whose thickness is the plate's.
    pub thickness_m: Option<f64>,
    /// Index into the model's material list.
    pub material: usize,
    /// Number of element layers through it (≥ 1).
    pub sublayers: usize,
}

/// One trilinear hexahedron.
#[derive(Debug, Clone, PartialEq)]
pub struct Hexahedron {
    /// Degrees of freedom of the 8 corners: the lower quad's 4 then the upper quad's 4.
    pub dofs: [usize; 8],
    pub material: usize,
    /// Geometric conduction matrix G (row-major 8×8, symmetric), m.
    pub conduction_m: [f64; 64],
}

/// Why a conduction grid could not be built.
#[derive(Debug, Clone, PartialEq)]
pub enum GridError {
    /// The plate has no quads, a bad index, a mismatched thickness list or a non-finite value.
    BadPlate(String),
    /// An element with zero or inverted volume.
    Degenerate { quad: usize, segment: usize },
}

impl std::fmt::Display for GridError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GridError::BadPlate(message) => write!(f, "{message}"),
            GridError::Degenerate { quad, segment } => write!(
                f,
                "element of quad {quad}, through-thickness segment {segment} has no volume"
            ),
        }
    }
}

/// The extruded grid.
#[derive(Debug, Clone, PartialEq)]
pub struct ThermalGrid {
    pub n_plate_nodes: usize,
    pub n_levels: usize,
    pub n_materials: usize,
    /// Position of every degree of freedom, m.
    pub positions_m: Vec<Point3<f64>>,
    pub elements: Vec<Hexahedron>,
    /// Lumped volume of each dof per material: `[dof * n_materials + material]`, m³.
    pub volume_m3: Vec<f64>,
    /// Banded-solver position of each dof (reverse Cuthill-McKee over the plate nodes).
    pub band_index: Vec<usize>,
    /// Half-bandwidth of the conduction matrix in band order.
    pub bandwidth: usize,
    /// Lowest and highest level of the structure.
    pub structure_levels: (usize, usize),
    /// Unit normal at each plate node, pointing to the upper face.
    pub up: Vec<Vector3<f64>>,
}

/// Corners of the reference brick in the order of [`Hexahedron::dofs`].
const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Reference derivatives of the 8 trilinear shape functions at (ξ, η, ζ), and their values.
fn shape(xi: f64, eta: f64, zeta: f64) -> ([f64; 8], [[f64; 3]; 8]) {
    let mut n = [0.0; 8];
    let mut d = [[0.0; 3]; 8];
    for (a, c) in CORNERS.iter().enumerate() {
        let (fx, fy, fz) = (1.0 + xi * c[0], 1.0 + eta * c[1], 1.0 + zeta * c[2]);
        n[a] = 0.125 * fx * fy * fz;
        d[a] = [
            0.125 * c[0] * fy * fz,
            0.125 * fx * c[1] * fz,
            0.125 * fx * fy * c[2],
        ];
    }
    (n, d)
}

/// G_ab = ∫ ∇N_a·∇N_b dV and V_a = ∫ N_a dV of a brick, 2×2×2 Gauss; `None` if degenerate.
fn brick_matrices(x: &[Point3<f64>; 8]) -> Option<([f64; 64], [f64; 8])> {
    let g = 1.0 / 3f64.sqrt();
    let mut conduction = [0.0; 64];
    let mut volume = [0.0; 8];
    for &xi in &[-g, g] {
        for &eta in &[-g, g] {
            for &zeta in &[-g, g] {
                let (n, d) = shape(xi, eta, zeta);
                // J_ij = ∂x_i/∂ξ_j.
                let mut j = Matrix3::<f64>::zeros();
                for a in 0..8 {
                    for i in 0..3 {
                        for k in 0..3 {
                            j[(i, k)] += x[a][i] * d[a][k];
                        }
                    }
                }
                let det = j.determinant();
                if !(det.abs() > 0.0 && det.is_finite()) {
                    return None;
                }
                let inv_t = j.try_inverse()?.transpose();
                let grads: Vec<Vector3<f64>> = d
                    .iter()
                    .map(|da| inv_t * Vector3::new(da[0], da[1], da[2]))
                    .collect();
                let w = det.abs();
                for a in 0..8 {
                    volume[a] += n[a] * w;
                    for b in 0..8 {
                        conduction[a * 8 + b] += grads[a].dot(&grads[b]) * w;
                    }
                }
            }
        }
    }
    Some((conduction, volume))
}

/// Unit normal of a quad from its diagonals, turned to face −z (the upper side).
fn quad_up(p: &[Point3<f64>], q: &[usize; 4]) -> Vector3<f64> {
    let n = (p[q[2]] - p[q[0]]).cross(&(p[q[3]] - p[q[1]]));
    let n = if n.z > 0.0 { -n } else { n };
    n.try_normalize(0.0).unwrap_or_else(|| -Vector3::z())
}

fn check_plate(plate: &SurfaceGrid) -> Result<(), GridError> {
    let n = plate.positions_m.len();
    if plate.elements.is_empty() {
        return Err(GridError::BadPlate("the plate has no quads".to_owned()));
    }
    if plate.thickness_m.len() != n {
        return Err(GridError::BadPlate(format!(
            "{} thicknesses for {n} plate nodes",
            plate.thickness_m.len()
        )));
    }
    if let Some((i, t)) = plate
        .thickness_m
        .iter()
        .enumerate()
        .find(|(_, t)| !(t.is_finite() && **t >= 0.0))
    {
        return Err(GridError::BadPlate(format!(
            "thickness of plate node {i} is {t} m (must be finite and >= 0)"
        )));
    }
    if let Some(i) = plate
        .positions_m
        .iter()
        .position(|p| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
    {
        return Err(GridError::BadPlate(format!(
            "plate node {i} has a non-finite position"
        )));
    }
    for (e, q) in plate.elements.iter().enumerate() {
        if let Some(&bad) = q.iter().find(|&&v| v >= n) {
            return Err(GridError::BadPlate(format!(
                "quad {e} refers to node {bad}, but the plate has {n} nodes"
            )));
        }
    }
    Ok(())
}

impl ThermalGrid {
    /// Extrudes `plate` through `layers` (lower face first, structure in the middle) with the
    /// structure at least `minimum_thickness_m` thick.
    pub fn new(
        plate: &SurfaceGrid,
        layers: &[Layer],
        n_materials: usize,
        minimum_thickness_m: f64,
    ) -> Result<Self, GridError> {
        check_plate(plate)?;
        let n = plate.positions_m.len();
        // Node normals: average of the adjacent quads' upward normals.
        let mut up = vec![Vector3::zeros(); n];
        for q in &plate.elements {
            let nq = quad_up(&plate.positions_m, q);
            for &v in q {
                up[v] += nq;
            }
        }
        for u in &mut up {
            *u = u.try_normalize(0.0).unwrap_or_else(|| -Vector3::z());
        }
        // Segment list (layer index of each element layer) and the structure's level range.
        let mut segments = Vec::new();
        let mut structure_levels = (0, 0);
        for (l, layer) in layers.iter().enumerate() {
            if layer.thickness_m.is_none() {
                structure_levels.0 = segments.len();
                structure_levels.1 = segments.len() + layer.sublayers;
            }
            segments.extend(std::iter::repeat_n(l, layer.sublayers));
        }
        let n_levels = segments.len() + 1;
        // Level offsets along the normal at each node, from the lower face.
        let mut positions_m = vec![Point3::origin(); n * n_levels];
        for v in 0..n {
            let h = plate.thickness_m[v].max(minimum_thickness_m);
            let total: f64 = layers.iter().map(|l| l.thickness_m.unwrap_or(h)).sum();
            let mut s = -0.5 * total;
            positions_m[v * n_levels] = plate.positions_m[v] + up[v] * s;
            for (k, &l) in segments.iter().enumerate() {
                let layer = &layers[l];
                s += layer.thickness_m.unwrap_or(h) / layer.sublayers as f64;
                positions_m[v * n_levels + k + 1] = plate.positions_m[v] + up[v] * s;
            }
        }
        // Band order from the plate-node graph.
        let mut adjacency = vec![Vec::new(); n];
        for q in &plate.elements {
            for &a in q {
                for &b in q {
                    if a != b {
                        adjacency[a].push(b);
                    }
                }
            }
        }
        for list in &mut adjacency {
            list.sort_unstable();
            list.dedup();
        }
        let order = reverse_cuthill_mckee(&adjacency);
        let mut node_position = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            node_position[old] = new;
        }
        let band_index: Vec<usize> = (0..n * n_levels)
            .map(|dof| node_position[dof / n_levels] * n_levels + dof % n_levels)
            .collect();
        let mut elements = Vec::with_capacity(plate.elements.len() * segments.len());
        let mut volume_m3 = vec![0.0; n * n_levels * n_materials];
        let mut bandwidth = 0;
        for (e, q) in plate.elements.iter().enumerate() {
            for (k, &l) in segments.iter().enumerate() {
                let mut dofs = [0; 8];
                for c in 0..4 {
                    dofs[c] = q[c] * n_levels + k;
                    dofs[c + 4] = q[c] * n_levels + k + 1;
                }
                let corners = dofs.map(|d| positions_m[d]);
                let (conduction_m, volume) =
                    brick_matrices(&corners).ok_or(GridError::Degenerate {
                        quad: e,
                        segment: k,
                    })?;
                let material = layers[l].material;
                for (a, &d) in dofs.iter().enumerate() {
                    volume_m3[d * n_materials + material] += volume[a];
                }
                let lo = dofs.iter().map(|&d| band_index[d]).min().unwrap_or(0);
                let hi = dofs.iter().map(|&d| band_index[d]).max().unwrap_or(0);
                bandwidth = bandwidth.max(hi - lo);
                elements.push(Hexahedron {
                    dofs,
                    material,
                    conduction_m,
                });
            }
        }
        Ok(Self {
            n_plate_nodes: n,
            n_levels,
            n_materials,
            positions_m,
            elements,
            volume_m3,
            band_index,
            bandwidth,
            structure_levels,
            up,
        })
    }

    pub fn n_dofs(&self) -> usize {
        self.n_plate_nodes * self.n_levels
    }

    /// Dof of `plate_node` at `level`.
    pub fn dof(&self, plate_node: usize, level: usize) -> usize {
        plate_node * self.n_levels + level
    }

    /// Share of a uniform flux on the grid's side face at `plate_node` taken by each level:
    /// w_k = ∫ N_k ds / H = (s_{k+1} − s_{k−1}) / 2H along the node's stack (the consistent
    /// load of linear elements, Hughes §3.5); (level, weight), summing to 1.
    pub fn side_face_weights(&self, plate_node: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let at = move |level: usize| self.positions_m[self.dof(plate_node, level)];
        let top = self.n_levels - 1;
        let gap = move |level: usize| (at(level + 1) - at(level)).norm();
        let height: f64 = (0..top).map(gap).sum();
        (0..=top).map(move |level| {
            let below = if level > 0 { gap(level - 1) } else { 0.0 };
            let above = if level < top { gap(level) } else { 0.0 };
            (level, 0.5 * (below + above) / height)
        })
    }

    /// Weights over the structure's levels whose sum is the thickness average (trapezoid rule
    /// over its equal sub-layers): (level, weight).
    pub fn structure_average_weights(&self) -> Vec<(usize, f64)> {
        let (lo, hi) = self.structure_levels;
        let n = (hi - lo) as f64;
        (lo..=hi)
            .map(|l| {
                let w = if l == lo || l == hi { 0.5 / n } else { 1.0 / n };
                (l, w)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn unit_square(thickness: f64) -> SurfaceGrid {
        SurfaceGrid::rectangular(1.0, 2.0, thickness, 1, 1).unwrap()
    }

    #[test]
    fn brick_volumes_and_conduction_are_exact_for_a_box() {
        let layers = [Layer {
            thickness_m: None,
            material: 0,
            sublayers: 1,
        }];
        let grid = ThermalGrid::new(&unit_square(0.1), &layers, 1, 0.0).unwrap();
        let total: f64 = grid.volume_m3.iter().sum();
        assert_relative_eq!(total, 0.2, max_relative = 1e-12);
        // T = s (distance along the normal) has unit gradient: G T gives the face fluxes
        // ±∫N dA = ±A/4 = ±0.5 m² per face node of the 2 m² box.
        let e = &grid.elements[0];
        let t: Vec<f64> = e
            .dofs
            .iter()
            .map(|&d| grid.positions_m[d].coords.dot(&grid.up[0]))
            .collect();
        for a in 0..8 {
            let flux: f64 = (0..8).map(|b| e.conduction_m[a * 8 + b] * t[b]).sum();
            let expected = if a < 4 { -0.5 } else { 0.5 };
            assert_relative_eq!(flux, expected, epsilon = 1e-12);
        }
    }
}
