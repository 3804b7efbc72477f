//! Vehicle assembly: each region of `[regions.*]` built from named models through the registry,
//! checked before t = 0 for the roles and capabilities an analysis needs, and regions wired
//! together through the data manager.
//!
//! A [`Region`] owns its models and state and talks to other regions only through topics it
//! declares at assembly ([`wire`] fails when a subscribed topic has no publisher).

pub mod check;
pub mod error;
pub mod friction;
pub mod partitioned;
pub mod region_rate;
pub mod regions;
pub mod rigid;
pub mod staggered;

use hsv_core::aero::AeroModel;
use hsv_core::config::{LoadedConfig, REGION_NAMES, RegionModels};
use hsv_core::data::{DataError, DataManager, DataManagerBuilder};
use hsv_core::mesh::RegionKind;
use hsv_core::propulsion::PropulsionModel;
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry, Role, RoleModel};
use hsv_core::structure::{Capability, StructureModel, require};
use hsv_core::thermal::{ConductionModel, HeatFluxModel};

/// Whether the main body's aero model loads panels of `region`: the body's own, and the engine's
/// ramp and nozzle when the vehicle has no engine to load them (a glide; module
/// [`rigid`]'s ownership rule). Caps ([`RegionKind::Other`]) carry no load either way.
pub fn body_aero_loads(region: RegionKind, powered: bool) -> bool {
    region == RegionKind::MainBody || (!powered && region == RegionKind::Propulsion)
}

/// Why a vehicle could not be assembled: always names the region, and the model, role or
/// capability at fault.
#[derive(Debug, thiserror::Error)]
pub enum AssemblyError {
    #[error(
        "{file}: region `{region}` has no {role} model, which {analysis} needs (set `regions.{region}.{key}`)"
    )]
    MissingRole {
        file: String,
        region: String,
        role: Role,
        key: &'static str,
        analysis: String,
    },
    // The model's error is part of this message, not a source: printed as a chain it would
    // appear twice.
    #[error("{file}: region `{region}`: {cause}")]
    Model {
        file: String,
        region: String,
        cause: Box<dyn std::error::Error + Send + Sync>,
    },
    #[error(transparent)]
    Config(#[from] hsv_core::config::ConfigError),
    #[error("wiring the regions: {0}")]
    Data(#[from] DataError),
}

/// What an analysis needs of one kind of region: roles that must be present and capabilities
/// its structure model must have.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RegionNeeds {
    pub roles: Vec<Role>,
    pub structure: Vec<Capability>,
    /// Skin friction on the region's panels (unless the config turns it off with
    /// `skin_friction = false`): the wall shear of its heat-flux model, `eckert` if it has none.
    pub friction: bool,
}

/// What every analysis needs of the fixed vertical fin, when the vehicle has one: aero and skin
/// friction (the fin has no structure, heating or controls of its own: a rigid, massless surface
/// on the body, whose loads the body takes).
pub fn fin_needs() -> RegionNeeds {
    RegionNeeds {
        roles: vec![Role::Aero],
        structure: Vec::new(),
        friction: true,
    }
}

/// What an analysis needs of every region, by region name.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisNeeds {
    /// The analysis, as messages name it ("trim", "the aerothermoelastic simulation").
    pub analysis: String,
    pub regions: Vec<(&'static str, RegionNeeds)>,
}

impl AnalysisNeeds {
    /// The partitioned aerothermoelastic vehicle (paper §III): a flexible main body with mass
    /// properties and rigid-body coupling, two heated lifting surfaces whose structures take
    /// temperatures and give root loads, and an engine.
    pub fn aerothermoelastic(analysis: &str) -> Self {
        let surface = RegionNeeds {
            roles: vec![
                Role::Aero,
                Role::HeatFlux,
                Role::Conduction,
                Role::Structure,
            ],
            structure: vec![
                Capability::ThermalStiffness,
                Capability::RootLoads,
                Capability::MassProperties,
                Capability::RigidBodyCoupling,
            ],
            friction: true,
        };
        Self {
            analysis: analysis.to_owned(),
            regions: vec![
                (
                    "main_body",
                    RegionNeeds {
                        roles: vec![Role::Aero, Role::Structure],
                        structure: vec![Capability::MassProperties, Capability::RigidBodyCoupling],
                        friction: true,
                    },
                ),
                ("left_surface", surface.clone()),
                ("right_surface", surface),
                (
                    "propulsion",
                    RegionNeeds {
                        roles: vec![Role::Propulsion],
                        structure: Vec::new(),
                        friction: false,
                    },
                ),
                ("vertical_fin", fin_needs()),
            ],
        }
    }
}

/// The models of one region, built by name, with the region they were built for.
pub struct RegionModelSet {
    pub info: RegionInfo,
    /// The model names, as configured.
    pub names: RegionModels,
    pub aero: Option<Box<dyn AeroModel>>,
    pub heat_flux: Option<Box<dyn HeatFluxModel>>,
    pub conduction: Option<Box<dyn ConductionModel>>,
    pub structure: Option<Box<dyn StructureModel>>,
    pub propulsion: Option<Box<dyn PropulsionModel>>,
    /// The heat-flux model whose wall shear gives the region's skin friction, when the analysis
    /// asks for friction and the config does not turn it off.
    pub friction: Option<Box<dyn HeatFluxModel>>,
}

/// Builds model `name` of role `M` for `region`, naming the region on failure.
fn build<M: ?Sized + RoleModel>(
    region: &RegionInfo,
    registry: &Registry,
    name: Option<&str>,
) -> Result<Option<Box<M>>, AssemblyError> {
    let Some(name) = name else {
        return Ok(None);
    };
    let settings = region.model_settings(name);
    registry
        .create::<M>(name, &ModelContext::new(region, registry, &settings))
        .map(Some)
        .map_err(|e| AssemblyError::Model {
            file: region.file.clone(),
            region: region.name.clone(),
            cause: Box::new(e),
        })
}

/// The config key of a role in a `[regions.*]` table.
fn role_key(role: Role) -> &'static str {
    match role {
        Role::Aero => "aero",
        Role::HeatFlux => "heat_flux",
        Role::Conduction => "conduction",
        Role::Structure => "structure",
        Role::Propulsion => "propulsion",
        // Not a region role: the run's controller is `[control] controller`.
        Role::Control => "controller",
    }
}

/// Builds the models every region of the vehicle needs for the analysis, by name, and checks
/// them before anything runs. Roles the analysis does not use are not built (a rigid trim trains no POD
/// basis); regions it does not list get no models.
pub fn assemble(
    loaded: &LoadedConfig,
    registry: &Registry,
    needs: &AnalysisNeeds,
) -> Result<Vec<RegionModelSet>, AssemblyError> {
    let mut sets = Vec::with_capacity(REGION_NAMES.len());
    for name in REGION_NAMES {
        let Some((_, need)) = needs.regions.iter().find(|(r, _)| *r == name) else {
            continue;
        };
        // A region the config leaves out (only the engine may be: a glide) is not part of the
        // vehicle; the vehicle says what it cannot do without it.
        let Some(names) = loaded.config.regions.region(name) else {
            continue;
        };
        let info = loaded.region(name)?;
        let wanted = |role: Role, model: &Option<String>| {
            need.roles.contains(&role).then(|| model.clone()).flatten()
        };
        let set = RegionModelSet {
            aero: build(&info, registry, wanted(Role::Aero, &names.aero).as_deref())?,
            heat_flux: build(
                &info,
                registry,
                wanted(Role::HeatFlux, &names.heat_flux).as_deref(),
            )?,
            conduction: build(
                &info,
                registry,
                wanted(Role::Conduction, &names.conduction).as_deref(),
            )?,
            structure: build(
                &info,
                registry,
                wanted(Role::Structure, &names.structure).as_deref(),
            )?,
            propulsion: build(
                &info,
                registry,
                wanted(Role::Propulsion, &names.propulsion).as_deref(),
            )?,
            friction: friction_model(&info, registry, &names, need)?,
            info,
            names,
        };
        check_needs(&set, need, &needs.analysis)?;
        sets.push(set);
    }
    Ok(sets)
}

/// The skin-friction model of a region: its heat-flux model (or `eckert`), which must have a
/// wall-shear law.
fn friction_model(
    info: &RegionInfo,
    registry: &Registry,
    names: &RegionModels,
    need: &RegionNeeds,
) -> Result<Option<Box<dyn HeatFluxModel>>, AssemblyError> {
    if !need.friction || names.skin_friction == Some(false) {
        return Ok(None);
    }
    let name = names.heat_flux.as_deref().unwrap_or("eckert");
    let mut model: Option<Box<dyn HeatFluxModel>> = build(info, registry, Some(name))?;
    if model.as_mut().is_some_and(|m| m.skin_friction().is_none()) {
        return Err(AssemblyError::Model {
            file: info.file.clone(),
            region: info.name.clone(),
            cause: format!(
                "heat-flux model `{name}` has no wall-shear law for skin friction; name one that \
                 has (eckert) or set `regions.{}.skin_friction = false`",
                info.name
            )
            .into(),
        });
    }
    Ok(model)
}

/// Checks one region's models against what the analysis needs.
fn check_needs(
    set: &RegionModelSet,
    need: &RegionNeeds,
    analysis: &str,
) -> Result<(), AssemblyError> {
    for &role in &need.roles {
        let present = match role {
            Role::Aero => set.aero.is_some(),
            Role::HeatFlux => set.heat_flux.is_some(),
            Role::Conduction => set.conduction.is_some(),
            Role::Structure => set.structure.is_some(),
            Role::Propulsion => set.propulsion.is_some(),
            // Regions carry no controller (the run's is `[control]`); no analysis asks.
            Role::Control => true,
        };
        if !present {
            return Err(AssemblyError::MissingRole {
                file: set.info.file.clone(),
                region: set.info.name.clone(),
                role,
                key: role_key(role),
                analysis: analysis.to_owned(),
            });
        }
    }
    if let Some(structure) = &set.structure {
        require(structure.as_ref(), &need.structure, analysis).map_err(|e| {
            AssemblyError::Model {
                file: set.info.file.clone(),
                region: set.info.name.clone(),
                cause: Box::new(e),
            }
        })?;
    }
    Ok(())
}

/// Why a region could not advance: the time, the region and what went wrong.
#[derive(Debug, thiserror::Error)]
#[error("region `{region}` at t = {time_s} s: {message}")]
pub struct RegionError {
    pub region: String,
    pub time_s: f64,
    pub message: String,
}

/// Counters a region reports after a run (sub-steps taken, model evaluations, wall time).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct RegionDiagnostics {
    pub steps: usize,
    pub evaluations: usize,
    pub wall_time_s: f64,
}

/// One region of the partitioned vehicle (paper §III): it declares what it publishes and
/// reads, then advances its own state on its own sub-step.
pub trait Region: Send {
    /// The region's config name.
    fn name(&self) -> &str;

    /// Declares the topics the region publishes and subscribes to, keeping the handles.
    fn declare(&mut self, data: &mut DataManagerBuilder) -> Result<(), DataError>;

    /// Advances the region's state to `time_s`, reading its inputs from and publishing its
    /// outputs to `data`.
    fn step_to(&mut self, time_s: f64, data: &mut DataManager) -> Result<(), RegionError>;

    /// What the region did so far.
    fn diagnostics(&self) -> RegionDiagnostics;
}

/// Lets every region declare its topics and builds the data manager; a topic someone reads
/// and nobody publishes is an error naming topic and readers.
pub fn wire(regions: &mut [Box<dyn Region>]) -> Result<DataManager, AssemblyError> {
    let mut builder = DataManagerBuilder::new();
    for region in regions.iter_mut() {
        region.declare(&mut builder)?;
    }
    Ok(builder.build()?)
}

/// The flexible vehicle of `model` assembled from the config, with the default gravity and
/// coupling settings: what trim, simulate, linearize and compare start from.
pub fn flexible_vehicle(
    loaded: &LoadedConfig,
    registry: &Registry,
    model: partitioned::SurfaceModel,
    analysis: &str,
) -> Result<partitioned::PartitionedVehicle, AssemblyError> {
    flexible_vehicle_with(loaded, registry, model, false, analysis)
}

/// [`flexible_vehicle`], with the partitioned surfaces heating in flight when `heated`.
pub fn flexible_vehicle_with(
    loaded: &LoadedConfig,
    registry: &Registry,
    model: partitioned::SurfaceModel,
    heated: bool,
    analysis: &str,
) -> Result<partitioned::PartitionedVehicle, AssemblyError> {
    let needs = match model {
        partitioned::SurfaceModel::Partitioned if heated => partitioned::heated_needs(analysis),
        partitioned::SurfaceModel::Partitioned => partitioned::partitioned_needs(analysis),
        partitioned::SurfaceModel::Monolithic { .. } => partitioned::monolithic_needs(analysis),
    };
    let sets = assemble(loaded, registry, &needs)?;
    let coupling = &loaded.config.coupling;
    let mut vehicle = partitioned::PartitionedVehicle::build(
        sets,
        crate::dynamics::GravityModel::default(),
        partitioned::CouplingSettings {
            tolerance: coupling.tolerance,
            max_iterations: coupling.max_iterations,
        },
        model,
    )?;
    vehicle.set_acceleration(coupling);
    // The time loop staggers the partitioned vehicle's regions when asked; the monolithic
    // comparison model has no body-surface interface to stagger.
    if coupling.scheme == hsv_core::config::CouplingSchemeName::Staggered
        && model == partitioned::SurfaceModel::Partitioned
    {
        vehicle.set_staggered(Some(staggered::StaggeredSettings {
            residual_tolerance_m: coupling.residual_tolerance_m,
            max_sub_iterations: coupling.max_sub_iterations,
        }));
    }
    Ok(vehicle)
}
