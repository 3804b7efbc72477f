//! `hsv._hsv`: the native half of the Python package `hsv` (PyO3, abi3). Thin bindings over the
//! `hsv-run` library: a vehicle from a config, its trim and linear model, and a flight advanced
//! one aeroelastic step at a time, with the GIL released while Rust runs. The Python half
//! (`python/hsv/`) turns JSON into dicts and adds the Gymnasium environment.

use std::path::PathBuf;

use hsv_core::config::LoadedConfig;
use hsv_core::control::ControlCommands;
use hsv_core::registry::Registry;
use hsv_run::analysis::flight::{Flight, FlightOptions};
use hsv_run::analysis::simulate::Sample;
use hsv_run::dynamics::{AttitudeCoordinates, PerturbationRule};
use hsv_run::vehicle::partitioned::SurfaceModel;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::create_exception!(_hsv, HsvError, PyException, "An hsv analysis failed.");
pyo3::create_exception!(
    _hsv,
    ConfigError,
    HsvError,
    "A vehicle config was refused: the message names the file, the key path and what is allowed."
);

/// An analysis error as `HsvError`, with its whole chain of causes.
fn hsv_error(e: impl Into<anyhow::Error>) -> PyErr {
    HsvError::new_err(hsv_run::error_line::error_line(&e.into()))
}

/// A config error as `ConfigError`.
fn config_error(e: impl Into<anyhow::Error>) -> PyErr {
    ConfigError::new_err(hsv_run::error_line::error_line(&e.into()))
}

/// The built-in registry (every model crate linked into this module).
fn builtin() -> PyResult<&'static Registry> {
    hsv_run::shared_registry().map_err(hsv_error)
}

/// Every registered model as JSON (the `models` command's `--json`).
#[pyfunction]
fn models_json() -> PyResult<String> {
    serde_json::to_string(&hsv_run::commands::catalog::models_json(builtin()?)).map_err(hsv_error)
}

/// The embedded sample vehicle's config as JSON (its tables as objects).
#[pyfunction]
fn sample_config_json() -> PyResult<String> {
    let loaded = LoadedConfig::sample().map_err(config_error)?;
    serde_json::to_string(&loaded.raw).map_err(hsv_error)
}

/// A config given as JSON (a Python dict) as TOML text, the form the loader checks.
fn toml_of_json(json: &str, name: &str) -> PyResult<String> {
    let value: serde_json::Value = serde_json::from_str(json)
        .map_err(|e| ConfigError::new_err(format!("{name}: not a config: {e}")))?;
    if !value.is_object() {
        return Err(ConfigError::new_err(format!(
            "{name}: a config is a dict of tables, got {value}"
        )));
    }
    toml::to_string(&value).map_err(|e| ConfigError::new_err(format!("{name}: {e}")))
}

/// A vehicle: its config (checked as the CLI checks it) and the models it may name.
#[pyclass(module = "hsv._hsv", frozen)]
struct Vehicle {
    loaded: LoadedConfig,
    registry: Registry,
}

#[pymethods]
impl Vehicle {
    /// `path`: a config TOML file; `json_text` (with `name` for messages): a config's tables
    /// as JSON; neither: the embedded sample vehicle.
    #[new]
    #[pyo3(signature = (path=None, json_text=None, name=None))]
    fn new(path: Option<PathBuf>, json_text: Option<&str>, name: Option<&str>) -> PyResult<Self> {
        let registry = builtin()?;
        let name = name.unwrap_or("<dict>");
        let toml_text = json_text.map(|j| toml_of_json(j, name)).transpose()?;
        let (loaded, registry) = match (path, toml_text.as_deref()) {
            (Some(_), Some(_)) => {
                return Err(ConfigError::new_err(
                    "give a config file or a config's text, not both",
                ));
            }
            (None, Some(text)) => hsv_run::commands::load_config_text(text, name, registry),
            (path, None) => hsv_run::commands::load_config(path.as_deref(), registry),
        }
        .map_err(config_error)?;
        Ok(Self { loaded, registry })
    }

    /// The file (or name) the config came from.
    #[getter]
    fn file(&self) -> &str {
        &self.loaded.file
    }

    /// The config's flight condition: (Mach, altitude m).
    #[getter]
    fn flight_condition(&self) -> (f64, f64) {
        (
            self.loaded.config.flight.mach,
            self.loaded.config.flight.altitude_m,
        )
    }

    /// Trim for steady level flight (paper Eq. 2), as the JSON of `hsv-run trim --json`.
    #[pyo3(signature = (rigid=false, mach=None, altitude_m=None))]
    fn trim_json(
        &self,
        py: Python<'_>,
        rigid: bool,
        mach: Option<f64>,
        altitude_m: Option<f64>,
    ) -> PyResult<String> {
        let result = py
            .detach(|| {
                hsv_run::commands::trim::trim_configured(
                    &self.loaded,
                    &self.registry,
                    !rigid,
                    mach,
                    altitude_m,
                    None,
                )
            })
            .map_err(hsv_error)?;
        let model = if rigid { "rigid" } else { "flexible" };
        serde_json::to_string(&hsv_run::commands::trim::summary(&result, model)).map_err(hsv_error)
    }

    /// The trimmed flexible vehicle's linear model (paper Eqs. 6-7, central differences, the
    /// `linearize` command's rule): a dict of `A`, `B`, `C`, `D` (numpy), `x0`, `u0`, the state,
    /// input and output names, and the named modes as JSON.
    #[pyo3(signature = (relative=None, absolute=None))]
    fn linearize<'py>(
        &self,
        py: Python<'py>,
        relative: Option<f64>,
        absolute: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let rule = perturbation_rule(relative, absolute)?;
        let (_, _, lin) = py
            .detach(|| {
                hsv_run::analysis::linearize::linearize_configured(
                    &self.loaded,
                    &self.registry,
                    &rule,
                )
            })
            .map_err(hsv_error)?;
        let m = &lin.model;
        let out = PyDict::new(py);
        for (key, matrix) in [("A", &m.a), ("B", &m.b), ("C", &m.c), ("D", &m.d)] {
            out.set_item(key, matrix_to_numpy(py, matrix)?)?;
        }
        out.set_item("x0", m.x0.as_slice().to_vec().into_pyarray(py))?;
        out.set_item("u0", m.u0.as_slice().to_vec().into_pyarray(py))?;
        out.set_item("state_names", m.state_names.clone())?;
        out.set_item("input_names", m.input_names.clone())?;
        out.set_item("output_names", m.output_names.clone())?;
        out.set_item(
            "modes_json",
            serde_json::to_string(&lin.modes).map_err(hsv_error)?,
        )?;
        Ok(out)
    }

    /// `hsv-run aero --json` on this vehicle with the command's `flags` (its `--config` is
    /// this vehicle's): the JSON summary.
    fn aero_json(&self, py: Python<'_>, flags: Vec<String>) -> PyResult<String> {
        use hsv_run::commands::aero::{AeroArgs, evaluate, summary};
        let args: AeroArgs =
            hsv_run::commands::parse_flags("aero", &flags).map_err(config_error)?;
        let report = py
            .detach(|| evaluate(&args, &self.loaded, &self.registry))
            .map_err(hsv_error)?;
        serde_json::to_string(&summary(&report)).map_err(hsv_error)
    }

    /// `hsv-run flutter --json` on this vehicle with the command's `flags` (a flutter map; its
    /// run folder is written as the command writes it): the JSON summary.
    fn flutter_json(&self, py: Python<'_>, flags: Vec<String>) -> PyResult<String> {
        use hsv_run::commands::flutter::{FlutterArgs, map_json};
        let args: FlutterArgs =
            hsv_run::commands::parse_flags("flutter", &flags).map_err(config_error)?;
        let summary = py
            .detach(|| map_json(&args, &self.loaded, &self.registry))
            .map_err(hsv_error)?;
        serde_json::to_string(&summary).map_err(hsv_error)
    }

    /// Linear models over `machs` × `altitudes_m` (`hsv-run linearize --grid`), points side by
    /// side with the GIL released: a dict of the `.npz`'s arrays (`A` of shape (Mach, altitude,
    /// states, states), ..., `ok`, names) and `errors`, the failed points' messages by index.
    #[pyo3(signature = (machs, altitudes_m, relative=None, absolute=None))]
    fn linearize_grid<'py>(
        &self,
        py: Python<'py>,
        machs: Vec<f64>,
        altitudes_m: Vec<f64>,
        relative: Option<f64>,
        absolute: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        use hsv_run::analysis::linear_grid::{LinearGridSpec, grid_arrays, linearize_shard};
        use hsv_run::analysis::shards::Shard;
        use hsv_run::npz::NpyData;
        let rule = perturbation_rule(relative, absolute)?;
        let spec = LinearGridSpec::new(&machs, &altitudes_m, rule, None, &self.loaded)
            .map_err(config_error)?;
        let (arrays, errors) = py
            .detach(|| {
                let grid = linearize_shard(&spec, &self.loaded, &self.registry, Shard::ALL, |_| {});
                let errors: Vec<(usize, String)> = (grid.cases.iter())
                    .filter_map(|p| Some((p.index, p.error.clone()?)))
                    .collect();
                grid_arrays(&spec, &grid.cases).map(|arrays| (arrays, errors))
            })
            .map_err(hsv_error)?;
        let out = PyDict::new(py);
        for array in arrays {
            let value = match array.data {
                NpyData::F64(v) => v.into_pyarray(py).reshape(array.shape.clone())?.into_any(),
                NpyData::Bool(v) => v.into_pyarray(py).reshape(array.shape.clone())?.into_any(),
                NpyData::Str(v) => v.into_pyobject(py)?.into_any(),
            };
            out.set_item(array.name, value)?;
        }
        out.set_item(
            "errors",
            errors
                .into_iter()
                .collect::<std::collections::BTreeMap<_, _>>(),
        )?;
        Ok(out)
    }

    /// The config as TOML text.
    fn config_toml(&self) -> PyResult<String> {
        toml::to_string(&self.loaded.raw).map_err(hsv_error)
    }
}

/// The `linearize` perturbation rule with `relative` and `absolute` where given, checked.
fn perturbation_rule(relative: Option<f64>, absolute: Option<f64>) -> PyResult<PerturbationRule> {
    let mut rule = PerturbationRule::default();
    if let Some(r) = relative {
        rule.relative = r;
    }
    if let Some(a) = absolute {
        rule.absolute = a;
    }
    rule.steps(&nalgebra::DVector::zeros(1))
        .map_err(|e| ConfigError::new_err(e.to_string()))?;
    Ok(rule)
}

/// A dense matrix as a C-ordered 2-D numpy array.
fn matrix_to_numpy<'py>(
    py: Python<'py>,
    m: &nalgebra::DMatrix<f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows: Vec<Vec<f64>> = m.row_iter().map(|r| r.iter().copied().collect()).collect();
    PyArray2::from_vec2(py, &rows).map_err(|e| HsvError::new_err(e.to_string()))
}

/// The trimmed vehicle in flight, advanced step by step (`hsv-run simulate`'s loop).
#[pyclass(module = "hsv._hsv", unsendable)]
struct Simulation {
    flight: Flight,
    /// Body modal amplitudes follow the flight-state columns of the outputs.
    body_modes: usize,
}

/// The outputs of `flight` now: the [`Sample`] columns, then the body's modal amplitudes.
fn outputs(flight: &mut Flight) -> PyResult<Vec<f64>> {
    let sample = flight.sample().map_err(hsv_error)?;
    let mut v = sample.values().to_vec();
    v.extend(flight.state.body_modes.q.iter().copied());
    Ok(v)
}

#[pymethods]
impl Simulation {
    /// Trims `vehicle` at its flight condition and starts the flight there. `controller`: a
    /// registered controller's name (`schedule`, `lqr`, ...) or None for the host's commands
    /// (`step(u)`), held from the trim commands. `disturbances_json`: a `[disturbances]` table
    /// as JSON in place of the config's (None: the config's).
    #[new]
    #[pyo3(signature = (vehicle, dt_s=0.001, controller=None, heating=true, monolithic=false, lumped_surface_mass=false, disturbances_json=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        vehicle: &Vehicle,
        dt_s: f64,
        controller: Option<String>,
        heating: bool,
        monolithic: bool,
        lumped_surface_mass: bool,
        disturbances_json: Option<&str>,
    ) -> PyResult<Self> {
        let disturbances = disturbances_json
            .map(|text| {
                let table = toml_of_json(text, "disturbances")?;
                let table: toml::Table = toml::from_str(&table).map_err(config_error)?;
                hsv_core::config::parse_table(&table, "<disturbances>", "disturbances")
                    .map_err(config_error)
            })
            .transpose()?;
        let options = FlightOptions {
            model: if monolithic {
                SurfaceModel::Monolithic {
                    lumped_mass: lumped_surface_mass,
                }
            } else {
                SurfaceModel::Partitioned
            },
            heated: heating,
            controller,
            dt_s,
            disturbances,
        };
        let flight = py
            .detach(|| Flight::trimmed(&vehicle.loaded, &vehicle.registry, &options, |_| {}))
            .map_err(hsv_error)?;
        let body_modes = flight.state.body_modes.q.len();
        Ok(Self { flight, body_modes })
    }

    /// The output names, in the order of `step`'s array (units in the names).
    #[getter]
    fn output_names(&self) -> Vec<String> {
        Sample::COLUMNS
            .iter()
            .map(|s| s.to_string())
            .chain((0..self.body_modes).map(|k| format!("body_mode_{}_q", k + 1)))
            .collect()
    }

    /// The command names of `step(u)`'s `u`.
    #[getter]
    fn input_names(&self) -> Vec<&'static str> {
        vec![
            "elevon_deg",
            "differential_elevon_deg",
            "fuel_equivalence_ratio",
        ]
    }

    /// The flight time, s.
    #[getter]
    fn time_s(&self) -> f64 {
        self.flight.time_s()
    }

    /// The aeroelastic step, s.
    #[getter]
    fn dt_s(&self) -> f64 {
        self.flight.dt_s
    }

    /// The controller flying the vehicle (`external`: the host's commands).
    #[getter]
    fn controller(&self) -> &str {
        &self.flight.controller_name
    }

    /// The trim the flight started from: (α deg, elevon deg, φ, flight-path angle deg; a
    /// vehicle without an engine glides: φ 0, γ < 0).
    #[getter]
    fn trim(&self) -> (f64, f64, f64, f64) {
        let t = &self.flight.trim.result.trim;
        (
            t.alpha_deg,
            t.elevon_deg,
            t.fuel_equivalence_ratio,
            t.flight_path_angle_deg,
        )
    }

    /// The vehicle state as a vector (position NED, attitude quaternion, body velocities and
    /// rates, then the modal coordinates and rates), with `state_names`.
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let layout = self
            .flight
            .vehicle
            .dynamics()
            .layout(AttitudeCoordinates::Quaternion);
        let mut x = nalgebra::DVector::zeros(layout.len());
        layout.pack(&self.flight.state, &mut x).map_err(hsv_error)?;
        Ok(x.as_slice().to_vec().into_pyarray(py))
    }

    /// The vehicle state as the JSON `restart.json` stores it (`state`): rigid body, body and
    /// surface modal coordinates, every float round-tripping exactly.
    fn state_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.flight.state).map_err(hsv_error)
    }

    /// The names of `state`'s entries.
    #[getter]
    fn state_names(&self) -> Vec<String> {
        self.flight
            .vehicle
            .dynamics()
            .layout(AttitudeCoordinates::Quaternion)
            .names()
    }

    /// The outputs now.
    fn outputs<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(outputs(&mut self.flight)?.into_pyarray(py))
    }

    /// Back to the trimmed flight at t = 0 (no new trim); the outputs there.
    fn reset<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.flight.reset().map_err(hsv_error)?;
        self.outputs(py)
    }

    /// Everything the next step depends on (the flight's `RunState`: steps taken, vehicle
    /// state, coupling guesses, thermal states, the regions' publications, the control loop)
    /// as JSON whose floats round-trip exactly.
    fn run_state_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.flight.run_state()).map_err(hsv_error)
    }

    /// Back to a state of `run_state_json` (of this flight, or one built alike); the outputs
    /// there. The steps after it repeat those after it was taken, bit for bit.
    fn restore_json<'py>(
        &mut self,
        py: Python<'py>,
        text: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let run: hsv_run::analysis::flight::RunState = serde_json::from_str(text)
            .map_err(|e| hsv_error(anyhow::anyhow!("not a run state of this package: {e}")))?;
        self.flight.restore(&run).map_err(hsv_error)?;
        self.outputs(py)
    }

    /// `n` steps with the commands `u` (elevon deg, differential elevon deg, φ; absolute, held
    /// from now on; None keeps the last); the outputs at the end.
    #[pyo3(signature = (u=None, n=1))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        u: Option<[f64; 3]>,
        n: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        if let Some(u) = u {
            self.flight
                .command(ControlCommands {
                    symmetric_elevon_rad: u[0].to_radians(),
                    differential_elevon_rad: u[1].to_radians(),
                    fuel_equivalence_ratio: u[2],
                })
                .map_err(hsv_error)?;
        }
        let flight = &mut self.flight;
        py.detach(|| flight.advance(n)).map_err(hsv_error)?;
        self.outputs(py)
    }

    /// Flies `duration_s` under the flight's controller (the host's last commands held), an
    /// output row every `record_every` steps and at the start and end: a 2-D array, one row
    /// per sample, columns `output_names`.
    #[pyo3(signature = (duration_s, record_every=1))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        duration_s: f64,
        record_every: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let plan = hsv_run::steps::time_steps(duration_s, self.flight.dt_s)
            .map_err(|e| HsvError::new_err(format!("duration_s {duration_s}: {e}")))?;
        if plan.last_step_shortened() {
            return Err(HsvError::new_err(format!(
                "duration_s {duration_s} is not a whole number of steps of {} s",
                self.flight.dt_s
            )));
        }
        let every = record_every.max(1);
        let flight = &mut self.flight;
        let rows = py.detach(|| {
            let mut rows = vec![outputs(flight)?];
            let mut done = 0;
            while done < plan.steps {
                let n = every.min(plan.steps - done);
                flight.advance(n).map_err(hsv_error)?;
                done += n;
                rows.push(outputs(flight)?);
            }
            Ok::<_, PyErr>(rows)
        })?;
        PyArray2::from_vec2(py, &rows).map_err(|e| HsvError::new_err(e.to_string()))
    }
}

/// The native module.
#[pymodule]
fn _hsv(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("HsvError", m.py().get_type::<HsvError>())?;
    m.add("ConfigError", m.py().get_type::<ConfigError>())?;
    m.add_function(wrap_pyfunction!(models_json, m)?)?;
    m.add_function(wrap_pyfunction!(sample_config_json, m)?)?;
    m.add_class::<Vehicle>()?;
    m.add_class::<Simulation>()?;
    Ok(())
}
