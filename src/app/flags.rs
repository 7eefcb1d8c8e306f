//! The flag groups several commands share, each defined once (a clap
//! `Args` struct) and flattened into the commands it applies to, so that a
//! flag has one name, one meaning and one default everywhere:
//!
//! * [`SimulationFlags`]: [`Solve`], [`Backend`] and `--kernels` together;
//! * [`Solve`]: how each step is solved, [`StepMethodFlags`] (the
//!   iteration method, or the handout's code as written) and [`StepRules`]
//!   (stopping rules, budget, start, pins, and `--accuracy`, which names a
//!   method and rules instead of spelling them out);
//! * [`Backend`]: dense matrices, or how the sparse `Q` is factored
//!   ([`FactorFlags`]: ordering, factorization, supernodes, and
//!   [`ThreadsFlag`]);
//! * the value parsers: whole numbers and fractions within a range, names
//!   among a few, `--size WxH`; each error says the value and the range.

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use masssprings::linalg::kernels::Kernels;
use masssprings::linalg::sparse::{Method, Ordering, SupernodeMerging};
use masssprings::linalg::threads;
use masssprings::sim::control::{
    is_open_fraction, is_plain_multiple, Accuracy, Pins, Start, AT_LEAST_PLAIN_LIMITS, MAX_WINDOW,
};
use masssprings::sim::simulation::{SimulationOptions, Solver};
use masssprings::sim::StepMethod;
use std::str::FromStr;

/// How a simulation runs: how each step is solved and on which backend
/// (`simulate`, `render` and `view`).
#[derive(Args, Debug, Clone)]
pub struct SimulationFlags {
    #[command(flatten)]
    pub solve: Solve,
    #[command(flatten)]
    pub backend: Backend,
    /// The kernels of the solves, the factorization and the passes over the springs: native (the vector instructions this CPU has, AVX2 and FMA; default) or portable (the plain loops, which compute what the browser's WebAssembly page computes, to the bit; linalg/kernels.rs).
    #[arg(long, value_name = "K", default_value = "native", value_parser = choice::<Kernels>(&Kernels::ALL.map(Kernels::name)))]
    pub kernels: Kernels,
}

/// `--json`, the same in every command that reports numbers (whether the
/// progress stays on standard error is each command's to say).
#[derive(Args, Debug, Clone, Copy)]
pub struct JsonFlag {
    /// Print one JSON object instead of the report.
    #[arg(long)]
    pub json: bool,
}

impl SimulationFlags {
    /// Sets `options` from the flags that were given.
    pub fn apply(&self, options: &mut SimulationOptions) {
        self.solve.apply(options);
        self.backend.factor.apply(options);
        options.kernels = self.kernels;
    }
}

/// How each step is solved (`converge` compares every method, see its
/// `--methods`, and takes [`StepRules`] alone, with an `--iterations` of
/// its own: the length of its curves).
#[derive(Args, Debug, Clone)]
pub struct Solve {
    #[command(flatten)]
    pub method: StepMethodFlags,
    /// The most iterations a step may take (default 50, the assignment's; with --accuracy, the accuracy's).
    #[arg(long, value_name = "N", value_parser = whole(1, usize::MAX))]
    pub iterations: Option<usize>,
    #[command(flatten)]
    pub rules: StepRules,
}

/// The iteration method, or the handout's code.
#[derive(Args, Debug, Clone)]
pub struct StepMethodFlags {
    /// How each step is solved (default plain).
    #[arg(long, value_name = "M", value_parser = choice::<StepMethod>(&StepMethod::ALL.map(StepMethod::name)), conflicts_with = "accuracy")]
    pub method: Option<StepMethod>,
    /// Run the handout's precomputation and step as written (sim/textbook.rs): plain iterations, penalty pins, the simplicial factor; dense with --dense. It takes --iterations, --ordering and --dense, and refuses the flags of the fast path.
    #[arg(long, conflicts_with_all = TEXTBOOK_REFUSES)]
    pub textbook: bool,
}

/// The flags `--textbook` refuses: the handout's step has one method (plain
/// iterations from `U_cur`, all of them), penalty pins and the simplicial
/// factor, so each of these would be ignored.
const TEXTBOOK_REFUSES: [&str; 12] = [
    "method",
    "accuracy",
    "tolerance",
    "energy_tolerance",
    "at_least_plain",
    "rho",
    "relaxation",
    "window",
    "start",
    "pins",
    "factorization",
    "supernodes",
];

/// When a step stops, where it starts, how pins hold: shared by every
/// command that steps a simulation (the budget, `--iterations`, is each
/// command's: [`Solve`] and `converge` give it different defaults).
#[derive(Args, Debug, Clone)]
pub struct StepRules {
    /// Solve every step to a named accuracy, as fast as we know how: assignment (at least as low in energy as the assignment's 50 plain iterations from the same state: at least three plain iterations, then L-BFGS from the lower of the plain iterate and the inertial prediction until the energy is past what plain-50 can reach and has stopped falling steeply, at most 20 L-BFGS iterations unless --iterations says otherwise; docs/convergence.md, section 6). Instead of choosing a method and stopping rules.
    #[arg(long, value_name = "A", value_parser = choice::<Accuracy>(&Accuracy::ALL.map(Accuracy::name)), conflicts_with_all = ["tolerance", "energy_tolerance", "at_least_plain"])]
    pub accuracy: Option<Accuracy>,
    /// Stop a step once its relative gradient is at most T (between 0 and 1; default: run every iteration).
    #[arg(long, value_name = "T", value_parser = open_fraction)]
    pub tolerance: Option<f64>,
    /// Stop a step once an iteration lowers its energy by at most F times all it has lowered it since the first iterate (between 0 and 1; default: no such rule). With --tolerance, whichever is met first.
    #[arg(long, value_name = "F", value_parser = open_fraction)]
    pub energy_tolerance: Option<f64>,
    /// Let no rule stop a step before its energy has fallen by N times what the first plain iteration takes off (1 to 1e6; N plain iterations take off at most that while their decrease does not grow). With no other rule, stop there.
    #[arg(long, value_name = "N", value_parser = plain_multiple)]
    pub at_least_plain: Option<f64>,
    /// Chebyshev's spectral radius, between 0 and 1 (default: estimated).
    #[arg(long, value_name = "R", value_parser = open_fraction)]
    pub rho: Option<f64>,
    /// Chebyshev's relaxation γ of each plain step, above 0 and at most 2 (default 1.5; 1: none).
    #[arg(long, value_name = "G", value_parser = relaxation)]
    pub relaxation: Option<f64>,
    /// Anderson's and L-BFGS's history length, 1 to 100 (default 5).
    #[arg(long, value_name = "W", value_parser = whole(1, MAX_WINDOW))]
    pub window: Option<usize>,
    /// Where each step's iterations start: current (the positions at the step's start, the assignment's; default) or inertial (2 pᵗ − pᵗ⁻¹, where the cloth's momentum takes it, when its energy is lower).
    #[arg(long, value_name = "S", value_parser = choice::<Start>(&Start::ALL.map(Start::name)))]
    pub start: Option<Start>,
    /// How pins hold: penalty (the assignment's w = 1e10; default) or exact (pinned vertices removed from the unknowns).
    #[arg(long, value_name = "P", value_parser = choice::<Pins>(&["penalty", "exact"]))]
    pub pins: Option<Pins>,
}

/// Dense matrices, or how the sparse `Q` is factored.
#[derive(Args, Debug, Clone)]
pub struct Backend {
    /// Dense matrices and Cholesky (the assignment's dense path).
    #[arg(long, conflicts_with_all = ["ordering", "factorization", "supernodes"])]
    pub dense: bool,
    #[command(flatten)]
    pub factor: FactorFlags,
}

/// How the sparse `Q` is factored.
#[derive(Args, Debug, Clone)]
pub struct FactorFlags {
    #[command(flatten)]
    pub ordering: OrderingFlag,
    /// The sparse Cholesky factorization and its solves (simplicial: the textbook row-by-row method).
    #[arg(long, value_name = "F", default_value = "supernodal", value_parser = choice::<Method>(&["supernodal", "simplicial"]))]
    pub factorization: Method,
    /// The supernodal factorization's supernodes: small (those of at most three columns merged, storing a few zeros), fundamental (none merged) or relaxed (CHOLMOD's rule, many zeros).
    #[arg(long, value_name = "S", default_value = "small", value_parser = choice::<SupernodeMerging>(&["small", "fundamental", "relaxed"]))]
    pub supernodes: SupernodeMerging,
    #[command(flatten)]
    pub threads: ThreadsFlag,
}

/// The most threads `--threads` takes (more than any machine here has
/// cores; each is a thread of the operating system).
pub const MAX_THREADS: usize = 256;

/// `--threads N`, the same in every command that factors, solves or steps.
#[derive(Args, Debug, Clone, Copy)]
pub struct ThreadsFlag {
    /// Threads of the supernodal factorization, its solves and the plain iterations (default: the cores available); the results are the same to the bit on any number, and 1 runs the single-threaded code. The handout's code as written, the simplicial factorization and dense matrices run on one, and a simulation takes at most one thread per 500 vertices of its scene.
    #[arg(long, value_name = "N", value_parser = whole(1, MAX_THREADS))]
    pub threads: Option<usize>,
}

impl ThreadsFlag {
    /// The number asked for, or the cores available.
    pub fn count(&self) -> usize {
        self.threads.unwrap_or_else(threads::available)
    }
}

/// The fill-reducing ordering: every command that factors `Q` or draws it
/// in the factor's order.
#[derive(Args, Debug, Clone, Copy)]
pub struct OrderingFlag {
    /// The sparse Cholesky factorization's fill-reducing ordering (natural: none, the rows in the order given).
    #[arg(long, value_name = "O", default_value = "amd", value_parser = choice::<Ordering>(&["amd", "natural"]))]
    pub ordering: Ordering,
}

impl Solve {
    /// Sets `options` from the flags that were given: `--textbook` first
    /// (the solver, by `SimulationOptions::solved_by`, the one rule the
    /// viewer's solve picker uses too), then the rules and the method on
    /// top (a textbook run refuses those that are not the handout's).
    pub fn apply(&self, options: &mut SimulationOptions) {
        if self.method.textbook {
            *options = options.solved_by(Solver::Textbook);
        }
        self.rules.apply(options);
        options.step.iterations = self.iterations.unwrap_or(options.step.iterations);
        if let Some(method) = self.method.method {
            options.step.method = method;
        }
    }
}

impl StepRules {
    /// Sets `options` from the flags that were given: `--accuracy` first
    /// (its solver, by `SimulationOptions::solved_by`: its method, rules
    /// and budget), then each flag given on top (the budget,
    /// `--iterations`, is set after this by the command).
    pub fn apply(&self, options: &mut SimulationOptions) {
        if let Some(accuracy) = self.accuracy {
            *options = options.solved_by(Solver::Accuracy(accuracy));
        }
        let step = &mut options.step;
        step.tolerance = self.tolerance.or(step.tolerance);
        step.energy_tolerance = self.energy_tolerance.or(step.energy_tolerance);
        step.at_least_plain = self.at_least_plain.or(step.at_least_plain);
        step.rho = self.rho.or(step.rho);
        step.relaxation = self.relaxation.unwrap_or(step.relaxation);
        step.window = self.window.unwrap_or(step.window);
        step.start = self.start.unwrap_or(step.start);
        options.pins = self.pins.unwrap_or(options.pins);
    }
}

impl FactorFlags {
    /// Sets the sparse backend's ordering, factorization and threads.
    pub fn apply(&self, options: &mut SimulationOptions) {
        options.ordering = self.ordering.ordering;
        options.factorization = self.factorization;
        options.supernodes = self.supernodes;
        options.threads = self.threads.count();
    }
}

/// One of `names`, parsed into `T`; clap lists the names in the help and
/// suggests the nearest one for a typo.
pub fn choice<T>(names: &[&'static str]) -> impl TypedValueParser<Value = T>
where
    T: FromStr<Err = String> + Clone + Send + Sync + 'static,
{
    PossibleValuesParser::new(names.to_vec())
        .map(|name| T::from_str(&name).expect("every possible value parses"))
}

/// A whole number from `least` to `most` (`usize::MAX`: no upper bound).
pub fn whole(least: usize, most: usize) -> impl Fn(&str) -> Result<usize, String> + Clone {
    move |text| {
        let range = if most == usize::MAX {
            format!("a whole number ≥ {least}")
        } else {
            format!("a whole number from {least} to {most}")
        };
        match text.trim().parse::<u128>() {
            Ok(n) if n >= least as u128 && n <= most as u128 => Ok(n as usize),
            Ok(_) => Err(format!("expected {range}; {text} is out of range")),
            Err(_) => Err(format!("expected {range}, got '{text}'")),
        }
    }
}

/// A number within `range` (each end included), said as `what` in the
/// error.
fn number(text: &str, ok: impl Fn(f64) -> bool, what: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(value) if value.is_finite() && ok(value) => Ok(value),
        _ => Err(format!("expected {what}, got '{text}'")),
    }
}

/// A number strictly between 0 and 1 (a tolerance, `ρ`).
fn open_fraction(text: &str) -> Result<f64, String> {
    number(
        text,
        is_open_fraction,
        "a number between 0 and 1 (both excluded)",
    )
}

/// `--at-least-plain`'s multiple of the first plain iteration.
fn plain_multiple(text: &str) -> Result<f64, String> {
    let (fewest, most) = AT_LEAST_PLAIN_LIMITS;
    let what = format!("a number of plain iterations from {fewest} to {most}");
    number(text, is_plain_multiple, &what)
}

/// Chebyshev's `γ`: above 0, at most 2.
fn relaxation(text: &str) -> Result<f64, String> {
    number(
        text,
        |g| g > 0.0 && g <= 2.0,
        "a number above 0 and at most 2",
    )
}

/// A number from `least` to `most`, both included.
pub fn between(least: f64, most: f64) -> impl Fn(&str) -> Result<f64, String> + Clone {
    move |text| {
        let what = format!("a number from {least} to {most}");
        number(text, |x| (least..=most).contains(&x), &what)
    }
}

/// A picture's size in pixels: `WxH` (also `X` or `×`), or `N` for a
/// square.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size {
    pub width: usize,
    pub height: usize,
}

/// `--size WxH` (or `N`, a square), each side from `least` to `most`: the
/// one parser of every command that draws.
pub fn size(least: usize, most: usize) -> impl Fn(&str) -> Result<Size, String> + Clone {
    move |text| {
        let side = |s: &str| {
            s.trim()
                .parse::<usize>()
                .ok()
                .filter(|n| (least..=most).contains(n))
        };
        let (w, h) = text.split_once(['x', 'X', '×']).unwrap_or((text, text));
        match (side(w), side(h)) {
            (Some(width), Some(height)) => Ok(Size { width, height }),
            _ => Err(format!(
                "expected WIDTHxHEIGHT, each from {least} to {most} pixels (e.g. 480x360), \
                 got '{text}'"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_every_spelling_and_refuse_the_rest() {
        let parse = size(1, 2048);
        assert_eq!(
            parse("480x360"),
            Ok(Size {
                width: 480,
                height: 360
            })
        );
        assert_eq!(
            parse("3×2"),
            Ok(Size {
                width: 3,
                height: 2
            })
        );
        assert_eq!(
            parse("64"),
            Ok(Size {
                width: 64,
                height: 64
            })
        );
        for bad in ["", "x", "0x10", "10x", "4096x10", "ax3", "-3x3"] {
            let error = parse(bad).unwrap_err();
            assert!(
                error.contains("1 to 2048") && error.contains(bad),
                "{error}"
            );
        }
    }

    #[test]
    fn whole_numbers_name_the_range_and_the_value() {
        assert_eq!(whole(1, 100)("7"), Ok(7));
        assert_eq!(
            whole(1, usize::MAX)("0").unwrap_err(),
            "expected a whole number ≥ 1; 0 is out of range"
        );
        assert_eq!(
            whole(0, 65535)("ten").unwrap_err(),
            "expected a whole number from 0 to 65535, got 'ten'"
        );
        assert!(whole(0, 10)("99999999999999999999999999").is_err());
    }

    #[test]
    fn fractions_refuse_their_ends() {
        assert_eq!(open_fraction("0.5"), Ok(0.5));
        for bad in ["0", "1", "nan", "inf", "-0.1", "half"] {
            assert!(open_fraction(bad).is_err(), "{bad}");
        }
        assert_eq!(relaxation("2"), Ok(2.0));
        assert!(relaxation("0").is_err());
        assert!(between(1e-4, 1.0)("2").unwrap_err().contains("0.0001 to 1"));
    }
}
