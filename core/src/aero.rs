//! The aerodynamics role: panel pressures and boundary-layer edge states, and their integration
//! into forces, moments and coefficients.

use nalgebra::{Point3, Vector3};

use crate::error::ModelError;
use crate::flow::FlightCondition;
use crate::mesh::{PanelMesh, RegionKind};

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
        let rigid = flight.point_velocity_m_s(&mesh.panels[index].centroid);
        match self.elastic_velocity_m_s {
            Some(elastic) => rigid + elastic[index],
            None => rigid,
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
        let (sa, ca) = flight.alpha_rad.sin_cos();
        let (sb, cb) = flight.beta_rad.sin_cos();
        let f = loads.force_n;
        // Body -> wind axes (Etkin): x_w along V, z_w in the plane of symmetry.
        let drag = -(f.x * ca * cb + f.y * sb + f.z * sa * cb);
        let side = -f.x * ca * sb + f.y * cb - f.z * sa * sb;
        let lift = f.x * sa - f.z * ca;
        Self {
            cl: lift / q_s,
            cd: drag / q_s,
            cy: side / q_s,
            croll: loads.moment_nm.x / (q_s * reference.span_m),
            cm: loads.moment_nm.y / (q_s * reference.chord_m),
            cn: loads.moment_nm.z / (q_s * reference.span_m),
        }
    }
}
