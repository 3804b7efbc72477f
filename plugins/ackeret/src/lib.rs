//! Example hsv dylib plugin: `ackeret`, linearized (Ackeret) supersonic panel pressures.
//!
//! It shows what a third-party model needs: implement [`PluginAero`] and call
//! [`hsv_core::export_aero_plugin!`]; build with `cargo build --release -p hsv-plugin-ackeret`
//! and load with `hsv-run --plugin target/release/libhsv_plugin_ackeret.so models`.
//! The physics: small-disturbance supersonic flow gives C_p = 2θ / √(M² − 1) for a surface
//! inclined by θ into the flow (Ackeret 1925; Anderson, Fundamentals of Aerodynamics, eq. 12.15).

use hsv_core::plugin::{PluginAero, PluginAeroInput, PluginAeroOutput};

/// Linearized supersonic theory; stateless.
pub struct Ackeret;

/// Local inclination θ = asin(n · V̂) of a panel to its relative velocity, rad (θ > 0 windward).
fn inclination(normal: &[f64; 3], velocity: &[f64; 3]) -> f64 {
    let speed = (velocity[0].powi(2) + velocity[1].powi(2) + velocity[2].powi(2)).sqrt();
    let dot = normal[0] * velocity[0] + normal[1] * velocity[1] + normal[2] * velocity[2];
    (dot / speed).clamp(-1.0, 1.0).asin()
}

/// Ackeret pressure coefficient C_p = 2θ / √(M² − 1).
fn ackeret_cp(inclination_rad: f64, mach: f64) -> f64 {
    2.0 * inclination_rad / (mach * mach - 1.0).sqrt()
}

impl PluginAero for Ackeret {
    fn create(settings: &serde_json::Value) -> Result<Self, String> {
        match settings.as_object() {
            Some(map) if map.is_empty() => Ok(Ackeret),
            Some(map) => Err(format!(
                "unknown setting(s) {}; `ackeret` has no settings",
                map.keys()
                    .map(|k| format!("`{k}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            None => Err("settings must be a table".to_owned()),
        }
    }

    fn evaluate(
        &mut self,
        input: &PluginAeroInput<'_>,
        output: &mut PluginAeroOutput<'_>,
    ) -> Result<(), String> {
        let f = &input.freestream;
        if f.mach.is_nan() || f.mach <= 1.0 {
            return Err(format!(
                "Mach number {} is outside the model's range (> 1: linearized supersonic theory)",
                f.mach
            ));
        }
        let q = 0.5 * f.density_kg_m3 * f.velocity_m_s * f.velocity_m_s;
        let gamma = f.gamma;
        let total_temperature = f.temperature_k * (1.0 + 0.5 * (gamma - 1.0) * f.mach * f.mach);
        for (i, ((normal, velocity), pressure)) in input
            .normal
            .iter()
            .zip(input.panel_velocity_m_s)
            .zip(output.pressure_pa.iter_mut())
            .enumerate()
        {
            let cp = ackeret_cp(inclination(normal, velocity), f.mach);
            // Linear theory can predict negative absolute pressure on steep lee faces: vacuum.
            let p = (f.pressure_pa + q * cp).max(0.0);
            *pressure = p;
            // Edge state: isentropic from the freestream to p, total temperature conserved.
            let temperature = f.temperature_k * (p / f.pressure_pa).powf((gamma - 1.0) / gamma);
            let mach_sq = (2.0 / (gamma - 1.0) * (total_temperature / temperature - 1.0)).max(0.0);
            let sound = (gamma * f.gas_constant_j_kg_k * temperature).sqrt();
            output.edge[i] = [
                mach_sq.sqrt(),
                p,
                temperature,
                p / (f.gas_constant_j_kg_k * temperature),
                mach_sq.sqrt() * sound,
            ];
        }
        Ok(())
    }
}

hsv_core::export_aero_plugin!(
    Ackeret,
    name: "ackeret",
    fidelity: 0,
    summary: "Linearized supersonic (Ackeret) panel pressures, Cp = 2 theta / sqrt(M^2 - 1); example dylib plugin",
    settings: "",
);
