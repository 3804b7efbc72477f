//! Flight conditions: the freestream state and the vehicle's motion through it.

use nalgebra::{Point3, Vector3};

use crate::atmosphere::us_standard_atmosphere_1976;
use crate::error::ModelError;
use crate::gas::PerfectGas;

/// Undisturbed air ahead of the vehicle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Freestream {
    pub mach: f64,
    /// Geometric altitude, m.
    pub altitude_m: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
    /// Airspeed, m/s.
    pub velocity_m_s: f64,
    pub dynamic_viscosity_pa_s: f64,
    /// q = ρ V² / 2, Pa.
    pub dynamic_pressure_pa: f64,
    pub gas: PerfectGas,
}

impl Freestream {
    /// Freestream at `mach` and geometric `altitude_m` in the US Standard Atmosphere 1976.
    ///
    /// Temperature, pressure and viscosity come from the atmosphere table; the speed of sound from
    /// `gas`, so a non-standard γ stays consistent with the Mach number.
    pub fn standard(mach: f64, altitude_m: f64, gas: PerfectGas) -> Result<Self, ModelError> {
        if !mach.is_finite() || mach <= 0.0 {
            return Err(ModelError::out_of_range(
                "freestream",
                "Mach number",
                mach,
                "finite and > 0",
            ));
        }
        let air = us_standard_atmosphere_1976(altitude_m)?;
        let speed_of_sound_m_s = gas.speed_of_sound(air.temperature_k);
        Ok(Self::from_air(
            mach,
            mach * speed_of_sound_m_s,
            altitude_m,
            &air,
            gas,
        ))
    }

    /// Freestream at airspeed `velocity_m_s` and geometric `altitude_m` in the US Standard
    /// Atmosphere 1976: M = V / a(T), one atmosphere lookup (the time loop's path).
    pub fn at_airspeed(
        velocity_m_s: f64,
        altitude_m: f64,
        gas: PerfectGas,
    ) -> Result<Self, ModelError> {
        if !velocity_m_s.is_finite() || velocity_m_s <= 0.0 {
            return Err(ModelError::out_of_range(
                "freestream",
                "airspeed (m/s)",
                velocity_m_s,
                "finite and > 0",
            ));
        }
        let air = us_standard_atmosphere_1976(altitude_m)?;
        let mach = velocity_m_s / gas.speed_of_sound(air.temperature_k);
        Ok(Self::from_air(mach, velocity_m_s, altitude_m, &air, gas))
    }

    fn from_air(
        mach: f64,
        velocity_m_s: f64,
        altitude_m: f64,
        air: &crate::atmosphere::AtmosphereState,
        gas: PerfectGas,
    ) -> Self {
        let speed_of_sound_m_s = gas.speed_of_sound(air.temperature_k);
        let density_kg_m3 = air.pressure_pa / (gas.gas_constant_j_kg_k * air.temperature_k);
        Self {
            mach,
            altitude_m,
            pressure_pa: air.pressure_pa,
            temperature_k: air.temperature_k,
            density_kg_m3,
            speed_of_sound_m_s,
            velocity_m_s,
            dynamic_viscosity_pa_s: air.dynamic_viscosity_pa_s,
            dynamic_pressure_pa: 0.5 * density_kg_m3 * velocity_m_s * velocity_m_s,
            gas,
        }
    }

    /// Stagnation (total) temperature T0 = T (1 + (γ-1)/2 M²), K.
    pub fn total_temperature_k(&self) -> f64 {
        self.temperature_k * crate::gas::total_temperature_ratio(self.mach, self.gas.gamma)
    }
}

/// The vehicle's motion relative to the air: freestream plus attitude to the wind and body rates.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FlightCondition {
    pub freestream: Freestream,
    /// Angle of attack α, rad.
    pub alpha_rad: f64,
    /// Sideslip angle β, rad.
    pub beta_rad: f64,
    /// Body angular velocity (p, q, r) relative to the air mass, rad/s.
    pub angular_velocity_rad_s: Vector3<f64>,
    /// Point the body rotates about (the reference point of the body frame), m.
    pub rotation_center_m: Point3<f64>,
}

impl FlightCondition {
    /// Steady flight at (α, β) with no rotation.
    pub fn steady(freestream: Freestream, alpha_rad: f64, beta_rad: f64) -> Self {
        Self {
            freestream,
            alpha_rad,
            beta_rad,
            angular_velocity_rad_s: Vector3::zeros(),
            rotation_center_m: Point3::origin(),
        }
    }

    /// Velocity of the vehicle's reference point relative to the air, body axes:
    /// V (cos α cos β, sin β, sin α cos β), m/s.
    pub fn velocity_body_m_s(&self) -> Vector3<f64> {
        crate::frames::body_velocity_from_wind(
            self.freestream.velocity_m_s,
            self.alpha_rad,
            self.beta_rad,
        )
    }

    /// Velocity of a body-fixed point relative to the air: V + ω × (r - r_c), m/s.
    pub fn point_velocity_m_s(&self, point: &Point3<f64>) -> Vector3<f64> {
        self.point_velocity_from(self.velocity_body_m_s(), point)
    }

    /// [`Self::point_velocity_m_s`] from the centre's velocity V ([`Self::velocity_body_m_s`],
    /// whose trigonometry a loop over many points takes once), m/s.
    pub fn point_velocity_from(
        &self,
        body_velocity_m_s: Vector3<f64>,
        point: &Point3<f64>,
    ) -> Vector3<f64> {
        body_velocity_m_s
            + self
                .angular_velocity_rad_s
                .cross(&(point - self.rotation_center_m))
    }

    /// Checks that every number is finite, naming the first that is not.
    pub fn check_finite(&self) -> Result<(), ModelError> {
        let named = [
            ("Mach number", self.freestream.mach),
            ("altitude (m)", self.freestream.altitude_m),
            ("angle of attack (rad)", self.alpha_rad),
            ("sideslip (rad)", self.beta_rad),
            ("roll rate (rad/s)", self.angular_velocity_rad_s.x),
            ("pitch rate (rad/s)", self.angular_velocity_rad_s.y),
            ("yaw rate (rad/s)", self.angular_velocity_rad_s.z),
        ];
        for (quantity, value) in named {
            if !value.is_finite() {
                return Err(ModelError::out_of_range(
                    "flight condition",
                    quantity,
                    value,
                    "a finite number",
                ));
            }
        }
        Ok(())
    }
}
