//! Actuators between the controller and the vehicle: each channel a first-order lag
//! τ ẋ = c − x toward the held command, its rate and position then limited.
//!
//! Over one aeroelastic step Δt with the command held, the lag is integrated exactly,
//! x₁ = c + (x₀ − c) e^(−Δt/τ); the change is then capped at the rate limit times Δt and the
//! position clamped to its range. `[control.actuators]` keys (defaults in brackets):
//! `elevon_limit_deg` [30: the travel of an all-moving hypersonic control surface; a choice,
//! not from the paper], `elevon_rate_limit_deg_s` \[100\], `elevon_time_constant_s` [0.02: a
//! 50 rad/s servo], `phi_min` \[0\], `phi_max` \[1\], `phi_time_constant_s` [0.1: the fuel
//! system's lag], `phi_rate_limit_per_s` \[2\].

use hsv_core::control::ControlCommands;

/// `[control.actuators]`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ActuatorSettings {
    /// Elevon position limit (symmetric plus differential on each side), ± deg.
    pub elevon_limit_deg: f64,
    pub elevon_rate_limit_deg_s: f64,
    pub elevon_time_constant_s: f64,
    pub phi_min: f64,
    pub phi_max: f64,
    pub phi_time_constant_s: f64,
    pub phi_rate_limit_per_s: f64,
}

impl Default for ActuatorSettings {
    fn default() -> Self {
        Self {
            elevon_limit_deg: 30.0,
            elevon_rate_limit_deg_s: 100.0,
            elevon_time_constant_s: 0.02,
            phi_min: 0.0,
            phi_max: 1.0,
            phi_time_constant_s: 0.1,
            phi_rate_limit_per_s: 2.0,
        }
    }
}

/// Which limits an actuator met over a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct Saturation {
    pub elevon_position: bool,
    pub elevon_rate: bool,
    pub phi_position: bool,
    pub phi_rate: bool,
}

/// The checked actuators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Actuators {
    settings: ActuatorSettings,
}

impl Actuators {
    /// Checks the settings; `key` is their table's path for messages.
    pub fn new(settings: ActuatorSettings, key: &str) -> Result<Self, String> {
        let s = &settings;
        for (name, v) in [
            ("elevon_limit_deg", s.elevon_limit_deg),
            ("elevon_rate_limit_deg_s", s.elevon_rate_limit_deg_s),
            ("phi_rate_limit_per_s", s.phi_rate_limit_per_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("key `{key}.{name}` is {v}; expected a number > 0"));
            }
        }
        for (name, v) in [
            ("elevon_time_constant_s", s.elevon_time_constant_s),
            ("phi_time_constant_s", s.phi_time_constant_s),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!(
                    "key `{key}.{name}` is {v}; expected seconds >= 0 (0: no lag)"
                ));
            }
        }
        if !(s.phi_min.is_finite() && s.phi_max.is_finite() && 0.0 <= s.phi_min)
            || s.phi_min >= s.phi_max
            || s.phi_max > 1.0
        {
            return Err(format!(
                "keys `{key}.phi_min` = {} and `{key}.phi_max` = {}: expected 0 <= phi_min < \
                 phi_max <= 1",
                s.phi_min, s.phi_max
            ));
        }
        Ok(Self { settings })
    }

    pub fn settings(&self) -> &ActuatorSettings {
        &self.settings
    }

    /// The positions after `dt` s from `from` under the held `command`, and which limits bit.
    pub fn advance(
        &self,
        from: &ControlCommands,
        command: &ControlCommands,
        dt: f64,
    ) -> (ControlCommands, Saturation) {
        let s = &self.settings;
        let limit = s.elevon_limit_deg.to_radians();
        let rate = s.elevon_rate_limit_deg_s.to_radians();
        let mut sat = Saturation::default();
        let channel = |x0: f64, c: f64, tau: f64, rate: f64, lo: f64, hi: f64| {
            let lagged = if tau > 0.0 {
                c + (x0 - c) * (-dt / tau).exp()
            } else {
                c
            };
            let max_step = rate * dt;
            let stepped = x0 + (lagged - x0).clamp(-max_step, max_step);
            let rate_hit = (lagged - x0).abs() > max_step;
            let x1 = stepped.clamp(lo, hi);
            (x1, rate_hit, x1 != stepped)
        };
        // Each side's deflection is symmetric ± differential; the symmetric channel keeps the
        // room the differential one leaves.
        let (d, d_rate, _) = channel(
            from.differential_elevon_rad,
            command.differential_elevon_rad,
            s.elevon_time_constant_s,
            rate,
            -limit,
            limit,
        );
        let room = (limit - d.abs()).max(0.0);
        let (e, e_rate, e_pos) = channel(
            from.symmetric_elevon_rad,
            command.symmetric_elevon_rad,
            s.elevon_time_constant_s,
            rate,
            -room,
            room,
        );
        let (phi, phi_rate, phi_pos) = channel(
            from.fuel_equivalence_ratio,
            command.fuel_equivalence_ratio,
            s.phi_time_constant_s,
            s.phi_rate_limit_per_s,
            s.phi_min,
            s.phi_max,
        );
        sat.elevon_position = e_pos || d.abs() >= limit;
        sat.elevon_rate = e_rate || d_rate;
        sat.phi_position = phi_pos;
        sat.phi_rate = phi_rate;
        (
            ControlCommands {
                symmetric_elevon_rad: e,
                differential_elevon_rad: d,
                fuel_equivalence_ratio: phi,
            },
            sat,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A first-order lag from 0 toward a unit step reaches 1 − e^(−t/τ) (exact solution of
    /// τ ẋ = 1 − x), 1e-12; rate and position limits bite and are flagged.
    #[test]
    fn lag_rate_and_position_limits() {
        let act = Actuators::new(
            ActuatorSettings {
                elevon_rate_limit_deg_s: 1e6,
                ..ActuatorSettings::default()
            },
            "control.actuators",
        )
        .unwrap();
        let mut x = ControlCommands {
            fuel_equivalence_ratio: 0.5,
            ..ControlCommands::default()
        };
        let c = ControlCommands {
            symmetric_elevon_rad: 1f64.to_radians(),
            fuel_equivalence_ratio: 0.5,
            ..ControlCommands::default()
        };
        for _ in 0..10 {
            x = act.advance(&x, &c, 0.001).0;
        }
        let want = 1f64.to_radians() * (1.0 - (-0.01f64 / 0.02).exp());
        assert!((x.symmetric_elevon_rad - want).abs() < 1e-12);
        // Rate: 100 deg/s over 1 ms is 0.1 deg at most.
        let slow = Actuators::new(ActuatorSettings::default(), "a").unwrap();
        let big = ControlCommands {
            symmetric_elevon_rad: 50f64.to_radians(),
            fuel_equivalence_ratio: 3.0,
            ..ControlCommands::default()
        };
        let (y, sat) = slow.advance(&ControlCommands::default(), &big, 0.001);
        assert!((y.symmetric_elevon_rad - 0.1f64.to_radians()).abs() < 1e-15);
        assert!(sat.elevon_rate && sat.phi_rate);
        // Position: held at the 30 deg stop, phi at 1.
        let mut z = ControlCommands::default();
        let mut last = Saturation::default();
        for _ in 0..2000 {
            (z, last) = slow.advance(&z, &big, 0.001);
        }
        assert_eq!(z.symmetric_elevon_rad, 30f64.to_radians());
        assert_eq!(z.fuel_equivalence_ratio, 1.0);
        assert!(last.elevon_position && last.phi_position);
    }
}
