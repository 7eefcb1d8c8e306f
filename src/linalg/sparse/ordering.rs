//! The choice of fill-reducing ordering.
//!
//! Eliminating the unknowns of `A x = b` in a different order changes how
//! many nonzeros the Cholesky factor gets ("fill"), by orders of magnitude
//! on meshes, but never the answer. [`Ordering::Amd`] is the one to use;
//! [`Ordering::Natural`] keeps the given numbering, for comparison.

use super::amd::{amd, AmdOptions};
use super::csc::CscMatrix;
use super::permutation::Permutation;
use crate::linalg::error::LinalgError;

/// Which fill-reducing ordering to apply before factoring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ordering {
    /// Approximate minimum degree, with SuiteSparse's default options.
    #[default]
    Amd,
    /// The matrix's own numbering.
    Natural,
}

impl Ordering {
    /// The permutation (`perm[new] = old`) this ordering gives for the
    /// pattern of the square matrix `a`.
    ///
    /// # Errors
    /// [`LinalgError::NotSquare`]; [`LinalgError::TooLarge`] when AMD's
    /// 32-bit workspace cannot hold the pattern.
    pub fn permutation(self, a: &CscMatrix) -> Result<Permutation, LinalgError> {
        if a.nrows() != a.ncols() {
            return Err(LinalgError::NotSquare {
                nrows: a.nrows(),
                ncols: a.ncols(),
            });
        }
        match self {
            Ordering::Amd => amd(a, &AmdOptions::default()).map(|(perm, _)| perm),
            Ordering::Natural => Ok(Permutation::identity(a.ncols())),
        }
    }

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Ordering::Amd => "amd",
            Ordering::Natural => "natural",
        }
    }
}

impl std::str::FromStr for Ordering {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        match name {
            "amd" => Ok(Ordering::Amd),
            "natural" => Ok(Ordering::Natural),
            other => Err(format!(
                "unknown ordering '{other}' (expected amd or natural)"
            )),
        }
    }
}
