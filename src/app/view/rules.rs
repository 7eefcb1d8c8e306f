//! The page's rules, whichever backend runs its simulation: what its
//! sliders, pickers and drags may ask (the parameters' ranges, a method
//! and its stopping rules, where a vertex may be pulled), and the words it shows for how a simulation is solved
//! (the name of its options: a solver's, `converged`, or none, the
//! expert's own; the options of a name; which path and functions run its
//! step). Pure functions of the options, so that the viewer's server and
//! the page's WebAssembly module (`src/web`, which compiles this file too)
//! check and say the same.
//!
//! How a solver's name becomes options is `SimulationOptions::solved_by`,
//! the one rule `--textbook` and `--accuracy` use too; nothing here
//! repeats it.

use masssprings::files::{escaped, number};
use masssprings::mesh::bounding_box::BoundingBox;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Solver, Start, StepControl, StepMethod, Stop};

/// The most iterations a step of the viewer may take, from the command line
/// as from the page: a step must end within moments for the viewer to
/// answer and to stop (and any can be cancelled).
pub const MAX_ITERATIONS: usize = 1000;

/// Refuses parameters out of the sliders' ranges, saying which.
///
/// # Errors
/// The first value out of its range, and the range.
pub fn check_parameters(
    [k, delta_t, mass_scale]: [f64; 3],
    iterations: usize,
) -> Result<(), String> {
    let in_range = |x: f64, low: f64, high: f64| x.is_finite() && (low..=high).contains(&x);
    if !in_range(k, 1e-6, 1e12) {
        return Err(format!(
            "k = {}: expected a stiffness from 1e-6 to 1e12",
            number(k)
        ));
    }
    if !in_range(delta_t, 1e-4, 1.0) {
        return Err(format!(
            "Δt = {}: expected from 0.0001 to 1 s",
            number(delta_t)
        ));
    }
    if !in_range(mass_scale, 1e-3, 1e3) {
        return Err(format!(
            "mass scale {}: expected from 0.001 to 1000",
            number(mass_scale)
        ));
    }
    if !(1..=MAX_ITERATIONS).contains(&iterations) {
        return Err(format!(
            "{iterations} iterations: expected from 1 to {MAX_ITERATIONS}"
        ));
    }
    Ok(())
}

/// Where a dragged vertex may be pulled: within ten times the rest
/// shape's diagonal (at least 10) of its centre, a guard against targets
/// that would blow the solve up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragReach {
    center: [f64; 3],
    reach: f64,
}

impl DragReach {
    /// The reach of a scene at rest in `rest`.
    pub fn of(rest: &[[f64; 3]]) -> DragReach {
        let bounds = BoundingBox::of(rest);
        DragReach {
            center: bounds.centre(),
            reach: 10.0 * bounds.diagonal().max(1.0),
        }
    }

    /// Refuses a target that is not finite or too far from the scene.
    ///
    /// # Errors
    /// Saying so.
    pub fn check(&self, target: [f64; 3]) -> Result<(), String> {
        let distance = (0..3)
            .map(|axis| (target[axis] - self.center[axis]).powi(2))
            .sum::<f64>()
            .sqrt();
        if distance.is_finite() && distance <= self.reach {
            Ok(())
        } else {
            Err("the drag target is too far from the scene".into())
        }
    }
}

/// `current` solved by another method, tolerances (the relative
/// gradient's and the energy's), floor (`--at-least-plain`) or start
/// (`None`: kept): its budget and history window stay, and so does how the
/// method runs (L-BFGS's plain start) while it stays.
///
/// # Errors
/// An unknown method or start, or a rule out of its range.
pub fn method_step(
    current: StepControl,
    method: &str,
    [tolerance, energy_tolerance]: [Option<f64>; 2],
    at_least_plain: Option<f64>,
    start: Option<&str>,
) -> Result<StepControl, String> {
    let method: StepMethod = method.parse()?;
    let start: Start = match start {
        Some(name) => name.parse()?,
        None => current.start,
    };
    let step = StepControl {
        method,
        tolerance,
        energy_tolerance,
        at_least_plain,
        start,
        plain_first: current.plain_first && method == current.method,
        ..current
    };
    step.check_rules()?;
    Ok(step)
}

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
    let solver = name.parse::<Solver>().map_err(|_| {
        let mut names = solver_names();
        names.push(CONVERGED);
        format!(
            "unknown solver '{}' (expected {})",
            escaped(name),
            names.join(", ")
        )
    })?;
    Ok(base.solved_by(solver))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refused_parameters_are_written_short() {
        let refused = check_parameters([1e308, 0.03, 1.0], 10).unwrap_err();
        assert_eq!(refused, "k = 1e308: expected a stiffness from 1e-6 to 1e12");
        let refused = check_parameters([1.0, 1e-300, 1.0], 10).unwrap_err();
        assert!(refused.starts_with("Δt = 1e-300:"), "{refused}");
    }

    #[test]
    fn an_unknown_solver_is_refused_naming_every_one_compare_takes() {
        let refused = options_named(SimulationOptions::default(), "fast\n").unwrap_err();
        assert!(refused.starts_with("unknown solver 'fast\\n'"), "{refused}");
        for name in solver_names().into_iter().chain([CONVERGED]) {
            assert!(refused.contains(name), "{name}: {refused}");
        }
    }
}
