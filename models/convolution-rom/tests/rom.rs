//! `convolution-rom` on the sample right lifting surface against its sources (one file: one test
//! binary whose checks share the stand-in registry and builders below).
//!
//! Stand-ins registered in a test registry (as `pod`'s tests do): `stand-in-plate`, a structure
//! of three vertical-displacement modes (plunge, pitch about the mid-chord, parabolic spanwise
//! bending; peak displacement 1 m per unit modal coordinate; frequencies 8, 20 and 35 Hz, test
//! values), and `linear-piston`, first-order piston theory in small-slope form, exactly linear
//! in the modal coordinates and velocities of such modes. The nonlinear source is the real
//! `shock-expansion-piston`.

use std::sync::Arc;

use hsv_core::aero::{AeroModel, AeroSolution, EdgeState, ModalHistoryAero, PanelMotion};
use hsv_core::config::LoadedConfig;
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{ModeShapes, PanelMesh};
use hsv_core::region::RegionInfo;
use hsv_core::registry::{Factory, ModelContext, Origin, Registry, RegistryEntry};
use hsv_core::structure::{ModalModel, StructureModel};
use hsv_model_convolution_rom::{CheckOptions, ConvolutionRom, check_against_source};
use hsv_model_shock_expansion as _;
use nalgebra::{DMatrix, DVector};

const FREQUENCIES_HZ: [f64; 3] = [8.0, 20.0, 35.0];

/// Three vertical-displacement modes built on whatever mesh it is asked for.
struct StandInPlate {
    modal: ModalModel,
}

impl StandInPlate {
    fn new() -> Self {
        let n = FREQUENCIES_HZ.len();
        let omega2 = DVector::from_iterator(
            n,
            FREQUENCIES_HZ
                .iter()
                .map(|f| (std::f64::consts::TAU * f).powi(2)),
        );
        Self {
            modal: ModalModel {
                names: vec!["plunge".into(), "pitch".into(), "bending".into()],
                mass: DMatrix::identity(n, n),
                damping: DMatrix::zeros(n, n),
                stiffness: DMatrix::from_diagonal(&omega2),
            },
        }
    }
}

impl StructureModel for StandInPlate {
    fn name(&self) -> &str {
        "stand-in-plate"
    }
    fn modal_model(&self) -> &ModalModel {
        &self.modal
    }
    fn natural_frequencies_hz(&self) -> Result<Vec<f64>, ModelError> {
        Ok(FREQUENCIES_HZ.to_vec())
    }
    /// z = 1 (plunge), z = (x − x_mid) / max|x − x_mid| (pitch), z = η² (bending), with η the
    /// spanwise position from the inboard edge.
    fn mode_shapes_on(&self, mesh: &PanelMesh) -> Result<ModeShapes, ModelError> {
        let (lo, hi) = mesh.bounding_box();
        let x_mid = 0.5 * (lo.x + hi.x);
        let half = 0.5 * (hi.x - lo.x);
        let inboard = if lo.y.abs() < hi.y.abs() { lo.y } else { hi.y };
        let span = hi.y - lo.y;
        let nv = mesh.vertices.len();
        let mut phi = DMatrix::zeros(3 * nv, 3);
        for (i, v) in mesh.vertices.iter().enumerate() {
            let eta = (v.y - inboard).abs() / span;
            phi[(3 * i + 2, 0)] = 1.0;
            phi[(3 * i + 2, 1)] = (v.x - x_mid) / half;
            phi[(3 * i + 2, 2)] = eta * eta;
        }
        Ok(ModeShapes {
            vertex_displacement: phi,
        })
    }
}

/// First-order piston theory in small-slope form: p = p∞ + ρ∞ a∞ w with
/// w = V · (A n) / |A n_z| + v_z sign(n_z) (V the rigid velocity, v the elastic one). Under
/// vertical vertex displacements A n = (d1 × d2)/2 keeps its z component and its x, y
/// components are affine in the displacements, so w (and p) is exactly affine in q and q̇.
/// Panels standing vertical (|n_z| < 1e-3) keep p∞.
struct LinearPiston;

impl AeroModel for LinearPiston {
    fn name(&self) -> &str {
        "linear-piston"
    }
    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        let f = &flight.freestream;
        out.reset(mesh.panels.len());
        for (i, panel) in mesh.panels.iter().enumerate() {
            let c = panel.normal * panel.area_m2;
            let mut p = f.pressure_pa;
            if c.z.abs() >= 1e-3 * c.norm() {
                let rigid = flight.point_velocity_m_s(&panel.centroid);
                let elastic = motion.elastic_velocity_m_s.map_or(0.0, |v| v[i].z);
                let w = rigid.dot(&c) / c.z.abs() + elastic * c.z.signum();
                p += f.density_kg_m3 * f.speed_of_sound_m_s * w;
            }
            out.pressure_pa[i] = p;
            out.edge[i] = EdgeState {
                mach: f.mach,
                pressure_pa: p,
                temperature_k: f.temperature_k,
                density_kg_m3: f.density_kg_m3,
                velocity_m_s: f.velocity_m_s,
            };
        }
        Ok(())
    }
}

fn registry() -> Registry {
    let mut registry = Registry::builtin().unwrap();
    let entry = |name: &str, factory: Factory| RegistryEntry {
        name: name.to_owned(),
        fidelity: 0,
        summary: String::new(),
        settings_doc: String::new(),
        origin: Origin::BuiltIn("convolution-rom test".to_owned()),
        factory,
    };
    registry
        .insert(entry(
            "stand-in-plate",
            Factory::Structure(Arc::new(|_| Ok(Box::new(StandInPlate::new())))),
        ))
        .unwrap();
    registry
        .insert(entry(
            "linear-piston",
            Factory::Aero(Arc::new(|_| Ok(Box::new(LinearPiston)))),
        ))
        .unwrap();
    registry
}

fn region() -> &'static RegionInfo {
    hsv_core::testing::sample_region("right_surface")
}

fn build(
    registry: &Registry,
    region: &RegionInfo,
    settings: &str,
) -> Result<ConvolutionRom, ModelError> {
    let table: toml::Table = toml::from_str(settings).unwrap();
    let ctx = ModelContext {
        settings: &table,
        key_path: "models.convolution-rom",
        file: "test.toml",
        region,
        registry,
    };
    ConvolutionRom::new(&ctx)
}

fn flight(mach: f64, altitude_m: f64, alpha_deg: f64) -> FlightCondition {
    let f = Freestream::standard(mach, altitude_m, PerfectGas::AIR).unwrap();
    FlightCondition::steady(f, alpha_deg.to_radians(), 0.0)
}

const LINEAR: &str = "source = \"linear-piston\"\nstructure = \"stand-in-plate\"\n\
                      alpha_deg = 2.0\ncache_file = \"\"\n";

/// A linear source is reproduced to round-off on arbitrary modal motion (each mode at its
/// natural frequency and a random three-mode motion), at the identification condition and off
/// it (Mach 6.5 at 30 km: Δp/p∞ = γ M w/V is linear in M, so the Mach-interpolated correction
/// factor is exact), for generalized forces and panel pressures alike.
#[test]
fn a_linear_source_is_reproduced_to_round_off_on_and_off_design() {
    let registry = registry();
    let mut rom = build(&registry, region(), LINEAR).unwrap();
    assert_eq!(rom.identification().forces.samples, 1, "no memory");
    for condition in [flight(6.0, 26_000.0, 2.0), flight(6.5, 30_000.0, 2.0)] {
        let report = check_against_source(&mut rom, &condition, &CheckOptions::default()).unwrap();
        for m in &report.motions {
            println!(
                "Mach {}: {}: relative RMS error {:.2e}, max {:.2e}, speed-up {:.1}",
                report.mach, m.name, m.relative_rms_error, m.relative_max_error, m.speedup
            );
        }
        assert_eq!(report.motions.len(), 4);
        assert!(
            report.worst_relative_rms_error() < 1e-9,
            "{}",
            report.worst_relative_rms_error()
        );
    }
    // Pressures: one state of the random kind, ROM against the source panel by panel.
    let condition = flight(6.5, 30_000.0, 2.0);
    let q = DVector::from_vec(vec![0.02, -0.03, 0.04]);
    let q_dot = DVector::from_vec(vec![1.5, -2.0, 3.0]);
    let mesh = region().mesh.clone();
    let history = rom.initial_history(0.0, &q).unwrap();
    let mut forces = vec![0.0; 3];
    let mut rom_solution = AeroSolution::default();
    rom.evaluate_modal(
        &mesh,
        &condition,
        &history,
        0.01,
        &q,
        &q_dot,
        &mut forces,
        Some(&mut rom_solution),
    )
    .unwrap();
    let shapes = rom.mode_shapes().clone();
    let mut deformed = PanelMesh::default();
    shapes.deform(&mesh, &q, &mut deformed);
    let mut velocities = vec![nalgebra::Vector3::zeros(); mesh.panels.len()];
    shapes.panel_velocities(&mesh, &q_dot, &mut velocities);
    let mut source = AeroSolution::default();
    LinearPiston
        .evaluate(
            &deformed,
            &condition,
            &PanelMotion {
                elastic_velocity_m_s: Some(&velocities),
            },
            &mut source,
        )
        .unwrap();
    let p_inf = condition.freestream.pressure_pa;
    for (i, (r, s)) in rom_solution
        .pressure_pa
        .iter()
        .zip(&source.pressure_pa)
        .enumerate()
    {
        assert!((r - s).abs() < 1e-9 * p_inf, "panel {i}: {r} vs {s}");
    }
}

/// Independent check of the identified rate response: for a plunging surface, first-order
/// piston theory gives the force −ρ∞ a∞ ż on every unit of projected area of each face
/// (Ashley & Zartarian, "Piston theory — a new aerodynamic tool for the aeroelastician",
/// J. Aero. Sci. 23(12), 1956), so with φ_z = 1 the generalized damping is
/// C_11 = −2 ρ∞ a∞ S, S the planform area (root + tip chord)/2 × span of the sample surface;
/// plunge does not change any slope, so K_11 = 0. Tolerance 1e-9 (round-off).
#[test]
fn identified_plunge_damping_is_piston_theory_on_the_planform() {
    let registry = registry();
    let rom = build(&registry, region(), LINEAR).unwrap();
    let condition = flight(6.0, 26_000.0, 2.0);
    let (stiffness, damping) = rom.linear_coefficients(&condition);
    let cfg = LoadedConfig::sample().unwrap().config.lifting_surface;
    let planform_m2 = 0.5 * (cfg.root_chord_m + cfg.tip_chord_m) * cfg.span_m;
    let f = &condition.freestream;
    let expected = -2.0 * f.density_kg_m3 * f.speed_of_sound_m_s * planform_m2;
    println!("C_11 = {} N s/m, expected {expected}", damping[(0, 0)]);
    assert!((damping[(0, 0)] / expected - 1.0).abs() < 1e-9);
    assert!(stiffness[(0, 0)].abs() < 1e-9 * expected.abs());
}

const NONLINEAR: &str = "source = \"shock-expansion-piston\"\nstructure = \"stand-in-plate\"\n\
                         alpha_deg = 2.0\nmax_displacement_m = 0.2\ncache_file = \"\"\n";

/// `shock-expansion-piston` (nonlinear in the surface slopes) on motions of up to 0.18 m peak
/// displacement (pitch: 5° of incidence change on the 5 % double wedge at Mach 6, hypersonic
/// similarity parameter M θ ≈ 0.5; no velocity cap, so every mode moves at that amplitude):
/// with the correction factor the ROM stays within 3 % (RMS, relative to the aeroelastic part
/// of the forces) of the source at the identification Mach and off it (Mach 6.5); the linear
/// convolution alone is at least 3 times worse.
#[test]
fn a_nonlinear_source_needs_the_correction_factor() {
    let registry = registry();
    let mut rom = build(&registry, region(), NONLINEAR).unwrap();
    let options = CheckOptions {
        max_velocity_ratio: None,
        ..CheckOptions::default()
    };
    for condition in [flight(6.0, 26_000.0, 2.0), flight(6.5, 26_000.0, 2.0)] {
        rom.set_correction(true);
        let corrected = check_against_source(&mut rom, &condition, &options).unwrap();
        rom.set_correction(false);
        let linear = check_against_source(&mut rom, &condition, &options).unwrap();
        for (c, l) in corrected.motions.iter().zip(&linear.motions) {
            println!(
                "Mach {}: {}: corrected RMS {:.4} (max {:.4}), linear RMS {:.4} (max {:.4}), \
                 speed-up {:.1}",
                corrected.mach,
                c.name,
                c.relative_rms_error,
                c.relative_max_error,
                l.relative_rms_error,
                l.relative_max_error,
                c.speedup
            );
        }
        let (c, l) = (
            corrected.worst_relative_rms_error(),
            linear.worst_relative_rms_error(),
        );
        let forces_only = CheckOptions {
            pressures: false,
            ..options.clone()
        };
        rom.set_correction(true);
        let fast = check_against_source(&mut rom, &condition, &forces_only).unwrap();
        println!(
            "Mach {}: speed-up {:.1} with pressures, {:.1} forces only",
            corrected.mach,
            corrected.overall_speedup(),
            fast.overall_speedup()
        );
        assert!(c < 0.03, "corrected error {c}");
        assert!(l > 3.0 * c, "linear {l} vs corrected {c}");
    }
}

/// A unique scratch directory for one test.
fn scratch_dir(test: &str) -> std::path::PathBuf {
    let dir =
        std::env::temp_dir().join(format!("hsv-convolution-rom-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Indicial responses of the CSV test: Q_k = δ_kj K_j (1 − a e^(−t/T)) per unit step of q_j
/// (a first-order lag; arbitrary test values, chosen for their closed-form Duhamel integral).
const K: [f64; 3] = [-500.0, 300.0, -200.0];
const LAG_A: f64 = 0.4;
const LAG_T_S: f64 = 0.01;
const CSV_DT_S: f64 = 5e-4;
const CSV_SAMPLES: usize = 401;

fn indicial(t: f64) -> f64 {
    1.0 - LAG_A * (-t / LAG_T_S).exp()
}

fn write_lag_csv(path: &std::path::Path) {
    let step = 0.01;
    let mut text = String::from(
        "# first-order lag indicial responses\ninput,mode,step,time_s,force_1,force_2,force_3\n",
    );
    for (j, gain) in K.iter().enumerate() {
        for i in 0..CSV_SAMPLES {
            let t = i as f64 * CSV_DT_S;
            let forces: Vec<String> = (0..3)
                .map(|k| {
                    if k == j {
                        format!("{:e}", gain * step * indicial(t))
                    } else {
                        "0".into()
                    }
                })
                .collect();
            text.push_str(&format!(
                "displacement,{},{step},{t:e},{}\n",
                j + 1,
                forces.join(",")
            ));
        }
    }
    std::fs::write(path, text).unwrap();
}

/// Runs the ROM on q(t_n) for n = 1..=steps at step h from rest at q = 0; returns
/// Q(t_n) − Q(rest) of every step.
fn run(
    rom: &mut ConvolutionRom,
    condition: &FlightCondition,
    h: f64,
    steps: usize,
    q_of: impl Fn(f64) -> (DVector<f64>, DVector<f64>),
) -> (Vec<Vec<f64>>, hsv_core::aero::ModalHistory) {
    let mesh = region().mesh.clone();
    let zero = DVector::zeros(3);
    let mut history = rom.initial_history(0.0, &zero).unwrap();
    let mut rest = vec![0.0; 3];
    rom.evaluate_modal(
        &mesh, condition, &history, 0.0, &zero, &zero, &mut rest, None,
    )
    .unwrap();
    let mut out = Vec::with_capacity(steps);
    let mut forces = vec![0.0; 3];
    for n in 1..=steps {
        let (q, q_dot) = q_of(n as f64 * h);
        rom.evaluate_modal(&mesh, condition, &history, h, &q, &q_dot, &mut forces, None)
            .unwrap();
        rom.commit(&mut history, condition, h, &q, &q_dot).unwrap();
        out.push(forces.iter().zip(&rest).map(|(f, r)| f - r).collect());
    }
    (out, history)
}

/// Step/impulse consistency and the discrete Duhamel integral, on CSV step responses with
/// memory: a step input reproduces the CSV samples; an impulse (one step up, one step down)
/// gives the first difference of the step response; a sinusoid converges at first order in the
/// time step to the closed-form Duhamel integral x(t) = ∫ A(t − τ) q̇(τ) dτ (Etkin, Dynamics of
/// Atmospheric Flight, App. A.3) of the lag A(t) = K (1 − a e^(−t/T)):
/// K [q(t) − a ω A_q T (cos ωt + ωT sin ωt − e^(−t/T)) / (1 + ω²T²)]; and the history kept
/// stays bounded by the responses' length.
#[test]
fn step_impulse_and_sinusoid_follow_the_duhamel_integral() {
    let dir = scratch_dir("lag");
    let csv = dir.join("lag.csv");
    write_lag_csv(&csv);
    let settings = format!(
        "{LINEAR}correction = false\nstep_csv = {:?}\n",
        csv.display().to_string()
    );
    let registry = registry();
    let mut rom = build(&registry, region(), &settings).unwrap();
    assert_eq!(rom.identification().forces.samples, CSV_SAMPLES);
    let condition = flight(6.0, 26_000.0, 2.0);
    let steps = 600;
    let unit = |j: usize| {
        let mut q = DVector::zeros(3);
        q[j] = 1.0;
        q
    };
    let (step, _) = run(&mut rom, &condition, CSV_DT_S, steps, |_| {
        (unit(1), DVector::zeros(3))
    });
    for (n, y) in step.iter().enumerate() {
        let want = K[1] * indicial(n as f64 * CSV_DT_S);
        assert!(
            (y[1] - want).abs() < 1e-9 * K[1].abs(),
            "step {n}: {} vs {want}",
            y[1]
        );
        assert!(y[0].abs() < 1e-9 && y[2].abs() < 1e-9);
    }
    let (impulse, _) = run(&mut rom, &condition, CSV_DT_S, steps, |t| {
        let q = if t < 1.5 * CSV_DT_S {
            unit(1)
        } else {
            DVector::zeros(3)
        };
        (q, DVector::zeros(3))
    });
    for n in 1..steps {
        let want = step[n][1] - step[n - 1][1];
        assert!(
            (impulse[n][1] - want).abs() < 1e-9 * K[1].abs(),
            "impulse {n}"
        );
    }
    // A sinusoid in mode 3 against the closed-form Duhamel integral, at two time steps.
    let (amplitude, omega) = (0.05, std::f64::consts::TAU * 20.0);
    let exact = |t: f64| {
        let wt = omega * LAG_T_S;
        K[2] * (amplitude * (omega * t).sin()
            - LAG_A
                * amplitude
                * omega
                * LAG_T_S
                * ((omega * t).cos() + wt * (omega * t).sin() - (-t / LAG_T_S).exp())
                / (1.0 + wt * wt))
    };
    let mut errors = Vec::new();
    for h in [CSV_DT_S, CSV_DT_S / 2.0] {
        let steps = (0.5 / h).round() as usize;
        let (y, history) = run(&mut rom, &condition, h, steps, |t| {
            let mut q = DVector::zeros(3);
            let mut q_dot = DVector::zeros(3);
            q[2] = amplitude * (omega * t).sin();
            q_dot[2] = amplitude * omega * (omega * t).cos();
            (q, q_dot)
        });
        let error = y
            .iter()
            .enumerate()
            .map(|(n, y)| (y[2] - exact((n + 1) as f64 * h)).abs())
            .fold(0.0, f64::max);
        let memory_steps = ((CSV_SAMPLES - 1) as f64 * CSV_DT_S / h).ceil() as usize;
        println!(
            "h = {h:e} s: max error {error:.3e} N m of {:.1}; history {} increments (memory {memory_steps} steps)",
            K[2].abs() * amplitude,
            history.increment_times_s.len()
        );
        assert!(history.increment_times_s.len() <= memory_steps + 1);
        errors.push(error);
    }
    assert!(errors[0] < 0.05 * K[2].abs() * amplitude, "{errors:?}");
    let order = errors[1] / errors[0];
    assert!(
        (0.4..0.6).contains(&order),
        "first-order convergence: {errors:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The identification is cached, reused while nothing it was built from changes, and rebuilt
/// when the mesh (or a setting) changes.
#[test]
fn the_cache_is_rebuilt_when_the_mesh_changes() {
    let dir = scratch_dir("cache");
    let settings = format!(
        "source = \"linear-piston\"\nstructure = \"stand-in-plate\"\ncache_file = {:?}\n",
        dir.join("rom-{region}.json").display().to_string()
    );
    let file = dir.join("rom-right_surface.json");
    let registry = registry();
    let original = region().clone();
    let first = build(&registry, &original, &settings).unwrap();
    assert!(!first.from_cache());
    assert!(file.exists());
    let again = build(&registry, &original, &settings).unwrap();
    assert!(again.from_cache());
    // serde_json parses floats to within an ulp (no `float_roundtrip`): compare to 1e-14.
    let (a, b) = (again.identification(), first.identification());
    assert_eq!(a.fingerprint, b.fingerprint);
    for (x, y) in a
        .forces
        .steps
        .iter()
        .chain(&a.pressures.correction)
        .zip(b.forces.steps.iter().chain(&b.pressures.correction))
    {
        assert!((x - y).abs() <= 1e-14 * x.abs().max(y.abs()), "{x} vs {y}");
    }
    // The same surface 1 mm lower: a different mesh, rebuilt (and its file replaces the old).
    let mut moved = original.clone();
    for v in &mut moved.mesh.vertices {
        v.z += 1e-3;
    }
    moved.mesh.update_geometry();
    let rebuilt = build(&registry, &moved, &settings).unwrap();
    assert!(!rebuilt.from_cache());
    assert_ne!(
        rebuilt.identification().fingerprint,
        first.identification().fingerprint
    );
    assert!(build(&registry, &moved, &settings).unwrap().from_cache());
    assert!(!build(&registry, &original, &settings).unwrap().from_cache());
    // A changed identification setting rebuilds too.
    let other_alpha = format!("{settings}alpha_deg = 1.0\n");
    assert!(
        !build(&registry, &original, &other_alpha)
            .unwrap()
            .from_cache()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad settings and inputs name the key, the value and the allowed range.
#[test]
fn bad_settings_and_inputs_are_named() {
    let registry = registry();
    let err = |settings: &str| {
        build(&registry, region(), settings)
            .err()
            .unwrap()
            .to_string()
    };
    let e = err(&format!("{LINEAR}sourse = \"x\"\n"));
    assert!(
        e.contains("models.convolution-rom") && e.contains("sourse"),
        "{e}"
    );
    let e = err(&format!("{LINEAR}mach = 0.5\n"));
    assert!(e.contains("models.convolution-rom.mach"), "{e}");
    let e =
        err("source = \"convolution-rom\"\nstructure = \"stand-in-plate\"\ncache_file = \"\"\n");
    assert!(e.contains("models.convolution-rom.source"), "{e}");
    let e = err("source = \"shock-expansio\"\nstructure = \"stand-in-plate\"\ncache_file = \"\"\n");
    assert!(e.contains("did you mean"), "{e}");
    let e = err(&format!("{LINEAR}modes = 7\n"));
    assert!(
        e.contains("models.convolution-rom.modes") && e.contains("1..=3"),
        "{e}"
    );
    let dir = scratch_dir("bad-csv");
    let csv = dir.join("bad.csv");
    std::fs::write(&csv, "input,mode,time_s,force_1\n").unwrap();
    let e = err(&format!(
        "{LINEAR}step_csv = {:?}\n",
        csv.display().to_string()
    ));
    assert!(e.contains("header") && e.contains("force_3"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    // Outside the correction table's Mach range.
    let mut rom = build(&registry, region(), LINEAR).unwrap();
    let zero = DVector::zeros(3);
    let history = rom.initial_history(0.0, &zero).unwrap();
    let mut forces = vec![0.0; 3];
    let e = rom
        .evaluate_modal(
            &region().mesh,
            &flight(8.0, 26_000.0, 2.0),
            &history,
            0.01,
            &zero,
            &zero,
            &mut forces,
            None,
        )
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("Mach") && e.contains("correction_mach"), "{e}");
}
