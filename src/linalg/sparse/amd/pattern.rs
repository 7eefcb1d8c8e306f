//! The pattern of `A + Aᵀ` without its diagonal, laid out as AMD's initial
//! quotient graph.
//!
//! **What it computes.** For every row `i`, the sorted list of `j ≠ i` with
//! `A(i, j) ≠ 0` or `A(j, i) ≠ 0`, all rows stored one after the other at the
//! front of a single `i32` workspace that has elbow room behind them:
//! `len = nnz(A + Aᵀ) + nnz(A + Aᵀ) / 5 + n`, the size SuiteSparse's
//! `amd_order` gives `amd_2`. The quotient graph grows into that room.
//!
//! **The idea.** Row `j` of `A + Aᵀ` is the union of column `j` of `A` and
//! column `j` of `Aᵀ` (row `j` of `A`). Both are sorted (a CSC invariant, and
//! a transpose by counting sort produces sorted columns), so one merge per
//! row gives the union sorted and without duplicates. For a symmetric input
//! this is exactly the row order SuiteSparse's `amd_1` builds, which matters
//! for ties.
//!
//! **Cost.** `O(nnz(A) + n)` time; the transpose of the pattern is a
//! temporary of `nnz(A)` entries.
//!
//! **Source.** SuiteSparse AMD `amd_aat.c` / `amd_1.c` (which build the same
//! union in place); Davis 2006, §2.5 (transpose) and §7.1 (`cs_amd` forms
//! `A + Aᵀ` with `cs_add`).

use crate::linalg::error::LinalgError;
use crate::linalg::sparse::csc::CscMatrix;

/// Rows of `A + Aᵀ` (diagonal dropped) in the front of a workspace.
pub(super) struct SymmetricPattern {
    /// The workspace: row `i` is `lists[start[i] .. start[i] + length[i]]`;
    /// `lists[used ..]` is free.
    pub lists: Vec<i32>,
    /// Where each row starts in `lists`.
    pub start: Vec<i32>,
    /// Number of off-diagonal entries of each row.
    pub length: Vec<i32>,
    /// Entries of `lists` in use (`nnz(A + Aᵀ)` minus the diagonal).
    pub used: usize,
}

/// Builds the rows of `A + Aᵀ` without the diagonal, in a workspace sized
/// for the whole ordering.
///
/// # Errors
/// [`LinalgError::TooLarge`] when the workspace would not fit `i32` indices.
pub(super) fn symmetric_pattern(matrix: &CscMatrix) -> Result<SymmetricPattern, LinalgError> {
    let n = matrix.ncols();
    let too_large = || LinalgError::TooLarge { n };
    let limit = i32::MAX as usize;
    if n >= limit {
        return Err(too_large());
    }
    // A + Aᵀ has at most 2·nnz(A) entries, the workspace at most 1.2 times that + n.
    let worst_used = 2 * matrix.nnz();
    let worst_len = worst_used + worst_used / 5 + n;

    let (row_start, row_cols) = transpose_pattern(matrix);
    let (col_ptr, row_idx) = (matrix.col_ptr(), matrix.row_idx());

    let mut lists = Vec::with_capacity(worst_len.min(limit));
    let mut start = Vec::with_capacity(n);
    let mut length = Vec::with_capacity(n);
    for j in 0..n {
        let row_begin = lists.len();
        merge_without(
            j as i32,
            &row_idx[col_ptr[j]..col_ptr[j + 1]],
            &row_cols[row_start[j]..row_start[j + 1]],
            &mut lists,
        );
        if lists.len() >= limit {
            return Err(too_large());
        }
        start.push(row_begin as i32);
        length.push((lists.len() - row_begin) as i32);
    }

    let used = lists.len();
    let workspace_len = used + used / 5 + n;
    if workspace_len >= limit {
        return Err(too_large());
    }
    lists.resize(workspace_len, 0);
    Ok(SymmetricPattern {
        lists,
        start,
        length,
        used,
    })
}

/// The pattern of `Aᵀ` in CSC form (`row_start`, column indices of each row
/// of `A`, increasing), by counting sort.
fn transpose_pattern(matrix: &CscMatrix) -> (Vec<usize>, Vec<i32>) {
    let n = matrix.nrows();
    let (col_ptr, row_idx) = (matrix.col_ptr(), matrix.row_idx());
    let mut row_start = vec![0usize; n + 1];
    for &i in row_idx {
        row_start[i + 1] += 1;
    }
    for i in 0..n {
        row_start[i + 1] += row_start[i];
    }
    let mut next = row_start[..n].to_vec();
    let mut row_cols = vec![0i32; row_idx.len()];
    for j in 0..matrix.ncols() {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            row_cols[next[i]] = j as i32;
            next[i] += 1;
        }
    }
    (row_start, row_cols)
}

/// Appends the sorted union of `column` (`usize` rows) and `row` (`i32`
/// columns), both sorted, to `out`, leaving out `diagonal`.
fn merge_without(diagonal: i32, column: &[usize], row: &[i32], out: &mut Vec<i32>) {
    let (mut a, mut b) = (0, 0);
    while a < column.len() || b < row.len() {
        let from_column = column.get(a).map_or(i32::MAX, |&i| i as i32);
        let from_row = row.get(b).copied().unwrap_or(i32::MAX);
        let next = from_column.min(from_row);
        if from_column == next {
            a += 1;
        }
        if from_row == next {
            b += 1;
        }
        if next != diagonal {
            out.push(next);
        }
    }
}
