//! The aerodynamics role: panel pressures and boundary-layer edge states, and their integration
//! into forces, moments and coefficients; a reduced-order model's optional capability in
//! [`reduced_order`].

use nalgebra::{Point3, Vector3};

use crate::error::ModelError;
use crate::flow::FlightCondition;
use crate::mesh::{PanelMesh, RegionKind};

pub mod reduced_order;

/// Inviscid flow state at the outer edge of the boundary layer over one panel; what heat-flux
/// models start from.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct EdgeState {
    pub mach: f64,
    pub pressure_pa: f64,
    pub temperature_k: f64,
    pub density_kg_m3: f64,
    /// Edge velocity magnitude, m/s.
    pub velocity_m_s: f64,
}

/// Counts of the places where a model left its range of validity during one evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct AeroDiagnostics {
    /// Panels facing away from the flow (pressure set by the model's shadow rule).
    pub shadowed_panels: usize,
    /// Panels whose turning angle exceeded the maximum oblique-shock deflection.
    pub detached_shocks: usize,
    /// Panels whose normal velocity reached the speed of sound, where piston theory is invalid.
    pub piston_theory_violations: usize,
    /// Panels whose expansion would reach vacuum (pressure clipped at zero).
    pub vacuum_expansions: usize,
}

/// Output of an aero evaluation; buffers are reused between evaluations.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AeroSolution {
    /// Absolute static pressure on each panel, Pa.
    pub pressure_pa: Vec<f64>,
    /// Edge state over each panel.
    pub edge: Vec<EdgeState>,
    pub diagnostics: AeroDiagnostics,
}

impl AeroSolution {
    /// Sizes the buffers for `n_panels` and clears the diagnostics, keeping capacity.
    pub fn reset(&mut self, n_panels: usize) {
        self.pressure_pa.clear();
        self.pressure_pa.resize(n_panels, 0.0);
        self.edge.clear();
        self.edge.resize(n_panels, EdgeState::default());
        self.diagnostics = AeroDiagnostics::default();
    }
}

/// Motion of the panels beyond the rigid-body motion in [`FlightCondition`].
#[derive(Debug, Clone, Copy, Default)]
pub struct PanelMotion<'a> {
    /// Elastic velocity of each panel centroid in body axes, m/s (from modal velocities).
    pub elastic_velocity_m_s: Option<&'a [Vector3<f64>]>,
}

impl PanelMotion<'_> {
    /// Velocity of panel `index` relative to the air: rigid-body motion plus elastic velocity, m/s.
    pub fn panel_velocity_m_s(
        &self,
        flight: &FlightCondition,
        mesh: &PanelMesh,
        index: usize,
    ) -> Vector3<f64> {
        self.velocity_of_panels(flight, mesh)(index)
    }

    /// [`Self::panel_velocity_m_s`] of any panel by index, the flight's body velocity (two
    /// `sin_cos`) computed once: what a loop over the panels calls.
    pub fn velocity_of_panels<'m>(
        &'m self,
        flight: &'m FlightCondition,
        mesh: &'m PanelMesh,
    ) -> impl Fn(usize) -> Vector3<f64> + 'm {
        let body_velocity_m_s = flight.velocity_body_m_s();
        move |index| {
            let rigid = flight.point_velocity_from(body_velocity_m_s, &mesh.panels[index].centroid);
            match self.elastic_velocity_m_s {
                Some(elastic) => rigid + elastic[index],
                None => rigid,
            }
        }
    }
}

/// Checks what every supersonic panel method needs before it starts: a finite flight condition, a
/// physical freestream (p, T, ρ, R > 0, γ > 1), M ≥ 1, and one elastic velocity per panel.
pub fn check_panel_method_inputs(
    model: &str,
    mesh: &PanelMesh,
    flight: &FlightCondition,
    motion: &PanelMotion<'_>,
) -> Result<(), ModelError> {
    flight.check_finite()?;
    let f = &flight.freestream;
    if f.mach < 1.0 {
        return Err(ModelError::out_of_range(
            model,
            "Mach number",
            f.mach,
            ">= 1 (supersonic methods)",
        ));
    }
    let positive = [
        ("freestream pressure (Pa)", f.pressure_pa),
        ("freestream temperature (K)", f.temperature_k),
        ("freestream density (kg/m^3)", f.density_kg_m3),
        ("freestream speed of sound (m/s)", f.speed_of_sound_m_s),
        ("gas constant (J/(kg K))", f.gas.gas_constant_j_kg_k),
    ];
    for (quantity, value) in positive {
        if !(value.is_finite() && value > 0.0) {
            return Err(ModelError::out_of_range(
                model,
                quantity,
                value,
                "finite and > 0",
            ));
        }
    }
    if !(f.gas.gamma.is_finite() && f.gas.gamma > 1.0) {
        return Err(ModelError::out_of_range(
            model,
            "ratio of specific heats",
            f.gas.gamma,
            "finite and > 1",
        ));
    }
    if let Some(elastic) = motion.elastic_velocity_m_s
        && elastic.len() != mesh.panels.len()
    {
        return Err(ModelError::inconsistent(
            model,
            format!(
                "{} elastic panel velocities for a mesh of {} panels",
                elastic.len(),
                mesh.panels.len()
            ),
        ));
    }
    Ok(())
}

/// An aerodynamic model: pressures on every panel of a mesh at a flight condition.
///
/// Implementations keep only scratch buffers; everything that changes in time comes in through
/// the arguments, so one instance can serve several regions in turn.
pub trait AeroModel: Send {
    /// The registered name (`shock-expansion`, `newtonian-vector`, ...).
    fn name(&self) -> &str;

    /// Fills `out` with the absolute pressure and edge state of every panel of `mesh`.
    fn evaluate(
        &mut self,
        mesh: &PanelMesh,
        flight: &FlightCondition,
        motion: &PanelMotion<'_>,
        out: &mut AeroSolution,
    ) -> Result<(), ModelError>;

    /// Generalized forces from the history of the modal motion, if the model has memory of it
    /// (a convolution ROM); `None` by default. Regions that find it own a [`ModalHistory`] and
    /// call [`ModalHistoryAero::evaluate_modal`] instead of [`Self::evaluate`].
    fn modal_history(&mut self) -> Option<&mut dyn ModalHistoryAero> {
        None
    }

    /// Identification from a source model and the check against it, if the model is a reduced
    /// model of another (a convolution ROM); `None` by default. Commands ask for it with
    /// [`reduced_order::require`].
    fn reduced_order(&mut self) -> Option<&mut dyn reduced_order::ReducedOrderAero> {
        None
    }
}

/// The modal-input history an aero model with memory convolves: simulation state owned by the
/// region (plain data, so coupling iterations and linearizations clone it), not by the model.
///
/// Inputs are the model's own (for `convolution-rom`: modal coordinates, then modal velocities
/// over the freestream speed of sound); only the model that made a history interprets it.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct ModalHistory {
    /// Time of the latest committed sample, s.
    pub time_s: f64,
    /// The inputs committed at `time_s`.
    pub input: Vec<f64>,
    /// Times of the committed input increments still in the model's memory, oldest first, s.
    pub increment_times_s: std::collections::VecDeque<f64>,
    /// Those increments, `input.len()` values each, in the order of `increment_times_s`.
    pub increments: std::collections::VecDeque<f64>,
}

/// An aero model whose generalized forces depend on the history of the modal motion (the
/// [`AeroModel::modal_history`] capability).
///
/// A time step is: [`Self::evaluate_modal`] at the trial modal state as often as the coupling
/// iterates (the history is not changed), then [`Self::commit`] once for the accepted state.
pub trait ModalHistoryAero {
    /// Number of modes the model takes (length of the modal coordinates and velocities).
    fn n_modes(&self) -> usize;

    /// A history at rest: the modal state held at `modal_coordinates` (velocities zero) for all
    /// time before `time_s`.
    fn initial_history(
        &self,
        time_s: f64,
        modal_coordinates: &nalgebra::DVector<f64>,
    ) -> Result<ModalHistory, ModelError>;

    /// Generalized forces Q_k = −∫ (p − p∞) n·φ_k dA (one per mode, summed on the reference
    /// geometry) and, if `pressures` is given, panel pressures and edge states, at time
    /// `history.time_s + dt_s` for the trial modal coordinates and velocities. `rigid_mesh` is
    /// the region's undeformed mesh in its current rigid position (an elevon rotation applied),
    /// in the panel order of the region's mesh.
    #[allow(clippy::too_many_arguments)]
    fn evaluate_modal(
        &mut self,
        rigid_mesh: &PanelMesh,
        flight: &FlightCondition,
        history: &ModalHistory,
        dt_s: f64,
        modal_coordinates: &nalgebra::DVector<f64>,
        modal_velocities: &nalgebra::DVector<f64>,
        generalized_forces: &mut [f64],
        pressures: Option<&mut AeroSolution>,
    ) -> Result<(), ModelError>;

    /// Commits the accepted modal state at `history.time_s + dt_s` into `history`.
    fn commit(
        &self,
        history: &mut ModalHistory,
        flight: &FlightCondition,
        dt_s: f64,
        modal_coordinates: &nalgebra::DVector<f64>,
        modal_velocities: &nalgebra::DVector<f64>,
    ) -> Result<(), ModelError>;
}

/// Force and moment, body axes.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Loads {
    /// N.
    pub force_n: Vector3<f64>,
    /// About the chosen reference point, N m.
    pub moment_nm: Vector3<f64>,
}

impl std::ops::Add for Loads {
    type Output = Loads;
    fn add(self, other: Loads) -> Loads {
        Loads {
            force_n: self.force_n + other.force_n,
            moment_nm: self.moment_nm + other.moment_nm,
        }
    }
}

/// Sums F = -Σ (p - p_ref) A n and M = Σ (r - r_0) × F over the panels whose region passes
/// `include`.
///
/// Gauge pressure against the freestream makes open surfaces (a body with the engine flow path
/// cut out) give the same loads as the closed surface would outside it.
pub fn integrate_pressure(
    mesh: &PanelMesh,
    pressure_pa: &[f64],
    reference_pressure_pa: f64,
    moment_point_m: &Point3<f64>,
    include: impl Fn(RegionKind) -> bool,
) -> Loads {
    let mut loads = Loads::default();
    for (panel, &p) in mesh.panels.iter().zip(pressure_pa) {
        if !include(mesh.surfaces[panel.surface as usize].region) {
            continue;
        }
        let force = -(p - reference_pressure_pa) * panel.area_m2 * panel.normal;
        loads.force_n += force;
        loads.moment_nm += (panel.centroid - moment_point_m).cross(&force);
    }
    loads
}

/// Unit direction of the edge flow over a panel of outward normal `normal`: the air's velocity
/// relative to the panel, −v, projected on the panel plane, t̂ = −(v − (v·n) n) / |…|; `None` on
/// a face normal to the flow (a stagnation point, where the shear has no mean direction).
///
/// The inviscid edge flow of a surface panel method runs along the surface, so the wall shear of
/// a thin boundary layer acts along this direction (the boundary-layer assumption of
/// White, Viscous Fluid Flow, 3rd ed., §4-1: the wall shear is parallel to the outer flow).
pub fn edge_flow_direction(
    normal: &Vector3<f64>,
    panel_velocity_m_s: &Vector3<f64>,
) -> Option<Vector3<f64>> {
    let tangential = -(panel_velocity_m_s - panel_velocity_m_s.dot(normal) * normal);
    let norm = tangential.norm();
    (norm > 1e-9 * panel_velocity_m_s.norm() && norm > 0.0).then(|| tangential / norm)
}

/// Sums the skin-friction loads F = Σ τ A t̂ and M = Σ (r − r_0) × F over the panels whose region
/// passes `include`, with τ the wall shear of each panel (Pa) and t̂ its
/// [`edge_flow_direction`] from the panel's velocity relative to the air (rigid-body motion of
/// `flight` plus the elastic velocity of `motion`). Panels normal to the flow carry none.
pub fn integrate_shear(
    mesh: &PanelMesh,
    shear_pa: &[f64],
    flight: &FlightCondition,
    motion: &PanelMotion<'_>,
    moment_point_m: &Point3<f64>,
    include: impl Fn(RegionKind) -> bool,
) -> Loads {
    let mut loads = Loads::default();
    let panel_velocity = motion.velocity_of_panels(flight, mesh);
    for (i, (panel, &tau)) in mesh.panels.iter().zip(shear_pa).enumerate() {
        if !include(mesh.surfaces[panel.surface as usize].region) {
            continue;
        }
        let velocity = panel_velocity(i);
        let Some(direction) = edge_flow_direction(&panel.normal, &velocity) else {
            continue;
        };
        let force = tau * panel.area_m2 * direction;
        loads.force_n += force;
        loads.moment_nm += (panel.centroid - moment_point_m).cross(&force);
    }
    loads
}

/// Reference quantities that turn loads into coefficients.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceValues {
    /// Reference area S, m².
    pub area_m2: f64,
    /// Reference (mean aerodynamic) chord for pitching moment, m.
    pub chord_m: f64,
    /// Reference span for rolling and yawing moments, m.
    pub span_m: f64,
    /// Moment reference point in body axes, m.
    pub moment_point_m: [f64; 3],
}

impl ReferenceValues {
    pub fn moment_point(&self) -> Point3<f64> {
        Point3::from(self.moment_point_m)
    }
}

/// Non-dimensional force and moment coefficients in wind and body axes.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Coefficients {
    pub cl: f64,
    pub cd: f64,
    /// Side-force coefficient (wind axes).
    pub cy: f64,
    /// Rolling-moment coefficient (body x, span).
    pub croll: f64,
    /// Pitching-moment coefficient (body y, chord).
    pub cm: f64,
    /// Yawing-moment coefficient (body z, span).
    pub cn: f64,
}

impl Coefficients {
    /// Lift is normal to the velocity in the body x-z plane (positive up), drag along -V, side force
    /// completes the wind frame; moments are body-axis moments over q S l.
    pub fn from_loads(
        loads: &Loads,
        flight: &FlightCondition,
        reference: &ReferenceValues,
    ) -> Self {
        let q_s = flight.freestream.dynamic_pressure_pa * reference.area_m2;
        let wind =
            crate::frames::wind_axis_forces(&loads.force_n, flight.alpha_rad, flight.beta_rad);
        Self {
            cl: wind.lift_n / q_s,
            cd: wind.drag_n / q_s,
            cy: wind.side_n / q_s,
            croll: loads.moment_nm.x / (q_s * reference.span_m),
            cm: loads.moment_nm.y / (q_s * reference.chord_m),
            cn: loads.moment_nm.z / (q_s * reference.span_m),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::Freestream;
    use crate::gas::PerfectGas;
    use crate::mesh::{PanelSpec, Strip, Surface};

    /// A 2 m × 1 m plate in the body x-y plane from x = 0 back to x = −2 in four quads (surface 0,
    /// main body), and one 1 m² quad of a second surface (propulsion) at x = −3 … −4.
    fn plate() -> PanelMesh {
        let mut vertices = Vec::new();
        for i in 0..=4 {
            let x = -0.5 * f64::from(i);
            vertices.push(Point3::new(x, 0.0, 0.0));
            vertices.push(Point3::new(x, 1.0, 0.0));
        }
        let mut specs: Vec<PanelSpec> = (0..4)
            .map(|i| PanelSpec::quad(2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1, 0))
            .collect();
        let b = vertices.len();
        vertices.extend([
            Point3::new(-3.0, 0.0, 0.0),
            Point3::new(-4.0, 0.0, 0.0),
            Point3::new(-4.0, 1.0, 0.0),
            Point3::new(-3.0, 1.0, 0.0),
        ]);
        specs.push(PanelSpec::quad(b, b + 1, b + 2, b + 3, 1));
        PanelMesh::new(
            vertices,
            &specs,
            vec![Strip {
                panels: vec![0, 1, 2, 3],
            }],
            vec![
                Surface::new("plate", RegionKind::MainBody),
                Surface::new("engine", RegionKind::Propulsion),
            ],
        )
        .unwrap()
    }

    /// One 1 m² quad centred at the origin with outward normal `normal` (unit).
    fn single_panel(normal: Vector3<f64>) -> PanelMesh {
        let a = if normal.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let u = normal.cross(&a).normalize() * 0.5;
        let w = normal.cross(&u);
        let corners = [-u - w, u - w, u + w, -u + w].map(Point3::from);
        let mesh = PanelMesh::new(
            corners.to_vec(),
            &[PanelSpec::quad(0, 1, 2, 3, 0)],
            vec![],
            vec![Surface::new("panel", RegionKind::LiftingSurface)],
        )
        .unwrap();
        assert!((mesh.panels[0].area_m2 - 1.0).abs() < 1e-12);
        mesh
    }

    fn flight(alpha_deg: f64, beta_deg: f64) -> FlightCondition {
        let f = Freestream::standard(6.0, 26_000.0, PerfectGas::AIR).unwrap();
        FlightCondition::steady(f, alpha_deg.to_radians(), beta_deg.to_radians())
    }

    fn close(a: Vector3<f64>, b: Vector3<f64>) -> bool {
        (a - b).norm() <= 1e-9 * b.norm().max(1.0)
    }

    /// A plate aligned with the flow: the friction force is τ̄ A along −x (τ̄ the area-weighted
    /// mean shear), the moment about a point is Σ (r − r_0) × F by hand, and a region the filter
    /// leaves out adds nothing.
    #[test]
    fn friction_on_an_aligned_plate_is_mean_shear_times_area_along_minus_x() {
        let mesh = plate();
        let shear = [40.0, 30.0, 20.0, 10.0, 1000.0];
        let point = Point3::new(-1.0, 0.5, 1.0);
        let loads = integrate_shear(
            &mesh,
            &shear,
            &flight(0.0, 0.0),
            &PanelMotion::default(),
            &point,
            |r| r == RegionKind::MainBody,
        );
        // τ̄ = 25 Pa on A = 2 m²: F = (−50, 0, 0) N.
        assert!(close(loads.force_n, Vector3::new(-50.0, 0.0, 0.0)));
        // Panel centroids (−0.25 − 0.5 i, 0.5, 0): r − r_0 = (0.75 − 0.5 i, 0, −1) and
        // F_i = (−τ_i/2, 0, 0), so M_i = (0, (−1)(−τ_i/2), 0): a nose-up +τ_i/2 about y (drag
        // acting above the point, z down).
        let expected_my: f64 = shear[..4].iter().map(|t| 0.5 * t).sum();
        assert!(close(loads.moment_nm, Vector3::new(0.0, expected_my, 0.0)));
        let all = integrate_shear(
            &mesh,
            &shear,
            &flight(0.0, 0.0),
            &PanelMotion::default(),
            &point,
            |_| true,
        );
        assert!(close(all.force_n, Vector3::new(-1050.0, 0.0, 0.0)));
    }

    /// Shear follows the flow projected on the panel: a plate inclined by θ to the flow in the x-z
    /// plane gets t̂ = (−cos θ, 0, sin θ) for outward normal (sin θ, 0, cos θ); a plate in the x-y
    /// plane at sideslip β gets −(cos β, sin β, 0) (across its strip direction), and at incidence α
    /// stays along −x (the flow's normal component does not shear it).
    #[test]
    fn shear_on_an_inclined_plate_points_along_the_projected_flow() {
        let theta = 20f64.to_radians();
        let mesh = single_panel(Vector3::new(theta.sin(), 0.0, theta.cos()));
        let origin = Point3::origin();
        let f = integrate_shear(
            &mesh,
            &[10.0],
            &flight(0.0, 0.0),
            &PanelMotion::default(),
            &origin,
            |_| true,
        );
        assert!(close(
            f.force_n,
            10.0 * Vector3::new(-theta.cos(), 0.0, theta.sin())
        ));

        let flat = single_panel(Vector3::z());
        let beta = 15f64.to_radians();
        let f = integrate_shear(
            &flat,
            &[10.0],
            &flight(0.0, 15.0),
            &PanelMotion::default(),
            &origin,
            |_| true,
        );
        assert!(close(
            f.force_n,
            -10.0 * Vector3::new(beta.cos(), beta.sin(), 0.0)
        ));
        let f = integrate_shear(
            &flat,
            &[10.0],
            &flight(8.0, 0.0),
            &PanelMotion::default(),
            &origin,
            |_| true,
        );
        assert!(close(f.force_n, Vector3::new(-10.0, 0.0, 0.0)));
    }

    /// A face normal to the flow has no edge-flow direction (stagnation point) and carries no
    /// friction; an elastic velocity turns the direction with the panel's relative velocity.
    #[test]
    fn shear_direction_needs_a_tangential_flow_and_follows_elastic_motion() {
        let face = single_panel(Vector3::x());
        let origin = Point3::origin();
        let loads = integrate_shear(
            &face,
            &[10.0],
            &flight(0.0, 0.0),
            &PanelMotion::default(),
            &origin,
            |_| true,
        );
        assert_eq!(loads.force_n, Vector3::zeros());
        // The x-normal face moving sideways (+y) at the flight speed: relative air along −y.
        let fl = flight(0.0, 0.0);
        let elastic = [Vector3::new(0.0, fl.freestream.velocity_m_s, 0.0)];
        let motion = PanelMotion {
            elastic_velocity_m_s: Some(&elastic),
        };
        let loads = integrate_shear(&face, &[10.0], &fl, &motion, &origin, |_| true);
        assert!(close(loads.force_n, Vector3::new(0.0, -10.0, 0.0)));
    }
}
