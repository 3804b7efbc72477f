//! The `piston-theory` aero model: third-order piston theory from the freestream, panel by panel.
//!
//! Each panel is treated as a piston pushing into the undisturbed gas with the component of its
//! velocity relative to the air along its outward normal, w = V_panel · n (rigid-body motion,
//! rotation and elastic velocity; w > 0 compresses). The pressure is the third-order expansion of
//! the simple-wave relation in w/a∞ (Lighthill 1953, "Oscillating airfoils at high Mach number",
//! J. Aero. Sci. 20(6); Ashley & Zartarian 1956, "Piston theory — a new aerodynamic tool for the
//! aeroelastician", J. Aero. Sci. 23(12)):
//!
//! p / p∞ = 1 + γ (w/a∞) + γ(γ+1)/4 (w/a∞)² + γ(γ+1)/12 (w/a∞)³.
//!
//! Validity: the expansion needs |w|/a∞ < 1 (counted in
//! `AeroDiagnostics::piston_theory_violations` otherwise). The piston analogy itself (each panel
//! sees only its own one-dimensional wave, no memory of the flow upstream) is the hypersonic
//! small-disturbance limit: classically M∞ ≳ 2 with thin surfaces, slopes τ ≪ 1, and M∞ τ up to
//! about 1 for the third-order form (Ashley & Zartarian); at M∞ τ ≫ 1 Newtonian or
//! shock-expansion methods apply instead. The model rejects subsonic freestreams (M∞ ≤ 1) and
//! counts |w|/a∞ ≥ 1; the M∞ ≳ 2 and slope conditions are not checked (they are properties of the
//! configuration, not of one panel). A strong expansion that makes the cubic negative is clipped
//! at zero pressure (counted in `vacuum_expansions`).
//!
//! Edge state: isentropic simple wave from the freestream to the panel pressure, with the
//! freestream total temperature conserved. A vacuum-clipped panel gets the all-zero
//! [`EdgeState::default`] (no gas: zero pressure, density, temperature and velocity).

use hsv_core::aero::{AeroModel, AeroSolution, EdgeState, PanelMotion, check_panel_method_inputs};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::piston_pressure_ratio_third_order;
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};

/// Registered name.
pub const NAME: &str = "piston-theory";

/// Settings of `[models.piston-theory]`: none yet; unknown keys are rejected.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {}

/// Third-order piston theory from the freestream. Stateless: holds no scratch.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PistonTheory {
    settings: Settings,
}

impl PistonTheory {
    /// The model with `settings`.
    pub fn new(settings: Settings) -> Self {
        Self { settings }
    }

    /// The settings it was built with.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }
}

fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    Ok(Box::new(PistonTheory::new(settings)))
}

hsv_core::register_model!(ModelDescriptor {
    name: NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 2,
    summary: "third-order piston theory from the freestream (Lighthill; Ashley & Zartarian); \
              valid for |w|/a < 1 and M >~ 2",
    settings_doc: "# no settings",
    constructor: Constructor::Aero(construct),
});

impl AeroModel for PistonTheory {
    fn name(&self) -> &str {
        NAME
    }

    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        check_panel_method_inputs(NAME, mesh, flight, motion)?;
        let freestream = &flight.freestream;
        let total_temperature_k = freestream.total_temperature_k();
        out.reset(mesh.panels.len());
        let panel_velocity = motion.velocity_of_panels(flight, mesh);
        for (i, panel) in mesh.panels.iter().enumerate() {
            let velocity = panel_velocity(i);
            let w_over_a = velocity.dot(&panel.normal) / freestream.speed_of_sound_m_s;
            if !w_over_a.is_finite() {
                return Err(ModelError::non_finite_at_panel(
                    NAME,
                    "panel normal velocity",
                    i,
                ));
            }
            if w_over_a.abs() >= 1.0 {
                out.diagnostics.piston_theory_violations += 1;
            }
            let ratio = piston_pressure_ratio_third_order(w_over_a, freestream.gas.gamma);
            if ratio > 0.0 {
                out.pressure_pa[i] = freestream.pressure_pa * ratio;
                out.edge[i] = simple_wave_edge(freestream, total_temperature_k, ratio);
            } else {
                out.diagnostics.vacuum_expansions += 1;
                out.pressure_pa[i] = 0.0;
                out.edge[i] = EdgeState::default();
            }
            check_panel(out, i)?;
        }
        Ok(())
    }
}

/// Simple-wave edge state at p = p∞ · ratio: T = T∞ (p/p∞)^((γ-1)/γ), M² = 2/(γ-1) (T0/T - 1)
/// (isentropic, NACA Report 1135 eqs. 43-44), ρ = p/(R T), |V| = M a.
fn simple_wave_edge(freestream: &Freestream, total_temperature_k: f64, ratio: f64) -> EdgeState {
    let gas = &freestream.gas;
    let gamma = gas.gamma;
    let pressure_pa = freestream.pressure_pa * ratio;
    let temperature_k = freestream.temperature_k * ratio.powf((gamma - 1.0) / gamma);
    // A compression past the freestream stagnation pressure (far outside validity) stalls the
    // edge flow rather than giving an imaginary Mach number.
    let mach_squared = (2.0 / (gamma - 1.0) * (total_temperature_k / temperature_k - 1.0)).max(0.0);
    let mach = mach_squared.sqrt();
    EdgeState {
        mach,
        pressure_pa,
        temperature_k,
        density_kg_m3: pressure_pa / (gas.gas_constant_j_kg_k * temperature_k),
        velocity_m_s: mach * gas.speed_of_sound(temperature_k),
    }
}

/// Fails with [`ModelError::NonFinite`] if panel `i`'s pressure or edge state is not finite.
fn check_panel(out: &AeroSolution, i: usize) -> Result<(), ModelError> {
    let edge = &out.edge[i];
    let values = [
        ("pressure", out.pressure_pa[i]),
        ("edge Mach number", edge.mach),
        ("edge temperature", edge.temperature_k),
        ("edge density", edge.density_kg_m3),
        ("edge velocity", edge.velocity_m_s),
    ];
    match values.iter().find(|(_, v)| !v.is_finite()) {
        Some((quantity, _)) => Err(ModelError::non_finite_at_panel(NAME, quantity, i)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn context(settings: &toml::Table) -> ModelContext<'_> {
        ModelContext {
            settings,
            key_path: "models.piston-theory",
            file: "test.toml",
            region: hsv_core::testing::sample_region("right_surface"),
            registry: hsv_core::testing::empty_registry(),
        }
    }

    #[test]
    fn unknown_settings_keys_are_rejected_with_their_path() {
        let settings: toml::Table = toml::from_str("order = 3").unwrap();
        let err = construct(&context(&settings)).err().unwrap().to_string();
        assert!(err.contains("models.piston-theory"), "{err}");
        assert!(err.contains("order"), "{err}");
    }

    #[test]
    fn empty_settings_build_the_model() {
        let settings = toml::Table::new();
        let model = construct(&context(&settings)).unwrap();
        assert_eq!(model.name(), NAME);
    }

    #[test]
    fn registered_in_the_builtin_registry() {
        let registry = hsv_core::registry::Registry::builtin().unwrap();
        let entry = registry.get(NAME).unwrap();
        assert_eq!(entry.fidelity, 2);
    }
}
