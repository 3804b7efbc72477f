//! Validation of `ritz-plate` against plate theory: Leissa's frequencies, classical thermal
//! buckling, E(T) scaling, Ritz reduction, orthogonality and statics. Each test names its
//! source and tolerance.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use hsv_core::material::Material;
use hsv_core::structure::{StructureModel, ThermalStiffness};
use hsv_core::surface_grid::{GridEdge, SurfaceGrid};
use hsv_model_ritz_plate::plate::{PlateModel, Supports};
use hsv_model_ritz_plate::{RitzPlate, Settings};
use nalgebra::DVector;

const E: f64 = 70e9;
const NU: f64 = 0.3;
const RHO: f64 = 2700.0;
const ALPHA: f64 = 23e-6;

/// Aluminium-like constant material (the checks are non-dimensional), valid 100-1000 K.
fn constant_material() -> Material {
    Material::constant(
        "test alloy",
        RHO,
        NU,
        E,
        ALPHA,
        150.0,
        900.0,
        (100.0, 1000.0),
    )
    .expect("material")
}

/// Flexural rigidity D = E h³ / (12 (1 − ν²)).
fn rigidity(h: f64) -> f64 {
    E * h.powi(3) / (12.0 * (1.0 - NU * NU))
}

/// Frequency parameter λ = ω a² √(ρ h / D) (Leissa, NASA SP-160, 1969, ch. 4).
fn lambda(f_hz: f64, a: f64, h: f64) -> f64 {
    2.0 * PI * f_hz * a * a * (RHO * h / rigidity(h)).sqrt()
}

/// Square plate of side a = 1 m, h = 5 mm (h/a = 0.005: thin, transverse shear < 0.1 %).
const A: f64 = 1.0;
const H: f64 = 0.005;

/// Square plate, hard simple support (w = 0 and the tangential rotation held) and in-plane
/// immovable edges.
fn ssss_supports(grid: &SurfaceGrid) -> Supports {
    let mut s = Supports::free(grid.n_nodes());
    for e in [
        GridEdge::Root,
        GridEdge::Tip,
        GridEdge::LeadingEdge,
        GridEdge::TrailingEdge,
    ] {
        s = s
            .simply_support(grid, e)
            .restrain_in_plane(&grid.edge_nodes(e));
    }
    s
}

fn ssss(n: usize) -> PlateModel {
    let grid = SurfaceGrid::rectangular(A, A, H, n, n).expect("grid");
    let s = ssss_supports(&grid);
    PlateModel::new(grid, constant_material(), s).expect("plate")
}

/// SSSS square plate: λ = π² (m² + n²) exactly (Leissa, Vibration of Plates, NASA SP-160,
/// 1969, ch. 4, the SSSS closed form): 19.739, 49.348, 49.348, 78.957, 98.696, 98.696. Within 1 %
/// on a 40 × 40 MITC4 mesh.
#[test]
fn ssss_square_plate_matches_leissa_within_one_percent() {
    let exact = [2.0, 5.0, 5.0, 8.0, 10.0, 10.0].map(|k: f64| PI * PI * k);
    let errors = |n: usize| -> Vec<f64> {
        let f = ssss(n).frequencies_hz(None, 6).expect("modes");
        f.iter()
            .zip(exact)
            .enumerate()
            .map(|(i, (&fi, ex))| {
                let l = lambda(fi, A, H);
                eprintln!("SSSS {n}x{n} mode {}: λ = {l:.4} (Leissa {ex:.4})", i + 1);
                (l / ex - 1.0).abs()
            })
            .collect()
    };
    let fine = errors(40);
    assert!(fine.iter().all(|&e| e < 0.01), "{fine:?}");
    // Converging with the mesh: the 16 × 16 errors are larger, mode by mode.
    let coarse = errors(16);
    assert!(
        coarse.iter().zip(&fine).all(|(c, f)| c > f),
        "{coarse:?} vs {fine:?}"
    );
}

/// CFFF (cantilever) square plate, ν = 0.3: λ = 3.492, 8.525, 21.43, 27.33, 31.11 (Leissa,
/// NASA SP-160, 1969, ch. 4; Leissa, "The free vibration of rectangular plates", J. Sound Vib.
/// 31(3) 1973 257-293, a/b = 1). Within 1 % on a
/// 32 × 32 mesh.
#[test]
fn cantilever_square_plate_matches_leissa_within_one_percent() {
    let grid = SurfaceGrid::rectangular(A, A, H, 32, 32).expect("grid");
    let s = Supports::free(grid.n_nodes()).clamp(&grid.root_nodes.clone());
    let plate = PlateModel::new(grid, constant_material(), s).expect("plate");
    let f = plate.frequencies_hz(None, 5).expect("modes");
    for (i, (&fi, ex)) in f
        .iter()
        .zip([3.492, 8.525, 21.43, 27.33, 31.11])
        .enumerate()
    {
        let l = lambda(fi, A, H);
        eprintln!("CFFF mode {}: λ = {l:.4} (Leissa {ex})", i + 1);
        assert_relative_eq!(l, ex, max_relative = 0.01);
    }
}

fn sample_surface() -> hsv_core::geometry::LiftingSurfaceConfig {
    hsv_core::config::LoadedConfig::sample()
        .expect("sample")
        .config
        .lifting_surface
}

fn sample_ritz(settings: &Settings) -> RitzPlate {
    ritz_on(&sample_surface(), settings)
}

fn ritz_on(surface: &hsv_core::geometry::LiftingSurfaceConfig, settings: &Settings) -> RitzPlate {
    let grid = SurfaceGrid::lifting_surface(
        surface,
        hsv_core::geometry::Side::Right,
        settings.elements_chordwise,
        settings.elements_spanwise,
    )
    .expect("grid");
    RitzPlate::new(grid, Material::ti_6al_4v(), settings).expect("model")
}

/// Thermal buckling of a uniformly heated SSSS square plate with immovable edges: membrane
/// force N = E h α ΔT / (1 − ν) (Boley & Weiner, Theory of Thermal Stresses, 1960:
/// plane stress with the free expansion fully restrained) reaches the biaxial buckling load
/// N_cr = π² D (1/a² + 1/b²) (Timoshenko & Gere, Theory of Elastic Stability, 2nd ed., 1961,
/// ch. 9, biaxial compression, m = n = 1) at ΔT_cr = π² h² (1/a² + 1/b²) / (12 (1 + ν) α) (Gossard, Seide & Roberts,
/// NACA TN 2771, 1952). Below it the fundamental frequency falls as ω = ω₀ √(1 − ΔT/ΔT_cr)
/// (the prestressed SSSS plate keeps the sin-sin mode shape, so ω² = ω₀² (1 − N/N_cr); Leissa,
/// NASA SP-160, 1969, plates with in-plane forces). Reduced (Ritz) model on a 24 × 24 mesh:
/// frequency ratios within 1 %, buckling
/// reported between 0.98 and 1.02 ΔT_cr.
#[test]
fn uniformly_heated_restrained_plate_buckles_near_the_classical_temperature() {
    let h = 0.01;
    let grid = SurfaceGrid::rectangular(A, A, h, 24, 24).expect("grid");
    let supports = ssss_supports(&grid);
    let n = grid.n_nodes();
    let mut model =
        RitzPlate::with_supports(grid, constant_material(), supports, &Settings::default())
            .expect("model");
    let dt_cr = PI * PI * h * h * 2.0 / (12.0 * (1.0 + NU) * ALPHA);
    let f0 = model.natural_frequencies_hz().expect("cold")[0];
    // The cold plate's fundamental mode against Leissa, as a sanity anchor (1 %).
    assert_relative_eq!(lambda(f0, A, h), 2.0 * PI * PI, max_relative = 0.01);
    for ratio in [0.25, 0.5, 0.75, 0.9] {
        model
            .set_temperatures(&vec![293.0 + ratio * dt_cr; n])
            .expect("heated");
        let f = model.natural_frequencies_hz().expect("not yet buckled")[0];
        eprintln!(
            "ΔT/ΔT_cr = {ratio}: f/f0 = {:.4} (theory {:.4})",
            f / f0,
            (1.0 - ratio).sqrt()
        );
        assert_relative_eq!(f / f0, (1.0f64 - ratio).sqrt(), max_relative = 0.01);
        // Membrane force of fully restrained expansion (Boley & Weiner), 1e-9.
        let nxx = model.membrane_resultants()[100][0];
        assert_relative_eq!(
            nxx,
            -E * h * ALPHA * ratio * dt_cr / (1.0 - NU),
            max_relative = 1e-9
        );
    }
    model
        .set_temperatures(&vec![293.0 + 0.98 * dt_cr; n])
        .expect("heated");
    assert!(model.natural_frequencies_hz().is_ok());
    model
        .set_temperatures(&vec![293.0 + 1.02 * dt_cr; n])
        .expect("heated");
    let err = model.natural_frequencies_hz().unwrap_err().to_string();
    eprintln!("{err}");
    assert!(
        err.contains("buckled") && err.contains("mode 1") && err.contains("e"),
        "{err}"
    );
}

/// Uniform heating with free in-plane expansion (in-plane supports statically determinate)
/// causes no thermal stress, so every frequency scales with √(E(T)/E(293 K)) (ω² ∝ D ∝ E,
/// mass unchanged). Ti-6Al-4V at 600 K and 900 K; reduced model vs that scaling within 1e-9,
/// resultants below 1e-6 of the fully restrained value.
#[test]
fn free_expansion_scales_frequencies_with_the_square_root_of_the_modulus() {
    let grid =
        SurfaceGrid::lifting_surface(&sample_surface(), hsv_core::geometry::Side::Right, 12, 8)
            .expect("grid");
    let root = grid.edge_nodes(GridEdge::Root);
    let mut supports = Supports::free(grid.n_nodes());
    for &n in &root {
        supports.bending[n] = [true; 3];
    }
    let supports = supports
        .restrain_in_plane(&[root[0]])
        .hold_v(&[root[root.len() - 1]]);
    let n = grid.n_nodes();
    let ti = Material::ti_6al_4v();
    let mut model =
        RitzPlate::with_supports(grid, ti.clone(), supports, &Settings::default()).expect("model");
    let f0 = model.natural_frequencies_hz().expect("cold");
    for t in [600.0, 900.0] {
        model.set_temperatures(&vec![t; n]).expect("heated");
        let f = model.natural_frequencies_hz().expect("hot");
        let scale =
            (ti.youngs_modulus_pa(t).unwrap() / ti.youngs_modulus_pa(293.0).unwrap()).sqrt();
        for (a, b) in f.iter().zip(&f0) {
            assert_relative_eq!(a / b, scale, max_relative = 1e-9);
        }
        let restrained = ti.youngs_modulus_pa(t).unwrap() * 0.1 * ti.thermal_strain(t).unwrap();
        let worst = model
            .membrane_resultants()
            .iter()
            .flat_map(|r| r.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(worst < 1e-6 * restrained, "resultant {worst} N/m");
    }
}

/// Rayleigh-Ritz on a subspace containing the first N eigenvectors reproduces them exactly
/// (Bathe, Finite Element Procedures, 1996, Rayleigh-Ritz analysis): the 10 free-vibration frequencies of the
/// reduced model equal the full model's within 1e-8 at 293 K. Heated (hot leading edge,
/// 293-700 K, root held: thermal stress and E(T)), the reduced frequencies bound the full
/// model's from above (Rayleigh-Ritz), the 5 static shapes reduce every error, and the
/// 10 + 5 basis is within 2 % of the full model.
#[test]
fn ritz_basis_reproduces_the_free_modes_and_static_shapes_improve_the_heated_response() {
    let settings = Settings {
        elements_chordwise: 12,
        elements_spanwise: 10,
        ..Settings::default()
    };
    // A 5 % section: the sample's 2.8 % buckles under this 700 K leading edge, and the test is
    // about the Ritz basis, not the sample.
    let surface = hsv_core::geometry::LiftingSurfaceConfig {
        thickness_to_chord: 0.05,
        ..sample_surface()
    };
    let full_basis = ritz_on(&surface, &settings);
    let modes_only = ritz_on(
        &surface,
        &Settings {
            static_shapes: 0,
            ..settings.clone()
        },
    );
    let plate = full_basis.plate();
    let f_full = plate.frequencies_hz(None, 10).expect("full");
    let f_ritz = full_basis.natural_frequencies_hz().expect("ritz");
    for (a, b) in f_ritz.iter().zip(&f_full) {
        assert_relative_eq!(a, b, max_relative = 1e-8);
    }
    // Hot leading edge: T falls linearly from 700 K at the leading edge to 293 K at mid-chord.
    let g = &plate.grid;
    let temps: Vec<f64> = (0..g.n_nodes())
        .map(|n| {
            let u = g.chord_fractions[n % g.nodes_chordwise()];
            293.0 + 407.0 * (1.0 - 2.0 * u).max(0.0)
        })
        .collect();
    let hot_full = plate.frequencies_hz(Some(&temps), 10).expect("full heated");
    let mut with_static = full_basis.clone();
    with_static.set_temperatures(&temps).expect("heated");
    let mut without = modes_only.clone();
    without.set_temperatures(&temps).expect("heated");
    let a = with_static.natural_frequencies_hz().expect("ritz heated");
    let b = without.natural_frequencies_hz().expect("ritz heated");
    for i in 0..10 {
        let (ea, eb) = (a[i] / hot_full[i] - 1.0, b[i] / hot_full[i] - 1.0);
        eprintln!(
            "mode {}: full {:.3} Hz (cold {:.3}), 10+5 {:.3} ({:+.2e}), 10+0 {:.3} ({:+.2e})",
            i + 1,
            hot_full[i],
            f_full[i],
            a[i],
            ea,
            b[i],
            eb
        );
        assert!(
            ea > -1e-9 && eb >= ea - 1e-9,
            "mode {}: {ea} vs {eb}",
            i + 1
        );
        assert!(ea < 0.02, "mode {}: {ea}", i + 1);
    }
    assert!(
        hot_full[0] < f_full[0],
        "heating lowers the fundamental frequency"
    );
}

/// Modal orthogonality: the Ritz basis is M-orthonormal (Φᵀ M Φ = I) and K-orthogonal at
/// 293 K (Φᵀ K Φ = diag ω²), checked on the assembled full-order matrices to 1e-9.
#[test]
fn ritz_basis_is_mass_orthonormal_and_stiffness_orthogonal() {
    let model = sample_ritz(&Settings::default());
    let plate = model.plate();
    let (k, m) = (plate.assemble_stiffness(None), plate.assemble_mass());
    let b = model.basis();
    let r = b.ncols();
    let mut mb = b.clone();
    let mut kb = b.clone();
    for c in 0..r {
        let col: Vec<f64> = b.column(c).iter().copied().collect();
        let mut out = vec![0.0; col.len()];
        m.mul_vec(&col, &mut out);
        mb.column_mut(c).copy_from_slice(&out);
        k.mul_vec(&col, &mut out);
        kb.column_mut(c).copy_from_slice(&out);
    }
    let mr = b.transpose() * mb;
    let kr = b.transpose() * kb;
    let scale = kr.diagonal().max();
    for i in 0..r {
        for j in 0..r {
            let id = if i == j { 1.0 } else { 0.0 };
            assert!(
                (mr[(i, j)] - id).abs() < 1e-9,
                "M_r[{i},{j}] = {}",
                mr[(i, j)]
            );
            if i != j {
                assert!(
                    kr[(i, j)].abs() < 1e-9 * scale,
                    "K_r[{i},{j}] = {}",
                    kr[(i, j)]
                );
            }
        }
        // The reduced stiffness assembled from per-element contributions agrees (1e-9).
        assert_relative_eq!(
            model.modal_model().stiffness[(i, i)],
            kr[(i, i)],
            max_relative = 1e-9
        );
    }
}

/// Statics: under a uniform pressure p on the sample surface the reduced static solution
/// (the uniform-pressure shape is in the basis, so it is the full-order solution) gives root
/// reactions equal to the applied load: F_z = p S and M = Σ (r − r_pivot) × F about the pivot
/// (Newton's third law on the free-body of the surface), to 1e-6. These are the
/// mode-displacement reactions of `RitzPlate::root_loads_by_mode_displacement`, which see the free nodes' share;
/// force summation (tests/loads.rs) adds the root row's own.
#[test]
fn root_loads_balance_a_uniform_pressure() {
    let model = sample_ritz(&Settings::default());
    let plate = model.plate();
    let g = &plate.grid;
    let p = 5.0e4;
    let nodal = plate.to_equations(|n| [p * g.node_areas_m2[n], 0.0, 0.0]);
    let q_gen = model.basis().transpose() * DVector::from_vec(nodal);
    let k_r = &model.modal_model().stiffness;
    let q = k_r.clone().lu().solve(&q_gen).expect("solve");
    let zero = DVector::zeros(q.len());
    let loads = model
        .root_loads_by_mode_displacement(&q, &zero, &zero)
        .expect("loads");
    // Applied load over the free nodes (the root nodes' share goes straight to the tube).
    let free: Vec<usize> = (0..g.n_nodes())
        .filter(|n| !g.root_nodes.contains(n))
        .collect();
    let fz: f64 = free.iter().map(|&n| p * g.node_areas_m2[n]).sum();
    let pivot = g.pivot_m;
    let my: f64 = free
        .iter()
        .map(|&n| -(g.positions_m[n].x - pivot.x) * p * g.node_areas_m2[n])
        .sum();
    let mx: f64 = free
        .iter()
        .map(|&n| (g.positions_m[n].y - pivot.y) * p * g.node_areas_m2[n])
        .sum();
    eprintln!("root loads {loads:?}; applied Fz {fz}, Mx {mx}, My {my}");
    assert_relative_eq!(loads.force_n.z, fz, max_relative = 1e-6);
    assert_relative_eq!(loads.moment_nm.x, mx, max_relative = 1e-6);
    assert_relative_eq!(loads.moment_nm.y, my, max_relative = 1e-6);
    assert!(loads.force_n.x.abs() < 1e-9 * fz && loads.moment_nm.z.abs() < 1e-6 * mx.abs());
}
