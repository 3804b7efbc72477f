//! The conduction grid: a plate (mid-plane quads with a thickness per node) extruded through
//! its thickness into trilinear hexahedra, layer by layer, with each element's geometric
//! conduction matrix, each node's lumped volume, and the map from wetted panels to face nodes (one
//! file: the element integration is private to the grid that assembles it, and the tests check both
//! on the same small stacks).
//!
//! **Through the thickness.** At every plate node the stack runs from the lower outer face to
//! the upper outer face along the node normal ("up" = the side facing −z, body axes): the outer
//! layers in reverse order (outermost first in the settings), the plate's own thickness, then
//! the outer layers again, outermost last. The plate's thickness is either one solid structural
//! layer (at least `minimum_thickness_m`) or, built up, a lower skin, an interior (the plate's
//! thickness less the two skins, at least `minimum_thickness_m`) and an upper skin: the one
//! layer without a fixed thickness fills what the plate's thickness leaves. The structure is
//! then a set of level ranges ([`ThermalGrid::structure_ranges`]), one or two.
//! Each layer is split into equal sub-layers; the levels between them carry the degrees of
//! freedom, numbered `plate_node * n_levels + level` (level 0 on the lower face).
//!
//! **Elements.** Trilinear 8-node hexahedra: geometric conduction matrix
//! G_ab = ∫ ∇N_a · ∇N_b dV by the [`Quadrature`] chosen, and lumped volume V_a = ∫ N_a dV by
//! 2×2×2 Gauss quadrature (Hughes, The Finite Element Method, 1987, §3.5 and §7.3.2; row-sum
//! lumping is positive for the trilinear brick). The conductance of an element is k(T) G; the
//! heat capacity of a node is Σ_materials ρ c_p(T) V.
//!
//! **Thin elements and the maximum principle.** Ciarlet & Raviart ("Maximum principle and
//! uniform convergence for the finite element method", Comput. Methods Appl. Mech. Eng. 2,
//! 1973) show that a finite-element matrix keeps the discrete maximum principle when its
//! off-diagonal entries are ≤ 0 and its rows sum to ≥ 0. With the lumped (diagonal) capacity,
//! the backward-Euler matrix C/Δt + K is then a diagonally dominant M-matrix, whose inverse is
//! non-negative: with no heat taken out, no temperature falls below its initial minimum. The
//! consistent (Gauss) G of a brick of in-plane size a and thickness h ≪ a carries
//! the through-thickness term ∫ N_a,z N_b,z dV ≈ (1/h) ∫ N_a N_b dA between nodes of one face,
//! which is positive and of order a²/h, far above the negative in-plane term of order h: the
//! off-diagonal is positive, and heating one face makes its unheated neighbours undershoot.
//! Nodal (2-point Gauss-Lobatto, corner) quadrature drops the in-plane "mass" ∫ N_a N_b dA to
//! its diagonal, so for a rectangular brick only the 12 edge neighbours couple, each by
//! −A/L ≤ 0 (A a quarter of the face across the edge, L the edge): the 7-point finite-volume
//! stencil, an M-matrix. Its rows still sum to zero (Σ_b ∇N_b = 0 at every point), so energy
//! is conserved exactly as with Gauss.

use nalgebra::{Matrix3, Point3, Vector3};

use hsv_core::surface_grid::SurfaceGrid;

use hsv_core::linalg::reverse_cuthill_mckee;

/// Quadrature of the conduction matrix G_ab = ∫ ∇N_a·∇N_b dV (module docs); 8 points of
/// weight 1 in natural coordinates either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Quadrature {
    /// 2×2×2 Gauss, points at ±1/√3: the consistent Galerkin matrix, exact for the brick.
    Gauss,
    /// 2-point Gauss-Lobatto, points at the 8 corners: the finite-volume stencil for a
    /// rectangular brick, non-positive off-diagonals at any aspect ratio.
    Nodal,
}

impl Quadrature {
    /// Natural coordinate of the points along each axis (±).
    fn abscissa(self) -> f64 {
        match self {
            Quadrature::Gauss => 1.0 / 3f64.sqrt(),
            Quadrature::Nodal => 1.0,
        }
    }
}

/// What a layer of the stack is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LayerKind {
    /// Outside the plate's thickness (a thermal-protection layer).
    Outer,
    /// Structure: the whole solid plate, or one skin of a built-up one.
    Structure,
    /// The non-structural interior between the skins of a built-up plate.
    Interior,
}

/// One layer of the through-thickness stack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    /// Thickness, m; `None` for the one layer within the plate that fills the plate's thickness
    /// less the fixed layers within it (the solid structure, or a built-up plate's interior),
    /// at least the grid's minimum thickness.
    pub thickness_m: Option<f64>,
    /// Outer, structural or interior.
    pub kind: LayerKind,
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
    /// A stack with no structure, more than one filling layer, an outer filling layer, a bad
    /// thickness or no sub-layers.
    BadStack(String),
    /// An element with zero or inverted volume.
    Degenerate { quad: usize, segment: usize },
}

impl std::fmt::Display for GridError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GridError::BadPlate(message) | GridError::BadStack(message) => write!(f, "{message}"),
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
    /// Lowest and highest level of each structural layer, lower face first: one range for a
    /// solid structure, the lower and upper skin for a built-up one.
    pub structure_ranges: Vec<(usize, usize)>,
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

/// Jacobian determinant and physical shape-function gradients ∇N_a = J⁻ᵀ ∇_ξ N_a at one point;
/// `None` where the map is degenerate.
fn gradients(x: &[Point3<f64>; 8], d: &[[f64; 3]; 8]) -> Option<(f64, [Vector3<f64>; 8])> {
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
    let grads = d.map(|da| inv_t * Vector3::new(da[0], da[1], da[2]));
    Some((det.abs(), grads))
}

/// Σ over the 8 points (±p, ±p, ±p), weight 1, of `f(N, ∇N, |J|)`; `None` if degenerate.
fn integrate(
    x: &[Point3<f64>; 8],
    quadrature: Quadrature,
    mut f: impl FnMut(&[f64; 8], &[Vector3<f64>; 8], f64),
) -> Option<()> {
    let p = quadrature.abscissa();
    for &xi in &[-p, p] {
        for &eta in &[-p, p] {
            for &zeta in &[-p, p] {
                let (n, d) = shape(xi, eta, zeta);
                let (w, grads) = gradients(x, &d)?;
                f(&n, &grads, w);
            }
        }
    }
    Some(())
}

/// G_ab = Σ_points ∇N_a·∇N_b |J| (`quadrature`) and V_a = ∫ N_a dV (2×2×2 Gauss) of a brick;
/// `None` if degenerate.
fn brick_matrices(x: &[Point3<f64>; 8], quadrature: Quadrature) -> Option<([f64; 64], [f64; 8])> {
    let mut conduction = [0.0; 64];
    let mut volume = [0.0; 8];
    let add_conduction = |conduction: &mut [f64; 64], grads: &[Vector3<f64>; 8], w: f64| {
        for a in 0..8 {
            for b in 0..8 {
                conduction[a * 8 + b] += grads[a].dot(&grads[b]) * w;
            }
        }
    };
    integrate(x, Quadrature::Gauss, |n, grads, w| {
        for a in 0..8 {
            volume[a] += n[a] * w;
        }
        if quadrature == Quadrature::Gauss {
            add_conduction(&mut conduction, grads, w);
        }
    })?;
    if quadrature == Quadrature::Nodal {
        integrate(x, Quadrature::Nodal, |_, grads, w| {
            add_conduction(&mut conduction, grads, w)
        })?;
    }
    Some((conduction, volume))
}

/// Unit normal of a quad from its diagonals, turned to face −z (the upper side).
fn quad_up(p: &[Point3<f64>], q: &[usize; 4]) -> Vector3<f64> {
    let n = (p[q[2]] - p[q[0]]).cross(&(p[q[3]] - p[q[1]]));
    let n = if n.z > 0.0 { -n } else { n };
    n.try_normalize(0.0).unwrap_or_else(|| -Vector3::z())
}

/// A stack the grid can build: at least one structural layer, at most one filling layer and
/// that one within the plate, fixed thicknesses finite and > 0, every layer ≥ 1 sub-layer.
fn check_stack(layers: &[Layer]) -> Result<(), GridError> {
    let bad = |m: String| Err(GridError::BadStack(m));
    if !layers.iter().any(|l| l.kind == LayerKind::Structure) {
        return bad("the through-thickness stack has no structural layer".to_owned());
    }
    let filling: Vec<usize> = (layers.iter().enumerate())
        .filter(|(_, l)| l.thickness_m.is_none())
        .map(|(i, _)| i)
        .collect();
    if filling.len() > 1 {
        return bad(format!(
            "layers {filling:?} all take the plate's thickness; at most one may"
        ));
    }
    for (i, layer) in layers.iter().enumerate() {
        if layer.thickness_m.is_none() && layer.kind == LayerKind::Outer {
            return bad(format!(
                "outer layer {i} has no thickness; only a layer within the plate fills it"
            ));
        }
        if let Some(t) = layer.thickness_m
            && !(t.is_finite() && t > 0.0)
        {
            return bad(format!("layer {i} is {t} m thick (must be finite and > 0)"));
        }
        if layer.sublayers == 0 {
            return bad(format!("layer {i} has no sub-layers (must have >= 1)"));
        }
    }
    Ok(())
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
    /// Extrudes `plate` through `layers` (lower face first, the plate's own layers in the
    /// middle) with the filling layer (the solid structure or the interior) at least
    /// `minimum_thickness_m` thick, its conduction matrices by `quadrature`.
    pub fn new(
        plate: &SurfaceGrid,
        layers: &[Layer],
        n_materials: usize,
        minimum_thickness_m: f64,
        quadrature: Quadrature,
    ) -> Result<Self, GridError> {
        check_plate(plate)?;
        check_stack(layers)?;
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
        // Segment list (layer index of each element layer) and the structure's level ranges.
        let mut segments = Vec::new();
        let mut structure_ranges = Vec::new();
        for (l, layer) in layers.iter().enumerate() {
            if layer.kind == LayerKind::Structure {
                structure_ranges.push((segments.len(), segments.len() + layer.sublayers));
            }
            segments.extend(std::iter::repeat_n(l, layer.sublayers));
        }
        let n_levels = segments.len() + 1;
        // The fixed layers within the plate's thickness (a built-up plate's skins).
        let fixed_within: f64 = (layers.iter())
            .filter(|l| l.kind != LayerKind::Outer)
            .filter_map(|l| l.thickness_m)
            .sum();
        // Level offsets along the normal at each node, from the lower face.
        let mut positions_m = vec![Point3::origin(); n * n_levels];
        for v in 0..n {
            // The filling layer's thickness (solid: the plate's, as fixed_within is 0).
            let h = (plate.thickness_m[v] - fixed_within).max(minimum_thickness_m);
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
                    brick_matrices(&corners, quadrature).ok_or(GridError::Degenerate {
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
            structure_ranges,
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

    /// Weights over the structure's levels whose sum is its mean temperature: the trapezoid
    /// average over each structural layer's equal sub-layers, the layers weighted equally (the
    /// two skins of a built-up plate have one thickness): (level, weight), summing to 1.
    pub fn structure_average_weights(&self) -> Vec<(usize, f64)> {
        let share = 1.0 / self.structure_ranges.len() as f64;
        (self.structure_ranges.iter())
            .flat_map(|&range| layer_average_weights(range).map(move |(l, w)| (l, w * share)))
            .collect()
    }

    /// Weights over the structure's levels whose sum is its through-thickness difference ΔT,
    /// lower minus upper: solid, T at its lowest level minus T at its highest (the faces, for a
    /// temperature linear through the thickness); built up, the lower skin's mean temperature
    /// minus the upper skin's (trapezoid averages), what the thermal moment of two skins,
    /// M_T = E α ΔT t_s d/2, takes. (level, weight), summing to 0.
    pub fn structure_difference_weights(&self) -> Vec<(usize, f64)> {
        match self.structure_ranges.as_slice() {
            [] => Vec::new(),
            [(lo, hi)] => vec![(*lo, 1.0), (*hi, -1.0)],
            [lower, .., upper] => layer_average_weights(*lower)
                .chain(layer_average_weights(*upper).map(|(l, w)| (l, -w)))
                .collect(),
        }
    }
}

/// Trapezoid-rule weights of the levels `lo..=hi` of one layer's equal sub-layers, summing to 1.
fn layer_average_weights((lo, hi): (usize, usize)) -> impl Iterator<Item = (usize, f64)> {
    let n = (hi - lo) as f64;
    (lo..=hi).map(move |l| {
        let w = if l == lo || l == hi { 0.5 / n } else { 1.0 / n };
        (l, w)
    })
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
            kind: LayerKind::Structure,
            material: 0,
            sublayers: 1,
        }];
        let grid = ThermalGrid::new(&unit_square(0.1), &layers, 1, 0.0, Quadrature::Gauss).unwrap();
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

    fn layer(
        thickness_m: Option<f64>,
        kind: LayerKind,
        material: usize,
        sublayers: usize,
    ) -> Layer {
        Layer {
            thickness_m,
            kind,
            material,
            sublayers,
        }
    }

    /// Outer layer 1 mm, skins 2 mm (2 sub-layers), interior filling: on a 20 mm plate the
    /// interior is 16 mm, the faces stay at ±11 mm (the plate ± the outer layers), the skins are
    /// the level ranges (1, 3) and (4, 6); where the plate is thinner than the skins and the
    /// minimum interior, the interior keeps the minimum.
    #[test]
    fn a_built_up_stack_puts_the_skins_inside_the_plate_thickness() {
        let outer = layer(Some(0.001), LayerKind::Outer, 1, 1);
        let skin = layer(Some(0.002), LayerKind::Structure, 0, 2);
        let interior = layer(None, LayerKind::Interior, 2, 1);
        let stack = [outer, skin, interior, skin, outer];
        let grid =
            ThermalGrid::new(&unit_square(0.02), &stack, 3, 1e-3, Quadrature::Gauss).unwrap();
        assert_eq!(grid.n_levels, 8);
        assert_eq!(grid.structure_ranges, vec![(1, 3), (4, 6)]);
        let s = |level: usize| grid.positions_m[grid.dof(0, level)].coords.dot(&grid.up[0]);
        let expected = [-0.011, -0.010, -0.009, -0.008, 0.008, 0.009, 0.010, 0.011];
        for (level, e) in expected.iter().enumerate() {
            assert_relative_eq!(s(level), *e, epsilon = 1e-15);
        }
        // Interior volume: 16 mm over the 2 m² plate, all of it material 2.
        let air: f64 = (0..grid.n_dofs()).map(|d| grid.volume_m3[d * 3 + 2]).sum();
        assert_relative_eq!(air, 0.016 * 2.0, max_relative = 1e-12);
        // Averages: each skin's trapezoid rule, the skins weighted equally.
        let avg = grid.structure_average_weights();
        let expected_avg = [
            (1, 0.125),
            (2, 0.25),
            (3, 0.125),
            (4, 0.125),
            (5, 0.25),
            (6, 0.125),
        ];
        assert_eq!(avg.len(), expected_avg.len());
        for ((l, w), (el, ew)) in avg.iter().zip(expected_avg) {
            assert_eq!(*l, el);
            assert_relative_eq!(*w, ew, epsilon = 1e-15);
        }
        let diff = grid.structure_difference_weights();
        let total: f64 = diff.iter().map(|(_, w)| w).sum();
        assert_relative_eq!(total, 0.0, epsilon = 1e-15);
        assert_eq!(diff[0], (1, 0.25));
        assert_eq!(diff[3], (4, -0.25));
        // A plate thinner than two skins plus the minimum interior: the interior keeps 1 mm.
        let thin =
            ThermalGrid::new(&unit_square(0.003), &stack, 3, 1e-3, Quadrature::Gauss).unwrap();
        let s = |level: usize| thin.positions_m[thin.dof(0, level)].coords.dot(&thin.up[0]);
        assert_relative_eq!(s(4) - s(3), 1e-3, epsilon = 1e-15);
    }

    /// Solid: one structural range, the difference between its end levels.
    #[test]
    fn a_solid_structure_differences_its_end_levels() {
        let stack = [layer(None, LayerKind::Structure, 0, 4)];
        let grid =
            ThermalGrid::new(&unit_square(0.01), &stack, 1, 1e-3, Quadrature::Gauss).unwrap();
        assert_eq!(grid.structure_ranges, vec![(0, 4)]);
        assert_eq!(
            grid.structure_difference_weights(),
            vec![(0, 1.0), (4, -1.0)]
        );
        let sum: f64 = grid.structure_average_weights().iter().map(|p| p.1).sum();
        assert_relative_eq!(sum, 1.0, epsilon = 1e-15);
    }

    #[test]
    fn bad_stacks_are_errors() {
        let plate = unit_square(0.01);
        let structure = layer(None, LayerKind::Structure, 0, 1);
        let cases: [(&[Layer], &str); 4] = [
            (
                &[layer(Some(0.01), LayerKind::Outer, 0, 1)],
                "no structural layer",
            ),
            (
                &[structure, layer(None, LayerKind::Interior, 0, 1)],
                "at most one",
            ),
            (
                &[
                    layer(None, LayerKind::Outer, 0, 1),
                    layer(Some(0.01), LayerKind::Structure, 0, 1),
                ],
                "outer layer 0",
            ),
            (
                &[layer(Some(0.001), LayerKind::Structure, 0, 0)],
                "no sub-layers",
            ),
        ];
        for (stack, message) in cases {
            let err = ThermalGrid::new(&plate, stack, 1, 1e-3, Quadrature::Gauss)
                .unwrap_err()
                .to_string();
            assert!(err.contains(message), "{err}");
        }
    }

    /// A rectangular brick 0.25 m × 0.5 m × 1.25 mm (aspect ratio 200, a thin skin sub-layer):
    /// nodal quadrature gives exactly the 7-point finite-volume conductances, −A/L between edge
    /// neighbours (A a quarter of the face across the edge, L the edge) and 0 between face- and
    /// body-diagonal ones (1e-12 relative to the largest entry), with zero row sums; the
    /// consistent Gauss matrix of the same brick has positive off-diagonals (module docs).
    #[test]
    // Index loops mirror the matrix entries they check.
    #[allow(clippy::needless_range_loop)]
    fn nodal_quadrature_of_a_thin_brick_is_the_finite_volume_stencil() {
        let layers = [layer(None, LayerKind::Structure, 0, 1)];
        let plate = SurfaceGrid::rectangular(0.25, 0.5, 0.00125, 1, 1).unwrap();
        let nodal = ThermalGrid::new(&plate, &layers, 1, 0.0, Quadrature::Nodal).unwrap();
        let gauss = ThermalGrid::new(&plate, &layers, 1, 0.0, Quadrature::Gauss).unwrap();
        assert_eq!(nodal.volume_m3, gauss.volume_m3);
        let e = &nodal.elements[0];
        let x = e.dofs.map(|d| nodal.positions_m[d]);
        // Box edges along the three axes, from corner 0.
        let lengths = [
            (x[1] - x[0]).norm(),
            (x[3] - x[0]).norm(),
            (x[4] - x[0]).norm(),
        ];
        let scale = e.conduction_m.iter().fold(0.0_f64, |m, g| m.max(g.abs()));
        let mut edges = 0;
        for a in 0..8 {
            let row: f64 = (0..8).map(|b| e.conduction_m[a * 8 + b]).sum();
            assert!(row.abs() < 1e-12 * scale, "row {a} sums to {row}");
            for b in (0..8).filter(|&b| b != a) {
                let g = e.conduction_m[a * 8 + b];
                assert!(g <= 1e-12 * scale, "G[{a}][{b}] = {g} > 0");
                let differ: Vec<usize> =
                    (0..3).filter(|&i| CORNERS[a][i] != CORNERS[b][i]).collect();
                if let [axis] = differ.as_slice() {
                    let others: f64 = (0..3).filter(|i| i != axis).map(|i| lengths[i]).product();
                    let finite_volume = -0.25 * others / lengths[*axis];
                    assert_relative_eq!(g, finite_volume, max_relative = 1e-12);
                    edges += 1;
                } else {
                    assert!(g.abs() < 1e-12 * scale, "G[{a}][{b}] = {g}");
                }
            }
        }
        assert_eq!(edges, 24);
        let most_positive = (0..64)
            .filter(|i| i / 8 != i % 8)
            .map(|i| gauss.elements[0].conduction_m[i])
            .fold(f64::NEG_INFINITY, f64::max);
        println!("largest Gauss off-diagonal {most_positive:.4e} m (nodal: none > 0)");
        assert!(most_positive > 0.0);
    }
}
