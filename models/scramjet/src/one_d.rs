//! `scramjet-1d` on one section, after Bolender & Doman (2007): ramp shock, spillage, the
//! momentum-conserving turn into the duct ([`crate::duct_entry`]), isentropic diffuser, constant-area combustor with Rayleigh heat (and fuel mass) addition, isentropic
//! internal nozzle, and the quasi-one-dimensional plume expansion along the external nozzle
//! (shared with `scramjet-q1d`).

use hsv_core::error::ModelError;
use hsv_core::propulsion::EngineStatus;

use crate::flow::{
    Compression, FlowState, burned_total_temperature_k, constant_area_combustor,
    supersonic_area_change,
};
use crate::geometry::SectionGeometry;
use crate::inlet::{capture, duct_entry};
use crate::section::{
    COMBUSTOR_ENTRY, COMBUSTOR_EXIT, Fuel, INLET, NOZZLE_EXIT, SectionConditions, SectionSolution,
    Station, add_flow_path_force, check_finite, plume_pressures, ramp_flow, unstarted,
};

/// Registered name.
pub const NAME: &str = "scramjet-1d";

/// The one-dimensional engine's parameters (resolved settings).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OneDEngine {
    pub fuel: Fuel,
    /// Combustor area over the inlet face height (A2/A1).
    pub diffuser_area_ratio: f64,
    /// Internal nozzle exit area over the combustor area (Ae/A3 ≥ 1).
    pub internal_nozzle_area_ratio: f64,
}

impl OneDEngine {
    /// Solves one section into `out` (buffers reused).
    pub fn solve(
        &self,
        geometry: &SectionGeometry,
        conditions: &SectionConditions<'_>,
        out: &mut SectionSolution,
    ) -> Result<(), ModelError> {
        out.reset(geometry);
        let f = conditions.freestream;
        let gas = &f.gas;
        let p_inf = f.pressure_pa;

        // Ramp: bow shock from the first segment, isentropic turns after it (B&D's single
        // forebody shock on a straight ramp).
        let ramp = match ramp_flow(
            geometry,
            conditions,
            Compression::Isentropic,
            &mut out.ramp_pressure_pa,
        )? {
            Ok(r) => r,
            Err(_) => return unstarted(out, geometry, conditions, None),
        };
        out.ramp_shock_wave_angle_rad = ramp.shock_wave_angle_rad;
        let Some(cap) = capture(geometry, conditions, &ramp.inlet) else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };
        let inlet = cap.state;
        let air = cap.mass_flow_kg_s_per_m;

        // Turn into the duct (axial stream thrust kept), then the diffuser (isolator):
        // isentropic area change to the combustor area A2 = (A2/A1) × inlet face height.
        let Some((turned, duct_area)) = duct_entry(&cap, geometry, conditions) else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };
        let face_height = (geometry.cowl_lip() - geometry.ramp_end()).norm();
        let combustor_area = self.diffuser_area_ratio * face_height;
        let Some(entry) = supersonic_area_change(&turned, duct_area, combustor_area, gas)? else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };

        // Combustor: heat and fuel mass from φ.
        let phi = conditions.fuel_equivalence_ratio;
        let fuel_air = self.fuel.fuel_air_ratio(phi);
        let t0_exit = burned_total_temperature_k(
            entry.total_temperature_k(gas),
            fuel_air,
            self.fuel.burned_fuel_air_ratio(phi),
            self.fuel.heat_release_j_kg(),
            gas,
        );
        let burned = constant_area_combustor(&entry, fuel_air, t0_exit, gas)?;
        let exit_air_fuel = air * (1.0 + fuel_air);

        // Internal nozzle: isentropic expansion to Ae = (Ae/A3) A3.
        let nozzle_area = self.internal_nozzle_area_ratio * combustor_area;
        let Some(nozzle_exit) =
            supersonic_area_change(&burned.state, combustor_area, nozzle_area, gas)?
        else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };

        out.status = if !burned.within_limit {
            EngineStatus::ThermalChoking
        } else if cap.spills() {
            EngineStatus::Spillage
        } else {
            EngineStatus::Ok
        };
        out.air_mass_flow_kg_s_per_m = air;
        out.captured_fraction = cap.fraction();
        out.fuel_air_ratio = fuel_air;
        let station = |name, state: FlowState, area, mass| Station {
            name,
            state,
            area_m2_per_m: area,
            mass_flow_kg_s_per_m: mass,
        };
        out.stations.extend([
            station(INLET, inlet, cap.face_area_m2_per_m, air),
            station(COMBUSTOR_ENTRY, entry, combustor_area, air),
            station(COMBUSTOR_EXIT, burned.state, combustor_area, exit_air_fuel),
            station(NOZZLE_EXIT, nozzle_exit, nozzle_area, exit_air_fuel),
        ]);

        // External nozzle: the plume between the aftbody and its pressure-matched lower
        // boundary, quasi-one-dimensional (`plume_pressures`, shared with `scramjet-q1d`).
        plume_pressures(
            geometry,
            conditions,
            &nozzle_exit,
            nozzle_area,
            &mut out.nozzle_pressure_pa,
        )?;

        let reference = conditions.reference_m;
        let ramp_p = std::mem::take(&mut out.ramp_pressure_pa);
        out.add_surface_pressure(&geometry.ramp_m, &ramp_p, p_inf, &reference);
        out.ramp_pressure_pa = ramp_p;
        let nozzle_p = std::mem::take(&mut out.nozzle_pressure_pa);
        out.add_surface_pressure(&geometry.nozzle_m, &nozzle_p, p_inf, &reference);
        out.nozzle_pressure_pa = nozzle_p;
        let last = out.stations[3];
        add_flow_path_force(
            NAME,
            out,
            geometry,
            conditions,
            cap.face_stream_thrust_n_per_m,
            &last,
        )?;
        check_finite(NAME, out, geometry.y_m)
    }
}

/// Aftbody pressure at arc length s from the engine exit, p(s) = p_e / (1 + (s/L)(p_e/p∞ − 1)),
/// falling from p_e at s = 0 to p∞ at the tail s = L (Chavez & Schmidt, "Analytical
/// aeropropulsive/aeroelastic hypersonic-vehicle model with dynamic analysis", J. Guidance
/// Control Dynamics 17(6), 1994), Pa.
pub fn aftbody_pressure_pa(exit_pa: f64, freestream_pa: f64, length_m: f64, s_m: f64) -> f64 {
    exit_pa / (1.0 + s_m / length_m * (exit_pa / freestream_pa - 1.0))
}

/// Mean of `aftbody_pressure_pa` over s ∈ [s0, s1]:
/// p_e ln((1 + k s1)/(1 + k s0)) / (k (s1 − s0)), k = (p_e/p∞ − 1)/L, Pa.
pub fn aftbody_mean_pressure_pa(
    exit_pa: f64,
    freestream_pa: f64,
    length_m: f64,
    s0_m: f64,
    s1_m: f64,
) -> f64 {
    let k = (exit_pa / freestream_pa - 1.0) / length_m;
    let span = s1_m - s0_m;
    // k → 0 (p_e = p∞) or a zero-length segment is 0/0; there the midpoint value is exact to
    // O((k span)²).
    if (k * span).abs() < 1e-9 {
        return aftbody_pressure_pa(exit_pa, freestream_pa, length_m, 0.5 * (s0_m + s1_m));
    }
    exit_pa * ((k * s1_m).ln_1p() - (k * s0_m).ln_1p()) / (k * span)
}
