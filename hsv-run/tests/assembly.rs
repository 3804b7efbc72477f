//! Vehicle assembly: regions built from `[regions.*]` by name, refused before t = 0 when a role,
//! a capability or a publisher is missing, with messages that name what and where.

use hsv_core::config::{SAMPLE_CONFIG_TOML, parse_config};
use hsv_core::data::{DataError, DataManager, DataManagerBuilder, Subscriber};
use hsv_core::structure::RigidDof;
use hsv_run::vehicle::{AnalysisNeeds, Region, RegionDiagnostics, RegionError, assemble, wire};

/// The sample vehicle with full-order conduction (the POD basis file is a run artefact) and
/// `edit` applied to its text.
fn config(edit: impl Fn(String) -> String) -> hsv_core::config::LoadedConfig {
    let text = SAMPLE_CONFIG_TOML.replace("conduction = \"pod\"", "conduction = \"full-order\"");
    parse_config(&edit(text), "test.toml").expect("config parses")
}

#[test]
fn the_sample_vehicle_assembles_for_the_aerothermoelastic_analysis() {
    let registry = hsv_run::registry().expect("registry");
    let loaded = config(|t| t);
    let needs = AnalysisNeeds::aerothermoelastic("the aerothermoelastic simulation");
    let sets = assemble(&loaded, &registry, &needs).expect("assembles");
    let names: Vec<&str> = sets.iter().map(|s| s.info.name.as_str()).collect();
    assert_eq!(
        names,
        ["main_body", "left_surface", "right_surface", "propulsion"]
    );
    // Each surface is its own model instance, built for its own side: the left surface's
    // mass lies at y < 0, the right one's at y > 0, mirror images of each other.
    let mass = |i: usize| {
        let structure = sets[i].structure.as_ref().expect("structure");
        structure.mass_properties().expect("mass").mass_properties()
    };
    let (left, right) = (mass(1), mass(2));
    assert!(left.center_of_mass_m.y < 0.0 && right.center_of_mass_m.y > 0.0);
    assert!((left.mass_kg - right.mass_kg).abs() <= 1e-9 * right.mass_kg);
    assert!((left.center_of_mass_m.y + right.center_of_mass_m.y).abs() < 1e-9);
    let coupling = sets[2]
        .structure
        .as_ref()
        .and_then(|s| s.rigid_body_coupling());
    let dofs = coupling.expect("surface coupling").rigid_dofs();
    assert_eq!(
        dofs,
        [
            RigidDof::TranslationX,
            RigidDof::TranslationZ,
            RigidDof::RotationX,
            RigidDof::RotationY
        ]
    );
}

#[test]
fn a_structure_without_a_needed_capability_is_refused_naming_model_capability_and_analysis() {
    let registry = hsv_run::registry().expect("registry");
    // A beam as the lifting surfaces' structure (placed by a per-region override) has no
    // temperature-dependent stiffness.
    let loaded = config(|t| {
        t.replace("structure = \"ritz-plate\"", "structure = \"free-free-beam\"")
            .replace(
                "[regions.propulsion]",
                "[regions.lifting_surfaces.models.free-free-beam]\naxis_z_m = 0.0\n\n[regions.propulsion]",
            )
    });
    let needs = AnalysisNeeds::aerothermoelastic("the aerothermoelastic simulation");
    let err = assemble(&loaded, &registry, &needs)
        .err()
        .expect("refused")
        .to_string();
    for part in [
        "test.toml",
        "left_surface",
        "free-free-beam",
        "temperature-dependent stiffness",
        "the aerothermoelastic simulation",
    ] {
        assert!(err.contains(part), "`{part}` missing from: {err}");
    }
}

#[test]
fn a_missing_role_is_refused_with_the_key_to_set() {
    let registry = hsv_run::registry().expect("registry");
    let loaded = config(|t| t.replace("heat_flux = \"eckert\"", ""));
    let needs = AnalysisNeeds::aerothermoelastic("trim");
    let err = assemble(&loaded, &registry, &needs)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        err.contains("left_surface")
            && err.contains("heat-flux")
            && err.contains("regions.left_surface.heat_flux")
            && err.contains("trim"),
        "{err}"
    );
}

/// A region that reads the root loads of the left surface and publishes nothing.
struct Reader {
    root_loads: Option<Subscriber<[f64; 6]>>,
}

impl Region for Reader {
    fn name(&self) -> &str {
        "main_body"
    }
    fn declare(&mut self, data: &mut DataManagerBuilder) -> Result<(), DataError> {
        self.root_loads = Some(data.subscribe("main_body", "left_surface.root_loads")?);
        Ok(())
    }
    fn step_to(&mut self, _time_s: f64, _data: &mut DataManager) -> Result<(), RegionError> {
        Ok(())
    }
    fn diagnostics(&self) -> RegionDiagnostics {
        RegionDiagnostics::default()
    }
}

#[test]
fn a_topic_without_a_publisher_is_refused_naming_topic_and_reader() {
    let mut regions: Vec<Box<dyn Region>> = vec![Box::new(Reader { root_loads: None })];
    let err = wire(&mut regions).expect_err("refused").to_string();
    assert!(
        err.contains("left_surface.root_loads") && err.contains("main_body"),
        "{err}"
    );
}
