//! The spherical and rotating Earth (`[simulation] earth`, issue 21 item 5): a free body in a
//! circular equatorial orbit stays on it, the Earth turning beneath it; level flight over a
//! sphere feels exactly the centrifugal relief V²/r; and the trimmed flexible vehicle over a
//! sphere equals the flat-Earth trim with that relief taken out of gravity.

mod common;

use hsv_core::aero::Loads;
use hsv_core::structure::MassProperties;
use hsv_run::dynamics::rigid_body::{
    WGS84_EQUATORIAL_RADIUS_M, WGS84_GM_M3_S2, WGS84_ROTATION_RAD_S,
};
use hsv_run::dynamics::{EarthModel, GravityModel, RigidBody, RigidBodyState};
use nalgebra::{Matrix3, Point3, Quaternion, UnitQuaternion, Vector3};

fn body(gravity: GravityModel, earth: EarthModel) -> RigidBody {
    let mass = MassProperties {
        mass_kg: 30_000.0,
        center_of_mass_m: Point3::origin(),
        inertia_kg_m2: Matrix3::from_diagonal(&Vector3::new(1.0e5, 2.4e6, 2.4e6)),
    };
    let mut body = RigidBody::new(&mass, gravity).expect("rigid body");
    body.set_earth(earth);
    body
}

/// One classical Runge-Kutta step of the rigid body under `loads`.
fn rk4(body: &RigidBody, state: &RigidBodyState, loads: &Loads, dt: f64) -> RigidBodyState {
    let shifted = |base: &RigidBodyState, k: &hsv_run::dynamics::RigidBodyDerivative, h: f64| {
        let q = base.attitude.quaternion() + k.attitude_rate * h;
        RigidBodyState {
            position_ned_m: base.position_ned_m + k.position_rate_ned_m_s * h,
            attitude: UnitQuaternion::new_unchecked(q),
            velocity_body_m_s: base.velocity_body_m_s + k.acceleration_body_m_s2 * h,
            angular_velocity_body_rad_s: base.angular_velocity_body_rad_s
                + k.angular_acceleration_body_rad_s2 * h,
        }
    };
    let k1 = body.derivative(state, loads);
    let k2 = body.derivative(&shifted(state, &k1, dt / 2.0), loads);
    let k3 = body.derivative(&shifted(state, &k2, dt / 2.0), loads);
    let k4 = body.derivative(&shifted(state, &k3, dt), loads);
    let sum = |f: fn(&hsv_run::dynamics::RigidBodyDerivative) -> Vector3<f64>| {
        (f(&k1) + 2.0 * f(&k2) + 2.0 * f(&k3) + f(&k4)) * (dt / 6.0)
    };
    let q: Quaternion<f64> = state.attitude.quaternion()
        + (k1.attitude_rate + k2.attitude_rate * 2.0 + k3.attitude_rate * 2.0 + k4.attitude_rate)
            * (dt / 6.0);
    RigidBodyState {
        position_ned_m: state.position_ned_m + sum(|k| k.position_rate_ned_m_s),
        attitude: UnitQuaternion::from_quaternion(q),
        velocity_body_m_s: state.velocity_body_m_s + sum(|k| k.acceleration_body_m_s2),
        angular_velocity_body_rad_s: state.angular_velocity_body_rad_s
            + sum(|k| k.angular_acceleration_body_rad_s2),
    }
}

/// A body with no loads flying east along the equator at 26 km with the circular orbital speed
/// √(GM/r) in inertial space (so √(GM/r) − Ω r relative to the rotating Earth), its attitude
/// level: over one orbital period T = 2π √(r³/GM) (Kepler) RK4 at 1 s keeps the altitude to
/// 1e-6 of itself, the latitude at zero and the body level (pitch below 1e-6 rad), and the
/// ground track covers 2π − Ω T of longitude, the Earth having turned by Ω T underneath (to
/// 1e-6 relative).
#[test]
fn a_circular_equatorial_orbit_holds_its_altitude_over_one_revolution() {
    let earth = EarthModel::from_name("spherical-rotating", 0.0).expect("a model");
    let body = body(GravityModel::default(), earth);
    let altitude_m = 26_000.0;
    let r = WGS84_EQUATORIAL_RADIUS_M + altitude_m;
    let inertial_speed = (WGS84_GM_M3_S2 / r).sqrt();
    let ground_speed = inertial_speed - WGS84_ROTATION_RAD_S * r;
    let mut state = RigidBodyState::from_euler(
        Vector3::new(0.0, 0.0, -altitude_m),
        (0.0, 0.0, std::f64::consts::FRAC_PI_2),
        Vector3::new(ground_speed, 0.0, 0.0),
        Vector3::zeros(),
    );
    let rho = earth.transport_rate_ned(&state, &state.velocity_ned_m_s());
    state.angular_velocity_body_rad_s = state.attitude.inverse_transform_vector(&rho);
    let period_s = 2.0 * std::f64::consts::PI * (r.powi(3) / WGS84_GM_M3_S2).sqrt();
    let steps = period_s.round() as usize;
    let dt = period_s / steps as f64;
    let none = Loads::default();
    let mut worst_altitude = 0.0_f64;
    let mut worst_pitch = 0.0_f64;
    for _ in 0..steps {
        state = rk4(&body, &state, &none, dt);
        worst_altitude = worst_altitude.max((state.altitude_m() - altitude_m).abs());
        worst_pitch = worst_pitch.max(state.euler_angles().1.abs());
    }
    assert!(
        worst_altitude <= 1e-6 * altitude_m,
        "altitude strayed by {worst_altitude} m"
    );
    assert!(worst_pitch < 1e-6, "pitch strayed by {worst_pitch} rad");
    assert!(
        state.position_ned_m.x.abs() < 1e-6,
        "north {}",
        state.position_ned_m.x
    );
    let longitude = state.position_ned_m.y / WGS84_EQUATORIAL_RADIUS_M;
    let expected = 2.0 * std::f64::consts::PI - WGS84_ROTATION_RAD_S * period_s;
    assert!(
        (longitude - expected).abs() < 1e-6 * expected,
        "longitude {longitude} rad after one revolution, expected {expected}"
    );
}

/// Level flight over a non-rotating sphere, any loads: the derivative is the flat Earth's with
/// the centrifugal relief V²/r taken out of gravity (g_eff = GM/r² − V²/r), to 1e-12: the
/// body's turn with the horizon (ζ = C_bn ρ) is what supplies it.
#[test]
fn level_flight_over_a_sphere_feels_the_centrifugal_relief() {
    let (altitude_m, speed, alpha) = (26_000.0, 1_794.0, 0.03);
    let r = WGS84_EQUATORIAL_RADIUS_M + altitude_m;
    let g_eff = WGS84_GM_M3_S2 / (r * r) - speed * speed / r;
    let sphere = body(
        GravityModel::default(),
        EarthModel::from_name("spherical", 0.0).expect("a model"),
    );
    let flat = body(GravityModel::Uniform { g_m_s2: g_eff }, EarthModel::Flat);
    let loads = Loads {
        force_n: Vector3::new(4.0e4, 0.0, -2.8e5),
        moment_nm: Vector3::new(0.0, 1.0e4, 0.0),
    };
    let over_sphere = sphere.derivative(&sphere.level_flight(altitude_m, speed, alpha), &loads);
    let over_flat = flat.derivative(&flat.level_flight(altitude_m, speed, alpha), &loads);
    let a = over_sphere.acceleration_body_m_s2;
    let b = over_flat.acceleration_body_m_s2;
    assert!((a - b).norm() < 1e-12 * b.norm(), "{a} against {b}");
    let (p, q) = (
        over_sphere.angular_acceleration_body_rad_s2,
        over_flat.angular_acceleration_body_rad_s2,
    );
    assert!((p - q).norm() < 1e-12 * q.norm(), "{p} against {q}");
}

/// The trimmed flexible vehicle (coarse sample, Mach 6, 26 km) over a non-rotating sphere
/// equals the flat-Earth trim under the uniform gravity GM/r² − V²/r within 1e-4 relative in α,
/// δe and φ, and the relief lowers α and φ from the flat trim under GM/r² (α 1.693° → 1.565°,
/// φ 0.3304 → 0.3223 for a relief of 0.50 m/s²). The difference left (2-4e-5 relative) is
/// physics, not error: level flight over a sphere pitches at −V/r = −2.8e-4 rad/s through
/// still air, and the pitch damping (M_q ≈ −0.038 /s) needs about 2.7e-4° more elevon by the
/// elevon's 0.040 rad/s² per degree, where 2.2e-4° is seen. The 1e-4 band was set after
/// seeing the result.
#[test]
fn the_trim_over_a_sphere_is_the_flat_trim_with_the_relief() {
    use hsv_run::analysis::trim::{TrimRequest, trim};
    use hsv_run::vehicle::partitioned::{CouplingSettings, PartitionedVehicle, partitioned_needs};
    let loaded = common::parse(&common::coarse_text());
    let registry = hsv_run::registry().expect("registry");
    let request = TrimRequest::default();
    let freestream = hsv_core::flow::Freestream::standard(
        request.mach,
        request.altitude_m,
        hsv_core::gas::PerfectGas::AIR,
    )
    .expect("freestream");
    let r = WGS84_EQUATORIAL_RADIUS_M + request.altitude_m;
    let g = WGS84_GM_M3_S2 / (r * r);
    let relief = freestream.velocity_m_s.powi(2) / r;
    let trimmed = |gravity: GravityModel, earth: EarthModel| {
        let sets = hsv_run::vehicle::assemble(&loaded, &registry, &partitioned_needs("test"))
            .expect("assembles");
        let mut vehicle =
            PartitionedVehicle::new(sets, gravity, CouplingSettings::default()).expect("vehicle");
        vehicle.set_earth(earth);
        trim(&mut vehicle, &request).expect("trims").trim
    };
    let sphere = trimmed(
        GravityModel::default(),
        EarthModel::from_name("spherical", 0.0).expect("a model"),
    );
    let relieved = trimmed(
        GravityModel::Uniform { g_m_s2: g - relief },
        EarthModel::Flat,
    );
    let full = trimmed(GravityModel::Uniform { g_m_s2: g }, EarthModel::Flat);
    for (a, b, what) in [
        (sphere.alpha_deg, relieved.alpha_deg, "alpha"),
        (sphere.elevon_deg, relieved.elevon_deg, "elevon"),
        (
            sphere.fuel_equivalence_ratio,
            relieved.fuel_equivalence_ratio,
            "phi",
        ),
    ] {
        assert!(
            (a - b).abs() < 1e-4 * b.abs(),
            "{what}: {a} over the sphere, {b} flat"
        );
    }
    assert!(sphere.alpha_deg < full.alpha_deg);
    assert!(sphere.fuel_equivalence_ratio < full.fuel_equivalence_ratio);
    eprintln!(
        "relief {relief:.4} m/s^2 of g {g:.4}: alpha {:.4} -> {:.4} deg, elevon {:.4} -> {:.4} deg, phi {:.5} -> {:.5}",
        full.alpha_deg,
        sphere.alpha_deg,
        full.elevon_deg,
        sphere.elevon_deg,
        full.fuel_equivalence_ratio,
        sphere.fuel_equivalence_ratio
    );
}
