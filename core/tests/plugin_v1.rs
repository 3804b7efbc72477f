//! ABI-1 plugins still load: a v1 aero plugin written against the unchanged v1 API
//! (`PluginAero` + `export_aero_plugin!`) goes through the same header checks as a loaded
//! library and becomes a normal `AeroModel`.

use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Surface};
use hsv_core::plugin::{PluginAero, PluginAeroInput, PluginAeroOutput, PluginHeader};
use hsv_core::registry::{ModelContext, Registry};
use nalgebra::Point3;

/// Ackeret's linearized supersonic pressure, p = p∞ + q 2θ/√(M² − 1), as a v1 plugin.
struct LinearizedV1;

impl PluginAero for LinearizedV1 {
    fn create(settings: &serde_json::Value) -> Result<Self, String> {
        match settings.as_object() {
            Some(map) if map.is_empty() => Ok(LinearizedV1),
            _ => Err("`linearized-v1` has no settings".to_owned()),
        }
    }

    fn evaluate(
        &mut self,
        input: &PluginAeroInput<'_>,
        output: &mut PluginAeroOutput<'_>,
    ) -> Result<(), String> {
        let f = &input.freestream;
        let q = 0.5 * f.density_kg_m3 * f.velocity_m_s * f.velocity_m_s;
        for ((n, v), p) in input
            .normal
            .iter()
            .zip(input.panel_velocity_m_s)
            .zip(output.pressure_pa.iter_mut())
        {
            let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let theta = ((n[0] * v[0] + n[1] * v[1] + n[2] * v[2]) / speed).asin();
            *p = f.pressure_pa + q * 2.0 * theta / (f.mach * f.mach - 1.0).sqrt();
        }
        for edge in output.edge.iter_mut() {
            *edge = [
                f.mach,
                f.pressure_pa,
                f.temperature_k,
                f.density_kg_m3,
                f.velocity_m_s,
            ];
        }
        Ok(())
    }
}

hsv_core::export_aero_plugin!(
    LinearizedV1,
    name: "linearized-v1",
    fidelity: 0,
    summary: "Ackeret pressures through ABI 1",
    settings: "",
);

/// Upper (normal −z) and lower (normal +z) faces of a 1 m² plate.
fn plate() -> PanelMesh {
    let vertices = vec![
        Point3::new(1.0, -0.5, 0.0),
        Point3::new(0.0, -0.5, 0.0),
        Point3::new(0.0, 0.5, 0.0),
        Point3::new(1.0, 0.5, 0.0),
    ];
    PanelMesh::new(
        vertices,
        &[
            PanelSpec::quad(0, 1, 2, 3, 0),
            PanelSpec::quad(0, 3, 2, 1, 0),
        ],
        Vec::new(),
        vec![Surface::new("plate", RegionKind::Other)],
    )
    .unwrap()
}

/// At α = 2°, Mach 3: lower face p∞ + q·2α/√8, upper face p∞ − q·2α/√8 (Ackeret; Anderson,
/// Fundamentals of Aerodynamics, eq. 12.15, with θ = asin(n·V̂) = ±α exactly). Tolerance 1e-12.
#[test]
fn a_v1_plugin_loads_and_evaluates() {
    let header: &'static PluginHeader = unsafe { &*hsv_plugin_entry() };
    assert_eq!(header.abi_version, 1);
    let mut registry = Registry::empty();
    // SAFETY: the header comes from the v1 export macro.
    let count = unsafe { registry.register_plugin_header(header, "v1 in-process") }.unwrap();
    assert_eq!(count, 1);

    let region = hsv_core::testing::sample_region("right_surface");
    let settings = region.model_settings("linearized-v1");
    let context = ModelContext::new(region, &registry, &settings);
    let mut model = registry
        .create::<dyn AeroModel>("linearized-v1", &context)
        .unwrap();
    let mach = 3.0;
    let alpha = 2f64.to_radians();
    let freestream = Freestream::standard(mach, 20_000.0, PerfectGas::AIR).unwrap();
    let mut solution = AeroSolution::default();
    model
        .evaluate(
            &plate(),
            &FlightCondition::steady(freestream, alpha, 0.0),
            &PanelMotion::default(),
            &mut solution,
        )
        .unwrap();
    let delta = freestream.dynamic_pressure_pa * 2.0 * alpha / (mach * mach - 1.0_f64).sqrt();
    let expected = [
        freestream.pressure_pa - delta,
        freestream.pressure_pa + delta,
    ];
    for (p, e) in solution.pressure_pa.iter().zip(expected) {
        assert!((p - e).abs() <= 1e-12 * e, "{p} vs {e}");
    }
    assert_eq!(solution.edge[0].mach, mach);

    let mut bad = settings.clone();
    bad.table.insert("order".into(), toml::Value::Integer(2));
    let err = registry
        .create::<dyn AeroModel>("linearized-v1", &ModelContext::new(region, &registry, &bad))
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("has no settings"), "{err}");
}
