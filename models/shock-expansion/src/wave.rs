//! Local inviscid flow states and how one turn changes them: oblique shock, Prandtl-Meyer
//! expansion, detached-shock stagnation, sonic re-expansion and vacuum.
//!
//! Every change is written as ratios of the local state, so the total temperature is carried
//! exactly from the freestream (adiabatic flow) and only the edge velocity needs the gas constant.

use hsv_core::aero::EdgeState;
use hsv_core::gas::{self, GasError, PerfectGas, ShockBranch};

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
    /// Stagnation state behind a detached shock (or a compression of subsonic flow).
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
///   sees the stagnation state behind a normal shock ([`stagnation`]).
/// - Subsonic (behind a detached or a strong-ending weak shock), turn > 0: isentropic
///   stagnation of the local flow, counted as detached.
/// - Supersonic, turn < 0: Prandtl-Meyer expansion; past ν_max: [`vacuum`].
/// - Subsonic, turn < 0: the flow accelerates isentropically to sonic at the shoulder, then
///   expands by the turn from M = 1 ([`sonic`]).
/// - Turn = 0 or vacuum: unchanged.
pub fn turn(local: Local, turn_rad: f64, gamma: f64) -> Result<Local, GasError> {
    if local.regime == Regime::Vacuum || turn_rad == 0.0 {
        return Ok(local);
    }
    let flow = local.flow;
    if turn_rad > 0.0 {
        if flow.mach < 1.0 {
            return stagnation(flow, gamma);
        }
        return match gas::oblique_shock(flow.mach, turn_rad, gamma, ShockBranch::Weak) {
            Ok(shock) => Ok(Local {
                flow: flow.scaled(
                    shock.mach_downstream,
                    shock.pressure_ratio,
                    shock.temperature_ratio,
                    shock.density_ratio,
                ),
                regime: Regime::Compression,
            }),
            Err(GasError::Detached { .. }) => stagnation(flow, gamma),
            Err(other) => Err(other),
        };
    }
    let start = if flow.mach < 1.0 {
        sonic(flow, gamma)
    } else {
        flow
    };
    match gas::prandtl_meyer_expansion(start.mach, -turn_rad, gamma) {
        Ok(fan) => Ok(Local {
            flow: start.scaled(
                fan.mach_downstream,
                fan.pressure_ratio,
                fan.temperature_ratio,
                fan.density_ratio,
            ),
            regime: Regime::Expansion,
        }),
        Err(GasError::VacuumExpansion { .. }) => Ok(vacuum(flow, gamma)),
        Err(other) => Err(other),
    }
}

/// Stagnation state behind a normal shock: p = p02 = p (p02/p1) (Rayleigh pitot formula,
/// NACA 1135 eq. 100; isentropic p0/p, eq. 44, for M < 1), T = T0, ρ = ρ (p02/p)/(T0/T), M = 0.
pub fn stagnation(flow: Flow, gamma: f64) -> Result<Local, GasError> {
    let pressure = gas::rayleigh_pitot_pressure_ratio(flow.mach, gamma)?;
    let temperature = gas::total_temperature_ratio(flow.mach, gamma);
    Ok(Local {
        flow: flow.scaled(0.0, pressure, temperature, pressure / temperature),
        regime: Regime::Detached,
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
        let p_star = detached.flow.pressure_pa / gas::total_pressure_ratio(1.0, G);
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
