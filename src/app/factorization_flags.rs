//! `--ordering amd|natural` and `--factorization simplicial|supernodal`:
//! how the sparse backend factors `Q` in `simulate` and `view`.
//!
//! The defaults, AMD and supernodal, are the fast path. With
//! `--ordering natural --factorization simplicial` a step runs the textbook
//! code end to end: `Q` factored row by row in its own numbering
//! (`up_looking.rs`), then plain forward and back substitution
//! (`triangular_solve.rs`).

use super::args::{Args, Flag};
use super::AppError;
use masssprings::sim::simulation::SimulationOptions;

pub const ORDERING: Flag = Flag::value(
    "ordering",
    "amd|natural",
    "The sparse Q's fill-reducing ordering (default amd; natural: the textbook path).",
);
pub const FACTORIZATION: Flag = Flag::value(
    "factorization",
    "supernodal|simplicial",
    "The sparse Q's factorization and solves (default supernodal; simplicial: the textbook \
     row-by-row method).",
);

/// Sets `options` from the flags that were given.
///
/// # Errors
/// A usage error for an unknown ordering or factorization.
pub fn apply(args: &Args, options: &mut SimulationOptions) -> Result<(), AppError> {
    if args.declares("ordering") {
        options.ordering = args.parsed("ordering", options.ordering, "amd or natural")?;
    }
    if args.declares("factorization") {
        options.factorization = args.parsed(
            "factorization",
            options.factorization,
            "supernodal or simplicial",
        )?;
    }
    Ok(())
}
