//! The ROM against its source on prescribed modal motion: one sinusoid per mode at its natural
//! frequency, and a random multi-mode motion; errors of the generalized forces and the speed-up
//! (what `hsv-run rom check` reports).

use std::time::Instant;

use hsv_core::aero::{AeroSolution, ModalHistoryAero};
use hsv_core::error::ModelError;
use hsv_core::flow::FlightCondition;
pub use hsv_core::reduced_order::{CheckOptions, CheckReport, MotionReport};
use nalgebra::DVector;

use crate::identify::SourceProbe;
use crate::{ConvolutionRom, NAME};

/// Sum of sinusoids per mode: q_j(t) = Σ A sin(ω t + φ).
struct Motion {
    name: String,
    /// Per mode: (amplitude, ω rad/s, phase rad).
    terms: Vec<Vec<(f64, f64, f64)>>,
    dt_s: f64,
    steps: usize,
}

impl Motion {
    fn state(&self, t: f64, q: &mut DVector<f64>, q_dot: &mut DVector<f64>) {
        for (j, terms) in self.terms.iter().enumerate() {
            q[j] = terms.iter().map(|(a, w, p)| a * (w * t + p).sin()).sum();
            q_dot[j] = terms
                .iter()
                .map(|(a, w, p)| a * w * (w * t + p).cos())
                .sum();
        }
    }
}

/// xorshift64* (Vigna, "An experimental exploration of Marsaglia's xorshift generators,
/// scrambled", ACM TOMS 42(4), 2016): uniform numbers in [0, 1).
struct Xorshift(u64);

impl Xorshift {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The check's motions at speed of sound `sound_m_s`. Each mode alone moves at
/// `amplitude_fraction` of the correction table's largest amplitude, lowered where its peak
/// vertex velocity would pass `max_velocity_ratio` a∞. In the random motion every mode takes
/// 30-100 % of that, scaled down together so that the sums of the modes' peak displacements and
/// peak velocities stay within the single-mode limits: no point of the surface moves further
/// or faster than in the single-mode motions.
fn motions(
    rom: &ConvolutionRom,
    options: &CheckOptions,
    sound_m_s: f64,
) -> Result<Vec<Motion>, ModelError> {
    let frequencies = rom.natural_frequencies_hz();
    let two_pi = std::f64::consts::TAU;
    let peak = &rom.peak_displacement_m;
    let max_displacement_m = options.amplitude_fraction * rom.settings.max_displacement_m;
    let max_velocity_m_s = options
        .max_velocity_ratio
        .map_or(f64::INFINITY, |r| r * sound_m_s);
    let amplitudes: Vec<f64> = (0..peak.len())
        .map(|j| {
            let by_velocity = max_velocity_m_s / (two_pi * frequencies[j] * peak[j]);
            (max_displacement_m / peak[j]).min(by_velocity)
        })
        .collect();
    if let Some(&f) = frequencies.iter().find(|f| !(f.is_finite() && **f > 0.0)) {
        return Err(ModelError::out_of_range(
            NAME,
            "natural frequency (Hz) of the check motion",
            f,
            "finite and > 0",
        ));
    }
    let n = amplitudes.len();
    let steps_for = |f_min: f64, f_max: f64| {
        let dt = 1.0 / (options.steps_per_period as f64 * f_max);
        (dt, (options.periods / f_min / dt).ceil() as usize)
    };
    let mut out = Vec::with_capacity(n + 1);
    for j in 0..n {
        let mut terms = vec![Vec::new(); n];
        terms[j].push((amplitudes[j], two_pi * frequencies[j], 0.0));
        let (dt_s, steps) = steps_for(frequencies[j], frequencies[j]);
        out.push(Motion {
            name: format!("mode {} at {:.3} Hz", j + 1, frequencies[j]),
            terms,
            dt_s,
            steps,
        });
    }
    // Every mode at once: random amplitude (30-100 % of the mode's), frequency (0.8-1.2 of its
    // natural frequency) and phase.
    let mut random = Xorshift(options.seed.max(1));
    let mut terms = Vec::with_capacity(n);
    let (mut f_min, mut f_max) = (f64::INFINITY, 0.0f64);
    for j in 0..n {
        let a = amplitudes[j] * (0.3 + 0.7 * random.uniform());
        let f = frequencies[j] * (0.8 + 0.4 * random.uniform());
        let phase = two_pi * random.uniform();
        terms.push(vec![(a, two_pi * f, phase)]);
        f_min = f_min.min(f);
        f_max = f_max.max(f);
    }
    let sum = |rate: bool| -> f64 {
        terms
            .iter()
            .zip(peak)
            .map(|(t, p)| t[0].0 * p * if rate { t[0].1 } else { 1.0 })
            .sum()
    };
    let scale = (max_displacement_m / sum(false))
        .min(max_velocity_m_s / sum(true))
        .min(1.0);
    for t in &mut terms {
        t[0].0 *= scale;
    }
    let (dt_s, steps) = steps_for(f_min, f_max);
    out.push(Motion {
        name: "random multi-mode".to_owned(),
        terms,
        dt_s,
        steps,
    });
    Ok(out)
}

/// Runs the ROM and its own source side by side on each prescribed motion at `flight`.
///
/// The source sees what a coupled run would give it: the reference mesh deformed by Φ q, the
/// elastic panel velocities Φ q̇, and generalized forces by the reference-geometry projection.
/// The ROM starts from a history at rest at q(0) and is committed every step.
pub fn check_against_source(
    rom: &mut ConvolutionRom,
    flight: &FlightCondition,
    options: &CheckOptions,
) -> Result<CheckReport, ModelError> {
    if !(options.periods.is_finite() && options.periods > 0.0)
        || options.steps_per_period < 2
        || !(options.amplitude_fraction.is_finite() && options.amplitude_fraction >= 0.0)
        || options
            .max_velocity_ratio
            .is_some_and(|r| !(r.is_finite() && r > 0.0))
    {
        return Err(ModelError::inconsistent(
            NAME,
            format!(
                "check options: periods {} (> 0), steps_per_period {} (>= 2), \
                 amplitude_fraction {} (>= 0), max_velocity_ratio {:?} (> 0 or none)",
                options.periods,
                options.steps_per_period,
                options.amplitude_fraction,
                options.max_velocity_ratio
            ),
        ));
    }
    let n = rom.identification.n_modes;
    let rigid = rom.reference_mesh.clone();
    let p_inf = flight.freestream.pressure_pa;
    let mut probe = SourceProbe::default();
    let mut outputs = Vec::new();
    let (mut q, mut q_dot) = (DVector::zeros(n), DVector::zeros(n));
    probe.outputs(
        rom.source.as_mut(),
        &rom.reference_mesh,
        &rom.shapes,
        &rom.projection,
        flight,
        &q,
        &q_dot,
        &mut outputs,
    )?;
    let rest: Vec<f64> = outputs[..n].iter().map(|v| v * p_inf).collect();
    // The steady value is computed once per flight condition and rigid position: time it apart.
    let start = Instant::now();
    rom.update_baseline(&rigid, flight)?;
    let steady_value_seconds = start.elapsed().as_secs_f64();
    let mut reports = Vec::new();
    let mut rom_forces = vec![0.0; n];
    let mut rom_pressures = AeroSolution::default();
    for motion in motions(rom, options, flight.freestream.speed_of_sound_m_s)? {
        motion.state(0.0, &mut q, &mut q_dot);
        let mut history = rom.initial_history(0.0, &q)?;
        let (mut source_time, mut rom_time) = (0.0, 0.0);
        let mut report = MotionReport {
            name: motion.name.clone(),
            relative_rms_error: 0.0,
            relative_max_error: 0.0,
            steps: motion.steps,
            dt_s: motion.dt_s,
            source_seconds_per_step: 0.0,
            rom_seconds_per_step: 0.0,
            speedup: 0.0,
            time_s: Vec::with_capacity(motion.steps),
            source_generalized_forces: Vec::with_capacity(motion.steps),
            rom_generalized_forces: Vec::with_capacity(motion.steps),
        };
        let (mut error2, mut signal2, mut error_max, mut signal_max) = (0.0, 0.0, 0.0f64, 0.0f64);
        for step in 1..=motion.steps {
            let t = step as f64 * motion.dt_s;
            motion.state(t, &mut q, &mut q_dot);
            let start = Instant::now();
            probe.outputs(
                rom.source.as_mut(),
                &rom.reference_mesh,
                &rom.shapes,
                &rom.projection,
                flight,
                &q,
                &q_dot,
                &mut outputs,
            )?;
            source_time += start.elapsed().as_secs_f64();
            let start = Instant::now();
            rom.evaluate_modal(
                &rigid,
                flight,
                &history,
                motion.dt_s,
                &q,
                &q_dot,
                &mut rom_forces,
                options.pressures.then_some(&mut rom_pressures),
            )?;
            rom.commit(&mut history, flight, motion.dt_s, &q, &q_dot)?;
            rom_time += start.elapsed().as_secs_f64();
            let source: Vec<f64> = outputs[..n].iter().map(|v| v * p_inf).collect();
            for k in 0..n {
                let e = rom_forces[k] - source[k];
                let s = source[k] - rest[k];
                error2 += e * e;
                signal2 += s * s;
                error_max = error_max.max(e.abs());
                signal_max = signal_max.max(s.abs());
            }
            report.time_s.push(t);
            report.source_generalized_forces.push(source);
            report.rom_generalized_forces.push(rom_forces.clone());
        }
        if !signal2.is_finite() || signal2 <= 0.0 {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{}: the source's generalized forces do not change with the motion (zero \
                     amplitude?), so no relative error can be formed",
                    motion.name
                ),
            ));
        }
        report.relative_rms_error = (error2 / signal2).sqrt();
        report.relative_max_error = error_max / signal_max;
        let steps = motion.steps.max(1) as f64;
        report.source_seconds_per_step = source_time / steps;
        report.rom_seconds_per_step = rom_time / steps;
        report.speedup = source_time / rom_time.max(f64::MIN_POSITIVE);
        reports.push(report);
    }
    Ok(CheckReport {
        mach: flight.freestream.mach,
        altitude_m: flight.freestream.altitude_m,
        alpha_deg: flight.alpha_rad.to_degrees(),
        correction: rom.correction(),
        steady_value_seconds,
        motions: reports,
    })
}
