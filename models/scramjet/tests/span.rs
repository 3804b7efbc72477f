//! The engine across its span, a consistency check of the span integration (not a validation:
//! the section physics is validated against Heiser & Pratt and Bolender & Doman in the other
//! files). On a spanwise-uniform engine (the sample vehicle's, a 2D inlet, combustor and nozzle
//! extruded across 3 m) every section is the same two-dimensional problem, so the quadratic span
//! fit must integrate the sections' per-span loads to exactly those loads times the width, and
//! the sections share one solve (every section equal to the first, to the bit).

use hsv_core::config::LoadedConfig;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::geometry::build_vehicle;
use hsv_core::propulsion::{EngineInputs, PropulsionModel, PropulsionSolution};
use hsv_model_scramjet::{Checker, OneDSettings, Scramjet};
use nalgebra::Point3;

#[test]
fn a_spanwise_uniform_engine_carries_its_section_loads_times_the_width() {
    let loaded = LoadedConfig::sample().expect("embedded config");
    let geometry = &loaded.config.geometry;
    let check = Checker {
        file: "test",
        key_path: "models.scramjet-1d",
    };
    let (engine, strips) = OneDSettings::default().engine(geometry, &check).unwrap();
    let reference = Point3::new(-15.2, 0.0, 0.0);
    let mut model = Scramjet::new(engine, strips, reference);
    let body = build_vehicle(geometry, &loaded.config.lifting_surface)
        .expect("sample vehicle")
        .body;
    let freestream = Freestream::standard(6.0, 26_000.0, PerfectGas::AIR).expect("atmosphere");
    let flight = FlightCondition::steady(freestream, 2f64.to_radians(), 0.0);
    let mut out = PropulsionSolution::default();
    model
        .evaluate(
            &EngineInputs {
                flight: &flight,
                body: &body,
                fuel_equivalence_ratio: 0.2,
            },
            &mut out,
        )
        .expect("engine runs");

    let y = model.section_positions_m();
    let n = y.len() as f64;
    // Sections at the centres of equal bands: the engine's width is n band widths.
    let width_m = (y[y.len() - 1] - y[0]) * n / (n - 1.0);
    assert!((width_m - 3.0).abs() < 1e-9, "engine width {width_m} m");
    let first = &model.sections()[0];
    for section in model.sections() {
        assert_eq!(
            section, first,
            "every section of a uniform engine is the first's"
        );
    }
    let force_x = first.force_n_per_m.x * width_m;
    let force_z = first.force_n_per_m.y * width_m;
    let moment_y = first.pitching_moment_nm_per_m * width_m;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
    assert!(
        close(out.loads.force_n.x, force_x),
        "{} vs {force_x}",
        out.loads.force_n.x
    );
    assert!(
        close(out.loads.force_n.z, force_z),
        "{} vs {force_z}",
        out.loads.force_n.z
    );
    assert!(
        close(out.loads.moment_nm.y, moment_y),
        "{} vs {moment_y}",
        out.loads.moment_nm.y
    );
    assert!(
        close(out.mass_flow_kg_s, first.air_mass_flow_kg_s_per_m * width_m),
        "mass flow {}",
        out.mass_flow_kg_s
    );
}
