//! The `convolution-rom` aero model: generalized forces (and panel pressures) of a region from
//! the convolution of identified step responses with the history of its modal motion, times a
//! nonlinear correction factor (paper §III.D after Skujins & Cesnik, "Reduced-Order Modeling of
//! Unsteady Aerodynamics Across Multiple Mach Regimes", J. Aircraft 51(6), 2014, and Skujins'
//! dissertation: "linear convolution combined with a nonlinear correction factor", the factor
//! making the ROM accurate "over a range of vehicle elastic modal deformation amplitudes as well
//! as flight conditions representing off-design conditions").
//!
//! **Inputs and outputs.** The inputs are the region's modal coordinates q_j and modal
//! velocities over the freestream speed of sound, q̇_j / a∞ (2 n inputs for n modes). The
//! outputs are the generalized forces Q_k = −Σ (p − p∞) A n·φ_k on the reference geometry over
//! the panels of the region's own kind (the partitioned vehicle's `ModalProjection`; a root cap
//! tagged `other` carries none) and the panel gauge pressures p − p∞, all over
//! p∞. Normalizing by p∞ and a∞ makes the responses of perfect-gas panel methods independent of
//! altitude at a given Mach number (pressure ratios depend on M and the geometry only; the
//! piston-theory rate term is γ w/a∞).
//!
//! **Evaluation** (linear part: Duhamel's integral in its sum form, Etkin, *Dynamics of
//! Atmospheric Flight*, App. A.3: x(t) = f(0) A(t) + Σ A(t − τ) Δf(τ)): with S_c(τ) the
//! response to a unit step of input c, sampled every Δt_id and settled after its last sample,
//!
//! y(t) = Σ_c [ S_c(∞) u_c(t) + Σ_m (S_c(τ_m) − S_c(∞)) Δu_c,m ],
//!
//! Δu_c,m the committed input increments (and the trial increment at lag 0), τ_m = (t − t_m)
//! V∞ / V∞,id (lags in distance flown, as the Wagner function counts semichords). Increments
//! older than the responses' length are dropped (their S − S(∞) is zero), so the cost per step
//! is bounded by the memory length. Then
//!
//! Q_k = Q_0,k(M, α, mesh) + p∞ Σ_j [ c_kj(q_j, M) y_k,j + y_k,n+j ],
//!
//! Q_0 the source's steady value of the undeformed surface in its current rigid position (cached
//! while the flight condition and position are unchanged) and c_kj the correction factor of
//! output k for mode j: the ratio of the source's nonlinear steady response to a static
//! deflection q_j of mode j, F(q_j e_j) − F(0), to the linear prediction S_j(∞) q_j, tabulated
//! over ± amplitudes of each mode and over Mach numbers at the identification altitude and
//! angle of attack (at zero amplitude its limit F'(0)/S_j: the source's linear response at that
//! Mach over the identification's, so the ROM linearized about the undeformed surface is the
//! source's linearization at every Mach of the table), interpolated bilinearly (the edge value held beyond the amplitude table; a
//! Mach number outside the table is an error). Rate inputs are corrected over Mach only, by
//! the source's linear rate response at each tabulated Mach over the identification's. Panel pressures
//! follow the same formula per panel; their edge states are the steady ones scaled
//! isentropically to the new pressure (T ∝ p^((γ−1)/γ), ρ ∝ p^(1/γ), NACA 1135 eqs. 43-44).
//!
//! **Identification** from the source aero model (any registered or plugin model, by name):
//! central differences of the source's outputs for steps ±ε in each modal coordinate (the
//! undeformed mesh deformed by ±ε φ_j, no velocity) and ±ε̇ in each modal velocity (the
//! elastic panel velocities ±ε̇ φ_j on the undeformed mesh). An `AeroModel` has no memory by
//! contract (everything that changes in time comes in through its arguments), so its step
//! response is immediate and constant: a single sample. With such a source the convolution
//! reduces to Q = Q_0 + p∞ (c K q + C q̇ / a∞): the ROM then captures exactly the source's
//! quasi-steady physics, linearized, with the correction for the displacement nonlinearity; it
//! cannot show lag the source does not have. Responses with memory (from CFD) come from a CSV.
//!
//! **Step-response CSV** (`step_csv`): generalized-force step responses computed by the user
//! (e.g. CFD) at the identification condition (`mach`, `altitude_m`, `alpha_deg`), replacing the
//! source's force responses (pressures and the correction factor stay the source's):
//!
//! ```text
//! input,mode,step,time_s,force_1,force_2,...,force_n
//! displacement,1,0.001,0.0,-12.5,3.1,...
//! displacement,1,0.001,0.0005,-12.9,3.0,...
//! velocity,1,0.01,0.0,...
//! ```
//!
//! `input`: `displacement` (a step in modal coordinate q_mode of size `step`, in the modal
//! coordinate's units) or `velocity` (a step in the modal velocity q̇_mode of size `step`,
//! units of q per second; optional: a CFD displacement step already carries the rate effect);
//! `mode`: 1-based mode number of the region's structure; `time_s`: time since the step, s,
//! uniform from 0 and the same in every block; `force_k`: generalized-force change of mode k
//! since before the step, Q_k(t) − Q_k(0⁻) = −∫ (p − p_before) n·φ_k dA, N m per unit modal
//! coordinate (φ in m per unit q). Every mode needs a displacement block. Lines starting with
//! `#` are comments.
//!
//! **Cache.** The identification is saved as JSON to `cache_file` (`{region}` replaced by the
//! region name; empty: no cache) with a fingerprint of everything it was built from (source name
//! and settings, structure name and settings, identification settings, the mesh, the mode
//! shapes, the CSV's contents, the gas); a file with another fingerprint is rebuilt and replaced.
//!
//! **Plain `evaluate`** (no history: steady analyses, trim, heating) is the source model itself
//! on the given (deformed) mesh: the ROM's steady limit at zero rates is the source's steady
//! value by construction only to the correction table's interpolation error, so the exact source
//! is returned where no history is available.

mod cache;
pub mod check;
pub mod identify;
mod rom;
mod step_csv;

use hsv_core::aero::AeroModel;
use hsv_core::error::ModelError;
use hsv_core::registry::{Constructor, ModelCheck, ModelContext, ModelDescriptor};

pub use check::{CheckOptions, CheckReport, MotionReport, check_against_source};
pub use identify::{Identification, ReferenceCondition, ResponseBlock};
pub use rom::{ConvolutionRom, read_cache};

/// Registered name.
pub const NAME: &str = "convolution-rom";

/// The `[models.convolution-rom]` table.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Aero model the ROM is identified from (registered or plugin name).
    pub source: String,
    /// Structure model of the region giving the mode shapes (registered or plugin name).
    pub structure: String,
    /// Number of modes (the structure's first ones); 0: all of them.
    pub modes: usize,
    /// Identification Mach number.
    pub mach: f64,
    /// Identification (geometric) altitude, m.
    pub altitude_m: f64,
    /// Identification angle of attack, deg.
    pub alpha_deg: f64,
    /// Mach numbers of the correction table (at the identification altitude and α).
    pub correction_mach: Vec<f64>,
    /// Largest modal amplitude of the correction table, as the mode's peak vertex displacement, m.
    pub max_displacement_m: f64,
    /// Amplitudes of the correction table per sign, evenly spaced up to the largest.
    pub amplitude_points: usize,
    /// Identification step in each modal coordinate, as the mode's peak vertex displacement, m.
    pub step_displacement_m: f64,
    /// Identification step in each modal velocity, as the mode's peak vertex velocity, m/s.
    pub step_velocity_m_s: f64,
    /// Apply the nonlinear correction factor.
    pub correction: bool,
    /// Generalized-force step responses from the user (CSV, format in the crate docs); empty:
    /// identified from the source.
    pub step_csv: String,
    /// Identification cache (JSON; `{region}` is replaced by the region name); empty: none.
    pub cache_file: String,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            // Paper §III.D: the lifting surfaces' unsteady model of the paper.
            source: "shock-expansion-piston".to_owned(),
            structure: "ritz-plate".to_owned(),
            modes: 0,
            // DESIGN §5: the paper's cruise, Mach 6 at 26 km in level flight.
            mach: 6.0,
            altitude_m: 26_000.0,
            alpha_deg: 0.0,
            // Our choice: one Mach number either side of the cruise.
            correction_mach: vec![5.0, 6.0, 7.0],
            // Our choice: 10 cm peak displacement, a few degrees of local incidence on the
            // sample surface's 1.6-4 m chords.
            max_displacement_m: 0.1,
            amplitude_points: 4,
            // Our choice: small against the 5 % thick surface, large against round-off.
            step_displacement_m: 1e-4,
            step_velocity_m_s: 1e-3,
            correction: true,
            step_csv: String::new(),
            cache_file: "hsv-cache/convolution-rom-{region}.json".to_owned(),
        }
    }
}

/// What `hsv-run describe convolution-rom` prints.
pub const SETTINGS_DOC: &str = "\
source = \"shock-expansion-piston\"  # aero model the step responses and the correction come from (any registered name)
structure = \"ritz-plate\"            # structure model of the region giving the mode shapes
modes = 0                            # number of modes (the first ones); 0: all
mach = 6.0                           # identification Mach number
altitude_m = 26000.0                 # identification altitude, m (responses scale with p_inf and a_inf)
alpha_deg = 0.0                      # identification angle of attack, deg
correction_mach = [5.0, 6.0, 7.0]    # Mach numbers of the correction-factor table
max_displacement_m = 0.1             # largest amplitude of the correction table, as peak mode displacement, m
amplitude_points = 4                 # correction-table amplitudes per sign
step_displacement_m = 1e-4           # identification step in q, as peak mode displacement, m
step_velocity_m_s = 1e-3             # identification step in q-dot, as peak mode velocity, m/s
correction = true                    # apply the nonlinear correction factor
step_csv = \"\"                        # CFD generalized-force step responses (input,mode,step,time_s,force_1..n); empty: from source
cache_file = \"hsv-cache/convolution-rom-{region}.json\"  # identification cache, rebuilt when its inputs change; empty: none";

impl Settings {
    /// The first setting outside its range: key, value and the allowed range.
    pub fn first_invalid(&self) -> Option<(String, f64, &'static str)> {
        let positive = [
            ("mach", self.mach),
            ("max_displacement_m", self.max_displacement_m),
            ("step_displacement_m", self.step_displacement_m),
            ("step_velocity_m_s", self.step_velocity_m_s),
        ];
        for (key, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Some((key.to_owned(), value, "finite and > 0"));
            }
        }
        if self.mach < 1.0 {
            return Some(("mach".to_owned(), self.mach, ">= 1 (supersonic sources)"));
        }
        if !(self.altitude_m.is_finite() && self.alpha_deg.is_finite()) {
            return Some((
                "altitude_m".to_owned(),
                self.altitude_m,
                "finite (and a finite alpha_deg)",
            ));
        }
        if self.alpha_deg.abs() >= 90.0 {
            return Some(("alpha_deg".to_owned(), self.alpha_deg, "|alpha| < 90"));
        }
        if self.correction {
            if self.correction_mach.is_empty() {
                return Some((
                    "correction_mach".to_owned(),
                    0.0,
                    "at least one Mach number when correction = true",
                ));
            }
            for (i, pair) in self.correction_mach.windows(2).enumerate() {
                if pair[1] <= pair[0] {
                    return Some((format!("correction_mach[{}]", i + 1), pair[1], "increasing"));
                }
            }
            if let Some((i, &m)) = self
                .correction_mach
                .iter()
                .enumerate()
                .find(|(_, m)| !(m.is_finite() && **m >= 1.0))
            {
                return Some((format!("correction_mach[{i}]"), m, "finite and >= 1"));
            }
            if self.amplitude_points == 0 {
                return Some(("amplitude_points".to_owned(), 0.0, ">= 1"));
            }
        }
        if self.step_displacement_m >= self.max_displacement_m {
            return Some((
                "step_displacement_m".to_owned(),
                self.step_displacement_m,
                "< max_displacement_m (a small step)",
            ));
        }
        None
    }

    /// The cache path for region `region`, or `None` without a cache.
    pub fn cache_path(&self, region: &str) -> Option<std::path::PathBuf> {
        (!self.cache_file.is_empty())
            .then(|| std::path::PathBuf::from(self.cache_file.replace("{region}", region)))
    }
}

fn construct(ctx: &ModelContext<'_>) -> Result<Box<dyn AeroModel>, ModelError> {
    if ctx.region.geometry == hsv_core::region::RegionGeometry::Mesh {
        // A bare mesh (the `aero` command's whole vehicle, an STL) has no structure whose modes
        // could be identified: the ROM is its source's plain evaluation, as it is everywhere
        // outside a modal history.
        let settings = rom::checked_settings(ctx)?;
        let source_settings = ctx.settings_for(&settings.source);
        let source = ctx
            .build::<dyn AeroModel>(&settings.source, &source_settings)
            .map_err(|e| ctx.settings_error("source", e.to_string()))?;
        return Ok(Box::new(SourceOnly { source }));
    }
    Ok(Box::new(ConvolutionRom::new(ctx)?))
}

/// The ROM on a mesh without modes: its source model's plain evaluation.
struct SourceOnly {
    source: Box<dyn AeroModel>,
}

impl AeroModel for SourceOnly {
    fn name(&self) -> &str {
        NAME
    }

    fn evaluate(
        &mut self,
        mesh: &hsv_core::mesh::PanelMesh,
        flight: &hsv_core::flow::FlightCondition,
        motion: &hsv_core::aero::PanelMotion<'_>,
        out: &mut hsv_core::aero::AeroSolution,
    ) -> Result<(), ModelError> {
        self.source.evaluate(mesh, flight, motion, out)
    }
}

hsv_core::register_model!(ModelDescriptor {
    name: NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 3,
    summary: "convolution ROM (Skujins & Cesnik): generalized forces and pressures from step \
              responses identified from any aero model (or CFD step responses from a CSV) \
              convolved with the modal history, times a nonlinear correction factor over modal \
              amplitude and Mach; plain evaluation is the source model",
    settings_doc: SETTINGS_DOC,
    constructor: Constructor::Aero(construct),
});

hsv_core::register_model_check!(ModelCheck {
    name: NAME,
    check: rom::check,
});

#[cfg(test)]
mod tests {
    use super::*;

    /// The documented settings are the defaults (the doc cannot drift from the code).
    #[test]
    fn settings_doc_is_the_defaults() {
        let parsed: Settings = toml::from_str(SETTINGS_DOC).expect("SETTINGS_DOC parses");
        assert_eq!(parsed, Settings::default());
        assert_eq!(Settings::default().first_invalid(), None);
    }

    #[test]
    fn registered_in_the_builtin_registry() {
        let registry = hsv_core::registry::Registry::builtin().expect("registry");
        let entry = registry.get(NAME).expect("registered");
        assert_eq!(entry.role(), hsv_core::registry::Role::Aero);
    }
}
