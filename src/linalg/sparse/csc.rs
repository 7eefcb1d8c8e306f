//! Compressed sparse column (CSC) storage.
//!
//! A sparse `nrows × ncols` matrix stores only its nonzeros, column by column:
//!
//! ```text
//! column j holds the entries  values[p]  at rows  row_idx[p]
//! for p in col_ptr[j] .. col_ptr[j + 1]
//! ```
//!
//! so `col_ptr` has `ncols + 1` entries, starts at 0 and ends at `nnz`. In
//! every matrix this type hands out, the rows inside each column are strictly
//! increasing (sorted, no duplicates). This is the format of Davis, *Direct
//! Methods for Sparse Linear Systems* (SIAM 2006), §2.2, where the arrays are
//! called `Ap`, `Ai`, `Ax`.
//!
//! Build a `CscMatrix` from a list of `(i, j, v)` triplets with
//! [`TripletMatrix`](super::triplets::TripletMatrix); the operations live in
//! their own files next to this one.

use crate::linalg::dense::DenseMatrix;
use crate::linalg::error::LinalgError;

/// One triangle of a square matrix, diagonal included.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Triangle {
    /// Entries `(i, j)` with `i ≤ j`.
    Upper,
    /// Entries `(i, j)` with `i ≥ j`.
    Lower,
}

impl Triangle {
    /// Does entry `(row, col)` belong to this triangle?
    pub fn contains(self, row: usize, col: usize) -> bool {
        match self {
            Triangle::Upper => row <= col,
            Triangle::Lower => row >= col,
        }
    }
}

/// A sparse matrix in compressed sparse column form, rows sorted in each column.
///
/// Column `j` holds the entries `col_ptr[j] .. col_ptr[j + 1]` of `row_idx`
/// (their rows) and `values`.
///
/// # Examples
///
/// ```
/// use masssprings::linalg::sparse::{CscMatrix, Triangle};
///
/// // ⎡ 4 −1 ⎤
/// // ⎣−1  3 ⎦, column by column
/// let a = CscMatrix::from_parts(2, 2, vec![0, 2, 4], vec![0, 1, 0, 1], vec![4.0, -1.0, -1.0, 3.0])?;
/// assert_eq!(a.get(1, 0), -1.0);
/// assert_eq!(a.column(1), (&[0, 1][..], &[-1.0, 3.0][..]));
///
/// let mut y = [0.0; 2];
/// a.mul_vec(&[1.0, 2.0], &mut y)?;
/// assert_eq!(y, [2.0, 5.0]);
///
/// // the lower triangle, which the Cholesky factorization reads
/// let lower = a.triangle(Triangle::Lower);
/// assert_eq!((lower.col_ptr(), lower.row_idx()), (&[0, 2, 3][..], &[0, 1, 1][..]));
/// # Ok::<(), masssprings::linalg::LinalgError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct CscMatrix {
    nrows: usize,
    ncols: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl CscMatrix {
    /// Builds a matrix from its three arrays, checking every CSC invariant.
    ///
    /// # Errors
    /// [`LinalgError::InvalidStructure`] when `col_ptr` does not have
    /// `ncols + 1` nondecreasing entries from 0 to `row_idx.len()`, when the
    /// arrays differ in length, or when the rows of a column are not strictly
    /// increasing; [`LinalgError::IndexOutOfBounds`] for a row `≥ nrows`.
    pub fn from_parts(
        nrows: usize,
        ncols: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Result<Self, LinalgError> {
        check_structure(nrows, ncols, &col_ptr, &row_idx, &values)?;
        Ok(CscMatrix {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            values,
        })
    }

    /// Builds a matrix from arrays this crate has produced itself, so a
    /// broken invariant is a bug here, not bad input: it panics rather than
    /// returning an error (one pass over the arrays, small beside building
    /// them).
    pub(crate) fn from_valid_parts(
        nrows: usize,
        ncols: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Self {
        assert_eq!(
            check_structure(nrows, ncols, &col_ptr, &row_idx, &values),
            Ok(())
        );
        CscMatrix {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            values,
        }
    }

    /// The `nrows × ncols` matrix with no stored entries.
    pub fn zeros(nrows: usize, ncols: usize) -> Self {
        Self::from_valid_parts(nrows, ncols, vec![0; ncols + 1], Vec::new(), Vec::new())
    }

    /// The `n × n` identity matrix.
    pub fn identity(n: usize) -> Self {
        Self::from_diagonal(&vec![1.0; n])
    }

    /// The square matrix with `diagonal` on its diagonal (every diagonal
    /// entry is stored, zeros included, so the pattern does not depend on
    /// the values).
    pub fn from_diagonal(diagonal: &[f64]) -> Self {
        let n = diagonal.len();
        Self::from_valid_parts(n, n, (0..=n).collect(), (0..n).collect(), diagonal.to_vec())
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// `col_ptr[j] .. col_ptr[j + 1]` indexes column `j` in `row_idx` and `values`.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row of every stored entry, column by column.
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// Value of every stored entry, column by column.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Values for writing in place; the pattern cannot change.
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// The rows and values of column `j`.
    ///
    /// # Panics
    /// When `j ≥ ncols`.
    pub fn column(&self, j: usize) -> (&[usize], &[f64]) {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        (&self.row_idx[range.clone()], &self.values[range])
    }

    /// Entry `(i, j)`, zero when it is not stored (binary search in column `j`).
    ///
    /// # Panics
    /// When `(i, j)` is outside the matrix.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        assert!(
            i < self.nrows && j < self.ncols,
            "index ({i}, {j}) out of range"
        );
        let (rows, values) = self.column(j);
        rows.binary_search(&i).map_or(0.0, |p| values[p])
    }

    /// The diagonal `(A₀₀, A₁₁, …)`, of length `min(nrows, ncols)`.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.nrows.min(self.ncols))
            .map(|j| self.get(j, j))
            .collect()
    }

    /// The same matrix with every entry, zeros included, written out.
    pub fn to_dense(&self) -> DenseMatrix {
        let mut dense = DenseMatrix::zeros(self.nrows, self.ncols);
        for j in 0..self.ncols {
            let (rows, values) = self.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                dense[(i, j)] = v;
            }
        }
        dense
    }

    /// The entries of one triangle (diagonal included); the others are dropped.
    pub fn triangle(&self, triangle: Triangle) -> CscMatrix {
        let mut col_ptr = Vec::with_capacity(self.ncols + 1);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        col_ptr.push(0);
        for j in 0..self.ncols {
            let (rows, vals) = self.column(j);
            for (&i, &v) in rows.iter().zip(vals) {
                if triangle.contains(i, j) {
                    row_idx.push(i);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        Self::from_valid_parts(self.nrows, self.ncols, col_ptr, row_idx, values)
    }

    /// Does `other` store exactly the same positions?
    pub fn same_pattern(&self, other: &CscMatrix) -> bool {
        self.nrows == other.nrows
            && self.ncols == other.ncols
            && self.col_ptr == other.col_ptr
            && self.row_idx == other.row_idx
    }
}

/// Turns per-column counts into column pointers: `ptr[0] = 0`,
/// `ptr[j + 1] = counts[0] + … + counts[j]` (Davis 2006, `cs_cumsum`).
pub fn cumulative_sum(counts: &[usize]) -> Vec<usize> {
    let mut ptr = Vec::with_capacity(counts.len() + 1);
    let mut total = 0;
    ptr.push(0);
    for &c in counts {
        total += c;
        ptr.push(total);
    }
    ptr
}

fn check_structure(
    nrows: usize,
    ncols: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
    values: &[f64],
) -> Result<(), LinalgError> {
    let invalid = |why: String| Err(LinalgError::InvalidStructure(why));
    if col_ptr.len() != ncols + 1 {
        return invalid(format!(
            "col_ptr has {} entries, expected ncols + 1 = {}",
            col_ptr.len(),
            ncols + 1
        ));
    }
    if row_idx.len() != values.len() {
        return invalid(format!(
            "row_idx has {} entries but values has {}",
            row_idx.len(),
            values.len()
        ));
    }
    if col_ptr[0] != 0 || col_ptr[ncols] != row_idx.len() {
        return invalid(format!(
            "col_ptr must run from 0 to nnz = {}, it runs from {} to {}",
            row_idx.len(),
            col_ptr[0],
            col_ptr[ncols]
        ));
    }
    for j in 0..ncols {
        if col_ptr[j] > col_ptr[j + 1] {
            return invalid(format!("col_ptr decreases at column {j}"));
        }
        let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
        if let Some(&row) = rows.iter().find(|&&i| i >= nrows) {
            return Err(LinalgError::IndexOutOfBounds {
                row,
                col: j,
                nrows,
                ncols,
            });
        }
        if rows.windows(2).any(|w| w[0] >= w[1]) {
            return invalid(format!("rows of column {j} are not strictly increasing"));
        }
    }
    Ok(())
}
