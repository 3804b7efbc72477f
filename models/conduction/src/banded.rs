//! Symmetric positive-definite banded matrices: reverse Cuthill-McKee ordering, in-place banded
//! Cholesky factorization and triangular solves (Golub & Van Loan, Matrix Computations, 4th
//! ed., §4.3.5 and Alg. 4.3.5).

// Index loops mirror the matrix algebra they implement.
#![allow(clippy::needless_range_loop)]

/// Reverse Cuthill-McKee ordering of a graph given by adjacency lists: `order[new] = old`.
///
/// Each component starts from a node of minimum degree; neighbours are visited in increasing
/// degree (George & Liu, Computer Solution of Large Sparse Positive Definite Systems, 1981).
pub fn reverse_cuthill_mckee(adjacency: &[Vec<usize>]) -> Vec<usize> {
    let n = adjacency.len();
    let degree: Vec<usize> = adjacency.iter().map(Vec::len).collect();
    let mut visited = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut by_degree: Vec<usize> = (0..n).collect();
    by_degree.sort_by_key(|&i| degree[i]);
    for &start in &by_degree {
        if visited[start] {
            continue;
        }
        visited[start] = true;
        let mut head = order.len();
        order.push(start);
        while head < order.len() {
            let node = order[head];
            head += 1;
            let mut next: Vec<usize> = adjacency[node]
                .iter()
                .copied()
                .filter(|&m| !visited[m])
                .collect();
            next.sort_by_key(|&m| degree[m]);
            next.dedup();
            for m in next {
                if !visited[m] {
                    visited[m] = true;
                    order.push(m);
                }
            }
        }
    }
    order.reverse();
    order
}

/// Lower band of a symmetric n × n matrix with half-bandwidth `bandwidth`: entry (i, j), i ≥ j,
/// i − j ≤ bandwidth, stored at `data[i * (bandwidth + 1) + (bandwidth − (i − j))]`.
#[derive(Debug, Clone, PartialEq)]
pub struct BandMatrix {
    n: usize,
    bandwidth: usize,
    data: Vec<f64>,
}

/// Why a banded factorization failed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NotPositiveDefinite {
    /// Row whose pivot was not positive.
    pub row: usize,
    pub pivot: f64,
}

impl BandMatrix {
    /// A zero matrix.
    pub fn zeros(n: usize, bandwidth: usize) -> Self {
        Self {
            n,
            bandwidth,
            data: vec![0.0; n * (bandwidth + 1)],
        }
    }

    pub fn size(&self) -> usize {
        self.n
    }

    pub fn bandwidth(&self) -> usize {
        self.bandwidth
    }

    /// Sets every entry to zero, keeping the storage.
    pub fn clear(&mut self) {
        self.data.fill(0.0);
    }

    fn index(&self, i: usize, j: usize) -> usize {
        i * (self.bandwidth + 1) + (self.bandwidth - (i - j))
    }

    /// Adds `value` at (i, j) of the symmetric matrix (either triangle; the lower one is kept).
    /// Entries outside the band are a logic error of the caller and are ignored in release.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        debug_assert!(i - j <= self.bandwidth, "entry ({i}, {j}) outside the band");
        if i - j <= self.bandwidth {
            let k = self.index(i, j);
            self.data[k] += value;
        }
    }

    /// Entry (i, j) of the symmetric matrix.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > self.bandwidth {
            0.0
        } else {
            self.data[self.index(i, j)]
        }
    }

    /// y = A x for the symmetric matrix.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for i in 0..self.n {
            let j0 = i.saturating_sub(self.bandwidth);
            for j in j0..i {
                let a = self.data[self.index(i, j)];
                y[i] += a * x[j];
                y[j] += a * x[i];
            }
            y[i] += self.data[self.index(i, i)] * x[i];
        }
    }

    /// In-place Cholesky A = L Lᵀ of the band (L overwrites the lower band).
    pub fn factorize(&mut self) -> Result<(), NotPositiveDefinite> {
        let b = self.bandwidth;
        let w = b + 1;
        for j in 0..self.n {
            // Column j: L_jj = sqrt(A_jj − Σ_k L_jk²), L_ij = (A_ij − Σ_k L_ik L_jk) / L_jj.
            let k0 = j.saturating_sub(b);
            let row_j = j * w + b - j;
            let mut d = self.data[row_j + j];
            for k in k0..j {
                let l = self.data[row_j + k];
                d -= l * l;
            }
            if !(d > 0.0 && d.is_finite()) {
                return Err(NotPositiveDefinite { row: j, pivot: d });
            }
            let d = d.sqrt();
            self.data[row_j + j] = d;
            let i_end = (j + b).min(self.n - 1);
            for i in j + 1..=i_end {
                let row_i = i * w + b - i;
                let k_start = k0.max(i.saturating_sub(b));
                let mut s = self.data[row_i + j];
                for k in k_start..j {
                    s -= self.data[row_i + k] * self.data[row_j + k];
                }
                self.data[row_i + j] = s / d;
            }
        }
        Ok(())
    }

    /// Solves L Lᵀ x = b in place after [`Self::factorize`].
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let b = self.bandwidth;
        let w = b + 1;
        for i in 0..self.n {
            let row = i * w + b - i;
            let mut s = x[i];
            for k in i.saturating_sub(b)..i {
                s -= self.data[row + k] * x[k];
            }
            x[i] = s / self.data[row + i];
        }
        for i in (0..self.n).rev() {
            let row = i * w + b - i;
            x[i] /= self.data[row + i];
            let xi = x[i];
            for k in i.saturating_sub(b)..i {
                x[k] -= self.data[row + k] * xi;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    #[test]
    fn banded_cholesky_solves_like_a_dense_solver() {
        // A tridiagonal-plus SPD matrix with half-bandwidth 2.
        let n = 9;
        let mut band = BandMatrix::zeros(n, 2);
        let mut dense = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for (off, v) in [(0usize, 6.0 + i as f64), (1, -1.5), (2, -0.7)] {
                if i + off < n {
                    band.add(i + off, i, v);
                    dense[(i + off, i)] += v;
                    if off > 0 {
                        dense[(i, i + off)] += v;
                    }
                }
            }
        }
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
        let expected = dense
            .clone()
            .lu()
            .solve(&nalgebra::DVector::from_vec(rhs.clone()))
            .unwrap();
        let mut y = vec![0.0; n];
        band.mul_vec(expected.as_slice(), &mut y);
        for (a, b) in y.iter().zip(&rhs) {
            assert!((a - b).abs() < 1e-12);
        }
        band.factorize().unwrap();
        let mut x = rhs;
        band.solve_in_place(&mut x);
        for (a, b) in x.iter().zip(expected.iter()) {
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn rcm_orders_a_path_graph_with_unit_bandwidth() {
        // 0-3-1-4-2 path scrambled; RCM gives a contiguous path.
        let adjacency = vec![vec![3], vec![3, 4], vec![4], vec![0, 1], vec![1, 2]];
        let order = reverse_cuthill_mckee(&adjacency);
        let mut position = [0; 5];
        for (new, &old) in order.iter().enumerate() {
            position[old] = new;
        }
        for (i, neighbours) in adjacency.iter().enumerate() {
            for &j in neighbours {
                assert_eq!(position[i].abs_diff(position[j]), 1);
            }
        }
    }

    #[test]
    fn indefinite_matrices_are_reported() {
        let mut band = BandMatrix::zeros(2, 1);
        band.add(0, 0, 1.0);
        band.add(1, 0, 2.0);
        band.add(1, 1, 1.0);
        assert_eq!(band.factorize().unwrap_err().row, 1);
    }
}
