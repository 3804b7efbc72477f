//! The identification: the source aero model's step responses by central differences, the
//! correction-factor tables, and the `Identification` the online model reads. The step-response
//! CSV import is in `step_csv.rs`, the fingerprint and JSON cache in `cache.rs` (their public
//! items are re-exported here).

use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::coupling::ModalProjection;
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{ModeShapes, PanelMesh};
use nalgebra::{DVector, Vector3};

use crate::{NAME, Settings};

pub use crate::cache::FORMAT;
pub(crate) use crate::cache::{fingerprint, load, save};
pub use crate::step_csv::{CSV_COLUMNS, read_step_csv};

/// The flight condition the step responses were identified at.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReferenceCondition {
    pub mach: f64,
    pub altitude_m: f64,
    pub alpha_deg: f64,
    /// Freestream static pressure p∞, Pa.
    pub pressure_pa: f64,
    /// Freestream speed of sound a∞, m/s.
    pub speed_of_sound_m_s: f64,
    /// Airspeed V∞, m/s.
    pub velocity_m_s: f64,
}

impl ReferenceCondition {
    /// The condition of `settings` in `gas`.
    pub fn new(settings: &Settings, gas: PerfectGas) -> Result<Self, ModelError> {
        let f = Freestream::standard(settings.mach, settings.altitude_m, gas)?;
        Ok(Self {
            mach: settings.mach,
            altitude_m: settings.altitude_m,
            alpha_deg: settings.alpha_deg,
            pressure_pa: f.pressure_pa,
            speed_of_sound_m_s: f.speed_of_sound_m_s,
            velocity_m_s: f.velocity_m_s,
        })
    }
}

/// Steady flight at Mach `mach`, the identification altitude and angle of attack.
fn flight_at(
    reference: &ReferenceCondition,
    mach: f64,
    gas: PerfectGas,
) -> Result<FlightCondition, ModelError> {
    let f = Freestream::standard(mach, reference.altitude_m, gas)?;
    Ok(FlightCondition::steady(
        f,
        reference.alpha_deg.to_radians(),
        0.0,
    ))
}

/// Step responses and correction factors of one group of outputs (the generalized forces, or
/// the panel gauge pressures).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ResponseBlock {
    pub n_outputs: usize,
    /// Sample interval of the step responses, s at the reference airspeed (0: one sample).
    pub dt_s: f64,
    /// Samples per step response; settled from the last one on.
    pub samples: usize,
    /// Step responses over p∞ per unit (normalized) input, `[sample][input][output]`.
    pub steps: Vec<f64>,
    /// Correction factors `[mach][mode][amplitude][output]`; empty without correction.
    pub correction: Vec<f64>,
    /// Mach correction of the rate responses `[mach][mode][output]` (`tabulate_rate_correction`);
    /// empty without correction.
    pub rate_correction: Vec<f64>,
}

impl ResponseBlock {
    pub(crate) fn zeros(n_outputs: usize, n_inputs: usize, samples: usize, dt_s: f64) -> Self {
        Self {
            n_outputs,
            dt_s,
            samples,
            steps: vec![0.0; samples * n_inputs * n_outputs],
            correction: Vec::new(),
            rate_correction: Vec::new(),
        }
    }

    /// The response of every output to a unit step of `input`, `sample` samples after the step.
    pub fn step(&self, sample: usize, input: usize, n_inputs: usize) -> &[f64] {
        let start = (sample * n_inputs + input) * self.n_outputs;
        &self.steps[start..start + self.n_outputs]
    }

    pub(crate) fn step_mut(&mut self, sample: usize, input: usize, n_inputs: usize) -> &mut [f64] {
        let start = (sample * n_inputs + input) * self.n_outputs;
        &mut self.steps[start..start + self.n_outputs]
    }

    /// How long the responses remember an input, s at the reference airspeed.
    pub fn memory_s(&self) -> f64 {
        self.dt_s * self.samples.saturating_sub(1) as f64
    }
}

/// Everything the online model needs; what the cache file holds.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Identification {
    pub format: u32,
    /// What it was built from (`fingerprint`); a mismatch forces a rebuild.
    pub fingerprint: String,
    /// The source aero model.
    pub source: String,
    /// Where the generalized-force step responses come from: `source` or the CSV path.
    pub force_origin: String,
    pub n_modes: usize,
    pub n_panels: usize,
    pub reference: ReferenceCondition,
    /// Mach numbers of the correction table; empty without correction.
    pub correction_mach: Vec<f64>,
    /// Amplitudes of the correction table, `[mode][amplitude]`, ascending, modal-coordinate
    /// units (± `amplitude_points` values up to `max_displacement_m` of peak displacement, and
    /// zero).
    pub amplitudes: Vec<Vec<f64>>,
    /// Generalized forces over p∞.
    pub forces: ResponseBlock,
    /// Panel gauge pressures (p − p∞) over p∞.
    pub pressures: ResponseBlock,
}

impl Identification {
    /// Inputs: modal coordinates, then modal velocities over a∞.
    pub fn n_inputs(&self) -> usize {
        2 * self.n_modes
    }

    /// Every array as long as the counts say (a cache can be edited; the online model indexes
    /// without checks).
    pub fn check_shapes(&self) -> Result<(), String> {
        let n_amp = self.amplitudes.first().map_or(0, Vec::len);
        if self.amplitudes.iter().any(|a| a.len() != n_amp)
            || !(self.amplitudes.is_empty() || self.amplitudes.len() == self.n_modes)
        {
            return Err(format!(
                "amplitude table of {} rows for {} modes, rows of unequal length",
                self.amplitudes.len(),
                self.n_modes
            ));
        }
        let n_mach = self.correction_mach.len();
        for (name, block, n_outputs) in [
            ("forces", &self.forces, self.n_modes),
            ("pressures", &self.pressures, self.n_panels),
        ] {
            let steps = block.samples * self.n_inputs() * block.n_outputs;
            let correction = n_mach * self.n_modes * n_amp * block.n_outputs;
            let rate = n_mach * self.n_modes * block.n_outputs;
            if block.n_outputs != n_outputs
                || block.samples == 0
                || block.steps.len() != steps
                || !(block.correction.is_empty() || block.correction.len() == correction)
                || !(block.rate_correction.is_empty() || block.rate_correction.len() == rate)
            {
                return Err(format!(
                    "{name}: {} outputs (expected {n_outputs}), {} samples, {} step entries                      (expected {steps}), {} correction entries (expected 0 or {correction}), {}                      rate-correction entries (expected 0 or {rate})",
                    block.n_outputs,
                    block.samples,
                    block.steps.len(),
                    block.correction.len(),
                    block.rate_correction.len()
                ));
            }
        }
        Ok(())
    }
}

/// Peak vertex displacement of each mode per unit modal coordinate, m; an error names a mode
/// that does not move the mesh.
pub fn peak_displacements(shapes: &ModeShapes) -> Result<Vec<f64>, ModelError> {
    let phi = &shapes.vertex_displacement;
    (0..shapes.n_modes())
        .map(|k| {
            let column = phi.column(k);
            let peak = column
                .as_slice()
                .chunks_exact(3)
                .map(|d| Vector3::new(d[0], d[1], d[2]).norm())
                .fold(0.0, f64::max);
            if peak.is_finite() && peak > 0.0 {
                Ok(peak)
            } else {
                Err(ModelError::inconsistent(
                    NAME,
                    format!(
                        "mode {} has peak displacement {peak} m on the region's mesh; every mode \
                         must move it",
                        k + 1
                    ),
                ))
            }
        })
        .collect()
}

/// Runs the source on the deformed reference mesh: scratch for its deformed mesh, panel
/// velocities and solution.
#[derive(Default)]
pub(crate) struct SourceProbe {
    deformed: PanelMesh,
    velocities: Vec<Vector3<f64>>,
    solution: AeroSolution,
    forces: Vec<f64>,
}

impl SourceProbe {
    /// The source's outputs over p∞ at modal coordinates `q` and velocities `q_dot`:
    /// [Q/p∞; (p − p∞)/p∞], Q = −P (p − p∞) on the reference geometry.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn outputs(
        &mut self,
        source: &mut dyn AeroModel,
        base: &PanelMesh,
        shapes: &ModeShapes,
        projection: &ModalProjection,
        flight: &FlightCondition,
        q: &DVector<f64>,
        q_dot: &DVector<f64>,
        out: &mut Vec<f64>,
    ) -> Result<(), ModelError> {
        shapes.deform(base, q, &mut self.deformed);
        self.velocities.resize(base.panels.len(), Vector3::zeros());
        shapes.panel_velocities(base, q_dot, &mut self.velocities);
        let motion = PanelMotion {
            elastic_velocity_m_s: Some(&self.velocities),
        };
        source.evaluate(&self.deformed, flight, &motion, &mut self.solution)?;
        let p_inf = flight.freestream.pressure_pa;
        self.forces.resize(projection.n_modes(), 0.0);
        projection
            .generalized_forces(&self.solution.pressure_pa, p_inf, &mut self.forces)
            .map_err(|e| {
                ModelError::inconsistent(NAME, format!("source `{}`: {e}", source.name()))
            })?;
        out.clear();
        out.extend(self.forces.iter().map(|q| q / p_inf));
        out.extend(
            self.solution
                .pressure_pa
                .iter()
                .map(|p| (p - p_inf) / p_inf),
        );
        Ok(())
    }
}

/// What identification runs on: the source and the region's reference mesh, modes and
/// projection.
pub(crate) struct Subject<'a> {
    pub source: &'a mut dyn AeroModel,
    pub mesh: &'a PanelMesh,
    pub shapes: &'a ModeShapes,
    pub projection: &'a ModalProjection,
    pub gas: PerfectGas,
}

/// Identifies the ROM: quasi-steady step responses of the source by central differences, the
/// user's force step responses if `csv` = (path, contents) is given, and the correction table.
pub(crate) fn identify(
    settings: &Settings,
    subject: Subject<'_>,
    csv: Option<(&str, &str)>,
) -> Result<Identification, ModelError> {
    let reference = ReferenceCondition::new(settings, subject.gas)?;
    let flight = flight_at(&reference, reference.mach, subject.gas)?;
    let n = subject.shapes.n_modes();
    let n_panels = subject.mesh.panels.len();
    let n_inputs = 2 * n;
    let peaks = peak_displacements(subject.shapes)?;
    let mut probe = SourceProbe::default();
    let mut forces = ResponseBlock::zeros(n, n_inputs, 1, 0.0);
    let mut pressures = ResponseBlock::zeros(n_panels, n_inputs, 1, 0.0);
    let (mut plus, mut minus) = (Vec::new(), Vec::new());
    let zero = DVector::zeros(n);
    for input in 0..n_inputs {
        let mode = input % n;
        let is_rate = input >= n;
        // Modal step ε (coordinate or velocity) and the normalized input step it makes.
        let (step, input_step) = if is_rate {
            let e = settings.step_velocity_m_s / peaks[mode];
            (e, e / reference.speed_of_sound_m_s)
        } else {
            let e = settings.step_displacement_m / peaks[mode];
            (e, e)
        };
        let mut delta = zero.clone();
        for (sign, out) in [(1.0, &mut plus), (-1.0, &mut minus)] {
            delta[mode] = sign * step;
            let (q, q_dot) = if is_rate {
                (&zero, &delta)
            } else {
                (&delta, &zero)
            };
            probe.outputs(
                subject.source,
                subject.mesh,
                subject.shapes,
                subject.projection,
                &flight,
                q,
                q_dot,
                out,
            )?;
        }
        let derivative = |k: usize| (plus[k] - minus[k]) / (2.0 * input_step);
        for (k, s) in forces.step_mut(0, input, n_inputs).iter_mut().enumerate() {
            *s = derivative(k);
        }
        for (k, s) in pressures
            .step_mut(0, input, n_inputs)
            .iter_mut()
            .enumerate()
        {
            *s = derivative(n + k);
        }
    }
    check_finite_block(&forces, "generalized-force step response")?;
    check_finite_block(&pressures, "pressure step response")?;
    let mut identification = Identification {
        format: FORMAT,
        fingerprint: String::new(),
        source: subject.source.name().to_owned(),
        force_origin: "source".to_owned(),
        n_modes: n,
        n_panels,
        reference,
        correction_mach: Vec::new(),
        amplitudes: Vec::new(),
        forces,
        pressures,
    };
    if settings.correction {
        tabulate_correction(settings, &mut identification, &peaks, subject, &mut probe)?;
    }
    if let Some((path, text)) = csv {
        let mut block = read_step_csv(path, text, n, &identification.reference)?;
        block.correction = std::mem::take(&mut identification.forces.correction);
        block.rate_correction = std::mem::take(&mut identification.forces.rate_correction);
        identification.forces = block;
        identification.force_origin = path.to_owned();
    }
    Ok(identification)
}

fn check_finite_block(block: &ResponseBlock, quantity: &str) -> Result<(), ModelError> {
    match block.steps.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(ModelError::NonFinite {
            model: NAME.to_owned(),
            quantity: quantity.to_owned(),
            location: format!(" (entry {i} of the identification)"),
        }),
    }
}

/// c = (F(a e_j) − F(0)) / (S_j a) per output: the source's nonlinear steady response to a
/// static deflection a of mode j over its own linear prediction, at every Mach number of the
/// table (Skujins & Cesnik's nonlinear correction factor). At a = 0 the factor is its limit,
/// F'(0) / S_j: the source's linear response at that Mach (central differences with the
/// identification step) over the identification's, 1 at the identification Mach, so the ROM
/// linearized about the undeformed surface is the source's linearization at every Mach of the
/// table. Outputs whose linear prediction is below 1e-6 of their largest one get 1 (the ratio
/// is then round-off over round-off).
fn tabulate_correction(
    settings: &Settings,
    identification: &mut Identification,
    peaks: &[f64],
    mut subject: Subject<'_>,
    probe: &mut SourceProbe,
) -> Result<(), ModelError> {
    let n = identification.n_modes;
    let n_inputs = identification.n_inputs();
    let points = settings.amplitude_points;
    identification.amplitudes = peaks
        .iter()
        .map(|peak| {
            let top = settings.max_displacement_m / peak;
            let mut a: Vec<f64> = (1..=points)
                .map(|i| -top * (points + 1 - i) as f64 / points as f64)
                .collect();
            a.push(0.0);
            a.extend((1..=points).map(|i| top * i as f64 / points as f64));
            a
        })
        .collect();
    let n_amplitudes = 2 * points + 1;
    let n_out = n + identification.n_panels;
    // Linear predictions S_j a, [mode][amplitude][output], and each output's largest.
    let linear = |j: usize, a: f64, k: usize| {
        let block = if k < n {
            identification.forces.step(0, j, n_inputs)[k]
        } else {
            identification.pressures.step(0, j, n_inputs)[k - n]
        };
        block * a
    };
    let mut scale = vec![0.0f64; n_out];
    for (j, amplitudes) in identification.amplitudes.iter().enumerate() {
        for &a in amplitudes {
            for (k, s) in scale.iter_mut().enumerate() {
                *s = s.max(linear(j, a, k).abs());
            }
        }
    }
    let n_mach = settings.correction_mach.len();
    let mut force_factors = vec![1.0; n_mach * n * n_amplitudes * n];
    let mut pressure_factors = vec![1.0; n_mach * n * n_amplitudes * identification.n_panels];
    let (mut base, mut deflected, mut minus) = (Vec::new(), Vec::new(), Vec::new());
    let zero = DVector::zeros(n);
    for (m, &mach) in settings.correction_mach.iter().enumerate() {
        let flight = flight_at(&identification.reference, mach, subject.gas)?;
        let source = &mut *subject.source;
        probe.outputs(
            source,
            subject.mesh,
            subject.shapes,
            subject.projection,
            &flight,
            &zero,
            &zero,
            &mut base,
        )?;
        for j in 0..n {
            let top = identification.amplitudes[j][n_amplitudes - 1];
            for (ia, &a) in identification.amplitudes[j].iter().enumerate() {
                // At zero amplitude: the central difference ±ε of the identification.
                let (a_eval, a_lin) = if a == 0.0 {
                    (settings.step_displacement_m / peaks[j], None)
                } else {
                    (a, Some(a))
                };
                let mut q = zero.clone();
                q[j] = a_eval;
                let mut evaluate = |q: &DVector<f64>, out: &mut Vec<f64>| {
                    probe.outputs(
                        &mut *source,
                        subject.mesh,
                        subject.shapes,
                        subject.projection,
                        &flight,
                        q,
                        &zero,
                        out,
                    )
                };
                evaluate(&q, &mut deflected)?;
                if a_lin.is_none() {
                    q[j] = -a_eval;
                    evaluate(&q, &mut minus)?;
                }
                for k in 0..n_out {
                    let factor = match a_lin {
                        _ if linear(j, top, k).abs() <= 1e-6 * scale[k] => 1.0,
                        Some(a) => (deflected[k] - base[k]) / linear(j, a, k),
                        None => (deflected[k] - minus[k]) / (2.0 * linear(j, a_eval, k)),
                    };
                    if !factor.is_finite() {
                        return Err(ModelError::NonFinite {
                            model: NAME.to_owned(),
                            quantity: "correction factor".to_owned(),
                            location: format!(" (Mach {mach}, mode {}, amplitude {a})", j + 1),
                        });
                    }
                    if k < n {
                        force_factors[((m * n + j) * n_amplitudes + ia) * n + k] = factor;
                    } else {
                        let n_p = identification.n_panels;
                        pressure_factors[((m * n + j) * n_amplitudes + ia) * n_p + k - n] = factor;
                    }
                }
            }
        }
    }
    identification.correction_mach = settings.correction_mach.clone();
    identification.forces.correction = force_factors;
    identification.pressures.correction = pressure_factors;
    tabulate_rate_correction(settings, identification, peaks, &mut subject, probe)
}

/// c_rate = F'_q̇(M) / S_q̇ per output and mode: the source's linear response to the modal
/// velocity at each Mach number of the table (central differences ±ε̇ on the undeformed
/// surface) over the identification's, 1 at the identification Mach. Piston theory's rate
/// term γ [1 + (γ+1)/2 μ₀ + …] (μ₀ = M θ₀ the steady piston Mach number of a sloped panel,
/// Lighthill 1953) changes with M on a wedge, so without it the ROM's aerodynamic damping
/// would keep the identification Mach's. Outputs with a negligible rate response get 1.
fn tabulate_rate_correction(
    settings: &Settings,
    identification: &mut Identification,
    peaks: &[f64],
    subject: &mut Subject<'_>,
    probe: &mut SourceProbe,
) -> Result<(), ModelError> {
    let n = identification.n_modes;
    let n_inputs = identification.n_inputs();
    let n_panels = identification.n_panels;
    let n_out = n + n_panels;
    let linear = |j: usize, k: usize| {
        if k < n {
            identification.forces.step(0, n + j, n_inputs)[k]
        } else {
            identification.pressures.step(0, n + j, n_inputs)[k - n]
        }
    };
    let scale: Vec<f64> = (0..n_out)
        .map(|k| (0..n).map(|j| linear(j, k).abs()).fold(0.0, f64::max))
        .collect();
    let n_mach = settings.correction_mach.len();
    let mut force_factors = vec![1.0; n_mach * n * n];
    let mut pressure_factors = vec![1.0; n_mach * n * n_panels];
    let (mut plus, mut minus) = (Vec::new(), Vec::new());
    let zero = DVector::zeros(n);
    for (m, &mach) in settings.correction_mach.iter().enumerate() {
        let flight = flight_at(&identification.reference, mach, subject.gas)?;
        let sound = flight.freestream.speed_of_sound_m_s;
        for j in 0..n {
            let step = settings.step_velocity_m_s / peaks[j];
            let mut q_dot = zero.clone();
            for (sign, out) in [(1.0, &mut plus), (-1.0, &mut minus)] {
                q_dot[j] = sign * step;
                probe.outputs(
                    &mut *subject.source,
                    subject.mesh,
                    subject.shapes,
                    subject.projection,
                    &flight,
                    &zero,
                    &q_dot,
                    out,
                )?;
            }
            for k in 0..n_out {
                let lin = linear(j, k);
                let factor = if lin.abs() > 1e-6 * scale[k] {
                    (plus[k] - minus[k]) / (2.0 * step / sound * lin)
                } else {
                    1.0
                };
                if !factor.is_finite() {
                    return Err(ModelError::NonFinite {
                        model: NAME.to_owned(),
                        quantity: "rate correction factor".to_owned(),
                        location: format!(" (Mach {mach}, mode {})", j + 1),
                    });
                }
                if k < n {
                    force_factors[(m * n + j) * n + k] = factor;
                } else {
                    pressure_factors[(m * n + j) * n_panels + k - n] = factor;
                }
            }
        }
    }
    identification.forces.rate_correction = force_factors;
    identification.pressures.rate_correction = pressure_factors;
    Ok(())
}
