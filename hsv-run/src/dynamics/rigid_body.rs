//! Rigid-body motion of the vehicle's body frame (paper Eq. 1, β and ζ rows): Newton-Euler
//! equations about the centre of mass in body axes, flat-earth NED position, quaternion
//! attitude, and gravity varying with altitude.
//!
//! **Reference point.** The body frame's origin is the vehicle's centre of mass (with the
//! lifting surfaces' rigid mass lumped in): for the free-free body's mean axes the origin is
//! the instantaneous centre of mass and the rigid and elastic equations decouple (Waszak &
//! Schmidt, "Flight dynamics of aeroelastic vehicles", J. Aircraft 25(6), 1988). Loads are
//! body-axis forces and moments about the centre of mass; [`moment_about`] moves a moment from
//! another point (the nose, a pivot).
//!
//! **Attitude: a quaternion.** The body → earth rotation is carried as a unit quaternion, not
//! 3-2-1 Euler angles, because the Euler kinematics are singular at θ = ±90° (a tumbling test
//! body, a pull-up through the vertical) and the quaternion is not; Euler angles are computed
//! from it for output ([`RigidBodyState::euler_angles`]), and the linearization layout can
//! carry Euler angles instead (`vehicle::AttitudeCoordinates::Euler321`), where a minimal,
//! unconstrained set is what a linear model needs.

use hsv_core::aero::Loads;
use hsv_core::atmosphere;
use hsv_core::frames;
use hsv_core::structure::MassProperties;
use nalgebra::{Matrix3, Point3, Quaternion, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use super::DynamicsError;

/// The rigid-body state of the body frame: plain data (serializable, cloneable for rollback and
/// linearization).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigidBodyState {
    /// Centre-of-mass position in the flat-earth NED frame, m (altitude = −down).
    pub position_ned_m: Vector3<f64>,
    /// Body → earth rotation: `v_ned = attitude * v_body`.
    pub attitude: UnitQuaternion<f64>,
    /// β: centre-of-mass velocity relative to the earth, body axes (u, v, w), m/s.
    pub velocity_body_m_s: Vector3<f64>,
    /// ζ: angular velocity relative to the earth, body axes (p, q, r), rad/s.
    pub angular_velocity_body_rad_s: Vector3<f64>,
}

impl Default for RigidBodyState {
    fn default() -> Self {
        Self {
            position_ned_m: Vector3::zeros(),
            attitude: UnitQuaternion::identity(),
            velocity_body_m_s: Vector3::zeros(),
            angular_velocity_body_rad_s: Vector3::zeros(),
        }
    }
}

impl RigidBodyState {
    /// A state from 3-2-1 Euler angles (roll φ, pitch θ, yaw ψ), rad.
    pub fn from_euler(
        position_ned_m: Vector3<f64>,
        (roll_rad, pitch_rad, yaw_rad): (f64, f64, f64),
        velocity_body_m_s: Vector3<f64>,
        angular_velocity_body_rad_s: Vector3<f64>,
    ) -> Self {
        Self {
            position_ned_m,
            attitude: frames::attitude_from_euler(roll_rad, pitch_rad, yaw_rad),
            velocity_body_m_s,
            angular_velocity_body_rad_s,
        }
    }

    /// Steady level flight at altitude `altitude_m`, heading north at airspeed `airspeed_m_s`
    /// with angle of attack `alpha_rad` (pitch θ = α, no wind).
    pub fn level_flight(altitude_m: f64, airspeed_m_s: f64, alpha_rad: f64) -> Self {
        Self::steady_flight(altitude_m, airspeed_m_s, alpha_rad, 0.0)
    }

    /// Steady wings-level flight on a path `flight_path_angle_rad` above the horizon (γ < 0
    /// descends), heading north at `airspeed_m_s` with angle of attack `alpha_rad`: pitch
    /// θ = α + γ, no wind.
    pub fn steady_flight(
        altitude_m: f64,
        airspeed_m_s: f64,
        alpha_rad: f64,
        flight_path_angle_rad: f64,
    ) -> Self {
        Self::from_euler(
            Vector3::new(0.0, 0.0, -altitude_m),
            (0.0, alpha_rad + flight_path_angle_rad, 0.0),
            frames::body_velocity_from_wind(airspeed_m_s, alpha_rad, 0.0),
            Vector3::zeros(),
        )
    }

    /// 3-2-1 Euler angles (roll φ, pitch θ, yaw ψ), rad.
    pub fn euler_angles(&self) -> (f64, f64, f64) {
        frames::euler_from_attitude(&self.attitude)
    }

    /// Geometric altitude h = −z_NED, m.
    pub fn altitude_m(&self) -> f64 {
        -self.position_ned_m.z
    }

    /// Centre-of-mass velocity in NED axes, m/s.
    pub fn velocity_ned_m_s(&self) -> Vector3<f64> {
        self.attitude * self.velocity_body_m_s
    }

    /// (airspeed m/s, α rad, β rad) of the centre of mass in a wind given in NED axes (m/s):
    /// the body-axis velocity relative to the air, β − C_be w.
    pub fn air_data(&self, wind_ned_m_s: &Vector3<f64>) -> (f64, f64, f64) {
        let relative =
            self.velocity_body_m_s - self.attitude.inverse_transform_vector(wind_ned_m_s);
        frames::wind_angles(&relative)
    }
}

/// WGS-84 equatorial radius, m (NIMA TR8350.2, 3rd ed., 2000, Table 3.1).
pub const WGS84_EQUATORIAL_RADIUS_M: f64 = 6_378_137.0;
/// WGS-84 gravitational parameter GM, m³/s² (NIMA TR8350.2, Table 3.1).
pub const WGS84_GM_M3_S2: f64 = 3.986_004_418e14;
/// WGS-84 Earth rotation rate, rad/s (NIMA TR8350.2, Table 3.1).
pub const WGS84_ROTATION_RAD_S: f64 = 7.292_115e-5;

/// The Earth the vehicle flies over (`[simulation] earth`).
///
/// `Flat` is the paper's: a flat, non-rotating Earth (NED is inertial), gravity by the
/// [`GravityModel`]. `Spherical` flies over a sphere of the WGS-84 equatorial radius R with
/// point-mass gravitation GM/r² (no J2), rotating at `rotation_rad_s` (0: not rotating) about
/// the polar axis. The state keeps its layout: the attitude is body → local NED, the velocity
/// and angular velocity are relative to the Earth in body axes, and the position is north and
/// east arc lengths on the sphere of radius R (latitude = latitude₀ + north / R) and
/// down = −h. The equations are the rotating-Earth forms of Stevens, Lewis & Johnson,
/// "Aircraft Control and Simulation", 3rd ed., §1.6-1.7 (module docs of
/// [`RigidBody::derivative`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum EarthModel {
    #[default]
    Flat,
    Spherical {
        rotation_rad_s: f64,
        initial_latitude_rad: f64,
    },
}

impl EarthModel {
    /// The names of `[simulation] earth`.
    pub const NAMES: [&'static str; 3] = ["flat", "spherical", "spherical-rotating"];

    /// The model of `[simulation] earth = name` starting at `latitude_rad`.
    pub fn from_name(name: &str, latitude_rad: f64) -> Option<Self> {
        match name {
            "flat" => Some(Self::Flat),
            "spherical" => Some(Self::Spherical {
                rotation_rad_s: 0.0,
                initial_latitude_rad: latitude_rad,
            }),
            "spherical-rotating" => Some(Self::Spherical {
                rotation_rad_s: WGS84_ROTATION_RAD_S,
                initial_latitude_rad: latitude_rad,
            }),
            _ => None,
        }
    }

    /// The name `[simulation] earth` writes.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Flat => "flat",
            Self::Spherical { rotation_rad_s, .. } if *rotation_rad_s == 0.0 => "spherical",
            Self::Spherical { .. } => "spherical-rotating",
        }
    }

    /// The transport rate ρ of the local NED frame relative to the Earth, NED axes, rad/s, for
    /// a velocity `v_ned` relative to the Earth at `state`'s position: (v_E / r, −v_N / r,
    /// −v_E tan λ / r) (Stevens, Lewis & Johnson §1.7); zero on a flat Earth.
    pub fn transport_rate_ned(&self, state: &RigidBodyState, v_ned: &Vector3<f64>) -> Vector3<f64> {
        match *self {
            Self::Flat => Vector3::zeros(),
            Self::Spherical { .. } => {
                let r = WGS84_EQUATORIAL_RADIUS_M + state.altitude_m();
                let latitude = self.latitude_rad(state);
                Vector3::new(v_ned.y / r, -v_ned.x / r, -v_ned.y * latitude.tan() / r)
            }
        }
    }

    /// Geodetic (= geocentric, on a sphere) latitude of `state`, rad; 0 on a flat Earth.
    pub fn latitude_rad(&self, state: &RigidBodyState) -> f64 {
        match *self {
            Self::Flat => 0.0,
            Self::Spherical {
                initial_latitude_rad,
                ..
            } => initial_latitude_rad + state.position_ned_m.x / WGS84_EQUATORIAL_RADIUS_M,
        }
    }
}

/// How gravity varies over the flight (DESIGN §4: flat earth, altitude-dependent gravity
/// unless the config says otherwise).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum GravityModel {
    /// g(h) = g0 (R_e / (R_e + h))², g0 = 9.80665 m/s², R_e = 6 356 766 m (USSA-1976 eq. 17;
    /// [`hsv_core::atmosphere::gravity`]).
    #[default]
    InverseSquare,
    /// The same g at every altitude, m/s² (textbook linear models assume this).
    Uniform { g_m_s2: f64 },
    /// No gravity (torque-free and force-free tests).
    Off,
}

impl GravityModel {
    /// Gravitational acceleration at geometric altitude `altitude_m`, m/s², pointing down.
    pub fn magnitude_m_s2(&self, altitude_m: f64) -> f64 {
        match *self {
            GravityModel::InverseSquare => atmosphere::gravity(altitude_m),
            GravityModel::Uniform { g_m_s2 } => g_m_s2,
            GravityModel::Off => 0.0,
        }
    }
}

/// The time derivative of a [`RigidBodyState`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBodyDerivative {
    /// ṗ = C_eb β, m/s.
    pub position_rate_ned_m_s: Vector3<f64>,
    /// q̇ = ½ q ⊗ (0, ζ).
    pub attitude_rate: Quaternion<f64>,
    /// β̇: rate of change of the body-axis velocity components, m/s².
    pub acceleration_body_m_s2: Vector3<f64>,
    /// ζ̇: rate of change of the body-axis angular velocity, rad/s².
    pub angular_acceleration_body_rad_s2: Vector3<f64>,
    /// Gravity in body axes, as used, m/s².
    pub gravity_body_m_s2: Vector3<f64>,
    /// Inertial acceleration of the centre of mass, body axes, m/s²: β̇ + ζ × β on a flat
    /// Earth, F/m + g with the Coriolis and centrifugal terms on a rotating one.
    pub inertial_acceleration_body_m_s2: Vector3<f64>,
}

impl Default for RigidBodyDerivative {
    fn default() -> Self {
        Self {
            position_rate_ned_m_s: Vector3::zeros(),
            attitude_rate: Quaternion::new(0.0, 0.0, 0.0, 0.0),
            acceleration_body_m_s2: Vector3::zeros(),
            angular_acceleration_body_rad_s2: Vector3::zeros(),
            gravity_body_m_s2: Vector3::zeros(),
            inertial_acceleration_body_m_s2: Vector3::zeros(),
        }
    }
}

/// The rigid body: mass, inertia about the centre of mass, and the gravity model.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    mass_kg: f64,
    inertia_kg_m2: Matrix3<f64>,
    inverse_inertia: Matrix3<f64>,
    center_of_mass_m: Point3<f64>,
    gravity: GravityModel,
    earth: EarthModel,
}

impl RigidBody {
    /// From the vehicle's mass properties (mass, centre of mass in the structural axes, inertia
    /// tensor about the centre of mass); the error names a non-positive mass or an inertia that
    /// is not symmetric positive definite.
    pub fn new(mass: &MassProperties, gravity: GravityModel) -> Result<Self, DynamicsError> {
        if !(mass.mass_kg.is_finite() && mass.mass_kg > 0.0) {
            return Err(DynamicsError::InvalidParameter {
                quantity: "vehicle mass (kg)".into(),
                value: mass.mass_kg,
                allowed: "finite and > 0",
            });
        }
        if let GravityModel::Uniform { g_m_s2 } = gravity
            && !g_m_s2.is_finite()
        {
            return Err(DynamicsError::InvalidParameter {
                quantity: "uniform gravity (m/s²)".into(),
                value: g_m_s2,
                allowed: "finite",
            });
        }
        let i = mass.inertia_kg_m2;
        let diagonal_kg_m2 = [i[(0, 0)], i[(1, 1)], i[(2, 2)]];
        let scale = i.abs().max();
        let symmetric = (i - i.transpose()).abs().max() <= 1e-9 * scale;
        let inverse = i
            .cholesky()
            .filter(|_| symmetric && i.iter().all(|v| v.is_finite()))
            .map(|c| c.inverse())
            .ok_or(DynamicsError::InertiaNotPositiveDefinite { diagonal_kg_m2 })?;
        Ok(Self {
            mass_kg: mass.mass_kg,
            inertia_kg_m2: i,
            inverse_inertia: inverse,
            center_of_mass_m: mass.center_of_mass_m,
            gravity,
            earth: EarthModel::Flat,
        })
    }

    /// Flies over `earth` from now on (the gravity model then serves the flat Earth only).
    pub fn set_earth(&mut self, earth: EarthModel) {
        self.earth = earth;
    }

    pub fn earth(&self) -> EarthModel {
        self.earth
    }

    /// Steady level flight at `altitude_m`, heading north at `airspeed_m_s` with angle of attack
    /// `alpha_rad` (pitch θ = α, no wind) over this body's Earth: on a sphere the body turns
    /// with the local horizon, ζ = C_bn ρ (ρ the transport rate), so it stays level.
    pub fn level_flight(
        &self,
        altitude_m: f64,
        airspeed_m_s: f64,
        alpha_rad: f64,
    ) -> RigidBodyState {
        self.steady_flight(altitude_m, airspeed_m_s, alpha_rad, 0.0)
    }

    /// [`Self::level_flight`] on a path `flight_path_angle_rad` above the horizon (a glide
    /// descends, γ < 0; pitch θ = α + γ).
    pub fn steady_flight(
        &self,
        altitude_m: f64,
        airspeed_m_s: f64,
        alpha_rad: f64,
        flight_path_angle_rad: f64,
    ) -> RigidBodyState {
        let mut state = RigidBodyState::steady_flight(
            altitude_m,
            airspeed_m_s,
            alpha_rad,
            flight_path_angle_rad,
        );
        let rho = self
            .earth
            .transport_rate_ned(&state, &state.velocity_ned_m_s());
        state.angular_velocity_body_rad_s = state.attitude.inverse_transform_vector(&rho);
        state
    }

    pub fn mass_kg(&self) -> f64 {
        self.mass_kg
    }

    /// Inertia tensor about the centre of mass, body axes, kg m².
    pub fn inertia_kg_m2(&self) -> &Matrix3<f64> {
        &self.inertia_kg_m2
    }

    /// Centre of mass in the structural (nose-origin) body axes, m.
    pub fn center_of_mass_m(&self) -> Point3<f64> {
        self.center_of_mass_m
    }

    pub fn gravity_model(&self) -> GravityModel {
        self.gravity
    }

    /// Gravity in body axes, g_b = C_be (0, 0, g(h)), m/s²: the gravity model's on a flat
    /// Earth, GM / (R + h)² on a sphere.
    pub fn gravity_body_m_s2(&self, state: &RigidBodyState) -> Vector3<f64> {
        let g = match self.earth {
            EarthModel::Flat => self.gravity.magnitude_m_s2(state.altitude_m()),
            EarthModel::Spherical { .. } => {
                let r = WGS84_EQUATORIAL_RADIUS_M + state.altitude_m();
                WGS84_GM_M3_S2 / (r * r)
            }
        };
        state
            .attitude
            .inverse_transform_vector(&Vector3::new(0.0, 0.0, g))
    }

    /// The state derivative for body-axis loads about the centre of mass (gravity excluded; it
    /// is added here): m(β̇ + ζ × β) = F + m g_b, J ζ̇ + ζ × J ζ = M, ṗ = C_eb β,
    /// q̇ = ½ q ⊗ (0, ζ).
    ///
    /// Reference: Stevens, Lewis & Johnson, *Aircraft Control and Simulation*, 3rd ed. (2016),
    /// ch. 1 (rigid-body equations in body axes over a flat earth).
    ///
    /// Over a rotating sphere ([`EarthModel::Spherical`], Stevens, Lewis & Johnson §1.6-1.7),
    /// with Ω the Earth's rate and r the position from its centre (body axes), ρ the transport
    /// rate and ω = ζ + Ω the inertial angular velocity:
    /// β̇ = F/m + g − (ζ + 2Ω) × β − Ω × (Ω × r) (Coriolis and centrifugal),
    /// J ω̇ + ω × J ω = M with ζ̇ = ω̇ + ζ × Ω (Ω is fixed in the Earth),
    /// q̇ = ½ q ⊗ (0, ζ − C_bn ρ) (the attitude is to the local NED frame, which turns with ρ),
    /// and the position moves along the sphere: ṅ = v_N R / r, ė = v_E R / r, ḋ = v_D.
    pub fn derivative(&self, state: &RigidBodyState, loads: &Loads) -> RigidBodyDerivative {
        let EarthModel::Spherical { rotation_rad_s, .. } = self.earth else {
            return self.flat_derivative(state, loads);
        };
        let beta = &state.velocity_body_m_s;
        let zeta = &state.angular_velocity_body_rad_s;
        let gravity_body = self.gravity_body_m_s2(state);
        let latitude = self.earth.latitude_rad(state);
        let radius_m = WGS84_EQUATORIAL_RADIUS_M + state.altitude_m();
        let to_body = |v: &Vector3<f64>| state.attitude.inverse_transform_vector(v);
        let earth_rate_ned = rotation_rad_s * Vector3::new(latitude.cos(), 0.0, -latitude.sin());
        let position_ned = Vector3::new(0.0, 0.0, -radius_m);
        let centrifugal_ned = earth_rate_ned.cross(&earth_rate_ned.cross(&position_ned));
        let earth_rate = to_body(&earth_rate_ned);
        let inertial_acceleration = loads.force_n / self.mass_kg + gravity_body;
        let acceleration = inertial_acceleration
            - (zeta + 2.0 * earth_rate).cross(beta)
            - to_body(&centrifugal_ned);
        let omega = zeta + earth_rate;
        let angular_momentum = self.inertia_kg_m2 * omega;
        let angular_acceleration = self.inverse_inertia
            * (loads.moment_nm - omega.cross(&angular_momentum))
            + zeta.cross(&earth_rate);
        let v_ned = state.attitude * beta;
        let transport = self.earth.transport_rate_ned(state, &v_ned);
        let along_sphere = WGS84_EQUATORIAL_RADIUS_M / radius_m;
        RigidBodyDerivative {
            position_rate_ned_m_s: Vector3::new(
                v_ned.x * along_sphere,
                v_ned.y * along_sphere,
                v_ned.z,
            ),
            attitude_rate: frames::attitude_rate(&state.attitude, &(zeta - to_body(&transport))),
            acceleration_body_m_s2: acceleration,
            angular_acceleration_body_rad_s2: angular_acceleration,
            gravity_body_m_s2: gravity_body,
            inertial_acceleration_body_m_s2: inertial_acceleration,
        }
    }

    /// [`Self::derivative`] over the flat, non-rotating Earth.
    fn flat_derivative(&self, state: &RigidBodyState, loads: &Loads) -> RigidBodyDerivative {
        let beta = &state.velocity_body_m_s;
        let zeta = &state.angular_velocity_body_rad_s;
        let gravity_body = self.gravity_body_m_s2(state);
        let acceleration = loads.force_n / self.mass_kg + gravity_body - zeta.cross(beta);
        let angular_momentum = self.inertia_kg_m2 * zeta;
        let angular_acceleration =
            self.inverse_inertia * (loads.moment_nm - zeta.cross(&angular_momentum));
        RigidBodyDerivative {
            position_rate_ned_m_s: state.attitude * beta,
            attitude_rate: frames::attitude_rate(&state.attitude, zeta),
            acceleration_body_m_s2: acceleration,
            angular_acceleration_body_rad_s2: angular_acceleration,
            gravity_body_m_s2: gravity_body,
            inertial_acceleration_body_m_s2: acceleration + zeta.cross(beta),
        }
    }

    /// Position of a structural point relative to the centre of mass, body axes, m.
    pub fn offset_from_center_of_mass(&self, point_m: &Point3<f64>) -> Vector3<f64> {
        point_m - self.center_of_mass_m
    }
}

/// The loads about `to` of loads given about `from` (same force):
/// M_to = M_from + (r_from − r_to) × F.
pub fn moment_about(loads: &Loads, from_m: &Point3<f64>, to_m: &Point3<f64>) -> Loads {
    Loads {
        force_n: loads.force_n,
        moment_nm: loads.moment_nm + (from_m - to_m).cross(&loads.force_n),
    }
}

/// Inertial acceleration, in body axes, of a point moving in the body frame at `offset_m`
/// from the centre of mass with velocity `relative_velocity_m_s` and acceleration
/// `relative_acceleration_m_s2` relative to the body axes:
/// a = a_cm + ζ̇ × d + ζ × (ζ × d) + 2 ζ × ḋ + d̈.
///
/// Reference: Greenwood, *Principles of Dynamics*, 2nd ed. (1988), ch. 2 (motion relative to
/// a rotating frame).
pub fn point_acceleration(
    state: &RigidBodyState,
    derivative: &RigidBodyDerivative,
    offset_m: &Vector3<f64>,
    relative_velocity_m_s: &Vector3<f64>,
    relative_acceleration_m_s2: &Vector3<f64>,
) -> Vector3<f64> {
    let zeta = &state.angular_velocity_body_rad_s;
    derivative.inertial_acceleration_body_m_s2
        + derivative.angular_acceleration_body_rad_s2.cross(offset_m)
        + zeta.cross(&zeta.cross(offset_m))
        + 2.0 * zeta.cross(relative_velocity_m_s)
        + relative_acceleration_m_s2
}
