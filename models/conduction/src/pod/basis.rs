//! The POD basis: `PodBasis` from full-order temperature snapshots by the method of snapshots
//! (the `pod` module docs, **Basis**), the full-order runs that collect the snapshots, and the
//! basis's sealed JSON file.

use std::path::Path;

use hsv_core::error::ModelError;
use hsv_core::thermal::ConductionModel;
use nalgebra::{DMatrix, DVector};

use super::NAME;
use crate::full_order::{FullOrder, Settings as FullOrderSettings};
use crate::training::Training;

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
