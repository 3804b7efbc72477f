//! Rigid design models for control from the full linearization of the trimmed flexible vehicle.
//!
//! The structural states (body modes and both surfaces' Ritz coordinates with their rates) are
//! removed by static residualization: they are set to their quasi-static response, ẋ_s = 0, so
//! x_s = −A_ss⁻¹ (A_sr x_r + B_s u) and A_red = A_rr − A_rs A_ss⁻¹ A_sr,
//! B_red = B_r − A_rs A_ss⁻¹ B_s. This keeps the static aeroelastic effect of the flexible
//! structure on the rigid-body derivatives and drops only its dynamics (the lowest structural
//! mode of the sample is about 9 Hz, the short period about 0.3 Hz). The other rigid axis's
//! states and the neutral north/east position and heading (nothing depends on them) are
//! truncated. The remaining rigid states are then mapped to measured outputs with the
//! linearization's C rows, z = T x_r, so a state-feedback law reads its state from
//! [`MeasuredOutputs`](hsv_core::control::MeasuredOutputs).

use hsv_core::control::LinearDesignModel;
use nalgebra::DMatrix;

use crate::dynamics::LinearModel;

/// One axis of the design: rigid states of the full model, the outputs that measure them (same
/// count; each the linearization's output name and a [`MeasuredOutputs`] name, which agree),
/// and the inputs used.
///
/// [`MeasuredOutputs`]: hsv_core::control::MeasuredOutputs
pub struct Axis {
    pub rigid_states: &'static [&'static str],
    pub outputs: &'static [&'static str],
    pub inputs: &'static [&'static str],
}

/// Longitudinal: u, w, q, θ, h measured as airspeed, α, q, θ, h; symmetric elevon and φ.
pub const LONGITUDINAL: Axis = Axis {
    rigid_states: &["u_m_s", "w_m_s", "q_rad_s", "pitch_rad", "down_m"],
    outputs: &[
        "airspeed_m_s",
        "alpha_rad",
        "q_rad_s",
        "pitch_rad",
        "altitude_m",
    ],
    inputs: &["symmetric_elevon_rad", "fuel_equivalence_ratio"],
};

/// Lateral: v, p, r, φ measured as β, p, r, roll; differential elevon.
pub const LATERAL: Axis = Axis {
    rigid_states: &["v_m_s", "p_rad_s", "r_rad_s", "roll_rad"],
    outputs: &["beta_rad", "p_rad_s", "r_rad_s", "roll_rad"],
    inputs: &["differential_elevon_rad"],
};

/// Whether a state of the full model is structural (residualized).
fn is_structural(name: &str) -> bool {
    name.starts_with("body_eta") || name.starts_with("surface_")
}

fn index_of(names: &[String], wanted: &str, what: &str) -> Result<usize, String> {
    names
        .iter()
        .position(|n| n == wanted)
        .ok_or_else(|| format!("the linear model has no {what} `{wanted}`"))
}

/// The residualized rigid design model of `axis` from the full linear model.
pub fn design_model(full: &LinearModel, axis: &Axis) -> Result<LinearDesignModel, String> {
    let r: Vec<usize> = axis
        .rigid_states
        .iter()
        .map(|s| index_of(&full.state_names, s, "state"))
        .collect::<Result<_, _>>()?;
    let s: Vec<usize> = (0..full.state_names.len())
        .filter(|&i| is_structural(&full.state_names[i]))
        .collect();
    let u: Vec<usize> = axis
        .inputs
        .iter()
        .map(|s| index_of(&full.input_names, s, "input"))
        .collect::<Result<_, _>>()?;
    let pick = |m: &DMatrix<f64>, rows: &[usize], cols: &[usize]| {
        DMatrix::from_fn(rows.len(), cols.len(), |i, j| m[(rows[i], cols[j])])
    };
    let a_rr = pick(&full.a, &r, &r);
    let b_r = pick(&full.b, &r, &u);
    let (a_red, b_red) = if s.is_empty() {
        (a_rr, b_r)
    } else {
        let a_ss = pick(&full.a, &s, &s);
        let a_rs = pick(&full.a, &r, &s);
        let a_sr = pick(&full.a, &s, &r);
        let b_s = pick(&full.b, &s, &u);
        let lu = a_ss.lu();
        let x_a = lu
            .solve(&a_sr)
            .ok_or("the structural block A_ss is singular: cannot residualize")?;
        let x_b = lu
            .solve(&b_s)
            .ok_or("the structural block A_ss is singular: cannot residualize")?;
        (a_rr - &a_rs * x_a, b_r - &a_rs * x_b)
    };
    let y: Vec<usize> = axis
        .outputs
        .iter()
        .map(|o| index_of(&full.output_names, o, "output"))
        .collect::<Result<_, _>>()?;
    let t = pick(&full.c, &y, &r);
    let t_inv = t
        .clone()
        .try_inverse()
        .ok_or("the measured outputs do not determine the rigid states (T singular)")?;
    Ok(LinearDesignModel {
        state_names: axis.outputs.iter().map(|m| m.to_string()).collect(),
        input_names: axis.inputs.iter().map(|s| s.to_string()).collect(),
        a: &t * a_red * t_inv,
        b: t * b_red,
        reduction: format!(
            "rigid states {} of {} kept, {} structural states statically residualized \
             (x_s = -A_ss^-1 (A_sr x_r + B_s u)), the rest truncated; states mapped to \
             measured outputs",
            r.len(),
            full.state_names.len(),
            s.len()
        ),
    })
}

/// The full linear model's state matrix closed by `laws`: A − Σ B_u K C_z, each law's design
/// states z read through the rows of C that measure them (so the structural dynamics the
/// design residualized stay in the loop).
pub fn closed_loop_matrix(
    full: &LinearModel,
    laws: &[hsv_core::control::StateFeedback],
) -> Result<DMatrix<f64>, String> {
    let mut a = full.a.clone();
    for law in laws {
        let y: Vec<usize> = law
            .state_names
            .iter()
            .map(|n| index_of(&full.output_names, n, "output"))
            .collect::<Result<_, _>>()?;
        let u: Vec<usize> = law
            .input_names
            .iter()
            .map(|n| index_of(&full.input_names, n, "input"))
            .collect::<Result<_, _>>()?;
        let c = DMatrix::from_fn(y.len(), full.c.ncols(), |i, j| full.c[(y[i], j)]);
        let b = DMatrix::from_fn(full.b.nrows(), u.len(), |i, j| full.b[(i, u[j])]);
        a -= b * &law.k * c;
    }
    Ok(a)
}

/// The eigenvalues (re, im) of [`closed_loop_matrix`], largest real part first.
pub fn closed_loop_eigenvalues(
    full: &LinearModel,
    laws: &[hsv_core::control::StateFeedback],
) -> Result<Vec<[f64; 2]>, String> {
    let a = closed_loop_matrix(full, laws)?;
    let eig = hsv_core::linalg::general_eigen(&a).map_err(|e| e.to_string())?;
    let mut values: Vec<[f64; 2]> = eig.values.iter().map(|c| [c.re, c.im]).collect();
    values.sort_by(|a, b| b[0].total_cmp(&a[0]));
    Ok(values)
}
