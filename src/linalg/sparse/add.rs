//! Sums and scalings of CSC matrices: `C = α A + β B`.
//!
//! Because the rows of every column are sorted, the columns of `A` and `B`
//! can be merged like two sorted lists: walk both, emit the smaller row, add
//! the two values when the rows are equal. The result comes out sorted with
//! no workspace. The pattern of `C` is the union of the two patterns (an
//! entry that cancels to zero stays stored, so `C`'s pattern never depends
//! on the values).
//!
//! Cost `O(nnz(A) + nnz(B) + ncols)`. Source: Davis 2006, §2.6 (`cs_add`,
//! which scatters into a dense work vector instead of merging).

use super::csc::CscMatrix;
use crate::linalg::error::LinalgError;

impl CscMatrix {
    /// `α A + β B`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] when the shapes differ.
    pub fn add_scaled(
        &self,
        alpha: f64,
        other: &CscMatrix,
        beta: f64,
    ) -> Result<CscMatrix, LinalgError> {
        if (self.nrows(), self.ncols()) != (other.nrows(), other.ncols()) {
            return Err(LinalgError::DimensionMismatch {
                operation: "A + B",
                left: (self.nrows(), self.ncols()),
                right: (other.nrows(), other.ncols()),
            });
        }
        let capacity = self.nnz() + other.nnz();
        let mut col_ptr = Vec::with_capacity(self.ncols() + 1);
        let mut row_idx = Vec::with_capacity(capacity);
        let mut values = Vec::with_capacity(capacity);
        col_ptr.push(0);
        for j in 0..self.ncols() {
            let a = self.column(j);
            let b = other.column(j);
            merge_columns(a, alpha, b, beta, &mut row_idx, &mut values);
            col_ptr.push(row_idx.len());
        }
        Ok(CscMatrix::from_valid_parts(
            self.nrows(),
            self.ncols(),
            col_ptr,
            row_idx,
            values,
        ))
    }

    /// `A + B`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] when the shapes differ.
    pub fn add(&self, other: &CscMatrix) -> Result<CscMatrix, LinalgError> {
        self.add_scaled(1.0, other, 1.0)
    }

    /// `s A` (same pattern).
    pub fn scale(&self, s: f64) -> CscMatrix {
        let mut scaled = self.clone();
        scaled.values_mut().iter_mut().for_each(|v| *v *= s);
        scaled
    }
}

/// Appends `α a + β b` for two sorted columns `(rows, values)`.
fn merge_columns(
    (a_rows, a_vals): (&[usize], &[f64]),
    alpha: f64,
    (b_rows, b_vals): (&[usize], &[f64]),
    beta: f64,
    row_idx: &mut Vec<usize>,
    values: &mut Vec<f64>,
) {
    let (mut p, mut q) = (0, 0);
    while p < a_rows.len() || q < b_rows.len() {
        let a_row = a_rows.get(p).copied().unwrap_or(usize::MAX);
        let b_row = b_rows.get(q).copied().unwrap_or(usize::MAX);
        let row = a_row.min(b_row);
        let mut value = 0.0;
        if a_row == row {
            value += alpha * a_vals[p];
            p += 1;
        }
        if b_row == row {
            value += beta * b_vals[q];
            q += 1;
        }
        row_idx.push(row);
        values.push(value);
    }
}
