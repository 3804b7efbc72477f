//! Eigenvalue solvers: subspace iteration for the lowest modes of a large banded generalized
//! problem K φ = λ M φ (Bathe, Finite Element Procedures, 1996, §11.6), and the cyclic Jacobi
//! method for small dense symmetric matrices (Golub & Van Loan, Matrix Computations, 4th ed., §8.5), the latter
//! allocation-free on caller-provided buffers.

use nalgebra::DMatrix;

use crate::banded::BandedMatrix;

/// Why an eigen-solve failed.
#[derive(Debug, Clone, PartialEq)]
pub enum EigenError {
    /// The reduced mass matrix lost positive definiteness (starting vectors in the null space).
    SingularSubspace,
    /// No convergence within the iteration limit; `residual` is the worst relative change.
    NotConverged { iterations: usize, residual: f64 },
}

/// Lowest `p` eigenpairs of K φ = λ M φ. `k_factor` is the Cholesky factor of K
/// ([`BandedMatrix::cholesky_in_place`]), `m` the (unfactored) mass matrix. Returns the
/// eigenvalues ascending and the M-orthonormal eigenvectors (columns).
pub fn subspace_iteration(
    k_factor: &BandedMatrix,
    m: &BandedMatrix,
    p: usize,
    tolerance: f64,
) -> Result<(Vec<f64>, DMatrix<f64>), EigenError> {
    let n = m.n();
    let q = (2 * p).max(p + 8).min(n);
    let mut x = starting_vectors(m, q);
    let mut y = DMatrix::<f64>::zeros(n, q);
    let mut previous = vec![f64::INFINITY; q];
    let mut col = vec![0.0; n];
    let mut out = vec![0.0; n];
    let max_iterations = 500;
    let mut worst = f64::INFINITY;
    for iteration in 0..max_iterations {
        // Y = M X; X̄ = K⁻¹ Y.
        for c in 0..q {
            col.copy_from_slice(x.column(c).as_slice());
            m.mul_vec(&col, &mut out);
            y.column_mut(c).copy_from_slice(&out);
            k_factor.cholesky_solve(&mut out);
            x.column_mut(c).copy_from_slice(&out);
        }
        let k_r = x.transpose() * &y;
        let mut mx = DMatrix::<f64>::zeros(n, q);
        for c in 0..q {
            col.copy_from_slice(x.column(c).as_slice());
            m.mul_vec(&col, &mut out);
            mx.column_mut(c).copy_from_slice(&out);
        }
        let m_r = x.transpose() * &mx;
        let (values, vectors) = small_generalized(&k_r, &m_r)?;
        x = &x * &vectors;
        worst = (0..p)
            .map(|i| ((values[i] - previous[i]) / values[i]).abs())
            .fold(0.0, f64::max);
        previous.copy_from_slice(&values);
        if worst <= tolerance && iteration > 1 {
            let vecs = x.columns(0, p).into_owned();
            return Ok((values[..p].to_vec(), vecs));
        }
    }
    Err(EigenError::NotConverged {
        iterations: max_iterations,
        residual: worst,
    })
}

/// diag(M) and deterministic pseudo-random vectors (a 64-bit LCG, Knuth MMIX constants).
fn starting_vectors(m: &BandedMatrix, q: usize) -> DMatrix<f64> {
    let n = m.n();
    let mut x = DMatrix::<f64>::zeros(n, q);
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    for c in 0..q {
        for r in 0..n {
            x[(r, c)] = if c == 0 {
                m.get(r, r)
            } else {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
            };
        }
    }
    x
}

/// Eigenpairs of the small problem K_r Q = M_r Q Λ, ascending, Qᵀ M_r Q = I.
pub fn small_generalized(
    k_r: &DMatrix<f64>,
    m_r: &DMatrix<f64>,
) -> Result<(Vec<f64>, DMatrix<f64>), EigenError> {
    let sym = |a: &DMatrix<f64>| 0.5 * (a + a.transpose());
    let chol = nalgebra::Cholesky::new(sym(m_r)).ok_or(EigenError::SingularSubspace)?;
    let l = chol.l();
    let l_inv = l
        .clone()
        .try_inverse()
        .ok_or(EigenError::SingularSubspace)?;
    let c = sym(&(&l_inv * sym(k_r) * l_inv.transpose()));
    let eig = nalgebra::SymmetricEigen::new(c);
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let values: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let z = DMatrix::from_fn(eig.eigenvalues.len(), order.len(), |r, k| {
        eig.eigenvectors[(r, order[k])]
    });
    let q = l_inv.transpose() * z;
    Ok((values, q))
}

/// Eigen-decomposition of the symmetric matrix in `a` (destroyed) by cyclic Jacobi rotations:
/// eigenvalues ascending into `values`, orthonormal eigenvectors into the columns of
/// `vectors`. Allocation-free. Returns the number of sweeps.
pub fn jacobi_eigen(a: &mut DMatrix<f64>, values: &mut [f64], vectors: &mut DMatrix<f64>) -> usize {
    let n = a.nrows();
    vectors.fill(0.0);
    for i in 0..n {
        vectors[(i, i)] = 1.0;
    }
    let mut sweeps = 0;
    for sweep in 0..100 {
        sweeps = sweep + 1;
        let mut off = 0.0;
        let mut diag = 0.0;
        for i in 0..n {
            diag += a[(i, i)] * a[(i, i)];
            for j in (i + 1)..n {
                off += a[(i, j)] * a[(i, j)];
            }
        }
        if off <= 1e-30 * diag.max(f64::MIN_POSITIVE) {
            break;
        }
        for p in 0..n {
            for q in (p + 1)..n {
                let apq = a[(p, q)];
                if apq == 0.0 {
                    continue;
                }
                // Rotation zeroing a[p][q] (Golub & Van Loan's sym.schur2).
                let tau = (a[(q, q)] - a[(p, p)]) / (2.0 * apq);
                let t = tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt());
                let t = if tau == 0.0 { 1.0 } else { t };
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = t * c;
                for k in 0..n {
                    let akp = a[(k, p)];
                    let akq = a[(k, q)];
                    a[(k, p)] = c * akp - s * akq;
                    a[(k, q)] = s * akp + c * akq;
                }
                for k in 0..n {
                    let apk = a[(p, k)];
                    let aqk = a[(q, k)];
                    a[(p, k)] = c * apk - s * aqk;
                    a[(q, k)] = s * apk + c * aqk;
                }
                for k in 0..n {
                    let vkp = vectors[(k, p)];
                    let vkq = vectors[(k, q)];
                    vectors[(k, p)] = c * vkp - s * vkq;
                    vectors[(k, q)] = s * vkp + c * vkq;
                }
            }
        }
    }
    for i in 0..n {
        values[i] = a[(i, i)];
    }
    // Selection sort of the pairs, ascending (n is small).
    for i in 0..n {
        let mut best = i;
        for j in (i + 1)..n {
            if values[j] < values[best] {
                best = j;
            }
        }
        if best != i {
            values.swap(i, best);
            vectors.swap_columns(i, best);
        }
    }
    sweeps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_matches_a_known_spectrum() {
        // Tridiagonal (2, −1): eigenvalues 2 − 2 cos(kπ/(n+1)).
        let n = 6;
        let mut a = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            a[(i, i)] = 2.0;
            if i + 1 < n {
                a[(i, i + 1)] = -1.0;
                a[(i + 1, i)] = -1.0;
            }
        }
        let a0 = a.clone();
        let mut vals = vec![0.0; n];
        let mut vecs = DMatrix::<f64>::zeros(n, n);
        jacobi_eigen(&mut a, &mut vals, &mut vecs);
        for (k, v) in vals.iter().enumerate() {
            let exact = 2.0 - 2.0 * ((k + 1) as f64 * std::f64::consts::PI / (n + 1) as f64).cos();
            assert!((v - exact).abs() < 1e-12, "{v} vs {exact}");
            let r = &a0 * vecs.column(k) - vecs.column(k) * *v;
            assert!(r.norm() < 1e-12);
        }
    }

    #[test]
    fn subspace_iteration_finds_the_lowest_string_modes() {
        // Fixed-fixed string, lumped unit masses: λ_k = 2 − 2 cos(kπ/(n+1)).
        let n = 60;
        let mut k = BandedMatrix::zeros(n, 1);
        let mut m = BandedMatrix::zeros(n, 0);
        for i in 0..n {
            k.add_lower(i, i, 2.0);
            m.add_lower(i, i, 1.0);
            if i > 0 {
                k.add_lower(i, i - 1, -1.0);
            }
        }
        k.cholesky_in_place().expect("SPD");
        let (vals, _) = subspace_iteration(&k, &m, 5, 1e-12).expect("converged");
        for (i, v) in vals.iter().enumerate() {
            let exact = 2.0 - 2.0 * ((i + 1) as f64 * std::f64::consts::PI / (n + 1) as f64).cos();
            assert!((v / exact - 1.0).abs() < 1e-9, "{v} vs {exact}");
        }
    }
}
