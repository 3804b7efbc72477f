//! Trim of steady level flight (paper §IV.B, Eq. 2): Nelder-Mead on J = u̇² + ẇ² + q̇² over the
//! angle of attack, the symmetric elevon and the fuel equivalence ratio, then a restart from a
//! seeded random perturbation of up to 10 % of each parameter; the trim is accepted when both
//! minima agree within 1 % (the paper's rule), otherwise both are reported (one file: the request,
//! the Nelder-Mead search and the status rules are the paper's one procedure, joined by the private
//! cost function).
//!
//! A vehicle without an engine cannot fly level: its steady flight is a glide, where the
//! weight's component along the descending path balances the drag (tan γ = −D/L). Its third
//! parameter is then the flight-path angle γ in place of φ ([`Balance::Glide`]).

use std::cell::RefCell;
use std::time::Instant;

use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;
use rand_xoshiro::Xoshiro256Plus;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};

use crate::vehicle::rigid::{Accelerations, Controls, RigidLoads};
use hsv_core::flow::Freestream;
use hsv_core::propulsion::EngineStatus;

/// Nelder-Mead's tolerance on J's spread when it alone must find the minimum.
const FINE_TOLERANCE: f64 = 1e-14;

/// Cost of a point the models refuse (an unstarted engine, a detached inlet), above any real J.
const REFUSED_COST: f64 = 1e12;

/// Fuel equivalence ratios the search may try (rich beyond stoichiometric is refused).
const PHI_RANGE: (f64, f64) = (1e-3, 1.0);

/// Flight-path angles a glide's search may try, deg (steeper is a dive, not a glide).
const GAMMA_RANGE_DEG: (f64, f64) = (-60.0, 60.0);

/// What balances the drag in steady flight, and so the trim's third parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Balance {
    /// Level flight: the engine's thrust; the third parameter is φ.
    Thrust,
    /// A vehicle without an engine glides: the weight along the path; the third parameter is
    /// the flight-path angle γ, deg.
    Glide,
}

impl Balance {
    /// The balance of `vehicle`: thrust with an engine, a glide without.
    pub fn of(vehicle: &dyn SteadyFlight) -> Self {
        if vehicle.powered() {
            Self::Thrust
        } else {
            Self::Glide
        }
    }

    /// The third trim parameter `value` named for messages: `phi 0.3309` or
    /// `glide gamma -26.1200 deg`.
    pub fn named(self, value: f64) -> String {
        match self {
            Self::Thrust => format!("phi {value:.4}"),
            Self::Glide => format!("glide gamma {value:.4} deg"),
        }
    }

    /// Whether `third` is a value the search may try.
    fn allows(self, third: f64) -> bool {
        match self {
            Self::Thrust => (PHI_RANGE.0..=PHI_RANGE.1).contains(&third),
            Self::Glide => (GAMMA_RANGE_DEG.0..=GAMMA_RANGE_DEG.1).contains(&third),
        }
    }

    /// How far `third` lies outside the search's range (0 inside).
    fn outside(self, third: f64) -> f64 {
        let (lo, hi) = match self {
            Self::Thrust => PHI_RANGE,
            Self::Glide => GAMMA_RANGE_DEG,
        };
        (lo - third).max(third - hi).max(0.0)
    }
}

impl TrimPoint {
    /// The search's third parameter: φ, or a glide's γ (deg).
    pub fn third(&self) -> f64 {
        match self.balance {
            Balance::Thrust => self.fuel_equivalence_ratio,
            Balance::Glide => self.flight_path_angle_deg,
        }
    }

    /// What balances the drag, with its value, for messages (`phi 0.3309`, `glide gamma ...`).
    pub fn balance_named(&self) -> String {
        self.balance.named(self.third())
    }
}

/// What to trim for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrimRequest {
    pub mach: f64,
    pub altitude_m: f64,
    /// Starting guess: α (deg), δe (deg), φ.
    pub start: [f64; 3],
    /// Initial simplex steps: α (deg), δe (deg), φ.
    pub steps: [f64; 3],
    /// A glide's starting flight-path angle and its simplex step, deg (in place of φ's).
    pub glide_start_deg: f64,
    pub glide_step_deg: f64,
    /// Nelder-Mead stops when the standard deviation of J over the simplex is below this
    /// (1e-2 by default: the basin, where the Newton polish takes over).
    pub tolerance: f64,
    pub max_iterations: u64,
    /// Newton steps (Broyden-updated Jacobian) that polish the Nelder-Mead point; 0 for
    /// Nelder-Mead alone (then a `tolerance` of 1e-14 is the exact path).
    pub newton_iterations: usize,
    /// Seed of the restart's perturbation.
    pub seed: u64,
}

impl Default for TrimRequest {
    fn default() -> Self {
        Self {
            mach: 6.0,
            altitude_m: 26_000.0,
            start: [2.0, 0.0, 0.3],
            steps: [1.0, 2.0, 0.1],
            // Our choice: a hypersonic lifting body's L/D of 3-6 glides at -10 to -19 deg.
            glide_start_deg: -10.0,
            glide_step_deg: 2.0,
            tolerance: 1e-2,
            max_iterations: 3000,
            newton_iterations: 8,
            seed: 1,
        }
    }
}

/// One minimum: the controls, the loads there and the residual accelerations.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrimPoint {
    pub alpha_deg: f64,
    pub elevon_deg: f64,
    /// φ (0 for a glide).
    pub fuel_equivalence_ratio: f64,
    /// γ, deg (0 for level flight; a glide's descent, negative).
    pub flight_path_angle_deg: f64,
    /// What balances the drag: which of φ and γ the search varied.
    pub balance: Balance,
    pub cost: f64,
    pub accelerations: Accelerations,
    pub loads: RigidLoads,
    pub evaluations: u64,
    /// Body modal amplitudes at the trim (flexible vehicle).
    pub modal_amplitudes: Vec<(String, f64)>,
}

/// What a converged trim is worth (issue 26: a trim outside the vehicle's envelope says so).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TrimStatus {
    /// Level flight inside the models' and the engine's range.
    Converged,
    /// Level flight, but outside the air-breathing corridor, the perfect-gas range or the
    /// search's own check ([`TrimResult::notes`] say where).
    ConvergedWithWarnings,
    /// The accelerations vanish only with the engine unstarted or choked, or φ at its bound: no
    /// flight a run may start from.
    Failed,
}

impl TrimStatus {
    /// The status's name in JSON and messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Converged => "converged",
            Self::ConvergedWithWarnings => "converged-with-warnings",
            Self::Failed => "failed",
        }
    }
}

/// Dynamic pressures of the air-breathing corridor, Pa: 500 to 2000 lbf/ft² (Heiser & Pratt,
/// Hypersonic Airbreathing Propulsion, AIAA 1994, ch. 1: below, too little air for the engine;
/// above, loads and heating beyond the airframe's).
pub const CORRIDOR_DYNAMIC_PRESSURE_PA: (f64, f64) = (23_940.0, 95_760.0);

/// Freestream stagnation temperature above which calorically perfect air is no longer a model of
/// the flow, K: oxygen dissociates from about 2000-2500 K (Anderson, Hypersonic and
/// High-Temperature Gas Dynamics, 2nd ed., 2006, ch. 1; vibrational excitation already from
/// 800 K). Every aero and engine model here assumes γ = 1.4 air.
pub const PERFECT_GAS_STAGNATION_LIMIT_K: f64 = 2500.0;

/// The status of a trim at `freestream` and what it rests on: failures first, then warnings.
pub fn trim_status(
    freestream: &Freestream,
    trim: &TrimPoint,
    agreed: bool,
) -> (TrimStatus, Vec<String>) {
    let mut failures = Vec::new();
    let mut warnings = Vec::new();
    let powered = trim.balance == Balance::Thrust;
    match trim.loads.engine_status {
        _ if !powered => {}
        EngineStatus::Unstart => failures.push(
            "the engine is unstarted at the trim (the inlet cannot swallow its shocks)".to_owned(),
        ),
        EngineStatus::ThermalChoking => failures.push(
            "the combustor is thermally choked at the trim (more heat than its flow can take)"
                .to_owned(),
        ),
        EngineStatus::Ok | EngineStatus::Spillage => {}
    }
    let phi = trim.fuel_equivalence_ratio;
    if powered && (phi <= PHI_RANGE.0 * (1.0 + 1e-6) || phi >= PHI_RANGE.1 * (1.0 - 1e-6)) {
        failures.push(format!(
            "the fuel equivalence ratio {phi} is at the search's bound [{}, {}]",
            PHI_RANGE.0, PHI_RANGE.1
        ));
    }
    let gamma = trim.flight_path_angle_deg;
    let (g_lo, g_hi) = GAMMA_RANGE_DEG;
    if !powered && (gamma <= g_lo + 1e-6 || gamma >= g_hi - 1e-6) {
        failures.push(format!(
            "the glide's flight-path angle {gamma} deg is at the search's bound [{g_lo}, {g_hi}]"
        ));
    }
    let q = freestream.dynamic_pressure_pa;
    let (lo, hi) = CORRIDOR_DYNAMIC_PRESSURE_PA;
    if !(lo..=hi).contains(&q) {
        warnings.push(format!(
            "dynamic pressure {:.1} kPa is outside the air-breathing corridor {:.1}-{:.1} kPa \
             (500-2000 lbf/ft^2, Heiser & Pratt 1994)",
            q / 1e3,
            lo / 1e3,
            hi / 1e3
        ));
    }
    let t0 = freestream.total_temperature_k();
    if t0 > PERFECT_GAS_STAGNATION_LIMIT_K {
        warnings.push(format!(
            "stagnation temperature {t0:.0} K is above {PERFECT_GAS_STAGNATION_LIMIT_K:.0} K, \
             where air dissociates and the models' calorically perfect gas no longer holds"
        ));
    }
    if !agreed {
        warnings.push(
            "the restart from a perturbed start found a minimum more than 1 % away (paper \
             §IV.B's check): the trim may be a local minimum"
                .to_owned(),
        );
    }
    let status = if !failures.is_empty() {
        TrimStatus::Failed
    } else if !warnings.is_empty() {
        TrimStatus::ConvergedWithWarnings
    } else {
        TrimStatus::Converged
    };
    failures.extend(warnings);
    (status, failures)
}

/// The trim and its check.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrimResult {
    pub mach: f64,
    pub altitude_m: f64,
    pub trim: TrimPoint,
    /// The minimum found again from the perturbed start.
    pub restart: TrimPoint,
    /// Both minima agree within 1 % in every parameter.
    pub agreed: bool,
    /// What the trim is worth ([`trim_status`]).
    pub status: TrimStatus,
    /// Why the status is not `converged`: failures first, then warnings.
    pub notes: Vec<String>,
    pub mass_kg: f64,
    pub wall_time_s: f64,
}

/// Why trim failed.
#[derive(Debug, thiserror::Error)]
pub enum TrimError {
    #[error("trim at Mach {mach}, {altitude_m} m: {message}")]
    Search {
        mach: f64,
        altitude_m: f64,
        message: String,
    },
    #[error(
        "no trim at Mach {mach}, {altitude_m} m: the search stalled at alpha {alpha_deg:.3} deg, \
         elevon {elevon_deg:.3} deg, {third} with residual u_dot {u_dot:.3e} m/s^2, \
         w_dot {w_dot:.3e} m/s^2, q_dot {q_dot:.3e} rad/s^2 (J {cost:.3e}){reason}"
    )]
    Untrimmable {
        mach: f64,
        altitude_m: f64,
        alpha_deg: f64,
        elevon_deg: f64,
        /// φ or the glide's γ, named.
        third: String,
        u_dot: f64,
        w_dot: f64,
        q_dot: f64,
        cost: f64,
        reason: String,
    },
}

/// The models trim drives (defined beside them, so the vehicles need nothing of the analyses).
pub use crate::vehicle::rigid::SteadyFlight;

/// The cost function argmin minimizes; the vehicle's scratch is behind a `RefCell` because
/// argmin's cost takes `&self`.
struct Problem<'c, 'v> {
    vehicle: &'c RefCell<&'v mut dyn SteadyFlight>,
    balance: Balance,
    mach: f64,
    altitude_m: f64,
    evaluations: &'c RefCell<u64>,
    last_refusal: &'c RefCell<Option<String>>,
}

/// The steady-flight controls at search point `p` (α deg, δe deg, then φ or γ deg).
fn controls(p: &[f64], balance: Balance) -> Controls {
    let (fuel_equivalence_ratio, flight_path_angle_rad) = match balance {
        Balance::Thrust => (p[2], 0.0),
        Balance::Glide => (0.0, p[2].to_radians()),
    };
    Controls {
        alpha_rad: p[0].to_radians(),
        elevon_rad: p[1].to_radians(),
        fuel_equivalence_ratio,
        flight_path_angle_rad,
    }
}

impl CostFunction for Problem<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, p: &Self::Param) -> Result<f64, ArgminError> {
        *self.evaluations.borrow_mut() += 1;
        if !self.balance.allows(p[2]) {
            // Outside the engine's (or the glide's) range: a wall that grows with the
            // distance, so the simplex turns back.
            return Ok(REFUSED_COST * (1.0 + self.balance.outside(p[2])));
        }
        let result = self.vehicle.borrow_mut().steady_accelerations(
            self.mach,
            self.altitude_m,
            &controls(p, self.balance),
        );
        match result {
            Ok((acc, _)) => Ok(acc.cost()),
            Err(e) => {
                *self.last_refusal.borrow_mut() = Some(e.to_string());
                Ok(REFUSED_COST)
            }
        }
    }
}

/// Nelder-Mead from `start` with the request's simplex steps to `tolerance`: the best point,
/// the evaluations and the last refusal of the models on the way.
fn nelder_mead(
    vehicle: &mut dyn SteadyFlight,
    request: &TrimRequest,
    start: [f64; 3],
    tolerance: f64,
) -> Result<([f64; 3], u64, Option<String>), TrimError> {
    let search_error = |message: String| TrimError::Search {
        mach: request.mach,
        altitude_m: request.altitude_m,
        message,
    };
    let balance = Balance::of(vehicle);
    let steps = match balance {
        Balance::Thrust => request.steps,
        Balance::Glide => [request.steps[0], request.steps[1], request.glide_step_deg],
    };
    let mut simplex = vec![start.to_vec()];
    for k in 0..3 {
        let mut vertex = start.to_vec();
        vertex[k] += steps[k];
        simplex.push(vertex);
    }
    let evaluations = RefCell::new(0);
    let last_refusal = RefCell::new(None);
    let cell = RefCell::new(vehicle);
    let problem = Problem {
        vehicle: &cell,
        balance,
        mach: request.mach,
        altitude_m: request.altitude_m,
        evaluations: &evaluations,
        last_refusal: &last_refusal,
    };
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(tolerance)
        .map_err(|e| search_error(e.to_string()))?;
    let result = Executor::new(problem, solver)
        .configure(|state| state.max_iters(request.max_iterations))
        .run()
        .map_err(|e| search_error(e.to_string()))?;
    let best = result
        .state()
        .get_best_param()
        .cloned()
        .ok_or_else(|| search_error("Nelder-Mead returned no point".to_owned()))?;
    // The result holds the problem, which borrows the cells.
    drop(result);
    Ok((
        [best[0], best[1], best[2]],
        evaluations.into_inner(),
        last_refusal.into_inner(),
    ))
}

/// Nelder-Mead to the request's tolerance from `start`, then Newton's polish; when that point
/// is not trimmed (Newton left the basin, or the simplex stopped short of it), Nelder-Mead to
/// 1e-14 from there and the polish again: the search as it was before the polish existed.
fn minimize(
    vehicle: &mut dyn SteadyFlight,
    request: &TrimRequest,
    start: [f64; 3],
) -> Result<(TrimPoint, Option<String>), TrimError> {
    let (coarse, mut evaluations, mut refusal) =
        nelder_mead(vehicle, request, start, request.tolerance)?;
    let mut best = polish(vehicle, request, coarse, &mut evaluations);
    let mut at_best = evaluate(vehicle, request, &best);
    let trimmed = at_best
        .as_ref()
        .is_ok_and(|(accelerations, _)| is_trimmed(accelerations));
    if !trimmed && request.tolerance > FINE_TOLERANCE {
        let (fine, more, fine_refusal) = nelder_mead(vehicle, request, best, FINE_TOLERANCE)?;
        evaluations += more;
        refusal = fine_refusal.or(refusal);
        best = polish(vehicle, request, fine, &mut evaluations);
        at_best = evaluate(vehicle, request, &best);
    }
    let (accelerations, loads) = at_best?;
    let balance = Balance::of(vehicle);
    let (fuel_equivalence_ratio, flight_path_angle_deg) = match balance {
        Balance::Thrust => (best[2], 0.0),
        Balance::Glide => (0.0, best[2]),
    };
    Ok((
        TrimPoint {
            alpha_deg: best[0],
            elevon_deg: best[1],
            fuel_equivalence_ratio,
            flight_path_angle_deg,
            balance,
            cost: accelerations.cost(),
            accelerations,
            loads,
            evaluations,
            modal_amplitudes: vehicle.modal_amplitudes(),
        },
        refusal,
    ))
}

/// The accelerations and loads at the search's best point `best`; the models refusing it is an
/// untrimmable point.
fn evaluate(
    vehicle: &mut dyn SteadyFlight,
    request: &TrimRequest,
    best: &[f64; 3],
) -> Result<(Accelerations, RigidLoads), TrimError> {
    let balance = Balance::of(vehicle);
    vehicle
        .steady_accelerations(request.mach, request.altitude_m, &controls(best, balance))
        .map_err(|e| TrimError::Untrimmable {
            mach: request.mach,
            altitude_m: request.altitude_m,
            alpha_deg: best[0],
            elevon_deg: best[1],
            third: balance.named(best[2]),
            u_dot: f64::NAN,
            w_dot: f64::NAN,
            q_dot: f64::NAN,
            cost: f64::NAN,
            reason: format!("; the models refuse the best point: {e}"),
        })
}

/// The residual accelerations (u̇, ẇ, q̇) at `p`, or `None` where the search may not go (φ or γ
/// out of range, a point the models refuse).
fn residual(
    vehicle: &mut dyn SteadyFlight,
    request: &TrimRequest,
    p: &[f64; 3],
    evaluations: &mut u64,
) -> Option<nalgebra::Vector3<f64>> {
    let balance = Balance::of(vehicle);
    if !balance.allows(p[2]) {
        return None;
    }
    *evaluations += 1;
    let (a, _) = vehicle
        .steady_accelerations(request.mach, request.altitude_m, &controls(p, balance))
        .ok()?;
    Some(nalgebra::Vector3::new(
        a.u_dot_m_s2,
        a.w_dot_m_s2,
        a.q_dot_rad_s2,
    ))
}

/// Newton's method on r(p) = (u̇, ẇ, q̇) = 0 from the Nelder-Mead point `start`, the Jacobian by
/// forward differences at each iterate and the step halved (up to four times) until it lowers
/// J (Dennis & Schnabel, "Numerical Methods for Unconstrained Optimization and Nonlinear
/// Equations", 1983, §6.3), `request.newton_iterations` steps at most. The three equations in
/// three unknowns converge quadratically where Nelder-Mead's simplex crawls, so Nelder-Mead
/// needs only to reach the basin; a point Newton cannot improve is returned as it came.
fn polish(
    vehicle: &mut dyn SteadyFlight,
    request: &TrimRequest,
    start: [f64; 3],
    evaluations: &mut u64,
) -> [f64; 3] {
    // Steps of 1e-4 deg and 1e-5 in φ: the settled residual is smooth there (a step 100 times
    // larger gives the same Jacobian to 2 %) and r is linear over them. A glide's γ, like the
    // angles, by 1e-4 deg.
    const H: [f64; 3] = [1e-4, 1e-4, 1e-5];
    let h = match Balance::of(vehicle) {
        Balance::Thrust => H,
        Balance::Glide => [H[0], H[1], 1e-4],
    };
    let mut p = start;
    let Some(mut r) = residual(vehicle, request, &p, evaluations) else {
        return start;
    };
    for _ in 0..request.newton_iterations {
        let mut jacobian = nalgebra::Matrix3::zeros();
        for k in 0..3 {
            let mut shifted = p;
            shifted[k] += h[k];
            let Some(rk) = residual(vehicle, request, &shifted, evaluations) else {
                return p;
            };
            jacobian.set_column(k, &((rk - r) / h[k]));
        }
        let Some(step) = jacobian.lu().solve(&(-r)) else {
            return p;
        };
        let mut accepted = None;
        let mut fraction = 1.0;
        for _ in 0..5 {
            let next = [
                p[0] + fraction * step[0],
                p[1] + fraction * step[1],
                p[2] + fraction * step[2],
            ];
            if let Some(r_next) = residual(vehicle, request, &next, evaluations)
                && r_next.norm_squared() < r.norm_squared()
            {
                accepted = Some((next, r_next));
                break;
            }
            fraction *= 0.5;
        }
        let Some((next, r_next)) = accepted else {
            return p;
        };
        let moved = (0..3).all(|k| (next[k] - p[k]).abs() <= 1e-12 * (1.0 + p[k].abs()));
        p = next;
        r = r_next;
        if moved {
            break;
        }
    }
    p
}

/// A point of 10 % random perturbation around `p` (each parameter scaled by 1 + U(−0.1, 0.1)).
fn perturbed(p: &TrimPoint, seed: u64) -> [f64; 3] {
    let mut rng = Xoshiro256Plus::seed_from_u64(seed);
    let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
    [
        p.alpha_deg * (1.0 + 0.1 * unit()),
        p.elevon_deg * (1.0 + 0.1 * unit()),
        p.third() * (1.0 + 0.1 * unit()),
    ]
}

/// Both minima agree within 1 % in each parameter (absolute 1e-3 deg or 1e-4 in φ near zero).
fn agree(a: &TrimPoint, b: &TrimPoint) -> bool {
    let close =
        |x: f64, y: f64, floor: f64| (x - y).abs() <= (0.01 * x.abs().max(y.abs())).max(floor);
    close(a.alpha_deg, b.alpha_deg, 1e-3)
        && close(a.elevon_deg, b.elevon_deg, 1e-3)
        && close(a.fuel_equivalence_ratio, b.fuel_equivalence_ratio, 1e-4)
        && close(a.flight_path_angle_deg, b.flight_path_angle_deg, 1e-3)
}

/// Accelerations below which a point is trimmed: 1e-3 m/s² and 1e-4 rad/s² (our choice: four
/// orders below g; the paper's rigid partitioned trim left 0.24 m/s²).
pub const TRIMMED_ACCELERATION_M_S2: f64 = 1e-3;
pub const TRIMMED_PITCH_ACCELERATION_RAD_S2: f64 = 1e-4;

fn is_trimmed(a: &Accelerations) -> bool {
    a.u_dot_m_s2.abs() <= TRIMMED_ACCELERATION_M_S2
        && a.w_dot_m_s2.abs() <= TRIMMED_ACCELERATION_M_S2
        && a.q_dot_rad_s2.abs() <= TRIMMED_PITCH_ACCELERATION_RAD_S2
}

/// Trims `vehicle` for steady flight (module docs): level with an engine, a glide without.
pub fn trim(
    vehicle: &mut dyn SteadyFlight,
    request: &TrimRequest,
) -> Result<TrimResult, TrimError> {
    let start = Instant::now();
    let search_start = match Balance::of(vehicle) {
        Balance::Thrust => request.start,
        Balance::Glide => [request.start[0], request.start[1], request.glide_start_deg],
    };
    let (first, refusal) = minimize(vehicle, request, search_start)?;
    if !is_trimmed(&first.accelerations) {
        let a = first.accelerations;
        return Err(TrimError::Untrimmable {
            mach: request.mach,
            altitude_m: request.altitude_m,
            alpha_deg: first.alpha_deg,
            elevon_deg: first.elevon_deg,
            third: first.balance_named(),
            u_dot: a.u_dot_m_s2,
            w_dot: a.w_dot_m_s2,
            q_dot: a.q_dot_rad_s2,
            cost: first.cost,
            reason: refusal.map_or_else(String::new, |r| {
                format!("; the models refused some points on the way, last: {r}")
            }),
        });
    }
    let (restart, _) = minimize(vehicle, request, perturbed(&first, request.seed))?;
    let agreed = agree(&first, &restart);
    let freestream = Freestream::standard(request.mach, request.altitude_m, vehicle.gas())
        .map_err(|e| TrimError::Search {
            mach: request.mach,
            altitude_m: request.altitude_m,
            message: e.to_string(),
        })?;
    let (status, notes) = trim_status(&freestream, &first, agreed);
    Ok(TrimResult {
        mach: request.mach,
        altitude_m: request.altitude_m,
        agreed,
        status,
        notes,
        trim: first,
        restart,
        mass_kg: vehicle.mass_kg(),
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}
