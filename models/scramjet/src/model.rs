//! The propulsion model proper: the engine evaluated on spanwise sections of the deformed body
//! mesh, sectional loads fitted across the span by quadratic least squares and integrated, and
//! the fitted pressures written to the engine-owned panels.

use hsv_core::aero::{Loads, PanelMotion, check_panel_method_inputs};
use hsv_core::error::ModelError;
use hsv_core::propulsion::{
    EngineInputs, EngineStatus, PropulsionModel, PropulsionSolution, StationState,
};
use nalgebra::{Point2, Point3, Vector3};

use crate::geometry::{EngineSurfaces, SectionGeometry};
use crate::section::{SectionConditions, SectionSolution};
use crate::span::{SpanFit, apply};

/// One engine model on one two-dimensional section.
pub trait SectionEngine: Send {
    /// Registered name.
    fn name(&self) -> &'static str;

    /// Solves one section into `out` (buffers reused).
    fn solve(
        &self,
        geometry: &SectionGeometry,
        conditions: &SectionConditions<'_>,
        out: &mut SectionSolution,
    ) -> Result<(), ModelError>;
}

/// Buffers reused between evaluations.
#[derive(Debug, Clone, Default)]
struct Scratch {
    surfaces: EngineSurfaces,
    geometry: SectionGeometry,
    /// The polylines of the last section solved (its `y_m` is not kept).
    solved: SectionGeometry,
    sections: Vec<SectionSolution>,
    station_y_m: Vec<f64>,
    fit: SpanFit,
    weights: Vec<f64>,
}

/// A scramjet on `strips` spanwise sections (paper §III.E).
#[derive(Debug, Clone)]
pub struct Scramjet<E> {
    engine: E,
    strips: usize,
    reference_m: Point3<f64>,
    scratch: Scratch,
}

/// Largest distance, m, at which two sections' points count as the same: rounding of the
/// mesh's coordinates (about 1e-15 m on a 30 m body; the sample vehicle's sections differ by
/// 2e-15 m) and nothing a flow can resolve.
const SAME_POINT_M: f64 = 1e-12;

/// Whether `a` and `b` have the same ramp, cowl and nozzle polylines, point by point within
/// [`SAME_POINT_M`].
fn same_polylines(a: &SectionGeometry, b: &SectionGeometry) -> bool {
    let same = |p: &[Point2<f64>], q: &[Point2<f64>]| {
        p.len() == q.len()
            && p.iter().zip(q).all(|(p, q)| {
                (p.x - q.x).abs() <= SAME_POINT_M && (p.y - q.y).abs() <= SAME_POINT_M
            })
    };
    same(&a.ramp_m, &b.ramp_m) && same(&a.cowl_m, &b.cowl_m) && same(&a.nozzle_m, &b.nozzle_m)
}

/// Severity order of the engine states: a vehicle's engine is as bad as its worst section.
fn severity(status: EngineStatus) -> u8 {
    match status {
        EngineStatus::Ok => 0,
        EngineStatus::Spillage => 1,
        EngineStatus::ThermalChoking => 2,
        EngineStatus::Unstart => 3,
    }
}

impl<E: SectionEngine> Scramjet<E> {
    /// `engine` on `strips ≥ 3` equal-width spanwise sections, moments about `reference_m`.
    pub fn new(engine: E, strips: usize, reference_m: Point3<f64>) -> Self {
        Self {
            engine,
            strips: strips.max(3),
            reference_m,
            scratch: Scratch::default(),
        }
    }

    /// The section engine.
    pub fn engine(&self) -> &E {
        &self.engine
    }

    /// Spanwise positions of the sections of the last evaluation, m.
    pub fn section_positions_m(&self) -> &[f64] {
        &self.scratch.station_y_m
    }

    /// Section results of the last evaluation, in spanwise order.
    pub fn sections(&self) -> &[SectionSolution] {
        &self.scratch.sections[..self.scratch.station_y_m.len()]
    }

    fn check_inputs(&self, inputs: &EngineInputs<'_>) -> Result<(), ModelError> {
        let name = self.engine.name();
        check_panel_method_inputs(name, inputs.body, inputs.flight, &PanelMotion::default())?;
        let phi = inputs.fuel_equivalence_ratio;
        if !(phi.is_finite() && phi >= 0.0) {
            return Err(ModelError::out_of_range(
                name,
                "fuel equivalence ratio phi",
                phi,
                "finite and >= 0",
            ));
        }
        Ok(())
    }
}

impl<E: SectionEngine> PropulsionModel for Scramjet<E> {
    fn name(&self) -> &str {
        self.engine.name()
    }

    fn evaluate(
        &mut self,
        inputs: &EngineInputs<'_>,
        out: &mut PropulsionSolution,
    ) -> Result<(), ModelError> {
        self.check_inputs(inputs)?;
        let name = self.engine.name();
        let mesh = inputs.body;
        let freestream = &inputs.flight.freestream;
        let s = &mut self.scratch;
        s.surfaces.read(name, mesh)?;

        // Equal-width bands across the engine, one section at each band's centre.
        let (lo, width) = (s.surfaces.y_min_m, s.surfaces.width_m());
        s.station_y_m.clear();
        s.station_y_m
            .extend((0..self.strips).map(|k| lo + (k as f64 + 0.5) * width / self.strips as f64));
        if s.sections.len() < self.strips {
            s.sections
                .resize_with(self.strips, SectionSolution::default);
        }
        let conditions = SectionConditions {
            freestream,
            alpha_rad: inputs.flight.alpha_rad,
            fuel_equivalence_ratio: inputs.fuel_equivalence_ratio,
            reference_m: Point2::new(self.reference_m.x, self.reference_m.z),
        };
        for (k, &y) in s.station_y_m.iter().enumerate() {
            s.surfaces.section_at(y, &mut s.geometry);
            // A section solve reads no y (only the section's polylines, the freestream and α),
            // so a section that repeats the last solved one has its solution: every section
            // of a spanwise-uniform engine, such as the sample vehicle's.
            if k > 0 && same_polylines(&s.solved, &s.geometry) {
                let (done, rest) = s.sections.split_at_mut(k);
                rest[0].copy_from(&done[k - 1]);
                continue;
            }
            self.engine
                .solve(&s.geometry, &conditions, &mut s.sections[k])?;
            s.solved.ramp_m.clone_from(&s.geometry.ramp_m);
            s.solved.cowl_m.clone_from(&s.geometry.cowl_m);
            s.solved.nozzle_m.clone_from(&s.geometry.nozzle_m);
        }
        let sections = &s.sections[..self.strips];

        if !s
            .fit
            .reset(s.surfaces.y_min_m, s.surfaces.y_max_m, &s.station_y_m)
        {
            return Err(ModelError::inconsistent(
                name,
                "the spanwise sections are too few or coincide; the quadratic fit needs three",
            ));
        }
        s.fit.integral_weights(&mut s.weights);
        let fx = apply(&s.weights, sections.iter().map(|c| c.force_n_per_m.x));
        let fz = apply(&s.weights, sections.iter().map(|c| c.force_n_per_m.y));
        let my = apply(
            &s.weights,
            sections.iter().map(|c| c.pitching_moment_nm_per_m),
        );
        let mass = apply(
            &s.weights,
            sections.iter().map(|c| c.air_mass_flow_kg_s_per_m),
        );
        s.fit
            .first_moment_weights(self.reference_m.y, &mut s.weights);
        // (r × F) with r = (·, y - y_ref, ·), F = (f_x, 0, f_z): M_x = (y - y_ref) f_z,
        // M_z = -(y - y_ref) f_x.
        let mx = apply(&s.weights, sections.iter().map(|c| c.force_n_per_m.y));
        let mz = -apply(&s.weights, sections.iter().map(|c| c.force_n_per_m.x));
        out.loads = Loads {
            force_n: Vector3::new(fx, 0.0, fz),
            moment_nm: Vector3::new(mx, my, mz),
        };
        out.mass_flow_kg_s = mass;
        out.status = sections
            .iter()
            .map(|c| c.status)
            .max_by_key(|&st| severity(st))
            .unwrap_or_default();

        // Stations of the middle section (the centreline for an odd count).
        let middle = &sections[self.strips / 2];
        out.stations.truncate(middle.stations.len());
        for (k, st) in middle.stations.iter().enumerate() {
            if k == out.stations.len() {
                out.stations.push(StationState {
                    station: String::new(),
                    mach: 0.0,
                    pressure_pa: 0.0,
                    temperature_k: 0.0,
                });
            }
            let o = &mut out.stations[k];
            if o.station != st.name {
                o.station.clear();
                o.station.push_str(st.name);
            }
            o.mach = st.state.mach;
            o.pressure_pa = st.state.pressure_pa;
            o.temperature_k = st.state.temperature_k;
        }

        // Engine-owned panels: the fitted sectional pressure at each column; others p∞.
        out.panel_pressure_pa.clear();
        out.panel_pressure_pa
            .resize(mesh.panels.len(), freestream.pressure_pa);
        for column in &s.surfaces.columns {
            s.fit.value_weights(column.y_m, &mut s.weights);
            for (i, &panel) in column.ramp_panels.iter().enumerate() {
                out.panel_pressure_pa[panel] =
                    apply(&s.weights, sections.iter().map(|c| c.ramp_pressure_pa[i]));
            }
            for (i, &panel) in column.nozzle_panels.iter().enumerate() {
                out.panel_pressure_pa[panel] =
                    apply(&s.weights, sections.iter().map(|c| c.nozzle_pressure_pa[i]));
            }
        }
        let finite = out.loads.force_n.iter().all(|v| v.is_finite())
            && out.loads.moment_nm.iter().all(|v| v.is_finite())
            && out.mass_flow_kg_s.is_finite();
        if !finite {
            return Err(ModelError::NonFinite {
                model: name.to_owned(),
                quantity: "engine loads".to_owned(),
                location: " after the spanwise fit".to_owned(),
            });
        }
        if let Some(p) = out.panel_pressure_pa.iter().position(|p| !p.is_finite()) {
            return Err(ModelError::non_finite_at_panel(name, "engine pressure", p));
        }
        Ok(())
    }
}
