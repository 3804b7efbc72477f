//! The cheaper gas kernels against the formulations they replaced, and against the published
//! values those formulations were validated with.
//!
//! `reference` below is the previous code, kept verbatim in spirit: the weak oblique shock by
//! safeguarded Newton in β on the θ-β-M relation (Anderson MCF eq. 4.17), the inverse
//! Prandtl-Meyer function by safeguarded Newton from Hall's start (Anderson MCF eq. 4.44; Hall,
//! Aeronautical J. 79, 1975), and the isentropic/normal-shock powers by `powf`, `ln` and `exp`
//! (NACA 1135 eqs. 44, 45, 99). The new forms (the θ-β-M cubic in sin²β, NACA 1135 eq. 150;
//! Halley's method; `powi` + `sqrt` for half-integer exponents) must give the same numbers to
//! rounding: 1e-12 relative over the vehicle's operating range (Mach 1.05 to 25 for shocks,
//! deflections 0.1 % to 99.9 % of θ_max and down to 1e-9 rad; Mach 1.01 to 60 for the inverse
//! Prandtl-Meyer function, 1.01 to 20 with turns of 1e-9 to 1 rad for expansions; γ 1.2 to 1.67;
//! 1e-11 on expansion pressure and density ratios, which raise T2/T1 to the power 2.5-6). The published checks: NACA 1135 Tables I-II and the Çengel & Cimbala
//! oblique-shock example (Ma1 = 2, δ = 10°), to half a unit in the last printed digit.

use hsv_core::gas::*;

const G: f64 = GAMMA_AIR;

/// The formulations the kernels replaced.
mod reference {
    use std::f64::consts::FRAC_PI_2;

    /// Numerical Recipes `rtsafe` as `hsv_core::gas` had it (private there).
    pub fn solve_bracketed(
        f: impl Fn(f64) -> (f64, f64),
        mut lo: f64,
        mut hi: f64,
        guess: f64,
        increasing: bool,
        f_tolerance: f64,
    ) -> f64 {
        let mut x = if guess > lo && guess < hi {
            guess
        } else {
            0.5 * (lo + hi)
        };
        let mut best = (x, f64::INFINITY);
        let mut close = false;
        for _ in 0..200 {
            let (fx, dfx) = f(x);
            if fx.abs() <= f_tolerance {
                return x;
            }
            if fx.abs() < best.1 {
                best = (x, fx.abs());
            } else if close {
                return best.0;
            }
            if (fx < 0.0) == increasing {
                lo = x;
            } else {
                hi = x;
            }
            let newton = x - fx / dfx;
            let step = (newton - x).abs();
            if newton.is_finite() && step <= 4.0 * f64::EPSILON * x.abs() {
                return newton;
            }
            close = newton.is_finite() && step <= 1e-6 * x.abs();
            let next = if newton.is_finite() && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= 4.0 * f64::EPSILON * next.abs() {
                return next;
            }
            x = next;
        }
        x
    }

    fn theta_beta_parts(mach: f64, beta: f64, gamma: f64) -> (f64, f64) {
        let m2 = mach * mach;
        let (s, c) = beta.sin_cos();
        let numerator = 2.0 * c / s * (m2 * s * s - 1.0);
        let denominator = m2 * (gamma + (2.0 * beta).cos()) + 2.0;
        (numerator, denominator)
    }

    fn theta_and_slope(mach: f64, beta: f64, gamma: f64) -> (f64, f64) {
        let m2 = mach * mach;
        let (s, c) = beta.sin_cos();
        let (n, d) = theta_beta_parts(mach, beta, gamma);
        let dn = -2.0 * (m2 * s * s - 1.0) / (s * s) + 4.0 * m2 * c * c;
        let dd = -2.0 * m2 * (2.0 * beta).sin();
        (n.atan2(d), (dn * d - n * dd) / (d * d + n * n))
    }

    fn wave_angle_at_max_deflection(mach: f64, gamma: f64) -> f64 {
        let m2 = mach * mach;
        let gp1 = gamma + 1.0;
        let root = (gp1 * (gp1 * m2 * m2 + 8.0 * (gamma - 1.0) * m2 + 16.0)).sqrt();
        let sin2 = (gp1 * m2 - 4.0 + root) / (4.0 * gamma * m2);
        sin2.clamp(0.0, 1.0).sqrt().asin()
    }

    fn weak_closed_form(mach: f64, theta: f64, gamma: f64) -> f64 {
        let m2 = mach * mach;
        let t = theta.tan();
        let a = 1.0 + 0.5 * (gamma - 1.0) * m2;
        let lambda2 = (m2 - 1.0).powi(2) - 3.0 * a * (1.0 + 0.5 * (gamma + 1.0) * m2) * t * t;
        let lambda = lambda2.max(0.0).sqrt();
        let chi = ((m2 - 1.0).powi(3) - 9.0 * a * (a + 0.25 * (gamma + 1.0) * m2 * m2) * t * t)
            / (lambda * lambda * lambda);
        let angle = (4.0 * std::f64::consts::PI + chi.clamp(-1.0, 1.0).acos()) / 3.0;
        ((m2 - 1.0 + 2.0 * lambda * angle.cos()) / (3.0 * a * t)).atan()
    }

    /// (β, M2, p2/p1, ρ2/ρ1, T2/T1, p02/p01) of the weak shock, θ in (0, θ_max).
    pub fn weak_oblique_shock(m: f64, theta: f64, gamma: f64) -> [f64; 6] {
        let beta_max = wave_angle_at_max_deflection(m, gamma);
        let theta_max = theta_beta_parts(m, beta_max, gamma);
        let theta_max = theta_max.0.atan2(theta_max.1).max(0.0);
        let mu = (1.0 / m).asin();
        let guess = if theta < 1e-3 * theta_max {
            mu + (gamma + 1.0) * m * m / (4.0 * (m - 1.0) * (m + 1.0)) * theta
        } else {
            weak_closed_form(m, theta, gamma)
        };
        let residual = |b: f64| {
            let (t, slope) = theta_and_slope(m, b, gamma);
            (t - theta, slope)
        };
        let beta = solve_bracketed(residual, mu, beta_max, guess, true, 8.0 * f64::EPSILON);
        let normal = normal_shock((m * beta.sin()).max(1.0), gamma);
        let turn = beta - theta;
        let m2 = if turn > 0.0 {
            normal[0] / turn.sin()
        } else {
            0.0
        };
        [beta, m2, normal[1], normal[2], normal[3], normal[4]]
    }

    /// (M2, p2/p1, ρ2/ρ1, T2/T1, p02/p01), NACA 1135 eqs. 93-99 with `ln`/`exp`.
    pub fn normal_shock(mach: f64, gamma: f64) -> [f64; 5] {
        let m2 = mach.max(1.0).powi(2);
        let p = 1.0 + 2.0 * gamma / (gamma + 1.0) * (m2 - 1.0);
        let rho = (gamma + 1.0) * m2 / ((gamma - 1.0) * m2 + 2.0);
        let m_down = (((gamma - 1.0) * m2 + 2.0) / (2.0 * gamma * m2 - (gamma - 1.0))).sqrt();
        let p0 = ((gamma * rho.ln() - p.ln()) / (gamma - 1.0)).exp();
        [m_down, p, rho, p / rho, p0.min(1.0)]
    }

    fn pm_of_x(x: f64, a: f64) -> f64 {
        a * (x / a).atan() - x.atan()
    }

    fn pm_deficit_of_x(x: f64, a: f64) -> f64 {
        a * (a / x).atan() - (1.0 / x).atan()
    }

    fn pm_slope_of_x(x: f64, a: f64) -> f64 {
        let x2 = x * x;
        x2 * (1.0 - 1.0 / (a * a)) / ((1.0 + x2 / (a * a)) * (1.0 + x2))
    }

    /// M(ν) by safeguarded Newton from Hall's start, ν in (0, ν_max).
    pub fn inverse_prandtl_meyer(nu: f64, gamma: f64) -> f64 {
        let a = ((gamma + 1.0) / (gamma - 1.0)).sqrt();
        let nu_max = FRAC_PI_2 * (a - 1.0);
        let y = (nu / nu_max).powf(2.0 / 3.0);
        let hall = (1.0 + y * (1.360_4 + y * (0.096_2 - 0.512_7 * y)))
            / (1.0 - y * (0.672_2 + 0.327_8 * y));
        let deficit = nu_max - nu;
        let hi = (a * a - 1.0) / deficit;
        let guess = if nu < 1e-6 * nu_max {
            (3.0 * nu / (1.0 - 1.0 / (a * a))).cbrt()
        } else if hall.is_finite() && hall > 1.0 {
            ((hall - 1.0) * (hall + 1.0)).sqrt()
        } else {
            0.5 * hi
        };
        let x = if nu <= 0.5 * nu_max {
            let f = |x| (pm_of_x(x, a) - nu, pm_slope_of_x(x, a));
            solve_bracketed(f, 0.0, hi, guess, true, 0.0)
        } else {
            let f = |x| (pm_deficit_of_x(x, a) - deficit, -pm_slope_of_x(x, a));
            solve_bracketed(f, 0.0, hi, guess, false, 0.0)
        };
        (1.0 + x * x).sqrt()
    }
}

/// Asserts |new/old - 1| <= tolerance, naming the quantity and the point.
fn assert_same(what: &str, new: f64, old: f64, tolerance: f64) {
    let error = if old == 0.0 {
        new.abs()
    } else {
        (new / old - 1.0).abs()
    };
    assert!(
        error <= tolerance,
        "{what}: new {new:e}, old {old:e}, relative difference {error:e} > {tolerance:e}"
    );
}

/// Log-spaced points from `lo` to `hi` (inclusive), `n` of them.
fn log_space(lo: f64, hi: f64, n: usize) -> impl Iterator<Item = f64> {
    let (a, b) = (lo.ln(), hi.ln());
    (0..n).map(move |i| (a + (b - a) * i as f64 / (n - 1) as f64).exp())
}

#[test]
fn weak_oblique_shock_cubic_in_sin2_beta_equals_newton_in_beta() {
    for gamma in [1.2, G, 1.67] {
        for mach in log_space(1.05, 25.0, 60) {
            let (theta_max, _) = max_deflection(mach, gamma).unwrap();
            let fractions = (1..=99).map(|k| f64::from(k) / 100.0).chain([0.001, 0.999]);
            let small = [1e-9, 1e-7, 1e-5, 1e-3].map(|t| t / theta_max);
            for fraction in fractions.chain(small) {
                let theta = fraction * theta_max;
                let new = oblique_shock(mach, theta, gamma, ShockBranch::Weak).unwrap();
                let old = reference::weak_oblique_shock(mach, theta, gamma);
                let at = format!("M {mach}, theta {theta}, gamma {gamma}");
                assert_same(&format!("beta at {at}"), new.wave_angle_rad, old[0], 1e-12);
                assert_same(&format!("M2 at {at}"), new.mach_downstream, old[1], 1e-12);
                assert_same(&format!("p2/p1 at {at}"), new.pressure_ratio, old[2], 1e-12);
                assert_same(
                    &format!("rho2/rho1 at {at}"),
                    new.density_ratio,
                    old[3],
                    1e-12,
                );
                assert_same(
                    &format!("T2/T1 at {at}"),
                    new.temperature_ratio,
                    old[4],
                    1e-12,
                );
                assert_same(
                    &format!("p02/p01 at {at}"),
                    new.total_pressure_ratio,
                    old[5],
                    1e-12,
                );
            }
        }
    }
}

#[test]
fn normal_shock_half_integer_powers_equal_ln_exp() {
    for gamma in [1.2, G, 1.67, 1.3] {
        for mach in log_space(1.0, 50.0, 400) {
            let new = normal_shock(mach, gamma).unwrap();
            let old = reference::normal_shock(mach, gamma);
            let at = format!("M {mach}, gamma {gamma}");
            assert_same(
                &format!("p02/p01 at {at}"),
                new.total_pressure_ratio,
                old[4],
                1e-12,
            );
            assert_same(&format!("M2 at {at}"), new.mach_downstream, old[0], 1e-15);
        }
    }
}

#[test]
fn inverse_prandtl_meyer_by_halley_equals_newton() {
    for gamma in [1.2, G, 1.67, 1.3] {
        for mach in log_space(1.01, 60.0, 2000) {
            let nu = prandtl_meyer(mach, gamma).unwrap();
            let new = inverse_prandtl_meyer(nu, gamma).unwrap();
            let old = reference::inverse_prandtl_meyer(nu, gamma);
            assert_same(
                &format!("M(nu = {nu}) at M {mach}, gamma {gamma}"),
                new,
                old,
                1e-12,
            );
        }
    }
}

#[test]
fn expansion_from_the_upstream_state_equals_the_inverse_from_hall() {
    // The previous expansion: M2 = M(ν(M1) + τ) from Hall's start, p and ρ ratios by `powf`.
    for gamma in [1.2, G, 1.67] {
        for mach in log_space(1.01, 20.0, 80) {
            let nu1 = prandtl_meyer(mach, gamma).unwrap();
            let room = max_prandtl_meyer(gamma) - nu1;
            for turn in log_space(1e-9, 1.0, 60).filter(|t| *t < 0.999 * room) {
                let new = prandtl_meyer_expansion(mach, turn, gamma).unwrap();
                let m2 = reference::inverse_prandtl_meyer(nu1 + turn, gamma);
                let t = total_temperature_ratio(mach, gamma) / total_temperature_ratio(m2, gamma);
                let at = format!("M {mach}, turn {turn}, gamma {gamma}");
                assert_same(&format!("M2 at {at}"), new.mach_downstream, m2, 1e-12);
                assert_same(&format!("T2/T1 at {at}"), new.temperature_ratio, t, 1e-12);
                let p = t.powf(gamma / (gamma - 1.0));
                assert_same(&format!("p2/p1 at {at}"), new.pressure_ratio, p, 1e-11);
                let rho = t.powf(1.0 / (gamma - 1.0));
                assert_same(&format!("rho2/rho1 at {at}"), new.density_ratio, rho, 1e-11);
            }
        }
    }
}

#[test]
fn expansion_from_a_known_angle_equals_the_expansion_from_mach() {
    // A strip's second expansion starts from ν(M1) + τ1 of the first instead of ν(M2): the same
    // state to 1e-12 (ν(M2) = ν(M1) + τ1 holds to the solve's rounding).
    for gamma in [1.2, G, 1.67] {
        for mach in log_space(1.01, 20.0, 40) {
            for first in log_space(1e-6, 0.5, 12) {
                let Ok(a) = prandtl_meyer_expansion(mach, first, gamma) else {
                    continue;
                };
                for second in log_space(1e-9, 0.5, 12) {
                    let fresh = prandtl_meyer_expansion(a.mach_downstream, second, gamma);
                    let known = prandtl_meyer_expansion_from(
                        a.mach_downstream,
                        a.prandtl_meyer_downstream_rad,
                        second,
                        gamma,
                    );
                    let (Ok(fresh), Ok(known)) = (fresh, known) else {
                        continue;
                    };
                    let at = format!("M {mach}, turns {first} + {second}, gamma {gamma}");
                    let pairs = [
                        ("M2", known.mach_downstream, fresh.mach_downstream),
                        ("p2/p1", known.pressure_ratio, fresh.pressure_ratio),
                        ("rho2/rho1", known.density_ratio, fresh.density_ratio),
                    ];
                    for (what, k, f) in pairs {
                        assert_same(&format!("{what} at {at}"), k, f, 1e-12);
                    }
                }
            }
        }
    }
}

#[test]
fn isentropic_powers_equal_powf() {
    for gamma in [1.2, G, 1.67, 1.3, 1.05] {
        for mach in log_space(0.01, 60.0, 400) {
            let t = total_temperature_ratio(mach, gamma);
            let at = format!("M {mach}, gamma {gamma}");
            assert_same(
                &format!("p0/p at {at}"),
                total_pressure_ratio(mach, gamma),
                t.powf(gamma / (gamma - 1.0)),
                1e-13,
            );
            assert_same(
                &format!("rho0/rho at {at}"),
                total_density_ratio(mach, gamma),
                t.powf(1.0 / (gamma - 1.0)),
                1e-13,
            );
            let exponent = 0.5 * (gamma + 1.0) / (gamma - 1.0);
            assert_same(
                &format!("A/A* at {at}"),
                area_mach_ratio(mach, gamma),
                (2.0 / (gamma + 1.0) * t).powf(exponent) / mach,
                1e-13,
            );
        }
    }
}

#[test]
fn kernels_keep_the_published_values() {
    // NACA 1135 Table I, M = 2.00: p/p0 = 0.1278, ρ/ρ0 = 0.2300, A/A* = 1.6875.
    assert!((1.0 / total_pressure_ratio(2.0, G) - 0.1278).abs() <= 0.5e-4);
    assert!((1.0 / total_density_ratio(2.0, G) - 0.2300).abs() <= 0.5e-4);
    assert!((area_mach_ratio(2.0, G) - 1.6875).abs() <= 0.5e-4);
    // NACA 1135 Table II, M = 2.00: p02/p01 = 0.7209.
    let shock = normal_shock(2.0, G).unwrap();
    assert!((shock.total_pressure_ratio - 0.7209).abs() <= 0.5e-4);
    // Çengel & Cimbala: Ma1 = 2, δ = 10°: β_weak = 39.3°, P2/P1 = 128/75, Ma2 = 1.64.
    let weak = oblique_shock(2.0, 10f64.to_radians(), G, ShockBranch::Weak).unwrap();
    assert!((weak.wave_angle_rad.to_degrees() - 39.3).abs() <= 0.05);
    assert!((75.0 * weak.pressure_ratio - 128.0).abs() <= 0.5);
    assert!((weak.mach_downstream - 1.64).abs() <= 0.005);
    // NACA 1135 Table II: ν = 26.38° at M = 2.00 and 84.96° at M = 6.00; inverting them gives
    // the Mach number to the 0.005° rounding of ν (dM = dν / (dν/dM)).
    for (nu_deg, mach) in [(26.38f64, 2.0f64), (84.96, 6.0)] {
        let m = inverse_prandtl_meyer(nu_deg.to_radians(), G).unwrap();
        let x = (mach * mach - 1.0).sqrt();
        let slope = x / (mach * (1.0 + 0.2 * mach * mach));
        assert!(
            (m - mach).abs() <= 0.005f64.to_radians() / slope + 1e-9,
            "M(nu) {m}"
        );
    }
}

/// The small-turn expansion (second order in θ) against 50-digit solutions of the exact
/// relations (mpmath, γ = 1.4): the weak oblique shock of the θ-β-M relation (Anderson MCF eq.
/// 4.17 with NACA 1135 eqs. 93-96) for θ > 0, the Prandtl-Meyer fan (Anderson MCF eq. 4.44,
/// isentropic ratios NACA 1135 eqs. 43-45) for θ < 0. Columns: M1, θ (rad), M2, p2/p1, T2/T1,
/// printed to 20 digits. The expansion must give each to 1e-15 relative, which resolves the
/// turn's whole effect (p2/p1 - 1 is 5.6e-12 at the smallest turn).
#[test]
#[allow(clippy::excessive_precision)] // the reference values as printed, to 20 digits
fn small_turns_match_fifty_digit_shocks_and_fans() {
    let reference: [[f64; 5]; 9] = [
        [
            6.0,
            1e-7,
            5.9999991683683129118,
            1.0000008519157942933,
            1.0000002434044385981,
        ],
        [
            6.0,
            -1e-7,
            6.0000008316318862176,
            0.99999914808481676045,
            0.99999975659558787443,
        ],
        [
            2.0,
            1e-6,
            1.9999979215396309143,
            1.0000032331656141314,
            1.0000009237605373711,
        ],
        [
            2.0,
            -1e-6,
            2.0000020784615690834,
            0.99999676684259920215,
            0.99999907623967596326,
        ],
        [
            20.0,
            3e-8,
            19.999997566957084756,
            1.0000008410522755151,
            1.0000002403005779667,
        ],
        [
            1.2,
            -2e-7,
            1.2000004660157689921,
            0.99999939215346428669,
            0.99999982632952352298,
        ],
        [
            200.0,
            -2e-14,
            200.0000000001600220003,
            0.9999999999943999299987,
            0.9999999999983999799996,
        ],
        [
            4.5,
            2e-11,
            4.499999999896409836,
            1.000000000129231293712,
            1.000000000036923226773,
        ],
        [
            1.5,
            1e-12,
            1.49999999999805462086,
            1.000000000002817445652,
            1.000000000000804984472,
        ],
    ];
    for [mach, theta, m2, p, t] in reference {
        let at = format!("M {mach}, turn {theta:e}");
        let change = small_turn(mach, theta, G).unwrap_or_else(|| panic!("{at}: refused"));
        assert_same(&format!("M2 at {at}"), change.mach_downstream, m2, 1e-15);
        assert_same(&format!("p2/p1 at {at}"), change.pressure_ratio, p, 1e-15);
        assert_same(
            &format!("T2/T1 at {at}"),
            change.temperature_ratio,
            t,
            1e-15,
        );
        assert_same(
            &format!("rho2/rho1 at {at}"),
            change.density_ratio,
            p / t,
            1e-15,
        );
    }
}

/// Wherever the small-turn expansion accepts a turn (M 1.02 to 500, |θ| from 1e-14 to 1e-5,
/// both signs) it refuses every turn above 1.26e-6 rad, accepts the panel-to-panel turns it is
/// for (θ ≤ 1e-7 at M 1.5 to 20), and from 1e-8 rad up gives the weak shock's or the fan's
/// state to 1e-15 plus 1e-7 of the turn's change: the exact paths resolve a turn through ν(M)
/// or β, so to about 4e-16/θ of the change (at M 200, θ = -2e-14 the fan is 2 % off the change
/// the 50-digit value gives; the expansion is checked there by
/// `small_turns_match_fifty_digit_shocks_and_fans`).
#[test]
fn small_turns_agree_with_the_exact_turns_wherever_accepted() {
    let close = |what: &str, new: f64, old: f64, upstream: f64| {
        let tolerance = 1e-15 * upstream.abs() + 1e-7 * (old - upstream).abs();
        assert!(
            (new - old).abs() <= tolerance,
            "{what}: new {new:e}, old {old:e}, tolerance {tolerance:e}"
        );
    };
    let mut compared = 0;
    for mach in log_space(1.02, 500.0, 80) {
        for size in log_space(1e-14, 1e-5, 60) {
            for theta in [size, -size] {
                let Some(change) = small_turn(mach, theta, G) else {
                    assert!(
                        size > 1e-7 || !(1.5..=20.0).contains(&mach),
                        "M {mach}, turn {theta:e} refused"
                    );
                    continue;
                };
                assert!(size <= 1.26e-6, "M {mach}, turn {theta:e} accepted");
                if size < 1e-8 {
                    continue;
                }
                compared += 1;
                let at = format!("M {mach}, turn {theta:e}");
                let (m2, p, t, rho) = if theta > 0.0 {
                    let s = oblique_shock(mach, theta, G, ShockBranch::Weak).unwrap();
                    (
                        s.mach_downstream,
                        s.pressure_ratio,
                        s.temperature_ratio,
                        s.density_ratio,
                    )
                } else {
                    let e = prandtl_meyer_expansion(mach, -theta, G).unwrap();
                    (
                        e.mach_downstream,
                        e.pressure_ratio,
                        e.temperature_ratio,
                        e.density_ratio,
                    )
                };
                close(&format!("M2 at {at}"), change.mach_downstream, m2, mach);
                close(&format!("p2/p1 at {at}"), change.pressure_ratio, p, 1.0);
                close(&format!("T2/T1 at {at}"), change.temperature_ratio, t, 1.0);
                close(
                    &format!("rho2/rho1 at {at}"),
                    change.density_ratio,
                    rho,
                    1.0,
                );
            }
        }
    }
    assert!(compared > 500, "{compared} turns compared");
}

/// The weak shock's state change without its wave angle against published values: the Çengel &
/// Cimbala example (Ma1 = 2, δ = 10°: P2/P1 = 128/75 from their chart's 1.71, Ma2 = 1.64, to half
/// a unit in the last printed digit) and the maximum deflection of NACA 1135 (M = 3: θ_max =
/// 34.07°): attached at 34.0°, detached at 34.1°.
#[test]
fn the_weak_turn_keeps_the_published_oblique_shock_values() {
    let weak = weak_oblique_turn(2.0, 10f64.to_radians(), G).unwrap();
    assert!(
        (75.0 * weak.pressure_ratio - 128.0).abs() <= 0.5,
        "{weak:?}"
    );
    assert!((weak.mach_downstream - 1.64).abs() <= 0.005, "{weak:?}");
    assert!(
        (weak.density_ratio * weak.temperature_ratio - weak.pressure_ratio).abs() <= 1e-12,
        "perfect gas: p2/p1 = (rho2/rho1)(T2/T1)"
    );
    assert!(weak_oblique_turn(3.0, 34.0f64.to_radians(), G).is_ok());
    assert!(matches!(
        weak_oblique_turn(3.0, 34.1f64.to_radians(), G),
        Err(GasError::Detached { .. })
    ));
}
