//! The vertex-first modal kernels against the per-panel formulation they replaced, on the sample
//! vehicle's main-body and lifting-surface meshes with smooth, non-trivial mode shapes.
//!
//! `ModeShapes::panel_velocities` now forms the vertex velocities Φ q̇ and averages them per
//! panel; `coupling::generalized_forces` now spreads each panel's force −(p − p_ref) A n over
//! its vertices and takes Φᵀ F. The previous forms, Σ_k φ̄_k(panel) q̇_k and
//! Q_k = −Σ (p − p_ref) A n · φ̄_k(panel) with φ̄ the vertex mean (`ModeShapes::panel_displacement`,
//! the rule of Thomson, *Theory of Vibration with Applications* (2010) Eq. (11.1-10) as
//! `ModalProjection` still builds it), are the same sums in another order: they must agree to
//! 1e-12 of the largest term. The panel geometry now shares one reciprocal per diagonal split
//! where it divided nine times; it must agree with the previous form (Hess & Smith 1967 normal
//! from the diagonals, area-weighted centroids of both splits) to 1e-14 of the panel size. The
//! closed-form checks (rigid modes, uniform heave, planar panel geometry) stay in `mesh.rs` and
//! `coupling.rs`.

use hsv_core::coupling::{ModalProjection, generalized_forces};
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use hsv_core::testing::sample_region;
use nalgebra::{DMatrix, DVector, Point3, Vector3};

/// Eight smooth shapes (bending, twist, in-plane, non-linear in x, y, z), m per unit coordinate.
fn shapes(mesh: &PanelMesh) -> ModeShapes {
    let n_modes = 8;
    let mut phi = DMatrix::zeros(3 * mesh.vertices.len(), n_modes);
    for (i, r) in mesh.vertices.iter().enumerate() {
        for k in 0..n_modes {
            let f = 0.3 * (k as f64 + 1.0);
            let d = Vector3::new(
                (f * r.y).sin() * 0.1,
                (f * r.z + 0.2 * r.x).cos() * 0.05,
                (f * r.x).sin() * (1.0 + 0.1 * r.y * r.y),
            );
            for c in 0..3 {
                phi[(3 * i + c, k)] = d[c];
            }
        }
    }
    ModeShapes {
        vertex_displacement: phi,
    }
}

fn modal_velocities() -> DVector<f64> {
    DVector::from_fn(8, |k, _| 0.7 - 0.23 * k as f64)
}

#[test]
fn panel_velocities_equal_the_per_panel_mode_sum() {
    for region in ["main_body", "left_surface"] {
        let mesh = &sample_region(region).mesh;
        let shapes = shapes(mesh);
        let q_dot = modal_velocities();
        let mut velocities = vec![Vector3::zeros(); mesh.panels.len()];
        shapes.panel_velocities(mesh, &q_dot, &mut velocities);
        let previous: Vec<Vector3<f64>> = mesh
            .panels
            .iter()
            .map(|panel| {
                (0..shapes.n_modes())
                    .map(|k| shapes.panel_displacement(panel, k) * q_dot[k])
                    .sum()
            })
            .collect();
        let scale = previous.iter().map(|v| v.amax()).fold(0.0, f64::max);
        for (p, (new, old)) in velocities.iter().zip(&previous).enumerate() {
            assert!(
                (new - old).amax() <= 1e-12 * scale,
                "{region} panel {p}: {new:?} against {old:?}"
            );
        }
    }
}

/// The fused pass (one read of the mode columns) gives the two separate kernels' results bit
/// for bit: the same sums in the same order.
#[test]
fn displacement_with_velocities_equals_the_two_kernels() {
    for region in ["main_body", "left_surface"] {
        let mesh = &sample_region(region).mesh;
        let shapes = shapes(mesh);
        let q = DVector::from_fn(8, |k, _| 0.05 * (k as f64 - 3.0));
        let q_dot = modal_velocities();
        let (mut vertices, mut velocities) = (
            mesh.vertices.clone(),
            vec![Vector3::zeros(); mesh.panels.len()],
        );
        shapes.displace_with_velocities(mesh, &q, &q_dot, &mut vertices, &mut velocities);
        let mut separate_vertices = mesh.vertices.clone();
        shapes.displace_vertices(&mesh.vertices, &q, &mut separate_vertices);
        let mut separate_velocities = vec![Vector3::zeros(); mesh.panels.len()];
        shapes.panel_velocities(mesh, &q_dot, &mut separate_velocities);
        assert_eq!(vertices, separate_vertices, "{region}");
        assert_eq!(velocities, separate_velocities, "{region}");
        assert!(vertices.iter().zip(&mesh.vertices).any(|(a, b)| a != b));
    }
}

#[test]
fn generalized_forces_equal_the_per_panel_projection() {
    for region in ["main_body", "left_surface"] {
        let mesh = &sample_region(region).mesh;
        let shapes = shapes(mesh);
        let p_inf = 2188.0;
        let pressure: Vec<f64> = (0..mesh.panels.len())
            .map(|j| p_inf * (1.0 + 3.0 * ((j as f64) * 0.37).sin().abs()))
            .collect();
        for include in [
            (|r: RegionKind| r == RegionKind::MainBody) as fn(RegionKind) -> bool,
            |r: RegionKind| r == RegionKind::Propulsion,
            |_| true,
        ] {
            let mut new = vec![0.0; shapes.n_modes()];
            generalized_forces(mesh, &shapes, &pressure, p_inf, include, &mut new).expect("Q");
            let projection = ModalProjection::new(mesh, &shapes, include).expect("P");
            let mut old = vec![0.0; shapes.n_modes()];
            projection
                .generalized_forces(&pressure, p_inf, &mut old)
                .expect("Q");
            // The sum's size: Σ |p - p_ref| A |φ̄| over the panels.
            let scale: f64 = mesh
                .panels
                .iter()
                .zip(&pressure)
                .map(|(panel, p)| (p - p_inf).abs() * panel.area_m2)
                .sum::<f64>()
                * shapes.vertex_displacement.amax();
            for (k, (n, o)) in new.iter().zip(&old).enumerate() {
                assert!(
                    (n - o).abs() <= 1e-12 * scale,
                    "{region} mode {k}: {n} against {o} (scale {scale})"
                );
            }
        }
    }
}

/// The previous `panel_geometry`: (centroid, normal, area) with a division per component.
fn previous_geometry(v: [Point3<f64>; 4]) -> (Point3<f64>, Vector3<f64>, f64) {
    let [v0, v1, v2, v3] = v;
    let cross = (v2 - v0).cross(&(v3 - v1));
    let twice_area = cross.norm();
    let normal = cross / twice_area;
    let split = |a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>, d: &Point3<f64>| {
        let w1 = (b - a).cross(&(c - a)).norm();
        let w2 = (c - a).cross(&(d - a)).norm();
        let c1 = (a.coords + b.coords + c.coords) / 3.0;
        let c2 = (a.coords + c.coords + d.coords) / 3.0;
        (c1 * w1 + c2 * w2) / (w1 + w2)
    };
    let centroid = Point3::from((split(&v0, &v1, &v2, &v3) + split(&v1, &v2, &v3, &v0)) / 2.0);
    (centroid, normal, 0.5 * twice_area)
}

#[test]
fn panel_geometry_equals_the_previous_divisions() {
    for region in ["main_body", "left_surface"] {
        let mesh = &sample_region(region).mesh;
        // Warp the mesh (non-planar quads) the way modal deformation does.
        let shapes = shapes(mesh);
        let mut warped = PanelMesh::default();
        shapes.deform(mesh, &DVector::from_element(8, 0.05), &mut warped);
        for m in [mesh, &warped] {
            for (p, panel) in m.panels.iter().enumerate() {
                let idx = panel.vertices;
                let v = idx.map(|i| m.vertices[i]);
                let (centroid, normal, area) = previous_geometry(v);
                let size = area.sqrt();
                assert!(
                    (panel.centroid - centroid).amax() <= 1e-14 * (size + centroid.coords.amax()),
                    "{region} panel {p}: centroid {:?} against {centroid:?}",
                    panel.centroid
                );
                assert!(
                    (panel.normal - normal).amax() <= 1e-15,
                    "{region} panel {p}"
                );
                assert!(
                    (panel.area_m2 / area - 1.0).abs() <= 1e-15,
                    "{region} panel {p}"
                );
            }
        }
    }
}
