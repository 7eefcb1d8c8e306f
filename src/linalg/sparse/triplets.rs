//! Triplet lists and their compression to CSC.
//!
//! The assignment builds every sparse matrix the way Eigen's
//! `setFromTriplets` does: collect `(i, j, v)` entries in any order, with
//! repeats allowed, then convert once. Repeated positions are *summed*
//! (`A(i, j) += v`), which is what assembling `AᵀA` or a mass matrix from
//! per-element pieces needs.
//!
//! Compression is two counting sorts, `O(nnz + nrows + ncols)` and no
//! comparison sort (the "sort by transposing twice" idea of Davis 2006, §2.4
//! and `cs_compress` / `cs_dupl`):
//!
//! 1. bucket the entries by row;
//! 2. walk the rows in increasing order and drop each entry into its column's
//!    bucket, so every column receives its rows already sorted;
//! 3. in each column, add up neighbours that share a row.

use super::csc::{cumulative_sum, CscMatrix};
use crate::linalg::error::LinalgError;

/// A list of `(row, col, value)` entries of an `nrows × ncols` matrix.
///
/// # Examples
///
/// The signed incidence matrix `A` of one spring between vertices 0 and 1,
/// pushed twice: repeated positions add up when compressed.
///
/// ```
/// use masssprings::linalg::sparse::TripletMatrix;
///
/// let mut a = TripletMatrix::new(1, 2);
/// for _ in 0..2 {
///     a.push(0, 0, 1.0)?;
///     a.push(0, 1, -1.0)?;
/// }
/// assert_eq!(a.len(), 4);
/// let csc = a.to_csc();
/// assert_eq!(csc.nnz(), 2);
/// assert_eq!(csc.values(), [2.0, -2.0]);
/// assert!(a.push(1, 0, 1.0).is_err()); // row 1 of a 1-row matrix
/// # Ok::<(), masssprings::linalg::LinalgError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct TripletMatrix {
    nrows: usize,
    ncols: usize,
    rows: Vec<usize>,
    cols: Vec<usize>,
    values: Vec<f64>,
}

impl TripletMatrix {
    /// An empty list for an `nrows × ncols` matrix.
    pub fn new(nrows: usize, ncols: usize) -> Self {
        Self::with_capacity(nrows, ncols, 0)
    }

    /// An empty list with room for `capacity` entries.
    pub fn with_capacity(nrows: usize, ncols: usize, capacity: usize) -> Self {
        TripletMatrix {
            nrows,
            ncols,
            rows: Vec::with_capacity(capacity),
            cols: Vec::with_capacity(capacity),
            values: Vec::with_capacity(capacity),
        }
    }

    /// Number of rows of the matrix being built.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns of the matrix being built.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Number of entries pushed so far (repeats counted).
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// No entry pushed yet?
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Adds `value` at `(row, col)`; a repeated position is summed on compression.
    ///
    /// # Errors
    /// [`LinalgError::IndexOutOfBounds`] when `(row, col)` is outside the matrix;
    /// nothing is pushed then.
    pub fn push(&mut self, row: usize, col: usize, value: f64) -> Result<(), LinalgError> {
        if row >= self.nrows || col >= self.ncols {
            return Err(LinalgError::IndexOutOfBounds {
                row,
                col,
                nrows: self.nrows,
                ncols: self.ncols,
            });
        }
        self.rows.push(row);
        self.cols.push(col);
        self.values.push(value);
        Ok(())
    }

    /// Builds a list from `(row, col, value)` entries, checking every index.
    ///
    /// # Errors
    /// [`LinalgError::IndexOutOfBounds`] for the first entry outside the matrix.
    pub fn from_entries(
        nrows: usize,
        ncols: usize,
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
    ) -> Result<Self, LinalgError> {
        let mut triplets = Self::new(nrows, ncols);
        for (i, j, v) in entries {
            triplets.push(i, j, v)?;
        }
        Ok(triplets)
    }

    /// Compresses to CSC: rows sorted in each column, repeats summed.
    ///
    /// A position whose repeats sum to zero is still stored, so the pattern
    /// depends only on the positions pushed, never on the values.
    pub fn to_csc(&self) -> CscMatrix {
        let (col_ptr, order) =
            sort_by_column_then_row(self.nrows, self.ncols, &self.rows, &self.cols);
        let rows = order.iter().map(|&e| self.rows[e]).collect();
        let values = order.iter().map(|&e| self.values[e]).collect();
        sum_repeated_rows(self.nrows, self.ncols, col_ptr, rows, values)
    }
}

/// Steps 1 and 2: the order that sorts entries by column and, inside a
/// column, by row, found with two counting sorts; also the column pointers
/// of that order (repeats still counted separately).
pub(crate) fn sort_by_column_then_row(
    nrows: usize,
    ncols: usize,
    rows: &[usize],
    cols: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let (_, by_row) = counting_sort(nrows, rows, 0..rows.len());
    counting_sort(ncols, cols, by_row.into_iter())
}

/// A stable counting sort of the entry numbers `entries` by `key[entry]`
/// (`key < buckets`): returns the bucket pointers and the sorted entries.
fn counting_sort(
    buckets: usize,
    key: &[usize],
    entries: impl Iterator<Item = usize> + Clone,
) -> (Vec<usize>, Vec<usize>) {
    let mut count = vec![0usize; buckets];
    for e in entries.clone() {
        count[key[e]] += 1;
    }
    let ptr = cumulative_sum(&count);
    let mut next = ptr[..buckets].to_vec();
    let mut sorted = vec![0usize; ptr[buckets]];
    for e in entries {
        sorted[next[key[e]]] = e;
        next[key[e]] += 1;
    }
    (ptr, sorted)
}

/// Step 3: in each (row-sorted) column, merge neighbours with the same row by
/// adding their values, compacting the arrays in place.
fn sum_repeated_rows(
    nrows: usize,
    ncols: usize,
    mut col_ptr: Vec<usize>,
    mut rows: Vec<usize>,
    mut values: Vec<f64>,
) -> CscMatrix {
    let mut write = 0;
    let mut column_start = 0;
    for j in 0..ncols {
        let column_end = col_ptr[j + 1];
        let first_of_column = write;
        for read in column_start..column_end {
            if write > first_of_column && rows[write - 1] == rows[read] {
                values[write - 1] += values[read];
            } else {
                rows[write] = rows[read];
                values[write] = values[read];
                write += 1;
            }
        }
        column_start = column_end;
        col_ptr[j + 1] = write;
    }
    rows.truncate(write);
    values.truncate(write);
    CscMatrix::from_valid_parts(nrows, ncols, col_ptr, rows, values)
}
