//! The control role through plugin ABI 2.1: the example plugin (`plugins/pole-placement`) loads
//! from its cdylib and places the poles it is asked to; the built-in controllers exported through
//! the same `extern "C"` tables (in process, by `plugin_header!`) fly bit for bit as they do
//! built in, state and design models crossing the boundary; and a failing plugin controller
//! is a clear error.

use hsv_core::control::{
    ControlCommands, Controller, DesignSource, LinearDesignModel, MeasuredOutputs,
};
use hsv_core::error::ModelError;
use hsv_core::registry::ControlContext;
use hsv_core::registry::Registry;
use hsv_core::testing::plugin_path;
use nalgebra::DMatrix;

/// A rigid longitudinal design model of the shape the runner builds (states are measured
/// outputs): the α-q block is the sample vehicle's (from `hsv-run linearize --controller
/// pole-placement`, short period +1.81 and −1.95 /s), the rest a plausible point-mass
/// coupling at 1 800 m/s.
fn longitudinal() -> LinearDesignModel {
    let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect();
    LinearDesignModel {
        state_names: names(&[
            "airspeed_m_s",
            "alpha_rad",
            "q_rad_s",
            "pitch_rad",
            "altitude_m",
        ]),
        input_names: names(&["symmetric_elevon_rad", "fuel_equivalence_ratio"]),
        #[rustfmt::skip]
        a: DMatrix::from_row_slice(5, 5, &[
            -0.005, -5.0, 0.0, -9.8, 0.0,
            0.0, -0.09597, 0.99998, 0.0, 0.0,
            0.0, 3.5356, -0.04576, 0.0, 0.0,
            0.0, 0.0, 1.0, 0.0, 0.0,
            0.0, -1800.0, 0.0, 1800.0, 0.0,
        ]),
        #[rustfmt::skip]
        b: DMatrix::from_row_slice(5, 2, &[
            0.1, 20.0,
            0.012176, 0.0,
            2.2623, 0.0,
            0.0, 0.0,
            0.0, 0.0,
        ]),
        reduction: "synthetic".into(),
    }
}

fn lateral() -> LinearDesignModel {
    let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect();
    LinearDesignModel {
        state_names: names(&["beta_rad", "p_rad_s", "r_rad_s", "roll_rad"]),
        input_names: names(&["differential_elevon_rad"]),
        #[rustfmt::skip]
        a: DMatrix::from_row_slice(4, 4, &[
            -0.05, 0.03, -1.0, 0.005,
            -20.0, -0.5, 0.3, 0.0,
            3.0, -0.02, -0.1, 0.0,
            0.0, 1.0, 0.03, 0.0,
        ]),
        b: DMatrix::from_column_slice(4, 1, &[0.0, 15.0, 1.0, 0.0]),
        reduction: "synthetic".into(),
    }
}

/// The design source of the tests; `failing` answers every request with an error.
struct Synthetic {
    failing: bool,
}

impl DesignSource for Synthetic {
    fn longitudinal(&self) -> Result<LinearDesignModel, ModelError> {
        if self.failing {
            return Err(ModelError::inconsistent(
                "vehicle",
                "the trim did not converge",
            ));
        }
        Ok(longitudinal())
    }
    fn lateral(&self) -> Result<LinearDesignModel, ModelError> {
        if self.failing {
            return Err(ModelError::inconsistent(
                "vehicle",
                "the trim did not converge",
            ));
        }
        Ok(lateral())
    }
}

fn trim_outputs() -> MeasuredOutputs {
    MeasuredOutputs {
        airspeed_m_s: 1790.0,
        alpha_rad: 0.0296,
        mach: 6.0,
        altitude_m: 26_000.0,
        pitch_rad: 0.0296,
        symmetric_elevon_rad: -0.098,
        fuel_equivalence_ratio: 0.33,
        ..Default::default()
    }
}

fn trim_commands() -> ControlCommands {
    ControlCommands {
        symmetric_elevon_rad: -0.098,
        differential_elevon_rad: 0.0,
        fuel_equivalence_ratio: 0.33,
    }
}

fn table(text: &str) -> toml::Table {
    text.parse().expect("test TOML")
}

/// Builds controller `name` of `registry` from `settings` (at `models.<name>`), the doublet
/// as `[simulation.inputs]` and a 50 m climb as `[control.commands]`.
fn build(
    registry: &Registry,
    name: &str,
    settings: &str,
    design: &dyn DesignSource,
) -> Result<Box<dyn Controller>, String> {
    let settings = table(settings);
    let schedule = table(
        "symmetric_elevon_deg = { time_s = [0.0, 0.5, 0.51, 1.0, 1.01, 1.5, 1.51], value = [0.0, 0.0, 1.0, 1.0, -1.0, -1.0, 0.0] }",
    );
    let commands = table("altitude_m = { time_s = [0.0, 1.0], value = [0.0, 50.0] }");
    let key_path = format!("models.{name}");
    let context = ControlContext {
        settings: &settings,
        key_path: &key_path,
        file: "test.toml",
        trim_outputs: &trim_outputs(),
        trim_commands: &trim_commands(),
        design,
        schedule: &schedule,
        commands: &commands,
        registry,
    };
    registry
        .create_controller(name, &context)
        .map_err(|e| e.to_string())
}

fn pole_placement_registry() -> Registry {
    let mut registry = Registry::empty();
    registry
        .load_plugin(&plugin_path("hsv_plugin_pole_placement"))
        .expect("the pole-placement plugin loads");
    registry
}

/// The placed poles are the roots of s² + 2ζω s + ω² (Ackermann's formula is exact): the α-q
/// block of the design model closed by the plugin's gain (read back through the ABI's state
/// feedback) has eigenvalues −ζω ± jω√(1 − ζ²) to 1e-9 relative, for settings passed as
/// `[models.pole-placement]`; one sample commands δe = δe_trim − K Δz and holds φ and the
/// differential elevon at trim.
#[test]
fn pole_placement_plugin_places_the_short_period_poles() {
    let registry = pole_placement_registry();
    let (omega, zeta): (f64, f64) = (5.0, 0.6);
    let mut controller = build(
        &registry,
        "pole-placement",
        &format!(
            "short_period_frequency_rad_s = {omega}\nshort_period_damping = {zeta}\nsample_interval_s = 0.02"
        ),
        &Synthetic { failing: false },
    )
    .expect("designs");
    assert_eq!(controller.sample_interval_s(), Some(0.02));
    assert_eq!(controller.state_len(), 0);
    let laws = controller.state_feedback();
    assert_eq!(laws.len(), 1);
    assert_eq!(laws[0].state_names, ["alpha_rad", "q_rad_s"]);
    let k = &laws[0].k;
    let model = longitudinal();
    let a = DMatrix::from_fn(2, 2, |i, j| model.a[(i + 1, j + 1)]);
    let b = DMatrix::from_fn(2, 1, |i, _| model.b[(i + 1, 0)]);
    let closed = a - b * k;
    let eig = hsv_core::linalg::general_eigen(&closed).expect("eigenvalues");
    let (re, im) = (-zeta * omega, omega * (1.0 - zeta * zeta).sqrt());
    for value in eig.values.iter() {
        assert!(
            (value.re - re).abs() < 1e-9 * omega && (value.im.abs() - im).abs() < 1e-9 * omega,
            "closed-loop pole {value}, placed {re} ± {im} j"
        );
    }
    let report = controller.design_report();
    assert_eq!(report["placed"]["damping"], zeta);

    let mut outputs = trim_outputs();
    outputs.alpha_rad += 0.01;
    outputs.q_rad_s = -0.02;
    let mut commands = ControlCommands::default();
    controller
        .update(&outputs, &mut [], &mut commands)
        .expect("a sample");
    let expected = trim_commands().symmetric_elevon_rad - (k[(0, 0)] * 0.01 + k[(0, 1)] * -0.02);
    assert!((commands.symmetric_elevon_rad - expected).abs() < 1e-15);
    assert_eq!(commands.differential_elevon_rad, 0.0);
    assert_eq!(
        commands.fuel_equivalence_ratio,
        trim_commands().fuel_equivalence_ratio
    );
}

/// A bad setting names its key, a design model the host cannot build is the host's message,
/// and the host keeps working after both.
#[test]
fn plugin_controller_errors_are_clear() {
    let registry = pole_placement_registry();
    let design = Synthetic { failing: false };
    let err = build(&registry, "pole-placement", "damping = 0.7", &design)
        .err()
        .expect("an unknown key");
    assert!(
        err.contains("models.pole-placement") && err.contains("damping"),
        "{err}"
    );
    let err = build(
        &registry,
        "pole-placement",
        "short_period_damping = -1.0",
        &design,
    )
    .err()
    .expect("a negative damping");
    assert!(
        err.contains("short_period_damping") && err.contains("> 0"),
        "{err}"
    );
    let err = build(
        &registry,
        "pole-placement",
        "",
        &Synthetic { failing: true },
    )
    .err()
    .expect("no design model");
    assert!(err.contains("the trim did not converge"), "{err}");
    build(&registry, "pole-placement", "", &design).expect("still designs");
}

// ---------------------------------------------------------------------------------------------
// The built-in controllers exported through the ABI in process, against themselves built in.

fn builtin() -> &'static Registry {
    hsv_run::shared_registry().expect("built-in models register")
}

fn builtin_controller(
    name: &str,
    ctx: &ControlContext<'_>,
) -> Result<Box<dyn Controller>, ModelError> {
    // The guest's context carries an empty registry; the twins build from the host's.
    let ctx = ControlContext {
        registry: builtin(),
        ..*ctx
    };
    builtin()
        .create_controller(name, &ctx)
        .map_err(|e| ModelError::inconsistent(name, e.to_string()))
}

fn lqr(ctx: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    builtin_controller("lqr", ctx)
}
fn tracking(ctx: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    builtin_controller("tracking", ctx)
}
fn schedule(ctx: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    builtin_controller("schedule", ctx)
}

struct Panicking;

impl Controller for Panicking {
    fn name(&self) -> &str {
        "panicking"
    }
    fn sample_interval_s(&self) -> Option<f64> {
        Some(0.01)
    }
    fn update(
        &mut self,
        _: &MeasuredOutputs,
        _: &mut [f64],
        _: &mut ControlCommands,
    ) -> Result<(), ModelError> {
        panic!("a controller bug")
    }
}

fn panicking(_: &ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> {
    Ok(Box::new(Panicking))
}

hsv_core::plugin_header! {
    static TWINS = [
        control { name: "lqr-twin", fidelity: 1, summary: "lqr through the ABI", settings: "", constructor: lqr },
        control { name: "tracking-twin", fidelity: 1, summary: "tracking through the ABI", settings: "", constructor: tracking },
        control { name: "schedule-twin", fidelity: 0, summary: "schedule through the ABI", settings: "", constructor: schedule },
        control { name: "panicking", fidelity: 0, summary: "panics in update", settings: "", constructor: panicking },
    ];
}

fn twins() -> Registry {
    let mut registry = Registry::empty();
    // SAFETY: TWINS is built by `plugin_header!`, which follows the ABI.
    unsafe { registry.register_plugin_header(&TWINS, "in-process twins") }.expect("twins register");
    registry
}

/// The measured outputs of sample `k`: trim plus a deterministic wander in every channel.
fn wander(k: usize) -> MeasuredOutputs {
    let t = k as f64 * 0.01;
    let mut values = trim_outputs().values();
    values[0] = t;
    for (i, v) in values.iter_mut().enumerate().skip(1) {
        *v += 1e-3 * ((i as f64 + 1.0) * t).sin() * (1.0 + v.abs());
    }
    MeasuredOutputs::from_values(values)
}

/// `lqr` (memoryless), `tracking` (integrator state, commands from `[control.commands]`) and
/// `schedule` (a law of time from `[simulation.inputs]`) give the same sample interval, state,
/// design report, state feedback and 300 samples of commands and state through the ABI as
/// built in, to the last bit: the design models, tables and state cross the boundary intact.
#[test]
fn builtin_controllers_through_the_abi_fly_as_built_in() {
    let registry = twins();
    let design = Synthetic { failing: false };
    for (name, twin) in [
        ("lqr", "lqr-twin"),
        ("tracking", "tracking-twin"),
        ("schedule", "schedule-twin"),
    ] {
        let mut direct = build(builtin(), name, "", &design).expect("built in");
        let mut exported = build(&registry, twin, "", &design).expect("through the ABI");
        assert_eq!(
            direct.sample_interval_s(),
            exported.sample_interval_s(),
            "{name}"
        );
        assert_eq!(direct.state_len(), exported.state_len(), "{name}");
        assert_eq!(direct.design_report(), exported.design_report(), "{name}");
        assert_eq!(direct.state_feedback(), exported.state_feedback(), "{name}");
        let n = direct.state_len();
        let (mut x_direct, mut x_exported) = (vec![1.0; n], vec![2.0; n]);
        direct.initial_state(&mut x_direct);
        exported.initial_state(&mut x_exported);
        assert_eq!(x_direct, x_exported, "{name}: initial state");
        for k in 0..300 {
            let outputs = wander(k);
            let (mut u_direct, mut u_exported) =
                (ControlCommands::default(), ControlCommands::default());
            direct
                .update(&outputs, &mut x_direct, &mut u_direct)
                .expect("built-in sample");
            exported
                .update(&outputs, &mut x_exported, &mut u_exported)
                .expect("ABI sample");
            assert_eq!(u_direct, u_exported, "{name}: commands at sample {k}");
            assert_eq!(x_direct, x_exported, "{name}: state at sample {k}");
        }
    }
}

/// A panic inside a plugin controller's update is an error naming it, not an abort; the host
/// goes on.
#[test]
fn a_panicking_plugin_controller_is_an_error() {
    let registry = twins();
    let design = Synthetic { failing: false };
    let mut controller = build(&registry, "panicking", "", &design).expect("creates");
    let err = controller
        .update(&trim_outputs(), &mut [], &mut ControlCommands::default())
        .expect_err("the panic is an error")
        .to_string();
    assert!(
        err.contains("panicked") && err.contains("a controller bug"),
        "{err}"
    );
    build(&registry, "lqr-twin", "", &design).expect("the host goes on");
}
