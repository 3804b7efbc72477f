//! The partitioned flexible vehicle (paper §III): the regions ([`super::regions`]: the body,
//! its engine and followers, the lifting surfaces and their heating) evaluated at their rates and
//! coupled through what they publish in the data manager. One file per job — `build`
//! (assembly), `step` (the step's protocol and the regions' rates), `publish` (the regions'
//! publications and the coupling's reads), `interface` (the coupled derivative), `heating`,
//! `restart` and `steady` (equilibrium, trim's interface). The partitioned and monolithic
//! models, in-flight heating and restart share it: the state derivative with the body-surface
//! coupling closed by a fixed-point iteration with Aitken relaxation.
//!
//! Per derivative evaluation:
//! 1. flight condition from the rigid state (airspeed, α, β, rates about the centre of mass);
//! 2. main body: OML deformed by the beam modes, aero on its panels with their elastic
//!    velocities, engine on the deformed underside, generalized forces on the deformed geometry;
//! 3. each lifting surface: Ritz-deformed mesh rotated about its pivot by its elevon, aero,
//!    generalized forces by the reference-geometry projection (exact under the common rotation),
//!    thermal-moment forces, and the applied load about the pivot;
//! 4. coupling: the surfaces' root loads by force summation need their modal accelerations,
//!    which need the body's acceleration at the pivots, which needs the root loads: iterate
//!    q̈_surfaces with Aitken's Δ² relaxation until the root loads change by less than the
//!    tolerance (relative), recording iterations and the residual.
//!
//! The elastic interface is two-way (paper §II.B): the body's modes move each surface's root
//! (its mesh and the boundary velocities its aero sees, by the pivot's translation and the
//! rotation of the body's section there), drive the surface's root acceleration, and take the
//! surface's wrench at the pivot into their generalized forces; the iteration's unknowns are the
//! surfaces' q̈ and the body's η̈ (mass bookkeeping: [`crate::dynamics::equations_of_motion`]).
//!
//! That is the implicit scheme, the default. The staggered scheme of `[coupling]` evaluates
//! steps 1-3 and each region once per stage with the interface of the previous sub-iteration
//! ([`PartitionedVehicle::staggered_derivative`]) and sub-iterates the whole step instead
//! ([`super::staggered`]).

use hsv_core::ModelError;
use hsv_core::acceleration::Acceleration;
use hsv_core::aero::{AeroSolution, Loads, ModalHistory};
use hsv_core::config::CouplingConfig;
use hsv_core::coupling::ModalProjection;
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{PanelMesh, RegionKind};
use hsv_core::region::RegionGeometry;
use hsv_core::structure::{Capability, MassProperties, StructureModel};
use nalgebra::{DVector, Point3, Vector3};
use rayon::prelude::*;

use super::friction::RegionFriction;
use super::region_rate::{DEFAULT_BODY_FRICTION_DT_S, Publication, RegionExchange, RegionLoadRate};
use super::{AnalysisNeeds, AssemblyError, RegionModelSet, RegionNeeds};
use crate::disturbance::Disturbances;
use crate::dynamics::{
    GravityModel, RigidBody, SurfaceAttachment, VehicleDerivative, VehicleDynamics, VehicleLoads,
    VehicleState,
};
use hsv_core::registry::Role;

mod build;
mod heating;
mod interface;
mod publish;
mod restart;
mod steady;
mod step;

pub use super::regions::heated::ThermalRestart;
pub use restart::{VehicleMemory, VehicleRestart};

pub use super::error::VehicleError;
use super::error::{assembly_error, model_error};
use super::regions::body::{Body, body_region_loads};
use super::regions::engine::Engine;
use super::regions::follower::{FollowerSurface, follower_loads};
pub use super::regions::heated::HeatingRates;
use super::regions::heated::{
    HeatedSurface, heat_flux_due, heat_surface, read_structure_temperatures, refresh_heat_flux,
    surface_thermal,
};
use super::regions::surface::{
    Surface, add_thermal_generalized_forces, elevon_rotation, surfaces_loads,
};
pub use super::regions::{ElevonCommand, FlightControls};
use super::regions::{join, side_by_side};

/// What the partitioned vehicle needs of its regions.
pub fn partitioned_needs(analysis: &str) -> AnalysisNeeds {
    let surface = RegionNeeds {
        roles: vec![Role::Aero, Role::Structure],
        structure: vec![
            Capability::RootLoads,
            Capability::MassProperties,
            Capability::RigidBodyCoupling,
        ],
        friction: true,
    };
    AnalysisNeeds {
        analysis: analysis.to_owned(),
        regions: vec![
            (
                "main_body",
                RegionNeeds {
                    roles: vec![Role::Aero, Role::Structure],
                    structure: vec![Capability::MassProperties],
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
            ("vertical_fin", super::fin_needs()),
        ],
    }
}

/// How the lifting surfaces are modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SurfaceModel {
    /// Paper §III: each surface has its own Ritz modes, driven at its root and coupled to the
    /// body by root loads.
    Partitioned,
    /// Paper §IV's monolithic comparison model: the whole vehicle is one flexible body; the
    /// surfaces are OML that follow the fuselage's beam modes (their loads go straight to the
    /// body). With `lumped_mass` the surfaces' mass and inertia join the body's, the
    /// correction the paper proposes for its response mismatch; without it the body has the
    /// beam's mass alone (paper Table 1).
    Monolithic { lumped_mass: bool },
}

/// The partitioned vehicle with its surfaces heating in flight: also a heat-flux model, a
/// conduction model and temperature-dependent stiffness on each surface.
pub fn heated_needs(analysis: &str) -> AnalysisNeeds {
    let mut needs = partitioned_needs(analysis);
    for (name, need) in &mut needs.regions {
        if name.ends_with("_surface") {
            need.roles.extend([Role::HeatFlux, Role::Conduction]);
            need.structure.push(Capability::ThermalStiffness);
        }
    }
    needs
}

/// Temperatures of one heated surface, K.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct SurfaceTemperatures {
    pub min_k: f64,
    pub max_k: f64,
    pub mean_k: f64,
}

/// What the monolithic vehicle needs: aero and mass on the body and surfaces, an engine if the
/// vehicle has a propulsion region.
pub fn monolithic_needs(analysis: &str) -> AnalysisNeeds {
    let surface = RegionNeeds {
        roles: vec![Role::Aero, Role::Structure],
        structure: vec![Capability::MassProperties],
        friction: true,
    };
    let mut needs = partitioned_needs(analysis);
    for (name, need) in &mut needs.regions {
        if name.ends_with("_surface") {
            *need = surface.clone();
        }
    }
    needs
}

/// A time step opened at an accepted state by [`PartitionedVehicle::begin_step`] and not yet
/// committed: what its stage derivatives ([`PartitionedVehicle::stage_derivative`],
/// [`PartitionedVehicle::staggered_derivative`]) take to read the regions published at their
/// own rates, and what [`PartitionedVehicle::commit_step`] takes back. Plain data: the open
/// step is an argument, not a flag inside the vehicle.
#[derive(Debug, PartialEq)]
#[must_use = "a step opened must be committed with `commit_step`"]
pub struct OpenStep {
    /// Start of the step, s.
    pub start_s: f64,
    /// Whether a region runs at its own rate, so the stages read publications (and hold the
    /// surfaces' skin friction); false when every region is evaluated at every stage.
    pub reads_publications: bool,
}

/// Body-surface coupling settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CouplingSettings {
    /// Relative change of the root loads (and of the body's modal accelerations, against the η̈
    /// that moves a pivot by 1 g) below which the iteration has converged.
    pub tolerance: f64,
    pub max_iterations: usize,
}

impl Default for CouplingSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 50,
        }
    }
}

/// Where a coupling iteration starts: each surface's q̈ guess and the body's η̈.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingGuess {
    q_ddot: Vec<DVector<f64>>,
    body_q_ddot: DVector<f64>,
}

/// One in-vacuo mode of the assembled structure ([`PartitionedVehicle::in_vacuo_modes`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct InVacuoMode {
    pub frequency_hz: f64,
    /// Share of the mode's strain energy in each region ([`InVacuoModes::regions`]), summing
    /// to 1: where the mode deforms.
    pub strain_energy_shares: Vec<f64>,
}

/// The assembled structure's in-vacuo modes, ascending.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct InVacuoModes {
    /// The main body, then each lifting surface.
    pub regions: Vec<String>,
    pub modes: Vec<InVacuoMode>,
    /// max |M̃ − M̃ᵀ| / max |M̃| of the condensed mass from the partitioned equations: zero
    /// for an energy-consistent interface (a check, not a validation).
    pub mass_asymmetry: f64,
}

/// The coupling tolerance of analyses that difference the derivative (linearization, in-vacuo
/// modes).
pub const LINEARIZATION_TOLERANCE: f64 = 1e-12;

/// Elastic coordinate `j` of the stacked (body η, then each surface's ξ) vector.
fn set_elastic_coordinate(state: &mut VehicleState, j: usize, value: f64) {
    let n_body = state.body_modes.n_modes();
    if j < n_body {
        state.body_modes.q[j] = value;
        return;
    }
    let mut k = j - n_body;
    for m in &mut state.surface_modes {
        if k < m.n_modes() {
            m.q[k] = value;
            return;
        }
        k -= m.n_modes();
    }
}

/// `parts` end to end into `flat` (the interface vector's layout: each surface's q̈, then the
/// body's η̈).
fn gather<'a>(flat: &mut [f64], parts: impl Iterator<Item = &'a DVector<f64>>) {
    let mut k = 0;
    for v in parts {
        flat[k..k + v.len()].copy_from_slice(v.as_slice());
        k += v.len();
    }
}

/// `flat` back into `parts` ([`gather`]'s inverse).
fn scatter<'a>(flat: &[f64], parts: impl Iterator<Item = &'a mut DVector<f64>>) {
    let mut k = 0;
    for v in parts {
        let n = v.len();
        v.as_mut_slice().copy_from_slice(&flat[k..k + n]);
        k += n;
    }
}

/// The modal acceleration of stacked elastic coordinate `i`.
fn elastic_acceleration(out: &VehicleDerivative, n_body: usize, i: usize) -> f64 {
    if i < n_body {
        return out.body_modes.q_ddot[i];
    }
    let mut k = i - n_body;
    for m in &out.surface_modes {
        if k < m.q_ddot.len() {
            return m.q_ddot[k];
        }
        k -= m.q_ddot.len();
    }
    0.0
}

/// Iterations and final residual of the last coupling iteration.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct CouplingReport {
    pub iterations: usize,
    /// Largest relative change of a surface's root force, or of the body's η̈ (relative to the
    /// η̈ that accelerates a pivot by 1 g), in the last iteration.
    pub residual: f64,
}

/// What the coupling read of one lifting surface's publication for the current derivative
/// ([`PartitionedVehicle::read_surface_loads`]): the applied load about the pivot in the
/// surface's own frame and, turned by the stage's elevon rotation, in the body frame.
#[derive(Debug, Clone, Copy)]
struct SurfaceRead {
    applied_surface_frame: Loads,
    applied_about_pivot: Loads,
    elevon_rotation: nalgebra::Rotation3<f64>,
}

impl Default for SurfaceRead {
    fn default() -> Self {
        Self {
            applied_surface_frame: Loads::default(),
            applied_about_pivot: Loads::default(),
            elevon_rotation: nalgebra::Rotation3::identity(),
        }
    }
}

/// The partitioned vehicle (module docs).
pub struct PartitionedVehicle {
    dynamics: VehicleDynamics,
    body: Body,
    surfaces: Vec<Surface>,
    /// The monolithic model's surfaces (empty for the partitioned vehicle).
    followers: Vec<FollowerSurface>,
    surface_model: SurfaceModel,
    /// The propulsion region; `None` for a vehicle without one (a glide), whose body aero then
    /// loads the engine's ramp and nozzle panels.
    engine: Option<Engine>,
    mass: MassProperties,
    reference_point_m: Point3<f64>,
    gas: PerfectGas,
    settings: CouplingSettings,
    loads: VehicleLoads,
    /// Each surface's loads as the coupling read them for the current derivative: the applied
    /// load of force summation, fixed while the coupling iterates on q̈.
    surface_reads: Vec<SurfaceRead>,
    /// The vehicle's own state from derivative to derivative and step to step: time, the
    /// coupling's guesses and report, the surfaces' modal histories ([`VehicleMemory`]).
    memory: VehicleMemory,
    /// The fixed point's acceleration (`[coupling] acceleration`) and the flat interface
    /// vectors it works on (scratch).
    acceleration: Box<dyn Acceleration>,
    acceleration_config: CouplingConfig,
    iterate: Vec<f64>,
    produced: Vec<f64>,
    /// The η̈ that accelerates the most-moving pivot by 1 g (the scale of its residual).
    body_q_ddot_scale: f64,
    /// The staggered scheme's settings, or None for the implicit scheme (module
    /// [`super::staggered`]).
    staggered: Option<super::staggered::StaggeredSettings>,
    /// Each interface's residual at the last fixed-point iteration: every surface's relative
    /// root-force change, then the body's η̈ change (relative to the η̈ that moves a pivot by
    /// 1 g); [`PartitionedVehicle::interface_names`] names them.
    interface_residuals: Vec<f64>,
    warm_start: Option<VehicleState>,
    heating: HeatingRates,
    /// Aero loads of the body panels, and with the surfaces' applied loads, about the CG.
    aero_loads: Loads,
    aero_with_surfaces: Loads,
    body_mode_names: Vec<String>,
    /// Body modal amplitudes of the last steady evaluation.
    trim_modes: Vec<f64>,
    /// How often the body region is evaluated within a step (its publications are read by the
    /// stages of an open step: [`OpenStep`]).
    body_rate: RegionLoadRate,
    /// How often the body's skin friction is re-evaluated among the body's publications in a
    /// run (module [`super::region_rate`]); outside a run, at every evaluation.
    body_friction_rate: RegionLoadRate,
    /// How often the lifting surfaces are evaluated within a step (module
    /// [`super::region_rate`]).
    surface_rate: RegionLoadRate,
    /// The body's and the surfaces' publications at those rates, through the data manager.
    exchange: RegionExchange,
    /// The surfaces evaluated beside the body at the accepted state by `begin_step` (when they
    /// run at every stage): the time and controls, and the state, that the step's first stage
    /// must match to use them instead of evaluating them again.
    stage_one: Option<(f64, FlightControls)>,
    stage_one_state: VehicleState,
    /// The wind field the regions fly through (calm unless a flight sets one).
    disturbances: Disturbances,
    /// Each surface's flight condition in that field at the last evaluation (scratch).
    surface_flights: Vec<FlightCondition>,
}

/// How far past a step's start the wind field is generated when it opens: the step's stages and
/// the regions ahead of the centre of mass read no further, s.
const DISTURBANCE_LOOKAHEAD_S: f64 = 0.1;
