//! Coupling helpers: what the runner hands between regions and grids — generalized (modal)
//! forces from panel pressures, rigid rotation of a lifting surface about its torque tube
//! (elevon commands), and the temperature transfer from the conduction grid to the structural
//! grid.
//!
//! **Generalized forces.** For mode i with displacement φ_i, the virtual work of the pressure on
//! the outer mold line gives Q_i = −Σ_panels (p − p_ref) A n · φ_i(panel), with φ_i at a panel the
//! mean of its vertices' displacement (the rule of [`ModeShapes::panel_velocities`], so the
//! aero's elastic panel velocity and the force it does work against use the same φ). The rigid
//! force and moment are [`integrate_pressure`]'s F = −Σ (p − p_ref) A n, M = Σ (r − r_0) × F:
//! a rigid translation mode φ = e_k gives Q = F_k, a rigid rotation φ = e_k × (r − r_0) gives
//! Q = M_k (to the vertex-mean rule). Reference: Thomson, *Theory of Vibration with
//! Applications* (Taylor & Francis, 2010), Eq. (11.1-10): Q_i = ∫ p φ_i from the virtual work.
//!
//! **Linear structure.** [`ModalProjection`] freezes A n · φ_i on the reference (undeformed)
//! geometry, so each time step is one mat-vec. That neglects the rotation of the panels with
//! the deformation (follower-force terms of order q), which is the small-displacement
//! assumption the linear modal structure already makes. [`generalized_forces`] sums on whatever
//! geometry it is given: pass the deformed mesh for the exact deformed-geometry sum.
//!
//! **Deflected surfaces.** The modes of a lifting surface turn with it about the torque tube,
//! and A n · φ is unchanged when n and φ turn by the same rotation. So its generalized forces
//! are summed on the undeflected geometry (the [`ModalProjection`] of the reference mesh, or
//! [`generalized_forces`] on the elastically deformed mesh before the rotation) with the
//! pressures computed on the deflected mesh, whose panel order the rotation keeps. The rotated
//! mesh with unrotated shapes would be wrong.
//!
//! **Rotation about the torque tube.** Each all-movable lifting surface turns rigidly about
//! its pivot axis, parallel to body y through [`pivot_point`]. Positive elevon deflection gives
//! a nose-up pitching moment (DESIGN §4): for a surface aft of the centre of gravity that is
//! trailing edge up (negative incidence, lift down on the tail). In body axes (x forward, y
//! right, z down) a right-handed rotation θ about +y maps a trailing-edge offset (−d, 0, 0)
//! from the pivot to (−d cos θ, 0, d sin θ), i.e. trailing edge down for θ > 0; so deflection δ
//! is the rotation θ = −δ about +y. Per side, left = δe + δa and right = δe − δa; a positive
//! differential therefore raises the left trailing edge and lowers the right one, a negative
//! (left-wing-down) rolling moment.
//!
//! **Temperature transfer.** [`GridTransfer`] moves node temperatures from the conduction
//! model's [`SurfaceGrid`] to the structure's grid of the same planform (any resolutions): each
//! target node is located in the source grid ([`SurfaceGrid::map_points`], the same location
//! [`SurfaceGrid::resample`] uses) and gets the bilinear interpolation of the source cell's four
//! node values ([`SurfaceGrid::interpolate`]). The map is built once; every transfer is then
//! allocation-free, and a target node off the source planform (the other side's grid, a
//! different planform) is an error at construction instead of a silent clamp.
//! [`StructureTemperatures`] is the whole conduction-to-structure step every heating loop
//! takes: node mean and difference temperatures, moved, set on the structure's stiffness.

use nalgebra::{DMatrix, DVector, Point3, Rotation3, Unit, Vector3};

use crate::aero::{Loads, integrate_pressure};
use crate::error::ModelError;
use crate::geometry::{LiftingSurfaceConfig, Side, pivot_point};
use crate::mesh::{MeshError, ModeShapes, Panel, PanelMesh, RegionKind};
use crate::structure::ThermalStiffness;
use crate::surface_grid::{GridError, GridPoint, SurfaceGrid};
use crate::thermal::ConductionModel;

/// Why a coupling quantity could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CouplingError {
    /// A buffer does not fit the mesh, modes or grid it goes with.
    #[error("coupling: {quantity} has {len} entries, expected {expected}")]
    Length {
        quantity: &'static str,
        len: usize,
        expected: usize,
    },
    /// An input or result is NaN or infinite.
    #[error("coupling: {quantity} is non-finite ({value}) at index {index}")]
    NonFinite {
        quantity: &'static str,
        index: usize,
        value: f64,
    },
    /// An argument outside its allowed range.
    #[error("coupling: {quantity} = {value} is outside its range ({allowed})")]
    OutOfRange {
        quantity: &'static str,
        value: f64,
        allowed: &'static str,
    },
    /// Conduction temperatures that cannot reach a structure's nodes: neither shares the other's
    /// nodes nor has a grid to transfer them.
    #[error(
        "coupling: the conduction model's {conduction_nodes} node temperatures have no grid to \
         transfer them onto the structure's {structure_nodes} temperature nodes"
    )]
    NoTemperatureTransfer {
        conduction_nodes: usize,
        structure_nodes: usize,
    },
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Grid(#[from] GridError),
}

fn check_len(quantity: &'static str, len: usize, expected: usize) -> Result<(), CouplingError> {
    if len == expected {
        Ok(())
    } else {
        Err(CouplingError::Length {
            quantity,
            len,
            expected,
        })
    }
}

/// The first non-finite entry of `values`, as an error naming `quantity`.
fn check_finite(quantity: &'static str, values: &[f64]) -> Result<(), CouplingError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(CouplingError::NonFinite {
            quantity,
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

/// Results are finite unless the pressure was: name the pressure (the cause) before the result.
fn check_generalized_forces(pressure_pa: &[f64], out: &[f64]) -> Result<(), CouplingError> {
    if out.iter().all(|q| q.is_finite()) {
        return Ok(());
    }
    check_finite("panel pressure (Pa)", pressure_pa)?;
    check_finite("generalized force", out)
}

/// Whether `panel`'s surface belongs to a region `include` accepts (as [`integrate_pressure`]).
fn included(mesh: &PanelMesh, panel: &Panel, include: &impl Fn(RegionKind) -> bool) -> bool {
    mesh.surfaces
        .get(usize::from(panel.surface))
        .is_some_and(|s| include(s.region))
}

/// A n · φ_k of one panel, m³ per unit modal coordinate: its generalized force per unit
/// gauge pressure is the negative of this.
fn panel_projection(shapes: &ModeShapes, panel: &Panel, mode: usize) -> f64 {
    panel.area_m2 * panel.normal.dot(&shapes.panel_displacement(panel, mode))
}

/// Q_k = −Σ (p − p_ref) A n · φ_k over the panels whose region passes `include`, on the geometry
/// of `mesh` as given (pass the deformed mesh for the exact deformed-geometry sum), into `out`
/// (one entry per mode).
///
/// Summed as Q_k = Σ_v F_v · φ_k(v): each panel's force −(p − p_ref) A n goes in equal shares to
/// its vertices (φ at a panel is its vertices' mean), then one pass down each contiguous mode
/// column; the same sum in another order, about four times fewer multiplications than
/// averaging φ per panel and mode. The vertex buffer is per thread: it allocates on a thread's
/// first call (and when a larger mesh comes), never after.
pub fn generalized_forces(
    mesh: &PanelMesh,
    shapes: &ModeShapes,
    pressure_pa: &[f64],
    reference_pressure_pa: f64,
    include: impl Fn(RegionKind) -> bool,
    out: &mut [f64],
) -> Result<(), CouplingError> {
    shapes.check(mesh)?;
    check_len("panel pressure (Pa)", pressure_pa.len(), mesh.panels.len())?;
    check_len("generalized-force buffer", out.len(), shapes.n_modes())?;
    out.fill(0.0);
    VERTEX_FORCE_SCRATCH.with_borrow_mut(|vertex_force| {
        vertex_force.clear();
        vertex_force.resize(shapes.vertex_displacement.nrows(), 0.0);
        for (panel, &p) in mesh.panels.iter().zip(pressure_pa) {
            if !included(mesh, panel, &include) {
                continue;
            }
            let idx = panel.vertex_indices();
            let share = -(p - reference_pressure_pa) * panel.area_m2 / idx.len() as f64;
            let force = panel.normal * share;
            for &v in idx {
                vertex_force[3 * v] += force.x;
                vertex_force[3 * v + 1] += force.y;
                vertex_force[3 * v + 2] += force.z;
            }
        }
        // Column-major storage: mode k is the contiguous slice [k n_rows, (k+1) n_rows).
        let n_rows = vertex_force.len().max(1);
        let columns = shapes.vertex_displacement.as_slice().chunks_exact(n_rows);
        for (q, column) in out.iter_mut().zip(columns) {
            *q = vertex_force
                .iter()
                .zip(column)
                .map(|(f, phi)| f * phi)
                .sum();
        }
    });
    check_generalized_forces(pressure_pa, out)
}

thread_local! {
    /// Per-vertex force scratch (x, y, z interleaved) of [`generalized_forces`].
    static VERTEX_FORCE_SCRATCH: std::cell::RefCell<Vec<f64>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// Rigid loads ([`integrate_pressure`]: F = −Σ (p − p_ref) A n, M = Σ (r − r_0) × F about
/// `moment_point_m`) and the generalized forces of [`generalized_forces`] (into
/// `generalized_out`) of the same panels, on the geometry of `mesh` as given.
pub fn pressure_loads(
    mesh: &PanelMesh,
    shapes: &ModeShapes,
    pressure_pa: &[f64],
    reference_pressure_pa: f64,
    moment_point_m: &Point3<f64>,
    include: impl Fn(RegionKind) -> bool,
    generalized_out: &mut [f64],
) -> Result<Loads, CouplingError> {
    generalized_forces(
        mesh,
        shapes,
        pressure_pa,
        reference_pressure_pa,
        &include,
        generalized_out,
    )?;
    let loads = integrate_pressure(
        mesh,
        pressure_pa,
        reference_pressure_pa,
        moment_point_m,
        include,
    );
    check_finite("moment point (m)", moment_point_m.coords.as_slice())?;
    Ok(loads)
}

/// The panel-to-mode projection P_kj = A_j n_j · φ_k(panel j) on the reference geometry
/// (module docs: the linear-structure assumption), so Q = −P (p − p_ref) is one mat-vec.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalProjection {
    /// n_modes × n_panels, m³; zero columns for excluded panels.
    projection: DMatrix<f64>,
}

impl ModalProjection {
    /// Builds P on `reference_mesh` (undeformed) for the panels whose region passes `include`.
    pub fn new(
        reference_mesh: &PanelMesh,
        shapes: &ModeShapes,
        include: impl Fn(RegionKind) -> bool,
    ) -> Result<Self, CouplingError> {
        shapes.check(reference_mesh)?;
        let mut projection = DMatrix::zeros(shapes.n_modes(), reference_mesh.panels.len());
        for (j, panel) in reference_mesh.panels.iter().enumerate() {
            if !included(reference_mesh, panel, &include) {
                continue;
            }
            for k in 0..shapes.n_modes() {
                projection[(k, j)] = panel_projection(shapes, panel, k);
            }
        }
        Ok(Self { projection })
    }

    /// Number of modes (rows).
    pub fn n_modes(&self) -> usize {
        self.projection.nrows()
    }

    /// Number of panels (columns).
    pub fn n_panels(&self) -> usize {
        self.projection.ncols()
    }

    /// P, n_modes × n_panels, m³.
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.projection
    }

    /// Q = −P (p − p_ref) into `out` (one entry per mode). Allocates nothing.
    pub fn generalized_forces(
        &self,
        pressure_pa: &[f64],
        reference_pressure_pa: f64,
        out: &mut [f64],
    ) -> Result<(), CouplingError> {
        check_len("panel pressure (Pa)", pressure_pa.len(), self.n_panels())?;
        check_len("generalized-force buffer", out.len(), self.n_modes())?;
        out.fill(0.0);
        // Column-major P: one contiguous column per panel.
        for (j, &p) in pressure_pa.iter().enumerate() {
            let gauge = p - reference_pressure_pa;
            for (q, &pkj) in out.iter_mut().zip(self.projection.column(j).iter()) {
                *q -= gauge * pkj;
            }
        }
        check_generalized_forces(pressure_pa, out)
    }
}

/// The torque-tube (pivot) axis direction of both lifting surfaces: body +y.
pub fn pivot_axis() -> Unit<Vector3<f64>> {
    Vector3::y_axis()
}

/// The rotation by `angle_rad` about `axis` (right-handed; any non-zero length).
pub fn rotation_about_axis(
    axis: &Vector3<f64>,
    angle_rad: f64,
) -> Result<Rotation3<f64>, CouplingError> {
    if !angle_rad.is_finite() {
        return Err(CouplingError::OutOfRange {
            quantity: "rotation angle (rad)",
            value: angle_rad,
            allowed: "finite",
        });
    }
    let norm = axis.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(CouplingError::OutOfRange {
            quantity: "rotation axis length",
            value: norm,
            allowed: "finite and > 0",
        });
    }
    Ok(Rotation3::from_axis_angle(
        &Unit::new_unchecked(axis / norm),
        angle_rad,
    ))
}

/// r' = r_0 + R (r − r_0) for every point, into `out` (same length).
pub fn rotate_points(
    points: &[Point3<f64>],
    point_m: &Point3<f64>,
    rotation: &Rotation3<f64>,
    out: &mut [Point3<f64>],
) -> Result<(), CouplingError> {
    check_len("rotated-point buffer", out.len(), points.len())?;
    for (o, p) in out.iter_mut().zip(points) {
        *o = point_m + rotation * (p - point_m);
    }
    Ok(())
}

/// `mesh` rotated by `angle_rad` about the line through `point_m` along `axis`, into `out`, its
/// panel geometry recomputed by [`PanelMesh::update_geometry`].
///
/// Allocates nothing once `out` has `mesh`'s vertex and panel counts (the first call clones
/// `mesh` into `out`); vertices and panels are copied from `mesh` on every call, so `out` never
/// accumulates rotations.
pub fn rotate_about_axis(
    mesh: &PanelMesh,
    point_m: &Point3<f64>,
    axis: &Vector3<f64>,
    angle_rad: f64,
    out: &mut PanelMesh,
) -> Result<(), CouplingError> {
    let rotation = rotation_about_axis(axis, angle_rad)?;
    if out.vertices.len() != mesh.vertices.len() || out.panels.len() != mesh.panels.len() {
        out.clone_from(mesh);
    } else {
        out.panels.copy_from_slice(&mesh.panels);
    }
    rotate_points(&mesh.vertices, point_m, &rotation, &mut out.vertices)?;
    out.update_geometry();
    Ok(())
}

/// Node positions of `grid` rotated by `angle_rad` about the line through `point_m` along
/// `axis`, into `out` (one per node).
///
/// The grid itself stays in its reference (undeflected) placement: its planform maps
/// ([`SurfaceGrid::locate`]) are defined there, and the structure works in that frame.
pub fn rotate_grid_positions(
    grid: &SurfaceGrid,
    point_m: &Point3<f64>,
    axis: &Vector3<f64>,
    angle_rad: f64,
    out: &mut [Point3<f64>],
) -> Result<(), CouplingError> {
    let rotation = rotation_about_axis(axis, angle_rad)?;
    rotate_points(&grid.positions_m, point_m, &rotation, out)
}

/// Elevon command: symmetric (pitch) and differential (roll) deflection, rad. Positive
/// symmetric deflection is trailing edge up, nose-up pitching moment (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElevonCommand {
    /// δe, rad.
    pub symmetric_rad: f64,
    /// δa, rad.
    pub differential_rad: f64,
}

impl ElevonCommand {
    /// Deflection of the `side` surface: left δe + δa, right δe − δa, rad.
    pub fn deflection_rad(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.symmetric_rad + self.differential_rad,
            Side::Right => self.symmetric_rad - self.differential_rad,
        }
    }
}

/// Rotation angle about +y ([`pivot_axis`]) that deflects a surface by `deflection_rad`
/// (positive trailing edge up): θ = −δ (module docs).
pub fn elevon_rotation_angle_rad(deflection_rad: f64) -> f64 {
    -deflection_rad
}

/// The `side` lifting-surface mesh (undeflected, from
/// [`crate::geometry::lifting_surface_mesh`]) deflected by `deflection_rad` (positive trailing
/// edge up) about its torque tube through [`pivot_point`]`(cfg, side)`, into `out`.
pub fn deflect_lifting_surface(
    mesh: &PanelMesh,
    cfg: &LiftingSurfaceConfig,
    side: Side,
    deflection_rad: f64,
    out: &mut PanelMesh,
) -> Result<(), CouplingError> {
    rotate_about_axis(
        mesh,
        &pivot_point(cfg, side),
        &pivot_axis(),
        elevon_rotation_angle_rad(deflection_rad),
        out,
    )
}

/// Node positions of a lifting-surface grid deflected by `deflection_rad` (positive trailing
/// edge up) about its torque tube through `grid.pivot_m`, into `out` (one per node).
pub fn deflect_grid_positions(
    grid: &SurfaceGrid,
    deflection_rad: f64,
    out: &mut [Point3<f64>],
) -> Result<(), CouplingError> {
    rotate_grid_positions(
        grid,
        &grid.pivot_m,
        &pivot_axis(),
        elevon_rotation_angle_rad(deflection_rad),
        out,
    )
}

/// Node-value transfer from one [`SurfaceGrid`] to another of the same planform: T_target(n) =
/// Σ_k w_k T_source(node_k) with the bilinear weights of the source cell over target node n
/// (module docs). Exact for fields bilinear in each source cell, e.g. linear in x and y.
#[derive(Debug, Clone, PartialEq)]
pub struct GridTransfer {
    map: Vec<GridPoint>,
    n_source: usize,
}

impl GridTransfer {
    /// Locates every node of `target` in `source`; fails on a target node off the source's
    /// planform (beyond 1e-6 of its size).
    pub fn new(source: &SurfaceGrid, target: &SurfaceGrid) -> Result<Self, CouplingError> {
        Ok(Self {
            map: source.map_points(&target.positions_m, "target grid node")?,
            n_source: source.n_nodes(),
        })
    }

    /// The transfer from a conduction grid onto a structure's temperature grid of the same
    /// surface; a structure keeping the other side's grid (same node order) is taken at its
    /// nodes' mirror images on the conduction's side.
    pub fn onto_structure_grid(
        conduction: &SurfaceGrid,
        structure: &SurfaceGrid,
    ) -> Result<Self, CouplingError> {
        if structure.side == conduction.side {
            return Self::new(conduction, structure);
        }
        let mut mirrored = structure.clone();
        mirrored.positions_m.iter_mut().for_each(|p| p.y = -p.y);
        mirrored.side = conduction.side;
        Self::new(conduction, &mirrored)
    }

    /// The one transfer of a conduction model's node temperatures onto a structure's
    /// temperature nodes: across their grids when both have one
    /// ([`Self::onto_structure_grid`]); `None` when one lacks a grid and both count the same nodes (they are taken as
    /// the same nodes); an error otherwise, never a silent fallback.
    pub fn conduction_to_structure(
        conduction: (Option<&SurfaceGrid>, usize),
        structure: (Option<&SurfaceGrid>, usize),
    ) -> Result<Option<Self>, CouplingError> {
        match (conduction, structure) {
            ((Some(source), _), (Some(target), _)) => {
                Self::onto_structure_grid(source, target).map(Some)
            }
            ((_, n_source), (_, n_target)) if n_source == n_target => Ok(None),
            ((_, conduction_nodes), (_, structure_nodes)) => {
                Err(CouplingError::NoTemperatureTransfer {
                    conduction_nodes,
                    structure_nodes,
                })
            }
        }
    }

    /// Number of source-grid nodes.
    pub fn n_source(&self) -> usize {
        self.n_source
    }

    /// Number of target-grid nodes.
    pub fn n_target(&self) -> usize {
        self.map.len()
    }

    /// Target node values (e.g. structure temperatures, K) from source node values (conduction
    /// temperatures, K), into `target_values`. Allocates nothing.
    pub fn apply(
        &self,
        source_values: &[f64],
        target_values: &mut [f64],
    ) -> Result<(), CouplingError> {
        check_len("source node values", source_values.len(), self.n_source)?;
        check_len("target node values", target_values.len(), self.n_target())?;
        check_finite("source node values", source_values)?;
        SurfaceGrid::interpolate(&self.map, source_values, target_values);
        Ok(())
    }
}

/// A conduction model's temperature field on a structure's temperature nodes: the node mean
/// and through-thickness difference temperatures (K) moved by the one conduction-to-structure
/// transfer ([`GridTransfer::conduction_to_structure`]) and set on the structure's
/// temperature-dependent stiffness. The one step from conduction to structure of the in-flight
/// heating, the flutter march and `hsv-run heat`; allocates nothing once built.
#[derive(Debug, Clone, PartialEq)]
pub struct StructureTemperatures {
    transfer: Option<GridTransfer>,
    node_k: Vec<f64>,
    node_difference_k: Vec<f64>,
    /// Mean temperature at each structure node, K (of the last [`Self::update`]).
    pub mean_k: Vec<f64>,
    /// Through-thickness temperature difference at each structure node, K.
    pub difference_k: Vec<f64>,
}

impl StructureTemperatures {
    /// The transfer from `conduction`'s nodes onto `structure`'s temperature nodes, with zero
    /// fields; an error when they share neither nodes nor grids.
    pub fn new(
        conduction: &dyn ConductionModel,
        structure: &dyn ThermalStiffness,
    ) -> Result<Self, CouplingError> {
        let (n_source, n_target) = (conduction.n_nodes(), structure.temperature_nodes());
        let transfer = GridTransfer::conduction_to_structure(
            (conduction.node_grid(), n_source),
            (structure.temperature_grid(), n_target),
        )?;
        Ok(Self {
            transfer,
            node_k: vec![0.0; n_source],
            node_difference_k: vec![0.0; n_source],
            mean_k: vec![0.0; n_target],
            difference_k: vec![0.0; n_target],
        })
    }

    /// Moves the field of conduction `state` onto the structure's nodes ([`Self::mean_k`],
    /// [`Self::difference_k`]).
    pub fn update(
        &mut self,
        conduction: &dyn ConductionModel,
        state: &DVector<f64>,
    ) -> Result<(), CouplingError> {
        conduction.node_temperatures(state, &mut self.node_k);
        conduction.node_temperature_differences(state, &mut self.node_difference_k);
        match &self.transfer {
            Some(transfer) => {
                transfer.apply(&self.node_k, &mut self.mean_k)?;
                transfer.apply(&self.node_difference_k, &mut self.difference_k)
            }
            None => {
                self.mean_k.copy_from_slice(&self.node_k);
                self.difference_k.copy_from_slice(&self.node_difference_k);
                Ok(())
            }
        }
    }

    /// Sets the moved field on `structure`'s stiffness.
    pub fn apply(&self, structure: &mut dyn ThermalStiffness) -> Result<(), ModelError> {
        structure.set_temperature_field(&self.mean_k, &self.difference_k)
    }

    /// The conduction nodes' mean temperatures of the last [`Self::update`], K.
    pub fn conduction_node_k(&self) -> &[f64] {
        &self.node_k
    }
}
