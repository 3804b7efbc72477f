//! `scramjet-q1d` on one section: a two-dimensional inlet wave system (bow shock and ramp
//! shocks/expansions panel by panel, cowl shock, reflections between the duct walls up to the
//! isolator exit, which decides whether the inlet starts), the momentum-conserving turn into
//! the duct shared with `scramjet-1d` ([`crate::duct_entry`]), a quasi-one-dimensional combustor integrated along its length (area change,
//! wall friction, fuel mass addition and heat release following a mixing-efficiency curve), an
//! isentropic internal nozzle and a quasi-one-dimensional plume expansion along the aftbody,
//! bounded below by a pressure-matched shear layer.

use hsv_core::error::ModelError;
use hsv_core::gas::{GasError, PerfectGas};
use hsv_core::propulsion::EngineStatus;

use crate::flow::{Compression, FlowState, supersonic_area_change, turn};
use crate::geometry::{SectionGeometry, slope_rad};
use crate::inlet::{capture, duct_entry};
use crate::section::{
    COMBUSTOR_ENTRY, COMBUSTOR_EXIT, Fuel, INLET, NOZZLE_EXIT, SectionConditions, SectionSolution,
    Station, add_flow_path_force, check_finite, plume_pressures, ramp_flow, unstarted,
};

/// Registered name.
pub const NAME: &str = "scramjet-q1d";

/// Most wave reflections traced through the isolator before it is taken as mixed out.
const MAX_REFLECTIONS: usize = 64;

/// The quasi-one-dimensional engine's parameters (resolved settings).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuasiOneDEngine {
    pub fuel: Fuel,
    /// Combustor entry area over inlet face height.
    pub diffuser_area_ratio: f64,
    /// Internal nozzle exit area over combustor exit area (≥ 1).
    pub internal_nozzle_area_ratio: f64,
    /// Combustor exit area over entry area.
    pub combustor_area_ratio: f64,
    /// Wall skin-friction coefficient c_f.
    pub wall_friction_coefficient: f64,
    /// θ of the mixing-efficiency curve.
    pub mixing_shape_parameter: f64,
    pub isolator_length_fraction: f64,
    pub combustor_length_fraction: f64,
    pub combustor_steps: usize,
}

/// The combustor problem on one section.
#[derive(Debug, Clone, Copy)]
pub struct Burner<'a> {
    pub gas: &'a PerfectGas,
    pub entry: FlowState,
    /// Entry area per unit span (duct height), m²/m.
    pub entry_area_m2_per_m: f64,
    pub area_ratio: f64,
    pub length_m: f64,
    pub friction_coefficient: f64,
    pub mixing_shape_parameter: f64,
    /// Fuel mass added per unit air mass once fully mixed.
    pub fuel_air_ratio: f64,
    /// Heat released per unit air mass once fully mixed, J/kg.
    pub heat_per_air_j_kg: f64,
    pub steps: usize,
}

/// Mixing efficiency η_m(χ) = θχ/(1 + (θ-1)χ) and dη_m/dχ = θ/(1 + (θ-1)χ)² (the
/// total-temperature distribution of Heiser & Pratt, Hypersonic Airbreathing Propulsion, AIAA
/// 1994, ch. 6: T0(χ)/T0,in = 1 + (τ_b - 1) θχ/(1 + (θ-1)χ)).
pub fn mixing_efficiency(chi: f64, theta: f64) -> (f64, f64) {
    let d = 1.0 + (theta - 1.0) * chi;
    (theta * chi / d, theta / (d * d))
}

impl Burner<'_> {
    /// d(ln M, ln p)/dx at x for heat scaled by `heat_scale`, from the generalized
    /// one-dimensional flow relations (Shapiro 1953, ch. 8, influence coefficients; mass added
    /// without axial momentum, D_h = 2 h):
    /// dM/M = Ψ/(1-M²) [(1+γM²)(dṁ/ṁ + ½ dT0/T0) - dA/A + γM² 2 c_f dx/D_h],
    /// dp/p = dṁ/ṁ - dA/A - dM/M + ½ (dT0/T0 - (γ-1)M²/Ψ dM/M), Ψ = 1 + (γ-1)/2 M².
    /// `None` at or below Mach 1 (the flow chokes).
    fn rates(&self, x: f64, y: [f64; 2], heat_scale: f64) -> Option<[f64; 2]> {
        let g = self.gas.gamma;
        let cp = self.gas.cp();
        let m = y[0].exp();
        let m2 = m * m;
        if !(m2.is_finite() && m2 > 1.0 + 1e-6) {
            return None;
        }
        let l = self.length_m;
        let chi = x / l;
        let (eta, eta_slope) = mixing_efficiency(chi, self.mixing_shape_parameter);
        let eta_rate = eta_slope / l;
        let area_factor = 1.0 + (self.area_ratio - 1.0) * chi;
        let area_rate = (self.area_ratio - 1.0) / (l * area_factor);
        let height = self.entry_area_m2_per_m * area_factor;
        let f = self.fuel_air_ratio;
        let mass_rate = f * eta_rate / (1.0 + f * eta);
        let q = heat_scale * self.heat_per_air_j_kg;
        let energy = cp * self.entry.total_temperature_k(self.gas) + q * eta;
        let t0_rate = q * eta_rate / energy - mass_rate;
        let psi = 1.0 + 0.5 * (g - 1.0) * m2;
        let friction = 2.0 * self.friction_coefficient / (2.0 * height);
        let dlnm = psi / (1.0 - m2)
            * ((1.0 + g * m2) * (mass_rate + 0.5 * t0_rate) - area_rate + g * m2 * friction);
        let k = (g - 1.0) * m2 / psi;
        let dlnp = mass_rate - area_rate - dlnm + 0.5 * (t0_rate - k * dlnm);
        (dlnm.is_finite() && dlnp.is_finite()).then_some([dlnm, dlnp])
    }

    /// Exit state after classical RK4 over `steps` steps with heat scaled by `heat_scale`;
    /// `None` when the flow chokes on the way.
    pub fn integrate(&self, heat_scale: f64) -> Option<FlowState> {
        let n = self.steps.max(1);
        let h = self.length_m / n as f64;
        let mut y = [self.entry.mach.ln(), self.entry.pressure_pa.ln()];
        let add = |y: [f64; 2], k: [f64; 2], s: f64| [y[0] + s * k[0], y[1] + s * k[1]];
        for i in 0..n {
            let x = i as f64 * h;
            let k1 = self.rates(x, y, heat_scale)?;
            let k2 = self.rates(x + 0.5 * h, add(y, k1, 0.5 * h), heat_scale)?;
            let k3 = self.rates(x + 0.5 * h, add(y, k2, 0.5 * h), heat_scale)?;
            let k4 = self.rates(x + h, add(y, k3, h), heat_scale)?;
            for j in 0..2 {
                y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
        }
        let mach = y[0].exp();
        if !(mach.is_finite() && mach > 1.0) {
            return None;
        }
        let f = self.fuel_air_ratio;
        let cp = self.gas.cp();
        let t0 = (cp * self.entry.total_temperature_k(self.gas)
            + heat_scale * self.heat_per_air_j_kg)
            / (cp * (1.0 + f));
        Some(FlowState {
            mach,
            pressure_pa: y[1].exp(),
            temperature_k: t0 / (1.0 + 0.5 * (self.gas.gamma - 1.0) * mach * mach),
        })
    }

    /// The exit with all the heat, or (thermal choking) with the largest fraction of it the
    /// duct can take (bisection on the heat fraction to 1e-6); `None` when even no heat chokes
    /// it.
    pub fn solve(&self) -> Option<(FlowState, bool)> {
        if let Some(exit) = self.integrate(1.0) {
            return Some((exit, true));
        }
        let mut lo = 0.0;
        let mut hi = 1.0;
        let mut best = self.integrate(0.0)?;
        while hi - lo > 1e-6 {
            let mid = 0.5 * (lo + hi);
            match self.integrate(mid) {
                Some(exit) => {
                    lo = mid;
                    best = exit;
                }
                None => hi = mid,
            }
        }
        Some((best, false))
    }
}

impl QuasiOneDEngine {
    /// Whether the inlet starts: the wave system from the cowl lip to the isolator exit stays
    /// attached and supersonic. At each wall the flow is turned parallel to that wall (cowl
    /// shock at the lip, then reflections), by an oblique shock for compression or a
    /// Prandtl-Meyer fan for expansion; each wave crosses the duct of height h in
    /// Δs = h / tan(β - δ) (β wave angle to the upstream flow, δ the turn). The duct's upper
    /// wall is taken parallel to the cowl at the same station (the unmeshed flow-path top of a
    /// rigid engine cross-section). False: a wave detaches or chokes the flow (unstart).
    ///
    /// The waves' uniform end state is not the isolator's state: it leaves part of the duct
    /// to an unmodelled shoulder expansion, and filling the duct from it isentropically made
    /// 961 N/m of axial force from walls with no axial area (Mach 6, 26 km, c_f = 0; issue 10
    /// item 8). The isolator state is the conservative stream-thrust average
    /// ([`crate::duct_entry`]).
    fn inlet_starts(
        &self,
        geometry: &SectionGeometry,
        inlet: &FlowState,
        gas: &PerfectGas,
    ) -> Result<bool, ModelError> {
        let cowl = &geometry.cowl_m;
        let lip = geometry.cowl_lip();
        let e = nalgebra::Vector2::from(cowl[1] - cowl[0]).normalize();
        let r = geometry.ramp_end() - lip;
        let height = (r.x * e.y - r.y * e.x).abs();
        let isolator = self.isolator_length_fraction * geometry.engine_length_m();
        let wall_slope_at = |s: f64| {
            let mut run = 0.0;
            for w in cowl.windows(2) {
                let l = (w[1] - w[0]).norm();
                if s < run + l {
                    return slope_rad(&w[0], &w[1]);
                }
                run += l;
            }
            let n = cowl.len();
            slope_rad(&cowl[n - 2], &cowl[n - 1])
        };
        let mut state = *inlet;
        let n = geometry.ramp_m.len();
        let mut flow_slope = slope_rad(&geometry.ramp_m[n - 2], &geometry.ramp_m[n - 1]);
        let mut s = 0.0;
        let mut on_cowl = true;
        for _ in 0..MAX_REFLECTIONS {
            let wall = wall_slope_at(s);
            // Below the flow (cowl) a wall turning up compresses; above it (flow-path top) a
            // wall turning down does.
            let compression = if on_cowl {
                flow_slope - wall
            } else {
                wall - flow_slope
            };
            let turned = match turn(&state, compression, gas, Compression::Shock) {
                Ok(t) => t,
                Err(GasError::Detached { .. }) | Err(GasError::Subsonic { .. }) => {
                    return Ok(false);
                }
                Err(e) => return Err(e.into()),
            };
            let crossing = turned.wave_angle_rad - compression;
            if crossing.is_nan() || crossing <= 0.0 {
                return Ok(false);
            }
            state = turned.state;
            flow_slope = wall;
            s += height / crossing.tan();
            if s >= isolator {
                break;
            }
            on_cowl = !on_cowl;
        }
        Ok(true)
    }

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

        let ramp = match ramp_flow(
            geometry,
            conditions,
            Compression::Shock,
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

        if !self.inlet_starts(geometry, &inlet, gas)? {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        }
        // The isolator: the captured flow turned into the duct with its axial stream thrust
        // kept, then an isentropic area change to the combustor entry area.
        let Some((turned, duct_area)) = duct_entry(&cap, geometry, conditions) else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };
        let face_height = (geometry.cowl_lip() - geometry.ramp_end()).norm();
        let entry_area = self.diffuser_area_ratio * face_height;
        let Some(entry) = supersonic_area_change(&turned, duct_area, entry_area, gas)? else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };

        let phi = conditions.fuel_equivalence_ratio;
        let fuel_air = self.fuel.fuel_air_ratio(phi);
        let length = geometry.engine_length_m();
        let burner = Burner {
            gas,
            entry,
            entry_area_m2_per_m: entry_area,
            area_ratio: self.combustor_area_ratio,
            length_m: self.combustor_length_fraction * length,
            friction_coefficient: self.wall_friction_coefficient,
            mixing_shape_parameter: self.mixing_shape_parameter,
            fuel_air_ratio: fuel_air,
            heat_per_air_j_kg: self.fuel.burned_fuel_air_ratio(phi) * self.fuel.heat_release_j_kg(),
            steps: self.combustor_steps,
        };
        let Some((burned, within_limit)) = burner.solve() else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };
        let exit_area = entry_area * self.combustor_area_ratio;
        let nozzle_area = exit_area * self.internal_nozzle_area_ratio;
        let Some(nozzle_exit) = supersonic_area_change(&burned, exit_area, nozzle_area, gas)?
        else {
            return unstarted(out, geometry, conditions, Some(ramp.inlet));
        };
        let exit_mass = air * (1.0 + fuel_air);

        out.status = if !within_limit {
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
            station(COMBUSTOR_ENTRY, entry, entry_area, air),
            station(COMBUSTOR_EXIT, burned, exit_area, exit_mass),
            station(NOZZLE_EXIT, nozzle_exit, nozzle_area, exit_mass),
        ]);

        // External nozzle: the plume between the aftbody and its pressure-matched lower
        // boundary, quasi-one-dimensional (see `plume_pressures`).
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
