//! Both engines as thermodynamic cycles (issue 10, item 8): the conservation laws that Heiser
//! & Pratt's cycle analysis rests on, checked station by station and on the loads, so that the
//! engines' thrust is the stream-thrust difference of the published cycle analysis and nothing
//! else.
//!
//! Sources: Heiser & Pratt, Hypersonic Airbreathing Propulsion (AIAA 1994), ch. 4 (uninstalled
//! thrust as the stream-thrust difference F = S_e - ṁ0 V0 with S = ṁ V + (p - p0) A; the
//! burner energy balance (1 + f) c_p T0,e = c_p T0,0 + η f h_PR; the fully expanded exit
//! velocity V10 = √(2 c_p T0,e (1 - (p0/p0,e)^((γ-1)/γ)))); Shapiro, The Dynamics and
//! Thermodynamics of Compressible Fluid Flow (1953), ch. 8, and Anderson, Modern Compressible
//! Flow (3rd ed.), eq. 3.79 (constant-area flow without friction conserves the impulse
//! p + ρu², with fuel injected normal to the flow); NACA Report 1135, eq. 139 (shock on lip).

use approx::assert_relative_eq;
use hsv_core::config::LoadedConfig;
use hsv_core::flow::Freestream;
use hsv_core::gas::PerfectGas;
use hsv_model_scramjet::{
    COMBUSTOR_ENTRY, COMBUSTOR_EXIT, Checker, INLET, NOZZLE_EXIT, OneDSettings, QuasiOneDSettings,
    SectionConditions, SectionGeometry, SectionSolution, Station,
};
use nalgebra::{Point2, Vector2};

const GAMMA: f64 = 1.4;
/// Heiser & Pratt (1994): H2-air f_st and h_PR; the engines' default η_b.
const F_ST: f64 = 0.0291;
const H_PR_J_KG: f64 = 1.2e8;
const ETA_B: f64 = 0.9;

type Solver = Box<dyn Fn(&SectionGeometry, &SectionConditions<'_>) -> SectionSolution>;

/// The sample section and both engines with their default settings (`friction` overrides the
/// q1d wall friction coefficient).
fn setup(friction: Option<f64>) -> (SectionGeometry, Vec<(&'static str, Solver)>) {
    let loaded = LoadedConfig::sample().expect("embedded config");
    let geometry = loaded.config.geometry;
    let profile = hsv_core::geometry::body_profile(&geometry).expect("profile");
    let section = SectionGeometry::from_profile(&profile, 0.0, 29, 12, 19);
    let check = Checker {
        file: "test",
        key_path: "models.x",
    };
    let (one, _) = OneDSettings::default()
        .engine(&geometry, &check)
        .expect("1-d");
    let mut q_settings = QuasiOneDSettings::default();
    if let Some(c_f) = friction {
        q_settings.wall_friction_coefficient = c_f;
    }
    let (q, _) = q_settings.engine(&geometry, &check).expect("q1d");
    let solvers: Vec<(&'static str, Solver)> = vec![
        (
            "scramjet-1d",
            Box::new(move |g, c| {
                let mut out = SectionSolution::default();
                one.solve(g, c, &mut out).expect("1-d section");
                out
            }),
        ),
        (
            "scramjet-q1d",
            Box::new(move |g, c| {
                let mut out = SectionSolution::default();
                q.solve(g, c, &mut out).expect("q1d section");
                out
            }),
        ),
    ];
    (section, solvers)
}

fn conditions(freestream: &Freestream, phi: f64) -> SectionConditions<'_> {
    conditions_at(freestream, 0.0, phi)
}

fn conditions_at(freestream: &Freestream, alpha_deg: f64, phi: f64) -> SectionConditions<'_> {
    SectionConditions {
        freestream,
        alpha_rad: alpha_deg.to_radians(),
        fuel_equivalence_ratio: phi,
        reference_m: Point2::new(-15.2, 0.0),
    }
}

/// Gauge-pressure force of a lower-surface polyline on the vehicle, by hand: each segment d
/// pushes with -(p - p∞) (d_z, -d_x) (outward normal down, out of the body), N/m.
fn surface_force(line: &[Point2<f64>], pressure_pa: &[f64], p_inf: f64) -> Vector2<f64> {
    line.windows(2)
        .zip(pressure_pa)
        .map(|(w, p)| {
            let d = w[1] - w[0];
            -(p - p_inf) * Vector2::new(d.y, -d.x)
        })
        .sum()
}

/// Heiser & Pratt's stream thrust S = ṁ V + (p - p0) A of a station, N/m.
fn stream_thrust(s: &Station, gas: &PerfectGas, p_inf: f64) -> f64 {
    s.mass_flow_kg_s_per_m * s.state.velocity_m_s(gas)
        + (s.state.pressure_pa - p_inf) * s.area_m2_per_m
}

/// The Mach number at which the sample's bow shock meets the cowl lip at α = 0 (NACA 1135
/// eq. 139 solved for M² with β the lip angle seen from the nose and θ the 6.2° ramp).
fn shock_on_lip_mach(section: &SectionGeometry) -> f64 {
    let to_lip = section.cowl_lip() - section.nose();
    let beta = (to_lip.y / -to_lip.x).atan();
    let theta = 6.2f64.to_radians();
    let cot = 1.0 / beta.tan();
    let m2 = 2.0 * (cot + theta.tan())
        / (2.0 * cot * beta.sin().powi(2) - theta.tan() * (GAMMA + (2.0 * beta).cos()));
    m2.sqrt()
}

/// From shock-on-lip up, nothing spills: the captured stream tube runs in undisturbed
/// freestream up to the lip, so momentum conservation over the forebody (freestream plane,
/// ramp, inlet face) gives ramp force + inlet-face stream thrust = ṁ V∞ (aft), exactly. The
/// engines' force on the vehicle must therefore be Heiser & Pratt's uninstalled thrust, the
/// stream-thrust difference S_e - ṁ V∞ (exit flow aft through the level exit face), plus the
/// aftbody's gauge-pressure force, here summed by hand: in x and z, to 1e-9 of ṁ V∞, for
/// φ = 0 (no fuel) and 0.3, at the on-lip Mach number (10.47) and at 1.1 and 1.3 times it
/// (bow shock inside the cowl), and at 1.3 times it with α = ±2° (the freestream, aft at
/// angle α, u = (-cos α, -sin α) in body x-z: the force is then ṁ V∞ u - S_e x̂ + aftbody). Before issue 10 item 8 the engines took the inlet-face
/// pressure along the flow instead of normal to the face (off by 8 % of the z force at
/// shock-on-lip) and, with the shock inside the cowl, all the captured flow at the
/// shock-layer state (at 1.1 times the on-lip Mach 275 N/m too much thrust).
#[test]
fn engine_force_is_the_stream_thrust_difference_plus_the_aftbody() {
    let (section, solvers) = setup(None);
    for (factor, alpha_deg) in [(1.0, 0.0), (1.1, 0.0), (1.3, 0.0), (1.3, 2.0), (1.3, -2.0)] {
        let mach = factor * shock_on_lip_mach(&section);
        let f = Freestream::standard(mach, 30_000.0, PerfectGas::AIR).expect("atmosphere");
        check_forebody_momentum(&section, &solvers, &f, alpha_deg);
    }
}

/// Asserts the forebody momentum closure at `f` for both engines, φ = 0 and 0.3.
fn check_forebody_momentum(
    section: &SectionGeometry,
    solvers: &[(&str, Solver)],
    f: &Freestream,
    alpha_deg: f64,
) {
    let gas = f.gas;
    let alpha = alpha_deg.to_radians();
    let u = Vector2::new(-alpha.cos(), -alpha.sin());
    for (name, solve) in solvers {
        for phi in [0.0, 0.3] {
            let out = solve(section, &conditions_at(f, alpha_deg, phi));
            assert_relative_eq!(out.captured_fraction, 1.0, epsilon = 1e-9);
            let air = out.air_mass_flow_kg_s_per_m;
            let exit = out.station(NOZZLE_EXIT).expect("started");
            let s_e = stream_thrust(exit, &gas, f.pressure_pa);
            let aftbody = surface_force(&section.nozzle_m, &out.nozzle_pressure_pa, f.pressure_pa);
            let expected = air * f.velocity_m_s * u + Vector2::new(s_e, 0.0) + aftbody;
            eprintln!(
                "{name} M {:.3} alpha {alpha_deg} phi {phi}: F = {:?} N/m, expected {expected:?}",
                f.mach, out.force_n_per_m
            );
            assert!(
                (out.force_n_per_m - expected).norm() < 1e-9 * air * f.velocity_m_s,
                "{name} M {} phi {phi}: force {:?} N/m, stream-thrust difference + aftbody \
                 {expected:?}",
                f.mach,
                out.force_n_per_m
            );
        }
    }
}

/// Energy: the total temperature leaving the nozzle follows Heiser & Pratt's burner energy
/// balance from the freestream total temperature (shocks, the isolator, the internal nozzle
/// and the wave turns are adiabatic): (1 + f) c_p T0,e = c_p T0,∞ + η_b min(φ, 1) f_st h_PR,
/// to 1e-9, at Mach 6, 26 km for φ = 0.13 and 0.3 (started, unchoked); past thermal choking
/// the duct passes less heat, so T0,e falls short of it.
#[test]
fn nozzle_exit_total_temperature_closes_the_burner_energy_balance() {
    let (section, solvers) = setup(None);
    let f = Freestream::standard(6.0, 26_000.0, PerfectGas::AIR).expect("atmosphere");
    let gas = f.gas;
    let t0_inf = f.temperature_k * (1.0 + 0.5 * (GAMMA - 1.0) * f.mach * f.mach);
    let cp = GAMMA * gas.gas_constant_j_kg_k / (GAMMA - 1.0);
    let balance = |phi: f64| {
        (cp * t0_inf + ETA_B * phi.min(1.0) * F_ST * H_PR_J_KG) / (cp * (1.0 + phi * F_ST))
    };
    for (name, solve) in &solvers {
        for phi in [0.13, 0.3] {
            let out = solve(&section, &conditions(&f, phi));
            let exit = out.station(NOZZLE_EXIT).expect("started").state;
            assert_relative_eq!(
                exit.total_temperature_k(&gas),
                balance(phi),
                max_relative = 1e-9
            );
        }
        let out = solve(&section, &conditions(&f, 1.0));
        let exit = out.station(NOZZLE_EXIT).expect("started").state;
        assert!(
            exit.total_temperature_k(&gas) < balance(1.0) * (1.0 - 1e-3),
            "{name}: choked at phi 1 yet T0,e = {}",
            exit.total_temperature_k(&gas)
        );
    }
}

/// Impulse: a constant-area combustor without friction, with fuel injected normal to the flow,
/// conserves S = ṁ V + p A (Anderson MCF eq. 3.79; Shapiro ch. 8), whatever heat it adds: the
/// combustor-exit stream thrust equals the combustor-entry one to 1e-10 (1-d, closed form) and
/// 1e-6 (q1d with c_f = 0, RK4). On the sample (A_e/A_3 = 1, no internal expansion) the whole
/// thrust gained from fuel therefore appears on the aftbody: dF/dφ equals the aftbody's
/// dF/dφ, to 1e-9 of it (1-d). This is why the aftbody model, not the combustor, set the
/// sixfold gap between the engines that issue 10 found.
#[test]
fn constant_area_combustor_conserves_impulse_so_fuel_thrust_is_aftbody_thrust() {
    let (section, solvers) = setup(Some(0.0));
    let f = Freestream::standard(6.0, 26_000.0, PerfectGas::AIR).expect("atmosphere");
    let gas = f.gas;
    for ((name, solve), tolerance) in solvers.iter().zip([1e-10, 1e-6]) {
        for phi in [0.13, 0.3] {
            let out = solve(&section, &conditions(&f, phi));
            let entry = out.station(COMBUSTOR_ENTRY).expect("entry");
            let exit = out.station(COMBUSTOR_EXIT).expect("exit");
            let impulse = |s: &Station| {
                s.mass_flow_kg_s_per_m * s.state.velocity_m_s(&gas)
                    + s.state.pressure_pa * s.area_m2_per_m
            };
            assert_relative_eq!(impulse(exit), impulse(entry), max_relative = tolerance);
            eprintln!(
                "{name} phi {phi}: S entry {} exit {} N/m",
                impulse(entry),
                impulse(exit)
            );
        }
    }
    let (_, one) = &solvers[0];
    let lo = one(&section, &conditions(&f, 0.13));
    let hi = one(&section, &conditions(&f, 0.3));
    let aft = |o: &SectionSolution| {
        surface_force(&section.nozzle_m, &o.nozzle_pressure_pa, f.pressure_pa).x
    };
    let engine = hi.force_n_per_m.x - lo.force_n_per_m.x;
    let aftbody = aft(&hi) - aft(&lo);
    assert!(aftbody > 0.0);
    assert_relative_eq!(engine, aftbody, max_relative = 1e-9);
    // The inlet station is upstream of the fuel: the same for both φ.
    assert_eq!(
        lo.station(INLET).expect("inlet").state,
        hi.station(INLET).expect("inlet").state
    );
}

/// Axial momentum in the duct: the sample's flow path between the inlet face and the engine
/// exit has walls parallel to the exhaust (horizontal) and vertical faces, so without wall
/// friction its walls can push the flow only up or down and the flow path's axial force on
/// the vehicle, engine force minus ramp and aftbody gauge-pressure forces (summed by hand),
/// is zero (momentum conservation; Heiser & Pratt's stream thrust is unchanged between the
/// faces). To 1e-9 (1-d) and 1e-7 (q1d with c_f = 0, RK4) of ṁ V∞, at Mach 6, 26 km for
/// φ = 0, 0.13 and 0.3. Before issue 10 item 8 both engines turned the ramp flow into the duct
/// isentropically and created 1187 N/m (1-d) and 961 N/m (q1d) of axial force here.
#[test]
fn walls_without_axial_area_exert_no_axial_force() {
    let (section, solvers) = setup(Some(0.0));
    let f = Freestream::standard(6.0, 26_000.0, PerfectGas::AIR).expect("atmosphere");
    for ((name, solve), tolerance) in solvers.iter().zip([1e-9, 1e-7]) {
        for phi in [0.0, 0.13, 0.3] {
            let out = solve(&section, &conditions(&f, phi));
            let ramp = surface_force(&section.ramp_m, &out.ramp_pressure_pa, f.pressure_pa);
            let aftbody = surface_force(&section.nozzle_m, &out.nozzle_pressure_pa, f.pressure_pa);
            let duct = out.force_n_per_m - ramp - aftbody;
            let scale = out.air_mass_flow_kg_s_per_m * f.velocity_m_s;
            eprintln!("{name} phi {phi}: flow-path force {duct:?} N/m");
            assert!(
                duct.x.abs() < tolerance * scale,
                "{name} phi {phi}: the flow path pushes {} N/m axially",
                duct.x
            );
        }
    }
}

/// Second law: no aftbody bounded by a free shear layer beats the fully expanded cycle. At
/// shock-on-lip (no additive drag) each engine's thrust stays below Heiser & Pratt's
/// uninstalled thrust with the exhaust expanded isentropically to p∞,
/// F_ideal = ṁ (1 + f) V10 - ṁ V∞, V10 = √(2 c_p T0,e (1 - (p∞/p0,e)^((γ-1)/γ))), from the
/// nozzle-exit T0 and p0; the ratio (the aftbody's share of the available expansion) is
/// printed, not asserted.
#[test]
fn thrust_stays_below_the_fully_expanded_cycle() {
    let (section, solvers) = setup(None);
    let mach = shock_on_lip_mach(&section);
    let f = Freestream::standard(mach, 30_000.0, PerfectGas::AIR).expect("atmosphere");
    let gas = f.gas;
    let cp = GAMMA * gas.gas_constant_j_kg_k / (GAMMA - 1.0);
    for (name, solve) in &solvers {
        for phi in [0.1, 0.3, 0.6] {
            let out = solve(&section, &conditions(&f, phi));
            let exit = out.station(NOZZLE_EXIT).expect("started").state;
            let air = out.air_mass_flow_kg_s_per_m;
            let expansion =
                (f.pressure_pa / exit.total_pressure_pa(&gas)).powf((GAMMA - 1.0) / GAMMA);
            let v10 = (2.0 * cp * exit.total_temperature_k(&gas) * (1.0 - expansion)).sqrt();
            let ideal = air * (1.0 + phi * F_ST) * v10 - air * f.velocity_m_s;
            let thrust = out.force_n_per_m.x;
            eprintln!(
                "{name} M {mach:.2} phi {phi}: F = {thrust:.0} N/m, fully expanded {ideal:.0} N/m, ratio {:.3}",
                thrust / ideal
            );
            assert!(thrust < ideal, "{name} phi {phi}: {thrust} >= {ideal}");
        }
    }
}

/// Stream-thrust averaging keeps mass, stream thrust and total enthalpy, whose two uniform
/// solutions are the two sides of a normal shock (Rankine-Hugoniot). Fed the uniform flow
/// behind a Mach 3 normal shock (NACA 1135 normal-shock table, γ = 1.4: M2 = 0.47519,
/// p2/p1 = 10.333, T2/T1 = 2.6790), it must return the supersonic side: M = 3 and the
/// upstream p and T, to 2e-4 (five-digit table).
#[test]
fn stream_thrust_average_returns_the_supersonic_side_of_a_normal_shock() {
    let gas = PerfectGas::AIR;
    let (p1, t1) = (1.0e4, 300.0);
    let behind = hsv_model_scramjet::FlowState {
        mach: 0.47519,
        pressure_pa: 10.333 * p1,
        temperature_k: 2.6790 * t1,
    };
    let area = 0.7;
    let mass = behind.mass_flux_kg_m2_s(&gas) * area;
    let impulse = mass * behind.velocity_m_s(&gas) + behind.pressure_pa * area;
    let enthalpy = gas.cp() * behind.total_temperature_k(&gas);
    let ahead = hsv_model_scramjet::stream_thrust_average(mass, impulse, area, enthalpy, &gas)
        .expect("supersonic root");
    assert_relative_eq!(ahead.mach, 3.0, max_relative = 2e-4);
    assert_relative_eq!(ahead.pressure_pa, p1, max_relative = 2e-4);
    assert_relative_eq!(ahead.temperature_k, t1, max_relative = 2e-4);
}
