//! Dense matrices: a row-major matrix type and its Cholesky factorization,
//! plus the one dense kernel the supernodal sparse factorization runs on.
//!
//! The dense path of the simulation exists to teach and to cross-check the
//! sparse one: it is written to be obviously correct, not fast. The kernel
//! in [`gram_block`] is the exception: it is where the sparse factorization
//! spends its time.

pub mod cholesky;
pub mod gram_block;
pub mod matrix;

pub use cholesky::{back_substitution_dense, forward_substitution_dense, DenseCholesky};
pub use matrix::DenseMatrix;
