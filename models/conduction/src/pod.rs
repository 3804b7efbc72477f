//! The `pod` conduction model: proper orthogonal decomposition of full-order temperature
//! snapshots and Galerkin projection of the full-order equations onto the modes.
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

use std::path::Path;

use hsv_core::error::ModelError;
use hsv_core::linalg::BandedMatrix;
use hsv_core::material::Material;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::{ConductionModel, check_step_inputs};
use nalgebra::{DMatrix, DVector};

use crate::full_order::{FullOrder, Settings as FullOrderSettings};
use crate::grid::ThermalGrid;
use crate::training::Training;

/// Registered name.
pub const NAME: &str = "pod";

/// The most modes a basis may be asked for: far above the paper's 32, below a size whose
/// Galerkin matrices would not fit the snapshot runs that train them.
pub const MAX_MODES: usize = 1000;

/// Tag of the basis file format.
pub const BASIS_FORMAT: &str = "hsv-pod-basis-1";

/// A POD basis with what it was built from; saved and reloaded as JSON.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PodBasis {
    /// [`BASIS_FORMAT`].
    pub format: String,
    /// Full-order settings of the grid the snapshots came from.
    pub full_order: FullOrderSettings,
    /// Orthonormal modes (n_dofs × n_modes), mode 0 uniform.
    pub modes: DMatrix<f64>,
    /// Singular values of the snapshots less their uniform part, largest first.
    pub singular_values: Vec<f64>,
    /// Σ σ_k² of the retained non-uniform modes over Σ σ_k² of all.
    pub energy_fraction: f64,
    pub n_snapshots: usize,
    /// Lowest and highest snapshot temperature, K (the range of the property fits).
    pub temperature_range_k: (f64, f64),
    /// The conditions the snapshots were run at, when the model trained it.
    #[serde(default)]
    pub training: Option<Training>,
    /// What the basis was built from ([`crate::training::fingerprint`]); empty for a basis
    /// built by hand, which is used as it is.
    #[serde(default)]
    pub fingerprint: String,
}

impl PodBasis {
    /// `n_modes` modes (mode 0 uniform) from full-order snapshots (method of snapshots).
    pub fn from_snapshots(
        snapshots: &[DVector<f64>],
        n_modes: usize,
        full_order: FullOrderSettings,
    ) -> Result<Self, ModelError> {
        if n_modes < 1 {
            return Err(ModelError::out_of_range(NAME, "modes", 0.0, ">= 1"));
        }
        if snapshots.len() < n_modes {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "the snapshot set has {} snapshots, fewer than the {n_modes} modes requested; \
                     collect more snapshots or ask for at most {} modes",
                    snapshots.len(),
                    snapshots.len()
                ),
            ));
        }
        let n = snapshots[0].len();
        if let Some(bad) = snapshots.iter().position(|s| s.len() != n) {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "snapshot {bad} has {} temperatures, snapshot 0 has {n}",
                    snapshots[bad].len()
                ),
            ));
        }
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for s in snapshots {
            for &t in s.iter() {
                if !t.is_finite() {
                    return Err(ModelError::NonFinite {
                        model: NAME.to_owned(),
                        quantity: "snapshot temperature".to_owned(),
                        location: String::new(),
                    });
                }
                lo = lo.min(t);
                hi = hi.max(t);
            }
        }
        let m = snapshots.len();
        let uniform = DVector::from_element(n, 1.0 / (n as f64).sqrt());
        let mut x = DMatrix::zeros(n, m);
        for (j, s) in snapshots.iter().enumerate() {
            let fluctuation = s - &uniform * uniform.dot(s);
            x.set_column(j, &fluctuation);
        }
        let correlation = x.transpose() * &x;
        // The method of snapshots: XᵀX = V Λ Vᵀ (the workspace's one symmetric eigen path).
        let mut eigenvalues = vec![0.0; m];
        let mut eigenvectors = DMatrix::zeros(m, m);
        hsv_core::linalg::SymmetricEigenSolver::new(m)
            .decompose(&correlation, &mut eigenvalues, &mut eigenvectors)
            .map_err(|e| {
                ModelError::inconsistent(NAME, format!("snapshot correlation matrix: {e}"))
            })?;
        // Largest first.
        let order: Vec<usize> = (0..m).rev().collect();
        let singular_values: Vec<f64> = order
            .iter()
            .map(|&k| eigenvalues[k].max(0.0).sqrt())
            .collect();
        let total: f64 = singular_values.iter().map(|s| s * s).sum();
        let mut modes = DMatrix::zeros(n, n_modes);
        modes.set_column(0, &uniform);
        let largest = singular_values.first().copied().unwrap_or(0.0);
        for k in 1..n_modes {
            let sigma = singular_values[k - 1];
            if !(sigma > 1e-10 * largest && sigma > 0.0) {
                return Err(ModelError::inconsistent(
                    NAME,
                    format!(
                        "the snapshots span only {} independent non-uniform directions; ask for \
                         at most {} modes",
                        k - 1,
                        k
                    ),
                ));
            }
            let v = eigenvectors.column(order[k - 1]);
            let phi = (&x * v) / sigma;
            modes.set_column(k, &phi);
        }
        orthonormalize(&mut modes)?;
        let retained: f64 = singular_values[..n_modes - 1].iter().map(|s| s * s).sum();
        Ok(Self {
            format: BASIS_FORMAT.to_owned(),
            full_order,
            modes,
            singular_values,
            energy_fraction: if total > 0.0 { retained / total } else { 1.0 },
            n_snapshots: m,
            temperature_range_k: (lo, hi),
            training: None,
            fingerprint: String::new(),
        })
    }

    pub fn n_modes(&self) -> usize {
        self.modes.ncols()
    }

    /// Writes the basis to `path` as a sealed cache ([`hsv_core::cache`]: checksummed, written
    /// atomically).
    pub fn save(&self, path: &Path) -> Result<(), ModelError> {
        hsv_core::cache::save(path, self).map_err(|e| ModelError::inconsistent(NAME, e.to_string()))
    }

    /// Reads a basis written by [`Self::save`]: refused when the file is missing, damaged (its
    /// seal does not match its content), of another format, or its arrays disagree in shape.
    pub fn load(path: &Path) -> Result<Self, ModelError> {
        Self::load_cache(path).map_err(|e| ModelError::inconsistent(NAME, e.to_string()))
    }

    /// [`Self::load`] with the reason kept apart, so a caller can tell a first run (missing) from
    /// a damaged cache it must say it rebuilds.
    pub fn load_cache(path: &Path) -> Result<Self, hsv_core::cache::CacheError> {
        let damaged = |reason: String| hsv_core::cache::CacheError::Damaged {
            path: path.to_owned(),
            reason,
        };
        let basis: Self = hsv_core::cache::load(path)?;
        if basis.format != BASIS_FORMAT {
            return Err(damaged(format!(
                "POD basis format `{}`, expected `{BASIS_FORMAT}`",
                basis.format
            )));
        }
        let (n_dofs, n_modes) = basis.modes.shape();
        if n_modes == 0 || n_dofs == 0 || basis.singular_values.len() < n_modes.saturating_sub(1) {
            return Err(damaged(format!(
                "a {n_dofs} x {n_modes} mode matrix with {} singular values",
                basis.singular_values.len()
            )));
        }
        Ok(basis)
    }
}

/// dst += a src (same shapes), without allocating.
fn add_scaled(dst: &mut DMatrix<f64>, a: f64, src: &DMatrix<f64>) {
    for (d, s) in dst.as_mut_slice().iter_mut().zip(src.as_slice()) {
        *d += a * s;
    }
}

/// The lower triangle (diagonal included) of a symmetric r × r matrix, column by column: the
/// entries a Cholesky factorization reads, r(r+1)/2 of them.
fn packed_lower(m: &DMatrix<f64>) -> DVector<f64> {
    let r = m.nrows();
    DVector::from_iterator(
        r * (r + 1) / 2,
        (0..r).flat_map(|b| (b..r).map(move |a| m[(a, b)])),
    )
}

/// The matrix whose column j is `matrices[j]` stored by [`packed_lower`].
fn packed_columns(matrices: &[DMatrix<f64>]) -> DMatrix<f64> {
    let r = matrices.first().map_or(0, |m| m.nrows());
    let mut out = DMatrix::zeros(r * (r + 1) / 2, matrices.len());
    for (j, m) in matrices.iter().enumerate() {
        out.set_column(j, &packed_lower(m));
    }
    out
}

/// y = α S x for a symmetric S stored by [`packed_lower`].
fn packed_symmetric_mul(alpha: f64, packed: &DVector<f64>, x: &DVector<f64>, y: &mut DVector<f64>) {
    let r = x.len();
    y.fill(0.0);
    let mut idx = 0;
    for b in 0..r {
        y[b] += packed[idx] * x[b];
        idx += 1;
        for a in b + 1..r {
            y[a] += packed[idx] * x[b];
            y[b] += packed[idx] * x[a];
            idx += 1;
        }
    }
    *y *= alpha;
}

/// Modified Gram-Schmidt on the columns, in place.
fn orthonormalize(modes: &mut DMatrix<f64>) -> Result<(), ModelError> {
    for k in 0..modes.ncols() {
        for j in 0..k {
            let dot = modes.column(j).dot(&modes.column(k));
            let prev = modes.column(j).clone_owned();
            let mut col = modes.column_mut(k);
            col.axpy(-dot, &prev, 1.0);
        }
        let norm = modes.column(k).norm();
        if norm.is_nan() || norm <= 1e-12 {
            return Err(ModelError::inconsistent(
                NAME,
                format!("POD mode {k} is linearly dependent on the earlier modes"),
            ));
        }
        modes.column_mut(k).scale_mut(1.0 / norm);
    }
    Ok(())
}

/// Runs `model` from a uniform `initial_k` for `steps` steps of `dt_s`, with the heat flux of
/// each step from `flux(surface temperatures, out)`, and returns the state after every
/// `every`-th step (the snapshots of one flight condition).
pub fn collect_snapshots(
    model: &mut FullOrder,
    initial_k: f64,
    dt_s: f64,
    steps: usize,
    every: usize,
    mut flux: impl FnMut(&[f64], &mut [f64]) -> Result<(), ModelError>,
) -> Result<Vec<DVector<f64>>, ModelError> {
    let every = every.max(1);
    let mut state = model.uniform_state(initial_k)?;
    let mut surface = vec![0.0; model.n_surface_panels()];
    let mut q = vec![0.0; model.n_surface_panels()];
    let mut out = Vec::with_capacity(steps / every + 1);
    for k in 1..=steps {
        model.surface_temperatures(&state, &mut surface);
        flux(&surface, &mut q)?;
        model.step(&mut state, &q, dt_s)?;
        if k % every == 0 {
            out.push(state.clone());
        }
    }
    Ok(out)
}

/// Least-squares line a + b T through `f` over [lo, hi] sampled every ≤ 1 K.
fn linear_fit(
    f: impl Fn(f64) -> Result<f64, ModelError>,
    lo: f64,
    hi: f64,
) -> Result<(f64, f64), ModelError> {
    if hi - lo < 1e-9 {
        return Ok((f(lo)?, 0.0));
    }
    let n = ((hi - lo).ceil() as usize).max(2) + 1;
    let (mut st, mut sy, mut stt, mut sty) = (0.0, 0.0, 0.0, 0.0);
    for k in 0..n {
        let t = lo + (hi - lo) * k as f64 / (n - 1) as f64;
        let y = f(t)?;
        st += t;
        sy += y;
        stt += t * t;
        sty += t * y;
    }
    let nf = n as f64;
    let b = (nf * sty - st * sy) / (nf * stt - st * st);
    Ok(((sy - b * st) / nf, b))
}

/// Lines (k₀, k₁, c₀, c₁) of a material's conductivity and specific heat over [lo, hi].
fn property_lines(m: &Material, lo: f64, hi: f64) -> Result<[f64; 4], ModelError> {
    let err = |e: hsv_core::material::MaterialError| e.into_model_error(NAME);
    let (lo, hi) = (
        crate::clamp_round_off_k(m, lo),
        crate::clamp_round_off_k(m, hi),
    );
    let (k0, k1) = linear_fit(|t| m.conductivity_w_m_k(t).map_err(err), lo, hi)?;
    let (c0, c1) = linear_fit(|t| m.specific_heat_j_kg_k(t).map_err(err), lo, hi)?;
    Ok([k0, k1, c0, c1])
}

/// Folder of the caches models build for themselves, relative to the working directory.
pub const CACHE_DIR: &str = "hsv-cache";

/// Default [`Settings::basis_file`].
pub const DEFAULT_BASIS_FILE: &str = "hsv-cache/pod-basis-{region}.json";

/// How far, K, a step's surface temperatures may leave the basis's snapshot range
/// (`temperature_range_k`) before the step is refused: the larger of 25 K and a tenth of the
/// range. Within it the property lines extrapolate little; beyond it the basis was built for
/// another run (our choice, not the paper's).
pub fn range_margin_k((lo, hi): (f64, f64)) -> f64 {
    (0.1 * (hi - lo)).max(25.0)
}

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

/// The POD Galerkin conduction model (module docs). State: the r mode coefficients.
#[derive(Debug, Clone)]
pub struct Pod {
    settings: Settings,
    /// The full-order model's surface grid (node temperatures are on it).
    plate: SurfaceGrid,
    basis: PodBasis,
    r: usize,
    /// K(T) = K0 + Σ_j a_j K1_j and C(T) = C0 + Σ_j a_j C1_j, each stored by [`packed_lower`]:
    /// K0 and C0 as vectors, K1 and C1 as matrices whose column j is K1_j (C1_j), so forming
    /// K(T) or C(T) is one matrix-vector product over contiguous memory.
    k0: DVector<f64>,
    k1: DMatrix<f64>,
    c0: DVector<f64>,
    c1: DMatrix<f64>,
    /// Reduced load per unit panel flux: column p = Σ_a w_a A_p Φ(dof_a, :)ᵀ.
    load_map: DMatrix<f64>,
    /// Column p: panel p's wall temperature per coefficient.
    surface_map: DMatrix<f64>,
    /// Column i: structural node i's temperature per coefficient.
    node_map: DMatrix<f64>,
    /// Column i: structural node i's lower-minus-upper difference per coefficient (faces when
    /// solid, skin means when built up; [`FullOrder::node_difference_weights`]).
    difference_map: DMatrix<f64>,
    /// Φᵀ 1: the coefficients of a uniform unit field.
    uniform: DVector<f64>,
    /// Where the basis came from, for messages ("in memory" unless [`Pod::with_basis_file`]).
    basis_file: String,
    /// The cache file the basis came from (when built through the registry).
    cache: Option<hsv_core::thermal::CacheUse>,
    // Scratch.
    surface_k: Vec<f64>,
    matrix: BandedMatrix,
    /// C(T) and K(T) of the current Picard iterate ([`packed_lower`]).
    capacity: DVector<f64>,
    conduction: DVector<f64>,
    load: DVector<f64>,
    midpoint: DVector<f64>,
    iterate: DVector<f64>,
    rhs: DVector<f64>,
    picard_iterations: usize,
}

/// Row j, column `node`: Σ_levels w φ_j(node, level), the structure's mean temperature (or
/// through-thickness difference, as `weights` say) of POD mode j at each plate node.
fn level_map(grid: &ThermalGrid, phi: &DMatrix<f64>, weights: &[(usize, f64)]) -> DMatrix<f64> {
    let r = phi.ncols();
    let mut map = DMatrix::zeros(r, grid.n_plate_nodes);
    for node in 0..grid.n_plate_nodes {
        for &(level, w) in weights {
            for j in 0..r {
                map[(j, node)] += w * phi[(grid.dof(node, level), j)];
            }
        }
    }
    map
}

impl Pod {
    /// Projects `full` onto the first `settings.modes` modes of `basis`.
    pub fn new(full: &FullOrder, basis: PodBasis, settings: Settings) -> Result<Self, ModelError> {
        let grid = full.thermal_grid();
        if basis.modes.nrows() != grid.n_dofs() {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "the POD basis has {} temperatures per mode, the full-order grid {}",
                    basis.modes.nrows(),
                    grid.n_dofs()
                ),
            ));
        }
        if basis.full_order.resolved() != full.settings().resolved() {
            return Err(ModelError::inconsistent(
                NAME,
                "the POD basis was built for other [models.full-order] settings; rebuild it",
            ));
        }
        let r = settings.modes;
        if !(1..=basis.n_modes()).contains(&r) {
            return Err(ModelError::out_of_range(
                NAME,
                "modes",
                r as f64,
                format!("1 to {}, the modes in the basis", basis.n_modes()),
            ));
        }
        // The settings' own ranges, as the constructor checks them (a hand-built model too).
        if let Some((key, value, allowed)) = settings.first_invalid() {
            return Err(ModelError::out_of_range(NAME, &key, value, allowed));
        }
        let phi = basis.modes.columns(0, r).clone_owned();
        let (lo, hi) = basis.temperature_range_k;
        let lines: Vec<[f64; 4]> = full
            .materials()
            .iter()
            .map(|m| property_lines(m, lo, hi))
            .collect::<Result<_, _>>()?;
        // Conduction: per element, A_e = Φ_eᵀ G_e Φ_e.
        let mut k0 = DMatrix::zeros(r, r);
        let mut k1 = vec![DMatrix::zeros(r, r); r];
        for e in &grid.elements {
            let phi_e = DMatrix::from_fn(8, r, |a, j| phi[(e.dofs[a], j)]);
            let g = DMatrix::from_row_slice(8, 8, &e.conduction_m);
            let a_e = phi_e.transpose() * g * &phi_e;
            let [ka, kb, _, _] = lines[e.material];
            add_scaled(&mut k0, ka, &a_e);
            for j in 0..r {
                let mean = phi_e.column(j).sum() / 8.0;
                add_scaled(&mut k1[j], kb * mean, &a_e);
            }
        }
        // Capacity: c_i(T) = c0_i + c1_i T_i.
        let nm = grid.n_materials;
        let n = grid.n_dofs();
        let mut c0_diag = DVector::zeros(n);
        let mut c1_diag = DVector::zeros(n);
        for i in 0..n {
            for (m, material) in full.materials().iter().enumerate() {
                let v = grid.volume_m3[i * nm + m] * material.density_kg_m3;
                c0_diag[i] += v * lines[m][2];
                c1_diag[i] += v * lines[m][3];
            }
        }
        let weighted = |w: &DVector<f64>| {
            let scaled = DMatrix::from_fn(n, r, |i, j| w[i] * phi[(i, j)]);
            phi.transpose() * scaled
        };
        let c0 = weighted(&c0_diag);
        let c1: Vec<DMatrix<f64>> = (0..r)
            .map(|j| weighted(&c1_diag.component_mul(&phi.column(j))))
            .collect();
        // Inputs and outputs.
        let map = full.panel_map();
        let n_panels = map.n_panels();
        let mut load_map = DMatrix::zeros(r, n_panels);
        let mut surface_map = DMatrix::zeros(r, n_panels);
        for p in 0..n_panels {
            for (dof, w) in map.entries(p) {
                for j in 0..r {
                    let v = phi[(dof, j)];
                    load_map[(j, p)] += w * map.loaded_area_m2[p] * v;
                    surface_map[(j, p)] += w * v;
                }
            }
        }
        let node_map = level_map(grid, &phi, full.node_average_weights());
        let difference_map = level_map(grid, &phi, full.node_difference_weights());
        let uniform = phi.transpose() * DVector::from_element(n, 1.0);
        Ok(Self {
            difference_map,
            matrix: BandedMatrix::zeros(r, r.saturating_sub(1)),
            capacity: DVector::zeros(r * (r + 1) / 2),
            conduction: DVector::zeros(r * (r + 1) / 2),
            load: DVector::zeros(r),
            midpoint: DVector::zeros(r),
            iterate: DVector::zeros(r),
            rhs: DVector::zeros(r),
            picard_iterations: 0,
            plate: full.plate_grid().clone(),
            settings,
            basis,
            r,
            k0: packed_lower(&k0),
            k1: packed_columns(&k1),
            c0: packed_lower(&c0),
            c1: packed_columns(&c1),
            surface_k: vec![0.0; n_panels],
            basis_file: "(a basis in memory)".to_owned(),
            cache: None,
            load_map,
            surface_map,
            node_map,
            uniform,
        })
    }

    /// Names the file the basis was read from, for the messages of [`Pod::check_range`].
    pub fn with_basis_file(mut self, path: impl Into<String>) -> Self {
        self.basis_file = path.into();
        self
    }

    /// Records the cache file the basis came from and whether it was reused or trained.
    pub fn with_cache_use(mut self, cache: hsv_core::thermal::CacheUse) -> Self {
        self.cache = Some(cache);
        self
    }

    /// Refuses coefficients whose surface temperatures leave the basis's snapshot range by
    /// more than [`range_margin_k`]: the basis was built for another run, and its property
    /// lines and modes would be extrapolated silently.
    fn check_range(&mut self, coefficients: &DVector<f64>, dt_s: f64) -> Result<(), ModelError> {
        let (lo, hi) = self.basis.temperature_range_k;
        let margin = range_margin_k((lo, hi));
        for (p, out) in self.surface_k.iter_mut().enumerate() {
            *out = self.surface_map.column(p).dot(coefficients);
        }
        let (min, max) = self
            .surface_k
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                (a.min(t), b.max(t))
            });
        let (value, side) = if max > hi + margin {
            (max, "above")
        } else if min < lo - margin {
            (min, "below")
        } else {
            return Ok(());
        };
        Err(ModelError::inconsistent(
            NAME,
            format!(
                "a wall temperature of {value:.1} K after a {dt_s} s step is {side} the range \
                 {lo:.1}-{hi:.1} K (± {margin:.0} K) of the snapshots the POD basis {} was built \
                 from; rebuild it from conditions that cover this run ([models.pod.training]) \
                 or use the full-order model",
                self.basis_file
            ),
        ))
    }

    pub fn basis(&self) -> &PodBasis {
        &self.basis
    }

    /// Picard iterations of the last step.
    pub fn last_picard_iterations(&self) -> usize {
        self.picard_iterations
    }

    /// The full-order temperature field of coefficients `state`, Φ a.
    pub fn reconstruct(&self, state: &DVector<f64>) -> DVector<f64> {
        self.basis.modes.columns(0, self.r) * state
    }

    /// Coefficients of the full-order field `temperatures`, Φᵀ T.
    pub fn project(&self, temperatures: &DVector<f64>) -> DVector<f64> {
        self.basis.modes.columns(0, self.r).transpose() * temperatures
    }
}

impl ConductionModel for Pod {
    fn name(&self) -> &str {
        NAME
    }

    fn n_states(&self) -> usize {
        self.r
    }

    fn n_nodes(&self) -> usize {
        self.node_map.ncols()
    }

    fn n_surface_panels(&self) -> usize {
        self.surface_map.ncols()
    }

    fn uniform_state(&self, temperature_k: f64) -> Result<DVector<f64>, ModelError> {
        if !(temperature_k.is_finite() && temperature_k > 0.0) {
            return Err(ModelError::out_of_range(
                NAME,
                "temperature (K)",
                temperature_k,
                "finite and > 0",
            ));
        }
        Ok(&self.uniform * temperature_k)
    }

    fn step(
        &mut self,
        state: &mut DVector<f64>,
        surface_heat_flux_w_m2: &[f64],
        dt_s: f64,
    ) -> Result<(), ModelError> {
        if state.len() != self.r || surface_heat_flux_w_m2.len() != self.load_map.ncols() {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "{} coefficients and {} heat fluxes for a model of {} modes and {} panels",
                    state.len(),
                    surface_heat_flux_w_m2.len(),
                    self.r,
                    self.load_map.ncols()
                ),
            ));
        }
        check_step_inputs(NAME, surface_heat_flux_w_m2, dt_s)?;
        let r = self.r;
        for j in 0..r {
            self.load[j] = 0.0;
        }
        for (p, &q) in surface_heat_flux_w_m2.iter().enumerate() {
            self.load.axpy(q, &self.load_map.column(p), 1.0);
        }
        self.iterate.copy_from(state);
        for iteration in 1..=self.settings.max_picard_iterations {
            self.midpoint.copy_from(state);
            self.midpoint += &self.iterate;
            self.midpoint *= 0.5;
            // C(T) and K(T) are symmetric: only their lower triangles are formed and read (the
            // system matrix's Cholesky factorization and the symmetric product C(T) a).
            self.capacity.copy_from(&self.c0);
            self.capacity.gemv(1.0, &self.c1, &self.midpoint, 1.0);
            self.conduction.copy_from(&self.k0);
            self.conduction.gemv(1.0, &self.k1, &self.iterate, 1.0);
            self.matrix.clear();
            let mut idx = 0;
            for b in 0..r {
                for a in b..r {
                    let v = self.capacity[idx] / dt_s + self.conduction[idx];
                    self.matrix.add(a, b, v);
                    idx += 1;
                }
            }
            self.matrix.factorize().map_err(|e| {
                ModelError::inconsistent(
                    NAME,
                    format!(
                        "reduced conduction matrix is not positive definite (pivot {} at mode \
                         {}); the state left the range the basis represents",
                        e.pivot, e.row
                    ),
                )
            })?;
            packed_symmetric_mul(1.0 / dt_s, &self.capacity, state, &mut self.rhs);
            self.rhs += &self.load;
            self.matrix.solve_in_place(self.rhs.as_mut_slice());
            let mut change = 0.0;
            for j in 0..r {
                change += (self.rhs[j] - self.iterate[j]).powi(2);
            }
            let change = change.sqrt();
            self.iterate.copy_from(&self.rhs);
            if !change.is_finite() {
                return Err(ModelError::NonFinite {
                    model: NAME.to_owned(),
                    quantity: "mode coefficient".to_owned(),
                    location: format!(" in Picard iteration {iteration}"),
                });
            }
            if change < self.settings.picard_tolerance_k {
                self.picard_iterations = iteration;
                let converged = std::mem::replace(&mut self.iterate, DVector::zeros(0));
                let checked = self.check_range(&converged, dt_s);
                self.iterate = converged;
                checked?;
                state.copy_from(&self.iterate);
                return Ok(());
            }
        }
        Err(ModelError::inconsistent(
            NAME,
            format!(
                "Picard iteration did not converge to {} K in {} iterations (time step {dt_s} s)",
                self.settings.picard_tolerance_k, self.settings.max_picard_iterations
            ),
        ))
    }

    fn node_grid(&self) -> Option<&SurfaceGrid> {
        Some(&self.plate)
    }

    fn cache(&self) -> Option<hsv_core::thermal::CacheUse> {
        self.cache.clone()
    }

    fn surface_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        for (p, out) in out_k.iter_mut().enumerate().take(self.surface_map.ncols()) {
            *out = self.surface_map.column(p).dot(state);
        }
    }

    fn node_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        for (i, out) in out_k.iter_mut().enumerate().take(self.node_map.ncols()) {
            *out = self.node_map.column(i).dot(state);
        }
    }

    fn node_temperature_differences(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        for (i, out) in out_k
            .iter_mut()
            .enumerate()
            .take(self.difference_map.ncols())
        {
            *out = self.difference_map.column(i).dot(state);
        }
    }
}
