//! Transpose of a CSC matrix.
//!
//! `Aᵀ` in CSC is `A` in compressed sparse *row* form. One counting sort on
//! the row index does it: count the entries of each row, turn the counts into
//! pointers, then walk the columns of `A` in order and append each entry to
//! its row. Because columns are visited in increasing order, every row of
//! `A` (column of `Aᵀ`) receives its indices already sorted.
//!
//! Cost `O(nnz + nrows + ncols)`. Source: Davis 2006, §2.5 (`cs_transpose`).

use super::csc::{cumulative_sum, CscMatrix};

impl CscMatrix {
    /// `Aᵀ`, with sorted rows in every column.
    pub fn transpose(&self) -> CscMatrix {
        let mut entries_in_row = vec![0usize; self.nrows()];
        for &i in self.row_idx() {
            entries_in_row[i] += 1;
        }
        let col_ptr = cumulative_sum(&entries_in_row);
        let mut next = col_ptr[..self.nrows()].to_vec();
        let mut row_idx = vec![0usize; self.nnz()];
        let mut values = vec![0.0; self.nnz()];
        for j in 0..self.ncols() {
            let (rows, vals) = self.column(j);
            for (&i, &v) in rows.iter().zip(vals) {
                row_idx[next[i]] = j;
                values[next[i]] = v;
                next[i] += 1;
            }
        }
        CscMatrix::from_valid_parts(self.ncols(), self.nrows(), col_ptr, row_idx, values)
    }
}
