//! The partitioned vehicle assembled from its regions' models: mass properties, the body's and
//! the surfaces' modes, the attachments and the regions' buffers.

use super::*;

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
        let mut histories = Vec::new();
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
            let is_fin = matches!(set.info.geometry, RegionGeometry::VerticalFin(_));
            if (monolithic && is_surface) || is_fin {
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
                        published_generalized: vec![0.0; n],
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
                    histories.push(history);
                    surfaces.push(Surface {
                        thermal,
                        friction: set.friction.map(|m| RegionFriction::new(m, n_panels)),
                        held_friction: None,
                        applied_surface_frame: Loads::default(),
                        name: name.clone(),
                        rigid: set.info.mesh.clone(),
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
            let elevon = match &set.info.geometry {
                RegionGeometry::LiftingSurface { planform, side } => {
                    Some((planform.clone(), *side))
                }
                _ => None,
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
                elevon,
                loads: Loads::default(),
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
        let surface_names: Vec<String> = surfaces.iter().map(|s| s.name.clone()).collect();
        let n_surfaces = surfaces.len();
        let exchange = RegionExchange::new(
            &surface_names,
            RegionLoadRate::default(),
            RegionLoadRate::Interval(DEFAULT_BODY_FRICTION_DT_S),
            RegionLoadRate::EveryStage,
            HeatingRates::default().heat_flux_s,
        )?;
        Ok(Self {
            memory: VehicleMemory {
                time_s: 0.0,
                root_force_n: vec![Vector3::zeros(); q_ddot.len()],
                q_ddot,
                histories,
                coupling: CouplingReport::default(),
                body_q_ddot: DVector::zeros(body_modal.n_modes()),
            },
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
            engine: engine.map(|model| Engine::new(model, body_modal.n_modes())),
            mass,
            reference_point_m,
            gas,
            settings,
            loads,
            surface_reads: vec![SurfaceRead::default(); n_surfaces],
            interface_residuals: vec![0.0; n_surfaces + 1],
            warm_start: None,
            heating: HeatingRates::default(),
            aero_loads: Loads::default(),
            aero_with_surfaces: Loads::default(),
            body_mode_names: body_modal_names,
            trim_modes: Vec::new(),
            body_rate: RegionLoadRate::default(),
            body_friction_rate: RegionLoadRate::Interval(DEFAULT_BODY_FRICTION_DT_S),

            surface_rate: RegionLoadRate::EveryStage,
            exchange,
            stage_one: None,
            stage_one_state: VehicleState::default(),
            disturbances: Disturbances::default(),
            surface_flights: Vec::new(),
        })
    }
}
