//! The sample right surface heated at incidence (Mach 5, 10 km, α = 4°, 10 s from 293 K,
//! `shock-expansion` edge states and `eckert` heat flux): the windward face heats more than the
//! leeward one, so the structure carries a through-thickness temperature difference, the source
//! of the thermal moment M_T = ∫ E α ΔT z dz (Boley & Weiner).
//!
//! Reference: the full-order conduction model (validated against Carslaw & Jaeger and Incropera
//! in `models/conduction`). A POD basis trained only at zero incidence spans mirror-symmetric
//! fields alone (Carslaw & Jaeger §1.6: the symmetric section in symmetric flow heats
//! symmetrically), so its difference is zero to rounding, whatever the flight; a basis trained
//! either side of zero (`alpha_deg = [-4, 0, 4]`, the default) must reproduce the full-order
//! difference. Tolerances, chosen before running: the trained basis within 10 % of the
//! full-order model's largest |ΔT| at every structural node; the zero-incidence basis below
//! 1e-6 K.

mod common;

/// Lower-minus-upper structure temperature at every node after 10 s at Mach 5, α = 4°, K.
fn through_thickness_difference(
    region: &hsv_core::region::RegionInfo,
    conduction: &str,
) -> Vec<f64> {
    let mut heating = common::surface_heating(region, conduction, 5.0, 4.0);
    for _ in 0..100 {
        heating.advance(0.1).expect("heating step");
    }
    let model = heating.conduction();
    let mut difference = vec![0.0; model.n_nodes()];
    model.node_temperature_differences(heating.state(), &mut difference);
    difference
}

/// The sample right surface with a POD basis trained in `dir` from 10 s full-order runs at
/// Mach 4, 4.5 and 5 and the angles `alpha_deg`.
fn region(dir: &std::path::Path, alpha_deg: &[f64]) -> hsv_core::region::RegionInfo {
    common::surface_with_pod_training(dir, &[4.0, 4.5, 5.0], 10.0, alpha_deg)
}

#[test]
fn a_basis_trained_either_side_of_zero_incidence_carries_the_through_thickness_difference() {
    let dir = std::env::temp_dir().join(format!("hsv-asymmetric-heating-{}", std::process::id()));
    let (either_side, zero_only) = (dir.join("either-side"), dir.join("zero-only"));
    for d in [&either_side, &zero_only] {
        std::fs::create_dir_all(d).expect("temp dir");
    }
    let full = through_thickness_difference(&region(&either_side, &[-4.0, 0.0, 4.0]), "full-order");
    let largest = full.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
    assert!(
        largest > 1.0,
        "the incidence heats one face more: {largest} K"
    );

    let trained = through_thickness_difference(&region(&either_side, &[-4.0, 0.0, 4.0]), "pod");
    let worst = full
        .iter()
        .zip(&trained)
        .map(|(f, p)| (f - p).abs())
        .fold(0.0_f64, f64::max);
    println!("full-order largest |dT| {largest:.3} K; pod (-4, 0, 4 deg) worst error {worst:.3} K");
    assert!(worst <= 0.1 * largest, "{worst} K against {largest} K");

    let symmetric = through_thickness_difference(&region(&zero_only, &[0.0]), "pod");
    let spurious = symmetric.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
    println!("pod (0 deg only) largest |dT| {spurious:.3e} K");
    assert!(spurious < 1e-6, "{spurious} K");
    let _ = std::fs::remove_dir_all(&dir);
}
