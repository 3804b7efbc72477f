//! The `eckert` heat-flux model: flat-plate convection at a reference temperature along each
//! streamwise strip, Fay-Riddell stagnation heating on blunt (subsonic-edge) panels, minus
//! re-radiation from the hot wall (one file: the correlations are the numbered steps of the model
//! below, each beside its reference, and the model applies them panel by panel).
//!
//! For every panel, from the aero model's edge state (T_e, p_e, u_e, M_e), the running length x
//! from the leading edge and the wall temperature T_w:
//! 1. recovery factor r = Pr^(1/2) laminar, Pr^(1/3) turbulent, and recovery (adiabatic-wall)
//!    temperature T_aw = T_e (1 + r (γ−1)/2 M_e²) (Anderson, Hypersonic and High-Temperature Gas
//!    Dynamics, 2nd ed., §6.7);
//! 2. reference temperature T*: Eckert, T* = T_e + 0.5 (T_w − T_e) + 0.22 (T_aw − T_e) (Eckert,
//!    J. Aero. Sci. 22(8), 1955; Anderson §6.9), or Meador & Smart,
//!    T*/T_e = 0.45 + 0.55 T_w/T_e + 0.16 r (γ−1)/2 M_e² laminar and
//!    T*/T_e = 0.5 + 0.5 T_w/T_e + 0.16 r (γ−1)/2 M_e² turbulent
//!    (Meador & Smart, "Reference enthalpy method developed from solutions of the boundary-layer
//!    equations", AIAA J. 43(1), 2005; for a calorically perfect gas h* = c_p T*);
//! 3. properties at T*: ρ* = p_e / (R T*), μ* from Sutherland's law (USSA-1976 eq. 51), constant
//!    Prandtl number, Re_x* = ρ* u_e x / μ*;
//! 4. skin friction C_f* = 0.664 / √Re_x* laminar (Blasius) or C_f* = 0.0592 / Re_x*^0.2
//!    turbulent (1/7-power law; Schlichting, Boundary-Layer Theory, 7th ed., ch. XXI, 5e5 < Re_x < 1e7);
//! 5. Reynolds analogy (Colburn) St* = C_f*/2 · Pr^(−2/3);
//! 6. q_conv = ρ* u_e c_p St* (T_aw − T_w) and q_net = q_conv − ε σ T_w⁴.
//!
//! The regime is a setting: all laminar, all turbulent, or transitional (turbulent where the
//! edge Reynolds number ρ_e u_e x / μ_e reaches `transition_reynolds`).
//!
//! **Running length.** Along a strip (panels ordered leading edge to trailing edge) the running
//! length of panel i is Σ_{j<i} L_j + L_i / 2, with L_j = A_j / w_j the panel's mean length
//! along the strip and w_j its width across it. Panels in no strip (caps, unstructured meshes)
//! take `default_running_length_m`.
//!
//! **Stagnation region.** Where a windward panel's edge flow is subsonic (M_e < 1: behind a
//! detached shock, a blunt face; u_e = 0 at the stagnation state itself) flat-plate theory does
//! not hold. There the panel is taken as part of a blunt leading edge of radius
//! `leading_edge_radius_m` (a cylinder or a sphere, `leading_edge_shape`):
//! 7. Fay & Riddell's stagnation heating (J. Aeronaut. Sci. 25(2), 1958) for a perfect gas
//!    (Lewis number 1, no dissociation term),
//!    q_0 = K Pr^(−0.6) (ρ_e μ_e)^0.4 (ρ_w μ_w)^0.1 √(du_e/dx) c_p (T_0 − T_w),
//!    K = 0.763 sphere, 0.57 cylinder (two-dimensional), edge state the stagnation state behind
//!    a normal shock (pitot pressure p_0', T_0), wall state ρ_w = p_0'/(R T_w), μ_w = μ(T_w), and
//!    the Newtonian velocity gradient du_e/dx = (1/R_n) √(2 (p_0' − p_∞)/ρ_e) (Anderson,
//!    Hypersonic and High-Temperature Gas Dynamics, 2nd ed., ch. 6; Hirschel, Basics of
//!    Aerothermodynamics, §7);
//! 8. blended with the flat-plate value by the swept-cylinder rule of Tauber, Menees & Adelman
//!    (J. Aircraft 24(9), 1987), q = √(q_0² cos²Λ + q_fp² sin²Λ), where the panel's effective
//!    sweep Λ is the angle between its outward normal and the oncoming flow, cos Λ = sin θ with θ
//!    the panel's inclination to the flow: a face normal to the flow gets q_0, a face swept
//!    toward the flow direction tends to the flat-plate q_fp (steps 1-6; 0 where u_e = 0). A swept
//!    wing's leading edge carries its sweep into θ, so the cos Λ law needs no separate input.
//!    Tauber et al. write q_0 = q_sphere/√2 for the unswept cylinder; Fay-Riddell's 0.57/0.763 =
//!    0.75 is within 6 % of 1/√2.
//! Supersonic-edge panels (attached shocks, expansions) keep the flat-plate value alone, so a
//! sharp double wedge at small incidence is unchanged. `leading_edge_radius_m = 0` turns the
//! stagnation heating off (stagnation-region panels then get no convection).
//!
//! **Skin friction.** The same boundary layer gives the wall shear τ_w = ½ ρ* u_e² C_f* (step 4)
//! through the [`SkinFriction`] capability, for viscous loads
//! ([`hsv_core::aero::integrate_shear`]). Validated against van Driest II at Mach 6, Re_x = 1e7
//! (tests/skin_friction.rs): Meador-Smart within 10 %; Eckert's T* within 5 % on a 300 K wall but
//! 11-14 % low on 1000 K and adiabatic walls.
//!
//! **No boundary layer.** A vacuum panel (p_e = 0 or ρ_e = 0: expanded past the maximum
//! Prandtl-Meyer angle) gets no convection, only re-radiation. [`HeatFluxDiagnostics`] counts
//! vacuum, stagnant and stagnation-heated panels.

use hsv_core::aero::{AeroSolution, EdgeState};
use hsv_core::atmosphere::sutherland_viscosity;
use hsv_core::error::ModelError;
use hsv_core::flow::FlightCondition;
use hsv_core::gas::{PerfectGas, normal_shock, total_pressure_ratio};
use hsv_core::material::Material;
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};
use hsv_core::thermal::{
    HeatFluxModel, SkinFriction, check_heat_flux_inputs, check_wall_shear_inputs,
    check_wall_temperature,
};

/// Registered name.
pub const NAME: &str = "eckert";

pub use hsv_core::thermal::STEFAN_BOLTZMANN_W_M2_K4;

/// Which reference-temperature correlation sets T*.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reference {
    /// Eckert (1955): T* = T_e + 0.5 (T_w − T_e) + 0.22 (T_aw − T_e).
    Eckert,
    /// Meador & Smart (2005): separate laminar and turbulent fits to boundary-layer solutions.
    MeadorSmart,
}

/// Which boundary-layer state the skin-friction law assumes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    Laminar,
    Turbulent,
    /// Laminar below `transition_reynolds` (edge Reynolds number on the running length),
    /// turbulent from there on.
    Transitional,
}

/// Shape of the blunt leading edge that the stagnation heating assumes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LeadingEdgeShape {
    /// Two-dimensional (a wing's rounded leading edge): Fay-Riddell constant 0.57.
    Cylinder,
    /// Axisymmetric (a nose cap): Fay-Riddell constant 0.763.
    Sphere,
}

impl LeadingEdgeShape {
    /// K in q_0 = K Pr^(−0.6) (ρ_e μ_e)^0.4 (ρ_w μ_w)^0.1 √(du_e/dx) (h_0 − h_w) (Fay & Riddell
    /// 1958 sphere; 0.57 for the two-dimensional stagnation line, Hirschel, Basics of
    /// Aerothermodynamics, §7).
    pub fn fay_riddell_constant(self) -> f64 {
        match self {
            LeadingEdgeShape::Cylinder => 0.57,
            LeadingEdgeShape::Sphere => 0.763,
        }
    }
}

/// Settings of `[models.eckert]`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Reference-temperature correlation.
    pub reference: Reference,
    /// Laminar, turbulent or transitional.
    pub regime: Regime,
    /// Edge Reynolds number ρ_e u_e x / μ_e where a transitional boundary layer turns turbulent.
    pub transition_reynolds: f64,
    /// Prandtl number of air, constant (0.71 near 300-1000 K; Anderson, Hypersonic §6.7).
    pub prandtl_number: f64,
    /// Total hemispherical emissivity of the wall, 0 to 1.
    pub emissivity: f64,
    /// Wall temperature above which the structure has melted, K.
    pub melting_point_k: f64,
    /// Running length of panels that lie in no strip, m.
    pub default_running_length_m: f64,
    /// Radius of the blunt leading edge that stagnation-region panels belong to, m; 0 turns
    /// the stagnation heating off.
    pub leading_edge_radius_m: f64,
    /// Cylinder (wing leading edge) or sphere (nose cap).
    pub leading_edge_shape: LeadingEdgeShape,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            reference: Reference::Eckert,
            regime: Regime::Transitional,
            // Our choice: the classical flat-plate value (Schlichting ch. 15); hypersonic
            // transition is often later, so the default errs on the hot (turbulent) side.
            transition_reynolds: 5.0e5,
            prandtl_number: 0.71,
            // Our choice: oxidized titanium / high-emissivity coating, ε ≈ 0.8.
            emissivity: 0.8,
            // Ti-6Al-4V solidus, from the core material table (1877 K).
            melting_point_k: Material::ti_6al_4v().melting_point_k,
            default_running_length_m: 1.0,
            // Our choice: half the 2 mm minimum skin thickness the full-order conduction model
            // gives the sharp leading edges of the sample surface.
            leading_edge_radius_m: 0.001,
            leading_edge_shape: LeadingEdgeShape::Cylinder,
        }
    }
}

/// What `hsv-run describe eckert` prints.
pub const SETTINGS_DOC: &str = "\
reference = \"eckert\"            # \"eckert\" (Eckert 1955 T*) or \"meador-smart\" (Meador & Smart 2005)
regime = \"transitional\"         # \"laminar\", \"turbulent\" or \"transitional\"
transition_reynolds = 5e5       # edge Reynolds number on the running length where transition happens
prandtl_number = 0.71           # constant Prandtl number of air
emissivity = 0.8                # wall emissivity for re-radiation, 0 to 1
melting_point_k = 1877.0        # wall temperature limit (Ti-6Al-4V solidus), K
default_running_length_m = 1.0  # running length of panels in no strip, m
leading_edge_radius_m = 0.001   # blunt leading-edge radius for panels with a subsonic edge (detached shock), m; 0 = off
leading_edge_shape = \"cylinder\"  # \"cylinder\" (Fay-Riddell 0.57, wing edge) or \"sphere\" (0.763, nose cap)
                                # subsonic-edge panels: q = sqrt(q_0^2 sin^2(theta) + q_flat_plate^2 cos^2(theta))
                                #   (Tauber, Menees & Adelman 1987 swept cylinder, theta = inclination to the flow)";

impl Settings {
    /// The first setting outside its range: (key, value, allowed range).
    fn first_invalid(&self) -> Option<(&'static str, f64, &'static str)> {
        let checks: [(&'static str, f64, bool, &'static str); 6] = [
            (
                "transition_reynolds",
                self.transition_reynolds,
                self.transition_reynolds > 0.0,
                "finite and > 0",
            ),
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
            (
                "leading_edge_radius_m",
                self.leading_edge_radius_m,
                self.leading_edge_radius_m >= 0.0,
                "finite and >= 0 m",
            ),
        ];
        checks
            .into_iter()
            .find(|(_, value, ok, _)| !(value.is_finite() && *ok))
            .map(|(key, value, _, allowed)| (key, value, allowed))
    }
}

/// Counts from the last [`HeatFluxModel::heat_flux`] call.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct HeatFluxDiagnostics {
    /// Panels whose boundary layer was taken as turbulent.
    pub turbulent_panels: usize,
    /// Vacuum panels (p_e = 0 or ρ_e = 0): no convection.
    pub vacuum_panels: usize,
    /// Stagnant panels (u_e = 0, behind a detached shock): no flat-plate convection.
    pub stagnant_panels: usize,
    /// Windward panels with a subsonic edge that got the blended stagnation heating.
    pub stagnation_panels: usize,
}

/// Convective heating of one flat-plate station, with the intermediate quantities.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ConvectiveHeating {
    pub turbulent: bool,
    pub recovery_factor: f64,
    /// Recovery (adiabatic-wall) temperature T_aw, K.
    pub recovery_temperature_k: f64,
    /// Reference temperature T*, K.
    pub reference_temperature_k: f64,
    /// ρ* = p_e / (R T*), kg/m³.
    pub reference_density_kg_m3: f64,
    /// μ* = μ(T*), Pa s.
    pub reference_viscosity_pa_s: f64,
    /// Edge Reynolds number ρ_e u_e x / μ_e on the running length.
    pub edge_reynolds: f64,
    /// Re_x* = ρ* u_e x / μ*.
    pub reference_reynolds: f64,
    /// C_f* (based on ρ*).
    pub skin_friction: f64,
    /// St* (based on ρ*).
    pub stanton_number: f64,
    /// Wall shear stress τ_w = ½ ρ* u_e² C_f*, Pa.
    pub wall_shear_pa: f64,
    /// q_conv = ρ* u_e c_p St* (T_aw − T_w), W/m², positive into the wall.
    pub heat_flux_w_m2: f64,
}

/// The recovery factor and temperature are the shared kernels of `hsv_core::thermal` (kriging
/// uses them too).
pub use hsv_core::thermal::{recovery_factor, recovery_temperature_k};

/// T* = T_e + 0.5 (T_w − T_e) + 0.22 (T_aw − T_e), K (Eckert 1955; Anderson, Hypersonic §6.9).
pub fn eckert_reference_temperature_k(
    edge_temperature_k: f64,
    wall_temperature_k: f64,
    recovery_temperature_k: f64,
) -> f64 {
    edge_temperature_k
        + 0.5 * (wall_temperature_k - edge_temperature_k)
        + 0.22 * (recovery_temperature_k - edge_temperature_k)
}

/// T*/T_e = 0.45 + 0.55 T_w/T_e + 0.16 r (γ−1)/2 M_e² laminar, 0.5 + 0.5 T_w/T_e + 0.16 r (γ−1)/2
/// M_e² turbulent, K (Meador & Smart, AIAA J. 43(1), 2005).
pub fn meador_smart_reference_temperature_k(
    edge_temperature_k: f64,
    wall_temperature_k: f64,
    mach: f64,
    gamma: f64,
    r: f64,
    turbulent: bool,
) -> f64 {
    let (a, b) = if turbulent { (0.5, 0.5) } else { (0.45, 0.55) };
    let dissipation = 0.16 * r * 0.5 * (gamma - 1.0) * mach * mach;
    edge_temperature_k * (a + b * wall_temperature_k / edge_temperature_k + dissipation)
}

/// C_f = 0.664 / √Re_x (Blasius; Anderson, Hypersonic §6.9 at reference conditions).
pub fn laminar_skin_friction(reynolds: f64) -> f64 {
    0.664 / reynolds.sqrt()
}

/// C_f = 0.0592 / Re_x^0.2 (1/7-power law; Schlichting, Boundary-Layer Theory, 7th ed., ch. XXI).
pub fn turbulent_skin_friction(reynolds: f64) -> f64 {
    0.0592 / reynolds.powf(0.2)
}

/// St = C_f / 2 · Pr^(−2/3) (Colburn's Reynolds analogy; Anderson, Hypersonic §6.9).
pub fn stanton_number(skin_friction: f64, prandtl_number: f64) -> f64 {
    0.5 * skin_friction * prandtl_number.powf(-2.0 / 3.0)
}

/// Stagnation state behind the bow shock: pitot pressure p_0' (normal shock, then isentropic
/// compression; isentropic alone for M < 1), Pa.
pub fn pitot_pressure_pa(mach: f64, pressure_pa: f64, gamma: f64) -> f64 {
    match normal_shock(mach, gamma) {
        Ok(shock) => pressure_pa * total_pressure_ratio(mach, gamma) * shock.total_pressure_ratio,
        Err(_) => pressure_pa * total_pressure_ratio(mach, gamma),
    }
}

/// du_e/dx = (1/R_n) √(2 (p_e − p_∞)/ρ_e), 1/s (Newtonian stagnation-point velocity gradient;
/// Anderson, Hypersonic and High-Temperature Gas Dynamics, ch. 6).
pub fn newtonian_velocity_gradient_per_s(
    radius_m: f64,
    edge_pressure_pa: f64,
    freestream_pressure_pa: f64,
    edge_density_kg_m3: f64,
) -> f64 {
    (2.0 * (edge_pressure_pa - freestream_pressure_pa).max(0.0) / edge_density_kg_m3).sqrt()
        / radius_m
}

/// Fay-Riddell stagnation heating of a perfect gas (Le = 1), W/m², positive into the wall:
/// q_0 = K Pr^(−0.6) (ρ_e μ_e)^0.4 (ρ_w μ_w)^0.1 √(du_e/dx) c_p (T_0 − T_w) (Fay & Riddell,
/// J. Aeronaut. Sci. 25(2), 1958), at the stagnation state behind a normal shock.
pub fn fay_riddell_heat_flux_w_m2(
    freestream: &hsv_core::flow::Freestream,
    radius_m: f64,
    shape: LeadingEdgeShape,
    prandtl_number: f64,
    wall_temperature_k: f64,
) -> f64 {
    let gas = freestream.gas;
    let r = gas.gas_constant_j_kg_k;
    let t0 = freestream.total_temperature_k();
    let p0 = pitot_pressure_pa(freestream.mach, freestream.pressure_pa, gas.gamma);
    let rho_e = p0 / (r * t0);
    let rho_w = p0 / (r * wall_temperature_k);
    let gradient = newtonian_velocity_gradient_per_s(radius_m, p0, freestream.pressure_pa, rho_e);
    shape.fay_riddell_constant()
        * prandtl_number.powf(-0.6)
        * (rho_e * sutherland_viscosity(t0)).powf(0.4)
        * (rho_w * sutherland_viscosity(wall_temperature_k)).powf(0.1)
        * gradient.sqrt()
        * gas.cp()
        * (t0 - wall_temperature_k)
}

/// q = √(q_0² sin²θ + q_fp² cos²θ) with the sign of the dominant term, W/m²: Tauber, Menees &
/// Adelman's swept-cylinder blend (J. Aircraft 24(9), 1987) with effective sweep Λ = 90° − θ.
pub fn swept_blend_w_m2(stagnation_w_m2: f64, flat_plate_w_m2: f64, inclination_rad: f64) -> f64 {
    let (s, c) = inclination_rad.sin_cos();
    let a = stagnation_w_m2 * s;
    let b = flat_plate_w_m2 * c;
    // Both terms share the sign of (T_recovery − T_w) except in the narrow band between T_aw
    // and T_0; there the larger term sets the direction.
    let sign = if a.abs() >= b.abs() {
        a.signum()
    } else {
        b.signum()
    };
    sign * a.hypot(b)
}

/// The `eckert` heat-flux model. Scratch: running lengths of the last mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Eckert {
    settings: Settings,
    /// Powers of the (fixed) Prandtl number every panel needs, computed once.
    prandtl: PrandtlPowers,
    running_length_m: Vec<f64>,
    /// Per panel, the panel of an earlier strip whose flat-plate boundary layer it repeats
    /// ([`Eckert::find_repeats`]), or `None`.
    repeat_of: Vec<Option<usize>>,
    /// The flat-plate heating of each panel that repeats none (scratch of `heat_flux`).
    flat_plate: Vec<Option<ConvectiveHeating>>,
    diagnostics: HeatFluxDiagnostics,
}

/// The Prandtl-number powers of steps 1 and 5, from the settings at construction: the same
/// expressions as [`recovery_factor`] and [`stanton_number`], evaluated once per model instead
/// of once per panel.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PrandtlPowers {
    /// r = Pr^(1/2).
    laminar_recovery: f64,
    /// r = Pr^(1/3).
    turbulent_recovery: f64,
    /// Pr^(-2/3) of Colburn's analogy.
    colburn: f64,
}

impl PrandtlPowers {
    fn new(prandtl_number: f64) -> Self {
        Self {
            laminar_recovery: recovery_factor(prandtl_number, false),
            turbulent_recovery: recovery_factor(prandtl_number, true),
            colburn: prandtl_number.powf(-2.0 / 3.0),
        }
    }

    /// [`recovery_factor`] of the model's Prandtl number.
    fn recovery_factor(&self, turbulent: bool) -> f64 {
        if turbulent {
            self.turbulent_recovery
        } else {
            self.laminar_recovery
        }
    }

    /// [`stanton_number`] St = C_f / 2 · Pr^(−2/3) of the model's Prandtl number.
    fn stanton_number(&self, skin_friction: f64) -> f64 {
        0.5 * skin_friction * self.colburn
    }
}

impl Eckert {
    /// The model with `settings`; a setting out of range is an error naming it.
    pub fn new(settings: Settings) -> Result<Self, ModelError> {
        if let Some((key, value, allowed)) = settings.first_invalid() {
            return Err(ModelError::out_of_range(NAME, key, value, allowed));
        }
        Ok(Self {
            settings,
            prandtl: PrandtlPowers::new(settings.prandtl_number),
            running_length_m: Vec::new(),
            repeat_of: Vec::new(),
            flat_plate: Vec::new(),
            diagnostics: HeatFluxDiagnostics::default(),
        })
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Counts from the last heat-flux evaluation.
    pub fn diagnostics(&self) -> HeatFluxDiagnostics {
        self.diagnostics
    }

    /// Running length of each panel of the last evaluated mesh, m.
    pub fn running_lengths_m(&self) -> &[f64] {
        &self.running_length_m
    }

    /// Convective heat flux at one flat-plate station (module docs), or `None` where there is no
    /// boundary layer (vacuum or stagnant edge). Errors name the bad input.
    pub fn convective_heating(
        &self,
        edge: &EdgeState,
        gas: &PerfectGas,
        running_length_m: f64,
        wall_temperature_k: f64,
    ) -> Result<Option<ConvectiveHeating>, ModelError> {
        check_wall_temperature(
            NAME,
            wall_temperature_k,
            self.settings.melting_point_k,
            None,
        )?;
        check_edge(edge, None)?;
        if !(running_length_m.is_finite() && running_length_m > 0.0) {
            return Err(ModelError::out_of_range(
                NAME,
                "running length (m)",
                running_length_m,
                "finite and > 0",
            ));
        }
        if is_vacuum(edge) || edge.velocity_m_s == 0.0 {
            return Ok(None);
        }
        Ok(Some(self.heating(
            edge,
            gas,
            running_length_m,
            wall_temperature_k,
        )))
    }

    /// Steps 1-6 of the module docs for a checked, convecting edge state.
    fn heating(
        &self,
        edge: &EdgeState,
        gas: &PerfectGas,
        x_m: f64,
        wall_temperature_k: f64,
    ) -> ConvectiveHeating {
        let s = &self.settings;
        let te = edge.temperature_k;
        let u = edge.velocity_m_s;
        let edge_reynolds = edge.density_kg_m3 * u * x_m / sutherland_viscosity(te);
        let turbulent = match s.regime {
            Regime::Laminar => false,
            Regime::Turbulent => true,
            Regime::Transitional => edge_reynolds >= s.transition_reynolds,
        };
        let r = self.prandtl.recovery_factor(turbulent);
        let taw = recovery_temperature_k(te, edge.mach, gas.gamma, r);
        let t_ref = match s.reference {
            Reference::Eckert => eckert_reference_temperature_k(te, wall_temperature_k, taw),
            Reference::MeadorSmart => meador_smart_reference_temperature_k(
                te,
                wall_temperature_k,
                edge.mach,
                gas.gamma,
                r,
                turbulent,
            ),
        };
        let rho = edge.pressure_pa / (gas.gas_constant_j_kg_k * t_ref);
        let mu = sutherland_viscosity(t_ref);
        let reynolds = rho * u * x_m / mu;
        let cf = if turbulent {
            turbulent_skin_friction(reynolds)
        } else {
            laminar_skin_friction(reynolds)
        };
        let st = self.prandtl.stanton_number(cf);
        ConvectiveHeating {
            turbulent,
            recovery_factor: r,
            recovery_temperature_k: taw,
            reference_temperature_k: t_ref,
            reference_density_kg_m3: rho,
            reference_viscosity_pa_s: mu,
            edge_reynolds,
            reference_reynolds: reynolds,
            skin_friction: cf,
            stanton_number: st,
            wall_shear_pa: 0.5 * rho * u * u * cf,
            heat_flux_w_m2: rho * u * gas.cp() * st * (taw - wall_temperature_k),
        }
    }

    /// A windward panel (sin θ > 0, i.e. θ > 0) whose edge flow is subsonic (detached shock ahead
    /// of it), with stagnation heating switched on.
    fn in_stagnation_region(&self, edge: &EdgeState, sin_inclination: f64) -> bool {
        self.settings.leading_edge_radius_m > 0.0 && edge.mach < 1.0 && sin_inclination > 0.0
    }

    /// Re-radiation ε σ T_w⁴ from the wall to cold surroundings, W/m².
    pub fn radiated_flux_w_m2(&self, wall_temperature_k: f64) -> f64 {
        self.settings.emissivity * STEFAN_BOLTZMANN_W_M2_K4 * wall_temperature_k.powi(4)
    }
}

/// A panel with no convection: only re-radiation.
fn continue_radiating(out: &mut f64, radiated_w_m2: f64, panel: usize) -> Result<(), ModelError> {
    if !radiated_w_m2.is_finite() {
        return Err(ModelError::non_finite_at_panel(
            NAME,
            "net heat flux",
            panel,
        ));
    }
    *out = -radiated_w_m2;
    Ok(())
}

fn at_panel(panel: Option<usize>) -> String {
    panel.map_or_else(String::new, |p| format!(" at panel {p}"))
}

/// Checks an edge state is finite and non-negative with T_e > 0.
/// An edge expanded to vacuum (p_e = 0 or ρ_e = 0): no boundary layer forms on its panel.
fn is_vacuum(edge: &EdgeState) -> bool {
    edge.pressure_pa == 0.0 || edge.density_kg_m3 == 0.0
}

fn check_edge(edge: &EdgeState, panel: Option<usize>) -> Result<(), ModelError> {
    let named = [
        ("edge Mach number", edge.mach),
        ("edge pressure (Pa)", edge.pressure_pa),
        ("edge density (kg/m^3)", edge.density_kg_m3),
        ("edge velocity (m/s)", edge.velocity_m_s),
    ];
    for (quantity, value) in named {
        if !(value.is_finite() && value >= 0.0) {
            return Err(ModelError::out_of_range(
                NAME,
                &format!("{quantity}{}", at_panel(panel)),
                value,
                "finite and >= 0",
            ));
        }
    }
    // An expansion to vacuum (p_e = 0 or ρ_e = 0: piston theory or Prandtl-Meyer past its
    // maximum turning) also cools the edge to 0 K; such a panel has no boundary layer and is
    // counted as a vacuum panel, not refused.
    let temperature_ok = edge.temperature_k.is_finite()
        && (edge.temperature_k > 0.0 || (is_vacuum(edge) && edge.temperature_k == 0.0));
    if !temperature_ok {
        return Err(ModelError::out_of_range(
            NAME,
            &format!("edge temperature (K){}", at_panel(panel)),
            edge.temperature_k,
            "finite and > 0 (0 only on a vacuum panel, p_e = 0 or rho_e = 0)",
        ));
    }
    Ok(())
}

impl HeatFluxModel for Eckert {
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
        let n = mesh.panels.len();
        let gas = flight.freestream.gas;
        self.update_running_lengths(mesh, flight);
        let direction = flight.velocity_body_m_s().normalize();
        let mut diagnostics = HeatFluxDiagnostics::default();
        self.check_panels(aero, wall_temperature_k)?;
        self.find_repeats(mesh, aero, wall_temperature_k);
        let mut flat_plate = std::mem::take(&mut self.flat_plate);
        flat_plate.clear();
        flat_plate.extend((0..n).map(|i| {
            let edge = &aero.edge[i];
            let boundary_layer = !is_vacuum(edge) && edge.velocity_m_s != 0.0;
            (boundary_layer && self.repeat_of[i].is_none())
                .then(|| self.heating(edge, &gas, self.running_length_m[i], wall_temperature_k[i]))
        }));
        for i in 0..n {
            let tw = wall_temperature_k[i];
            let edge = &aero.edge[i];
            let flat_plate = if is_vacuum(edge) {
                diagnostics.vacuum_panels += 1;
                continue_radiating(&mut out_w_m2[i], self.radiated_flux_w_m2(tw), i)?;
                continue;
            } else if edge.velocity_m_s == 0.0 {
                diagnostics.stagnant_panels += 1;
                0.0
            } else {
                let root = self.repeat_of[i].unwrap_or(i);
                let h = flat_plate[root]
                    .unwrap_or_else(|| self.heating(edge, &gas, self.running_length_m[i], tw));
                diagnostics.turbulent_panels += usize::from(h.turbulent);
                h.heat_flux_w_m2
            };
            // sin θ = n · V̂; θ itself (an `asin`) only on the few stagnation-region panels.
            let sin_inclination = mesh.panels[i].normal.dot(&direction).clamp(-1.0, 1.0);
            let convection = if self.in_stagnation_region(edge, sin_inclination) {
                diagnostics.stagnation_panels += 1;
                let inclination_rad = sin_inclination.asin();
                let q0 = fay_riddell_heat_flux_w_m2(
                    &flight.freestream,
                    self.settings.leading_edge_radius_m,
                    self.settings.leading_edge_shape,
                    self.settings.prandtl_number,
                    tw,
                );
                swept_blend_w_m2(q0, flat_plate, inclination_rad)
            } else {
                flat_plate
            };
            let net = convection - self.radiated_flux_w_m2(tw);
            if !net.is_finite() {
                return Err(ModelError::non_finite_at_panel(NAME, "net heat flux", i));
            }
            out_w_m2[i] = net;
        }
        self.diagnostics = diagnostics;
        self.flat_plate = flat_plate;
        Ok(())
    }

    fn skin_friction(&mut self) -> Option<&mut dyn SkinFriction> {
        Some(self)
    }
}

impl Eckert {
    /// Fills the running length of every panel of `mesh` for a flight condition.
    fn update_running_lengths(&mut self, mesh: &PanelMesh, flight: &FlightCondition) {
        let mut running = std::mem::take(&mut self.running_length_m);
        mesh.strip_running_lengths_m(
            &flight.velocity_body_m_s(),
            self.settings.default_running_length_m,
            &mut running,
        );
        self.running_length_m = running;
    }

    /// Every panel's wall temperature and edge state checked, in panel order (the first bad
    /// one is the error, naming it).
    fn check_panels(
        &self,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
    ) -> Result<(), ModelError> {
        for (i, (&tw, edge)) in wall_temperature_k.iter().zip(&aero.edge).enumerate() {
            check_wall_temperature(NAME, tw, self.settings.melting_point_k, Some(i))?;
            check_edge(edge, Some(i))?;
        }
        Ok(())
    }

    /// Which panels repeat the flat-plate boundary layer of a panel of an earlier strip: at
    /// the same place in the strip before theirs (of as many panels), with the same edge state
    /// and wall temperature to the bit and a running length within 1e-12 relative (rounding of
    /// the mesh). Flat-plate heating and shear read nothing else, so a boundary layer repeated
    /// across a flat face is computed once (600 of the sample body's 1304 panels repeat one;
    /// the others' running lengths differ). Each repeat points at the first panel of its chain,
    /// which repeats none.
    fn find_repeats(&mut self, mesh: &PanelMesh, aero: &AeroSolution, wall_temperature_k: &[f64]) {
        let n = mesh.panels.len();
        self.repeat_of.clear();
        self.repeat_of.resize(n, None);
        let running = &self.running_length_m;
        for pair in mesh.strips.windows(2) {
            let (last, next) = (&pair[0].panels, &pair[1].panels);
            if last.len() != next.len() {
                continue;
            }
            for (&a, &b) in last.iter().zip(next) {
                let repeats = a != b
                    && a < n
                    && b < n
                    && self.repeat_of[b].is_none()
                    && aero.edge[a] == aero.edge[b]
                    && wall_temperature_k[a] == wall_temperature_k[b]
                    && (running[a] - running[b]).abs() <= 1e-12 * running[a].abs();
                if repeats {
                    self.repeat_of[b] = Some(self.repeat_of[a].unwrap_or(a));
                }
            }
        }
    }
}

impl SkinFriction for Eckert {
    /// τ_w = ½ ρ* u_e² C_f* of the flat-plate boundary layer (module docs, steps 1-4) on each
    /// panel's running length, in the configured regime; 0 where there is no boundary layer
    /// (vacuum, or a stagnant edge u_e = 0). Subsonic-edge (stagnation-region) panels keep the
    /// flat-plate shear of their edge velocity: the stagnation blend is a heating law only.
    fn wall_shear(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        aero: &AeroSolution,
        wall_temperature_k: &[f64],
        out_pa: &mut [f64],
    ) -> Result<(), ModelError> {
        check_wall_shear_inputs(NAME, mesh, flight, aero, wall_temperature_k, out_pa)?;
        self.update_running_lengths(mesh, flight);
        let gas = flight.freestream.gas;
        self.check_panels(aero, wall_temperature_k)?;
        self.find_repeats(mesh, aero, wall_temperature_k);
        // Panels that repeat none first, then each repeat takes its panel's shear.
        for (i, out) in out_pa.iter_mut().enumerate() {
            if self.repeat_of[i].is_some() {
                continue;
            }
            let tw = wall_temperature_k[i];
            let edge = &aero.edge[i];
            let no_boundary_layer = is_vacuum(edge) || edge.velocity_m_s == 0.0;
            let tau = if no_boundary_layer {
                0.0
            } else {
                self.heating(edge, &gas, self.running_length_m[i], tw)
                    .wall_shear_pa
            };
            if !tau.is_finite() {
                return Err(ModelError::non_finite_at_panel(NAME, "wall shear", i));
            }
            *out = tau;
        }
        for i in 0..out_pa.len() {
            if let Some(root) = self.repeat_of[i] {
                out_pa[i] = out_pa[root];
            }
        }
        Ok(())
    }
}

fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn HeatFluxModel>, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    if let Some((key, value, allowed)) = settings.first_invalid() {
        return Err(ModelError::Settings {
            file: ctx.file.to_owned(),
            key_path: format!("{}.{key}", ctx.key_path),
            message: format!("{value} is outside the allowed range ({allowed})"),
        });
    }
    Ok(Box::new(Eckert::new(settings)?))
}

hsv_core::register_model!(ModelDescriptor {
    name: NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "flat-plate aeroheating at the Eckert reference temperature (or Meador-Smart \
              reference enthalpy), laminar/turbulent, Reynolds analogy, Fay-Riddell stagnation heating \
              blended on subsonic-edge (blunt) panels, wall re-radiation; wall shear for skin-friction loads",
    settings_doc: SETTINGS_DOC,
    constructor: Constructor::HeatFlux(construct),
});
