//! The binary links every model crate: the registry holds exactly the expected models.
//!
//! A model crate listed in Cargo.toml but not named in `hsv-run/src/linked.rs` is never linked and
//! its registration silently vanishes; this test catches that.

use hsv_core::registry::{Family, Role};

#[test]
fn registry_holds_every_builtin_model() {
    let registry = hsv_run::registry().expect("no duplicate names");
    let names: Vec<(&str, Role)> = registry
        .iter()
        .map(|e| (e.name.as_str(), e.role()))
        .collect();
    let expected = [
        ("newtonian-scalar", Role::Aero),
        ("newtonian-vector", Role::Aero),
        ("piston-theory", Role::Aero),
        ("shock-expansion", Role::Aero),
        ("shock-expansion-piston", Role::Aero),
    ];
    assert_eq!(names, expected);
    for entry in registry.iter() {
        assert!(!entry.summary.is_empty(), "{} has no summary", entry.name);
        assert_eq!(entry.role().family(), Family::Aero);
    }
}
