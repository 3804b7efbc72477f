//! Coupling helpers against closed forms: generalized forces of uniform pressure on a flat plate
//! (Q_i = −Δp ∫ n · φ_i dA, the virtual-work generalized force of Thomson, *Theory of Vibration
//! with Applications* (2010) Eq. (11.1-10)), rigid modes against `integrate_pressure`, rigid
//! rotations about the torque tube (areas preserved, normals rotated, R_y(90°) images by hand),
//! the elevon sign (DESIGN §4), and bilinear grid transfer, exact on linear fields (one file: the
//! checks share the plate meshes and mode shapes built below).

use std::f64::consts::FRAC_PI_2;

use approx::assert_relative_eq;
use hsv_core::aero::integrate_pressure;
use hsv_core::config::LoadedConfig;
use hsv_core::coupling::{
    CouplingError, ElevonCommand, GridTransfer, ModalProjection, deflect_grid_positions,
    deflect_lifting_surface, generalized_forces, pivot_axis, pressure_loads, rotate_about_axis,
    rotate_grid_positions, rotate_points, rotation_about_axis,
};
use hsv_core::geometry::{LiftingSurfaceConfig, Side, lifting_surface_mesh, pivot_point};
use hsv_core::mesh::{ModeShapes, PanelMesh, PanelSpec, RegionKind, Surface};
use hsv_core::surface_grid::SurfaceGrid;
use nalgebra::{DMatrix, Point3, Rotation3, Vector3};

const P_INF_PA: f64 = 2188.0;

fn lifting_config() -> LiftingSurfaceConfig {
    LoadedConfig::sample()
        .expect("sample config")
        .config
        .lifting_surface
}

/// Flat plate x in [x0, x0 + a], y in [0, b], z = 0, nx × ny quads; normal +z when `plus_z`.
fn plate(x0: f64, a: f64, b: f64, nx: usize, ny: usize, plus_z: bool) -> PanelMesh {
    let mut vertices = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            vertices.push(Point3::new(
                x0 + a * i as f64 / nx as f64,
                b * j as f64 / ny as f64,
                0.0,
            ));
        }
    }
    let v = |i: usize, j: usize| j * (nx + 1) + i;
    let mut panels = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (a0, a1, a2, a3) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            // Diagonals (dx, dy, 0) × (−dx, dy, 0) = (0, 0, 2 dx dy): counter-clockwise in x-y is +z.
            panels.push(if plus_z {
                PanelSpec::quad(a0, a1, a2, a3, 0)
            } else {
                PanelSpec::quad(a0, a3, a2, a1, 0)
            });
        }
    }
    PanelMesh::new(
        vertices,
        &panels,
        Vec::new(),
        vec![Surface::new("plate", RegionKind::LiftingSurface)],
    )
    .expect("plate")
}

/// Three rectangular plates in general orientation (rotated with the helper under test, which
/// keeps rectangles rectangular, so each panel's vertex mean is its centroid): the first two on
/// a main-body surface, the third on a propulsion surface.
fn tilted_plates() -> PanelMesh {
    let mut mesh = PanelMesh::default();
    let tilts = [
        (Vector3::x(), 0.4, RegionKind::MainBody),
        (Vector3::new(0.3, 1.0, -0.2), 1.9, RegionKind::MainBody),
        (Vector3::new(-0.5, 0.2, 1.0), -2.3, RegionKind::Propulsion),
    ];
    for (k, (axis, angle, region)) in tilts.into_iter().enumerate() {
        let mut flat = plate(0.2 * k as f64, 1.0 + 0.3 * k as f64, 0.8, 3, 2, k % 2 == 0);
        flat.surfaces[0].region = region;
        let mut tilted = PanelMesh::default();
        rotate_about_axis(
            &flat,
            &Point3::new(0.1, -0.4, 0.6),
            &axis,
            angle,
            &mut tilted,
        )
        .expect("rotate");
        mesh.merge(&tilted);
    }
    mesh
}

/// A mode's displacement at a vertex, m per unit modal coordinate.
type ModeFn<'a> = &'a dyn Fn(&Point3<f64>) -> Vector3<f64>;

/// Mode shapes whose column k at vertex r is `modes[k](r)`.
fn shapes(mesh: &PanelMesh, modes: &[ModeFn<'_>]) -> ModeShapes {
    let mut phi = DMatrix::zeros(3 * mesh.vertices.len(), modes.len());
    for (i, r) in mesh.vertices.iter().enumerate() {
        for (k, mode) in modes.iter().enumerate() {
            let d = mode(r);
            for c in 0..3 {
                phi[(3 * i + c, k)] = d[c];
            }
        }
    }
    ModeShapes {
        vertex_displacement: phi,
    }
}

fn all(_: RegionKind) -> bool {
    true
}

/// Uniform heave w = 1 under uniform gauge pressure Δp: Q = −Δp ∫ n_z dA = −Δp A n_z exactly
/// (n_z = ±1); an in-plane mode does no work (n · φ = 0).
#[test]
fn heave_mode_on_a_flat_plate_gives_minus_gauge_pressure_times_area() {
    let (a, b) = (2.0, 1.5);
    let dp = 1234.5;
    for (plus_z, nz) in [(true, 1.0), (false, -1.0)] {
        let mesh = plate(0.5, a, b, 5, 3, plus_z);
        let modes = shapes(&mesh, &[&|_| Vector3::z(), &|_| Vector3::x()]);
        let pressure = vec![P_INF_PA + dp; mesh.panels.len()];
        let mut q = [0.0; 2];
        generalized_forces(&mesh, &modes, &pressure, P_INF_PA, all, &mut q).expect("Q");
        assert_relative_eq!(q[0], -dp * a * b * nz, max_relative = 1e-12);
        assert_relative_eq!(q[1], 0.0, epsilon = 1e-9);
    }
}

/// Linear mode w = x / a under uniform Δp: Q = −Δp n_z ∫ x dA / a = −Δp n_z A x̄ / a, with the
/// centroid x̄ = x0 + a/2 (exact for any discretisation: the vertex mean of a linear field on a
/// rectangle is its value at the centroid).
#[test]
fn linear_mode_on_a_flat_plate_gives_the_first_moment_of_area() {
    let (x0, a, b) = (0.5, 2.0, 1.5);
    let dp = -800.0;
    for (plus_z, nz) in [(true, 1.0), (false, -1.0)] {
        let mesh = plate(x0, a, b, 7, 2, plus_z);
        let modes = shapes(&mesh, &[&|r| Vector3::new(0.0, 0.0, r.x / a)]);
        let pressure = vec![P_INF_PA + dp; mesh.panels.len()];
        let mut q = [0.0];
        generalized_forces(&mesh, &modes, &pressure, P_INF_PA, all, &mut q).expect("Q");
        let x_bar = x0 + 0.5 * a;
        assert_relative_eq!(q[0], -dp * nz * a * b * x_bar / a, max_relative = 1e-12);
        // The precomputed projection gives the same number.
        let projection = ModalProjection::new(&mesh, &modes, all).expect("projection");
        let mut qp = [0.0];
        projection
            .generalized_forces(&pressure, P_INF_PA, &mut qp)
            .expect("Q");
        assert_relative_eq!(qp[0], q[0], max_relative = 1e-12);
    }
}

/// Rigid modes reproduce `integrate_pressure` (one convention): translation e_k gives
/// Q = F_k; rotation e_k × (r − r_0) gives Q = e_k · Σ (c − r_0) × F = M_k, exact where the vertex
/// mean is the centroid (rectangular panels). The region filter is the same.
#[test]
fn rigid_modes_reproduce_the_integrate_pressure_force_and_moment() {
    let mesh = tilted_plates();
    let r0 = Point3::new(0.3, -0.2, 0.7);
    let ex = Vector3::x();
    let ey = Vector3::y();
    let ez = Vector3::z();
    let modes = shapes(
        &mesh,
        &[
            &|_| ex,
            &|_| ey,
            &|_| ez,
            &|r| ex.cross(&(r - r0)),
            &|r| ey.cross(&(r - r0)),
            &|r| ez.cross(&(r - r0)),
        ],
    );
    let pressure: Vec<f64> = (0..mesh.panels.len())
        .map(|j| P_INF_PA + 1000.0 * (j as f64 + 1.0) * if j % 2 == 0 { 1.0 } else { -0.7 })
        .collect();
    let total = integrate_pressure(&mesh, &pressure, P_INF_PA, &r0, all);
    assert!(
        total
            .force_n
            .iter()
            .chain(total.moment_nm.iter())
            .all(|c| c.abs() > 10.0)
    );
    for include in [
        &all as &dyn Fn(RegionKind) -> bool,
        &|r: RegionKind| r == RegionKind::MainBody,
        &|r: RegionKind| r == RegionKind::Propulsion,
    ] {
        let mut q = [0.0; 6];
        let loads = pressure_loads(&mesh, &modes, &pressure, P_INF_PA, &r0, include, &mut q)
            .expect("loads");
        assert_eq!(
            loads,
            integrate_pressure(&mesh, &pressure, P_INF_PA, &r0, include)
        );
        for k in 0..3 {
            assert_relative_eq!(q[k], loads.force_n[k], epsilon = 1e-9);
            assert_relative_eq!(q[3 + k], loads.moment_nm[k], epsilon = 1e-9);
        }
    }
    // A lifting surface: translations give the integrated force of its lifting-surface panels.
    let cfg = lifting_config();
    let mesh = lifting_surface_mesh(&cfg, Side::Right).expect("mesh");
    let modes = shapes(&mesh, &[&|_| ex, &|_| ey, &|_| ez]);
    let pressure: Vec<f64> = mesh
        .panels
        .iter()
        .map(|p| P_INF_PA * (1.0 + 0.1 * p.centroid.x.sin() + 0.05 * p.centroid.y))
        .collect();
    let lifting = |r: RegionKind| r == RegionKind::LiftingSurface;
    let mut q = [0.0; 3];
    let loads =
        pressure_loads(&mesh, &modes, &pressure, P_INF_PA, &r0, lifting, &mut q).expect("loads");
    for (qk, fk) in q.iter().zip(loads.force_n.iter()) {
        assert_relative_eq!(*qk, *fk, epsilon = 1e-9);
    }
}

/// Smooth, non-rigid test modes on a lifting surface (bending, torsion, in-plane).
fn lifting_surface_modes(mesh: &PanelMesh, pivot: Point3<f64>) -> ModeShapes {
    shapes(
        mesh,
        &[
            &|r| Vector3::new(0.0, 0.0, (r.y - pivot.y).powi(2)),
            &|r| Vector3::new(0.0, 0.0, (r.x - pivot.x) * (r.y - pivot.y)),
            &|r| Vector3::new(0.1 * r.y, 0.0, (0.7 * r.x).sin()),
            &|r| Vector3::new(0.0, 0.02 * r.x, (r.y - pivot.y).powi(3)),
        ],
    )
}

/// The precomputed projection is the same sum as the direct one on the reference geometry,
/// to round-off (1e-12 of the largest term).
#[test]
fn modal_projection_equals_the_direct_sum_on_the_reference_geometry() {
    let cfg = lifting_config();
    for side in [Side::Left, Side::Right] {
        let mesh = lifting_surface_mesh(&cfg, side).expect("mesh");
        let modes = lifting_surface_modes(&mesh, pivot_point(&cfg, side));
        let pressure: Vec<f64> = mesh
            .panels
            .iter()
            .enumerate()
            .map(|(j, p)| P_INF_PA * (1.0 + 0.3 * (j as f64 * 0.37).sin() - 0.01 * p.centroid.x))
            .collect();
        let lifting = |r: RegionKind| r == RegionKind::LiftingSurface;
        let projection = ModalProjection::new(&mesh, &modes, lifting).expect("projection");
        assert_eq!(projection.n_modes(), 4);
        assert_eq!(projection.n_panels(), mesh.panels.len());
        let mut direct = [0.0; 4];
        let mut fast = [0.0; 4];
        generalized_forces(&mesh, &modes, &pressure, P_INF_PA, lifting, &mut direct).expect("Q");
        projection
            .generalized_forces(&pressure, P_INF_PA, &mut fast)
            .expect("Q");
        let scale = direct.iter().fold(0.0_f64, |m, q| m.max(q.abs()));
        assert!(scale > 0.0);
        for k in 0..4 {
            assert_relative_eq!(fast[k], direct[k], epsilon = 1e-12 * scale);
        }
        // Excluded panels (the root cap) have zero columns.
        let root_cap: Vec<usize> = mesh.panels_in_region(RegionKind::Other).collect();
        assert!(!root_cap.is_empty());
        for j in root_cap {
            assert!(projection.matrix().column(j).iter().all(|&v| v == 0.0));
        }
    }
}

/// A rigid translation keeps every A n, so the exact deformed-geometry sum equals the
/// reference-geometry projection (the linear-structure assumption is exact for it).
#[test]
fn a_translated_mesh_has_the_reference_generalized_forces() {
    let cfg = lifting_config();
    let mesh = lifting_surface_mesh(&cfg, Side::Right).expect("mesh");
    let modes = shapes(
        &mesh,
        &[&|_| Vector3::new(0.0, 0.0, 1.0), &|r| {
            Vector3::new(0.0, 0.0, r.y)
        }],
    );
    let mut deformed = PanelMesh::default();
    // Mode 0 alone: a heave of 0.3 m.
    modes.deform(
        &mesh,
        &nalgebra::DVector::from_vec(vec![0.3, 0.0]),
        &mut deformed,
    );
    let pressure: Vec<f64> = (0..mesh.panels.len())
        .map(|j| P_INF_PA + 50.0 * j as f64)
        .collect();
    let projection = ModalProjection::new(&mesh, &modes, all).expect("projection");
    let (mut on_reference, mut on_deformed) = ([0.0; 2], [0.0; 2]);
    projection
        .generalized_forces(&pressure, P_INF_PA, &mut on_reference)
        .expect("Q");
    generalized_forces(
        &deformed,
        &modes,
        &pressure,
        P_INF_PA,
        all,
        &mut on_deformed,
    )
    .expect("Q");
    for k in 0..2 {
        assert_relative_eq!(on_deformed[k], on_reference[k], max_relative = 1e-10);
    }
}

/// A rigid rotation R about the pivot line keeps every panel area, rotates every normal by R
/// and maps every centroid c to r_0 + R (c − r_0); points on the axis stay put.
#[test]
fn rotation_about_the_pivot_preserves_areas_and_rotates_normals() {
    let cfg = lifting_config();
    for side in [Side::Left, Side::Right] {
        let mesh = lifting_surface_mesh(&cfg, side).expect("mesh");
        let pivot = pivot_point(&cfg, side);
        let angle = 0.3;
        let rotation = Rotation3::from_axis_angle(&Vector3::y_axis(), angle);
        let mut out = PanelMesh::default();
        // Twice into the same buffer: the second call starts again from `mesh`.
        for _ in 0..2 {
            rotate_about_axis(&mesh, &pivot, &Vector3::y(), angle, &mut out).expect("rotate");
        }
        assert_eq!(out.panels.len(), mesh.panels.len());
        for (a, b) in mesh.panels.iter().zip(&out.panels) {
            assert_relative_eq!(b.area_m2, a.area_m2, max_relative = 1e-12);
            assert_relative_eq!(b.normal, rotation * a.normal, epsilon = 1e-12);
            assert_relative_eq!(
                b.centroid,
                pivot + rotation * (a.centroid - pivot),
                epsilon = 1e-12
            );
        }
        assert_relative_eq!(
            out.enclosed_volume_m3(),
            mesh.enclosed_volume_m3(),
            max_relative = 1e-12
        );
        // Points on the axis r_0 + s e_y are fixed, whatever the angle.
        let on_axis: Vec<Point3<f64>> = [-1.0, 0.0, 2.5]
            .iter()
            .map(|&s| pivot + s * Vector3::y())
            .collect();
        let mut image = vec![Point3::origin(); on_axis.len()];
        let r = rotation_about_axis(&pivot_axis(), 1.1).expect("rotation");
        rotate_points(&on_axis, &pivot, &r, &mut image).expect("rotate");
        for (a, b) in on_axis.iter().zip(&image) {
            assert_relative_eq!(*a, *b, epsilon = 1e-12);
        }
        // The grid's root node at the ridge (mid root chord, = the pivot fraction) is on the
        // axis too.
        let grid = SurfaceGrid::lifting_surface(&cfg, side, 10, 4).expect("grid");
        let mut moved = vec![Point3::origin(); grid.n_nodes()];
        rotate_grid_positions(&grid, &pivot, &Vector3::y(), 1.1, &mut moved).expect("rotate");
        let ridge = grid.node_index(5, 0);
        assert_relative_eq!(grid.positions_m[ridge], pivot, epsilon = 1e-12);
        assert_relative_eq!(moved[ridge], pivot, epsilon = 1e-12);
    }
}

/// A n · φ is invariant when mesh and modes turn together (R n · R φ = n · φ, areas kept): the
/// generalized forces of a deflected surface are those of the undeflected one under the same
/// panel pressures, so the reference-geometry projection serves every deflection.
#[test]
fn generalized_forces_are_invariant_when_mesh_and_modes_rotate_together() {
    let cfg = lifting_config();
    let mesh = lifting_surface_mesh(&cfg, Side::Right).expect("mesh");
    let pivot = pivot_point(&cfg, Side::Right);
    let modes = lifting_surface_modes(&mesh, pivot);
    let angle = -0.35;
    let rotation = Rotation3::from_axis_angle(&Vector3::y_axis(), angle);
    let mut deflected = PanelMesh::default();
    rotate_about_axis(&mesh, &pivot, &Vector3::y(), angle, &mut deflected).expect("rotate");
    let mut turned = modes.clone();
    for i in 0..mesh.vertices.len() {
        for k in 0..modes.n_modes() {
            let phi = modes.vertex_displacement.fixed_view::<3, 1>(3 * i, k);
            let r = rotation * Vector3::new(phi[0], phi[1], phi[2]);
            turned
                .vertex_displacement
                .fixed_view_mut::<3, 1>(3 * i, k)
                .copy_from(&r);
        }
    }
    let pressure: Vec<f64> = (0..mesh.panels.len())
        .map(|j| P_INF_PA * (1.0 + 0.2 * (0.3 * j as f64).cos()))
        .collect();
    let projection = ModalProjection::new(&mesh, &modes, all).expect("projection");
    let (mut reference, mut rotated) = ([0.0; 4], [0.0; 4]);
    projection
        .generalized_forces(&pressure, P_INF_PA, &mut reference)
        .expect("Q");
    generalized_forces(&deflected, &turned, &pressure, P_INF_PA, all, &mut rotated).expect("Q");
    let scale = reference.iter().fold(0.0_f64, |m, q| m.max(q.abs()));
    for k in 0..4 {
        assert_relative_eq!(rotated[k], reference[k], epsilon = 1e-12 * scale);
    }
}

/// The root trailing edge of the sample right surface is d = (1 − 0.5) c_r = 2 m aft of the
/// pivot (−25, 1.5, −0.9) on the mid-plane: (−27, 1.5, −0.9). R_y(90°) = [[0,0,1],[0,1,0],[−1,0,0]]
/// maps the offset (−2, 0, 0) to (0, 0, 2): the image is (−25, 1.5, 1.1).
#[test]
fn quarter_turn_maps_the_root_trailing_edge_to_its_hand_computed_image() {
    let cfg = lifting_config();
    let mesh = lifting_surface_mesh(&cfg, Side::Right).expect("mesh");
    let te = Point3::new(-27.0, 1.5, -0.9);
    let index = mesh
        .vertices
        .iter()
        .position(|v| (v - te).norm() < 1e-9)
        .expect("the root trailing-edge vertex of the sample surface");
    let mut out = PanelMesh::default();
    rotate_about_axis(
        &mesh,
        &pivot_point(&cfg, Side::Right),
        &Vector3::y(),
        FRAC_PI_2,
        &mut out,
    )
    .expect("rotate");
    assert_relative_eq!(
        out.vertices[index],
        Point3::new(-25.0, 1.5, 1.1),
        epsilon = 1e-12
    );
}

/// DESIGN §4: positive elevon is nose-up, trailing edge up (to smaller z) for surfaces aft of the
/// centre of gravity. A trailing edge d aft of the pivot goes to
/// (x_p − d cos δ, ·, z_p − d sin δ). Per side: left δe + δa, right δe − δa.
#[test]
fn positive_elevon_raises_the_trailing_edge() {
    let cfg = lifting_config();
    let d = (1.0 - cfg.pivot_root_chord_fraction) * cfg.root_chord_m;
    let delta = 5f64.to_radians();
    let command = ElevonCommand {
        symmetric_rad: delta,
        differential_rad: 0.0,
    };
    for side in [Side::Left, Side::Right] {
        let mesh = lifting_surface_mesh(&cfg, side).expect("mesh");
        let pivot = pivot_point(&cfg, side);
        let te = Point3::new(pivot.x - d, pivot.y, pivot.z);
        let index = mesh
            .vertices
            .iter()
            .position(|v| (v - te).norm() < 1e-9)
            .expect("root trailing-edge vertex");
        let mut out = PanelMesh::default();
        assert_eq!(command.deflection_rad(side), delta);
        deflect_lifting_surface(&mesh, &cfg, side, command.deflection_rad(side), &mut out)
            .expect("deflect");
        let moved = out.vertices[index];
        assert!(moved.z < te.z, "trailing edge moves up (smaller z)");
        assert_relative_eq!(
            moved,
            Point3::new(
                pivot.x - d * delta.cos(),
                pivot.y,
                pivot.z - d * delta.sin()
            ),
            epsilon = 1e-12
        );
        // The structural grid's root trailing-edge node moves the same way.
        let grid = SurfaceGrid::lifting_surface(&cfg, side, 8, 4).expect("grid");
        let mut nodes = vec![Point3::origin(); grid.n_nodes()];
        deflect_grid_positions(&grid, delta, &mut nodes).expect("deflect");
        let te_node = grid.node_index(grid.elements_chordwise, 0);
        assert_relative_eq!(grid.positions_m[te_node], te, epsilon = 1e-12);
        assert_relative_eq!(nodes[te_node], moved, epsilon = 1e-12);
    }
    // Differential: left = δe + δa, right = δe − δa; positive δa raises the left trailing edge
    // and lowers the right one.
    let roll = ElevonCommand {
        symmetric_rad: 0.02,
        differential_rad: 0.05,
    };
    assert_relative_eq!(roll.deflection_rad(Side::Left), 0.07, epsilon = 1e-15);
    assert_relative_eq!(roll.deflection_rad(Side::Right), -0.03, epsilon = 1e-15);
    let roll = ElevonCommand {
        symmetric_rad: 0.0,
        differential_rad: 0.05,
    };
    for (side, up) in [(Side::Left, true), (Side::Right, false)] {
        let grid = SurfaceGrid::lifting_surface(&cfg, side, 8, 4).expect("grid");
        let mut nodes = vec![Point3::origin(); grid.n_nodes()];
        deflect_grid_positions(&grid, roll.deflection_rad(side), &mut nodes).expect("deflect");
        let te_node = grid.node_index(grid.elements_chordwise, 0);
        assert_eq!(
            nodes[te_node].z < grid.positions_m[te_node].z,
            up,
            "{side:?}"
        );
    }
}

/// Bilinear interpolation is exact on fields bilinear in each source cell; on this planform
/// x and y are bilinear in the cell coordinates, so T = T0 + a x + b y transfers exactly, both
/// ways between two resolutions, and agrees with `SurfaceGrid::resample` (the same
/// interpolation).
#[test]
fn grid_transfer_reproduces_a_linear_temperature_field_exactly() {
    let cfg = lifting_config();
    let field = |p: &Point3<f64>| 1500.0 + 25.0 * p.x - 40.0 * p.y;
    for side in [Side::Left, Side::Right] {
        let conduction = SurfaceGrid::lifting_surface(&cfg, side, 8, 6).expect("grid");
        let structure = SurfaceGrid::lifting_surface(&cfg, side, 20, 13).expect("grid");
        for (source, target) in [(&conduction, &structure), (&structure, &conduction)] {
            let transfer = GridTransfer::new(source, target).expect("transfer");
            assert_eq!(transfer.n_source(), source.n_nodes());
            assert_eq!(transfer.n_target(), target.n_nodes());
            let values: Vec<f64> = source.positions_m.iter().map(field).collect();
            let mut out = vec![0.0; target.n_nodes()];
            transfer.apply(&values, &mut out).expect("apply");
            for (p, t) in target.positions_m.iter().zip(&out) {
                assert_relative_eq!(*t, field(p), max_relative = 1e-10);
            }
            let resampled = source.resample(&values, target);
            for (a, b) in out.iter().zip(&resampled) {
                assert_relative_eq!(*a, *b, max_relative = 1e-14);
            }
        }
    }
}

/// The one conduction-to-structure transfer (issue 25 item 6): a structure keeping the other
/// side's grid (the left surface's model built on the right's) is read at its nodes' mirror
/// images, so a field symmetric in y arrives exactly; nodes without grids pass through when
/// they count the same and are an error naming both counts otherwise, never a silent fallback.
#[test]
fn conduction_temperatures_reach_the_structure_by_one_rule() {
    let cfg = lifting_config();
    let field = |p: &Point3<f64>| 1500.0 + 25.0 * p.x - 40.0 * p.y.abs();
    let conduction = SurfaceGrid::lifting_surface(&cfg, Side::Left, 8, 6).expect("grid");
    let structure = SurfaceGrid::lifting_surface(&cfg, Side::Right, 20, 13).expect("grid");
    let transfer = GridTransfer::conduction_to_structure(
        (Some(&conduction), conduction.n_nodes()),
        (Some(&structure), structure.n_nodes()),
    )
    .expect("mirrored transfer")
    .expect("a grid transfer");
    let values: Vec<f64> = conduction.positions_m.iter().map(field).collect();
    let mut out = vec![0.0; structure.n_nodes()];
    transfer.apply(&values, &mut out).expect("apply");
    for (p, t) in structure.positions_m.iter().zip(&out) {
        assert_relative_eq!(*t, field(p), max_relative = 1e-10);
    }
    let same = GridTransfer::conduction_to_structure((None, 12), (Some(&structure), 12));
    assert_eq!(same.expect("same nodes"), None);
    let err = GridTransfer::conduction_to_structure((None, 12), (Some(&structure), 15))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("12 node temperatures") && err.contains("15 temperature nodes"),
        "{err}"
    );
}

#[test]
fn mismatched_grids_buffers_and_non_finite_inputs_are_errors_naming_the_quantity() {
    let cfg = lifting_config();
    let left = SurfaceGrid::lifting_surface(&cfg, Side::Left, 8, 6).expect("grid");
    let right = SurfaceGrid::lifting_surface(&cfg, Side::Right, 8, 6).expect("grid");
    let err = GridTransfer::new(&left, &right).unwrap_err();
    assert!(matches!(err, CouplingError::Grid(_)), "{err}");
    assert!(err.to_string().contains("outside the planform"), "{err}");

    let transfer = GridTransfer::new(&right, &right).expect("transfer");
    let mut out = vec![0.0; right.n_nodes()];
    let err = transfer
        .apply(&[300.0; 3], &mut out)
        .unwrap_err()
        .to_string();
    assert!(err.contains("source node values has 3 entries"), "{err}");
    let mut values = vec![300.0; right.n_nodes()];
    values[7] = f64::NAN;
    let err = transfer.apply(&values, &mut out).unwrap_err().to_string();
    assert!(
        err.contains("source node values") && err.contains("index 7"),
        "{err}"
    );

    let mesh = plate(0.0, 1.0, 1.0, 2, 2, true);
    let modes = shapes(&mesh, &[&|_| Vector3::z()]);
    let mut q = [0.0];
    let err = generalized_forces(&mesh, &modes, &[P_INF_PA; 3], P_INF_PA, all, &mut q)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("panel pressure (Pa) has 3 entries, expected 4"),
        "{err}"
    );
    let mut pressure = [P_INF_PA; 4];
    pressure[2] = f64::INFINITY;
    let err = generalized_forces(&mesh, &modes, &pressure, P_INF_PA, all, &mut q)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("panel pressure") && err.contains("index 2"),
        "{err}"
    );
    let projection = ModalProjection::new(&mesh, &modes, all).expect("projection");
    let err = projection
        .generalized_forces(&pressure, P_INF_PA, &mut q)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("panel pressure") && err.contains("index 2"),
        "{err}"
    );
    let err = projection
        .generalized_forces(&[P_INF_PA; 4], P_INF_PA, &mut [0.0; 2])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("generalized-force buffer has 2 entries"),
        "{err}"
    );
    let other = plate(0.0, 1.0, 1.0, 3, 2, true);
    let err = ModalProjection::new(&other, &modes, all)
        .unwrap_err()
        .to_string();
    assert!(err.contains("mode shapes have 27 rows"), "{err}");

    let mut out_mesh = PanelMesh::default();
    let err = rotate_about_axis(
        &mesh,
        &Point3::origin(),
        &Vector3::zeros(),
        0.1,
        &mut out_mesh,
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("rotation axis length"), "{err}");
    let err = rotate_about_axis(
        &mesh,
        &Point3::origin(),
        &Vector3::y(),
        f64::NAN,
        &mut out_mesh,
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("rotation angle (rad)"), "{err}");
}
