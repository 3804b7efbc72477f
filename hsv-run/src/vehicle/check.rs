//! `config --check`: every model a job could build from a config, checked with its settings in
//! its region, and every problem reported at once.
//!
//! Each region's named models are checked through [`Registry::check`] (built and dropped, or,
//! for models with costly constructors such as `pod`, a settings check that trains nothing);
//! structures are built so their capabilities can be held against what the aerothermoelastic
//! simulation needs. A `[models.*]` table that no region names (an engine kept for
//! `engine --all`, a surrogate for a trade study) is checked in the first region it is made for.

use std::collections::BTreeSet;

use hsv_core::config::{LoadedConfig, REGION_NAMES, RegionModels};
use hsv_core::error::ModelError;
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry, RegistryError, Role};
use hsv_core::structure::{StructureModel, require};

use super::{AnalysisNeeds, AssemblyError, RegionNeeds, friction_model};

/// One problem of a config: the regions where it arises and what is wrong.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Problem {
    /// The config file.
    pub file: String,
    /// Regions the problem arises in (one message for both surfaces of a shared setting).
    pub regions: Vec<String>,
    /// What is wrong, with the key path, the value and the allowed range where the model says.
    pub message: String,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let regions: Vec<String> = self.regions.iter().map(|r| format!("`{r}`")).collect();
        let noun = if regions.len() > 1 {
            "regions"
        } else {
            "region"
        };
        write!(
            f,
            "{}: {noun} {}: {}",
            self.file,
            regions.join(", "),
            self.message
        )
    }
}

/// Problems in the order found, one per distinct message.
#[derive(Debug, Default)]
struct Problems {
    file: String,
    list: Vec<Problem>,
}

impl Problems {
    fn push(&mut self, region: &str, message: String) {
        // A model's message may start with the file it names; the problem names it once.
        let message = match message.strip_prefix(&format!("{}: ", self.file)) {
            Some(rest) => rest.to_owned(),
            None => message,
        };
        match self.list.iter_mut().find(|p| p.message == message) {
            Some(p) if !p.regions.iter().any(|r| r == region) => p.regions.push(region.to_owned()),
            Some(_) => {}
            None => self.list.push(Problem {
                file: self.file.clone(),
                regions: vec![region.to_owned()],
                message,
            }),
        }
    }
}

/// Checks model `name` of `role` in region `info` with the settings the region sees; a
/// structure is built and held against `need`'s capabilities.
fn check_model(
    info: &RegionInfo,
    registry: &Registry,
    role: Role,
    name: &str,
    need: Option<&RegionNeeds>,
    analysis: &str,
) -> Result<(), RegistryError> {
    let settings = info.model_settings(name);
    let context = ModelContext::new(info, registry, &settings);
    if role != Role::Structure {
        return registry.check(role, name, &context);
    }
    let structure = registry.create::<dyn StructureModel>(name, &context)?;
    if let Some(need) = need {
        require(structure.as_ref(), &need.structure, analysis)?;
    }
    Ok(())
}

/// Every problem that building the config's models would meet, none if it is sound: each
/// region's models against what the aerothermoelastic simulation needs, its skin-friction
/// model, and every `[models.*]` table no region names.
pub fn check_models(loaded: &LoadedConfig, registry: &Registry) -> Vec<Problem> {
    let needs = AnalysisNeeds::aerothermoelastic("the aerothermoelastic simulation");
    let mut problems = Problems {
        file: loaded.file.clone(),
        list: Vec::new(),
    };
    let mut named = BTreeSet::new();
    // Each region built, with the model names it sees.
    let mut regions: Vec<(RegionInfo, RegionModels)> = Vec::new();
    for region in REGION_NAMES {
        let Some(names) = loaded.config.regions.region(region) else {
            continue;
        };
        let info = match loaded.region(region) {
            Ok(info) => info,
            Err(e) => {
                problems.push(region, e.to_string());
                continue;
            }
        };
        let need = needs
            .regions
            .iter()
            .find(|(r, _)| *r == region)
            .map(|(_, n)| n);
        for (key, role, model) in names.named() {
            match model {
                Some(model) => {
                    named.insert(model.to_owned());
                    match check_model(&info, registry, role, model, need, &needs.analysis) {
                        // The config's names are checked apart, at their own key path
                        // (`LoadedConfig::model_name_problems`).
                        Err(RegistryError::Unknown { .. } | RegistryError::WrongRole { .. }) => {}
                        Err(e) => problems.push(region, e.to_string()),
                        Ok(()) => {}
                    }
                }
                None if need.is_some_and(|n| n.roles.contains(&role)) => problems.push(
                    region,
                    format!(
                        "no {role} model, which {} needs (set `regions.{region}.{key}`)",
                        needs.analysis
                    ),
                ),
                None => {}
            }
        }
        if let Some(need) = need
            && let Err(e) = friction_model(&info, registry, &names, need)
        {
            problems.push(region, strip_region(e));
        }
        regions.push((info, names));
    }
    for model in loaded.config.models.keys() {
        if named.contains(model) {
            continue;
        }
        // An unknown table name is the config loader's error; a controller's table is read at
        // run start from the trimmed vehicle.
        let Ok(entry) = registry.get(model) else {
            continue;
        };
        let role = entry.role();
        // Regions that name a model of the same role come first: an engine is checked in
        // `propulsion`, a conduction model in a lifting surface.
        let mut homes: Vec<&(RegionInfo, RegionModels)> = regions.iter().collect();
        homes.sort_by_key(|(_, names)| {
            !names
                .named()
                .iter()
                .any(|(_, r, m)| *r == role && m.is_some())
        });
        let outcome = homes.into_iter().find_map(|(info, _)| {
            match check_model(info, registry, role, model, None, &needs.analysis) {
                Err(RegistryError::Model(ModelError::WrongRegion { .. })) => None,
                outcome => Some((info.name.clone(), outcome)),
            }
        });
        if let Some((region, Err(e))) = outcome {
            problems.push(&region, e.to_string());
        }
    }
    problems.list
}

/// An assembly error's message without the file and region it starts with.
fn strip_region(error: AssemblyError) -> String {
    match error {
        AssemblyError::Model { cause, .. } => cause.to_string(),
        other => other.to_string(),
    }
}
