//! Example hsv dylib plugin: `ackeret`, linearized (Ackeret) supersonic panel pressures.
//!
//! It shows what a third-party model needs: implement the role trait ([`AeroModel`]) and a
//! constructor exactly as a built-in model would, and export them with
//! [`hsv_core::export_plugin!`] (plugin ABI 2); build with
//! `cargo build --release -p hsv-plugin-ackeret` and load with
//! `hsv-run --plugin target/release/libhsv_plugin_ackeret.so models`.
//! The physics: small-disturbance supersonic flow gives C_p = 2θ / √(M² − 1) for a surface
//! inclined by θ into the flow (Ackeret 1925; Anderson, Fundamentals of Aerodynamics, eq. 12.15).

use hsv_core::aero::{AeroModel, AeroSolution, EdgeState, PanelMotion, check_panel_method_inputs};
use hsv_core::error::ModelError;
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::PanelMesh;
use hsv_core::registry::ModelContext;

/// Registered name.
pub const NAME: &str = "ackeret";

/// `[models.ackeret]` takes no settings.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {}

/// Linearized supersonic theory; stateless.
pub struct Ackeret;

/// Local inclination θ = asin(n · V̂) of a panel to its relative velocity, rad (θ > 0 windward).
fn inclination(normal: &[f64], velocity: &[f64]) -> f64 {
    let speed = velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
    let dot: f64 = normal.iter().zip(velocity).map(|(n, v)| n * v).sum();
    (dot / speed).clamp(-1.0, 1.0).asin()
}

/// Ackeret pressure coefficient C_p = 2θ / √(M² − 1).
pub fn ackeret_cp(inclination_rad: f64, mach: f64) -> f64 {
    2.0 * inclination_rad / (mach * mach - 1.0).sqrt()
}

impl AeroModel for Ackeret {
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
        let f = &flight.freestream;
        if f.mach <= 1.0 {
            return Err(ModelError::out_of_range(
                NAME,
                "Mach number",
                f.mach,
                "> 1 (linearized supersonic theory)",
            ));
        }
        out.reset(mesh.panels.len());
        let q = 0.5 * f.density_kg_m3 * f.velocity_m_s * f.velocity_m_s;
        let gamma = f.gas.gamma;
        let r = f.gas.gas_constant_j_kg_k;
        let total_temperature = f.temperature_k * (1.0 + 0.5 * (gamma - 1.0) * f.mach * f.mach);
        let panel_velocity = motion.velocity_of_panels(flight, mesh);
        for (i, panel) in mesh.panels.iter().enumerate() {
            let velocity = panel_velocity(i);
            let cp = ackeret_cp(
                inclination(panel.normal.as_slice(), velocity.as_slice()),
                f.mach,
            );
            // Linear theory can predict negative absolute pressure on steep lee faces: vacuum.
            let p = (f.pressure_pa + q * cp).max(0.0);
            out.pressure_pa[i] = p;
            if p == 0.0 {
                // Vacuum: no gas, no boundary layer (the edge state heat-flux models skip).
                out.diagnostics.vacuum_expansions += 1;
                out.edge[i] = EdgeState::default();
                continue;
            }
            // Edge state: isentropic from the freestream to p, total temperature conserved.
            let temperature = f.temperature_k * (p / f.pressure_pa).powf((gamma - 1.0) / gamma);
            let mach_sq = (2.0 / (gamma - 1.0) * (total_temperature / temperature - 1.0)).max(0.0);
            out.edge[i] = EdgeState {
                mach: mach_sq.sqrt(),
                pressure_pa: p,
                temperature_k: temperature,
                density_kg_m3: p / (r * temperature),
                velocity_m_s: mach_sq.sqrt() * (gamma * r * temperature).sqrt(),
            };
        }
        Ok(())
    }
}

/// Builds the model; `[models.ackeret]` must be empty.
pub fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    let Settings {} = ctx.parse_settings()?;
    Ok(Box::new(Ackeret))
}

hsv_core::export_plugin! {
    aero {
        name: NAME,
        fidelity: 0,
        summary: "Linearized supersonic (Ackeret) panel pressures, Cp = 2 theta / sqrt(M^2 - 1); example dylib plugin",
        settings: "",
        constructor: construct,
    }
}
