//! The inlet face of one section: the captured mass flow (spillage, or two streams when the
//! bow shock enters the cowl), the face's stream thrust and the uniform inlet state, by
//! stream-thrust averaging where the face carries more than one stream.

use hsv_core::gas::PerfectGas;
use nalgebra::{Point2, Vector2};

use crate::flow::FlowState;
use crate::geometry::SectionGeometry;
use crate::section::SectionConditions;

/// Captured mass flow of a section and the flow it brings through the inlet face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Capture {
    /// Captured air mass flow per unit span, kg/(s m).
    pub mass_flow_kg_s_per_m: f64,
    /// ρ∞ V∞ h∞: the freestream tube between the nose and the cowl lip, kg/(s m).
    pub max_mass_flow_kg_s_per_m: f64,
    /// Area of the inlet face normal to the ramp flow, m²/m: the inlet station's flow area.
    pub face_area_m2_per_m: f64,
    /// The uniform inlet-station state along the ramp flow: the shock-layer state, or, when
    /// the bow shock enters the cowl, the stream-thrust average of the shocked and unshocked
    /// parts of the face.
    pub state: FlowState,
    /// Stream thrust through the inlet face, Σ ṁ V ê + (p - p∞) l n̂ over its parts, N/m:
    /// the force the face's flow puts on the flow path (body x, z).
    pub face_stream_thrust_n_per_m: Vector2<f64>,
}

impl Capture {
    /// Captured over capturable.
    pub fn fraction(&self) -> f64 {
        self.mass_flow_kg_s_per_m / self.max_mass_flow_kg_s_per_m
    }

    /// Spillage: less than the whole tube from the nose to the lip is captured.
    pub fn spills(&self) -> bool {
        self.fraction() < 1.0 - 1e-9
    }
}

/// Mass capture with spillage: ṁ = min(ρ∞V∞ h∞, ρ1V1 A_face), where h∞ is the height of the
/// freestream tube between the nose and the cowl lip normal to the freestream and A_face the
/// inlet face (ramp end to lip) normal to the ramp flow (after Bolender & Doman, J. Spacecraft
/// Rockets 44(2), 2007, inlet model). When the bow shock passes ahead of the lip, the flow
/// between it and the lip spills and the face carries the shock-layer flow ρ1V1 A_face; at
/// shock-on-lip the two agree.
///
/// When the bow shock enters the cowl (faster flight, or α below the on-lip value), the whole
/// tube is captured and the face carries two streams: shocked flow next to the ramp and
/// undisturbed freestream next to the lip. Their lengths l_a + l_b = l on the face follow from
/// mass, ρ1V1 (n̂·ê1) l_a + ρ∞V∞ (n̂·u) l_b = ρ∞V∞ h∞ (exact for a straight ramp, where it
/// places the split where the shock crosses the face); the face's stream thrust sums both, and
/// the inlet station is their stream-thrust average along ê1 (`stream_thrust_average`), so
/// the forebody closes on the freestream momentum. (Before issue 10 item 8 the whole captured
/// flow was taken at the shock-layer state in a narrower tube: at 1.1 times the on-lip Mach
/// the sample's force was 275 N/m too much thrust and 2.5 kN/m too little lift.)
///
/// `None` when the inlet face lies within 84° of parallel to the ramp flow or the two streams
/// cannot mix to supersonic flow: the inlet cannot take the flow (unstart).
pub fn capture(
    geometry: &SectionGeometry,
    conditions: &SectionConditions<'_>,
    inlet: &FlowState,
) -> Option<Capture> {
    let f = conditions.freestream;
    let gas: &PerfectGas = &f.gas;
    // Freestream direction in (x, z): the air moves against the body velocity, aft and up for
    // α > 0.
    let v = hsv_core::frames::body_velocity_from_wind(1.0, conditions.alpha_rad, 0.0);
    let u = Vector2::new(-v.x, -v.z);
    let to_lip = geometry.cowl_lip() - geometry.nose();
    let tube_height = (to_lip.x * u.y - to_lip.y * u.x).abs();
    let max = f.density_kg_m3 * f.velocity_m_s * tube_height;
    let e1 = geometry.inlet_direction();
    let face = Face::new(geometry.ramp_end(), geometry.cowl_lip(), &e1)?;
    let face_area = face.length_m * face.cosine;
    let v1 = inlet.velocity_m_s(gas);
    let shocked_flux = inlet.mass_flux_kg_m2_s(gas) * face.cosine;
    let p_inf = f.pressure_pa;
    if shocked_flux * face.length_m <= max {
        let mass = shocked_flux * face.length_m;
        return Some(Capture {
            mass_flow_kg_s_per_m: mass,
            max_mass_flow_kg_s_per_m: max,
            face_area_m2_per_m: face_area,
            state: *inlet,
            face_stream_thrust_n_per_m: mass * v1 * e1
                + (inlet.pressure_pa - p_inf) * face.length_m * face.normal,
        });
    }
    let free_flux = f.density_kg_m3 * f.velocity_m_s * face.normal.dot(&u);
    if free_flux.is_nan() || free_flux <= 0.0 || shocked_flux <= free_flux {
        return None;
    }
    let shocked_length = (max - free_flux * face.length_m) / (shocked_flux - free_flux);
    let shocked_mass = shocked_flux * shocked_length;
    let free_mass = max - shocked_mass;
    let face_stream_thrust = shocked_mass * v1 * e1
        + (inlet.pressure_pa - p_inf) * shocked_length * face.normal
        + free_mass * f.velocity_m_s * u;
    // Absolute stream thrust along ê1 through the face's projection normal to ê1.
    let impulse = shocked_mass * v1
        + free_mass * f.velocity_m_s * u.dot(&e1)
        + (inlet.pressure_pa * shocked_length + p_inf * (face.length_m - shocked_length))
            * face.cosine;
    let total_enthalpy = gas.cp() * inlet.total_temperature_k(gas);
    let state = stream_thrust_average(max, impulse, face_area, total_enthalpy, gas)?;
    Some(Capture {
        mass_flow_kg_s_per_m: max,
        max_mass_flow_kg_s_per_m: max,
        face_area_m2_per_m: face_area,
        state,
        face_stream_thrust_n_per_m: face_stream_thrust,
    })
}

/// An engine face (inlet or exit) as a straight segment: its length, its unit normal n̂
/// oriented downstream and n̂·ê for the flow direction ê.
pub(crate) struct Face {
    pub length_m: f64,
    pub normal: Vector2<f64>,
    pub cosine: f64,
}

impl Face {
    /// The face from `a` to `b` crossed by flow along `flow`; `None` when n̂·ê < 0.1 (within 84°
    /// of parallel: a collapsed flow path).
    pub fn new(a: Point2<f64>, b: Point2<f64>, flow: &Vector2<f64>) -> Option<Self> {
        let d = b - a;
        let length_m = d.norm();
        let normal = Vector2::new(d.y, -d.x) / length_m;
        let cosine = normal.dot(flow);
        let (normal, cosine) = if cosine < 0.0 {
            (-normal, -cosine)
        } else {
            (normal, cosine)
        };
        (cosine >= 0.1).then_some(Self {
            length_m,
            normal,
            cosine,
        })
    }
}

/// The uniform supersonic flow with the mass flow ṁ, the stream thrust S = ṁ V + p A through
/// area A and the total enthalpy h0 of a non-uniform one (stream-thrust averaging: Heiser &
/// Pratt, Hypersonic Airbreathing Propulsion, AIAA 1994; used for scramjet intakes by Matthews,
/// Jones & Cain, J. Propulsion Power 21(5), 2005): with p = ρ R T and h0 = c_p T + V²/2,
/// (1 - R/(2 c_p)) V² - (S/ṁ) V + R h0/c_p = 0, the larger root (the smaller one is the state
/// behind a normal shock). `None` when no real root exists or it is subsonic.
pub fn stream_thrust_average(
    mass_flow: f64,
    stream_thrust: f64,
    area: f64,
    total_enthalpy_j_kg: f64,
    gas: &PerfectGas,
) -> Option<FlowState> {
    let r = gas.gas_constant_j_kg_k;
    let cp = gas.cp();
    let a = 1.0 - r / (2.0 * cp);
    let b = stream_thrust / mass_flow;
    let c = r * total_enthalpy_j_kg / cp;
    let discriminant = b * b - 4.0 * a * c;
    if discriminant.is_nan() || discriminant < 0.0 {
        return None;
    }
    let velocity = (b + discriminant.sqrt()) / (2.0 * a);
    let temperature_k = (total_enthalpy_j_kg - 0.5 * velocity * velocity) / cp;
    let state = FlowState {
        mach: velocity / gas.speed_of_sound(temperature_k),
        pressure_pa: (stream_thrust - mass_flow * velocity) / area,
        temperature_k,
    };
    (state.is_physical() && state.mach > 1.0).then_some(state)
}

/// The captured flow turned into the duct: the uniform flow along the cowl's first segment ê_d
/// with the captured mass flow, the total enthalpy and the inlet face's stream thrust along ê_d,
/// S_d = S_face·ê_d + p∞ l (n̂·ê_d), through the face's area normal to ê_d, A_d = l (n̂·ê_d)
/// (stream-thrust averaging, [`stream_thrust_average`]), and A_d. A duct whose walls run along
/// ê_d can push the flow only across ê_d, so the turn from the ramp direction keeps the axial
/// stream thrust and gives up the transverse momentum (to the cowl, as the down force it
/// carries) with the entropy that costs; the isentropic turn it replaced (issue 10 item 8)
/// created 1.19 kN/m of axial force from walls that have no axial area at Mach 6, 26 km, a
/// third of `scramjet-1d`'s net thrust at φ = 0.13. `None` when the turned flow cannot be
/// supersonic (unstart) or the face lies within 84° of parallel to the duct.
pub fn duct_entry(
    cap: &Capture,
    geometry: &SectionGeometry,
    conditions: &SectionConditions<'_>,
) -> Option<(FlowState, f64)> {
    let f = conditions.freestream;
    let cowl = &geometry.cowl_m;
    let axis = (cowl[1] - cowl[0]).normalize();
    let face = Face::new(geometry.ramp_end(), geometry.cowl_lip(), &axis)?;
    let area = face.length_m * face.cosine;
    let impulse = cap.face_stream_thrust_n_per_m.dot(&axis) + f.pressure_pa * area;
    let total_enthalpy = f.gas.cp() * cap.state.total_temperature_k(&f.gas);
    let state = stream_thrust_average(
        cap.mass_flow_kg_s_per_m,
        impulse,
        area,
        total_enthalpy,
        &f.gas,
    )?;
    Some((state, area))
}
