//! Symmetric banded matrices: assembly, matrix-vector products and an in-place Cholesky
//! factorization (Golub & Van Loan, Matrix Computations, 4th ed., §4.3, band Cholesky), allocation-free
//! once built.

/// Σ a_k b_k with four independent accumulators (the band rows are short; this keeps the
/// floating-point pipeline busy without reordering within an accumulator).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0; 4];
    let chunks = n / 4;
    for c in 0..chunks {
        let k = 4 * c;
        acc[0] += a[k] * b[k];
        acc[1] += a[k + 1] * b[k + 1];
        acc[2] += a[k + 2] * b[k + 2];
        acc[3] += a[k + 3] * b[k + 3];
    }
    let mut tail = 0.0;
    for k in 4 * chunks..n {
        tail += a[k] * b[k];
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// A symmetric n × n matrix with half-bandwidth `bandwidth` (A[i][j] = 0 for |i − j| > bw),
/// stored by rows of its lower band: `data[i (bw + 1) + (bw − (i − j))] = A[i][j]`, j ≤ i.
#[derive(Debug, Clone, PartialEq)]
pub struct BandedMatrix {
    n: usize,
    bandwidth: usize,
    data: Vec<f64>,
}

/// A factorization failed: the matrix is not positive definite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NotPositiveDefinite {
    /// Equation at which the pivot became ≤ 0.
    pub equation: usize,
    /// The pivot value.
    pub pivot: f64,
}

impl BandedMatrix {
    /// A zero matrix.
    pub fn zeros(n: usize, bandwidth: usize) -> Self {
        let bandwidth = bandwidth.min(n.saturating_sub(1));
        Self {
            n,
            bandwidth,
            data: vec![0.0; n * (bandwidth + 1)],
        }
    }

    pub fn n(&self) -> usize {
        self.n
    }

    pub fn bandwidth(&self) -> usize {
        self.bandwidth
    }

    /// Sets every entry to zero.
    pub fn clear(&mut self) {
        self.data.iter_mut().for_each(|v| *v = 0.0);
    }

    fn index(&self, i: usize, j: usize) -> Option<usize> {
        let (i, j) = if j > i { (j, i) } else { (i, j) };
        let d = i - j;
        (d <= self.bandwidth).then(|| i * (self.bandwidth + 1) + self.bandwidth - d)
    }

    /// A[i][j] (0 outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.index(i, j).map_or(0.0, |k| self.data[k])
    }

    /// A[i][j] += v for j ≤ i (the symmetric partner is implied). Entries outside the band
    /// are a bug in the bandwidth computation and are ignored in release builds.
    pub fn add_lower(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(j <= i);
        if let Some(k) = self.index(i, j) {
            self.data[k] += v;
        } else {
            debug_assert!(
                false,
                "entry ({i}, {j}) outside the band {}",
                self.bandwidth
            );
        }
    }

    /// y = A x.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        let bw = self.bandwidth;
        y.iter_mut().for_each(|v| *v = 0.0);
        for i in 0..self.n {
            let row = &self.data[i * (bw + 1)..(i + 1) * (bw + 1)];
            let j0 = i.saturating_sub(bw);
            let mut acc = 0.0;
            for j in j0..i {
                let a = row[bw - (i - j)];
                acc += a * x[j];
                y[j] += a * x[i];
            }
            y[i] += acc + row[bw] * x[i];
        }
    }

    /// In-place Cholesky factor L (A = L Lᵀ), stored in the same band; fails on a pivot ≤ 0
    /// (relative to the diagonal's scale), which for a stiffness matrix means a mechanism or
    /// a buckled structure.
    pub fn cholesky_in_place(&mut self) -> Result<(), NotPositiveDefinite> {
        let bw = self.bandwidth;
        let w = bw + 1;
        let scale = (0..self.n)
            .map(|i| self.data[i * w + bw].abs())
            .fold(0.0, f64::max);
        for i in 0..self.n {
            let j0 = i.saturating_sub(bw);
            for j in j0..=i {
                // L[i][j] = (A[i][j] − Σ_{k<j} L[i][k] L[j][k]) / L[j][j]; both rows are
                // contiguous over k in the band storage.
                let k0 = j0.max(j.saturating_sub(bw));
                let row_i = &self.data[i * w + bw - (i - k0)..i * w + bw - (i - j)];
                let row_j = &self.data[j * w + bw - (j - k0)..j * w + bw];
                let sum = self.data[i * w + bw - (i - j)] - dot(row_i, row_j);
                if i == j {
                    if sum.is_nan() || sum <= 1e-14 * scale || sum.is_infinite() {
                        return Err(NotPositiveDefinite {
                            equation: i,
                            pivot: sum,
                        });
                    }
                    self.data[i * w + bw] = sum.sqrt();
                } else {
                    self.data[i * w + bw - (i - j)] = sum / self.data[j * w + bw];
                }
            }
        }
        Ok(())
    }

    /// Solves L Lᵀ x = b in place (`self` holds the factor from [`Self::cholesky_in_place`]).
    pub fn cholesky_solve(&self, b: &mut [f64]) {
        let bw = self.bandwidth;
        let w = bw + 1;
        for i in 0..self.n {
            let k0 = i.saturating_sub(bw);
            let row = &self.data[i * w + bw - (i - k0)..i * w + bw];
            b[i] = (b[i] - dot(row, &b[k0..i])) / self.data[i * w + bw];
        }
        for i in (0..self.n).rev() {
            let end = (i + 1 + bw).min(self.n);
            let mut sum = b[i];
            for (k, bk) in b.iter().enumerate().take(end).skip(i + 1) {
                sum -= self.data[k * w + bw - (k - i)] * bk;
            }
            b[i] = sum / self.data[i * w + bw];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_a_tridiagonal_system() {
        // 1-D Laplacian with Dirichlet ends: solution of A x = 1 is x_i = (i+1)(n−i)/2.
        let n = 9;
        let mut a = BandedMatrix::zeros(n, 1);
        for i in 0..n {
            a.add_lower(i, i, 2.0);
            if i > 0 {
                a.add_lower(i, i - 1, -1.0);
            }
        }
        let x_exact: Vec<f64> = (0..n).map(|i| ((i + 1) * (n - i)) as f64 / 2.0).collect();
        let mut y = vec![0.0; n];
        a.mul_vec(&x_exact, &mut y);
        assert!(y.iter().all(|&v| (v - 1.0).abs() < 1e-12));
        a.cholesky_in_place().expect("SPD");
        let mut b = vec![1.0; n];
        a.cholesky_solve(&mut b);
        for (u, v) in b.iter().zip(&x_exact) {
            assert!((u - v).abs() < 1e-12);
        }
        let mut s = BandedMatrix::zeros(2, 1);
        s.add_lower(0, 0, 1.0);
        s.add_lower(1, 0, 2.0);
        s.add_lower(1, 1, 1.0);
        assert!(s.cholesky_in_place().is_err());
    }
}
