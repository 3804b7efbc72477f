//! Local inviscid flow states and how one turn changes them: oblique shock, Prandtl-Meyer
//! expansion, detached shock (modified Newtonian matched at θ_max), sonic re-expansion and vacuum.
//!
//! Every change is written as ratios of the local state, so the total temperature is carried
//! exactly from the freestream (adiabatic flow) and only the edge velocity needs the gas constant.

use hsv_core::aero::EdgeState;
use std::f64::consts::FRAC_PI_2;

use hsv_core::gas::{self, GasError, PerfectGas};

/// Mach number that stands for "expanded to vacuum" in an edge state: large enough that the
/// static temperature is ~1e-6 of the total temperature, finite so that T M² (and with it the
/// recovery temperature a heat-flux model computes) keeps its limit value (γ-1)/2 T M² → T0.
pub const VACUUM_EDGE_MACH: f64 = 1.0e3;

/// How a panel's local state was reached; the diagnostics count these.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regime {
    /// No turn from the freestream.
    Freestream,
    /// Last changed by an attached oblique shock.
    Compression,
    /// Last changed by a Prandtl-Meyer expansion.
    Expansion,
    /// Behind a detached shock (or a compression of subsonic flow): modified Newtonian.
    Detached,
    /// Expanded past ν_max: pressure and density zero.
    Vacuum,
}

/// Static state of the local inviscid flow over a panel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flow {
    pub mach: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
    pub density_kg_m3: f64,
}

/// A panel's local flow and how it was reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    pub flow: Flow,
    pub regime: Regime,
    /// ν(M), rad, when an expansion produced the state (its ν(M1) + turn): the next expansion
    /// of the strip starts from it instead of evaluating ν(M) again.
    pub prandtl_meyer_rad: Option<f64>,
}

impl Flow {
    /// Total temperature T0 = T (1 + (γ-1)/2 M²), K (NACA 1135 eq. 43).
    pub fn total_temperature_k(&self, gamma: f64) -> f64 {
        self.temperature_k * gas::total_temperature_ratio(self.mach, gamma)
    }

    /// Edge state with |V| = M √(γ R T) (Anderson MCF eq. 3.18).
    pub fn edge(&self, gas: &PerfectGas) -> EdgeState {
        EdgeState {
            mach: self.mach,
            pressure_pa: self.pressure_pa,
            temperature_k: self.temperature_k,
            density_kg_m3: self.density_kg_m3,
            velocity_m_s: self.mach * gas.speed_of_sound(self.temperature_k),
        }
    }

    /// The state scaled by pressure, temperature and density ratios at a new Mach number.
    fn scaled(&self, mach: f64, pressure: f64, temperature: f64, density: f64) -> Flow {
        Flow {
            mach,
            pressure_pa: self.pressure_pa * pressure,
            temperature_k: self.temperature_k * temperature,
            density_kg_m3: self.density_kg_m3 * density,
        }
    }
}

/// Changes `local` by turning the flow through `turn_rad` (> 0 into the surface: compression;
/// < 0 away from it: expansion), the panel-to-panel step of shock-expansion theory
/// (Anderson, Modern Compressible Flow, 3rd ed., §4.15).
///
/// - Supersonic, turn > 0: weak oblique shock; beyond θ_max the shock detaches and the panel
///   gets the modified-Newtonian pressure matched at θ_max ([`detached`]).
/// - Subsonic (behind a detached or a strong-ending weak shock), turn > 0: modified-Newtonian
///   impact of the local flow ([`subsonic_impact`]), counted as detached.
/// - Supersonic, turn < 0: Prandtl-Meyer expansion; past ν_max: [`vacuum`].
/// - Subsonic, turn < 0: the flow accelerates isentropically to sonic at the shoulder, then
///   expands by the turn from M = 1 ([`sonic`]).
/// - Turn = 0 or vacuum: unchanged.
pub fn turn(local: Local, turn_rad: f64, gamma: f64) -> Result<Local, GasError> {
    if local.regime == Regime::Vacuum || turn_rad == 0.0 {
        return Ok(local);
    }
    let flow = local.flow;
    if flow.mach > 1.0
        && let Some(change) = gas::small_turn(flow.mach, turn_rad, gamma)
    {
        return Ok(small_turn(local, change, turn_rad, gamma));
    }
    if turn_rad > 0.0 {
        if flow.mach < 1.0 {
            return subsonic_impact(flow, turn_rad, gamma);
        }
        return match gas::weak_oblique_turn(flow.mach, turn_rad, gamma) {
            Ok(shock) => Ok(Local {
                flow: flow.scaled(
                    shock.mach_downstream,
                    shock.pressure_ratio,
                    shock.temperature_ratio,
                    shock.density_ratio,
                ),
                regime: Regime::Compression,
                prandtl_meyer_rad: None,
            }),
            Err(GasError::Detached { .. }) => detached(flow, turn_rad, gamma),
            Err(other) => Err(other),
        };
    }
    let start = if flow.mach < 1.0 {
        sonic(flow, gamma)
    } else {
        flow
    };
    let fan = match local.prandtl_meyer_rad {
        Some(nu) if flow.mach >= 1.0 => {
            gas::prandtl_meyer_expansion_from(start.mach, nu, -turn_rad, gamma)
        }
        _ => gas::prandtl_meyer_expansion(start.mach, -turn_rad, gamma),
    };
    match fan {
        Ok(fan) => Ok(Local {
            flow: start.scaled(
                fan.mach_downstream,
                fan.pressure_ratio,
                fan.temperature_ratio,
                fan.density_ratio,
            ),
            regime: Regime::Expansion,
            prandtl_meyer_rad: Some(fan.prandtl_meyer_downstream_rad),
        }),
        Err(GasError::VacuumExpansion { .. }) => Ok(vacuum(flow, gamma)),
        Err(other) => Err(other),
    }
}

/// A turn small enough for [`gas::small_turn`]: labelled and carried like the weak shock or
/// the expansion it stands for (an expansion's ν(M) moves by the turn).
fn small_turn(local: Local, change: gas::TurnChange, turn_rad: f64, gamma: f64) -> Local {
    let flow = local.flow.scaled(
        change.mach_downstream,
        change.pressure_ratio,
        change.temperature_ratio,
        change.density_ratio,
    );
    if turn_rad > 0.0 {
        return Local {
            flow,
            regime: Regime::Compression,
            prandtl_meyer_rad: None,
        };
    }
    let nu_max = gas::max_prandtl_meyer(gamma);
    Local {
        flow,
        regime: Regime::Expansion,
        prandtl_meyer_rad: local
            .prandtl_meyer_rad
            .map(|nu| nu - turn_rad)
            .filter(|&nu| nu < nu_max),
    }
}

/// Supersonic flow turned by θ beyond θ_max (detached shock): p from the modified-Newtonian
/// pressure matched to the weak shock at θ_max and reaching the pitot pressure at 90°
/// ([`gas::detached_surface`]; Anderson, Hypersonic and High-Temperature Gas Dynamics, eq.
/// 3.15). The surface flow keeps T0 and has the blended total pressure p0, so
/// M = M(p0/p) (NACA 1135 eq. 44), T = T0/(1 + (γ-1)/2 M²) (eq. 43), ρ ∝ p/T: continuous with
/// the attached-shock state at θ_max and the stagnation state (M = 0, T = T0) at 90°.
pub fn detached(flow: Flow, turn_rad: f64, gamma: f64) -> Result<Local, GasError> {
    let surface = gas::detached_surface(flow.mach, turn_rad, gamma)?;
    at_total_pressure(
        flow,
        surface.pressure_ratio,
        surface.total_pressure_ratio,
        gamma,
    )
}

/// Subsonic flow (behind a detached shock) turned further by θ > 0: the same modified-Newtonian
/// rule in the local flow, p = p + (p0 - p) sin²θ with the isentropic stagnation pressure p0 as
/// the impact pressure (Anderson, Hypersonic and High-Temperature Gas Dynamics, eq. 3.15, with
/// Cp_max from NACA 1135 eq. 44; our choice for a panel-to-panel turn of subsonic flow), total
/// pressure and temperature kept: continuous from no turn (θ = 0) to stagnation (θ >= 90°).
pub fn subsonic_impact(flow: Flow, turn_rad: f64, gamma: f64) -> Result<Local, GasError> {
    let total = gas::total_pressure_ratio(flow.mach, gamma);
    let weight = turn_rad.clamp(0.0, FRAC_PI_2).sin().powi(2);
    at_total_pressure(flow, 1.0 + (total - 1.0) * weight, total, gamma)
}

/// The state at p = p_ratio p with total pressure p0 = total_ratio p (both over `flow`'s static
/// pressure) and `flow`'s total temperature: M from p0/p (inverse of NACA 1135 eq. 44),
/// T = T0/(1 + (γ-1)/2 M²), ρ = ρ (p/p_flow)/(T/T_flow); counted as detached.
fn at_total_pressure(
    flow: Flow,
    pressure_ratio: f64,
    total_ratio: f64,
    gamma: f64,
) -> Result<Local, GasError> {
    // p0 >= p holds by construction; rounding may leave it a few ulp short.
    let mach = gas::mach_from_total_pressure_ratio((total_ratio / pressure_ratio).max(1.0), gamma)?;
    let temperature =
        gas::total_temperature_ratio(flow.mach, gamma) / gas::total_temperature_ratio(mach, gamma);
    Ok(Local {
        flow: flow.scaled(
            mach,
            pressure_ratio,
            temperature,
            pressure_ratio / temperature,
        ),
        regime: Regime::Detached,
        prandtl_meyer_rad: None,
    })
}

/// Isentropic acceleration of subsonic flow to M = 1: p* = p (p0/p)(M) / (p0/p)(1), likewise T
/// and ρ (NACA 1135 eqs. 43-45).
pub fn sonic(flow: Flow, gamma: f64) -> Flow {
    let m = flow.mach;
    flow.scaled(
        1.0,
        gas::total_pressure_ratio(m, gamma) / gas::total_pressure_ratio(1.0, gamma),
        gas::total_temperature_ratio(m, gamma) / gas::total_temperature_ratio(1.0, gamma),
        gas::total_density_ratio(m, gamma) / gas::total_density_ratio(1.0, gamma),
    )
}

/// Vacuum limit of an expansion: p = ρ = 0, T = T0 / (1 + (γ-1)/2 M_v²) at M_v =
/// [`VACUUM_EDGE_MACH`], so |V| ≈ V_max = √(2 cp T0) (Anderson MCF §3.5).
pub fn vacuum(flow: Flow, gamma: f64) -> Local {
    let total_temperature = flow.total_temperature_k(gamma);
    Local {
        flow: Flow {
            mach: VACUUM_EDGE_MACH,
            pressure_pa: 0.0,
            temperature_k: total_temperature
                / gas::total_temperature_ratio(VACUUM_EDGE_MACH, gamma),
            density_kg_m3: 0.0,
        },
        regime: Regime::Vacuum,
        prandtl_meyer_rad: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const G: f64 = 1.4;

    fn freestream(mach: f64) -> Local {
        Local {
            flow: Flow {
                mach,
                pressure_pa: 1.0e4,
                temperature_k: 220.0,
                density_kg_m3: 1.0e4 / (287.0 * 220.0),
            },
            regime: Regime::Freestream,
            prandtl_meyer_rad: None,
        }
    }

    #[test]
    fn zero_turn_keeps_the_state() {
        let f = freestream(3.0);
        assert_eq!(turn(f, 0.0, G).unwrap(), f);
    }

    #[test]
    fn total_temperature_is_carried_through_every_wave() {
        let f = freestream(4.0);
        let t0 = f.flow.total_temperature_k(G);
        let mut local = f;
        for step in [0.1, 0.2, -0.3, 0.9, -0.2, -0.5, 0.05] {
            local = turn(local, step, G).unwrap();
            if local.regime != Regime::Vacuum {
                assert_relative_eq!(local.flow.total_temperature_k(G), t0, max_relative = 1e-12);
            }
        }
    }

    #[test]
    fn shoulder_after_detachment_is_sonic_then_prandtl_meyer() {
        let detached = turn(freestream(3.0), 1.0, G).unwrap();
        assert_eq!(detached.regime, Regime::Detached);
        let turned = turn(detached, -0.1, G).unwrap();
        let p_star = detached.flow.pressure_pa * gas::total_pressure_ratio(detached.flow.mach, G)
            / gas::total_pressure_ratio(1.0, G);
        let fan = gas::prandtl_meyer_expansion(1.0, 0.1, G).unwrap();
        assert_relative_eq!(
            turned.flow.pressure_pa,
            p_star * fan.pressure_ratio,
            max_relative = 1e-12
        );
        assert_eq!(turned.regime, Regime::Expansion);
    }

    #[test]
    fn vacuum_stays_vacuum() {
        let v = turn(freestream(3.0), -2.0, G).unwrap();
        assert_eq!(v.regime, Regime::Vacuum);
        assert_eq!(v.flow.pressure_pa, 0.0);
        assert_eq!(turn(v, 0.3, G).unwrap(), v);
    }
}
