//! The U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562) from sea level to 86 km geometric
//! altitude: temperature, pressure, density, speed of sound, viscosity, conductivity and gravity.
//!
//! The seven base layers are linear in molecular-scale temperature T_M against geopotential
//! altitude H (USSA-1976 Table 4); pressure follows the hydrostatic equations 33a/33b, density is
//! ρ = p M0 / (R* T_M) (eq. 42) and the speed of sound √(γ R* T_M / M0) (eq. 50), all exact for
//! the molecular-scale temperature.
//!
//! Model choice between 80 and 86 km: the kinetic temperature reported is T = T_M (M/M0), with the
//! mean-molecular-weight ratio M/M0 of USSA-1976 Table 8 interpolated linearly in geometric
//! altitude between its 0.5 km rows (1 at 80 km, 0.999579 at 86 km). This reproduces the Standard's
//! tabulated kinetic temperatures (186.87 K at 86 km, where T_M = 186.946 K). Viscosity (eq. 51)
//! and conductivity (eq. 53) use the kinetic temperature, as the Standard does. Below 80 km,
//! T = T_M.

use std::sync::LazyLock;

/// Lowest geometric altitude of the model, m.
pub const MIN_ALTITUDE_M: f64 = 0.0;
/// Highest geometric altitude of the model, m (84 852 m geopotential).
pub const MAX_ALTITUDE_M: f64 = 86_000.0;
/// Effective Earth radius r0 for the geopotential conversion, m (USSA-1976).
pub const EARTH_RADIUS_M: f64 = 6_356_766.0;
/// Sea-level standard gravity g0, m/s² (USSA-1976).
pub const STANDARD_GRAVITY_M_S2: f64 = 9.806_65;

/// Universal gas constant R*, J/(kmol K) (USSA-1976 Table 2).
const UNIVERSAL_GAS_CONSTANT: f64 = 8_314.32;
/// Sea-level mean molecular weight M0, kg/kmol (USSA-1976).
const SEA_LEVEL_MOLECULAR_WEIGHT: f64 = 28.964_4;
/// Ratio of specific heats used for the speed of sound (USSA-1976 eq. 50).
const GAMMA: f64 = 1.40;
/// g0 M0 / R*, K per geopotential metre (the hydrostatic constant of eqs. 33a/33b).
const GMR: f64 = STANDARD_GRAVITY_M_S2 * SEA_LEVEL_MOLECULAR_WEIGHT / UNIVERSAL_GAS_CONSTANT;
/// Sea-level pressure, Pa.
const SEA_LEVEL_PRESSURE_PA: f64 = 101_325.0;

/// Base geopotential altitudes H_b of the seven layers, m' (USSA-1976 Table 4).
const LAYER_BASE_M: [f64; 7] = [
    0.0, 11_000.0, 20_000.0, 32_000.0, 47_000.0, 51_000.0, 71_000.0,
];
/// Molecular-scale temperature gradients L_M,b, K/m' (USSA-1976 Table 4).
const LAYER_LAPSE_K_M: [f64; 7] = [-0.0065, 0.0, 0.001, 0.0028, 0.0, -0.0028, -0.002];
/// Base molecular-scale temperatures T_M,b, K (USSA-1976 Table 4, from 288.15 K and the gradients).
const LAYER_BASE_TEMPERATURE_K: [f64; 7] = [288.15, 216.65, 216.65, 228.65, 270.65, 270.65, 214.65];

/// Base pressures P_b, Pa, from 101 325 Pa through eqs. 33a/33b layer by layer.
static LAYER_BASE_PRESSURE_PA: LazyLock<[f64; 7]> = LazyLock::new(|| {
    let mut pressures = [SEA_LEVEL_PRESSURE_PA; 7];
    for i in 1..7 {
        let thickness = LAYER_BASE_M[i] - LAYER_BASE_M[i - 1];
        pressures[i] = layer_pressure(i - 1, pressures[i - 1], thickness);
    }
    pressures
});

/// M/M0 at geometric altitudes 80.0, 80.5, …, 86.0 km (USSA-1976 Table 8).
const MOLECULAR_WEIGHT_RATIO: [f64; 13] = [
    1.000_000, 0.999_996, 0.999_989, 0.999_971, 0.999_941, 0.999_909, 0.999_870, 0.999_829,
    0.999_786, 0.999_741, 0.999_694, 0.999_641, 0.999_579,
];
/// Geometric altitude of the first row of [`MOLECULAR_WEIGHT_RATIO`], m.
const MOLECULAR_WEIGHT_TABLE_START_M: f64 = 80_000.0;
/// Row spacing of [`MOLECULAR_WEIGHT_RATIO`], m.
const MOLECULAR_WEIGHT_TABLE_STEP_M: f64 = 500.0;

/// The atmosphere at one geometric altitude.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AtmosphereState {
    /// Geometric altitude Z above mean sea level, m.
    pub geometric_altitude_m: f64,
    /// Geopotential altitude H = r0 Z / (r0 + Z), m'.
    pub geopotential_altitude_m: f64,
    /// Kinetic temperature T, K.
    pub temperature_k: f64,
    /// Pressure p, Pa.
    pub pressure_pa: f64,
    /// Density ρ, kg/m³.
    pub density_kg_m3: f64,
    /// Speed of sound, m/s.
    pub speed_of_sound_m_s: f64,
    /// Dynamic viscosity μ, Pa s.
    pub dynamic_viscosity_pa_s: f64,
    /// Kinematic viscosity ν = μ/ρ, m²/s.
    pub kinematic_viscosity_m2_s: f64,
    /// Thermal conductivity k, W/(m K).
    pub thermal_conductivity_w_m_k: f64,
    /// Acceleration of gravity g, m/s².
    pub gravity_m_s2: f64,
}

/// Why the atmosphere could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AtmosphereError {
    /// The altitude is outside 0 to 86 000 m geometric.
    #[error(
        "altitude {altitude_m} m is outside the US Standard Atmosphere 1976 model (0 to 86000 m)"
    )]
    OutOfRange {
        /// The geometric altitude given, m.
        altitude_m: f64,
    },
    /// The altitude is NaN or infinite.
    #[error("altitude is not finite (NaN or infinite)")]
    NonFinite,
}

/// Pressure at `height` m' above the base of `layer` whose base pressure is `base_pressure`:
/// eq. 33a P_b [T_M,b / (T_M,b + L_M,b ΔH)]^(g0 M0 / (R* L_M,b)), or eq. 33b
/// P_b exp(-g0 M0 ΔH / (R* T_M,b)) where L_M,b = 0.
fn layer_pressure(layer: usize, base_pressure: f64, height: f64) -> f64 {
    let lapse = LAYER_LAPSE_K_M[layer];
    let base_temperature = LAYER_BASE_TEMPERATURE_K[layer];
    if lapse == 0.0 {
        base_pressure * (-GMR * height / base_temperature).exp()
    } else {
        let temperature = base_temperature + lapse * height;
        base_pressure * (base_temperature / temperature).powf(GMR / lapse)
    }
}

/// M/M0 at geometric altitude `z` m: 1 below 80 km, USSA-1976 Table 8 interpolated linearly above.
fn molecular_weight_ratio(z: f64) -> f64 {
    if z <= MOLECULAR_WEIGHT_TABLE_START_M {
        return 1.0;
    }
    let position = (z - MOLECULAR_WEIGHT_TABLE_START_M) / MOLECULAR_WEIGHT_TABLE_STEP_M;
    let last = MOLECULAR_WEIGHT_RATIO.len() - 1;
    // Truncation to the row index is intended; position is finite and >= 0 here.
    let row = (position.floor() as usize).min(last - 1);
    let fraction = (position - row as f64).min(1.0);
    MOLECULAR_WEIGHT_RATIO[row]
        + fraction * (MOLECULAR_WEIGHT_RATIO[row + 1] - MOLECULAR_WEIGHT_RATIO[row])
}

/// H = r0 Z / (r0 + Z), geopotential altitude in m' for geometric altitude Z in m (USSA-1976 eq. 18).
pub fn geopotential_altitude(geometric_altitude_m: f64) -> f64 {
    EARTH_RADIUS_M * geometric_altitude_m / (EARTH_RADIUS_M + geometric_altitude_m)
}

/// g = g0 (r0 / (r0 + Z))², m/s², at geometric altitude Z in m (USSA-1976 eq. 17).
pub fn gravity(geometric_altitude_m: f64) -> f64 {
    let ratio = EARTH_RADIUS_M / (EARTH_RADIUS_M + geometric_altitude_m);
    STANDARD_GRAVITY_M_S2 * ratio * ratio
}

/// μ = β T^(3/2) / (T + S), Pa s, β = 1.458e-6 kg/(m s K^½), S = 110.4 K (Sutherland; USSA-1976 eq. 51).
pub fn sutherland_viscosity(temperature_k: f64) -> f64 {
    1.458e-6 * temperature_k * temperature_k.sqrt() / (temperature_k + 110.4)
}

/// k = 2.64638e-3 T^(3/2) / (T + 245.4 · 10^(-12/T)), W/(m K) (USSA-1976 eq. 53).
pub fn air_thermal_conductivity(temperature_k: f64) -> f64 {
    2.646_38e-3 * temperature_k * temperature_k.sqrt()
        / (temperature_k + 245.4 * 10f64.powf(-12.0 / temperature_k))
}

/// The US Standard Atmosphere 1976 at geometric altitude Z in [0, 86 000] m.
pub fn us_standard_atmosphere_1976(
    geometric_altitude_m: f64,
) -> Result<AtmosphereState, AtmosphereError> {
    let z = geometric_altitude_m;
    if !z.is_finite() {
        return Err(AtmosphereError::NonFinite);
    }
    if !(MIN_ALTITUDE_M..=MAX_ALTITUDE_M).contains(&z) {
        return Err(AtmosphereError::OutOfRange { altitude_m: z });
    }
    let h = geopotential_altitude(z);
    let layer = LAYER_BASE_M
        .iter()
        .rposition(|&base| base <= h)
        .unwrap_or(0);
    let height = h - LAYER_BASE_M[layer];
    let molecular_temperature = LAYER_BASE_TEMPERATURE_K[layer] + LAYER_LAPSE_K_M[layer] * height;
    let pressure = layer_pressure(layer, LAYER_BASE_PRESSURE_PA[layer], height);
    let density =
        pressure * SEA_LEVEL_MOLECULAR_WEIGHT / (UNIVERSAL_GAS_CONSTANT * molecular_temperature);
    let temperature = molecular_temperature * molecular_weight_ratio(z);
    let viscosity = sutherland_viscosity(temperature);
    Ok(AtmosphereState {
        geometric_altitude_m: z,
        geopotential_altitude_m: h,
        temperature_k: temperature,
        pressure_pa: pressure,
        density_kg_m3: density,
        speed_of_sound_m_s: (GAMMA * UNIVERSAL_GAS_CONSTANT * molecular_temperature
            / SEA_LEVEL_MOLECULAR_WEIGHT)
            .sqrt(),
        dynamic_viscosity_pa_s: viscosity,
        kinematic_viscosity_m2_s: viscosity / density,
        thermal_conductivity_w_m_k: air_thermal_conductivity(temperature),
        gravity_m_s2: gravity(z),
    })
}
