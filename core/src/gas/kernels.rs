//! Cheaper formulations of the gas relations' inner kernels, kept apart from `gas.rs` so the
//! closed forms there read as the references state them: powers whose exponent is a multiple of
//! ½ (γ = 1.4 gives 2.5, 3, 3.5, 7) by `powi` and one `sqrt`, the weak oblique shock as a cubic
//! in sin²β - 1/M² (no trigonometry inside the iteration), and Halley's method for the inverse
//! Prandtl-Meyer function. Each agrees with the formulation it replaces to rounding
//! (`core/tests/gas_kernels.rs`).

/// bᵉ with b > 0 finite: `powi` and one `sqrt` when 2e is within 8 ulp of an integer n with
/// |n| <= 64 (bᵉ = b^⌊n/2⌋ √b for odd n; exact identity), `powf` otherwise (and for b <= 0, NaN,
/// ∞, where `powf`'s special cases apply).
pub(crate) fn pow_half_integer(base: f64, exponent: f64) -> f64 {
    let twice = 2.0 * exponent;
    let n = twice.round();
    let near_integer = (twice - n).abs() <= 8.0 * f64::EPSILON * twice.abs().max(1.0);
    if !(near_integer && n.abs() <= 64.0 && base.is_finite() && base > 0.0) {
        return base.powf(exponent);
    }
    // |n| <= 64, so the conversion is exact.
    let n = n as i32;
    let whole = base.powi(n.div_euclid(2));
    if n.rem_euclid(2) == 1 {
        whole * base.sqrt()
    } else {
        whole
    }
}

/// (B, C, D) of y³ + B y² + C y + D = 0, the θ-β-M relation as a cubic in y = sin²β - 1/M²
/// (NACA 1135 eq. 150, x³ + b x² + c x + d = 0 in x = sin²β, shifted to the Mach wave):
/// B = -(1 - 1/M²) - γ sin²θ, C = (γ+1) sin²θ ((γ+1)/4 - 1/M²), D = (γ+1)²/4 sin²θ / M².
/// At θ = 0 the Mach wave x = 1/M² is a double root of eq. 150, so its coefficients' rounding
/// moves the weak root by ~ε/θ; in y the polynomial is y²(y - (1 - 1/M²)) + O(sin²θ) with
/// exact leading terms and the root keeps full relative precision down to θ → 0.
pub(crate) fn mach_wave_cubic(mach: f64, sin_theta: f64, gamma: f64) -> [f64; 3] {
    let sin2 = sin_theta * sin_theta;
    let x0 = 1.0 / (mach * mach);
    // 1 - 1/M² without cancellation near M = 1.
    let one_minus_x0 = (mach - 1.0) * (mach + 1.0) * x0;
    let b = -one_minus_x0 - gamma * sin2;
    let c = (gamma + 1.0) * sin2 * (0.25 * (gamma + 1.0) - x0);
    let d = 0.25 * (gamma + 1.0) * (gamma + 1.0) * sin2 * x0;
    [b, c, d]
}

/// A cubic y³ + B y² + C y + D and its slope at y, by Horner's rule.
pub(crate) fn cubic_and_slope([b, c, d]: [f64; 3], y: f64) -> (f64, f64) {
    (((y + b) * y + c) * y + d, (3.0 * y + 2.0 * b) * y + c)
}

/// Halley's method x ← x - 2 r r' / (2 r'² - r r'') on a residual `f` returning (r, r', r'')
/// inside the open bracket (lo, hi), from `x`. Convergence is cubic, so once a step is below
/// 1e-6 |x| the error left is of order 1e-18 |x| and the iteration stops after that step.
/// `None` when the start or a step lies outside the bracket, is not finite, or 8 steps do not converge: the caller
/// then falls back to its safeguarded solver.
pub(crate) fn halley(
    f: impl Fn(f64) -> (f64, f64, f64),
    lo: f64,
    hi: f64,
    mut x: f64,
) -> Option<f64> {
    if !(x > lo && x < hi) {
        return None;
    }
    for _ in 0..8 {
        let (r, d1, d2) = f(x);
        if r == 0.0 {
            return Some(x);
        }
        let step = 2.0 * r * d1 / (2.0 * d1 * d1 - r * d2);
        let next = x - step;
        if !(next.is_finite() && next > lo && next < hi) {
            return None;
        }
        x = next;
        if step.abs() <= 1e-6 * x.abs() {
            return Some(x);
        }
    }
    None
}
