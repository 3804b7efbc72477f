//! The `shock-expansion` model: steady shock-expansion theory along streamwise strips, tangent
//! wedge / Prandtl-Meyer panel by panel elsewhere.

use hsv_core::aero::{
    AeroDiagnostics, AeroModel, AeroSolution, PanelMotion, check_panel_method_inputs,
};
use hsv_core::error::ModelError;
use hsv_core::flow::FlightCondition;
use hsv_core::mesh::PanelMesh;
use nalgebra::Vector3;

use crate::wave::{self, Flow, Local, Regime};

/// Registered name of the steady model.
pub const NAME: &str = "shock-expansion";

/// Steady shock-expansion theory (Anderson, Modern Compressible Flow, 3rd ed., §4.15).
///
/// Each panel's inclination to the flow is θ = asin(n · V̂) (n outward, V̂ the direction of the
/// vehicle's velocity through the air; θ > 0 windward). Along each strip of a structured mesh the
/// first panel turns the freestream by θ_0 and each following panel turns the local flow by
/// Δθ = θ_i - θ_{i-1}: weak oblique shock for Δθ > 0, Prandtl-Meyer expansion for Δθ < 0.
/// Panels in no strip (all panels of an unstructured mesh) turn the freestream by their own θ
/// (tangent wedge / Prandtl-Meyer).
///
/// Beyond the maximum deflection θ_max the shock detaches. The panel then gets a modified
/// Newtonian pressure matched to the attached shock: Cp(θ) = Cp_d + (Cp_max - Cp_d)(sin²θ -
/// sin²θ_max)/(1 - sin²θ_max), with Cp_d the weak-shock value at θ_max and Cp_max from the
/// Rayleigh pitot formula (Anderson, Hypersonic and High-Temperature Gas Dynamics, eq. 3.15;
/// the matching at θ_max is our choice), so the pressure is continuous and monotone in θ and
/// equals the pitot pressure at 90° (`hsv_core::gas::detached_surface`). The edge state keeps
/// T0 and a total pressure blended the same way between the oblique shock's at θ_max and the
/// normal shock's, so M and T are continuous too (M2 of the shock at θ_max, M = 0 and T = T0
/// at 90°). A compression of subsonic local flow by Δθ > 0 uses the same rule in the local
/// flow, p + (p0 - p) sin²Δθ with total pressure kept.
/// Downstream of a subsonic panel the flow keeps its state while Δθ = 0, compresses further
/// while Δθ > 0, and at the first expansion corner accelerates isentropically to sonic and then
/// expands by the turn from M = 1 (the sonic-shoulder assumption of blunt-body flows).
/// Expansions past ν_max give vacuum: p = ρ = 0 (see [`wave::VACUUM_EDGE_MACH`]); downstream
/// panels of that strip stay at vacuum. A panel listed in several strips keeps the last one's state.
///
/// Steady: body rates and elastic velocities are ignored (only the current geometry matters);
/// use `shock-expansion-piston` for the unsteady pressures.
#[derive(Debug, Clone)]
pub struct ShockExpansion {
    /// Name in messages: [`NAME`], or the piston model's when it runs this as its mean flow.
    name: &'static str,
    /// Inclination θ of each panel, rad.
    theta: Vec<f64>,
    /// Local flow over each panel.
    local: Vec<Local>,
    /// Whether a strip has set the panel.
    in_strip: Vec<bool>,
}

impl ShockExpansion {
    /// A model with empty scratch buffers (sized on the first evaluation).
    pub fn new() -> Self {
        Self::named(NAME)
    }

    /// The steady model reporting errors as `name`.
    pub(crate) fn named(name: &'static str) -> Self {
        Self {
            name,
            theta: Vec::new(),
            local: Vec::new(),
            in_strip: Vec::new(),
        }
    }

    /// Local flow of each panel from the last evaluation.
    pub(crate) fn local(&self) -> &[Local] {
        &self.local
    }

    /// Fills the scratch buffers with θ and the local flow of every panel.
    fn solve(&mut self, mesh: &PanelMesh, flight: &FlightCondition) -> Result<(), ModelError> {
        check_panel_method_inputs(self.name, mesh, flight, &PanelMotion::default())?;
        let freestream = freestream_local(flight);
        let gamma = flight.freestream.gas.gamma;
        let direction = flight_direction(self.name, flight)?;
        let n = mesh.panels.len();
        self.theta.clear();
        self.theta.reserve(n);
        for (index, panel) in mesh.panels.iter().enumerate() {
            let theta = inclination(&panel.normal, &direction);
            if !theta.is_finite() {
                return Err(ModelError::non_finite_at_panel(
                    self.name,
                    "panel inclination",
                    index,
                ));
            }
            self.theta.push(theta);
        }
        self.local.clear();
        self.local.resize(n, freestream);
        self.in_strip.clear();
        self.in_strip.resize(n, false);
        for (s, strip) in mesh.strips.iter().enumerate() {
            // A strip's march reads only its θ sequence (and the freestream): a strip that
            // repeats the one before it takes that one's states, as every strip across a flat
            // face of a beam-deformed body does (28 of the sample body's 36 strips).
            if s > 0 && self.repeats(&mesh.strips[s - 1].panels, &strip.panels) {
                for (&from, &to) in mesh.strips[s - 1].panels.iter().zip(&strip.panels) {
                    self.local[to] = self.local[from];
                    self.in_strip[to] = true;
                }
                continue;
            }
            let mut state = freestream;
            let mut previous = 0.0;
            for &index in &strip.panels {
                let Some(&theta) = self.theta.get(index) else {
                    return Err(ModelError::inconsistent(
                        self.name,
                        format!("strip {s} refers to panel {index}, but the mesh has {n} panels"),
                    ));
                };
                state = wave::turn(state, theta - previous, gamma)?;
                self.local[index] = state;
                self.in_strip[index] = true;
                previous = theta;
            }
        }
        for index in 0..n {
            if !self.in_strip[index] {
                self.local[index] = wave::turn(freestream, self.theta[index], gamma)?;
            }
        }
        Ok(())
    }

    /// Whether strip `next` repeats the marched strip `last`: as many panels, none of them
    /// set by a strip yet (a panel of both would be overwritten while it is read), and each
    /// panel's θ within [`SAME_INCLINATION_RAD`] of its counterpart's.
    fn repeats(&self, last: &[usize], next: &[usize]) -> bool {
        let n = self.theta.len();
        last.len() == next.len()
            && next.iter().all(|&i| i < n && !self.in_strip[i])
            && last.iter().zip(next).all(|(&a, &b)| {
                a < n && (self.theta[a] - self.theta[b]).abs() <= SAME_INCLINATION_RAD
            })
    }

    /// Copies pressures, edge states and diagnostics into `out`, rejecting non-finite values.
    fn write(&self, flight: &FlightCondition, out: &mut AeroSolution) -> Result<(), ModelError> {
        let gas = &flight.freestream.gas;
        out.reset(self.local.len());
        let mut diagnostics = AeroDiagnostics::default();
        for (index, (local, &theta)) in self.local.iter().zip(&self.theta).enumerate() {
            let edge = local.flow.edge(gas);
            if !edge.pressure_pa.is_finite() {
                return Err(ModelError::non_finite_at_panel(
                    self.name, "pressure", index,
                ));
            }
            if !(edge.temperature_k.is_finite()
                && edge.density_kg_m3.is_finite()
                && edge.velocity_m_s.is_finite()
                && edge.mach.is_finite())
            {
                return Err(ModelError::non_finite_at_panel(
                    self.name,
                    "edge state",
                    index,
                ));
            }
            out.pressure_pa[index] = edge.pressure_pa;
            out.edge[index] = edge;
            diagnostics.shadowed_panels += usize::from(theta < 0.0);
            diagnostics.detached_shocks += usize::from(local.regime == Regime::Detached);
            diagnostics.vacuum_expansions += usize::from(local.regime == Regime::Vacuum);
        }
        out.diagnostics = diagnostics;
        Ok(())
    }

    /// The steady evaluation shared with `shock-expansion-piston`.
    pub(crate) fn evaluate_steady(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        self.solve(mesh, flight)?;
        self.write(flight, out)
    }
}

impl Default for ShockExpansion {
    fn default() -> Self {
        Self::new()
    }
}

impl AeroModel for ShockExpansion {
    fn name(&self) -> &str {
        self.name
    }

    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        _motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        self.evaluate_steady(mesh, flight, out)
    }
}

/// Largest difference of inclination, rad, at which two panels count as equally inclined:
/// the rounding of θ on flat faces of a deformed mesh (at most 1.2e-15 rad across the sample
/// body's strips) and a pressure change of order 1e-12 relative, nothing a flow resolves.
const SAME_INCLINATION_RAD: f64 = 1e-12;

/// θ = asin(n · V̂), rad: the panel's inclination to the flow, > 0 windward (Newtonian impact
/// angle; Anderson, Hypersonic and High-Temperature Gas Dynamics, §3.2).
pub(crate) fn inclination(normal: &Vector3<f64>, direction: &Vector3<f64>) -> f64 {
    normal.dot(direction).clamp(-1.0, 1.0).asin()
}

/// V̂ = V / |V|, the vehicle's direction of motion through the air in body axes.
fn flight_direction(model: &str, flight: &FlightCondition) -> Result<Vector3<f64>, ModelError> {
    let velocity = flight.velocity_body_m_s();
    let speed = velocity.norm();
    if !(speed.is_finite() && speed > 0.0) {
        return Err(ModelError::out_of_range(
            model,
            "airspeed (m/s)",
            speed,
            "finite and > 0",
        ));
    }
    Ok(velocity / speed)
}

/// The freestream as the strips' starting state (inputs already checked).
fn freestream_local(flight: &FlightCondition) -> Local {
    let f = &flight.freestream;
    Local {
        flow: Flow {
            mach: f.mach,
            pressure_pa: f.pressure_pa,
            temperature_k: f.temperature_k,
            density_kg_m3: f.density_kg_m3,
        },
        regime: Regime::Freestream,
        prandtl_meyer_rad: None,
    }
}
