//! Cost of calling a model through the plugin ABI against its built-in twin, on the same inputs:
//! `shock-expansion` (aero, sample body mesh), `eckert` (heat flux, sample lifting surface) and
//! `scramjet-1d` (propulsion, sample body at φ = 0.13) exported in process with
//! `hsv_core::plugin_header!` and called through the host adapters (plain-buffer marshalling,
//! panic catching, NaN checks), and the two example cdylib plugins loaded from disk against the
//! nearest built-in model (`ackeret` beside `piston-theory`, `laminar-flat-plate` (crate laminar-plate) beside `eckert`).
//!
//! `cargo bench -p hsv-benches --bench plugins -- --measurement-time 3 --warm-up-time 1`.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use hsv_core::aero::{AeroModel, AeroSolution, PanelMotion};
use hsv_core::error::ModelError;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::geometry::build_vehicle;
use hsv_core::propulsion::{EngineInputs, PropulsionModel, PropulsionSolution};
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry, RoleModel};
use hsv_core::thermal::HeatFluxModel;
use hsv_plugin_ackeret as _;
use hsv_plugin_laminar_plate as _;

fn builtin() -> &'static Registry {
    hsv_run::shared_registry().expect("built-in models register")
}

/// The built-in model `name` on the guest side of the in-process plugin.
fn via_builtin<M: ?Sized + RoleModel>(
    name: &str,
    ctx: &ModelContext<'_>,
) -> Result<Box<M>, ModelError> {
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
fn scramjet_1d(ctx: &ModelContext<'_>) -> Result<Box<dyn PropulsionModel>, ModelError> {
    via_builtin("scramjet-1d", ctx)
}

hsv_core::plugin_header! {
    /// Built-in models exported through ABI 2, in process.
    static TWINS = [
        aero { name: "shock-expansion-abi", fidelity: 3, summary: "shock-expansion via ABI 2",
               settings: "", constructor: shock_expansion },
        heat_flux { name: "eckert-abi", fidelity: 1, summary: "eckert via ABI 2",
                    settings: "", constructor: eckert },
        propulsion { name: "scramjet-1d-abi", fidelity: 1, summary: "scramjet-1d via ABI 2",
                     settings: "", constructor: scramjet_1d },
    ];
}

/// The cdylib of example plugin crate `crate_name` (a dev-dependency, so built beside this
/// bench binary in `target/release/deps/`).
fn plugin_path(crate_name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("bench binary path");
    let deps = exe.parent().expect("target/release/deps");
    let file = format!(
        "{}{crate_name}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    [deps.join(&file), deps.join("..").join(&file)]
        .into_iter()
        .find(|p| p.exists())
        .unwrap_or_else(|| panic!("{file} not found beside {}", deps.display()))
}

/// The host registry: built-ins, the in-process twins and the two example cdylibs.
fn host() -> Registry {
    let mut registry = builtin().clone();
    // SAFETY: TWINS is built by `plugin_header!`, which follows the ABI.
    unsafe { registry.register_plugin_header(&TWINS, "in-process twins") }.expect("twins load");
    for krate in ["hsv_plugin_ackeret", "hsv_plugin_laminar_plate"] {
        registry
            .load_plugin(&plugin_path(krate))
            .expect("example plugin loads");
    }
    registry
}

/// Model `name` of `registry` in sample region `region` with the settings of `settings_of`.
fn build<M: ?Sized + RoleModel>(
    registry: &Registry,
    name: &str,
    region: &RegionInfo,
    settings_of: &str,
) -> Box<M> {
    let settings = region.model_settings(settings_of);
    registry
        .create::<M>(name, &ModelContext::new(region, registry, &settings))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn plugins(c: &mut Criterion) {
    let registry = host();
    let body_region = hsv_core::testing::sample_region("main_body");
    let surface = hsv_core::testing::sample_region("right_surface");
    let freestream = Freestream::standard(6.0, 26_000.0, body_region.gas).expect("atmosphere");
    let mut flight = FlightCondition::steady(freestream, 2f64.to_radians(), 0.0);
    flight.rotation_center_m = body_region.reference.moment_point();

    let mut group = c.benchmark_group("plugins/aero-sample-body");
    for (name, settings_of) in [
        ("shock-expansion", "shock-expansion"),
        ("shock-expansion-abi", "shock-expansion"),
        ("piston-theory", "piston-theory"),
        ("ackeret", "ackeret"),
    ] {
        let mut model: Box<dyn AeroModel> = build(&registry, name, body_region, settings_of);
        let mut out = AeroSolution::default();
        group.bench_function(name, |b| {
            b.iter(|| {
                model
                    .evaluate(
                        &body_region.mesh,
                        black_box(&flight),
                        &PanelMotion::default(),
                        &mut out,
                    )
                    .expect("evaluates");
                black_box(&out.pressure_pa);
            })
        });
    }
    group.finish();

    let mut aero = AeroSolution::default();
    build::<dyn AeroModel>(&registry, "shock-expansion", surface, "shock-expansion")
        .evaluate(&surface.mesh, &flight, &PanelMotion::default(), &mut aero)
        .expect("edge states");
    let wall = vec![600.0; surface.mesh.panels.len()];
    let mut q = vec![0.0; wall.len()];
    let mut group = c.benchmark_group("plugins/heat-flux-sample-surface");
    for (name, settings_of) in [
        ("eckert", "eckert"),
        ("eckert-abi", "eckert"),
        ("laminar-flat-plate", "laminar-flat-plate"),
    ] {
        let mut model: Box<dyn HeatFluxModel> = build(&registry, name, surface, settings_of);
        group.bench_function(name, |b| {
            b.iter(|| {
                model
                    .heat_flux(&surface.mesh, black_box(&flight), &aero, &wall, &mut q)
                    .expect("heat flux");
                black_box(&q);
            })
        });
    }
    group.finish();

    let geometry = build_vehicle(
        &hsv_core::config::LoadedConfig::sample()
            .expect("sample")
            .config
            .geometry,
        &hsv_core::config::LoadedConfig::sample()
            .expect("sample")
            .config
            .lifting_surface,
    )
    .expect("sample vehicle");
    let engine_region = hsv_core::testing::sample_region("propulsion");
    let inputs = EngineInputs {
        flight: &flight,
        body: &geometry.body,
        fuel_equivalence_ratio: 0.13,
    };
    let mut group = c.benchmark_group("plugins/propulsion-sample-body");
    for name in ["scramjet-1d", "scramjet-1d-abi"] {
        let mut model: Box<dyn PropulsionModel> =
            build(&registry, name, engine_region, "scramjet-1d");
        let mut out = PropulsionSolution::default();
        group.bench_function(name, |b| {
            b.iter(|| {
                model
                    .evaluate(black_box(&inputs), &mut out)
                    .expect("evaluates");
                black_box(&out.loads);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, plugins);
criterion_main!(benches);
