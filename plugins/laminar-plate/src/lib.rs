//! Example hsv dylib plugin: `laminar-flat-plate`, laminar flat-plate aeroheating with wall
//! re-radiation, written as a model author outside the hsv repository would: the role trait
//! ([`HeatFluxModel`]), a constructor, and [`hsv_core::export_plugin!`] (plugin ABI 2).
//!
//! For every panel, from the aero model's edge state (T_e, p_e, u_e, M_e), the running length x
//! from the leading edge of its strip and the wall temperature T_w:
//! 1. laminar recovery factor r = √Pr and T_aw = T_e (1 + r (γ−1)/2 M_e²) (Anderson, Hypersonic
//!    and High-Temperature Gas Dynamics, 2nd ed., §6.7);
//! 2. Eckert's reference temperature T* = T_e + 0.5 (T_w − T_e) + 0.22 (T_aw − T_e) (Eckert,
//!    J. Aero. Sci. 22(8), 1955; Anderson §6.9);
//! 3. ρ* = p_e / (R T*), μ* by Sutherland's law (USSA-1976 eq. 51), Re_x* = ρ* u_e x / μ*;
//! 4. Blasius C_f* = 0.664 / √Re_x* and Colburn's analogy St* = C_f*/2 · Pr^(−2/3);
//! 5. q = ρ* u_e c_p St* (T_aw − T_w) − ε σ T_w⁴, W/m², positive into the wall.
//!
//! In the low-speed limit (T* → film temperature) this is the Blasius-Pohlhausen result
//! Nu_x = 0.332 Re_x^½ Pr^⅓ (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, eq. 7.23).
//! Vacuum and stagnant panels (p_e, ρ_e or u_e = 0) only re-radiate. Panels in no strip take
//! `default_running_length_m`. The boundary layer is laminar everywhere: the model is meant for
//! low-Reynolds-number surfaces (Re_x below about 5e5) and says nothing about transition.
//!
//! Build: `cargo build --release -p hsv-plugin-laminar-plate`; load: `hsv-run --plugin
//! target/release/libhsv_plugin_laminar_plate.so ...`; select `laminar-flat-plate` as a region's
//! heat-flux model.

use hsv_core::aero::AeroSolution;
use hsv_core::error::ModelError;
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::ModelContext;
use hsv_core::thermal::{
    HeatFluxModel, STEFAN_BOLTZMANN_W_M2_K4, check_heat_flux_inputs, check_wall_temperature,
};

/// Registered name.
pub const NAME: &str = "laminar-flat-plate";

/// `[models.laminar-flat-plate]`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Prandtl number of air, constant.
    pub prandtl_number: f64,
    /// Total hemispherical emissivity of the wall, 0 to 1.
    pub emissivity: f64,
    /// Wall temperature above which the structure has melted, K.
    pub melting_point_k: f64,
    /// Running length of panels that lie in no strip, m.
    pub default_running_length_m: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            // Air near 300-1000 K (Anderson, Hypersonic §6.7).
            prandtl_number: 0.71,
            // Our choice: oxidized titanium / high-emissivity coating.
            emissivity: 0.8,
            // Ti-6Al-4V solidus, K.
            melting_point_k: 1877.0,
            default_running_length_m: 1.0,
        }
    }
}

/// What `hsv-run describe laminar-flat-plate` prints.
pub const SETTINGS_DOC: &str = "\
prandtl_number = 0.71           # constant Prandtl number of air
emissivity = 0.8                # wall emissivity for re-radiation, 0 to 1
melting_point_k = 1877.0        # wall temperature limit, K
default_running_length_m = 1.0  # running length of panels in no strip, m";

impl Settings {
    /// The first setting outside its range: (key, value, allowed range).
    fn first_invalid(&self) -> Option<(&'static str, f64, &'static str)> {
        [
            (
                "prandtl_number",
                self.prandtl_number,
                self.prandtl_number > 0.0 && self.prandtl_number <= 10.0,
                "0 < Pr <= 10",
            ),
            (
                "emissivity",
                self.emissivity,
                (0.0..=1.0).contains(&self.emissivity),
                "0 to 1",
            ),
            (
                "melting_point_k",
                self.melting_point_k,
                self.melting_point_k > 0.0,
                "finite and > 0 K",
            ),
            (
                "default_running_length_m",
                self.default_running_length_m,
                self.default_running_length_m > 0.0,
                "finite and > 0 m",
            ),
        ]
        .into_iter()
        .find(|(_, value, ok, _)| !(value.is_finite() && *ok))
        .map(|(key, value, _, allowed)| (key, value, allowed))
    }
}

/// μ = β T^(3/2) / (T + S), Pa s, β = 1.458e-6 kg/(m s K^½), S = 110.4 K (Sutherland;
/// USSA-1976 eq. 51).
pub fn sutherland_viscosity_pa_s(temperature_k: f64) -> f64 {
    1.458e-6 * temperature_k * temperature_k.sqrt() / (temperature_k + 110.4)
}

/// The `laminar-flat-plate` model. Scratch: running lengths of the last mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct LaminarFlatPlate {
    settings: Settings,
    running_length_m: Vec<f64>,
}

impl LaminarFlatPlate {
    /// The model with `settings`; a setting out of range is an error naming it.
    pub fn new(settings: Settings) -> Result<Self, ModelError> {
        if let Some((key, value, allowed)) = settings.first_invalid() {
            return Err(ModelError::out_of_range(NAME, key, value, allowed));
        }
        Ok(Self {
            settings,
            running_length_m: Vec::new(),
        })
    }

    /// Convective heat flux (steps 1-5 without radiation) of one station, W/m²: edge temperature
    /// `te` K, pressure `pe` Pa, velocity `u` m/s, Mach `me`, running length `x` m, wall `tw` K.
    #[allow(clippy::too_many_arguments)]
    pub fn convective_w_m2(
        &self,
        te: f64,
        pe: f64,
        u: f64,
        me: f64,
        x: f64,
        tw: f64,
        gamma: f64,
        gas_constant: f64,
    ) -> f64 {
        let pr = self.settings.prandtl_number;
        let r = pr.sqrt();
        let taw = te * (1.0 + r * 0.5 * (gamma - 1.0) * me * me);
        let t_ref = te + 0.5 * (tw - te) + 0.22 * (taw - te);
        let rho = pe / (gas_constant * t_ref);
        let reynolds = rho * u * x / sutherland_viscosity_pa_s(t_ref);
        let cf = 0.664 / reynolds.sqrt();
        let st = 0.5 * cf * pr.powf(-2.0 / 3.0);
        let cp = gamma * gas_constant / (gamma - 1.0);
        rho * u * cp * st * (taw - tw)
    }
}

impl HeatFluxModel for LaminarFlatPlate {
    fn name(&self) -> &str {
        NAME
    }

    fn heat_flux(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
        out_w_m2: &mut [f64],
    ) -> Result<(), ModelError> {
        check_heat_flux_inputs(NAME, mesh, flight, aero, wall_temperature_k, out_w_m2)?;
        let gas = flight.freestream.gas;
        mesh.strip_running_lengths_m(
            &flight.velocity_body_m_s(),
            self.settings.default_running_length_m,
            &mut self.running_length_m,
        );
        for (i, out) in out_w_m2.iter_mut().enumerate() {
            let tw = wall_temperature_k[i];
            check_wall_temperature(NAME, tw, self.settings.melting_point_k, Some(i))?;
            let e = &aero.edge[i];
            let edge = [
                e.mach,
                e.pressure_pa,
                e.temperature_k,
                e.density_kg_m3,
                e.velocity_m_s,
            ];
            if let Some(bad) = edge.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
                return Err(ModelError::out_of_range(
                    NAME,
                    &format!("edge state at panel {i}"),
                    *bad,
                    "finite and >= 0",
                ));
            }
            let boundary_layer =
                e.pressure_pa > 0.0 && e.density_kg_m3 > 0.0 && e.velocity_m_s > 0.0;
            let convection = if boundary_layer {
                if e.temperature_k <= 0.0 {
                    return Err(ModelError::out_of_range(
                        NAME,
                        &format!("edge temperature (K) at panel {i}"),
                        e.temperature_k,
                        "> 0",
                    ));
                }
                self.convective_w_m2(
                    e.temperature_k,
                    e.pressure_pa,
                    e.velocity_m_s,
                    e.mach,
                    self.running_length_m[i],
                    tw,
                    gas.gamma,
                    gas.gas_constant_j_kg_k,
                )
            } else {
                0.0
            };
            let net = convection - self.settings.emissivity * STEFAN_BOLTZMANN_W_M2_K4 * tw.powi(4);
            if !net.is_finite() {
                return Err(ModelError::non_finite_at_panel(NAME, "net heat flux", i));
            }
            *out = net;
        }
        Ok(())
    }
}

/// Builds the model from `[models.laminar-flat-plate]`.
pub fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn HeatFluxModel>, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    if let Some((key, value, allowed)) = settings.first_invalid() {
        return Err(ctx.settings_error(
            key,
            format!("{value} is outside the allowed range ({allowed})"),
        ));
    }
    Ok(Box::new(LaminarFlatPlate::new(settings)?))
}

hsv_core::export_plugin! {
    heat_flux {
        name: NAME,
        fidelity: 0,
        summary: "Laminar flat-plate aeroheating at the Eckert reference temperature (Blasius skin \
                  friction, Colburn analogy) minus wall re-radiation; example dylib plugin",
        settings: SETTINGS_DOC,
        constructor: construct,
    }
}
