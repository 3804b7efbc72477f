//! What both engine models share on one two-dimensional section: the conditions, the result,
//! the forebody ramp flow, the captured mass flow (spillage), the control-volume forces of the
//! flow path and the unstarted engine.

use hsv_core::error::ModelError;
use hsv_core::flow::Freestream;
use hsv_core::gas::{
    self, GasError, PerfectGas, detached_surface, mach_from_total_pressure_ratio,
    total_temperature_ratio,
};
use hsv_core::propulsion::EngineStatus;
use nalgebra::{Point2, Vector2};

use crate::flow::{Compression, FlowState, supersonic_area_change_near, turn};
use crate::geometry::{SectionGeometry, slope_rad};
use crate::inlet::Face;

/// Flight and fuel conditions of one section evaluation.
#[derive(Debug, Clone, Copy)]
pub struct SectionConditions<'a> {
    pub freestream: &'a Freestream,
    /// Angle of attack, rad (adds to the ramp turning).
    pub alpha_rad: f64,
    /// Fuel equivalence ratio φ ≥ 0.
    pub fuel_equivalence_ratio: f64,
    /// Moment reference point (x, z) in the body frame, m.
    pub reference_m: Point2<f64>,
}

/// Fuel: hydrogen by default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fuel {
    /// Stoichiometric fuel/air mass ratio f_st.
    pub stoichiometric_fuel_air_ratio: f64,
    /// Lower heating value, J/kg of fuel.
    pub heating_value_j_kg: f64,
    /// Fraction of the heating value released in the combustor.
    pub combustion_efficiency: f64,
}

impl Fuel {
    /// Fuel mass added per unit air mass, f = φ f_st.
    pub fn fuel_air_ratio(&self, phi: f64) -> f64 {
        phi * self.stoichiometric_fuel_air_ratio
    }

    /// Fuel that can burn per unit air mass: min(φ, 1) f_st (oxygen limits fuel-rich mixtures).
    pub fn burned_fuel_air_ratio(&self, phi: f64) -> f64 {
        phi.min(1.0) * self.stoichiometric_fuel_air_ratio
    }

    /// Heat released per unit mass of burned fuel, η h, J/kg.
    pub fn heat_release_j_kg(&self) -> f64 {
        self.combustion_efficiency * self.heating_value_j_kg
    }
}

/// A named engine station: state, flow area per unit span (m²/m) and mass flow per unit span
/// (kg/(s m)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Station {
    pub name: &'static str,
    pub state: FlowState,
    pub area_m2_per_m: f64,
    pub mass_flow_kg_s_per_m: f64,
}

/// Station names, in flow order.
pub const INLET: &str = "inlet";
pub const COMBUSTOR_ENTRY: &str = "combustor-entry";
pub const COMBUSTOR_EXIT: &str = "combustor-exit";
pub const NOZZLE_EXIT: &str = "nozzle-exit";

/// Result of one section; buffers are reused between evaluations.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SectionSolution {
    pub status: EngineStatus,
    /// Force per unit span on the vehicle, body (x, z), N/m.
    pub force_n_per_m: Vector2<f64>,
    /// Pitching moment per unit span about the reference point, N m/m.
    pub pitching_moment_nm_per_m: f64,
    /// Air mass flow captured per unit span, kg/(s m).
    pub air_mass_flow_kg_s_per_m: f64,
    /// Captured over the largest capturable (freestream tube from the nose to the cowl lip).
    pub captured_fraction: f64,
    /// Wave angle of the ramp (bow) shock relative to the freestream, rad; `None` when the
    /// nose expands the flow or the shock detaches.
    pub ramp_shock_wave_angle_rad: Option<f64>,
    /// Fuel added per unit air mass.
    pub fuel_air_ratio: f64,
    /// Inlet, combustor entry, combustor exit and nozzle exit (inlet only when unstarted).
    pub stations: Vec<Station>,
    /// Pressure on each ramp panel (segment), Pa.
    pub ramp_pressure_pa: Vec<f64>,
    /// Pressure on each nozzle panel (segment), Pa.
    pub nozzle_pressure_pa: Vec<f64>,
}

impl SectionSolution {
    /// `other` into this solution, reusing the buffers (a derived `clone_from` would allocate).
    pub fn copy_from(&mut self, other: &Self) {
        let Self {
            status,
            force_n_per_m,
            pitching_moment_nm_per_m,
            air_mass_flow_kg_s_per_m,
            captured_fraction,
            ramp_shock_wave_angle_rad,
            fuel_air_ratio,
            stations,
            ramp_pressure_pa,
            nozzle_pressure_pa,
        } = other;
        self.status = *status;
        self.force_n_per_m = *force_n_per_m;
        self.pitching_moment_nm_per_m = *pitching_moment_nm_per_m;
        self.air_mass_flow_kg_s_per_m = *air_mass_flow_kg_s_per_m;
        self.captured_fraction = *captured_fraction;
        self.ramp_shock_wave_angle_rad = *ramp_shock_wave_angle_rad;
        self.fuel_air_ratio = *fuel_air_ratio;
        self.stations.clone_from(stations);
        self.ramp_pressure_pa.clone_from(ramp_pressure_pa);
        self.nozzle_pressure_pa.clone_from(nozzle_pressure_pa);
    }

    /// Clears the result for `geometry`, keeping buffer capacity.
    pub fn reset(&mut self, geometry: &SectionGeometry) {
        self.status = EngineStatus::Ok;
        self.force_n_per_m = Vector2::zeros();
        self.pitching_moment_nm_per_m = 0.0;
        self.air_mass_flow_kg_s_per_m = 0.0;
        self.captured_fraction = 0.0;
        self.ramp_shock_wave_angle_rad = None;
        self.fuel_air_ratio = 0.0;
        self.stations.clear();
        self.ramp_pressure_pa.clear();
        self.ramp_pressure_pa
            .resize(geometry.ramp_m.len().saturating_sub(1), 0.0);
        self.nozzle_pressure_pa.clear();
        self.nozzle_pressure_pa
            .resize(geometry.nozzle_m.len().saturating_sub(1), 0.0);
    }

    /// The station called `name`.
    pub fn station(&self, name: &str) -> Option<&Station> {
        self.stations.iter().find(|s| s.name == name)
    }

    /// Adds the force and moment of a point force per unit span applied at `at`.
    pub fn add_force(&mut self, force: Vector2<f64>, at: &Point2<f64>, reference: &Point2<f64>) {
        let r = at - reference;
        self.force_n_per_m += force;
        // (r × F)_y with r, F in (x, z): r_z F_x - r_x F_z.
        self.pitching_moment_nm_per_m += r.y * force.x - r.x * force.y;
    }

    /// Adds the gauge-pressure force of every segment of a lower-surface polyline (outward
    /// normal pointing down, out of the body): F = -(p - p∞) l n with n = (dz, -dx)/l.
    pub fn add_surface_pressure(
        &mut self,
        line: &[Point2<f64>],
        pressure_pa: &[f64],
        freestream_pressure_pa: f64,
        reference: &Point2<f64>,
    ) {
        for (w, &p) in line.windows(2).zip(pressure_pa) {
            let d = w[1] - w[0];
            let normal_times_length = Vector2::new(d.y, -d.x);
            let mid = Point2::from((w[0].coords + w[1].coords) * 0.5);
            self.add_force(
                -(p - freestream_pressure_pa) * normal_times_length,
                &mid,
                reference,
            );
        }
    }
}

/// The flow along the ramp: the state on each ramp segment and the bow shock.
#[derive(Debug, Clone, Copy)]
pub struct RampFlow {
    /// State on the last ramp segment (entering the inlet face).
    pub inlet: FlowState,
    pub shock_wave_angle_rad: Option<f64>,
}

/// The ramp turning exceeds the maximum attached-shock deflection (the engine unstarts).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DetachedRampShock;

/// The ramp flow: bow shock (or expansion) from the freestream at the first ramp segment,
/// deflection = segment slope + α, then segment to segment with `compression` for concave
/// turns and Prandtl-Meyer expansions for convex ones. Writes each segment's pressure to
/// `pressure_pa`. `Err(DetachedRampShock)` when the bow shock detaches.
pub fn ramp_flow(
    geometry: &SectionGeometry,
    conditions: &SectionConditions<'_>,
    compression: Compression,
    pressure_pa: &mut [f64],
) -> Result<Result<RampFlow, DetachedRampShock>, ModelError> {
    let f = conditions.freestream;
    let gas = &f.gas;
    let free = FlowState {
        mach: f.mach,
        pressure_pa: f.pressure_pa,
        temperature_k: f.temperature_k,
    };
    let mut slope_before = -conditions.alpha_rad;
    let mut state = free;
    let mut shock = None;
    for (k, w) in geometry.ramp_m.windows(2).enumerate() {
        let slope = slope_rad(&w[0], &w[1]);
        let compression_rad = slope - slope_before;
        // The bow shock is always a shock; later concave turns follow `compression`.
        let how = if k == 0 {
            Compression::Shock
        } else {
            compression
        };
        match turn(&state, compression_rad, gas, how) {
            Ok(t) => {
                if k == 0 && compression_rad > 0.0 {
                    shock = Some(t.wave_angle_rad);
                }
                state = t.state;
            }
            Err(GasError::Detached { .. }) | Err(GasError::Subsonic { .. }) => {
                return Ok(Err(DetachedRampShock));
            }
            Err(e) => return Err(e.into()),
        }
        pressure_pa[k] = state.pressure_pa;
        slope_before = slope;
    }
    Ok(Ok(RampFlow {
        inlet: state,
        shock_wave_angle_rad: shock,
    }))
}

/// Force of the flow path between the inlet face and the engine exit on the vehicle, per unit
/// span, from the momentum balance of the duct's control volume with gauge pressures (the
/// stream-thrust difference of Heiser & Pratt, Hypersonic Airbreathing Propulsion, AIAA 1994,
/// ch. 4): F = S_1 - S_e, with S_1 the inlet face's stream thrust from [`crate::capture`] and
/// S_e = ṁ V ê + (p - p∞) (A / (n̂·ê)) n̂ at the exit, ê the flow direction, A the flow area
/// normal to ê and n̂ the unit normal of the face segment itself (exit top to exit bottom),
/// each applied at its face's centre for the moment (uniform faces).
///
/// Why n̂ and not ê for the pressure: a pressure acts normal to the surface it acts on. The
/// inlet face of the sample is vertical while the ramp flow crosses it 6.2° down, so
/// (p1 - p∞) A1 ê1 put a spurious 338 N/m down force (and 37 N/m too little drag) on the
/// vehicle at Mach 6, 26 km (issue 10 item 8); with n̂ the forebody closes exactly on the
/// freestream momentum at shock-on-lip (tests/cycle.rs). Errors when the exit face lies within
/// 84° of parallel to its flow (a collapsed flow path).
pub fn add_flow_path_force(
    model: &str,
    out: &mut SectionSolution,
    geometry: &SectionGeometry,
    conditions: &SectionConditions<'_>,
    inlet_face_stream_thrust_n_per_m: Vector2<f64>,
    exit: &Station,
) -> Result<(), ModelError> {
    let f = conditions.freestream;
    let reference = conditions.reference_m;
    let (top, bottom) = (geometry.nozzle_start(), geometry.exit_lower());
    let flow = geometry.exit_direction();
    let Some(face) = Face::new(top, bottom, &flow) else {
        return Err(ModelError::inconsistent(
            model,
            format!(
                "the engine exit face of the section at y = {} m lies within 84° of parallel to \
                 its flow; the flow path has collapsed",
                geometry.y_m
            ),
        ));
    };
    let exit_thrust = exit.mass_flow_kg_s_per_m * exit.state.velocity_m_s(&f.gas) * flow
        + (exit.state.pressure_pa - f.pressure_pa) * exit.area_m2_per_m / face.cosine * face.normal;
    let inlet_centre =
        Point2::from((geometry.ramp_end().coords + geometry.cowl_lip().coords) * 0.5);
    let exit_centre = Point2::from((top.coords + bottom.coords) * 0.5);
    out.add_force(inlet_face_stream_thrust_n_per_m, &inlet_centre, &reference);
    out.add_force(-exit_thrust, &exit_centre, &reference);
    Ok(())
}

/// The unstarted engine: no captured flow and no combustion; the ramp keeps its external
/// pressure (panel by panel from the freestream when the bow shock detaches, see
/// [`detached_ramp`], the same rule as the shock-expansion aero model), the nozzle sees the
/// freestream pressure. Only the ramp loads the vehicle. The inlet station is the flow on the
/// last ramp segment.
pub fn unstarted(
    out: &mut SectionSolution,
    geometry: &SectionGeometry,
    conditions: &SectionConditions<'_>,
    ramp_inlet: Option<FlowState>,
) -> Result<(), ModelError> {
    let f = conditions.freestream;
    let inlet = match ramp_inlet {
        Some(state) => state,
        None => {
            out.ramp_shock_wave_angle_rad = None;
            detached_ramp(geometry, conditions, &mut out.ramp_pressure_pa)?
        }
    };
    out.status = EngineStatus::Unstart;
    out.nozzle_pressure_pa
        .iter_mut()
        .for_each(|p| *p = f.pressure_pa);
    out.air_mass_flow_kg_s_per_m = 0.0;
    out.captured_fraction = 0.0;
    out.fuel_air_ratio = 0.0;
    out.stations.clear();
    out.stations.push(Station {
        name: INLET,
        state: inlet,
        area_m2_per_m: 0.0,
        mass_flow_kg_s_per_m: 0.0,
    });
    out.force_n_per_m = Vector2::zeros();
    out.pitching_moment_nm_per_m = 0.0;
    let ramp = std::mem::take(&mut out.ramp_pressure_pa);
    out.add_surface_pressure(
        &geometry.ramp_m,
        &ramp,
        f.pressure_pa,
        &conditions.reference_m,
    );
    out.ramp_pressure_pa = ramp;
    Ok(())
}

/// Ramp pressures when the bow shock detaches: each segment turns the freestream by its own
/// inclination θ = slope + α (tangent wedge): a weak oblique shock up to θ_max, beyond it the
/// modified-Newtonian pressure matched to the weak shock at θ_max and reaching the pitot
/// pressure at 90° (`hsv_core::gas::detached_surface`; Anderson, Hypersonic and
/// High-Temperature Gas Dynamics, eq. 3.15), so the ramp pressure is continuous in the turning
/// angle across detachment; a segment facing away from the flow expands (Prandtl-Meyer), to
/// zero pressure past ν_max. Returns the state on the last segment with gas (M from the blended
/// total pressure, T0 kept).
pub fn detached_ramp(
    geometry: &SectionGeometry,
    conditions: &SectionConditions<'_>,
    pressure_pa: &mut [f64],
) -> Result<FlowState, ModelError> {
    let f = conditions.freestream;
    let gas = &f.gas;
    let free = FlowState {
        mach: f.mach,
        pressure_pa: f.pressure_pa,
        temperature_k: f.temperature_k,
    };
    let mut state = free;
    for (w, p) in geometry.ramp_m.windows(2).zip(pressure_pa.iter_mut()) {
        let theta = slope_rad(&w[0], &w[1]) + conditions.alpha_rad;
        state = match turn(&free, theta, gas, Compression::Shock) {
            Ok(t) => t.state,
            Err(GasError::Detached { .. }) => {
                let surface = detached_surface(f.mach, theta, gas.gamma)?;
                let total = surface.total_pressure_ratio / surface.pressure_ratio;
                let mach = mach_from_total_pressure_ratio(total.max(1.0), gas.gamma)?;
                FlowState {
                    mach,
                    pressure_pa: f.pressure_pa * surface.pressure_ratio,
                    temperature_k: free.total_temperature_k(gas)
                        / total_temperature_ratio(mach, gas.gamma),
                }
            }
            Err(GasError::VacuumExpansion { .. }) => {
                // No gas on the segment; the station keeps the last physical state.
                *p = 0.0;
                continue;
            }
            Err(e) => return Err(e.into()),
        };
        *p = state.pressure_pa;
    }
    Ok(state)
}

/// Checks a finished section for non-finite numbers, naming the first.
pub fn check_finite(model: &str, out: &SectionSolution, y_m: f64) -> Result<(), ModelError> {
    let named = [
        ("thrust per unit span", out.force_n_per_m.x),
        ("normal force per unit span", out.force_n_per_m.y),
        (
            "pitching moment per unit span",
            out.pitching_moment_nm_per_m,
        ),
        ("captured mass flow", out.air_mass_flow_kg_s_per_m),
    ];
    for (quantity, value) in named {
        if !value.is_finite() {
            return Err(ModelError::NonFinite {
                model: model.to_owned(),
                quantity: quantity.to_owned(),
                location: format!(" on the engine section at y = {y_m} m"),
            });
        }
    }
    for s in &out.stations {
        if !s.state.is_physical() {
            return Err(ModelError::NonFinite {
                model: model.to_owned(),
                quantity: format!("the {} state", s.name),
                location: format!(" on the engine section at y = {y_m} m"),
            });
        }
    }
    if out
        .ramp_pressure_pa
        .iter()
        .chain(&out.nozzle_pressure_pa)
        .any(|p| !p.is_finite())
    {
        return Err(ModelError::NonFinite {
            model: model.to_owned(),
            quantity: "surface pressure".to_owned(),
            location: format!(" on the engine section at y = {y_m} m"),
        });
    }
    Ok(())
}

/// Angle δ, rad, by which the exhaust plume's lower boundary (the shear layer leaving the cowl
/// trailing edge) turns down into the external flow: the plume expanding by δ (Prandtl-Meyer)
/// and the external flow under the cowl compressed by δ (weak oblique shock) reach the same
/// pressure (pressure matching across a free boundary; Anderson MCF §4.13, the free-boundary
/// condition, as used for the exhaust plume by Bolender & Doman 2007). Zero when the exhaust
/// is not under-expanded; the largest admissible δ when no match exists before detachment or
/// vacuum. The Illinois variant of regula falsi (Dowell & Jarratt, BIT 11, 1971) on the bracket
/// [0, largest δ], to 1e-10 rad or a pressure match within 1e-13 of the external pressure
/// (bisection to 1e-10 rad took 33 pairs of turns; this takes at most 8 in the plume tests).
pub fn shear_layer_angle_rad(exhaust: &FlowState, external: &FlowState, gas: &PerfectGas) -> f64 {
    if exhaust.pressure_pa <= external.pressure_pa || exhaust.mach < 1.0 || external.mach <= 1.0 {
        return 0.0;
    }
    let g = gas.gamma;
    let limit = |m: f64| match (
        gas::max_deflection(m, g),
        gas::prandtl_meyer(exhaust.mach, g),
    ) {
        (Ok((theta_max, _)), Ok(nu)) => theta_max.min(gas::max_prandtl_meyer(g) - nu),
        _ => 0.0,
    };
    let mut hi = limit(external.mach) * (1.0 - 1e-9);
    let mismatch = |delta: f64| -> Option<f64> {
        let plume = turn(exhaust, -delta, gas, Compression::Shock).ok()?;
        let outer = turn(external, delta, gas, Compression::Shock).ok()?;
        Some(plume.state.pressure_pa - outer.state.pressure_pa)
    };
    let mut f_hi = match mismatch(hi) {
        Some(m) if m < 0.0 => m,
        _ => return hi.max(0.0),
    };
    let (mut lo, mut f_lo) = (0.0, exhaust.pressure_pa - external.pressure_pa);
    let matched = 1e-13 * external.pressure_pa;
    // Which end moved last: the other end's value is halved when the same end moves twice.
    let mut last_low = None;
    while hi - lo > 1e-10 {
        let secant = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        let x = if secant > lo && secant < hi {
            secant
        } else {
            0.5 * (lo + hi)
        };
        match mismatch(x) {
            Some(m) if m.abs() <= matched => return x,
            Some(m) if m > 0.0 => {
                (lo, f_lo) = (x, m);
                if last_low == Some(true) {
                    f_hi *= 0.5;
                }
                last_low = Some(true);
            }
            Some(m) => {
                (hi, f_hi) = (x, m);
                if last_low == Some(false) {
                    f_lo *= 0.5;
                }
                last_low = Some(false);
            }
            // A turn that fails (detachment, vacuum) lies beyond the match: bisect back.
            None => {
                hi = x;
                f_hi = f64::NAN;
                last_low = None;
            }
        }
    }
    0.5 * (lo + hi)
}

/// Aftbody (external nozzle) pressures of both engines: the exhaust leaves the engine exit
/// (height h_e, direction of the cowl's last segment) and expands as a quasi-one-dimensional
/// isentropic stream tube (NACA 1135 eq. 80, supersonic branch) between the aftbody and its
/// lower boundary, a straight shear layer from the cowl trailing edge turned down by the
/// pressure-matching angle δ ([`shear_layer_angle_rad`]); at distance ξ downstream of the exit
/// with the wall risen by r above the exhaust direction, A/A_e = (h_e + r + ξ tan δ)/h_e. The
/// external flow under the cowl is the freestream turned by the cowl (deflection = α plus the
/// cowl slope). Each segment takes the plume pressure at its midpoint, but not below the external
/// pressure under the cowl (a free boundary carries the same pressure on both sides, Anderson
/// MCF §4.13, so a plume that has expanded to the external pressure stops expanding instead of
/// over-expanding behind a straight boundary; capped at p_e for an over-expanded exit); a wall
/// that closes the plume below the sonic area gets the sonic pressure. Our simplifications: a
/// straight boundary at the initial matching angle (the real one curves back as the plume
/// pressure falls, so the far-field area is overstated and the aftbody pressure understated).
/// Trustworthy for the integrated aftbody force of an under-expanded exhaust to the accuracy of
/// a 1-D nozzle analysis; the pressure distribution is not a method-of-characteristics
/// solution.
///
/// Why not a simple wave (the former `scramjet-q1d` aftbody): a Prandtl-Meyer turn at the
/// nozzle corner is the wall pressure only until the expansion from the cowl trailing edge
/// (where the plume meets the lower external pressure) reaches the wall, about one exit height
/// downstream; applied to the whole aftbody it kept the corner pressure over ten exit heights
/// and overstated the nozzle force severalfold. Why not Chavez & Schmidt's law
/// p_e/(1 + (s/L)(p_e/p∞ - 1)) (the former `scramjet-1d` aftbody, [`crate::aftbody_pressure_pa`]):
/// its mean grows only as p∞ ln(p_e/p∞) for a strongly under-expanded exhaust, so more
/// combustor pressure barely reached the aftbody (issue 10, item 8).
pub fn plume_pressures(
    geometry: &SectionGeometry,
    conditions: &SectionConditions<'_>,
    exit: &FlowState,
    exit_height_m: f64,
    pressure_pa: &mut [f64],
) -> Result<(), ModelError> {
    let f = conditions.freestream;
    let gas = &f.gas;
    let free = FlowState {
        mach: f.mach,
        pressure_pa: f.pressure_pa,
        temperature_k: f.temperature_k,
    };
    let n = geometry.cowl_m.len();
    let cowl_deflection =
        slope_rad(&geometry.cowl_m[n - 2], &geometry.cowl_m[n - 1]) + conditions.alpha_rad;
    let external = turn(&free, cowl_deflection, gas, Compression::Shock)
        .map(|t| t.state)
        .unwrap_or(free);
    let delta = shear_layer_angle_rad(exit, &external, gas);
    // The plume does not expand below the undisturbed external pressure: where the straight
    // boundary would over-expand the stream tube, the free boundary turns back instead.
    let boundary_pa = external.pressure_pa;
    let e = geometry.exit_direction();
    // Unit normal from the exhaust direction toward the body (up for a level exit).
    let up = nalgebra::Vector2::new(-e.y, e.x);
    let start = geometry.nozzle_start();
    let spread = delta.tan();
    // The stations march down the aftbody: each one's Mach number starts the next inversion.
    let mut previous_mach = None;
    for (w, p) in geometry.nozzle_m.windows(2).zip(pressure_pa.iter_mut()) {
        let mid = nalgebra::Point2::from((w[0].coords + w[1].coords) * 0.5);
        let r = mid - start;
        let height = exit_height_m + r.dot(&up) + r.dot(&e).max(0.0) * spread;
        let plume =
            match supersonic_area_change_near(exit, exit_height_m, height, gas, previous_mach)? {
                Some(state) => {
                    previous_mach = Some(state.mach);
                    state.pressure_pa
                }
                None => exit.isentropic_to_mach(1.0, gas).pressure_pa,
            };
        *p = plume.max(boundary_pa.min(exit.pressure_pa));
    }
    Ok(())
}
