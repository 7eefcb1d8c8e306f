//! The monitor: the stopping rules and the observer of a step.
//!
//! After every iteration a method shows its iterate to the [`Monitor`],
//! which
//!
//! * shows it to an observer, if any (`masssprings converge` plots every
//!   iterate; the viewer plots every step);
//! * tests the stopping rules of the step's [`StepControl`]: the relative
//!   gradient `‖∇E(p)‖ / ‖∇E(p⁰)‖` over the free vertices against
//!   `tolerance`, the energy's progress against `energy_tolerance`, and the
//!   floor `at_least_plain` under both (the rules are written out at
//!   [`Monitor::after`]).
//!
//! It computes only what a rule or an observer needs: with neither (the
//! assignment's fixed 50 iterations) it computes nothing at all.
//!
//! Sources: the relative-gradient rule, Nocedal & Wright, *Numerical
//! Optimization* (2006), §3.3; the relative-progress rule of projective
//! dynamics codes (Bouaziz et al. 2014); the floor is this crate's
//! (`docs/convergence.md`, "Stopping rules").

use super::backend::LinearAlgebra;
use super::control::{StepControl, Stop};
use super::energy::{free_norm, StepEnergy};
use super::global_step::StepContext;
use std::sync::atomic::{AtomicBool, Ordering};

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

/// What [`Monitor::after`] knows of `∇E` at the iterate it is shown.
#[derive(Clone, Copy)]
pub enum Gradient<'g> {
    /// Nothing: the monitor computes it if its rule needs it.
    Unknown,
    /// The method's own.
    Given(&'g [[f64; 3]]),
    /// The local step made at the iterate filled the monitor's room
    /// ([`Monitor::room_for_gradient`]) with it.
    InRoom,
}

/// The stopping rule and the observer, consulted after every iteration.
pub struct Monitor<'a, 'o> {
    /// The step's rules (`tolerance`, `energy_tolerance`, `at_least_plain`).
    rules: StepControl,
    /// The energy an iterate must reach before a rule may stop the step
    /// (with `at_least_plain`, once the first plain iterate's is known).
    floor: Option<f64>,
    /// Stop, floor or not, once an iteration takes off at most this
    /// fraction of the step's decrease, or at most the rounding of the
    /// energy ([`Monitor::stop_when_converged`]).
    converged: Option<(f64, f64)>,
    /// `E − E(p⁰)` at the first iterate and at the last one recorded.
    first_energy: f64,
    last_energy: f64,
    /// Where the energy rule measures the step's gain from: the first
    /// iterate's energy, or where the iterations started again
    /// ([`Monitor::restart_at`]).
    rule_origin: f64,
    /// The energy rule also waits for a decrease at most this
    /// ([`Monitor::keep_pace_with`]).
    pace: f64,
    /// `‖∇E(p⁰)‖` over the free vertices, when the step measured it (it
    /// does whenever a rule, an observer or the report needs it).
    initial_gradient: Option<f64>,
    /// Room for a gradient, when the method did not compute one.
    gradient: &'a mut [[f64; 3]],
    observer: Option<Observer<'o>>,
    /// Set by someone else to stop the step at the next iterate
    /// ([`Monitor::cancel_on`]).
    cancel: Option<&'a AtomicBool>,
    /// The relative gradient at the last iterate recorded, when known.
    pub relative_gradient: Option<f64>,
}

impl<'a, 'o> Monitor<'a, 'o> {
    pub fn new(
        control: &StepControl,
        initial_gradient: Option<f64>,
        gradient: &'a mut [[f64; 3]],
        observer: Option<Observer<'o>>,
    ) -> Self {
        Monitor {
            rules: *control,
            floor: None,
            converged: None,
            first_energy: 0.0,
            last_energy: 0.0,
            rule_origin: 0.0,
            pace: f64::INFINITY,
            initial_gradient,
            gradient,
            observer,
            cancel: None,
            relative_gradient: None,
        }
    }

    /// From now on, [`Monitor::after`] says [`Stop::Cancelled`] at the
    /// first iterate after `flag` is set (one relaxed load per iteration).
    pub fn cancel_on(&mut self, flag: Option<&'a AtomicBool>) {
        self.cancel = flag;
    }

    /// The room for a gradient when nothing will need it before the step
    /// ends (no tolerance, no observer), as scratch for iterations that do
    /// not consult the monitor (so not when the step may be cancelled).
    pub fn unused_room(&mut self) -> Option<&mut [[f64; 3]]> {
        match (self.tests_iterates(), &self.observer, self.cancel) {
            (false, None, None) => Some(&mut *self.gradient),
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

    /// Sets the floor to the energy `floor` (`E − E(pᵗ)`) directly, once:
    /// a method that ran `j` plain iterations itself knows a closer bound
    /// on plain-`N`'s energy than `N` times the first one's decrease.
    pub fn set_floor(&mut self, floor: f64) {
        if self.rules.at_least_plain.is_some() && self.floor.is_none() {
            self.floor = Some(floor);
        }
    }

    /// The iterations start again from an iterate of energy `energy` (`E −
    /// E(pᵗ)`), by another method: the next decrease is measured from
    /// there, and so is the gain the energy rule weighs it against. (After
    /// plain iterations that took off the stiff modes' energy, a rule
    /// weighing L-BFGS's decreases against the whole step's would stop it
    /// at its first iterate past the floor, whatever it was still taking
    /// off.)
    pub fn restart_at(&mut self, energy: f64) {
        self.last_energy = energy;
        self.rule_origin = energy;
    }

    /// From now on the energy rule also waits for an iteration that takes
    /// off at most `decrease`: the last plain iteration's, when L-BFGS takes
    /// over from plain. While L-BFGS still takes off more per iteration
    /// than plain did, it has not converged further than plain's pace, and
    /// where plain speeds up later (a buckling cloth) plain-50 would pass
    /// it.
    pub fn keep_pace_with(&mut self, decrease: f64) {
        self.pace = decrease;
    }

    /// From now on, stop the step, past the floor or not, at an iteration
    /// that takes off at most `fraction` of all the step has taken off, or
    /// once the next descent direction `d` promises at most `rounding`,
    /// `−∇Eᵀd ≤ rounding` ([`Monitor::direction_converged`]): with
    /// `fraction` far below any rule's and `rounding` below the energy's
    /// own rounding, the iterate has converged
    /// (`methods/plain_then_lbfgs.rs` says when it is safe). Only beside
    /// the energy rule, which records each iterate's energy.
    pub fn stop_when_converged(&mut self, fraction: f64, rounding: f64) {
        self.converged = Some((fraction, rounding));
    }

    /// Has the descent converged to rounding ([`Monitor::stop_when_converged`])
    /// when its next direction has the slope `∇Eᵀd`? The slope, unlike a
    /// decrease measured between two energies, is not itself rounded to
    /// `η`: a decrease at rounding may be noise over a step that still has
    /// a few `η` to go, a slope below it says none is left.
    pub fn direction_converged(&self, slope: f64) -> bool {
        self.converged
            .is_some_and(|(_, rounding)| -slope <= rounding)
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
        if self.show(iteration, context, p) {
            return Some(Stop::Cancelled);
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
            (self.first_energy, self.last_energy, self.rule_origin) = (energy, energy, energy);
        }
        if self.converged_at(iteration, energy) {
            return Some(Stop::EnergyTolerance);
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
        let relative = relative_gradient(norm, self.initial_gradient?);
        self.relative_gradient = Some(relative);
        (relative <= tolerance).then_some(Stop::Tolerance)
    }

    /// Shows iterate `iteration` at `p` to the observer, if any; true when
    /// the step was cancelled ([`Monitor::cancel_on`]).
    fn show<B: LinearAlgebra>(
        &mut self,
        iteration: usize,
        context: &StepContext<'_, B>,
        p: &[[f64; 3]],
    ) -> bool {
        if let Some(observer) = self.observer.as_mut() {
            observer(&Iterate {
                iteration,
                positions: p,
                energy: &context.energy,
                pinned: context.pinned,
            });
        }
        self.cancel.is_some_and(|flag| flag.load(Ordering::Relaxed))
    }

    /// Has the step converged ([`Monitor::stop_when_converged`]) at
    /// iterate `iteration` of energy `energy`? The last energy is the one
    /// the energy rule recorded.
    fn converged_at(&self, iteration: usize, energy: Option<f64>) -> bool {
        let (Some((fraction, _)), Some(energy)) = (self.converged, energy) else {
            return false;
        };
        let decrease = self.last_energy - energy;
        let small = fraction * (self.first_energy - energy);
        iteration > 0 && (0.0..=small).contains(&decrease)
    }

    /// Records the energy of iterate `iteration` and says whether the
    /// energy rule with tolerance `fraction` stops there.
    fn energy_rule_met(&mut self, fraction: f64, iteration: usize, energy: f64) -> bool {
        let last = std::mem::replace(&mut self.last_energy, energy);
        if iteration == 0 {
            return false;
        }
        let decrease = last - energy;
        let small = (fraction * (self.rule_origin - energy)).min(self.pace);
        (0.0..=small).contains(&decrease)
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
    /// last [`Monitor::after`] already did); `None` when the step did not
    /// measure the gradient where it started.
    pub fn final_relative_gradient(
        &mut self,
        energy: &StepEnergy<'_>,
        pinned: &[bool],
        p: &[[f64; 3]],
    ) -> Option<f64> {
        if let Some(known) = self.relative_gradient {
            return Some(known);
        }
        let initial = self.initial_gradient?;
        energy.gradient(p, self.gradient);
        Some(relative_gradient(free_norm(self.gradient, pinned), initial))
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

#[cfg(test)]
mod tests {
    use super::{relative_gradient, Monitor};
    use crate::sim::control::StepControl;

    /// A monitor of `control`'s rules with room for a gradient of one row.
    fn monitor_of(control: StepControl, room: &mut [[f64; 3]]) -> Monitor<'_, 'static> {
        Monitor::new(&control, Some(1.0), room, None)
    }

    #[test]
    fn the_energy_rule_stops_once_the_last_decrease_is_a_small_share_of_all_so_far() {
        let control = StepControl {
            energy_tolerance: Some(0.15),
            ..StepControl::default()
        };
        let mut room = [[0.0; 3]];
        let mut monitor = monitor_of(control, &mut room);
        // energies E − E(p⁰) of iterates 0, 1, 2, 3: decreases 10, 5, 2
        assert!(!monitor.energy_rule_met(0.15, 0, 0.0)); // nothing to compare yet
        assert!(!monitor.energy_rule_met(0.15, 1, -10.0)); // 10 > 0.15 × 10
        assert!(!monitor.energy_rule_met(0.15, 2, -15.0)); // 5 > 0.15 × 15
        assert!(monitor.energy_rule_met(0.15, 3, -17.0)); // 2 ≤ 0.15 × 17 = 2.55
    }

    #[test]
    fn the_energy_rule_is_met_at_the_first_small_enough_decrease_and_never_on_a_rise() {
        let control = StepControl::default();
        let mut room = [[0.0; 3]];
        let mut monitor = monitor_of(control, &mut room);
        monitor.energy_rule_met(0.15, 0, 0.0);
        assert!(!monitor.energy_rule_met(0.15, 1, -10.0));
        assert!(monitor.energy_rule_met(0.15, 2, -11.0)); // 1 ≤ 0.15 × 11
        assert!(!monitor.energy_rule_met(0.15, 3, -10.5)); // a rise is no progress
    }

    #[test]
    fn the_floor_holds_the_rules_back_until_n_first_plain_decreases_are_taken_off() {
        let control = StepControl {
            at_least_plain: Some(3.0),
            ..StepControl::default()
        };
        let mut room = [[0.0; 3]];
        let mut monitor = monitor_of(control, &mut room);
        assert!(monitor.wants_plain_first());
        assert!(!monitor.past_floor(1, Some(-100.0)), "no floor known yet");
        monitor.plain_first(-2.0); // the first plain iteration takes off 2
        assert!(!monitor.wants_plain_first());
        monitor.plain_first(-50.0); // later calls change nothing
        assert!(!monitor.past_floor(1, Some(-5.9)));
        assert!(monitor.past_floor(1, Some(-6.0))); // 3 × 2
        assert!(
            !monitor.past_floor(0, Some(-6.0)),
            "never the first iterate"
        );
        assert!(!monitor.past_floor(2, None), "an energy not measured");
    }

    #[test]
    fn after_a_restart_the_energy_rule_weighs_decreases_against_the_gain_since_it() {
        let control = StepControl {
            energy_tolerance: Some(0.15),
            ..StepControl::default()
        };
        let mut room = [[0.0; 3]];
        let mut monitor = monitor_of(control, &mut room);
        monitor.energy_rule_met(0.15, 0, 0.0);
        monitor.energy_rule_met(0.15, 1, -1000.0); // plain's first iteration
        monitor.restart_at(-1000.0);
        assert!(
            !monitor.energy_rule_met(0.15, 2, -1001.0),
            "1 of the 1 gained since the restart, not of the step's 1001"
        );
        assert!(monitor.energy_rule_met(0.15, 3, -1001.1));
        monitor.keep_pace_with(0.05);
        assert!(
            !monitor.energy_rule_met(0.15, 4, -1001.2),
            "0.1 is more than plain's last decrease"
        );
        assert!(monitor.energy_rule_met(0.15, 5, -1001.24));
    }

    #[test]
    fn a_floor_set_directly_counts_once_and_convergence_stops_below_it() {
        let control = StepControl {
            at_least_plain: Some(50.0),
            energy_tolerance: Some(0.15),
            ..StepControl::default()
        };
        let mut room = [[0.0; 3]];
        let mut monitor = monitor_of(control, &mut room);
        monitor.set_floor(-100.0);
        monitor.set_floor(-1.0); // later ones change nothing
        monitor.plain_first(-50.0); // nor the first plain iterate's
        assert!(!monitor.past_floor(1, Some(-99.0)));
        assert!(monitor.past_floor(1, Some(-100.0)));
        monitor.stop_when_converged(1e-11, 1e-13);
        monitor.energy_rule_met(0.15, 0, 0.0);
        monitor.energy_rule_met(0.15, 1, -10.0);
        assert!(
            !monitor.converged_at(2, Some(-10.0 - 1e-9)),
            "1e-10 of the decrease"
        );
        assert!(monitor.converged_at(2, Some(-10.0 - 1e-11)));
        assert!(
            !monitor.converged_at(2, Some(-9.0)),
            "a rise is not convergence"
        );
        assert!(
            !monitor.converged_at(0, Some(-10.0)),
            "never the first iterate"
        );
        monitor.stop_when_converged(1e-11, 1e-9);
        assert!(
            !monitor.converged_at(2, Some(-10.0 - 1e-10)),
            "a decrease below the rounding may be rounding's"
        );
        assert!(monitor.direction_converged(-1e-9));
        assert!(!monitor.direction_converged(-2e-9));
    }

    #[test]
    fn without_a_floor_every_iterate_may_stop_the_step() {
        let mut room = [[0.0; 3]];
        let monitor = monitor_of(StepControl::default(), &mut room);
        assert!(!monitor.wants_plain_first());
        assert!(monitor.past_floor(1, None));
    }

    #[test]
    fn the_relative_gradient_falls_back_to_the_norm_at_a_minimiser() {
        assert_eq!(relative_gradient(1.0, 4.0), 0.25);
        assert_eq!(relative_gradient(1e-20, 0.0), 1e-20);
    }

    #[test]
    fn every_stop_has_a_name_of_its_own_in_the_command_lines_words() {
        use crate::sim::control::Stop;
        let names: Vec<&str> = Stop::ALL.iter().map(|s| s.name()).collect();
        assert_eq!(
            names,
            [
                "iterations",
                "tolerance",
                "energy-tolerance",
                "at-least-plain",
                "stalled",
                "cancelled"
            ]
        );
        assert_eq!(Stop::EnergyTolerance.to_string(), "energy-tolerance");
    }
}
