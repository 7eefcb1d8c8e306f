//! The vocabulary of a time step: how it is solved and why it stopped.
//!
//! The assignment's step is fixed: 50 local/global iterations
//! ([`ITERATIONS`]), pins by a penalty. Everything a user can choose beyond
//! that is named here, and nothing here computes anything, so every other
//! file of the simulation can use these words without depending on how a
//! step is carried out:
//!
//! | name | what it says |
//! |---|---|
//! | [`StepMethod`] | which iteration solves the step (`plain` is the handout's) |
//! | [`StepControl`] | the method, the most iterations, the stopping rules |
//! | [`Start`] | where a step's iterations start |
//! | [`Stop`] | why a step stopped |
//! | [`Outcome`] | what a method reports back |
//! | [`Pins`] | pins by the handout's penalty, or exact |
//! | [`Accuracy`] | a named accuracy, and the fastest control known to reach it |
//!
//! Source: the assignment ("50 iterations", "more advanced stopping
//! criteria"); the methods' own files cite theirs.

use std::fmt;
use std::str::FromStr;

/// The assignment's number of local/global iterations per step.
pub const ITERATIONS: usize = 50;

/// Chebyshev's relaxation `γ` of each plain step when none is given
/// (measured: see `methods/chebyshev.rs`).
pub const DEFAULT_RELAXATION: f64 = 1.5;

/// How a step is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum StepMethod {
    /// The assignment's local/global iteration.
    #[default]
    Plain,
    /// Chebyshev semi-iteration on the local/global iterate (Wang 2015).
    Chebyshev,
    /// Anderson acceleration with an energy safeguard (Peng et al. 2018).
    Anderson,
    /// L-BFGS with `Q` as the initial Hessian (Liu, Bouaziz & Kavan 2017).
    Lbfgs,
    /// Newton's method on the exact Hessian, Levenberg–Marquardt damped.
    Newton,
}

impl StepMethod {
    /// Every method, in the order the docs present them.
    pub const ALL: [StepMethod; 5] = [
        StepMethod::Plain,
        StepMethod::Chebyshev,
        StepMethod::Anderson,
        StepMethod::Lbfgs,
        StepMethod::Newton,
    ];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            StepMethod::Plain => "plain",
            StepMethod::Chebyshev => "chebyshev",
            StepMethod::Anderson => "anderson",
            StepMethod::Lbfgs => "lbfgs",
            StepMethod::Newton => "newton",
        }
    }
}

impl fmt::Display for StepMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for StepMethod {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        StepMethod::ALL
            .into_iter()
            .find(|m| m.name() == text)
            .ok_or_else(|| {
                format!("unknown method '{text}' (expected plain, chebyshev, anderson, lbfgs or newton)")
            })
    }
}

/// Where a step's iterations start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Start {
    /// At `pᵗ`, the positions at the step's start: the assignment's.
    #[default]
    Current,
    /// At the inertial prediction `ŷ = 2pᵗ − pᵗ⁻ᐞᵗ`, where the cloth
    /// would go by its momentum alone, when its energy is below `pᵗ`'s
    /// (otherwise at `pᵗ`). Projective dynamics starts there (Bouaziz et
    /// al. 2014, Algorithm 1); on a cloth in steady motion it is already
    /// close to the minimiser.
    Inertial,
}

impl Start {
    /// Both starts.
    pub const ALL: [Start; 2] = [Start::Current, Start::Inertial];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Start::Current => "current",
            Start::Inertial => "inertial",
        }
    }
}

impl FromStr for Start {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Start::ALL
            .into_iter()
            .find(|s| s.name() == text)
            .ok_or_else(|| format!("unknown start '{text}' (expected current or inertial)"))
    }
}

/// How one step is solved: the method and when to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepControl {
    /// The method.
    pub method: StepMethod,
    /// The most iterations a step may take (the assignment: 50).
    pub iterations: usize,
    /// Stop once `‖∇E(p)‖ / ‖∇E(p⁰)‖` over the free vertices is at most
    /// this; `None` runs all `iterations`.
    pub tolerance: Option<f64>,
    /// Stop once the last iteration's energy decrease is at most this
    /// fraction of the decrease since the first iterate (see
    /// `Monitor::after` in `monitor.rs`); `None`: no such rule.
    pub energy_tolerance: Option<f64>,
    /// Let no rule stop a step before its energy has fallen, from the
    /// first iterate, by this many times the first plain iteration's
    /// decrease from there (see `Monitor::after` in `monitor.rs`); with no other rule,
    /// stop there. `None`: no such floor.
    pub at_least_plain: Option<f64>,
    /// Chebyshev's spectral radius `ρ`; `None` estimates it.
    pub rho: Option<f64>,
    /// Chebyshev's relaxation `γ` of each plain step (1: none).
    pub relaxation: f64,
    /// Anderson's and L-BFGS's history: the last `window` iterates.
    pub window: usize,
    /// Where the iterations start.
    pub start: Start,
    /// With L-BFGS: begin each step with plain iterations and hand over
    /// to L-BFGS only once plain slows down (`methods/plain_then_lbfgs.rs`).
    pub plain_first: bool,
    /// Measure the step's energy decrease and relative gradient for its
    /// report even when no rule or observer needs them (the plain
    /// fixed-count step otherwise computes neither: about three passes
    /// over the springs saved per step).
    pub measure: bool,
}

impl StepControl {
    /// Does a stopping rule (either tolerance, or the floor of
    /// `at_least_plain`) end steps before `iterations`?
    pub fn has_stopping_rule(&self) -> bool {
        self.tolerance.is_some() || self.energy_tolerance.is_some() || self.at_least_plain.is_some()
    }

    /// The same control with every stopping rule removed (its steps run
    /// all `iterations`), the other way of reading the rules that
    /// [`StepControl::has_stopping_rule`] lists.
    pub fn without_stopping_rules(self) -> Self {
        StepControl {
            tolerance: None,
            energy_tolerance: None,
            at_least_plain: None,
            plain_first: false,
            ..self
        }
    }
}

/// An accuracy to solve every step to, named instead of spelled out as a
/// method and its rules ([`StepControl::for_accuracy`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Accuracy {
    /// Every step at least as low in energy as the assignment's 50 plain
    /// iterations from `pᵗ` would leave it, as fast as the rules here
    /// know how.
    Assignment,
}

impl Accuracy {
    /// Every accuracy.
    pub const ALL: [Accuracy; 1] = [Accuracy::Assignment];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Accuracy::Assignment => "assignment",
        }
    }

    /// The accuracy whose method, start and rules `control` has (its
    /// budget and history window may differ), if any.
    pub fn of(control: &StepControl) -> Option<Accuracy> {
        let rules = |c: &StepControl| {
            (
                c.method,
                c.start,
                c.tolerance,
                c.energy_tolerance,
                c.at_least_plain,
                c.plain_first,
            )
        };
        Accuracy::ALL
            .into_iter()
            .find(|&a| rules(&StepControl::for_accuracy(a)) == rules(control))
    }
}

impl FromStr for Accuracy {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Accuracy::ALL
            .into_iter()
            .find(|a| a.name() == text)
            .ok_or_else(|| format!("unknown accuracy '{text}' (expected assignment)"))
    }
}

/// The energy rule's `F` of [`Accuracy::Assignment`]: past the floor, stop
/// once an L-BFGS iteration takes off at most 0.15 of all the descent has
/// taken off. Tuned on each run's own trajectory (`docs/convergence.md`,
/// "How to choose"): 0.1 cost about a tenth more on the flag and the skirt,
/// and 0.3 stopped short of plain-50's energy on the skirt's swing and on
/// the flag with `k` ×0.1.
pub const ASSIGNMENT_ENERGY_TOLERANCE: f64 = 0.15;

/// The budget of [`Accuracy::Assignment`]: at most 20 L-BFGS iterations a
/// step after its plain ones (at least three, `plain_then_lbfgs::
/// FEWEST_PLAIN`). Measured, not derived: the steps that reach it are the
/// steps from rest and the swings, where the energy falls steeply for
/// many iterations (`docs/convergence.md`, "How to choose").
pub const ASSIGNMENT_ITERATIONS: usize = 20;

impl StepControl {
    /// The fastest control known to reach `accuracy` on every step.
    ///
    /// [`Accuracy::Assignment`]: plain iterations from `pᵗ` (at least
    /// three, more while they converge fast), then L-BFGS from the lower of
    /// the plain iterate and the inertial prediction
    /// (`methods/plain_then_lbfgs.rs`), with the floor `at_least_plain =
    /// 50` and the energy rule [`ASSIGNMENT_ENERGY_TOLERANCE`] above it,
    /// within [`ASSIGNMENT_ITERATIONS`] L-BFGS iterations. The floor is not
    /// tuned: while plain's decrease per iteration does not grow, after `j`
    /// plain iterations plain-50 takes off at most `50 − j` times the last
    /// one's, so a step past the floor is at least as low as plain-50's.
    /// Where plain speeds up (a cloth swinging through or buckling) the
    /// floor is too high, and the energy rule keeps L-BFGS going while the
    /// energy still falls steeply; where plain converges fast, plain alone
    /// finishes the step at plain-50's energy.
    pub fn for_accuracy(accuracy: Accuracy) -> Self {
        match accuracy {
            Accuracy::Assignment => StepControl {
                method: StepMethod::Lbfgs,
                iterations: ASSIGNMENT_ITERATIONS,
                energy_tolerance: Some(ASSIGNMENT_ENERGY_TOLERANCE),
                at_least_plain: Some(ITERATIONS as f64),
                start: Start::Current,
                plain_first: true,
                ..StepControl::default()
            },
        }
    }
}

/// The multiples `N` of `at_least_plain` a step accepts: at least one
/// plain iteration, at most a million.
pub const AT_LEAST_PLAIN_LIMITS: (f64, f64) = (1.0, 1e6);

/// Is `value` strictly between 0 and 1, as both tolerances (and `ρ`) must be?
pub fn is_open_fraction(value: f64) -> bool {
    value > 0.0 && value < 1.0
}

/// Is `n` a multiple `at_least_plain` accepts ([`AT_LEAST_PLAIN_LIMITS`])?
pub fn is_plain_multiple(n: f64) -> bool {
    let (fewest, most) = AT_LEAST_PLAIN_LIMITS;
    (fewest..=most).contains(&n)
}

impl StepControl {
    /// The first of the stopping rules' numbers out of its range, if any,
    /// said in words (for a caller that takes them from a user).
    pub fn check_rules(&self) -> Result<(), String> {
        for (what, value) in [
            ("tolerance", self.tolerance),
            ("energy tolerance", self.energy_tolerance),
        ] {
            if let Some(t) = value.filter(|&t| !is_open_fraction(t)) {
                return Err(format!("{what} {t}: expected between 0 and 1"));
            }
        }
        if let Some(n) = self.at_least_plain.filter(|&n| !is_plain_multiple(n)) {
            let (fewest, most) = AT_LEAST_PLAIN_LIMITS;
            return Err(format!(
                "at least plain-{n}: expected {fewest} to {most} iterations"
            ));
        }
        Ok(())
    }
}

/// The history window of Anderson and L-BFGS when none is given.
pub const DEFAULT_WINDOW: usize = 5;

/// The longest history window (a longer one is cut to this).
pub const MAX_WINDOW: usize = 100;

impl Default for StepControl {
    fn default() -> Self {
        StepControl {
            method: StepMethod::Plain,
            iterations: ITERATIONS,
            tolerance: None,
            energy_tolerance: None,
            at_least_plain: None,
            rho: None,
            relaxation: DEFAULT_RELAXATION,
            window: DEFAULT_WINDOW,
            start: Start::Current,
            plain_first: false,
            measure: false,
        }
    }
}

/// Why a step stopped iterating.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// It ran every iteration it was allowed.
    Iterations,
    /// The relative gradient reached the tolerance.
    Tolerance,
    /// The energy's progress fell to the energy tolerance.
    EnergyTolerance,
    /// The energy fell by the given multiple of the first plain
    /// iteration's decrease (`--at-least-plain` with no other rule).
    AtLeastPlain,
    /// The line search found no lower energy: the iterate is as good as
    /// rounding lets this method make it.
    Stalled,
    /// Someone asked the step to stop (the viewer's stop button) before it
    /// was done: the step is thrown away
    /// ([`SimulationError::Cancelled`](super::SimulationError::Cancelled)).
    Cancelled,
}

/// The names of the reasons a step stops, as the command line and its
/// output say them (the words of the flags behind the rules: `tolerance`,
/// `energy-tolerance`, `at-least-plain`, the budget `iterations`), never
/// Rust's names of the variants.
impl Stop {
    /// Every reason, in the order of the enum.
    pub const ALL: [Stop; 6] = [
        Stop::Iterations,
        Stop::Tolerance,
        Stop::EnergyTolerance,
        Stop::AtLeastPlain,
        Stop::Stalled,
        Stop::Cancelled,
    ];

    /// The name in the output: the word of the flag whose rule stopped
    /// the step (`Iterations`: the budget, `--iterations`), or `stalled`, or
    /// `cancelled`.
    pub fn name(self) -> &'static str {
        match self {
            Stop::Iterations => "iterations",
            Stop::Tolerance => "tolerance",
            Stop::EnergyTolerance => "energy-tolerance",
            Stop::AtLeastPlain => "at-least-plain",
            Stop::Stalled => "stalled",
            Stop::Cancelled => "cancelled",
        }
    }
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a method reports: iterations run, why it stopped, and the energy
/// where it stopped when it knows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    pub iterations: usize,
    pub stop: Stop,
    /// `E(p) − E(p⁰)` at the returned `p`, when the method measured it
    /// there (the step's report then needs no pass of its own).
    pub energy: Option<f64>,
    /// The method that ran, when not the control's (a step that plain
    /// iterations finished before L-BFGS took over).
    pub method: Option<StepMethod>,
}

impl Outcome {
    /// Stopped by `stop` after `iterations`.
    pub fn new(iterations: usize, stop: Stop) -> Self {
        Outcome {
            iterations,
            stop,
            energy: None,
            method: None,
        }
    }

    /// The same, said to have been run by `method`.
    pub fn ran_by(self, method: StepMethod) -> Self {
        Outcome {
            method: Some(method),
            ..self
        }
    }

    /// The same, with the energy measured at the returned iterate.
    pub fn measured(iterations: usize, stop: Stop, energy: f64) -> Self {
        Outcome {
            energy: Some(energy),
            ..Outcome::new(iterations, stop)
        }
    }
}

/// How pinned vertices are held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pins {
    /// The assignment's penalty `½ w ‖p_c − t_c‖²`, `w = 1e10`.
    #[default]
    Penalty,
    /// Removed from the unknowns ([`exact_pins`](super::exact_pins)).
    Exact,
}

impl FromStr for Pins {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        match text {
            "penalty" => Ok(Pins::Penalty),
            "exact" => Ok(Pins::Exact),
            _ => Err(format!("unknown pins '{text}' (expected penalty or exact)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::StepControl;

    #[test]
    fn a_control_without_stopping_rules_has_none_and_keeps_the_rest() {
        let ruled = StepControl {
            iterations: 7,
            tolerance: Some(0.5),
            energy_tolerance: Some(0.1),
            at_least_plain: Some(50.0),
            ..StepControl::default()
        };
        assert!(ruled.has_stopping_rule());
        let bare = ruled.without_stopping_rules();
        assert!(!bare.has_stopping_rule());
        assert_eq!(bare.iterations, 7);
        // only the rules differ
        assert_eq!(
            bare,
            StepControl {
                iterations: 7,
                ..StepControl::default()
            }
        );
    }
}
