//! Reference frames: earth (NED) to body rotations, wind angles and body-to-wind axes.
//!
//! Body axes: x forward, y right, z down. Earth axes: north, east, down (flat earth). Euler
//! angles are the 3-2-1 sequence (yaw ψ, pitch θ, roll φ). Wind (stability) axes: x along the
//! vehicle's velocity relative to the air, z in the body x-z plane pointing down, so lift is
//! along -z_wind and drag along -x_wind. Angles in radians.
//!
//! Reference: Stevens, Lewis & Johnson, *Aircraft Control and Simulation*, 3rd ed. (2016),
//! §1.3 (Euler angles) and §2.3 (wind axes).

use nalgebra::{Matrix3, Rotation3, Vector3};

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
    fn degree_conversions() {
        assert_relative_eq!(deg(std::f64::consts::PI), 180.0);
        assert_relative_eq!(rad(90.0), FRAC_PI_2);
    }
}
