//! Dylib plugins through ABI 2: the two example plugins (`plugins/ackeret`, aero, and
//! `plugins/laminar-plate`, heat flux) load from their cdylibs and compute what their names say;
//! a model of each of the five roles exported through the same `extern "C"` tables (in process,
//! built by `plugin_header!` from the built-in constructors) gives the built-in model's answer
//! bit for bit; and every failure at the boundary (not a library, not a plugin, wrong ABI or API
//! version, a panic, a NaN) is a clear error that leaves the host running (one file: the checks
//! share the plugin-loading and twin-registry fixtures below).

use approx::assert_relative_eq;
use hsv_core::aero::{AeroModel, AeroSolution, EdgeState, PanelMotion, integrate_pressure};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Strip, Surface};
use hsv_core::plugin::{PLUGIN_MAGIC, PluginHeader};
use hsv_core::propulsion::{EngineInputs, PropulsionModel, PropulsionSolution};
use hsv_core::region::{ModelSettings, RegionInfo};
use hsv_core::registry::{ModelContext, Registry, RoleModel};
use hsv_core::structure::StructureModel;
use hsv_core::testing::plugin_path;
use hsv_core::thermal::{ConductionModel, HeatFluxModel};
use nalgebra::{DVector, Point3, Vector3};

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

/// The context of model `name` in sample region `region` with `settings`.
fn context<'a>(
    region: &'a RegionInfo,
    registry: &'a Registry,
    settings: &'a ModelSettings,
) -> ModelContext<'a> {
    ModelContext::new(region, registry, settings)
}

fn sample(region: &str) -> &'static RegionInfo {
    hsv_core::testing::sample_region(region)
}

/// Model `name` of `registry` in sample region `region` with that region's settings of
/// `settings_of` (so a plugin twin gets its built-in's settings).
fn build<M: ?Sized + RoleModel>(
    registry: &Registry,
    name: &str,
    region: &str,
    settings_of: &str,
) -> Box<M> {
    let region = sample(region);
    let settings = region.model_settings(settings_of);
    registry
        .create::<M>(name, &context(region, registry, &settings))
        .unwrap_or_else(|e| panic!("{name} in {}: {e}", region.name))
}

fn builtin() -> &'static Registry {
    hsv_run::shared_registry().expect("built-in models register")
}

// ---------------------------------------------------------------------------------------------
// The example dylib plugins.

/// Ackeret flat-plate lift c_l = 4α/√(M²−1) (Anderson, Fundamentals of Aerodynamics, 6th ed.,
/// eq. 12.23), here with the exact normal-force projection c_l = c_n cos α, c_n = 4α/√(M²−1),
/// which differs from the small-angle form by 1 − cos α (0.06 % at 2°). Tolerance 1e-9.
#[test]
fn ackeret_plugin_reproduces_flat_plate_lift_slope() {
    let mut registry = Registry::empty();
    let count = registry
        .load_plugin(&plugin_path("hsv_plugin_ackeret"))
        .expect("plugin loads");
    assert_eq!(count, 1);
    let entry = registry.get("ackeret").expect("registered");
    assert!(entry.origin.to_string().contains("plugin"));

    let mut model: Box<dyn AeroModel> = build(&registry, "ackeret", "right_surface", "ackeret");
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
    registry
        .load_plugin(&plugin_path("hsv_plugin_ackeret"))
        .expect("plugin loads");
    let region = sample("right_surface");
    let mut bad = region.model_settings("ackeret");
    bad.table.insert("order".into(), toml::Value::Integer(3));
    let err = registry
        .create::<dyn AeroModel>("ackeret", &context(region, &registry, &bad))
        .err()
        .expect("unknown setting rejected")
        .to_string();
    // The plugin's own settings error, naming the key path, through the boundary.
    assert!(err.contains("`order`"), "{err}");
    assert!(err.contains("models.ackeret"), "{err}");

    let mut model: Box<dyn AeroModel> = build(&registry, "ackeret", "right_surface", "ackeret");
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
    assert!(err.contains("Mach number = 0.8"), "{err}");
}

/// A flat plate of span 1 m and chord 1 m in `n` streamwise quads on one strip (x from 0 back to
/// −1, normal −z), so panel k has running length (k + ½)/n m.
fn strip_plate(n: usize) -> PanelMesh {
    let mut vertices = Vec::new();
    for i in 0..=n {
        let x = -(i as f64) / n as f64;
        vertices.push(Point3::new(x, 0.0, 0.0));
        vertices.push(Point3::new(x, 1.0, 0.0));
    }
    let specs: Vec<PanelSpec> = (0..n)
        .map(|i| PanelSpec::quad(2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2, 0))
        .collect();
    PanelMesh::new(
        vertices,
        &specs,
        vec![Strip {
            panels: (0..n).collect(),
        }],
        vec![Surface::new("plate", RegionKind::LiftingSurface)],
    )
    .expect("valid plate")
}

/// Low-speed limit of the laminar-plate plugin against the Blasius-Pohlhausen local Nusselt
/// number Nu_x = 0.332 Re_x^½ Pr^⅓ (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer,
/// 6th ed., eq. 7.23) with properties at the film temperature (T_e + T_w)/2 and
/// k = μ c_p / Pr: air at 300 K and 5 m/s over a 350 K wall, no radiation. At M_e = 0.014 the
/// recovery temperature is T_aw = T_e + 0.01 K, so Eckert's T* is the film temperature within
/// 0.003 K and the driving difference T_aw − T_w is T_e − T_w within 0.02 %; tolerance 0.1 %.
#[test]
fn laminar_plate_plugin_matches_blasius_pohlhausen_at_low_speed() {
    let mut registry = Registry::empty();
    registry
        .load_plugin(&plugin_path("hsv_plugin_laminar_plate"))
        .expect("plugin loads");
    let region = sample("right_surface");
    let mut settings = region.model_settings("laminar-flat-plate");
    settings
        .table
        .insert("emissivity".into(), toml::Value::Float(0.0));
    let mut model = registry
        .create::<dyn HeatFluxModel>("laminar-flat-plate", &context(region, &registry, &settings))
        .expect("creates");
    let gas = PerfectGas::AIR;
    let (te, tw, u, pe) = (300.0, 350.0, 5.0, 101_325.0);
    let sound = (gas.gamma * gas.gas_constant_j_kg_k * te).sqrt();
    let edge = EdgeState {
        mach: u / sound,
        pressure_pa: pe,
        temperature_k: te,
        density_kg_m3: pe / (gas.gas_constant_j_kg_k * te),
        velocity_m_s: u,
    };
    let plate = strip_plate(4);
    let aero = AeroSolution {
        pressure_pa: vec![pe; 4],
        edge: vec![edge; 4],
        ..AeroSolution::default()
    };
    let flight = FlightCondition::steady(Freestream::standard(0.0144, 0.0, gas).unwrap(), 0.0, 0.0);
    let mut q = vec![0.0; 4];
    model
        .heat_flux(&plate, &flight, &aero, &[tw; 4], &mut q)
        .expect("evaluates");
    let film = 0.5 * (te + tw);
    let mu = 1.458e-6 * film.powf(1.5) / (film + 110.4);
    let (pr, cp) = (0.71, gas.cp());
    let k = mu * cp / pr;
    let rho = pe / (gas.gas_constant_j_kg_k * film);
    for (i, q) in q.iter().enumerate() {
        let x = (i as f64 + 0.5) / 4.0;
        let nusselt = 0.332 * (rho * u * x / mu).sqrt() * pr.cbrt();
        let blasius = nusselt * k / x * (te - tw);
        assert_relative_eq!(*q, blasius, max_relative = 1e-3);
    }
}

/// The laminar-plate plugin's built-in twin is `eckert` held laminar with the stagnation
/// heating off: on the sample lifting surface at Mach 6, 26 km, 2° (edge states from
/// shock-expansion) and a 700 K wall both give the same net heat flux to 1e-12.
#[test]
fn laminar_plate_plugin_equals_its_builtin_twin() {
    let mut registry = Registry::empty();
    registry
        .load_plugin(&plugin_path("hsv_plugin_laminar_plate"))
        .expect("plugin loads");
    let region = sample("right_surface");
    let mesh = &region.mesh;
    let flight = FlightCondition::steady(
        Freestream::standard(6.0, 26_000.0, PerfectGas::AIR).unwrap(),
        2f64.to_radians(),
        0.0,
    );
    let mut aero: Box<dyn AeroModel> = build(
        builtin(),
        "shock-expansion",
        "right_surface",
        "shock-expansion",
    );
    let mut solution = AeroSolution::default();
    aero.evaluate(mesh, &flight, &PanelMotion::default(), &mut solution)
        .unwrap();
    let wall = vec![700.0; mesh.panels.len()];

    let mut eckert = region.model_settings("eckert");
    eckert.table = toml::from_str(
        "regime = \"laminar\"\nleading_edge_radius_m = 0.0\nemissivity = 0.8\nprandtl_number = 0.71",
    )
    .unwrap();
    let mut twin = builtin()
        .create::<dyn HeatFluxModel>("eckert", &context(region, builtin(), &eckert))
        .unwrap();
    let plugin_settings = region.model_settings("laminar-flat-plate");
    let mut plugin = registry
        .create::<dyn HeatFluxModel>(
            "laminar-flat-plate",
            &context(region, &registry, &plugin_settings),
        )
        .unwrap();
    let (mut expected, mut got) = (wall.clone(), wall.clone());
    twin.heat_flux(mesh, &flight, &solution, &wall, &mut expected)
        .unwrap();
    plugin
        .heat_flux(mesh, &flight, &solution, &wall, &mut got)
        .unwrap();
    assert!(expected.iter().any(|q| q.abs() > 1e3), "{expected:?}");
    for (g, e) in got.iter().zip(&expected) {
        assert_relative_eq!(*g, *e, max_relative = 1e-12);
    }
    // The plugin has no skin-friction law, and the adapter says so.
    assert!(plugin.skin_friction().is_none());
}

// ---------------------------------------------------------------------------------------------
// Every role through the ABI-2 tables, in process: the built-in constructors exported with
// `plugin_header!` and loaded through the host adapters, against the built-in models.

fn via_builtin<M: ?Sized + RoleModel>(
    name: &str,
    ctx: &ModelContext<'_>,
) -> Result<Box<M>, ModelError> {
    // The guest side rebuilds `ctx.region` from plain data; build the built-in model on it.
    let guest = ModelContext {
        registry: builtin(),
        ..*ctx
    };
    builtin()
        .create::<M>(name, &guest)
        .map_err(|e| ModelError::inconsistent(name, e.to_string()))
}

fn shock_expansion(ctx: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    via_builtin("shock-expansion", ctx)
}
fn eckert(ctx: &ModelContext<'_>) -> Result<Box<dyn HeatFluxModel>, ModelError> {
    via_builtin("eckert", ctx)
}
fn full_order(ctx: &ModelContext<'_>) -> Result<Box<dyn ConductionModel>, ModelError> {
    via_builtin("full-order", ctx)
}
fn ritz_plate(ctx: &ModelContext<'_>) -> Result<Box<dyn StructureModel>, ModelError> {
    via_builtin("ritz-plate", ctx)
}
fn free_free_beam(ctx: &ModelContext<'_>) -> Result<Box<dyn StructureModel>, ModelError> {
    via_builtin("free-free-beam", ctx)
}
fn scramjet_1d(ctx: &ModelContext<'_>) -> Result<Box<dyn PropulsionModel>, ModelError> {
    via_builtin("scramjet-1d", ctx)
}

hsv_core::plugin_header! {
    /// Six models of all five roles in one plugin table.
    static TWINS = [
        aero { name: "shock-expansion-abi", fidelity: 2, summary: "shock-expansion via ABI 2",
               settings: "", constructor: shock_expansion },
        heat_flux { name: "eckert-abi", fidelity: 1, summary: "eckert via ABI 2",
                    settings: "", constructor: eckert },
        conduction { name: "full-order-abi", fidelity: 2, summary: "full-order via ABI 2",
                     settings: "", constructor: full_order },
        structure { name: "ritz-plate-abi", fidelity: 2, summary: "ritz-plate via ABI 2",
                    settings: "", constructor: ritz_plate },
        structure { name: "free-free-beam-abi", fidelity: 1, summary: "free-free-beam via ABI 2",
                    settings: "", constructor: free_free_beam },
        propulsion { name: "scramjet-1d-abi", fidelity: 1, summary: "scramjet-1d via ABI 2",
                     settings: "", constructor: scramjet_1d },
    ];
}

fn twins() -> &'static Registry {
    static REGISTRY: std::sync::OnceLock<Registry> = std::sync::OnceLock::new();
    REGISTRY.get_or_init(|| {
        let mut registry = Registry::empty();
        // SAFETY: TWINS is built by `plugin_header!`, which follows the ABI.
        let count = unsafe { registry.register_plugin_header(&TWINS, "in-process twins") }
            .expect("twin table loads");
        assert_eq!(count, 6);
        registry
    })
}

fn mach_6_flight() -> FlightCondition {
    let mut flight = FlightCondition::steady(
        Freestream::standard(6.0, 26_000.0, PerfectGas::AIR).unwrap(),
        3f64.to_radians(),
        0.5f64.to_radians(),
    );
    flight.angular_velocity_rad_s = Vector3::new(0.01, 0.05, -0.02);
    flight.rotation_center_m = Point3::new(-15.2, 0.0, 0.5);
    flight
}

/// Aero: pressures, edge states and diagnostics of shock-expansion on the sample lifting surface
/// with body rates and elastic panel velocities are bit-identical through the ABI.
#[test]
fn aero_through_the_abi_equals_the_builtin() {
    let region = sample("right_surface");
    let mesh = &region.mesh;
    let flight = mach_6_flight();
    let elastic: Vec<Vector3<f64>> = (0..mesh.panels.len())
        .map(|i| Vector3::new(0.0, 0.0, 0.5 * (i as f64 * 0.1).sin()))
        .collect();
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&elastic),
    };
    let mut direct: Box<dyn AeroModel> = build(
        builtin(),
        "shock-expansion",
        "right_surface",
        "shock-expansion",
    );
    let mut plugin: Box<dyn AeroModel> = build(
        twins(),
        "shock-expansion-abi",
        "right_surface",
        "shock-expansion",
    );
    let (mut expected, mut got) = (AeroSolution::default(), AeroSolution::default());
    direct
        .evaluate(mesh, &flight, &motion, &mut expected)
        .unwrap();
    plugin.evaluate(mesh, &flight, &motion, &mut got).unwrap();
    assert_eq!(got, expected);
    // Twice, reusing every buffer, on another region's mesh.
    let body = &sample("main_body").mesh;
    direct
        .evaluate(body, &flight, &PanelMotion::default(), &mut expected)
        .unwrap();
    plugin
        .evaluate(body, &flight, &PanelMotion::default(), &mut got)
        .unwrap();
    assert_eq!(got, expected);
}

/// Heat flux and wall shear: eckert (with its skin-friction capability) is bit-identical through
/// the ABI on the sample lifting surface.
#[test]
fn heat_flux_through_the_abi_equals_the_builtin() {
    let region = sample("right_surface");
    let mesh = &region.mesh;
    let flight = mach_6_flight();
    let mut aero: Box<dyn AeroModel> = build(
        builtin(),
        "shock-expansion",
        "right_surface",
        "shock-expansion",
    );
    let mut solution = AeroSolution::default();
    aero.evaluate(mesh, &flight, &PanelMotion::default(), &mut solution)
        .unwrap();
    let wall: Vec<f64> = (0..mesh.panels.len())
        .map(|i| 400.0 + 3.0 * i as f64)
        .collect();
    let mut direct: Box<dyn HeatFluxModel> = build(builtin(), "eckert", "right_surface", "eckert");
    let mut plugin: Box<dyn HeatFluxModel> =
        build(twins(), "eckert-abi", "right_surface", "eckert");
    let n = mesh.panels.len();
    let (mut expected, mut got) = (vec![0.0; n], vec![0.0; n]);
    direct
        .heat_flux(mesh, &flight, &solution, &wall, &mut expected)
        .unwrap();
    plugin
        .heat_flux(mesh, &flight, &solution, &wall, &mut got)
        .unwrap();
    assert_eq!(got, expected);
    direct
        .skin_friction()
        .unwrap()
        .wall_shear(mesh, &flight, &solution, &wall, &mut expected)
        .unwrap();
    plugin
        .skin_friction()
        .expect("capability crosses the ABI")
        .wall_shear(mesh, &flight, &solution, &wall, &mut got)
        .unwrap();
    assert_eq!(got, expected);
    assert!(got.iter().any(|&tau| tau > 0.0));
}

/// Conduction: full-order sizes, uniform state, three 10 ms steps under a heat flux and the
/// three temperature read-outs are bit-identical through the ABI.
#[test]
fn conduction_through_the_abi_equals_the_builtin() {
    let mut direct: Box<dyn ConductionModel> =
        build(builtin(), "full-order", "right_surface", "full-order");
    let mut plugin: Box<dyn ConductionModel> =
        build(twins(), "full-order-abi", "right_surface", "full-order");
    assert_eq!(
        (
            plugin.n_states(),
            plugin.n_nodes(),
            plugin.n_surface_panels()
        ),
        (
            direct.n_states(),
            direct.n_nodes(),
            direct.n_surface_panels()
        )
    );
    let mut expected = direct.uniform_state(300.0).unwrap();
    let mut got = plugin.uniform_state(300.0).unwrap();
    assert_eq!(got, expected);
    let flux: Vec<f64> = (0..direct.n_surface_panels())
        .map(|i| 2.0e4 + 500.0 * (i % 7) as f64)
        .collect();
    for _ in 0..3 {
        direct.step(&mut expected, &flux, 0.01).unwrap();
        plugin.step(&mut got, &flux, 0.01).unwrap();
    }
    assert_eq!(got, expected);
    assert!(expected.max() > 300.0);
    type Read = fn(&dyn ConductionModel, &DVector<f64>, &mut [f64]);
    let reads: [Read; 3] = [
        |m, s, o| m.surface_temperatures(s, o),
        |m, s, o| m.node_temperatures(s, o),
        |m, s, o| m.node_temperature_differences(s, o),
    ];
    for (k, read) in reads.iter().enumerate() {
        let n = if k == 0 {
            direct.n_surface_panels()
        } else {
            direct.n_nodes()
        };
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        read(direct.as_ref(), &expected, &mut a);
        read(plugin.as_ref(), &got, &mut b);
        assert_eq!(b, a, "read-out {k}");
    }
}

/// Compares everything a structure exposes, capability by capability.
fn assert_same_structure(direct: &mut dyn StructureModel, plugin: &mut dyn StructureModel) {
    assert_eq!(plugin.modal_model(), direct.modal_model());
    assert_eq!(
        plugin.natural_frequencies_hz().unwrap(),
        direct.natural_frequencies_hz().unwrap()
    );
    for region in ["right_surface", "main_body"] {
        let mesh = &sample(region).mesh;
        if let Ok(shapes) = direct.mode_shapes_on(mesh) {
            assert_eq!(
                plugin.mode_shapes_on(mesh).unwrap().vertex_displacement,
                shapes.vertex_displacement
            );
        }
    }
    let n = direct.modal_model().n_modes();
    assert_eq!(plugin.root_loads().is_some(), direct.root_loads().is_some());
    if let (Some(a), Some(b)) = (direct.root_loads(), plugin.root_loads()) {
        assert_eq!(b.root_reference_m(), a.root_reference_m());
        let q = DVector::from_fn(n, |i, _| 1e-3 * (i as f64 + 1.0));
        let q_dot = DVector::from_fn(n, |i, _| 1e-2 * i as f64);
        let q_ddot = DVector::from_fn(n, |i, _| 0.1 * (i as f64).cos());
        let applied = hsv_core::aero::Loads {
            force_n: Vector3::new(10.0, 200.0, -3000.0),
            moment_nm: Vector3::new(5.0, -40.0, 7.0),
        };
        assert_eq!(
            b.root_loads(&q, &q_dot, &q_ddot, &applied).unwrap(),
            a.root_loads(&q, &q_dot, &q_ddot, &applied).unwrap()
        );
    }
    assert_eq!(
        plugin.mass_properties().map(|m| m.mass_properties()),
        direct.mass_properties().map(|m| m.mass_properties())
    );
    assert_eq!(
        plugin.rigid_body_coupling().is_some(),
        direct.rigid_body_coupling().is_some()
    );
    if let (Some(a), Some(b)) = (direct.rigid_body_coupling(), plugin.rigid_body_coupling()) {
        assert_eq!(b.rigid_dofs(), a.rigid_dofs());
        assert_eq!(b.rigid_reference_point_m(), a.rigid_reference_point_m());
        assert_eq!(b.rigid_coupling(), a.rigid_coupling());
    }
    assert_eq!(
        plugin.thermal_stiffness().is_some(),
        direct.thermal_stiffness().is_some()
    );
}

/// Structure: ritz-plate (all four capabilities) and free-free-beam give the same modal
/// matrices, names, frequencies, mode shapes on a mesh's vertices, root loads, mass properties
/// and rigid coupling through the ABI, and the same matrices and thermal generalized forces
/// after a temperature update.
#[test]
fn structure_through_the_abi_equals_the_builtin() {
    let mut direct: Box<dyn StructureModel> =
        build(builtin(), "ritz-plate", "right_surface", "ritz-plate");
    let mut plugin: Box<dyn StructureModel> =
        build(twins(), "ritz-plate-abi", "right_surface", "ritz-plate");
    assert_same_structure(direct.as_mut(), plugin.as_mut());
    let nodes = direct.thermal_stiffness().unwrap().temperature_nodes();
    assert_eq!(
        plugin.thermal_stiffness().unwrap().temperature_nodes(),
        nodes
    );
    let mean: Vec<f64> = (0..nodes).map(|i| 500.0 + (i % 11) as f64 * 20.0).collect();
    let difference: Vec<f64> = (0..nodes).map(|i| (i % 5) as f64).collect();
    for model in [&mut direct, &mut plugin] {
        model
            .thermal_stiffness_mut()
            .unwrap()
            .set_temperature_field(&mean, &difference)
            .unwrap();
    }
    assert_same_structure(direct.as_mut(), plugin.as_mut());
    assert_eq!(
        plugin
            .thermal_stiffness()
            .unwrap()
            .thermal_generalized_forces(),
        direct
            .thermal_stiffness()
            .unwrap()
            .thermal_generalized_forces()
    );

    let mut direct: Box<dyn StructureModel> =
        build(builtin(), "free-free-beam", "main_body", "free-free-beam");
    let mut plugin: Box<dyn StructureModel> =
        build(twins(), "free-free-beam-abi", "main_body", "free-free-beam");
    assert_same_structure(direct.as_mut(), plugin.as_mut());
}

/// Propulsion: scramjet-1d loads, mass flow, status, owned-panel pressures and station states
/// are bit-identical through the ABI.
#[test]
fn propulsion_through_the_abi_equals_the_builtin() {
    let region = sample("propulsion");
    let flight = FlightCondition::steady(
        Freestream::standard(8.0, 26_000.0, PerfectGas::AIR).unwrap(),
        2f64.to_radians(),
        0.0,
    );
    let inputs = EngineInputs {
        flight: &flight,
        body: &region.mesh,
        fuel_equivalence_ratio: 0.5,
    };
    let mut direct: Box<dyn PropulsionModel> =
        build(builtin(), "scramjet-1d", "propulsion", "scramjet-1d");
    let mut plugin: Box<dyn PropulsionModel> =
        build(twins(), "scramjet-1d-abi", "propulsion", "scramjet-1d");
    let (mut expected, mut got) = (PropulsionSolution::default(), PropulsionSolution::default());
    direct.evaluate(&inputs, &mut expected).unwrap();
    plugin.evaluate(&inputs, &mut got).unwrap();
    assert_eq!(got, expected);
    assert!(expected.loads.force_n.x.abs() > 0.0 && !expected.stations.is_empty());
}

// ---------------------------------------------------------------------------------------------
// Failures at the boundary.

/// An aero model that panics, one that returns NaN, and one whose constructor panics.
struct Faulty {
    nan: bool,
}

impl AeroModel for Faulty {
    fn name(&self) -> &str {
        "faulty"
    }
    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        _motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError> {
        if !self.nan {
            panic!("index out of bounds in the faulty plugin");
        }
        out.reset(mesh.panels.len());
        out.pressure_pa.fill(flight.freestream.pressure_pa);
        out.pressure_pa[1] = f64::NAN;
        Ok(())
    }
}

fn panicking(_: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    Ok(Box::new(Faulty { nan: false }))
}
fn returns_nan(_: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    Ok(Box::new(Faulty { nan: true }))
}
fn panics_in_create(_: &ModelContext<'_>) -> Result<Box<dyn HeatFluxModel>, ModelError> {
    panic!("the faulty plugin cannot start")
}

hsv_core::plugin_header! {
    static FAULTY = [
        aero { name: "panicking", fidelity: 0, summary: "panics", settings: "", constructor: panicking },
        aero { name: "returns-nan", fidelity: 0, summary: "NaN", settings: "", constructor: returns_nan },
        heat_flux { name: "panics-in-create", fidelity: 0, summary: "panics", settings: "",
                    constructor: panics_in_create },
    ];
}

fn evaluate_plate(model: &mut dyn AeroModel) -> Result<AeroSolution, ModelError> {
    let freestream = Freestream::standard(3.0, 20_000.0, PerfectGas::AIR).unwrap();
    let mut solution = AeroSolution::default();
    model.evaluate(
        &flat_plate(),
        &FlightCondition::steady(freestream, 0.02, 0.0),
        &PanelMotion::default(),
        &mut solution,
    )?;
    Ok(solution)
}

#[test]
fn panics_and_nans_are_errors_and_the_host_keeps_running() {
    let mut registry = Registry::empty();
    // SAFETY: FAULTY is built by `plugin_header!`.
    unsafe { registry.register_plugin_header(&FAULTY, "faulty in-process plugin") }.unwrap();
    registry
        .load_plugin(&plugin_path("hsv_plugin_ackeret"))
        .unwrap();

    let mut panicking: Box<dyn AeroModel> =
        build(&registry, "panicking", "right_surface", "panicking");
    let err = evaluate_plate(panicking.as_mut()).unwrap_err().to_string();
    assert!(err.contains("panicked in evaluate"), "{err}");
    assert!(
        err.contains("index out of bounds in the faulty plugin"),
        "{err}"
    );
    // The same handle fails the same way again: the panic did not take the host down.
    assert!(evaluate_plate(panicking.as_mut()).is_err());

    let mut nan: Box<dyn AeroModel> =
        build(&registry, "returns-nan", "right_surface", "returns-nan");
    let err = evaluate_plate(nan.as_mut()).unwrap_err();
    assert!(
        matches!(&err, ModelError::NonFinite { quantity, location, .. }
            if quantity.starts_with("pressure") && location.contains("panel 1")),
        "{err}"
    );

    let region = sample("right_surface");
    let settings = region.model_settings("panics-in-create");
    let err = registry
        .create::<dyn HeatFluxModel>("panics-in-create", &context(region, &registry, &settings))
        .err()
        .expect("create fails")
        .to_string();
    assert!(err.contains("panicked in create"), "{err}");
    assert!(err.contains("the faulty plugin cannot start"), "{err}");

    // The host still runs models of the same registry.
    let mut ackeret: Box<dyn AeroModel> = build(&registry, "ackeret", "right_surface", "ackeret");
    let solution = evaluate_plate(ackeret.as_mut()).unwrap();
    assert!(
        solution
            .pressure_pa
            .iter()
            .all(|p| p.is_finite() && *p > 0.0)
    );
}

/// A header built at run time around the faulty table with one field changed.
fn altered_header(change: impl FnOnce(&mut PluginHeader)) -> &'static PluginHeader {
    let mut header = PluginHeader {
        magic: PLUGIN_MAGIC,
        abi_version: FAULTY.abi_version,
        api_version: FAULTY.api_version,
        model_count: FAULTY.model_count,
        models: FAULTY.models,
    };
    change(&mut header);
    Box::leak(Box::new(header))
}

#[test]
fn header_mismatches_are_clear_errors() {
    type Change = fn(&mut PluginHeader);
    let cases: [(Change, &str); 4] = [
        (|h| h.magic = *b"NOTHSV\0\0", "wrong magic bytes"),
        (|h| h.abi_version = 3, "ABI version 3"),
        (
            |h| h.api_version = [3, 0, 0],
            "plugin API 3.0.0 is incompatible",
        ),
        (|h| h.model_count = 0, "declares no models"),
    ];
    for (change, message) in cases {
        let mut registry = Registry::empty();
        // SAFETY: the header is checked before anything it points at is used.
        let err = unsafe { registry.register_plugin_header(altered_header(change), "test.so") }
            .unwrap_err()
            .to_string();
        assert!(err.contains(message) && err.contains("test.so"), "{err}");
        assert!(registry.is_empty());
    }
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

/// A real shared library without the entry point (the C maths library).
#[test]
fn a_library_without_the_entry_point_is_a_clear_error() {
    let candidates = [
        "/lib/x86_64-linux-gnu/libm.so.6",
        "/usr/lib/x86_64-linux-gnu/libm.so.6",
        "/lib/aarch64-linux-gnu/libm.so.6",
        "/usr/lib/aarch64-linux-gnu/libm.so.6",
        "/lib64/libm.so.6",
        "/usr/lib64/libm.so.6",
        "/usr/lib/libm.so.6",
        "/usr/lib/libSystem.B.dylib",
    ];
    let libm = candidates
        .iter()
        .map(std::path::PathBuf::from)
        .find(|p| p.exists())
        .expect("a C maths library in a standard place");
    let mut registry = Registry::empty();
    let err = registry.load_plugin(&libm).unwrap_err().to_string();
    assert!(err.contains("no `hsv_plugin_entry` entry point"), "{err}");
    assert!(registry.is_empty());
}

/// Two plugins that both claim a name: the second load fails naming both, and registers none of
/// its models.
#[test]
fn a_taken_name_rejects_the_whole_plugin() {
    let mut registry = Registry::empty();
    registry
        .load_plugin(&plugin_path("hsv_plugin_ackeret"))
        .unwrap();
    let err = registry
        .load_plugin(&plugin_path("hsv_plugin_ackeret"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("`ackeret` is registered twice"), "{err}");
    assert_eq!(registry.len(), 1);
}
