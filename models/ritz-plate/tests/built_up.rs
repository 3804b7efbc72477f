//! The built-up section of `ritz-plate` (two face skins, spar and rib webs) against sandwich-plate
//! theory: the cantilever frequency with the sandwich rigidity, the mass of skins and webs, and
//! the free thermal curvature of skins at different temperatures. Each test names its source and
//! tolerance.

mod common;
use common::build;

use approx::assert_relative_eq;
use hsv_core::material::Material;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_model_ritz_plate::fe::{BuiltUp, Section};
use hsv_model_ritz_plate::plate::PlateModel;

/// Depth 20 mm, skins 0.5 mm, webs 1 mm every 0.2 m both ways (w = 0.01 m/m).
const DEPTH: f64 = 0.02;
const SKIN: f64 = 0.0005;
const WEB: f64 = 0.001;
const PITCH: f64 = 0.2;

/// I = 2 t_s (d/2)² + t_s³/6 + (w/2) h³/12 per unit width, d = h − t_s: the faces' parallel-axis
/// and own inertia (Allen, Analysis and Design of Structural Sandwich Panels, 1969, eq. 2.3) plus
/// the webs smeared at their mean over both directions.
fn sandwich_inertia_m3() -> f64 {
    let d = DEPTH - SKIN;
    let w = 2.0 * WEB / PITCH;
    2.0 * SKIN * (0.5 * d).powi(2) + SKIN.powi(3) / 6.0 + 0.5 * w * DEPTH.powi(3) / 12.0
}

/// Mass per unit area over ρ: two skins and the webs through the depth.
fn sandwich_mass_m() -> f64 {
    2.0 * SKIN + 2.0 * WEB / PITCH * DEPTH
}

/// A 1 m square built-up cantilever plate (16 × 16) vibrates as Kirchhoff's plate with the
/// sandwich's rigidity D = E I/(1 − ν²) and mass ρ (2 t_s + w h): f₁ = λ₁/(2π a²) √(D/m) with
/// Leissa's CFFF λ₁ = 3.492 (NASA SP-160, 1969, ch. 4), within 2 % (the solid plate's band; the
/// webs' shear flexibility D/(G A_s a²) = 0.5 % is left in); its mass is ρ m a² to 1e-10.
#[test]
fn built_up_cantilever_plate_vibrates_with_the_sandwich_rigidity() {
    let model = build(&format!(
        "planform = \"rectangular\"\nroot = \"clamped\"\nelements_chordwise = 16\n\
         elements_spanwise = 16\n[rectangular]\nchord_m = 1.0\nspan_m = 1.0\nthickness_m = {DEPTH}\n\
         [built_up]\nskin_thickness_m = {SKIN}\nweb_thickness_m = {WEB}\nspar_pitch_m = {PITCH}\n\
         rib_pitch_m = {PITCH}\n"
    ))
    .expect("built-up plate");
    let ti = Material::ti_6al_4v();
    let e = ti.youngs_modulus_pa(293.0).unwrap();
    let nu = ti.poisson_ratio;
    let d = e * sandwich_inertia_m3() / (1.0 - nu * nu);
    let m = ti.density_kg_m3 * sandwich_mass_m();
    let f1 = 3.492 / (2.0 * std::f64::consts::PI) * (d / m).sqrt();
    let f = model.natural_frequencies_hz().expect("frequencies");
    eprintln!("built-up cantilever: {:.3} Hz, Kirchhoff {f1:.3} Hz", f[0]);
    assert_relative_eq!(f[0], f1, max_relative = 0.02);
    let mass = model.mass_properties().expect("mass").mass_properties();
    assert_relative_eq!(mass.mass_kg, m, max_relative = 1e-10);
}

/// Skins whose free strains differ by Δε = α ΔT (lower hotter) bend a free built-up plate
/// stress-free to κ_x = κ_y = Δε t_s d/(2 I), which is Δε/d for thin faces alone (the skins
/// stretch apart about the neutral plane: Allen 1969, ch. 2, and Boley & Weiner, Theory of
/// Thermal Stresses, 1960, ch. 12); 1 m × 0.6 m, 10 × 10, ΔT = 20 K, w held at three corners:
/// curvatures from nodal second differences and the
/// rotation gradients within 1e-6, no net thermal load.
#[test]
fn skins_at_different_temperatures_bend_a_free_built_up_plate() {
    let alpha = 9e-6;
    let material = Material::constant(
        "test alloy",
        4430.0,
        0.31,
        110e9,
        alpha,
        7.0,
        560.0,
        (100.0, 1000.0),
    )
    .expect("material");
    let (c, s, dt) = (1.0, 0.6, 20.0);
    let grid = SurfaceGrid::rectangular(c, s, DEPTH, 10, 10).expect("grid");
    let supports = common::three_corner_supports(&grid);
    let section = Section::BuiltUp(BuiltUp {
        skin_m: SKIN,
        spar_web_ratio: WEB / PITCH,
        rib_web_ratio: WEB / PITCH,
    });
    let plate = PlateModel::with_section(grid, material, supports, section).expect("plate");
    let n = plate.grid.n_nodes();
    let kappa = alpha * dt * SKIN * (DEPTH - SKIN) / (2.0 * sandwich_inertia_m3());
    let bent = common::free_thermal_bending(&plate, &vec![293.0; n], &vec![dt; n], kappa, (c, s));
    let worst = bent.worst_curvature.max(bent.worst_rotation_gradient);
    eprintln!(
        "free built-up plate: κ = {kappa:.6e} 1/m (thin faces alone Δε/d = {:.6e}); worst {worst:.2e}",
        alpha * dt / (DEPTH - SKIN)
    );
    assert!(worst < 1e-6, "{worst}");
    assert!(bent.net_load_ratio < 1e-10, "{}", bent.net_load_ratio);
}

/// Where the depth is not more than two skins (the sharp edges of a double wedge) the section
/// is solid; just above, the skins' bending inertia joins the solid one continuously
/// (2 t_s (t_s/2)² + t_s³/6 = (2 t_s)³/12), as does the in-plane area (2 t_s).
#[test]
fn a_section_thinner_than_two_skins_is_solid_and_joins_continuously() {
    let b = BuiltUp {
        skin_m: 0.002,
        spar_web_ratio: 0.0,
        rib_web_ratio: 0.0,
    };
    let section = Section::BuiltUp(b);
    assert_eq!(section.properties(0.003), Section::Solid.properties(0.003));
    let below = section.properties(0.004);
    let above = section.properties(0.004 * (1.0 + 1e-12));
    assert_relative_eq!(above.bending_m3, below.bending_m3, max_relative = 1e-9);
    assert_relative_eq!(above.membrane_m, below.membrane_m, max_relative = 1e-9);
    assert_relative_eq!(above.mass_m, below.mass_m, max_relative = 1e-9);
}

/// A built-up setting out of range names its key.
#[test]
fn a_bad_built_up_setting_names_its_key() {
    let err = build(
        "elements_chordwise = 8\nelements_spanwise = 6\n[built_up]\nskin_thickness_m = 0.0\n\
         web_thickness_m = 0.001\nspar_pitch_m = 0.5\nrib_pitch_m = 0.5\n",
    )
    .err()
    .expect("zero skin")
    .to_string();
    assert!(err.contains("built_up.skin_thickness_m"), "{err}");
    let err = build("[built_up]\nskin_thickness_m = 0.003\n")
        .err()
        .expect("missing keys")
        .to_string();
    assert!(err.contains("web_thickness_m"), "{err}");
}
