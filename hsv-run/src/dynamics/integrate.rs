//! Fixed-step time integration: the classical fourth-order Runge-Kutta method on a
//! preallocated workspace (no allocation per step).
//!
//! The paper marches the aeroelastic equations at Δt_AE = 0.001 s, heat transfer at
//! Δt_HT = 0.001 s and the aerothermal update at Δt_AT = 0.01 s (Table 3). RK4 is stable for
//! an undamped oscillator while ω Δt < 2√2 ≈ 2.83, so Δt = 0.001 s carries modes up to about
//! 2800 rad/s (450 Hz); a surface Ritz basis with stiffer static shapes needs a smaller step
//! or sub-iteration in that region.

use nalgebra::{DMatrix, DVector};

use super::{DynamicsError, check_finite, check_len};

/// Workspace of the classical Runge-Kutta method for states of one length:
/// x_{n+1} = x_n + Δt/6 (k1 + 2 k2 + 2 k3 + k4).
///
/// Reference: Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.
/// (1993), §II.1 (the "classical" fourth-order method).
#[derive(Debug, Clone)]
pub struct Rk4 {
    k1: DVector<f64>,
    k2: DVector<f64>,
    k3: DVector<f64>,
    k4: DVector<f64>,
    stage: DVector<f64>,
}

impl Rk4 {
    /// A workspace for states of length `n`.
    pub fn new(n: usize) -> Self {
        Self {
            k1: DVector::zeros(n),
            k2: DVector::zeros(n),
            k3: DVector::zeros(n),
            k4: DVector::zeros(n),
            stage: DVector::zeros(n),
        }
    }

    pub fn len(&self) -> usize {
        self.k1.len()
    }

    pub fn is_empty(&self) -> bool {
        self.k1.is_empty()
    }

    /// Advances `x` from `t` to `t + dt` in place with the derivative `f(t, x, dx)`. No
    /// allocation; a non-finite state after the step is an error naming the entry.
    pub fn step<F, E>(&mut self, f: &mut F, t: f64, dt: f64, x: &mut DVector<f64>) -> Result<(), E>
    where
        F: FnMut(f64, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
        E: From<DynamicsError>,
    {
        check_step(self.len(), x, dt)?;
        let half = 0.5 * dt;
        f(t, x, &mut self.k1)?;
        self.stage.copy_from(x);
        self.stage.axpy(half, &self.k1, 1.0);
        f(t + half, &self.stage, &mut self.k2)?;
        self.stage.copy_from(x);
        self.stage.axpy(half, &self.k2, 1.0);
        f(t + half, &self.stage, &mut self.k3)?;
        self.stage.copy_from(x);
        self.stage.axpy(dt, &self.k3, 1.0);
        f(t + dt, &self.stage, &mut self.k4)?;
        let sixth = dt / 6.0;
        x.axpy(sixth, &self.k1, 1.0);
        x.axpy(2.0 * sixth, &self.k2, 1.0);
        x.axpy(2.0 * sixth, &self.k3, 1.0);
        x.axpy(sixth, &self.k4, 1.0);
        check_finite(|| format!("state after the step from t = {t} s"), x.iter())?;
        Ok(())
    }
}

/// A state of the workspace's length `n` and a finite, positive step, else the error naming
/// which.
fn check_step(n: usize, x: &DVector<f64>, dt: f64) -> Result<(), DynamicsError> {
    check_len(|| "integrated state".into(), n, x.len())?;
    if dt.is_finite() && dt > 0.0 {
        Ok(())
    } else {
        Err(DynamicsError::InvalidParameter {
            quantity: "time step (s)".into(),
            value: dt,
            allowed: "finite and > 0",
        })
    }
}

/// A linear block ẋ_b = L x_b + … of the state, entries `start..start + L.nrows()`, that
/// [`ExponentialRk4`] integrates exactly.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearBlock {
    pub start: usize,
    /// The generator L (square).
    pub generator: DMatrix<f64>,
}

/// The matrix functions of one block for one step h: e^{hL/2}, φ₁(hL/2), e^{hL} and the
/// final-stage weights scaled by 6 (identity when L = 0): 6 (φ₁ − 3φ₂ + 4φ₃),
/// 6 (φ₂ − 2φ₃), 6 (−φ₂ + 4φ₃), all of hL.
#[derive(Debug, Clone)]
struct Propagators {
    exp_half: DMatrix<f64>,
    phi1_half: DMatrix<f64>,
    exp_full: DMatrix<f64>,
    weight_1: DMatrix<f64>,
    weight_23: DMatrix<f64>,
    weight_4: DMatrix<f64>,
}

impl Propagators {
    /// From the exponential of the augmented matrix [[A, I, 0, 0], [0, 0, I, 0], [0, 0, 0, I],
    /// [0, 0, 0, 0]], whose first block row is [e^A, φ₁(A), φ₂(A), φ₃(A)] (Saad 1992, SIAM J.
    /// Numer. Anal. 29, 209-228; Al-Mohy & Higham 2011, SIAM J. Sci. Comput. 33, 488-511),
    /// with A = hL and A = hL/2; the exponential is nalgebra's scaling-and-squaring Padé.
    fn new(generator: &DMatrix<f64>, h: f64) -> Self {
        let m = generator.nrows();
        let phis = |a: DMatrix<f64>, p: usize| {
            let mut w = DMatrix::zeros((p + 1) * m, (p + 1) * m);
            w.view_mut((0, 0), (m, m)).copy_from(&a);
            for k in 0..p {
                w.view_mut((k * m, (k + 1) * m), (m, m))
                    .fill_with_identity();
            }
            let e = w.exp();
            (0..=p)
                .map(|k| e.view((0, k * m), (m, m)).into_owned())
                .collect::<Vec<_>>()
        };
        let half = phis(generator * (0.5 * h), 1);
        let full = phis(generator * h, 3);
        let (phi1, phi2, phi3) = (&full[1], &full[2], &full[3]);
        Self {
            exp_half: half[0].clone(),
            phi1_half: half[1].clone(),
            exp_full: full[0].clone(),
            weight_1: (phi1 - phi2 * 3.0 + phi3 * 4.0) * 6.0,
            weight_23: (phi2 - phi3 * 2.0) * 6.0,
            weight_4: (phi3 * 4.0 - phi2) * 6.0,
        }
    }
}

/// The fourth-order exponential time-differencing Runge-Kutta method (ETDRK4) for
/// ẋ = L x + N(t, x) with L block-diagonal: the linear part is integrated exactly through
/// e^{hL} and the φ-functions, and only N limits the step. With E = e^{hL/2}, P = φ₁(hL/2):
/// a = E x + h/2 P N(x), b = E x + h/2 P N(a), c = E a + h/2 P (2 N(b) − N(x)),
/// x⁺ = e^{hL} x + h [f₁ N(x) + 2 f₂ (N(a) + N(b)) + f₃ N(c)],
/// f₁ = φ₁ − 3φ₂ + 4φ₃, f₂ = φ₂ − 2φ₃, f₃ = −φ₂ + 4φ₃ (of hL).
///
/// Reference: Cox & Matthews, "Exponential time differencing for stiff systems", J. Comput.
/// Phys. 176 (2002) 430-455, eqs. (26)-(29); Hochbruck & Ostermann, "Exponential
/// integrators", Acta Numerica 19 (2010) §2.3. Unlike Lawson's integrating-factor form it
/// keeps equilibria (a constant N balancing L x is integrated exactly), so a trimmed vehicle
/// stays put. Outside the blocks (L = 0) it is classical RK4 up to rounding. Used for the
/// lifting surfaces' stiff Ritz vectors (a 5 % surface's reach 525 Hz: ω Δt = 3.3 at the
/// paper's 1 ms, beyond RK4's 2.83), whose structural part is linear.
#[derive(Debug, Clone)]
pub struct ExponentialRk4 {
    blocks: Vec<LinearBlock>,
    propagators: Vec<Propagators>,
    step_s: f64,
    k: [DVector<f64>; 4],
    stage: DVector<f64>,
    a: DVector<f64>,
    scratch: DVector<f64>,
}

impl ExponentialRk4 {
    /// A workspace for states of length `n` with the linear `blocks` (each inside the state,
    /// square, finite, not overlapping).
    pub fn new(n: usize, blocks: Vec<LinearBlock>) -> Result<Self, DynamicsError> {
        let mut end = 0;
        let mut sorted: Vec<&LinearBlock> = blocks.iter().collect();
        sorted.sort_by_key(|b| b.start);
        for b in sorted {
            let m = b.generator.nrows();
            check_len(|| "linear block columns".into(), m, b.generator.ncols())?;
            check_finite(|| "linear block generator".into(), b.generator.iter())?;
            if b.start < end || b.start + m > n {
                return Err(DynamicsError::Dimension {
                    what: format!(
                        "linear block at {}..{} (blocks must lie in the state and not overlap)",
                        b.start,
                        b.start + m
                    ),
                    expected: n,
                    got: b.start + m,
                });
            }
            end = b.start + m;
        }
        let zeros = || DVector::zeros(n);
        Ok(Self {
            blocks,
            propagators: Vec::new(),
            step_s: f64::NAN,
            k: [zeros(), zeros(), zeros(), zeros()],
            stage: zeros(),
            a: zeros(),
            scratch: zeros(),
        })
    }

    pub fn len(&self) -> usize {
        self.stage.len()
    }

    pub fn is_empty(&self) -> bool {
        self.stage.is_empty()
    }

    /// Advances `x` from `t` to `t + dt` in place with the full derivative `f(t, x, dx)`
    /// (L x included: the method subtracts it). Allocates only when `dt` differs from the
    /// previous step's (the propagators are recomputed); a non-finite state after the step is
    /// an error naming the entry.
    pub fn step<F, E>(&mut self, f: &mut F, t: f64, dt: f64, x: &mut DVector<f64>) -> Result<(), E>
    where
        F: FnMut(f64, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
        E: From<DynamicsError>,
    {
        check_step(self.len(), x, dt)?;
        if dt.to_bits() != self.step_s.to_bits() {
            self.propagators = self
                .blocks
                .iter()
                .map(|b| Propagators::new(&b.generator, dt))
                .collect();
            self.step_s = dt;
        }
        let (blocks, props) = (&self.blocks, &self.propagators);
        let half = 0.5 * dt;
        let [k1, k2, k3, k4] = &mut self.k;
        // N(x)
        f(t, x, k1)?;
        subtract_linear(blocks, x, k1);
        // a = E x + h/2 P N(x)
        apply(blocks, props, |p| &p.exp_half, x, &mut self.a);
        apply(blocks, props, |p| &p.phi1_half, k1, &mut self.scratch);
        self.a.axpy(half, &self.scratch, 1.0);
        f(t + half, &self.a, k2)?;
        subtract_linear(blocks, &self.a, k2);
        // b = E x + h/2 P N(a)
        apply(blocks, props, |p| &p.exp_half, x, &mut self.stage);
        apply(blocks, props, |p| &p.phi1_half, k2, &mut self.scratch);
        self.stage.axpy(half, &self.scratch, 1.0);
        f(t + half, &self.stage, k3)?;
        subtract_linear(blocks, &self.stage, k3);
        // c = E a + h/2 P (2 N(b) − N(x))
        self.stage.copy_from(k3);
        self.stage.axpy(-0.5, k1, 1.0);
        apply(
            blocks,
            props,
            |p| &p.phi1_half,
            &self.stage,
            &mut self.scratch,
        );
        apply(blocks, props, |p| &p.exp_half, &self.a, &mut self.stage);
        self.stage.axpy(dt, &self.scratch, 1.0);
        f(t + dt, &self.stage, k4)?;
        subtract_linear(blocks, &self.stage, k4);
        // x⁺ = e^{hL} x + h/6 [6f₁ N(x) + 2·6f₂ (N(a) + N(b)) + 6f₃ N(c)]
        apply(blocks, props, |p| &p.exp_full, x, &mut self.stage);
        x.copy_from(&self.stage);
        let sixth = dt / 6.0;
        apply(blocks, props, |p| &p.weight_1, k1, &mut self.scratch);
        x.axpy(sixth, &self.scratch, 1.0);
        apply(blocks, props, |p| &p.weight_23, k2, &mut self.scratch);
        x.axpy(2.0 * sixth, &self.scratch, 1.0);
        apply(blocks, props, |p| &p.weight_23, k3, &mut self.scratch);
        x.axpy(2.0 * sixth, &self.scratch, 1.0);
        apply(blocks, props, |p| &p.weight_4, k4, &mut self.scratch);
        x.axpy(sixth, &self.scratch, 1.0);
        check_finite(|| format!("state after the step from t = {t} s"), x.iter())?;
        Ok(())
    }
}

/// dx ← dx − L x on every block (the nonlinear remainder N of the full derivative).
fn subtract_linear(blocks: &[LinearBlock], x: &DVector<f64>, dx: &mut DVector<f64>) {
    for b in blocks {
        let m = b.generator.nrows();
        dx.rows_mut(b.start, m)
            .gemv(-1.0, &b.generator, &x.rows(b.start, m), 1.0);
    }
}

/// out ← F v with the matrix `which` picks on each block and the identity elsewhere.
fn apply(
    blocks: &[LinearBlock],
    props: &[Propagators],
    which: impl Fn(&Propagators) -> &DMatrix<f64>,
    v: &DVector<f64>,
    out: &mut DVector<f64>,
) {
    out.copy_from(v);
    for (b, p) in blocks.iter().zip(props) {
        let m = b.generator.nrows();
        out.rows_mut(b.start, m)
            .gemv(1.0, which(p), &v.rows(b.start, m), 0.0);
    }
}

#[cfg(test)]
mod exponential_tests {
    use super::*;

    /// A 5 % surface's stiffest Ritz vector (525 Hz) at the paper's 1 ms step, ω Δt = 3.3:
    /// classical RK4 grows without bound, ETDRK4 follows the closed form for 1 s.
    #[test]
    fn a_stiff_forced_oscillator_at_the_papers_step_follows_the_closed_form() {
        let omega = 2.0 * std::f64::consts::PI * 525.0;
        let forcing = 2.0 * std::f64::consts::PI * 2.0;
        // Undamped oscillator q̈ + ω² q = cos Ω t, x = (q, q̇), the structural part as the
        // linear block; closed form from rest: q = (cos Ω t − cos ω t)/(ω² − Ω²) (Thomson &
        // Dahleh, Theory of Vibration, §3.1).
        let l = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -omega * omega, 0.0]);
        let mut f = |t: f64, x: &DVector<f64>, dx: &mut DVector<f64>| {
            dx[0] = x[1];
            dx[1] = -omega * omega * x[0] + (forcing * t).cos();
            Ok::<(), DynamicsError>(())
        };
        let exact = |t: f64| {
            ((forcing * t).cos() - (omega * t).cos()) / (omega * omega - forcing * forcing)
        };
        let (dt, steps) = (1e-3, 1000);
        let mut lawson = ExponentialRk4::new(
            2,
            vec![LinearBlock {
                start: 0,
                generator: l,
            }],
        )
        .expect("block");
        let mut x = DVector::zeros(2);
        for k in 0..steps {
            lawson
                .step(&mut f, k as f64 * dt, dt, &mut x)
                .expect("ETDRK4 stays finite");
        }
        // The forced response's scale is F/ω² = 9.2e-8 m; the quasi-static part is exact to
        // O((Ω h)⁴) and the free part is propagated exactly: within 1 % of that scale.
        let scale = 1.0 / (omega * omega);
        assert!(
            (x[0] - exact(1.0)).abs() < 1e-2 * scale,
            "{} vs {}",
            x[0],
            exact(1.0)
        );
        let mut rk4 = Rk4::new(2);
        let mut y = DVector::zeros(2);
        let mut diverged = false;
        for k in 0..steps {
            if rk4.step(&mut f, k as f64 * dt, dt, &mut y).is_err() || y[0].abs() > 1e3 * scale {
                diverged = true;
                break;
            }
        }
        assert!(diverged, "classical RK4 is unstable at ω Δt = 3.3");
    }

    /// At least fourth order on a non-stiff problem with a nonlinear remainder: halving the step
    /// divides the error at t = 1 by at least about 2⁴ = 16 (Hochbruck & Ostermann 2010, §2.6;
    /// a third-order method would give 8). On this problem it does better (32: its error
    /// constant of order four nearly cancels), so only the lower bound is asserted.
    #[test]
    fn the_exponential_form_is_fourth_order() {
        // ẋ = −x + x² sin t … written as L = −1 and N = x² sin t; reference from RK4 at a
        // step 64 times finer (its error is 64⁴ times smaller).
        let l = DMatrix::from_element(1, 1, -1.0);
        let mut f = |t: f64, x: &DVector<f64>, dx: &mut DVector<f64>| {
            dx[0] = -x[0] + x[0] * x[0] * t.sin();
            Ok::<(), DynamicsError>(())
        };
        let mut run = |dt: f64, lawson: bool| {
            let mut x = DVector::from_element(1, 0.8);
            let steps = (1.0 / dt).round() as usize;
            let mut la = ExponentialRk4::new(
                1,
                vec![LinearBlock {
                    start: 0,
                    generator: l.clone(),
                }],
            )
            .expect("block");
            let mut rk = Rk4::new(1);
            for k in 0..steps {
                let t = k as f64 * dt;
                if lawson {
                    la.step(&mut f, t, dt, &mut x).expect("step");
                } else {
                    rk.step(&mut f, t, dt, &mut x).expect("step");
                }
            }
            x[0]
        };
        let reference = run(0.1 / 64.0, false);
        let e1 = (run(0.1, true) - reference).abs();
        let e2 = (run(0.05, true) - reference).abs();
        let ratio = e1 / e2;
        assert!(ratio > 12.0, "error ratio {ratio} ({e1}, {e2})");
    }

    /// Without blocks the method is classical RK4 (to rounding: its third stage is summed
    /// differently).
    #[test]
    fn without_blocks_it_is_classical_rk4() {
        let mut f = |t: f64, x: &DVector<f64>, dx: &mut DVector<f64>| {
            dx[0] = x[1];
            dx[1] = -4.0 * x[0] + t.cos();
            Ok::<(), DynamicsError>(())
        };
        let mut a = DVector::from_vec(vec![1.0, 0.0]);
        let mut b = a.clone();
        let mut la = ExponentialRk4::new(2, Vec::new()).expect("empty");
        let mut rk = Rk4::new(2);
        for k in 0..50 {
            la.step(&mut f, k as f64 * 0.01, 0.01, &mut a)
                .expect("step");
            rk.step(&mut f, k as f64 * 0.01, 0.01, &mut b)
                .expect("step");
        }
        assert!((&a - &b).norm() < 1e-13 * b.norm(), "{a} vs {b}");
    }

    /// The φ-functions from the augmented exponential against their closed forms for a scalar:
    /// φ₁ = (e^z − 1)/z, φ₂ = (e^z − 1 − z)/z², φ₃ = (e^z − 1 − z − z²/2)/z³ (Cox & Matthews
    /// 2002, eq. (28) and following).
    #[test]
    fn the_phi_functions_match_their_closed_forms() {
        let (l, h) = (-3.0_f64, 0.7_f64);
        let p = Propagators::new(&DMatrix::from_element(1, 1, l), h);
        let z = l * h;
        let phi1 = (z.exp() - 1.0) / z;
        let phi2 = (z.exp() - 1.0 - z) / (z * z);
        let phi3 = (z.exp() - 1.0 - z - 0.5 * z * z) / (z * z * z);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b.abs().max(1.0);
        assert!(close(p.exp_full[0], z.exp()));
        assert!(close(p.exp_half[0], (0.5 * z).exp()));
        assert!(close(p.phi1_half[0], ((0.5 * z).exp() - 1.0) / (0.5 * z)));
        assert!(close(p.weight_1[0], 6.0 * (phi1 - 3.0 * phi2 + 4.0 * phi3)));
        assert!(close(p.weight_23[0], 6.0 * (phi2 - 2.0 * phi3)));
        assert!(close(p.weight_4[0], 6.0 * (4.0 * phi3 - phi2)));
    }

    /// An equilibrium of a stiff oscillator under a constant load, q = F/ω², stays put to
    /// rounding at ω Δt = 3.3 (the property the integrating-factor form lacks: a trimmed
    /// vehicle would drift).
    #[test]
    fn a_static_equilibrium_stays_put_at_a_stiff_step() {
        let omega = 2.0 * std::f64::consts::PI * 525.0;
        let l = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -omega * omega, 0.0]);
        let mut f = |_t: f64, x: &DVector<f64>, dx: &mut DVector<f64>| {
            dx[0] = x[1];
            dx[1] = -omega * omega * x[0] + 1.0;
            Ok::<(), DynamicsError>(())
        };
        let q = 1.0 / (omega * omega);
        let mut x = DVector::from_vec(vec![q, 0.0]);
        let mut s = ExponentialRk4::new(
            2,
            vec![LinearBlock {
                start: 0,
                generator: l,
            }],
        )
        .expect("block");
        for k in 0..1000 {
            s.step(&mut f, k as f64 * 1e-3, 1e-3, &mut x).expect("step");
        }
        assert!((x[0] - q).abs() < 1e-10 * q, "{} vs {q}", x[0]);
        assert!(x[1].abs() < 1e-10 * q * omega, "{}", x[1]);
    }
}
