//! The continuous algebraic Riccati equation Aᵀ X + X A − X B R⁻¹ Bᵀ X + Q = 0 and the LQR gain
//! K = R⁻¹ Bᵀ X.
//!
//! Solved in two checked stages:
//! 1. the matrix sign function of the Hamiltonian H = [A, −G; −Q, −Aᵀ], G = B R⁻¹ Bᵀ, by the
//!    Newton iteration Z ← (c Z + (c Z)⁻¹)/2 with determinant scaling c = |det Z|^(−1/2n)
//!    (Byers, "Solving the algebraic Riccati equation with the matrix sign function", Linear
//!    Algebra Appl. 85, 1987; Gardiner & Laub, Int. J. Control 44(3), 1986). The stable
//!    invariant subspace [I; X] satisfies (sign H + I)[I; X] = 0, so X solves the
//!    overdetermined [W₁₂; W₂₂ + I] X = −[W₁₁ + I; W₂₁] (least squares through the normal
//!    equations' QR). Needs no stabilizing initial gain, so it takes open-loop unstable plants.
//! 2. Newton-Kleinman refinement (Kleinman, "On an iterative technique for Riccati equation
//!    computations", IEEE TAC 13(1), 1968): with K = R⁻¹ Bᵀ X and A_K = A − B K, the next X
//!    solves the Lyapunov equation A_Kᵀ X + X A_K = −(Q + Kᵀ R K), here by its Kronecker form
//!    (I ⊗ A_Kᵀ + A_Kᵀ ⊗ I) vec X = −vec(Q + Kᵀ R K) with dense LU, adequate for design models
//!    of a few states (n² unknowns). Steps continue while the residual falls.
//!
//! The answer carries the relative residual ‖Aᵀ X + X A − X G X + Q‖_F / (‖Aᵀ X‖_F + ‖X A‖_F +
//! ‖X G X‖_F + ‖Q‖_F), so callers can check it.

use nalgebra::DMatrix;

/// Why the Riccati equation was not solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RiccatiError {
    #[error("matrix sizes do not fit: {0}")]
    Dimensions(String),
    #[error("R is not symmetric positive definite")]
    WeightR,
    #[error(
        "the Hamiltonian has eigenvalues on the imaginary axis (the sign iteration met a \
         singular matrix): (A, B) is not stabilizable or (A, Q) has an undamped unobservable mode"
    )]
    Singular,
    #[error("the sign iteration did not converge in {0} steps")]
    NoConvergence(usize),
    #[error("non-finite values in the solution")]
    NonFinite,
}

/// The stabilizing solution of the CARE and the LQR gain.
#[derive(Debug, Clone, PartialEq)]
pub struct RiccatiSolution {
    /// X = Xᵀ ≥ 0.
    pub x: DMatrix<f64>,
    /// K = R⁻¹ Bᵀ X; the law u = −K x.
    pub k: DMatrix<f64>,
    /// The relative residual (module doc).
    pub relative_residual: f64,
    /// Sign iterations and Newton-Kleinman refinement steps taken.
    pub sign_iterations: usize,
    pub newton_steps: usize,
}

/// The relative residual of `x` in the CARE.
pub fn care_residual(
    a: &DMatrix<f64>,
    g: &DMatrix<f64>,
    q: &DMatrix<f64>,
    x: &DMatrix<f64>,
) -> f64 {
    let atx = a.transpose() * x;
    let xa = x * a;
    let xgx = x * g * x;
    let r = &atx + &xa - &xgx + q;
    let scale = atx.norm() + xa.norm() + xgx.norm() + q.norm();
    if scale == 0.0 {
        r.norm()
    } else {
        r.norm() / scale
    }
}

/// Solves the CARE for the stabilizing X and the gain K (module doc for the method).
pub fn solve_care(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<RiccatiSolution, RiccatiError> {
    let n = a.nrows();
    let m = b.ncols();
    if a.ncols() != n || b.nrows() != n || q.shape() != (n, n) || r.shape() != (m, m) {
        return Err(RiccatiError::Dimensions(format!(
            "A {:?}, B {:?}, Q {:?}, R {:?}",
            a.shape(),
            b.shape(),
            q.shape(),
            r.shape()
        )));
    }
    let r_chol = r.clone().cholesky().ok_or(RiccatiError::WeightR)?;
    let r_inv_bt = r_chol.solve(&b.transpose());
    let g = b * &r_inv_bt;
    let q_sym = (q + q.transpose()) * 0.5;
    // The Hamiltonian.
    let mut h = DMatrix::zeros(2 * n, 2 * n);
    h.view_mut((0, 0), (n, n)).copy_from(a);
    h.view_mut((0, n), (n, n)).copy_from(&(-&g));
    h.view_mut((n, 0), (n, n)).copy_from(&(-&q_sym));
    h.view_mut((n, n), (n, n)).copy_from(&(-a.transpose()));
    const MAX_SIGN: usize = 100;
    let mut z = h;
    let mut sign_iterations = 0;
    loop {
        if sign_iterations == MAX_SIGN {
            return Err(RiccatiError::NoConvergence(MAX_SIGN));
        }
        sign_iterations += 1;
        let lu = z.clone().lu();
        let det = lu.determinant();
        let z_inv = lu.try_inverse().ok_or(RiccatiError::Singular)?;
        if !(det.is_finite() && det != 0.0) {
            return Err(RiccatiError::Singular);
        }
        let c = det.abs().powf(-1.0 / (2 * n) as f64);
        let next = (&z * c + z_inv / c) * 0.5;
        let change = (&next - &z).norm();
        let size = next.norm();
        z = next;
        if !size.is_finite() {
            return Err(RiccatiError::NonFinite);
        }
        if change <= 1e-13 * size {
            break;
        }
    }
    // [W12; W22 + I] X = −[W11 + I; W21].
    let mut lhs = DMatrix::zeros(2 * n, n);
    lhs.view_mut((0, 0), (n, n))
        .copy_from(&z.view((0, n), (n, n)));
    lhs.view_mut((n, 0), (n, n))
        .copy_from(&(z.view((n, n), (n, n)) + DMatrix::identity(n, n)));
    let mut rhs = DMatrix::zeros(2 * n, n);
    rhs.view_mut((0, 0), (n, n))
        .copy_from(&(-(z.view((0, 0), (n, n)) + DMatrix::identity(n, n))));
    rhs.view_mut((n, 0), (n, n))
        .copy_from(&(-z.view((n, 0), (n, n))));
    let qr = lhs.qr();
    let qt_rhs = qr.q().transpose() * rhs;
    let mut x = qr
        .r()
        .solve_upper_triangular(&qt_rhs)
        .ok_or(RiccatiError::Singular)?;
    x = (&x + x.transpose()) * 0.5;
    let mut residual = care_residual(a, &g, &q_sym, &x);
    // Newton-Kleinman refinement.
    let mut newton_steps = 0;
    let identity = DMatrix::<f64>::identity(n, n);
    for _ in 0..10 {
        if residual < 1e-15 {
            break;
        }
        let k = &r_inv_bt * &x;
        let a_k = a - b * &k;
        let rhs = -(&q_sym + k.transpose() * r * &k);
        let a_kt = a_k.transpose();
        let lyap = identity.kronecker(&a_kt) + a_kt.kronecker(&identity);
        let vec_rhs = DMatrix::from_column_slice(n * n, 1, rhs.as_slice());
        let Some(vec_x) = lyap.lu().solve(&vec_rhs) else {
            break;
        };
        let mut candidate = DMatrix::from_column_slice(n, n, vec_x.as_slice());
        candidate = (&candidate + candidate.transpose()) * 0.5;
        let candidate_residual = care_residual(a, &g, &q_sym, &candidate);
        if candidate_residual.partial_cmp(&residual) != Some(std::cmp::Ordering::Less) {
            break;
        }
        x = candidate;
        residual = candidate_residual;
        newton_steps += 1;
    }
    if !x.iter().all(|v| v.is_finite()) {
        return Err(RiccatiError::NonFinite);
    }
    let k = &r_inv_bt * &x;
    Ok(RiccatiSolution {
        x,
        k,
        relative_residual: residual,
        sign_iterations,
        newton_steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Scalar plant ẋ = a x + b u, cost ∫ q x² + r u²: the CARE 2 a X − X² b²/r + q = 0 has the
    /// stabilizing root X = r (a + √(a² + b² q / r)) / b² (the scalar regulator of Anderson &
    /// Moore, "Optimal Control: Linear Quadratic Methods", Prentice Hall 1990, ch. 3, and of
    /// Lewis, Vrabie & Syrmos, "Optimal Control", 3rd ed., Wiley 2012, ch. 3: the quadratic's
    /// positive root). Tolerance 1e-10 relative.
    #[test]
    fn scalar_plant_matches_the_closed_form() {
        for (a, b, q, r) in [
            (1.8, 2.0, 3.0, 0.5),
            (-0.7, 1.0, 1.0, 1.0),
            (0.0, 0.3, 5.0, 2.0),
        ] {
            let s = solve_care(
                &DMatrix::from_element(1, 1, a),
                &DMatrix::from_element(1, 1, b),
                &DMatrix::from_element(1, 1, q),
                &DMatrix::from_element(1, 1, r),
            )
            .unwrap();
            let x: f64 = r * (a + (a * a + b * b * q / r).sqrt()) / (b * b);
            assert!(
                (s.x[(0, 0)] - x).abs() <= 1e-10 * x,
                "{} vs {x}",
                s.x[(0, 0)]
            );
            let k = b * x / r;
            assert!((s.k[(0, 0)] - k).abs() <= 1e-10 * k);
        }
    }

    /// Double integrator ẍ = u with Q = diag(q₁, q₂), R = r: X₁₁ = √(q₁ r)·√(2√(q₁/r) + q₂/r),
    /// X₁₂ = √(q₁ r), X₂₂ = r √(2√(q₁/r) + q₂/r), K = [√(q₁/r), √(2√(q₁/r) + q₂/r)] (the
    /// double-integrator regulator of Lewis, Vrabie & Syrmos 2012, ch. 3, from the three scalar
    /// equations (1,1): q₁ = X₁₂²/r, (1,2): X₁₁ = X₁₂X₂₂/r, (2,2): X₂₂² = r(2X₁₂ + q₂); with
    /// q₁ = r = 1, q₂ = 0 the classic K = [1, √2], closed loop ω_n = 1, ζ = 1/√2). Tolerance
    /// 1e-10.
    #[test]
    fn double_integrator_matches_the_closed_form() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
        for (q1, q2, r) in [(1.0, 0.0, 1.0), (1.0, 1.0, 1.0), (4.0, 0.5, 0.25)] {
            let q = DMatrix::from_row_slice(2, 2, &[q1, 0.0, 0.0, q2]);
            let s = solve_care(&a, &b, &q, &DMatrix::from_element(1, 1, r)).unwrap();
            let w = (q1 / r).sqrt();
            let v = (2.0 * w + q2 / r).sqrt();
            let x = [(q1 * r).sqrt() * v, (q1 * r).sqrt(), r * v];
            for (got, want) in [
                (s.x[(0, 0)], x[0]),
                (s.x[(0, 1)], x[1]),
                (s.x[(1, 1)], x[2]),
            ] {
                assert!((got - want).abs() <= 1e-10 * want, "{got} vs {want}");
            }
            assert!((s.k[(0, 0)] - w).abs() <= 1e-10 * w);
            assert!((s.k[(0, 1)] - v).abs() <= 1e-10 * v);
        }
        let q = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.0]);
        let s = solve_care(&a, &b, &q, &DMatrix::from_element(1, 1, 1.0)).unwrap();
        assert!((s.k[(0, 1)] - 2f64.sqrt()).abs() <= 1e-10);
    }

    /// A plant with an undamped unobservable mode has no stabilizing solution: refused.
    #[test]
    fn imaginary_axis_hamiltonian_is_refused() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
        let b = DMatrix::zeros(2, 1);
        let q = DMatrix::zeros(2, 2);
        let r = DMatrix::from_element(1, 1, 1.0);
        assert!(solve_care(&a, &b, &q, &r).is_err());
    }
}
