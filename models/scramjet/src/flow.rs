//! Uniform flow states of a calorically perfect gas and the wave turns, area changes and heat
//! additions that carry them through the engine (all relations from `hsv_core::gas`).

use hsv_core::gas::{
    self, FlowBranch, GasError, PerfectGas, ShockBranch, area_mach_ratio, inverse_prandtl_meyer,
    mach_from_area_ratio_near, prandtl_meyer, prandtl_meyer_expansion, total_pressure_ratio,
    total_temperature_ratio,
};

/// A uniform flow state: Mach number, static pressure (Pa) and static temperature (K).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FlowState {
    pub mach: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
}

impl FlowState {
    /// ρ = p / (R T), kg/m³.
    pub fn density_kg_m3(&self, gas: &PerfectGas) -> f64 {
        self.pressure_pa / (gas.gas_constant_j_kg_k * self.temperature_k)
    }

    /// V = M √(γ R T), m/s.
    pub fn velocity_m_s(&self, gas: &PerfectGas) -> f64 {
        self.mach * gas.speed_of_sound(self.temperature_k)
    }

    /// ρ V, kg/(m² s).
    pub fn mass_flux_kg_m2_s(&self, gas: &PerfectGas) -> f64 {
        self.density_kg_m3(gas) * self.velocity_m_s(gas)
    }

    /// T0 = T (1 + (γ-1)/2 M²), K (NACA 1135 eq. 43).
    pub fn total_temperature_k(&self, gas: &PerfectGas) -> f64 {
        self.temperature_k * total_temperature_ratio(self.mach, gas.gamma)
    }

    /// p0 = p (1 + (γ-1)/2 M²)^(γ/(γ-1)), Pa (NACA 1135 eq. 44).
    pub fn total_pressure_pa(&self, gas: &PerfectGas) -> f64 {
        self.pressure_pa * total_pressure_ratio(self.mach, gas.gamma)
    }

    /// The state at Mach `mach` with the same total temperature and pressure (isentropic).
    pub fn isentropic_to_mach(&self, mach: f64, gas: &PerfectGas) -> FlowState {
        FlowState {
            mach,
            pressure_pa: self.total_pressure_pa(gas) / total_pressure_ratio(mach, gas.gamma),
            temperature_k: self.total_temperature_k(gas) / total_temperature_ratio(mach, gas.gamma),
        }
    }

    /// True when every field is finite and p, T > 0, M ≥ 0.
    pub fn is_physical(&self) -> bool {
        self.mach.is_finite()
            && self.pressure_pa.is_finite()
            && self.temperature_k.is_finite()
            && self.mach >= 0.0
            && self.pressure_pa > 0.0
            && self.temperature_k > 0.0
    }
}

/// How compressive turns are taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Compression {
    /// Oblique shock, weak branch (Anderson MCF eq. 4.17 via `gas::oblique_shock`).
    Shock,
    /// Isentropic (Prandtl-Meyer) compression: ν2 = ν1 - θ (Anderson MCF eq. 4.44).
    Isentropic,
}

/// A turned state and, for a shock, its wave angle relative to the upstream flow (rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turned {
    pub state: FlowState,
    /// Shock wave angle β for a shock; the upstream Mach angle for isentropic turns.
    pub wave_angle_rad: f64,
}

/// Turns supersonic flow by `compression_rad` (> 0 toward the wall: compression; < 0 away
/// from it: Prandtl-Meyer expansion). Errors: detached shock, compression to subsonic flow,
/// expansion to vacuum (`GasError`).
pub fn turn(
    state: &FlowState,
    compression_rad: f64,
    gas: &PerfectGas,
    compression: Compression,
) -> Result<Turned, GasError> {
    let g = gas.gamma;
    let mach_angle = gas::mach_angle(state.mach)?;
    // Turns at the rounding level of a straight polyline's segment slopes are no turn.
    if compression_rad.abs() <= 1e-12 {
        return Ok(Turned {
            state: *state,
            wave_angle_rad: mach_angle,
        });
    }
    if compression_rad < 0.0 {
        let e = prandtl_meyer_expansion(state.mach, -compression_rad, g)?;
        return Ok(Turned {
            state: FlowState {
                mach: e.mach_downstream,
                pressure_pa: state.pressure_pa * e.pressure_ratio,
                temperature_k: state.temperature_k * e.temperature_ratio,
            },
            wave_angle_rad: mach_angle,
        });
    }
    match compression {
        Compression::Shock => {
            let s = gas::oblique_shock(state.mach, compression_rad, g, ShockBranch::Weak)?;
            Ok(Turned {
                state: FlowState {
                    mach: s.mach_downstream,
                    pressure_pa: state.pressure_pa * s.pressure_ratio,
                    temperature_k: state.temperature_k * s.temperature_ratio,
                },
                wave_angle_rad: s.wave_angle_rad,
            })
        }
        Compression::Isentropic => {
            let nu = prandtl_meyer(state.mach, g)? - compression_rad;
            if nu < 0.0 {
                return Err(GasError::Subsonic {
                    mach: state.mach,
                    needed: "an isentropic compression of this size would make the flow subsonic",
                });
            }
            let mach = inverse_prandtl_meyer(nu, g)?;
            Ok(Turned {
                state: state.isentropic_to_mach(mach, gas),
                wave_angle_rad: mach_angle,
            })
        }
    }
}

/// Isentropic area change of supersonic flow from area `a1` to `a2` (any units):
/// A2/A* = (A2/A1)(A1/A*) on the supersonic branch (NACA 1135 eq. 80). `None` when A2/A* < 1:
/// the duct cannot pass the flow (it chokes).
pub fn supersonic_area_change(
    state: &FlowState,
    a1: f64,
    a2: f64,
    gas: &PerfectGas,
) -> Result<Option<FlowState>, GasError> {
    supersonic_area_change_near(state, a1, a2, gas, None)
}

/// [`supersonic_area_change`] with the area-Mach inversion started at `mach_guess` (a nearby
/// station's Mach number, when marching through slowly changing areas).
pub fn supersonic_area_change_near(
    state: &FlowState,
    a1: f64,
    a2: f64,
    gas: &PerfectGas,
    mach_guess: Option<f64>,
) -> Result<Option<FlowState>, GasError> {
    let ratio = a2 / a1 * area_mach_ratio(state.mach, gas.gamma);
    // A sonic (choked) state keeps A/A* = 1 up to rounding.
    if !ratio.is_finite() || ratio < 1.0 - 1e-9 {
        return Ok(None);
    }
    let ratio = ratio.max(1.0);
    let mach = mach_from_area_ratio_near(ratio, gas.gamma, FlowBranch::Supersonic, mach_guess)?;
    Ok(Some(state.isentropic_to_mach(mach, gas)))
}

/// Total temperature after burning fuel in air, K: (1 + f) c_p T0,out = c_p T0,in + η f_b h
/// (burner energy balance with the fuel's sensible enthalpy neglected; Heiser & Pratt,
/// Hypersonic Airbreathing Propulsion, AIAA 1994, ch. 7), with f the fuel mass added per
/// unit air mass and f_b ≤ f the part that burns.
pub fn burned_total_temperature_k(
    total_temperature_in_k: f64,
    fuel_air_ratio: f64,
    burned_fuel_air_ratio: f64,
    heat_release_j_kg: f64,
    gas: &PerfectGas,
) -> f64 {
    (gas.cp() * total_temperature_in_k + burned_fuel_air_ratio * heat_release_j_kg)
        / (gas.cp() * (1.0 + fuel_air_ratio))
}

/// Outcome of constant-area heat and mass addition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CombustorExit {
    pub state: FlowState,
    /// False when the heat asked for would choke the duct; `state` is then the sonic
    /// (choking-limit) exit with the largest total temperature the duct can take.
    pub within_limit: bool,
}

/// Constant-area combustor with heat and mass addition (fuel injected without axial
/// momentum): mass ρV(1+f), impulse p(1 + γM²) and energy conserved, so the Rayleigh
/// function T0/T0*(M) scales as T0/T0*(M_out) = T0/T0*(M_in) (1+f)² T0,out/T0,in (Shapiro,
/// The Dynamics and Thermodynamics of Compressible Fluid Flow, 1953, ch. 8; pure heat
/// addition, f = 0, is Rayleigh flow, Anderson MCF ch. 3). Exit pressure from the impulse:
/// p_out = p_in (1 + γM_in²)/(1 + γM_out²). The supersonic branch is kept; a ratio above 1 is
/// thermal choking and returns the sonic exit at the limit.
pub fn constant_area_combustor(
    entry: &FlowState,
    fuel_air_ratio: f64,
    exit_total_temperature_k: f64,
    gas: &PerfectGas,
) -> Result<CombustorExit, GasError> {
    let g = gas.gamma;
    let t0_in = entry.total_temperature_k(gas);
    let rayleigh_in = gas::rayleigh_flow(entry.mach, g)?.total_temperature_ratio;
    let mass = (1.0 + fuel_air_ratio).powi(2);
    let wanted = rayleigh_in * mass * exit_total_temperature_k / t0_in;
    let (ratio, t0_out, within_limit) = if wanted > 1.0 {
        (1.0, t0_in / (rayleigh_in * mass), false)
    } else {
        (wanted, exit_total_temperature_k, true)
    };
    let mach = if ratio >= 1.0 {
        1.0
    } else {
        gas::rayleigh_mach_from_total_temperature_ratio(ratio, g, FlowBranch::Supersonic)?
    };
    let pressure_pa =
        entry.pressure_pa * (1.0 + g * entry.mach * entry.mach) / (1.0 + g * mach * mach);
    Ok(CombustorExit {
        state: FlowState {
            mach,
            pressure_pa,
            temperature_k: t0_out / total_temperature_ratio(mach, g),
        },
        within_limit,
    })
}
