//! The binary links every model crate: the registry holds exactly the expected models.
//!
//! A model crate listed in Cargo.toml but not named in `hsv-run/src/linked.rs` is never linked and
//! its registration silently vanishes; this test catches that.

use hsv_core::registry::Role;

#[test]
fn registry_holds_every_builtin_model() {
    let registry = hsv_run::registry().expect("no duplicate names");
    let names: Vec<(&str, Role)> = registry
        .iter()
        .map(|e| (e.name.as_str(), e.role()))
        .collect();
    let expected = [
        ("convolution-rom", Role::Aero),
        ("eckert", Role::HeatFlux),
        ("free-free-beam", Role::Structure),
        ("full-order", Role::Conduction),
        ("kriging-stanton", Role::HeatFlux),
        ("lqr", Role::Control),
        ("newtonian-scalar", Role::Aero),
        ("newtonian-vector", Role::Aero),
        ("piston-theory", Role::Aero),
        ("pod", Role::Conduction),
        ("ritz-plate", Role::Structure),
        ("schedule", Role::Control),
        ("scramjet-1d", Role::Propulsion),
        ("scramjet-q1d", Role::Propulsion),
        ("shock-expansion", Role::Aero),
        ("shock-expansion-piston", Role::Aero),
        ("tracking", Role::Control),
    ];
    assert_eq!(names, expected);
    for entry in registry.iter() {
        assert!(!entry.summary.is_empty(), "{} has no summary", entry.name);
    }
}
