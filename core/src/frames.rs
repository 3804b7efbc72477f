//! Reference frames: earth (NED) to body rotations (Euler 3-2-1 and quaternion), attitude
//! kinematics, wind angles, body-to-wind axes and wind-axis forces. Every body/wind/earth
//! transform in the workspace is meant to go through this module.
//!
//! Body axes: x forward, y right, z down. Earth axes: north, east, down (flat earth). Euler
//! angles are the 3-2-1 sequence (yaw ψ, pitch θ, roll φ). Wind (stability) axes: x along the
//! vehicle's velocity relative to the air, z in the body x-z plane pointing down, so lift is
//! along -z_wind and drag along -x_wind. Angles in radians.
//!
//! The attitude quaternion is the body -> earth rotation: `v_earth = q * v_body`, and
//! `v_body = q.inverse() * v_earth` (the earth -> body DCM of [`earth_to_body`] is its inverse).
//!
//! Reference: Stevens, Lewis & Johnson, *Aircraft Control and Simulation*, 3rd ed. (2016),
//! §1.3 (Euler angles), ch. 1 (Euler and quaternion kinematics) and §2.3 (wind axes).

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};

/// Direction cosine matrix earth(NED)->body for 3-2-1 Euler angles (psi, theta, phi).
///
/// C_be = R_x(φ) R_y(θ) R_z(ψ) (passive rotations), so `v_body = C_be * v_earth`.
/// Reference: Stevens, Lewis & Johnson (2016), Eq. (1.3-20).
pub fn earth_to_body(roll_rad: f64, pitch_rad: f64, yaw_rad: f64) -> Rotation3<f64> {
    // nalgebra's from_euler_angles is the active body->earth rotation R_z(ψ) R_y(θ) R_x(φ).
    Rotation3::from_euler_angles(roll_rad, pitch_rad, yaw_rad).inverse()
}

/// Vehicle velocity relative to the air in body axes from airspeed, angle of attack and sideslip:
/// V (cos a cos b, sin b, sin a cos b), m/s.
///
/// Reference: Stevens, Lewis & Johnson (2016), Eq. (2.3-6).
pub fn body_velocity_from_wind(airspeed_m_s: f64, alpha_rad: f64, beta_rad: f64) -> Vector3<f64> {
    let (sa, ca) = alpha_rad.sin_cos();
    let (sb, cb) = beta_rad.sin_cos();
    Vector3::new(ca * cb, sb, sa * cb) * airspeed_m_s
}

/// (airspeed m/s, alpha rad, beta rad) from a body-axis velocity relative to the air:
/// V = |v|, α = atan2(w, u), β = asin(v / V).
///
/// A zero velocity gives (0, 0, 0). Reference: Stevens, Lewis & Johnson (2016), Eq. (2.3-7).
pub fn wind_angles(velocity_body_m_s: &Vector3<f64>) -> (f64, f64, f64) {
    let airspeed = velocity_body_m_s.norm();
    if airspeed == 0.0 || !airspeed.is_finite() {
        return (airspeed, 0.0, 0.0);
    }
    let alpha = velocity_body_m_s.z.atan2(velocity_body_m_s.x);
    let beta = (velocity_body_m_s.y / airspeed).clamp(-1.0, 1.0).asin();
    (airspeed, alpha, beta)
}

/// Body -> wind (stability) axes rotation, to turn body forces into lift/drag/side force:
/// C_wb = R_z(β) R_y(-α), `F_wind = C_wb * F_body`; drag = -F_wind.x, side force = F_wind.y,
/// lift = -F_wind.z.
///
/// Reference: Stevens, Lewis & Johnson (2016), Eq. (2.3-2).
pub fn body_to_wind(alpha_rad: f64, beta_rad: f64) -> Rotation3<f64> {
    let (sa, ca) = alpha_rad.sin_cos();
    let (sb, cb) = beta_rad.sin_cos();
    #[rustfmt::skip]
    let m = Matrix3::new(
        ca * cb,  sb, sa * cb,
        -ca * sb, cb, -sa * sb,
        -sa,      0.0, ca,
    );
    Rotation3::from_matrix_unchecked(m)
}

/// Lift, drag and side force, N: the body-axis force in wind axes, `F_w = C_wb F_b`, with
/// drag = −F_w,x, side = F_w,y, lift = −F_w,z.
///
/// Reference: Stevens, Lewis & Johnson (2016), §2.3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindAxisForces {
    pub lift_n: f64,
    pub drag_n: f64,
    pub side_n: f64,
}

/// Lift, drag and side force of a body-axis force at angle of attack α and sideslip β.
pub fn wind_axis_forces(
    force_body_n: &Vector3<f64>,
    alpha_rad: f64,
    beta_rad: f64,
) -> WindAxisForces {
    let f = body_to_wind(alpha_rad, beta_rad) * force_body_n;
    WindAxisForces {
        lift_n: -f.z,
        drag_n: -f.x,
        side_n: f.y,
    }
}

/// Attitude quaternion (body -> earth) from 3-2-1 Euler angles: q = q_z(ψ) q_y(θ) q_x(φ).
pub fn attitude_from_euler(roll_rad: f64, pitch_rad: f64, yaw_rad: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_euler_angles(roll_rad, pitch_rad, yaw_rad)
}

/// 3-2-1 Euler angles (roll φ, pitch θ, yaw ψ), rad, of a body -> earth attitude quaternion;
/// θ in [−π/2, π/2], φ and ψ in (−π, π].
pub fn euler_from_attitude(attitude: &UnitQuaternion<f64>) -> (f64, f64, f64) {
    attitude.euler_angles()
}

/// Quaternion kinematics q̇ = ½ q ⊗ (0, ω_b) for the body -> earth quaternion and the body-axis
/// angular velocity ω_b = (p, q, r), rad/s.
///
/// Reference: Stevens, Lewis & Johnson (2016), ch. 1 (quaternion kinematic equation).
pub fn attitude_rate(
    attitude: &UnitQuaternion<f64>,
    angular_velocity_body_rad_s: &Vector3<f64>,
) -> Quaternion<f64> {
    attitude.quaternion() * Quaternion::from_imag(*angular_velocity_body_rad_s) * 0.5
}

/// The Euler kinematic equations are singular at θ = ±90°: within this of cos θ = 0 the
/// rates are not returned.
pub const GIMBAL_LOCK_COS_PITCH: f64 = 1e-9;

/// 3-2-1 Euler angle rates (φ̇, θ̇, ψ̇), rad/s, from body rates (p, q, r):
/// φ̇ = p + tan θ (q sin φ + r cos φ), θ̇ = q cos φ − r sin φ, ψ̇ = (q sin φ + r cos φ)/cos θ.
///
/// `None` at gimbal lock (|cos θ| < [`GIMBAL_LOCK_COS_PITCH`]), where the 3-2-1 angles have no
/// rates. Reference: Stevens, Lewis & Johnson (2016), ch. 1 (Euler kinematic equations).
pub fn euler_rates(
    roll_rad: f64,
    pitch_rad: f64,
    angular_velocity_body_rad_s: &Vector3<f64>,
) -> Option<Vector3<f64>> {
    let (sp, cp) = roll_rad.sin_cos();
    let (st, ct) = pitch_rad.sin_cos();
    if ct.abs() < GIMBAL_LOCK_COS_PITCH {
        return None;
    }
    let w = angular_velocity_body_rad_s;
    let yaw_like = w.y * sp + w.z * cp;
    Some(Vector3::new(
        w.x + st / ct * yaw_like,
        w.y * cp - w.z * sp,
        yaw_like / ct,
    ))
}

/// Body rates (p, q, r), rad/s, from 3-2-1 Euler angle rates (the inverse of [`euler_rates`],
/// defined everywhere): p = φ̇ − ψ̇ sin θ, q = θ̇ cos φ + ψ̇ sin φ cos θ,
/// r = −θ̇ sin φ + ψ̇ cos φ cos θ.
///
/// Reference: Stevens, Lewis & Johnson (2016), ch. 1 (Euler kinematic equations).
pub fn body_rates_from_euler_rates(
    roll_rad: f64,
    pitch_rad: f64,
    euler_rates_rad_s: &Vector3<f64>,
) -> Vector3<f64> {
    let (sp, cp) = roll_rad.sin_cos();
    let (st, ct) = pitch_rad.sin_cos();
    let e = euler_rates_rad_s;
    Vector3::new(
        e.x - e.z * st,
        e.y * cp + e.z * sp * ct,
        -e.y * sp + e.z * cp * ct,
    )
}

/// Flight-path angle γ = atan2(−v_D, √(v_N² + v_E²)), rad (positive climbing), of an NED
/// velocity; 0 for a zero velocity.
pub fn flight_path_angle(velocity_ned_m_s: &Vector3<f64>) -> f64 {
    let horizontal = velocity_ned_m_s.x.hypot(velocity_ned_m_s.y);
    if horizontal == 0.0 && velocity_ned_m_s.z == 0.0 {
        return 0.0;
    }
    (-velocity_ned_m_s.z).atan2(horizontal)
}

/// Radians to degrees.
pub fn deg(rad: f64) -> f64 {
    rad.to_degrees()
}

/// Degrees to radians.
pub fn rad(deg: f64) -> f64 {
    deg.to_radians()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::FRAC_PI_2;

    fn assert_orthonormal(r: &Rotation3<f64>) {
        let m = r.matrix();
        assert_relative_eq!(m * m.transpose(), Matrix3::identity(), epsilon = 1e-12);
        assert_relative_eq!(m.determinant(), 1.0, epsilon = 1e-12);
    }

    #[test]
    fn rotations_are_orthonormal() {
        for &(a, b, c) in &[(0.1, -0.4, 2.0), (1.2, 0.3, -3.0), (-2.5, 1.4, 0.7)] {
            assert_orthonormal(&earth_to_body(a, b, c));
            assert_orthonormal(&body_to_wind(a, b.clamp(-1.5, 1.5)));
        }
    }

    #[test]
    fn known_rotations() {
        // Yaw 90 deg: nose points east, so north is to the vehicle's left (-y).
        let c = earth_to_body(0.0, 0.0, FRAC_PI_2);
        assert_relative_eq!(
            c * Vector3::x(),
            Vector3::new(0.0, -1.0, 0.0),
            epsilon = 1e-12
        );
        // Pitch 90 deg nose up: "up" (-z earth) is along the nose (+x body).
        let c = earth_to_body(0.0, FRAC_PI_2, 0.0);
        assert_relative_eq!(
            c * Vector3::new(0.0, 0.0, -1.0),
            Vector3::x(),
            epsilon = 1e-12
        );
        // Roll 90 deg right wing down: "down" (earth z) is along the right wing (+y body).
        let c = earth_to_body(FRAC_PI_2, 0.0, 0.0);
        assert_relative_eq!(c * Vector3::z(), Vector3::y(), epsilon = 1e-12);
        // Gravity in body axes at pitch θ: g (-sin θ, 0, cos θ) (Stevens et al. Eq. 2.5-7).
        let theta = 0.3;
        let g = earth_to_body(0.0, theta, 0.0) * Vector3::new(0.0, 0.0, 9.81);
        assert_relative_eq!(
            g,
            Vector3::new(-9.81 * theta.sin(), 0.0, 9.81 * theta.cos()),
            epsilon = 1e-12
        );
    }

    #[test]
    fn wind_angles_round_trip() {
        for &(v, a, b) in &[(1800.0, 0.05, 0.0), (300.0, -0.2, 0.1), (10.0, 1.0, -0.5)] {
            let vel = body_velocity_from_wind(v, a, b);
            let (v2, a2, b2) = wind_angles(&vel);
            assert_relative_eq!(v2, v, max_relative = 1e-12);
            assert_relative_eq!(a2, a, epsilon = 1e-12);
            assert_relative_eq!(b2, b, epsilon = 1e-12);
        }
        assert_eq!(wind_angles(&Vector3::zeros()), (0.0, 0.0, 0.0));
    }

    #[test]
    fn wind_x_is_along_velocity_and_lift_is_perpendicular() {
        let (a, b) = (0.12, -0.07);
        let c = body_to_wind(a, b);
        let v = body_velocity_from_wind(1.0, a, b);
        assert_relative_eq!(c * v, Vector3::x(), epsilon = 1e-12);
        // Lift direction in body axes: -z_wind expressed in body.
        let lift_dir = c.inverse() * Vector3::new(0.0, 0.0, -1.0);
        assert_relative_eq!(lift_dir.dot(&v), 0.0, epsilon = 1e-12);
        // Lift lies in the body x-z plane and points up (-z) at small alpha.
        assert_relative_eq!(lift_dir.y, 0.0, epsilon = 1e-12);
        assert!(lift_dir.z < 0.0);
    }

    #[test]
    fn attitude_quaternion_is_the_inverse_of_the_earth_to_body_dcm() {
        for &(a, b, c) in &[(0.1, -0.4, 2.0), (1.2, 0.3, -3.0), (-2.5, 1.4, 0.7)] {
            let q = attitude_from_euler(a, b, c);
            assert_relative_eq!(
                q.inverse().to_rotation_matrix().matrix(),
                earth_to_body(a, b, c).matrix(),
                epsilon = 1e-12
            );
            let (a2, b2, c2) = euler_from_attitude(&q);
            assert_relative_eq!(a2, a, epsilon = 1e-12);
            assert_relative_eq!(b2, b, epsilon = 1e-12);
            assert_relative_eq!(c2, c, epsilon = 1e-12);
        }
    }

    /// A constant body rate ω is a rotation about a body-fixed axis, q(t) = q0 ⊗ exp(½ ω t)
    /// exactly; the kinematics must match its central difference (error O(h²) ≈ 1e-10), and the
    /// Euler rates must match the central difference of the Euler angles of q(t).
    #[test]
    fn kinematics_match_central_differences_of_a_constant_rate_rotation() {
        let q0 = attitude_from_euler(0.3, -0.2, 1.1);
        let w = Vector3::new(0.4, -0.7, 0.25);
        let at = |t: f64| q0 * UnitQuaternion::from_scaled_axis(w * t);
        let h = 1e-5;
        let fd = (at(h).quaternion() - at(-h).quaternion()) / (2.0 * h);
        assert_relative_eq!(attitude_rate(&q0, &w), fd, epsilon = 1e-9);
        let e = |t: f64| {
            let (r, p, y) = euler_from_attitude(&at(t));
            Vector3::new(r, p, y)
        };
        let fd_euler = (e(h) - e(-h)) / (2.0 * h);
        let rates = euler_rates(0.3, -0.2, &w).expect("away from gimbal lock");
        assert_relative_eq!(rates, fd_euler, epsilon = 1e-8);
        assert_relative_eq!(
            body_rates_from_euler_rates(0.3, -0.2, &rates),
            w,
            epsilon = 1e-12
        );
        assert!(euler_rates(0.1, FRAC_PI_2, &w).is_none());
    }

    /// At β = 0, written out by hand in the plane of symmetry: L = F_x sin α − F_z cos α,
    /// D = −(F_x cos α + F_z sin α) (Stevens, Lewis & Johnson 2016, §2.3).
    #[test]
    fn wind_axis_forces_in_the_plane_of_symmetry() {
        let (a, f) = (0.2_f64, Vector3::new(-1.0e3, 0.0, -5.0e4));
        let w = wind_axis_forces(&f, a, 0.0);
        assert_relative_eq!(w.lift_n, f.x * a.sin() - f.z * a.cos(), epsilon = 1e-9);
        assert_relative_eq!(w.drag_n, -(f.x * a.cos() + f.z * a.sin()), epsilon = 1e-9);
        assert_relative_eq!(w.side_n, 0.0);
        assert_relative_eq!(
            flight_path_angle(&Vector3::new(3.0, 4.0, -5.0)),
            std::f64::consts::FRAC_PI_4,
            epsilon = 1e-12
        );
    }

    #[test]
    fn degree_conversions() {
        assert_relative_eq!(deg(std::f64::consts::PI), 180.0);
        assert_relative_eq!(rad(90.0), FRAC_PI_2);
    }
}
