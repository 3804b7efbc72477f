//! Sensors between the vehicle and its controller (`[control.sensors]`): a transport delay of
//! whole aeroelastic steps, and per measured output a constant bias and seeded Gaussian white
//! noise, read when the controller samples (its sample rate is the sensors').
//!
//! The noise of a reading depends only on the seed and the step it is read at (a generator
//! seeded from both), so a resumed run reads the same noise without carrying a generator; the
//! delay line of true outputs is simulation state ([`super::ControlState::sensor_history`]).

use std::collections::BTreeMap;

use hsv_core::control::MeasuredOutputs;
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;
use serde::{Deserialize, Serialize};

/// `[control.sensors]`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSettings {
    /// Transport delay, s: a whole number of aeroelastic steps (0: none).
    #[serde(default)]
    pub delay_s: f64,
    /// Seed of the noise (the same seed, the same readings).
    #[serde(default)]
    pub seed: u64,
    /// Noise standard deviation per measured output (`hsv_core::control::MeasuredOutputs`
    /// names but `time_s`), in its units.
    #[serde(default)]
    pub noise: BTreeMap<String, f64>,
    /// Constant bias per measured output, in its units.
    #[serde(default)]
    pub bias: BTreeMap<String, f64>,
}

/// The sensors of a control loop, built from [`SensorSettings`].
#[derive(Debug, Clone, PartialEq)]
pub struct Sensors {
    pub delay_steps: usize,
    seed: u64,
    noise: [f64; 16],
    bias: [f64; 16],
}

impl Sensors {
    /// The sensors of `settings` (at `key`, for messages) in a loop of step `dt_s`.
    pub fn new(settings: &SensorSettings, dt_s: f64, key: &str) -> Result<Self, String> {
        let delay = settings.delay_s / dt_s;
        let delay_steps = delay.round();
        if !(settings.delay_s.is_finite()
            && settings.delay_s >= 0.0
            && (delay - delay_steps).abs() <= 1e-6)
        {
            return Err(format!(
                "key `{key}.delay_s`: {} s must be >= 0 and a whole number of steps of {dt_s} s",
                settings.delay_s
            ));
        }
        let channels = |table: &BTreeMap<String, f64>, what: &str| -> Result<[f64; 16], String> {
            let mut out = [0.0; 16];
            for (name, &value) in table {
                let Some(k) = MeasuredOutputs::NAMES
                    .iter()
                    .position(|n| n == name)
                    .filter(|&k| k > 0)
                else {
                    return Err(format!(
                        "key `{key}.{what}.{name}`: no such measured output; allowed: {}",
                        MeasuredOutputs::NAMES[1..].join(", ")
                    ));
                };
                let ok = value.is_finite() && (what == "bias" || value >= 0.0);
                if !ok {
                    return Err(format!(
                        "key `{key}.{what}.{name}`: {value} must be finite{}",
                        if what == "noise" { " and >= 0" } else { "" }
                    ));
                }
                out[k] = value;
            }
            Ok(out)
        };
        Ok(Self {
            delay_steps: delay_steps as usize,
            seed: settings.seed,
            noise: channels(&settings.noise, "noise")?,
            bias: channels(&settings.bias, "bias")?,
        })
    }

    /// What the sensors report at step `step` (time `time_s`) of the true outputs `truth`
    /// (already delayed): truth + bias + σ n, n standard normal, independent per channel and
    /// step.
    pub fn read(&self, step: usize, time_s: f64, truth: &MeasuredOutputs) -> MeasuredOutputs {
        // SplitMix64's increment spreads consecutive steps over the seed space.
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(
            self.seed ^ (step as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
        );
        let mut v = truth.values();
        for ((value, bias), sigma) in v.iter_mut().zip(&self.bias).zip(&self.noise).skip(1) {
            let n: f64 = StandardNormal.sample(&mut rng);
            *value += bias + sigma * n;
        }
        v[0] = time_s;
        MeasuredOutputs::from_values(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensors(noise: &[(&str, f64)], bias: &[(&str, f64)]) -> Sensors {
        let table =
            |pairs: &[(&str, f64)]| pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect();
        Sensors::new(
            &SensorSettings {
                delay_s: 0.0,
                seed: 5,
                noise: table(noise),
                bias: table(bias),
            },
            1e-3,
            "control.sensors",
        )
        .expect("valid")
    }

    /// Over N readings of a constant truth the sample mean is truth + bias within 4σ/√N and
    /// the sample standard deviation σ within 4 σ/√(2N) (Gaussian sampling statistics); the
    /// noise of consecutive steps is uncorrelated (|r| < 4/√N); untouched channels are exact.
    #[test]
    fn readings_have_the_bias_and_noise_asked_for() {
        let (sigma, bias) = (2e-3, 5e-4);
        let s = sensors(
            &[("q_rad_s", sigma)],
            &[("q_rad_s", bias), ("alpha_rad", -1e-3)],
        );
        let truth = MeasuredOutputs {
            q_rad_s: 0.01,
            alpha_rad: 0.03,
            altitude_m: 26_000.0,
            ..MeasuredOutputs::default()
        };
        let n = 40_000;
        let q: Vec<f64> = (0..n)
            .map(|k| s.read(k, k as f64 * 1e-3, &truth).q_rad_s - truth.q_rad_s)
            .collect();
        let mean = q.iter().sum::<f64>() / n as f64;
        let var = q.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let root_n = (n as f64).sqrt();
        assert!((mean - bias).abs() < 4.0 * sigma / root_n, "mean {mean}");
        assert!(
            (var.sqrt() - sigma).abs() < 4.0 * sigma / (2.0 * n as f64).sqrt(),
            "std {}",
            var.sqrt()
        );
        let lag = q
            .windows(2)
            .map(|w| (w[0] - mean) * (w[1] - mean))
            .sum::<f64>()
            / ((n - 1) as f64 * var);
        assert!(lag.abs() < 4.0 / root_n, "lag-one correlation {lag}");
        let one = s.read(7, 0.007, &truth);
        assert_eq!(one.alpha_rad, truth.alpha_rad - 1e-3);
        assert_eq!(one.altitude_m, truth.altitude_m);
        assert_eq!(one.time_s, 0.007);
        assert_eq!(
            one,
            s.read(7, 0.007, &truth),
            "same seed and step, same reading"
        );
    }

    /// A controller that commands the symmetric elevon it is told the pitch rate is.
    struct Echo;

    impl hsv_core::control::Controller for Echo {
        fn name(&self) -> &str {
            "echo"
        }
        fn sample_interval_s(&self) -> Option<f64> {
            Some(1e-3)
        }
        fn update(
            &mut self,
            outputs: &MeasuredOutputs,
            _state: &mut [f64],
            commands: &mut hsv_core::control::ControlCommands,
        ) -> Result<(), hsv_core::ModelError> {
            commands.symmetric_elevon_rad = outputs.q_rad_s;
            Ok(())
        }
    }

    /// A 3 ms delay at 1 ms steps: the controller sampling at step k sees the pitch rate of
    /// step k − 3 (the trim's before the line fills), exactly, and a restored loop state
    /// carries the line.
    #[test]
    fn the_controller_sees_the_outputs_of_delay_steps_ago() {
        let trim = crate::vehicle::partitioned::FlightControls::default();
        let mut control =
            crate::analysis::control::ControlLoop::new(Box::new(Echo), None, &trim, 1e-3)
                .expect("loop");
        let settings = SensorSettings {
            delay_s: 0.003,
            ..SensorSettings::default()
        };
        control.set_sensors(Some(
            Sensors::new(&settings, 1e-3, "control.sensors").expect("valid"),
        ));
        let mut state = crate::dynamics::VehicleState::default();
        let mut seen = Vec::new();
        for k in 0..10 {
            state.rigid.angular_velocity_body_rad_s.y = 0.01 * (k + 1) as f64;
            control
                .begin_step(
                    k,
                    k as f64 * 1e-3,
                    1e-3,
                    &state,
                    &nalgebra::Vector3::zeros(),
                )
                .expect("step");
            seen.push(control.state.command.symmetric_elevon_rad);
        }
        let expected: Vec<f64> = (0..10)
            .map(|k: usize| 0.01 * (k.saturating_sub(3) + 1) as f64)
            .collect();
        assert_eq!(seen, expected);
        assert_eq!(control.state.sensor_history.len(), 4);
    }

    #[test]
    fn bad_settings_name_their_key() {
        let bad = |settings: SensorSettings, needle: &str| {
            let e = Sensors::new(&settings, 1e-3, "control.sensors").expect_err("refused");
            assert!(e.contains(needle), "{e}");
        };
        bad(
            SensorSettings {
                delay_s: 0.0015,
                ..SensorSettings::default()
            },
            "control.sensors.delay_s",
        );
        bad(
            SensorSettings {
                noise: [("pitch_rate".to_string(), 1.0)].into(),
                ..SensorSettings::default()
            },
            "control.sensors.noise.pitch_rate`: no such measured output; allowed: p_rad_s",
        );
        bad(
            SensorSettings {
                noise: [("q_rad_s".to_string(), -1.0)].into(),
                ..SensorSettings::default()
            },
            "must be finite and >= 0",
        );
    }
}
