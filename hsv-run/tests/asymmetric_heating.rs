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

use hsv_core::flow::{FlightCondition, Freestream};
use hsv_run::analysis::heating::{HeatingModels, HeatingSteps, SurfaceHeating};

/// The sample right surface with a POD basis trained in `dir` from 10 s full-order runs at
/// Mach 4, 4.5 and 5 and the angles `alpha_deg`.
fn region(dir: &std::path::Path, alpha_deg: &[f64]) -> hsv_core::region::RegionInfo {
    let mut region = hsv_core::testing::sample_region("right_surface").clone();
    let mut pod = region.model_settings("pod");
    let basis = dir.join("pod-basis-{region}.json");
    pod.table.insert(
        "basis_file".into(),
        toml::Value::String(basis.display().to_string()),
    );
    let mut training = pod
        .table
        .get("training")
        .and_then(|t| t.as_table())
        .cloned()
        .unwrap_or_default();
    let floats = |v: &[f64]| toml::Value::Array(v.iter().map(|&x| toml::Value::Float(x)).collect());
    training.insert("mach".into(), floats(&[4.0, 4.5, 5.0]));
    training.insert("duration_s".into(), toml::Value::Float(10.0));
    training.insert("alpha_deg".into(), floats(alpha_deg));
    pod.table
        .insert("training".into(), toml::Value::Table(training));
    region.settings.insert("pod".into(), pod);
    region
}

/// Lower-minus-upper structure temperature at every node after 10 s at Mach 5, α = 4°, K.
fn through_thickness_difference(
    region: &hsv_core::region::RegionInfo,
    conduction: &str,
) -> Vec<f64> {
    let registry = hsv_run::registry().expect("registry");
    let freestream = Freestream::standard(5.0, 10_000.0, region.gas).expect("freestream");
    let mut heating = SurfaceHeating::new(
        region.clone(),
        &registry,
        HeatingModels {
            aero: "shock-expansion".to_owned(),
            heat_flux: "eckert".to_owned(),
            conduction: conduction.to_owned(),
        },
        FlightCondition::steady(freestream, 4f64.to_radians(), 0.0),
        HeatingSteps {
            dt_s: 0.1,
            flux_every: 1,
            initial_k: 293.0,
        },
    )
    .expect("heating run");
    for _ in 0..100 {
        heating.advance(0.1).expect("heating step");
    }
    let model = heating.conduction();
    let mut difference = vec![0.0; model.n_nodes()];
    model.node_temperature_differences(heating.state(), &mut difference);
    difference
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
