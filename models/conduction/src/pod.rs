//! The `pod` conduction model: its name, limits and settings here; the basis (proper orthogonal
//! decomposition of full-order temperature snapshots) in `pod/basis.rs`, and the reduced model
//! (Galerkin projection of the full-order equations onto the modes) in `pod/model.rs`.
//!
//! **Basis** (method of snapshots, Sirovich, Q. Appl. Math. 45(3), 1987; Holmes, Lumley &
//! Berkooz, Turbulence, Coherent Structures, Dynamical Systems and Symmetry, ch. 3): mode 0 is
//! the uniform field 1/√n, so any uniform temperature (the initial state) is exact; the other
//! modes are the leading left singular vectors of the snapshots with their uniform part
//! removed, from the eigenvectors of the snapshot correlation matrix XᵀX. The energy captured,
//! Σ_{k<r−1} σ_k² / Σ σ_k², is reported (paper: 32 modes, Falkiewicz & Cesnik).
//!
//! **Galerkin projection.** T ≈ Φ a with Φ orthonormal (n × r). The full-order step
//! C(½(Tⁿ+Tⁿ⁺¹)) (Tⁿ⁺¹ − Tⁿ)/Δt + K(Tⁿ⁺¹) Tⁿ⁺¹ = F projected with Φᵀ gives
//! C_r(½(aⁿ+aⁿ⁺¹)) (aⁿ⁺¹ − aⁿ)/Δt + K_r(aⁿ⁺¹) aⁿ⁺¹ = L q.
//!
//! **Nonlinearity.** Each material's k(T) and c_p(T) are replaced by their least-squares lines
//! k ≈ k₀ + k₁ T, c_p ≈ c₀ + c₁ T over the snapshots' temperature range (Ti-6Al-4V: c_p is
//! linear in the core table up to the β transus, where it steps down by 119 J/(kg K) at
//! 1267-1268 K; k is within ±0.3 W/(m K) of its line over 293-923 K, and steepens above).
//! Snapshots that cross the transus get poorer lines. Then
//! K_r(a) = K₀ + Σ_j a_j K₁ⱼ and C_r(a) = C₀ + Σ_j a_j C₁ⱼ exactly, with K₀ = Σ_e k₀ Φ_eᵀ G_e Φ_e,
//! K₁ⱼ = Σ_e k₁ φ̄_ej Φ_eᵀ G_e Φ_e (φ̄_ej: mode j's mean over element e, as the full order takes
//! k at the element's mean temperature), C₀ = Φᵀ diag(c₀) Φ, C₁ⱼ = Φᵀ diag(c₁ ∘ φ_j) Φ. The
//! online step (Picard iteration, each an r × r assembly of O(r³) and a Cholesky solve) costs
//! nothing that grows with the grid; only the panel flux input and the outputs scale with the
//! panel and node counts. Beyond the snapshot range the lines extrapolate.

// Index loops mirror the matrix algebra they implement.
#![allow(clippy::needless_range_loop)]

mod basis;
mod model;

use crate::training::Training;

pub use basis::{BASIS_FORMAT, PodBasis, collect_snapshots};
pub use model::{Pod, range_margin_k};

/// Registered name.
pub const NAME: &str = "pod";

/// The most modes a basis may be asked for: far above the paper's 32, below a size whose
/// Galerkin matrices would not fit the snapshot runs that train them.
pub const MAX_MODES: usize = 1000;

/// Folder of the caches models build for themselves, relative to the working directory.
pub const CACHE_DIR: &str = "hsv-cache";

/// Default [`Settings::basis_file`].
pub const DEFAULT_BASIS_FILE: &str = "hsv-cache/pod-basis-{region}.json";

/// Settings of `[models.pod]`; the grid and materials come from `[models.full-order]`.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// JSON basis file (written by `PodBasis::save`), relative to the working directory;
    /// `{region}` is replaced by the region's name ([`Settings::basis_path`]). Default: in the
    /// cache folder [`CACHE_DIR`], one per region.
    pub basis_file: String,
    /// Modes to use, at most the basis's (paper: 32).
    pub modes: usize,
    /// Picard iterations stop when the coefficient change (an upper bound of the largest
    /// temperature change) is below this, K.
    pub picard_tolerance_k: f64,
    pub max_picard_iterations: usize,
    /// `[models.pod.training]`: when given, a missing basis, or one built from anything else
    /// (conditions, grid, planform, base-model settings), is trained anew and saved.
    pub training: Option<Training>,
}

impl Settings {
    /// The first setting outside its range, as (key, value, allowed), training included.
    pub fn first_invalid(&self) -> Option<(String, f64, &'static str)> {
        if !(1..=MAX_MODES).contains(&self.modes) {
            return Some(("modes".to_owned(), self.modes as f64, "1 to 1000"));
        }
        if !(self.picard_tolerance_k.is_finite() && self.picard_tolerance_k > 0.0) {
            return Some((
                "picard_tolerance_k".to_owned(),
                self.picard_tolerance_k,
                "finite and > 0",
            ));
        }
        if self.max_picard_iterations < 1 {
            return Some(("max_picard_iterations".to_owned(), 0.0, ">= 1"));
        }
        self.training.as_ref().and_then(Training::first_invalid)
    }

    /// The basis file of region `region`: [`Self::basis_file`] with `{region}` replaced.
    pub fn basis_path(&self, region: &str) -> std::path::PathBuf {
        std::path::PathBuf::from(self.basis_file.replace("{region}", region))
    }

    /// The other regions' basis files [`Self::basis_file`] names: the files of its folder
    /// whose names match it with any text for `{region}` (none without the placeholder).
    pub fn sibling_basis_paths(&self, region: &str) -> Vec<std::path::PathBuf> {
        let own = self.basis_path(region);
        let pattern = std::path::Path::new(&self.basis_file);
        let Some(name) = pattern.file_name().and_then(|n| n.to_str()) else {
            return Vec::new();
        };
        let Some((prefix, suffix)) = name.split_once("{region}") else {
            return Vec::new();
        };
        let folder = pattern
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        let Ok(entries) = std::fs::read_dir(folder) else {
            return Vec::new();
        };
        let mut paths: Vec<std::path::PathBuf> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| {
                p.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                    n.len() > prefix.len() + suffix.len()
                        && n.starts_with(prefix)
                        && n.ends_with(suffix)
                })
            })
            .filter(|p| p.file_name() != own.file_name())
            .collect();
        paths.sort();
        paths
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            basis_file: DEFAULT_BASIS_FILE.to_owned(),
            modes: 32,
            picard_tolerance_k: 1e-3,
            max_picard_iterations: 30,
            training: None,
        }
    }
}

/// What `hsv-run describe pod` prints.
pub const SETTINGS_DOC: &str = "\
basis_file = \"hsv-cache/pod-basis-{region}.json\"  # POD basis cache (JSON, folder created when missing); {region} = region name
modes = 32                     # modes used (paper: 32), at most the basis's
picard_tolerance_k = 1e-3      # Picard convergence on the mode coefficients, K
max_picard_iterations = 30     # Picard iterations allowed per step
[models.pod.training]          # optional: train the basis when missing or built from other conditions
heat_flux = \"eckert\"           # heat-flux model of the snapshot runs (any registered name)
aero = \"shock-expansion\"       # aero model giving the edge states
mach = [5.0, 5.5, 6.0]         # one full-order run per Mach number
altitude_m = 10000.0           # m (paper: 10 km)
alpha_deg = [-4.0, 0.0, 4.0]   # deg, a number or a list: one run per Mach number and angle (zero
                               #   alone gives a mirror-symmetric basis: no through-thickness difference)
duration_s = 100.0             # s in the flow per run (paper: up to 100 s)
dt_s = 0.1                     # conduction step, s
snapshots_per_run = 100
initial_k = 293.0              # uniform initial temperature, K";
