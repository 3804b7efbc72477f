//! The `free-free-beam` settings: the `[models.free-free-beam]` table (paper Table 1 section
//! properties, element count, damping, modes kept per kind, axis height), its defaults and
//! documented form, the checks of its ranges with their limits, and the finite-element mesh it
//! describes.

use crate::{BeamMesh, ModeKind, Section};

/// Most elements accepted: the eigen-solve is dense, O((6 n)³).
pub const MAX_ELEMENTS: usize = 240;

/// Most modes kept per kind.
pub const MAX_MODES_PER_KIND: usize = 20;

/// Elements needed per half-wave of the highest kept mode, so its frequency is converged
/// (Hermite bending: < 1e-4 relative; linear torsion: (π/8)²/12 ≈ 1 % at worst, far less at
/// the default element count).
pub const ELEMENTS_PER_HALF_WAVE: usize = 4;

/// Settings of `[models.free-free-beam]`; defaults are the paper's Table 1 and our choices.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// L_f, nose to the fore/aft junction, m (paper Table 1: 15.2).
    pub forebody_length_m: f64,
    /// L_a, junction to tail, m (paper Table 1: 15.2).
    pub aftbody_length_m: f64,
    /// μ_f, kg/m (paper Table 1: 838).
    pub forebody_mass_per_length_kg_m: f64,
    /// μ_a, kg/m (paper Table 1: 1250).
    pub aftbody_mass_per_length_kg_m: f64,
    /// I_x, rotary inertia about the beam axis per unit length, kg m²/m (paper Table 1: 3.28e3).
    pub torsional_inertia_kg_m: f64,
    /// EI_zz, bending in the x-y plane, N m² (paper Table 1: 5.06e10).
    pub lateral_bending_stiffness_n_m2: f64,
    /// EI_yy, bending in the x-z plane, N m² (paper Table 1: 6.32e9).
    pub vertical_bending_stiffness_n_m2: f64,
    /// GJ, N m² (paper Table 1: 4.74e9).
    pub torsional_stiffness_n_m2: f64,
    /// EA, N (our choice: the paper gives none and keeps no axial mode).
    pub axial_stiffness_n: f64,
    /// Finite elements along the beam (split over fore- and aftbody by length).
    pub elements: usize,
    /// Modal damping ratio ζ of every kept mode (our choice; the paper gives none).
    pub damping_ratio: f64,
    /// Lateral bending modes kept (paper: 1).
    pub lateral_bending_modes: usize,
    /// Vertical (longitudinal) bending modes kept (paper: 1).
    pub vertical_bending_modes: usize,
    /// Torsion modes kept (paper: 1).
    pub torsion_modes: usize,
    /// Axial modes kept (paper: 0).
    pub axial_modes: usize,
    /// Beam axis height below the nose line, m; default: the centroid of the `[geometry]` side
    /// profile.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis_z_m: Option<f64>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            forebody_length_m: 15.2,
            aftbody_length_m: 15.2,
            forebody_mass_per_length_kg_m: 838.0,
            aftbody_mass_per_length_kg_m: 1250.0,
            torsional_inertia_kg_m: 3.28e3,
            lateral_bending_stiffness_n_m2: 5.06e10,
            vertical_bending_stiffness_n_m2: 6.32e9,
            torsional_stiffness_n_m2: 4.74e9,
            axial_stiffness_n: 6.32e9,
            elements: 60,
            damping_ratio: 0.02,
            lateral_bending_modes: 1,
            vertical_bending_modes: 1,
            torsion_modes: 1,
            axial_modes: 0,
            axis_z_m: None,
        }
    }
}

pub(crate) const SETTINGS_DOC: &str = "\
forebody_length_m = 15.2                   # L_f, m (paper Table 1); must match [geometry] forebody_length_m
aftbody_length_m = 15.2                    # L_a, m (paper Table 1); L_f + L_a must match [geometry] length_m
forebody_mass_per_length_kg_m = 838.0      # mu_f, kg/m (paper Table 1)
aftbody_mass_per_length_kg_m = 1250.0      # mu_a, kg/m (paper Table 1)
torsional_inertia_kg_m = 3280.0            # I_x per unit length, kg m^2/m (paper Table 1)
lateral_bending_stiffness_n_m2 = 5.06e10   # EI_zz, x-y plane, N m^2 (paper Table 1)
vertical_bending_stiffness_n_m2 = 6.32e9   # EI_yy, x-z plane, N m^2 (paper Table 1)
torsional_stiffness_n_m2 = 4.74e9          # GJ, N m^2 (paper Table 1)
axial_stiffness_n = 6.32e9                 # EA, N (our choice; no axial mode is kept by default)
elements = 60                              # finite elements along the beam (2..240)
damping_ratio = 0.02                       # modal damping ratio zeta of every kept mode (our choice)
lateral_bending_modes = 1                  # modes kept per kind (paper: 1, 1, 1, 0)
vertical_bending_modes = 1
torsion_modes = 1
axial_modes = 0
# axis_z_m = 0.4                           # beam axis below the nose line, m (default: centroid of the [geometry] side profile)";

/// A setting outside its range: key, value, allowed values.
pub(crate) struct Invalid {
    pub(crate) key: &'static str,
    pub(crate) value: f64,
    pub(crate) allowed: String,
}

impl Settings {
    /// Checks every value; the first bad one is returned with its key.
    pub(crate) fn check(&self) -> Result<(), Invalid> {
        let positive = [
            ("forebody_length_m", self.forebody_length_m),
            ("aftbody_length_m", self.aftbody_length_m),
            (
                "forebody_mass_per_length_kg_m",
                self.forebody_mass_per_length_kg_m,
            ),
            (
                "aftbody_mass_per_length_kg_m",
                self.aftbody_mass_per_length_kg_m,
            ),
            ("torsional_inertia_kg_m", self.torsional_inertia_kg_m),
            (
                "lateral_bending_stiffness_n_m2",
                self.lateral_bending_stiffness_n_m2,
            ),
            (
                "vertical_bending_stiffness_n_m2",
                self.vertical_bending_stiffness_n_m2,
            ),
            ("torsional_stiffness_n_m2", self.torsional_stiffness_n_m2),
            ("axial_stiffness_n", self.axial_stiffness_n),
        ];
        for (key, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(Invalid {
                    key,
                    value,
                    allowed: "finite and > 0".to_owned(),
                });
            }
        }
        if !(self.damping_ratio.is_finite() && (0.0..1.0).contains(&self.damping_ratio)) {
            return Err(Invalid {
                key: "damping_ratio",
                value: self.damping_ratio,
                allowed: "0 <= zeta < 1".to_owned(),
            });
        }
        if let Some(z) = self.axis_z_m
            && !z.is_finite()
        {
            return Err(Invalid {
                key: "axis_z_m",
                value: z,
                allowed: "finite".to_owned(),
            });
        }
        for kind in ModeKind::ALL {
            let n = self.modes_of(kind);
            if n > MAX_MODES_PER_KIND {
                return Err(Invalid {
                    key: match kind {
                        ModeKind::LateralBending => "lateral_bending_modes",
                        ModeKind::VerticalBending => "vertical_bending_modes",
                        ModeKind::Torsion => "torsion_modes",
                        ModeKind::Axial => "axial_modes",
                    },
                    value: n as f64,
                    allowed: format!("0..={MAX_MODES_PER_KIND}"),
                });
            }
        }
        if self.kept_mode_count() == 0 {
            return Err(Invalid {
                key: "vertical_bending_modes",
                value: 0.0,
                allowed: "at least one mode of some kind (lateral_bending_modes, \
                          vertical_bending_modes, torsion_modes, axial_modes)"
                    .to_owned(),
            });
        }
        let needed = self.min_elements();
        if self.elements < needed || self.elements > MAX_ELEMENTS {
            return Err(Invalid {
                key: "elements",
                value: self.elements as f64,
                allowed: format!(
                    "{needed}..={MAX_ELEMENTS}: the requested modes need {ELEMENTS_PER_HALF_WAVE} \
                     elements per half-wave of the highest one"
                ),
            });
        }
        Ok(())
    }

    /// Modes kept, all kinds.
    pub fn kept_mode_count(&self) -> usize {
        self.lateral_bending_modes
            + self.vertical_bending_modes
            + self.torsion_modes
            + self.axial_modes
    }

    /// Modes kept of `kind`.
    pub fn modes_of(&self, kind: ModeKind) -> usize {
        match kind {
            ModeKind::LateralBending => self.lateral_bending_modes,
            ModeKind::VerticalBending => self.vertical_bending_modes,
            ModeKind::Torsion => self.torsion_modes,
            ModeKind::Axial => self.axial_modes,
        }
    }

    /// Fewest elements for the requested modes: the n-th free-free bending mode has about n + 1
    /// half-waves, the n-th torsion or axial mode n; at least one element per segment.
    pub fn min_elements(&self) -> usize {
        let half_waves = [
            self.lateral_bending_modes.saturating_add(1)
                * usize::from(self.lateral_bending_modes > 0),
            self.vertical_bending_modes.saturating_add(1)
                * usize::from(self.vertical_bending_modes > 0),
            self.torsion_modes,
            self.axial_modes,
        ]
        .into_iter()
        .max()
        .unwrap_or(0);
        half_waves.saturating_mul(ELEMENTS_PER_HALF_WAVE).max(2)
    }

    /// Total beam length, m.
    pub fn length_m(&self) -> f64 {
        self.forebody_length_m + self.aftbody_length_m
    }

    /// The finite-element mesh: fore- and aftbody segments, elements split by length.
    pub fn beam_mesh(&self) -> BeamMesh {
        let section = |mu: f64| Section {
            mass_per_length_kg_m: mu,
            torsional_inertia_kg_m: self.torsional_inertia_kg_m,
            lateral_bending_stiffness_n_m2: self.lateral_bending_stiffness_n_m2,
            vertical_bending_stiffness_n_m2: self.vertical_bending_stiffness_n_m2,
            torsional_stiffness_n_m2: self.torsional_stiffness_n_m2,
            axial_stiffness_n: self.axial_stiffness_n,
        };
        let fore = ((self.elements as f64 * self.forebody_length_m / self.length_m()).round()
            as usize)
            .clamp(1, self.elements.saturating_sub(1).max(1));
        let aft = self.elements.saturating_sub(fore).max(1);
        BeamMesh::from_segments(&[
            (
                self.forebody_length_m,
                section(self.forebody_mass_per_length_kg_m),
                fore,
            ),
            (
                self.aftbody_length_m,
                section(self.aftbody_mass_per_length_kg_m),
                aft,
            ),
        ])
    }
}
