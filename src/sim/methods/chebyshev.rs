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
//! later steps. On the bundled cloths it is 0.97–0.999 and the cap decides. `G` is nonlinear, so the
//! extrapolation can overshoot: when the energy rises, the iterate is
//! replaced by the plain `x̂ₖ₊₁` (whose energy never rises) and the
//! recurrence restarts from `ω₁`.
//!
//! Cost per iteration: one plain iteration, one energy evaluation `O(m + n)`
//! and two vector updates `O(n)`.
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
    let mut energy = 0.0; // E(p) − E(p⁰) at the current iterate
    let mut k = 0; // iterations since the recurrence (re)started
    let mut omega_k = 1.0;
    let mut last_step_norm = 0.0;
    let mut largest_ratio: f64 = 0.0;
    work.previous.copy_from_slice(p);
    for iteration in 1..=control.iterations {
        context.global.iterate(p, &mut work.plain);
        let Some(radius) = rho else {
            // Still measuring ρ: a plain iteration.
            subtract(&work.plain, p, &mut work.spare);
            let step_norm = norm(&work.spare);
            if last_step_norm > 0.0 {
                largest_ratio = largest_ratio.max(step_norm / last_step_norm);
            }
            if iteration == ESTIMATION_ITERATIONS {
                let estimate = largest_ratio.min(RHO_CAP);
                work.estimated_rho = Some(estimate);
                rho = Some(estimate);
            }
            last_step_norm = step_norm;
            work.previous.copy_from_slice(p);
            p.copy_from_slice(&work.plain);
            if rho.is_some() {
                energy = context.energy.change(p).total();
            }
            if monitor.after(iteration, context, p, None) {
                return Outcome::new(iteration, Stop::Tolerance);
            }
            continue;
        };
        k += 1;
        omega_k = omega(k, radius, omega_k);
        // candidate xₖ₊₁ = ω x̂ + (1 − ω) xₖ₋₁, built in `previous`
        for (x, x_hat) in work.previous.iter_mut().zip(&work.plain) {
            *x = std::array::from_fn(|c| omega_k * x_hat[c] + (1.0 - omega_k) * x[c]);
        }
        context.global.hold_pins(&mut work.previous);
        let candidate_energy = context.energy.change(&work.previous).total();
        if candidate_energy <= energy {
            // accept: xₖ₋₁ ← xₖ, xₖ ← candidate
            work.spare.copy_from_slice(p);
            p.copy_from_slice(&work.previous);
            work.previous.copy_from_slice(&work.spare);
            energy = candidate_energy;
        } else {
            // overshoot: take the plain iterate and restart the recurrence
            work.previous.copy_from_slice(p);
            p.copy_from_slice(&work.plain);
            energy = context.energy.change(p).total();
            k = 0;
        }
        if monitor.after(iteration, context, p, None) {
            return Outcome::new(iteration, Stop::Tolerance);
        }
    }
    Outcome::new(control.iterations, Stop::Iterations)
}
