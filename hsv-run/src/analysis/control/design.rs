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

/// What lies between a sampled state-feedback law and the vehicle's inputs in the linear
/// closed loop: the actuators' first-order lags and the loop's transport delay.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoopDynamics {
    /// Elevon servo time constant, s (0: none).
    pub elevon_time_constant_s: f64,
    /// Fuel-system time constant of φ, s (0: none).
    pub phi_time_constant_s: f64,
    /// Delay from measurement to command, s: half the sample interval (the zero-order hold's
    /// average delay; Franklin, Powell & Workman, "Digital Control of Dynamic Systems", 3rd ed.,
    /// §6.3) plus the sensors' transport delay.
    pub delay_s: f64,
}

impl LoopDynamics {
    fn time_constant_s(&self, input: &str) -> f64 {
        if input == "fuel_equivalence_ratio" {
            self.phi_time_constant_s
        } else {
            self.elevon_time_constant_s
        }
    }
}

/// The full linear model closed by `laws` through `dynamics`, each law's design states z read
/// through the rows of C that measure them (so the structural dynamics the design residualized
/// stay in the loop; the design states are states, with no feedthrough D).
///
/// The commands c = −Σ K C_z x of the inputs the laws drive pass a first-order Padé delay
/// e^(−sT) ≈ (1 − sT/2)/(1 + sT/2) (state w, ẇ = (4c − 2w)/T, output w − c) and then the
/// actuator lag τ ȧ = d − a, whose position a drives the vehicle: states [x, a, w], each
/// block present when its time constant is. With neither it is A − Σ B K C_z.
pub fn closed_loop_matrix(
    full: &LinearModel,
    laws: &[hsv_core::control::StateFeedback],
    dynamics: &LoopDynamics,
) -> Result<DMatrix<f64>, String> {
    let n = full.a.nrows();
    // The inputs the laws drive, and the command gain c = G x on each.
    let mut driven: Vec<usize> = Vec::new();
    let mut gain_rows: Vec<nalgebra::RowDVector<f64>> = Vec::new();
    for law in laws {
        let y: Vec<usize> = law
            .state_names
            .iter()
            .map(|name| index_of(&full.output_names, name, "output"))
            .collect::<Result<_, _>>()?;
        let c = DMatrix::from_fn(y.len(), n, |i, j| full.c[(y[i], j)]);
        let g = -(&law.k * c);
        for (row, name) in law.input_names.iter().enumerate() {
            let u = index_of(&full.input_names, name, "input")?;
            match driven.iter().position(|&d| d == u) {
                Some(k) => gain_rows[k] += g.row(row),
                None => {
                    driven.push(u);
                    gain_rows.push(g.row(row).into_owned());
                }
            }
        }
    }
    let m = driven.len();
    let g = DMatrix::from_fn(m, n, |i, j| gain_rows[i][j]);
    let b = DMatrix::from_fn(n, m, |i, j| full.b[(i, driven[j])]);
    let tau: Vec<f64> = driven
        .iter()
        .map(|&u| dynamics.time_constant_s(&full.input_names[u]))
        .collect();
    let delay = dynamics.delay_s;
    if tau.iter().any(|t| !(t.is_finite() && *t >= 0.0)) || !(delay.is_finite() && delay >= 0.0) {
        return Err(format!(
            "actuator time constants {tau:?} s and delay {delay} s must be >= 0"
        ));
    }
    let lagged: Vec<usize> = (0..m).filter(|&k| tau[k] > 0.0).collect();
    let (na, nw) = (lagged.len(), if delay > 0.0 { m } else { 0 });
    let mut a = DMatrix::zeros(n + na + nw, n + na + nw);
    a.view_mut((0, 0), (n, n)).copy_from(&full.a);
    // The delayed command d = w − G x (or G x without the delay), as rows over [x, a, w].
    let command_row = |k: usize| {
        let mut row = nalgebra::RowDVector::zeros(n + na + nw);
        row.columns_mut(0, n).copy_from(&g.row(k));
        if nw > 0 {
            row.columns_mut(0, n).neg_mut();
            row[n + na + k] = 1.0;
        }
        row
    };
    for k in 0..m {
        let d = command_row(k);
        match lagged.iter().position(|&l| l == k) {
            // The actuator position drives the vehicle; τ ȧ = d − a.
            Some(slot) => {
                for i in 0..n {
                    a[(i, n + slot)] += b[(i, k)];
                }
                let mut row = d / tau[k];
                row[n + slot] -= 1.0 / tau[k];
                let mut target = a.row_mut(n + slot);
                target += row;
            }
            // No lag: the (delayed) command drives the vehicle directly.
            None => {
                for i in 0..n {
                    let mut target = a.row_mut(i);
                    target += &d * b[(i, k)];
                }
            }
        }
        if nw > 0 {
            // ẇ = (4 c − 2 w) / T with c = G x.
            let w = n + na + k;
            for j in 0..n {
                a[(w, j)] += 4.0 * g[(k, j)] / delay;
            }
            a[(w, w)] -= 2.0 / delay;
        }
    }
    Ok(a)
}

/// The eigenvalues (re, im) of [`closed_loop_matrix`], largest real part first.
pub fn closed_loop_eigenvalues(
    full: &LinearModel,
    laws: &[hsv_core::control::StateFeedback],
    dynamics: &LoopDynamics,
) -> Result<Vec<[f64; 2]>, String> {
    let a = closed_loop_matrix(full, laws, dynamics)?;
    let eig = hsv_core::linalg::general_eigen(&a).map_err(|e| e.to_string())?;
    let mut values: Vec<[f64; 2]> = eig.values.iter().map(|c| [c.re, c.im]).collect();
    values.sort_by(|a, b| b[0].total_cmp(&a[0]));
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Complex, DVector};

    /// ẋ = a x + b u, y = x, under u = −k y.
    fn scalar_loop(dynamics: LoopDynamics) -> Vec<Complex<f64>> {
        let (a, b, k) = (2.0, 3.0, 2.0);
        let model = LinearModel {
            state_names: vec!["w_m_s".into()],
            input_names: vec!["symmetric_elevon_rad".into()],
            output_names: vec!["alpha_rad".into()],
            x0: DVector::zeros(1),
            u0: DVector::zeros(1),
            a: DMatrix::from_element(1, 1, a),
            b: DMatrix::from_element(1, 1, b),
            c: DMatrix::from_element(1, 1, 1.0),
            d: DMatrix::zeros(1, 1),
        };
        let law = hsv_core::control::StateFeedback {
            state_names: vec!["alpha_rad".into()],
            input_names: vec!["symmetric_elevon_rad".into()],
            k: DMatrix::from_element(1, 1, k),
        };
        let closed = closed_loop_matrix(&model, &[law], &dynamics).unwrap();
        hsv_core::linalg::general_eigen(&closed)
            .unwrap()
            .values
            .iter()
            .copied()
            .collect()
    }

    /// Each eigenvalue is a root of the loop's characteristic polynomial (coefficients highest
    /// power first), and there are as many as its degree.
    fn assert_roots_of(values: &[Complex<f64>], coefficients: &[f64]) {
        assert_eq!(values.len(), coefficients.len() - 1, "{values:?}");
        for &s in values {
            let p = coefficients
                .iter()
                .fold(Complex::new(0.0, 0.0), |acc, &c| acc * s + c);
            let scale: f64 = coefficients
                .iter()
                .enumerate()
                .map(|(i, c)| c.abs() * s.norm().powi((coefficients.len() - 1 - i) as i32))
                .sum();
            assert!(p.norm() < 1e-12 * scale, "p({s}) = {p}");
        }
    }

    /// Closed forms of the scalar loop (a = 2, b = 3, k = 2): without dynamics s = a − bk; with
    /// an actuator lag τ, (s − a)(τs + 1) + bk = 0; with a first-order Padé delay T as well,
    /// (s − a)(τs + 1)(1 + sT/2) + bk(1 − sT/2) = 0 (Franklin, Powell & Emami-Naeini, "Feedback
    /// Control of Dynamic Systems", §5.6 for the Padé form).
    #[test]
    fn closed_loop_has_the_closed_form_characteristic_polynomial() {
        let (a, bk, tau, t) = (2.0, 6.0, 0.1, 0.02);
        let bare = scalar_loop(LoopDynamics::default());
        assert_roots_of(&bare, &[1.0, bk - a]);
        let lag = LoopDynamics {
            elevon_time_constant_s: tau,
            ..Default::default()
        };
        assert_roots_of(&scalar_loop(lag), &[tau, 1.0 - a * tau, bk - a]);
        let delay = LoopDynamics {
            delay_s: t,
            ..Default::default()
        };
        // (s − a)(1 + sT/2) + bk(1 − sT/2)
        assert_roots_of(
            &scalar_loop(delay),
            &[t / 2.0, 1.0 - a * t / 2.0 - bk * t / 2.0, bk - a],
        );
        let both = LoopDynamics {
            elevon_time_constant_s: tau,
            delay_s: t,
            ..Default::default()
        };
        // (τs² + (1 − aτ)s − a)(1 + sT/2) + bk(1 − sT/2)
        let h = t / 2.0;
        assert_roots_of(
            &scalar_loop(both),
            &[
                tau * h,
                tau + (1.0 - a * tau) * h,
                (1.0 - a * tau) - a * h - bk * h,
                -a + bk,
            ],
        );
    }
}
