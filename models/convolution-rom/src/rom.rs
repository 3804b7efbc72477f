//! The online model: the truncated convolution of the step responses with the region's modal
//! history, the interpolated correction factor and the cached steady value of the source (one file:
//! one model type and the three aero traits it implements on the same scratch buffers).

use std::path::{Path, PathBuf};
use std::time::Instant;

use hsv_core::aero::{
    AeroModel, AeroSolution, EdgeState, ModalHistory, ModalHistoryAero, PanelMotion,
};
use hsv_core::coupling::ModalProjection;
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use hsv_core::reduced_order::{CheckOptions, CheckReport, ReducedOrderAero, RomSummary};
use hsv_core::registry::{ModelContext, RegistryError, Role};
use hsv_core::structure::StructureModel;
use nalgebra::{DMatrix, DVector, Point3};

use crate::identify::{self, Identification, ResponseBlock, Subject};
use crate::{NAME, Settings};

/// The source's steady solution of the undeformed surface in its latest rigid position.
#[derive(Default)]
struct Baseline {
    flight: Option<FlightCondition>,
    vertices: Vec<Point3<f64>>,
    solution: AeroSolution,
    forces: Vec<f64>,
}

/// Buffers reused by every evaluation.
#[derive(Default)]
struct Scratch {
    /// Normalized inputs (q, q̇ / a∞).
    input: Vec<f64>,
    /// Correction factors of the forces and of the pressures, `[mode][output]`.
    force_factors: Vec<f64>,
    pressure_factors: Vec<f64>,
    /// Linear (corrected) increments over p∞.
    forces: Vec<f64>,
    pressures: Vec<f64>,
}

/// The `convolution-rom` model: its identification, its source (plain evaluations and the
/// steady value), the region's reference mesh and modes, and scratch.
pub struct ConvolutionRom {
    pub(crate) identification: Identification,
    pub(crate) source: Box<dyn AeroModel>,
    pub(crate) reference_mesh: PanelMesh,
    pub(crate) shapes: ModeShapes,
    pub(crate) projection: ModalProjection,
    pub(crate) natural_frequencies_hz: Vec<f64>,
    /// Peak vertex displacement per unit modal coordinate of each mode, m.
    pub(crate) peak_displacement_m: Vec<f64>,
    pub(crate) settings: Settings,
    /// What the identification is built from ([`identify::fingerprint`]) and where it is
    /// cached: what [`ReducedOrderAero::reidentify`] needs to rebuild it.
    fingerprint: String,
    cache: Option<PathBuf>,
    csv: Option<String>,
    gas: PerfectGas,
    from_cache: bool,
    identification_seconds: f64,
    correction: bool,
    baseline: Baseline,
    scratch: Scratch,
}

/// `[models.convolution-rom]` parsed and range-checked; the ROM cannot be its own source.
pub fn checked_settings(ctx: &ModelContext<'_>) -> Result<Settings, ModelError> {
    let settings: Settings = ctx.parse_settings()?;
    if let Some((key, value, allowed)) = settings.first_invalid() {
        return Err(ctx.settings_error(
            &key,
            format!("{value} is outside the allowed range ({allowed})"),
        ));
    }
    if settings.source == NAME {
        return Err(ctx.settings_error(
            "source",
            format!("`{NAME}` cannot be its own source; name a panel method or a plugin"),
        ));
    }
    Ok(settings)
}

/// `config --check` of the ROM: its settings, its structure's modes on the region's mesh and
/// its source model, without identifying the step responses.
pub fn check(ctx: &ModelContext<'_>) -> Result<(), ModelError> {
    let settings = checked_settings(ctx)?;
    let source = ctx.settings_for(&settings.source);
    ctx.check(Role::Aero, &settings.source, &source)
        .map_err(|e| ctx.base_model_error("source", e))?;
    if ctx.region.geometry == hsv_core::region::RegionGeometry::Mesh {
        return Ok(());
    }
    structure_modes(ctx, &settings)?;
    Ok(())
}

/// The region's structure (`settings.structure`, as the region sees its settings) and its
/// first `settings.modes` modes on the region's mesh with their natural frequencies. A region
/// the structure is not made for stays `WrongRegion`, so a check can look elsewhere.
fn structure_modes(
    ctx: &ModelContext<'_>,
    settings: &Settings,
) -> Result<(hsv_core::region::ModelSettings, ModeShapes, Vec<f64>), ModelError> {
    let structure_settings = ctx.settings_for(&settings.structure);
    let structure = ctx
        .build::<dyn StructureModel>(&settings.structure, &structure_settings)
        .map_err(|e| match e {
            RegistryError::Model(wrong @ ModelError::WrongRegion { .. }) => wrong,
            e => ctx.settings_error("structure", e.to_string()),
        })?;
    let (shapes, frequencies_hz) =
        region_modes(structure.as_ref(), &ctx.region.mesh, settings.modes)
            .map_err(|e| ctx.settings_error("modes", e.to_string()))?;
    Ok((structure_settings, shapes, frequencies_hz))
}

impl ConvolutionRom {
    /// Builds the source and the structure of the region by name through the host registry,
    /// and loads the cached identification if it was built from the same inputs, else
    /// identifies (and caches) it.
    pub fn new(ctx: &ModelContext<'_>) -> Result<Self, ModelError> {
        let settings = checked_settings(ctx)?;
        let (structure_settings, shapes, natural_frequencies_hz) = structure_modes(ctx, &settings)?;
        let mesh = ctx.region.mesh.clone();
        let source_settings = ctx.settings_for(&settings.source);
        let mut source = ctx
            .build::<dyn AeroModel>(&settings.source, &source_settings)
            .map_err(|e| ctx.settings_error("source", e.to_string()))?;
        // The region's own panels, as the partitioned vehicle sums them (a root cap tagged
        // `other` carries no generalized force); a standalone mesh counts whole.
        let kind = ctx.region.kind;
        let projection =
            ModalProjection::new(&mesh, &shapes, |r| kind == RegionKind::Other || r == kind)
                .map_err(|e| ModelError::inconsistent(NAME, e.to_string()))?;
        let csv = if settings.step_csv.is_empty() {
            None
        } else {
            Some(std::fs::read_to_string(&settings.step_csv).map_err(|e| {
                ctx.settings_error(
                    "step_csv",
                    format!("cannot read `{}`: {e}", settings.step_csv),
                )
            })?)
        };
        let fingerprint = identify::fingerprint(
            &settings,
            &source_settings.table,
            &structure_settings.table,
            &mesh,
            &shapes,
            csv.as_deref(),
            &ctx.region.gas,
        )?;
        let cache = settings.cache_path(&ctx.region.name);
        let cached = cache
            .as_deref()
            .and_then(|path| identify::load(path, &fingerprint));
        let from_cache = cached.is_some();
        let start = Instant::now();
        let identification = match cached {
            Some(identification) => identification,
            None => {
                let subject = Subject {
                    source: source.as_mut(),
                    mesh: &mesh,
                    shapes: &shapes,
                    projection: &projection,
                    gas: ctx.region.gas,
                };
                identify_and_save(&settings, subject, csv.as_deref(), &fingerprint, &cache)?
            }
        };
        let identification_seconds = if from_cache {
            0.0
        } else {
            start.elapsed().as_secs_f64()
        };
        let peak_displacement_m = identify::peak_displacements(&shapes)?;
        Ok(Self {
            correction: settings.correction && !identification.correction_mach.is_empty(),
            identification,
            source,
            reference_mesh: mesh,
            shapes,
            projection,
            natural_frequencies_hz,
            peak_displacement_m,
            settings,
            fingerprint,
            cache,
            csv,
            gas: ctx.region.gas,
            from_cache,
            identification_seconds,
            baseline: Baseline::default(),
            scratch: Scratch::default(),
        })
    }

    /// The identified step responses and correction table.
    pub fn identification(&self) -> &Identification {
        &self.identification
    }

    /// Whether the identification came from the cache file (not rebuilt).
    pub fn from_cache(&self) -> bool {
        self.from_cache
    }

    /// Turns the correction factor on or off (off: the linear convolution alone); it stays off
    /// when none was identified.
    pub fn set_correction(&mut self, on: bool) {
        self.correction = on && !self.identification.correction_mach.is_empty();
    }

    /// Whether the correction factor is applied.
    pub fn correction(&self) -> bool {
        self.correction
    }

    /// The region's natural frequencies of the ROM's modes at construction, Hz.
    pub fn natural_frequencies_hz(&self) -> &[f64] {
        &self.natural_frequencies_hz
    }

    /// The mode shapes on the region's mesh.
    pub fn mode_shapes(&self) -> &ModeShapes {
        &self.shapes
    }

    /// The region's undeformed mesh.
    pub fn reference_mesh(&self) -> &PanelMesh {
        &self.reference_mesh
    }

    /// The largest amplitude of each mode in the correction table (`max_displacement_m` of peak
    /// displacement), modal-coordinate units.
    pub fn max_amplitudes(&self) -> Vec<f64> {
        self.peak_displacement_m
            .iter()
            .map(|peak| self.settings.max_displacement_m / peak)
            .collect()
    }

    /// Settled linear generalized aerodynamic stiffness K = ∂Q/∂q and damping C = ∂Q/∂q̇
    /// (n_modes × n_modes, row: force, column: mode) at `flight`: p∞ S_q(∞) and p∞ / a∞ S_q̇(∞).
    pub fn linear_coefficients(&self, flight: &FlightCondition) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.identification.n_modes;
        let block = &self.identification.forces;
        let settled = block.samples - 1;
        let p = flight.freestream.pressure_pa;
        let a = flight.freestream.speed_of_sound_m_s;
        let stiffness = DMatrix::from_fn(n, n, |k, j| p * block.step(settled, j, 2 * n)[k]);
        let damping = DMatrix::from_fn(n, n, |k, j| p / a * block.step(settled, n + j, 2 * n)[k]);
        (stiffness, damping)
    }

    /// The source's steady solution on `rigid_mesh` at `flight`, recomputed only when either
    /// changed since the last call.
    pub(crate) fn update_baseline(
        &mut self,
        rigid_mesh: &PanelMesh,
        flight: &FlightCondition,
    ) -> Result<(), ModelError> {
        let b = &mut self.baseline;
        if b.flight.as_ref() == Some(flight) && b.vertices == rigid_mesh.vertices {
            return Ok(());
        }
        b.flight = None;
        self.source
            .evaluate(rigid_mesh, flight, &PanelMotion::default(), &mut b.solution)?;
        b.forces.resize(self.identification.n_modes, 0.0);
        self.projection
            .generalized_forces(
                &b.solution.pressure_pa,
                flight.freestream.pressure_pa,
                &mut b.forces,
            )
            .map_err(|e| ModelError::inconsistent(NAME, format!("steady value: {e}")))?;
        b.vertices.clone_from(&rigid_mesh.vertices);
        b.flight = Some(*flight);
        Ok(())
    }

    fn check_modal_inputs(
        &self,
        dt_s: f64,
        q: &DVector<f64>,
        q_dot: &DVector<f64>,
        history: &ModalHistory,
    ) -> Result<(), ModelError> {
        let n = self.identification.n_modes;
        if q.len() != n || q_dot.len() != n {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} modal coordinates and {} velocities for a ROM of {n} modes",
                    q.len(),
                    q_dot.len()
                ),
            ));
        }
        if history.input.len() != 2 * n {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "a history of {} inputs for a ROM of {} (start it with initial_history)",
                    history.input.len(),
                    2 * n
                ),
            ));
        }
        if !(dt_s.is_finite() && dt_s >= 0.0) {
            return Err(ModelError::out_of_range(
                NAME,
                "time step (s)",
                dt_s,
                "finite and >= 0",
            ));
        }
        if let Some(i) = q.iter().chain(q_dot.iter()).position(|v| !v.is_finite()) {
            let (what, index) = if i < n {
                ("modal coordinate", i)
            } else {
                ("modal velocity", i - n)
            };
            return Err(ModelError::out_of_range(
                NAME,
                &format!("{what} {}", index + 1),
                f64::NAN,
                "a finite number",
            ));
        }
        Ok(())
    }

    /// The Mach bracket of the correction table; an error outside it.
    fn mach_bracket(&self, mach: f64) -> Result<Bracket, ModelError> {
        let grid = &self.identification.correction_mach;
        let (lo, hi) = (grid[0], grid[grid.len() - 1]);
        if mach < lo - 1e-9 || mach > hi + 1e-9 {
            return Err(ModelError::out_of_range(
                NAME,
                "Mach number",
                mach,
                format!(
                    "the correction table [{lo}, {hi}] (setting correction_mach; widen it, or \
                     set correction = false)"
                ),
            ));
        }
        Ok(Bracket::of(grid, mach))
    }
}

/// Identifies from the source (or the user's CSV), stamps the identification with
/// `fingerprint` and writes it to `cache`.
fn identify_and_save(
    settings: &Settings,
    subject: Subject<'_>,
    csv: Option<&str>,
    fingerprint: &str,
    cache: &Option<PathBuf>,
) -> Result<Identification, ModelError> {
    let csv_input = csv.map(|text| (settings.step_csv.as_str(), text));
    let mut identification = identify::identify(settings, subject, csv_input)?;
    identification.fingerprint = fingerprint.to_owned();
    if let Some(path) = cache.as_deref() {
        identify::save(path, &identification)?;
    }
    Ok(identification)
}

/// The first `modes` modes of `structure` on `mesh` (0: all) and their natural frequencies.
fn region_modes(
    structure: &dyn StructureModel,
    mesh: &PanelMesh,
    modes: usize,
) -> Result<(ModeShapes, Vec<f64>), ModelError> {
    let all = structure.mode_shapes_on(mesh)?;
    all.check(mesh)
        .map_err(|e| ModelError::inconsistent(NAME, e.to_string()))?;
    let available = all.n_modes();
    let n = if modes == 0 { available } else { modes };
    if n > available || n == 0 {
        return Err(ModelError::out_of_range(
            NAME,
            "number of modes",
            n as f64,
            format!(
                "1..={available} (the modes of structure `{}`)",
                structure.name()
            ),
        ));
    }
    let frequencies = structure.natural_frequencies_hz()?;
    let shapes = ModeShapes {
        vertex_displacement: all.vertex_displacement.columns(0, n).into_owned(),
    };
    Ok((shapes, frequencies.into_iter().take(n).collect()))
}

/// Linear interpolation weights in an ascending grid, clamped to its ends.
#[derive(Debug, Clone, Copy)]
struct Bracket {
    lo: usize,
    hi: usize,
    /// Weight of `hi`.
    w: f64,
}

impl Bracket {
    fn of(grid: &[f64], x: f64) -> Self {
        let last = grid.len() - 1;
        if last == 0 || x <= grid[0] {
            return Self {
                lo: 0,
                hi: 0,
                w: 0.0,
            };
        }
        if x >= grid[last] {
            return Self {
                lo: last,
                hi: last,
                w: 0.0,
            };
        }
        let hi = grid.partition_point(|g| *g <= x).clamp(1, last);
        let lo = hi - 1;
        Self {
            lo,
            hi,
            w: (x - grid[lo]) / (grid[hi] - grid[lo]),
        }
    }
}

/// Bilinearly interpolated correction factors `[input][output]` of `block` at Mach bracket
/// `mach` and the modal coordinates `q` (amplitudes clamped to the table): the displacement
/// inputs' over Mach and amplitude, then the rate inputs' over Mach.
fn interpolate_factors(
    block: &ResponseBlock,
    amplitudes: &[Vec<f64>],
    mach: Bracket,
    q: &DVector<f64>,
    out: &mut Vec<f64>,
) {
    let n = amplitudes.len();
    let n_out = block.n_outputs;
    let n_amp = amplitudes.first().map_or(0, Vec::len);
    out.clear();
    out.resize(2 * n * n_out, 1.0);
    let at = |m: usize, j: usize, a: usize| {
        let start = ((m * n + j) * n_amp + a) * n_out;
        &block.correction[start..start + n_out]
    };
    for j in 0..n {
        let amp = Bracket::of(&amplitudes[j], q[j]);
        let corners = [
            (mach.lo, amp.lo, (1.0 - mach.w) * (1.0 - amp.w)),
            (mach.lo, amp.hi, (1.0 - mach.w) * amp.w),
            (mach.hi, amp.lo, mach.w * (1.0 - amp.w)),
            (mach.hi, amp.hi, mach.w * amp.w),
        ];
        let row = &mut out[j * n_out..(j + 1) * n_out];
        row.fill(0.0);
        for (m, a, weight) in corners {
            if weight == 0.0 {
                continue;
            }
            for (f, c) in row.iter_mut().zip(at(m, j, a)) {
                *f += weight * c;
            }
        }
    }
    if block.rate_correction.is_empty() {
        return;
    }
    let rate = |m: usize, j: usize| &block.rate_correction[(m * n + j) * n_out..][..n_out];
    for j in 0..n {
        let row = &mut out[(n + j) * n_out..(n + j + 1) * n_out];
        for ((f, lo), hi) in row.iter_mut().zip(rate(mach.lo, j)).zip(rate(mach.hi, j)) {
            *f = (1.0 - mach.w) * lo + mach.w * hi;
        }
    }
}

/// y = Σ_c f_c [S_c(∞) u_c + (S_c(0) − S_c(∞)) (u_c − u_last,c) + Σ_m (S_c(τ_m) − S_c(∞)) Δu_c,m]
/// into `out` (over p∞), f_c the correction factor of input c (1 without `factors`),
/// τ_m = (t − t_m) `lag_scale` the lags of the history's increments.
fn convolve(
    block: &ResponseBlock,
    factors: Option<&[f64]>,
    input: &[f64],
    history: &ModalHistory,
    time_s: f64,
    lag_scale: f64,
    out: &mut Vec<f64>,
) {
    let n_inputs = input.len();
    let n_out = block.n_outputs;
    let settled = block.samples - 1;
    out.clear();
    out.resize(n_out, 0.0);
    let factor = |c: usize, k: usize| factors.map_or(1.0, |f| f[c * n_out + k]);
    for (c, (&u, &last)) in input.iter().zip(&history.input).enumerate() {
        let s_inf = block.step(settled, c, n_inputs);
        let s_0 = block.step(0, c, n_inputs);
        let du = u - last;
        for (k, y) in out.iter_mut().enumerate() {
            *y += factor(c, k) * (s_inf[k] * u + (s_0[k] - s_inf[k]) * du);
        }
    }
    if settled == 0 {
        return;
    }
    for (m, &t_m) in history.increment_times_s.iter().enumerate() {
        let position = (time_s - t_m) * lag_scale / block.dt_s;
        if position.is_nan() || position >= settled as f64 {
            continue;
        }
        let i = position.floor().max(0.0) as usize;
        let w = position - i as f64;
        let increments = history.increments.range(m * n_inputs..(m + 1) * n_inputs);
        for (c, &du) in increments.enumerate() {
            if du == 0.0 {
                continue;
            }
            let (s_a, s_b) = (block.step(i, c, n_inputs), block.step(i + 1, c, n_inputs));
            let s_inf = block.step(settled, c, n_inputs);
            for (k, y) in out.iter_mut().enumerate() {
                let s = (1.0 - w) * s_a[k] + w * s_b[k];
                *y += factor(c, k) * (s - s_inf[k]) * du;
            }
        }
    }
}

/// Normalized inputs (q, q̇ / a∞) into `out`.
fn normalized_input(q: &DVector<f64>, q_dot: &DVector<f64>, sound_m_s: f64, out: &mut Vec<f64>) {
    out.clear();
    out.extend(q.iter().copied());
    out.extend(q_dot.iter().map(|v| v / sound_m_s));
}

/// Edge state of a steady panel compressed or expanded isentropically to `pressure_pa`:
/// T ∝ p^((γ−1)/γ), ρ ∝ p^(1/γ), velocity kept (NACA 1135 eqs. 43-44).
fn scaled_edge(steady: &EdgeState, pressure_pa: f64, gas: &hsv_core::gas::PerfectGas) -> EdgeState {
    if !(steady.pressure_pa > 0.0 && steady.temperature_k > 0.0) {
        return EdgeState {
            pressure_pa,
            ..*steady
        };
    }
    let ratio = pressure_pa / steady.pressure_pa;
    let temperature_k = steady.temperature_k * ratio.powf((gas.gamma - 1.0) / gas.gamma);
    EdgeState {
        mach: steady.velocity_m_s / gas.speed_of_sound(temperature_k),
        pressure_pa,
        temperature_k,
        density_kg_m3: steady.density_kg_m3 * ratio.powf(1.0 / gas.gamma),
        velocity_m_s: steady.velocity_m_s,
    }
}

impl AeroModel for ConvolutionRom {
    fn name(&self) -> &str {
        NAME
    }

    /// Without a modal history the ROM is its source: the source's (quasi-)steady pressures on
    /// the given deformed mesh.
    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        self.source.evaluate(mesh, flight, motion, out)
    }

    fn modal_history(&mut self) -> Option<&mut dyn ModalHistoryAero> {
        Some(self)
    }

    fn reduced_order(&mut self) -> Option<&mut dyn ReducedOrderAero> {
        Some(self)
    }
}

impl ReducedOrderAero for ConvolutionRom {
    fn summary(&self) -> RomSummary {
        let id = &self.identification;
        RomSummary {
            model: NAME.to_owned(),
            source: id.source.clone(),
            force_origin: id.force_origin.clone(),
            n_modes: id.n_modes,
            n_panels: id.n_panels,
            mach: id.reference.mach,
            altitude_m: id.reference.altitude_m,
            alpha_deg: id.reference.alpha_deg,
            correction_mach: id.correction_mach.clone(),
            correction_amplitudes: id.amplitudes.first().map_or(0, Vec::len),
            response_samples: id.forces.samples,
            response_dt_s: id.forces.dt_s,
            natural_frequencies_hz: self.natural_frequencies_hz.clone(),
            cache_file: self.cache.as_ref().map(|p| p.display().to_string()),
            from_cache: self.from_cache,
            identification_seconds: self.identification_seconds,
        }
    }

    fn reidentify(&mut self) -> Result<(), ModelError> {
        let start = Instant::now();
        let subject = Subject {
            source: self.source.as_mut(),
            mesh: &self.reference_mesh,
            shapes: &self.shapes,
            projection: &self.projection,
            gas: self.gas,
        };
        self.identification = identify_and_save(
            &self.settings,
            subject,
            self.csv.as_deref(),
            &self.fingerprint,
            &self.cache,
        )?;
        self.identification_seconds = start.elapsed().as_secs_f64();
        self.from_cache = false;
        self.set_correction(self.settings.correction);
        Ok(())
    }

    fn reference_flight(&self) -> Result<FlightCondition, ModelError> {
        let r = &self.identification.reference;
        let freestream = Freestream::standard(r.mach, r.altitude_m, self.gas)?;
        Ok(FlightCondition::steady(
            freestream,
            r.alpha_deg.to_radians(),
            0.0,
        ))
    }

    fn linear_coefficients(&self, flight: &FlightCondition) -> (DMatrix<f64>, DMatrix<f64>) {
        ConvolutionRom::linear_coefficients(self, flight)
    }

    fn set_correction(&mut self, on: bool) {
        ConvolutionRom::set_correction(self, on);
    }

    fn check(
        &mut self,
        flight: &FlightCondition,
        options: &CheckOptions,
    ) -> Result<CheckReport, ModelError> {
        crate::check::check_against_source(self, flight, options)
    }
}

impl ModalHistoryAero for ConvolutionRom {
    fn n_modes(&self) -> usize {
        self.identification.n_modes
    }

    fn initial_history(
        &self,
        time_s: f64,
        modal_coordinates: &DVector<f64>,
    ) -> Result<ModalHistory, ModelError> {
        let n = self.identification.n_modes;
        if modal_coordinates.len() != n || !time_s.is_finite() {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "initial history at t = {time_s} s with {} modal coordinates for a ROM of \
                     {n} modes",
                    modal_coordinates.len()
                ),
            ));
        }
        let mut input: Vec<f64> = modal_coordinates.iter().copied().collect();
        input.resize(2 * n, 0.0);
        Ok(ModalHistory {
            time_s,
            input,
            ..ModalHistory::default()
        })
    }

    fn evaluate_modal(
        &mut self,
        rigid_mesh: &PanelMesh,
        flight: &FlightCondition,
        history: &ModalHistory,
        dt_s: f64,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
        generalized_forces: &mut [f64],
        pressures: Option<&mut AeroSolution>,
    ) -> Result<(), ModelError> {
        self.check_modal_inputs(dt_s, modal_coordinates, modal_velocities, history)?;
        let n = self.identification.n_modes;
        if generalized_forces.len() != n || rigid_mesh.panels.len() != self.identification.n_panels
        {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} generalized forces and a mesh of {} panels for a ROM of {n} modes on {} \
                     panels",
                    generalized_forces.len(),
                    rigid_mesh.panels.len(),
                    self.identification.n_panels
                ),
            ));
        }
        let mach = if self.correction {
            Some(self.mach_bracket(flight.freestream.mach)?)
        } else {
            None
        };
        self.update_baseline(rigid_mesh, flight)?;
        let f = &flight.freestream;
        let time_s = history.time_s + dt_s;
        let lag_scale = f.velocity_m_s / self.identification.reference.velocity_m_s;
        let id = &self.identification;
        let s = &mut self.scratch;
        normalized_input(
            modal_coordinates,
            modal_velocities,
            f.speed_of_sound_m_s,
            &mut s.input,
        );
        if let Some(mach) = mach {
            interpolate_factors(
                &id.forces,
                &id.amplitudes,
                mach,
                modal_coordinates,
                &mut s.force_factors,
            );
        }
        let factors = mach.map(|_| s.force_factors.as_slice());
        convolve(
            &id.forces,
            factors,
            &s.input,
            history,
            time_s,
            lag_scale,
            &mut s.forces,
        );
        for (k, q) in generalized_forces.iter_mut().enumerate() {
            *q = self.baseline.forces[k] + f.pressure_pa * s.forces[k];
            if !q.is_finite() {
                return Err(ModelError::NonFinite {
                    model: NAME.to_owned(),
                    quantity: format!("generalized force {}", k + 1),
                    location: String::new(),
                });
            }
        }
        let Some(out) = pressures else {
            return Ok(());
        };
        if let Some(mach) = mach {
            interpolate_factors(
                &id.pressures,
                &id.amplitudes,
                mach,
                modal_coordinates,
                &mut s.pressure_factors,
            );
        }
        let factors = mach.map(|_| s.pressure_factors.as_slice());
        convolve(
            &id.pressures,
            factors,
            &s.input,
            history,
            time_s,
            lag_scale,
            &mut s.pressures,
        );
        let steady = &self.baseline.solution;
        out.reset(id.n_panels);
        out.diagnostics = steady.diagnostics;
        for i in 0..id.n_panels {
            let p = steady.pressure_pa[i] + f.pressure_pa * s.pressures[i];
            if !p.is_finite() {
                return Err(ModelError::non_finite_at_panel(NAME, "pressure", i));
            }
            if p > 0.0 {
                out.pressure_pa[i] = p;
                out.edge[i] = scaled_edge(&steady.edge[i], p, &f.gas);
            } else {
                // An expansion past vacuum: no gas (as the panel methods clip it).
                out.diagnostics.vacuum_expansions += 1;
            }
        }
        Ok(())
    }

    fn commit(
        &self,
        history: &mut ModalHistory,
        flight: &FlightCondition,
        dt_s: f64,
        modal_coordinates: &DVector<f64>,
        modal_velocities: &DVector<f64>,
    ) -> Result<(), ModelError> {
        self.check_modal_inputs(dt_s, modal_coordinates, modal_velocities, history)?;
        let f = &flight.freestream;
        let id = &self.identification;
        let n_inputs = id.n_inputs();
        let time_s = history.time_s + dt_s;
        let memory_s = id.forces.memory_s().max(id.pressures.memory_s());
        let lag_scale = f.velocity_m_s / id.reference.velocity_m_s;
        let mut changed = false;
        for c in 0..n_inputs {
            let u = if c < id.n_modes {
                modal_coordinates[c]
            } else {
                modal_velocities[c - id.n_modes] / f.speed_of_sound_m_s
            };
            let du = u - history.input[c];
            changed |= du != 0.0;
            if memory_s > 0.0 {
                history.increments.push_back(du);
            }
            history.input[c] = u;
        }
        if memory_s > 0.0 {
            if changed {
                history.increment_times_s.push_back(time_s);
            } else {
                history
                    .increments
                    .truncate(history.increments.len() - n_inputs);
            }
        }
        history.time_s = time_s;
        // Increments whose lag passed the responses' length contribute S(∞) − S(∞) = 0.
        while let Some(&t) = history.increment_times_s.front() {
            if (time_s - t) * lag_scale < memory_s {
                break;
            }
            history.increment_times_s.pop_front();
            history.increments.drain(..n_inputs);
        }
        Ok(())
    }
}

/// Loads a cached identification without building the ROM (for `hsv-run rom` reports).
pub fn read_cache(path: &Path) -> Result<Identification, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        ModelError::inconsistent(NAME, format!("cannot read `{}`: {e}", path.display()))
    })?;
    serde_json::from_str(&text).map_err(|e| {
        ModelError::inconsistent(
            NAME,
            format!("`{}` is not a ROM cache: {e}", path.display()),
        )
    })
}
