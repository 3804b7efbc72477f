//! Polygon soup to closed panel mesh: weld, drop collapsed polygons, orient outward, build.

use nalgebra::{Point3, Vector3};

use crate::mesh::{PanelMesh, PanelSpec, RegionKind, Strip, Surface, weld_vertices};

use super::checks::VehicleError;

/// Splits `n` items over segments proportionally to `lengths` (largest remainder), ≥ 1 each.
pub(super) fn distribute(n: usize, lengths: &[f64]) -> Vec<usize> {
    let total: f64 = lengths.iter().sum();
    let n = n.max(lengths.len());
    let spare = n - lengths.len();
    let ideal: Vec<f64> = lengths.iter().map(|l| spare as f64 * l / total).collect();
    let mut counts: Vec<usize> = ideal.iter().map(|x| 1 + x.floor() as usize).collect();
    let mut left = n.saturating_sub(counts.iter().sum());
    let mut order: Vec<usize> = (0..lengths.len()).collect();
    order.sort_by(|&a, &b| (ideal[b] - ideal[b].floor()).total_cmp(&(ideal[a] - ideal[a].floor())));
    for &i in order.iter().cycle() {
        if left == 0 {
            break;
        }
        counts[i] += 1;
        left -= 1;
    }
    counts
}

/// a (1 - t) + b t, exact at t = 0 and t = 1.
pub(super) fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a * (1.0 - t) + b * t
}

/// Collects polygons over free points, then welds, drops collapsed polygons, orients each by
/// an outward hint and builds the mesh.
#[derive(Default)]
pub(super) struct Builder {
    points: Vec<Point3<f64>>,
    polys: Vec<([usize; 4], u16, Vector3<f64>)>,
    strips: Vec<Vec<usize>>,
    surfaces: Vec<Surface>,
}

impl Builder {
    pub(super) fn surface(&mut self, name: impl Into<String>, region: RegionKind) -> u16 {
        self.surfaces.push(Surface::new(name, region));
        // A handful of surfaces per mesh; cannot overflow.
        u16::try_from(self.surfaces.len() - 1).unwrap_or(u16::MAX)
    }

    /// Quads over `nodes[i][j]` (i streamwise, j across); with `strips`, one strip per j with
    /// panels in increasing i.
    pub(super) fn grid(
        &mut self,
        nodes: &[Vec<Point3<f64>>],
        surface_of: impl Fn(usize) -> u16,
        outward: Vector3<f64>,
        strips: bool,
    ) {
        let ni = nodes.len().saturating_sub(1);
        let nj = nodes.first().map_or(0, |r| r.len().saturating_sub(1));
        let base = self.points.len();
        for row in nodes {
            self.points.extend_from_slice(row);
        }
        let id = |i: usize, j: usize| base + i * (nj + 1) + j;
        let first_poly = self.polys.len();
        for j in 0..nj {
            for i in 0..ni {
                self.polys.push((
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
                    surface_of(i),
                    outward,
                ));
            }
        }
        if strips {
            for j in 0..nj {
                self.strips
                    .push((0..ni).map(|i| first_poly + j * ni + i).collect());
            }
        }
    }

    pub(super) fn finish(self, what: &'static str) -> Result<PanelMesh, VehicleError> {
        let (lo, hi) = crate::mesh::bounding_box_of(&self.points);
        let size = (hi - lo).norm();
        let (welded, map) = weld_vertices(&self.points, 1e-9 * size);
        let min_twice_area = 2.0 * (1e-10 * size).powi(2);
        let mut new_index = vec![None; self.polys.len()];
        let mut specs = Vec::with_capacity(self.polys.len());
        for (k, (raw, surface, outward)) in self.polys.iter().enumerate() {
            // Map to welded vertices and drop repeats (cyclically).
            let mut v: Vec<usize> = Vec::with_capacity(4);
            for &r in raw {
                let w = map[r];
                if v.last() != Some(&w) {
                    v.push(w);
                }
            }
            while v.len() > 1 && v.first() == v.last() {
                v.pop();
            }
            if v.len() < 3 {
                continue;
            }
            let p = |i: usize| welded[v[i]];
            let cross = if v.len() == 4 {
                (p(2) - p(0)).cross(&(p(3) - p(1)))
            } else {
                (p(1) - p(0)).cross(&(p(2) - p(0)))
            };
            if cross.norm() <= min_twice_area {
                continue;
            }
            if cross.dot(outward) < 0.0 {
                v.reverse();
            }
            new_index[k] = Some(specs.len());
            specs.push(if v.len() == 4 {
                PanelSpec::quad(v[0], v[1], v[2], v[3], *surface)
            } else {
                PanelSpec::triangle(v[0], v[1], v[2], *surface)
            });
        }
        let strips = self
            .strips
            .iter()
            .map(|s| Strip {
                panels: s.iter().filter_map(|&k| new_index[k]).collect(),
            })
            .filter(|s| !s.panels.is_empty())
            .collect();
        PanelMesh::new(welded, &specs, strips, self.surfaces)
            .map_err(|source| VehicleError::Mesh { what, source })
    }
}
