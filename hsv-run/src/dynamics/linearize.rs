//! Linear models by central differences around an operating point (paper Eqs. 6-7):
//! ẋ = A x + B u, y = C x + D u, with the paper's perturbation rule, and the paper's
//! sixth-order forward difference for a state derivative sampled from a short time history.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::{DynamicsError, check_finite, check_len};

/// The perturbation of paper Eq. 7: ε_k = `relative` |x_k| (1 % in the paper), or `absolute`
/// when the k-th operating value is zero. `absolute` is also a floor, so that a value that is
/// merely tiny does not give a step lost in round-off: ε_k = max(relative |x_k|, absolute).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerturbationRule {
    pub relative: f64,
    pub absolute: f64,
}

impl Default for PerturbationRule {
    /// The paper's 1 %, with 1e-6 (in the state's units) where the state is zero.
    fn default() -> Self {
        Self {
            relative: 0.01,
            absolute: 1e-6,
        }
    }
}

impl PerturbationRule {
    /// The step for an operating value: max(relative |x|, absolute).
    pub fn step(&self, value: f64) -> f64 {
        (self.relative * value.abs()).max(self.absolute)
    }

    /// The steps for every entry of an operating point; the error names a rule that gives a
    /// zero or non-finite step.
    pub fn steps(&self, point: &DVector<f64>) -> Result<DVector<f64>, DynamicsError> {
        for (quantity, value) in [
            ("relative perturbation", self.relative),
            ("absolute perturbation", self.absolute),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(DynamicsError::InvalidParameter {
                    quantity: quantity.into(),
                    value,
                    allowed: "finite and >= 0",
                });
            }
        }
        if self.absolute <= 0.0 {
            return Err(DynamicsError::InvalidParameter {
                quantity: "absolute perturbation".into(),
                value: self.absolute,
                allowed: "> 0 (the step where the operating value is zero)",
            });
        }
        check_finite(|| "operating point".into(), point.iter())?;
        Ok(point.map(|v| self.step(v)))
    }
}

/// Jacobians of `h(x, u)` (into a buffer of length `n_out`) by central differences with the
/// given steps: J_x[:, k] = (h(x + ε_k e_k, u) − h(x − ε_k e_k, u)) / 2ε_k (paper Eq. 6), and
/// likewise for u.
pub fn central_difference_jacobians<H, E>(
    mut h: H,
    x0: &DVector<f64>,
    u0: &DVector<f64>,
    n_out: usize,
    x_steps: &DVector<f64>,
    u_steps: &DVector<f64>,
) -> Result<(DMatrix<f64>, DMatrix<f64>), E>
where
    H: FnMut(&DVector<f64>, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
    E: From<DynamicsError>,
{
    check_len(|| "state perturbations".into(), x0.len(), x_steps.len())?;
    check_len(|| "input perturbations".into(), u0.len(), u_steps.len())?;
    for (what, steps) in [("state", x_steps), ("input", u_steps)] {
        if let Some((index, &value)) = steps
            .iter()
            .enumerate()
            .find(|(_, s)| !(s.is_finite() && **s > 0.0))
        {
            return Err(DynamicsError::InvalidParameter {
                quantity: format!("{what} perturbation {index}"),
                value,
                allowed: "finite and > 0",
            }
            .into());
        }
    }
    let mut plus = DVector::zeros(n_out);
    let mut minus = DVector::zeros(n_out);
    let mut x = x0.clone();
    let mut u = u0.clone();
    let mut jx = DMatrix::zeros(n_out, x0.len());
    for k in 0..x0.len() {
        let eps = x_steps[k];
        x[k] = x0[k] + eps;
        h(&x, &u, &mut plus)?;
        x[k] = x0[k] - eps;
        h(&x, &u, &mut minus)?;
        x[k] = x0[k];
        // The step actually taken (x0 ± ε rounds), so a linear h is recovered to round-off.
        let span = (x0[k] + eps) - (x0[k] - eps);
        jx.set_column(k, &((&plus - &minus) / span));
    }
    let mut ju = DMatrix::zeros(n_out, u0.len());
    for k in 0..u0.len() {
        let eps = u_steps[k];
        u[k] = u0[k] + eps;
        h(&x, &u, &mut plus)?;
        u[k] = u0[k] - eps;
        h(&x, &u, &mut minus)?;
        u[k] = u0[k];
        let span = (u0[k] + eps) - (u0[k] - eps);
        ju.set_column(k, &((&plus - &minus) / span));
    }
    check_finite(|| "Jacobian with respect to the state".into(), jx.iter())?;
    check_finite(|| "Jacobian with respect to the inputs".into(), ju.iter())?;
    Ok((jx, ju))
}

/// (A, B) of ẋ = f(x, u) around (x0, u0) by central differences with the paper's perturbation
/// rule (Eqs. 6-7). `f(x, u, ẋ)` writes the state derivative.
pub fn linearize<F, E>(
    f: F,
    x0: &DVector<f64>,
    u0: &DVector<f64>,
    rule: &PerturbationRule,
) -> Result<(DMatrix<f64>, DMatrix<f64>), E>
where
    F: FnMut(&DVector<f64>, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
    E: From<DynamicsError>,
{
    let x_steps = rule.steps(x0)?;
    let u_steps = rule.steps(u0)?;
    central_difference_jacobians(f, x0, u0, x0.len(), &x_steps, &u_steps)
}

/// (C, D) of y = g(x, u) (length `n_outputs`) around (x0, u0), as [`linearize`].
pub fn linearize_outputs<G, E>(
    g: G,
    x0: &DVector<f64>,
    u0: &DVector<f64>,
    n_outputs: usize,
    rule: &PerturbationRule,
) -> Result<(DMatrix<f64>, DMatrix<f64>), E>
where
    G: FnMut(&DVector<f64>, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
    E: From<DynamicsError>,
{
    let x_steps = rule.steps(x0)?;
    let u_steps = rule.steps(u0)?;
    central_difference_jacobians(g, x0, u0, n_outputs, &x_steps, &u_steps)
}

/// ẋ = A x + B u, y = C x + D u around an operating point, with the names of the states,
/// inputs and outputs (units in the names).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearModel {
    pub state_names: Vec<String>,
    pub input_names: Vec<String>,
    pub output_names: Vec<String>,
    pub x0: DVector<f64>,
    pub u0: DVector<f64>,
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub d: DMatrix<f64>,
}

impl LinearModel {
    /// Linearizes the dynamics `f` and outputs `g` (one per output name) around (x0, u0).
    #[allow(clippy::too_many_arguments)]
    pub fn build<F, G, E>(
        f: F,
        g: G,
        x0: &DVector<f64>,
        u0: &DVector<f64>,
        rule: &PerturbationRule,
        state_names: Vec<String>,
        input_names: Vec<String>,
        output_names: Vec<String>,
    ) -> Result<Self, E>
    where
        F: FnMut(&DVector<f64>, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
        G: FnMut(&DVector<f64>, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
        E: From<DynamicsError>,
    {
        let x_steps = rule.steps(x0)?;
        let u_steps = rule.steps(u0)?;
        Self::build_with_steps(
            f,
            g,
            x0,
            u0,
            (&x_steps, &u_steps),
            state_names,
            input_names,
            output_names,
        )
    }

    /// [`Self::build`] with the perturbation of every state and input given (`steps`: states,
    /// inputs), for states whose scale is not their operating value.
    #[allow(clippy::too_many_arguments)]
    pub fn build_with_steps<F, G, E>(
        f: F,
        g: G,
        x0: &DVector<f64>,
        u0: &DVector<f64>,
        steps: (&DVector<f64>, &DVector<f64>),
        state_names: Vec<String>,
        input_names: Vec<String>,
        output_names: Vec<String>,
    ) -> Result<Self, E>
    where
        F: FnMut(&DVector<f64>, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
        G: FnMut(&DVector<f64>, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
        E: From<DynamicsError>,
    {
        check_len(|| "state names".into(), x0.len(), state_names.len())?;
        check_len(|| "input names".into(), u0.len(), input_names.len())?;
        let (x_steps, u_steps) = steps;
        let (a, b) = central_difference_jacobians(f, x0, u0, x0.len(), x_steps, u_steps)?;
        let (c, d) = central_difference_jacobians(g, x0, u0, output_names.len(), x_steps, u_steps)?;
        Ok(Self {
            state_names,
            input_names,
            output_names,
            x0: x0.clone(),
            u0: u0.clone(),
            a,
            b,
            c,
            d,
        })
    }
}

/// Weights of the one-sided sixth-order first-derivative formula on 7 equally spaced samples:
/// f'(t0) ≈ Σ w_j f(t0 + j Δt) / Δt, the unique weights exact for polynomials up to degree 6
/// (Fornberg, "Generation of finite difference formulas on arbitrarily spaced grids", Math.
/// Comp. 51(184), 1988).
pub const FORWARD_DIFFERENCE_6: [f64; 7] = [
    -49.0 / 20.0,
    6.0,
    -15.0 / 2.0,
    20.0 / 3.0,
    -15.0 / 4.0,
    6.0 / 5.0,
    -1.0 / 6.0,
];

/// The paper's state derivative from a short time simulation (§IV.D: "a 6th-order forward
/// difference of 7 time steps"): ẋ(t0) ≈ Σ_j w_j x(t0 + j Δt) / Δt over `samples` = x(t0),
/// x(t0 + Δt), ..., x(t0 + 6Δt), into `out`. No allocation.
pub fn forward_difference_derivative(
    samples: &[DVector<f64>],
    dt: f64,
    out: &mut DVector<f64>,
) -> Result<(), DynamicsError> {
    check_len(|| "time-history samples".into(), 7, samples.len())?;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(DynamicsError::InvalidParameter {
            quantity: "sample interval (s)".into(),
            value: dt,
            allowed: "finite and > 0",
        });
    }
    out.fill(0.0);
    for (sample, &w) in samples.iter().zip(FORWARD_DIFFERENCE_6.iter()) {
        check_len(|| "time-history sample".into(), out.len(), sample.len())?;
        out.axpy(w / dt, sample, 1.0);
    }
    check_finite(|| "forward-difference derivative".into(), out.iter())
}
