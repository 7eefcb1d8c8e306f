//! `--textbook`, `--ordering amd|natural` and `--factorization
//! simplicial|supernodal`: which code runs a step in `simulate`, `render`
//! and `view`, and how the sparse backend factors `Q`.
//!
//! The defaults, AMD and supernodal, are the fast path. `--textbook` runs
//! the handout's functions as written instead (`sim/textbook.rs`): `Q`
//! factored row by row (`up_looking.rs`), the local step one spring at a
//! time, plain forward and back substitution (`triangular_solve.rs`), dense
//! with `--dense`; `--ordering natural` there too drops the fill-reducing
//! ordering.

use super::args::{Args, Flag};
use super::AppError;
use masssprings::sim::simulation::SimulationOptions;

pub const ORDERING: Flag = Flag::value(
    "ordering",
    "amd|natural",
    "The sparse Q's fill-reducing ordering (default amd; natural: none, the rows in the scene's order).",
);
pub const FACTORIZATION: Flag = Flag::value(
    "factorization",
    "supernodal|simplicial",
    "The sparse Q's factorization and solves (default supernodal; simplicial: the textbook \
     row-by-row method).",
);

pub const TEXTBOOK: Flag = Flag::switch(
    "textbook",
    "Run the handout's precomputation and step as written (sim/textbook.rs): plain \
     iterations, penalty pins, the simplicial factor; dense with --dense.",
);

/// Sets `options` from the flags that were given.
///
/// # Errors
/// A usage error for an unknown ordering or factorization.
pub fn apply(args: &Args, options: &mut SimulationOptions) -> Result<(), AppError> {
    if args.declares("textbook") {
        options.textbook = args.switch("textbook");
    }
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
