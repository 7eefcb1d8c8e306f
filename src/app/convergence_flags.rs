//! The flags that choose how each step is solved, shared by `simulate`,
//! `render`, `view` and `converge`: `--method`, `--tolerance`,
//! `--energy-tolerance`, `--at-least-plain`, `--iterations`, `--rho`,
//! `--relaxation`, `--window`, `--start`, `--pins`, and `--accuracy`,
//! which names the method and rules instead of spelling them out. A command lists the ones it accepts in
//! its flag table ([`super::args::CommandSpec`]); [`apply`] reads those
//! that were declared.

use super::args::{Args, Flag};
use super::AppError;
use masssprings::sim::control::{
    is_open_fraction, is_plain_multiple, Accuracy, Start, AT_LEAST_PLAIN_LIMITS, MAX_WINDOW,
};
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{StepControl, StepMethod};

pub const METHOD: Flag = Flag::value(
    "method",
    "M",
    "How each step is solved: plain, chebyshev, anderson, lbfgs or newton (default plain).",
);
pub const ACCURACY: Flag = Flag::value(
    "accuracy",
    "A",
    "Solve every step to a named accuracy, as fast as we know how: assignment (at least as \
     low in energy as the assignment's 50 plain iterations; L-BFGS, --energy-tolerance 0.15 \
     --at-least-plain 50, at most 20 iterations unless --iterations says otherwise). Instead \
     of --method and the stopping rules.",
);
/// The flags `--accuracy` chooses for the user.
const CHOSEN_BY_ACCURACY: [&str; 4] = ["method", "tolerance", "energy-tolerance", "at-least-plain"];

pub const TOLERANCE: Flag = Flag::value(
    "tolerance",
    "T",
    "Stop a step once its relative gradient is at most T (between 0 and 1; default: run \
     every iteration).",
);
pub const ENERGY_TOLERANCE: Flag = Flag::value(
    "energy-tolerance",
    "F",
    "Stop a step once an iteration lowers its energy by at most F times all it has lowered \
     it since the first iterate (between 0 and 1; default: no such rule). With --tolerance, \
     whichever is met first.",
);
pub const AT_LEAST_PLAIN: Flag = Flag::value(
    "at-least-plain",
    "N",
    "Let no rule stop a step before its energy has fallen by N times what the first plain \
     iteration takes off (at least 1; N plain iterations take off at most that while their \
     decrease does not grow). With no other rule, stop there.",
);
pub const ITERATIONS: Flag = Flag::value(
    "iterations",
    "N",
    "The most iterations a step may take (default 50).",
);
pub const RHO: Flag = Flag::value(
    "rho",
    "R",
    "Chebyshev's spectral radius, between 0 and 1 (default: estimated).",
);
pub const RELAXATION: Flag = Flag::value(
    "relaxation",
    "G",
    "Chebyshev's relaxation γ of each plain step, above 0 and at most 2 (default 1.5; 1: \
     none).",
);
pub const WINDOW: Flag = Flag::value(
    "window",
    "W",
    "Anderson's and L-BFGS's history length, 1 to 100.",
);
pub const START: Flag = Flag::value(
    "start",
    "S",
    "Where each step's iterations start: current (the positions at the step's start, the \
     assignment's; default) or inertial (2 pᵗ − pᵗ⁻¹, where the cloth's momentum takes it, \
     when its energy is lower).",
);

pub const PINS: Flag = Flag::value(
    "pins",
    "P",
    "penalty (the assignment's w = 1e10, default) or exact (pinned vertices removed from the \
     unknowns).",
);

/// Sets `options` from the flags that were given (among those the command
/// declares).
///
/// # Errors
/// A usage error for an unknown method or a value out of range.
pub fn apply(args: &Args, options: &mut SimulationOptions) -> Result<(), AppError> {
    if let Some(accuracy) = accuracy(args)? {
        options.step = StepControl {
            measure: options.step.measure,
            ..StepControl::for_accuracy(accuracy)
        };
    }
    if args.declares("method") {
        let names = StepMethod::ALL.map(StepMethod::name);
        let name = args.choice("method", options.step.method.name(), &names)?;
        options.step.method = name.parse().map_err(AppError::Usage)?;
    }
    if args.declares("pins") {
        let name = args.choice("pins", "penalty", &["penalty", "exact"])?;
        options.pins = name.parse().map_err(AppError::Usage)?;
    }
    if args.declares("start") {
        let names = Start::ALL.map(Start::name);
        let name = args.choice("start", options.step.start.name(), &names)?;
        options.step.start = name.parse().map_err(AppError::Usage)?;
    }
    if args.declares("iterations") {
        options.step.iterations = args.count("iterations", options.step.iterations, 1)?;
    }
    if args.declares("tolerance") {
        options.step.tolerance = open_unit_interval(args, "tolerance", "a relative gradient")?
            .or(options.step.tolerance);
    }
    if args.declares("energy-tolerance") {
        options.step.energy_tolerance =
            open_unit_interval(args, "energy-tolerance", "a fraction of the decrease")?
                .or(options.step.energy_tolerance);
    }
    if args.declares("at-least-plain") {
        if let Some(text) = args.text("at-least-plain") {
            let (fewest, most) = AT_LEAST_PLAIN_LIMITS;
            options.step.at_least_plain = match text.trim().parse::<f64>() {
                Ok(value) if is_plain_multiple(value) => Some(value),
                _ => {
                    return Err(AppError::Usage(format!(
                        "--at-least-plain expects a number of plain iterations from {fewest} \
                         to {most}, got '{text}'"
                    )))
                }
            };
        }
    }
    if args.declares("rho") {
        options.step.rho =
            open_unit_interval(args, "rho", "a spectral radius")?.or(options.step.rho);
    }
    if args.declares("relaxation") {
        if let Some(text) = args.text("relaxation") {
            options.step.relaxation = match text.trim().parse::<f64>() {
                Ok(value) if value > 0.0 && value <= 2.0 => value,
                _ => {
                    return Err(AppError::Usage(format!(
                        "--relaxation expects a number above 0 and at most 2, got '{text}'"
                    )))
                }
            };
        }
    }
    if args.declares("window") {
        options.step.window =
            args.whole_number("window", options.step.window as u64, 1..=MAX_WINDOW as u64)?
                as usize;
    }
    Ok(())
}

/// `--accuracy`, if declared and given; refused beside a flag it sets.
fn accuracy(args: &Args) -> Result<Option<Accuracy>, AppError> {
    if !args.declares("accuracy") {
        return Ok(None);
    }
    let Some(text) = args.text("accuracy") else {
        return Ok(None);
    };
    if let Some(other) = CHOSEN_BY_ACCURACY
        .into_iter()
        .find(|&name| args.declares(name) && args.text(name).is_some())
    {
        return Err(AppError::Usage(format!(
            "--accuracy and --{other} cannot be given together (--accuracy chooses the method \
             and the stopping rules)"
        )));
    }
    text.trim().parse().map(Some).map_err(AppError::Usage)
}

/// `--name` as a number strictly between 0 and 1, if given.
fn open_unit_interval(args: &Args, name: &str, what: &str) -> Result<Option<f64>, AppError> {
    let Some(text) = args.text(name) else {
        return Ok(None);
    };
    match text.trim().parse::<f64>() {
        Ok(value) if is_open_fraction(value) => Ok(Some(value)),
        _ => Err(AppError::Usage(format!(
            "--{name} expects {what} between 0 and 1, got '{text}'"
        ))),
    }
}
