//! Atmospheric disturbances: Dryden turbulence (MIL-F-8785C §3.7.2-3.7.4, the medium/high
//! altitude form) and discrete 1-cosine gusts, as a gust velocity field frozen in the air mass
//! (Taylor's hypothesis): the field moves past the vehicle at the trim airspeed, so a region
//! `lead_m` ahead of the centre of mass meets at time t what the centre of mass meets at
//! t + lead_m / V (one file: the tests check the sampled records against the intensity table and
//! spectra defined here).
//!
//! Components are along the body axes (u forward, v right, w down), as MIL-F-8785C defines the
//! Dryden spectra for the flight path. The forming filters are discretized exactly (zero-order
//! hold of white noise, Van Loan's integral), so the sampled record has the Dryden variance and
//! correlation at any step; a record depends on its seed alone.

use nalgebra::{Matrix2, Matrix4, Vector2, Vector3};
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;
use serde::{Deserialize, Serialize};

/// One foot, m.
const FT_M: f64 = 0.3048;

/// Altitudes of MIL-F-8785C Fig. 7 (MIL-HDBK-1797 Fig. 266), ft.
const INTENSITY_ALTITUDES_FT: [f64; 12] = [
    500.0, 1750.0, 3750.0, 7500.0, 15000.0, 25000.0, 35000.0, 45000.0, 55000.0, 65000.0, 75000.0,
    80000.0,
];

/// Probabilities of exceedance of the rows of `INTENSITY_FT_S`.
pub const EXCEEDANCE_PROBABILITIES: [f64; 7] = [2e-1, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6];

/// Medium/high-altitude turbulence intensity σ_u = σ_v = σ_w, ft/s, by probability of
/// exceedance (rows) and altitude (columns): MIL-F-8785C Fig. 7.
const INTENSITY_FT_S: [[f64; 12]; 7] = [
    [3.2, 2.2, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [4.2, 3.6, 3.3, 1.6, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [6.6, 6.9, 7.4, 6.7, 4.6, 2.7, 0.4, 0.0, 0.0, 0.0, 0.0, 0.0],
    [8.6, 9.6, 10.6, 10.1, 8.0, 6.6, 5.0, 4.2, 2.7, 0.0, 0.0, 0.0],
    [
        11.8, 13.0, 16.0, 15.1, 11.6, 9.7, 8.1, 8.2, 7.9, 4.9, 3.2, 2.1,
    ],
    [
        15.6, 17.6, 23.0, 23.6, 22.1, 20.0, 16.0, 15.1, 12.1, 7.9, 6.2, 5.1,
    ],
    [
        18.7, 21.5, 28.4, 30.2, 30.7, 31.0, 25.2, 23.1, 17.5, 10.7, 8.4, 7.2,
    ],
];

/// Dryden scale length above 2000 ft: L_u = L_v = L_w = 1750 ft (MIL-F-8785C §3.7.2.3, the
/// form of the spectra in [`longitudinal_psd`] and [`lateral_psd`]), m.
pub const HIGH_ALTITUDE_SCALE_M: f64 = 1750.0 * FT_M;

/// The lowest altitude of the medium/high-altitude model (MIL-F-8785C: above 2000 ft), m.
pub const HIGH_ALTITUDE_FLOOR_M: f64 = 2000.0 * FT_M;

/// Turbulence severity as MIL-F-8785C §3.7.2 names it: light, moderate and severe are the
/// probabilities of exceedance 1e-2, 1e-3 and 1e-5.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Severity {
    Light,
    Moderate,
    Severe,
}

impl Severity {
    pub fn exceedance_probability(self) -> f64 {
        match self {
            Self::Light => 1e-2,
            Self::Moderate => 1e-3,
            Self::Severe => 1e-5,
        }
    }
}

/// σ_u = σ_v = σ_w at `altitude_m` for a probability of exceedance of the table, m/s: linear
/// in altitude between the table's rows, its 80 000 ft value held above them (the table's top;
/// Mach 6 at 26 km flies at 85 300 ft). Refused below 2000 ft (the low-altitude model, which
/// needs the wind at 20 ft, is not built) and for a probability that is not a table row.
pub fn high_altitude_intensity_m_s(altitude_m: f64, exceedance: f64) -> Result<f64, String> {
    let Some(row) = EXCEEDANCE_PROBABILITIES
        .iter()
        .position(|&p| (p - exceedance).abs() <= 1e-9 * p)
    else {
        return Err(format!(
            "probability of exceedance {exceedance} is not one of MIL-F-8785C's {:?}",
            EXCEEDANCE_PROBABILITIES
        ));
    };
    if altitude_m.is_nan() || altitude_m < HIGH_ALTITUDE_FLOOR_M {
        return Err(format!(
            "Dryden turbulence is modelled above 2000 ft ({HIGH_ALTITUDE_FLOOR_M:.1} m) only, \
             got {altitude_m} m"
        ));
    }
    let h_ft = altitude_m / FT_M;
    let sigma = &INTENSITY_FT_S[row];
    let k = INTENSITY_ALTITUDES_FT.partition_point(|&a| a <= h_ft);
    let ft_s = if k == INTENSITY_ALTITUDES_FT.len() {
        sigma[k - 1]
    } else {
        let (a0, a1) = (INTENSITY_ALTITUDES_FT[k - 1], INTENSITY_ALTITUDES_FT[k]);
        sigma[k - 1] + (sigma[k] - sigma[k - 1]) * (h_ft - a0) / (a1 - a0)
    };
    Ok(ft_s * FT_M)
}

/// Dryden longitudinal (u) one-sided spectrum in temporal frequency ω (rad/s) at airspeed V:
/// Φ_u(ω) = σ² (2L/πV) / (1 + (Lω/V)²), (m/s)²/(rad/s); ∫₀^∞ Φ_u dω = σ² (MIL-F-8785C
/// §3.7.2.3).
pub fn longitudinal_psd(sigma_m_s: f64, scale_m: f64, airspeed_m_s: f64, omega: f64) -> f64 {
    let x = scale_m * omega / airspeed_m_s;
    sigma_m_s.powi(2) * 2.0 * scale_m / (std::f64::consts::PI * airspeed_m_s) / (1.0 + x * x)
}

/// Dryden lateral and vertical (v, w) one-sided spectrum:
/// Φ(ω) = σ² (L/πV) (1 + 3(Lω/V)²) / (1 + (Lω/V)²)², (m/s)²/(rad/s) (MIL-F-8785C §3.7.2.3).
pub fn lateral_psd(sigma_m_s: f64, scale_m: f64, airspeed_m_s: f64, omega: f64) -> f64 {
    let x = scale_m * omega / airspeed_m_s;
    sigma_m_s.powi(2) * scale_m / (std::f64::consts::PI * airspeed_m_s) * (1.0 + 3.0 * x * x)
        / (1.0 + x * x).powi(2)
}

/// `[disturbances.dryden]`: continuous turbulence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DrydenSettings {
    /// `light`, `moderate` or `severe` (probability of exceedance 1e-2, 1e-3, 1e-5), unless
    /// `sigma_m_s` is given.
    #[serde(default)]
    pub severity: Option<Severity>,
    /// σ_u = σ_v = σ_w, m/s, in place of the MIL-F-8785C table.
    #[serde(default)]
    pub sigma_m_s: Option<f64>,
    /// L_u = L_v = L_w, m (default 1750 ft).
    #[serde(default = "default_scale_m")]
    pub scale_m: f64,
    /// Seed of the white noise (the same seed, the same record).
    #[serde(default)]
    pub seed: u64,
}

fn default_scale_m() -> f64 {
    HIGH_ALTITUDE_SCALE_M
}

/// `[[disturbances.gusts]]`: a discrete 1-cosine gust, v(x) = (v_m/2)(1 − cos(π x / d)) for
/// 0 ≤ x ≤ 2d of distance flown into it (MIL-F-8785C §3.7.5's shape, rising over d and falling
/// back over the next d, as FAR 25.341 applies it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GustSettings {
    /// When the centre of mass enters the gust, s.
    pub start_s: f64,
    /// Peak gust velocity along the body axes (u, v, w; w down), m/s.
    pub amplitude_m_s: [f64; 3],
    /// Gust half length d (rise distance), m.
    pub half_length_m: f64,
}

impl GustSettings {
    /// The gust velocity (body axes, m/s) `distance_m` into the gust.
    pub fn velocity_at(&self, distance_m: f64) -> Vector3<f64> {
        if !(0.0..=2.0 * self.half_length_m).contains(&distance_m) {
            return Vector3::zeros();
        }
        let shape = 0.5 * (1.0 - (std::f64::consts::PI * distance_m / self.half_length_m).cos());
        Vector3::from(self.amplitude_m_s) * shape
    }
}

/// `[disturbances]`: what a flight flies through (nothing when the table is absent).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisturbanceSettings {
    #[serde(default)]
    pub dryden: Option<DrydenSettings>,
    #[serde(default)]
    pub gusts: Vec<GustSettings>,
}

impl DisturbanceSettings {
    /// The `[disturbances]` table of `loaded`, checked: errors name the file and key path.
    pub fn from_config(loaded: &hsv_core::config::LoadedConfig) -> anyhow::Result<Self> {
        let settings: Self = hsv_core::config::parse_table(
            &loaded.config.disturbances,
            &loaded.file,
            "disturbances",
        )?;
        settings.check().map_err(|(key, why)| {
            anyhow::anyhow!("{}: key `disturbances.{key}`: {why}", loaded.file)
        })?;
        Ok(settings)
    }

    /// The first invalid value as (key path below `disturbances`, why).
    pub fn check(&self) -> Result<(), (String, String)> {
        if let Some(d) = &self.dryden {
            match (d.severity, d.sigma_m_s) {
                (Some(_), Some(_)) => {
                    return Err((
                        "dryden".into(),
                        "give `severity` or `sigma_m_s`, not both".into(),
                    ));
                }
                (None, None) => {
                    return Err((
                        "dryden".into(),
                        "give `severity` (light, moderate, severe) or `sigma_m_s`".into(),
                    ));
                }
                (None, Some(s)) if !(s.is_finite() && s >= 0.0) => {
                    return Err((
                        "dryden.sigma_m_s".into(),
                        format!("must be a finite number >= 0, got {s}"),
                    ));
                }
                _ => {}
            }
            if !(d.scale_m.is_finite() && d.scale_m > 0.0) {
                return Err((
                    "dryden.scale_m".into(),
                    format!("must be a positive length, got {}", d.scale_m),
                ));
            }
        }
        for (i, g) in self.gusts.iter().enumerate() {
            if !(g.start_s.is_finite() && g.start_s >= 0.0) {
                return Err((
                    format!("gusts[{i}].start_s"),
                    format!("must be a time >= 0, got {}", g.start_s),
                ));
            }
            if !(g.half_length_m.is_finite() && g.half_length_m > 0.0) {
                return Err((
                    format!("gusts[{i}].half_length_m"),
                    format!("must be a positive length, got {}", g.half_length_m),
                ));
            }
            if !g.amplitude_m_s.iter().all(|v| v.is_finite()) {
                return Err((
                    format!("gusts[{i}].amplitude_m_s"),
                    format!("must be finite, got {:?}", g.amplitude_m_s),
                ));
            }
        }
        Ok(())
    }

    /// The wind field of a flight at `altitude_m` and `airspeed_m_s` with aeroelastic step
    /// `dt_s` (the turbulence intensity of a severity from MIL-F-8785C Fig. 7 at the altitude).
    pub fn field(
        &self,
        altitude_m: f64,
        airspeed_m_s: f64,
        dt_s: f64,
    ) -> Result<Disturbances, String> {
        let dryden = match &self.dryden {
            None => None,
            Some(d) => {
                let sigma = match (d.sigma_m_s, d.severity) {
                    (Some(s), _) => s,
                    (None, Some(severity)) => {
                        high_altitude_intensity_m_s(altitude_m, severity.exceedance_probability())?
                    }
                    (None, None) => return Err("Dryden turbulence without an intensity".into()),
                };
                Some(DrydenRecord::new(
                    sigma,
                    d.scale_m,
                    airspeed_m_s,
                    dt_s,
                    d.seed,
                )?)
            }
        };
        Ok(Disturbances {
            dryden,
            gusts: self.gusts.clone(),
            airspeed_m_s,
        })
    }
}

/// A second-order-or-less forming filter discretized exactly over one step: x ← Φ x + w,
/// w ~ N(0, Q), output y = c · x.
#[derive(Debug, Clone, PartialEq)]
struct Filter {
    phi: Matrix2<f64>,
    /// Lower Cholesky factor of Q.
    noise: Matrix2<f64>,
    c: Vector2<f64>,
    x: Vector2<f64>,
}

impl Filter {
    /// The filter x' = A x + b n(t), y = c·x, driven by white noise of one-sided spectrum 1
    /// per rad/s (intensity π), discretized over `dt_s` by Van Loan's method and started from
    /// its stationary distribution's mean (zero).
    fn new(a: Matrix2<f64>, b: Vector2<f64>, c: Vector2<f64>, dt_s: f64) -> Self {
        let intensity = std::f64::consts::PI;
        let mut m = Matrix4::zeros();
        m.fixed_view_mut::<2, 2>(0, 0).copy_from(&(-a * dt_s));
        m.fixed_view_mut::<2, 2>(0, 2)
            .copy_from(&(b * b.transpose() * intensity * dt_s));
        m.fixed_view_mut::<2, 2>(2, 2)
            .copy_from(&(a.transpose() * dt_s));
        let e = m.exp();
        let phi = e.fixed_view::<2, 2>(2, 2).transpose();
        let q = phi * e.fixed_view::<2, 2>(0, 2);
        let q = 0.5 * (q + q.transpose());
        // A first-order filter has a zero second state: Q is singular there.
        let noise = match q.cholesky() {
            Some(l) => l.l(),
            None => Matrix2::new(q[(0, 0)].max(0.0).sqrt(), 0.0, 0.0, 0.0),
        };
        Self {
            phi,
            noise,
            c,
            x: Vector2::zeros(),
        }
    }

    fn step(&mut self, white: Vector2<f64>) -> f64 {
        self.x = self.phi * self.x + self.noise * white;
        self.c.dot(&self.x)
    }
}

/// Dryden turbulence along the body axes, sampled every `dt_s` from t = 0 (the record the
/// centre of mass meets; [`Self::velocity_at`] reads it between samples and ahead of it).
#[derive(Debug, Clone)]
pub struct DrydenRecord {
    pub sigma_m_s: f64,
    pub scale_m: f64,
    pub airspeed_m_s: f64,
    pub dt_s: f64,
    pub seed: u64,
    filters: [Filter; 3],
    rng: Xoshiro256PlusPlus,
    samples: Vec<Vector3<f64>>,
}

impl DrydenRecord {
    /// The record for turbulence of intensity `sigma_m_s` and scale `scale_m` met at
    /// `airspeed_m_s`, sampled every `dt_s`.
    pub fn new(
        sigma_m_s: f64,
        scale_m: f64,
        airspeed_m_s: f64,
        dt_s: f64,
        seed: u64,
    ) -> Result<Self, String> {
        for (name, v) in [
            ("sigma_m_s", sigma_m_s),
            ("scale_m", scale_m),
            ("airspeed_m_s", airspeed_m_s),
            ("dt_s", dt_s),
        ] {
            let ok = v.is_finite() && (v > 0.0 || (name == "sigma_m_s" && v == 0.0));
            if !ok {
                return Err(format!(
                    "Dryden turbulence: {name} must be positive, got {v}"
                ));
            }
        }
        let tau = scale_m / airspeed_m_s;
        // u: σ √(2L/πV) / (1 + τ s), as x' = −x/τ + n, y = σ √(2τ/π)/τ x.
        let u = Filter::new(
            Matrix2::new(-1.0 / tau, 0.0, 0.0, -1.0 / tau),
            Vector2::new(1.0, 0.0),
            Vector2::new(
                sigma_m_s * (2.0 * tau / std::f64::consts::PI).sqrt() / tau,
                0.0,
            ),
            dt_s,
        );
        // v, w: σ √(L/πV) (1 + √3 τ s)/(1 + τ s)², in controllable canonical form.
        let gain = sigma_m_s * (tau / std::f64::consts::PI).sqrt() / (tau * tau);
        let lateral = || {
            Filter::new(
                Matrix2::new(0.0, 1.0, -1.0 / (tau * tau), -2.0 / tau),
                Vector2::new(0.0, 1.0),
                Vector2::new(gain, gain * 3f64.sqrt() * tau),
                dt_s,
            )
        };
        Ok(Self {
            sigma_m_s,
            scale_m,
            airspeed_m_s,
            dt_s,
            seed,
            filters: [u, lateral(), lateral()],
            rng: Xoshiro256PlusPlus::seed_from_u64(seed),
            samples: vec![Vector3::zeros()],
        })
    }

    /// Generates the record up to `time_s` (and one sample beyond).
    pub fn extend_to(&mut self, time_s: f64) {
        let needed = (time_s / self.dt_s).ceil().max(0.0) as usize + 2;
        while self.samples.len() < needed {
            let mut next = Vector3::zeros();
            for (k, f) in self.filters.iter_mut().enumerate() {
                let white = Vector2::new(
                    StandardNormal.sample(&mut self.rng),
                    StandardNormal.sample(&mut self.rng),
                );
                next[k] = f.step(white);
            }
            self.samples.push(next);
        }
    }

    /// The gust velocity (body axes, m/s) met at `time_s`: linear between samples; beyond the
    /// generated record (call [`Self::extend_to`] first) its last sample.
    pub fn velocity_at(&self, time_s: f64) -> Vector3<f64> {
        let x = (time_s / self.dt_s).max(0.0);
        let k = x.floor() as usize;
        let last = self.samples.len() - 1;
        if k >= last {
            return self.samples[last];
        }
        let w = x - k as f64;
        self.samples[k] * (1.0 - w) + self.samples[k + 1] * w
    }

    /// The samples generated so far.
    pub fn samples(&self) -> &[Vector3<f64>] {
        &self.samples
    }
}

/// Every disturbance of a flight: the wind field the regions fly through.
#[derive(Debug, Clone, Default)]
pub struct Disturbances {
    pub dryden: Option<DrydenRecord>,
    pub gusts: Vec<GustSettings>,
    /// The airspeed the field is frozen at (the trim's), m/s.
    pub airspeed_m_s: f64,
}

impl Disturbances {
    /// No disturbance at all (every region flies in still air).
    pub fn is_calm(&self) -> bool {
        self.dryden.is_none() && self.gusts.is_empty()
    }

    /// Generates what the next step up to `time_s` reads, for regions up to `lead_m` ahead.
    pub fn extend_to(&mut self, time_s: f64, lead_m: f64) {
        let ahead = lead_m.max(0.0) / self.airspeed_m_s;
        if let Some(d) = &mut self.dryden {
            d.extend_to(time_s + ahead);
        }
    }

    /// The gust velocity (body axes, m/s) at `time_s` at a point `lead_m` ahead of the centre
    /// of mass along the body x axis (frozen field: it meets now what the centre of mass meets
    /// lead/V later).
    pub fn velocity_at(&self, time_s: f64, lead_m: f64) -> Vector3<f64> {
        let t = time_s + lead_m / self.airspeed_m_s;
        let mut v = self
            .dryden
            .as_ref()
            .map_or_else(Vector3::zeros, |d| d.velocity_at(t));
        for g in &self.gusts {
            v += g.velocity_at((t - g.start_s) * self.airspeed_m_s);
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MIL-F-8785C Fig. 7 at its own rows, between them and above them.
    #[test]
    fn intensity_is_the_table() {
        let at = |h_ft: f64, p: f64| high_altitude_intensity_m_s(h_ft * FT_M, p).expect("in range");
        assert!((at(25000.0, 1e-3) - 6.6 * FT_M).abs() < 1e-12);
        assert!((at(30000.0, 1e-3) - 5.8 * FT_M).abs() < 1e-12);
        // Mach 6 at 26 km: above the table's 80 000 ft, its top value held.
        assert!(
            (high_altitude_intensity_m_s(26_000.0, 1e-5).expect("held") - 5.1 * FT_M).abs() < 1e-12
        );
        assert_eq!(high_altitude_intensity_m_s(26_000.0, 1e-3), Ok(0.0));
        assert!(high_altitude_intensity_m_s(26_000.0, 3e-3).is_err());
        assert!(high_altitude_intensity_m_s(100.0, 1e-3).is_err());
    }

    /// Each spectrum integrates to σ² (MIL-F-8785C's normalization), by the trapezoid rule on
    /// x = tan θ.
    #[test]
    fn spectra_integrate_to_the_variance() {
        let (sigma, l, v) = (1.5, HIGH_ALTITUDE_SCALE_M, 1800.0);
        for psd in [longitudinal_psd, lateral_psd] {
            let n = 200_000;
            let mut total = 0.0;
            for k in 0..n {
                let theta = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
                let x = theta.tan();
                let omega = x * v / l;
                total += psd(sigma, l, v, omega) * (v / l) / theta.cos().powi(2);
            }
            total *= std::f64::consts::FRAC_PI_2 / n as f64;
            assert!((total - sigma * sigma).abs() < 1e-6, "{total}");
        }
    }

    /// The exact discretization has the Dryden stationary variance σ² and, for u, the lag-one
    /// correlation e^{−V dt / L} (R_u(ξ) = σ² e^{−ξ/L}, MIL-F-8785C), over a long record.
    #[test]
    fn record_has_the_dryden_variance_and_correlation() {
        let (sigma, l, v, dt) = (2.0, HIGH_ALTITUDE_SCALE_M, 1800.0, 1e-3);
        let mut r = DrydenRecord::new(sigma, l, v, dt, 7).expect("valid");
        let n = 400_000;
        r.extend_to(n as f64 * dt);
        let s = &r.samples()[1000..];
        for k in 0..3 {
            let var = s.iter().map(|x| x[k] * x[k]).sum::<f64>() / s.len() as f64;
            // Correlation time L/V = 0.3 s: 400 s holds about 700 of them, ±15 % at 3σ.
            assert!((var / (sigma * sigma) - 1.0).abs() < 0.15, "{k}: {var}");
        }
        let lag = 100;
        let c = s.windows(lag + 1).map(|w| w[0].x * w[lag].x).sum::<f64>() / (s.len() - lag) as f64;
        let var = s.iter().map(|x| x.x * x.x).sum::<f64>() / s.len() as f64;
        let expected = (-v * lag as f64 * dt / l).exp();
        assert!(
            (c / var - expected).abs() < 0.05,
            "{} vs {expected}",
            c / var
        );
    }

    /// The check: the record's power spectral density, averaged over a long seeded
    /// record (Welch: 800 Hann-windowed segments of 40.96 s, so the estimate's own scatter is
    /// 3.5 %), matches the analytic Dryden spectrum within 10 % from a tenth of the corner
    /// frequency V/L to ten times it (sampled every 5 ms, which aliases 1 % onto the highest).
    #[test]
    fn record_spectrum_is_the_dryden_spectrum() {
        let (sigma, l, v, dt) = (1.5, HIGH_ALTITUDE_SCALE_M, 1800.0, 0.005);
        let (segment, segments) = (8192, 800);
        let mut r = DrydenRecord::new(sigma, l, v, dt, 11).expect("valid");
        r.extend_to((segment * segments) as f64 * dt);
        let window: Vec<f64> = (0..segment)
            .map(|k| {
                (std::f64::consts::PI * k as f64 / segment as f64)
                    .sin()
                    .powi(2)
            })
            .collect();
        let power: f64 = window.iter().map(|w| w * w).sum();
        let corner = v / l;
        for omega in [0.1, 0.3, 1.0, 3.0, 10.0].map(|f| f * corner) {
            let mut estimate = [0.0; 3];
            for s in r.samples()[1..].chunks_exact(segment).take(segments) {
                for (k, e) in estimate.iter_mut().enumerate() {
                    let (mut re, mut im) = (0.0, 0.0);
                    for (j, (x, w)) in s.iter().zip(&window).enumerate() {
                        let phase = omega * j as f64 * dt;
                        re += w * x[k] * phase.cos();
                        im -= w * x[k] * phase.sin();
                    }
                    *e += (re * re + im * im) * dt / (std::f64::consts::PI * power);
                }
            }
            for (k, e) in estimate.iter().enumerate() {
                let measured = e / segments as f64;
                let analytic = if k == 0 {
                    longitudinal_psd(sigma, l, v, omega)
                } else {
                    lateral_psd(sigma, l, v, omega)
                };
                assert!(
                    (measured / analytic - 1.0).abs() < 0.10,
                    "component {k} at {omega:.2} rad/s: {measured:.4e} vs {analytic:.4e}"
                );
            }
        }
    }

    #[test]
    fn same_seed_same_record_other_seed_other_record() {
        let make = |seed| {
            let mut r = DrydenRecord::new(1.0, 500.0, 1800.0, 1e-3, seed).expect("valid");
            r.extend_to(1.0);
            r.samples().to_vec()
        };
        assert_eq!(make(3), make(3));
        assert_ne!(make(3), make(4));
    }

    /// The 1-cosine gust: zero outside [0, 2d], its peak at d, half of it at d/2.
    #[test]
    fn one_minus_cosine_gust_has_its_closed_form() {
        let g = GustSettings {
            start_s: 1.0,
            amplitude_m_s: [0.0, 0.0, 10.0],
            half_length_m: 100.0,
        };
        assert_eq!(g.velocity_at(-1.0), Vector3::zeros());
        assert_eq!(g.velocity_at(200.1), Vector3::zeros());
        assert!((g.velocity_at(100.0).z - 10.0).abs() < 1e-12);
        assert!((g.velocity_at(50.0).z - 5.0).abs() < 1e-12);
        let d = Disturbances {
            gusts: vec![g],
            airspeed_m_s: 1000.0,
            ..Disturbances::default()
        };
        // A point 10 m ahead meets the peak 10 ms before the centre of mass.
        assert!((d.velocity_at(1.09, 10.0).z - 10.0).abs() < 1e-9);
        assert!((d.velocity_at(1.1, 0.0).z - 10.0).abs() < 1e-9);
    }
}
