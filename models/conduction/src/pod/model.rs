//! The POD Galerkin reduced model: `Pod`, the full-order equations projected onto a basis with
//! each material's properties linear in T (the `pod` module docs, **Galerkin projection** and
//! **Nonlinearity**), stepped by Picard iteration on r × r systems.

use hsv_core::error::ModelError;
use hsv_core::linalg::BandedMatrix;
use hsv_core::material::Material;
use hsv_core::surface_grid::SurfaceGrid;
use hsv_core::thermal::{ConductionModel, check_step_inputs};
use nalgebra::{DMatrix, DVector};

use super::basis::PodBasis;
use super::{NAME, Settings};
use crate::full_order::FullOrder;
use crate::grid::ThermalGrid;

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

/// How far, K, a step's surface temperatures may leave the basis's snapshot range
/// (`temperature_range_k`) before the step is refused: the larger of 25 K and a tenth of the
/// range. Within it the property lines extrapolate little; beyond it the basis was built for
/// another run (our choice, not the paper's).
pub fn range_margin_k((lo, hi): (f64, f64)) -> f64 {
    (0.1 * (hi - lo)).max(25.0)
}

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

    /// Names the file the basis was read from, for the messages of `Pod::check_range`.
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
