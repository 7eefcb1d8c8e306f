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
//! Two safeguards make it work on cloth (measured in the project's
//! prototype: without them every pair was rejected and L-BFGS *was* the
//! plain iteration):
//! * **Powell damping.** Along the iteration's direction the energy can
//!   curve downward (`sᵀy < 0`: springs under compression), and a pair with
//!   `sᵀy ≤ 0` would make `H` indefinite. With `B₀ = Q`, when
//!   `sᵀy < 0.2 sᵀQs` the pair's `y` is replaced by `θ y + (1 − θ) Q s`,
//!   `θ = 0.8 sᵀQs / (sᵀQs − sᵀy)`, so that `sᵀy = 0.2 sᵀQs > 0`.
//! * **A line search that also expands** ([`line_search`](super::line_search)):
//!   from `t = 1`, `t` doubles while the energy keeps falling, or halves
//!   until the Armijo condition holds.
//!
//! Cost per iteration: one solve with `Q`, one gradient and two or more
//! energy evaluations (`O(m + n)` each), one product `Q s`, and `O(m n)` for
//! the recursion.
//!
//! Sources: T. Liu, S. Bouaziz, L. Kavan, "Quasi-Newton Methods for
//! Real-time Simulation of Hyperelastic Materials", ACM TOG 36(3), 2017,
//! §4 (L-BFGS with `Q` as the initial Hessian); J. Nocedal & S. J. Wright,
//! *Numerical Optimization*, 2nd ed., 2006, Algorithm 7.4 (two-loop
//! recursion), §18.3, Procedure 18.2 (Powell's damped update), §3.1 (Armijo).

use super::block_vector::{add_scaled, dot, moved, scale, subtract};
use super::line_search::{line_search, Search};
use super::{Monitor, Outcome, StepContext, StepControl, Stop};
use crate::sim::backend::LinearAlgebra;

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
    /// `∇E(p)`, `∇E(p_new)`, the direction, a trial point, `Q s`.
    gradient: Vec<[f64; 3]>,
    new_gradient: Vec<[f64; 3]>,
    direction: Vec<[f64; 3]>,
    trial: Vec<[f64; 3]>,
    q_s: Vec<[f64; 3]>,
}

impl Workspace {
    pub fn new(n: usize, window: usize) -> Self {
        let window = window.max(1);
        Workspace {
            s: vec![vec![[0.0; 3]; n]; window],
            y: vec![vec![[0.0; 3]; n]; window],
            inverse_sy: vec![0.0; window],
            alpha: vec![0.0; window],
            oldest: 0,
            held: 0,
            gradient: vec![[0.0; 3]; n],
            new_gradient: vec![[0.0; 3]; n],
            direction: vec![[0.0; 3]; n],
            trial: vec![[0.0; 3]; n],
            q_s: vec![[0.0; 3]; n],
        }
    }

    pub(crate) fn window(&self) -> usize {
        self.s.len()
    }

    /// Ring slot of the `age`-th oldest pair.
    fn slot(&self, age: usize) -> usize {
        (self.oldest + age) % self.window()
    }
}

impl Workspace {
    /// `direction = −H ∇E(p)` by the two-loop recursion, `H₀ = Q⁻¹`
    /// applied by `solve_with_q`.
    fn two_loop(&mut self, solve_with_q: impl FnOnce(&mut [[f64; 3]])) {
        self.direction.copy_from_slice(&self.gradient);
        for age in (0..self.held).rev() {
            let j = self.slot(age);
            let alpha = dot(&self.s[j], &self.direction) * self.inverse_sy[j];
            self.alpha[j] = alpha;
            add_scaled(&mut self.direction, -alpha, &self.y[j]);
        }
        solve_with_q(&mut self.direction);
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
    /// returns the (damped) `sᵀy`.
    fn damp(&mut self, slot: usize) -> f64 {
        let s_q_s = dot(&self.s[slot], &self.q_s);
        let s_y = dot(&self.s[slot], &self.y[slot]);
        if s_y >= 0.2 * s_q_s {
            return s_y;
        }
        let theta = 0.8 * s_q_s / (s_q_s - s_y);
        for (y, q_s) in self.y[slot].iter_mut().zip(&self.q_s) {
            *y = std::array::from_fn(|c| theta * y[c] + (1.0 - theta) * q_s[c]);
        }
        dot(&self.s[slot], &self.y[slot])
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
    context.energy.gradient(p, &mut work.gradient);
    let mut energy = 0.0; // E(p) − E(p⁰)
    for iteration in 1..=control.iterations {
        let Some(slope) = descent_direction(context, work) else {
            return Outcome::new(iteration - 1, Stop::Stalled);
        };
        let Some((t, new_energy)) = line_search(
            &context.energy,
            Search::Expanding,
            p,
            &work.direction,
            slope,
            energy,
            &mut work.trial,
        ) else {
            return Outcome::new(iteration - 1, Stop::Stalled);
        };
        let slot = work.next_slot();
        moved(p, t, &work.direction, &mut work.trial);
        subtract(&work.trial, p, &mut work.s[slot]);
        p.copy_from_slice(&work.trial);
        energy = new_energy;
        context.energy.gradient(p, &mut work.new_gradient);
        subtract(&work.new_gradient, &work.gradient, &mut work.y[slot]);
        context.global.mul_q(&work.s[slot], &mut work.q_s);
        let s_y = work.damp(slot);
        if s_y > 0.0 {
            work.commit(s_y);
        }
        std::mem::swap(&mut work.gradient, &mut work.new_gradient);
        if monitor.after(iteration, context, p, Some(&work.gradient)) {
            return Outcome::new(iteration, Stop::Tolerance);
        }
    }
    Outcome::new(control.iterations, Stop::Iterations)
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
