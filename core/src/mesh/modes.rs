//! Modal deformation of a mesh: mode shapes as vertex displacement columns, the displaced
//! vertices and the panels' velocities from modal coordinates and their rates.

use super::*;

/// Modal displacement field on a mesh: column k holds the displacement (x,y,z interleaved per
/// vertex, m per unit modal coordinate) of mode k.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeShapes {
    /// 3 n_vertices x n_modes.
    pub vertex_displacement: DMatrix<f64>,
}

impl ModeShapes {
    /// Number of modes (columns).
    pub fn n_modes(&self) -> usize {
        self.vertex_displacement.ncols()
    }

    /// Checks that the shapes fit `mesh` (3 rows per vertex); call once at assembly.
    pub fn check(&self, mesh: &PanelMesh) -> Result<(), MeshError> {
        if self.vertex_displacement.nrows() != 3 * mesh.vertices.len() {
            return Err(MeshError::ModeShapeSize {
                rows: self.vertex_displacement.nrows(),
                n_vertices: mesh.vertices.len(),
            });
        }
        Ok(())
    }

    /// Deformed mesh: vertices = base + Φ q, then `update_geometry`, m.
    ///
    /// Allocates nothing once `out` has `base`'s topology (the first call copies `base` into
    /// `out` when it does not). Sizes must agree ([`ModeShapes::check`]); extra rows, modes or
    /// coordinates are ignored.
    pub fn deform(&self, base: &PanelMesh, modal_coordinates: &DVector<f64>, out: &mut PanelMesh) {
        debug_assert_eq!(self.vertex_displacement.nrows(), 3 * base.vertices.len());
        debug_assert_eq!(modal_coordinates.len(), self.n_modes());
        if out.vertices.len() != base.vertices.len() || out.panels.len() != base.panels.len() {
            out.clone_from(base);
        }
        self.displace_vertices(&base.vertices, modal_coordinates, &mut out.vertices);
        out.update_geometry();
    }

    /// Displaced vertices base + Φ q into `out` (one per base vertex), without the panel
    /// geometry: for a caller that moves them further (an elevon rotation) before computing it
    /// once. Allocates nothing; extra rows, modes or coordinates are ignored.
    pub fn displace_vertices(
        &self,
        base: &[Point3<f64>],
        modal_coordinates: &DVector<f64>,
        out: &mut [Point3<f64>],
    ) {
        debug_assert_eq!(out.len(), base.len());
        out.copy_from_slice(base);
        let n_modes = self.n_modes().min(modal_coordinates.len());
        // Each mode column read three rows (one vertex) at a time.
        for (col, &q) in self
            .mode_columns()
            .zip(modal_coordinates.iter())
            .take(n_modes)
        {
            if q == 0.0 {
                continue;
            }
            for (v, d) in out.iter_mut().zip(col.chunks_exact(3)) {
                v.x += d[0] * q;
                v.y += d[1] * q;
                v.z += d[2] * q;
            }
        }
    }

    /// Mode `mode`'s displacement at a panel: the mean of its vertices' displacement, m per unit
    /// modal coordinate (the panel rule of generalized forces and panel velocities). Shapes must
    /// fit the mesh ([`ModeShapes::check`]).
    pub fn panel_displacement(&self, panel: &Panel, mode: usize) -> Vector3<f64> {
        let n_rows = self.vertex_displacement.nrows();
        let data = self.vertex_displacement.as_slice();
        vertex_mean(&data[mode * n_rows..(mode + 1) * n_rows], panel)
    }

    /// [`ModeShapes::displace_vertices`] and [`ModeShapes::panel_velocities`] in one pass down
    /// each mode column (the shapes are read once instead of twice: a lifting surface's Ritz
    /// vectors are read at every Runge-Kutta stage). Same sums in the same order as the two.
    pub fn displace_with_velocities(
        &self,
        mesh: &PanelMesh,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        vertices_out: &mut [Point3<f64>],
        velocities_out: &mut [Vector3<f64>],
    ) {
        debug_assert_eq!(vertices_out.len(), mesh.vertices.len());
        debug_assert_eq!(velocities_out.len(), mesh.panels.len());
        vertices_out.copy_from_slice(&mesh.vertices);
        let n_modes = self
            .n_modes()
            .min(modal_coordinates.len())
            .min(modal_velocities.len());
        self.with_vertex_scratch(|vertex_velocity| {
            for ((column, &q), &q_dot) in self
                .mode_columns()
                .zip(modal_coordinates.iter())
                .zip(modal_velocities.iter())
                .take(n_modes)
            {
                // Two branch-free sweeps (they vectorize) instead of one that tests q and q̇
                // at every vertex; each entry gets the same sum in the same order.
                if q != 0.0 {
                    for (v, d) in vertices_out.iter_mut().zip(column.chunks_exact(3)) {
                        v.x += d[0] * q;
                        v.y += d[1] * q;
                        v.z += d[2] * q;
                    }
                }
                if q_dot != 0.0 {
                    for (w, d) in vertex_velocity.iter_mut().zip(column) {
                        *w += d * q_dot;
                    }
                }
            }
            panel_means(mesh, vertex_velocity, velocities_out);
        });
    }

    /// Mode k's vertex displacements (x, y, z interleaved): column-major storage makes each the
    /// contiguous slice [k n_rows, (k+1) n_rows).
    fn mode_columns(&self) -> std::slice::ChunksExact<'_, f64> {
        let n_rows = self.vertex_displacement.nrows();
        self.vertex_displacement
            .as_slice()
            .chunks_exact(n_rows.max(1))
    }

    /// Runs `f` on this thread's vertex buffer, zeroed to one entry per row of the shapes.
    fn with_vertex_scratch(&self, f: impl FnOnce(&mut [f64])) {
        VERTEX_SCRATCH.with_borrow_mut(|buffer| {
            buffer.clear();
            buffer.resize(self.vertex_displacement.nrows(), 0.0);
            f(buffer)
        });
    }

    /// Velocity of each panel centroid from modal velocities (mean of its vertices' Φ q̇), m/s,
    /// written into `out` (len = panels).
    ///
    /// The vertex velocities Φ q̇ come first (one pass down each contiguous mode column), then
    /// each panel averages its 3-4 vertices: every vertex is shared by about four panels, so
    /// this is about four times fewer multiplications than averaging Φ per panel and mode, with
    /// the same sums in another order. The vertex buffer is per thread: it allocates on a
    /// thread's first call (and when a larger mesh comes), never after.
    pub fn panel_velocities(
        &self,
        mesh: &PanelMesh,
        modal_velocities: &DVector<f64>,
        out: &mut [Vector3<f64>],
    ) {
        debug_assert_eq!(out.len(), mesh.panels.len());
        debug_assert_eq!(modal_velocities.len(), self.n_modes());
        let n_modes = self.n_modes().min(modal_velocities.len());
        self.with_vertex_scratch(|vertex_velocity| {
            for (column, &q_dot) in self
                .mode_columns()
                .zip(modal_velocities.iter())
                .take(n_modes)
            {
                if q_dot == 0.0 {
                    continue;
                }
                for (v, &phi) in vertex_velocity.iter_mut().zip(column) {
                    *v += phi * q_dot;
                }
            }
            panel_means(mesh, vertex_velocity, out);
        });
    }
}

/// Each panel's mean of a per-vertex field (x, y, z interleaved) into `out` (one per panel).
fn panel_means(mesh: &PanelMesh, field: &[f64], out: &mut [Vector3<f64>]) {
    for (panel, v_out) in mesh.panels.iter().zip(out.iter_mut()) {
        *v_out = vertex_mean(field, panel);
    }
}

thread_local! {
    /// Per-vertex scratch (x, y, z interleaved) of [`ModeShapes::panel_velocities`].
    static VERTEX_SCRATCH: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Mean over a panel's vertices of a per-vertex field stored x, y, z interleaved (the panel rule
/// of [`ModeShapes::panel_displacement`]).
fn vertex_mean(field: &[f64], panel: &Panel) -> Vector3<f64> {
    let idx = panel.vertex_indices();
    let sum = idx.iter().fold(Vector3::zeros(), |acc, &v| {
        acc + Vector3::new(field[3 * v], field[3 * v + 1], field[3 * v + 2])
    });
    sum / idx.len() as f64
}
