//! Validation of `free-free-beam` against closed-form and exact solutions of free-free beams,
//! plus the modal properties every modal model must have (one file: the checks share the uniform,
//! Table 1 and sample-config beams built below).
//!
//! References:
//! - Bending roots βL = 4.7300, 7.8532, 10.9956 of cos βL cosh βL = 1 (free-free = clamped-clamped
//!   roots): Thomson, Theory of Vibration with Applications, App. D (D.1-D.2); Blevins, Formulas
//!   for Natural Frequency and Mode Shape, Table 8-1. ω_n = (βL)_n² / L² √(EI/μ).
//! - Free-free torsion (and axial) of a uniform shaft: ω_n = nπ/L √(GJ/I_x) (√(EA/μ)); Thomson
//!   ch. 9 (longitudinal and torsional vibration of rods).
//! - Stepped (two-segment) beam, exact: transfer matrix of w'''' = β⁴ w per segment in Krylov
//!   functions, continuity of w, w', EI w'', EI w''' at the step; Pestel & Leckie, Matrix Methods
//!   in Elastomechanics (1963).

use std::f64::consts::{PI, TAU};

use approx::assert_relative_eq;
use hsv_core::config::LoadedConfig;
use hsv_core::error::ModelError;
use hsv_core::mesh::{ModeShapes, PanelMesh};
use hsv_core::registry::{ModelContext, Registry, Role};
use hsv_core::structure::StructureModel;
use hsv_model_free_free_beam::{FreeFreeBeam, ModeKind, NAME, Settings};
use nalgebra::{DMatrix, DVector, Matrix4, Vector4};

/// A uniform beam of length 10 m with distinct stiffness per kind (no coincident frequencies
/// among the modes checked).
fn uniform(elements: usize) -> Settings {
    Settings {
        forebody_length_m: 5.0,
        aftbody_length_m: 5.0,
        forebody_mass_per_length_kg_m: 3.0,
        aftbody_mass_per_length_kg_m: 3.0,
        torsional_inertia_kg_m: 0.7,
        lateral_bending_stiffness_n_m2: 5.0e6,
        vertical_bending_stiffness_n_m2: 2.0e6,
        torsional_stiffness_n_m2: 3.0e5,
        axial_stiffness_n: 4.0e8,
        elements,
        damping_ratio: 0.0,
        lateral_bending_modes: 3,
        vertical_bending_modes: 3,
        torsion_modes: 3,
        axial_modes: 3,
        axis_z_m: Some(0.0),
    }
}

/// The paper's Table 1 beam (the defaults) with `elements` elements.
fn table1(elements: usize) -> FreeFreeBeam {
    FreeFreeBeam::new(
        Settings {
            elements,
            ..Settings::default()
        },
        0.0,
    )
    .expect("Table 1 beam")
}

/// ω (rad/s) of the kept modes of `kind`, ascending.
fn omegas(beam: &FreeFreeBeam, kind: ModeKind) -> Vec<f64> {
    let kinds = beam.kept_kinds();
    let k = &beam.modal_model().stiffness;
    (0..kinds.len())
        .filter(|&i| kinds[i] == kind)
        .map(|i| k[(i, i)].sqrt())
        .collect()
}

#[test]
fn uniform_bending_matches_the_free_free_roots_thomson_blevins() {
    // Tolerance 0.1 % (the roots are tabulated to 5 digits; Hermite cubics converge as h⁴).
    const BETA_L: [f64; 3] = [4.7300, 7.8532, 10.9956];
    let s = uniform(100);
    let beam = FreeFreeBeam::new(s.clone(), 0.0).expect("beam");
    let l: f64 = 10.0;
    for (kind, ei) in [
        (ModeKind::VerticalBending, s.vertical_bending_stiffness_n_m2),
        (ModeKind::LateralBending, s.lateral_bending_stiffness_n_m2),
    ] {
        let w = omegas(&beam, kind);
        assert_eq!(w.len(), 3, "{kind:?}");
        for (n, beta_l) in BETA_L.iter().enumerate() {
            let exact = beta_l * beta_l / (l * l) * (ei / 3.0).sqrt();
            assert_relative_eq!(w[n], exact, max_relative = 1e-3);
        }
    }
}

#[test]
fn uniform_torsion_and_axial_match_n_pi_over_l_thomson() {
    // ω_n = nπ/L √(GJ/I_x), √(EA/μ); tolerance 0.1 % (linear elements converge as h²).
    let s = uniform(120);
    let beam = FreeFreeBeam::new(s.clone(), 0.0).expect("beam");
    for (kind, wave_speed) in [
        (
            ModeKind::Torsion,
            (s.torsional_stiffness_n_m2 / s.torsional_inertia_kg_m).sqrt(),
        ),
        (
            ModeKind::Axial,
            (s.axial_stiffness_n / s.forebody_mass_per_length_kg_m).sqrt(),
        ),
    ] {
        let w = omegas(&beam, kind);
        assert_eq!(w.len(), 3);
        for (n, w_n) in w.iter().enumerate() {
            let exact = (n + 1) as f64 * PI / 10.0 * wave_speed;
            assert_relative_eq!(*w_n, exact, max_relative = 1e-3);
            // Consistent mass: Rayleigh-Ritz upper bound.
            assert!(*w_n > exact, "{kind:?} {n}: {w_n} < {exact}");
        }
    }
}

#[test]
fn six_rigid_body_modes_are_found_and_removed() {
    // A free body has six zero frequencies; they are found by their content in the span of the
    // analytic rigid motions (≈ 1, elastic modes ≈ 0), not by position in the spectrum.
    let beam = table1(60);
    let elastic = beam.elastic_modes();
    assert_eq!(elastic.rigid_body_omega2.len(), 6);
    let first = elastic.omega2[0];
    for w2 in &elastic.rigid_body_omega2 {
        // f_rigid < 1e-3 f_1.
        assert!(
            w2.abs() < 1e-6 * first,
            "rigid {w2} vs first elastic {first}"
        );
    }
    assert!(elastic.rigid_body_content.iter().all(|&p| p > 1.0 - 1e-9));
    assert!(elastic.max_elastic_rigid_content < 1e-9);
    assert!(elastic.omega2.iter().all(|&w2| w2 >= first && w2 > 0.0));
    // Elastic modes carry no rigid motion: Φᵀ M R = 0 (zero momentum and angular momentum).
    let r = beam.beam_mesh().rigid_body_modes();
    let coupling = elastic.shapes.transpose() * beam.mass_matrix() * r;
    assert!(coupling.amax() < 1e-9, "{}", coupling.amax());
}

#[test]
fn modes_are_orthonormal_in_mass_and_diagonal_in_stiffness() {
    // Φᵀ M Φ = I and Φᵀ K Φ = diag(ω²) within 1e-9 (stiffness relative to each ω_i ω_j).
    let beam = table1(60);
    let e = beam.elastic_modes();
    let phi = &e.shapes;
    let gm = phi.transpose() * beam.mass_matrix() * phi;
    let gk = phi.transpose() * beam.stiffness_matrix() * phi;
    let n = phi.ncols();
    let id = DMatrix::<f64>::identity(n, n);
    assert!((&gm - &id).amax() < 1e-9, "{}", (&gm - &id).amax());
    for i in 0..n {
        for j in 0..n {
            let expected = if i == j { e.omega2[i] } else { 0.0 };
            let scale = (e.omega2[i] * e.omega2[j]).sqrt();
            assert!(
                (gk[(i, j)] - expected).abs() < 1e-9 * scale,
                "K[{i},{j}] = {} vs {expected}",
                gk[(i, j)]
            );
        }
    }
    // Kept modes: the modal model is exactly their generalized matrices.
    let kept = beam.kept_shapes();
    let gk = kept.transpose() * beam.stiffness_matrix() * kept;
    let m = beam.modal_model();
    assert!(
        (&gk - &m.stiffness).amax() < 1e-9 * m.stiffness.amax(),
        "{gk} vs {}",
        m.stiffness
    );
    assert_eq!(m.mass, DMatrix::<f64>::identity(3, 3));
}

/// Krylov functions S, T, U, V of βs (Pestel & Leckie).
fn krylov(x: f64) -> [f64; 4] {
    let (ch, sh, c, s) = (x.cosh(), x.sinh(), x.cos(), x.sin());
    [
        (ch + c) / 2.0,
        (sh + s) / 2.0,
        (ch - c) / 2.0,
        (sh - s) / 2.0,
    ]
}

/// Transfer matrix of (w, w', w'', w''') over a uniform segment of length l, β⁴ = μω²/EI.
fn segment_transfer(beta: f64, l: f64) -> Matrix4<f64> {
    let [s, t, u, v] = krylov(beta * l);
    let b = beta;
    Matrix4::new(
        s,
        t / b,
        u / (b * b),
        v / (b * b * b),
        b * v,
        s,
        t / b,
        u / (b * b),
        b * b * u,
        b * v,
        s,
        t / b,
        b * b * b * t,
        b * b * u,
        b * v,
        s,
    )
}

/// Free-free frequency determinant of the two-segment beam (common EI): with (w, w', 0, 0) at
/// the nose, w'' = w''' = 0 at the tail.
fn stepped_determinant(omega: f64, ei: f64, segments: &[(f64, f64)]) -> f64 {
    let mut t = Matrix4::identity();
    for &(l, mu) in segments {
        let beta = (mu * omega * omega / ei).powf(0.25);
        t = segment_transfer(beta, l) * t;
    }
    // Columns 0, 1 (free w, w' at the nose), rows 2, 3 (w'', w''' at the tail).
    let d = t[(2, 0)] * t[(3, 1)] - t[(2, 1)] * t[(3, 0)];
    // Scale out the cosh² growth so the sign scan stays well-conditioned.
    let total_beta_l: f64 = segments
        .iter()
        .map(|&(l, mu)| (mu * omega * omega / ei).powf(0.25) * l)
        .sum();
    d / total_beta_l.cosh().powi(2)
}

/// Lowest `n` roots ω of the stepped-beam determinant (scan, then bisection).
fn stepped_roots(ei: f64, segments: &[(f64, f64)], n: usize) -> Vec<f64> {
    let mut roots = Vec::new();
    let f = |w: f64| stepped_determinant(w, ei, segments);
    let (mut a, mut fa) = (0.5, f(0.5));
    let step = 0.01;
    while roots.len() < n {
        let b = a + step;
        let fb = f(b);
        if fa.signum() != fb.signum() {
            let (mut lo, mut hi, mut flo) = (a, b, fa);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                let fm = f(mid);
                if fm.signum() == flo.signum() {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            roots.push(0.5 * (lo + hi));
        }
        a = b;
        fa = fb;
    }
    roots
}

#[test]
fn stepped_beam_transfer_matrix_reproduces_the_uniform_roots() {
    // Check of the exact reference itself: equal segments give βL = 4.7300 (Thomson App. D).
    let roots = stepped_roots(2.0e6, &[(5.0, 3.0), (5.0, 3.0)], 2);
    assert_relative_eq!(
        roots[0],
        4.7300f64.powi(2) / 100.0 * (2.0e6f64 / 3.0).sqrt(),
        max_relative = 1e-4
    );
    assert_relative_eq!(
        roots[1],
        7.8532f64.powi(2) / 100.0 * (2.0e6f64 / 3.0).sqrt(),
        max_relative = 1e-4
    );
}

#[test]
fn table1_beam_converges_from_above_to_the_exact_stepped_beam() {
    // Paper Table 1 beam. Bending: FE upper bounds falling as h⁴ (successive differences shrink
    // by about 16 per halving) to the exact stepped-beam roots (transfer matrix, Pestel &
    // Leckie) within 1e-6 after Richardson extrapolation; torsion (uniform GJ and I_x) as h²
    // (ratio 4) to f = 1/(2L) √(GJ/I_x) (Thomson ch. 9).
    let s = Settings::default();
    let counts = [8, 16, 32, 64, 128];
    let beams: Vec<FreeFreeBeam> = counts.iter().map(|&n| table1(n)).collect();
    let segments = [
        (s.forebody_length_m, s.forebody_mass_per_length_kg_m),
        (s.aftbody_length_m, s.aftbody_mass_per_length_kg_m),
    ];
    for (kind, order, exact_hz) in [
        (
            ModeKind::VerticalBending,
            4,
            stepped_roots(s.vertical_bending_stiffness_n_m2, &segments, 1)[0] / TAU,
        ),
        (
            ModeKind::LateralBending,
            4,
            stepped_roots(s.lateral_bending_stiffness_n_m2, &segments, 1)[0] / TAU,
        ),
        (
            ModeKind::Torsion,
            2,
            (s.torsional_stiffness_n_m2 / s.torsional_inertia_kg_m).sqrt() / (2.0 * s.length_m()),
        ),
    ] {
        let f: Vec<f64> = beams.iter().map(|b| omegas(b, kind)[0] / TAU).collect();
        for w in f.windows(2) {
            assert!(w[1] < w[0], "{kind:?}: not monotone from above: {f:?}");
        }
        assert!(
            f.iter().all(|&fi| fi > exact_hz),
            "{kind:?}: {f:?} vs {exact_hz}"
        );
        let ratio = (f[3] - f[2]) / (f[4] - f[3]);
        let expected = 2f64.powi(order);
        assert!(
            (ratio / expected - 1.0).abs() < 0.15,
            "{kind:?}: convergence ratio {ratio}, expected {expected}"
        );
        let richardson = f[4] - (f[3] - f[4]) / (expected - 1.0);
        eprintln!(
            "{kind:?}: f(N = {counts:?}) = {f:?} Hz; Richardson {richardson:.6} Hz; exact {exact_hz:.6} Hz"
        );
        assert_relative_eq!(richardson, exact_hz, max_relative = 1e-6);
        assert_relative_eq!(f[2], exact_hz, max_relative = 1e-3);
    }
}

fn sample_context<'a>(loaded: &'a LoadedConfig) -> ModelContext<'a> {
    ModelContext {
        settings: loaded.model_settings(NAME),
        key_path: "models.free-free-beam",
        file: &loaded.file,
        region: hsv_core::testing::sample_region("main_body"),
        registry: hsv_core::testing::empty_registry(),
    }
}

fn sample_beam_and_body() -> (FreeFreeBeam, PanelMesh, ModeShapes) {
    let loaded = LoadedConfig::sample().expect("sample config");
    let beam = FreeFreeBeam::from_context(&sample_context(&loaded)).expect("sample beam");
    let body = LoadedConfig::sample()
        .expect("sample")
        .vehicle()
        .expect("sample vehicle")
        .body;
    let shapes = beam.mode_shapes_on(&body).expect("shapes");
    shapes.check(&body).expect("shape size");
    (beam, body, shapes)
}

fn mode_index(beam: &FreeFreeBeam, kind: ModeKind) -> usize {
    beam.kept_kinds()
        .iter()
        .position(|&k| k == kind)
        .expect("kept kind")
}

#[test]
fn torsion_mode_rotates_the_side_panel_normals_about_x() {
    let (beam, body, shapes) = sample_beam_and_body();
    let k = mode_index(&beam, ModeKind::Torsion);
    // Scale so the largest twist is 1 mrad (small-rotation regime).
    let max_twist = (0..=304)
        .map(|i| beam.section_motion(k, -0.1 * f64::from(i)).rotation.x.abs())
        .fold(0.0, f64::max);
    let q = 1e-3 / max_twist;
    let mut q_vec = DVector::zeros(shapes.n_modes());
    q_vec[k] = q;
    let mut deformed = PanelMesh::default();
    shapes.deform(&body, &q_vec, &mut deformed);
    let side = body.surface_index("right-side").expect("right side");
    let mut checked = 0;
    for p in body.panels_in_surface(side) {
        let (n0, n1) = (body.panels[p].normal, deformed.panels[p].normal);
        let twist = q * beam.section_motion(k, body.panels[p].centroid.x).rotation.x;
        // Side face (normal ŷ): only u_y = −θx(x) (z − z_axis) tilts it, so
        // n' = ŷ + θx ẑ + θx'(x) (z − z_axis) x̂ to first order.
        let c = body.panels[p].centroid;
        let dx = 1e-3;
        let rate = q
            * (beam.section_motion(k, c.x + dx).rotation.x
                - beam.section_motion(k, c.x - dx).rotation.x)
            / (2.0 * dx);
        assert!(
            (n1.z - twist * n0.y).abs() < 0.02 * 1e-3,
            "panel {p}: n_z {} vs twist {twist}",
            n1.z
        );
        assert!(
            (n1.x - rate * (c.z - beam.axis_z_m()) * n0.y).abs() < 0.02 * 1e-3,
            "panel {p}: n_x {} vs twist rate {rate}",
            n1.x
        );
        checked += 1;
    }
    assert!(checked > 0);
    // And the twist is real: some side panel normal tilts by more than half the maximum.
    let tilted = body
        .panels_in_surface(side)
        .map(|p| deformed.panels[p].normal.z.abs())
        .fold(0.0, f64::max);
    assert!(tilted > 0.5e-3, "max tilt {tilted}");
}

#[test]
fn vertical_bending_moves_vertices_in_z_and_keeps_sections_plane() {
    // Euler-Bernoulli kinematics: every vertex of a station moves by w(x) in z; the only other
    // component is the plane section's rotation θy (z − z_axis) in x; nothing moves in y.
    let (beam, body, shapes) = sample_beam_and_body();
    let k = mode_index(&beam, ModeKind::VerticalBending);
    let col = shapes.vertex_displacement.column(k);
    let max_w = (0..body.vertices.len())
        .map(|v| col[3 * v + 2].abs())
        .fold(0.0, f64::max);
    assert!(max_w > 0.0);
    for (v, r) in body.vertices.iter().enumerate() {
        let motion = beam.section_motion(k, r.x);
        let (ux, uy, uz) = (col[3 * v], col[3 * v + 1], col[3 * v + 2]);
        assert!(uy.abs() < 1e-9 * max_w, "vertex {v} moves in y: {uy}");
        assert_relative_eq!(uz, motion.displacement.z, epsilon = 1e-9 * max_w);
        assert_relative_eq!(
            ux,
            motion.rotation.y * (r.z - beam.axis_z_m()),
            epsilon = 1e-9 * max_w
        );
    }
    // The lateral mode, conversely, moves nothing in z.
    let k = mode_index(&beam, ModeKind::LateralBending);
    let col = shapes.vertex_displacement.column(k);
    let max_v = (0..body.vertices.len())
        .map(|v| col[3 * v + 1].abs())
        .fold(0.0, f64::max);
    assert!((0..body.vertices.len()).all(|v| col[3 * v + 2].abs() < 1e-9 * max_v));
}

#[test]
fn sample_config_builds_the_paper_beam_with_three_named_modes() {
    let loaded = LoadedConfig::sample().expect("sample config");
    let registry = Registry::builtin().expect("registry");
    let entry = registry.get(NAME).expect("registered");
    assert_eq!(entry.role(), Role::Structure);
    let model = registry
        .create::<dyn hsv_core::structure::StructureModel>(NAME, &sample_context(&loaded))
        .expect("built from the sample config");
    let m = model.modal_model();
    assert_eq!(m.n_modes(), 3);
    let mut names = m.names.clone();
    names.sort();
    assert_eq!(
        names,
        ["lateral bending 1", "torsion 1", "vertical bending 1"]
    );
    let f = model.natural_frequencies_hz().expect("frequencies");
    assert!(f.windows(2).all(|w| w[0] < w[1]), "ascending: {f:?}");
    // Damping 2ζω with the sample's ζ.
    let beam = FreeFreeBeam::from_context(&sample_context(&loaded)).expect("beam");
    let zeta = beam.settings().damping_ratio;
    for (i, f_i) in f.iter().enumerate() {
        assert_relative_eq!(
            m.damping[(i, i)],
            2.0 * zeta * TAU * f_i,
            max_relative = 1e-12
        );
    }
    // Axis through the profile centroid: between the upper surface and the cowl.
    assert!(
        beam.axis_z_m() > -1.6 && beam.axis_z_m() < 2.6,
        "{}",
        beam.axis_z_m()
    );
    assert!(
        model.thermal_stiffness().is_none() && model.root_loads().is_none(),
        "the main body is temperature independent and free"
    );
}

fn err_of(settings: Settings) -> String {
    match FreeFreeBeam::new(settings, 0.0) {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_settings_are_errors_naming_the_quantity() {
    let base = Settings::default();
    let err = err_of(Settings {
        vertical_bending_stiffness_n_m2: -1.0,
        ..base.clone()
    });
    assert!(
        err.contains("vertical_bending_stiffness_n_m2") && err.contains("> 0"),
        "{err}"
    );
    let err = err_of(Settings {
        aftbody_mass_per_length_kg_m: 0.0,
        ..base.clone()
    });
    assert!(err.contains("aftbody_mass_per_length_kg_m"), "{err}");
    let err = err_of(Settings {
        torsional_stiffness_n_m2: f64::NAN,
        ..base.clone()
    });
    assert!(
        err.contains("torsional_stiffness_n_m2") && err.contains("NaN"),
        "{err}"
    );
    let err = err_of(Settings {
        elements: 10,
        vertical_bending_modes: 3,
        ..base.clone()
    });
    assert!(err.contains("elements") && err.contains("16"), "{err}");
    let err = err_of(Settings {
        damping_ratio: 1.5,
        ..base.clone()
    });
    assert!(err.contains("damping_ratio"), "{err}");
    assert!(matches!(
        FreeFreeBeam::new(base, f64::INFINITY),
        Err(ModelError::OutOfRange { .. })
    ));
}

#[test]
fn config_errors_name_file_and_key_path() {
    let loaded = LoadedConfig::sample().expect("sample config");
    let mut settings = loaded.model_settings(NAME).clone();
    settings.insert("element".into(), toml::Value::Integer(10));
    let ctx = ModelContext {
        settings: &settings,
        ..sample_context(&loaded)
    };
    let err = FreeFreeBeam::from_context(&ctx).unwrap_err().to_string();
    assert!(err.contains("models.free-free-beam.element"), "{err}");

    let mut settings = loaded.model_settings(NAME).clone();
    settings.insert("aftbody_length_m".into(), toml::Value::Float(20.0));
    let ctx = ModelContext {
        settings: &settings,
        ..sample_context(&loaded)
    };
    let err = FreeFreeBeam::from_context(&ctx).unwrap_err().to_string();
    assert!(
        err.contains("models.free-free-beam.aftbody_length_m") && err.contains("geometry.length_m"),
        "{err}"
    );

    let mut settings = loaded.model_settings(NAME).clone();
    settings.insert("torsional_stiffness_n_m2".into(), toml::Value::Float(-4.0));
    let ctx = ModelContext {
        settings: &settings,
        ..sample_context(&loaded)
    };
    let err = FreeFreeBeam::from_context(&ctx).unwrap_err().to_string();
    assert!(
        err.contains("models.free-free-beam.torsional_stiffness_n_m2") && err.contains("-4"),
        "{err}"
    );
}

#[test]
fn coincident_frequencies_of_different_kinds_are_not_mixed() {
    // Torsion tuned to coincide exactly with the first vertical bending mode of the FE model:
    // the degenerate pair must still come out as one pure mode of each kind.
    let mut s = uniform(40);
    s.torsion_modes = 1;
    s.axial_modes = 0;
    let w_bend = omegas(
        &FreeFreeBeam::new(s.clone(), 0.0).expect("beam"),
        ModeKind::VerticalBending,
    )[0];
    let w_torsion = omegas(
        &FreeFreeBeam::new(s.clone(), 0.0).expect("beam"),
        ModeKind::Torsion,
    )[0];
    s.torsional_stiffness_n_m2 *= (w_bend / w_torsion).powi(2);
    let beam = FreeFreeBeam::new(s, 0.0).expect("beam");
    let w_t = omegas(&beam, ModeKind::Torsion)[0];
    assert_relative_eq!(w_t, w_bend, max_relative = 1e-9);
    for f in &beam.elastic_modes().kinetic_energy_fractions {
        let max = f.iter().fold(0.0f64, |m, v| m.max(*v));
        assert!(max > 1.0 - 1e-9, "mixed mode: {f:?}");
    }
}

#[test]
fn interpolated_shapes_match_the_nodal_values() {
    let beam = table1(20);
    let mesh = beam.beam_mesh();
    let phi = beam.kept_shapes();
    for mode in 0..phi.ncols() {
        for (i, &s) in mesh.nodes_s_m.iter().enumerate() {
            let m = beam.section_motion(mode, -s);
            let node = Vector4::new(
                phi[(6 * i + 1, mode)],
                phi[(6 * i + 2, mode)],
                phi[(6 * i + 3, mode)],
                phi[(6 * i + 4, mode)],
            );
            let got = Vector4::new(
                m.displacement.y,
                m.displacement.z,
                m.rotation.x,
                m.rotation.y,
            );
            assert!(
                (got - node).amax() < 1e-12 * phi.column(mode).amax(),
                "mode {mode} node {i}"
            );
            assert_relative_eq!(
                m.rotation.z,
                phi[(6 * i + 5, mode)],
                epsilon = 1e-12 * phi.column(mode).amax()
            );
        }
    }
}
