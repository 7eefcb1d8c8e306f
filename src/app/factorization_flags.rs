//! `--ordering amd|natural` and `--factorization simplicial|supernodal`:
//! how the sparse backend factors `Q` in `simulate` and `view`.
//!
//! The defaults, AMD and supernodal, are the fast path. With
//! `--ordering natural --factorization simplicial` a step runs the textbook
//! code end to end: `Q` factored row by row in its own numbering
//! (`up_looking.rs`), then plain forward and back substitution
//! (`triangular_solve.rs`).

use super::args::Args;
use super::AppError;
use masssprings::linalg::sparse::{Method, Ordering};
use masssprings::sim::simulation::SimulationOptions;

/// The option names, for [`Args::parse`].
pub const NAMES: [&str; 2] = ["ordering", "factorization"];

/// `options` with the ordering and factorization the flags ask for.
///
/// # Errors
/// [`AppError::Usage`] for an unknown ordering or factorization.
pub fn apply(args: &Args, options: SimulationOptions) -> Result<SimulationOptions, AppError> {
    Ok(SimulationOptions {
        ordering: args.value_or("ordering", Ordering::Amd)?,
        factorization: args.value_or("factorization", Method::Supernodal)?,
        ..options
    })
}
