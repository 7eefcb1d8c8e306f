//! The pattern of `A + Aᵀ` without its diagonal, laid out as AMD's initial
//! quotient graph.
//!
//! **What it computes.** For every row `i`, the sorted list of `j ≠ i` with
//! `A(i, j) ≠ 0` or `A(j, i) ≠ 0`, all rows stored one after the other in a
//! single `i32` vector whose capacity leaves elbow room behind them:
//! `nnz + nnz / 5 + n` for `nnz` off-diagonal entries of `A + Aᵀ`, the
//! workspace SuiteSparse's `amd_order` gives `amd_2`. The quotient graph
//! grows into that room.
//!
//! **The idea.** Every edge `{i, j}` of `A + Aᵀ` must be listed once even
//! when both `A(i, j)` and `A(j, i)` are stored. Walk the columns `k` in
//! order; each strictly upper entry `A(j, k)` is an edge, and its mirror
//! `A(k, j)` (if stored) sits in the lower part of column `j`. Column `j`
//! keeps a cursor into its lower part, and on meeting `A(j, k)` the cursor
//! advances up to row `k`: entries `A(i, j)` with `i < k` passed on the way
//! have no mirror (it would have been met in column `i`), so they are edges
//! of their own, and `A(k, j)` itself is skipped. Whatever the cursors have
//! not passed at the end is lower-only too. One walk counts the row lengths,
//! a second fills the rows.
//!
//! When every edge turned out to be stored both ways, `A` is structurally
//! symmetric and the rows are simply its columns without the diagonal, copied
//! in order. Otherwise the second walk fills the rows; they come out sorted
//! for a triangular input (as in SuiteSparse's `amd_1`, whose order this
//! is), and any row that is not is sorted, so the ordering depends on the
//! pattern of `A + Aᵀ` only.
//!
//! **Cost.** `O(nnz(A) + n)` time (plus the sorting of out-of-order rows of
//! an unsymmetric input), no memory beyond the workspace and two `n`-vectors.
//!
//! **Source.** SuiteSparse AMD `amd_aat.c` (count) and `amd_1.c` (fill);
//! Davis 2006, §7.1 (`cs_amd` forms `A + Aᵀ` with `cs_add` instead).

use crate::linalg::error::LinalgError;
use crate::linalg::sparse::csc::CscMatrix;

/// Rows of `A + Aᵀ` (diagonal dropped) in the front of a workspace.
pub(super) struct SymmetricPattern {
    /// The rows: row `i` is `lists[start[i] .. start[i] + length[i]]`; the
    /// capacity is the workspace length.
    pub lists: Vec<i32>,
    /// Capacity reserved for `lists`: `nnz + nnz / 5 + n`.
    pub workspace_len: usize,
    /// Where each row starts in `lists`.
    pub start: Vec<i32>,
    /// Number of off-diagonal entries of each row.
    pub length: Vec<i32>,
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
    // A + Aᵀ has at most 2·nnz(A) entries: with that below the limit, no
    // count below can overflow an i32.
    if n >= limit || 2 * matrix.nnz() >= limit {
        return Err(too_large());
    }

    // Pass 1: row lengths.
    let mut cursor = vec![0; n];
    let mut length = vec![0i32; n];
    let mirrored_pairs = for_each_edge(matrix, &mut cursor, &mut RowLengths(&mut length));
    let mut start = Vec::with_capacity(n);
    let mut used = 0usize;
    for &len in &length {
        start.push(used as i32);
        used += len as usize;
    }
    let workspace_len = used + used / 5 + n;
    if workspace_len >= limit {
        return Err(too_large());
    }

    // Pass 2: the rows.
    let mut lists = Vec::with_capacity(workspace_len);
    if used == 2 * mirrored_pairs {
        // Every edge is stored both ways: A + Aᵀ = A, and row j is column j
        // without its diagonal, already sorted.
        let (col_ptr, row_idx) = (matrix.col_ptr(), matrix.row_idx());
        for j in 0..n {
            let column = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            lists.extend(column.iter().filter(|&&i| i != j).map(|&i| i as i32));
        }
    } else {
        lists.resize(used, 0);
        let mut end = start.clone();
        let mut rows = RowFiller {
            lists: &mut lists,
            end: &mut end,
        };
        for_each_edge(matrix, &mut cursor, &mut rows);
        for (&s, &e) in start.iter().zip(&end) {
            let row = &mut lists[s as usize..e as usize];
            if !row.is_sorted() {
                row.sort_unstable();
            }
        }
    }

    Ok(SymmetricPattern {
        lists,
        workspace_len,
        start,
        length,
    })
}

/// What a walk over the edges of `A + Aᵀ` does with them.
trait EdgeVisitor {
    /// The edge `{i, j}`.
    fn edge(&mut self, i: usize, j: usize);
    /// The edges `{i, j}` for every `i` in `rows`, in order: the lower
    /// entries of column `j` that no cursor reached. Row `j`'s side is kept
    /// in a register here, where one edge at a time would make each
    /// addition to row `j` wait for the one before it, through memory.
    fn edges_to(&mut self, j: usize, rows: &[usize]);
}

/// The first walk: counts each row's length.
struct RowLengths<'a>(&'a mut [i32]);

impl EdgeVisitor for RowLengths<'_> {
    fn edge(&mut self, i: usize, j: usize) {
        self.0[i] += 1;
        self.0[j] += 1;
    }

    fn edges_to(&mut self, j: usize, rows: &[usize]) {
        for &i in rows {
            self.0[i] += 1;
        }
        self.0[j] += rows.len() as i32;
    }
}

/// The second walk: appends each edge to both of its rows, `end[i]` being
/// where row `i` continues.
struct RowFiller<'a> {
    lists: &'a mut [i32],
    end: &'a mut [i32],
}

impl EdgeVisitor for RowFiller<'_> {
    fn edge(&mut self, i: usize, j: usize) {
        self.lists[self.end[i] as usize] = j as i32;
        self.end[i] += 1;
        self.lists[self.end[j] as usize] = i as i32;
        self.end[j] += 1;
    }

    fn edges_to(&mut self, j: usize, rows: &[usize]) {
        let row_j = self.end[j] as usize;
        for (t, &i) in rows.iter().enumerate() {
            self.lists[self.end[i] as usize] = j as i32;
            self.end[i] += 1;
            self.lists[row_j + t] = i as i32;
        }
        self.end[j] += rows.len() as i32;
    }
}

/// Shows `visitor` every off-diagonal edge `{i, j}` of the pattern of
/// `A + Aᵀ` once (rows of each column of `A` must be sorted, as a
/// [`CscMatrix`] guarantees) and returns how many edges were stored both
/// ways, as `A(i, j)` and `A(j, i)`. `cursor` is an `n`-vector of workspace.
fn for_each_edge(
    matrix: &CscMatrix,
    cursor: &mut [usize],
    visitor: &mut impl EdgeVisitor,
) -> usize {
    let (col_ptr, row_idx) = (matrix.col_ptr(), matrix.row_idx());
    let mut mirrored_pairs = 0;
    for k in 0..matrix.ncols() {
        let mut p = col_ptr[k];
        while p < col_ptr[k + 1] {
            let j = row_idx[p];
            if j >= k {
                if j == k {
                    p += 1; // the diagonal
                }
                break;
            }
            // A(j, k), strictly upper: an edge.
            visitor.edge(j, k);
            p += 1;
            // Column j's lower part up to row k: unmirrored entries are edges.
            let mut q = cursor[j];
            while q < col_ptr[j + 1] {
                let i = row_idx[q];
                if i > k {
                    break;
                }
                q += 1;
                if i == k {
                    mirrored_pairs += 1; // A(k, j) mirrors A(j, k)
                    break;
                }
                visitor.edge(i, j);
            }
            cursor[j] = q;
        }
        // Column k's lower part starts here.
        cursor[k] = p;
    }
    // Lower entries never reached by a cursor have no mirror.
    for j in 0..matrix.ncols() {
        visitor.edges_to(j, &row_idx[cursor[j]..col_ptr[j + 1]]);
    }
    mirrored_pairs
}
