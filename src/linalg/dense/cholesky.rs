//! Dense Cholesky factorization (placeholder, being written).

/// Placeholder.
pub struct DenseCholesky;
