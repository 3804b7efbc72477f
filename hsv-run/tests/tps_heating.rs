//! The sample right surface with the thermal-protection variant of `configs/sample-hsv.toml`
//! (2 mm of `vdi-l1400` on both faces, the commented `layers` line of `[models.full-order]`)
//! heated for the paper's 100 s at Mach 6, 10 km (paper Fig. 14's "prolonged cruise"), zero
//! incidence, `shock-expansion` edge states, `eckert` heat flux, `full-order` conduction from
//! 293 K, 0.2 s steps.
//!
//! What must hold, fixed before sizing the layer: every conduction node stays inside its
//! material's thermal data (the run completes: `full-order` refuses a temperature outside a
//! table), and the titanium stays below its β transus, 1267 K (the α-phase rows of the
//! Ti-6Al-4V table end there; `core/src/material.rs`), so inside its mechanical data (E and α to
//! 1323.66 K) to the end. The bare surface leaves the mechanical data after about 21 s at the
//! same conditions (checked here over 30 s). The 2 mm is the thinnest whole millimetre that
//! meets the transus criterion (1 mm: 1371 K after 100 s); the full-order maximum is 1168 K
//! (sample grid, 0.1 s steps).

use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::material::Material;
use hsv_core::region::RegionInfo;
use hsv_run::analysis::heating::{HeatingModels, HeatingSteps, SurfaceHeating};

/// Ti-6Al-4V β transus (the table's α-phase rows end at 1267 K).
const BETA_TRANSUS_K: f64 = 1267.0;

/// The sample right surface, with `layers` (a TOML array) in `[models.full-order]`.
fn region(layers: Option<&str>) -> RegionInfo {
    let mut region = hsv_core::testing::sample_region("right_surface").clone();
    if let Some(layers) = layers {
        let mut full = region.model_settings("full-order");
        let parsed: toml::Table = toml::from_str(&format!("layers = {layers}")).expect("toml");
        full.table.insert("layers".into(), parsed["layers"].clone());
        region.settings.insert("full-order".into(), full);
    }
    region
}

/// Heats `region` at Mach 6, 10 km for `duration_s`; the largest structure node temperature, K.
fn hottest_structure_k(region: RegionInfo, duration_s: f64) -> f64 {
    let registry = hsv_run::registry().expect("registry");
    let freestream = Freestream::standard(6.0, 10_000.0, region.gas).expect("freestream");
    let dt_s = 0.2;
    let mut heating = SurfaceHeating::new(
        region,
        &registry,
        HeatingModels {
            aero: "shock-expansion".to_owned(),
            heat_flux: "eckert".to_owned(),
            conduction: "full-order".to_owned(),
        },
        FlightCondition::steady(freestream, 0.0, 0.0),
        HeatingSteps {
            dt_s,
            flux_every: 1,
            initial_k: 293.0,
        },
    )
    .expect("heating run");
    let steps = (duration_s / dt_s).round() as usize;
    for step in 0..steps {
        heating
            .advance(dt_s)
            .unwrap_or_else(|e| panic!("step {step} ({} s): {e}", step as f64 * dt_s));
    }
    heating
        .node_temperatures_k()
        .iter()
        .fold(0.0, |m, &t| m.max(t))
}

#[test]
fn protected_surface_stays_inside_its_material_data_for_100_s_at_mach_6() {
    let layer = r#"[{ thickness_m = 0.002, material = "vdi-l1400", sublayers = 2 }]"#;
    let hottest = hottest_structure_k(region(Some(layer)), 100.0);
    let (_, mechanical_top) = Material::ti_6al_4v().mechanical_temperature_range_k();
    println!("protected: hottest structure node after 100 s {hottest:.1} K");
    assert!(hottest < BETA_TRANSUS_K, "{hottest} K");
    assert!(hottest < mechanical_top);
    let bare = hottest_structure_k(region(None), 30.0);
    println!("bare: hottest structure node after 30 s {bare:.1} K");
    assert!(bare > mechanical_top, "{bare} K");
}
