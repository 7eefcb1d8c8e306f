//! Hand-written linear algebra: everything the mass-spring solver needs, and
//! nothing about springs.
//!
//! * [`dense`]: a row-major matrix and a dense Cholesky factorization.
//! * [`sparse`]: triplets → CSC, CSC operations, orderings (AMD), the sparse
//!   Cholesky pipeline (analyse once, factor, solve).
//! * [`matrix_market`]: reading and writing Matrix Market files.
//!
//! The pipeline from triplets to a solve is walked through in
//! `docs/sparse-cholesky.md`.

pub mod dense;
pub mod error;
pub mod matrix_market;
pub mod sparse;

pub use error::LinalgError;
