//! Stability of an identified state matrix (paper Eq. 8): eigenvalues λ = σ + iω with
//! frequency |ω|/2π and damping ratio ζ = −σ/|λ|, the largest real part, mode tracking by
//! eigenvector correlation, and Brent's root finder for the Mach number where the largest real
//! part crosses zero.
//!
//! **Growth threshold.** An undamped system (the classical panel) has purely imaginary roots
//! below flutter, which the eigen-solver returns with round-off real parts of order
//! ε_machine ‖A‖. A root counts as growing when σ > 1e-9 ‖A‖_F: far above round-off, far below
//! any physical damping (a 1 % damped 1 Hz mode has σ = −0.06 /s, and ‖A‖_F of a 15-mode
//! surface is about the largest ω², 1e6-1e8 /s²).
//!
//! **Flutter and divergence.** A growing oscillatory pair (ω > 0) is flutter; a growing real
//! root (ω = 0: the Schur form's 1 × 1 blocks, whose imaginary part the solver returns as
//! exactly zero) is static divergence, or thermal buckling when the heated structure alone has
//! lost its stiffness. [`Instability`] names the two, and each has its own margin, so that a
//! boundary of one is never reported under the other's name.
//!
//! **Tracking.** Roots are matched to reference roots by the modal assurance criterion of
//! their displacement parts, MAC(a, b) = |aᴴ b|² / ((aᴴ a)(bᴴ b)) (Allemang & Brown, "A
//! correlation coefficient for modal vector analysis", 1st IMAC, 1982), greedily from the best
//! pair down.

use std::f64::consts::PI;

use hsv_core::linalg::general_eigen;
use nalgebra::{Complex, DMatrix, DVector};

use super::FlutterError;

/// One root of A: an oscillatory pair's upper member, or a real root.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FlutterRoot {
    /// σ, 1/s.
    pub real_per_s: f64,
    /// ω ≥ 0, rad/s.
    pub imag_rad_s: f64,
    pub frequency_hz: f64,
    /// ζ = −σ/|λ| (1 for a decaying real root, −1 for a growing one).
    pub damping_ratio: f64,
    /// Displacement part of the eigenvector (first n entries), unit norm.
    pub shape: DVector<Complex<f64>>,
}

impl FlutterRoot {
    /// Whether this is a real root (ω = 0, module docs): one that crosses is divergence.
    pub fn is_real(&self) -> bool {
        self.imag_rad_s == 0.0
    }
}

/// The two ways a root of A crosses into the right half plane (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Instability {
    /// An oscillatory pair crosses: flutter.
    Flutter,
    /// A real root crosses: static divergence, or thermal buckling in the flow.
    Divergence,
}

impl Instability {
    /// Whether `root` is of this kind.
    pub fn admits(self, root: &FlutterRoot) -> bool {
        match self {
            Instability::Flutter => !root.is_real(),
            Instability::Divergence => root.is_real(),
        }
    }

    /// `flutter` or `divergence`.
    pub fn name(self) -> &'static str {
        match self {
            Instability::Flutter => "flutter",
            Instability::Divergence => "divergence",
        }
    }
}

/// Roots of one state matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct Stability {
    /// Oscillatory roots (one per conjugate pair) and real roots, by frequency.
    pub roots: Vec<FlutterRoot>,
    /// The largest σ of all eigenvalues, 1/s.
    pub max_real_per_s: f64,
    /// Index in `roots` of the root with the largest σ.
    pub critical: usize,
    /// The growth threshold 1e-9 ‖A‖_F, 1/s (module docs).
    pub growth_threshold_per_s: f64,
}

impl Stability {
    /// max σ − threshold: positive when a root grows (the function whose zero is flutter).
    pub fn growth_margin_per_s(&self) -> f64 {
        self.max_real_per_s - self.growth_threshold_per_s
    }

    /// Whether a root grows.
    pub fn is_unstable(&self) -> bool {
        self.growth_margin_per_s() > 0.0
    }

    /// Index in `roots` of the root of kind `kind` with the largest σ, if A has one.
    pub fn critical_of(&self, kind: Instability) -> Option<usize> {
        self.roots
            .iter()
            .enumerate()
            .filter(|(_, r)| kind.admits(r))
            .max_by(|a, b| a.1.real_per_s.total_cmp(&b.1.real_per_s))
            .map(|(i, _)| i)
    }

    /// The largest σ of the roots of kind `kind` minus the growth threshold, 1/s (positive:
    /// that kind of instability); `None` when A has no root of that kind.
    pub fn margin_per_s(&self, kind: Instability) -> Option<f64> {
        self.critical_of(kind)
            .map(|i| self.roots[i].real_per_s - self.growth_threshold_per_s)
    }

    /// The least damping ratio over all roots.
    pub fn least_damping_ratio(&self) -> f64 {
        self.roots
            .iter()
            .map(|r| r.damping_ratio)
            .fold(f64::INFINITY, f64::min)
    }
}

/// Eigenvalues and eigenvectors of `a` (2n × 2n, state [q; q̇]) as [`Stability`].
pub fn stability(a: &DMatrix<f64>) -> Result<Stability, FlutterError> {
    let n_states = a.nrows();
    if n_states == 0 || !n_states.is_multiple_of(2) || a.ncols() != n_states {
        return Err(FlutterError::Inconsistent(format!(
            "state matrix is {} × {}, expected 2n × 2n",
            a.nrows(),
            a.ncols()
        )));
    }
    let n = n_states / 2;
    let eigen = general_eigen(a)?;
    let scale = a.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut roots = Vec::with_capacity(n_states);
    let mut max_real = f64::NEG_INFINITY;
    for (k, lambda) in eigen.values.iter().enumerate() {
        max_real = max_real.max(lambda.re);
        if lambda.im < 0.0 {
            continue;
        }
        let mut shape: DVector<Complex<f64>> = eigen.vectors.column(k).rows(0, n).into_owned();
        let norm = shape.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
        if norm > 0.0 {
            shape /= Complex::new(norm, 0.0);
        }
        let modulus = lambda.norm();
        roots.push(FlutterRoot {
            real_per_s: lambda.re,
            imag_rad_s: lambda.im,
            frequency_hz: lambda.im / (2.0 * PI),
            damping_ratio: if modulus > 0.0 {
                -lambda.re / modulus
            } else {
                0.0
            },
            shape,
        });
    }
    roots.sort_by(|a, b| {
        a.imag_rad_s
            .total_cmp(&b.imag_rad_s)
            .then(b.real_per_s.total_cmp(&a.real_per_s))
    });
    let critical = roots
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.real_per_s.total_cmp(&b.1.real_per_s))
        .map_or(0, |(i, _)| i);
    Ok(Stability {
        roots,
        max_real_per_s: max_real,
        critical,
        growth_threshold_per_s: 1e-9 * scale,
    })
}

/// MAC(a, b) = |aᴴ b|² / ((aᴴ a)(bᴴ b)) in [0, 1] (module docs).
pub fn mac(a: &DVector<Complex<f64>>, b: &DVector<Complex<f64>>) -> f64 {
    let ab: Complex<f64> = a.iter().zip(b.iter()).map(|(x, y)| x.conj() * y).sum();
    let aa: f64 = a.iter().map(|z| z.norm_sqr()).sum();
    let bb: f64 = b.iter().map(|z| z.norm_sqr()).sum();
    if aa > 0.0 && bb > 0.0 {
        ab.norm_sqr() / (aa * bb)
    } else {
        0.0
    }
}

/// For each reference shape, the index of the root of `roots` it continues (greedy by MAC,
/// best pair first; `None` when every root is taken).
pub fn track(reference: &[DVector<Complex<f64>>], roots: &[FlutterRoot]) -> Vec<Option<usize>> {
    let mut pairs: Vec<(f64, usize, usize)> = reference
        .iter()
        .enumerate()
        .flat_map(|(i, r)| {
            roots
                .iter()
                .enumerate()
                .map(move |(j, root)| (mac(r, &root.shape), i, j))
        })
        .collect();
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut assigned = vec![None; reference.len()];
    let mut taken = vec![false; roots.len()];
    for (_, i, j) in pairs {
        if assigned[i].is_none() && !taken[j] {
            assigned[i] = Some(j);
            taken[j] = true;
        }
    }
    assigned
}

/// Result of [`brent_root`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RootSearch {
    pub root: f64,
    /// The final bracket [a, b] with a sign change.
    pub bracket: (f64, f64),
    pub evaluations: usize,
}

/// The zero of `g` in [a, b] (g(a), g(b) of opposite signs, given as `ga`, `gb`) to within
/// `tolerance`, by Brent's method: inverse quadratic interpolation or secant steps kept inside
/// the bracket, bisection when they are not fast enough (Brent, *Algorithms for Minimization
/// without Derivatives*, Prentice-Hall, 1973, ch. 4, procedure `zero`).
pub fn brent_root<E>(
    mut g: impl FnMut(f64) -> Result<f64, E>,
    (mut a, mut b): (f64, f64),
    (mut fa, mut fb): (f64, f64),
    tolerance: f64,
    max_evaluations: usize,
) -> Result<RootSearch, E>
where
    E: From<FlutterError>,
{
    if fa.is_nan() || fb.is_nan() || fa * fb > 0.0 {
        return Err(FlutterError::Inconsistent(format!(
            "Brent's method needs a sign change: g({a}) = {fa}, g({b}) = {fb}"
        ))
        .into());
    }
    let mut evaluations = 0;
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    loop {
        if fb * fc > 0.0 {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * tolerance;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 || evaluations >= max_evaluations {
            let bracket = if b < c { (b, c) } else { (c, b) };
            return Ok(RootSearch {
                root: b,
                bracket,
                evaluations,
            });
        }
        if e.abs() < tol || fa.abs() <= fb.abs() {
            d = m;
            e = m;
        } else {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < 3.0 * m * q - (tol * q).abs() && p < (0.5 * e * q).abs() {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol {
            d
        } else if m > 0.0 {
            tol
        } else {
            -tol
        };
        fb = g(b)?;
        evaluations += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brent finds √2 as the zero of x² − 2 on [0, 2] to 1e-12.
    #[test]
    fn brent_finds_the_square_root_of_two() {
        let r =
            brent_root::<FlutterError>(|x| Ok(x * x - 2.0), (0.0, 2.0), (-2.0, 2.0), 1e-12, 100)
                .expect("root");
        assert!((r.root - 2f64.sqrt()).abs() < 1e-11, "{r:?}");
        assert!(r.evaluations < 15, "{r:?}");
    }

    /// A damped oscillator ẍ + 2ζω ẋ + ω² x = 0 has λ = −ζω ± iω√(1−ζ²): frequency and damping
    /// ratio come back exactly.
    #[test]
    fn damped_oscillator_roots_give_frequency_and_damping() {
        let (omega, zeta) = (10.0, 0.05);
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -omega * omega, -2.0 * zeta * omega]);
        let s = stability(&a).expect("stability");
        assert_eq!(s.roots.len(), 1);
        let r = &s.roots[0];
        assert!((r.damping_ratio - zeta).abs() < 1e-12, "{r:?}");
        assert!((r.imag_rad_s - omega * (1.0 - zeta * zeta).sqrt()).abs() < 1e-10);
        assert!(!s.is_unstable());
    }

    /// A damped oscillator beside a statically divergent coordinate (ẍ = +k x, λ = ±√k):
    /// the growing real root √k is divergence, the damped pair is not flutter; each margin
    /// sees only its own kind.
    #[test]
    fn real_root_is_divergence_and_pair_is_not_flutter() {
        let (omega, zeta, k) = (10.0, 0.05, 4.0);
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0,
                0.0,
                1.0,
                0.0, //
                0.0,
                0.0,
                0.0,
                1.0, //
                -omega * omega,
                0.0,
                -2.0 * zeta * omega,
                0.0, //
                0.0,
                k,
                0.0,
                0.0,
            ],
        );
        let s = stability(&a).expect("stability");
        let divergence = s.margin_per_s(Instability::Divergence).expect("real roots");
        let flutter = s.margin_per_s(Instability::Flutter).expect("a pair");
        assert!((divergence + s.growth_threshold_per_s - 2.0).abs() < 1e-10);
        assert!((flutter + s.growth_threshold_per_s + zeta * omega).abs() < 1e-10);
        let critical = &s.roots[s.critical_of(Instability::Divergence).expect("root")];
        assert!(critical.is_real());
    }
}
