//! The signed incidence matrix `A` of the spring network.
//!
//! `A` is `m × n` (springs × vertices). Row `e`, for spring `e = (i, j)`, has
//! `+1` in column `i`, `−1` in column `j` and zeros elsewhere, so that
//! `A p` stacks the spring vectors `pᵢ − pⱼ` (assignment, "Matrices").
//! The same orientation `(i, j)` is used for `d` in the local step.
//!
//! Cost `O(m)` entries; `O(mn)` memory for the dense matrix, `O(m)` sparse.
//!
//! The spring list *is* `A` in its most compact form: row `e` holds `+1`
//! at `springs[e][0]` and `−1` at `springs[e][1]`, nothing else. So the
//! products the simulation needs in every iteration are taken straight from
//! it ([`incidence_mul_points`], [`incidence_transpose_mul_points`]), with
//! no matrix kept: the precomputation builds `A` as a matrix only to
//! assemble `Q = k AᵀA + …`, then drops it (at a million vertices a CSC `A`
//! held 136 MB, `docs/performance.md`). `Aᵀd` adds, at each vertex, its
//! springs' `±dₑ` in increasing `e`: the same sums in the same order as the
//! CSC product `Aᵀd` (whose columns list their rows in increasing order),
//! so the results are the same to the last bit.
//!
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

/// `out = A x`: `out[e] = x[i] − x[j]` for spring `e = (i, j)`, one row per
/// spring, without forming `A`.
///
/// # Panics
/// When `out` does not have one row per spring, or a spring joins a vertex
/// beyond `x`.
pub fn incidence_mul_points(springs: &[[usize; 2]], x: &[[f64; 3]], out: &mut [[f64; 3]]) {
    assert_eq!(out.len(), springs.len(), "A x has one row per spring");
    for (row, &[i, j]) in out.iter_mut().zip(springs) {
        *row = std::array::from_fn(|c| x[i][c] - x[j][c]);
    }
}

/// `out = Aᵀ d` without forming `A`: spring `e = (i, j)` adds `d[e]` to
/// row `i` and subtracts it from row `j`, springs in increasing order (the
/// order of the CSC product, so the same bits). A spring from a vertex to
/// itself is a zero row of `A` and adds nothing.
///
/// # Panics
/// When `d` does not have one row per spring, or a spring joins a vertex
/// beyond `out`.
pub fn incidence_transpose_mul_points(
    springs: &[[usize; 2]],
    d: &[[f64; 3]],
    out: &mut [[f64; 3]],
) {
    assert_eq!(d.len(), springs.len(), "d has one row per spring");
    out.fill([0.0; 3]);
    for (&[i, j], de) in springs.iter().zip(d) {
        if i != j {
            for c in 0..3 {
                out[i][c] += de[c];
                out[j][c] -= de[c];
            }
        }
    }
}
