//! The `newtonian-scalar` and `newtonian-vector` aero models: modified Newtonian impact pressures.
//!
//! Lees' modified Newtonian law (Anderson, Hypersonic and High-Temperature Gas Dynamics, 2nd ed.,
//! ch. 3, eqs. 3.15-3.16): C_p = C_p,max sin²θ on panels facing the flow, where θ is the angle
//! between the panel and the relative velocity and C_p,max = (p02 − p∞)/q∞ is the stagnation
//! value behind a normal shock (Rayleigh pitot formula, NACA Report 1135 eq. 100). Panels facing
//! away from the flow (sin θ ≤ 0) get p∞ and are counted in `shadowed_panels`.
//!
//! - `newtonian-scalar` (fidelity 1): θ from the panel normal and the vehicle velocity only,
//!   sin θ = n · V̂_body; p = p∞ + q∞ C_p,max sin²θ. Deformed normals count, panel rates do not.
//! - `newtonian-vector` (fidelity 2): each panel's own velocity relative to the air V_p (rigid
//!   translation and rotation plus elastic velocity); sin θ = n · V_p / |V_p| and
//!   p = p∞ + ½ ρ∞ |V_p|² C_p,max(M_p) sin²θ with M_p = |V_p|/a∞, i.e. the modified Newtonian
//!   law applied in the panel's own frame, so a panel moving straight into the gas stagnates at
//!   the pitot pressure of its own relative Mach number. Fidelity 2 because it resolves the
//!   motion-induced (unsteady, aerodynamic-damping) pressures the scalar form misses; its
//!   steady pressures are identical to the scalar form's.
//!
//! Edge state: windward panels expand isentropically from the normal-shock total state (T0
//! conserved, p02 from the pitot formula) to the panel pressure; shadowed panels see the
//! freestream.

use hsv_core::aero::{AeroModel, AeroSolution, EdgeState, PanelMotion, check_panel_method_inputs};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::{
    PerfectGas, mach_from_total_pressure_ratio, newtonian_cp_max, rayleigh_pitot_pressure_ratio,
    total_temperature_ratio,
};
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};
use nalgebra::Vector3;

/// Registered name of the scalar form.
pub const SCALAR_NAME: &str = "newtonian-scalar";
/// Registered name of the vector form.
pub const VECTOR_NAME: &str = "newtonian-vector";

/// Settings of `[models.newtonian-scalar]` and `[models.newtonian-vector]`: none yet; unknown
/// keys are rejected.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {}

/// Which relative velocity sets each panel's inclination.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// The vehicle's velocity only (steady inclination).
    Scalar,
    /// Each panel's full velocity relative to the air (rotation and elastic motion).
    Vector,
}

/// Modified Newtonian pressures. Stateless: holds no scratch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Newtonian {
    form: Form,
    settings: Settings,
}

impl Newtonian {
    /// The model in `form` with `settings`.
    pub fn new(form: Form, settings: Settings) -> Self {
        Self { form, settings }
    }

    pub fn form(&self) -> Form {
        self.form
    }

    /// The settings it was built with.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }
}

fn construct_scalar(ctx: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    Ok(Box::new(Newtonian::new(Form::Scalar, settings)))
}

fn construct_vector(ctx: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    Ok(Box::new(Newtonian::new(Form::Vector, settings)))
}

hsv_core::register_model!(ModelDescriptor {
    name: SCALAR_NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "modified Newtonian, Cp = Cp,max sin^2(theta) from the panel inclination to the \
              vehicle velocity (Lees; Anderson)",
    settings_doc: "# no settings",
    constructor: Constructor::Aero(construct_scalar),
});

hsv_core::register_model!(ModelDescriptor {
    name: VECTOR_NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 2,
    summary: "modified Newtonian on each panel's full relative velocity (rotation and elastic \
              motion)",
    settings_doc: "# no settings",
    constructor: Constructor::Aero(construct_vector),
});

/// Stagnation state behind the normal shock of a flow at Mach `m`: T0 and p02.
#[derive(Debug, Clone, Copy)]
struct Stagnation {
    total_temperature_k: f64,
    pitot_pressure_pa: f64,
}

impl Stagnation {
    /// T0 = T∞ (1 + (γ−1)/2 M²) (NACA 1135 eq. 43); p02 = p∞ · pitot(M) (NACA 1135 eq. 100).
    fn at_mach(freestream: &Freestream, mach: f64) -> Result<Self, ModelError> {
        let gamma = freestream.gas.gamma;
        Ok(Self {
            total_temperature_k: freestream.temperature_k * total_temperature_ratio(mach, gamma),
            pitot_pressure_pa: freestream.pressure_pa * rayleigh_pitot_pressure_ratio(mach, gamma)?,
        })
    }

    /// Isentropic expansion to `pressure_pa`: M from p02/p (NACA 1135 eq. 44 inverted),
    /// T = T0/(1 + (γ−1)/2 M²), ρ = p/(R T), |V| = M a. A pressure at or above p02 stagnates.
    fn expand_to(&self, pressure_pa: f64, gas: &PerfectGas) -> Result<EdgeState, ModelError> {
        let ratio = (self.pitot_pressure_pa / pressure_pa).max(1.0);
        let mach = mach_from_total_pressure_ratio(ratio, gas.gamma)?;
        let temperature_k = self.total_temperature_k / total_temperature_ratio(mach, gas.gamma);
        Ok(EdgeState {
            mach,
            pressure_pa,
            temperature_k,
            density_kg_m3: pressure_pa / (gas.gas_constant_j_kg_k * temperature_k),
            velocity_m_s: mach * gas.speed_of_sound(temperature_k),
        })
    }
}

/// The undisturbed flow as an edge state (shadowed panels).
fn freestream_edge(freestream: &Freestream) -> EdgeState {
    EdgeState {
        mach: freestream.mach,
        pressure_pa: freestream.pressure_pa,
        temperature_k: freestream.temperature_k,
        density_kg_m3: freestream.density_kg_m3,
        velocity_m_s: freestream.velocity_m_s,
    }
}

impl AeroModel for Newtonian {
    fn name(&self) -> &str {
        match self.form {
            Form::Scalar => SCALAR_NAME,
            Form::Vector => VECTOR_NAME,
        }
    }

    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        check_panel_method_inputs(self.name(), mesh, flight, motion)?;
        out.reset(mesh.panels.len());
        match self.form {
            Form::Scalar => self.evaluate_scalar(mesh, flight, out),
            Form::Vector => self.evaluate_vector(mesh, flight, motion, out),
        }
    }
}

impl Newtonian {
    /// p = p∞ + q∞ C_p,max (n · V̂_body)² on windward panels.
    fn evaluate_scalar(
        &self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        let freestream = &flight.freestream;
        let direction = flight.velocity_body_m_s() / freestream.velocity_m_s;
        let cp_max = newtonian_cp_max(freestream.mach, freestream.gas.gamma)?;
        let stagnation = Stagnation::at_mach(freestream, freestream.mach)?;
        for (i, panel) in mesh.panels.iter().enumerate() {
            let sin_theta = panel.normal.dot(&direction);
            if !sin_theta.is_finite() {
                return Err(ModelError::non_finite_at_panel(
                    self.name(),
                    "panel inclination",
                    i,
                ));
            }
            if sin_theta <= 0.0 {
                self.shadow(freestream, out, i);
                continue;
            }
            let pressure_pa = freestream.pressure_pa
                + freestream.dynamic_pressure_pa * cp_max * sin_theta.powi(2);
            self.set_windward(&stagnation, pressure_pa, &freestream.gas, out, i)?;
        }
        Ok(())
    }

    /// p = p∞ + ½ ρ∞ |V_p|² C_p,max(|V_p|/a∞) (n · V_p/|V_p|)² on windward panels.
    fn evaluate_vector(
        &self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        let freestream = &flight.freestream;
        // C_p,max and the stagnation state depend on the panel's speed alone: panels moving
        // alike (all of them in steady flight without rotation) reuse the last panel's.
        let mut last: Option<(u64, f64, Stagnation)> = None;
        let panel_velocity = motion.velocity_of_panels(flight, mesh);
        for (i, panel) in mesh.panels.iter().enumerate() {
            let velocity = panel_velocity(i);
            let Some((speed, sin_theta)) = self.inclination(&velocity, &panel.normal, i)? else {
                self.shadow(freestream, out, i);
                continue;
            };
            let (cp_max, stagnation) = match last {
                Some((bits, cp_max, stagnation)) if bits == speed.to_bits() => (cp_max, stagnation),
                _ => {
                    let mach = speed / freestream.speed_of_sound_m_s;
                    let at_speed = (
                        newtonian_cp_max(mach, freestream.gas.gamma)?,
                        Stagnation::at_mach(freestream, mach)?,
                    );
                    last = Some((speed.to_bits(), at_speed.0, at_speed.1));
                    at_speed
                }
            };
            let dynamic_pressure_pa = 0.5 * freestream.density_kg_m3 * speed * speed;
            let pressure_pa =
                freestream.pressure_pa + dynamic_pressure_pa * cp_max * sin_theta.powi(2);
            self.set_windward(&stagnation, pressure_pa, &freestream.gas, out, i)?;
        }
        Ok(())
    }

    /// (|V|, sin θ = n · V/|V|) of a windward panel, `None` if the panel is shadowed or at rest
    /// relative to the air.
    fn inclination(
        &self,
        velocity: &Vector3<f64>,
        normal: &Vector3<f64>,
        panel: usize,
    ) -> Result<Option<(f64, f64)>, ModelError> {
        let speed = velocity.norm();
        if !speed.is_finite() {
            return Err(ModelError::non_finite_at_panel(
                self.name(),
                "panel velocity",
                panel,
            ));
        }
        if speed == 0.0 {
            return Ok(None);
        }
        let sin_theta = normal.dot(velocity) / speed;
        if !sin_theta.is_finite() {
            return Err(ModelError::non_finite_at_panel(
                self.name(),
                "panel inclination",
                panel,
            ));
        }
        Ok((sin_theta > 0.0).then_some((speed, sin_theta)))
    }

    fn shadow(&self, freestream: &Freestream, out: &mut AeroSolution, i: usize) {
        out.diagnostics.shadowed_panels += 1;
        out.pressure_pa[i] = freestream.pressure_pa;
        out.edge[i] = freestream_edge(freestream);
    }

    fn set_windward(
        &self,
        stagnation: &Stagnation,
        pressure_pa: f64,
        gas: &PerfectGas,
        out: &mut AeroSolution,
        i: usize,
    ) -> Result<(), ModelError> {
        if !pressure_pa.is_finite() {
            return Err(ModelError::non_finite_at_panel(self.name(), "pressure", i));
        }
        let edge = stagnation.expand_to(pressure_pa, gas)?;
        let values = [
            ("edge Mach number", edge.mach),
            ("edge temperature", edge.temperature_k),
            ("edge density", edge.density_kg_m3),
            ("edge velocity", edge.velocity_m_s),
        ];
        if let Some((quantity, _)) = values.iter().find(|(_, v)| !v.is_finite()) {
            return Err(ModelError::non_finite_at_panel(self.name(), quantity, i));
        }
        out.pressure_pa[i] = pressure_pa;
        out.edge[i] = edge;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hsv_core::registry::Registry;

    fn context(settings: &toml::Table) -> ModelContext<'_> {
        ModelContext {
            settings,
            key_path: "models.newtonian-vector",
            file: "test.toml",
            region: hsv_core::testing::sample_region("right_surface"),
            registry: hsv_core::testing::empty_registry(),
        }
    }

    #[test]
    fn unknown_settings_keys_are_rejected_with_their_path() {
        let settings: toml::Table = toml::from_str("cp_max = 2.0").unwrap();
        let err = construct_vector(&context(&settings))
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("models.newtonian-vector"), "{err}");
        assert!(err.contains("cp_max"), "{err}");
    }

    #[test]
    fn both_forms_are_registered() {
        let registry = Registry::builtin().unwrap();
        assert_eq!(registry.get(SCALAR_NAME).unwrap().fidelity, 1);
        assert_eq!(registry.get(VECTOR_NAME).unwrap().fidelity, 2);
        let settings = toml::Table::new();
        assert_eq!(
            construct_scalar(&context(&settings)).unwrap().name(),
            SCALAR_NAME
        );
        assert_eq!(
            construct_vector(&context(&settings)).unwrap().name(),
            VECTOR_NAME
        );
    }
}
