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
//! with the prefactored `Q` (`O(nnz(L))`). When a tolerance is tested, the
//! local step's pass over the springs also makes the gradient
//! ([`local_step_measuring`](crate::sim::global_step::StepContext::local_step_measuring)),
//! for one more pass over the vertices.
//!
//! Source: Liu et al. 2013, Algorithm 1; the assignment,
//! `fast_mass_springs_step_dense.cpp` / `_sparse.cpp`.

use super::factor_order::{self, PlainProblem};
use crate::sim::backend::LinearAlgebra;
use crate::sim::control::{Outcome, StepControl, Stop};
use crate::sim::global_step::StepContext;
use crate::sim::monitor::{Gradient, Monitor};

/// Iterates from `p` (in place) until the control says stop. With the
/// sparse backend, penalty pins and nothing watching the iterates, the
/// same iterations run in the factor's order ([`factor_order`], the same
/// bits) with the springs of `work` (which the step makes for the sparse
/// backend).
pub(crate) fn solve<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    work: Option<&factor_order::Workspace>,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    if monitor.tests_iterates() {
        return solve_to_tolerance(context, control, p, monitor);
    }
    if let (Some(work), Some(room)) = (work, monitor.unused_room()) {
        if in_factor_order(context, work, room, control.iterations, p) {
            return Outcome::new(control.iterations, Stop::Iterations);
        }
    }
    for iteration in 1..=control.iterations {
        context.global.iterate_in_place(p);
        // No rule: only observed, or cancelled.
        if let Some(stop) = monitor.after(iteration, context, p, Gradient::Unknown, None) {
            return Outcome::new(iteration, stop);
        }
    }
    Outcome::new(control.iterations, Stop::Iterations)
}

/// The same iterates, when a tolerance is tested: the local step at each
/// iterate is made as soon as it is reached, so that its pass over the
/// springs also gives the gradient the rule tests.
fn solve_to_tolerance<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    let mut energy = context.local_step_at_start(p, None);
    for iteration in 1..=control.iterations {
        context.global_step(p);
        energy = context.local_step_measuring(p, monitor.room_for_gradient());
        if iteration == 1 {
            monitor.plain_first(energy); // the first iterate is G(p⁰)
        }
        if let Some(stop) = monitor.after(iteration, context, p, Gradient::InRoom, Some(energy)) {
            return Outcome::measured(iteration, stop, energy);
        }
    }
    Outcome::measured(control.iterations, Stop::Iterations, energy)
}

/// `iterations` iterations in the factor's order, when the pins are
/// penalties and the factorization is the sparse one; `false` (nothing
/// done) otherwise.
fn in_factor_order<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    work: &factor_order::Workspace,
    room: &mut [[f64; 3]],
    iterations: usize,
    p: &mut [[f64; 3]],
) -> bool {
    let global = &mut context.global;
    if global.exact() {
        return false;
    }
    let Some(cholesky) = B::as_sparse_cholesky(global.factorization) else {
        return false;
    };
    let problem = PlainProblem {
        r: global.r,
        k: global.k,
        y: global.y,
        pin_rhs: global.pin_rhs,
        pinned: global.pinned,
    };
    factor_order::iterate(work, cholesky, &problem, global.b, room, p, iterations);
    true
}
