//! `full-order` and `pod` with a built-up structure (`skin_thickness_m`): two titanium-like skins
//! at the faces of the plate with still air between them, heated through the lower face only (one
//! file: the checks share the slab, its flux and its closed forms below).
//!
//! A 1 m × 1 m plate 20 mm thick (one grid element, adiabatic sides, so conduction is
//! one-dimensional through the thickness) of 2 mm constant-property skins (ρ = 4430 kg/m³,
//! c_p = 560 J/(kg K), k = 7 W/(m K)) over a 16 mm interior of the built-in `air` (Incropera &
//! DeWitt Table A.4, k 0.026-0.038 W/(m K) over the run), starting at 300 K; a uniform flux
//! q = 40 kW/m² enters the lower face for 20 s.
//!
//! Closed forms:
//! - **Lumped lower skin** (first law on the skin; its Biot-like number q t_s / (2 k) / ΔT_rise
//!   is 3.5 %, and the mean temperature is the stored heat whatever the gradient): the skin's
//!   mean rises at q / (ρ c_p t_s) = 8.06 K/s, less what leaks into the interior.
//! - **Conduction leak through the interior** (Fourier's law across the gap, Incropera &
//!   DeWitt §3.1): at most k_air(T_max) ΔT / h_i, with ΔT ≤ the lower skin's lumped rise
//!   q t / (ρ c_p t_s); integrated over the run, Q_leak ≤ k_air(T_max) q t² / (2 ρ c_p t_s h_i),
//!   which bounds the heat the upper skin receives (the air's own heat capacity and its
//!   diffusion time h_i²/α ≈ 12 s only delay it).

mod common;
use approx::assert_relative_eq;
use common::{CP, RHO, constant_material, faces};
use hsv_core::material::{Material, MaterialSetting};
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind};
use hsv_core::registry::Registry;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::ConductionModel;
use hsv_model_conduction::full_order::LayerSetting;
use hsv_model_conduction::grid::Quadrature;
use hsv_model_conduction::{
    FullOrder, FullOrderSettings, Pod, PodBasis, PodSettings, collect_snapshots,
};
use nalgebra::DVector;

/// Plate (outer mould line) thickness, m.
const H: f64 = 0.02;
/// Skin thickness, m.
const T_S: f64 = 0.002;
/// Heat flux into the lower face, W/m².
const Q: f64 = 4.0e4;
const T0: f64 = 300.0;
const DT: f64 = 0.1;
const STEPS: usize = 200;

fn settings() -> FullOrderSettings {
    FullOrderSettings {
        structure_material: constant_material(),
        structure_sublayers: 2,
        skin_thickness_m: Some(T_S),
        interior_sublayers: 4,
        minimum_thickness_m: 1e-3,
        picard_tolerance_k: 1e-7,
        ..FullOrderSettings::default()
    }
}

fn slab() -> FullOrder {
    let grid = SurfaceGrid::rectangular(1.0, 1.0, H, 1, 1).unwrap();
    FullOrder::new(&grid, &faces(H), settings()).unwrap()
}

/// Flux into the lower face only: panel 0 is the upper face, panel 1 the lower.
fn lower_face_flux(q_w_m2: f64) -> [f64; 2] {
    [0.0, q_w_m2]
}

/// Trapezoid mean over the levels lo..=hi of plate node 0.
fn level_mean(model: &FullOrder, state: &DVector<f64>, (lo, hi): (usize, usize)) -> f64 {
    let g = model.thermal_grid();
    let n = (hi - lo) as f64;
    (lo..=hi)
        .map(|l| {
            let w = if l == lo || l == hi { 0.5 } else { 1.0 };
            w * state[g.dof(0, l)]
        })
        .sum::<f64>()
        / n
}

/// (lower skin mean, upper skin mean) at plate node 0, K.
fn skin_means(model: &FullOrder, state: &DVector<f64>) -> (f64, f64) {
    let ranges = &model.thermal_grid().structure_ranges;
    assert_eq!(ranges.len(), 2, "two skins");
    (
        level_mean(model, state, ranges[0]),
        level_mean(model, state, ranges[1]),
    )
}

/// Lumped rise of the heated skin with no leak, q t / (ρ c_p t_s), K.
fn lumped_rise(q_w_m2: f64, time_s: f64) -> f64 {
    q_w_m2 * time_s / (RHO * CP * T_S)
}

/// Closed-form bound on the heat through the interior over `time_s`, J/m²:
/// k_air(T_max) q t² / (2 ρ c_p t_s h_i) (module docs).
fn leak_bound_j_m2(q_w_m2: f64, time_s: f64) -> f64 {
    let hottest = T0 + lumped_rise(q_w_m2, time_s);
    let k_air = Material::air().conductivity_w_m_k(hottest).unwrap();
    let h_interior = H - 2.0 * T_S;
    k_air * q_w_m2 * time_s * time_s / (2.0 * RHO * CP * T_S * h_interior)
}

/// The 20 s run: the state after every step.
fn run(model: &mut FullOrder, q_w_m2: f64) -> Vec<DVector<f64>> {
    collect_snapshots(model, T0, DT, STEPS, 1, |_, q| {
        q.copy_from_slice(&lower_face_flux(q_w_m2));
        Ok(())
    })
    .unwrap()
}

/// Energy balance of the built-up slab against the closed forms of the module docs:
/// - the lower skin's mean rise within 1 % of the lumped q t / (ρ c_p t_s) = 161.2 K, and not
///   above it (heat only leaves it);
/// - the upper skin's rise positive and below the conduction-leak bound
///   k_air ΔT / h_i integrated (0.77 K), so within a few K of its start;
/// - all the heat is stored (first law, 1e-6 relative);
/// - ΔT from `node_temperature_differences` is mean(lower skin) − mean(upper skin) (1e-9 K) at
///   every node, and `node_temperatures` the mean of the two skins' means.
#[test]
fn a_built_up_slab_heated_below_stores_the_heat_in_its_lower_skin() {
    let mut model = slab();
    let states = run(&mut model, Q);
    let state = states.last().unwrap();
    let t = DT * STEPS as f64;
    let (lower, upper) = skin_means(&model, state);
    let lumped = lumped_rise(Q, t);
    let leak_bound = leak_bound_j_m2(Q, t) / (RHO * CP * T_S);
    println!(
        "lower skin rise {:.4} K (lumped {lumped:.4} K), upper skin rise {:.4} K (leak bound \
         {leak_bound:.4} K)",
        lower - T0,
        upper - T0
    );
    assert_relative_eq!(lower - T0, lumped, max_relative = 0.01);
    assert!(lower - T0 <= lumped, "{} > {lumped}", lower - T0);
    assert!(
        upper - T0 > 0.0 && upper - T0 < leak_bound,
        "{}",
        upper - T0
    );
    assert!(
        leak_bound < 1.0,
        "the closed-form bound itself: {leak_bound} K"
    );
    let stored = model.stored_energy_j(state, T0).unwrap();
    assert_relative_eq!(stored, Q * t, max_relative = 1e-6);
    // Outputs the plate model receives.
    let n = model.n_nodes();
    let (mut difference, mut mean) = (vec![0.0; n], vec![0.0; n]);
    model.node_temperature_differences(state, &mut difference);
    model.node_temperatures(state, &mut mean);
    for node in 0..n {
        assert_relative_eq!(difference[node], lower - upper, epsilon = 1e-9);
        assert_relative_eq!(mean[node], 0.5 * (lower + upper), epsilon = 1e-9);
    }
    // ΔT against the closed forms: the lumped rise less at most 1 % and the upper skin's rise.
    assert_relative_eq!(
        difference[0],
        lumped,
        max_relative = 0.01 + leak_bound / lumped
    );
    // The outer mould line is where the solid plate's is: the faces at ∓h/2, the skins t_s thick.
    let g = model.thermal_grid();
    let s = |level: usize| g.positions_m[g.dof(0, level)].coords.dot(&g.up[0]);
    let (lo, _) = g.structure_ranges[0];
    let (_, hi) = g.structure_ranges[1];
    assert_relative_eq!(s(lo), -0.5 * H, epsilon = 1e-15);
    assert_relative_eq!(s(hi), 0.5 * H, epsilon = 1e-15);
    assert_relative_eq!(s(g.structure_ranges[0].1) - s(lo), T_S, epsilon = 1e-15);
}

/// `pod` trained on the snapshots of that run (every 0.1 s step, 200 snapshots, 6 modes) against
/// the full-order model, at the trained flux and at q = 30 kW/m², which is not in the
/// snapshots: every temperature, both skin means and ΔT within the POD tests' usual 1 % of the
/// largest temperature rise.
#[test]
fn pod_reproduces_the_built_up_slab() {
    let mut full = slab();
    let snapshots = run(&mut full, Q);
    let basis = PodBasis::from_snapshots(&snapshots, 6, settings()).unwrap();
    println!("energy fraction {:.9}", basis.energy_fraction);
    for q in [Q, 3.0e4] {
        let mut full = slab();
        let mut pod = Pod::new(
            &full,
            basis.clone(),
            PodSettings {
                modes: 6,
                picard_tolerance_k: 1e-7,
                ..PodSettings::default()
            },
        )
        .unwrap();
        let mut t_full = full.uniform_state(T0).unwrap();
        let mut a = pod.uniform_state(T0).unwrap();
        let (mut worst, mut rise): (f64, f64) = (0.0, 0.0);
        let n = full.n_nodes();
        let (mut d_full, mut d_pod) = (vec![0.0; n], vec![0.0; n]);
        let (mut m_full, mut m_pod) = (vec![0.0; n], vec![0.0; n]);
        let mut worst_output: f64 = 0.0;
        for _ in 0..STEPS {
            full.step(&mut t_full, &lower_face_flux(q), DT).unwrap();
            pod.step(&mut a, &lower_face_flux(q), DT).unwrap();
            let reconstructed = pod.reconstruct(&a);
            worst = worst.max((&reconstructed - &t_full).amax());
            rise = rise.max(t_full.max() - T0);
            full.node_temperature_differences(&t_full, &mut d_full);
            pod.node_temperature_differences(&a, &mut d_pod);
            full.node_temperatures(&t_full, &mut m_full);
            pod.node_temperatures(&a, &mut m_pod);
            for i in 0..n {
                worst_output = worst_output
                    .max((d_full[i] - d_pod[i]).abs())
                    .max((m_full[i] - m_pod[i]).abs());
            }
        }
        let (lower_f, upper_f) = skin_means(&full, &t_full);
        let (lower_p, upper_p) = skin_means(&full, &pod.reconstruct(&a));
        println!(
            "q {q}: largest |T_pod - T_full| {worst:.2e} K, outputs {worst_output:.2e} K, rise \
             {rise:.1} K; skins {lower_f:.3}/{upper_f:.3} K full, {lower_p:.3}/{upper_p:.3} K pod"
        );
        assert!(rise > 100.0);
        assert!(worst < 0.01 * rise, "{worst} K vs rise {rise} K");
        assert!(worst_output < 0.01 * rise, "{worst_output} K vs {rise} K");
        assert!((lower_f - lower_p).abs() < 0.01 * rise);
        assert!((upper_f - upper_p).abs() < 0.01 * rise);
    }
}

fn create(text: &str) -> Result<Box<dyn ConductionModel>, String> {
    let settings: toml::Table = toml::from_str(text).unwrap();
    Registry::builtin()
        .unwrap()
        .create::<dyn ConductionModel>(
            "full-order",
            &common::sample_context(&settings, "models.full-order"),
        )
        .map_err(|e| e.to_string())
}

/// Bad built-up settings name their key path: a skin that is not finite and > 0, skins that
/// leave no room for the interior on the sample surface, an unknown interior material, no
/// elements through the interior; and the model built directly names the key too.
#[test]
fn bad_built_up_settings_name_their_keys() {
    for (text, key) in [
        (
            "skin_thickness_m = -0.001",
            "models.full-order.skin_thickness_m",
        ),
        (
            "skin_thickness_m = 0.0",
            "models.full-order.skin_thickness_m",
        ),
        (
            "skin_thickness_m = nan",
            "models.full-order.skin_thickness_m",
        ),
        (
            "skin_thickness_m = 0.5",
            "models.full-order.skin_thickness_m",
        ),
        (
            "skin_thickness_m = 0.001\ninterior_material = \"unobtainium\"",
            "models.full-order.interior_material",
        ),
        (
            "skin_thickness_m = 0.001\ninterior_sublayers = 0",
            "models.full-order.interior_sublayers",
        ),
    ] {
        let err = create(text).err().expect(text);
        assert!(err.contains(key), "{text}: {err}");
    }
    let err = create("skin_thickness_m = -0.001").err().unwrap();
    assert!(err.contains("-0.001") && err.contains("> 0"), "{err}");
    let err = create("skin_thickness_m = 0.5").err().unwrap();
    assert!(err.contains("interior has room"), "{err}");
    // Direct construction.
    let grid = SurfaceGrid::rectangular(1.0, 1.0, H, 1, 1).unwrap();
    for skin in [f64::INFINITY, 0.5 * H] {
        let err = FullOrder::new(
            &grid,
            &faces(H),
            FullOrderSettings {
                skin_thickness_m: Some(skin),
                ..settings()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("skin_thickness_m"), "{err}");
    }
}

/// The registered model built up on the sample lifting surface (1.5 mm skins, 2 mm minimum
/// interior at the sharp edges): every watt of a uniform flux Σ q A Δt is stored (first law,
/// 1e-5 as for the solid surface), its interior adds one material and the air's levels, and a
/// uniform state has no through-thickness difference.
#[test]
fn registered_built_up_model_heats_the_sample_surface() {
    let mut model = create("skin_thickness_m = 0.0015").unwrap();
    let mut state = model.uniform_state(293.0).unwrap();
    let mut difference = vec![1.0; model.n_nodes()];
    model.node_temperature_differences(&state, &mut difference);
    assert!(difference.iter().all(|d| d.abs() < 1e-12));
    let n = model.n_surface_panels();
    for _ in 0..4 {
        model.step(&mut state, &vec![5.0e4; n], 0.5).unwrap();
    }
    let loaded = hsv_core::config::LoadedConfig::sample().unwrap();
    let cfg = &loaded.config.lifting_surface;
    let side = hsv_core::geometry::Side::Right;
    let mesh = hsv_core::geometry::lifting_surface_mesh(cfg, side).unwrap();
    let grid = SurfaceGrid::lifting_surface(cfg, side, 16, 8).unwrap();
    let direct = FullOrder::new(
        &grid,
        &mesh,
        FullOrderSettings {
            skin_thickness_m: Some(0.0015),
            ..FullOrderSettings::default()
        },
    )
    .unwrap();
    assert_eq!(direct.materials().len(), 2);
    assert_eq!(direct.thermal_grid().n_levels, 6);
    assert_eq!(direct.n_states(), model.n_states());
    let wetted: f64 = mesh
        .panels
        .iter()
        .filter(|p| mesh.surfaces[p.surface as usize].region == RegionKind::LiftingSurface)
        .map(|p| p.area_m2)
        .sum();
    let stored = direct.stored_energy_j(&state, 293.0).unwrap();
    assert_relative_eq!(stored, 5.0e4 * wetted * 2.0, max_relative = 1e-5);
}

/// The settings a POD basis records and fingerprints: a solid configuration serializes as before
/// the built-up keys existed (no new keys, so its cached basis still serves); skins or an
/// interior other than the default do appear, so a basis built for one is not reused for the
/// other, and a basis built solid is refused by a built-up model.
#[test]
fn built_up_settings_change_what_a_pod_basis_records() {
    let solid = serde_json::to_value(FullOrderSettings::default()).unwrap();
    for key in [
        "skin_thickness_m",
        "interior_material",
        "interior_sublayers",
    ] {
        assert!(solid.get(key).is_none(), "{key} in {solid}");
    }
    let built_up = FullOrderSettings {
        skin_thickness_m: Some(0.0015),
        ..FullOrderSettings::default()
    };
    let json = serde_json::to_value(&built_up).unwrap();
    assert_eq!(json["skin_thickness_m"], 0.0015);
    let back: FullOrderSettings = serde_json::from_value(json).unwrap();
    assert_eq!(back, built_up);
    let other_interior = FullOrderSettings {
        interior_material: MaterialSetting::Name("vdi-l1400".to_owned()),
        interior_sublayers: 3,
        ..built_up.clone()
    };
    let json = serde_json::to_value(&other_interior).unwrap();
    assert_eq!(json["interior_material"], "vdi-l1400");
    assert_eq!(json["interior_sublayers"], 3);
    // A basis of the solid slab does not serve the built-up one.
    let grid = SurfaceGrid::rectangular(1.0, 1.0, H, 1, 1).unwrap();
    let solid_slab = FullOrder::new(
        &grid,
        &faces(H),
        FullOrderSettings {
            skin_thickness_m: None,
            ..settings()
        },
    )
    .unwrap();
    let mut solid_model = solid_slab.clone();
    let snapshots = collect_snapshots(&mut solid_model, T0, DT, 20, 1, |_, q| {
        q.copy_from_slice(&lower_face_flux(Q));
        Ok(())
    })
    .unwrap();
    let basis = PodBasis::from_snapshots(&snapshots, 2, solid_slab.settings().clone()).unwrap();
    let err = Pod::new(&slab(), basis, PodSettings::default())
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("basis"), "{err}");
}

/// Solid (no `skin_thickness_m`), as before the built-up structure existed: one structural
/// range from the lower face to the upper, ΔT exactly T(lowest level) − T(highest) and the node
/// temperature exactly the trapezoid average, bit for bit; the settings serialize (and so
/// fingerprint a POD basis) exactly as they did.
#[test]
fn a_solid_structure_is_unchanged() {
    let grid = SurfaceGrid::rectangular(1.0, 1.0, H, 1, 1).unwrap();
    let mut model = FullOrder::new(
        &grid,
        &faces(H),
        FullOrderSettings {
            skin_thickness_m: None,
            structure_sublayers: 4,
            ..settings()
        },
    )
    .unwrap();
    assert_eq!(model.materials().len(), 1);
    assert_eq!(model.thermal_grid().structure_ranges, vec![(0, 4)]);
    let mut state = model.uniform_state(T0).unwrap();
    for _ in 0..10 {
        model.step(&mut state, &lower_face_flux(Q), DT).unwrap();
    }
    let g = model.thermal_grid();
    let n = model.n_nodes();
    let (mut difference, mut mean) = (vec![0.0; n], vec![0.0; n]);
    model.node_temperature_differences(&state, &mut difference);
    model.node_temperatures(&state, &mut mean);
    for node in 0..n {
        let at = |level: usize| state[g.dof(node, level)];
        assert_eq!(difference[node], at(0) - at(4));
        let trapezoid = [0.125, 0.25, 0.25, 0.25, 0.125];
        let expected: f64 = (0..=4).map(|l| trapezoid[l] * at(l)).sum();
        assert_relative_eq!(mean[node], expected, max_relative = 1e-15);
    }
    assert_eq!(
        serde_json::to_string(&FullOrderSettings::default()).unwrap(),
        "{\"elements_chordwise\":16,\"elements_spanwise\":8,\"structure_material\":\"ti-6al-4v\",\
         \"structure_sublayers\":2,\"minimum_thickness_m\":0.002,\"layers\":[],\
         \"picard_tolerance_k\":0.001,\"max_picard_iterations\":30}"
    );
}

/// `hsv-run describe full-order` prints the defaults, the built-up keys included.
#[test]
fn the_settings_doc_is_the_defaults() {
    let doc: FullOrderSettings =
        toml::from_str(hsv_model_conduction::full_order::SETTINGS_DOC).unwrap();
    assert_eq!(doc, FullOrderSettings::default());
    assert!(hsv_model_conduction::full_order::SETTINGS_DOC.contains("skin_thickness_m"));
}

/// A 1 m × 1 m plate, 4 × 4 elements (0.25 m wide), with outer faces at ∓h/2: the upper face
/// one panel, the lower face 4 × 4 panels over the elements (so panel i heats the 4 face
/// nodes of element i), the lower panels first in row-major (x, then y) order.
fn split_lower_face(h: f64) -> PanelMesh {
    let v = |x: f64, y: f64, z: f64| nalgebra::Point3::new(x, y, z);
    let mut vertices = vec![
        v(0.0, 0.0, -h / 2.0),
        v(-1.0, 0.0, -h / 2.0),
        v(-1.0, 1.0, -h / 2.0),
        v(0.0, 1.0, -h / 2.0),
    ];
    let mut specs = vec![PanelSpec::quad(0, 1, 2, 3, 0)];
    for j in 0..4 {
        for i in 0..4 {
            let (x0, x1) = (-0.25 * i as f64, -0.25 * (i + 1) as f64);
            let (y0, y1) = (0.25 * j as f64, 0.25 * (j + 1) as f64);
            let first = vertices.len();
            vertices.extend([
                v(x0, y0, h / 2.0),
                v(x0, y1, h / 2.0),
                v(x1, y1, h / 2.0),
                v(x1, y0, h / 2.0),
            ]);
            specs.push(PanelSpec::quad(first, first + 1, first + 2, first + 3, 0));
        }
    }
    let mesh = common::plate_mesh(vertices, &specs);
    assert!(mesh.panels[0].normal.z < 0.0 && mesh.panels.iter().skip(1).all(|p| p.normal.z > 0.0));
    mesh
}

/// `material` with the properties of its first table row (293 K for the built-in tables) at
/// every temperature from 200 K to 1800 K: constant k and c_p, for which the midpoint capacity
/// makes the first law exact, and a floor low enough that a run that undershoots 293 K reports
/// by how much.
fn held_at_floor(material: Material) -> MaterialSetting {
    let mut m = material;
    let (mut low, mut high) = (m.table[0], m.table[0]);
    low.temperature_k = 200.0;
    high.temperature_k = 1800.0;
    m.table = vec![low, high];
    MaterialSetting::Table(m)
}

/// Thermal-protection thickness and skin thickness of the thin stack, m.
const TPS_M: f64 = 0.002;
const THIN_SKIN_M: f64 = 0.0025;
/// Heat flux into the heated half of the lower face, W/m².
const HARD_Q: f64 = 3.0e5;

/// The 20 mm plate with 2.5 mm Ti-6Al-4V skins in 2 sub-layers and 2 mm `vdi-l1400` outer
/// layers in 2 sub-layers on 4 × 4 elements 0.25 m wide: elements 200 (skins) and 250 (outer
/// layers) times wider than thick.
fn thin_stack(
    quadrature: Option<Quadrature>,
    structure: MaterialSetting,
    tps: MaterialSetting,
) -> FullOrder {
    let grid = SurfaceGrid::rectangular(1.0, 1.0, H, 4, 4).unwrap();
    let settings = FullOrderSettings {
        structure_material: structure,
        structure_sublayers: 2,
        skin_thickness_m: Some(THIN_SKIN_M),
        conduction_quadrature: quadrature,
        layers: vec![LayerSetting {
            thickness_m: TPS_M,
            material: tps,
            sublayers: 2,
        }],
        minimum_thickness_m: 1e-3,
        picard_tolerance_k: 1e-9,
        ..FullOrderSettings::default()
    };
    FullOrder::new(&grid, &split_lower_face(H), settings).unwrap()
}

/// 1 s in 0.1 s steps from 293 K with HARD_Q on the lower panels of the half y < 0.5 (none
/// elsewhere): (lowest temperature of any dof at any step, K; stored heat over Σ q A t).
fn heat_half(model: &mut FullOrder) -> Result<(f64, f64), String> {
    let mut state = model.uniform_state(293.0).map_err(|e| e.to_string())?;
    let flux: Vec<f64> = (0..model.n_surface_panels())
        .map(|p| if (1..=8).contains(&p) { HARD_Q } else { 0.0 })
        .collect();
    let mut lowest = f64::INFINITY;
    for _ in 0..10 {
        model
            .step(&mut state, &flux, 0.1)
            .map_err(|e| e.to_string())?;
        lowest = lowest.min(state.min());
    }
    let stored = model
        .stored_energy_j(&state, 293.0)
        .map_err(|e| e.to_string())?;
    Ok((lowest, stored / (HARD_Q * 0.5 * 1.0)))
}

/// The discrete maximum principle (Ciarlet & Raviart 1973; `grid` module docs) in thin
/// elements: heating half of the lower face of the built-up plate from 293 K, 300 kW/m² for 1 s,
/// with no heat taken out anywhere, no temperature may fall below 293 K.
/// - Constant properties (`ti-6al-4v` and `vdi-l1400` at 293 K): with `nodal` the lowest
///   temperature of any dof at any step is ≥ 293 K less 1e-9 K, with `gauss` it undershoots
///   (by more than 1 K); both store all the heat, Σ q A t, to 1e-6 (first law: K's rows sum to
///   zero under either quadrature, and the midpoint capacity is exact for constant c_p).
/// - The built-in tables (which start at 293 K): `nodal`, the built-up default, stays ≥ 293 K
///   less 1e-9 K and stores the heat to 1e-5 (the midpoint capacity is exact only for c_p linear
///   over a step, and the heated face crosses several table rows per 0.1 s step), while `gauss`
///   is refused below the tables' floor.
#[test]
fn nodal_quadrature_keeps_a_thin_built_up_plate_above_its_initial_temperature() {
    let constant = |q| {
        thin_stack(
            q,
            held_at_floor(Material::ti_6al_4v()),
            held_at_floor(Material::vdi_l1400()),
        )
    };
    let mut nodal = constant(Some(Quadrature::Nodal));
    let (lowest_nodal, energy_nodal) = heat_half(&mut nodal).unwrap();
    let (lowest_gauss, energy_gauss) = heat_half(&mut constant(Some(Quadrature::Gauss))).unwrap();
    println!(
        "constant properties: lowest temperature nodal {lowest_nodal:.12} K, gauss \
         {lowest_gauss:.6} K (undershoot {:.4} K); stored/supplied nodal {energy_nodal:.12}, \
         gauss {energy_gauss:.12}",
        293.0 - lowest_gauss
    );
    assert!(lowest_nodal >= 293.0 - 1e-9, "{lowest_nodal}");
    assert!(lowest_gauss < 293.0 - 1.0, "{lowest_gauss}");
    assert_relative_eq!(energy_nodal, 1.0, max_relative = 1e-6);
    assert_relative_eq!(energy_gauss, 1.0, max_relative = 1e-6);

    let built_in = |q| {
        let name = |n: &str| MaterialSetting::Name(n.to_owned());
        thin_stack(q, name("ti-6al-4v"), name("vdi-l1400"))
    };
    let mut default = built_in(None);
    assert_eq!(default.settings().quadrature(), Quadrature::Nodal);
    let (lowest, energy) = heat_half(&mut default).unwrap();
    let refused = heat_half(&mut built_in(Some(Quadrature::Gauss))).unwrap_err();
    println!(
        "built-in tables: lowest temperature nodal {lowest:.12} K, stored/supplied \
         {energy:.12}; gauss: {refused}"
    );
    assert!(lowest >= 293.0 - 1e-9, "{lowest}");
    assert_relative_eq!(energy, 1.0, max_relative = 1e-5);
    assert!(refused.contains("outside the model's range"), "{refused}");
}

/// The quadrature in effect and what a POD basis is fingerprinted by: absent, `gauss` when solid
/// (serialized as before the key, no `conduction_quadrature`) and `nodal` when built up (written
/// out, so a built-up basis from before the key, built with Gauss, is not reused); an explicit
/// `gauss` on a solid structure fingerprints as the absent key; the key parses in kebab case and
/// an unknown value is an error naming the key path.
#[test]
fn the_conduction_quadrature_defaults_by_structure_and_fingerprints() {
    let solid = FullOrderSettings::default();
    assert_eq!(solid.quadrature(), Quadrature::Gauss);
    assert_eq!(solid.resolved(), solid);
    let explicit_gauss = FullOrderSettings {
        conduction_quadrature: Some(Quadrature::Gauss),
        ..solid.clone()
    };
    assert_eq!(explicit_gauss.resolved(), solid);
    let built_up = FullOrderSettings {
        skin_thickness_m: Some(0.0015),
        ..solid.clone()
    };
    assert_eq!(built_up.quadrature(), Quadrature::Nodal);
    let json = serde_json::to_value(built_up.resolved()).unwrap();
    assert_eq!(json["conduction_quadrature"], "nodal");
    assert!(
        serde_json::to_value(&built_up)
            .unwrap()
            .get("conduction_quadrature")
            .is_none()
    );
    let gauss_built_up = FullOrderSettings {
        conduction_quadrature: Some(Quadrature::Gauss),
        ..built_up.clone()
    };
    assert_ne!(gauss_built_up.resolved(), built_up.resolved());
    let parsed: FullOrderSettings = toml::from_str("conduction_quadrature = \"nodal\"").unwrap();
    assert_eq!(parsed.quadrature(), Quadrature::Nodal);
    let err = create("conduction_quadrature = \"simpson\"").err().unwrap();
    assert!(
        err.contains("models.full-order") && err.contains("conduction_quadrature"),
        "{err}"
    );
    // A basis recorded with `nodal` written out serves the built-up model left at its default.
    let mut model = slab();
    let snapshots = collect_snapshots(&mut model, T0, DT, 20, 1, |_, q| {
        q.copy_from_slice(&lower_face_flux(Q));
        Ok(())
    })
    .unwrap();
    let recorded = FullOrderSettings {
        conduction_quadrature: Some(Quadrature::Nodal),
        ..settings()
    };
    let basis = PodBasis::from_snapshots(&snapshots, 2, recorded).unwrap();
    let two = PodSettings {
        modes: 2,
        ..PodSettings::default()
    };
    Pod::new(&slab(), basis.clone(), two.clone()).unwrap();
    let gauss_slab = FullOrder::new(
        &SurfaceGrid::rectangular(1.0, 1.0, H, 1, 1).unwrap(),
        &faces(H),
        FullOrderSettings {
            conduction_quadrature: Some(Quadrature::Gauss),
            ..settings()
        },
    )
    .unwrap();
    let err = Pod::new(&gauss_slab, basis, two).err().unwrap().to_string();
    assert!(err.contains("other [models.full-order] settings"), "{err}");
}
