//! The model registry: every model known by name, from built-in crates (`inventory`) and plugins
//! (one file: the descriptors, the context a constructor receives and the registry that finds them
//! are the one contract a model crate is written against).
//!
//! A model crate registers itself with [`register_model!`](crate::register_model); the binary links it with a
//! `use hsv_model_x as _;` line. [`Registry::builtin`] collects the descriptors, sorts them by
//! name and rejects duplicates; look-ups of unknown names answer with the closest known names.
//! Plugins join through `Registry::load_plugin` (in `plugin.rs`, so this module does not know them).

use std::collections::BTreeMap;
use std::fmt;
use std::sync::Arc;

use serde::de::DeserializeOwned;

use crate::aero::AeroModel;
use crate::control::Controller;
use crate::error::ModelError;
use crate::propulsion::PropulsionModel;
use crate::region::{ModelSettings, RegionInfo};
use crate::structure::StructureModel;
use crate::thermal::{ConductionModel, HeatFluxModel};

pub use crate::role::{Family, Role};

/// What a controller constructor gets: its settings and the operating point.
#[derive(Clone, Copy)]
pub struct ControlContext<'a> {
    /// `[models.<name>]`.
    pub settings: &'a toml::Table,
    /// Dotted key path of `settings`, for messages.
    pub key_path: &'a str,
    /// The config file.
    pub file: &'a str,
    /// The measured outputs at trim.
    pub trim_outputs: &'a crate::control::MeasuredOutputs,
    /// The trim commands.
    pub trim_commands: &'a crate::control::ControlCommands,
    /// The linear design model, built on request.
    pub design: &'a dyn crate::control::DesignSource,
    /// The `[simulation.inputs]`-style schedule of offsets from trim, as its raw table (empty
    /// when the config has none), for controllers that fly one.
    pub schedule: &'a toml::Table,
    /// `[control.commands]`: the reference commands of a tracking controller (tables of
    /// offsets from trim by time) as its raw table, empty when the config has none.
    pub commands: &'a toml::Table,
    pub registry: &'a Registry,
}

impl ControlContext<'_> {
    /// Parses the settings into `T` (`#[serde(deny_unknown_fields)]`), naming file and key.
    pub fn parse_settings<T: DeserializeOwned>(&self) -> Result<T, ModelError> {
        crate::config::parse_table(self.settings, self.file, self.key_path)
            .map_err(ModelError::from)
    }

    /// A settings error at `key` under this controller's table.
    pub fn settings_error(&self, key: &str, message: impl Into<String>) -> ModelError {
        ModelError::settings_at(self.file, self.key_path, key, message)
    }
}

/// A controller constructor.
pub type ControllerConstructor = fn(&ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError>;

/// What a constructor gets: its settings, the region it is built for and the host registry.
///
/// Composite models (a surrogate trained on a base model, a reduced model built from a full one)
/// build their base models through [`ModelContext::registry`], so plugins serve as base models
/// too, and read the base model's settings as the same region sees them with
/// [`ModelContext::settings_for`].
#[derive(Debug, Clone, Copy)]
pub struct ModelContext<'a> {
    /// The model's settings (`[models.<name>]` overlaid by `[regions.<region>.models.<name>]`).
    pub settings: &'a toml::Table,
    /// Dotted key path of `settings` in the config file, for error messages.
    pub key_path: &'a str,
    /// The config file the settings come from.
    pub file: &'a str,
    /// The region the model is built for: name, kind, side, geometry, mesh.
    pub region: &'a RegionInfo,
    /// The host registry (built-in models and loaded plugins).
    pub registry: &'a Registry,
}

impl<'a> ModelContext<'a> {
    /// The context of model `name` in `region`: its settings as the region sees them.
    pub fn new(
        region: &'a RegionInfo,
        registry: &'a Registry,
        settings: &'a ModelSettings,
    ) -> Self {
        Self {
            settings: &settings.table,
            key_path: &settings.key_path,
            file: &region.file,
            region,
            registry,
        }
    }

    /// Parses the settings table into `T`, naming file and full key path on any error.
    ///
    /// `T` should be `#[serde(deny_unknown_fields)]` so misspelt keys are caught.
    pub fn parse_settings<T: DeserializeOwned>(&self) -> Result<T, ModelError> {
        crate::settings::parse_table(self.settings, self.file, self.key_path)
            .map_err(ModelError::from)
    }

    /// Settings of another model (`name`) as this region sees them, for composite models.
    pub fn settings_for(&self, name: &str) -> ModelSettings {
        self.region.model_settings(name)
    }

    /// Builds model `name` of role `M` in the same region with `settings` (from
    /// [`Self::settings_for`], possibly adjusted), through the host registry.
    pub fn build<M: ?Sized + RoleModel>(
        &self,
        name: &str,
        settings: &ModelSettings,
    ) -> Result<Box<M>, RegistryError> {
        self.registry.create::<M>(
            name,
            &ModelContext::new(self.region, self.registry, settings),
        )
    }

    /// Checks model `name` of `role` in the same region with `settings` as building it would
    /// ([`Registry::check`]): how a composite's [`SettingsCheck`] checks its base models.
    pub fn check(
        &self,
        role: Role,
        name: &str,
        settings: &ModelSettings,
    ) -> Result<(), RegistryError> {
        self.registry.check(
            role,
            name,
            &ModelContext::new(self.region, self.registry, settings),
        )
    }

    /// `error` placed in the config: a constructor's out-of-range quantity that is one of the
    /// model's own settings keys becomes a settings error at that key's path, so the message
    /// names file and key whichever way the model phrased it.
    pub fn locate(&self, error: ModelError) -> ModelError {
        match error {
            ModelError::OutOfRange {
                quantity,
                value,
                allowed,
                ..
            } if self.settings.contains_key(&quantity) => self.settings_error(
                &quantity,
                format!("{value} is outside the allowed range ({allowed})"),
            ),
            other => other,
        }
    }

    /// A base model's failure as this model's error: the base model's own error when it has
    /// one (it names its own key path), else a settings error at `key`, the setting that names
    /// the base model (an unknown name, a model of another role).
    pub fn base_model_error(&self, key: &str, error: RegistryError) -> ModelError {
        match error {
            RegistryError::Model(error) => error,
            other => self.settings_error(key, other.to_string()),
        }
    }

    /// A settings error at `key` under this model's table.
    pub fn settings_error(&self, key: &str, message: impl Into<String>) -> ModelError {
        ModelError::settings_at(self.file, self.key_path, key, message)
    }
}

/// A constructor for each role. Built-in models give plain function pointers.
pub type AeroConstructor = fn(&ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError>;
pub type HeatFluxConstructor = fn(&ModelContext<'_>) -> Result<Box<dyn HeatFluxModel>, ModelError>;
pub type ConductionConstructor =
    fn(&ModelContext<'_>) -> Result<Box<dyn ConductionModel>, ModelError>;
pub type StructureConstructor =
    fn(&ModelContext<'_>) -> Result<Box<dyn StructureModel>, ModelError>;
pub type PropulsionConstructor =
    fn(&ModelContext<'_>) -> Result<Box<dyn PropulsionModel>, ModelError>;

/// The constructor of a built-in model; its variant fixes the model's role.
#[derive(Clone, Copy)]
pub enum Constructor {
    Aero(AeroConstructor),
    HeatFlux(HeatFluxConstructor),
    Conduction(ConductionConstructor),
    Structure(StructureConstructor),
    Propulsion(PropulsionConstructor),
    Control(ControllerConstructor),
}

impl Constructor {
    pub fn role(&self) -> Role {
        match self {
            Constructor::Aero(_) => Role::Aero,
            Constructor::HeatFlux(_) => Role::HeatFlux,
            Constructor::Conduction(_) => Role::Conduction,
            Constructor::Structure(_) => Role::Structure,
            Constructor::Propulsion(_) => Role::Propulsion,
            Constructor::Control(_) => Role::Control,
        }
    }
}

/// What a built-in model crate submits with [`register_model!`](crate::register_model).
pub struct ModelDescriptor {
    /// Stable kebab-case name; the user's interface.
    pub name: &'static str,
    /// Crate that registered it (`env!("CARGO_PKG_NAME")`).
    pub origin: &'static str,
    /// Fidelity rank within its role: higher resolves more physics (and usually costs more).
    pub fidelity: u8,
    /// One-line summary.
    pub summary: &'static str,
    /// Settings the model reads from `[models.<name>]`, one `key = default  # meaning` per line.
    pub settings_doc: &'static str,
    pub constructor: Constructor,
}

inventory::collect!(ModelDescriptor);

/// Checks a model's settings in a region as its constructor would, without the costly work the
/// constructor may do on a first run (training a POD basis or a surrogate, identifying a ROM):
/// what `config --check` runs.
pub type SettingsCheck = fn(&ModelContext<'_>) -> Result<(), ModelError>;

/// What a built-in model with a costly constructor submits beside its [`ModelDescriptor`] with
/// [`register_model_check!`](crate::register_model_check); models without one are checked by building them.
pub struct ModelCheck {
    /// The model's registered name.
    pub name: &'static str,
    pub check: SettingsCheck,
}

inventory::collect!(ModelCheck);

/// Registers a built-in model's settings check: `hsv_core::register_model_check!(ModelCheck { .. });`
#[macro_export]
macro_rules! register_model_check {
    ($check:expr) => {
        $crate::inventory::submit! { $check }
    };
}

/// Registers a built-in model: `hsv_core::register_model!(ModelDescriptor { .. });`
#[macro_export]
macro_rules! register_model {
    ($descriptor:expr) => {
        $crate::inventory::submit! { $descriptor }
    };
}

/// A shared constructor: boxed so plugin adapters (closures over a loaded library) fit beside
/// built-in function pointers.
pub type SharedConstructor<M> =
    Arc<dyn Fn(&ModelContext<'_>) -> Result<Box<M>, ModelError> + Send + Sync>;

/// A shared controller constructor (a built-in function or a plugin adapter's closure).
pub type SharedControllerConstructor =
    Arc<dyn Fn(&ControlContext<'_>) -> Result<Box<dyn Controller>, ModelError> + Send + Sync>;

/// Constructors as the registry stores them.
#[derive(Clone)]
pub enum Factory {
    Aero(SharedConstructor<dyn AeroModel>),
    HeatFlux(SharedConstructor<dyn HeatFluxModel>),
    Conduction(SharedConstructor<dyn ConductionModel>),
    Structure(SharedConstructor<dyn StructureModel>),
    Propulsion(SharedConstructor<dyn PropulsionModel>),
    Control(SharedControllerConstructor),
}

impl Factory {
    pub fn role(&self) -> Role {
        match self {
            Factory::Aero(_) => Role::Aero,
            Factory::HeatFlux(_) => Role::HeatFlux,
            Factory::Conduction(_) => Role::Conduction,
            Factory::Structure(_) => Role::Structure,
            Factory::Propulsion(_) => Role::Propulsion,
            Factory::Control(_) => Role::Control,
        }
    }
}

impl From<Constructor> for Factory {
    fn from(constructor: Constructor) -> Self {
        match constructor {
            Constructor::Aero(f) => Factory::Aero(Arc::new(f)),
            Constructor::HeatFlux(f) => Factory::HeatFlux(Arc::new(f)),
            Constructor::Conduction(f) => Factory::Conduction(Arc::new(f)),
            Constructor::Structure(f) => Factory::Structure(Arc::new(f)),
            Constructor::Propulsion(f) => Factory::Propulsion(Arc::new(f)),
            Constructor::Control(f) => Factory::Control(Arc::new(f)),
        }
    }
}

/// Where a registered model comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Origin {
    /// A crate linked into the binary.
    BuiltIn(String),
    /// A dylib plugin loaded from this path.
    Plugin(String),
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::BuiltIn(krate) => write!(f, "built-in ({krate})"),
            Origin::Plugin(path) => write!(f, "plugin ({path})"),
        }
    }
}

/// One registered model.
#[derive(Clone)]
pub struct RegistryEntry {
    pub name: String,
    pub fidelity: u8,
    pub summary: String,
    pub settings_doc: String,
    pub origin: Origin,
    pub factory: Factory,
}

impl RegistryEntry {
    pub fn role(&self) -> Role {
        self.factory.role()
    }
}

impl fmt::Debug for RegistryEntry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RegistryEntry")
            .field("name", &self.name)
            .field("role", &self.role())
            .field("fidelity", &self.fidelity)
            .field("origin", &self.origin)
            .finish()
    }
}

/// Why a registry operation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RegistryError {
    #[error("unknown {role} model `{name}`{hint}")]
    Unknown {
        name: String,
        role: String,
        /// ", did you mean `x`? (known: ...)" or the list of known names.
        hint: String,
    },
    #[error("model `{name}` is a {actual} model, but a {wanted} model is needed here")]
    WrongRole {
        name: String,
        actual: Role,
        wanted: Role,
    },
    #[error("model name `{name}` is registered twice: by {first} and by {second}")]
    Duplicate {
        name: String,
        first: String,
        second: String,
    },
    #[error("model name `{name}` is not kebab-case (lowercase letters, digits and '-')")]
    BadName { name: String },
    #[error(transparent)]
    Model(#[from] ModelError),
}

/// Every model known by name.
#[derive(Clone, Default)]
pub struct Registry {
    entries: BTreeMap<String, RegistryEntry>,
    /// Settings checks of built-in models with costly constructors, by name.
    checks: BTreeMap<String, SettingsCheck>,
}

impl fmt::Debug for Registry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.entries.keys()).finish()
    }
}

fn is_kebab_case(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('-')
        && !name.ends_with('-')
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
}

impl Registry {
    /// An empty registry (tests and plugin hosts build their own).
    pub fn empty() -> Self {
        Self::default()
    }

    /// All models linked into this binary.
    pub fn builtin() -> Result<Self, RegistryError> {
        let mut registry = Self::empty();
        for descriptor in inventory::iter::<ModelDescriptor> {
            registry.insert(RegistryEntry {
                name: descriptor.name.to_owned(),
                fidelity: descriptor.fidelity,
                summary: descriptor.summary.to_owned(),
                settings_doc: descriptor.settings_doc.to_owned(),
                origin: Origin::BuiltIn(descriptor.origin.to_owned()),
                factory: descriptor.constructor.into(),
            })?;
        }
        for check in inventory::iter::<ModelCheck> {
            if registry.entries.contains_key(check.name) {
                registry.checks.insert(check.name.to_owned(), check.check);
            }
        }
        Ok(registry)
    }

    /// Adds one model; a name already taken is an error naming both origins.
    pub fn insert(&mut self, entry: RegistryEntry) -> Result<(), RegistryError> {
        if !is_kebab_case(&entry.name) {
            return Err(RegistryError::BadName { name: entry.name });
        }
        if let Some(existing) = self.entries.get(&entry.name) {
            return Err(RegistryError::Duplicate {
                name: entry.name.clone(),
                first: existing.origin.to_string(),
                second: entry.origin.to_string(),
            });
        }
        self.entries.insert(entry.name.clone(), entry);
        Ok(())
    }

    /// Entries sorted by name.
    pub fn iter(&self) -> impl Iterator<Item = &RegistryEntry> {
        self.entries.values()
    }

    /// Names of the models with `role`, sorted.
    pub fn names(&self, role: Role) -> Vec<&str> {
        self.iter()
            .filter(|e| e.role() == role)
            .map(|e| e.name.as_str())
            .collect()
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The entry called `name`; unknown names get the closest known names as a hint.
    pub fn get(&self, name: &str) -> Result<&RegistryEntry, RegistryError> {
        self.entries
            .get(name)
            .ok_or_else(|| self.unknown(name, None))
    }

    fn unknown(&self, name: &str, role: Option<Role>) -> RegistryError {
        let candidates: Vec<&str> = self
            .iter()
            .filter(|e| role.is_none_or(|r| e.role() == r))
            .map(|e| e.name.as_str())
            .collect();
        let mut scored: Vec<(f64, &str)> = candidates
            .iter()
            .map(|c| (strsim::normalized_damerau_levenshtein(name, c), *c))
            .filter(|(score, c)| *score >= 0.5 || c.contains(name) || name.contains(*c))
            .collect();
        scored.sort_by(|a, b| b.0.total_cmp(&a.0));
        let close: Vec<String> = scored
            .iter()
            .take(3)
            .map(|(_, c)| format!("`{c}`"))
            .collect();
        let known = if candidates.is_empty() {
            "none registered".to_owned()
        } else {
            candidates.join(", ")
        };
        let hint = if close.is_empty() {
            format!(" (known: {known})")
        } else {
            format!("; did you mean {}? (known: {known})", close.join(" or "))
        };
        RegistryError::Unknown {
            name: name.to_owned(),
            role: role.map_or_else(|| "hsv".to_owned(), |r| r.to_string()),
            hint,
        }
    }

    fn entry_for(&self, name: &str, wanted: Role) -> Result<&RegistryEntry, RegistryError> {
        let entry = self
            .entries
            .get(name)
            .ok_or_else(|| self.unknown(name, Some(wanted)))?;
        if entry.role() != wanted {
            return Err(wrong_role(name, entry.role(), wanted));
        }
        Ok(entry)
    }

    /// Builds model `name` of role `M` (`dyn AeroModel`, `dyn HeatFluxModel`, ...):
    /// `registry.create::<dyn AeroModel>("shock-expansion", &context)`.
    pub fn create<M: ?Sized + RoleModel>(
        &self,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Box<M>, RegistryError> {
        let entry = self.entry_for(name, M::ROLE)?;
        match M::constructor(&entry.factory) {
            Some(build) => build(context).map_err(|e| RegistryError::Model(context.locate(e))),
            None => Err(wrong_role(name, entry.role(), M::ROLE)),
        }
    }
}

impl Registry {
    /// Checks model `name` of `role` in the region of `context` as building it would: its
    /// registered [`SettingsCheck`] when it has one (a costly constructor), else by building it
    /// and dropping the model. Controllers are built at run start, from the trimmed vehicle, and
    /// are only looked up here.
    pub fn check(
        &self,
        role: Role,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<(), RegistryError> {
        let entry = self.entry_for(name, role)?;
        let located = |e| RegistryError::Model(context.locate(e));
        if let Some(check) = self.checks.get(name) {
            return check(context).map_err(located);
        }
        match &entry.factory {
            Factory::Aero(build) => drop(build(context).map_err(located)?),
            Factory::HeatFlux(build) => drop(build(context).map_err(located)?),
            Factory::Conduction(build) => drop(build(context).map_err(located)?),
            Factory::Structure(build) => drop(build(context).map_err(located)?),
            Factory::Propulsion(build) => drop(build(context).map_err(located)?),
            Factory::Control(_) => {}
        }
        Ok(())
    }

    /// Builds controller `name` (role `control`) for the run described by `context`.
    pub fn create_controller(
        &self,
        name: &str,
        context: &ControlContext<'_>,
    ) -> Result<Box<dyn Controller>, RegistryError> {
        let entry = self.entry_for(name, Role::Control)?;
        match &entry.factory {
            Factory::Control(build) => Ok(build(context)?),
            _ => Err(wrong_role(name, entry.role(), Role::Control)),
        }
    }
}

/// The trait object of one role, so [`Registry::create`] is one generic function.
pub trait RoleModel {
    const ROLE: Role;
    /// The constructor in `factory` if it builds this role.
    fn constructor(factory: &Factory) -> Option<&SharedConstructor<Self>>;
}

macro_rules! role_model {
    ($trait:path, $role:ident) => {
        impl RoleModel for dyn $trait {
            const ROLE: Role = Role::$role;
            fn constructor(factory: &Factory) -> Option<&SharedConstructor<Self>> {
                match factory {
                    Factory::$role(build) => Some(build),
                    _ => None,
                }
            }
        }
    };
}

role_model!(AeroModel, Aero);
role_model!(HeatFluxModel, HeatFlux);
role_model!(ConductionModel, Conduction);
role_model!(StructureModel, Structure);
role_model!(PropulsionModel, Propulsion);

fn wrong_role(name: &str, actual: Role, wanted: Role) -> RegistryError {
    RegistryError::WrongRole {
        name: name.to_owned(),
        actual,
        wanted,
    }
}

/// A config's model names checked against the registry: here, so the config does not depend on
/// the registry that builds its models.
impl crate::config::LoadedConfig {
    /// Every model named in `[regions.*]` exists in `registry` with the role its key says
    /// (`regions.left_surface.aero` names an aero model): the first that does not is an error
    /// naming the file and key path, before anything runs.
    pub fn check_models(&self, registry: &Registry) -> Result<(), crate::config::ConfigError> {
        match self.model_name_problems(registry).into_iter().next() {
            Some(problem) => Err(problem),
            None => Ok(()),
        }
    }

    /// Every `[regions.*]` model name that is not a registered model of its key's role, each
    /// an error naming the file and key path, in the order of the config's tables.
    pub fn model_name_problems(&self, registry: &Registry) -> Vec<crate::config::ConfigError> {
        let regions = &self.config.regions;
        let tables = [
            ("main_body", Some(&regions.main_body)),
            ("lifting_surfaces", Some(&regions.lifting_surfaces)),
            ("left_surface", Some(&regions.left_surface)),
            ("right_surface", Some(&regions.right_surface)),
            ("propulsion", regions.propulsion.as_ref()),
            ("vertical_fin", regions.vertical_fin.as_ref()),
        ];
        let mut problems = Vec::new();
        for (region, models) in tables {
            let Some(models) = models else { continue };
            for (key, wanted, name) in models.named() {
                let Some(name) = name else { continue };
                let error = |message: String| crate::config::ConfigError {
                    file: self.file.clone(),
                    key_path: format!("regions.{region}.{key}"),
                    message,
                };
                match registry.get(name) {
                    Err(e) => problems.push(error(e.to_string())),
                    Ok(entry) if entry.role() != wanted => {
                        let known = registry.names(wanted).join(", ");
                        problems.push(error(format!(
                            "`{name}` is a {} model, but this key names a {wanted} model (known: {known})",
                            entry.role()
                        )));
                    }
                    Ok(_) => {}
                }
            }
        }
        problems
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aero::{AeroSolution, PanelMotion};
    use crate::flow::FlightCondition;
    use crate::mesh::PanelMesh;

    struct Freestream;
    impl AeroModel for Freestream {
        fn name(&self) -> &str {
            "freestream-pressure"
        }
        fn evaluate(
            &mut self,
            mesh: &PanelMesh,
            flight: &FlightCondition,
            _motion: &PanelMotion<'_>,
            out: &mut AeroSolution,
        ) -> Result<(), ModelError> {
            out.reset(mesh.panels.len());
            out.pressure_pa.fill(flight.freestream.pressure_pa);
            Ok(())
        }
    }

    fn entry(name: &str, origin: &str) -> RegistryEntry {
        RegistryEntry {
            name: name.to_owned(),
            fidelity: 0,
            summary: String::new(),
            settings_doc: String::new(),
            origin: Origin::BuiltIn(origin.to_owned()),
            factory: Factory::Aero(Arc::new(|_| Ok(Box::new(Freestream)))),
        }
    }

    #[test]
    fn duplicate_names_name_both_origins() {
        let mut registry = Registry::empty();
        registry
            .insert(entry("freestream-pressure", "crate-a"))
            .unwrap();
        let err = registry
            .insert(entry("freestream-pressure", "crate-b"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("crate-a") && err.contains("crate-b"), "{err}");
    }

    #[test]
    fn unknown_names_suggest_the_closest() {
        let mut registry = Registry::empty();
        registry.insert(entry("shock-expansion", "a")).unwrap();
        registry.insert(entry("newtonian-vector", "a")).unwrap();
        let err = registry.get("shock-expanson").unwrap_err().to_string();
        assert!(err.contains("did you mean `shock-expansion`"), "{err}");
        let err = registry.get("vortex-lattice").unwrap_err().to_string();
        assert!(
            err.contains("known: newtonian-vector, shock-expansion"),
            "{err}"
        );
    }

    /// A region with an empty mesh, for contexts.
    fn test_region() -> RegionInfo {
        RegionInfo::standalone(
            "test",
            PanelMesh::default(),
            crate::aero::ReferenceValues {
                area_m2: 1.0,
                chord_m: 1.0,
                span_m: 1.0,
                moment_point_m: [0.0; 3],
            },
            crate::gas::PerfectGas::AIR,
            "test.toml",
        )
    }

    #[test]
    fn wrong_role_is_reported() {
        let mut registry = Registry::empty();
        registry.insert(entry("shock-expansion", "a")).unwrap();
        let region = test_region();
        let settings = region.model_settings("shock-expansion");
        let context = ModelContext::new(&region, &registry, &settings);
        let err = registry
            .create::<dyn StructureModel>("shock-expansion", &context)
            .err()
            .unwrap();
        assert!(matches!(err, RegistryError::WrongRole { .. }), "{err}");
        assert!(
            registry
                .create::<dyn AeroModel>("shock-expansion", &context)
                .is_ok()
        );
    }

    #[test]
    fn a_constructors_out_of_range_setting_is_reported_at_its_key_path() {
        let mut registry = Registry::empty();
        let mut refusing = entry("refusing", "a");
        refusing.factory = Factory::Aero(Arc::new(|_| {
            Err(ModelError::out_of_range("refusing", "cells", 0.0, ">= 1"))
        }));
        registry.insert(refusing).unwrap();
        let region = test_region();
        let mut settings = region.model_settings("refusing");
        let unset = ModelContext::new(&region, &registry, &settings);
        let err = registry.check(Role::Aero, "refusing", &unset).unwrap_err();
        assert!(
            matches!(err, RegistryError::Model(ModelError::OutOfRange { .. })),
            "{err}"
        );
        settings
            .table
            .insert("cells".into(), toml::Value::Integer(0));
        let set = ModelContext::new(&region, &registry, &settings);
        let err = registry.check(Role::Aero, "refusing", &set).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "test.toml: key `{}.cells`: 0 is outside the allowed range (>= 1)",
                settings.key_path
            )
        );
        let err = registry
            .check(Role::Structure, "refusing", &set)
            .unwrap_err();
        assert!(matches!(err, RegistryError::WrongRole { .. }), "{err}");
    }

    #[test]
    fn names_must_be_kebab_case() {
        let mut registry = Registry::empty();
        assert!(matches!(
            registry.insert(entry("Shock_Expansion", "a")),
            Err(RegistryError::BadName { .. })
        ));
    }
}
