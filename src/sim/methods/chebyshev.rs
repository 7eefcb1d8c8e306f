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
//! xₖ₊₁ = ωₖ₊₁ (x̂ₖ₊₁ − xₖ₋₁) + xₖ₋₁
//! ω₁ = 1,   ω₂ = 2 / (2 − ρ²),   ωₖ₊₁ = 4 / (4 − ρ² ωₖ)
//! ```
//!
//! `ρ` is the user's (`--rho`), or estimated once: the first step runs
//! 20 plain iterations and takes the largest ratio of successive plain
//! steps `‖xₖ₊₁ − xₖ‖ / ‖xₖ − xₖ₋₁‖` (the ratio creeps up toward the
//! asymptotic rate as the fast modes die out, so the largest is the best
//! guess), capped at 0.995 since an overestimate diverges, and keeps it for
//! later steps. On the bundled cloths it is 0.97–0.999 and the cap decides.
//!
//! `G` is nonlinear, so the extrapolation can overshoot. The energy of each
//! iterate is measured by the local step of the next iteration, on its way
//! (the pass over the springs that computes `d` has every length already:
//! [`iterate_measuring`](super::StepContext::iterate_measuring)); when it is
//! above the energy of the iterate before, the extrapolated `xₖ₊₁` is
//! dropped for the plain `x̂ₖ₊₁` it was made from (whose energy cannot be
//! higher), and the recurrence restarts from `ω₁`. A restart thus costs the
//! one iteration spent on the overshooting iterate, and the energy seen
//! iteration by iteration may rise once before it does; in exchange the
//! energy test costs almost nothing. The last iterate of a step is tested
//! by a separate energy evaluation, so a step never ends on an overshoot.
//!
//! Cost per iteration: one plain iteration, one pass over the vertices for
//! the energy, and vector updates `O(n)`.
//!
//! Source: H. Wang, "A Chebyshev Semi-Iterative Approach for Accelerating
//! Projective and Position-based Dynamics", ACM TOG 34(6), 2015, §4–5 (the
//! update, Eq. 12, without under-relaxation); Golub & Van Loan, *Matrix
//! Computations*, 4th ed., §11.2.8 (the semi-iterative method).

use super::block_vector::{norm, subtract};
use super::{Monitor, Outcome, StepContext, StepControl, Stop};
use crate::sim::backend::LinearAlgebra;

/// The largest spectral radius an estimate may give.
pub const RHO_CAP: f64 = 0.995;

/// Plain iterations that measure `ρ` when it is neither given nor known.
pub const ESTIMATION_ITERATIONS: usize = 20;

/// Chebyshev's work arrays, and its estimate of `ρ` from earlier steps.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// `xₖ₋₁`, then the candidate `xₖ₊₁`.
    previous: Vec<[f64; 3]>,
    /// `x̂ₖ₊₁ = G(xₖ)`.
    plain: Vec<[f64; 3]>,
    /// `x̂ₖ`, the plain iterate the last extrapolation was made from: where
    /// to go back to if that extrapolation raised the energy.
    fallback: Vec<[f64; 3]>,
    /// Room to move vectors around.
    spare: Vec<[f64; 3]>,
    /// `ρ` measured in an earlier step.
    pub estimated_rho: Option<f64>,
}

impl Workspace {
    pub fn new(n: usize) -> Self {
        Workspace {
            previous: vec![[0.0; 3]; n],
            plain: vec![[0.0; 3]; n],
            fallback: vec![[0.0; 3]; n],
            spare: vec![[0.0; 3]; n],
            estimated_rho: None,
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
    let mut estimate = RhoEstimate::default();
    let mut checked_energy = 0.0; // E − E(p⁰) of the last iterate whose energy was measured
    let mut k = 0; // extrapolations since the recurrence (re)started
    let mut omega_k = 1.0;
    work.previous.copy_from_slice(p);
    for iteration in 1..=control.iterations {
        let energy = context.iterate_measuring(p, &mut work.plain);
        if k > 0 && energy > checked_energy {
            // The last extrapolation overshot: back to the plain iterate it
            // was made from (`G` of the last good iterate), and restart.
            p.copy_from_slice(&work.fallback);
            k = 0;
        } else {
            checked_energy = energy;
            match rho {
                None => {
                    // Still measuring ρ: a plain iteration.
                    rho = estimate.record(iteration, p, &work.plain, &mut work.spare);
                    work.estimated_rho = work.estimated_rho.or(rho);
                    p.copy_from_slice(&work.plain);
                }
                Some(radius) => {
                    k += 1;
                    omega_k = omega(k, radius, omega_k);
                    extrapolate(context, work, omega_k, p);
                }
            }
        }
        if monitor.after(iteration, context, p, None) {
            return Outcome::new(iteration, Stop::Tolerance);
        }
    }
    if k > 0 && context.energy.change(p).total() > checked_energy {
        p.copy_from_slice(&work.fallback); // the last extrapolation overshot
    }
    Outcome::new(control.iterations, Stop::Iterations)
}

/// `xₖ₊₁ = ω x̂ₖ₊₁ + (1 − ω) xₖ₋₁` into `p`, with `x̂ₖ₊₁ = G(p)` in
/// `work.plain`; `work.previous` becomes `xₖ` and `work.fallback` `x̂ₖ₊₁`.
fn extrapolate<B: LinearAlgebra>(
    context: &StepContext<'_, B>,
    work: &mut Workspace,
    omega: f64,
    p: &mut [[f64; 3]],
) {
    for (x, x_hat) in work.previous.iter_mut().zip(&work.plain) {
        *x = std::array::from_fn(|c| omega * x_hat[c] + (1.0 - omega) * x[c]);
    }
    context.global.hold_pins(&mut work.previous);
    work.spare.copy_from_slice(p);
    p.copy_from_slice(&work.previous);
    std::mem::swap(&mut work.previous, &mut work.spare);
    std::mem::swap(&mut work.fallback, &mut work.plain);
}

/// The measurement of `ρ` from the first plain steps of the first step.
#[derive(Debug, Default)]
struct RhoEstimate {
    last_step_norm: f64,
    largest_ratio: f64,
}

impl RhoEstimate {
    /// Records the plain step `x̂ − x`; returns `ρ` once
    /// [`ESTIMATION_ITERATIONS`] have been recorded.
    fn record(
        &mut self,
        iteration: usize,
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
        (iteration == ESTIMATION_ITERATIONS).then(|| self.largest_ratio.min(RHO_CAP))
    }
}
