//! Errors of the linear-algebra layer.
//!
//! Every operation that can fail on *data* (an index out of range, a matrix
//! that is not positive definite, shapes that do not fit) returns
//! `Result<_, LinalgError>`. Panics are kept for programmer errors that a
//! caller cannot trigger through data, and each such function documents them
//! under `# Panics`.

use std::fmt;

/// What went wrong in a linear-algebra operation.
#[derive(Debug, Clone, PartialEq)]
pub enum LinalgError {
    /// An entry `(row, col)` lies outside an `nrows × ncols` matrix.
    IndexOutOfBounds {
        row: usize,
        col: usize,
        nrows: usize,
        ncols: usize,
    },
    /// Two operands do not have compatible shapes for `operation`.
    DimensionMismatch {
        operation: &'static str,
        left: (usize, usize),
        right: (usize, usize),
    },
    /// The operation needs a square matrix.
    NotSquare { nrows: usize, ncols: usize },
    /// Cholesky met a pivot that is not strictly positive (or not finite) in
    /// `column` (0-based, in the numbering of the matrix that was passed in).
    NotPositiveDefinite { column: usize, pivot: f64 },
    /// Compressed arrays that break the CSC invariants (see `CscMatrix`).
    InvalidStructure(String),
    /// A numeric refactorization was given a matrix whose sparsity pattern
    /// differs from the one analysed.
    PatternMismatch,
    /// The matrix is too large for the 32-bit row indices of the factor.
    TooLarge { n: usize },
    /// Someone asked the operation to stop ([`Cancel`](super::Cancel))
    /// before it was done; nothing of its result is left.
    Cancelled,
}

impl fmt::Display for LinalgError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinalgError::IndexOutOfBounds {
                row,
                col,
                nrows,
                ncols,
            } => write!(
                f,
                "entry ({row}, {col}) is outside a {nrows}×{ncols} matrix (indices are 0-based)"
            ),
            LinalgError::DimensionMismatch {
                operation,
                left,
                right,
            } => write!(
                f,
                "{operation}: shapes {}×{} and {}×{} do not fit",
                left.0, left.1, right.0, right.1
            ),
            LinalgError::NotSquare { nrows, ncols } => {
                write!(f, "the matrix must be square, it is {nrows}×{ncols}")
            }
            LinalgError::NotPositiveDefinite { column, pivot } => write!(
                f,
                "the matrix is not positive definite: pivot {pivot:e} in column {column} (0-based)"
            ),
            LinalgError::InvalidStructure(why) => write!(f, "invalid sparse structure: {why}"),
            LinalgError::PatternMismatch => write!(
                f,
                "the matrix does not have the sparsity pattern that was analysed"
            ),
            LinalgError::TooLarge { n } => write!(
                f,
                "a {n}×{n} matrix is too large for 32-bit row indices in the factor"
            ),
            LinalgError::Cancelled => write!(f, "cancelled before it was done"),
        }
    }
}

impl std::error::Error for LinalgError {}
