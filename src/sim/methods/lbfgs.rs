//! L-BFGS with the prefactored `Q` as the initial Hessian.
//!
//! A quasi-Newton method on the step's energy `E`: the search direction is
//! `d = −H ∇E(p)`, where `H` approximates the inverse Hessian from the last
//! `m` pairs `sⱼ = pⱼ₊₁ − pⱼ`, `yⱼ = ∇E(pⱼ₊₁) − ∇E(pⱼ)`, starting from
//! `H₀ = Q⁻¹` (Liu et al. 2017: `Q` is the Hessian of `E` with every spring
//! at its rest length, and it is already factored). The two-loop recursion
//! applies `H` without forming it:
//!
//! ```text
//! q = ∇E(p)
//! for j = newest … oldest:  αⱼ = sⱼᵀq / yⱼᵀsⱼ,  q ← q − αⱼ yⱼ
//! z = Q⁻¹ q                                            one solve with L
//! for j = oldest … newest:  βⱼ = yⱼᵀz / yⱼᵀsⱼ,  z ← z + sⱼ (αⱼ − βⱼ)
//! d = −z
//! ```
//!
//! With no pairs, `p + d` is exactly the plain local/global iterate.
//!
//! **The scale of `H₀`.** `Q` is stiffer than `E` along the slow modes
//! (a spring at rest length resists bending through `Q` but not through
//! `E`), so the quasi-Newton step with `H₀ = Q⁻¹` comes out too short by a
//! steady factor. Once there is a pair, `H₀ = γ Q⁻¹` with
//!
//! ```text
//! γ = sᵀQs / sᵀy          (newest pair; Nocedal & Wright's eq. 7.20 in Q's metric)
//! ```
//!
//! the ratio of `Q`'s curvature along the last step to `E`'s, so the step
//! has the right length and every line search starts at `t = 1`. Without
//! it the searches had to start where the last one ended, a start that
//! sticks: on the single spring with `k` ten times the bundled one's,
//! L-BFGS kept half its error an iteration and needed 25 iterations to
//! converge (step 10); with `γ`, 8. Over 100 steps of `--accuracy
//! assignment` (`masssprings converge SCENE --steps 100 --accuracy
//! assignment`) the flag took 469 iterations without `γ` and takes 390, the
//! skirt 516 and 430.
//!
//! Two safeguards make it work on cloth (measured in the project's
//! prototype: without them every pair was rejected and L-BFGS *was* the
//! plain iteration):
//! * **Powell damping.** Along the iteration's direction the energy can
//!   curve downward (`sᵀy < 0`: springs under compression), and a pair with
//!   `sᵀy ≤ 0` would make `H` indefinite. With `B₀ = Q`, when
//!   `sᵀy < 0.2 sᵀQs` the pair's `y` is replaced by `θ y + (1 − θ) Q s`,
//!   `θ = 0.8 sᵀQs / (sᵀQs − sᵀy)`, so that `sᵀy = 0.2 sᵀQs > 0`.
//! * **A line search that also expands** ([`line_search`](super::line_search)):
//!   from `t = 1`, it looks further while the energy keeps falling, or
//!   halves `t` until the Armijo condition holds.
//!
//! Each trial point of the line search gets its energy and its gradient
//! from one pass over the springs ([`change_and_gradient`]), so the
//! accepted point's gradient, which the next pair needs, costs nothing more.
//!
//! Cost per iteration: one solve with `Q`, one energy-and-gradient
//! evaluation per trial point (the first, and the fitted parabola's
//! minimum when it lies well beyond),
//! `O(m + n)` each, one product `Q s`, and `O(m n)` for the recursion.
//!
//! [`change_and_gradient`]: crate::sim::energy::StepEnergy::change_and_gradient
//!
//! Sources: T. Liu, S. Bouaziz, L. Kavan, "Quasi-Newton Methods for
//! Real-time Simulation of Hyperelastic Materials", ACM TOG 36(3), 2017,
//! §4 (L-BFGS with `Q` as the initial Hessian); J. Nocedal & S. J. Wright,
//! *Numerical Optimization*, 2nd ed., 2006, Algorithm 7.4 (two-loop
//! recursion), §18.3, Procedure 18.2 (Powell's damped update), §3.1 (Armijo).

use super::block_vector::{add_scaled, dot, moved, scale, subtract};
use super::line_search::{line_search, Search};
use crate::sim::backend::LinearAlgebra;
use crate::sim::control::{Outcome, StepControl, Stop, MAX_WINDOW};
use crate::sim::global_step::StepContext;
use crate::sim::monitor::{Gradient, Monitor};

/// L-BFGS's history and work arrays.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// The ring of pairs `(sⱼ, yⱼ)` and their `1 / yⱼᵀsⱼ`.
    s: Vec<Vec<[f64; 3]>>,
    y: Vec<Vec<[f64; 3]>>,
    inverse_sy: Vec<f64>,
    alpha: Vec<f64>,
    /// Ring position of the oldest pair, and how many are held.
    oldest: usize,
    held: usize,
    /// `∇E(p)`, the direction, `Q s`.
    gradient: Vec<[f64; 3]>,
    direction: Vec<[f64; 3]>,
    q_s: Vec<[f64; 3]>,
    /// The line search's last two trial points `p + t d`, their gradients
    /// and their `t`.
    trials: [Vec<[f64; 3]>; 2],
    trial_gradients: [Vec<[f64; 3]>; 2],
    trial_lengths: [f64; 2],
    /// The energy at the last search's first trial point.
    first_trial_energy: f64,
    /// `γ` of `H₀ = γ Q⁻¹`, from the newest pair.
    h0_scale: f64,
}

impl Workspace {
    pub fn new(n: usize, window: usize) -> Self {
        let window = window.clamp(1, MAX_WINDOW);
        Workspace {
            s: vec![vec![[0.0; 3]; n]; window],
            y: vec![vec![[0.0; 3]; n]; window],
            inverse_sy: vec![0.0; window],
            alpha: vec![0.0; window],
            oldest: 0,
            held: 0,
            gradient: vec![[0.0; 3]; n],
            direction: vec![[0.0; 3]; n],
            q_s: vec![[0.0; 3]; n],
            trials: [vec![[0.0; 3]; n], vec![[0.0; 3]; n]],
            trial_gradients: [vec![[0.0; 3]; n], vec![[0.0; 3]; n]],
            trial_lengths: [f64::NAN; 2],
            first_trial_energy: f64::NAN,
            h0_scale: 1.0,
        }
    }

    pub(crate) fn window(&self) -> usize {
        self.s.len()
    }

    /// Which trial buffer holds the point at step length `t`.
    fn trial_holding(&self, t: f64) -> usize {
        if self.trial_lengths[0] == t {
            0
        } else {
            1
        }
    }

    /// Ring slot of the `age`-th oldest pair.
    fn slot(&self, age: usize) -> usize {
        (self.oldest + age) % self.window()
    }
}

impl Workspace {
    /// `direction = −H ∇E(p)` by the two-loop recursion, `H₀ = γ Q⁻¹`
    /// applied by `solve_with_q` and the scale `γ` (1 with no pairs).
    fn two_loop(&mut self, solve_with_q: impl FnOnce(&mut [[f64; 3]])) {
        self.direction.copy_from_slice(&self.gradient);
        for age in (0..self.held).rev() {
            let j = self.slot(age);
            let alpha = dot(&self.s[j], &self.direction) * self.inverse_sy[j];
            self.alpha[j] = alpha;
            add_scaled(&mut self.direction, -alpha, &self.y[j]);
        }
        solve_with_q(&mut self.direction);
        if self.held > 0 {
            scale(&mut self.direction, self.h0_scale);
        }
        for age in 0..self.held {
            let j = self.slot(age);
            let beta = dot(&self.y[j], &self.direction) * self.inverse_sy[j];
            add_scaled(&mut self.direction, self.alpha[j] - beta, &self.s[j]);
        }
        scale(&mut self.direction, -1.0);
    }

    /// The ring slot the next pair is written to (the oldest, when full).
    fn next_slot(&self) -> usize {
        if self.held < self.window() {
            self.slot(self.held)
        } else {
            self.oldest
        }
    }

    /// Keeps the pair written to [`Workspace::next_slot`].
    fn commit(&mut self, sy: f64) {
        let slot = self.next_slot();
        self.inverse_sy[slot] = 1.0 / sy;
        if self.held < self.window() {
            self.held += 1;
        } else {
            self.oldest = (self.oldest + 1) % self.window();
        }
    }

    /// Powell's damping of the pair in `slot`, given `Q s` in `q_s`;
    /// returns the (damped) `sᵀy` and `sᵀQs`.
    fn damp(&mut self, slot: usize) -> (f64, f64) {
        let s_q_s = dot(&self.s[slot], &self.q_s);
        let s_y = dot(&self.s[slot], &self.y[slot]);
        if s_y >= 0.2 * s_q_s {
            return (s_y, s_q_s);
        }
        let theta = 0.8 * s_q_s / (s_q_s - s_y);
        for (y, q_s) in self.y[slot].iter_mut().zip(&self.q_s) {
            *y = std::array::from_fn(|c| theta * y[c] + (1.0 - theta) * q_s[c]);
        }
        (dot(&self.s[slot], &self.y[slot]), s_q_s)
    }
}

/// Iterates from `p` (in place) until the control says stop.
pub(crate) fn solve<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    work: &mut Workspace,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    work.held = 0;
    work.oldest = 0;
    work.h0_scale = 1.0;
    let rounding = context.rounding();
    if context.start_measured {
        work.gradient.copy_from_slice(monitor.start_gradient());
    } else {
        context.energy.gradient(p, &mut work.gradient);
    }
    let mut energy = context.start_energy; // E(p) − E(p⁰)
    for iteration in 1..=control.iterations {
        let Some(slope) = descent_direction(context, work) else {
            return Outcome::measured(iteration - 1, Stop::Stalled, energy);
        };
        if monitor.direction_converged(slope) {
            return Outcome::measured(iteration - 1, Stop::EnergyTolerance, energy);
        }
        let Some((t, new_energy)) =
            search_along_direction(context, work, p, slope, energy, rounding)
        else {
            return Outcome::measured(iteration - 1, Stop::Stalled, energy);
        };
        if iteration == 1 {
            // no pairs yet and `t = 1` first: that trial was `p⁰ − Q⁻¹ ∇E(p⁰)
            // = G(p⁰)`, the plain iterate
            monitor.plain_first(work.first_trial_energy);
        }
        energy = new_energy;
        let slot = work.next_slot();
        let trial = work.trial_holding(t);
        subtract(&work.trials[trial], p, &mut work.s[slot]);
        p.copy_from_slice(&work.trials[trial]);
        subtract(
            &work.trial_gradients[trial],
            &work.gradient,
            &mut work.y[slot],
        );
        std::mem::swap(&mut work.gradient, &mut work.trial_gradients[trial]);
        context.global.mul_q(&work.s[slot], &mut work.q_s);
        let (s_y, s_q_s) = work.damp(slot);
        if s_y > 0.0 {
            work.h0_scale = s_q_s / s_y;
            work.commit(s_y);
        }
        let gradient = Gradient::Given(&work.gradient);
        if let Some(stop) = monitor.after(iteration, context, p, gradient, Some(energy)) {
            return Outcome::measured(iteration, stop, energy);
        }
    }
    Outcome::measured(control.iterations, Stop::Iterations, energy)
}

/// The line search along `work.direction` from `p`. Each trial point is
/// built in one of two buffers, taken in turn, with its energy and
/// gradient from one evaluation: the accepted point is always the last or
/// the one before it, so its gradient is at hand when the search ends.
fn search_along_direction<B: LinearAlgebra>(
    context: &StepContext<'_, B>,
    work: &mut Workspace,
    p: &[[f64; 3]],
    slope: f64,
    energy: f64,
    rounding: f64,
) -> Option<(f64, f64)> {
    let Workspace {
        direction,
        trials,
        trial_gradients,
        trial_lengths,
        first_trial_energy,
        ..
    } = work;
    *trial_lengths = [f64::NAN; 2];
    let mut next = 0;
    line_search(Search::Expanding, 1.0, slope, energy, rounding, |t| {
        moved(p, t, direction, &mut trials[next]);
        let change = context
            .energy
            .change_and_gradient(&trials[next], &mut trial_gradients[next])
            .total();
        if trial_lengths.iter().all(|t| t.is_nan()) {
            *first_trial_energy = change; // the search's first trial
        }
        trial_lengths[next] = t;
        next = 1 - next;
        change
    })
}

/// Sets `work.direction` to the L-BFGS direction, or to the plain one
/// `−Q⁻¹ ∇E` (clearing the history) if that is not a descent direction;
/// returns the slope `∇Eᵀd < 0`, or `None` when not even the plain
/// direction descends (the gradient is zero to rounding).
fn descent_direction<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    work: &mut Workspace,
) -> Option<f64> {
    work.two_loop(|v| context.global.solve(v));
    let slope = dot(&work.gradient, &work.direction);
    if slope < 0.0 {
        return Some(slope);
    }
    work.held = 0;
    work.two_loop(|v| context.global.solve(v));
    let slope = dot(&work.gradient, &work.direction);
    (slope < 0.0).then_some(slope)
}
