//! Patterns without values: what the symbolic analysis reads of `C = P A Pᵀ`.
//!
//! The symbolic analysis never looks at a value, nor at the order of the
//! rows inside a column: the elimination tree climbs from each `C(i, k)`,
//! `i < k`, whatever order they come in, and the column counts classify
//! each `C(i, j)`, `i > j`, on its own. So instead of the sorted permuted
//! triangles with values and sources that the numeric code keeps
//! ([`PermutedTriangle`](super::permute::PermutedTriangle)), the analysis
//! builds both strict triangles of `C` at once, pattern only, rows unsorted
//! and 32-bit: one pass over `A`'s lower triangle to count, one to place.
//!
//! ```text
//! A(i, j), i > j   →   r = inverse[i], c = inverse[j]
//!                      upper column max(r, c) gets row min(r, c)
//!                      lower column min(r, c) gets row max(r, c)
//! ```
//!
//! Diagonal entries are left out (the tree and the counts skip them).
//! [`ColumnPattern`] is what the tree, the counts and the supernodes' rows
//! read, so they take a [`CscMatrix`] (for teaching) or a [`Pattern`]
//! (for speed) alike, and [`Relabeled`] reads a pattern through a
//! renumbering of its columns and rows without copying it.
//!
//! Cost `O(nnz(A) + n)`, two counting passes and no sort. Source: Davis
//! 2006, §2.7 (`cs_symperm`, here without values and for both triangles);
//! faer's and CHOLMOD's analyses likewise read unsorted patterns.

use super::csc::{cumulative_sum, CscMatrix};

/// Columns of row indices: a sparse matrix's pattern, as the symbolic
/// analysis reads it.
pub trait ColumnPattern {
    /// Number of columns.
    fn ncols(&self) -> usize;
    /// The rows of column `j`, in any order.
    fn rows(&self, j: usize) -> impl Iterator<Item = usize> + '_;
}

impl ColumnPattern for CscMatrix {
    fn ncols(&self) -> usize {
        CscMatrix::ncols(self)
    }

    fn rows(&self, j: usize) -> impl Iterator<Item = usize> + '_ {
        self.column(j).0.iter().copied()
    }
}

/// A pattern with 32-bit rows, unsorted within each column.
#[derive(Debug, Clone)]
pub struct Pattern {
    /// Column `j` is `rows[col_ptr[j] .. col_ptr[j + 1]]`.
    col_ptr: Vec<usize>,
    rows: Vec<u32>,
}

impl ColumnPattern for Pattern {
    fn ncols(&self) -> usize {
        self.col_ptr.len() - 1
    }

    #[inline]
    fn rows(&self, j: usize) -> impl Iterator<Item = usize> + '_ {
        self.rows[self.col_ptr[j]..self.col_ptr[j + 1]]
            .iter()
            .map(|&i| i as usize)
    }
}

/// The strict upper and strict lower triangles of `C = P A Pᵀ`, where
/// `inverse[old] = new`, from the lower triangle of `a` (entries above its
/// diagonal are ignored). `n` must fit in `u32` (the caller checks).
pub fn permuted_triangles(a: &CscMatrix, inverse: &[usize]) -> (Pattern, Pattern) {
    let n = a.ncols();
    let (mut upper_count, mut lower_count) = (vec![0usize; n], vec![0usize; n]);
    for_each_strictly_lower(a, inverse, |r, c| {
        upper_count[r] += 1; // column max(r, c) = r of the upper triangle
        lower_count[c] += 1;
    });
    let mut upper = Pattern::with_counts(&upper_count);
    let mut lower = Pattern::with_counts(&lower_count);
    let (mut upper_next, mut lower_next) = (upper_count, lower_count);
    upper_next.copy_from_slice(&upper.col_ptr[..n]);
    lower_next.copy_from_slice(&lower.col_ptr[..n]);
    for_each_strictly_lower(a, inverse, |r, c| {
        upper.rows[upper_next[r]] = c as u32; // n fits in u32
        upper_next[r] += 1;
        lower.rows[lower_next[c]] = r as u32;
        lower_next[c] += 1;
    });
    (upper, lower)
}

impl Pattern {
    /// Room for `count[j]` rows in each column `j`.
    fn with_counts(count: &[usize]) -> Self {
        let col_ptr = cumulative_sum(count);
        let rows = vec![0; col_ptr[count.len()]];
        Pattern { col_ptr, rows }
    }
}

/// Calls `visit(r, c)`, `r > c`, for every off-diagonal entry of `a`'s
/// lower triangle, renumbered by `inverse` into the lower triangle of `C`.
fn for_each_strictly_lower(a: &CscMatrix, inverse: &[usize], mut visit: impl FnMut(usize, usize)) {
    let (col_ptr, row_idx) = (a.col_ptr(), a.row_idx());
    for j in 0..a.ncols() {
        let new_j = inverse[j];
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if i > j {
                let new_i = inverse[i];
                visit(new_i.max(new_j), new_i.min(new_j));
            }
        }
    }
}

/// The pattern `pattern` renumbered: column `k` here is column `old[k]`
/// there, with each row `i` read as `new[i]` (`old` and `new` inverse
/// permutations). No copy is made.
pub struct Relabeled<'a, P> {
    pub pattern: &'a P,
    pub old: &'a [usize],
    pub new: &'a [usize],
}

impl<P: ColumnPattern> ColumnPattern for Relabeled<'_, P> {
    fn ncols(&self) -> usize {
        self.pattern.ncols()
    }

    #[inline]
    fn rows(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        self.pattern.rows(self.old[k]).map(|i| self.new[i])
    }
}
