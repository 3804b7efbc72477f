//! `convolution-rom` against its source (`shock-expansion-piston`) on the sample right lifting
//! surface (15 Ritz modes, 180 panels) at Mach 6, 26 km: one evaluation of the generalized
//! forces (the source: deform the mesh, panel velocities, evaluate, project; the ROM: with and
//! without its panel pressures), 0.1 s of modal motion at 1 ms steps (every mode at its natural
//! frequency, 1 mm of peak displacement; the ROM committing its history every step), and its
//! construction without a cache (its own `ritz-plate` modes and the identification).
//!
//! `cargo bench -p hsv-benches --bench rom`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::config::LoadedConfig;
use hsv_core::coupling::ModalProjection;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use hsv_core::region::{ModelSettings, RegionInfo};
use hsv_core::registry::{ModelContext, Registry, RoleModel};
use hsv_core::structure::StructureModel;
use nalgebra::{DVector, Vector3};

const STEP_S: f64 = 1e-3;
const STEPS: usize = 100;

fn build<M: ?Sized + RoleModel>(region: &RegionInfo, registry: &Registry, name: &str) -> Box<M> {
    let settings = region.model_settings(name);
    registry
        .create::<M>(name, &ModelContext::new(region, registry, &settings))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The source's generalized forces at (q, q̇), as a coupled run computes them.
struct SourceRun {
    aero: Box<dyn AeroModel>,
    mesh: PanelMesh,
    shapes: ModeShapes,
    projection: ModalProjection,
    deformed: PanelMesh,
    velocities: Vec<Vector3<f64>>,
    solution: AeroSolution,
    forces: Vec<f64>,
}

impl SourceRun {
    fn forces(&mut self, flight: &FlightCondition, q: &DVector<f64>, q_dot: &DVector<f64>) {
        self.shapes.deform(&self.mesh, q, &mut self.deformed);
        self.shapes
            .panel_velocities(&self.mesh, q_dot, &mut self.velocities);
        let motion = PanelMotion {
            elastic_velocity_m_s: Some(&self.velocities),
        };
        self.aero
            .evaluate(&self.deformed, flight, &motion, &mut self.solution)
            .expect("source");
        self.projection
            .generalized_forces(
                &self.solution.pressure_pa,
                flight.freestream.pressure_pa,
                &mut self.forces,
            )
            .expect("projection");
    }
}

/// q_j(t) = a_j sin(ω_j t), a_j giving 1 mm of peak displacement.
fn motion(
    amplitudes: &[f64],
    omegas: &[f64],
    t: f64,
    q: &mut DVector<f64>,
    q_dot: &mut DVector<f64>,
) {
    for (j, (a, w)) in amplitudes.iter().zip(omegas).enumerate() {
        q[j] = a * (w * t).sin();
        q_dot[j] = a * w * (w * t).cos();
    }
}

fn rom(c: &mut Criterion) {
    let registry = hsv_run::registry().expect("registry");
    let loaded = LoadedConfig::sample().expect("embedded config parses");
    let mut region = loaded.region("right_surface").expect("region");
    let mut table = region.model_settings("convolution-rom").table;
    table.insert("cache_file".into(), "".into());
    region.settings.insert(
        "convolution-rom".into(),
        ModelSettings {
            table,
            key_path: "models.convolution-rom".into(),
        },
    );
    let structure: Box<dyn StructureModel> = build(&region, &registry, "ritz-plate");
    let shapes = structure.mode_shapes_on(&region.mesh).expect("shapes");
    let n = shapes.n_modes();
    let projection =
        ModalProjection::new(&region.mesh, &shapes, |r| r == RegionKind::LiftingSurface)
            .expect("projection");
    let omegas: Vec<f64> = structure
        .natural_frequencies_hz()
        .expect("frequencies")
        .iter()
        .map(|f| std::f64::consts::TAU * f)
        .collect();
    let amplitudes: Vec<f64> = (0..n)
        .map(|j| {
            let column = shapes.vertex_displacement.column(j);
            1e-3 / column.amax()
        })
        .collect();
    let mut source = SourceRun {
        aero: build(&region, &registry, "shock-expansion-piston"),
        deformed: region.mesh.clone(),
        velocities: vec![Vector3::zeros(); region.mesh.panels.len()],
        mesh: region.mesh.clone(),
        shapes,
        projection,
        solution: AeroSolution::default(),
        forces: vec![0.0; n],
    };
    let mut model: Box<dyn AeroModel> = build(&region, &registry, "convolution-rom");
    let rom = model
        .modal_history()
        .expect("convolution-rom has a modal history");
    let freestream = Freestream::standard(6.0, 26_000.0, region.gas).expect("freestream");
    let flight = FlightCondition::steady(freestream, 0.0, 0.0);
    let (mut q, mut q_dot) = (DVector::zeros(n), DVector::zeros(n));
    motion(&amplitudes, &omegas, 0.37 * STEP_S, &mut q, &mut q_dot);
    let mut forces = vec![0.0; n];
    let mut pressures = AeroSolution::default();
    let rest = rom
        .initial_history(0.0, &DVector::zeros(n))
        .expect("history");

    let mut group = c.benchmark_group("rom/right-surface");
    group.bench_function("source shock-expansion-piston: one evaluation", |b| {
        b.iter(|| {
            source.forces(&flight, black_box(&q), &q_dot);
            black_box(source.forces[0])
        })
    });
    for (name, with_pressures) in [
        ("convolution-rom: one evaluation with pressures", true),
        ("convolution-rom: one evaluation, forces only", false),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let out = with_pressures.then_some(&mut pressures);
                rom.evaluate_modal(
                    &region.mesh,
                    &flight,
                    &rest,
                    STEP_S,
                    black_box(&q),
                    &q_dot,
                    &mut forces,
                    out,
                )
                .expect("rom");
                black_box(forces[0])
            })
        });
    }
    group.bench_function("source: 0.1 s of modal motion (100 steps)", |b| {
        b.iter(|| {
            for step in 1..=STEPS {
                motion(
                    &amplitudes,
                    &omegas,
                    step as f64 * STEP_S,
                    &mut q,
                    &mut q_dot,
                );
                source.forces(&flight, &q, &q_dot);
            }
            black_box(source.forces[0])
        })
    });
    group.bench_function(
        "convolution-rom: 0.1 s of modal motion with pressures",
        |b| {
            b.iter(|| {
                let mut history = rest.clone();
                for step in 1..=STEPS {
                    motion(
                        &amplitudes,
                        &omegas,
                        step as f64 * STEP_S,
                        &mut q,
                        &mut q_dot,
                    );
                    rom.evaluate_modal(
                        &region.mesh,
                        &flight,
                        &history,
                        STEP_S,
                        &q,
                        &q_dot,
                        &mut forces,
                        Some(&mut pressures),
                    )
                    .expect("rom");
                    rom.commit(&mut history, &flight, STEP_S, &q, &q_dot)
                        .expect("commit");
                }
                black_box(forces[0])
            })
        },
    );
    group.finish();
    let mut group = c.benchmark_group("rom/identification");
    group.sample_size(10);
    group.bench_function(
        "convolution-rom from shock-expansion-piston (no cache)",
        |b| {
            b.iter(|| {
                let model: Box<dyn AeroModel> = build(&region, &registry, "convolution-rom");
                black_box(model.name().len())
            })
        },
    );
    group.finish();
}

criterion_group!(benches, rom);
criterion_main!(benches);
