//! The vehicle config file: its types, loading, and errors that name the file and key path (one
//! file: the tables, their parse and the checks across tables are read together; the tests at
//! its end, about a fifth of it, exercise them on the embedded sample).
//!
//! Every table is `deny_unknown_fields`, so a misspelt key is an error that names the key path
//! and the allowed keys, never a silently ignored setting.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::aero::ReferenceValues;
use crate::gas::PerfectGas;
use crate::geometry::{
    GeometryConfig, LiftingSurfaceConfig, Side, VehicleGeometry, VerticalFinConfig, body_mesh,
    build_vehicle, lifting_surface_mesh, vertical_fin_mesh,
};
use crate::mesh::{PanelMesh, RegionKind};
use crate::region::{ModelSettings, RegionGeometry, RegionInfo, merge_tables};

/// The sample vehicle config, embedded in every binary.
pub const SAMPLE_CONFIG_TOML: &str = include_str!("../../configs/sample-hsv.toml");

/// Name under which the embedded sample config is reported in messages.
pub const EMBEDDED_CONFIG_NAME: &str = "<embedded configs/sample-hsv.toml>";

use crate::settings::first_line;
pub use crate::settings::{ConfigError, parse_table};

/// The flight condition a command starts from.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlightConfig {
    pub mach: f64,
    /// Geometric altitude, m.
    pub altitude_m: f64,
    #[serde(default)]
    pub alpha_deg: f64,
    #[serde(default)]
    pub beta_deg: f64,
}

/// How the regions' interfaces are closed (`[coupling]`, typed; preCICE's idea of a coupling
/// scheme chosen in configuration).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CouplingSchemeName {
    /// The body-surface fixed point converged inside every Runge-Kutta stage (`tolerance`):
    /// the monolithic solution of the partitioned equations.
    #[default]
    Implicit,
    /// The paper's scheme (§III, Table 3): the regions exchange their interface data once per
    /// aeroelastic step, each marching its own equations over the step with the other's data
    /// from the previous sub-iteration, sub-iterated until the interface displacements change
    /// by less than `residual_tolerance_m`.
    Staggered,
}

/// How a coupling fixed point is accelerated ([`crate::acceleration`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AccelerationName {
    /// Aitken's Δ² relaxation, from `relaxation`, clamped to `relaxation_bounds`.
    #[default]
    Aitken,
    /// A constant relaxation factor `relaxation`.
    Constant,
}

/// `[simulation]`: how every flight (`simulate`, `compare`, trade studies, Python, the FMU)
/// runs (its rates, integrator and Earth) and what it flies (its input tables). Keys are checked
/// here; values (ranges, names) by the runner, which knows the integrators and Earth models.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimulationConfig {
    /// Tables of offsets from trim by time (`symmetric_elevon_deg`, `differential_elevon_deg`,
    /// `fuel_equivalence_ratio`: `time_s`, `value`); absent: the paper's elevon doublet.
    pub inputs: Option<toml::Table>,
    /// `flat` (the paper's, the default), `spherical` or `spherical-rotating`.
    pub earth: Option<String>,
    /// Latitude the flight starts at over a spherical Earth, deg (default 0).
    pub latitude_deg: Option<f64>,
    /// Conduction step, s (paper Table 3: heat transfer 1 ms).
    pub heat_transfer_dt_s: Option<f64>,
    /// Heat-flux interval, s (paper Table 3: aerothermal 10 ms).
    pub aerothermal_dt_s: Option<f64>,
    /// Interval between stiffness updates from the temperature field, s.
    pub stiffness_interval_s: Option<f64>,
    /// The surfaces' uniform starting temperature, K (paper: 293 K).
    pub initial_temperature_k: Option<f64>,
    /// How often the main body region is evaluated, s (0: at every Runge-Kutta stage).
    pub body_loads_dt_s: Option<f64>,
    /// How often the body's skin friction is evaluated again, s (0: at every evaluation).
    pub body_friction_dt_s: Option<f64>,
    /// How often the lifting surfaces' aero is evaluated, s (0, the default: at every
    /// Runge-Kutta stage).
    pub surface_loads_dt_s: Option<f64>,
    /// `exponential-rk4` (the default) or `rk4`.
    pub integrator: Option<String>,
}

/// `[coupling]`: the scheme and its tolerances.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CouplingConfig {
    pub scheme: CouplingSchemeName,
    /// Implicit scheme: relative change of the root loads (and of the body's modal
    /// accelerations per 1 g at a pivot) below which a stage's fixed point has converged.
    pub tolerance: f64,
    /// Implicit scheme: fixed-point iterations allowed per stage.
    pub max_iterations: usize,
    /// Staggered scheme: change of the interface displacements (the body's elastic motion at
    /// each pivot, the surfaces' deflection) between sub-iterations below which a step has
    /// converged, m (paper Table 3: R_tol = 1e-5 m).
    pub residual_tolerance_m: f64,
    /// Staggered scheme: sub-iterations allowed per step.
    pub max_sub_iterations: usize,
    /// How both schemes' fixed points are accelerated.
    pub acceleration: AccelerationName,
    /// The relaxation factor: Aitken's first, or the constant one.
    pub relaxation: f64,
    /// Aitken's clamp on its factor (lower, upper).
    pub relaxation_bounds: [f64; 2],
}

impl Default for CouplingConfig {
    fn default() -> Self {
        Self {
            scheme: CouplingSchemeName::Implicit,
            tolerance: 1e-8,
            max_iterations: 50,
            residual_tolerance_m: 1e-5,
            max_sub_iterations: 30,
            acceleration: AccelerationName::Aitken,
            relaxation: 1.0,
            relaxation_bounds: [0.05, 1.5],
        }
    }
}

/// Model names for one region, and its overrides of model settings; absent roles are not
/// modelled in that region.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionModels {
    pub aero: Option<String>,
    pub heat_flux: Option<String>,
    pub conduction: Option<String>,
    pub structure: Option<String>,
    pub propulsion: Option<String>,
    /// Skin friction on the region's panels in trim and simulation (default: on), from the
    /// wall shear of its heat-flux model (`eckert` when it names none).
    pub skin_friction: Option<bool>,
    /// `[regions.<region>.models.<name>]`: keys that override `[models.<name>]` in this region.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub models: BTreeMap<String, toml::Table>,
}

impl RegionModels {
    /// The model each role key names: (key, role, name), in the table's key order.
    pub fn named(&self) -> [(&'static str, crate::role::Role, Option<&str>); 5] {
        let names = [
            &self.aero,
            &self.heat_flux,
            &self.conduction,
            &self.structure,
            &self.propulsion,
        ];
        std::array::from_fn(|k| {
            (
                REGION_ROLE_KEYS[k].0,
                REGION_ROLE_KEYS[k].1,
                names[k].as_deref(),
            )
        })
    }

    /// `self` with every name and setting `over` gives replacing ours.
    fn overlaid(&self, over: &RegionModels) -> RegionModels {
        let pick = |a: &Option<String>, b: &Option<String>| b.clone().or_else(|| a.clone());
        let mut models = self.models.clone();
        for (name, table) in &over.models {
            merge_tables(models.entry(name.clone()).or_default(), table);
        }
        RegionModels {
            aero: pick(&self.aero, &over.aero),
            heat_flux: pick(&self.heat_flux, &over.heat_flux),
            conduction: pick(&self.conduction, &over.conduction),
            structure: pick(&self.structure, &over.structure),
            propulsion: pick(&self.propulsion, &over.propulsion),
            skin_friction: over.skin_friction.or(self.skin_friction),
            models,
        }
    }
}

/// Which models each region of the vehicle runs. `lifting_surfaces` applies to both surfaces;
/// `left_surface` and `right_surface` override it for one side.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionsConfig {
    #[serde(default)]
    pub main_body: RegionModels,
    #[serde(default)]
    pub lifting_surfaces: RegionModels,
    #[serde(default)]
    pub left_surface: RegionModels,
    #[serde(default)]
    pub right_surface: RegionModels,
    /// Absent (no `[regions.propulsion]` table): the vehicle has no engine and glides; its
    /// aero models then load the engine's ramp and nozzle as outer surfaces.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub propulsion: Option<RegionModels>,
    /// Present (`[regions.vertical_fin]`, with the `[vertical_fin]` planform): the vehicle has a
    /// fixed vertical fin, a region of its own; absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_fin: Option<RegionModels>,
}

/// The regions of the vehicle, in assembly order.
pub const REGION_NAMES: [&str; 5] = [
    "main_body",
    "left_surface",
    "right_surface",
    "propulsion",
    "vertical_fin",
];

impl RegionsConfig {
    /// Whether the vehicle has region `name`: the body and the lifting surfaces always; the
    /// propulsion region and the vertical fin when the config has their tables.
    pub fn has(&self, name: &str) -> bool {
        match name {
            "propulsion" => self.propulsion.is_some(),
            "vertical_fin" => self.vertical_fin.is_some(),
            _ => true,
        }
    }

    /// The models of region `name` (one of [`REGION_NAMES`]), overrides applied; `None` for
    /// an unknown name or a region the vehicle does not have.
    pub fn region(&self, name: &str) -> Option<RegionModels> {
        match name {
            "main_body" => Some(self.main_body.clone()),
            "left_surface" => Some(self.lifting_surfaces.overlaid(&self.left_surface)),
            "right_surface" => Some(self.lifting_surfaces.overlaid(&self.right_surface)),
            "propulsion" => self.propulsion.clone(),
            "vertical_fin" => self.vertical_fin.clone(),
            _ => None,
        }
    }

    /// The config table that holds region `name`'s overrides of model `model`, most specific
    /// first, for messages.
    fn override_path(&self, region: &str, model: &str) -> Option<String> {
        let own = match region {
            "main_body" => &self.main_body,
            "left_surface" => &self.left_surface,
            "right_surface" => &self.right_surface,
            "propulsion" => self.propulsion.as_ref()?,
            "vertical_fin" => self.vertical_fin.as_ref()?,
            _ => return None,
        };
        if own.models.contains_key(model) {
            return Some(format!("regions.{region}.models.{model}"));
        }
        let shared = matches!(region, "left_surface" | "right_surface")
            && self.lifting_surfaces.models.contains_key(model);
        shared.then(|| format!("regions.lifting_surfaces.models.{model}"))
    }
}

/// The whole vehicle config.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HsvConfig {
    pub flight: FlightConfig,
    pub reference: ReferenceValues,
    #[serde(default)]
    pub gas: PerfectGas,
    pub geometry: GeometryConfig,
    pub lifting_surface: LiftingSurfaceConfig,
    /// `[vertical_fin]`: the planform of the vertical fin region (`[regions.vertical_fin]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_fin: Option<VerticalFinConfig>,
    #[serde(default)]
    pub regions: RegionsConfig,
    /// Per-model settings, `[models.<name>]`; checked by each model's constructor.
    #[serde(default)]
    pub models: BTreeMap<String, toml::Table>,
    /// Dylib plugins to load before models are looked up.
    #[serde(default)]
    pub plugins: Vec<PathBuf>,
    /// `[simulation]`: how a flight runs and what it flies.
    #[serde(default)]
    pub simulation: SimulationConfig,
    /// `[coupling]`: how the body-surface interfaces are closed.
    #[serde(default)]
    pub coupling: CouplingConfig,
    /// `[control]`: the controller flying `hsv-run simulate` (its name, sample rate, actuators),
    /// checked by the runner; the controller's own settings are `[models.<name>]`.
    #[serde(default)]
    pub control: toml::Table,
    /// `[trade]`: the fidelity trade study of `hsv-run trade` (job, varied models), checked by
    /// the runner.
    #[serde(default)]
    pub trade: toml::Table,
    /// `[disturbances]`: Dryden turbulence and discrete gusts every flight flies through,
    /// checked by the runner.
    #[serde(default)]
    pub disturbances: toml::Table,
}

/// A parsed config together with its raw table (for model constructors) and its origin.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedConfig {
    pub config: HsvConfig,
    pub raw: toml::Table,
    /// The file name used in messages.
    pub file: String,
}

impl LoadedConfig {
    /// The embedded sample vehicle.
    pub fn sample() -> Result<Self, ConfigError> {
        parse_config(SAMPLE_CONFIG_TOML, EMBEDDED_CONFIG_NAME)
    }

    /// The config at `path`, or the embedded sample when `path` is `None`.
    pub fn load(path: Option<&Path>) -> Result<Self, ConfigError> {
        match path {
            None => Self::sample(),
            Some(path) => {
                let file = path.display().to_string();
                let text = std::fs::read_to_string(path).map_err(|e| ConfigError {
                    file: file.clone(),
                    key_path: String::new(),
                    message: format!("cannot read: {e}"),
                })?;
                parse_config(&text, &file)
            }
        }
    }

    /// Settings table of model `name` (`[models.<name>]`), empty if absent.
    pub fn model_settings(&self, name: &str) -> &toml::Table {
        static EMPTY: std::sync::OnceLock<toml::Table> = std::sync::OnceLock::new();
        self.config
            .models
            .get(name)
            .unwrap_or_else(|| EMPTY.get_or_init(toml::Table::new))
    }

    /// The body and both lifting-surface meshes.
    pub fn vehicle(&self) -> Result<VehicleGeometry, ConfigError> {
        build_vehicle(&self.config.geometry, &self.config.lifting_surface).map_err(|e| {
            ConfigError {
                file: self.file.clone(),
                key_path: String::new(),
                message: format!("building the vehicle geometry: {e}"),
            }
        })
    }

    /// A region around an arbitrary `mesh` (the whole vehicle, an STL file) that sees the global
    /// `[models.*]` settings.
    pub fn mesh_region(&self, name: &str, mesh: PanelMesh) -> RegionInfo {
        let mut region = RegionInfo::standalone(
            name,
            mesh,
            self.config.reference,
            self.config.gas,
            &self.file,
        );
        for (model, table) in &self.config.models {
            region.settings.insert(
                model.clone(),
                ModelSettings {
                    table: table.clone(),
                    key_path: format!("models.{model}"),
                },
            );
        }
        region
    }

    /// Region `name` (one of [`REGION_NAMES`]) as its models see it: kind, side, geometry,
    /// undeformed mesh and every model's settings with the region's overrides applied.
    pub fn region(&self, name: &str) -> Result<RegionInfo, ConfigError> {
        let c = &self.config;
        let Some(models) = c.regions.region(name) else {
            let message = if REGION_NAMES.contains(&name) {
                format!(
                    "the vehicle has no {name} region (the config has no `[regions.{name}]` table)"
                )
            } else {
                format!(
                    "unknown region; the regions are {}",
                    REGION_NAMES.join(", ")
                )
            };
            return Err(ConfigError {
                file: self.file.clone(),
                key_path: format!("regions.{name}"),
                message,
            });
        };
        let mesh_error = |e: crate::geometry::VehicleError| ConfigError {
            file: self.file.clone(),
            key_path: String::new(),
            message: format!("building the {name} mesh: {e}"),
        };
        let (kind, side, geometry, mesh) = match name {
            "left_surface" | "right_surface" => {
                let side = if name == "left_surface" {
                    Side::Left
                } else {
                    Side::Right
                };
                let mesh = lifting_surface_mesh(&c.lifting_surface, side).map_err(mesh_error)?;
                let geometry = RegionGeometry::LiftingSurface {
                    planform: c.lifting_surface.clone(),
                    side,
                };
                (RegionKind::LiftingSurface, Some(side), geometry, mesh)
            }
            "vertical_fin" => {
                let fin = c.vertical_fin.as_ref().ok_or_else(|| ConfigError {
                    file: self.file.clone(),
                    key_path: "vertical_fin".to_owned(),
                    message: "the vertical_fin region needs its planform: a `[vertical_fin]` \
                              table"
                        .to_owned(),
                })?;
                let mesh = vertical_fin_mesh(fin).map_err(mesh_error)?;
                let geometry = RegionGeometry::VerticalFin(fin.clone());
                (RegionKind::LiftingSurface, None, geometry, mesh)
            }
            _ => {
                let kind = if name == "propulsion" {
                    RegionKind::Propulsion
                } else {
                    RegionKind::MainBody
                };
                let mesh = body_mesh(&c.geometry).map_err(mesh_error)?;
                (kind, None, RegionGeometry::Body(c.geometry.clone()), mesh)
            }
        };
        let mut settings = BTreeMap::new();
        let named = c.models.keys().chain(models.models.keys());
        for model in named {
            let mut table = c.models.get(model).cloned().unwrap_or_default();
            if let Some(over) = models.models.get(model) {
                merge_tables(&mut table, over);
            }
            let key_path = c
                .regions
                .override_path(name, model)
                .unwrap_or_else(|| format!("models.{model}"));
            settings.insert(model.clone(), ModelSettings { table, key_path });
        }
        Ok(RegionInfo {
            name: name.to_owned(),
            kind,
            side,
            geometry,
            mesh,
            reference: c.reference,
            gas: c.gas,
            file: self.file.clone(),
            settings,
        })
    }
}

/// Parses config text; `file` names it in errors.
pub fn parse_config(text: &str, file: &str) -> Result<LoadedConfig, ConfigError> {
    let raw: toml::Table = toml::from_str(text).map_err(|e| {
        let place = e.span().map_or_else(String::new, |span| {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
            format!(" at line {line}, column {column}")
        });
        ConfigError {
            file: file.to_owned(),
            key_path: String::new(),
            message: format!("not valid TOML{place}: {}", first_line(e.message())),
        }
    })?;
    check_finite(&raw, file, "")?;
    let config: HsvConfig = parse_table(&raw, file, "")?;
    check_values(&config, file)?;
    Ok(LoadedConfig {
        config,
        raw,
        file: file.to_owned(),
    })
}

/// Every number in `table` (found at `key_path`) is finite: TOML allows `nan` and `inf`, which
/// no setting means; the first one found is an error at its key path.
fn check_finite(table: &toml::Table, file: &str, key_path: &str) -> Result<(), ConfigError> {
    fn walk(value: &toml::Value, path: &str, file: &str) -> Result<(), ConfigError> {
        match value {
            toml::Value::Float(x) if !x.is_finite() => Err(ConfigError {
                file: file.to_owned(),
                key_path: path.to_owned(),
                message: format!("must be a finite number, got {x}"),
            }),
            toml::Value::Table(table) => check_finite(table, file, path),
            toml::Value::Array(items) => items
                .iter()
                .enumerate()
                .try_for_each(|(i, item)| walk(item, &format!("{path}[{i}]"), file)),
            _ => Ok(()),
        }
    }
    table.iter().try_for_each(|(key, value)| {
        let path = if key_path.is_empty() {
            key.clone()
        } else {
            format!("{key_path}.{key}")
        };
        walk(value, &path, file)
    })
}

/// Checks the values every command relies on: a positive flight Mach number and altitude in the
/// standard atmosphere, positive reference area, length and span (they divide the coefficients).
fn check_values(config: &HsvConfig, file: &str) -> Result<(), ConfigError> {
    use crate::atmosphere::{MAX_ALTITUDE_M, MIN_ALTITUDE_M};
    let error = |key_path: &str, message: String| ConfigError {
        file: file.to_owned(),
        key_path: key_path.to_owned(),
        message,
    };
    let flight = &config.flight;
    if flight.mach <= 0.0 {
        return Err(error(
            "flight.mach",
            format!("must be a positive Mach number, got {}", flight.mach),
        ));
    }
    if !(MIN_ALTITUDE_M..=MAX_ALTITUDE_M).contains(&flight.altitude_m) {
        return Err(error(
            "flight.altitude_m",
            format!(
                "{} m is outside the standard atmosphere ({MIN_ALTITUDE_M} to {MAX_ALTITUDE_M} m)",
                flight.altitude_m
            ),
        ));
    }
    for (key, value) in [
        ("flight.alpha_deg", flight.alpha_deg),
        ("flight.beta_deg", flight.beta_deg),
    ] {
        flow_angle_deg(value).map_err(|message| error(key, message))?;
    }
    let coupling = &config.coupling;
    for (key, value) in [
        ("coupling.tolerance", coupling.tolerance),
        (
            "coupling.residual_tolerance_m",
            coupling.residual_tolerance_m,
        ),
    ] {
        if value <= 0.0 {
            return Err(error(
                key,
                format!("must be a positive tolerance, got {value}"),
            ));
        }
    }
    let [low, high] = coupling.relaxation_bounds;
    if !(coupling.relaxation > 0.0 && low > 0.0 && low <= high) {
        return Err(error(
            "coupling.relaxation",
            format!(
                "relaxation = {} and relaxation_bounds = [{low}, {high}]: need a positive \
                 factor and 0 < lower <= upper",
                coupling.relaxation
            ),
        ));
    }
    for (key, value) in [
        ("coupling.max_iterations", coupling.max_iterations),
        ("coupling.max_sub_iterations", coupling.max_sub_iterations),
    ] {
        if value == 0 {
            return Err(error(key, "must be at least 1".to_owned()));
        }
    }
    // The fin's planform and its region come together: one without the other is a typing slip.
    match (&config.vertical_fin, &config.regions.vertical_fin) {
        (Some(_), None) => {
            return Err(error(
                "vertical_fin",
                "a fin planform without its region: add `[regions.vertical_fin]` with the fin's \
                 aero model (or remove the table)"
                    .to_owned(),
            ));
        }
        (None, Some(_)) => {
            return Err(error(
                "regions.vertical_fin",
                "the vertical_fin region needs its planform: a `[vertical_fin]` table".to_owned(),
            ));
        }
        _ => {}
    }
    let reference = &config.reference;
    for (key, value, what) in [
        ("reference.area_m2", reference.area_m2, "reference area, m²"),
        (
            "reference.chord_m",
            reference.chord_m,
            "reference length, m",
        ),
        ("reference.span_m", reference.span_m, "reference span, m"),
    ] {
        if value <= 0.0 {
            return Err(error(
                key,
                format!("the {what}, must be positive (it divides the coefficients), got {value}"),
            ));
        }
    }
    Ok(())
}

/// The config key of each model-name field of a region table, with the role it names.
const REGION_ROLE_KEYS: [(&str, crate::role::Role); 5] = [
    ("aero", crate::role::Role::Aero),
    ("heat_flux", crate::role::Role::HeatFlux),
    ("conduction", crate::role::Role::Conduction),
    ("structure", crate::role::Role::Structure),
    ("propulsion", crate::role::Role::Propulsion),
];

/// Largest magnitude of a flow angle (α, β), deg: an angle is one turn at most, so 720° is a
/// typing error, not 0°.
pub const MAX_FLOW_ANGLE_DEG: f64 = 180.0;

/// `value_deg` if it is a finite flow angle within ±[`MAX_FLOW_ANGLE_DEG`], else what is wrong.
pub fn flow_angle_deg(value_deg: f64) -> Result<f64, String> {
    if value_deg.is_finite() && value_deg.abs() <= MAX_FLOW_ANGLE_DEG {
        Ok(value_deg)
    } else {
        Err(format!(
            "must be a finite angle from -{MAX_FLOW_ANGLE_DEG} to {MAX_FLOW_ANGLE_DEG} deg, got {value_deg}"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coupling_table_is_typed_with_clear_errors() {
        let sample = parse_config(SAMPLE_CONFIG_TOML, "s.toml").expect("sample");
        assert_eq!(sample.config.coupling, CouplingConfig::default());
        // The sample's own [coupling] table is its last: replaced by the one under test.
        let base = &SAMPLE_CONFIG_TOML[..SAMPLE_CONFIG_TOML
            .find("\n[coupling]")
            .expect("the sample has a [coupling] table")];
        let with = |table: &str| format!("{base}\n[coupling]\n{table}\n");
        let staggered = parse_config(
            &with("scheme = \"staggered\"\nresidual_tolerance_m = 1e-6"),
            "s.toml",
        )
        .expect("staggered");
        assert_eq!(
            staggered.config.coupling.scheme,
            CouplingSchemeName::Staggered
        );
        assert_eq!(staggered.config.coupling.residual_tolerance_m, 1e-6);
        for (table, needles) in [
            (
                "scheme = \"loose\"",
                &["coupling.scheme", "implicit", "staggered"][..],
            ),
            (
                "residual_tolerance_m = -1.0",
                &["coupling.residual_tolerance_m", "positive"],
            ),
            (
                "max_sub_iterations = 0",
                &["coupling.max_sub_iterations", "at least 1"],
            ),
            ("tolerence = 1e-8", &["coupling.tolerence"]),
            (
                "acceleration = \"iqn-ils\"",
                &["coupling.acceleration", "aitken", "constant"],
            ),
            (
                "relaxation_bounds = [1.0, 0.5]",
                &["coupling.relaxation", "lower <= upper"],
            ),
        ] {
            let err = parse_config(&with(table), "my.toml")
                .unwrap_err()
                .to_string();
            for needle in needles.iter().chain(&["my.toml"]) {
                assert!(err.contains(needle), "{table}: `{needle}` not in {err}");
            }
        }
    }

    #[test]
    fn unknown_and_missing_keys_are_errors_naming_the_key() {
        let text = SAMPLE_CONFIG_TOML.replace("width_m = 3.0", "widht_m = 3.0");
        let err = parse_config(&text, "my.toml").unwrap_err().to_string();
        assert!(
            err.contains("my.toml") && err.contains("geometry.widht_m"),
            "{err}"
        );
        let text = SAMPLE_CONFIG_TOML.replace("[lifting_surface]", "[lifting_surfaces]");
        let err = parse_config(&text, "my.toml").unwrap_err().to_string();
        assert!(err.contains("lifting_surface"), "{err}");
    }

    /// The sample's commented fin block, uncommented (as its comment says to).
    fn sample_with_fin() -> String {
        let mut inside = false;
        let mut out = String::new();
        for line in SAMPLE_CONFIG_TOML.lines() {
            inside = (inside || line.starts_with("# >>> vertical fin"))
                && !line.starts_with("# <<< vertical fin");
            let commented_toml = inside && line.starts_with('#') && !line.starts_with("# ");
            out.push_str(if commented_toml { &line[1..] } else { line });
            out.push('\n');
        }
        out
    }

    #[test]
    fn the_vertical_fin_is_a_region_by_configuration_alone() {
        let sample = parse_config(SAMPLE_CONFIG_TOML, "s.toml").expect("sample");
        assert!(!sample.config.regions.has("vertical_fin"));
        let fin = parse_config(&sample_with_fin(), "fin.toml").expect("with the fin");
        assert!(fin.config.regions.has("vertical_fin"));
        let region = fin.region("vertical_fin").expect("the fin region");
        assert!(matches!(region.geometry, RegionGeometry::VerticalFin(_)));
        assert_eq!(region.side, None);
        // The planform without its region, and the region without its planform, are refused
        // naming the missing table.
        let text = sample_with_fin();
        let header = text.find("\n[regions.vertical_fin]\n").expect("the region");
        let aero_line = header + "\n[regions.vertical_fin]\n".len();
        let after = aero_line + text[aero_line..].find('\n').expect("its aero line");
        let planform_only = format!("{}{}", &text[..header], &text[after..]);
        let err = parse_config(&planform_only, "fin.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("fin.toml") && err.contains("vertical_fin") && err.contains("[regions"),
            "{err}"
        );
        let start = text.find("\n[vertical_fin]\n").expect("the table");
        let end = start + text[start..].find("\n\n").expect("a blank line after it");
        let region_only = format!("{}{}", &text[..start], &text[end..]);
        let err = parse_config(&region_only, "fin.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("regions.vertical_fin") && err.contains("[vertical_fin]"),
            "{err}"
        );
    }

    #[test]
    fn simulation_keys_are_typed_and_unknown_ones_refused_at_load() {
        // Issue 25 item 3: `[simulation]` is read like every other table, so a misspelt key
        // fails at load (for every command, not only when a flight starts), naming its path
        // and the keys allowed; whole numbers are accepted for seconds and kelvins.
        let with = |table: &str| format!("{SAMPLE_CONFIG_TOML}\n[simulation]\n{table}\n");
        let err = parse_config(&with("body_load_dt_s = 0.002"), "my.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("my.toml")
                && err.contains("simulation.body_load_dt_s")
                && err.contains("body_loads_dt_s"),
            "{err}"
        );
        let err = parse_config(&with("heat_transfer_dt_s = \"1 ms\""), "my.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("simulation.heat_transfer_dt_s"), "{err}");
        let loaded = parse_config(
            &with("initial_temperature_k = 700\nintegrator = \"rk4\""),
            "my.toml",
        )
        .expect("config");
        let simulation = &loaded.config.simulation;
        assert_eq!(simulation.initial_temperature_k, Some(700.0));
        assert_eq!(simulation.integrator.as_deref(), Some("rk4"));
        assert_eq!(simulation.inputs, None);
    }

    #[test]
    fn region_settings_override_global_ones_per_side() {
        let text = SAMPLE_CONFIG_TOML.replace(
            "[regions.propulsion]",
            "[regions.left_surface.models.eckert]\nemissivity = 0.5\n\n[regions.propulsion]",
        );
        let loaded = parse_config(&text, "my.toml").expect("config");
        let left = loaded.region("left_surface").expect("left");
        let right = loaded.region("right_surface").expect("right");
        let eckert = left.model_settings("eckert");
        assert_eq!(eckert.table["emissivity"].as_float(), Some(0.5));
        assert_eq!(eckert.key_path, "regions.left_surface.models.eckert");
        // Keys the region does not override keep their global values.
        assert_eq!(
            eckert.table["prandtl_number"],
            loaded.model_settings("eckert")["prandtl_number"]
        );
        let global = right.model_settings("eckert");
        assert_eq!(global.table["emissivity"].as_float(), Some(0.8));
        assert_eq!(global.key_path, "models.eckert");
        assert_eq!(left.side, Some(Side::Left));
        assert!(left.mesh.vertices.iter().all(|v| v.y < 0.0));
        let err = loaded.region("tail").unwrap_err().to_string();
        assert!(
            err.contains("regions.tail") && err.contains("main_body"),
            "{err}"
        );
    }
}
