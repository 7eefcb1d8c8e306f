//! The error every command returns, and the exit code it maps to (see
//! `app/mod.rs`): a usage error (2) or a failure (1), each with the
//! sentence to print.

/// What went wrong, and whether it was the way the program was called.
#[derive(Debug)]
pub enum AppError {
    /// Wrong arguments: exit code 2, with a hint to see the usage.
    Usage(String),
    /// Bad input or a failure while working: exit code 1.
    Failed(String),
}

impl<E: std::error::Error> From<E> for AppError {
    fn from(error: E) -> Self {
        AppError::Failed(error.to_string())
    }
}
