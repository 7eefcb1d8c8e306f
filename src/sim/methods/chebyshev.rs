//! Chebyshev semi-iteration on the local/global iterate.
//!
//! The plain iteration `x̂ = G(x)` contracts the error by about `ρ` per
//! iteration, `ρ` the spectral radius of its Jacobian at the minimiser.
//! Chebyshev's idea: combine the iterates so that the error is multiplied by
//! the Chebyshev polynomial of degree `k` scaled to `[−ρ, ρ]` instead of by
//! `ρᵏ`, which shrinks like `(ρ/(1 + √(1 − ρ²)))ᵏ`: from ρ = 0.99 that is
//! 0.87 per iteration instead of 0.99. The three-term recurrence of the
//! polynomials gives the update
//!
//! ```text
//! x̂ₖ₊₁ = G(xₖ)                                 one local/global iteration
//! xₖ₊₁ = ωₖ₊₁ (γ (x̂ₖ₊₁ − xₖ) + xₖ − xₖ₋₁) + xₖ₋₁
//! ω₁ = 1,   ω₂ = 2 / (2 − ρ²),   ωₖ₊₁ = 4 / (4 − ρ² ωₖ)
//! ```
//!
//! With `γ = 1` this is the plain semi-iteration `ω (x̂ₖ₊₁ − xₖ₋₁) + xₖ₋₁`.
//! Wang relaxes each plain step by `γ`: below 1 for projective dynamics'
//! Jacobi-style solves, which overshoot. Here the global step is an exact
//! solve with `Q`, and `Q` is *stiffer* than the energy's true Hessian
//! (compressed springs add no stiffness across, and the Hessian of a
//! compressed spring is even indefinite), so each plain step is too short:
//! L-BFGS's line search on the same steps settles on 2–4 times its
//! direction. Over-relaxing by `γ = 1.5` (`--relaxation`, default) took
//! the iterations to plain-50's energy from 10, 8, 14, 11 to 8, 7, 10, 9 on
//! the flag and skirt at steps 1 and 11, and from 26 to 16 on grid-32's
//! first step; `γ = 0.8` and `0.9` were worse everywhere, `γ = 2` no
//! better than 1.5–1.7 (`masssprings converge SCENE --step K --methods
//! plain,chebyshev --relaxation G`).
//!
//! `ρ` is the user's (`--rho`), or estimated once: the first 20
//! iterations are plain ones (over as many steps as a stopping rule makes
//! them take, no ratio taken across two steps), and `ρ` is the largest
//! ratio of successive plain steps `‖xₖ₊₁ − xₖ‖ / ‖xₖ − xₖ₋₁‖` among them
//! (the ratio creeps up toward the asymptotic rate as the fast modes die
//! out, so the largest is the best guess), capped at 0.995 since an
//! overestimate diverges, and kept for later steps. On the bundled cloths
//! it is 0.97–0.999 and the cap decides.
//!
//! `G` is nonlinear, so the extrapolation can overshoot: when the energy
//! rises, the iterate is replaced by the plain `x̂ₖ₊₁` (whose energy never
//! rises) and the recurrence restarts from `ω₁`. The energy of a candidate
//! is measured by the local step made at it
//! ([`local_step_measuring`](crate::sim::global_step::StepContext::local_step_measuring)),
//! which the next global step needs anyway, so the test costs a pass over
//! the vertices, and a restart one more local step.
//!
//! Cost per iteration: one plain iteration, one pass over the vertices for
//! the energy, and vector updates `O(n)`. With a tolerance, the same local
//! step also makes the gradient the rule tests (its spring forces added on
//! the way, one more pass over the vertices).
//!
//! Source: H. Wang, "A Chebyshev Semi-Iterative Approach for Accelerating
//! Projective and Position-based Dynamics", ACM TOG 34(6), 2015, §4–5 (the
//! update, Eq. 12, with its relaxation `γ`); Golub & Van Loan, *Matrix
//! Computations*, 4th ed., §11.2.8 (the semi-iterative method).

use super::block_vector::{norm, subtract};
use crate::sim::backend::LinearAlgebra;
use crate::sim::control::{Outcome, StepControl, Stop};
use crate::sim::global_step::StepContext;
use crate::sim::monitor::{Gradient, Monitor};

/// The largest spectral radius an estimate may give.
pub const RHO_CAP: f64 = 0.995;

/// Plain iterations that measure `ρ` when it is neither given nor known.
pub const ESTIMATION_ITERATIONS: usize = 20;

/// Chebyshev's work arrays, and its estimate of `ρ` from earlier steps.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// `xₖ`, the current iterate.
    current: Vec<[f64; 3]>,
    /// `xₖ₋₁`, then the candidate `xₖ₊₁`.
    previous: Vec<[f64; 3]>,
    /// `x̂ₖ₊₁ = G(xₖ)`.
    plain: Vec<[f64; 3]>,
    /// Room to move vectors around.
    spare: Vec<[f64; 3]>,
    /// `ρ` measured in an earlier step.
    pub estimated_rho: Option<f64>,
    /// The measurement of `ρ` while it lasts.
    estimate: RhoEstimate,
}

impl Workspace {
    pub fn new(n: usize) -> Self {
        Workspace {
            current: vec![[0.0; 3]; n],
            previous: vec![[0.0; 3]; n],
            plain: vec![[0.0; 3]; n],
            spare: vec![[0.0; 3]; n],
            estimated_rho: None,
            estimate: RhoEstimate::default(),
        }
    }
}

/// `ρ` from the norms `‖xₖ₊₁ − xₖ‖` of the first plain steps: the
/// largest ratio of successive ones, capped at [`RHO_CAP`] (what the first
/// step measures; `masssprings converge` applies it to its plain run).
pub fn estimate_rho(step_norms: &[f64]) -> f64 {
    step_norms
        .windows(2)
        .take(ESTIMATION_ITERATIONS - 1)
        .filter(|w| w[0] > 0.0)
        .map(|w| w[1] / w[0])
        .fold(0.0, f64::max)
        .min(RHO_CAP)
}

/// The weight `ω` of iteration `k` (1-based) of the recurrence.
pub fn omega(k: usize, rho: f64, previous_omega: f64) -> f64 {
    match k {
        1 => 1.0,
        2 => 2.0 / (2.0 - rho * rho),
        _ => 4.0 / (4.0 - rho * rho * previous_omega),
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
    let mut rho = control.rho.or(work.estimated_rho);
    work.estimate.new_step();
    let mut recurrence = Recurrence { k: 0, omega: 1.0 };
    // xₖ in `current`, xₖ₋₁ in `previous`; the buffers trade places
    // instead of being copied.
    work.current.copy_from_slice(p);
    work.previous.copy_from_slice(p);
    // The local step at each iterate is made when it is reached (it
    // measures the energy that decides), and used by the next global step.
    let mut energy = context.local_step_at_start(p, monitor.room_for_gradient());
    let mut outcome = Outcome::new(control.iterations, Stop::Iterations);
    for iteration in 1..=control.iterations {
        context.global_step(&mut work.plain);
        match rho {
            None => {
                // Still measuring ρ: a plain iteration.
                rho = work
                    .estimate
                    .record(&work.current, &work.plain, &mut work.spare);
                work.estimated_rho = work.estimated_rho.or(rho);
                work.take_plain();
                energy = context.local_step_measuring(&work.current, monitor.room_for_gradient());
                if iteration == 1 {
                    monitor.plain_first(energy); // this iterate is G(p⁰)
                }
            }
            Some(radius) => {
                let step = Extrapolation {
                    radius,
                    relaxation: control.relaxation,
                };
                energy = step.iterate(context, work, monitor, &mut recurrence, energy);
            }
        }
        // the last local step was made at `work.current`
        let current = &work.current;
        if let Some(stop) =
            monitor.after(iteration, context, current, Gradient::InRoom, Some(energy))
        {
            outcome.iterations = iteration;
            outcome.stop = stop;
            break;
        }
    }
    p.copy_from_slice(&work.current);
    Outcome::measured(outcome.iterations, outcome.stop, energy)
}

/// Chebyshev's recurrence: extrapolations since it (re)started, and the
/// last weight `ωₖ`.
struct Recurrence {
    k: usize,
    omega: f64,
}

/// One extrapolated iteration, with the spectral radius `radius` and the
/// relaxation `γ`.
struct Extrapolation {
    radius: f64,
    relaxation: f64,
}

impl Extrapolation {
    /// After the plain iterate `G(xₖ)` in `work.plain`: extrapolates, and
    /// keeps the candidate if its energy is no higher than `energy` (the
    /// current iterate's); otherwise takes the plain iterate and restarts
    /// the recurrence. Returns the energy at the new `xₖ`, whose local step
    /// is made.
    fn iterate<B: LinearAlgebra>(
        &self,
        context: &mut StepContext<'_, B>,
        work: &mut Workspace,
        monitor: &mut Monitor<'_, '_>,
        recurrence: &mut Recurrence,
        energy: f64,
    ) -> f64 {
        if monitor.wants_plain_first() {
            // the first iteration: x̂₁ = G(p⁰), which the extrapolation
            // moves away from
            monitor.plain_first(context.energy.change(&work.plain).total());
        }
        recurrence.k += 1;
        recurrence.omega = omega(recurrence.k, self.radius, recurrence.omega);
        extrapolate(context, work, recurrence.omega, self.relaxation);
        let candidate = context.local_step_measuring(&work.previous, monitor.room_for_gradient());
        if candidate <= energy {
            std::mem::swap(&mut work.current, &mut work.previous);
            return candidate;
        }
        // overshoot: the plain iterate, and the recurrence restarts
        work.take_plain();
        recurrence.k = 0;
        context.local_step_measuring(&work.current, monitor.room_for_gradient())
    }
}

impl Workspace {
    /// `xₖ₋₁ ← xₖ`, `xₖ ← x̂ₖ₊₁` (by trading buffers).
    fn take_plain(&mut self) {
        std::mem::swap(&mut self.previous, &mut self.current);
        std::mem::swap(&mut self.current, &mut self.plain);
    }
}

/// The candidate `xₖ₊₁ = ω (γ (x̂ₖ₊₁ − xₖ) + xₖ − xₖ₋₁) + xₖ₋₁` into
/// `work.previous` (which holds `xₖ₋₁`), with `x̂ₖ₊₁ = G(xₖ)` in
/// `work.plain`.
fn extrapolate<B: LinearAlgebra>(
    context: &StepContext<'_, B>,
    work: &mut Workspace,
    omega: f64,
    gamma: f64,
) {
    // as flat arrays, so that the compiler takes the numbers two or four
    // to an instruction
    let previous = work.previous.as_flattened_mut().iter_mut();
    let (plain, current) = (work.plain.as_flattened(), work.current.as_flattened());
    for ((x, x_hat), x_k) in previous.zip(plain).zip(current) {
        *x = omega * (gamma * (x_hat - x_k) + x_k - *x) + *x;
    }
    context.global.hold_pins(&mut work.previous);
}

/// What Chebyshev carries from step to step: `ρ` once estimated, and the
/// measurement while it lasts (a resumed run needs both to give the same
/// bits as a run that never stopped).
#[derive(Debug, Default, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Carried {
    /// `ρ` as estimated (`None` while it is measured).
    pub rho: Option<f64>,
    /// Plain iterations recorded toward the estimate.
    pub recorded: usize,
    /// The largest ratio of successive plain steps among them.
    pub largest_ratio: f64,
}

impl Workspace {
    /// What this workspace carries to the next step.
    pub fn carried(&self) -> Carried {
        Carried {
            rho: self.estimated_rho,
            recorded: self.estimate.recorded,
            largest_ratio: self.estimate.largest_ratio,
        }
    }

    /// Takes up what an earlier run carried ([`Workspace::carried`]).
    pub fn carry(&mut self, carried: Carried) {
        self.estimated_rho = carried.rho;
        self.estimate.recorded = carried.recorded;
        self.estimate.largest_ratio = carried.largest_ratio;
    }
}

/// The measurement of `ρ` from the first plain iterations.
#[derive(Debug, Default, Clone)]
struct RhoEstimate {
    recorded: usize,
    last_step_norm: f64,
    largest_ratio: f64,
}

impl RhoEstimate {
    /// A step begins: its first plain step is not compared with the last
    /// one of the step before.
    fn new_step(&mut self) {
        self.last_step_norm = 0.0;
    }

    /// Records the plain step `x̂ − x`; returns `ρ` once
    /// [`ESTIMATION_ITERATIONS`] have been recorded.
    fn record(
        &mut self,
        x: &[[f64; 3]],
        x_hat: &[[f64; 3]],
        scratch: &mut [[f64; 3]],
    ) -> Option<f64> {
        subtract(x_hat, x, scratch);
        let step_norm = norm(scratch);
        if self.last_step_norm > 0.0 {
            self.largest_ratio = self.largest_ratio.max(step_norm / self.last_step_norm);
        }
        self.last_step_norm = step_norm;
        self.recorded += 1;
        (self.recorded == ESTIMATION_ITERATIONS).then(|| self.largest_ratio.min(RHO_CAP))
    }
}

#[cfg(test)]
mod tests {
    use super::{RhoEstimate, ESTIMATION_ITERATIONS, RHO_CAP};

    /// Records plain steps of the given lengths (`x̂ − x` along one axis).
    fn record(estimate: &mut RhoEstimate, lengths: &[f64]) -> Vec<Option<f64>> {
        let (x, mut x_hat, mut scratch) = (vec![[0.0; 3]], vec![[0.0; 3]], vec![[0.0; 3]]);
        lengths
            .iter()
            .map(|&length| {
                x_hat[0][0] = length;
                estimate.record(&x, &x_hat, &mut scratch)
            })
            .collect()
    }

    #[test]
    fn rho_is_measured_over_twenty_plain_iterations_however_many_steps_they_take() {
        let mut estimate = RhoEstimate::default();
        // a first step of 12 iterations, contracting by 0.9
        let first: Vec<f64> = (0..12).map(|k| 0.9f64.powi(k)).collect();
        assert!(record(&mut estimate, &first).iter().all(Option::is_none));
        // the next step starts afresh (a larger step than the last one):
        // that ratio must not count
        estimate.new_step();
        let second: Vec<f64> = (0..8).map(|k| 5.0 * 0.8f64.powi(k)).collect();
        let results = record(&mut estimate, &second);
        assert!(results[..7].iter().all(Option::is_none));
        let rho = results[7].expect("measured at the 20th plain iteration");
        assert_eq!(ESTIMATION_ITERATIONS, 20);
        assert!((rho - 0.9).abs() < 1e-12 && rho <= RHO_CAP, "{rho}");
    }
}
