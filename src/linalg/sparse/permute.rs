//! Symmetric permutation of one triangle: `C = P A Pᵀ`.
//!
//! A fill-reducing ordering renumbers the unknowns: old index `i` becomes
//! `inverse[i]`. For a symmetric `A` stored by its lower triangle, the
//! entry `A(i, j)` (`i ≥ j`) moves to `C(inverse[i], inverse[j])`, which may
//! now lie above the diagonal; since `C` is symmetric too, it is stored in
//! whichever triangle the caller wants by swapping row and column when
//! needed. Entries are then ordered by column and row with the same two
//! counting sorts that compress triplets.
//!
//! Besides `C`, the result remembers, for every entry of `C`, which entry of
//! `A`'s value array it came from. When only the values of `A` change (a new
//! time step, stiffness, masses or pins), [`PermutedTriangle::refill`] copies
//! them across in `O(nnz)` without redoing any of this.
//!
//! Cost `O(nnz(A) + n)`. Source: Davis 2006, §2.7 (`cs_symperm`, which reads
//! and writes the upper triangle).

use super::csc::{CscMatrix, Triangle};
use super::permutation::Permutation;
use super::triplets::sort_by_column_then_row;
use crate::linalg::error::LinalgError;

/// One triangle of `P A Pᵀ`, and where each of its entries came from in `A`.
#[derive(Debug, Clone)]
pub struct PermutedTriangle {
    matrix: CscMatrix,
    /// `matrix.values()[p] == a.values()[source_entry[p]]`.
    source_entry: Vec<usize>,
    /// A fingerprint of the pattern of the `A` this was built from, to check
    /// refills against without keeping a copy of that pattern.
    source_pattern: u64,
}

impl PermutedTriangle {
    /// `C = P A Pᵀ` from the lower triangle of the square matrix `a` (entries
    /// above the diagonal are ignored), stored as the `target` triangle.
    ///
    /// # Errors
    /// [`LinalgError::NotSquare`] for a non-square `a`;
    /// [`LinalgError::DimensionMismatch`] when `perm` has the wrong length.
    pub fn new(a: &CscMatrix, perm: &Permutation, target: Triangle) -> Result<Self, LinalgError> {
        check_permutation_fits(a, perm)?;
        let n = a.ncols();
        let (rows, cols, sources) = permuted_lower_entries(a, perm.inverse(), target);
        let (col_ptr, order) = sort_by_column_then_row(n, n, &rows, &cols);
        let row_idx = order.iter().map(|&e| rows[e]).collect();
        let source_entry: Vec<usize> = order.iter().map(|&e| sources[e]).collect();
        let values = source_entry.iter().map(|&s| a.values()[s]).collect();
        Ok(PermutedTriangle {
            matrix: CscMatrix::from_valid_parts(n, n, col_ptr, row_idx, values),
            source_entry,
            source_pattern: pattern_fingerprint(a),
        })
    }

    /// Bytes held (array lengths): `C` and the source of each entry.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        let c = &self.matrix;
        (c.col_ptr().len() + c.row_idx().len() + self.source_entry.len()) * size_of::<usize>()
            + std::mem::size_of_val(c.values())
    }

    /// The permuted triangle `C`.
    pub fn matrix(&self) -> &CscMatrix {
        &self.matrix
    }

    /// Copies new values of `a` into `C`; `a` must have the pattern this was
    /// built from.
    ///
    /// # Errors
    /// [`LinalgError::PatternMismatch`] when the pattern of `a` differs.
    pub fn refill(&mut self, a: &CscMatrix) -> Result<(), LinalgError> {
        if pattern_fingerprint(a) != self.source_pattern {
            return Err(LinalgError::PatternMismatch);
        }
        let source_values = a.values();
        for (value, &s) in self.matrix.values_mut().iter_mut().zip(&self.source_entry) {
            *value = source_values[s];
        }
        Ok(())
    }
}

/// `P A Pᵀ` needs a square `A` and a permutation of its size.
///
/// # Errors
/// [`LinalgError::NotSquare`]; [`LinalgError::DimensionMismatch`].
pub(crate) fn check_permutation_fits(a: &CscMatrix, perm: &Permutation) -> Result<(), LinalgError> {
    let n = a.ncols();
    if a.nrows() != n {
        return Err(LinalgError::NotSquare {
            nrows: a.nrows(),
            ncols: n,
        });
    }
    if perm.len() != n {
        return Err(LinalgError::DimensionMismatch {
            operation: "P A Pᵀ",
            left: (perm.len(), perm.len()),
            right: (n, n),
        });
    }
    Ok(())
}

/// A 64-bit hash of the shape, column pointers and row indices (FNV-1a
/// taken a word at a time): two different patterns give the same
/// fingerprint with probability about 2⁻⁶⁴. Cost `O(nnz)`, like comparing
/// the patterns, but no copy of the pattern is kept.
pub(crate) fn pattern_fingerprint(a: &CscMatrix) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let words = [a.nrows(), a.ncols()].into_iter();
    let words = words
        .chain(a.col_ptr().iter().copied())
        .chain(a.row_idx().iter().copied());
    words.fold(0xcbf2_9ce4_8422_2325, |hash, word| {
        (hash ^ word as u64).wrapping_mul(PRIME)
    })
}

/// The entries of `A`'s lower triangle, renumbered by `inverse` and put in
/// the `target` triangle: `(rows, cols, position in A)`.
fn permuted_lower_entries(
    a: &CscMatrix,
    inverse: &[usize],
    target: Triangle,
) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let (mut rows, mut cols, mut sources) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..a.ncols() {
        for p in a.col_ptr()[j]..a.col_ptr()[j + 1] {
            let i = a.row_idx()[p];
            if i < j {
                continue; // upper triangle: ignored
            }
            let (new_i, new_j) = (inverse[i], inverse[j]);
            let (low, high) = (new_i.min(new_j), new_i.max(new_j));
            let (row, col) = match target {
                Triangle::Lower => (high, low),
                Triangle::Upper => (low, high),
            };
            rows.push(row);
            cols.push(col);
            sources.push(p);
        }
    }
    (rows, cols, sources)
}
