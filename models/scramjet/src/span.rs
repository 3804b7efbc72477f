//! Spanwise quadratic least squares (paper §III.E): sectional values at the engine's spanwise
//! stations fitted by g(y) = c0 + c1 ŷ + c2 ŷ², ŷ = (y - y_mid)/(W/2), then integrated over the
//! span or evaluated at a panel's position. The fit is linear in the data, so every use is a
//! fixed weight vector over the stations.

use nalgebra::{Matrix3, Vector3};

/// Least-squares weights for `n ≥ 3` stations across a span [y_min, y_max].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpanFit {
    y_mid_m: f64,
    half_width_m: f64,
    /// (VᵀV)⁻¹ with V the n × 3 design matrix of the stations.
    inverse_normal: Matrix3<f64>,
    /// Normalized station positions ŷ_k.
    stations: Vec<f64>,
}

impl SpanFit {
    /// Fit over stations at `y_m` (at least three distinct values) spanning [y_min_m, y_max_m].
    /// `None` when the normal equations are singular (fewer than three distinct stations).
    pub fn new(y_min_m: f64, y_max_m: f64, y_m: &[f64]) -> Option<Self> {
        let mut fit = Self::default();
        fit.reset(y_min_m, y_max_m, y_m).then_some(fit)
    }

    /// Refits for new stations and span, keeping buffers; false when singular.
    pub fn reset(&mut self, y_min_m: f64, y_max_m: f64, y_m: &[f64]) -> bool {
        self.y_mid_m = 0.5 * (y_min_m + y_max_m);
        self.half_width_m = 0.5 * (y_max_m - y_min_m);
        self.stations.clear();
        self.stations
            .extend(y_m.iter().map(|y| (y - self.y_mid_m) / self.half_width_m));
        let mut normal = Matrix3::zeros();
        for &s in &self.stations {
            let row = Vector3::new(1.0, s, s * s);
            normal += row * row.transpose();
        }
        // Conditioned by the scaling to ŷ in [-1, 1]; near-singular means fewer than three
        // distinct stations.
        let scale = normal.trace().powi(3);
        let determinant = normal.determinant().abs();
        if determinant.is_nan() || determinant <= 1e-12 * scale {
            return false;
        }
        match normal.try_inverse() {
            Some(inverse) if self.stations.len() >= 3 => {
                self.inverse_normal = inverse;
                true
            }
            _ => false,
        }
    }

    /// Σ_k w_k v_k = aᵀ c where c = (VᵀV)⁻¹ Vᵀ v are the fitted coefficients: w_k = aᵀ (VᵀV)⁻¹ V_kᵀ.
    fn weights_for(&self, a: Vector3<f64>, out: &mut Vec<f64>) {
        let b = self.inverse_normal * a;
        out.clear();
        out.extend(self.stations.iter().map(|&s| b.x + b.y * s + b.z * s * s));
    }

    /// Weights of the fitted value at `y_m`: a = (1, ŷ, ŷ²).
    pub fn value_weights(&self, y_m: f64, out: &mut Vec<f64>) {
        let s = (y_m - self.y_mid_m) / self.half_width_m;
        self.weights_for(Vector3::new(1.0, s, s * s), out);
    }

    /// Weights of ∫ g dy over the span: (W/2) ∫₋₁¹ (c0 + c1 ŷ + c2 ŷ²) dŷ = (W/2)(2 c0 + 2 c2/3).
    pub fn integral_weights(&self, out: &mut Vec<f64>) {
        let h = self.half_width_m;
        self.weights_for(Vector3::new(2.0 * h, 0.0, 2.0 * h / 3.0), out);
    }

    /// Weights of ∫ (y - y_ref) g dy over the span, with y - y_ref = (y_mid - y_ref) + (W/2) ŷ:
    /// (W/2)[(y_mid - y_ref)(2 c0 + 2 c2/3) + (W/2)(2 c1/3)].
    pub fn first_moment_weights(&self, y_ref_m: f64, out: &mut Vec<f64>) {
        let h = self.half_width_m;
        let d = self.y_mid_m - y_ref_m;
        self.weights_for(
            Vector3::new(2.0 * h * d, 2.0 * h * h / 3.0, 2.0 * h * d / 3.0),
            out,
        );
    }
}

/// Σ w_k v_k.
pub fn apply(weights: &[f64], values: impl Iterator<Item = f64>) -> f64 {
    weights.iter().zip(values).map(|(w, v)| w * v).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn quadratic_data_is_reproduced_and_integrated_exactly() {
        // g(y) = 2 - 3 y + 5 y² over [-1.5, 1.5]: ∫ g = 2·3 + 5·(2·1.5³/3) = 6 + 11.25 = 17.25;
        // ∫ y g = -3 · 2·1.5³/3 = -6.75 (analytic).
        let ys: Vec<f64> = (0..5)
            .map(|k| -1.5 + (k as f64 + 0.5) * 3.0 / 5.0)
            .collect();
        let g = |y: f64| 2.0 - 3.0 * y + 5.0 * y * y;
        let fit = SpanFit::new(-1.5, 1.5, &ys).expect("fit");
        let mut w = Vec::new();
        fit.integral_weights(&mut w);
        assert_relative_eq!(apply(&w, ys.iter().map(|&y| g(y))), 17.25, epsilon = 1e-12);
        fit.first_moment_weights(0.0, &mut w);
        assert_relative_eq!(apply(&w, ys.iter().map(|&y| g(y))), -6.75, epsilon = 1e-12);
        fit.value_weights(0.7, &mut w);
        assert_relative_eq!(apply(&w, ys.iter().map(|&y| g(y))), g(0.7), epsilon = 1e-12);
        // Constants: weights of a value sum to one, of the integral to the width.
        fit.value_weights(-1.2, &mut w);
        assert_relative_eq!(w.iter().sum::<f64>(), 1.0, epsilon = 1e-13);
        fit.integral_weights(&mut w);
        assert_relative_eq!(w.iter().sum::<f64>(), 3.0, epsilon = 1e-13);
    }

    #[test]
    fn fewer_than_three_stations_is_singular() {
        assert!(SpanFit::new(-1.0, 1.0, &[-0.5, 0.5]).is_none());
        assert!(SpanFit::new(-1.0, 1.0, &[0.1, 0.1, 0.1]).is_none());
    }
}
