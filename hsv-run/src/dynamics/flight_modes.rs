//! Eigenvalues of a linear state matrix with natural frequency and damping, and the classical
//! rigid-aircraft names (short period, phugoid, height, roll, Dutch roll, spiral, heading) or
//! the structural mode, decided by eigenvector content.
//!
//! **Content.** Each eigenvector entry is made comparable by its role: speeds over the reference
//! speed V (u/V ≈ relative speed, w/V ≈ α, v/V ≈ β), angles as they are, rates over |λ| (a rate
//! of an oscillation of frequency |λ| is |λ| times its angle), altitude and position times
//! |λ|/V (a flight-path angle), modal coordinates times a structural scale. The shares of the
//! longitudinal, lateral, structural and position groups decide the group.
//!
//! **Names** (Etkin & Reid, *Dynamics of Flight: Stability and Control*, 3rd ed., 1996, ch. 6:
//! the classical mode shapes of a jet transport): a longitudinal mode with more speed than
//! incidence content is the phugoid (speed exchanged at nearly constant α), with more incidence
//! than speed the short period (α and q at nearly constant speed; also when it splits into
//! real roots, as for a statically unstable vehicle); altitude-dominated, the height mode. A
//! lateral oscillation is the Dutch roll; of the real lateral roots the fastest is the roll
//! subsidence and the slowest the spiral; heading-dominated, the heading mode (a zero root).

use std::f64::consts::PI;
use std::fmt;

use hsv_core::linalg::general_eigen;
use nalgebra::{Complex, DMatrix, DVector};
use serde::Serialize;

use super::{DynamicsError, check_len};

/// What a state-vector entry is, for naming modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StateRole {
    /// u, m/s.
    ForwardSpeed,
    /// w, m/s.
    NormalSpeed,
    /// α, rad.
    AngleOfAttack,
    /// q, rad/s.
    PitchRate,
    /// θ, rad.
    Pitch,
    /// Altitude or NED down, m.
    Altitude,
    /// v, m/s.
    SideSpeed,
    /// β, rad.
    Sideslip,
    /// p, rad/s.
    RollRate,
    /// r, rad/s.
    YawRate,
    /// φ, rad.
    Roll,
    /// ψ, rad.
    Heading,
    /// North or east, m.
    Position,
    /// A modal coordinate (numbered across the structures).
    Structural { mode: usize },
    /// A modal velocity.
    StructuralRate { mode: usize },
    /// Not used for naming (quaternion components, engine states).
    Other,
}

/// The name given to an eigenmode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModeName {
    ShortPeriod,
    Phugoid,
    Height,
    Roll,
    DutchRoll,
    Spiral,
    Heading,
    Position,
    Structural {
        mode: usize,
    },
    /// Longitudinal, none of the above.
    Longitudinal,
    /// Lateral-directional, none of the above.
    Lateral,
    /// No entry with a role carries it.
    Unnamed,
}

impl fmt::Display for ModeName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModeName::ShortPeriod => write!(f, "short period"),
            ModeName::Phugoid => write!(f, "phugoid"),
            ModeName::Height => write!(f, "height"),
            ModeName::Roll => write!(f, "roll"),
            ModeName::DutchRoll => write!(f, "Dutch roll"),
            ModeName::Spiral => write!(f, "spiral"),
            ModeName::Heading => write!(f, "heading"),
            ModeName::Position => write!(f, "position"),
            ModeName::Structural { mode } => write!(f, "structural mode {}", mode + 1),
            ModeName::Longitudinal => write!(f, "longitudinal"),
            ModeName::Lateral => write!(f, "lateral"),
            ModeName::Unnamed => write!(f, "unnamed"),
        }
    }
}

/// Share of each group in a mode's scaled eigenvector (summing to 1 unless the mode has no
/// role-carrying entries).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct ModeContent {
    pub longitudinal: f64,
    pub lateral: f64,
    pub structural: f64,
    pub position: f64,
    /// Within the longitudinal group: u.
    pub speed: f64,
    /// Within the longitudinal group: w or α.
    pub incidence: f64,
    /// Within the longitudinal group: altitude.
    pub altitude: f64,
    /// Within the lateral group: ψ.
    pub heading: f64,
}

/// One eigenvalue (one per conjugate pair) with its frequency, damping, eigenvector and name.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FlightMode {
    pub real_per_s: f64,
    /// Im λ ≥ 0 (the upper member of a conjugate pair).
    pub imaginary_rad_s: f64,
    /// ω_n = |λ|, rad/s.
    pub natural_frequency_rad_s: f64,
    /// ω_d / 2π = Im λ / 2π, Hz.
    pub damped_frequency_hz: f64,
    /// ζ = −Re λ / |λ| (1 for a stable real root, −1 unstable, 0 for λ = 0).
    pub damping_ratio: f64,
    /// Time to half (stable) or double (unstable) amplitude, ln 2 / |Re λ|, s; `None` when
    /// Re λ = 0.
    pub time_to_half_or_double_s: Option<f64>,
    pub oscillatory: bool,
    pub name: ModeName,
    pub content: ModeContent,
    /// Right eigenvector, unit 2-norm (not serialized).
    #[serde(skip)]
    pub vector: DVector<Complex<f64>>,
}

/// How eigenvector entries are made comparable ([`flight_modes`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeScales {
    /// Reference (trim) speed V, m/s.
    pub reference_speed_m_s: f64,
    /// Multiplies modal coordinates (and modal velocities over |λ|).
    pub structural: f64,
    /// Floor on |λ| in the rate and position scalings, rad/s (keeps zero roots finite).
    pub frequency_floor_rad_s: f64,
    /// Roots slower than this (rad/s) are named by their rigid-body content alone: far below
    /// the structure's natural frequencies the modal coordinates in their eigenvectors are the
    /// quasi-static deflection that follows the flight condition (a phugoid changes dynamic
    /// pressure, so a flexible surface's static bending follows it), not a vibration. 0: off.
    pub quasi_static_below_rad_s: f64,
}

impl ModeScales {
    pub fn new(reference_speed_m_s: f64) -> Self {
        Self {
            reference_speed_m_s,
            structural: 1.0,
            frequency_floor_rad_s: 1e-3,
            quasi_static_below_rad_s: 0.0,
        }
    }

    /// Names roots slower than a tenth of `lowest_structural_rad_s` by their rigid-body content
    /// (a tenth: the quasi-static response of a mode excited at a tenth of its natural frequency
    /// is within 1 % of its static deflection, 1/(1 − 0.1²)).
    pub fn with_structure(self, lowest_structural_rad_s: f64) -> Self {
        Self {
            quasi_static_below_rad_s: 0.1 * lowest_structural_rad_s,
            ..self
        }
    }
}

/// Eigenmodes of the state matrix `a` (one per conjugate pair, in the order of
/// [`general_eigen`]), named by content with `roles` (one per state).
pub fn flight_modes(
    a: &DMatrix<f64>,
    roles: &[StateRole],
    scales: &ModeScales,
) -> Result<Vec<FlightMode>, DynamicsError> {
    check_len(|| "state roles".into(), a.nrows(), roles.len())?;
    let v = scales.reference_speed_m_s;
    if !(v.is_finite() && v > 0.0) {
        return Err(DynamicsError::InvalidParameter {
            quantity: "reference speed (m/s)".into(),
            value: v,
            allowed: "finite and > 0",
        });
    }
    let eigen = general_eigen(a)?;
    let mut modes: Vec<FlightMode> = eigen
        .values
        .iter()
        .enumerate()
        .filter(|(_, l)| l.im >= 0.0)
        .map(|(k, l)| {
            let vector = eigen.vectors.column(k).into_owned();
            mode_of(*l, vector, roles, scales)
        })
        .collect();
    name_lateral_real_roots(&mut modes);
    Ok(modes)
}

fn mode_of(
    lambda: Complex<f64>,
    vector: DVector<Complex<f64>>,
    roles: &[StateRole],
    scales: &ModeScales,
) -> FlightMode {
    let magnitude = lambda.norm();
    let oscillatory = lambda.im > 1e-10 * (1.0 + magnitude);
    let content = content_of(&vector, roles, magnitude, scales);
    let quasi_static = magnitude < scales.quasi_static_below_rad_s;
    let name = first_name(&content, roles, &vector, oscillatory, quasi_static);
    FlightMode {
        real_per_s: lambda.re,
        imaginary_rad_s: lambda.im,
        natural_frequency_rad_s: magnitude,
        damped_frequency_hz: lambda.im / (2.0 * PI),
        damping_ratio: if magnitude > 0.0 {
            -lambda.re / magnitude
        } else {
            0.0
        },
        time_to_half_or_double_s: (lambda.re != 0.0).then(|| 2f64.ln() / lambda.re.abs()),
        oscillatory,
        name,
        content,
        vector,
    }
}

/// Scaled magnitude of one eigenvector entry by its role.
fn scaled(role: StateRole, value: f64, magnitude: f64, scales: &ModeScales) -> f64 {
    let w = magnitude.max(scales.frequency_floor_rad_s);
    let v = scales.reference_speed_m_s;
    value
        * match role {
            StateRole::ForwardSpeed | StateRole::NormalSpeed | StateRole::SideSpeed => 1.0 / v,
            StateRole::AngleOfAttack
            | StateRole::Pitch
            | StateRole::Sideslip
            | StateRole::Roll
            | StateRole::Heading => 1.0,
            StateRole::PitchRate | StateRole::RollRate | StateRole::YawRate => 1.0 / w,
            StateRole::Altitude | StateRole::Position => w / v,
            StateRole::Structural { .. } => scales.structural,
            StateRole::StructuralRate { .. } => scales.structural / w,
            StateRole::Other => 0.0,
        }
}

fn content_of(
    vector: &DVector<Complex<f64>>,
    roles: &[StateRole],
    magnitude: f64,
    scales: &ModeScales,
) -> ModeContent {
    let mut c = ModeContent::default();
    let (mut longitudinal, mut lateral) = (0.0, 0.0);
    for (z, &role) in vector.iter().zip(roles) {
        let m = scaled(role, z.norm(), magnitude, scales);
        match role {
            StateRole::ForwardSpeed => c.speed += m,
            StateRole::NormalSpeed | StateRole::AngleOfAttack => c.incidence += m,
            StateRole::Altitude => c.altitude += m,
            StateRole::Heading => c.heading += m,
            _ => {}
        }
        match role {
            StateRole::ForwardSpeed
            | StateRole::NormalSpeed
            | StateRole::AngleOfAttack
            | StateRole::PitchRate
            | StateRole::Pitch
            | StateRole::Altitude => longitudinal += m,
            StateRole::SideSpeed
            | StateRole::Sideslip
            | StateRole::RollRate
            | StateRole::YawRate
            | StateRole::Roll
            | StateRole::Heading => lateral += m,
            StateRole::Structural { .. } | StateRole::StructuralRate { .. } => c.structural += m,
            StateRole::Position => c.position += m,
            StateRole::Other => {}
        }
    }
    let total = longitudinal + lateral + c.structural + c.position;
    if total > 0.0 {
        if longitudinal > 0.0 {
            c.speed /= longitudinal;
            c.incidence /= longitudinal;
            c.altitude /= longitudinal;
        }
        if lateral > 0.0 {
            c.heading /= lateral;
        }
        c.longitudinal = longitudinal / total;
        c.lateral = lateral / total;
        c.structural /= total;
        c.position /= total;
    }
    c
}

/// The name from this mode alone; real lateral roots get [`ModeName::Lateral`] here and are
/// sorted into roll and spiral by [`name_lateral_real_roots`].
fn first_name(
    c: &ModeContent,
    roles: &[StateRole],
    vector: &DVector<Complex<f64>>,
    oscillatory: bool,
    quasi_static: bool,
) -> ModeName {
    let structural = if quasi_static { 0.0 } else { c.structural };
    let groups = [c.longitudinal, c.lateral, structural, c.position];
    let best = groups
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i);
    if groups.iter().all(|&g| g == 0.0) {
        return ModeName::Unnamed;
    }
    match best {
        Some(0) if c.altitude > 0.5 => ModeName::Height,
        Some(0) if c.speed > c.incidence => ModeName::Phugoid,
        Some(0) if c.incidence > 0.0 => ModeName::ShortPeriod,
        Some(0) => ModeName::Longitudinal,
        Some(1) if c.heading > 0.5 => ModeName::Heading,
        Some(1) if oscillatory => ModeName::DutchRoll,
        Some(1) => ModeName::Lateral,
        Some(2) => dominant_structural_mode(roles, vector),
        Some(3) => ModeName::Position,
        _ => ModeName::Unnamed,
    }
}

fn dominant_structural_mode(roles: &[StateRole], vector: &DVector<Complex<f64>>) -> ModeName {
    roles
        .iter()
        .zip(vector.iter())
        .filter_map(|(role, z)| match role {
            StateRole::Structural { mode } => Some((*mode, z.norm())),
            _ => None,
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(ModeName::Unnamed, |(mode, _)| ModeName::Structural { mode })
}

/// Real lateral roots: the fastest is the roll subsidence, the slowest the spiral; a single one
/// is the roll mode when roll dominates its content, otherwise the spiral.
fn name_lateral_real_roots(modes: &mut [FlightMode]) {
    let mut real: Vec<usize> = modes
        .iter()
        .enumerate()
        .filter(|(_, m)| m.name == ModeName::Lateral && !m.oscillatory)
        .map(|(i, _)| i)
        .collect();
    real.sort_by(|&a, &b| {
        modes[a]
            .natural_frequency_rad_s
            .total_cmp(&modes[b].natural_frequency_rad_s)
    });
    match real.as_slice() {
        [] => {}
        [only] => {
            let m = &mut modes[*only];
            m.name = if m.content.heading < 0.25 {
                ModeName::Roll
            } else {
                ModeName::Spiral
            };
        }
        [slowest, .., fastest] => {
            modes[*fastest].name = ModeName::Roll;
            modes[*slowest].name = ModeName::Spiral;
        }
    }
}
