//! Independent validation of the partitioned vehicle's assembled in-vacuo modes against a
//! monolithic finite-element model of the same structure (one file: the reference model reads
//! best beside the comparison it serves).
//!
//! **What is compared.** The lowest six coupled elastic natural frequencies of the free vehicle
//! in vacuo (no aero, engine or gravity; the six rigid-body modes removed), and the strain-energy
//! shares (main body / left surface / right surface) of the modes near 9 Hz, from
//!
//! * the partitioned vehicle, [`PartitionedVehicle::in_vacuo_modes`]: the free-free beam's
//!   kept modes (component modes of the fuselage) coupled through the two-way pivot interface
//!   with the two surfaces' Ritz models (clamped-root modes relative to the torque tube, which
//!   the beam drives), the rigid-body motion condensed out; and
//! * a monolithic finite-element model written here, with no modal truncation anywhere: the
//!   free-free beam's assembled FE mass and stiffness (6 DOF per node, every DOF kept), and for
//!   each surface the full MITC4 plate of the same grid, material and thickness with *free*
//!   supports, whose root (torque-tube) nodes are slaved rigidly to the motion of the pivot
//!   point, which itself moves rigidly with the beam section at the pivot station
//!   (u_P = u_axis + θ × (P − r_axis)). The plate's in-plane motion is taken rigid with the
//!   pivot (x, y translation and yaw; the section is symmetric, so in-plane and bending decouple)
//!   and enters as a 3 × 3 rigid mass from the plate's consistent membrane mass. The coupled
//!   problem K v = ω² M v on [beam DOFs, left plate non-root DOFs, right plate non-root DOFs]
//!   is solved densely (Cholesky of M, symmetric eigen of L⁻¹ K L⁻ᵀ).
//!
//! **Independence.** The reference shares only the element matrices with the code under test
//! (beam `BeamMesh::assemble`, plate `PlateModel` element matrices and section interpolation);
//! the interface kinematics (pivot offset from the beam axis, slaving of the root nodes, sign
//! conventions of the plate rotations, mirroring of the left surface), the surfaces' rigid
//! inertia and the coupling are written here from the FE DOF definitions, without the
//! partitioned code's component modes, root loads, pivot mass matrices or fixed-point iteration.
//! Both models use the same (coarse 8 × 6) plate grid and the same 60-element beam, so the
//! difference measures modal truncation plus any error of the partitioned interface.
//!
//! **Tolerance.** 1 % relative on each of the first six elastic frequencies: the paper / issue
//! target for the partitioned model's agreement with a monolithic reference, not widened here.
//! Enough component modes are kept (6 per beam bending/torsion kind, 3 axial, 20 clamped-root
//! plate modes) that the truncation of the component-mode synthesis is well inside it; the
//! strain-energy shares of those six modes must agree within 0.01 (our choice).
//!
//! **Result** (coarse 8 × 6 plate, 60-element beam; printed by the test): the first six agree
//! within 0.13 % (worst: the antisymmetric surface-bending mode at 9.19 Hz, +0.13 %), the first
//! fourteen within 0.36 %, and every share within 0.007. The residual is component-mode
//! truncation, mostly of the beam: the 9.19 Hz error is +0.47 % with the paper's one mode per
//! kind, +0.34 % with 3, +0.13 % with 6 and +0.10 % with 8, while 10 → 26 plate modes change
//! nothing. The small negative errors (≤ 0.03 %, modes 3, 4, 6) cannot come from truncation
//! (a Rayleigh-Ritz subspace bounds from above); they are consistent with the partitioned
//! model's rigid surface inertia at the pivot coming from lumped-node mass properties (about
//! the pivot: roll +2.3 %, pitch +4.7 %, yaw +3.0 % against the consistent FE mass on this
//! grid), which would lower surface-inertia-loaded modes slightly (not isolated here). With
//! the paper's default truncation (1 mode per beam kind) modes 5-6 are simply missing (the
//! beam's second vertical and first lateral bending are not kept), as expected. The 0.1
//! body/surface share criterion near 9 Hz holds for the symmetric pair (8.87 and 9.75 Hz); the
//! antisymmetric 9.19 Hz mode has a body strain share of 0.07 in *both* models.

use hsv_core::config::{LoadedConfig, SAMPLE_CONFIG_TOML, parse_config};
use hsv_core::linalg::BandedMatrix;
use hsv_core::region::RegionInfo;
use hsv_core::registry::ModelContext;
use hsv_core::structure::{MassDistribution, StructureModel};
use hsv_model_free_free_beam::FreeFreeBeam;
use hsv_model_ritz_plate::RitzPlate;
use hsv_model_ritz_plate::plate::{PlateModel, Supports};
use hsv_run::vehicle::partitioned::SurfaceModel;
use nalgebra::{DMatrix, DVector, Point3, Vector3};

/// Clamped-root plate modes kept by the partitioned surfaces.
const PLATE_MODES: usize = 20;
/// Beam modes kept per bending/torsion kind by the partitioned body.
const BEAM_MODES_PER_KIND: usize = 6;
/// Beam axial modes kept by the partitioned body.
const BEAM_AXIAL_MODES: usize = 3;
/// Relative tolerance on each compared frequency (paper / issue target).
const TOLERANCE: f64 = 0.01;
/// Frequencies compared.
const COMPARED: usize = 6;
/// Absolute tolerance on each region's strain-energy share of a compared mode (our choice:
/// the shares are a cross-check of the mode shapes, not the paper's target).
const SHARE_TOLERANCE: f64 = 0.01;

/// The sample config with the coarse 8 × 6 plate grid, no static shapes and more component
/// modes in both partitioned models, so their truncation converges.
fn config_text() -> String {
    let replacements = [
        (
            "free_vibration_modes = 10",
            format!("free_vibration_modes = {PLATE_MODES}"),
        ),
        ("static_shapes = 5", "static_shapes = 0".to_owned()),
        (
            "elements_chordwise = 24",
            "elements_chordwise = 8".to_owned(),
        ),
        ("elements_spanwise = 18", "elements_spanwise = 6".to_owned()),
        (
            "lateral_bending_modes = 1",
            format!("lateral_bending_modes = {BEAM_MODES_PER_KIND}"),
        ),
        (
            "vertical_bending_modes = 1",
            format!("vertical_bending_modes = {BEAM_MODES_PER_KIND}"),
        ),
        (
            "torsion_modes = 1",
            format!("torsion_modes = {BEAM_MODES_PER_KIND}"),
        ),
        (
            "axial_modes = 0",
            format!("axial_modes = {BEAM_AXIAL_MODES}"),
        ),
    ];
    let mut text = SAMPLE_CONFIG_TOML.to_owned();
    for (from, to) in replacements {
        assert_eq!(
            text.matches(from).count(),
            1,
            "`{from}` must occur once in the sample config"
        );
        text = text.replace(from, &to);
    }
    text
}

/// Dense copy of a symmetric banded matrix.
fn dense(b: &BandedMatrix) -> DMatrix<f64> {
    let n = b.size();
    let w = b.bandwidth();
    let mut out = DMatrix::zeros(n, n);
    for i in 0..n {
        for j in i.saturating_sub(w)..=i {
            let v = b.get(i, j);
            out[(i, j)] = v;
            out[(j, i)] = v;
        }
    }
    out
}

/// One lifting surface of the monolithic model.
struct PlateFe {
    /// Full free-plate bending mass and stiffness over every node's (w, βx, βy).
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    /// Map from the free-plate equations to the global DOFs (n_eq × n_global).
    transform: DMatrix<f64>,
    /// Global DOF range of this plate's non-root DOFs.
    global_range: std::ops::Range<usize>,
}

/// The 6 × n_beam matrix S_P: rigid motion (translation x, y, z; rotation x, y, z, body axes)
/// of the point `pivot` carried by the beam section at the pivot's station, per beam DOF.
fn pivot_kinematics(beam: &FreeFreeBeam, pivot: &Point3<f64>) -> DMatrix<f64> {
    let mesh = beam.beam_mesh();
    let n = mesh.n_dof();
    // Stations are measured aft of the nose: s = −x.
    let s_p = -pivot.x;
    assert!(s_p > 0.0 && s_p < mesh.length_m(), "pivot on the beam");
    let arm = Vector3::new(0.0, pivot.y, pivot.z - beam.axis_z_m());
    let mut s = DMatrix::zeros(6, n);
    for col in 0..n {
        let motion = mesh.section_motion_of(|i| f64::from(u8::from(i == col)), s_p);
        let translation = motion.displacement + motion.rotation.cross(&arm);
        for k in 0..3 {
            s[(k, col)] = translation[k];
            s[(3 + k, col)] = motion.rotation[k];
        }
    }
    s
}

/// (w, βx, βy) at a plate node at `p` (right-side grid coordinates) of a rigid motion (d, θ)
/// of the tube about the pivot, body axes of the side (3 × 6): w = d_z + θx (y − y_p) −
/// θy (x − x_p), and the plate FE's rotations β = −∇w, so pitch gives βx = θy and roll
/// βy = −θx. On the mirrored side (`side_sign` = −1) the grid's y is body −y: the roll column
/// reverses.
fn tube_motion(p: &Point3<f64>, pivot: &Point3<f64>, side_sign: f64) -> DMatrix<f64> {
    let mut a = DMatrix::<f64>::zeros(3, 6);
    a[(0, 2)] = 1.0;
    a[(0, 3)] = side_sign * (p.y - pivot.y);
    a[(0, 4)] = -(p.x - pivot.x);
    a[(1, 4)] = 1.0;
    a[(2, 3)] = -side_sign;
    a
}

/// The plate's consistent rigid mass about the pivot (6 × 6 on (d, θ), body axes of the right
/// side): bending mass on the tube motions of every node plus the in-plane `pivot_mass`.
fn consistent_rigid_mass(plate: &PlateModel, in_plane: &DMatrix<f64>) -> DMatrix<f64> {
    let grid = &plate.grid;
    let mut r = DMatrix::<f64>::zeros(3 * grid.n_nodes(), 6);
    for (node, p) in grid.positions_m.iter().enumerate() {
        let a = tube_motion(p, &grid.pivot_m, 1.0);
        for d in 0..3 {
            let eq = plate.bending_map.equation[3 * node + d].expect("free");
            r.row_mut(eq).copy_from(&a.row(d));
        }
    }
    // The slaving kinematics are the plate FE's own rigid motions: they strain nothing.
    let k = dense(&plate.assemble_stiffness(None));
    let strain = (&k * &r).amax();
    assert!(
        strain < 1e-9 * k.amax() * r.amax(),
        "rigid tube motions strain the free plate: |K R| = {strain:e}"
    );
    r.transpose() * dense(&plate.assemble_mass()) * r + in_plane
}

/// The free plate of one side coupled to the beam at its pivot: root nodes slaved to the pivot's
/// rigid motion, the in-plane rigid inertia returned as a 6 × 6 pivot mass.
///
/// `mirror` selects the left surface, the mirror image in y of the right-side grid: the plate's
/// own DOFs stay those of the right-side grid (w along body z, βx, βy as the FE defines them),
/// so a roll of the left tube, w = θx (y_L − y_pL) = −θx (y_R − y_pR), reverses the roll column.
fn plate_fe(
    plate: &PlateModel,
    beam_pivot: &DMatrix<f64>,
    mirror: bool,
    n_global: usize,
    first_global: usize,
) -> (PlateFe, DMatrix<f64>) {
    let grid = &plate.grid;
    let n_nodes = grid.n_nodes();
    let map = &plate.bending_map;
    assert_eq!(
        map.n_equations,
        3 * n_nodes,
        "free plate: every bending DOF"
    );
    let pivot = grid.pivot_m;
    let side_sign = if mirror { -1.0 } else { 1.0 };
    let is_root: Vec<bool> = (0..n_nodes).map(|n| grid.root_nodes.contains(&n)).collect();
    // The plate mid-plane is the pivot's plane: rotations about x and y move no mid-plane
    // point in-plane.
    for p in &grid.positions_m {
        assert!((p.z - pivot.z).abs() < 1e-12, "mid-plane through the pivot");
    }
    let mut transform = DMatrix::zeros(map.n_equations, n_global);
    let mut next = first_global;
    for (node, (&p, &root)) in grid
        .positions_m
        .iter()
        .zip(&is_root)
        .enumerate()
        .take(n_nodes)
    {
        if root {
            let rows = tube_motion(&p, &pivot, side_sign) * beam_pivot;
            for d in 0..3 {
                let eq = map.equation[3 * node + d].expect("free");
                for c in 0..beam_pivot.ncols() {
                    transform[(eq, c)] = rows[(d, c)];
                }
            }
        } else {
            for d in 0..3 {
                let eq = map.equation[3 * node + d].expect("free");
                transform[(eq, next)] = 1.0;
                next += 1;
            }
        }
    }
    // In-plane rigid inertia about the pivot from the consistent membrane mass: nodal
    // (u, v) = (u_P − θz (y − y_p), v_P + θz (x − x_p)) in body axes of the side; the grid's
    // own v is body −v on the mirrored (left) side.
    let mut in_plane = DMatrix::<f64>::zeros(3, 3);
    for (e, el) in grid.elements.iter().enumerate() {
        let mut r = DMatrix::<f64>::zeros(8, 3);
        for (k, &n) in el.iter().enumerate() {
            let p = grid.positions_m[n];
            let (x, y) = (p.x - pivot.x, side_sign * (p.y - pivot.y));
            r[(2 * k, 0)] = 1.0;
            r[(2 * k, 2)] = -y;
            r[(2 * k + 1, 1)] = side_sign;
            r[(2 * k + 1, 2)] = side_sign * x;
        }
        let me = DMatrix::from_fn(8, 8, |i, j| plate.membrane_mass[e][(i, j)]);
        in_plane += r.transpose() * me * &r;
    }
    let mut pivot_mass = DMatrix::<f64>::zeros(6, 6);
    for (a, &ia) in [0usize, 1, 5].iter().enumerate() {
        for (b, &ib) in [0usize, 1, 5].iter().enumerate() {
            pivot_mass[(ia, ib)] = in_plane[(a, b)];
        }
    }
    (
        PlateFe {
            mass: dense(&plate.assemble_mass()),
            stiffness: dense(&plate.assemble_stiffness(None)),
            transform,
            global_range: first_global..next,
        },
        pivot_mass,
    )
}

/// A coupled mode: frequency and the strain-energy shares (body, left, right).
#[derive(Debug, Clone)]
struct Mode {
    frequency_hz: f64,
    strain_shares: [f64; 3],
    kinetic_shares: [f64; 3],
    /// Correlation of the left and right plates' DOFs (right-grid DOFs on both): +1 for a
    /// mirror-symmetric mode, −1 for an antisymmetric one.
    symmetry: f64,
}

struct Reference {
    /// All modes, ascending, rigid-body ones included.
    modes: Vec<Mode>,
    total_mass_kg: f64,
}

fn region(loaded: &LoadedConfig, name: &str) -> RegionInfo {
    loaded.region(name).expect("region")
}

/// Builds and solves the monolithic model of `loaded`.
fn monolithic_reference(loaded: &LoadedConfig) -> Reference {
    let registry = hsv_core::testing::empty_registry();
    let body = region(loaded, "main_body");
    let beam_settings = body.model_settings(hsv_model_free_free_beam::NAME);
    let beam = FreeFreeBeam::from_context(&ModelContext::new(&body, registry, &beam_settings))
        .expect("beam");
    let right = region(loaded, "right_surface");
    let plate_settings_table = right.model_settings(hsv_model_ritz_plate::NAME);
    let ctx = ModelContext::new(&right, registry, &plate_settings_table);
    let plate_settings: hsv_model_ritz_plate::Settings = ctx.parse_settings().expect("settings");
    let material = plate_settings.material.resolve().expect("material");
    let (grid, _) = hsv_model_ritz_plate::structural_grid(&plate_settings, &ctx).expect("grid");
    // The clamped Ritz model of the same grid, for its mass properties (a consistency check).
    let ritz = RitzPlate::new(grid.clone(), material.clone(), &plate_settings).expect("ritz");
    let free = PlateModel::new(grid.clone(), material, Supports::free(grid.n_nodes()))
        .expect("free plate")
        .with_non_structural_mass(plate_settings.non_structural_mass_kg_m2);

    let n_beam = beam.beam_mesh().n_dof();
    let n_free_per_plate = 3 * (grid.n_nodes() - grid.root_nodes.len());
    let n_global = n_beam + 2 * n_free_per_plate;
    let pivot_right = grid.pivot_m;
    let pivot_left = Point3::new(pivot_right.x, -pivot_right.y, pivot_right.z);
    let s_left = pivot_kinematics(&beam, &pivot_left);
    let s_right = pivot_kinematics(&beam, &pivot_right);
    let (left, in_plane_left) = plate_fe(&free, &s_left, true, n_global, n_beam);
    let (right, in_plane_right) =
        plate_fe(&free, &s_right, false, n_global, n_beam + n_free_per_plate);
    assert_eq!(right.global_range.end, n_global);

    let mut m = DMatrix::<f64>::zeros(n_global, n_global);
    let mut k = DMatrix::<f64>::zeros(n_global, n_global);
    m.view_mut((0, 0), (n_beam, n_beam))
        .copy_from(beam.mass_matrix());
    k.view_mut((0, 0), (n_beam, n_beam))
        .copy_from(beam.stiffness_matrix());
    for (s, ip) in [(&s_left, &in_plane_left), (&s_right, &in_plane_right)] {
        let add = s.transpose() * ip * s;
        let mut block = m.view_mut((0, 0), (n_beam, n_beam));
        block += add;
    }
    for p in [&left, &right] {
        m += p.transform.transpose() * &p.mass * &p.transform;
        k += p.transform.transpose() * &p.stiffness * &p.transform;
    }
    // Exact symmetry for the eigen-solve.
    let m = (&m + m.transpose()) * 0.5;
    let k = (&k + k.transpose()) * 0.5;

    // Total mass from the rigid x translation of everything (beam DOF 0 of each node).
    let mut ones_x = DVector::<f64>::zeros(n_global);
    for node in 0..beam.beam_mesh().n_nodes() {
        ones_x[6 * node] = 1.0;
    }
    let mut ones_z = DVector::<f64>::zeros(n_global);
    for node in 0..beam.beam_mesh().n_nodes() {
        ones_z[6 * node + 2] = 1.0;
    }
    for p in [&left, &right] {
        // Non-root plate w DOFs follow a z translation too.
        let grid = &free.grid;
        let mut g = p.global_range.start;
        for node in 0..grid.n_nodes() {
            if !grid.root_nodes.contains(&node) {
                ones_z[g] = 1.0;
                g += 3;
            }
        }
    }
    let total_mass_kg = (ones_x.transpose() * &m * &ones_x)[(0, 0)];
    let mass_z = (ones_z.transpose() * &m * &ones_z)[(0, 0)];
    let surface_mass = MassDistribution::mass_properties(&ritz).mass_kg;
    let beam_mass = MassDistribution::mass_properties(&beam).mass_kg;
    eprintln!(
        "FE model: {n_global} DOFs; mass {total_mass_kg:.2} kg (x), {mass_z:.2} kg (z); beam \
         {beam_mass:.2} kg + 2 × surface {surface_mass:.2} kg (RitzPlate::mass_properties) = {:.2} kg",
        beam_mass + 2.0 * surface_mass
    );
    // The uncoupled components, to label the coupled modes.
    let beam_alone: Vec<String> = beam
        .elastic_modes()
        .omega2
        .iter()
        .zip(&beam.elastic_modes().kinds)
        .take(8)
        .map(|(w2, kind)| {
            format!(
                "{:.3} Hz {}",
                w2.sqrt() / std::f64::consts::TAU,
                kind.label()
            )
        })
        .collect();
    eprintln!("free-free beam alone: {}", beam_alone.join(", "));
    let clamped = ritz.natural_frequencies_hz().expect("plate frequencies");
    let clamped: Vec<String> = clamped
        .iter()
        .zip(&ritz.modal_model().names)
        .take(5)
        .map(|(f, name)| format!("{f:.4} Hz {name}"))
        .collect();
    eprintln!("surface clamped at the tube: {}", clamped.join(", "));
    // Rigid inertia of a surface about its pivot: consistent FE (used here) against the
    // lumped-node mass properties the partitioned model's pivot mass is built from.
    let consistent = consistent_rigid_mass(&free, &in_plane_right);
    let lumped = MassDistribution::mass_properties(&ritz).inertia_about(&pivot_right);
    eprintln!(
        "surface inertia about the pivot, kg m² (consistent FE / lumped mass properties): \
         roll {:.2} / {:.2}, pitch {:.2} / {:.2}, yaw {:.2} / {:.2}; mass {:.3} / {:.3} kg",
        consistent[(3, 3)],
        lumped[(0, 0)],
        consistent[(4, 4)],
        lumped[(1, 1)],
        consistent[(5, 5)],
        lumped[(2, 2)],
        consistent[(2, 2)],
        surface_mass
    );
    assert!(
        (total_mass_kg - (beam_mass + 2.0 * surface_mass)).abs() < 1e-9 * total_mass_kg,
        "x-translation mass matches the models' mass properties"
    );
    assert!(
        (mass_z - total_mass_kg).abs() < 1e-9 * total_mass_kg,
        "z-translation mass matches the x-translation mass"
    );

    // K v = ω² M v: M = L Lᵀ, A = L⁻¹ K L⁻ᵀ, v = L⁻ᵀ y.
    let chol = m.clone().cholesky().expect("M positive definite");
    let l = chol.l();
    let l_inv = l
        .clone()
        .solve_lower_triangular(&DMatrix::identity(n_global, n_global))
        .expect("L invertible");
    let a = &l_inv * &k * l_inv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let eigen = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..n_global).collect();
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let n_keep = 40.min(n_global);
    let modes = order[..n_keep]
        .iter()
        .map(|&i| {
            let y = eigen.eigenvectors.column(i);
            let v = l_inv.transpose() * y;
            let beam_part = v.rows(0, n_beam).into_owned();
            let strain_beam =
                (beam_part.transpose() * beam.stiffness_matrix() * &beam_part)[(0, 0)];
            let kin_beam = (beam_part.transpose() * beam.mass_matrix() * &beam_part)[(0, 0)];
            let mut strain = [strain_beam, 0.0, 0.0];
            let mut kinetic = [kin_beam, 0.0, 0.0];
            for (slot, (p, (s, ip))) in [
                (&left, (&s_left, &in_plane_left)),
                (&right, (&s_right, &in_plane_right)),
            ]
            .into_iter()
            .enumerate()
            {
                let u = &p.transform * &v;
                strain[slot + 1] = (u.transpose() * &p.stiffness * &u)[(0, 0)];
                let d = s * &beam_part;
                kinetic[slot + 1] =
                    (u.transpose() * &p.mass * &u)[(0, 0)] + (d.transpose() * ip * &d)[(0, 0)];
            }
            let (l, r) = (
                v.rows_range(left.global_range.clone()),
                v.rows_range(right.global_range.clone()),
            );
            let symmetry = l.dot(&r) / (l.norm() * r.norm()).max(f64::MIN_POSITIVE);
            let ts: f64 = strain.iter().sum();
            let tk: f64 = kinetic.iter().sum();
            let lam = eigen.eigenvalues[i];
            Mode {
                frequency_hz: lam.max(0.0).sqrt() / std::f64::consts::TAU,
                strain_shares: strain.map(|e| e / ts.max(f64::MIN_POSITIVE)),
                kinetic_shares: kinetic.map(|e| e / tk),
                symmetry,
            }
        })
        .collect();
    Reference {
        modes,
        total_mass_kg,
    }
}

#[test]
fn partitioned_in_vacuo_modes_match_a_monolithic_finite_element_model() {
    let text = config_text();
    let loaded = parse_config(&text, "test.toml").expect("config");

    let reference = monolithic_reference(&loaded);
    assert!(reference.total_mass_kg > 0.0);
    let fe = &reference.modes;
    // Six rigid-body modes, then the elastic ones.
    let first_elastic = fe[6].frequency_hz;
    for m in &fe[..6] {
        assert!(
            m.frequency_hz < 1e-3 * first_elastic,
            "rigid-body mode at {} Hz (first elastic {first_elastic} Hz)",
            m.frequency_hz
        );
    }
    let fe_elastic: Vec<&Mode> = fe[6..].iter().collect();

    let registry = hsv_run::registry().expect("registry");
    let mut v = hsv_run::vehicle::flexible_vehicle_with(
        &loaded,
        &registry,
        SurfaceModel::Partitioned,
        false,
        "test",
    )
    .expect("vehicle");
    let modes = v.in_vacuo_modes().expect("modes");
    assert_eq!(
        modes.regions,
        ["main_body", "left_surface", "right_surface"],
        "region order (the FE shares are body, left, right)"
    );
    eprintln!(
        "partitioned: {} coupled coordinates, mass asymmetry {:.2e}",
        modes.modes.len(),
        modes.mass_asymmetry
    );

    eprintln!(
        "{:>4} {:>5} {:>11} {:>11} {:>9}   {:<26} {:<26} {:<26}",
        "mode",
        "sym",
        "FE Hz",
        "part. Hz",
        "rel. err",
        "FE strain (B, L, R)",
        "part. strain (B, L, R)",
        "FE kinetic (B, L, R)"
    );
    let shares = |s: &[f64]| format!("{:.3} {:.3} {:.3}", s[0], s[1], s[2]);
    let rows = 14.min(fe_elastic.len()).min(modes.modes.len());
    let mut worst: f64 = 0.0;
    for (i, (a, b)) in fe_elastic.iter().zip(&modes.modes).enumerate().take(rows) {
        let err = (b.frequency_hz - a.frequency_hz) / a.frequency_hz;
        if i < COMPARED {
            worst = worst.max(err.abs());
        }
        eprintln!(
            "{:>4} {:>+5.2} {:>11.4} {:>11.4} {:>+9.4}%  {:<26} {:<26} {:<26}",
            i + 1,
            a.symmetry,
            a.frequency_hz,
            b.frequency_hz,
            100.0 * err,
            shares(&a.strain_shares),
            shares(&b.strain_energy_shares),
            shares(&a.kinetic_shares),
        );
    }
    eprintln!(
        "worst relative error of the first {COMPARED}: {:.3} % (tolerance {:.1} %)",
        100.0 * worst,
        100.0 * TOLERANCE
    );

    // Strain-energy shares, mode by mode, over the compared modes.
    for (i, (fe, part)) in fe_elastic
        .iter()
        .zip(&modes.modes)
        .enumerate()
        .take(COMPARED)
    {
        let (a, b) = (&fe.strain_shares, &part.strain_energy_shares);
        for r in 0..3 {
            assert!(
                (a[r] - b[r]).abs() <= SHARE_TOLERANCE,
                "coupled elastic mode {}: {} strain share partitioned {:.4} vs FE {:.4}",
                i + 1,
                modes.regions[r],
                b[r],
                a[r]
            );
        }
    }

    // The modes near 9 Hz (8-10 Hz: the surfaces' clamped first bending, 8.87 Hz, and the
    // body's first vertical bending, 9.51 Hz): the symmetric pair that the surface bending and
    // the body's vertical bending form has body and surface strain shares above 0.1 in both
    // models. The antisymmetric surface-bending mode between them (9.19 Hz) has a body strain
    // share of only ≈ 0.07 in both models (kinetic ≈ 0.13 in the FE model): it is not held to
    // the 0.1, which is a property of the structure, not of the partitioned interface.
    let near = |f: f64| (8.0..10.0).contains(&f);
    let mixed = |s: &[f64]| s[0] > 0.1 && s[1] + s[2] > 0.1;
    let fe_near: Vec<&&Mode> = fe_elastic.iter().filter(|m| near(m.frequency_hz)).collect();
    let part_near: Vec<_> = modes
        .modes
        .iter()
        .filter(|m| near(m.frequency_hz))
        .collect();
    assert_eq!(fe_near.len(), part_near.len(), "modes between 8 and 10 Hz");
    for (a, b) in fe_near.iter().zip(&part_near) {
        eprintln!(
            "near 9 Hz: FE {:.4} Hz ({}) shares {}, partitioned {:.4} Hz shares {}",
            a.frequency_hz,
            if a.symmetry > 0.0 {
                "symmetric"
            } else {
                "antisymmetric"
            },
            shares(&a.strain_shares),
            b.frequency_hz,
            shares(&b.strain_energy_shares)
        );
    }
    let fe_mixed: Vec<f64> = fe_near
        .iter()
        .filter(|m| mixed(&m.strain_shares))
        .map(|m| m.frequency_hz)
        .collect();
    let part_mixed: Vec<f64> = part_near
        .iter()
        .filter(|m| mixed(&m.strain_energy_shares))
        .map(|m| m.frequency_hz)
        .collect();
    assert!(
        fe_mixed.len() >= 2 && part_mixed.len() == fe_mixed.len(),
        "body-surface modes near 9 Hz (body and surface strain shares > 0.1): FE {fe_mixed:?}, \
         partitioned {part_mixed:?}"
    );
    for m in fe_near.iter().filter(|m| mixed(&m.strain_shares)) {
        assert!(
            m.symmetry > 0.99,
            "the body-surface pair near 9 Hz is symmetric"
        );
    }

    for (i, (fe, part)) in fe_elastic
        .iter()
        .zip(&modes.modes)
        .enumerate()
        .take(COMPARED)
    {
        let (a, b) = (fe.frequency_hz, part.frequency_hz);
        assert!(
            ((b - a) / a).abs() <= TOLERANCE,
            "coupled elastic mode {}: partitioned {b:.4} Hz vs FE {a:.4} Hz ({:+.3} %, tolerance \
             {:.1} %)",
            i + 1,
            100.0 * (b - a) / a,
            100.0 * TOLERANCE
        );
    }
}
