//! The example dylib plugin (`plugins/ackeret`) loads through the plugin ABI, computes what its
//! name says, and reports its errors through the boundary.

use std::path::PathBuf;

use approx::assert_relative_eq;
use hsv_core::aero::{AeroSolution, PanelMotion, integrate_pressure};
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Surface};
use hsv_core::registry::{ModelContext, Registry};
use nalgebra::Point3;

/// The example plugin's cdylib: built as a dev-dependency of this crate, so it sits in
/// `target/<profile>/deps/` next to this test binary (or one level up after `cargo build`).
fn plugin_path() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    let deps_dir = exe.parent().expect("target/<profile>/deps/<test>");
    let file = format!(
        "{}hsv_plugin_ackeret{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    let candidates = [deps_dir.join(&file), deps_dir.join("..").join(&file)];
    candidates
        .iter()
        .find(|path| path.exists())
        .cloned()
        .unwrap_or_else(|| panic!("{file} not found next to {}", deps_dir.display()))
}

/// A 1 m x 1 m flat plate of zero thickness in the x-y plane: upper face (normal -z) and lower
/// face (normal +z).
fn flat_plate() -> PanelMesh {
    let vertices = vec![
        Point3::new(1.0, -0.5, 0.0),
        Point3::new(0.0, -0.5, 0.0),
        Point3::new(0.0, 0.5, 0.0),
        Point3::new(1.0, 0.5, 0.0),
    ];
    let panels = [
        PanelSpec::quad(0, 1, 2, 3, 0),
        PanelSpec::quad(0, 3, 2, 1, 0),
    ];
    PanelMesh::new(
        vertices,
        &panels,
        Vec::new(),
        vec![Surface::new("plate", RegionKind::Other)],
    )
    .expect("valid plate")
}

fn context<'a>(settings: &'a toml::Table, _empty: &'a toml::Table) -> ModelContext<'a> {
    ModelContext {
        settings,
        key_path: "models.ackeret",
        file: "test.toml",
        region: hsv_core::testing::sample_region("right_surface"),
        registry: hsv_core::testing::empty_registry(),
    }
}

/// Ackeret flat-plate lift c_l = 4α/√(M²−1) (Anderson, Fundamentals of Aerodynamics, 6th ed.,
/// eq. 12.23), here with the exact normal-force projection c_l = c_n cos α, c_n = 4α/√(M²−1),
/// which differs from the small-angle form by 1 − cos α (0.06 % at 2°). Tolerance 1e-9.
#[test]
fn ackeret_plugin_reproduces_flat_plate_lift_slope() {
    let mut registry = Registry::empty();
    let count = registry.load_plugin(&plugin_path()).expect("plugin loads");
    assert_eq!(count, 1);
    let entry = registry.get("ackeret").expect("registered");
    assert!(entry.origin.to_string().contains("plugin"));

    let empty = toml::Table::new();
    let mut model = registry
        .create::<dyn hsv_core::aero::AeroModel>("ackeret", &context(&empty, &empty))
        .expect("creates");
    let plate = flat_plate();
    let mach = 3.0;
    let alpha = 2.0_f64.to_radians();
    let freestream = Freestream::standard(mach, 20_000.0, PerfectGas::AIR).unwrap();
    let flight = FlightCondition::steady(freestream, alpha, 0.0);
    let mut solution = AeroSolution::default();
    model
        .evaluate(&plate, &flight, &PanelMotion::default(), &mut solution)
        .expect("evaluates");
    let loads = integrate_pressure(
        &plate,
        &solution.pressure_pa,
        freestream.pressure_pa,
        &Point3::origin(),
        |_| true,
    );
    let q = freestream.dynamic_pressure_pa;
    let lift = loads.force_n.x * alpha.sin() - loads.force_n.z * alpha.cos();
    let beta = (mach * mach - 1.0_f64).sqrt();
    assert_relative_eq!(
        lift / q,
        4.0 * alpha / beta * alpha.cos(),
        max_relative = 1e-9
    );
    assert_relative_eq!(lift / q, 4.0 * alpha / beta, max_relative = 1e-3);
    // Edge states come back through the ABI too.
    assert!(solution.edge.iter().all(|e| e.mach > 2.5 && e.mach < 3.5));
}

#[test]
fn plugin_errors_cross_the_boundary_as_messages() {
    let mut registry = Registry::empty();
    registry.load_plugin(&plugin_path()).expect("plugin loads");
    let mut settings = toml::Table::new();
    settings.insert("order".into(), toml::Value::Integer(3));
    let empty = toml::Table::new();
    let err = registry
        .create::<dyn hsv_core::aero::AeroModel>("ackeret", &context(&settings, &empty))
        .err()
        .expect("unknown setting rejected")
        .to_string();
    assert!(err.contains("`order`"), "{err}");

    let mut model = registry
        .create::<dyn hsv_core::aero::AeroModel>("ackeret", &context(&empty, &empty))
        .unwrap();
    let subsonic = Freestream::standard(0.8, 10_000.0, PerfectGas::AIR).unwrap();
    let err = model
        .evaluate(
            &flat_plate(),
            &FlightCondition::steady(subsonic, 0.0, 0.0),
            &PanelMotion::default(),
            &mut AeroSolution::default(),
        )
        .unwrap_err()
        .to_string();
    assert!(err.contains("Mach number 0.8"), "{err}");
}

#[test]
fn loading_something_that_is_not_a_plugin_is_a_clear_error() {
    let dir = std::env::temp_dir().join(format!("hsv-plugin-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fake = dir.join("libnot_a_plugin.so");
    std::fs::write(&fake, b"this is not a shared library").unwrap();
    let err = Registry::empty()
        .load_plugin(&fake)
        .unwrap_err()
        .to_string();
    assert!(err.contains("cannot load the library"), "{err}");
    assert!(err.contains("libnot_a_plugin.so"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
