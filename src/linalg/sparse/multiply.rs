//! Products of a CSC matrix with a vector and with an n×3 block of points.
//!
//! CSC stores columns, so `y = A x` is a sum of scaled columns
//! (`y += x_j · A(:, j)`, a "saxpy" per column) and `y = Aᵀ x` is a dot
//! product per column (`y_j = A(:, j) · x`). Neither needs `Aᵀ` formed.
//!
//! The simulation keeps positions as an n×3 row-major block `[[f64; 3]]`,
//! one point per row; its products touch the three coordinates of a point
//! together, so each stored entry of `A` is read once for x, y and z.
//!
//! Cost `O(nnz + nrows + ncols)`. Source: Davis 2006, §2.3 (`cs_gaxpy`).

use super::csc::CscMatrix;
use crate::linalg::error::LinalgError;

impl CscMatrix {
    /// `y = A x` for a vector `x`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] unless `x.len() == ncols` and `y.len() == nrows`.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) -> Result<(), LinalgError> {
        self.check_shapes("A x", false, x.len(), y.len(), 1)?;
        y.fill(0.0);
        for (j, &xj) in x.iter().enumerate() {
            let (rows, vals) = self.column(j);
            for (&i, &a) in rows.iter().zip(vals) {
                y[i] += a * xj;
            }
        }
        Ok(())
    }

    /// `y = A x` for an n×3 block of points `x` (x, y, z at once).
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] unless `x.len() == ncols` and `y.len() == nrows`.
    pub fn mul_points(&self, x: &[[f64; 3]], y: &mut [[f64; 3]]) -> Result<(), LinalgError> {
        self.check_shapes("A X", false, x.len(), y.len(), 3)?;
        y.fill([0.0; 3]);
        for (j, xj) in x.iter().enumerate() {
            let (rows, vals) = self.column(j);
            for (&i, &a) in rows.iter().zip(vals) {
                for c in 0..3 {
                    y[i][c] += a * xj[c];
                }
            }
        }
        Ok(())
    }

    /// `y = Aᵀ x` for an n×3 block of points, one dot product per column of `A`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] unless `x.len() == nrows` and `y.len() == ncols`.
    pub fn transpose_mul_points(
        &self,
        x: &[[f64; 3]],
        y: &mut [[f64; 3]],
    ) -> Result<(), LinalgError> {
        self.check_shapes("Aᵀ X", true, x.len(), y.len(), 3)?;
        for (j, yj) in y.iter_mut().enumerate() {
            let (rows, vals) = self.column(j);
            let mut sum = [0.0; 3];
            for (&i, &a) in rows.iter().zip(vals) {
                for c in 0..3 {
                    sum[c] += a * x[i][c];
                }
            }
            *yj = sum;
        }
        Ok(())
    }

    /// Checks `y = op(A) x` shapes, where `op(A)` is `A` or `Aᵀ`.
    fn check_shapes(
        &self,
        operation: &'static str,
        transposed: bool,
        x_rows: usize,
        y_rows: usize,
        width: usize,
    ) -> Result<(), LinalgError> {
        let (op_rows, op_cols) = if transposed {
            (self.ncols(), self.nrows())
        } else {
            (self.nrows(), self.ncols())
        };
        if x_rows != op_cols || y_rows != op_rows {
            return Err(LinalgError::DimensionMismatch {
                operation,
                left: (op_rows, op_cols),
                right: (x_rows, width),
            });
        }
        Ok(())
    }
}
