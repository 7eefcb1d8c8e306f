//! Dense matrices: a row-major matrix type and its Cholesky factorization.
//!
//! The dense path exists to teach and to cross-check the sparse one: it is
//! written to be obviously correct, not fast.

pub mod cholesky;
pub mod matrix;

pub use cholesky::{back_substitution, forward_substitution, DenseCholesky};
pub use matrix::DenseMatrix;
