//! Where each entry of `A` goes in the storage of `L`, for the supernodal
//! factorization's first step ("load the block with `C = P A Pᵀ`").
//!
//! Entry `A(i, j)`, `i ≥ j` (the lower triangle; entries above the
//! diagonal are not read), lands in `C(r, c)` with
//! `r = max(inverse[i], inverse[j])`, `c = min(…)`, and `L`'s column `c`
//! stores row `r` at a known slot (its rows are sorted: a binary search).
//! So instead of keeping the permuted matrix `C` (its own column pointers,
//! 64-bit rows, values, and the source of each value: 24 bytes an entry),
//! this keeps, column by column of `C`, pairs of 32-bit numbers
//! `(slot in L's column c, position in A's value array)`: 8 bytes an entry,
//! and no second copy of a pattern. Refactoring reads the new values of `A`
//! straight through it.
//!
//! Cost `O(nnz(A) log n)` once (the searches), `O(nnz(A))` per load.
//! Source: the scatter of `A` into the supernodal factor in CHOLMOD's
//! `super_numeric` (Chen, Davis, Hager, Rajamanickam, ACM TOMS 35(3), 2008),
//! with the slots computed once instead of per factorization.

use super::csc::{cumulative_sum, CscMatrix};
use super::permute::pattern_fingerprint;
use super::symbolic::SymbolicCholesky;
use crate::linalg::error::LinalgError;

/// The slots of `A`'s lower-triangle entries in `L`, by column of `C`.
#[derive(Debug, Clone)]
pub struct FactorLoading {
    /// Column `c` of `C` is `entries[start[c] .. start[c + 1]]`.
    start: Vec<usize>,
    /// `(slot, source)`: `values_of_L[col_ptr[c] + slot] = a.values()[source]`.
    entries: Vec<[u32; 2]>,
    /// A fingerprint of `A`'s pattern, to check refills against.
    source_pattern: u64,
}

impl FactorLoading {
    /// The slots for the matrix `a` analysed by `symbolic`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] when `a` is not the analysed size;
    /// [`LinalgError::TooLarge`] when `A` has 2³² entries or more (32-bit
    /// positions); [`LinalgError::PatternMismatch`] when an entry of `a` is
    /// outside the analysed pattern of `L`.
    pub fn new(a: &CscMatrix, symbolic: &SymbolicCholesky) -> Result<Self, LinalgError> {
        let n = symbolic.n();
        if a.nrows() != n || a.ncols() != n {
            return Err(LinalgError::DimensionMismatch {
                operation: "load A into L",
                left: (n, n),
                right: (a.nrows(), a.ncols()),
            });
        }
        if u32::try_from(a.nnz()).is_err() {
            return Err(LinalgError::TooLarge { n });
        }
        let inverse = symbolic.permutation().inverse();
        let target = |i: usize, j: usize| {
            let (r, c) = (inverse[i].max(inverse[j]), inverse[i].min(inverse[j]));
            (r, c)
        };
        let mut count = vec![0usize; n];
        for_each_lower_entry(a, |i, j, _| count[target(i, j).1] += 1);
        let start = cumulative_sum(&count);
        let mut next = start[..n].to_vec();
        let mut entries = vec![[0u32; 2]; start[n]];
        let mut outside = false;
        for_each_lower_entry(a, |i, j, p| {
            let (r, c) = target(i, j);
            let rows = symbolic.column_rows(c);
            match rows.binary_search(&(r as u32)) {
                Ok(slot) => {
                    entries[next[c]] = [slot as u32, p as u32]; // both fit, checked above
                    next[c] += 1;
                }
                Err(_) => outside = true,
            }
        });
        if outside {
            return Err(LinalgError::PatternMismatch);
        }
        Ok(FactorLoading {
            start,
            entries,
            source_pattern: pattern_fingerprint(a),
        })
    }

    /// Is `a`'s pattern the one these slots were computed for?
    pub fn fits(&self, a: &CscMatrix) -> bool {
        pattern_fingerprint(a) == self.source_pattern
    }

    /// Writes column `c` of `C` (values from `a`) into `column`, the stored
    /// entries of `L`'s column `c`, after zeroing it.
    #[inline]
    pub fn load_column(&self, a: &CscMatrix, c: usize, column: &mut [f64]) {
        column.fill(0.0);
        let values = a.values();
        for &[slot, source] in &self.entries[self.start[c]..self.start[c + 1]] {
            column[slot as usize] = values[source as usize];
        }
    }

    /// Bytes held (array lengths).
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(&self.start[..]) + std::mem::size_of_val(&self.entries[..])
    }
}

/// Calls `visit(i, j, p)` for every entry `p` of `a` with `i ≥ j`.
fn for_each_lower_entry(a: &CscMatrix, mut visit: impl FnMut(usize, usize, usize)) {
    for j in 0..a.ncols() {
        for p in a.col_ptr()[j]..a.col_ptr()[j + 1] {
            let i = a.row_idx()[p];
            if i >= j {
                visit(i, j, p);
            }
        }
    }
}
