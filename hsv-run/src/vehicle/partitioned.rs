//! The partitioned flexible vehicle (paper §III), one file because the partitioned and monolithic
//! models, in-flight heating and restart share its regions' buffers: the loads every region
//! computes from the vehicle state, and the state derivative with the body-surface coupling closed
//! by a fixed-point iteration with Aitken relaxation.
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
//! surfaces' q̈ and the body's η̈ (mass bookkeeping: [`crate::dynamics::vehicle`]).
//!
//! That is the implicit scheme, the default. The staggered scheme of `[coupling]` evaluates
//! steps 1-3 and each region once per stage with the interface of the previous sub-iteration
//! ([`PartitionedVehicle::staggered_derivative`]) and sub-iterates the whole step instead
//! ([`super::staggered`]).

use hsv_core::ModelError;
use hsv_core::acceleration::Acceleration;
use hsv_core::aero::{AeroModel, AeroSolution, Loads, PanelMotion, integrate_pressure};
use hsv_core::config::CouplingConfig;
pub use hsv_core::coupling::ElevonCommand;
use hsv_core::coupling::{
    ModalProjection, deflect_lifting_surface, elevon_rotation_angle_rad, generalized_forces,
    pivot_axis, rotate_points, rotation_about_axis,
};
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{ModeShapes, PanelMesh, RegionKind};
use hsv_core::propulsion::{EngineInputs, PropulsionModel, PropulsionSolution};
use hsv_core::region::RegionGeometry;
use hsv_core::structure::{Capability, MassProperties, StructureModel};
use hsv_core::vehicle::{LiftingSurfaceConfig, Side, pivot_point};
use nalgebra::{DVector, Point3, Vector3};
use rayon::prelude::*;

use super::friction::RegionFriction;
use super::region_rate::{DEFAULT_BODY_FRICTION_DT_S, RegionLoadHistory, RegionLoadRate};
use super::{AnalysisNeeds, AssemblyError, RegionModelSet, RegionNeeds};
use crate::disturbance::Disturbances;
use crate::dynamics::vehicle::pivot_motion;
use crate::dynamics::{
    GravityModel, RigidBody, SurfaceAttachment, VehicleDerivative, VehicleDynamics, VehicleLoads,
    VehicleState,
};
use hsv_core::registry::Role;

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

/// Rates of the in-flight heating (paper Table 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatingRates {
    /// Conduction step, s (paper: heat transfer 1 ms).
    pub conduction_s: f64,
    /// Interval between heat-flux updates, s (paper: aerothermal 10 ms); the flux is refreshed
    /// at the start of the step where it falls due, from the accepted state.
    pub heat_flux_s: f64,
    /// Interval between stiffness updates from the temperature field, s (our choice).
    pub stiffness_s: f64,
    /// Initial uniform temperature, K (paper: 293 K).
    pub initial_k: f64,
}

impl Default for HeatingRates {
    fn default() -> Self {
        Self {
            conduction_s: 1e-3,
            heat_flux_s: 1e-2,
            stiffness_s: 0.1,
            initial_k: 293.0,
        }
    }
}

/// One surface's thermal model and state: heat flux from its latest aero solution, conduction,
/// and the structure's stiffness updated from the temperature field.
struct SurfaceThermal {
    heat_flux: Box<dyn hsv_core::thermal::HeatFluxModel>,
    conduction: Box<dyn hsv_core::thermal::ConductionModel>,
    /// The conduction state: simulation state of the region.
    state: DVector<f64>,
    trial: DVector<f64>,
    wall_k: Vec<f64>,
    flux_w_m2: Vec<f64>,
    node_k: Vec<f64>,
    node_difference_k: Vec<f64>,
    structure_k: Vec<f64>,
    structure_difference_k: Vec<f64>,
    transfer: Option<hsv_core::coupling::GridTransfer>,
    /// Time up to which conduction has been stepped, and of the last flux and stiffness update.
    conduction_time_s: f64,
    flux_time_s: f64,
    stiffness_time_s: f64,
    /// Set when the stiffness was updated and the vehicle's modal matrices must follow.
    stiffness_changed: bool,
}

/// One heated surface's thermal state for a restart file.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ThermalRestart {
    pub state: DVector<f64>,
    pub flux_w_m2: Vec<f64>,
    pub structure_k: Vec<f64>,
    pub structure_difference_k: Vec<f64>,
    pub conduction_time_s: f64,
    pub flux_time_s: f64,
    pub stiffness_time_s: f64,
}

/// Everything of the vehicle, beyond its [`VehicleState`], that the next step depends on: the
/// coupling iteration's guesses, the surfaces' thermal states and modal histories. With it a
/// run continues bit for bit.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct VehicleRestart {
    pub time_s: f64,
    pub q_ddot: Vec<DVector<f64>>,
    pub root_force_n: Vec<Vector3<f64>>,
    pub thermal: Vec<Option<ThermalRestart>>,
    pub histories: Vec<Option<hsv_core::aero::ModalHistory>>,
    pub heating_conduction_s: f64,
    pub heating_heat_flux_s: f64,
    pub heating_stiffness_s: f64,
    pub heating_initial_k: f64,
    /// The body region's last publications (absent in restart files of runs that evaluated the
    /// body at every stage).
    #[serde(default)]
    pub body_loads: RegionLoadHistory,
    /// Each lifting surface's last publications (empty in restart files of runs that evaluated
    /// the surfaces at every stage).
    #[serde(default)]
    pub surface_loads: Vec<RegionLoadHistory>,
    /// The last coupling iteration's report (the first sample of a continued run shows it;
    /// absent in older restart files).
    #[serde(default)]
    pub coupling: CouplingReport,
    /// The body's η̈ guess of the elastic interface (absent in restart files from before the
    /// two-way interface: zeros).
    #[serde(default)]
    pub body_q_ddot: DVector<f64>,
}

/// Temperatures of one heated surface, K.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct SurfaceTemperatures {
    pub min_k: f64,
    pub max_k: f64,
    pub mean_k: f64,
}

/// What the monolithic vehicle needs: aero and mass on the body and surfaces, an engine.
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

/// A lifting surface of the monolithic model: OML that follows the body's modes.
struct FollowerSurface {
    name: String,
    base: PanelMesh,
    deformed: PanelMesh,
    deflected: PanelMesh,
    /// The body's beam modes on this surface's vertices.
    shapes: ModeShapes,
    aero: Box<dyn AeroModel>,
    friction: Option<RegionFriction>,
    planform: LiftingSurfaceConfig,
    side: Side,
    velocities: Vec<Vector3<f64>>,
    solution: AeroSolution,
    generalized: Vec<f64>,
}

/// The controls at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct FlightControls {
    pub elevon: ElevonCommand,
    /// Fuel equivalence ratio φ.
    pub fuel_equivalence_ratio: f64,
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

/// Why a derivative could not be computed: the region and quantity.
#[derive(Debug, thiserror::Error)]
pub enum VehicleError {
    #[error("region `{region}`: {source}")]
    Model {
        region: String,
        #[source]
        source: ModelError,
    },
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
    /// A run's inputs are refused (its steps, its tables).
    #[error("{0}")]
    Input(String),
    #[error(
        "body-surface coupling did not converge in {iterations} iterations at the pivots of \
         {interfaces}: last relative root-load changes {residuals:?} (tolerance {tolerance})"
    )]
    Coupling {
        iterations: usize,
        interfaces: String,
        residuals: Vec<f64>,
        tolerance: f64,
    },
}

struct Body {
    friction: Option<RegionFriction>,
    /// Skin friction about the centre of mass of the last body evaluation, and the value the
    /// next evaluation takes instead of evaluating the friction law (set by `begin_step` between
    /// the friction's evaluations: module [`super::region_rate`]), as the surfaces' `held_friction`.
    friction_loads: Loads,
    held_friction: Option<Loads>,
    base: PanelMesh,
    mesh: PanelMesh,
    shapes: ModeShapes,
    aero: Box<dyn AeroModel>,
    velocities: Vec<Vector3<f64>>,
    solution: AeroSolution,
    generalized: Vec<f64>,
    engine_generalized: Vec<f64>,
}

struct Surface {
    thermal: Option<SurfaceThermal>,
    friction: Option<RegionFriction>,
    /// Skin friction about the pivot (body frame) evaluated at the open step's first stage, the
    /// accepted state, and held by its other stages (see [`surface_region_loads`]).
    held_friction: Option<Loads>,
    /// Pressure and friction loads about the pivot in the surface's own (undeflected) frame, from
    /// the last region evaluation: the applied load of force summation, fixed while the coupling
    /// iterates on q̈.
    applied_surface_frame: Loads,
    /// The same loads in the body frame.
    applied_about_pivot: Loads,
    /// The elevon's rotation of the surface at the last region evaluation.
    elevon_rotation: nalgebra::Rotation3<f64>,
    name: String,
    base: PanelMesh,
    /// The base vertices displaced by the modes, before the elevon's rotation, m.
    displaced_m: Vec<Point3<f64>>,
    deflected: PanelMesh,
    shapes: ModeShapes,
    projection: ModalProjection,
    structure: Box<dyn StructureModel>,
    aero: Box<dyn AeroModel>,
    planform: LiftingSurfaceConfig,
    side: Side,
    pivot_m: Point3<f64>,
    /// The base mesh rotated rigidly by the elevon (what a model with memory evaluates on).
    rigid: PanelMesh,
    /// The modal history of an aero model with memory: simulation state of this region.
    history: Option<hsv_core::aero::ModalHistory>,
    velocities: Vec<Vector3<f64>>,
    solution: AeroSolution,
    generalized: Vec<f64>,
    root_force_n: Vector3<f64>,
    /// The body's mode shapes at the pivot (6 × n_body: translation m, section rotation rad).
    body_modes_at_pivot: nalgebra::DMatrix<f64>,
}

/// The partitioned vehicle (module docs).
pub struct PartitionedVehicle {
    dynamics: VehicleDynamics,
    body: Body,
    surfaces: Vec<Surface>,
    /// The monolithic model's surfaces (empty for the partitioned vehicle).
    followers: Vec<FollowerSurface>,
    surface_model: SurfaceModel,
    engine: Box<dyn PropulsionModel>,
    engine_solution: PropulsionSolution,
    mass: MassProperties,
    reference_point_m: Point3<f64>,
    gas: PerfectGas,
    settings: CouplingSettings,
    loads: VehicleLoads,
    /// Surface modal accelerations: the coupling's unknown, kept from the last derivative as
    /// the next guess.
    q_ddot: Vec<DVector<f64>>,
    /// The body's η̈, the interface's other unknown.
    body_q_ddot: DVector<f64>,
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
    report: CouplingReport,
    warm_start: Option<VehicleState>,
    heating: HeatingRates,
    /// Simulation time of the next derivative, s (for models with memory).
    time_s: f64,
    /// Aero loads of the body panels, and with the surfaces' applied loads, about the CG.
    aero_loads: Loads,
    aero_with_surfaces: Loads,
    body_mode_names: Vec<String>,
    /// Body modal amplitudes of the last steady evaluation.
    trim_modes: Vec<f64>,
    /// How often the body region is evaluated within a step, its publications, and whether a
    /// step is open (between [`PartitionedVehicle::begin_step`] and `commit_step`): only then
    /// do derivatives read the published body loads.
    body_rate: RegionLoadRate,
    /// How often the body's skin friction is re-evaluated among the body's publications in a
    /// run (module [`super::region_rate`]); outside a run, at every evaluation.
    body_friction_rate: RegionLoadRate,
    body_history: RegionLoadHistory,
    /// How often the lifting surfaces are evaluated within a step, and each one's publications
    /// (module [`super::region_rate`]).
    surface_rate: RegionLoadRate,
    surface_histories: Vec<RegionLoadHistory>,
    in_step: bool,
    /// The wind field the regions fly through (calm unless a flight sets one).
    disturbances: Disturbances,
    /// Each surface's flight condition in that field at the last evaluation (scratch).
    surface_flights: Vec<FlightCondition>,
}

/// How far past a step's start the wind field is generated when it opens: the step's stages and
/// the regions ahead of the centre of mass read no further, s.
const DISTURBANCE_LOOKAHEAD_S: f64 = 0.1;

fn model_error(region: &str) -> impl Fn(ModelError) -> VehicleError + '_ {
    move |source| VehicleError::Model {
        region: region.to_owned(),
        source,
    }
}

/// A surface's thermal model, with the transfer of its conduction nodes onto the structure's
/// temperature grid (mirrored when the structure keeps the other side's grid).
fn surface_thermal(
    name: &str,
    heat_flux: Box<dyn hsv_core::thermal::HeatFluxModel>,
    conduction: Box<dyn hsv_core::thermal::ConductionModel>,
    structure: &dyn StructureModel,
    n_panels: usize,
) -> Result<SurfaceThermal, AssemblyError> {
    let thermal = structure
        .thermal_stiffness()
        .ok_or_else(|| assembly_error(name, "temperature-dependent stiffness".into()))?;
    let n_structure = thermal.temperature_nodes();
    let transfer = hsv_core::coupling::GridTransfer::conduction_to_structure(
        (conduction.node_grid(), conduction.n_nodes()),
        (thermal.temperature_grid(), n_structure),
    )
    .map_err(|e| assembly_error(name, format!("conduction `{}`: {e}", conduction.name())))?;
    if conduction.n_surface_panels() != n_panels {
        return Err(assembly_error(
            name,
            format!(
                "conduction `{}` takes {} surface panels, the region's mesh has {n_panels}",
                conduction.name(),
                conduction.n_surface_panels()
            ),
        ));
    }
    let n_nodes = conduction.n_nodes();
    Ok(SurfaceThermal {
        state: DVector::zeros(conduction.n_states()),
        trial: DVector::zeros(conduction.n_states()),
        heat_flux,
        conduction,
        wall_k: vec![0.0; n_panels],
        flux_w_m2: vec![0.0; n_panels],
        node_k: vec![0.0; n_nodes],
        node_difference_k: vec![0.0; n_nodes],
        structure_k: vec![0.0; n_structure],
        structure_difference_k: vec![0.0; n_structure],
        transfer,
        conduction_time_s: 0.0,
        flux_time_s: f64::NEG_INFINITY,
        stiffness_time_s: 0.0,
        stiffness_changed: false,
    })
}

fn assembly_error(region: &str, message: String) -> AssemblyError {
    AssemblyError::Model {
        file: String::new(),
        region: region.to_owned(),
        cause: message.into(),
    }
}

/// The main body's aero (pressure and friction) and engine loads about the centre of mass, and
/// its generalized forces, on the OML deformed by the beam modes.
#[allow(clippy::too_many_arguments)]
fn body_region_loads(
    b: &mut Body,
    engine: &mut dyn PropulsionModel,
    engine_solution: &mut PropulsionSolution,
    state: &VehicleState,
    controls: &FlightControls,
    flight: &FlightCondition,
    cg: &Point3<f64>,
    reference_point_m: &Point3<f64>,
) -> Result<(Loads, Loads), VehicleError> {
    let p_inf = flight.freestream.pressure_pa;
    let body_err = model_error("main_body");
    let modes = &state.body_modes;
    b.shapes.displace_with_velocities(
        &b.base,
        &modes.q,
        &modes.q_dot,
        &mut b.mesh.vertices,
        &mut b.velocities,
    );
    b.mesh.update_geometry();
    // The body's aero and its engine both read the deformed OML and nothing of each other:
    // side by side.
    let Body {
        friction,
        friction_loads,
        held_friction,
        mesh,
        shapes,
        aero,
        velocities,
        solution,
        generalized,
        engine_generalized,
        ..
    } = b;
    let (mesh, shapes) = (&*mesh, &*shapes);
    let (body_aero, engine_loads) = join(
        || -> Result<Loads, VehicleError> {
            let motion = PanelMotion {
                elastic_velocity_m_s: Some(velocities),
            };
            aero.evaluate(mesh, flight, &motion, solution)
                .map_err(&body_err)?;
            let main_body = |r: RegionKind| r == RegionKind::MainBody;
            let mut body_aero =
                integrate_pressure(mesh, &solution.pressure_pa, p_inf, cg, main_body);
            if let Some(f) = friction {
                *friction_loads = match held_friction {
                    Some(held) => *held,
                    None => f
                        .loads(mesh, flight, solution, &motion, cg, main_body)
                        .map_err(&body_err)?,
                };
                body_aero = body_aero + *friction_loads;
            }
            generalized_forces(
                mesh,
                shapes,
                &solution.pressure_pa,
                p_inf,
                main_body,
                generalized,
            )
            .map_err(|e| body_err(ModelError::inconsistent("coupling", e.to_string())))?;
            Ok(body_aero)
        },
        || -> Result<Loads, VehicleError> {
            // Engine on the deformed underside; its moment comes about the reference point.
            let engine_err = model_error("propulsion");
            engine
                .evaluate(
                    &EngineInputs {
                        flight,
                        body: mesh,
                        fuel_equivalence_ratio: controls.fuel_equivalence_ratio,
                    },
                    engine_solution,
                )
                .map_err(&engine_err)?;
            let e = engine_solution.loads;
            if engine_solution.panel_pressure_pa.len() == mesh.panels.len() {
                generalized_forces(
                    mesh,
                    shapes,
                    &engine_solution.panel_pressure_pa,
                    p_inf,
                    |r| r == RegionKind::Propulsion,
                    engine_generalized,
                )
                .map_err(|e| engine_err(ModelError::inconsistent("coupling", e.to_string())))?;
            } else {
                engine_generalized.iter_mut().for_each(|q| *q = 0.0);
            }
            Ok(Loads {
                force_n: e.force_n,
                moment_nm: e.moment_nm + (reference_point_m - cg).cross(&e.force_n),
            })
        },
    );
    Ok((body_aero?, engine_loads?))
}

/// One lifting surface's aero on its Ritz-deformed mesh rotated by its elevon (the mesh moves
/// with its own modes and the body's at the pivot, the modal states given): the panel solution
/// and, for a model with memory (convolution ROM), the generalized forces from its modal
/// history (`true`). Returns the elevon's rotation.
fn surface_aero(
    s: &mut Surface,
    (modes, body_modes): (&crate::dynamics::ModalState, &crate::dynamics::ModalState),
    elevon: &ElevonCommand,
    flight: &FlightCondition,
    time_s: f64,
) -> Result<(nalgebra::Rotation3<f64>, bool), VehicleError> {
    let err = model_error(&s.name);
    let deflection = elevon.deflection_rad(s.side);
    // Elastic displacement, then the elevon's rotation about the torque tube (what
    // `deflect_lifting_surface` does), with the panel geometry computed once at the end.
    let rotation = elevon_rotation(&s.name, deflection)?;
    s.shapes.displace_with_velocities(
        &s.base,
        &modes.q,
        &modes.q_dot,
        &mut s.displaced_m,
        &mut s.velocities,
    );
    rotate_points(
        &s.displaced_m,
        &pivot_point(&s.planform, s.side),
        &rotation,
        &mut s.deflected.vertices,
    )
    .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
    for v in &mut s.velocities {
        *v = rotation * *v;
    }
    // The body's elastic motion at the pivot carries the root: translation d and the section's
    // small rotation θ, r ← r + d + θ × (r − P), and their rates in the boundary velocity.
    // (Panel velocities: at the panels' centroids.)
    let carried = s.body_modes_at_pivot.ncols() > 0;
    if carried {
        let (d, theta) = pivot_motion(&s.body_modes_at_pivot, &body_modes.q);
        for r in &mut s.deflected.vertices {
            *r += d + theta.cross(&(*r - s.pivot_m));
        }
    }
    s.deflected.update_geometry();
    if carried {
        let (d_dot, theta_dot) = pivot_motion(&s.body_modes_at_pivot, &body_modes.q_dot);
        for (panel, v) in s.deflected.panels.iter().zip(s.velocities.iter_mut()) {
            *v += d_dot + theta_dot.cross(&(panel.centroid - s.pivot_m));
        }
    }
    let motion = PanelMotion {
        elastic_velocity_m_s: Some(&s.velocities),
    };
    let dt_since_commit = time_s - s.history.as_ref().map_or(0.0, |h| h.time_s);
    match (s.aero.modal_history(), s.history.as_ref()) {
        // A model with memory (convolution ROM): generalized forces from the modal history on
        // the rigidly deflected mesh.
        (Some(rom), Some(history)) => {
            deflect_lifting_surface(&s.base, &s.planform, s.side, deflection, &mut s.rigid)
                .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
            rom.evaluate_modal(
                &s.rigid,
                flight,
                history,
                dt_since_commit.max(0.0),
                &modes.q,
                &modes.q_dot,
                &mut s.generalized,
                Some(&mut s.solution),
            )
            .map_err(&err)?;
            Ok((rotation, true))
        }
        _ => {
            s.aero
                .evaluate(&s.deflected, flight, &motion, &mut s.solution)
                .map_err(&err)?;
            Ok((rotation, false))
        }
    }
}

/// One lifting surface's aero ([`surface_aero`]), its generalized forces (aero and thermal)
/// into `out`, and its skin friction about the pivot.
///
/// Inside an open step (`hold_friction`), the skin friction is evaluated at the step's first
/// stage, the accepted state, and held by the others: friction reaches only the root loads, and
/// it changes on the flight's time scale (the elevon ramps over 0.5 s), so holding it over one
/// 1 ms step moves the state by O(Δt · dF/dt) while sparing three of its four evaluations.
/// Outside a step (trim, linearization, flutter) and with `body_loads_dt_s = 0` (the every-stage
/// reference) it is evaluated every time.
fn surface_region_loads(
    s: &mut Surface,
    modes: (&crate::dynamics::ModalState, &crate::dynamics::ModalState),
    elevon: &ElevonCommand,
    flight: &FlightCondition,
    time_s: f64,
    hold_friction: bool,
    out: &mut DVector<f64>,
) -> Result<(), VehicleError> {
    let p_inf = flight.freestream.pressure_pa;
    let (rotation, from_history) = surface_aero(s, modes, elevon, flight, time_s)?;
    let err = model_error(&s.name);
    if !from_history {
        // The modes turn with the surface, so A n·φ is that of the reference geometry.
        s.projection
            .generalized_forces(&s.solution.pressure_pa, p_inf, &mut s.generalized)
            .map_err(|e| err(ModelError::inconsistent("coupling", e.to_string())))?;
    }
    // Pressure and skin friction on the deflected surface, about the pivot: the applied load of
    // the root loads' force summation, which works in the surface's own frame.
    let friction = match (&mut s.friction, s.held_friction.filter(|_| hold_friction)) {
        (Some(_), Some(held)) => held,
        (Some(f), _) => f
            .loads(
                &s.deflected,
                flight,
                &s.solution,
                &PanelMotion::default(),
                &s.pivot_m,
                |r| r == RegionKind::LiftingSurface,
            )
            .map_err(&err)?,
        (None, _) => Loads::default(),
    };
    s.held_friction = hold_friction.then_some(friction);
    let applied = integrate_pressure(
        &s.deflected,
        &s.solution.pressure_pa,
        p_inf,
        &s.pivot_m,
        |r| r == RegionKind::LiftingSurface,
    ) + friction;
    s.applied_surface_frame = Loads {
        force_n: rotation.inverse_transform_vector(&applied.force_n),
        moment_nm: rotation.inverse_transform_vector(&applied.moment_nm),
    };
    s.applied_about_pivot = applied;
    s.elevon_rotation = rotation;
    add_thermal_generalized_forces(s, out);
    Ok(())
}

/// The surface's generalized forces: the aero ones of its last evaluation plus the thermal
/// ones of its heated stiffness.
fn add_thermal_generalized_forces(s: &Surface, out: &mut DVector<f64>) {
    let thermal = s
        .structure
        .thermal_stiffness()
        .and_then(|t| t.thermal_generalized_forces());
    for (k, q) in out.iter_mut().enumerate() {
        *q = s.generalized[k] + thermal.map_or(0.0, |t| t[k]);
    }
}

/// The elevon's rotation of a surface about its torque tube for a deflection, rad.
fn elevon_rotation(
    surface: &str,
    deflection_rad: f64,
) -> Result<nalgebra::Rotation3<f64>, VehicleError> {
    rotation_about_axis(&pivot_axis(), elevon_rotation_angle_rad(deflection_rad))
        .map_err(|e| model_error(surface)(ModelError::inconsistent("elevon", e.to_string())))
}

/// Whether a heated surface's heat flux is due again at `time_s` (every heat-flux interval).
fn heat_flux_due(t: &SurfaceThermal, time_s: f64, rates: &HeatingRates) -> bool {
    time_s - t.flux_time_s >= rates.heat_flux_s - 1e-12
}

/// One surface's heat flux at `time_s` from its aero at the accepted state (the surface's
/// modes, the body's, the elevon and its flight condition), held until it is due again. The
/// aero is evaluated here, not read from the last derivative: inside a step that is the last
/// Runge-Kutta stage's predictor, not a state the flight passes through.
fn refresh_heat_flux(
    s: &mut Surface,
    modes: (&crate::dynamics::ModalState, &crate::dynamics::ModalState),
    elevon: &ElevonCommand,
    flight: &FlightCondition,
    time_s: f64,
    rates: &HeatingRates,
) -> Result<(), VehicleError> {
    if !s
        .thermal
        .as_ref()
        .is_some_and(|t| heat_flux_due(t, time_s, rates))
    {
        return Ok(());
    }
    // The panel solution only: the step's first stage evaluates the loads at this state.
    surface_aero(s, modes, elevon, flight, time_s)?;
    let err = model_error(&s.name);
    let Some(t) = &mut s.thermal else {
        return Ok(());
    };
    t.conduction.surface_temperatures(&t.state, &mut t.wall_k);
    t.heat_flux
        .heat_flux(
            &s.deflected,
            flight,
            &s.solution,
            &t.wall_k,
            &mut t.flux_w_m2,
        )
        .map_err(&err)?;
    t.flux_time_s = time_s;
    Ok(())
}

/// One surface's heating up to `time_s`: conduction steps under the heat flux last refreshed
/// ([`refresh_heat_flux`], at the steps' starts), and the stiffness from the temperature field
/// at its rate (flagged for the vehicle's modal matrices).
fn heat_surface(s: &mut Surface, time_s: f64, rates: &HeatingRates) -> Result<(), VehicleError> {
    let Some(t) = &mut s.thermal else {
        return Ok(());
    };
    let err = model_error(&s.name);
    let mut stepped = false;
    while time_s - t.conduction_time_s > 1e-9 * rates.conduction_s {
        let dt = rates.conduction_s.min(time_s - t.conduction_time_s);
        t.trial.copy_from(&t.state);
        t.conduction
            .step(&mut t.trial, &t.flux_w_m2, dt)
            .map_err(&err)?;
        std::mem::swap(&mut t.state, &mut t.trial);
        t.conduction_time_s += dt;
        stepped = true;
    }
    if stepped && time_s - t.stiffness_time_s >= rates.stiffness_s - 1e-12 {
        t.conduction.node_temperatures(&t.state, &mut t.node_k);
        t.conduction
            .node_temperature_differences(&t.state, &mut t.node_difference_k);
        match &t.transfer {
            Some(transfer) => {
                let to_err = |e: hsv_core::coupling::CouplingError| {
                    err(ModelError::inconsistent(
                        "temperature transfer",
                        e.to_string(),
                    ))
                };
                transfer
                    .apply(&t.node_k, &mut t.structure_k)
                    .map_err(to_err)?;
                transfer
                    .apply(&t.node_difference_k, &mut t.structure_difference_k)
                    .map_err(to_err)?;
            }
            None => {
                t.structure_k.copy_from_slice(&t.node_k);
                t.structure_difference_k
                    .copy_from_slice(&t.node_difference_k);
            }
        }
        if let Some(thermal) = s.structure.thermal_stiffness_mut() {
            thermal
                .set_temperature_field(&t.structure_k, &t.structure_difference_k)
                .map_err(&err)?;
        }
        t.stiffness_changed = true;
        t.stiffness_time_s = time_s;
    }
    Ok(())
}

/// Every lifting surface's region loads, side by side (rayon).
/// Each surface's loads in its own flight condition (`flights`, one per surface: the wind
/// where it flies).
fn surfaces_loads(
    surfaces: &mut [Surface],
    forces: &mut [DVector<f64>],
    state: &VehicleState,
    elevon: &ElevonCommand,
    flights: &[FlightCondition],
    time_s: f64,
    hold_friction: bool,
) -> Result<(), VehicleError> {
    let each = |(((s, out), modes), flight): (
        (
            (&mut Surface, &mut DVector<f64>),
            &crate::dynamics::ModalState,
        ),
        &FlightCondition,
    )| {
        surface_region_loads(
            s,
            (modes, &state.body_modes),
            elevon,
            flight,
            time_s,
            hold_friction,
            out,
        )
    };
    if side_by_side() {
        surfaces
            .par_iter_mut()
            .zip(forces.par_iter_mut())
            .zip(state.surface_modes.par_iter())
            .zip(flights.par_iter())
            .try_for_each(each)
    } else {
        surfaces
            .iter_mut()
            .zip(forces.iter_mut())
            .zip(state.surface_modes.iter())
            .zip(flights.iter())
            .try_for_each(each)
    }
}

/// Whether regions are evaluated side by side: only on a rayon worker thread (the simulation
/// loop runs on one). Called from outside the pool (trim, linearization, flutter), every
/// parallel section would hand its work to the pool and sleep on a latch, which cost 12 % of a
/// one-core run for two surface evaluations of about 70 µs each.
fn side_by_side() -> bool {
    rayon::current_thread_index().is_some()
}

/// `a` and `b` side by side when [`side_by_side`], one after the other otherwise.
fn join<RA: Send, RB: Send>(
    a: impl FnOnce() -> RA + Send,
    b: impl FnOnce() -> RB + Send,
) -> (RA, RB) {
    if side_by_side() {
        rayon::join(a, b)
    } else {
        (a(), b())
    }
}

impl PartitionedVehicle {
    /// The partitioned vehicle from assembled regions (checked with [`partitioned_needs`]).
    pub fn new(
        sets: Vec<RegionModelSet>,
        gravity: GravityModel,
        settings: CouplingSettings,
    ) -> Result<Self, AssemblyError> {
        Self::build(sets, gravity, settings, SurfaceModel::Partitioned)
    }

    /// The vehicle with its surfaces modelled as `surface_model` (regions checked with
    /// [`partitioned_needs`] or [`monolithic_needs`]).
    pub fn build(
        sets: Vec<RegionModelSet>,
        gravity: GravityModel,
        settings: CouplingSettings,
        surface_model: SurfaceModel,
    ) -> Result<Self, AssemblyError> {
        let monolithic = matches!(surface_model, SurfaceModel::Monolithic { .. });
        let lumped = matches!(
            surface_model,
            SurfaceModel::Monolithic { lumped_mass: true }
        );
        let mut body = None;
        let mut body_structure: Option<Box<dyn StructureModel>> = None;
        let mut follower_sets = Vec::new();
        let mut body_modal = None;
        let mut surfaces = Vec::new();
        let mut engine = None;
        let mut mass: Option<MassProperties> = None;
        let mut reference_point_m = Point3::origin();
        let mut gas = PerfectGas::AIR;
        for set in sets {
            let name = set.info.name.clone();
            let err = |e: ModelError| assembly_error(&name, e.to_string());
            reference_point_m = set.info.reference.moment_point();
            gas = set.info.gas;
            let is_surface = matches!(set.info.geometry, RegionGeometry::LiftingSurface { .. });
            if let Some(m) = set
                .structure
                .as_ref()
                .and_then(|s| s.mass_properties())
                .map(|m| m.mass_properties())
                && (!monolithic || lumped || !is_surface)
            {
                mass = Some(mass.map_or(m, |t| t.combined(&m)));
            }
            if monolithic && is_surface {
                follower_sets.push(set);
                continue;
            }
            match (&set.info.geometry, name.as_str()) {
                (_, "main_body") => {
                    let structure = set
                        .structure
                        .ok_or_else(|| assembly_error(&name, "a structure model".into()))?;
                    let aero = set
                        .aero
                        .ok_or_else(|| assembly_error(&name, "an aero model".into()))?;
                    let shapes = structure.mode_shapes_on(&set.info.mesh).map_err(err)?;
                    let n = shapes.n_modes();
                    body_modal = Some(structure.modal_model().clone());
                    body_structure = Some(structure);
                    let n_panels = set.info.mesh.panels.len();
                    body = Some(Body {
                        friction: set.friction.map(|m| RegionFriction::new(m, n_panels)),
                        friction_loads: Loads::default(),
                        held_friction: None,
                        velocities: vec![Vector3::zeros(); set.info.mesh.panels.len()],
                        mesh: set.info.mesh.clone(),
                        base: set.info.mesh,
                        shapes,
                        aero,
                        solution: AeroSolution::default(),
                        generalized: vec![0.0; n],
                        engine_generalized: vec![0.0; n],
                    });
                }
                (_, "propulsion") => {
                    engine = Some(
                        set.propulsion
                            .ok_or_else(|| assembly_error(&name, "a propulsion model".into()))?,
                    );
                }
                (RegionGeometry::LiftingSurface { planform, side }, _) => {
                    let structure = set
                        .structure
                        .ok_or_else(|| assembly_error(&name, "a structure model".into()))?;
                    let aero = set
                        .aero
                        .ok_or_else(|| assembly_error(&name, "an aero model".into()))?;
                    let shapes = structure.mode_shapes_on(&set.info.mesh).map_err(err)?;
                    let projection = ModalProjection::new(&set.info.mesh, &shapes, |r| {
                        r == RegionKind::LiftingSurface
                    })
                    .map_err(|e| assembly_error(&name, e.to_string()))?;
                    let pivot_m = structure
                        .root_loads()
                        .map(|r| r.root_reference_m())
                        .ok_or_else(|| assembly_error(&name, "root loads".into()))?;
                    let n = shapes.n_modes();
                    let mut aero = aero;
                    let history = match aero.modal_history() {
                        Some(rom) => {
                            Some(rom.initial_history(0.0, &DVector::zeros(n)).map_err(err)?)
                        }
                        None => None,
                    };
                    let n_panels = set.info.mesh.panels.len();
                    let thermal = match (set.heat_flux, set.conduction) {
                        (Some(heat_flux), Some(conduction)) => Some(surface_thermal(
                            &name,
                            heat_flux,
                            conduction,
                            structure.as_ref(),
                            n_panels,
                        )?),
                        _ => None,
                    };
                    surfaces.push(Surface {
                        thermal,
                        friction: set.friction.map(|m| RegionFriction::new(m, n_panels)),
                        held_friction: None,
                        applied_surface_frame: Loads::default(),
                        applied_about_pivot: Loads::default(),
                        elevon_rotation: nalgebra::Rotation3::identity(),
                        name: name.clone(),
                        rigid: set.info.mesh.clone(),
                        history,
                        velocities: vec![Vector3::zeros(); set.info.mesh.panels.len()],
                        displaced_m: set.info.mesh.vertices.clone(),
                        deflected: set.info.mesh.clone(),
                        base: set.info.mesh,
                        shapes,
                        projection,
                        structure,
                        aero,
                        planform: planform.clone(),
                        side: *side,
                        pivot_m,
                        solution: AeroSolution::default(),
                        generalized: vec![0.0; n],
                        root_force_n: Vector3::zeros(),
                        body_modes_at_pivot: nalgebra::DMatrix::zeros(6, 0),
                    });
                }
                _ => {}
            }
        }
        let body = body.ok_or_else(|| assembly_error("main_body", "the region".into()))?;
        let mut followers = Vec::new();
        for set in follower_sets {
            let name = set.info.name.clone();
            let RegionGeometry::LiftingSurface { planform, side } = &set.info.geometry else {
                continue;
            };
            let beam = body_structure
                .as_ref()
                .ok_or_else(|| assembly_error("main_body", "a structure model".into()))?;
            let shapes = beam
                .mode_shapes_on(&set.info.mesh)
                .map_err(|e| assembly_error(&name, e.to_string()))?;
            let n_panels = set.info.mesh.panels.len();
            followers.push(FollowerSurface {
                name: name.clone(),
                generalized: vec![0.0; shapes.n_modes()],
                shapes,
                aero: set
                    .aero
                    .ok_or_else(|| assembly_error(&name, "an aero model".into()))?,
                friction: set.friction.map(|m| RegionFriction::new(m, n_panels)),
                planform: planform.clone(),
                side: *side,
                velocities: vec![Vector3::zeros(); n_panels],
                solution: AeroSolution::default(),
                deformed: set.info.mesh.clone(),
                deflected: set.info.mesh.clone(),
                base: set.info.mesh,
            });
        }
        let body_modal =
            body_modal.ok_or_else(|| assembly_error("main_body", "a modal model".into()))?;
        let body_modal_names = body_modal.names.clone();
        let mass = mass.ok_or_else(|| assembly_error("main_body", "mass properties".into()))?;
        let rigid = RigidBody::new(&mass, gravity)
            .map_err(|e| assembly_error("main_body", e.to_string()))?;
        let beam = body_structure
            .as_ref()
            .ok_or_else(|| assembly_error("main_body", "a structure model".into()))?;
        let attachments: Vec<(SurfaceAttachment, hsv_core::structure::ModalModel)> = surfaces
            .iter_mut()
            .map(|s| {
                let coupling = s
                    .structure
                    .rigid_body_coupling()
                    .ok_or_else(|| assembly_error(&s.name, "rigid-body coupling".into()))?;
                let surface_mass = s
                    .structure
                    .mass_properties()
                    .ok_or_else(|| assembly_error(&s.name, "mass properties".into()))?
                    .mass_properties();
                let mut attachment = SurfaceAttachment::from_coupling(
                    &s.name,
                    coupling,
                    &surface_mass,
                    body_modal.n_modes(),
                );
                attachment.body_modes_at_pivot =
                    crate::dynamics::modal::pivot_mode_shapes(beam.as_ref(), &attachment.pivot_m)
                        .map_err(|e| {
                        assembly_error(&s.name, format!("body modes at the pivot: {e}"))
                    })?;
                s.body_modes_at_pivot = attachment.body_modes_at_pivot.clone();
                Ok((attachment, s.structure.modal_model().clone()))
            })
            .collect::<Result<_, AssemblyError>>()?;
        let largest_pivot_mode = surfaces
            .iter()
            .flat_map(|s| {
                s.body_modes_at_pivot
                    .rows(0, 3)
                    .iter()
                    .copied()
                    .collect::<Vec<_>>()
            })
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        let body_q_ddot_scale = if largest_pivot_mode > 0.0 {
            hsv_core::atmosphere::STANDARD_GRAVITY_M_S2 / largest_pivot_mode
        } else {
            1.0
        };
        let dynamics = VehicleDynamics::new(
            rigid,
            &body_modal,
            attachments.iter().map(|(a, m)| (a.clone(), m)).collect(),
        )
        .map_err(|e| assembly_error("main_body", e.to_string()))?;
        let loads = dynamics.zero_loads();
        let q_ddot: Vec<DVector<f64>> = surfaces
            .iter()
            .map(|s| DVector::zeros(s.shapes.n_modes()))
            .collect();
        let interface_len = q_ddot.iter().map(|q| q.len()).sum::<usize>() + body_modal.n_modes();
        Ok(Self {
            q_ddot,
            body_q_ddot: DVector::zeros(body_modal.n_modes()),
            acceleration: hsv_core::acceleration::acceleration(&CouplingConfig::default()),
            acceleration_config: CouplingConfig::default(),
            iterate: vec![0.0; interface_len],
            produced: vec![0.0; interface_len],
            body_q_ddot_scale,
            staggered: None,
            dynamics,
            body,
            surfaces,
            followers,
            surface_model,
            engine: engine.ok_or_else(|| assembly_error("propulsion", "the region".into()))?,
            engine_solution: PropulsionSolution::default(),
            mass,
            reference_point_m,
            gas,
            settings,
            loads,
            report: CouplingReport::default(),
            warm_start: None,
            heating: HeatingRates::default(),
            time_s: 0.0,
            aero_loads: Loads::default(),
            aero_with_surfaces: Loads::default(),
            body_mode_names: body_modal_names,
            trim_modes: Vec::new(),
            body_rate: RegionLoadRate::default(),
            body_friction_rate: RegionLoadRate::Interval(DEFAULT_BODY_FRICTION_DT_S),
            body_history: RegionLoadHistory::default(),
            surface_rate: RegionLoadRate::EveryStage,
            surface_histories: Vec::new(),
            in_step: false,
            disturbances: Disturbances::default(),
            surface_flights: Vec::new(),
        })
    }

    pub fn dynamics(&self) -> &VehicleDynamics {
        &self.dynamics
    }

    pub fn mass_properties(&self) -> &MassProperties {
        &self.mass
    }

    /// Sets the time the next derivatives are evaluated at (models with memory read their
    /// history up to it).
    pub fn set_time(&mut self, time_s: f64) {
        self.time_s = time_s;
    }

    /// Commits an accepted step ending at `time_s` with `state` into the surfaces' modal
    /// histories (aero models with memory; nothing for the others).
    pub fn commit_step(&mut self, state: &VehicleState, time_s: f64) -> Result<(), VehicleError> {
        self.time_s = time_s;
        let flight = self.flight(state)?;
        self.update_surface_flights(state, &flight)?;
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            if let (Some(rom), Some(history)) = (s.aero.modal_history(), s.history.as_mut()) {
                let dt = time_s - history.time_s;
                let modes = &state.surface_modes[i];
                rom.commit(
                    history,
                    &self.surface_flights[i],
                    dt,
                    &modes.q,
                    &modes.q_dot,
                )
                .map_err(model_error(&s.name))?;
            }
        }
        self.advance_heating(time_s)?;
        self.time_s = time_s;
        self.in_step = false;
        Ok(())
    }

    /// The Earth the vehicle flies over (`[simulation] earth`; flat by default).
    pub fn set_earth(&mut self, earth: crate::dynamics::EarthModel) {
        self.dynamics.set_earth(earth);
    }

    /// How often the body region is evaluated within a time step ([`RegionLoadRate`]).
    pub fn set_body_load_rate(&mut self, rate: RegionLoadRate) {
        self.body_rate = rate;
        self.body_history.clear();
    }

    pub fn body_load_rate(&self) -> RegionLoadRate {
        self.body_rate
    }

    /// How often, among the body region's publications, its skin friction is evaluated again
    /// (`EveryStage`: at every publication); default the aerothermal rate
    /// [`DEFAULT_BODY_FRICTION_DT_S`].
    pub fn set_body_friction_rate(&mut self, rate: RegionLoadRate) {
        self.body_friction_rate = rate;
        self.body_history.forget_friction();
    }

    /// How often the lifting surfaces are evaluated within a time step ([`RegionLoadRate`];
    /// `EveryStage` by default).
    pub fn set_surface_load_rate(&mut self, rate: RegionLoadRate) {
        self.surface_rate = rate;
        self.forget_surface_loads();
    }

    pub fn surface_load_rate(&self) -> RegionLoadRate {
        self.surface_rate
    }

    /// Forgets the regions' publications (a run starting afresh).
    pub fn forget_body_loads(&mut self) {
        self.body_history.clear();
        self.forget_surface_loads();
    }

    fn forget_surface_loads(&mut self) {
        self.surface_histories.clear();
        self.surface_histories
            .resize_with(self.surfaces.len(), RegionLoadHistory::default);
    }

    /// Opens the step starting at `time_s` from the accepted `state`: unless the body region
    /// runs at every stage, it is evaluated and published here when its rate says so, and the
    /// step's derivatives read its publications (extrapolated) until [`Self::commit_step`].
    pub fn begin_step(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        time_s: f64,
    ) -> Result<(), VehicleError> {
        self.in_step = false;
        // The field a step reads (its stages and every region ahead of the centre of mass).
        self.disturbances
            .extend_to(time_s + DISTURBANCE_LOOKAHEAD_S, self.region_lead_max_m());
        self.refresh_heat_fluxes(state, controls, time_s)?;
        if self.body_rate == RegionLoadRate::EveryStage
            && self.surface_rate == RegionLoadRate::EveryStage
        {
            return Ok(());
        }
        for s in &mut self.surfaces {
            s.held_friction = None;
        }
        let body_due = self.body_rate != RegionLoadRate::EveryStage
            && self
                .body_rate
                .is_due(time_s, self.body_history.latest_time_s());
        let surfaces_due = self.surface_rate != RegionLoadRate::EveryStage
            && !self.surfaces.is_empty()
            && self.surface_rate.is_due(
                time_s,
                self.surface_histories
                    .first()
                    .and_then(RegionLoadHistory::latest_time_s),
            );
        if body_due || surfaces_due {
            self.publish_regions(state, controls, time_s, body_due, surfaces_due)?;
        }
        self.in_step = true;
        Ok(())
    }

    /// The regions due at the step starting at `time_s` evaluated at the accepted `state`, side
    /// by side, and published (module [`super::region_rate`]).
    fn publish_regions(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        time_s: f64,
        body_due: bool,
        surfaces_due: bool,
    ) -> Result<(), VehicleError> {
        let flight = self.flight(state)?;
        self.time_s = time_s;
        if surfaces_due {
            self.update_surface_flights(state, &flight)?;
        }
        if body_due {
            self.body.held_friction = self
                .body_history
                .friction_at(time_s, &self.body_friction_rate);
        }
        let cg = self.mass.center_of_mass_m;
        let reference_point_m = self.reference_point_m;
        let body = &mut self.body;
        let engine = self.engine.as_mut();
        let engine_solution = &mut self.engine_solution;
        let surfaces = &mut self.surfaces;
        let surface_flights = &self.surface_flights;
        let surface_forces = &mut self.loads.surface_generalized_forces;
        let (body_loads, surfaces_done) = join(
            || {
                body_due.then(|| {
                    body_region_loads(
                        body,
                        engine,
                        engine_solution,
                        state,
                        controls,
                        &flight,
                        &cg,
                        &reference_point_m,
                    )
                })
            },
            || {
                surfaces_due.then(|| {
                    surfaces_loads(
                        surfaces,
                        surface_forces,
                        state,
                        &controls.elevon,
                        surface_flights,
                        time_s,
                        true,
                    )
                })
            },
        );
        let held = self.body.held_friction.take();
        if let Some(done) = surfaces_done {
            done?;
            for (s, history) in self.surfaces.iter().zip(&mut self.surface_histories) {
                history.publish(
                    time_s,
                    &s.applied_surface_frame,
                    &Loads::default(),
                    &s.generalized,
                );
            }
        }
        if let Some(loads) = body_loads {
            self.set_body_loads(loads?);
            self.follower_loads(state, controls, &flight)?;
            if held.is_none() && self.body.friction.is_some() {
                self.body_history
                    .publish_friction(time_s, &self.body.friction_loads);
            }
            self.body_history.publish(
                time_s,
                &self.loads.body,
                &self.aero_loads,
                self.loads.body_generalized_force.as_slice(),
            );
        }
        Ok(())
    }

    /// The heated surfaces' heat flux, where due, from their aero at the accepted `state`
    /// (each in its own flight condition, side by side).
    fn refresh_heat_fluxes(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        time_s: f64,
    ) -> Result<(), VehicleError> {
        let rates = self.heating;
        let due = |s: &Surface| {
            s.thermal
                .as_ref()
                .is_some_and(|t| heat_flux_due(t, time_s, &rates))
        };
        if !self.surfaces.iter().any(due) {
            return Ok(());
        }
        let flight = self.flight(state)?;
        self.update_surface_flights(state, &flight)?;
        let elevon = controls.elevon;
        let body_modes = &state.body_modes;
        let refresh = |((s, modes), flight): (
            (&mut Surface, &crate::dynamics::ModalState),
            &FlightCondition,
        )| {
            refresh_heat_flux(s, (modes, body_modes), &elevon, flight, time_s, &rates)
        };
        if side_by_side() {
            self.surfaces
                .par_iter_mut()
                .zip(state.surface_modes.par_iter())
                .zip(self.surface_flights.par_iter())
                .try_for_each(refresh)
        } else {
            self.surfaces
                .iter_mut()
                .zip(state.surface_modes.iter())
                .zip(self.surface_flights.iter())
                .try_for_each(refresh)
        }
    }

    /// The last derivative's coupling iterations and residual.
    pub fn coupling_report(&self) -> CouplingReport {
        self.report
    }

    /// The flight condition of a rigid state at the centre of mass: airspeed, α, β relative
    /// to the air (the disturbances' wind there) and rates about it.
    pub fn flight(&self, state: &VehicleState) -> Result<FlightCondition, VehicleError> {
        self.flight_at(state, 0.0)
    }

    /// Sets the wind field the regions fly through from the next evaluation on.
    pub fn set_disturbances(&mut self, disturbances: Disturbances) {
        self.disturbances = disturbances;
    }

    pub fn disturbances(&self) -> &Disturbances {
        &self.disturbances
    }

    /// The gust velocity at the centre of mass now, body axes, m/s.
    pub fn gust_body_m_s(&self) -> Vector3<f64> {
        if self.disturbances.is_calm() {
            return Vector3::zeros();
        }
        self.disturbances.velocity_at(self.time_s, 0.0)
    }

    /// How far ahead of the centre of mass the foremost region flies, m (at least zero).
    fn region_lead_max_m(&self) -> f64 {
        let cg_x = self.mass.center_of_mass_m.x;
        self.surfaces
            .iter()
            .map(|s| s.pivot_m.x - cg_x)
            .fold(0.0, f64::max)
    }

    /// Each surface's flight condition into `surface_flights`: the wind at its pivot, `lead`
    /// ahead of the centre of mass along the body axis (`flight`, the centre of mass's, when the
    /// air is calm).
    fn update_surface_flights(
        &mut self,
        state: &VehicleState,
        flight: &FlightCondition,
    ) -> Result<(), VehicleError> {
        self.surface_flights.clear();
        let cg_x = self.mass.center_of_mass_m.x;
        for i in 0..self.surfaces.len() {
            let f = if self.disturbances.is_calm() {
                *flight
            } else {
                self.flight_at(state, self.surfaces[i].pivot_m.x - cg_x)?
            };
            self.surface_flights.push(f);
        }
        Ok(())
    }

    /// The flight condition `lead_m` ahead of the centre of mass along the body x axis: the
    /// airspeed and wind angles of the centre of mass's velocity relative to the gust there.
    fn flight_at(
        &self,
        state: &VehicleState,
        lead_m: f64,
    ) -> Result<FlightCondition, VehicleError> {
        let rigid = &state.rigid;
        let wind_ned = if self.disturbances.is_calm() {
            Vector3::zeros()
        } else {
            rigid.attitude * self.disturbances.velocity_at(self.time_s, lead_m)
        };
        let (airspeed, alpha, beta) = rigid.air_data(&wind_ned);
        let altitude = rigid.altitude_m();
        let freestream = Freestream::at_airspeed(airspeed, altitude, self.gas)
            .map_err(model_error("main_body"))?;
        let mut flight = FlightCondition::steady(freestream, alpha, beta);
        flight.angular_velocity_rad_s = rigid.angular_velocity_body_rad_s;
        flight.rotation_center_m = self.mass.center_of_mass_m;
        Ok(flight)
    }

    /// Loads of every region except the root loads' inertia term (which waits for q̈): the
    /// main body with its engine, and each lifting surface, run side by side (rayon). Inside a
    /// step (unless the body runs at every stage) the body's loads are its published ones.
    fn region_loads(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        flight: &FlightCondition,
    ) -> Result<(), VehicleError> {
        let surfaces_read = self.in_step && self.read_surface_loads(&controls.elevon)?;
        let body_read = self.in_step
            && self.body_history.read(
                self.time_s,
                &mut self.loads.body,
                &mut self.aero_loads,
                self.loads.body_generalized_force.as_mut_slice(),
            );
        match (body_read, surfaces_read) {
            (true, true) => return Ok(()),
            (false, true) => return self.body_loads_now(state, controls, flight),
            (true, false) => {
                self.update_surface_flights(state, flight)?;
                return surfaces_loads(
                    &mut self.surfaces,
                    &mut self.loads.surface_generalized_forces,
                    state,
                    &controls.elevon,
                    &self.surface_flights,
                    self.time_s,
                    true,
                );
            }
            (false, false) => self.update_surface_flights(state, flight)?,
        }
        let cg = self.mass.center_of_mass_m;
        let reference_point_m = self.reference_point_m;
        let elevon = controls.elevon;
        let time_s = self.time_s;
        let hold_friction = self.in_step;
        let body = &mut self.body;
        let engine = self.engine.as_mut();
        let engine_solution = &mut self.engine_solution;
        let surfaces = &mut self.surfaces;
        let surface_flights = &self.surface_flights;
        let surface_forces = &mut self.loads.surface_generalized_forces;
        let (body_loads, surfaces_done) = join(
            || {
                body_region_loads(
                    body,
                    engine,
                    engine_solution,
                    state,
                    controls,
                    flight,
                    &cg,
                    &reference_point_m,
                )
            },
            || {
                surfaces_loads(
                    surfaces,
                    surface_forces,
                    state,
                    &elevon,
                    surface_flights,
                    time_s,
                    hold_friction,
                )
            },
        );
        surfaces_done?;
        self.set_body_loads(body_loads?);
        self.follower_loads(state, controls, flight)
    }

    /// The body region alone (body, engine, the monolithic model's surfaces) into the loads.
    fn body_loads_now(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        flight: &FlightCondition,
    ) -> Result<(), VehicleError> {
        let loads = body_region_loads(
            &mut self.body,
            self.engine.as_mut(),
            &mut self.engine_solution,
            state,
            controls,
            flight,
            &self.mass.center_of_mass_m,
            &self.reference_point_m,
        )?;
        self.set_body_loads(loads);
        self.follower_loads(state, controls, flight)
    }

    /// Each surface's loads at the stage time from its publications (module
    /// [`super::region_rate`]) with the stage's elevon rotation and thermal generalized forces;
    /// false when the surfaces are evaluated at every stage or nothing is published yet.
    fn read_surface_loads(&mut self, elevon: &ElevonCommand) -> Result<bool, VehicleError> {
        if self.surface_rate == RegionLoadRate::EveryStage || self.surfaces.is_empty() {
            return Ok(false);
        }
        let mut unused = Loads::default();
        for ((s, history), out) in self
            .surfaces
            .iter_mut()
            .zip(&self.surface_histories)
            .zip(self.loads.surface_generalized_forces.iter_mut())
        {
            if !history.read(
                self.time_s,
                &mut s.applied_surface_frame,
                &mut unused,
                &mut s.generalized,
            ) {
                return Ok(false);
            }
            let rotation = elevon_rotation(&s.name, elevon.deflection_rad(s.side))?;
            s.applied_about_pivot = Loads {
                force_n: rotation * s.applied_surface_frame.force_n,
                moment_nm: rotation * s.applied_surface_frame.moment_nm,
            };
            s.elevon_rotation = rotation;
            add_thermal_generalized_forces(s, out);
        }
        Ok(true)
    }

    /// The body's aero and engine loads and generalized forces into the vehicle loads.
    fn set_body_loads(&mut self, (body_aero, engine_loads): (Loads, Loads)) {
        self.loads.body = body_aero + engine_loads;
        self.aero_loads = body_aero;
        let b = &self.body;
        for (k, q) in self.loads.body_generalized_force.iter_mut().enumerate() {
            *q = b.generalized[k] + b.engine_generalized[k];
        }
    }

    /// The monolithic model's surfaces: OML following the body's modes, rotated by the elevon;
    /// their aero loads go straight to the body and to its generalized forces.
    fn follower_loads(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        flight: &FlightCondition,
    ) -> Result<(), VehicleError> {
        let cg = self.mass.center_of_mass_m;
        let p_inf = flight.freestream.pressure_pa;
        let elevon = controls.elevon;
        let surface = |r: RegionKind| r == RegionKind::LiftingSurface;
        for f in &mut self.followers {
            let err = model_error(&f.name);
            let deflection = elevon.deflection_rad(f.side);
            f.shapes
                .deform(&f.base, &state.body_modes.q, &mut f.deformed);
            deflect_lifting_surface(
                &f.deformed,
                &f.planform,
                f.side,
                deflection,
                &mut f.deflected,
            )
            .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
            let rotation =
                rotation_about_axis(&pivot_axis(), elevon_rotation_angle_rad(deflection))
                    .map_err(|e| err(ModelError::inconsistent("elevon", e.to_string())))?;
            f.shapes
                .panel_velocities(&f.base, &state.body_modes.q_dot, &mut f.velocities);
            for v in &mut f.velocities {
                *v = rotation * *v;
            }
            let motion = PanelMotion {
                elastic_velocity_m_s: Some(&f.velocities),
            };
            f.aero
                .evaluate(&f.deflected, flight, &motion, &mut f.solution)
                .map_err(&err)?;
            let mut loads =
                integrate_pressure(&f.deflected, &f.solution.pressure_pa, p_inf, &cg, surface);
            if let Some(friction) = &mut f.friction {
                loads = loads
                    + friction
                        .loads(&f.deflected, flight, &f.solution, &motion, &cg, surface)
                        .map_err(&err)?;
            }
            generalized_forces(
                &f.deflected,
                &f.shapes,
                &f.solution.pressure_pa,
                p_inf,
                surface,
                &mut f.generalized,
            )
            .map_err(|e| err(ModelError::inconsistent("coupling", e.to_string())))?;
            self.loads.body = self.loads.body + loads;
            self.aero_loads = self.aero_loads + loads;
            for (q, g) in self
                .loads
                .body_generalized_force
                .iter_mut()
                .zip(&f.generalized)
            {
                *q += g;
            }
        }
        Ok(())
    }

    /// Starts every heated surface at a uniform temperature with `rates` (call before flying).
    pub fn start_heating(&mut self, rates: &HeatingRates) -> Result<(), VehicleError> {
        self.heating = *rates;
        for s in &mut self.surfaces {
            if let Some(t) = &mut s.thermal {
                t.state = t
                    .conduction
                    .uniform_state(rates.initial_k)
                    .map_err(model_error(&s.name))?;
                t.trial.clone_from(&t.state);
                t.conduction_time_s = 0.0;
                t.flux_time_s = f64::NEG_INFINITY;
                t.stiffness_time_s = 0.0;
            }
        }
        Ok(())
    }

    /// Advances every heated surface to `time_s`: conduction steps under the heat flux of the
    /// step's start ([`Self::begin_step`]), and the structure's stiffness (and the modal
    /// equations) from the temperature field every stiffness interval.
    fn advance_heating(&mut self, time_s: f64) -> Result<(), VehicleError> {
        let rates = self.heating;
        // Each surface heats on its own (conduction, its stiffness): side by side.
        let heat = |s: &mut Surface| heat_surface(s, time_s, &rates);
        if side_by_side() {
            self.surfaces.par_iter_mut().try_for_each(heat)?;
        } else {
            self.surfaces.iter_mut().try_for_each(heat)?;
        }
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            if let Some(t) = &mut s.thermal
                && std::mem::take(&mut t.stiffness_changed)
            {
                self.dynamics
                    .set_surface_matrices(i, s.structure.modal_model())?;
            }
        }
        Ok(())
    }

    /// Structure temperatures of each heated surface (empty for unheated surfaces).
    pub fn surface_temperatures(&mut self) -> Vec<(String, SurfaceTemperatures)> {
        let mut out = Vec::new();
        self.each_surface_temperature(|name, t| out.push((name.to_owned(), t)));
        out
    }

    /// Lowest, highest and mean (of the surfaces' means) structure temperature over every
    /// heated surface, K; None when no surface heats. Allocates nothing (the time loop's record).
    pub fn heated_surface_range(&mut self) -> Option<SurfaceTemperatures> {
        let mut range: Option<SurfaceTemperatures> = None;
        let mut n = 0.0;
        self.each_surface_temperature(|_, t| {
            n += 1.0;
            range = Some(match range {
                None => t,
                Some(r) => SurfaceTemperatures {
                    min_k: r.min_k.min(t.min_k),
                    max_k: r.max_k.max(t.max_k),
                    mean_k: r.mean_k + (t.mean_k - r.mean_k) / n,
                },
            });
        });
        range
    }

    /// Each heated surface's name and temperatures.
    fn each_surface_temperature(&mut self, mut visit: impl FnMut(&str, SurfaceTemperatures)) {
        for s in &mut self.surfaces {
            if let Some(t) = &mut s.thermal {
                t.conduction.node_temperatures(&t.state, &mut t.node_k);
                let n = t.node_k.len().max(1) as f64;
                visit(
                    &s.name,
                    SurfaceTemperatures {
                        min_k: t.node_k.iter().copied().fold(f64::INFINITY, f64::min),
                        max_k: t.node_k.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                        mean_k: t.node_k.iter().sum::<f64>() / n,
                    },
                );
            }
        }
    }

    /// The vehicle's OML as last evaluated (body deformed by its modes, surfaces deformed and
    /// deflected) merged into one mesh, with the absolute pressure (Pa) and, for heated surfaces,
    /// the wall temperature (K; NaN elsewhere) of each panel: what a VTK frame shows.
    pub fn oml_snapshot(&mut self) -> (PanelMesh, Vec<f64>, Vec<f64>) {
        let mut mesh = self.body.mesh.clone();
        let mut pressure = self.body.solution.pressure_pa.clone();
        let mut wall = vec![f64::NAN; mesh.panels.len()];
        for s in &mut self.surfaces {
            mesh.merge(&s.deflected);
            pressure.extend_from_slice(&s.solution.pressure_pa);
            match &mut s.thermal {
                Some(t) => {
                    t.conduction.surface_temperatures(&t.state, &mut t.wall_k);
                    wall.extend_from_slice(&t.wall_k);
                }
                None => wall.extend(std::iter::repeat_n(f64::NAN, s.deflected.panels.len())),
            }
        }
        for f in &self.followers {
            mesh.merge(&f.deflected);
            pressure.extend_from_slice(&f.solution.pressure_pa);
            wall.extend(std::iter::repeat_n(f64::NAN, f.deflected.panels.len()));
        }
        pressure.resize(mesh.panels.len(), f64::NAN);
        (mesh, pressure, wall)
    }
    /// The coupling iteration's guesses (each surface's q̈ and the last Aitken step), which the
    /// next [`Self::derivative`] starts from.
    pub fn coupling_guess(&self) -> CouplingGuess {
        CouplingGuess {
            q_ddot: self.q_ddot.clone(),
            body_q_ddot: self.body_q_ddot.clone(),
        }
    }

    /// Starts the next coupling iteration from `guess` (a linearization restores one guess
    /// before every evaluation, so its derivative is a function of its arguments alone).
    pub fn set_coupling_guess(&mut self, guess: &CouplingGuess) -> Result<(), VehicleError> {
        let fits = |a: &[DVector<f64>], b: &[DVector<f64>]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.len() == y.len())
        };
        if !(fits(&guess.q_ddot, &self.q_ddot) && guess.body_q_ddot.len() == self.body_q_ddot.len())
        {
            return Err(VehicleError::Input(
                "a coupling guess of another vehicle (surface mode counts differ)".to_owned(),
            ));
        }
        self.q_ddot.clone_from(&guess.q_ddot);
        self.body_q_ddot.copy_from(&guess.body_q_ddot);
        Ok(())
    }

    /// Length of the interface vector of the staggered scheme ([`super::staggered`]): every
    /// surface's q̈, then the body's η̈.
    pub fn interface_len(&self) -> usize {
        self.q_ddot.iter().map(|q| q.len()).sum::<usize>() + self.body_q_ddot.len()
    }

    /// The interface unknowns the next derivative starts from, into `out`
    /// ([`Self::interface_len`] entries).
    pub fn interface_guess(&self, out: &mut [f64]) {
        gather(
            out,
            self.q_ddot.iter().chain(std::iter::once(&self.body_q_ddot)),
        );
    }

    /// Sets the interface unknowns from `guess` ([`Self::interface_len`] entries).
    pub fn set_interface_guess(&mut self, guess: &[f64]) {
        scatter(
            guess,
            self.q_ddot
                .iter_mut()
                .chain(std::iter::once(&mut self.body_q_ddot)),
        );
    }

    /// One evaluation of the staggered scheme: the regions' loads at `state`, then each region
    /// once with the other side's interface data `guess` (the previous sub-iteration's, at this
    /// stage), no fixed point; the interface the regions produce goes to `produced`.
    pub fn staggered_derivative(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        guess: &[f64],
        produced: &mut [f64],
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        let flight = self.flight(state)?;
        self.region_loads(state, controls, &flight)?;
        self.set_interface_guess(guess);
        let body_without_roots = self.loads.body;
        self.add_root_loads(state, &body_without_roots)?;
        self.loads
            .body_modal_acceleration
            .copy_from(&self.body_q_ddot);
        self.dynamics.derivative(state, &self.loads, out)?;
        gather(
            produced,
            out.surface_modes
                .iter()
                .map(|m| &m.q_ddot)
                .chain(std::iter::once(&out.body_modes.q_ddot)),
        );
        Ok(())
    }

    /// The largest change of an interface displacement between states `a` and `b`, m: the
    /// body's elastic translation at each pivot and each surface's deflection at its mesh
    /// vertices (the staggered scheme's residual, paper Table 3's R_tol).
    pub fn interface_displacement_change_m(&self, a: &VehicleState, b: &VehicleState) -> f64 {
        let mut worst: f64 = 0.0;
        for (i, s) in self.surfaces.iter().enumerate() {
            let mut pivot = Vector3::zeros();
            for (k, c) in s.body_modes_at_pivot.column_iter().enumerate() {
                let dq = a.body_modes.q[k] - b.body_modes.q[k];
                pivot += Vector3::new(c[0], c[1], c[2]) * dq;
            }
            worst = worst.max(pivot.norm());
            let (qa, qb) = (&a.surface_modes[i].q, &b.surface_modes[i].q);
            let d = &s.shapes.vertex_displacement;
            for v in 0..d.nrows() / 3 {
                let mut change = Vector3::zeros();
                for k in 0..d.ncols() {
                    let dq = qa[k] - qb[k];
                    change +=
                        Vector3::new(d[(3 * v, k)], d[(3 * v + 1, k)], d[(3 * v + 2, k)]) * dq;
                }
                worst = worst.max(change.norm());
            }
        }
        worst
    }

    /// Records a staggered step's sub-iterations and final interface residual (m) as the
    /// coupling report.
    pub fn set_staggered_report(&mut self, sub_iterations: usize, residual_m: f64) {
        self.report = CouplingReport {
            iterations: sub_iterations,
            residual: residual_m,
        };
    }

    /// The staggered scheme's settings, None when every stage closes the interface (implicit).
    pub fn staggered(&self) -> Option<super::staggered::StaggeredSettings> {
        self.staggered
    }

    /// Flies the staggered scheme with `settings`, or the implicit one with None. Trim and
    /// linearization always close the interface (a steady state has no step to stagger).
    pub fn set_staggered(&mut self, settings: Option<super::staggered::StaggeredSettings>) {
        self.staggered = settings;
    }

    /// Accelerates the coupling fixed points as `[coupling]` says (`acceleration`,
    /// `relaxation`, `relaxation_bounds`).
    pub fn set_acceleration(&mut self, config: &CouplingConfig) {
        self.acceleration = hsv_core::acceleration::acceleration(config);
        self.acceleration_config = *config;
    }

    /// A fresh acceleration of the configured kind, for a fixed point of the caller's (the
    /// staggered step's).
    pub fn new_acceleration(&self) -> Box<dyn Acceleration> {
        hsv_core::acceleration::acceleration(&self.acceleration_config)
    }

    /// How the coupling iteration converges.
    pub fn coupling_settings(&self) -> CouplingSettings {
        self.settings
    }

    /// Sets how the coupling iteration converges (a linearization tightens it).
    pub fn set_coupling_settings(&mut self, settings: CouplingSettings) {
        self.settings = settings;
    }

    /// The vehicle's own state for a restart file ([`VehicleRestart`]).
    pub fn restart(&self) -> VehicleRestart {
        VehicleRestart {
            time_s: self.time_s,
            q_ddot: self.q_ddot.clone(),
            root_force_n: self.surfaces.iter().map(|s| s.root_force_n).collect(),
            thermal: self
                .surfaces
                .iter()
                .map(|s| {
                    s.thermal.as_ref().map(|t| ThermalRestart {
                        state: t.state.clone(),
                        flux_w_m2: t.flux_w_m2.clone(),
                        structure_k: t.structure_k.clone(),
                        structure_difference_k: t.structure_difference_k.clone(),
                        conduction_time_s: t.conduction_time_s,
                        flux_time_s: t.flux_time_s,
                        stiffness_time_s: t.stiffness_time_s,
                    })
                })
                .collect(),
            histories: self.surfaces.iter().map(|s| s.history.clone()).collect(),
            heating_conduction_s: self.heating.conduction_s,
            heating_heat_flux_s: self.heating.heat_flux_s,
            heating_stiffness_s: self.heating.stiffness_s,
            heating_initial_k: self.heating.initial_k,
            body_loads: self.body_history.clone(),
            surface_loads: self.surface_histories.clone(),
            body_q_ddot: self.body_q_ddot.clone(),
            coupling: self.report,
        }
    }

    /// Restores the vehicle's own state from a restart file: the surfaces' stiffness is set from
    /// the saved temperature field again, so the modal matrices are those of the run.
    pub fn restore(&mut self, r: &VehicleRestart) -> Result<(), VehicleError> {
        let n = self.surfaces.len();
        if self.stiffness_heated()
            && r.thermal
                .iter()
                .flatten()
                .any(|t| t.stiffness_time_s <= 0.0)
        {
            // A heated structure cannot be cooled in place: its models keep no cold matrices.
            return Err(VehicleError::Input(
                "cannot restore a cold-stiffness state into a vehicle whose surfaces' stiffness \
                 has been heated; assemble the vehicle again"
                    .to_owned(),
            ));
        }
        for (what, len) in [
            ("coupling accelerations", r.q_ddot.len()),
            ("root forces", r.root_force_n.len()),
            ("thermal states", r.thermal.len()),
            ("modal histories", r.histories.len()),
        ] {
            if len != n {
                return Err(VehicleError::Input(format!(
                    "restart file: {len} {what} for a vehicle of {n} lifting surfaces"
                )));
            }
        }
        let n_body = self.body_q_ddot.len();
        let len = r.body_q_ddot.len();
        if len != 0 && len != n_body {
            return Err(VehicleError::Input(format!(
                "restart file: {len} body modal accelerations for a body of {n_body} modes"
            )));
        }
        self.time_s = r.time_s;
        self.report = r.coupling;
        self.body_history.clone_from(&r.body_loads);
        match r.surface_loads.len() {
            0 => self.forget_surface_loads(),
            len if len == n => self.surface_histories.clone_from(&r.surface_loads),
            len => {
                return Err(VehicleError::Input(format!(
                    "restart file: {len} surface load histories for a vehicle of {n} lifting \
                     surfaces"
                )));
            }
        }
        self.in_step = false;
        self.q_ddot.clone_from(&r.q_ddot);
        if r.body_q_ddot.is_empty() {
            self.body_q_ddot.fill(0.0);
        } else {
            self.body_q_ddot.copy_from(&r.body_q_ddot);
        }
        self.heating = HeatingRates {
            conduction_s: r.heating_conduction_s,
            heat_flux_s: r.heating_heat_flux_s,
            stiffness_s: r.heating_stiffness_s,
            initial_k: r.heating_initial_k,
        };
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            s.root_force_n = r.root_force_n[i];
            s.history.clone_from(&r.histories[i]);
            match (&mut s.thermal, &r.thermal[i]) {
                (Some(t), Some(saved)) => {
                    if saved.state.len() != t.state.len() {
                        return Err(VehicleError::Input(format!(
                            "restart file: {} thermal states for `{}`, whose conduction model has {}",
                            saved.state.len(),
                            s.name,
                            t.state.len()
                        )));
                    }
                    t.state.clone_from(&saved.state);
                    t.flux_w_m2.clone_from(&saved.flux_w_m2);
                    t.structure_k.clone_from(&saved.structure_k);
                    t.structure_difference_k
                        .clone_from(&saved.structure_difference_k);
                    t.conduction_time_s = saved.conduction_time_s;
                    t.flux_time_s = saved.flux_time_s;
                    t.stiffness_time_s = saved.stiffness_time_s;
                    if t.stiffness_time_s > 0.0 {
                        if let Some(thermal) = s.structure.thermal_stiffness_mut() {
                            thermal
                                .set_temperature_field(&t.structure_k, &t.structure_difference_k)
                                .map_err(model_error(&s.name))?;
                        }
                        self.dynamics
                            .set_surface_matrices(i, s.structure.modal_model())?;
                    }
                }
                (None, None) => {}
                _ => {
                    return Err(VehicleError::Input(format!(
                        "restart file: `{}` heats in one run and not in the other",
                        s.name
                    )));
                }
            }
        }
        Ok(())
    }

    /// Whether any surface's stiffness has been updated from its temperature field.
    pub fn stiffness_heated(&self) -> bool {
        self.surfaces
            .iter()
            .filter_map(|s| s.thermal.as_ref())
            .any(|t| t.stiffness_time_s > 0.0)
    }

    /// Force (N) and moment about the centre of mass (N m) of every load but gravity at the
    /// latest derivative evaluation: aero, engine and the surfaces' root loads, body axes.
    pub fn body_loads(&self) -> Loads {
        self.loads.body
    }

    /// Each region's aero model and the validity diagnostics of its latest evaluation.
    pub fn aero_diagnostics(&self) -> Vec<(String, String, hsv_core::aero::AeroDiagnostics)> {
        let mut out = vec![(
            "main_body".to_owned(),
            self.body.aero.name().to_owned(),
            self.body.solution.diagnostics,
        )];
        for s in &self.surfaces {
            out.push((
                s.name.clone(),
                s.aero.name().to_owned(),
                s.solution.diagnostics,
            ));
        }
        for f in &self.followers {
            out.push((
                f.name.clone(),
                f.aero.name().to_owned(),
                f.solution.diagnostics,
            ));
        }
        out
    }

    /// How the surfaces are modelled.
    pub fn surface_model(&self) -> SurfaceModel {
        self.surface_model
    }

    /// The surfaces' root loads on the body for the current q̈ guess, added to the body loads
    /// about the centre of mass; returns the largest relative change of a root force.
    fn add_root_loads(
        &mut self,
        state: &VehicleState,
        body_without_roots: &Loads,
    ) -> Result<f64, VehicleError> {
        let cg = self.mass.center_of_mass_m;
        let mut total = *body_without_roots;
        let mut aero = self.aero_loads;
        let mut change: f64 = 0.0;
        for (i, s) in self.surfaces.iter_mut().enumerate() {
            let err = model_error(&s.name);
            let (rotation, applied) = (s.elevon_rotation, s.applied_about_pivot);
            let modes = &state.surface_modes[i];
            let root = s
                .structure
                .root_loads()
                .ok_or_else(|| err(ModelError::inconsistent("coupling", "no root loads")))?
                .root_loads(
                    &modes.q,
                    &modes.q_dot,
                    &self.q_ddot[i],
                    &s.applied_surface_frame,
                )
                .map_err(&err)?;
            let force = rotation * root.force_n;
            let moment = rotation * root.moment_nm;
            let scale = force.norm().max(s.root_force_n.norm()).max(1.0);
            change = change.max((force - s.root_force_n).norm() / scale);
            s.root_force_n = force;
            self.loads.surface_root_loads[i] = Loads {
                force_n: force,
                moment_nm: moment,
            };
            aero = aero
                + Loads {
                    force_n: applied.force_n,
                    moment_nm: applied.moment_nm + (s.pivot_m - cg).cross(&applied.force_n),
                };
            total = total
                + Loads {
                    force_n: force,
                    moment_nm: moment + (s.pivot_m - cg).cross(&force),
                };
        }
        self.loads.body = total;
        self.aero_with_surfaces = aero;
        Ok(change)
    }

    /// The state derivative at `state` under `controls` into `out` (buffers from
    /// `dynamics().zero_derivative()`), with the body-surface coupling converged (module docs).
    pub fn derivative(
        &mut self,
        state: &VehicleState,
        controls: &FlightControls,
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        let flight = self.flight(state)?;
        self.region_loads(state, controls, &flight)?;
        self.close_interface(state, out)
    }

    /// The body-surface interface closed on the region loads of the last evaluation: the
    /// fixed point of (q̈, η̈) with Aitken's relaxation (module docs), the derivative into `out`.
    fn close_interface(
        &mut self,
        state: &VehicleState,
        out: &mut VehicleDerivative,
    ) -> Result<(), VehicleError> {
        let body_without_roots = self.loads.body;
        let n_surfaces = self.surfaces.len();
        let mut residual = f64::INFINITY;
        self.acceleration.reset();
        for iteration in 1..=self.settings.max_iterations.max(1) {
            residual = self.add_root_loads(state, &body_without_roots)?;
            self.loads
                .body_modal_acceleration
                .copy_from(&self.body_q_ddot);
            self.dynamics.derivative(state, &self.loads, out)?;
            // The body's side of the interface: η̈ against its iterate, relative to the η̈ that
            // moves a pivot by 1 g.
            let body_change = out
                .body_modes
                .q_ddot
                .iter()
                .zip(self.body_q_ddot.iter())
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
                / self.body_q_ddot_scale;
            residual = residual.max(body_change);
            if n_surfaces == 0 || (iteration > 1 && residual <= self.settings.tolerance) {
                self.report = CouplingReport {
                    iterations: iteration,
                    residual,
                };
                return Ok(());
            }
            // The (q̈, η̈) update, accelerated (`[coupling] acceleration`; both are
            // mass-normalized modal accelerations, so one inner product weighs them alike).
            gather(
                &mut self.iterate,
                self.q_ddot.iter().chain(std::iter::once(&self.body_q_ddot)),
            );
            gather(
                &mut self.produced,
                out.surface_modes
                    .iter()
                    .map(|m| &m.q_ddot)
                    .chain(std::iter::once(&out.body_modes.q_ddot)),
            );
            self.acceleration.update(&mut self.iterate, &self.produced);
            scatter(
                &self.iterate,
                self.q_ddot
                    .iter_mut()
                    .chain(std::iter::once(&mut self.body_q_ddot)),
            );
        }
        self.report = CouplingReport {
            iterations: self.settings.max_iterations,
            residual,
        };
        Err(VehicleError::Coupling {
            iterations: self.settings.max_iterations,
            interfaces: self
                .surfaces
                .iter()
                .map(|s| s.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            residuals: vec![residual],
            tolerance: self.settings.tolerance,
        })
    }

    /// The assembled structure's in-vacuo modes (no aero, engine or gravity load; the vehicle
    /// free in space): the elastic accelerations ẍ = −M̃⁻¹ K x of the partitioned equations with
    /// the interface closed, column by column for unit modal coordinates, give the condensed
    /// mass M̃ = K (M̃⁻¹ K)⁻¹ (the rigid motion eliminated), and K v = ω² M̃ v its modes. The
    /// surfaces are undeflected and at their current stiffness. Leaves the flight's coupling
    /// guess and settings as it found them. Allocates (an analysis, not the time loop).
    pub fn in_vacuo_modes(&mut self) -> Result<InVacuoModes, VehicleError> {
        let guess = self.coupling_guess();
        let settings = self.settings;
        // Ten times the linearization's tolerance: with many body modes the fixed point stalls
        // near 1e-12 in rounding; the condensed mass stays symmetric to ~1e-9 at 1e-11.
        self.settings = CouplingSettings {
            tolerance: 10.0 * LINEARIZATION_TOLERANCE,
            max_iterations: 400,
        };
        let result = self.in_vacuo_modes_inner();
        self.settings = settings;
        self.set_coupling_guess(&guess)?;
        result
    }

    fn in_vacuo_modes_inner(&mut self) -> Result<InVacuoModes, VehicleError> {
        let zero = self.dynamics.zero_loads();
        self.loads = zero;
        self.aero_loads = Loads::default();
        for s in &mut self.surfaces {
            s.applied_surface_frame = Loads::default();
            s.applied_about_pivot = Loads::default();
            s.elevon_rotation = nalgebra::Rotation3::identity();
        }
        let base = self.dynamics.zero_state();
        let n_body = base.body_modes.n_modes();
        let sizes: Vec<usize> = std::iter::once(n_body)
            .chain(base.surface_modes.iter().map(|m| m.n_modes()))
            .collect();
        let n: usize = sizes.iter().sum();
        let mut stiffness = nalgebra::DMatrix::zeros(n, n);
        let (_, _, k_body) = self.dynamics.body_modes().matrices();
        stiffness
            .view_mut((0, 0), (n_body, n_body))
            .copy_from(k_body);
        let mut start = n_body;
        for s in &self.surfaces {
            let k = &s.structure.modal_model().stiffness;
            stiffness
                .view_mut((start, start), (k.nrows(), k.ncols()))
                .copy_from(k);
            start += k.nrows();
        }
        // D = M̃⁻¹ K, column j from the accelerations at coordinate j = ±1: central differences
        // cancel the quadratic terms (the surfaces' pivot moved by the body's modes turning
        // with the rigid body, α × d), leaving the linear structure.
        let mut flexibility_rate = nalgebra::DMatrix::zeros(n, n);
        let mut out = self.dynamics.zero_derivative();
        for j in 0..n {
            for sign in [1.0, -1.0] {
                let mut state = base.clone();
                set_elastic_coordinate(&mut state, j, sign);
                // close_interface adds the root loads to the body's: each column starts unloaded.
                self.loads.body = Loads::default();
                self.close_interface(&state, &mut out)?;
                for i in 0..n {
                    flexibility_rate[(i, j)] -= 0.5 * sign * elastic_acceleration(&out, n_body, i);
                }
            }
        }
        let inverse = flexibility_rate.clone().try_inverse().ok_or_else(|| {
            VehicleError::Input("in-vacuo modes: the coupled accelerations are singular".into())
        })?;
        let mass = &stiffness * inverse;
        let scale = mass.amax().max(f64::MIN_POSITIVE);
        let mass_asymmetry = (&mass - mass.transpose()).amax() / scale;
        let pairs = hsv_core::linalg::generalized_symmetric_eigen(&stiffness, &mass, n)
            .map_err(|e| VehicleError::Input(format!("in-vacuo modes: {e}")))?;
        let mut names = vec!["main_body".to_owned()];
        names.extend(self.surfaces.iter().map(|s| s.name.clone()));
        let modes = (0..pairs.values.len())
            .map(|m| {
                let v = pairs.vectors.column(m);
                let total = (v.transpose() * &stiffness * v)[(0, 0)];
                let mut start = 0;
                let shares = sizes
                    .iter()
                    .map(|&len| {
                        let block = v.rows(start, len);
                        let k = stiffness.view((start, start), (len, len));
                        start += len;
                        (block.transpose() * k * block)[(0, 0)] / total
                    })
                    .collect();
                InVacuoMode {
                    frequency_hz: pairs.values[m].max(0.0).sqrt() / std::f64::consts::TAU,
                    strain_energy_shares: shares,
                }
            })
            .collect();
        Ok(InVacuoModes {
            regions: names,
            modes,
            mass_asymmetry,
        })
    }

    /// Brings the modal coordinates of the body and the surfaces to static equilibrium at the
    /// state's rigid motion (q̇ = 0): q ← q + ω K⁻¹ M q̈ until every modal acceleration is below
    /// `tolerance` (1/s²), which includes aero, engine, gravity and inertial relief through the
    /// root motion. Returns the iterations. Allocates (trim and start-up only).
    ///
    /// ω = 1 first (the plain fixed point q ← K⁻¹ F(q)); when it fails, again from the same
    /// start under-relaxed, ω = 1/2 then 1/4. With J = K⁻¹ ∂F/∂q the relaxed iteration's
    /// factors are 1 − ω (1 − λ(J)): aero loads that stiffen the structure strongly (λ < −1)
    /// make the plain iteration overshoot and diverge while a relaxed one converges; λ > 1 is
    /// static divergence, and no relaxation converges (the plain iteration's error is returned).
    pub fn settle(
        &mut self,
        state: &mut VehicleState,
        controls: &FlightControls,
        tolerance: f64,
        max_iterations: usize,
        out: &mut VehicleDerivative,
    ) -> Result<usize, VehicleError> {
        let start = state.clone();
        let plain = self.settle_relaxed(state, controls, tolerance, max_iterations, 1.0, out);
        let Err(plain_error) = plain else {
            return plain;
        };
        for relaxation in [0.5, 0.25] {
            state.clone_from(&start);
            if let Ok(iterations) =
                self.settle_relaxed(state, controls, tolerance, max_iterations, relaxation, out)
            {
                return Ok(iterations);
            }
        }
        state.clone_from(&start);
        Err(plain_error)
    }

    /// [`Self::settle`] at one relaxation factor ω.
    fn settle_relaxed(
        &mut self,
        state: &mut VehicleState,
        controls: &FlightControls,
        tolerance: f64,
        max_iterations: usize,
        relaxation: f64,
        out: &mut VehicleDerivative,
    ) -> Result<usize, VehicleError> {
        let body_k_m = {
            let (m, _, k) = self.dynamics.body_modes().matrices();
            k.clone().lu().solve(m)
        };
        let surface_k_m: Vec<Option<nalgebra::DMatrix<f64>>> = self
            .surfaces
            .iter()
            .map(|s| {
                let modal = s.structure.modal_model();
                modal.stiffness.clone().lu().solve(&modal.mass)
            })
            .collect();
        state.body_modes.q_dot.fill(0.0);
        for m in &mut state.surface_modes {
            m.q_dot.fill(0.0);
        }
        for iteration in 1..=max_iterations.max(1) {
            self.derivative(state, controls, out)?;
            let mut largest: f64 = out.body_modes.q_ddot.amax();
            for rate in &out.surface_modes {
                largest = largest.max(rate.q_ddot.amax());
            }
            if largest <= tolerance {
                return Ok(iteration);
            }
            if let Some(km) = &body_k_m {
                state.body_modes.q += relaxation * (km * &out.body_modes.q_ddot);
            }
            for (i, km) in surface_k_m.iter().enumerate() {
                if let Some(km) = km {
                    state.surface_modes[i].q += relaxation * (km * &out.surface_modes[i].q_ddot);
                }
            }
        }
        Err(VehicleError::Model {
            region: "vehicle".to_owned(),
            source: ModelError::inconsistent(
                "static elastic equilibrium",
                format!(
                    "modal accelerations still above {tolerance} 1/s^2 after {max_iterations} \
                     iterations (a surface near buckling or divergence?)"
                ),
            ),
        })
    }

    /// The state of steady level flight at `mach`, `altitude_m` and `alpha_rad` with the modes
    /// at static equilibrium under `controls`.
    pub fn level_flight_state(
        &mut self,
        mach: f64,
        altitude_m: f64,
        alpha_rad: f64,
        controls: &FlightControls,
    ) -> Result<(VehicleState, VehicleDerivative), VehicleError> {
        let airspeed_m_s = Freestream::standard(mach, altitude_m, self.gas)
            .map_err(model_error("main_body"))?
            .velocity_m_s;
        // Start from the last equilibrium: trim evaluates nearby controls one after another.
        let mut state = self
            .warm_start
            .take()
            .unwrap_or_else(|| self.dynamics.zero_state());
        state.rigid = self
            .dynamics
            .rigid_body()
            .level_flight(altitude_m, airspeed_m_s, alpha_rad);
        let mut out = self.dynamics.zero_derivative();
        self.settle(&mut state, controls, 1e-6, 200, &mut out)?;
        self.warm_start = Some(state.clone());
        Ok((state, out))
    }
}

impl super::rigid::SteadyFlight for PartitionedVehicle {
    fn steady_accelerations(
        &mut self,
        mach: f64,
        altitude_m: f64,
        c: &super::rigid::Controls,
    ) -> Result<(super::rigid::Accelerations, super::rigid::RigidLoads), ModelError> {
        let controls = FlightControls {
            elevon: ElevonCommand {
                symmetric_rad: c.elevon_rad,
                differential_rad: 0.0,
            },
            fuel_equivalence_ratio: c.fuel_equivalence_ratio,
        };
        let (state, out) = self
            .level_flight_state(mach, altitude_m, c.alpha_rad, &controls)
            .map_err(|e| ModelError::inconsistent("flexible vehicle", e.to_string()))?;
        self.trim_modes = state.body_modes.q.iter().copied().collect();
        let a = out.rigid.acceleration_body_m_s2;
        let wind =
            hsv_core::frames::wind_axis_forces(&self.aero_with_surfaces.force_n, c.alpha_rad, 0.0);
        let loads = super::rigid::RigidLoads {
            total: self.loads.body,
            drag_n: wind.drag_n,
            thrust_n: self.engine_solution.loads.force_n.x,
            engine_status: self.engine_solution.status,
            ..Default::default()
        };
        Ok((
            super::rigid::Accelerations {
                u_dot_m_s2: a.x,
                w_dot_m_s2: a.z,
                q_dot_rad_s2: out.rigid.angular_acceleration_body_rad_s2.y,
            },
            loads,
        ))
    }

    fn mass_kg(&self) -> f64 {
        self.mass.mass_kg
    }

    fn gas(&self) -> PerfectGas {
        self.gas
    }

    fn modal_amplitudes(&self) -> Vec<(String, f64)> {
        let names = &self.body_mode_names;
        names
            .iter()
            .cloned()
            .zip(self.trim_modes.iter().copied())
            .collect()
    }
}
