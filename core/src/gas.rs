//! Perfect-gas relations: isentropic flow, normal and oblique shocks, Prandtl-Meyer expansions,
//! Rayleigh flow, pitot and Newtonian stagnation pressures, and piston theory (one file: the
//! relations build on each other and share the input checks and the safeguarded solver; the
//! cheaper inner kernels are in `gas/kernels.rs`).
//!
//! Calorically perfect gas with constant ratio of specific heats γ. SI units; angles in radians.
//! References: NACA Report 1135 (Ames Research Staff, 1953, "Equations, Tables, and Charts for
//! Compressible Flow"); J. D. Anderson, "Modern Compressible Flow" (MCF) and "Hypersonic and
//! High-Temperature Gas Dynamics"; Lighthill (1953) and Ashley & Zartarian (1956) for piston theory.
//!
//! Functions returning a bare `f64` are closed forms that assume valid input (Mach ≥ 0, γ > 1) and
//! propagate NaN; every function that can fail checks its input and returns
//! `Result<_, GasError>`.

use std::f64::consts::FRAC_PI_2;

mod kernels;

use kernels::{cubic_and_slope, halley, mach_wave_cubic, pow_half_integer};

/// Ratio of specific heats of air below dissociation temperatures.
pub const GAMMA_AIR: f64 = 1.4;

/// Specific gas constant of dry air, J/(kg K): R*/M0 with R* = 8314.32 J/(kmol K) and
/// M0 = 28.96442 kg/kmol (the ICAO Standard Atmosphere value; USSA-1976's M0 = 28.9644 gives
/// 287.0531, 7e-7 relative difference).
pub const GAS_CONSTANT_AIR: f64 = 287.052_87;

/// A calorically perfect gas: constant γ and specific gas constant R.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PerfectGas {
    /// Ratio of specific heats γ = cp/cv (> 1).
    pub gamma: f64,
    /// Specific gas constant R, J/(kg K).
    pub gas_constant_j_kg_k: f64,
}

impl PerfectGas {
    /// Dry air: γ = 1.4, R = 287.05287 J/(kg K).
    pub const AIR: PerfectGas = PerfectGas {
        gamma: GAMMA_AIR,
        gas_constant_j_kg_k: GAS_CONSTANT_AIR,
    };

    /// A perfect gas with finite γ > 1 and finite R > 0 (J/(kg K)).
    pub fn new(gamma: f64, gas_constant_j_kg_k: f64) -> Result<Self, GasError> {
        check_gamma(gamma)?;
        let r = finite("gas constant (J/(kg K))", gas_constant_j_kg_k)?;
        if r <= 0.0 {
            return Err(GasError::out_of_range(
                "gas constant (J/(kg K))",
                r,
                "R > 0",
            ));
        }
        Ok(Self {
            gamma,
            gas_constant_j_kg_k,
        })
    }

    /// a = √(γ R T), m/s, for static temperature T in K (NaN for T < 0).
    pub fn speed_of_sound(&self, temperature_k: f64) -> f64 {
        (self.gamma * self.gas_constant_j_kg_k * temperature_k).sqrt()
    }

    /// cp = γ R / (γ - 1), J/(kg K).
    pub fn cp(&self) -> f64 {
        self.gamma * self.gas_constant_j_kg_k / (self.gamma - 1.0)
    }

    /// cv = R / (γ - 1), J/(kg K).
    pub fn cv(&self) -> f64 {
        self.gas_constant_j_kg_k / (self.gamma - 1.0)
    }
}

impl Default for PerfectGas {
    fn default() -> Self {
        Self::AIR
    }
}

/// Why a gas-dynamic relation could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GasError {
    /// The relation needs supersonic flow.
    #[error("Mach number {mach} is subsonic; {needed}")]
    Subsonic {
        /// The Mach number given.
        mach: f64,
        /// What needs supersonic flow, e.g. "an oblique shock needs M >= 1".
        needed: &'static str,
    },
    /// The deflection exceeds the maximum for an attached oblique shock.
    #[error(
        "deflection {deflection_rad} rad exceeds the maximum {max_deflection_rad} rad for an \
         attached oblique shock at Mach {mach}; the shock detaches"
    )]
    Detached {
        /// Upstream Mach number.
        mach: f64,
        /// Deflection asked for, rad.
        deflection_rad: f64,
        /// Largest deflection with an attached shock at this Mach number, rad.
        max_deflection_rad: f64,
    },
    /// An input is NaN or infinite.
    #[error("{quantity} is not finite (NaN or infinite)")]
    NonFinite {
        /// The input's name.
        quantity: &'static str,
    },
    /// An input is outside the relation's domain.
    #[error("{quantity} = {value} is out of range; allowed: {allowed}")]
    OutOfRange {
        /// The input's name.
        quantity: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range.
        allowed: String,
    },
    /// More heat than the flow can take: T0/T0* > 1 chokes a Rayleigh flow.
    #[error(
        "total temperature ratio T0/T0* = {total_temperature_ratio} exceeds 1: the heat addition \
         would thermally choke the Rayleigh flow"
    )]
    ThermalChoking {
        /// The T0/T0* given.
        total_temperature_ratio: f64,
    },
    /// A Prandtl-Meyer turn past ν_max: the flow would expand to vacuum.
    #[error(
        "turning Mach {mach} flow by {turn_rad} rad exceeds the {max_turn_rad} rad left before \
         ν_max; the flow would expand to vacuum"
    )]
    VacuumExpansion {
        /// Upstream Mach number.
        mach: f64,
        /// Turn asked for, rad.
        turn_rad: f64,
        /// ν_max - ν(M), rad.
        max_turn_rad: f64,
    },
    /// A piston withdrawing faster than the gas can follow: the pressure would fall below zero.
    #[error(
        "normal velocity ratio w/a = {normal_velocity_over_sound_speed} is at or below the \
         cavitation limit {limit} = -2/(γ-1); the gas separates from the surface"
    )]
    Cavitation {
        /// The w/a given.
        normal_velocity_over_sound_speed: f64,
        /// -2/(γ-1).
        limit: f64,
    },
}

impl GasError {
    fn out_of_range(quantity: &'static str, value: f64, allowed: impl Into<String>) -> Self {
        Self::OutOfRange {
            quantity,
            value,
            allowed: allowed.into(),
        }
    }
}

/// Which of the two oblique-shock solutions for a given deflection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ShockBranch {
    /// Smaller wave angle; downstream flow (nearly always) supersonic. What wedges and ramps show.
    Weak,
    /// Larger wave angle; downstream flow subsonic.
    Strong,
}

/// Which of the two Mach numbers sharing an area ratio (or Rayleigh total-temperature ratio).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum FlowBranch {
    /// M < 1.
    Subsonic,
    /// M > 1.
    Supersonic,
}

// ---------------------------------------------------------------------------------------------
// Input checks
// ---------------------------------------------------------------------------------------------

fn finite(quantity: &'static str, value: f64) -> Result<f64, GasError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(GasError::NonFinite { quantity })
    }
}

fn check_gamma(gamma: f64) -> Result<f64, GasError> {
    let g = finite("ratio of specific heats gamma", gamma)?;
    if g <= 1.0 {
        return Err(GasError::out_of_range(
            "ratio of specific heats gamma",
            g,
            "gamma > 1",
        ));
    }
    Ok(g)
}

fn check_mach_nonnegative(mach: f64) -> Result<f64, GasError> {
    let m = finite("Mach number", mach)?;
    if m < 0.0 {
        return Err(GasError::out_of_range("Mach number", m, "M >= 0"));
    }
    Ok(m)
}

fn check_supersonic(mach: f64, needed: &'static str) -> Result<f64, GasError> {
    let m = finite("Mach number", mach)?;
    if m < 1.0 {
        return Err(GasError::Subsonic { mach: m, needed });
    }
    Ok(m)
}

/// Root of `f` in `[lo, hi]` by Newton's method safeguarded with bisection (Numerical Recipes
/// `rtsafe`). `f` returns (value, derivative); `increasing` tells the sign of `f` across the
/// bracket (f(lo) <= 0 <= f(hi) when true). Stops when |f| <= `f_tolerance`, when the Newton step
/// falls to 4 ulp, when the bracket closes, or when |f| stops falling once within 1e-6 of the root
/// (the residual's rounding noise has been reached).
fn solve_bracketed(
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

// ---------------------------------------------------------------------------------------------
// Isentropic flow
// ---------------------------------------------------------------------------------------------

/// T0/T = 1 + (γ-1)/2 M² (NACA 1135 eq. 43).
pub fn total_temperature_ratio(mach: f64, gamma: f64) -> f64 {
    1.0 + 0.5 * (gamma - 1.0) * mach * mach
}

/// p0/p = (1 + (γ-1)/2 M²)^(γ/(γ-1)) (NACA 1135 eq. 44).
pub fn total_pressure_ratio(mach: f64, gamma: f64) -> f64 {
    pow_half_integer(total_temperature_ratio(mach, gamma), gamma / (gamma - 1.0))
}

/// ρ0/ρ = (1 + (γ-1)/2 M²)^(1/(γ-1)) (NACA 1135 eq. 45).
pub fn total_density_ratio(mach: f64, gamma: f64) -> f64 {
    pow_half_integer(total_temperature_ratio(mach, gamma), 1.0 / (gamma - 1.0))
}

/// A/A* = (1/M) [2/(γ+1) (1 + (γ-1)/2 M²)]^((γ+1)/(2(γ-1))) (NACA 1135 eq. 80); ∞ at M = 0.
pub fn area_mach_ratio(mach: f64, gamma: f64) -> f64 {
    let exponent = 0.5 * (gamma + 1.0) / (gamma - 1.0);
    pow_half_integer(
        2.0 / (gamma + 1.0) * total_temperature_ratio(mach, gamma),
        exponent,
    ) / mach
}

/// M from A/A* >= 1 on the chosen branch: inverse of NACA 1135 eq. 80 by safeguarded Newton in ln M.
pub fn mach_from_area_ratio(
    area_ratio: f64,
    gamma: f64,
    branch: FlowBranch,
) -> Result<f64, GasError> {
    mach_from_area_ratio_near(area_ratio, gamma, branch, None)
}

/// [`mach_from_area_ratio`] with Newton started at `mach_guess` when it lies inside the branch's
/// bracket: for a march through slowly changing areas (a nozzle's stations), where the last
/// station's Mach number is a start a few iterations from the root.
pub fn mach_from_area_ratio_near(
    area_ratio: f64,
    gamma: f64,
    branch: FlowBranch,
    mach_guess: Option<f64>,
) -> Result<f64, GasError> {
    let gamma = check_gamma(gamma)?;
    let target = finite("area ratio A/A*", area_ratio)?;
    if target < 1.0 {
        return Err(GasError::out_of_range(
            "area ratio A/A*",
            target,
            "A/A* >= 1",
        ));
    }
    if target == 1.0 {
        return Ok(1.0);
    }
    let ln_target = target.ln();
    let half_gm1 = 0.5 * (gamma - 1.0);
    let exponent = 0.5 * (gamma + 1.0) / (gamma - 1.0);
    // Residual in u = ln M: ln(A/A*) - ln(target), slope d ln(A/A*)/d ln M = (M²-1)/(1 + (γ-1)/2 M²).
    let residual = |u: f64| {
        let m = u.exp();
        let t = 1.0 + half_gm1 * m * m;
        let value = exponent * (2.0 / (gamma + 1.0) * t).ln() - u - ln_target;
        (value, (m - 1.0) * (m + 1.0) / t)
    };
    // Near M = 1: ln(A/A*) ≈ 2 (M-1)² / (γ+1).
    let near_sonic = (0.5 * (gamma + 1.0) * ln_target).sqrt();
    let f_tolerance = 4.0 * f64::EPSILON * ln_target.max(1.0);
    let ln_mach = match branch {
        FlowBranch::Subsonic => {
            // A/A* > (1/M) (1 + (γ-1)/2)^(-exponent), so M_lo = (1 + (γ-1)/2)^(-exponent) / target.
            let ln_lo = -exponent * (1.0 + half_gm1).ln() - ln_target;
            let guess = mach_guess.map_or_else(
                || ln_lo.max((1.0 - near_sonic).max(f64::MIN_POSITIVE).ln()),
                f64::ln,
            );
            solve_bracketed(residual, ln_lo, 0.0, guess, false, f_tolerance)
        }
        FlowBranch::Supersonic => {
            // A/A* > K M^(2/(γ-1)) with K = ((γ-1)/(γ+1))^exponent.
            let ln_k = exponent * ((gamma - 1.0) / (gamma + 1.0)).ln();
            let ln_hi = (half_gm1 * (ln_target - ln_k)).max(near_sonic.ln_1p());
            let guess = mach_guess.map_or_else(|| ln_hi.min(near_sonic.ln_1p()), f64::ln);
            solve_bracketed(residual, 0.0, ln_hi, guess, true, f_tolerance)
        }
    };
    let mach = ln_mach.exp();
    Ok(mach)
}

/// M = √(2/(γ-1) ((p0/p)^((γ-1)/γ) - 1)), inverse of NACA 1135 eq. 44; needs p0/p >= 1.
pub fn mach_from_total_pressure_ratio(p0_over_p: f64, gamma: f64) -> Result<f64, GasError> {
    let gamma = check_gamma(gamma)?;
    let ratio = finite("total pressure ratio p0/p", p0_over_p)?;
    if ratio < 1.0 {
        return Err(GasError::out_of_range(
            "total pressure ratio p0/p",
            ratio,
            "p0/p >= 1",
        ));
    }
    let excess = ((gamma - 1.0) / gamma * ratio.ln()).exp_m1();
    Ok((2.0 / (gamma - 1.0) * excess).sqrt())
}

/// μ = asin(1/M), rad, for M >= 1 (Mach angle; Anderson MCF eq. 4.1).
pub fn mach_angle(mach: f64) -> Result<f64, GasError> {
    let m = check_supersonic(mach, "a Mach angle needs M >= 1")?;
    Ok((1.0 / m).asin())
}

// ---------------------------------------------------------------------------------------------
// Normal shock
// ---------------------------------------------------------------------------------------------

/// State change across a normal shock; every ratio is downstream over upstream.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct NormalShock {
    /// M2 < 1 (= 1 for a Mach-1 "shock").
    pub mach_downstream: f64,
    /// p2/p1.
    pub pressure_ratio: f64,
    /// ρ2/ρ1 (= u1/u2).
    pub density_ratio: f64,
    /// T2/T1.
    pub temperature_ratio: f64,
    /// p02/p01 <= 1 (entropy rise).
    pub total_pressure_ratio: f64,
}

/// Normal-shock relations for M >= 1 (unchecked): NACA 1135 eqs. 93 (p), 94 (ρ), 96 (M2), 99 (p0).
fn normal_shock_unchecked(mach: f64, gamma: f64) -> NormalShock {
    normal_shock_of_mach_squared(mach.max(1.0).powi(2), gamma)
}

/// [`normal_shock_unchecked`] from M² >= 1, so an oblique shock passes M² sin²β without a root.
fn normal_shock_of_mach_squared(m2: f64, gamma: f64) -> NormalShock {
    let pressure_ratio = 1.0 + 2.0 * gamma / (gamma + 1.0) * (m2 - 1.0);
    let density_ratio = (gamma + 1.0) * m2 / ((gamma - 1.0) * m2 + 2.0);
    let mach_downstream = (((gamma - 1.0) * m2 + 2.0) / (2.0 * gamma * m2 - (gamma - 1.0))).sqrt();
    // p02/p01 = (ρ2/ρ1)^(γ/(γ-1)) (p2/p1)^(-1/(γ-1)) = (ρ2/ρ1) (T2/T1)^(-1/(γ-1)).
    let temperature_ratio = pressure_ratio / density_ratio;
    let total_pressure_ratio =
        density_ratio * pow_half_integer(temperature_ratio, -1.0 / (gamma - 1.0));
    NormalShock {
        mach_downstream,
        pressure_ratio,
        density_ratio,
        temperature_ratio,
        total_pressure_ratio: total_pressure_ratio.min(1.0),
    }
}

/// Normal shock at upstream M >= 1: Rankine-Hugoniot ratios (NACA 1135 eqs. 93-99).
pub fn normal_shock(mach: f64, gamma: f64) -> Result<NormalShock, GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_supersonic(mach, "a normal shock needs M >= 1")?;
    Ok(normal_shock_unchecked(m, gamma))
}

// ---------------------------------------------------------------------------------------------
// Oblique shock
// ---------------------------------------------------------------------------------------------

/// State change across a planar oblique shock; ratios are downstream over upstream.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ObliqueShock {
    /// Wave (shock) angle β to the upstream flow, rad.
    pub wave_angle_rad: f64,
    /// Flow deflection θ, rad.
    pub deflection_rad: f64,
    /// M1 sin β.
    pub normal_mach_upstream: f64,
    /// M2 = M2n / sin(β - θ).
    pub mach_downstream: f64,
    /// p2/p1.
    pub pressure_ratio: f64,
    /// ρ2/ρ1.
    pub density_ratio: f64,
    /// T2/T1.
    pub temperature_ratio: f64,
    /// p02/p01.
    pub total_pressure_ratio: f64,
}

/// θ-β-M relation as (numerator, denominator) of tan θ = 2 cot β (M² sin²β - 1) / (M² (γ + cos 2β) + 2).
fn theta_beta_parts(mach: f64, beta: f64, gamma: f64) -> (f64, f64) {
    let m2 = mach * mach;
    let (s, c) = beta.sin_cos();
    let numerator = 2.0 * c / s * (m2 * s * s - 1.0);
    let denominator = m2 * (gamma + (2.0 * beta).cos()) + 2.0;
    (numerator, denominator)
}

/// θ(β) and dθ/dβ for the safeguarded Newton polish.
fn theta_and_slope(mach: f64, beta: f64, gamma: f64) -> (f64, f64) {
    let m2 = mach * mach;
    let (s, c) = beta.sin_cos();
    let (n, d) = theta_beta_parts(mach, beta, gamma);
    let dn = -2.0 * (m2 * s * s - 1.0) / (s * s) + 4.0 * m2 * c * c;
    let dd = -2.0 * m2 * (2.0 * beta).sin();
    (n.atan2(d), (dn * d - n * dd) / (d * d + n * n))
}

/// Deflection θ(β) = atan[2 cot β (M² sin²β - 1) / (M² (γ + cos 2β) + 2)], rad (θ-β-M relation,
/// Anderson MCF eq. 4.17). Negative for β below the Mach angle.
pub fn deflection_from_wave_angle(mach: f64, wave_angle_rad: f64, gamma: f64) -> f64 {
    let (n, d) = theta_beta_parts(mach, wave_angle_rad, gamma);
    n.atan2(d)
}

/// sin²β at maximum deflection: [(γ+1)M² - 4 + √((γ+1)((γ+1)M⁴ + 8(γ-1)M² + 16))] / (4γM²)
/// (NACA 1135, oblique-shock maximum-deflection relation).
fn sin2_wave_angle_at_max_deflection(mach: f64, gamma: f64) -> f64 {
    let m2 = mach * mach;
    let gp1 = gamma + 1.0;
    let root = (gp1 * (gp1 * m2 * m2 + 8.0 * (gamma - 1.0) * m2 + 16.0)).sqrt();
    let sin2 = (gp1 * m2 - 4.0 + root) / (4.0 * gamma * m2);
    sin2.clamp(0.0, 1.0)
}

/// (θ_max, sin²β at θ_max) for M >= 1: every detachment test uses this one value of θ_max.
fn max_deflection_sin2(mach: f64, gamma: f64) -> (f64, f64) {
    let x_max = sin2_wave_angle_at_max_deflection(mach, gamma);
    let (numerator, denominator) = theta_beta_parts_of_sin2(mach * mach, x_max, gamma);
    (numerator.atan2(denominator).max(0.0), x_max)
}

/// (θ_max, β at θ_max), rad, from [`max_deflection_sin2`].
fn max_deflection_unchecked(mach: f64, gamma: f64) -> (f64, f64) {
    let (theta_max, x_max) = max_deflection_sin2(mach, gamma);
    (theta_max, x_max.sqrt().asin())
}

/// (numerator, denominator > 0) of tan θ in [`theta_beta_parts`] from M² and x = sin²β
/// (cot β = √((1-x)/x), cos 2β = 1 - 2x).
fn theta_beta_parts_of_sin2(mach2: f64, x: f64, gamma: f64) -> (f64, f64) {
    let cot = ((1.0 - x) / x).sqrt();
    let numerator = 2.0 * cot * (mach2 * x - 1.0);
    let denominator = mach2 * (gamma + 1.0 - 2.0 * x) + 2.0;
    (numerator, denominator)
}

/// (θ_max, β at θ_max), rad, for M >= 1: closed-form sin²β at θ_max (NACA 1135) into the θ-β-M
/// relation.
pub fn max_deflection(mach: f64, gamma: f64) -> Result<(f64, f64), GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_supersonic(mach, "an oblique shock needs M >= 1")?;
    Ok(max_deflection_unchecked(m, gamma))
}

/// Thompson's closed form for β(M, θ) (Thompson 1950, as given in Anderson MCF ch. 4):
/// tan β = [M² - 1 + 2λ cos((4πδ + acos χ)/3)] / [3 (1 + (γ-1)/2 M²) tan θ], δ = 1 weak, 0 strong.
fn wave_angle_closed_form(mach: f64, theta: f64, gamma: f64, branch: ShockBranch) -> f64 {
    thompson_tan_wave_angle(mach, theta.tan(), gamma, branch).atan()
}

/// tan β of [`wave_angle_closed_form`] from t = tan θ.
fn thompson_tan_wave_angle(mach: f64, t: f64, gamma: f64, branch: ShockBranch) -> f64 {
    let m2 = mach * mach;
    let a = 1.0 + 0.5 * (gamma - 1.0) * m2;
    let lambda2 = (m2 - 1.0).powi(2) - 3.0 * a * (1.0 + 0.5 * (gamma + 1.0) * m2) * t * t;
    let lambda = lambda2.max(0.0).sqrt();
    let chi = ((m2 - 1.0).powi(3) - 9.0 * a * (a + 0.25 * (gamma + 1.0) * m2 * m2) * t * t)
        / (lambda * lambda * lambda);
    let delta = match branch {
        ShockBranch::Weak => 1.0,
        ShockBranch::Strong => 0.0,
    };
    let angle = (4.0 * std::f64::consts::PI * delta + chi.clamp(-1.0, 1.0).acos()) / 3.0;
    (m2 - 1.0 + 2.0 * lambda * angle.cos()) / (3.0 * a * t)
}

/// Oblique-shock ratios from M and β: normal-shock relations on M1n = M1 sin β, M2 = M2n / sin(β - θ).
fn oblique_from_beta(mach: f64, beta: f64, theta: f64, gamma: f64) -> ObliqueShock {
    let normal_mach_upstream = (mach * beta.sin()).max(1.0);
    let normal = normal_shock_unchecked(normal_mach_upstream, gamma);
    let turn = beta - theta;
    let mach_downstream = if turn > 0.0 {
        normal.mach_downstream / turn.sin()
    } else {
        0.0
    };
    ObliqueShock {
        wave_angle_rad: beta,
        deflection_rad: theta,
        normal_mach_upstream,
        mach_downstream,
        pressure_ratio: normal.pressure_ratio,
        density_ratio: normal.density_ratio,
        temperature_ratio: normal.temperature_ratio,
        total_pressure_ratio: normal.total_pressure_ratio,
    }
}

/// Oblique-shock ratios from M and y = sin²β - 1/M²: normal-shock relations on
/// M1n² = M² sin²β = 1 + M² y, M2 = M2n / sin(β - θ) with sin(β - θ) = sin β cos θ - cos β sin θ.
fn oblique_from_mach_wave_offset(
    mach: f64,
    y: f64,
    theta: f64,
    (sin_theta, cos_theta): (f64, f64),
    gamma: f64,
) -> ObliqueShock {
    let (change, normal_mach2, normal, (sin_beta, cos_beta)) =
        change_from_mach_wave_offset(mach, y, (sin_theta, cos_theta), gamma);
    ObliqueShock {
        wave_angle_rad: sin_beta.atan2(cos_beta),
        deflection_rad: theta,
        normal_mach_upstream: normal_mach2.sqrt(),
        mach_downstream: change.mach_downstream,
        pressure_ratio: change.pressure_ratio,
        density_ratio: change.density_ratio,
        temperature_ratio: change.temperature_ratio,
        total_pressure_ratio: normal.total_pressure_ratio,
    }
}

/// The state change of [`oblique_from_mach_wave_offset`] with M1n², the normal shock on it and
/// (sin β, cos β): everything but the wave angle (an `atan2`).
fn change_from_mach_wave_offset(
    mach: f64,
    y: f64,
    (sin_theta, cos_theta): (f64, f64),
    gamma: f64,
) -> (TurnChange, f64, NormalShock, (f64, f64)) {
    let m2 = mach * mach;
    let normal_mach2 = (1.0 + m2 * y).max(1.0);
    let normal = normal_shock_of_mach_squared(normal_mach2, gamma);
    // sin²β = 1/M² + y, cos²β = (1 - 1/M²) - y.
    let sin_beta = (1.0 / m2 + y).sqrt();
    let cos_beta = ((mach - 1.0) * (mach + 1.0) / m2 - y).max(0.0).sqrt();
    let sin_turn = sin_beta * cos_theta - cos_beta * sin_theta;
    let change = TurnChange {
        mach_downstream: if sin_turn > 0.0 {
            normal.mach_downstream / sin_turn
        } else {
            0.0
        },
        pressure_ratio: normal.pressure_ratio,
        temperature_ratio: normal.temperature_ratio,
        density_ratio: normal.density_ratio,
    };
    (change, normal_mach2, normal, (sin_beta, cos_beta))
}

/// Weak oblique shock for θ >= 0 (checked inputs): y = sin²β - 1/M², the root of the θ-β-M
/// cubic (NACA 1135 eq. 150, [`mach_wave_cubic`]) between the Mach wave y = 0 and θ_max, by
/// safeguarded Newton from Thompson's closed form. One `sin_cos` of θ and no trigonometry
/// inside the iteration, where the β form needs a `sin_cos` and an `atan2` per step; the same
/// root to rounding.
fn weak_oblique_shock(m: f64, theta: f64, gamma: f64) -> Result<ObliqueShock, GasError> {
    let (y, trig) = weak_mach_wave_offset(m, theta, gamma)?;
    Ok(oblique_from_mach_wave_offset(m, y, theta, trig, gamma))
}

/// y = sin²β - 1/M² of the weak shock of checked (M, θ) and (sin θ, cos θ), or the detachment
/// error ([`weak_oblique_shock`]).
fn weak_mach_wave_offset(m: f64, theta: f64, gamma: f64) -> Result<(f64, (f64, f64)), GasError> {
    let x_max = sin2_wave_angle_at_max_deflection(m, gamma);
    let (numerator, denominator) = theta_beta_parts_of_sin2(m * m, x_max, gamma);
    let trig = theta.sin_cos();
    // tan θ_max = numerator / denominator with θ_max < π/2 and denominator > 0, so for θ < π/2
    // sin θ · denominator - numerator · cos θ has the sign of θ - θ_max: θ_max itself (an
    // atan2) is needed only near a tie or past it, and is then the value of [`max_deflection`].
    let gap = trig.0 * denominator - numerator * trig.1;
    let clear = theta < FRAC_PI_2 && gap < -1e-9 * (trig.0 * denominator).abs();
    let at_max = if clear {
        false
    } else {
        let theta_max = numerator.atan2(denominator).max(0.0);
        if theta > theta_max {
            return Err(GasError::Detached {
                mach: m,
                deflection_rad: theta,
                max_deflection_rad: theta_max,
            });
        }
        theta == theta_max
    };
    let x_mach_wave = 1.0 / (m * m);
    let y_max = x_max - x_mach_wave;
    let y = if at_max {
        y_max
    } else if theta == 0.0 {
        0.0
    } else {
        let cubic = mach_wave_cubic(m, trig.0, gamma);
        // Below tan θ = 0.1 tan θ_max the root of the cubic without its y³ term (y is small
        // there) starts Newton two or three steps from the root, cheaper than Thompson's
        // closed form (an `acos` and a `cos`), which also loses precision as θ → 0.
        let guess = if trig.0 * denominator < 0.1 * numerator * trig.1 {
            small_deflection_start(cubic)
        } else {
            let t = thompson_tan_wave_angle(m, trig.0 / trig.1, gamma, ShockBranch::Weak);
            t * t / (1.0 + t * t) - x_mach_wave
        };
        solve_bracketed(|y| cubic_and_slope(cubic, y), 0.0, y_max, guess, false, 0.0)
    };
    Ok((y, trig))
}

/// Positive root of B y² + C y + D = 0 (B < 0 < D), the cubic of [`mach_wave_cubic`] without
/// its y³ term, in the form without cancellation for either sign of C.
fn small_deflection_start([b, c, d]: [f64; 3]) -> f64 {
    let root = (c * c - 4.0 * b * d).sqrt();
    if c >= 0.0 {
        (c + root) / (-2.0 * b)
    } else {
        2.0 * d / (root - c)
    }
}

/// (M >= 1, θ >= 0, γ > 1) of an oblique shock, or the error naming the bad one.
fn check_oblique(mach: f64, deflection_rad: f64, gamma: f64) -> Result<(f64, f64, f64), GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_supersonic(mach, "an oblique shock needs M >= 1")?;
    let theta = finite("deflection (rad)", deflection_rad)?;
    if theta < 0.0 {
        return Err(GasError::out_of_range(
            "deflection (rad)",
            theta,
            "theta >= 0 (a negative turn is an expansion)",
        ));
    }
    Ok((m, theta, gamma))
}

/// Oblique shock turning M >= 1 flow by θ in [0, θ_max] rad on the chosen branch: on the weak
/// branch the root of the θ-β-M cubic in sin²β (`weak_oblique_shock`); on the strong branch
/// Thompson's closed form polished by safeguarded Newton on the θ-β-M relation (Anderson MCF
/// eq. 4.17).
pub fn oblique_shock(
    mach: f64,
    deflection_rad: f64,
    gamma: f64,
    branch: ShockBranch,
) -> Result<ObliqueShock, GasError> {
    let (m, theta, gamma) = check_oblique(mach, deflection_rad, gamma)?;
    if branch == ShockBranch::Weak {
        return weak_oblique_shock(m, theta, gamma);
    }
    let (theta_max, beta_max) = max_deflection_unchecked(m, gamma);
    if theta > theta_max {
        return Err(GasError::Detached {
            mach: m,
            deflection_rad: theta,
            max_deflection_rad: theta_max,
        });
    }
    let beta = if theta == theta_max {
        beta_max
    } else if theta == 0.0 {
        FRAC_PI_2
    } else {
        let guess = wave_angle_closed_form(m, theta, gamma, ShockBranch::Strong);
        let residual = |b: f64| {
            let (t, slope) = theta_and_slope(m, b, gamma);
            (t - theta, slope)
        };
        // θ(β) carries a few ulp of rounding; stop there.
        let f_tolerance = 8.0 * f64::EPSILON;
        solve_bracketed(residual, beta_max, FRAC_PI_2, guess, false, f_tolerance)
    };
    Ok(oblique_from_beta(m, beta, theta, gamma))
}

/// The weak [`oblique_shock`]'s state change alone (M2 and the static ratios, without the wave
/// angle and its `atan2`): the panel-to-panel compression of shock-expansion theory.
pub fn weak_oblique_turn(
    mach: f64,
    deflection_rad: f64,
    gamma: f64,
) -> Result<TurnChange, GasError> {
    let (m, theta, gamma) = check_oblique(mach, deflection_rad, gamma)?;
    let (y, trig) = weak_mach_wave_offset(m, theta, gamma)?;
    Ok(change_from_mach_wave_offset(m, y, trig, gamma).0)
}

/// Oblique shock from M >= 1 and wave angle β in [asin(1/M), π/2] rad; θ from the θ-β-M relation.
pub fn oblique_shock_from_wave_angle(
    mach: f64,
    wave_angle_rad: f64,
    gamma: f64,
) -> Result<ObliqueShock, GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_supersonic(mach, "an oblique shock needs M >= 1")?;
    let beta = finite("wave angle (rad)", wave_angle_rad)?;
    let mu = (1.0 / m).asin();
    // Allow a few ulp below the Mach angle so asin(1/M) computed by a caller is accepted.
    if beta < mu - 8.0 * f64::EPSILON || beta > FRAC_PI_2 + 8.0 * f64::EPSILON {
        return Err(GasError::out_of_range(
            "wave angle (rad)",
            beta,
            format!("Mach angle asin(1/M) = {mu} <= beta <= pi/2"),
        ));
    }
    let beta = beta.clamp(mu, FRAC_PI_2);
    let theta = deflection_from_wave_angle(m, beta, gamma).max(0.0);
    Ok(oblique_from_beta(m, beta, theta, gamma))
}

// ---------------------------------------------------------------------------------------------
// Prandtl-Meyer expansion
// ---------------------------------------------------------------------------------------------

/// √((γ+1)/(γ-1)), the Prandtl-Meyer scale.
fn pm_scale(gamma: f64) -> f64 {
    ((gamma + 1.0) / (gamma - 1.0)).sqrt()
}

/// ν(x) = a atan(x/a) - atan(x) with x = √(M²-1), a = √((γ+1)/(γ-1)).
fn pm_of_x(x: f64, a: f64) -> f64 {
    a * (x / a).atan() - x.atan()
}

/// ν_max - ν(x) = a atan(a/x) - atan(1/x), accurate for large x.
fn pm_deficit_of_x(x: f64, a: f64) -> f64 {
    a * (a / x).atan() - (1.0 / x).atan()
}

/// dν/dx = x² (1 - 1/a²) / ((1 + x²/a²)(1 + x²)).
fn pm_slope_of_x(x: f64, a: f64) -> f64 {
    let x2 = x * x;
    x2 * (1.0 - 1.0 / (a * a)) / ((1.0 + x2 / (a * a)) * (1.0 + x2))
}

/// (dν/dx, d²ν/dx²) = ((a²-1) x² / v, 2 (a²-1) x (a² - x⁴) / v²), v = (a² + x²)(1 + x²)
/// (derivatives of Anderson MCF eq. 4.44 in x = √(M²-1)).
fn pm_slope_and_curvature_of_x(x: f64, a: f64) -> (f64, f64) {
    let (a2, x2) = (a * a, x * x);
    let v = (a2 + x2) * (1.0 + x2);
    let slope = (a2 - 1.0) * x2 / v;
    (slope, 2.0 * (a2 - 1.0) * x * (a2 - x2 * x2) / (v * v))
}

/// ν(M) = √((γ+1)/(γ-1)) atan √((γ-1)/(γ+1) (M²-1)) - atan √(M²-1), rad, M >= 1
/// (Anderson MCF eq. 4.44).
pub fn prandtl_meyer(mach: f64, gamma: f64) -> Result<f64, GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_supersonic(mach, "the Prandtl-Meyer function needs M >= 1")?;
    let x = ((m - 1.0) * (m + 1.0)).sqrt();
    Ok(pm_of_x(x, pm_scale(gamma)))
}

/// The scale a = √((γ+1)/(γ-1)) and ν_max = π/2 (a - 1) of one γ, each a root and a division:
/// computed once per expansion instead of in every helper.
#[derive(Clone, Copy, Debug)]
struct PrandtlMeyerScale {
    a: f64,
    nu_max: f64,
}

impl PrandtlMeyerScale {
    fn new(gamma: f64) -> Self {
        let a = pm_scale(gamma);
        Self {
            a,
            nu_max: FRAC_PI_2 * (a - 1.0),
        }
    }
}

/// ν_max = π/2 (√((γ+1)/(γ-1)) - 1), rad: the turn from M = 1 to M = ∞ (Anderson MCF eq. 4.44, M → ∞).
pub fn max_prandtl_meyer(gamma: f64) -> f64 {
    PrandtlMeyerScale::new(gamma).nu_max
}

/// M(ν) for ν in [0, ν_max) rad: Hall (1975) rational approximation as the start, then Halley's
/// method on ν(√(M²-1)) (two steps from Hall's start reach machine precision; safeguarded Newton
/// if a step leaves the bracket) (Hall, Aeronautical J. 79, 1975, p. 417).
pub fn inverse_prandtl_meyer(nu_rad: f64, gamma: f64) -> Result<f64, GasError> {
    let gamma = check_gamma(gamma)?;
    let nu = check_prandtl_meyer_angle(nu_rad, max_prandtl_meyer(gamma))?;
    if nu == 0.0 {
        return Ok(1.0);
    }
    Ok(mach_from_prandtl_meyer(
        nu,
        PrandtlMeyerScale::new(gamma),
        None,
    ))
}

/// Hall's start x = √(M²-1) for ν in (0, ν_max) (exact coefficients for γ = 1.4; a fair start
/// for other γ); the small-turn asymptote ν ≈ (1 - 1/a²) x³ / 3 below 1e-6 ν_max.
fn hall_start(nu: f64, nu_max: f64, a: f64) -> f64 {
    if nu < 1e-6 * nu_max {
        return (3.0 * nu / (1.0 - 1.0 / (a * a))).cbrt();
    }
    // (ν/ν_max)^(2/3) as a cube root: the same start, no `powf`.
    let y = (nu / nu_max).powi(2).cbrt();
    let hall =
        (1.0 + y * (1.360_4 + y * (0.096_2 - 0.512_7 * y))) / (1.0 - y * (0.672_2 + 0.327_8 * y));
    if hall.is_finite() && hall > 1.0 {
        ((hall - 1.0) * (hall + 1.0)).sqrt()
    } else {
        f64::NAN
    }
}

/// M(ν) for a checked ν in (0, ν_max): Halley's method from `start` (x = √(M²-1)) or Hall's
/// start, safeguarded Newton if a step leaves the bracket (0, (a²-1)/(ν_max - ν)).
fn mach_from_prandtl_meyer(nu: f64, scale: PrandtlMeyerScale, start: Option<f64>) -> f64 {
    let PrandtlMeyerScale { a, nu_max } = scale;
    let deficit = nu_max - nu;
    // ν_max - ν(x) < (a²-1)/x, so x = (a²-1)/deficit brackets the root from above.
    let hi = (a * a - 1.0) / deficit;
    let start = start.unwrap_or_else(|| hall_start(nu, nu_max, a));
    let guess = if start > 0.0 && start < hi {
        start
    } else {
        0.5 * hi
    };
    let x = if nu <= 0.5 * nu_max {
        let residual = |x| {
            let (slope, curvature) = pm_slope_and_curvature_of_x(x, a);
            (pm_of_x(x, a) - nu, slope, curvature)
        };
        halley(residual, 0.0, hi, guess).unwrap_or_else(|| {
            solve_bracketed(
                |x| (pm_of_x(x, a) - nu, pm_slope_of_x(x, a)),
                0.0,
                hi,
                guess,
                true,
                0.0,
            )
        })
    } else {
        let residual = |x| {
            let (slope, curvature) = pm_slope_and_curvature_of_x(x, a);
            (pm_deficit_of_x(x, a) - deficit, -slope, -curvature)
        };
        halley(residual, 0.0, hi, guess).unwrap_or_else(|| {
            solve_bracketed(
                |x| (pm_deficit_of_x(x, a) - deficit, -pm_slope_of_x(x, a)),
                0.0,
                hi,
                guess,
                false,
                0.0,
            )
        })
    };
    (1.0 + x * x).sqrt()
}

/// Start for the downstream x2 = √(M2²-1) of a turn by τ from x1 > 0: the second-order Taylor
/// step Δx = τ/ν' - ν'' (τ/ν')² / (2ν') of ν(x) (derivatives of Anderson MCF eq. 4.44); `None`
/// when the step is not small against x1 (then Hall's start is the better one).
fn expansion_start(x1: f64, turn: f64, a: f64) -> Option<f64> {
    let (slope, curvature) = pm_slope_and_curvature_of_x(x1, a);
    let first = turn / slope;
    let step = first - 0.5 * curvature * first * first / slope;
    (x1 > 0.0 && step.is_finite() && step.abs() <= 0.25 * x1).then_some(x1 + step)
}

/// Isentropic state change through a Prandtl-Meyer expansion fan; ratios are downstream over upstream.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Expansion {
    /// M2 >= M1.
    pub mach_downstream: f64,
    /// p2/p1 <= 1.
    pub pressure_ratio: f64,
    /// T2/T1 <= 1.
    pub temperature_ratio: f64,
    /// ρ2/ρ1 <= 1.
    pub density_ratio: f64,
    /// ν(M2) = ν(M1) + turn, rad: the downstream Prandtl-Meyer angle, for the next turn of the
    /// same flow ([`prandtl_meyer_expansion_from`]).
    pub prandtl_meyer_downstream_rad: f64,
}

/// Expansion of M >= 1 flow turning away from itself by `turn_rad` >= 0: ν(M2) = ν(M1) + turn,
/// isentropic ratios T2/T1 = (1 + (γ-1)/2 M1²)/(1 + (γ-1)/2 M2²) (NACA 1135 eqs. 43-45).
pub fn prandtl_meyer_expansion(
    mach: f64,
    turn_rad: f64,
    gamma: f64,
) -> Result<Expansion, GasError> {
    let (m1, turn, gamma) = check_expansion(mach, turn_rad, gamma)?;
    let scale = PrandtlMeyerScale::new(gamma);
    let x1 = ((m1 - 1.0) * (m1 + 1.0)).sqrt();
    expansion_of_checked(m1, x1, pm_of_x(x1, scale.a), turn, scale, gamma)
}

/// [`prandtl_meyer_expansion`] of M >= 1 flow whose Prandtl-Meyer angle ν(M) is already known,
/// e.g. the [`Expansion::prandtl_meyer_downstream_rad`] of the expansion that produced it: the
/// same state change without evaluating ν(M) again (two `atan`s). `nu_rad` must be ν(mach) to
/// rounding; it is checked to lie in [0, ν_max).
pub fn prandtl_meyer_expansion_from(
    mach: f64,
    nu_rad: f64,
    turn_rad: f64,
    gamma: f64,
) -> Result<Expansion, GasError> {
    let (m1, turn, gamma) = check_expansion(mach, turn_rad, gamma)?;
    let scale = PrandtlMeyerScale::new(gamma);
    let nu1 = check_prandtl_meyer_angle(nu_rad, scale.nu_max)?;
    let x1 = ((m1 - 1.0) * (m1 + 1.0)).sqrt();
    expansion_of_checked(m1, x1, nu1, turn, scale, gamma)
}

/// (M >= 1, turn >= 0, γ > 1) of an expansion, or the error naming the bad one.
fn check_expansion(mach: f64, turn_rad: f64, gamma: f64) -> Result<(f64, f64, f64), GasError> {
    let gamma = check_gamma(gamma)?;
    let m1 = check_supersonic(mach, "a Prandtl-Meyer expansion needs M >= 1")?;
    let turn = finite("expansion turn (rad)", turn_rad)?;
    if turn < 0.0 {
        return Err(GasError::out_of_range(
            "expansion turn (rad)",
            turn,
            "turn >= 0 (a turn into the flow is a compression)",
        ));
    }
    Ok((m1, turn, gamma))
}

/// ν in [0, ν_max) rad, or the error giving the range.
fn check_prandtl_meyer_angle(nu_rad: f64, nu_max: f64) -> Result<f64, GasError> {
    let nu = finite("Prandtl-Meyer angle (rad)", nu_rad)?;
    if !(0.0..nu_max).contains(&nu) {
        return Err(GasError::out_of_range(
            "Prandtl-Meyer angle (rad)",
            nu,
            format!("0 <= nu < nu_max = {nu_max}"),
        ));
    }
    Ok(nu)
}

/// The expansion of checked M1 >= 1 (x1 = √(M1²-1), ν1 = ν(M1)) by a turn >= 0.
fn expansion_of_checked(
    m1: f64,
    x1: f64,
    nu1: f64,
    turn: f64,
    scale: PrandtlMeyerScale,
    gamma: f64,
) -> Result<Expansion, GasError> {
    let PrandtlMeyerScale { a, nu_max } = scale;
    let max_turn = nu_max - nu1;
    if turn >= max_turn || nu1 + turn >= nu_max {
        return Err(GasError::VacuumExpansion {
            mach: m1,
            turn_rad: turn,
            max_turn_rad: max_turn,
        });
    }
    // Small turns (panel to panel along a strip) start from the upstream state: one Halley step.
    let m2 = if turn == 0.0 {
        m1
    } else {
        mach_from_prandtl_meyer(nu1 + turn, scale, expansion_start(x1, turn, a))
    };
    let temperature_ratio = total_temperature_ratio(m1, gamma) / total_temperature_ratio(m2, gamma);
    let pressure_ratio = pow_half_integer(temperature_ratio, gamma / (gamma - 1.0));
    Ok(Expansion {
        mach_downstream: m2,
        pressure_ratio,
        temperature_ratio,
        // ρ2/ρ1 = (T2/T1)^(1/(γ-1)) = (p2/p1)/(T2/T1) (perfect gas), one power fewer.
        density_ratio: pressure_ratio / temperature_ratio,
        prandtl_meyer_downstream_rad: nu1 + turn,
    })
}

// ---------------------------------------------------------------------------------------------
// Small turns
// ---------------------------------------------------------------------------------------------

/// A turn's state change as ratios downstream over upstream (no wave angle): what a panel
/// method marching along a surface needs from each panel-to-panel turn.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TurnChange {
    pub mach_downstream: f64,
    /// p2/p1.
    pub pressure_ratio: f64,
    /// T2/T1.
    pub temperature_ratio: f64,
    /// ρ2/ρ1.
    pub density_ratio: f64,
}

/// Largest truncation error [`small_turn`] accepts, relative: a tenth of the rounding of 1.
const SMALL_TURN_TRUNCATION: f64 = 2e-17;

/// (SMALL_TURN_TRUNCATION / 10)^(1/3), rad: the largest turn [`small_turn`] can accept.
const SMALL_TURN_MAX_RAD: f64 = 1.26e-6;

/// A turn of M > 1 flow by `turn_rad` (> 0 compression, < 0 expansion) so small that its
/// second-order expansion is exact to rounding, else `None` (then use [`oblique_shock`] or
/// [`prandtl_meyer_expansion`]).
///
/// A weak oblique shock and the isentropic compression of the same turn agree to second order
/// in θ: the entropy rise is third order (Anderson MCF §4.14, eq. 4.31; Liepmann & Roshko,
/// Elements of Gasdynamics, §4.12). So both branches are ν(M2) = ν(M1) - θ inverted by the
/// second-order Taylor step of x = √(M²-1) in ν (derivatives of Anderson MCF eq. 4.44), with the
/// isentropic ratios T2/T1 = (1 + (γ-1)/2 M1²)/(1 + (γ-1)/2 M2²), p2/p1 = (T2/T1)^(γ/(γ-1)),
/// ρ2/ρ1 = (p2/p1)/(T2/T1) (NACA 1135 eqs. 43-45). Both the Taylor remainder and the shock's
/// entropy term are K θ³; the bound K = 1.5 (M⁶/(M²-1)^(3/2) + 10/(M²-1)^(7/2)) lies above the
/// error measured against 50-digit solutions of the exact relations from M = 1.02 to 500 for
/// γ = 1.2, 1.4 and 1.67 (by 1.3 to 46 times; spot values in `core/tests/gas_kernels.rs`), and
/// the expansion is used only for γ in that range and where K θ³ is below a tenth of the
/// rounding of 1. On a deformed mesh most panel-to-panel turns are of this kind (along flat
/// rows of panels θ differs by rounding), and each then costs a few products instead of a
/// shock's iteration or two arctangents.
pub fn small_turn(mach: f64, turn_rad: f64, gamma: f64) -> Option<TurnChange> {
    // K >= 10 at every Mach number, so no turn above (2e-18)^(1/3) passes: refused before the
    // bound's root and divisions (NaN fails the comparison too).
    let small = turn_rad.abs() <= SMALL_TURN_MAX_RAD;
    if !small {
        return None;
    }
    let x2 = (mach - 1.0) * (mach + 1.0);
    let t3 = (turn_rad * turn_rad * turn_rad).abs();
    if !(x2 > 0.0 && (1.2..=1.67).contains(&gamma)) {
        return None;
    }
    let x = x2.sqrt();
    let m2 = mach * mach;
    let bound = 1.5 * (m2 * m2 * m2 / (x2 * x) + 10.0 / (x2 * x2 * x2 * x));
    let exact_to_rounding = bound * t3 <= SMALL_TURN_TRUNCATION;
    if !exact_to_rounding {
        return None;
    }
    let a = pm_scale(gamma);
    let (slope, curvature) = pm_slope_and_curvature_of_x(x, a);
    // A compression lowers ν: Δν = -θ.
    let first = -turn_rad / slope;
    let step = first - 0.5 * curvature * first * first / slope;
    let x_downstream = x + step;
    let mach_downstream = (1.0 + x_downstream * x_downstream).sqrt();
    // T2/T1 = 1/(1 + (γ-1)/2 (M2² - M1²)/(1 + (γ-1)/2 M1²)) with M2² - M1² = Δx (2x + Δx):
    // no cancellation however small the turn.
    let half_gm1 = 0.5 * (gamma - 1.0);
    let temperature_ratio =
        1.0 / (1.0 + half_gm1 * step * (2.0 * x + step) / total_temperature_ratio(mach, gamma));
    let pressure_ratio = pow_half_integer(temperature_ratio, gamma / (gamma - 1.0));
    Some(TurnChange {
        mach_downstream,
        pressure_ratio,
        temperature_ratio,
        density_ratio: pressure_ratio / temperature_ratio,
    })
}

// ---------------------------------------------------------------------------------------------
// Pitot and Newtonian stagnation pressure
// ---------------------------------------------------------------------------------------------

/// p02/p1 = [(γ+1)²M²/(4γM² - 2(γ-1))]^(γ/(γ-1)) (1 - γ + 2γM²)/(γ+1) for M >= 1 (Rayleigh pitot
/// formula, NACA 1135 eq. 100); isentropic p0/p (eq. 44) for 0 <= M < 1.
pub fn rayleigh_pitot_pressure_ratio(mach: f64, gamma: f64) -> Result<f64, GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_mach_nonnegative(mach)?;
    if m < 1.0 {
        return Ok(total_pressure_ratio(m, gamma));
    }
    let m2 = m * m;
    let bracket = (gamma + 1.0).powi(2) * m2 / (4.0 * gamma * m2 - 2.0 * (gamma - 1.0));
    Ok(
        pow_half_integer(bracket, gamma / (gamma - 1.0)) * (1.0 - gamma + 2.0 * gamma * m2)
            / (gamma + 1.0),
    )
}

/// Cp,max = (p02/p1 - 1) / (γ/2 M²), the modified-Newtonian stagnation coefficient for M > 0
/// (Anderson, Hypersonic and High-Temperature Gas Dynamics, eq. 3.15).
pub fn newtonian_cp_max(mach: f64, gamma: f64) -> Result<f64, GasError> {
    let m = check_mach_nonnegative(mach)?;
    if m == 0.0 {
        return Err(GasError::out_of_range("Mach number", m, "M > 0"));
    }
    let pitot = rayleigh_pitot_pressure_ratio(m, gamma)?;
    Ok((pitot - 1.0) / (0.5 * gamma * m * m))
}

/// Surface state beyond shock detachment, as ratios to the upstream static state
/// (see [`detached_surface`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct DetachedSurface {
    /// p/p1 on the surface.
    pub pressure_ratio: f64,
    /// p0/p1: total pressure of the flow along the surface over the upstream static pressure
    /// (>= `pressure_ratio`; equal at a normal impact, where the surface flow stagnates).
    pub total_pressure_ratio: f64,
    /// w = (sin²θ - sin²θ_max)/(1 - sin²θ_max): 0 at detachment, 1 at a normal impact (θ >= π/2).
    pub newtonian_weight: f64,
}

/// Pressure on a surface inclined θ >= θ_max to M >= 1 flow, where no attached shock exists:
/// modified Newtonian Cp = Cp_max sin²θ (Anderson, Hypersonic and High-Temperature Gas Dynamics,
/// eq. 3.15, Cp_max from the Rayleigh pitot formula) rescaled so that it starts at the
/// weak-shock value at θ_max: Cp(θ) = Cp_d + (Cp_max - Cp_d) w, w = (sin²θ - sin²θ_max)/(1 -
/// sin²θ_max) (our matching; continuous at θ_max, monotone in θ, the pitot pressure at 90°).
/// Cp is linear in p/p1, so p/p1 = p_d + (p02/p1 - p_d) w, with p_d the oblique-shock p2/p1 at
/// (θ_max, β_max) (oblique-shock relations of NACA 1135) and p02/p1 the pitot ratio (NACA 1135 eq. 100). The
/// surface flow's total pressure is blended with the same w between the oblique shock's at
/// θ_max and the normal shock's (eq. 99), so an edge Mach number from p0/p is continuous too
/// (M2 at θ_max, 0 at 90°). θ beyond π/2 counts as π/2.
pub fn detached_surface(
    mach: f64,
    inclination_rad: f64,
    gamma: f64,
) -> Result<DetachedSurface, GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_supersonic(mach, "a detached-shock surface pressure needs M >= 1")?;
    let theta = finite("surface inclination (rad)", inclination_rad)?;
    let (theta_max, beta_max) = max_deflection_unchecked(m, gamma);
    // A few ulp below θ_max is rounding in the caller's detachment test.
    if theta < theta_max - 1e-9 {
        return Err(GasError::out_of_range(
            "surface inclination (rad)",
            theta,
            format!("theta >= theta_max = {theta_max} (below it the shock is attached)"),
        ));
    }
    let sin2_max = theta_max.sin().powi(2);
    let sin2 = theta.min(FRAC_PI_2).sin().powi(2);
    let weight = if sin2_max < 1.0 {
        ((sin2 - sin2_max) / (1.0 - sin2_max)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let attached = oblique_from_beta(m, beta_max, theta_max, gamma);
    let normal = normal_shock_unchecked(m, gamma);
    let upstream_total = total_pressure_ratio(m, gamma);
    let pitot = upstream_total * normal.total_pressure_ratio;
    let attached_total = upstream_total * attached.total_pressure_ratio;
    Ok(DetachedSurface {
        pressure_ratio: attached.pressure_ratio + (pitot - attached.pressure_ratio) * weight,
        total_pressure_ratio: attached_total + (pitot - attached_total) * weight,
        newtonian_weight: weight,
    })
}

// ---------------------------------------------------------------------------------------------
// Rayleigh flow (heat addition in a constant-area duct)
// ---------------------------------------------------------------------------------------------

/// Rayleigh-flow state over the sonic (star) state of the same flow.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RayleighFlow {
    /// T0/T0*.
    pub total_temperature_ratio: f64,
    /// T/T*.
    pub temperature_ratio: f64,
    /// p/p*.
    pub pressure_ratio: f64,
    /// p0/p0*.
    pub total_pressure_ratio: f64,
    /// V/V* = ρ*/ρ.
    pub velocity_ratio: f64,
}

/// Rayleigh-flow ratios for M >= 0 (Anderson MCF, Rayleigh-flow relations): p/p* = (1+γ)/(1+γM²),
/// T/T* = M² (p/p*)², T0/T0* = (γ+1)M²(2 + (γ-1)M²)/(1+γM²)², V/V* = (γ+1)M²/(1+γM²),
/// p0/p0* = (p/p*) [(2 + (γ-1)M²)/(γ+1)]^(γ/(γ-1)).
pub fn rayleigh_flow(mach: f64, gamma: f64) -> Result<RayleighFlow, GasError> {
    let gamma = check_gamma(gamma)?;
    let m = check_mach_nonnegative(mach)?;
    let m2 = m * m;
    let denominator = 1.0 + gamma * m2;
    let pressure_ratio = (1.0 + gamma) / denominator;
    let stagnation = (2.0 + (gamma - 1.0) * m2) / (gamma + 1.0);
    Ok(RayleighFlow {
        total_temperature_ratio: (gamma + 1.0).powi(2) * m2 * stagnation
            / (denominator * denominator),
        temperature_ratio: m2 * pressure_ratio * pressure_ratio,
        pressure_ratio,
        total_pressure_ratio: pressure_ratio * pow_half_integer(stagnation, gamma / (gamma - 1.0)),
        velocity_ratio: (gamma + 1.0) * m2 / denominator,
    })
}

/// M from T0/T0* in [0, 1] on the chosen branch: the quadratic in M² from the Rayleigh T0/T0*
/// relation, M² = r / q (subsonic) or q / (rγ² - γ² + 1) (supersonic), with
/// q = γ + 1 - rγ + (γ+1)√(1-r). T0/T0* > 1 is thermal choking; supersonic needs
/// T0/T0* > (γ²-1)/γ², its M → ∞ limit.
pub fn rayleigh_mach_from_total_temperature_ratio(
    t0_over_t0_star: f64,
    gamma: f64,
    branch: FlowBranch,
) -> Result<f64, GasError> {
    let gamma = check_gamma(gamma)?;
    let r = finite("total temperature ratio T0/T0*", t0_over_t0_star)?;
    if r > 1.0 {
        return Err(GasError::ThermalChoking {
            total_temperature_ratio: r,
        });
    }
    if r < 0.0 {
        return Err(GasError::out_of_range(
            "total temperature ratio T0/T0*",
            r,
            "0 <= T0/T0* <= 1",
        ));
    }
    let q = gamma + 1.0 - r * gamma + (gamma + 1.0) * (1.0 - r).sqrt();
    match branch {
        FlowBranch::Subsonic => Ok((r / q).sqrt()),
        FlowBranch::Supersonic => {
            let a = r * gamma * gamma - (gamma * gamma - 1.0);
            if a <= 0.0 {
                let limit = (gamma * gamma - 1.0) / (gamma * gamma);
                return Err(GasError::out_of_range(
                    "total temperature ratio T0/T0*",
                    r,
                    format!("{limit} < T0/T0* <= 1 for supersonic Rayleigh flow"),
                ));
            }
            Ok((q / a).sqrt())
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Piston theory
// ---------------------------------------------------------------------------------------------

/// p/p∞ = (1 + (γ-1)/2 · w/a)^(2γ/(γ-1)), simple-wave pressure on a piston moving into the gas at
/// normal velocity w (Lighthill 1953); w/a <= -2/(γ-1) is cavitation.
pub fn piston_pressure_ratio_exact(
    normal_velocity_over_sound_speed: f64,
    gamma: f64,
) -> Result<f64, GasError> {
    let gamma = check_gamma(gamma)?;
    let w = finite(
        "normal velocity over sound speed w/a",
        normal_velocity_over_sound_speed,
    )?;
    // a/a∞ = 1 + (γ-1)/2 w/a must stay positive.
    let sound_speed_ratio = 1.0 + 0.5 * (gamma - 1.0) * w;
    if sound_speed_ratio <= 0.0 {
        return Err(GasError::Cavitation {
            normal_velocity_over_sound_speed: w,
            limit: -2.0 / (gamma - 1.0),
        });
    }
    Ok(pow_half_integer(
        sound_speed_ratio,
        2.0 * gamma / (gamma - 1.0),
    ))
}

/// p/p∞ = 1 + γ w/a + γ(γ+1)/4 (w/a)² + γ(γ+1)/12 (w/a)³, third-order piston theory
/// (Ashley & Zartarian 1956).
pub fn piston_pressure_ratio_third_order(normal_velocity_over_sound_speed: f64, gamma: f64) -> f64 {
    let w = normal_velocity_over_sound_speed;
    let c2 = gamma * (gamma + 1.0) / 4.0;
    1.0 + w * (gamma + w * (c2 + w * c2 / 3.0))
}
