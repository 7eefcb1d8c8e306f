//! Simplicial numeric Cholesky, row by row ("up-looking").
//!
//! Row `k` of `L Lᵀ = C` (with `C = P A Pᵀ`) reads
//!
//! ```text
//! L(0:k, 0:k) · L(k, 0:k)ᵀ = C(0:k, k)        (a triangular solve)
//! L(k, k) = √( C(k, k) − L(k, 0:k) · L(k, 0:k)ᵀ )
//! ```
//!
//! The solve is sparse: only the columns in the pattern of row `k`
//! (found from the elimination tree by [`RowPattern`]) take part, visited
//! descendants first. Each `L(k, j)` found is appended to column `j`, whose
//! slots the symbolic analysis already sized, so nothing is allocated here.
//! A pivot `C(k, k) − ‖L(k, 0:k)‖² ≤ 0` means `C` is not positive definite.
//!
//! Cost: the flop count of the analysis, `Σ_j count[j]²`, one multiply-add
//! at a time. This is the textbook method (and Eigen's `SimplicialLLT`);
//! the supernodal factorization next to it does the same arithmetic in
//! dense blocks.
//!
//! Source: Davis 2006, §4.7 (`cs_chol`); Rose, Whitten, Sherman, Tarjan
//! (the up-looking form), see also Davis, Rajamanickam, Sid-Lakhdar, "A
//! survey of direct methods for sparse linear systems", Acta Numerica 2016.

use super::csc::CscMatrix;
use super::row_pattern::RowPattern;
use super::symbolic::SymbolicCholesky;

/// Work arrays of the up-looking factorization, sized once.
#[derive(Debug, Clone)]
pub struct UpLookingWorkspace {
    /// Dense accumulator for the current row, all zeros between rows.
    row_values: Vec<f64>,
    /// `next_slot[j]`: where the next entry of column `j` of `L` goes.
    next_slot: Vec<usize>,
    pattern: RowPattern,
}

impl UpLookingWorkspace {
    /// Work arrays for an `n × n` matrix.
    pub fn new(n: usize) -> Self {
        UpLookingWorkspace {
            row_values: vec![0.0; n],
            next_slot: vec![0; n],
            pattern: RowPattern::new(n),
        }
    }
}

impl UpLookingWorkspace {
    /// Bytes held (array lengths): `row_values`, `next_slot` and the
    /// row-pattern work arrays, about `4 n` words.
    pub fn bytes(&self) -> usize {
        let n = self.row_values.len();
        n * std::mem::size_of::<f64>() + n * std::mem::size_of::<usize>() + self.pattern.bytes()
    }
}

/// A pivot that was not positive: `(column of C, pivot value)`.
pub type FailedPivot = (usize, f64);

/// Fills `values` (laid out as `symbolic.col_ptr()` / `row_idx()`) with `L`
/// for `C = P A Pᵀ`, given by its upper triangle `upper`.
///
/// # Errors
/// The first column of `C` whose pivot is not positive and finite.
pub fn factor_up_looking(
    symbolic: &SymbolicCholesky,
    upper: &CscMatrix,
    values: &mut [f64],
    work: &mut UpLookingWorkspace,
) -> Result<(), FailedPivot> {
    let n = symbolic.n();
    let parent = symbolic.elimination_tree();
    let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx()); // per column: borrowed
    let x = &mut work.row_values;
    work.next_slot.copy_from_slice(&col_ptr[..n]);
    for k in 0..n {
        let (rows, vals) = upper.column(k);
        for (&i, &v) in rows.iter().zip(vals) {
            x[i] = v; // x = C(0:k, k)
        }
        let mut pivot = x[k];
        x[k] = 0.0;
        for &j in work.pattern.of_row(upper, parent, k) {
            // L(k, j) = x[j] / L(j, j); then x -= L(k, j) · L(:, j) below j
            let l_kj = x[j] / values[col_ptr[j]];
            x[j] = 0.0;
            for p in col_ptr[j] + 1..work.next_slot[j] {
                x[row_idx[p] as usize] -= values[p] * l_kj;
            }
            pivot -= l_kj * l_kj;
            values[work.next_slot[j]] = l_kj;
            work.next_slot[j] += 1;
        }
        if !(pivot > 0.0 && pivot.is_finite()) {
            x.fill(0.0);
            return Err((k, pivot));
        }
        values[work.next_slot[k]] = pivot.sqrt();
        work.next_slot[k] += 1;
    }
    Ok(())
}
