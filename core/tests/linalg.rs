//! hsv_core::linalg against closed forms: the 1-D Laplacian (tridiag(−1, 2, −1), eigenvalues
//! 2 − 2 cos(kπ/(n+1)), eigenvectors sin(ikπ/(n+1)); Golub & Van Loan, Matrix Computations,
//! 4th ed., §4.8.3), the linear finite-element string (Bathe, Finite Element Procedures, 1996,
//! §10.3: discrete frequencies of a uniform chain), the damped oscillator's state matrix
//! (λ = −ζω ± iω√(1−ζ²)), and residual checks of a random matrix.

use std::f64::consts::PI;

use hsv_core::testing::{CountingAllocator, allocations};

use hsv_core::linalg::{
    BandedMatrix, EigenError, NotPositiveDefinite, SymmetricEigenSolver, general_eigen,
    generalized_symmetric_eigen, lowest_banded_eigenpairs, reverse_cuthill_mckee,
};
use nalgebra::{Complex, DMatrix, DVector};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Eigenvalue k (1-based) of the n × n 1-D Laplacian tridiag(−1, 2, −1).
fn laplacian_eigenvalue(k: usize, n: usize) -> f64 {
    2.0 - 2.0 * (k as f64 * PI / (n + 1) as f64).cos()
}

fn banded_laplacian(n: usize) -> BandedMatrix {
    let mut a = BandedMatrix::zeros(n, 1);
    for i in 0..n {
        a.add(i, i, 2.0);
        if i > 0 {
            a.add(i, i - 1, -1.0);
        }
    }
    a
}

fn dense_laplacian(n: usize) -> DMatrix<f64> {
    DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => 2.0,
        1 => -1.0,
        _ => 0.0,
    })
}

#[test]
fn banded_solve_inverts_the_laplacian_on_its_sine_eigenvectors() {
    // A v_k = λ_k v_k with v_k(i) = sin((i+1)kπ/(n+1)), so A⁻¹ v_k = v_k / λ_k exactly;
    // factor once, solve for every k. Tolerance 1e-12 relative (cond(A) ≈ 4(n+1)²/π² ≈ 1e3).
    let n = 40;
    let mut a = banded_laplacian(n);
    let mut y = vec![0.0; n];
    let ones = vec![1.0; n];
    a.mul_vec(&ones, &mut y);
    assert_eq!((y[0], y[1], y[n - 1]), (1.0, 0.0, 1.0));
    a.factorize().expect("the Laplacian is SPD");
    let mut b = vec![0.0; n];
    for k in 1..=n {
        let v: Vec<f64> = (0..n)
            .map(|i| ((i + 1) as f64 * k as f64 * PI / (n + 1) as f64).sin())
            .collect();
        b.copy_from_slice(&v);
        let before = allocations();
        a.solve_in_place(&mut b);
        assert_eq!(allocations(), before, "solve_in_place allocated");
        let lambda = laplacian_eigenvalue(k, n);
        let err = b
            .iter()
            .zip(&v)
            .map(|(x, vi)| (x - vi / lambda).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-12 / lambda, "k = {k}: error {err:e}");
    }
    // A x = 1 has x_i = (i+1)(n−i)/2 (discrete Poisson problem with Dirichlet ends).
    b.fill(1.0);
    a.solve_in_place(&mut b);
    for (i, x) in b.iter().enumerate() {
        let exact = ((i + 1) * (n - i)) as f64 / 2.0;
        assert!((x - exact).abs() < 1e-12 * exact, "{x} vs {exact}");
    }
}

#[test]
fn banded_solve_matches_a_dense_solve_for_a_wider_band() {
    let n = 30;
    let mut band = BandedMatrix::zeros(n, 3);
    let mut dense = DMatrix::<f64>::zeros(n, n);
    for i in 0..n {
        for (off, v) in [(0usize, 8.0 + i as f64), (1, -1.5), (2, -0.7), (3, 0.3)] {
            if i + off < n {
                band.add(i, i + off, v);
                dense[(i + off, i)] += v;
                if off > 0 {
                    dense[(i, i + off)] += v;
                }
            }
        }
    }
    assert_eq!(band.get(5, 8), dense[(5, 8)]);
    let rhs = DVector::from_fn(n, |i, _| (i as f64).sin() + 1.0);
    let expected = dense.lu().solve(&rhs).expect("non-singular");
    band.factorize().expect("SPD");
    assert!(band.is_factored());
    let mut x = rhs.as_slice().to_vec();
    band.solve_in_place(&mut x);
    for (u, v) in x.iter().zip(expected.iter()) {
        assert!((u - v).abs() < 1e-13, "{u} vs {v}");
    }
    band.clear();
    assert!(!band.is_factored());
}

#[test]
fn indefinite_and_singular_banded_matrices_are_reported() {
    // [[1, 2], [2, 1]] has eigenvalues 3 and −1: the second pivot is 1 − 4 = −3.
    let mut a = BandedMatrix::zeros(2, 1);
    a.add(0, 0, 1.0);
    a.add(1, 0, 2.0);
    a.add(1, 1, 1.0);
    assert_eq!(
        a.factorize(),
        Err(NotPositiveDefinite {
            row: 1,
            pivot: -3.0
        })
    );
    // A free-free chain (no support) is singular: the last pivot vanishes.
    let mut free = BandedMatrix::zeros(4, 1);
    for i in 0..3 {
        free.add(i, i, 1.0);
        free.add(i + 1, i + 1, 1.0);
        free.add(i + 1, i, -1.0);
    }
    assert_eq!(free.factorize().map_err(|e| e.row), Err(3));
}

#[test]
fn reverse_cuthill_mckee_orders_a_scrambled_path_with_unit_bandwidth() {
    // The path 0-3-1-4-2: RCM must number it contiguously.
    let adjacency = vec![vec![3], vec![3, 4], vec![4], vec![0, 1], vec![1, 2]];
    let order = reverse_cuthill_mckee(&adjacency);
    let mut position = [0; 5];
    for (new, &old) in order.iter().enumerate() {
        position[old] = new;
    }
    for (i, neighbours) in adjacency.iter().enumerate() {
        for &j in neighbours {
            assert_eq!(position[i].abs_diff(position[j]), 1);
        }
    }
}

#[test]
fn symmetric_solver_reproduces_the_laplacian_spectrum_without_allocating() {
    let n = 12;
    let a = dense_laplacian(n);
    let mut solver = SymmetricEigenSolver::new(n);
    let mut values = vec![0.0; n];
    let mut vectors = DMatrix::zeros(n, n);
    solver
        .decompose(&a, &mut values, &mut vectors)
        .expect("converges");
    let before = allocations();
    solver
        .decompose(&a, &mut values, &mut vectors)
        .expect("converges");
    assert_eq!(allocations(), before, "decompose allocated");
    for (k, v) in values.iter().enumerate() {
        let exact = laplacian_eigenvalue(k + 1, n);
        assert!((v - exact).abs() < 1e-13, "{v} vs {exact}");
        let r = &a * vectors.column(k) - vectors.column(k) * *v;
        assert!(r.norm() < 1e-13);
    }
    let orthogonality = vectors.transpose() * &vectors - DMatrix::identity(n, n);
    assert!(orthogonality.norm() < 1e-13);
    let mut short = vec![0.0; n - 1];
    assert!(matches!(
        solver.decompose(&a, &mut short, &mut vectors),
        Err(EigenError::Shape { .. })
    ));
}

/// Linear finite-element string of n interior nodes, spacing h, tension T, density ρ, ends
/// fixed: K = (T/h) tridiag(−1, 2, −1), consistent M = (ρh/6) tridiag(1, 4, 1) = (ρh/6)(6I − A).
/// K and M share the sine eigenvectors, so ω_k² = (T/h) a_k / ((ρh/6)(6 − a_k)),
/// a_k = 2 − 2 cos(kπ/(n+1)) (Bathe 1996, §10.3; the FE string's discrete dispersion relation).
fn fe_string(n: usize) -> (f64, f64, Vec<f64>) {
    let (length_m, tension_n, density_kg_m) = (2.0, 150.0, 0.3);
    let h = length_m / (n + 1) as f64;
    let (k_scale, m_scale) = (tension_n / h, density_kg_m * h / 6.0);
    let exact = (1..=n)
        .map(|k| {
            let a = laplacian_eigenvalue(k, n);
            k_scale * a / (m_scale * (6.0 - a))
        })
        .collect();
    (k_scale, m_scale, exact)
}

fn check_generalized(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    values: &[f64],
    vectors: &DMatrix<f64>,
    tolerance: f64,
) {
    let modal_mass = vectors.transpose() * m * vectors;
    let id = DMatrix::identity(values.len(), values.len());
    assert!((modal_mass - id).norm() < 1e-10, "not M-orthonormal");
    for (c, lam) in values.iter().enumerate() {
        let v = vectors.column(c);
        let r = k * v - (m * v) * *lam;
        let relative = r.norm() / (lam.abs() * (m * v).norm());
        assert!(
            relative < tolerance,
            "mode {c}: relative residual {relative:e}"
        );
    }
}

#[test]
fn dense_generalized_eigenpairs_of_a_fe_string_match_the_closed_form() {
    let n = 25;
    let (k_scale, m_scale, exact) = fe_string(n);
    let a = dense_laplacian(n);
    let k = &a * k_scale;
    let m = (DMatrix::identity(n, n) * 6.0 - &a) * m_scale;
    let all = generalized_symmetric_eigen(&k, &m, n).expect("solves");
    for (v, e) in all.values.iter().zip(&exact) {
        assert!((v / e - 1.0).abs() < 1e-12, "{v} vs {e}");
    }
    check_generalized(&k, &m, &all.values, &all.vectors, 1e-12);
    let lowest = generalized_symmetric_eigen(&k, &m, 4).expect("solves");
    assert_eq!(lowest.values.len(), 4);
    assert_eq!(lowest.vectors.ncols(), 4);
    assert_eq!(lowest.values[..], all.values[..4]);
}

#[test]
fn banded_subspace_iteration_finds_the_lowest_fe_string_modes() {
    let n = 200;
    let (k_scale, m_scale, exact) = fe_string(n);
    let mut k = BandedMatrix::zeros(n, 1);
    let mut m = BandedMatrix::zeros(n, 1);
    for i in 0..n {
        k.add(i, i, 2.0 * k_scale);
        m.add(i, i, 4.0 * m_scale);
        if i > 0 {
            k.add(i, i - 1, -k_scale);
            m.add(i, i - 1, m_scale);
        }
    }
    let dense = |b: &BandedMatrix| DMatrix::from_fn(n, n, |i, j| b.get(i, j));
    let (k_dense, m_dense) = (dense(&k), dense(&m));
    k.factorize().expect("SPD");
    let modes = lowest_banded_eigenpairs(&k, &m, 6, 1e-12).expect("converges");
    for (v, e) in modes.values.iter().zip(&exact) {
        assert!((v / e - 1.0).abs() < 1e-9, "{v} vs {e}");
    }
    // The iteration stops on converged values; their error is quadratic in the vectors', so a
    // 1e-12 value tolerance leaves vector residuals near √1e-12.
    check_generalized(&k_dense, &m_dense, &modes.values, &modes.vectors, 1e-6);
}

#[test]
fn generalized_problems_with_bad_input_are_reported() {
    let k = dense_laplacian(3);
    let mut m = DMatrix::identity(3, 3);
    m[(2, 2)] = -1.0;
    assert!(matches!(
        generalized_symmetric_eigen(&k, &m, 2),
        Err(EigenError::NotPositiveDefinite { row: 2, .. })
    ));
    let id = DMatrix::identity(3, 3);
    assert!(matches!(
        generalized_symmetric_eigen(&k, &id, 4),
        Err(EigenError::TooManyEigenpairs {
            requested: 4,
            available: 3
        })
    ));
    let mut nan = k.clone();
    nan[(0, 1)] = f64::NAN;
    assert!(matches!(
        generalized_symmetric_eigen(&nan, &id, 1),
        Err(EigenError::NonFinite { .. })
    ));
    assert!(matches!(
        general_eigen(&DMatrix::zeros(2, 3)),
        Err(EigenError::Shape { .. })
    ));
}

#[test]
fn damped_oscillator_state_matrix_has_the_closed_form_eigenvalues() {
    // ẋ = A x, A = [[0, 1], [−ω², −2ζω]]: λ = −ζω ± iω√(1 − ζ²) (underdamped).
    for (omega, zeta) in [(2.0, 0.05), (1.0, 0.3), (0.5, 0.9)] {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -omega * omega, -2.0 * zeta * omega]);
        let eig = general_eigen(&a).expect("converges");
        let (re, im) = (-zeta * omega, omega * (1.0 - zeta * zeta).sqrt());
        let expected = [Complex::new(re, -im), Complex::new(re, im)];
        for (k, e) in expected.iter().enumerate() {
            assert!(
                (eig.values[k] - e).norm() < 1e-12,
                "ω = {omega}, ζ = {zeta}: {} vs {e}",
                eig.values[k]
            );
            // Eigenvector ∝ (1, λ): second component over first is λ.
            let v = eig.vectors.column(k);
            assert!((v[1] / v[0] - e).norm() < 1e-12);
            assert!((v.norm() - 1.0).abs() < 1e-14);
        }
    }
}

#[test]
fn rotation_generator_has_purely_imaginary_eigenvalues() {
    // [[0, −w], [w, 0]] generates rotation at rate w: λ = ±iw, v = (1, ∓i)/√2 up to phase.
    let w = 3.5;
    let a = DMatrix::from_row_slice(2, 2, &[0.0, -w, w, 0.0]);
    let eig = general_eigen(&a).expect("converges");
    assert!((eig.values[0] - Complex::new(0.0, -w)).norm() < 1e-14);
    assert!((eig.values[1] - Complex::new(0.0, w)).norm() < 1e-14);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    // Phase fixed: the largest component (both equal in modulus: the first found) is real.
    let v = eig.vectors.column(1);
    let ratio = v[1] / v[0];
    assert!((ratio - Complex::new(0.0, -1.0)).norm() < 1e-14, "{ratio}");
    assert!((v[0].norm() - s).abs() < 1e-14);
}

#[test]
fn general_eigenpairs_of_a_random_30x30_have_small_residuals() {
    let n = 30;
    let mut state: u64 = 12345;
    let a = DMatrix::from_fn(n, n, |_, _| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    });
    let eig = general_eigen(&a).expect("converges");
    let ac = a.map(|x| Complex::new(x, 0.0));
    let mut complex_pairs = 0;
    for k in 0..n {
        let (lam, v) = (eig.values[k], eig.vectors.column(k));
        let r = &ac * v - v * lam;
        assert!(r.norm() < 1e-10, "mode {k}: residual {:e}", r.norm());
        assert!((v.norm() - 1.0).abs() < 1e-12);
        if lam.im > 0.0 {
            complex_pairs += 1;
            assert!((eig.values[k - 1] - lam.conj()).norm() < 1e-12);
        }
    }
    // Trace = Σ λ (real), a check independent of the vectors.
    let sum: Complex<f64> = eig.values.iter().sum();
    assert!((sum.re - a.trace()).abs() < 1e-10 && sum.im.abs() < 1e-10);
    assert!(complex_pairs > 0, "a random real matrix has complex pairs");
}

#[test]
fn free_free_chains_with_six_rigid_modes_and_a_wide_stiffness_range_are_resolved() {
    // Six uncoupled free-free spring chains of N unit masses, stiffness scales 10^(2b): each has
    // λ = s_b · 4 sin²(kπ/(2N)), k = 0 … N−1, so six rigid (λ = 0) modes and a 1e10 spread — the
    // free-free beam's spectrum shape. Eigenvalue errors are bounded by ε‖K‖ (backward
    // stability): tolerance 1e-13 ‖K‖; residuals likewise.
    let chain = 61;
    let n = 6 * chain;
    let mut k = DMatrix::<f64>::zeros(n, n);
    let mut exact = Vec::new();
    for b in 0..6 {
        let s = 10f64.powi(2 * b as i32);
        for i in 0..chain - 1 {
            let (p, q) = (b * chain + i, b * chain + i + 1);
            k[(p, p)] += s;
            k[(q, q)] += s;
            k[(p, q)] -= s;
            k[(q, p)] -= s;
        }
        exact.extend(
            (0..chain).map(|j| s * 4.0 * (j as f64 * PI / (2 * chain) as f64).sin().powi(2)),
        );
    }
    exact.sort_by(f64::total_cmp);
    let k_norm = k.norm();
    let all = generalized_symmetric_eigen(&k, &DMatrix::identity(n, n), n).expect("solves");
    for (i, (v, e)) in all.values.iter().zip(&exact).enumerate() {
        assert!((v - e).abs() < 1e-13 * k_norm, "λ_{i} = {v:e} vs {e:e}");
    }
    for c in 0..n {
        let v = all.vectors.column(c);
        let r = &k * v - v * all.values[c];
        assert!(
            r.norm() < 1e-13 * k_norm,
            "residual of pair {c}: {:e}",
            r.norm()
        );
    }
}
