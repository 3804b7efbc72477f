//! The registered `ritz-plate` model: settings, mode shapes on the aero meshes, bad input.

mod common;
use common::{build, descriptor};

use approx::assert_relative_eq;
use hsv_core::config::LoadedConfig;
use hsv_core::geometry::{Side, lifting_surface_mesh};
use hsv_core::registry::{Constructor, ModelContext};
use hsv_core::surface_grid::SurfaceGrid;
use hsv_model_ritz_plate::NAME;
use nalgebra::DVector;

const SMALL: &str = "elements_chordwise = 8\nelements_spanwise = 6\n";

#[test]
fn sample_config_table_builds_the_vehicle_surface() {
    let loaded = LoadedConfig::sample().expect("sample");
    let settings = loaded.model_settings(NAME).clone();
    // The defaults are the sample's values (the benches rely on it).
    let parsed: hsv_model_ritz_plate::Settings = toml::Value::Table(settings.clone())
        .try_into()
        .expect("parses");
    assert_eq!(parsed, hsv_model_ritz_plate::Settings::default());
    let ctx = ModelContext {
        settings: &settings,
        key_path: "models.ritz-plate",
        file: "sample",
        region: hsv_core::testing::sample_region("right_surface"),
        registry: hsv_core::testing::empty_registry(),
    };
    let Constructor::Structure(f) = descriptor().constructor else {
        panic!("structure")
    };
    let model = f(&ctx).expect("sample builds");
    let freq = model.natural_frequencies_hz().expect("frequencies");
    assert_eq!(freq.len(), 15);
    assert!(freq.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(model.modal_model().names[0], "bending 1");
    eprintln!("sample surface at 293 K: {freq:?}");
}

/// The rectangular planform gives a cantilever plate: with Leissa's CFFF λ₁ = 3.492 (NASA
/// SP-160, 1969, ch. 4) for a 1 m square, 10 mm Ti-6Al-4V plate, f₁ = λ₁/(2π a²) √(D/(ρh))
/// within 2 % on a 16 × 16 grid.
#[test]
fn rectangular_planform_matches_the_cantilever_plate() {
    let model = build(
        "planform = \"rectangular\"\nroot = \"clamped\"\nelements_chordwise = 16\nelements_spanwise = 16\n\
         [rectangular]\nchord_m = 1.0\nspan_m = 1.0\nthickness_m = 0.01\n",
    )
    .expect("rectangular");
    let ti = hsv_core::material::Material::ti_6al_4v();
    let e = ti.youngs_modulus_pa(293.0).unwrap();
    let nu = ti.poisson_ratio;
    let d = e * 1e-6 / (12.0 * (1.0 - nu * nu));
    let f1 = 3.492 / (2.0 * std::f64::consts::PI) * (d / (ti.density_kg_m3 * 0.01)).sqrt();
    let f = model.natural_frequencies_hz().expect("frequencies");
    assert_relative_eq!(f[0], f1, max_relative = 0.02);
}

/// A uniform non-structural mass m (kg/m², e.g. thermal-protection layers) leaves the
/// stiffness alone, so the cantilever plate's frequencies become Leissa's with ρh + m in place of
/// ρh: f = λ/(2π a²) √(D/(ρh + m)) (Kirchhoff, NASA SP-160, 1969, eq. 4.1, λ₁ = 3.492), within
/// the 2 % of the bare check; the first five frequencies shift by exactly √(ρh/(ρh + m)) to
/// 1e-3 (Mindlin's rotary inertia, left out of the added mass, is O((h/a)²) = 1e-4 here); and
/// the mass properties carry (ρh + m) a² (1e-10).
#[test]
fn non_structural_mass_lowers_the_frequencies_as_plate_theory_says() {
    let plate = "planform = \"rectangular\"\nroot = \"clamped\"\nelements_chordwise = 16\n\
                 elements_spanwise = 16\n";
    let dims = "[rectangular]\nchord_m = 1.0\nspan_m = 1.0\nthickness_m = 0.01\n";
    let added = 22.15;
    let bare = build(&format!("{plate}{dims}")).expect("bare");
    let loaded = build(&format!(
        "{plate}non_structural_mass_kg_m2 = {added}\n{dims}"
    ))
    .expect("with added mass");
    let ti = hsv_core::material::Material::ti_6al_4v();
    let rho_h = ti.density_kg_m3 * 0.01;
    let e = ti.youngs_modulus_pa(293.0).unwrap();
    let d = e * 1e-6 / (12.0 * (1.0 - ti.poisson_ratio * ti.poisson_ratio));
    let f1 = 3.492 / (2.0 * std::f64::consts::PI) * (d / (rho_h + added)).sqrt();
    let (f_bare, f_loaded) = (
        bare.natural_frequencies_hz().expect("bare"),
        loaded.natural_frequencies_hz().expect("loaded"),
    );
    assert_relative_eq!(f_loaded[0], f1, max_relative = 0.02);
    let scale = (rho_h / (rho_h + added)).sqrt();
    for k in 0..5 {
        assert_relative_eq!(f_loaded[k] / f_bare[k], scale, max_relative = 1e-3);
    }
    let mass = loaded.mass_properties().expect("mass").mass_properties();
    assert_relative_eq!(mass.mass_kg, rho_h + added, max_relative = 1e-10);
    let err = build(&format!("{plate}non_structural_mass_kg_m2 = -1.0\n{dims}"))
        .err()
        .expect("negative mass")
        .to_string();
    assert!(err.contains("non_structural_mass_kg_m2"), "{err}");
}

#[test]
fn bad_settings_name_the_key() {
    let err = |text: &str| build(text).err().expect("must fail").to_string();
    let e = err("free_vibration_modse = 10\n");
    assert!(
        e.contains("models.ritz-plate") && e.contains("free_vibration_modse"),
        "{e}"
    );
    let e = err("planform = \"rectangular\"\n");
    assert!(e.contains("models.ritz-plate.rectangular"), "{e}");
    let e = err("material = \"unobtainium\"\n");
    assert!(
        e.contains("models.ritz-plate.material") && e.contains("ti-6al-4v"),
        "{e}"
    );
    let e = err("material = \"vdi-l1400\"\n");
    assert!(
        e.contains("models.ritz-plate.material") && e.contains("no mechanical data"),
        "{e}"
    );
    let e = err("elements_chordwise = 1\n");
    assert!(e.contains("elements_chordwise"), "{e}");
    let e = err(&format!("{SMALL}damping_ratio = -0.1\n"));
    assert!(e.contains("damping_ratio"), "{e}");
    let e = err(&format!("{SMALL}static_shapes = 6\n"));
    assert!(e.contains("static_shapes") && e.contains("0 to 5"), "{e}");
    // 2 × 2 elements cannot carry 15 modes and shapes.
    let e = err("elements_chordwise = 2\nelements_spanwise = 1\n");
    assert!(e.contains("too coarse"), "{e}");
    let e = err(
        "planform = \"rectangular\"\n[rectangular]\nchord_m = 1.0\nspan_m = 1.0\nthickness_m = -0.01\n",
    );
    assert!(e.contains("thickness_m"), "{e}");
}

#[test]
fn bad_temperatures_are_errors_naming_the_quantity() {
    let mut model = build(SMALL).expect("model");
    let n = 9 * 7;
    let thermal = model.thermal_stiffness_mut().expect("thermal stiffness");
    let e = thermal
        .set_temperatures(&vec![300.0; n - 1])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("62 node temperatures") && e.contains("63 nodes"),
        "{e}"
    );
    let mut t = vec![300.0; n];
    t[5] = f64::NAN;
    let e = thermal.set_temperatures(&t).unwrap_err().to_string();
    assert!(e.contains("node 5") && e.contains("not finite"), "{e}");
    // Above the end of the material's E data (whatever it is) and below the melting point.
    let ti = hsv_core::material::Material::ti_6al_4v();
    let (_, top) = ti.mechanical_temperature_range_k();
    let hot = 0.5 * (top + ti.melting_point_k);
    let e = thermal
        .set_temperatures(&vec![hot; n])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("temperature") && e.contains(&top.to_string()) && e.contains(&hot.to_string()),
        "{e}"
    );
    let e = model
        .root_loads()
        .expect("root loads")
        .root_loads(
            &DVector::zeros(3),
            &DVector::zeros(15),
            &DVector::zeros(15),
            &hsv_core::aero::Loads::default(),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("3 modal coordinates"), "{e}");
}

/// Mode shapes on the aero meshes: at every vertex the vertical displacement is the grid's
/// bilinear w, the in-plane one the section rotation times the vertex's offset from the
/// mid-plane; the left mesh gets the mirror image (w and u equal, v opposite).
#[test]
fn mode_shapes_map_to_both_aero_meshes_as_mirror_images() {
    let model = build(SMALL).expect("model");
    let surface = LoadedConfig::sample().unwrap().config.lifting_surface;
    let right = lifting_surface_mesh(&surface, Side::Right).expect("mesh");
    let left = lifting_surface_mesh(&surface, Side::Left).expect("mesh");
    let sr = model.mode_shapes_on(&right).expect("right shapes");
    let sl = model.mode_shapes_on(&left).expect("left shapes");
    sr.check(&right).expect("fits");
    assert_eq!(sr.n_modes(), 15);
    assert_eq!(right.vertices.len(), left.vertices.len());
    for v in 0..right.vertices.len() {
        for c in 0..15 {
            let r = sr.vertex_displacement.fixed_view::<3, 1>(3 * v, c);
            let l = sl.vertex_displacement.fixed_view::<3, 1>(3 * v, c);
            assert_relative_eq!(r[0], l[0], epsilon = 1e-12);
            assert_relative_eq!(r[1], -l[1], epsilon = 1e-12);
            assert_relative_eq!(r[2], l[2], epsilon = 1e-12);
        }
    }
    // Root vertices do not move (clamped to the tube).
    for (i, p) in right.vertices.iter().enumerate() {
        if (p.y - surface.root_y_m).abs() < 1e-9 {
            for c in 0..15 {
                assert!(sr.vertex_displacement[(3 * i + 2, c)].abs() < 1e-15);
            }
        }
    }
    // Upper and lower vertices over the same point: same w, opposite in-plane motion.
    let grid = SurfaceGrid::lifting_surface(&surface, Side::Right, 8, 6).expect("grid");
    let z_mid = grid.mid_plane_z_m();
    let mut pairs = 0;
    for (i, p) in right.vertices.iter().enumerate() {
        for (j, q) in right.vertices.iter().enumerate() {
            if i < j
                && (p.x - q.x).abs() < 1e-12
                && (p.y - q.y).abs() < 1e-12
                && (p.z - z_mid) * (q.z - z_mid) < 0.0
            {
                pairs += 1;
                for c in 0..15 {
                    let d = |k: usize, r: usize| sr.vertex_displacement[(3 * k + r, c)];
                    assert_relative_eq!(d(i, 2), d(j, 2), epsilon = 1e-12);
                    let ratio = (p.z - z_mid) / (q.z - z_mid);
                    assert_relative_eq!(d(i, 0), ratio * d(j, 0), epsilon = 1e-12);
                }
            }
        }
    }
    assert!(pairs > 50, "{pairs} upper/lower vertex pairs");
    // A mesh of another body does not fit.
    let body = LoadedConfig::sample()
        .expect("sample")
        .vehicle()
        .expect("vehicle")
        .body;
    assert!(model.mode_shapes_on(&body).is_err());
}

/// Left-side root loads are the mirror image of the right's (Fy, Mx, Mz change sign).
#[test]
fn left_side_root_loads_mirror_the_right() {
    let loaded = LoadedConfig::sample().unwrap();
    let grid =
        SurfaceGrid::lifting_surface(&loaded.config.lifting_surface, Side::Right, 8, 6).unwrap();
    let settings = hsv_model_ritz_plate::Settings {
        elements_chordwise: 8,
        elements_spanwise: 6,
        ..Default::default()
    };
    let right = hsv_model_ritz_plate::RitzPlate::new(
        grid,
        hsv_core::material::Material::ti_6al_4v(),
        &settings,
    )
    .unwrap();
    let left = right.clone().with_side(Side::Left);
    let q = DVector::from_fn(15, |i, _| 1e-3 * (i as f64 + 1.0));
    let z = DVector::zeros(15);
    let a = right.root_loads_by_mode_displacement(&q, &z, &q).unwrap();
    let b = left.root_loads_by_mode_displacement(&q, &z, &q).unwrap();
    assert_relative_eq!(a.force_n.z, b.force_n.z);
    assert_relative_eq!(a.moment_nm.x, -b.moment_nm.x);
    assert_relative_eq!(a.moment_nm.y, b.moment_nm.y);
    assert!(a.moment_nm.x.abs() > 0.0 && a.force_n.z.abs() > 0.0);
}

/// The construction keeps the last plate built for the mirror surface's copy; only the same
/// settings may take it. Cantilever plates of 10, again 10 (the copy) and 20 mm built one
/// after the other each match Leissa's CFFF λ₁ = 3.492 for their own thickness (f₁ ∝ h for a
/// Kirchhoff plate, within 2 % as above), and the copy is the first plate to the bit.
#[test]
fn plates_built_in_turn_each_have_their_own_thickness() {
    let ti = hsv_core::material::Material::ti_6al_4v();
    let e = ti.youngs_modulus_pa(293.0).unwrap();
    let nu = ti.poisson_ratio;
    let leissa_hz = |h: f64| {
        let d = e * h.powi(3) / (12.0 * (1.0 - nu * nu));
        3.492 / (2.0 * std::f64::consts::PI) * (d / (ti.density_kg_m3 * h)).sqrt()
    };
    let first_frequency = |h: f64| {
        let model = build(&format!(
            "planform = \"rectangular\"\nroot = \"clamped\"\nelements_chordwise = 12\n\
             elements_spanwise = 12\n[rectangular]\nchord_m = 1.0\nspan_m = 1.0\n\
             thickness_m = {h}\n"
        ))
        .expect("rectangular");
        model.natural_frequencies_hz().expect("frequencies")[0]
    };
    let thin = first_frequency(0.01);
    let thin_again = first_frequency(0.01);
    let thick = first_frequency(0.02);
    assert_relative_eq!(thin, leissa_hz(0.01), max_relative = 0.02);
    assert_relative_eq!(thick, leissa_hz(0.02), max_relative = 0.02);
    assert_eq!(thin_again, thin);
}
