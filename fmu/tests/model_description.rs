//! The FMU's model description against what it stands for: the FMI 3.0 co-simulation interface
//! named by its library, the outputs `hsv-run simulate` records (history.csv's columns but
//! time, which FMI keeps itself), and parameters that start at the sample vehicle's flight
//! condition. (Flying it through an FMI importer is python/tests/test_fmu.py.)

use std::ffi::CStr;

use hsv_core::config::LoadedConfig;
use hsv_run::analysis::simulate::Sample;

fn description() -> String {
    let text = hsv_fmu::hsv_fmu_model_description();
    assert!(!text.is_null(), "the library wrote no model description");
    // SAFETY: a non-null result is a NUL-terminated string the library keeps while loaded.
    unsafe { CStr::from_ptr(text) }
        .to_str()
        .expect("UTF-8 model description")
        .to_owned()
}

/// The `(name, causality, start)` of every scalar variable, in order.
fn variables(xml: &str) -> Vec<(String, String, Option<String>)> {
    let attribute = |element: &str, key: &str| -> Option<String> {
        let at = element.find(&format!(" {key}=\""))? + key.len() + 3;
        Some(element[at..at + element[at..].find('"')?].to_owned())
    };
    let body = &xml[xml.find("<ModelVariables>").expect("ModelVariables")..];
    let body = &body[..body
        .find("</ModelVariables>")
        .expect("end of ModelVariables")];
    body.split('<')
        .filter(|e| e.starts_with("Float64 ") || e.starts_with("String "))
        .map(|e| {
            let start = attribute(e, "start").or_else(|| {
                // A String's start is a child element.
                let rest = &body[body.find(e).expect("element")..];
                let child = &rest[rest.find("<Start ")?..];
                attribute(child, "value")
            });
            (
                attribute(e, "name").expect("name"),
                attribute(e, "causality").expect("causality"),
                start,
            )
        })
        .collect()
}

#[test]
fn it_is_a_co_simulation_fmu_named_by_its_library() {
    let xml = description();
    assert!(xml.contains("fmiVersion=\"3.0\""), "{xml}");
    assert!(
        xml.contains(&format!(
            "<CoSimulation modelIdentifier=\"{}\"",
            hsv_fmu::MODEL_IDENTIFIER
        )),
        "{xml}"
    );
    assert!(!xml.contains("<ModelExchange"), "{xml}");
}

#[test]
fn outputs_are_the_trim_and_the_recorded_flight() {
    let vars = variables(&description());
    let of = |causality: &str| -> Vec<&str> {
        vars.iter()
            .filter(|v| v.1 == causality)
            .map(|v| v.0.as_str())
            .collect()
    };
    let mut expected = vec![
        "trim_alpha_deg",
        "trim_elevon_deg",
        "trim_fuel_equivalence_ratio",
    ];
    expected.extend(Sample::COLUMNS.iter().skip(1));
    assert_eq!(of("output"), expected);
    assert_eq!(
        of("input"),
        [
            "elevon_offset_deg",
            "differential_elevon_command_deg",
            "fuel_equivalence_ratio_offset"
        ]
    );
    // Offsets start at zero: an importer that sets no input flies the trim.
    for v in vars.iter().filter(|v| v.1 == "input") {
        assert_eq!(v.2.as_deref(), Some("0"), "{v:?}");
    }
}

#[test]
fn parameters_start_at_the_sample_vehicles_flight_condition() {
    let sample = LoadedConfig::sample()
        .expect("the embedded sample config")
        .config;
    let vars = variables(&description());
    let start = |name: &str| -> String {
        vars.iter()
            .find(|v| v.0 == name)
            .and_then(|v| v.2.clone())
            .unwrap_or_else(|| panic!("no start for {name}"))
    };
    assert_eq!(
        start("trim_mach").parse::<f64>().expect("a number"),
        sample.flight.mach
    );
    assert_eq!(
        start("trim_altitude_m").parse::<f64>().expect("a number"),
        sample.flight.altitude_m
    );
    assert_eq!(start("dt_s").parse::<f64>().expect("a number"), 1e-3);
    assert_eq!(start("controller"), "external");
}
