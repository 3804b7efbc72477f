//! The `shock-expansion-piston` model: shock-expansion mean flow plus local third-order piston
//! theory for each panel's unsteady normal velocity.

use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion, check_panel_method_inputs};
use hsv_core::error::ModelError;
use hsv_core::flow::FlightCondition;
use hsv_core::gas;
use hsv_core::mesh::PanelMesh;

use crate::steady::ShockExpansion;
use crate::wave::{self, Regime};

/// Registered name of the unsteady model.
pub const NAME: &str = "shock-expansion-piston";

/// Shock-expansion mean flow with a local third-order piston-theory correction.
///
/// The mean flow is [`ShockExpansion`] on the current (deformed) geometry. Each panel's
/// unsteady normal velocity is w = (ω × (r - r_c) + v_elastic) · n, positive when the panel
/// moves out of the body into the flow, and its pressure is
/// p = p_SE · P3(w / a_e), P3(x) = 1 + γx + γ(γ+1)/4 x² + γ(γ+1)/12 x³, with a_e the speed of
/// sound of the local (edge) flow: "local piston theory" (Zhang, Ye, Zhang & Liu, "Supersonic
/// flutter analysis based on a local piston theory", AIAA J. 47(10), 2009; the same
/// shock-expansion + piston split as McNamara & Friedmann, AIAA J. 49(6), 2011, and Falkiewicz,
/// Cesnik, Crowell & McNamara, AIAA J. 49(8), 2011). P3 is the third-order expansion of the
/// simple-wave piston pressure (Lighthill 1953; Ashley & Zartarian 1956).
///
/// The edge state follows the simple wave isentropically (ρ ∝ p^(1/γ), T ∝ p/ρ = p^((γ-1)/γ)) with the
/// tangential edge velocity kept. |w|/a_e ≥ 1 is outside piston theory and counted in
/// `piston_theory_violations`; a cubic that falls below zero (w/a_e < about -1.27 for γ = 1.4)
/// is clipped to vacuum. Panels already at vacuum in the mean flow are left at zero pressure.
#[derive(Debug, Clone)]
pub struct ShockExpansionPiston {
    mean: ShockExpansion,
}

impl ShockExpansionPiston {
    /// A model with empty scratch buffers (sized on the first evaluation).
    pub fn new() -> Self {
        Self {
            mean: ShockExpansion::named(NAME),
        }
    }
}

impl Default for ShockExpansionPiston {
    fn default() -> Self {
        Self::new()
    }
}

impl AeroModel for ShockExpansionPiston {
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
        self.mean.evaluate_steady(mesh, flight, out)?;
        let gas = flight.freestream.gas;
        let omega = flight.angular_velocity_rad_s;
        for (index, (panel, local)) in mesh.panels.iter().zip(self.mean.local()).enumerate() {
            if local.regime == Regime::Vacuum {
                continue;
            }
            let edge = out.edge[index];
            let sound_speed = gas.speed_of_sound(edge.temperature_k);
            // The panel's velocity relative to the air minus the vehicle's, ω × (r - r_c) + v_el
            // (`PanelMotion::panel_velocity_m_s` without the mean velocity V it would add and
            // this would take away again, and without V's wind-to-body trigonometry).
            let rigid = omega.cross(&(panel.centroid - flight.rotation_center_m));
            let relative = match motion.elastic_velocity_m_s {
                Some(elastic) => rigid + elastic[index],
                None => rigid,
            };
            let w_over_a = relative.dot(&panel.normal) / sound_speed;
            if !w_over_a.is_finite() {
                return Err(ModelError::non_finite_at_panel(
                    NAME,
                    "normal velocity over sound speed w/a",
                    index,
                ));
            }
            if w_over_a == 0.0 {
                continue;
            }
            if w_over_a.abs() >= 1.0 {
                out.diagnostics.piston_theory_violations += 1;
            }
            let ratio = gas::piston_pressure_ratio_third_order(w_over_a, gas.gamma);
            if ratio > 0.0 {
                let pressure = edge.pressure_pa * ratio;
                let density_ratio = isentropic_density_ratio(ratio, gas.gamma);
                let temperature = edge.temperature_k * (ratio / density_ratio);
                out.pressure_pa[index] = pressure;
                out.edge[index].pressure_pa = pressure;
                out.edge[index].temperature_k = temperature;
                out.edge[index].density_kg_m3 = edge.density_kg_m3 * density_ratio;
                out.edge[index].mach = edge.velocity_m_s / gas.speed_of_sound(temperature);
            } else {
                let vacuum = wave::vacuum(local.flow, gas.gamma).flow;
                out.pressure_pa[index] = 0.0;
                out.edge[index] = vacuum.edge(&gas);
            }
        }
        Ok(())
    }
}

/// ρ2/ρ1 = (p2/p1)^(1/γ), isentropic (NACA 1135 eq. 45 with eq. 44); the temperature ratio is
/// then (p2/p1)/(ρ2/ρ1) = (p2/p1)^((γ-1)/γ) (perfect gas), one `powf` for both.
fn isentropic_density_ratio(pressure_ratio: f64, gamma: f64) -> f64 {
    pressure_ratio.powf(1.0 / gamma)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GAMMA: f64 = 1.4;

    /// T2/T1 = (p2/p1)/(ρ2/ρ1) with ρ2/ρ1 = (p2/p1)^(1/γ) is the isentropic (p2/p1)^((γ-1)/γ)
    /// it replaced (NACA 1135 eqs. 44-45), to 1e-14 relative over the piston-theory range of
    /// P3 (w/a_e from -1 to 1: p2/p1 from 0.07 to 3.9).
    #[test]
    fn one_power_gives_the_isentropic_temperature_ratio() {
        for k in 0..=200 {
            let w = -1.0 + 0.01 * f64::from(k);
            let ratio = gas::piston_pressure_ratio_third_order(w, GAMMA);
            let temperature = ratio / isentropic_density_ratio(ratio, GAMMA);
            let previous = ratio.powf((GAMMA - 1.0) / GAMMA);
            assert!(
                (temperature / previous - 1.0).abs() <= 1e-14,
                "w/a {w}: {temperature} against {previous}"
            );
        }
    }

    /// Along the exact simple wave p/p∞ = (1 + (γ-1)/2 w/a)^(2γ/(γ-1)) the temperature ratio is
    /// (1 + (γ-1)/2 w/a)² (Lighthill 1953: a/a∞ = 1 + (γ-1)/2 w/a), to 1e-14 relative.
    #[test]
    fn simple_wave_temperature_is_lighthills_closed_form() {
        for k in 0..=100 {
            let w = -0.5 + 0.01 * f64::from(k);
            let ratio = gas::piston_pressure_ratio_exact(w, GAMMA).unwrap();
            let temperature = ratio / isentropic_density_ratio(ratio, GAMMA);
            let closed_form = (1.0 + 0.5 * (GAMMA - 1.0) * w).powi(2);
            assert!(
                (temperature / closed_form - 1.0).abs() <= 1e-14,
                "w/a {w}: {temperature} against {closed_form}"
            );
        }
    }
}
