//! The workspace's shared linear algebra: the banded SPD solver (assembly, in-place Cholesky,
//! allocation-free solves, reverse Cuthill-McKee ordering), symmetric and generalized symmetric
//! eigenproblems K v = λ M v (dense, and the lowest modes of large banded ones by subspace
//! iteration), and the general real eigen-decomposition with complex eigenpairs.
//!
//! nalgebra is the matrix type at this API (`DMatrix<f64>` in, `DMatrix`/`DVector` out); the
//! dense decompositions run in faer on zero-copy views of nalgebra's column-major storage.
//!
//! The banded solver is in `banded.rs`, the eigen-solvers in `eigen.rs`; each file's docs give
//! the measurements that chose its implementation. Every item is re-exported here, at
//! `hsv_core::linalg::*`.

mod banded;
mod eigen;

pub use banded::{BandedMatrix, NotPositiveDefinite, reverse_cuthill_mckee};
pub use eigen::{
    ComplexEigenpairs, EigenError, Eigenpairs, SymmetricEigenSolver, general_eigen,
    generalized_symmetric_eigen, lowest_banded_eigenpairs,
};
