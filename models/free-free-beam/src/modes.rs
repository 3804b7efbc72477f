//! Free-free vibration modes: the generalized eigenproblem K φ = ω² M φ, rigid-body modes
//! identified and removed, elastic modes mass-normalized and classified by their DOF content.
//!
//! 1. All eigenpairs of the dense problem ([`hsv_core::linalg::generalized_symmetric_eigen`]:
//!    Cholesky M = L Lᵀ and the symmetric standard problem L⁻¹ K L⁻ᵀ z = ω² z, φ = L⁻ᵀ z;
//!    Bathe, Finite Element Procedures, §10.2.5).
//! 2. Rigid-body modes are the six eigenvectors that lie in the span of the analytic rigid-body
//!    motions R (M-projection content ≈ 1, elastic modes ≈ 0), not the six lowest by index;
//!    the split must be clean and their ω² negligible against the first elastic one.
//! 3. The dense solve has absolute eigenvalue errors of about ε‖K‖/‖M‖, large against the low
//!    ω² of a fine mesh; so the lowest elastic vectors (rigid content projected out) span a
//!    subspace in which a Rayleigh-Ritz step with the original K and M gives the modes with
//!    relative accuracy (Bathe §11.6: subspace iteration's Ritz step). Modes of different kinds
//!    with (numerically) equal frequencies are separated by their DOF-group energies.

use hsv_core::error::ModelError;
use hsv_core::linalg::{EigenError, SymmetricEigenSolver, generalized_symmetric_eigen};
use nalgebra::DMatrix;

use crate::fe::ModeKind;

/// Number of rigid-body modes of a free body in space.
pub const RIGID_BODY_MODES: usize = 6;

/// Elastic modes carried past the last one needed, so the Ritz subspace holds them all well.
const RITZ_MARGIN: usize = 12;

/// Rigid-body ω² must be below this fraction of the first elastic ω².
const RIGID_OMEGA2_FRACTION: f64 = 1e-3;

/// Refined eigenvalues closer than this (relative) form a degenerate cluster whose basis is
/// re-chosen to separate the DOF groups.
const DEGENERATE_RELATIVE_GAP: f64 = 1e-9;

/// The lowest elastic modes of a free-free structure, ascending in frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct ElasticModes {
    /// ω², rad²/s², = φᵀKφ of each mass-normalized shape.
    pub omega2: Vec<f64>,
    /// Mass-normalized shapes (φᵀMφ = 1), one column per mode.
    pub shapes: DMatrix<f64>,
    /// Dominant DOF group of each mode.
    pub kinds: Vec<ModeKind>,
    /// Share of each mode's kinetic energy in each DOF group, [`ModeKind::ALL`] order.
    pub kinetic_energy_fractions: Vec<[f64; 4]>,
    /// ω² of the six identified rigid-body modes, rad²/s² (round-off around zero).
    pub rigid_body_omega2: Vec<f64>,
    /// Share of each identified rigid-body mode in the span of the analytic rigid motions (≈ 1).
    pub rigid_body_content: Vec<f64>,
    /// Largest rigid-motion content among the elastic modes of the full solve (≈ 0).
    pub max_elastic_rigid_content: f64,
}

/// Solves K φ = ω² M φ for a free structure whose rigid-body motions are the columns of
/// `rigid_body`; `dof_kinds` names the group of every DOF; `wanted` is how many modes of each
/// kind ([`ModeKind::ALL`] order) the caller will keep, which sets the size of the Ritz step.
pub fn free_free_modes(
    model: &str,
    mass: &DMatrix<f64>,
    stiffness: &DMatrix<f64>,
    rigid_body: &DMatrix<f64>,
    dof_kinds: &[ModeKind],
    wanted: [usize; 4],
) -> Result<ElasticModes, ModelError> {
    let n = mass.nrows();
    let singular = || ModelError::inconsistent(model, "singular mass matrix factor");
    let full =
        generalized_symmetric_eigen(stiffness, mass, n).map_err(|e| eigen_error(model, e))?;
    let (eigenvalues, all_shapes) = (&full.values, &full.vectors);

    // M-orthonormal rigid basis R̂ = R G⁻ᵀ with G Gᵀ = Rᵀ M R; content of φ = |R̂ᵀ M φ|².
    let gram = rigid_body.transpose() * mass * rigid_body;
    let g = gram
        .cholesky()
        .ok_or_else(|| {
            ModelError::inconsistent(model, "the rigid-body motions are linearly dependent")
        })?
        .l();
    let rigid_hat = g
        .solve_lower_triangular(&rigid_body.transpose())
        .ok_or_else(singular)?
        .transpose();
    let m_rigid = mass * &rigid_hat;
    let content_matrix = m_rigid.transpose() * all_shapes;
    let content: Vec<f64> = (0..n)
        .map(|j| content_matrix.column(j).norm_squared())
        .collect();
    let mut by_content: Vec<usize> = (0..n).collect();
    by_content.sort_by(|&a, &b| content[b].total_cmp(&content[a]));
    let rigid: Vec<usize> = by_content[..RIGID_BODY_MODES].to_vec();
    let rigid_body_content: Vec<f64> = rigid.iter().map(|&j| content[j]).collect();
    let max_elastic_rigid_content = content[by_content[RIGID_BODY_MODES]];
    if rigid_body_content.iter().any(|&p| p < 0.99) || max_elastic_rigid_content > 0.01 {
        return Err(ModelError::inconsistent(
            model,
            format!(
                "cannot separate the six rigid-body modes: rigid-motion content {rigid_body_content:?} \
                 of the best six, {max_elastic_rigid_content:e} of the next"
            ),
        ));
    }
    let rigid_body_omega2: Vec<f64> = rigid.iter().map(|&j| eigenvalues[j]).collect();

    // Elastic modes of the full solve, ascending.
    let mut elastic: Vec<usize> = by_content[RIGID_BODY_MODES..].to_vec();
    elastic.sort_by(|&a, &b| eigenvalues[a].total_cmp(&eigenvalues[b]));
    let first_elastic = elastic
        .first()
        .map(|&j| eigenvalues[j])
        .ok_or_else(|| ModelError::inconsistent(model, "the model has no elastic modes"))?;
    if first_elastic.is_nan() || first_elastic <= 0.0 {
        return Err(ModelError::inconsistent(
            model,
            format!(
                "lowest elastic squared frequency {first_elastic:e} rad^2/s^2 is not positive: \
                 a mechanism (zero stiffness)"
            ),
        ));
    }
    if let Some(bad) = rigid_body_omega2
        .iter()
        .find(|w2| w2.is_nan() || w2.abs() >= RIGID_OMEGA2_FRACTION * first_elastic)
    {
        return Err(ModelError::inconsistent(
            model,
            format!(
                "a rigid-body mode has squared frequency {bad:e} rad^2/s^2, not negligible \
                 against the first elastic one ({first_elastic:e}): rigid motion strains the model"
            ),
        ));
    }

    // Ritz subspace: the lowest elastic vectors until every wanted kind is covered, plus margin.
    let mut seen = [0usize; 4];
    let mut needed = 0;
    for (i, &j) in elastic.iter().enumerate() {
        if seen.iter().zip(&wanted).all(|(s, w)| s >= w) {
            break;
        }
        let phi = all_shapes.column(j).into_owned();
        let kind = dominant(&group_fractions(mass, dof_kinds, &phi));
        seen[kind.index()] += 1;
        needed = i + 1;
    }
    let m = (needed + RITZ_MARGIN).min(elastic.len());
    let mut basis = DMatrix::from_fn(n, m, |r, c| all_shapes[(r, elastic[c])]);
    // Remove round-off rigid content so every Ritz vector is exactly free of rigid motion.
    let coupling = m_rigid.transpose() * &basis;
    basis -= &rigid_hat * coupling;

    let (omega2, shapes) = rayleigh_ritz(model, mass, stiffness, &basis)?;
    let mut shapes = shapes;
    separate_degenerate_clusters(model, mass, dof_kinds, &omega2, &mut shapes)?;

    let mut kinds = Vec::with_capacity(m);
    let mut fractions = Vec::with_capacity(m);
    let mut refined_omega2 = Vec::with_capacity(m);
    for k in 0..m {
        let phi = shapes.column(k).into_owned();
        let modal_mass = (phi.transpose() * mass * &phi)[(0, 0)];
        if !(modal_mass.is_finite() && modal_mass > 0.0) {
            return Err(non_finite(
                model,
                "modal mass",
                format!(" of elastic mode {}", k + 1),
            ));
        }
        let phi = phi / modal_mass.sqrt();
        let w2 = (phi.transpose() * stiffness * &phi)[(0, 0)];
        if !w2.is_finite() {
            return Err(non_finite(
                model,
                "squared natural frequency",
                format!(" of elastic mode {}", k + 1),
            ));
        }
        let f = group_fractions(mass, dof_kinds, &phi);
        shapes.set_column(k, &phi);
        kinds.push(dominant(&f));
        fractions.push(f);
        refined_omega2.push(w2);
    }
    Ok(ElasticModes {
        omega2: refined_omega2,
        shapes,
        kinds,
        kinetic_energy_fractions: fractions,
        rigid_body_omega2,
        rigid_body_content,
        max_elastic_rigid_content,
    })
}

fn non_finite(model: &str, quantity: &str, location: String) -> ModelError {
    ModelError::NonFinite {
        model: model.to_owned(),
        quantity: quantity.to_owned(),
        location,
    }
}

/// A linear-algebra failure as a model error.
fn eigen_error(model: &str, e: EigenError) -> ModelError {
    match e {
        EigenError::NonFinite { matrix } => non_finite(model, matrix, String::new()),
        e => ModelError::inconsistent(model, format!("free-free modes: {e}")),
    }
}

/// Rayleigh-Ritz in the span of `basis`: (Vᵀ K V) y = ω² (Vᵀ M V) y, shapes V y ascending.
fn rayleigh_ritz(
    model: &str,
    mass: &DMatrix<f64>,
    stiffness: &DMatrix<f64>,
    basis: &DMatrix<f64>,
) -> Result<(Vec<f64>, DMatrix<f64>), ModelError> {
    let k_r = basis.transpose() * stiffness * basis;
    let m_r = basis.transpose() * mass * basis;
    let ritz = generalized_symmetric_eigen(&k_r, &m_r, basis.ncols()).map_err(|e| match e {
        EigenError::NotPositiveDefinite { .. } => {
            ModelError::inconsistent(model, "the Ritz basis is linearly dependent")
        }
        e => eigen_error(model, e),
    })?;
    Ok((ritz.values, basis * ritz.vectors))
}

/// The kind with the largest share.
fn dominant(fractions: &[f64; 4]) -> ModeKind {
    ModeKind::ALL
        .into_iter()
        .max_by(|a, b| fractions[a.index()].total_cmp(&fractions[b.index()]))
        .unwrap_or(ModeKind::Axial)
}

/// Kinetic-energy share of each DOF group, Σ_{i∈g} φ_i (Mφ)_i / φᵀMφ.
fn group_fractions(
    mass: &DMatrix<f64>,
    dof_kinds: &[ModeKind],
    phi: &nalgebra::DVector<f64>,
) -> [f64; 4] {
    let m_phi = mass * phi;
    let mut f = [0.0; 4];
    for (i, kind) in dof_kinds.iter().enumerate() {
        f[kind.index()] += phi[i] * m_phi[i];
    }
    let total: f64 = f.iter().sum();
    if total > 0.0 {
        for v in &mut f {
            *v /= total;
        }
    }
    f
}

/// Within each cluster of (numerically) equal eigenvalues any basis is a valid set of modes;
/// choose the one that diagonalizes the DOF-group kinetic energies, so modes of different kinds
/// that happen to share a frequency are not returned mixed.
fn separate_degenerate_clusters(
    model: &str,
    mass: &DMatrix<f64>,
    dof_kinds: &[ModeKind],
    omega2: &[f64],
    shapes: &mut DMatrix<f64>,
) -> Result<(), ModelError> {
    let mut start = 0;
    while start < omega2.len() {
        let mut end = start + 1;
        while end < omega2.len()
            && (omega2[end] - omega2[end - 1]).abs()
                <= DEGENERATE_RELATIVE_GAP * omega2[end].abs().max(omega2[end - 1].abs())
        {
            end += 1;
        }
        if end - start > 1 {
            let k = end - start;
            let cluster = shapes.columns(start, k).into_owned();
            let m_cluster = mass * &cluster;
            // Σ_g (g+1) C_g with C_g = Φᵀ M_g Φ: distinct weights separate the groups.
            let weighted = DMatrix::from_fn(k, k, |a, b| {
                dof_kinds
                    .iter()
                    .enumerate()
                    .map(|(i, kind)| {
                        (kind.index() + 1) as f64
                            * 0.5
                            * (cluster[(i, a)] * m_cluster[(i, b)]
                                + cluster[(i, b)] * m_cluster[(i, a)])
                    })
                    .sum::<f64>()
            });
            let mut weights = vec![0.0; k];
            let mut rotation = DMatrix::zeros(k, k);
            SymmetricEigenSolver::new(k)
                .decompose(&weighted, &mut weights, &mut rotation)
                .map_err(|e| eigen_error(model, e))?;
            shapes
                .columns_mut(start, k)
                .copy_from(&(cluster * rotation));
        }
        start = end;
    }
    Ok(())
}
