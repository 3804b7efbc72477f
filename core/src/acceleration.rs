//! Acceleration of the fixed-point iterations that close partitioned interfaces (OpenMDAO's
//! nonlinear block Gauss-Seidel with Aitken; preCICE's `acceleration`): with the interface
//! iterate x_k and what the regions produce from it, G(x_k), the residual r_k = G(x_k) − x_k
//! and the next iterate x_{k+1} = x_k + ω_k r_k.
//!
//! - [`ConstantRelaxation`]: ω_k = ω (under-relaxation; ω = 1 is plain Gauss-Seidel/Jacobi);
//! - [`Aitken`]: Aitken's Δ² factor ω_k = −ω_{k−1} r_{k−1}ᵀ (r_k − r_{k−1}) / ‖r_k − r_{k−1}‖²
//!   (Irons & Tuck 1969; Küttler & Wall 2008, Comput. Mech. 43, 61-72, Eq. 44), clamped to
//!   bounds, starting each fixed point from the given ω.

use crate::config::{AccelerationName, CouplingConfig};

/// One fixed point's acceleration: the state of the method between its iterations (scratch of
/// the iteration that owns it, forgotten at [`Acceleration::reset`]).
pub trait Acceleration: Send + std::fmt::Debug {
    /// Starts a new fixed point.
    fn reset(&mut self);
    /// x ← x + ω r with r = `produced` − x (equal lengths).
    fn update(&mut self, x: &mut [f64], produced: &[f64]);
}

/// x ← x + ω (G(x) − x) with a constant ω.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantRelaxation {
    pub omega: f64,
}

impl Acceleration for ConstantRelaxation {
    fn reset(&mut self) {}

    fn update(&mut self, x: &mut [f64], produced: &[f64]) {
        for (x, g) in x.iter_mut().zip(produced) {
            *x += self.omega * (g - *x);
        }
    }
}

/// Aitken's Δ² relaxation (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Aitken {
    /// ω of each fixed point's first update.
    pub initial: f64,
    /// The clamp on ω (lower, upper).
    pub bounds: (f64, f64),
    omega: f64,
    previous: Vec<f64>,
    first: bool,
}

impl Aitken {
    pub fn new(initial: f64, bounds: (f64, f64)) -> Self {
        Self {
            initial,
            bounds,
            omega: initial,
            previous: Vec::new(),
            first: true,
        }
    }
}

impl Acceleration for Aitken {
    fn reset(&mut self) {
        self.omega = self.initial;
        self.first = true;
    }

    fn update(&mut self, x: &mut [f64], produced: &[f64]) {
        // Sized once for the interface; the time loop then allocates nothing.
        if self.previous.len() != x.len() {
            self.previous = vec![0.0; x.len()];
        }
        let (mut num, mut den) = (0.0, 0.0);
        for ((p, &x), &g) in self.previous.iter_mut().zip(x.iter()).zip(produced) {
            let r = g - x;
            let dr = r - *p;
            num += *p * dr;
            den += dr * dr;
            *p = r;
        }
        if !self.first && den > 0.0 {
            self.omega = (-self.omega * num / den).clamp(self.bounds.0, self.bounds.1);
        }
        self.first = false;
        for (x, r) in x.iter_mut().zip(&self.previous) {
            *x += self.omega * r;
        }
    }
}

/// The acceleration `[coupling]` names.
pub fn acceleration(config: &CouplingConfig) -> Box<dyn Acceleration> {
    match config.acceleration {
        AccelerationName::Aitken => Box::new(Aitken::new(
            config.relaxation,
            (config.relaxation_bounds[0], config.relaxation_bounds[1]),
        )),
        AccelerationName::Constant => Box::new(ConstantRelaxation {
            omega: config.relaxation,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The linear fixed point x = G(x) = a x + b (scalar, |a| > 1: plain iteration diverges).
    /// Aitken's factor for a linear map is the secant step, exact after one update:
    /// ω = 1/(1 − a) (Küttler & Wall 2008, §4.2), so the second update lands on x* = b/(1 − a)
    /// to rounding.
    #[test]
    fn aitken_solves_a_linear_fixed_point_in_two_updates() {
        let (a, b) = (-3.0, 2.0);
        let exact = b / (1.0 - a);
        let mut aitken = Aitken::new(0.1, (-10.0, 10.0));
        let mut x = [0.0];
        for _ in 0..3 {
            let g = [a * x[0] + b];
            aitken.update(&mut x, &g);
        }
        assert!((x[0] - exact).abs() < 1e-14, "{} vs {exact}", x[0]);
        // Under the default clamp the same map still converges, ω held within the bounds.
        let mut clamped = Aitken::new(1.0, (0.05, 1.5));
        let mut y = [0.0];
        for _ in 0..60 {
            let g = [a * y[0] + b];
            clamped.update(&mut y, &g);
        }
        assert!((y[0] - exact).abs() < 1e-12, "{} vs {exact}", y[0]);
    }

    /// Constant relaxation contracts x = a x + b by |1 − ω (1 − a)| per update (closed form).
    #[test]
    fn constant_relaxation_contracts_at_its_closed_form_rate() {
        let (a, b, omega) = (-3.0, 2.0, 0.2);
        let exact = b / (1.0 - a);
        let mut relax = ConstantRelaxation { omega };
        let mut x = [1.0];
        let e0 = x[0] - exact;
        let g = [a * x[0] + b];
        relax.update(&mut x, &g);
        let rate = (1.0 - omega * (1.0 - a)).abs();
        assert!(((x[0] - exact) / e0).abs() - rate < 1e-14);
    }
}
