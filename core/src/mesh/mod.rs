//! Panel meshes of the outer mold line: vertices, triangle/quad panels with their geometry,
//! streamwise strips, named surfaces tagged by region, and modal deformation of the mesh.
//!
//! Conventions: coordinates in body axes (x forward, y right, z down), metres. Panel vertices are
//! counter-clockwise seen from outside, so the right-hand-rule normal points out of the body
//! (into the flow). A quad may be non-planar: its normal is the unit cross product of its
//! diagonals and its area half the magnitude of that product (exact for planar quads).

use std::collections::HashMap;

use nalgebra::{DMatrix, DVector, Point3, Vector3};

mod modes;
mod weld;

pub use modes::ModeShapes;
pub use weld::weld_vertices;
use weld::{FastMap, fast_map};

/// Which region of the vehicle owns a surface (and therefore which model loads it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RegionKind {
    MainBody,
    LiftingSurface,
    Propulsion,
    Other,
}

/// A named part of a mesh, e.g. "upper-forebody" (main body) or "inlet-ramp" (propulsion).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Surface {
    pub name: String,
    pub region: RegionKind,
}

impl Surface {
    /// A surface named `name` in `region`.
    pub fn new(name: impl Into<String>, region: RegionKind) -> Self {
        Self {
            name: name.into(),
            region,
        }
    }
}

/// One panel: a triangle or a (possibly non-planar) quad, with its current geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// Indices into [`PanelMesh::vertices`], counter-clockwise seen from outside. For triangles
    /// the fourth entry repeats the third.
    pub vertices: [usize; 4],
    /// 3 (triangle) or 4 (quad).
    pub vertex_count: u8,
    /// Area centroid, m.
    pub centroid: Point3<f64>,
    /// Outward unit normal.
    pub normal: Vector3<f64>,
    /// Area, m².
    pub area_m2: f64,
    /// Index into [`PanelMesh::surfaces`].
    pub surface: u16,
}

impl Panel {
    /// The panel's vertex indices (3 or 4 of them).
    pub fn vertex_indices(&self) -> &[usize] {
        &self.vertices[..usize::from(self.vertex_count.clamp(3, 4))]
    }
}

/// Panel indices ordered upstream (leading edge / nose) to downstream.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Strip {
    pub panels: Vec<usize>,
}

/// Connectivity of one panel for [`PanelMesh::new`]: vertex indices, counter-clockwise seen from
/// outside, and the surface it belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PanelSpec {
    /// For triangles the fourth entry is ignored.
    pub vertices: [usize; 4],
    /// 3 or 4.
    pub vertex_count: u8,
    pub surface: u16,
}

impl PanelSpec {
    /// A triangle (a, b, c).
    pub fn triangle(a: usize, b: usize, c: usize, surface: u16) -> Self {
        Self {
            vertices: [a, b, c, c],
            vertex_count: 3,
            surface,
        }
    }

    /// A quad (a, b, c, d).
    pub fn quad(a: usize, b: usize, c: usize, d: usize, surface: u16) -> Self {
        Self {
            vertices: [a, b, c, d],
            vertex_count: 4,
            surface,
        }
    }
}

/// Why a mesh could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    #[error("mesh has no panels")]
    Empty,
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFiniteVertex {
        vertex: usize,
        x: f64,
        y: f64,
        z: f64,
    },
    #[error("panel {panel} has {count} vertices; panels have 3 or 4")]
    BadVertexCount { panel: usize, count: u8 },
    #[error("panel {panel} refers to vertex {vertex}, but the mesh has {n_vertices} vertices")]
    BadVertexIndex {
        panel: usize,
        vertex: usize,
        n_vertices: usize,
    },
    #[error("panel {panel} refers to surface {surface}, but the mesh has {n_surfaces} surfaces")]
    BadSurfaceIndex {
        panel: usize,
        surface: u16,
        n_surfaces: usize,
    },
    #[error("panel {panel} is degenerate (area {area_m2:e} m²)")]
    DegeneratePanel { panel: usize, area_m2: f64 },
    #[error("strip {strip} refers to panel {panel}, but the mesh has {n_panels} panels")]
    BadStripPanel {
        strip: usize,
        panel: usize,
        n_panels: usize,
    },
    #[error("strip {strip} is empty")]
    EmptyStrip { strip: usize },
    #[error("too many surfaces ({count}); at most {max}", max = u16::MAX)]
    TooManySurfaces { count: usize },
    #[error(
        "mode shapes have {rows} rows, but the mesh has {n_vertices} vertices (needs 3 x {n_vertices})"
    )]
    ModeShapeSize { rows: usize, n_vertices: usize },
}

/// How a mesh closes up as the surface of a solid ([`PanelMesh::closure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closure {
    /// Edges used by one panel only (holes, open ends).
    pub boundary_edges: usize,
    /// Edges shared by more than two panels (non-manifold).
    pub overshared_edges: usize,
    /// Edges whose two panels traverse them in the same direction (normals on opposite sides).
    pub misoriented_edges: usize,
    /// Signed enclosed volume, m³: positive when the normals point out of the solid.
    pub enclosed_volume_m3: f64,
}

impl Closure {
    /// Every edge shared by exactly two panels (watertight, manifold).
    pub fn is_closed(&self) -> bool {
        self.boundary_edges == 0 && self.overshared_edges == 0
    }

    /// Closed, consistently oriented, and the normals point outward (positive volume).
    pub fn is_closed_outward(&self) -> bool {
        self.is_closed() && self.misoriented_edges == 0 && self.enclosed_volume_m3 > 0.0
    }

    /// Closed and consistently oriented with every normal pointing into the solid.
    pub fn is_closed_inward(&self) -> bool {
        self.is_closed() && self.misoriented_edges == 0 && self.enclosed_volume_m3 < 0.0
    }

    /// What is wrong with the mesh as a solid's surface, e.g. "12 open edges"; empty if nothing.
    pub fn problems(&self) -> Vec<String> {
        let mut problems = Vec::new();
        if self.boundary_edges > 0 {
            problems.push(format!(
                "{} open edges (used by one facet only)",
                self.boundary_edges
            ));
        }
        if self.overshared_edges > 0 {
            problems.push(format!(
                "{} edges shared by more than two facets",
                self.overshared_edges
            ));
        }
        if self.misoriented_edges > 0 {
            problems.push(format!(
                "{} edges where neighbouring facets face opposite ways",
                self.misoriented_edges
            ));
        }
        if problems.is_empty() && self.enclosed_volume_m3 == 0.0 {
            problems.push("zero enclosed volume".to_owned());
        }
        problems
    }
}

/// A panel mesh: shared vertices, panels, optional streamwise strips and named surfaces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PanelMesh {
    /// m, body axes.
    pub vertices: Vec<Point3<f64>>,
    pub panels: Vec<Panel>,
    /// Empty for unstructured meshes (e.g. from STL).
    pub strips: Vec<Strip>,
    pub surfaces: Vec<Surface>,
}

/// Centroid, normal and area of the polygon `idx` over `vertices`.
///
/// Normal n = d1 × d2 / |d1 × d2| with diagonals d1 = v2 - v0, d2 = v3 - v1 (v3 = v2 for a
/// triangle), area |d1 × d2| / 2; centroid: area-weighted centroid of the two triangles on
/// either diagonal, averaged over both diagonals. Reference: Hess & Smith, "Calculation of potential flow about arbitrary bodies",
/// Prog. Aerospace Sci. 8 (1967) (quadrilateral element normal from the diagonals).
fn panel_geometry(
    vertices: &[Point3<f64>],
    idx: &[usize; 4],
    count: u8,
) -> (Point3<f64>, Vector3<f64>, f64) {
    let v0 = vertices[idx[0]];
    let v1 = vertices[idx[1]];
    let v2 = vertices[idx[2]];
    let v3 = if count == 4 { vertices[idx[3]] } else { v2 };
    let cross = (v2 - v0).cross(&(v3 - v1));
    let twice_area = cross.norm();
    let normal = if twice_area > 0.0 {
        cross * twice_area.recip()
    } else {
        Vector3::zeros()
    };
    // Area-weighted centroid of the split along one diagonal, averaged with the split along the
    // other: exact for planar panels, symmetric for warped ones. The triangle centroids' 1/3
    // and the weights' sum share one reciprocal (one division per split instead of nine).
    let split = |a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>, d: &Point3<f64>| {
        let w1 = (b - a).cross(&(c - a)).norm();
        let w2 = (c - a).cross(&(d - a)).norm();
        let s1 = a.coords + b.coords + c.coords;
        let s2 = a.coords + c.coords + d.coords;
        (w1 + w2 > 0.0).then(|| (s1 * w1 + s2 * w2) * (3.0 * (w1 + w2)).recip())
    };
    let centroid = match (split(&v0, &v1, &v2, &v3), split(&v1, &v2, &v3, &v0)) {
        (Some(a), Some(b)) => Point3::from((a + b) / 2.0),
        _ => Point3::from((v0.coords + v1.coords + v2.coords + v3.coords) / 4.0),
    };
    (centroid, normal, 0.5 * twice_area)
}

impl PanelMesh {
    /// Builds a mesh from vertices and panel connectivity, computes every panel's geometry and
    /// validates indices, strips and panel areas.
    pub fn new(
        vertices: Vec<Point3<f64>>,
        panels: &[PanelSpec],
        strips: Vec<Strip>,
        surfaces: Vec<Surface>,
    ) -> Result<Self, MeshError> {
        if panels.is_empty() {
            return Err(MeshError::Empty);
        }
        if surfaces.len() > usize::from(u16::MAX) {
            return Err(MeshError::TooManySurfaces {
                count: surfaces.len(),
            });
        }
        for (i, v) in vertices.iter().enumerate() {
            if !(v.x.is_finite() && v.y.is_finite() && v.z.is_finite()) {
                return Err(MeshError::NonFiniteVertex {
                    vertex: i,
                    x: v.x,
                    y: v.y,
                    z: v.z,
                });
            }
        }
        let (lo, hi) = bounding_box_of(&vertices);
        let size = (hi - lo).norm();
        // Areas below this are round-off, not geometry.
        let min_area = (size * 1e-10).powi(2);
        let mut out = Vec::with_capacity(panels.len());
        for (p, spec) in panels.iter().enumerate() {
            if spec.vertex_count != 3 && spec.vertex_count != 4 {
                return Err(MeshError::BadVertexCount {
                    panel: p,
                    count: spec.vertex_count,
                });
            }
            let mut idx = spec.vertices;
            if spec.vertex_count == 3 {
                idx[3] = idx[2];
            }
            for &v in &idx[..usize::from(spec.vertex_count)] {
                if v >= vertices.len() {
                    return Err(MeshError::BadVertexIndex {
                        panel: p,
                        vertex: v,
                        n_vertices: vertices.len(),
                    });
                }
            }
            if usize::from(spec.surface) >= surfaces.len() {
                return Err(MeshError::BadSurfaceIndex {
                    panel: p,
                    surface: spec.surface,
                    n_surfaces: surfaces.len(),
                });
            }
            let (centroid, normal, area_m2) = panel_geometry(&vertices, &idx, spec.vertex_count);
            if area_m2 <= min_area || normal == Vector3::zeros() {
                return Err(MeshError::DegeneratePanel { panel: p, area_m2 });
            }
            out.push(Panel {
                vertices: idx,
                vertex_count: spec.vertex_count,
                centroid,
                normal,
                area_m2,
                surface: spec.surface,
            });
        }
        for (s, strip) in strips.iter().enumerate() {
            if strip.panels.is_empty() {
                return Err(MeshError::EmptyStrip { strip: s });
            }
            if let Some(&bad) = strip.panels.iter().find(|&&p| p >= out.len()) {
                return Err(MeshError::BadStripPanel {
                    strip: s,
                    panel: bad,
                    n_panels: out.len(),
                });
            }
        }
        Ok(Self {
            vertices,
            panels: out,
            strips,
            surfaces,
        })
    }

    /// An unstructured mesh of triangles on one surface (no strips).
    pub fn from_triangles(
        vertices: Vec<Point3<f64>>,
        triangles: &[[usize; 3]],
        surface: Surface,
    ) -> Result<Self, MeshError> {
        let specs: Vec<PanelSpec> = triangles
            .iter()
            .map(|t| PanelSpec::triangle(t[0], t[1], t[2], 0))
            .collect();
        Self::new(vertices, &specs, Vec::new(), vec![surface])
    }

    /// Recomputes every panel's centroid, normal and area from the current vertices (after
    /// deformation). Allocates nothing. A panel that collapsed keeps its previous normal and
    /// gets zero area.
    pub fn update_geometry(&mut self) {
        let vertices = &self.vertices;
        for panel in &mut self.panels {
            let (centroid, normal, area) =
                panel_geometry(vertices, &panel.vertices, panel.vertex_count);
            panel.centroid = centroid;
            panel.area_m2 = area;
            if normal != Vector3::zeros() {
                panel.normal = normal;
            }
        }
    }

    /// True when the mesh has streamwise strips.
    pub fn is_structured(&self) -> bool {
        !self.strips.is_empty()
    }

    /// Sum of the panel areas, m².
    pub fn total_area_m2(&self) -> f64 {
        self.panels.iter().map(|p| p.area_m2).sum()
    }

    /// Enclosed volume by the divergence theorem, V = Σ v0 · (v1 × v2) / 6 over the triangles
    /// (0,1,2), (0,2,3) of each panel, m³. Positive for a closed mesh with outward normals.
    /// Reference: Zhang & Chen, "Efficient feature extraction for 2D/3D objects in mesh
    /// representation", ICIP 2001 (signed tetrahedron volumes).
    pub fn enclosed_volume_m3(&self) -> f64 {
        let mut six_v = 0.0;
        for p in &self.panels {
            let v = |k: usize| self.vertices[p.vertices[k]].coords;
            six_v += v(0).dot(&v(1).cross(&v(2)));
            if p.vertex_count == 4 {
                six_v += v(0).dot(&v(2).cross(&v(3)));
            }
        }
        six_v / 6.0
    }

    /// Directed edges of every panel, counted by undirected edge: (uses a->b with a<b, uses b->a).
    fn edge_uses(&self) -> FastMap<(usize, usize), (u32, u32)> {
        let mut edges: FastMap<(usize, usize), (u32, u32)> = fast_map(self.panels.len() * 2);
        for p in &self.panels {
            let idx = p.vertex_indices();
            for k in 0..idx.len() {
                let (a, b) = (idx[k], idx[(k + 1) % idx.len()]);
                let entry = edges.entry((a.min(b), a.max(b))).or_default();
                if a < b {
                    entry.0 += 1;
                } else {
                    entry.1 += 1;
                }
            }
        }
        edges
    }

    /// True when every edge is shared by exactly two panels (vertex-welded, watertight).
    pub fn is_closed(&self) -> bool {
        !self.panels.is_empty() && self.edge_uses().values().all(|&(f, b)| f + b == 2)
    }

    /// True when every edge shared by two panels is traversed once in each direction, so all
    /// normals point to the same side.
    pub fn is_consistently_oriented(&self) -> bool {
        self.edge_uses().values().all(|&(f, b)| f <= 1 && b <= 1)
    }

    /// How the panels close up as the surface of a solid: open and over-shared edges, edges
    /// two panels traverse the same way, and the signed enclosed volume (positive outward).
    pub fn closure(&self) -> Closure {
        let mut closure = Closure {
            boundary_edges: 0,
            overshared_edges: 0,
            misoriented_edges: 0,
            enclosed_volume_m3: self.enclosed_volume_m3(),
        };
        for &(forward, backward) in self.edge_uses().values() {
            match forward + backward {
                1 => closure.boundary_edges += 1,
                2 if forward != 1 => closure.misoriented_edges += 1,
                2 => {}
                _ => closure.overshared_edges += 1,
            }
        }
        closure
    }

    /// Turns every panel inside out: reverses its vertex order and recomputes its geometry
    /// (same area and centroid, opposite normal).
    pub fn reverse_orientation(&mut self) {
        for panel in &mut self.panels {
            let [a, b, c, d] = panel.vertices;
            panel.vertices = if panel.vertex_count == 4 {
                [a, d, c, b]
            } else {
                [a, c, b, b]
            };
            panel.normal = -panel.normal;
        }
        self.update_geometry();
    }

    /// Appends `other`, offsetting its vertex, panel and surface indices.
    pub fn merge(&mut self, other: &PanelMesh) {
        let v_off = self.vertices.len();
        let p_off = self.panels.len();
        // Surface indices are u16; PanelMesh::new caps the count, merging two capped meshes
        // could exceed it, so saturate rather than wrap.
        let s_off = u16::try_from(self.surfaces.len()).unwrap_or(u16::MAX);
        self.vertices.extend_from_slice(&other.vertices);
        self.surfaces.extend(other.surfaces.iter().cloned());
        self.panels.extend(other.panels.iter().map(|p| {
            let mut q = *p;
            for v in &mut q.vertices {
                *v += v_off;
            }
            q.surface = q.surface.saturating_add(s_off);
            q
        }));
        self.strips.extend(other.strips.iter().map(|s| Strip {
            panels: s.panels.iter().map(|&p| p + p_off).collect(),
        }));
    }

    /// Indices of the panels whose surface belongs to `region`.
    pub fn panels_in_region(&self, region: RegionKind) -> impl Iterator<Item = usize> + '_ {
        self.panels.iter().enumerate().filter_map(move |(i, p)| {
            (self.surfaces.get(usize::from(p.surface)).map(|s| s.region) == Some(region))
                .then_some(i)
        })
    }

    /// Index of the surface called `name`.
    pub fn surface_index(&self, name: &str) -> Option<u16> {
        self.surfaces
            .iter()
            .position(|s| s.name == name)
            .and_then(|i| u16::try_from(i).ok())
    }

    /// Indices of the panels on surface `surface`.
    pub fn panels_in_surface(&self, surface: u16) -> impl Iterator<Item = usize> + '_ {
        self.panels
            .iter()
            .enumerate()
            .filter_map(move |(i, p)| (p.surface == surface).then_some(i))
    }

    /// Running length of every panel from the leading edge of its strip, m: panel i of a strip
    /// gets Σ_{j<i} L_j + L_i / 2, with L_j = A_j / w_j the panel's mean length along the strip
    /// and w_j its width across it (flat-plate boundary-layer length for heating); panels in no
    /// strip get `default_m`. `flow_direction` orients one-panel strips. `out` is resized.
    pub fn strip_running_lengths_m(
        &self,
        flow_direction: &Vector3<f64>,
        default_m: f64,
        out: &mut Vec<f64>,
    ) {
        out.clear();
        out.resize(self.panels.len(), default_m);
        for strip in &self.strips {
            let panels = &strip.panels;
            let mut upstream = 0.0;
            for (k, &p) in panels.iter().enumerate() {
                let along = if panels.len() > 1 {
                    let prev = panels[k.saturating_sub(1)];
                    let next = panels[(k + 1).min(panels.len() - 1)];
                    self.panels[next].centroid - self.panels[prev].centroid
                } else {
                    *flow_direction
                };
                let length = self.panel_length_along_m(p, &along);
                out[p] = upstream + 0.5 * length;
                upstream += length;
            }
        }
    }

    /// Mean length of panel `p` along `along`: L = A / w, w = the panel's extent across `along`
    /// in its own plane; √A when `along` is normal to the panel.
    pub fn panel_length_along_m(&self, p: usize, along: &Vector3<f64>) -> f64 {
        let panel = &self.panels[p];
        let across = panel.normal.cross(along);
        // |n × along| <= ε max(|along|, 1), compared squared (one root fewer per panel).
        let norm2 = across.norm_squared();
        if norm2 <= f64::EPSILON * f64::EPSILON * along.norm_squared().max(1.0) {
            return panel.area_m2.sqrt();
        }
        // The extent along the unnormalized `across`, divided by its length once.
        let (lo, hi) = panel
            .vertex_indices()
            .iter()
            .map(|&v| self.vertices[v].coords.dot(&across))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s), hi.max(s))
            });
        let width = (hi - lo) / norm2.sqrt();
        if width > 0.0 {
            panel.area_m2 / width
        } else {
            panel.area_m2.sqrt()
        }
    }

    /// Axis-aligned bounding box (min, max) of the vertices, m; the origin twice when empty.
    pub fn bounding_box(&self) -> (Point3<f64>, Point3<f64>) {
        bounding_box_of(&self.vertices)
    }
}

/// Axis-aligned bounding box of `points`; the origin twice when empty.
pub fn bounding_box_of(points: &[Point3<f64>]) -> (Point3<f64>, Point3<f64>) {
    let Some(first) = points.first() else {
        return (Point3::origin(), Point3::origin());
    };
    points.iter().fold((*first, *first), |(lo, hi), p| {
        (
            Point3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)),
            Point3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)),
        )
    })
}
