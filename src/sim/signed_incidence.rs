//! The signed incidence matrix `A` of the spring network.
//!
//! `A` is `m × n` (springs × vertices). Row `e`, for spring `e = (i, j)`, has
//! `+1` in column `i`, `−1` in column `j` and zeros elsewhere, so that
//! `A p` stacks the spring vectors `pᵢ − pⱼ` (assignment, "Matrices").
//! The same orientation `(i, j)` is used for `d` in the local step.
//!
//! Cost `O(m)` entries; `O(mn)` memory for the dense matrix, `O(m)` sparse.
//! Source: the assignment's `signed_incidence_matrix_dense.cpp` /
//! `_sparse.cpp`; Liu et al. 2013, §3.

use super::backend::{Dense, LinearAlgebra, Sparse};
use crate::linalg::dense::DenseMatrix;
use crate::linalg::sparse::CscMatrix;

/// The nonzeros `(e, i, +1)` and `(e, j, −1)` of `A`, spring by spring.
pub fn signed_incidence_entries(
    springs: &[[usize; 2]],
) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    springs
        .iter()
        .enumerate()
        .flat_map(|(e, &[i, j])| [(e, i, 1.0), (e, j, -1.0)])
}

/// `A` for `n` vertices and the given springs, as a `B` matrix.
pub fn signed_incidence_matrix<B: LinearAlgebra>(n: usize, springs: &[[usize; 2]]) -> B::Matrix {
    B::from_entries(springs.len(), n, signed_incidence_entries(springs))
}

/// `A` as a dense matrix (the assignment's `signed_incidence_matrix_dense`).
pub fn signed_incidence_matrix_dense(n: usize, springs: &[[usize; 2]]) -> DenseMatrix {
    signed_incidence_matrix::<Dense>(n, springs)
}

/// `A` as a sparse matrix built from triplets (the assignment's
/// `signed_incidence_matrix_sparse`).
pub fn signed_incidence_matrix_sparse(n: usize, springs: &[[usize; 2]]) -> CscMatrix {
    signed_incidence_matrix::<Sparse>(n, springs)
}
