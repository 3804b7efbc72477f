//! The vehicle as one rigid body in steady flight: every region's loads at a flight condition,
//! elevon and fuel equivalence ratio, summed about the centre of mass, and the accelerations of
//! paper Eq. 1 without the modal part (what trim drives to zero).
//!
//! Ownership of the wetted surface: the main body's aero model loads the panels tagged
//! [`RegionKind::MainBody`], each lifting surface's aero model its [`RegionKind::LiftingSurface`]
//! panels (deflected about the pivot by the elevon), and the engine the body panels tagged
//! [`RegionKind::Propulsion`]; caps ([`RegionKind::Other`]) close meshes and carry no load. So no
//! surface is counted twice. A vehicle without a propulsion region (a glide) has no engine: its
//! body aero loads the engine's panels as well, and the duct is flow-through with no inner load.

use hsv_core::aero::{AeroModel, AeroSolution, Loads, PanelMotion, integrate_pressure};
use hsv_core::atmosphere::gravity;
use hsv_core::coupling::{ElevonCommand, deflect_lifting_surface};
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::frames;
use hsv_core::gas::PerfectGas;
use hsv_core::geometry::{LiftingSurfaceConfig, Side};
use hsv_core::mesh::{PanelMesh, RegionKind};
use hsv_core::propulsion::{EngineInputs, EngineStatus, PropulsionModel, PropulsionSolution};
use hsv_core::region::RegionGeometry;
use hsv_core::structure::{Capability, MassProperties};
use nalgebra::{Point3, Vector3};

use super::friction::RegionFriction;
use super::{AnalysisNeeds, AssemblyError, RegionModelSet, RegionNeeds};
use hsv_core::registry::Role;

/// What the rigid vehicle needs of its regions: aero on the body and both surfaces, mass
/// properties from every structure, an engine if the vehicle has a propulsion region, aero on
/// the vertical fin if it has one.
pub fn rigid_needs(analysis: &str) -> AnalysisNeeds {
    let with_mass = |roles: Vec<Role>| RegionNeeds {
        roles,
        structure: vec![Capability::MassProperties],
        friction: true,
    };
    AnalysisNeeds {
        analysis: analysis.to_owned(),
        regions: vec![
            ("main_body", with_mass(vec![Role::Aero, Role::Structure])),
            ("left_surface", with_mass(vec![Role::Aero, Role::Structure])),
            (
                "right_surface",
                with_mass(vec![Role::Aero, Role::Structure]),
            ),
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

/// The controls of steady flight.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Controls {
    /// Angle of attack, rad.
    pub alpha_rad: f64,
    /// Symmetric elevon deflection, rad (positive: trailing edge up, nose up).
    pub elevon_rad: f64,
    /// Fuel equivalence ratio φ (ignored by a vehicle without an engine).
    pub fuel_equivalence_ratio: f64,
    /// Flight-path angle γ, rad (0: level flight; negative: descending). The pitch angle is
    /// θ = α + γ, which sets where the weight acts in body axes.
    pub flight_path_angle_rad: f64,
}

/// Loads of one evaluation, body axes, moments about the centre of mass.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct RigidLoads {
    pub body_aero: Loads,
    pub surface_aero: Loads,
    pub engine: Loads,
    pub gravity: Loads,
    pub total: Loads,
    /// Drag (along −V) of the aero loads, skin friction included, N.
    pub drag_n: f64,
    /// The skin-friction part of the drag, N.
    pub friction_drag_n: f64,
    /// Engine thrust (body x), N.
    pub thrust_n: f64,
    pub engine_status: EngineStatus,
}

/// Accelerations of steady wings-level flight (paper Eq. 2's minimized set): u̇, ẇ (m/s², body
/// axes) and q̇ (rad/s²).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Accelerations {
    pub u_dot_m_s2: f64,
    pub w_dot_m_s2: f64,
    pub q_dot_rad_s2: f64,
}

impl Accelerations {
    /// J = u̇² + ẇ² + q̇² (paper Eq. 2, identity weights; SI units).
    pub fn cost(&self) -> f64 {
        self.u_dot_m_s2.powi(2) + self.w_dot_m_s2.powi(2) + self.q_dot_rad_s2.powi(2)
    }
}

/// One lifting surface, or the fixed vertical fin: its undeflected mesh, aero model, and for an
/// all-movable surface the planform and side the elevon rotates it by.
struct Surface {
    friction: Option<RegionFriction>,
    mesh: PanelMesh,
    deflected: PanelMesh,
    elevon: Option<(LiftingSurfaceConfig, Side)>,
    aero: Box<dyn AeroModel>,
}

/// The whole vehicle as a rigid body (module docs).
pub struct RigidVehicle {
    body_friction: Option<RegionFriction>,
    body_mesh: PanelMesh,
    body_aero: Box<dyn AeroModel>,
    surfaces: Vec<Surface>,
    /// `None` without a propulsion region (a glide): the body aero loads the engine's panels.
    engine: Option<Box<dyn PropulsionModel>>,
    mass: MassProperties,
    reference_point_m: Point3<f64>,
    gas: PerfectGas,
    solution: AeroSolution,
    engine_solution: PropulsionSolution,
}

fn missing(region: &str, what: &str) -> AssemblyError {
    AssemblyError::Model {
        file: String::new(),
        region: region.to_owned(),
        cause: format!("the rigid vehicle needs {what}").into(),
    }
}

impl RigidVehicle {
    /// The rigid vehicle from assembled regions (checked with [`rigid_needs`]).
    pub fn new(sets: Vec<RegionModelSet>) -> Result<Self, AssemblyError> {
        let mut body = None;
        let mut body_friction = None;
        let mut engine = None;
        let mut surfaces = Vec::new();
        let mut mass: Option<MassProperties> = None;
        let mut reference_point_m = Point3::origin();
        let mut gas = PerfectGas::AIR;
        for set in sets {
            let region = set.info.name.clone();
            if let Some(structure) = &set.structure
                && let Some(m) = structure.mass_properties()
            {
                let m = m.mass_properties();
                mass = Some(mass.map_or(m, |total| total.combined(&m)));
            }
            reference_point_m = set.info.reference.moment_point();
            gas = set.info.gas;
            match (&set.info.geometry, region.as_str()) {
                (_, "main_body") => {
                    let aero = set.aero.ok_or_else(|| missing(&region, "an aero model"))?;
                    let n = set.info.mesh.panels.len();
                    body_friction = set.friction.map(|m| RegionFriction::new(m, n));
                    body = Some((set.info.mesh, aero));
                }
                (_, "propulsion") => {
                    engine = Some(
                        set.propulsion
                            .ok_or_else(|| missing(&region, "a propulsion model"))?,
                    );
                }
                (RegionGeometry::LiftingSurface { .. } | RegionGeometry::VerticalFin(_), _) => {
                    let elevon = match &set.info.geometry {
                        RegionGeometry::LiftingSurface { planform, side } => {
                            Some((planform.clone(), *side))
                        }
                        _ => None,
                    };
                    let aero = set.aero.ok_or_else(|| missing(&region, "an aero model"))?;
                    let n = set.info.mesh.panels.len();
                    surfaces.push(Surface {
                        friction: set.friction.map(|m| RegionFriction::new(m, n)),
                        deflected: set.info.mesh.clone(),
                        mesh: set.info.mesh,
                        elevon,
                        aero,
                    });
                }
                _ => {}
            }
        }
        let (body_mesh, body_aero) = body.ok_or_else(|| missing("main_body", "the region"))?;
        Ok(Self {
            body_friction,
            body_mesh,
            body_aero,
            surfaces,
            engine,
            mass: mass.ok_or_else(|| missing("main_body", "mass properties"))?,
            reference_point_m,
            gas,
            solution: AeroSolution::default(),
            engine_solution: PropulsionSolution::default(),
        })
    }

    /// The gas the vehicle flies in.
    pub fn gas(&self) -> PerfectGas {
        self.gas
    }

    /// Mass, centre of mass and inertia of the whole vehicle.
    pub fn mass_properties(&self) -> &MassProperties {
        &self.mass
    }

    /// The flight condition of steady flight at `mach`, `altitude_m` and `alpha_rad`, rotating
    /// about the centre of mass.
    pub fn flight(
        &self,
        mach: f64,
        altitude_m: f64,
        alpha_rad: f64,
    ) -> Result<FlightCondition, hsv_core::ModelError> {
        let freestream = Freestream::standard(mach, altitude_m, self.gas)?;
        let mut flight = FlightCondition::steady(freestream, alpha_rad, 0.0);
        flight.rotation_center_m = self.mass.center_of_mass_m;
        Ok(flight)
    }

    /// Every region's loads and their sum about the centre of mass in steady wings-level
    /// flight (pitch angle θ = α + γ, no rates).
    pub fn loads(
        &mut self,
        mach: f64,
        altitude_m: f64,
        controls: &Controls,
    ) -> Result<RigidLoads, hsv_core::ModelError> {
        let flight = self.flight(mach, altitude_m, controls.alpha_rad)?;
        let cg = self.mass.center_of_mass_m;
        // Without an engine the body aero loads the engine's ramp and nozzle too.
        let powered = self.engine.is_some();
        let body_panels = |r: RegionKind| super::body_aero_loads(r, powered);
        let p_inf = flight.freestream.pressure_pa;
        self.body_aero.evaluate(
            &self.body_mesh,
            &flight,
            &PanelMotion::default(),
            &mut self.solution,
        )?;
        let mut body_aero = integrate_pressure(
            &self.body_mesh,
            &self.solution.pressure_pa,
            p_inf,
            &cg,
            body_panels,
        );
        let mut friction = Loads::default();
        if let Some(f) = &mut self.body_friction {
            friction = f.loads(
                &self.body_mesh,
                &flight,
                &self.solution,
                &PanelMotion::default(),
                &cg,
                body_panels,
            )?;
            body_aero = body_aero + friction;
        }
        let elevon = ElevonCommand {
            symmetric_rad: controls.elevon_rad,
            differential_rad: 0.0,
        };
        let mut surface_aero = Loads::default();
        for s in &mut self.surfaces {
            // The fixed fin has no elevon: its `deflected` mesh stays the undeflected one.
            if let Some((planform, side)) = &s.elevon {
                deflect_lifting_surface(
                    &s.mesh,
                    planform,
                    *side,
                    elevon.deflection_rad(*side),
                    &mut s.deflected,
                )
                .map_err(|e| hsv_core::ModelError::inconsistent("elevon", e.to_string()))?;
            }
            s.aero.evaluate(
                &s.deflected,
                &flight,
                &PanelMotion::default(),
                &mut self.solution,
            )?;
            surface_aero = surface_aero
                + integrate_pressure(&s.deflected, &self.solution.pressure_pa, p_inf, &cg, |r| {
                    r == RegionKind::LiftingSurface
                });
            if let Some(f) = &mut s.friction {
                let shear = f.loads(
                    &s.deflected,
                    &flight,
                    &self.solution,
                    &PanelMotion::default(),
                    &cg,
                    |r| r == RegionKind::LiftingSurface,
                )?;
                friction = friction + shear;
                surface_aero = surface_aero + shear;
            }
        }
        if let Some(engine) = &mut self.engine {
            engine.evaluate(
                &EngineInputs {
                    flight: &flight,
                    body: &self.body_mesh,
                    fuel_equivalence_ratio: controls.fuel_equivalence_ratio,
                },
                &mut self.engine_solution,
            )?;
        }
        // The engine gives its moment about the vehicle's reference point: move it to the CG.
        let engine_ref = self.engine_solution.loads;
        let engine = Loads {
            force_n: engine_ref.force_n,
            moment_nm: engine_ref.moment_nm
                + (self.reference_point_m - cg).cross(&engine_ref.force_n),
        };
        // Pitch θ = α + γ: the weight (down in earth axes) in body axes.
        let weight = self.mass.mass_kg * gravity(altitude_m);
        let pitch_rad = controls.alpha_rad + controls.flight_path_angle_rad;
        let gravity_loads = Loads {
            force_n: frames::earth_to_body(0.0, pitch_rad, 0.0) * Vector3::new(0.0, 0.0, weight),
            moment_nm: Vector3::zeros(),
        };
        let aero = body_aero + surface_aero;
        let drag_n = frames::wind_axis_forces(&aero.force_n, controls.alpha_rad, 0.0).drag_n;
        let total = aero + engine + gravity_loads;
        for (what, v) in [
            ("total force", total.force_n),
            ("total moment", total.moment_nm),
        ] {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(hsv_core::ModelError::NonFinite {
                    model: "rigid vehicle".to_owned(),
                    quantity: what.to_owned(),
                    location: format!(
                        " at alpha {:.4} deg, elevon {:.4} deg, phi {:.4}",
                        controls.alpha_rad.to_degrees(),
                        controls.elevon_rad.to_degrees(),
                        controls.fuel_equivalence_ratio
                    ),
                });
            }
        }
        Ok(RigidLoads {
            friction_drag_n: frames::wind_axis_forces(&friction.force_n, controls.alpha_rad, 0.0)
                .drag_n,
            body_aero,
            surface_aero,
            engine,
            gravity: gravity_loads,
            total,
            drag_n,
            thrust_n: engine.force_n.x,
            engine_status: self.engine_solution.status,
        })
    }

    /// u̇, ẇ and q̇ of steady level flight (paper Eq. 1 with zero rates: u̇ = F_x/m,
    /// ẇ = F_z/m, q̇ = M_y/I_yy about the centre of mass).
    pub fn accelerations(
        &mut self,
        mach: f64,
        altitude_m: f64,
        controls: &Controls,
    ) -> Result<(Accelerations, RigidLoads), hsv_core::ModelError> {
        let loads = self.loads(mach, altitude_m, controls)?;
        let m = self.mass.mass_kg;
        let i_yy = self.mass.inertia_kg_m2[(1, 1)];
        Ok((
            Accelerations {
                u_dot_m_s2: loads.total.force_n.x / m,
                w_dot_m_s2: loads.total.force_n.z / m,
                q_dot_rad_s2: loads.total.moment_nm.y / i_yy,
            },
            loads,
        ))
    }
}

/// A model trim can drive: the accelerations of steady flight at given controls.
pub trait SteadyFlight {
    /// u̇, ẇ, q̇ and the loads at `controls` and the request's Mach and altitude.
    fn steady_accelerations(
        &mut self,
        mach: f64,
        altitude_m: f64,
        controls: &Controls,
    ) -> Result<(Accelerations, RigidLoads), hsv_core::ModelError>;

    /// Mass of the vehicle, kg (reported).
    fn mass_kg(&self) -> f64;

    /// The gas the vehicle flies in (the trim's freestream, for its envelope checks).
    fn gas(&self) -> PerfectGas;

    /// Body modal amplitudes at the last evaluated point (empty for a rigid vehicle).
    fn modal_amplitudes(&self) -> Vec<(String, f64)> {
        Vec::new()
    }

    /// Whether the vehicle has an engine (without one, steady flight is a glide).
    fn powered(&self) -> bool;
}

impl SteadyFlight for RigidVehicle {
    fn steady_accelerations(
        &mut self,
        mach: f64,
        altitude_m: f64,
        controls: &Controls,
    ) -> Result<(Accelerations, RigidLoads), hsv_core::ModelError> {
        self.accelerations(mach, altitude_m, controls)
    }

    fn mass_kg(&self) -> f64 {
        self.mass_properties().mass_kg
    }

    fn gas(&self) -> PerfectGas {
        RigidVehicle::gas(self)
    }

    fn powered(&self) -> bool {
        self.engine.is_some()
    }
}
