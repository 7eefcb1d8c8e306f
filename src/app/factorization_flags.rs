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
use masssprings::sim::simulation::SimulationOptions;

/// The option names (each takes a value).
pub const OPTIONS: &[&str] = &["ordering", "factorization"];

/// Sets `options` from the flags that were given.
///
/// # Errors
/// A usage error for an unknown ordering or factorization.
pub fn apply(args: &Args, options: &mut SimulationOptions) -> Result<(), AppError> {
    options.ordering = args.value_or("ordering", options.ordering)?;
    options.factorization = args.value_or("factorization", options.factorization)?;
    Ok(())
}
