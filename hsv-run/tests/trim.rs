//! Trim of steady level flight (paper §IV.B, Eq. 2): the search against a model whose trim is
//! known in closed form, a model that cannot be trimmed, and the sample vehicle.

use hsv_core::config::LoadedConfig;
use hsv_run::analysis::trim::{
    Balance, SteadyFlight, TRIMMED_ACCELERATION_M_S2, TRIMMED_PITCH_ACCELERATION_RAD_S2, TrimPoint,
    TrimRequest, TrimStatus, trim, trim_status,
};
use hsv_run::vehicle::assemble;
use hsv_run::vehicle::rigid::{Accelerations, Controls, RigidLoads, RigidVehicle, rigid_needs};

/// Accelerations linear in (α deg, δe deg, φ): a = A x − b, so the trim is x* = A⁻¹ b exactly.
struct Linear {
    a: [[f64; 3]; 3],
    b: [f64; 3],
}

impl SteadyFlight for Linear {
    fn steady_accelerations(
        &mut self,
        _mach: f64,
        _altitude_m: f64,
        c: &Controls,
    ) -> Result<(Accelerations, RigidLoads), hsv_core::ModelError> {
        let x = [
            c.alpha_rad.to_degrees(),
            c.elevon_rad.to_degrees(),
            c.fuel_equivalence_ratio,
        ];
        let row = |i: usize| (0..3).map(|j| self.a[i][j] * x[j]).sum::<f64>() - self.b[i];
        Ok((
            Accelerations {
                u_dot_m_s2: row(0),
                w_dot_m_s2: row(1),
                q_dot_rad_s2: row(2),
            },
            RigidLoads::default(),
        ))
    }

    fn mass_kg(&self) -> f64 {
        1.0
    }

    fn gas(&self) -> hsv_core::gas::PerfectGas {
        hsv_core::gas::PerfectGas::AIR
    }

    fn powered(&self) -> bool {
        true
    }
}

#[test]
fn the_search_finds_the_closed_form_trim_of_a_linear_model() {
    // A coupled, non-symmetric A with a trim at α = 1.5°, δe = −3°, φ = 0.4 by construction.
    let a = [[0.2, 0.05, -9.0], [-3.0, 0.4, 1.0], [0.8, 1.2, 0.3]];
    let x_star = [1.5, -3.0, 0.4];
    let b = [0, 1, 2].map(|i| (0..3).map(|j| a[i][j] * x_star[j]).sum::<f64>());
    let mut model = Linear { a, b };
    let result = trim(&mut model, &TrimRequest::default()).expect("trims");
    let t = &result.trim;
    assert!((t.alpha_deg - 1.5).abs() < 1e-5, "{t:?}");
    assert!((t.elevon_deg + 3.0).abs() < 1e-5, "{t:?}");
    assert!((t.fuel_equivalence_ratio - 0.4).abs() < 1e-6, "{t:?}");
    assert!(result.agreed, "{result:?}");
}

#[test]
fn a_residual_no_control_removes_is_reported_with_where_the_search_stalled() {
    // u̇ = 2 m/s² whatever the controls: no trim exists.
    let mut model = Linear {
        a: [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        b: [-2.0, 0.0, 0.0],
    };
    let err = trim(&mut model, &TrimRequest::default())
        .expect_err("untrimmable")
        .to_string();
    assert!(
        err.contains("stalled at") && err.contains("u_dot 2.000e0"),
        "{err}"
    );
}

#[test]
fn the_sample_vehicle_trims_at_mach_6_26_km_with_a_physical_fuel_ratio() {
    let registry = hsv_run::registry().expect("registry");
    let loaded = LoadedConfig::sample().expect("sample");
    let sets = assemble(&loaded, &registry, &rigid_needs("trim")).expect("assembles");
    let mut vehicle = RigidVehicle::new(sets).expect("rigid vehicle");
    let result = trim(&mut vehicle, &TrimRequest::default()).expect("trims");
    let t = &result.trim;
    assert!(
        t.fuel_equivalence_ratio > 0.0 && t.fuel_equivalence_ratio <= 1.0,
        "{t:?}"
    );
    let a = t.accelerations;
    assert!(a.u_dot_m_s2.abs() <= TRIMMED_ACCELERATION_M_S2, "{a:?}");
    assert!(a.w_dot_m_s2.abs() <= TRIMMED_ACCELERATION_M_S2, "{a:?}");
    assert!(
        a.q_dot_rad_s2.abs() <= TRIMMED_PITCH_ACCELERATION_RAD_S2,
        "{a:?}"
    );
    assert!(result.agreed, "restart disagrees: {result:?}");
    // Level flight: lift balances weight and thrust balances drag, each to the trim residual.
    let m = result.mass_kg;
    let weight = m * hsv_core::atmosphere::gravity(26_000.0);
    let l = &t.loads;
    let lift = -(l.body_aero.force_n.z + l.surface_aero.force_n.z + l.engine.force_n.z);
    assert!((lift * t.alpha_deg.to_radians().cos() - weight).abs() < 0.01 * weight);
}

/// The sample vehicle without its `[regions.propulsion]` table: no engine, a glider.
fn without_propulsion(text: &str) -> String {
    let start = text
        .find("[regions.propulsion]")
        .expect("the sample has the table");
    let end = start + text[start..].find("\n\n").expect("a blank line after it");
    format!("{}{}", &text[..start], &text[end + 2..])
}

/// Issue 25 item 5: a vehicle without its propulsion region, by configuration alone, trims for a
/// steady glide. With no thrust, the aero force alone balances the weight: its magnitude is W
/// and the path descends at tan(−γ) = D/L (Anderson, Introduction to Flight, 8th ed., 2016,
/// §6.9, gliding flight). Bands: the trim's residual accelerations (1e-3 m/s² against g ≈ 9.7
/// m/s²) allow 1e-4 of W and 6e-3 deg in γ; the bounds are 1e-3 of W and 0.01 deg.
#[test]
fn a_vehicle_without_an_engine_trims_for_the_glide_its_lift_to_drag_ratio_sets() {
    let registry = hsv_run::registry().expect("registry");
    let text = without_propulsion(hsv_core::config::SAMPLE_CONFIG_TOML);
    let loaded = hsv_core::config::parse_config(&text, "glide.toml").expect("config");
    let sets = assemble(&loaded, &registry, &rigid_needs("trim")).expect("assembles");
    let mut vehicle = RigidVehicle::new(sets).expect("rigid vehicle");
    assert!(!vehicle.powered());
    let result = trim(&mut vehicle, &TrimRequest::default()).expect("trims");
    let t = &result.trim;
    assert_eq!(t.balance, Balance::Glide);
    assert_eq!(result.status, TrimStatus::Converged, "{:?}", result.notes);
    assert!(result.agreed, "restart disagrees: {result:?}");
    assert_eq!((t.fuel_equivalence_ratio, t.loads.thrust_n), (0.0, 0.0));
    let aero = t.loads.body_aero + t.loads.surface_aero;
    let wind = hsv_core::frames::wind_axis_forces(&aero.force_n, t.alpha_deg.to_radians(), 0.0);
    let weight = result.mass_kg * hsv_core::atmosphere::gravity(26_000.0);
    let resultant = wind.lift_n.hypot(wind.drag_n);
    assert!(
        (resultant - weight).abs() < 1e-3 * weight,
        "{resultant} N vs W {weight} N"
    );
    let glide_deg = -(wind.drag_n / wind.lift_n).atan().to_degrees();
    assert!(
        (t.flight_path_angle_deg - glide_deg).abs() < 0.01,
        "gamma {} deg vs -atan(D/L) {glide_deg} deg",
        t.flight_path_angle_deg
    );
}

mod common;

/// The coarse sample config with structures stiffened a thousandfold (beam EI and GJ, and the
/// lifting surfaces' modulus).
fn stiff_config() -> hsv_core::config::LoadedConfig {
    let ti = "material = { name = \"stiff-titanium\", density_kg_m3 = 4430.0, poisson_ratio = 0.31, \
              melting_point_k = 1877.0, table = [{ temperature_k = 200.0, youngs_modulus_pa = 1.1e14, \
              thermal_expansion_per_k = 8.6e-6, conductivity_w_m_k = 6.7, specific_heat_j_kg_k = 526.0 }, \
              { temperature_k = 1800.0, youngs_modulus_pa = 1.1e14, thermal_expansion_per_k = 8.6e-6, \
              conductivity_w_m_k = 6.7, specific_heat_j_kg_k = 526.0 }] }";
    let text = common::coarse_text().replace("material = \"ti-6al-4v\"", ti);
    common::parse(&common::stiffer_beam(&text, 3))
}

#[test]
fn very_stiff_structures_trim_like_the_rigid_vehicle_in_both_flexible_models() {
    // The coupled body-surface step converges, for structures a thousand times stiffer, to the
    // rigidly attached answer; the monolithic model with the surfaces' mass lumped into the body
    // is then the same vehicle too (paper §IV: partitioned and monolithic agree when rigid).
    let registry = hsv_run::registry().expect("registry");
    let loaded = stiff_config();
    let sets = assemble(&loaded, &registry, &rigid_needs("trim")).expect("rigid");
    let rigid = trim(
        &mut RigidVehicle::new(sets).expect("rigid"),
        &TrimRequest::default(),
    )
    .expect("rigid trim")
    .trim;
    for model in [
        hsv_run::vehicle::partitioned::SurfaceModel::Partitioned,
        hsv_run::vehicle::partitioned::SurfaceModel::Monolithic { lumped_mass: true },
    ] {
        let mut vehicle =
            hsv_run::vehicle::flexible_vehicle(&loaded, &registry, model, "trim").expect("vehicle");
        let t = trim(&mut vehicle, &TrimRequest::default())
            .expect("flexible trim")
            .trim;
        // Stiffness ×1000 leaves elastic deflections of 1e-3 of the sample's, whose effect on
        // the trim is itself below 1 % (compare `hsv-run compare`): 1e-3 relative is the bound.
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 * a.abs().max(b.abs()).max(1e-2);
        assert!(
            close(t.alpha_deg, rigid.alpha_deg),
            "{model:?}: {t:?} vs {rigid:?}"
        );
        assert!(
            close(t.elevon_deg, rigid.elevon_deg),
            "{model:?}: {t:?} vs {rigid:?}"
        );
        assert!(
            close(t.fuel_equivalence_ratio, rigid.fuel_equivalence_ratio),
            "{model:?}: {t:?} vs {rigid:?}"
        );
    }
}

/// A trim point with the given φ and engine status (the rest does not enter the status).
fn point(phi: f64, engine: hsv_core::propulsion::EngineStatus) -> TrimPoint {
    TrimPoint {
        alpha_deg: 1.0,
        elevon_deg: 0.0,
        fuel_equivalence_ratio: phi,
        flight_path_angle_deg: 0.0,
        balance: Balance::Thrust,
        cost: 0.0,
        accelerations: Accelerations::default(),
        loads: RigidLoads {
            engine_status: engine,
            ..RigidLoads::default()
        },
        evaluations: 1,
        modal_amplitudes: Vec::new(),
    }
}

/// Issue 26 item 5: the status of a converged trim, against closed forms of the freestream
/// (US Standard Atmosphere 1976, γ = 1.4): the paper's Mach 6, 26 km (q = 0.7 p M² ≈ 54 kPa,
/// T0 = T (1 + 0.2 M²) ≈ 1820 K) is inside Heiser & Pratt's 500-2000 lbf/ft² corridor and the
/// perfect-gas range; Mach 6 at sea level (q = 0.7 × 101325 Pa × 36 = 2553 kPa) is not; Mach 25
/// at 20 km leaves both (T0 ≈ 216.65 K × 126 = 27300 K); an unstarted or choked engine, or φ at
/// its bound, fails.
#[test]
fn a_trim_outside_the_envelope_or_on_a_failed_engine_says_so() {
    use hsv_core::propulsion::EngineStatus::{Ok, Spillage, ThermalChoking, Unstart};
    let air = |mach: f64, altitude_m: f64| {
        hsv_core::flow::Freestream::standard(mach, altitude_m, hsv_core::gas::PerfectGas::AIR)
            .unwrap()
    };
    let (status, notes) = trim_status(&air(6.0, 26_000.0), &point(0.3, Spillage), true);
    assert_eq!(status, TrimStatus::Converged, "{notes:?}");
    assert!(notes.is_empty());

    let (status, notes) = trim_status(&air(6.0, 0.0), &point(0.3, Ok), true);
    assert_eq!(status, TrimStatus::ConvergedWithWarnings);
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].contains("dynamic pressure 2553.4 kPa"),
        "{notes:?}"
    );

    let (status, notes) = trim_status(&air(25.0, 20_000.0), &point(0.3, Ok), true);
    assert_eq!(status, TrimStatus::ConvergedWithWarnings);
    assert!(notes[0].contains("dynamic pressure"), "{notes:?}");
    assert!(notes[1].contains("stagnation temperature 27"), "{notes:?}");

    let (status, notes) = trim_status(&air(6.0, 26_000.0), &point(0.3, Ok), false);
    assert_eq!(status, TrimStatus::ConvergedWithWarnings);
    assert!(notes[0].contains("local minimum"), "{notes:?}");

    for (phi, engine, needle) in [
        (0.3, Unstart, "unstarted"),
        (0.3, ThermalChoking, "thermally choked"),
        (1.0, Ok, "at the search's bound"),
    ] {
        let (status, notes) = trim_status(&air(6.0, 26_000.0), &point(phi, engine), true);
        assert_eq!(status, TrimStatus::Failed, "{needle}: {notes:?}");
        assert!(notes[0].contains(needle), "{notes:?}");
    }
}
