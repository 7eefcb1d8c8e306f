//! Sparse matrix–matrix product `C = A B` (and `AᵀA`).
//!
//! Column `j` of `C` is a combination of columns of `A`:
//! `C(:, j) = Σ_k B(k, j) · A(:, k)` over the entries of `B(:, j)`.
//! Gustavson's algorithm accumulates it in a dense work vector `accumulator`
//! of length `nrows`, remembering which rows it touched in `column_of_row`
//! (a row is new to this column when `column_of_row[i] != j`). The touched
//! rows are then sorted, so `C` keeps the sorted-rows invariant.
//!
//! Cost `O(flops + nnz(C) log)` where `flops = Σ_j Σ_{k ∈ B(:,j)} nnz(A(:,k))`.
//! Source: Gustavson, "Two fast algorithms for sparse matrices:
//! multiplication and permuted transposition", ACM TOMS 4(3), 1978; Davis
//! 2006, §2.8 (`cs_multiply`).

use super::csc::CscMatrix;
use crate::linalg::error::LinalgError;

impl CscMatrix {
    /// `A B`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] unless `A.ncols == B.nrows`.
    pub fn mul(&self, other: &CscMatrix) -> Result<CscMatrix, LinalgError> {
        if self.ncols() != other.nrows() {
            return Err(LinalgError::DimensionMismatch {
                operation: "A B",
                left: (self.nrows(), self.ncols()),
                right: (other.nrows(), other.ncols()),
            });
        }
        let mut accumulator = vec![0.0; self.nrows()];
        let mut column_of_row = vec![usize::MAX; self.nrows()];
        let mut col_ptr = Vec::with_capacity(other.ncols() + 1);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        col_ptr.push(0);
        for j in 0..other.ncols() {
            let start = row_idx.len();
            let (b_rows, b_vals) = other.column(j);
            for (&k, &b_kj) in b_rows.iter().zip(b_vals) {
                let (a_rows, a_vals) = self.column(k);
                for (&i, &a_ik) in a_rows.iter().zip(a_vals) {
                    if column_of_row[i] != j {
                        column_of_row[i] = j;
                        accumulator[i] = 0.0;
                        row_idx.push(i);
                    }
                    accumulator[i] += a_ik * b_kj;
                }
            }
            row_idx[start..].sort_unstable();
            values.extend(row_idx[start..].iter().map(|&i| accumulator[i]));
            col_ptr.push(row_idx.len());
        }
        Ok(CscMatrix::from_valid_parts(
            self.nrows(),
            other.ncols(),
            col_ptr,
            row_idx,
            values,
        ))
    }

    /// `AᵀA`, the product the assignment's `Q = k AᵀA + …` needs.
    pub fn transpose_mul_self(&self) -> CscMatrix {
        self.transpose()
            .mul(self)
            .expect("Aᵀ has as many columns as A has rows")
    }
}
