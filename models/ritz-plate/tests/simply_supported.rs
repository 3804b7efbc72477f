//! The `root = "simply-supported"` boundary of the registered model: a rectangular plate with
//! all four edges simply supported (the classical panel of panel-flutter theory).

use std::f64::consts::PI;

mod common;
use common::build;

/// SSSS square plate, 1 m × 1 m × 5 mm Ti-6Al-4V at 293 K: ω_mn = π² (m² + n²) √(D/(ρh)) / a²
/// (Leissa, Vibration of Plates, NASA SP-160, 1969, ch. 4, the SSSS closed form), so the first
/// four frequencies are in the ratios 2 : 5 : 5 : 8. Within 1.5 % on a 20 × 20 grid.
#[test]
fn simply_supported_square_plate_matches_leissa() {
    let model = build(
        "planform = \"rectangular\"\nroot = \"simply-supported\"\nfree_vibration_modes = 4\n\
         static_shapes = 0\nelements_chordwise = 20\nelements_spanwise = 20\n\
         [rectangular]\nchord_m = 1.0\nspan_m = 1.0\nthickness_m = 0.005\n",
    )
    .expect("simply supported plate");
    let ti = hsv_core::material::Material::ti_6al_4v();
    let e = ti.youngs_modulus_pa(293.0).expect("E");
    let nu = ti.poisson_ratio;
    let h = 0.005;
    let d = e * h * h * h / (12.0 * (1.0 - nu * nu));
    let base_hz = PI * PI * (d / (ti.density_kg_m3 * h)).sqrt() / (2.0 * PI);
    let f = model.natural_frequencies_hz().expect("frequencies");
    for (i, k) in [2.0, 5.0, 5.0, 8.0].iter().enumerate() {
        let exact = k * base_hz;
        let error = (f[i] / exact - 1.0).abs();
        eprintln!(
            "SSSS mode {}: {:.3} Hz (Leissa {exact:.3} Hz), error {error:.2e}",
            i + 1,
            f[i]
        );
        assert!(error < 0.015, "mode {}: {} Hz vs {exact} Hz", i + 1, f[i]);
    }
}

/// The clamped-root static shapes that load held dofs (tip force, tip twist) add nothing on a
/// simply supported plate and are skipped; the others stay in the basis.
#[test]
fn simply_supported_plate_keeps_the_pressure_shapes() {
    let model = build(
        "planform = \"rectangular\"\nroot = \"simply-supported\"\nfree_vibration_modes = 4\n\
         static_shapes = 5\nelements_chordwise = 8\nelements_spanwise = 8\n\
         [rectangular]\nchord_m = 1.0\nspan_m = 1.0\nthickness_m = 0.005\n",
    )
    .expect("simply supported plate");
    let n = model.modal_model().n_modes();
    assert!((5..=9).contains(&n), "{n} Ritz vectors");
    assert!(model.natural_frequencies_hz().is_ok());
}

/// Simple support on all four edges needs the rectangular planform: the error names the key.
#[test]
fn simply_supported_vehicle_planform_is_an_error_naming_the_key() {
    let err = build("root = \"simply-supported\"\nelements_chordwise = 8\nelements_spanwise = 6\n")
        .err()
        .expect("vehicle planform with simple support is refused")
        .to_string();
    assert!(err.contains("root") && err.contains("rectangular"), "{err}");
}
