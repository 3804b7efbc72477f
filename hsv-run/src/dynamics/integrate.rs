//! Fixed-step time integration: the classical fourth-order Runge-Kutta method on a
//! preallocated workspace (no allocation per step).
//!
//! The paper marches the aeroelastic equations at Δt_AE = 0.001 s, heat transfer at
//! Δt_HT = 0.001 s and the aerothermal update at Δt_AT = 0.01 s (Table 3). RK4 is stable for
//! an undamped oscillator while ω Δt < 2√2 ≈ 2.83, so Δt = 0.001 s carries modes up to about
//! 2800 rad/s (450 Hz); a surface Ritz basis with stiffer static shapes needs a smaller step
//! or sub-iteration in that region.

use nalgebra::DVector;

use super::{DynamicsError, check_finite, check_len};

/// Workspace of the classical Runge-Kutta method for states of one length:
/// x_{n+1} = x_n + Δt/6 (k1 + 2 k2 + 2 k3 + k4).
///
/// Reference: Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.
/// (1993), §II.1 (the "classical" fourth-order method).
#[derive(Debug, Clone)]
pub struct Rk4 {
    k1: DVector<f64>,
    k2: DVector<f64>,
    k3: DVector<f64>,
    k4: DVector<f64>,
    stage: DVector<f64>,
}

impl Rk4 {
    /// A workspace for states of length `n`.
    pub fn new(n: usize) -> Self {
        Self {
            k1: DVector::zeros(n),
            k2: DVector::zeros(n),
            k3: DVector::zeros(n),
            k4: DVector::zeros(n),
            stage: DVector::zeros(n),
        }
    }

    pub fn len(&self) -> usize {
        self.k1.len()
    }

    pub fn is_empty(&self) -> bool {
        self.k1.is_empty()
    }

    /// Advances `x` from `t` to `t + dt` in place with the derivative `f(t, x, dx)`. No
    /// allocation; a non-finite state after the step is an error naming the entry.
    pub fn step<F, E>(&mut self, f: &mut F, t: f64, dt: f64, x: &mut DVector<f64>) -> Result<(), E>
    where
        F: FnMut(f64, &DVector<f64>, &mut DVector<f64>) -> Result<(), E>,
        E: From<DynamicsError>,
    {
        check_len(|| "integrated state".into(), self.len(), x.len())?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(DynamicsError::InvalidParameter {
                quantity: "time step (s)".into(),
                value: dt,
                allowed: "finite and > 0",
            }
            .into());
        }
        let half = 0.5 * dt;
        f(t, x, &mut self.k1)?;
        self.stage.copy_from(x);
        self.stage.axpy(half, &self.k1, 1.0);
        f(t + half, &self.stage, &mut self.k2)?;
        self.stage.copy_from(x);
        self.stage.axpy(half, &self.k2, 1.0);
        f(t + half, &self.stage, &mut self.k3)?;
        self.stage.copy_from(x);
        self.stage.axpy(dt, &self.k3, 1.0);
        f(t + dt, &self.stage, &mut self.k4)?;
        let sixth = dt / 6.0;
        x.axpy(sixth, &self.k1, 1.0);
        x.axpy(2.0 * sixth, &self.k2, 1.0);
        x.axpy(2.0 * sixth, &self.k3, 1.0);
        x.axpy(sixth, &self.k4, 1.0);
        check_finite(|| format!("state after the step from t = {t} s"), x.iter())?;
        Ok(())
    }
}
