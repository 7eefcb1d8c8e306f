//! The plain local/global iteration: the assignment's step.
//!
//! ```text
//! repeat:
//!     dₑ = rₑ (pᵢ − pⱼ) / ‖pᵢ − pⱼ‖      local step, every spring
//!     p  = Q⁻¹ (k Aᵀ d + y + w CᵀC V)     global step
//! ```
//!
//! Each iteration minimises the energy exactly over `d` (with `p` fixed) and
//! then over `p` (with `d` fixed), so the energy never rises; written with
//! the gradient it is `p ← p − Q⁻¹ ∇E(p)`. It converges linearly, at a rate
//! that on cloth is close to 1 (ρ ≈ 0.9999 late in a step), which is what
//! the other methods accelerate.
//!
//! The arithmetic is exactly that of the assignment's solver, so that this
//! method keeps the fidelity of the reference trajectories bit for bit.
//!
//! Cost per iteration: `O(m)` local step, `O(m + n)` for `b`, one solve
//! with the prefactored `Q` (`O(nnz(L))`); plus one gradient, `O(m + n)`,
//! when a tolerance is tested.
//!
//! Source: Liu et al. 2013, Algorithm 1; the assignment,
//! `fast_mass_springs_step_dense.cpp` / `_sparse.cpp`.

use super::{Monitor, Outcome, StepContext, StepControl, Stop};
use crate::sim::backend::LinearAlgebra;

/// Iterates from `p` (in place) until the control says stop.
pub(crate) fn solve<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    for iteration in 1..=control.iterations {
        context.global.iterate_in_place(p);
        if monitor.after(iteration, context, p, None) {
            return Outcome::new(iteration, Stop::Tolerance);
        }
    }
    Outcome::new(control.iterations, Stop::Iterations)
}
