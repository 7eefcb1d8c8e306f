//! The words the page shows for how a simulation is solved: the name of
//! its options (a solver's, `converged`, or none: the expert's own), the
//! options of a name, and which path and functions run its step. Pure
//! functions of the options, so that the viewer's server and the page's
//! WebAssembly module (`src/web`, which compiles this file too) say the
//! same.
//!
//! How a solver's name becomes options is `SimulationOptions::solved_by`,
//! the one rule `--textbook` and `--accuracy` use too; nothing here
//! repeats it.

use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Solver, StepControl, StepMethod, Stop};

/// The comparison's name for a step solved far: L-BFGS until an
/// iteration takes off at most a thousandth of the step's decrease, at
/// most 200 iterations (`--method lbfgs --energy-tolerance 1e-3
/// --iterations 200`).
pub const CONVERGED: &str = "converged";

/// The names a page may ask for: the solvers, and what `compare` takes
/// besides ([`CONVERGED`]).
pub fn solver_names() -> Vec<&'static str> {
    Solver::ALL.map(Solver::name).to_vec()
}

/// The options of `name` (a solver, or [`CONVERGED`]) on top of `base`.
pub fn options_named(base: SimulationOptions, name: &str) -> Result<SimulationOptions, String> {
    if name == CONVERGED {
        let assignment = base.solved_by(Solver::Assignment);
        let step = StepControl {
            method: StepMethod::Lbfgs,
            energy_tolerance: Some(1e-3),
            iterations: 200,
            ..assignment.step
        };
        return Ok(SimulationOptions { step, ..assignment });
    }
    Ok(base.solved_by(name.parse::<Solver>()?))
}

/// The name of `options` for the status: a solver's, [`CONVERGED`], or
/// `None` (the expert's own method and rules).
pub fn name_of(options: &SimulationOptions) -> Option<&'static str> {
    if let Some(solver) = options.solver() {
        return Some(solver.name());
    }
    let converged = options_named(*options, CONVERGED).ok()?;
    (converged == *options).then_some(CONVERGED)
}

/// Which path runs a step of `options` on `backend` (`sparse` or
/// `dense`), and its functions, for the status.
pub fn functions(options: &SimulationOptions, backend: &str) -> String {
    let factor = match backend {
        "dense" => "dense Cholesky",
        _ if options.textbook => "simplicial sparse Cholesky",
        _ => "supernodal sparse Cholesky",
    };
    if options.textbook {
        return format!(
            "the handout's code as written: sim/textbook.rs, \
             fast_mass_springs_step_{backend} ({factor})"
        );
    }
    let step = &options.step;
    let method = match step.method {
        StepMethod::Lbfgs if step.plain_first => "plain_then_lbfgs",
        method => method.name(),
    };
    format!("fast path: sim/step.rs solve_step → sim/methods/{method}.rs ({factor})")
}

/// Did a step that stopped for `stop` reach one of its rules (a
/// tolerance, or plain-50's decrease), rather than its budget or a
/// stalled line search? The plot marks such steps as converged.
pub fn converged(stop: Stop) -> bool {
    matches!(
        stop,
        Stop::Tolerance | Stop::EnergyTolerance | Stop::AtLeastPlain
    )
}
