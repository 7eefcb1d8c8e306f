//! Five ways to solve one time step, and what they share.
//!
//! A step minimises the energy `E` of [`energy`](super::energy). The
//! assignment runs 50 local/global iterations and stops; each method here
//! instead iterates until the relative gradient over the free vertices,
//! `‖∇E(p)‖ / ‖∇E(p⁰)‖`, falls below a tolerance (or an iteration lowers
//! the energy by at most a given fraction of the step's decrease so far:
//! the energy tolerance), or a budget of iterations is spent. A floor can
//! hold those rules back until the energy has fallen by `N` times the
//! first plain iteration's decrease (`at_least_plain`, see
//! [`Monitor::after`]):
//!
//! | method | one iteration | file |
//! |---|---|---|
//! | `plain` | `p ← Q⁻¹ b(p)`, the assignment's local/global step | [`plain`] |
//! | `chebyshev` | the same, extrapolated by Chebyshev weights `ω` | [`chebyshev`] |
//! | `anderson` | the same, extrapolated from the last `m` iterates | [`anderson`] |
//! | `lbfgs` | a quasi-Newton step with `Q` as the initial Hessian, line search | [`lbfgs`] |
//! | `newton` | the exact Hessian, factored every iteration, line search | [`newton`] |
//!
//! All of them reuse the one factorization of `Q` from the precomputation
//! (Newton factors its own Hessian). A method's work arrays are sized the
//! first time it runs and reused after, so no step after a method's first
//! allocates.
//!
//! The pieces every method uses are here: `GlobalStep` (the plain
//! iteration and solves with `Q`) and `Monitor` (the stopping rule and the
//! per-iteration observer that `masssprings converge` listens to).
//! [`factor_order`] runs `plain`'s iterations, to the bit, with the
//! positions kept in the sparse factor's order, when nothing watches them.

pub mod anderson;
pub mod block_vector;
pub mod chebyshev;
pub mod factor_order;
pub mod lbfgs;
pub mod line_search;
pub mod newton;
pub mod plain;

use super::backend::LinearAlgebra;
use super::energy::{free_norm, StepEnergy};
use super::exact_pins::ExactPins;
use super::local_step::project_springs_into_transpose;
use std::fmt;
use std::str::FromStr;

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
    /// [`Monitor::after`]); `None`: no such rule.
    pub energy_tolerance: Option<f64>,
    /// Let no rule stop a step before its energy has fallen, from the
    /// first iterate, by this many times the first plain iteration's
    /// decrease from there (see [`Monitor::after`]); with no other rule,
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
            ..self
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
            iterations: super::step::ITERATIONS,
            tolerance: None,
            energy_tolerance: None,
            at_least_plain: None,
            rho: None,
            relaxation: chebyshev::DEFAULT_RELAXATION,
            window: DEFAULT_WINDOW,
            start: Start::Current,
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
}

impl Outcome {
    /// Stopped by `stop` after `iterations`.
    pub fn new(iterations: usize, stop: Stop) -> Self {
        Outcome {
            iterations,
            stop,
            energy: None,
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

/// The state after one iteration, shown to an observer.
pub struct Iterate<'a> {
    /// 0 for the step's start, then 1, 2, …
    pub iteration: usize,
    /// The current positions.
    pub positions: &'a [[f64; 3]],
    /// The step's energy, to evaluate at `positions`.
    pub energy: &'a StepEnergy<'a>,
    /// Which vertices are pinned (left out of the gradient's norm).
    pub pinned: &'a [bool],
}

/// Something that wants to see every iterate (`masssprings converge`).
pub type Observer<'o> = &'o mut dyn FnMut(&Iterate<'_>);

/// The global step: the plain iteration `p ← Q⁻¹ b(p)` and solves with the
/// prefactored `Q`.
#[allow(non_snake_case)] // the handout's Q
pub(crate) struct GlobalStep<'a, B: LinearAlgebra> {
    pub springs: &'a [[usize; 2]],
    pub r: &'a [f64],
    pub k: f64,
    pub Q: &'a B::Matrix,
    /// `y = M ŷ / Δt² + f_ext`.
    pub y: &'a [[f64; 3]],
    /// `w CᵀC V`.
    pub pin_rhs: &'a [[f64; 3]],
    pub factorization: &'a mut B::Factorization,
    /// The reduced system when pins are exact, and the pins.
    pub exact_pins: Option<&'a mut ExactPins<B>>,
    pub pinned: &'a [usize],
    pub pin_targets: &'a [[f64; 3]],
    /// The last local step's `Aᵀd` (the local step keeps only that of
    /// `d`; with exact pins the global step then turns it into `b`, then
    /// `Q_ff⁻¹ b`).
    pub b: &'a mut [[f64; 3]],
}

impl<B: LinearAlgebra> GlobalStep<'_, B> {
    /// One local/global iteration, in place: `p ← Q⁻¹ (k Aᵀ d(p) + y + w CᵀC V)`
    /// (with exact pins: the free rows from `Q_ff`, the pins at their targets).
    pub fn iterate_in_place(&mut self, p: &mut [[f64; 3]]) {
        // the local step, kept as Aᵀd (one pass, d itself never stored)
        project_springs_into_transpose(self.springs, self.r, p, self.b);
        self.global_step(p);
    }

    /// The global step from the last local step's `Aᵀd` in `b`: `p ← Q⁻¹
    /// (k Aᵀ d + y + w CᵀC V)`.
    fn global_step(&mut self, p: &mut [[f64; 3]]) {
        let Some(exact) = self.exact_pins.as_mut() else {
            // b = k Aᵀd + y + w CᵀC V, made row by row as the solve reads it
            let (k, a_t_d, y, pin_rhs) = (self.k, &*self.b, self.y, self.pin_rhs);
            let b_row = |i: usize| -> [f64; 3] {
                std::array::from_fn(|c| k * a_t_d[i][c] + y[i][c] + pin_rhs[i][c])
            };
            B::solve_points_from(self.factorization, b_row, p);
            return;
        };
        for ((b, y), pin) in self.b.iter_mut().zip(self.y).zip(&exact.pin_rhs) {
            *b = std::array::from_fn(|c| self.k * b[c] + y[c] + pin[c]);
        }
        exact.solve(self.b);
        for (&c, &t) in self.pinned.iter().zip(self.pin_targets) {
            self.b[c] = t;
        }
        p.copy_from_slice(self.b);
    }

    /// `v ← Q⁻¹ v` (with exact pins: `Q_ff⁻¹` on the free rows, the pinned
    /// rows 0, so that no direction moves a pin).
    pub fn solve(&mut self, v: &mut [[f64; 3]]) {
        match self.exact_pins.as_mut() {
            None => B::solve_points(self.factorization, v),
            Some(exact) => exact.solve(v),
        }
    }

    /// `out ← Q x` (with exact pins: `(k AᵀA + M/Δt²) x`, pinned rows 0).
    /// `Q` is symmetric, so `Q x = Qᵀ x`: the transposed product sums each
    /// row of `out` in registers, where `Q x` column by column would add
    /// into rows of `out` scattered over memory.
    pub fn mul_q(&self, x: &[[f64; 3]], out: &mut [[f64; 3]]) {
        match self.exact_pins.as_ref() {
            None => B::transpose_mul_points(self.Q, x, out),
            Some(exact) => {
                B::transpose_mul_points(&exact.q_without_pins, x, out);
                for &c in self.pinned {
                    out[c] = [0.0; 3];
                }
            }
        }
    }

    /// With exact pins, puts the pinned rows of `p` back at their targets
    /// (an extrapolation `ω x̂ + (1 − ω) x` rounds them); nothing with the
    /// penalty.
    pub fn hold_pins(&self, p: &mut [[f64; 3]]) {
        if self.exact() {
            for (&c, &t) in self.pinned.iter().zip(self.pin_targets) {
                p[c] = t;
            }
        }
    }

    /// Are the pins exact constraints?
    pub fn exact(&self) -> bool {
        self.exact_pins.is_some()
    }
}

/// Everything a method works with during one step.
pub(crate) struct StepContext<'a, B: LinearAlgebra> {
    pub energy: StepEnergy<'a>,
    /// `pinned[i]`: is vertex `i` pinned?
    pub pinned: &'a [bool],
    pub global: GlobalStep<'a, B>,
    /// Did the step make the local step at the first iterate already (its
    /// `Aᵀd` in place, `∇E` there in the monitor's room)? So that the first
    /// iterate's local step shares its pass with the initial gradient (at
    /// `pᵗ`) or with the test of the inertial start
    /// ([`StepContext::local_step_at_start`]).
    pub start_measured: bool,
    /// `E − E(pᵗ)` at the first iterate (0 when it is `pᵗ`).
    pub start_energy: f64,
}

impl<B: LinearAlgebra> StepContext<'_, B> {
    /// [`StepContext::local_step_measuring`] at the first iterate `p`,
    /// unless the step made it already; returns `E(p) − E(pᵗ)`.
    pub fn local_step_at_start(
        &mut self,
        p: &[[f64; 3]],
        gradient: Option<&mut [[f64; 3]]>,
    ) -> f64 {
        if self.start_measured {
            return self.start_energy;
        }
        self.local_step_measuring(p, gradient)
    }

    /// The local step at `p` (kept, as `Aᵀd`, for the next
    /// [`StepContext::global_step`]), returning `E(p) − E(p⁰)`: the local
    /// step's pass over the springs measures the energy on the way
    /// ([`spring_pass`](crate::sim::spring_pass)), so an iterate's energy
    /// costs one more pass over the vertices only. Peng et al. 2018 test
    /// each accelerated iterate this way.
    ///
    /// With `gradient` (the [`Monitor`]'s room, when its stopping rule will
    /// test `p`) the same pass also makes `∇E(p)`.
    pub fn local_step_measuring(
        &mut self,
        p: &[[f64; 3]],
        gradient: Option<&mut [[f64; 3]]>,
    ) -> f64 {
        let a_t_d = &mut *self.global.b;
        self.energy
            .change_with_local_step(p, a_t_d, gradient)
            .total()
    }

    /// `out ← G(p)` from the last local step (its `Aᵀd`), made at `p`.
    pub fn global_step(&mut self, out: &mut [[f64; 3]]) {
        self.global.global_step(out);
    }
}

/// What [`Monitor::after`] knows of `∇E` at the iterate it is shown.
#[derive(Clone, Copy)]
pub(crate) enum Gradient<'g> {
    /// Nothing: the monitor computes it if its rule needs it.
    Unknown,
    /// The method's own.
    Given(&'g [[f64; 3]]),
    /// The local step made at the iterate filled the monitor's room
    /// ([`Monitor::room_for_gradient`]) with it.
    InRoom,
}

/// The stopping rule and the observer, consulted after every iteration.
pub(crate) struct Monitor<'a, 'o> {
    /// The step's rules (`tolerance`, `energy_tolerance`, `at_least_plain`).
    rules: StepControl,
    /// The energy an iterate must reach before a rule may stop the step
    /// (with `at_least_plain`, once the first plain iterate's is known).
    floor: Option<f64>,
    /// `E − E(p⁰)` at the first iterate and at the last one recorded.
    first_energy: f64,
    last_energy: f64,
    /// `‖∇E(p⁰)‖` over the free vertices.
    initial_gradient: f64,
    /// Room for a gradient, when the method did not compute one.
    gradient: &'a mut [[f64; 3]],
    observer: Option<Observer<'o>>,
    /// The relative gradient at the last iterate recorded, when known.
    pub relative_gradient: Option<f64>,
}

impl<'a, 'o> Monitor<'a, 'o> {
    pub fn new(
        control: &StepControl,
        initial_gradient: f64,
        gradient: &'a mut [[f64; 3]],
        observer: Option<Observer<'o>>,
    ) -> Self {
        Monitor {
            rules: *control,
            floor: None,
            first_energy: 0.0,
            last_energy: 0.0,
            initial_gradient,
            gradient,
            observer,
            relative_gradient: None,
        }
    }

    /// The room for a gradient when nothing will need it before the step
    /// ends (no tolerance, no observer), as scratch for the iterations.
    pub fn unused_room(&mut self) -> Option<&mut [[f64; 3]]> {
        match (self.tests_iterates(), &self.observer) {
            (false, None) => Some(&mut *self.gradient),
            _ => None,
        }
    }

    /// Is there a stopping rule to test at each iterate?
    pub fn tests_iterates(&self) -> bool {
        self.rules.has_stopping_rule()
    }

    /// Does the floor of `at_least_plain` still wait for the energy of the
    /// first plain iterate `G(p⁰)` ([`Monitor::plain_first`])?
    pub fn wants_plain_first(&self) -> bool {
        self.rules.at_least_plain.is_some() && self.floor.is_none()
    }

    /// Gives the energy `E(G(p⁰)) − E(pᵗ)` of the first plain iterate, from
    /// which the floor is set (the first call counts; later ones, and any
    /// without `at_least_plain`, change nothing). A method whose first
    /// iterate is the plain one passes its energy; the others measure it.
    pub fn plain_first(&mut self, energy: f64) {
        if let (Some(multiple), None) = (self.rules.at_least_plain, self.floor) {
            let first_decrease = self.first_energy - energy;
            self.floor = Some(self.first_energy - multiple * first_decrease);
        }
    }

    /// Room for `∇E` at the next iterate, when the stopping rule will test
    /// it (`None` without a tolerance): a method whose local step at that
    /// iterate can make the gradient on the way fills it there, then tells
    /// [`Monitor::after`] so with [`Gradient::InRoom`].
    pub fn room_for_gradient(&mut self) -> Option<&mut [[f64; 3]]> {
        self.rules.tolerance.map(|_| &mut *self.gradient)
    }

    /// `∇E` at the first iterate, when the step measured it there
    /// ([`StepContext::start_measured`]) and no iteration has been recorded
    /// since.
    pub fn start_gradient(&self) -> &[[f64; 3]] {
        self.gradient
    }

    /// After iteration `iteration` reached `p` (iteration 0: the first
    /// iterate), whose energy `E(p) − E(p⁰)` is `energy` when the method
    /// measured it: shows it to the observer, and says which stopping rule
    /// is met, if any. `gradient` says what is known of `∇E(p)`; when
    /// nothing is, it is computed, only if there is a tolerance to test;
    /// an energy not given is computed only for the energy tolerance.
    ///
    /// The energy rule: with `Eⱼ` the energy at iterate `j`, stop at
    /// iteration `k ≥ 1` once `0 ≤ Eₖ₋₁ − Eₖ ≤ T (E₀ − Eₖ)`, the last
    /// decrease at most `T` times all the decrease since the first iterate
    /// (the relative-progress rule of projective-dynamics codes; like
    /// `ftol` of L-BFGS-B, but relative to the step's own decrease, since
    /// `E` itself is large and carries the pins' penalty).
    ///
    /// The floor (`at_least_plain = N`): no rule stops the step before
    /// `E₀ − Eₖ ≥ N (E₀ − E(G(p⁰)))`, `N` times the decrease of the first
    /// plain iteration `G` from the first iterate; with no other rule the
    /// step stops as soon as that holds. Why: the plain iteration's
    /// decrease per iteration, `δⱼ = E(xⱼ₋₁) − E(xⱼ)`, seldom grows, and
    /// while it does not, `N` plain iterations take off `Σ δⱼ ≤ N δ₁`; so
    /// an iterate past the floor is at least as low as plain-`N`'s.
    pub fn after<B: LinearAlgebra>(
        &mut self,
        iteration: usize,
        context: &StepContext<'_, B>,
        p: &[[f64; 3]],
        gradient: Gradient<'_>,
        energy: Option<f64>,
    ) -> Option<Stop> {
        if let Some(observer) = self.observer.as_mut() {
            observer(&Iterate {
                iteration,
                positions: p,
                energy: &context.energy,
                pinned: context.pinned,
            });
        }
        self.relative_gradient = None;
        let StepControl {
            tolerance,
            energy_tolerance,
            at_least_plain,
            ..
        } = self.rules;
        let measure = energy_tolerance.is_some() || at_least_plain.is_some();
        let energy = match energy {
            None if measure => Some(context.energy.change(p).total()),
            known => known,
        };
        if let (0, Some(energy)) = (iteration, energy) {
            (self.first_energy, self.last_energy) = (energy, energy);
        }
        let past_floor = self.past_floor(iteration, energy);
        if let (Some(fraction), Some(energy)) = (energy_tolerance, energy) {
            if self.energy_rule_met(fraction, iteration, energy) && past_floor {
                return Some(Stop::EnergyTolerance);
            }
        }
        if !past_floor {
            return None;
        }
        let Some(tolerance) = tolerance else {
            let floor_alone = at_least_plain.is_some() && energy_tolerance.is_none();
            return floor_alone.then_some(Stop::AtLeastPlain);
        };
        let norm = match gradient {
            Gradient::Given(g) => free_norm(g, context.pinned),
            Gradient::InRoom => free_norm(self.gradient, context.pinned),
            Gradient::Unknown => {
                context.energy.gradient(p, self.gradient);
                free_norm(self.gradient, context.pinned)
            }
        };
        let relative = relative_gradient(norm, self.initial_gradient);
        self.relative_gradient = Some(relative);
        (relative <= tolerance).then_some(Stop::Tolerance)
    }

    /// Records the energy of iterate `iteration` and says whether the
    /// energy rule with tolerance `fraction` stops there.
    fn energy_rule_met(&mut self, fraction: f64, iteration: usize, energy: f64) -> bool {
        let last = std::mem::replace(&mut self.last_energy, energy);
        if iteration == 0 {
            return false;
        }
        let decrease = last - energy;
        (0.0..=fraction * (self.first_energy - energy)).contains(&decrease)
    }

    /// May iterate `iteration`, of energy `energy`, stop the step? Always
    /// without `at_least_plain`; with it, once the floor is known and
    /// `energy` is at or below it.
    fn past_floor(&self, iteration: usize, energy: Option<f64>) -> bool {
        if self.rules.at_least_plain.is_none() {
            return true;
        }
        match (self.floor, energy) {
            (Some(floor), Some(energy)) => iteration > 0 && energy <= floor,
            _ => false,
        }
    }

    /// The relative gradient at `p`, the last iterate (computed unless the
    /// last [`Monitor::after`] already did).
    pub fn final_relative_gradient(
        &mut self,
        energy: &StepEnergy<'_>,
        pinned: &[bool],
        p: &[[f64; 3]],
    ) -> f64 {
        if let Some(known) = self.relative_gradient {
            return known;
        }
        energy.gradient(p, self.gradient);
        relative_gradient(free_norm(self.gradient, pinned), self.initial_gradient)
    }
}

/// `norm / initial`; when the step starts exactly at a minimiser
/// (`initial = 0`, e.g. at rest with no force) there is nothing to divide
/// by, and the absolute `norm` is reported.
fn relative_gradient(norm: f64, initial: f64) -> f64 {
    if initial > 0.0 {
        norm / initial
    } else {
        norm
    }
}

/// The work arrays of each method, made the first time it runs.
#[derive(Debug, Clone, Default)]
pub(crate) struct MethodWorkspaces {
    /// `plain`'s springs in the factor's order (sparse backend only).
    pub factor_order: Option<factor_order::Workspace>,
    pub chebyshev: Option<chebyshev::Workspace>,
    pub anderson: Option<anderson::Workspace>,
    pub lbfgs: Option<lbfgs::Workspace>,
    pub newton: Option<newton::Workspace>,
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
