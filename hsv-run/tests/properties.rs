//! Property tests: the `aero`, `engine`, `trim`, `modes` and `heat` jobs (issue 16) and, in
//! `properties/commands.rs`, whole commands through the binary (issue 26). Random flight
//! conditions, including extreme and non-finite values, and random edits of the sample config
//! give finite results or a clear error, never a panic or a NaN.

use hsv_core::config::{LoadedConfig, SAMPLE_CONFIG_TOML, parse_config};
use hsv_core::registry::Registry;
use hsv_run::aero_job::{self, AeroRequest};
use hsv_run::commands::engine::{EngineRequest, run_engine};
use hsv_run::commands::validate_config;
use proptest::prelude::*;

mod common;

/// Whole commands through the binary (issue 26 item 7).
#[path = "properties/commands.rs"]
mod commands;

use common::strategies::awkward;

/// A flight condition: Mach, altitude (m), angle of attack (deg).
fn flight() -> impl Strategy<Value = (f64, f64, f64)> {
    (
        awkward(0.5..25.0),
        awkward(-2_000.0..100_000.0),
        awkward(-100.0..100.0),
    )
}

/// The sample config with `key` in table `table` set to `value` (None: unchanged).
fn edited(edits: &[(&str, &str, f64)]) -> Result<LoadedConfig, String> {
    let mut raw: toml::Table = toml::from_str(SAMPLE_CONFIG_TOML).expect("sample parses");
    for (table, key, value) in edits {
        let slot = raw
            .get_mut(*table)
            .and_then(toml::Value::as_table_mut)
            .expect("table exists");
        let value = if slot.get(*key).is_some_and(toml::Value::is_integer) {
            // Panel counts: keep them integers, and small enough to mesh quickly.
            toml::Value::Integer(value.clamp(-5.0, 80.0) as i64)
        } else {
            toml::Value::Float(*value)
        };
        slot.insert((*key).to_owned(), value);
    }
    let text = toml::to_string(&raw).map_err(|e| e.to_string())?;
    parse_config(&text, "edited.toml").map_err(|e| e.to_string())
}

/// Config keys the edits touch: reference values, body geometry, lifting-surface planform.
const EDITABLE: [(&str, &str); 9] = [
    ("reference", "area_m2"),
    ("reference", "chord_m"),
    ("reference", "span_m"),
    ("geometry", "width_m"),
    ("geometry", "upper_forebody_angle_deg"),
    ("geometry", "lower_forebody_angle_deg"),
    ("geometry", "panels_along_x"),
    ("lifting_surface", "span_m"),
    ("lifting_surface", "thickness_to_chord"),
];

fn config_edits() -> impl Strategy<Value = Vec<(usize, f64)>> {
    prop::collection::vec((0..EDITABLE.len(), awkward(-10.0..120.0)), 0..3)
}

fn registry() -> &'static Registry {
    hsv_run::shared_registry().expect("registry")
}

/// A clear error: one non-empty line.
fn assert_clear(error: &anyhow::Error) {
    let text = format!("{error:#}");
    assert!(!text.trim().is_empty(), "empty error");
    assert!(!text.contains('\n'), "not one line: {text}");
}

/// The edited config, validated as every command does; `None` when refused (clearly).
fn config_or_error(edits: &[(usize, f64)]) -> Option<LoadedConfig> {
    let edits: Vec<(&str, &str, f64)> = edits
        .iter()
        .map(|&(k, v)| (EDITABLE[k].0, EDITABLE[k].1, v))
        .collect();
    let loaded = match edited(&edits) {
        Ok(loaded) => loaded,
        Err(message) => {
            assert!(
                message.contains("edited.toml") || message.contains("TOML"),
                "{message}"
            );
            return None;
        }
    };
    match validate_config(&loaded, registry()) {
        Ok(()) => Some(loaded),
        Err(error) => {
            assert_clear(&error);
            None
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn aero_gives_finite_loads_or_a_clear_error(
        (mach, altitude_m, alpha_deg) in flight(),
        beta_deg in awkward(-30.0..30.0),
        edits in config_edits(),
    ) {
        let Some(loaded) = config_or_error(&edits) else { return Ok(()) };
        let mesh = match aero_job::vehicle_mesh(&loaded) {
            Ok(mesh) => mesh,
            Err(error) => { assert_clear(&error); return Ok(()) }
        };
        let request = AeroRequest {
            mach,
            altitude_m,
            alpha_deg,
            beta_deg,
            models: vec!["shock-expansion".into(), "newtonian-vector".into(), "piston-theory".into()],
            reference: loaded.config.reference,
            include_engine_surfaces: false,
        };
        match aero_job::run_aero(&loaded, registry(), &mesh, &request) {
            Ok(rows) => {
                prop_assert_eq!(rows.len(), 3);
                for row in rows {
                    let c = row.coefficients;
                    let values = [
                        row.loads.force_n.x, row.loads.force_n.y, row.loads.force_n.z,
                        row.loads.moment_nm.x, row.loads.moment_nm.y, row.loads.moment_nm.z,
                        c.cl, c.cd, c.cy, c.cm, c.croll, c.cn,
                    ];
                    prop_assert!(
                        values.iter().all(|v| v.is_finite()),
                        "{}: non-finite result at Mach {mach}, {altitude_m} m, alpha {alpha_deg}: {values:?}",
                        row.model
                    );
                }
            }
            Err(error) => assert_clear(&error),
        }
    }

    #[test]
    fn engine_gives_finite_results_or_a_clear_error(
        (mach, altitude_m, alpha_deg) in flight(),
        phi in awkward(0.0..3.0),
        edits in config_edits(),
    ) {
        let Some(loaded) = config_or_error(&edits) else { return Ok(()) };
        let request = EngineRequest { mach, altitude_m, alpha_deg, phi, models: Vec::new() };
        match run_engine(&loaded, registry(), &request) {
            Ok(rows) => {
                prop_assert!(!rows.is_empty());
                for row in rows {
                    let s = &row.solution;
                    let values = [
                        s.loads.force_n.x, s.loads.force_n.z, s.loads.moment_nm.y, s.mass_flow_kg_s,
                    ];
                    prop_assert!(
                        values.iter().all(|v| v.is_finite()),
                        "{}: non-finite result at Mach {mach}, {altitude_m} m, alpha {alpha_deg}, phi {phi}: {values:?}",
                        row.model
                    );
                    for station in &s.stations {
                        prop_assert!(
                            station.mach.is_finite() && station.pressure_pa.is_finite() && station.temperature_k.is_finite(),
                            "{}: station {} not finite", row.model, station.station
                        );
                    }
                }
            }
            Err(error) => assert_clear(&error),
        }
    }
}

/// A clear error: one line that names what went wrong (not a panic, not empty).
fn clear(message: &str) -> bool {
    !message.is_empty() && !message.contains("panicked")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, failure_persistence: None, ..ProptestConfig::default() })]

    /// The trim job (rigid vehicle) at random flight conditions: finite trim values and
    /// residuals, or a clear error (untrimmable, outside the atmosphere, an engine refusing).
    #[test]
    fn trim_gives_finite_values_or_a_clear_error(
        mach in awkward(3.0..12.0),
        altitude_m in awkward(15_000.0..40_000.0),
    ) {
        use hsv_run::analysis::trim::{TrimRequest, trim};
        use hsv_run::vehicle::rigid::{RigidVehicle, rigid_needs};
        let registry = hsv_run::registry().expect("registry");
        let loaded = LoadedConfig::sample().expect("sample");
        let sets = hsv_run::vehicle::assemble(&loaded, &registry, &rigid_needs("trim"))
            .expect("assembles");
        let mut vehicle = RigidVehicle::new(sets).expect("vehicle");
        let request = TrimRequest { mach, altitude_m, max_iterations: 400, ..TrimRequest::default() };
        match trim(&mut vehicle, &request) {
            Ok(r) => {
                let t = &r.trim;
                prop_assert!(t.alpha_deg.is_finite() && t.elevon_deg.is_finite());
                prop_assert!(t.fuel_equivalence_ratio.is_finite() && t.cost.is_finite());
            }
            Err(e) => prop_assert!(clear(&e.to_string()), "{e}"),
        }
    }

    /// The modes job at random uniform surface temperatures: finite frequencies, a surface
    /// reported as buckled, or a clear error (outside the material's data).
    #[test]
    fn modes_give_finite_frequencies_or_a_clear_error(
        temperature_k in awkward(0.0..2_500.0),
    ) {
        use hsv_run::commands::modes::{ModesOutcome, Temperature, compute};
        let registry = hsv_run::registry().expect("registry");
        let loaded = LoadedConfig::sample().expect("sample");
        match compute(&loaded, &registry, Temperature::Uniform(temperature_k)) {
            Ok(report) => {
                for (_, s) in &report.surfaces {
                    if let ModesOutcome::Modes(rows) = &s.outcome {
                        prop_assert!(rows.iter().all(|r| r.frequency_hz.is_finite() && r.frequency_hz > 0.0));
                    }
                }
            }
            Err(e) => prop_assert!(clear(&format!("{e:#}")), "{e:#}"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, failure_persistence: None, ..ProptestConfig::default() })]

    /// The heat job (a lifting surface heating in steady flow, full-order conduction, ten
    /// steps) at random flight conditions: finite temperatures, or a clear error (outside the
    /// atmosphere, a melted wall, a material table left).
    #[test]
    fn heat_gives_finite_temperatures_or_a_clear_error(
        (mach, altitude_m, alpha_deg) in flight(),
    ) {
        use hsv_run::analysis::heating::{HeatingModels, HeatingSteps, SurfaceHeating};
        let registry = hsv_run::registry().expect("registry");
        let loaded = LoadedConfig::sample().expect("sample");
        let region = loaded.region("right_surface").expect("region");
        let flight = hsv_core::flow::Freestream::standard(mach, altitude_m, loaded.config.gas)
            .map(|f| hsv_core::flow::FlightCondition::steady(f, alpha_deg.to_radians(), 0.0));
        let flight = match flight {
            Ok(f) => f,
            Err(e) => {
                prop_assert!(clear(&e.to_string()), "{e}");
                return Ok(());
            }
        };
        let models = HeatingModels {
            aero: "shock-expansion".to_owned(),
            heat_flux: "eckert".to_owned(),
            conduction: "full-order".to_owned(),
        };
        let steps = HeatingSteps { dt_s: 0.1, flux_every: 1, initial_k: 293.0 };
        let run = SurfaceHeating::new(region, &registry, models, flight, steps)
            .map_err(|e| e.to_string())
            .and_then(|mut h| {
                for _ in 0..10 {
                    h.advance(0.1).map_err(|e| e.to_string())?;
                }
                Ok(h.node_temperatures_k().to_vec())
            });
        match run {
            Ok(t) => prop_assert!(t.iter().all(|v| v.is_finite() && *v > 0.0)),
            Err(e) => prop_assert!(clear(&e), "{e}"),
        }
    }
}
