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
        let by_row = self.bucket_by_row();
        let (col_ptr, unmerged_rows, unmerged_values) = self.bucket_by_column(&by_row);
        sum_repeated_rows(
            self.nrows,
            self.ncols,
            col_ptr,
            unmerged_rows,
            unmerged_values,
        )
    }

    /// Step 1: the entry numbers in order of their row (a counting sort).
    fn bucket_by_row(&self) -> Vec<usize> {
        let mut count = vec![0usize; self.nrows];
        for &i in &self.rows {
            count[i] += 1;
        }
        let row_ptr = cumulative_sum(&count);
        let mut next = row_ptr[..self.nrows].to_vec();
        let mut entry_of = vec![0usize; self.len()];
        for (e, &i) in self.rows.iter().enumerate() {
            entry_of[next[i]] = e;
            next[i] += 1;
        }
        entry_of
    }

    /// Step 2: visiting entries row by row, append each to its column, so the
    /// rows of every column come out sorted.
    fn bucket_by_column(&self, entries_by_row: &[usize]) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let mut count = vec![0usize; self.ncols];
        for &j in &self.cols {
            count[j] += 1;
        }
        let col_ptr = cumulative_sum(&count);
        let mut next = col_ptr[..self.ncols].to_vec();
        let mut rows = vec![0usize; self.len()];
        let mut values = vec![0.0; self.len()];
        for &e in entries_by_row {
            let j = self.cols[e];
            rows[next[j]] = self.rows[e];
            values[next[j]] = self.values[e];
            next[j] += 1;
        }
        (col_ptr, rows, values)
    }
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
    CscMatrix::from_parts_unchecked(nrows, ncols, col_ptr, rows, values)
}
