//! One time step: the local/global iteration.
//!
//! With `U_cur = p^t` and `U_prev = p^{t−Δt}`, the positions at `t + Δt`
//! minimise `½ tr(pᵀQp) − tr(pᵀb)`, found by alternating
//!
//! ```text
//! y = M (2 U_cur − U_prev) / Δt² + f_ext          once per step
//! repeat (50 times):
//!     dₑ = rₑ (pᵢ − pⱼ) / ‖pᵢ − pⱼ‖               local step, every spring
//!     b  = k Aᵀ d + y + w CᵀC V                    right-hand side
//!     p  = Q⁻¹ b                                   global step, two triangular solves
//! ```
//!
//! starting from `p = U_cur`. The factorization of `Q` comes from the
//! precomputation; the three columns x, y, z are solved together. The step
//! allocates nothing and reports how many iterations it ran and how much the
//! last one still changed the positions, so that stopping rules and
//! accelerations can be plugged in.
//!
//! Cost per iteration: `O(m)` local step, `O(m + n)` for `b`,
//! `O(nnz(L))` for the solve (sparse; `O(n²)` dense).
//! Source: Liu et al. 2013, Algorithm 1 (§4); the assignment
//! (`fast_mass_springs_step_dense.cpp` / `_sparse.cpp`, "Step 1–3").

use super::backend::{Dense, LinearAlgebra, Sparse};
use super::local_step::project_springs;
use super::precomputation::MassSpringSystem;
use super::SimulationError;

/// The assignment's number of local/global iterations per step.
pub const ITERATIONS: usize = 50;

/// What a step did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    /// Local/global iterations run.
    pub iterations: usize,
    /// `‖p_last − p_before‖ / ‖p_last‖` over the final iteration: how far
    /// from converged the step stopped.
    pub relative_change: f64,
}

/// Computes `u_next` from `u_cur` and `u_prev` under the forces `f_ext`,
/// with `iterations` local/global iterations.
///
/// # Errors
/// [`SimulationError::NotFinite`] when the new positions hold NaN or
/// infinity (reported, not propagated: `u_next` is then not a state to
/// continue from).
///
/// # Panics
/// When a slice does not have one row per vertex.
pub fn fast_mass_springs_step<B: LinearAlgebra>(
    system: &mut MassSpringSystem<B>,
    iterations: usize,
    f_ext: &[[f64; 3]],
    u_prev: &[[f64; 3]],
    u_cur: &[[f64; 3]],
    u_next: &mut [[f64; 3]],
) -> Result<StepReport, SimulationError> {
    let n = system.n();
    assert!(f_ext.len() == n && u_prev.len() == n && u_cur.len() == n && u_next.len() == n);
    inertial_term(system, f_ext, u_prev, u_cur);
    u_next.copy_from_slice(u_cur);
    for iteration in 0..iterations {
        let buffers = &mut system.buffers;
        project_springs(&system.springs, &system.r, u_next, &mut buffers.d);
        B::transpose_mul_points(&system.A, &buffers.d, &mut buffers.b);
        for ((b, y), pin) in buffers.b.iter_mut().zip(&buffers.y).zip(&system.pin_rhs) {
            *b = std::array::from_fn(|c| system.k * b[c] + y[c] + pin[c]);
        }
        if iteration + 1 == iterations {
            buffers.previous.copy_from_slice(u_next);
        }
        B::solve_points(&mut system.prefactorization, &mut buffers.b);
        u_next.copy_from_slice(&buffers.b);
    }
    if let Some(vertex) = u_next.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return Err(SimulationError::NotFinite { vertex });
    }
    Ok(StepReport {
        iterations,
        relative_change: relative_change(&system.buffers.previous, u_next, iterations),
    })
}

/// `y = M (2 U_cur − U_prev) / Δt² + f_ext`, into the system's buffer.
fn inertial_term<B: LinearAlgebra>(
    system: &mut MassSpringSystem<B>,
    f_ext: &[[f64; 3]],
    u_prev: &[[f64; 3]],
    u_cur: &[[f64; 3]],
) {
    let buffers = &mut system.buffers;
    for ((inertia, cur), prev) in buffers.inertia.iter_mut().zip(u_cur).zip(u_prev) {
        *inertia = std::array::from_fn(|c| 2.0 * cur[c] - prev[c]);
    }
    B::mul_points(&system.M, &buffers.inertia, &mut buffers.y);
    let dt2 = system.delta_t * system.delta_t;
    for (y, f) in buffers.y.iter_mut().zip(f_ext) {
        *y = std::array::from_fn(|c| y[c] / dt2 + f[c]);
    }
}

/// `‖now − before‖ / ‖now‖` (0 when no iteration ran or `now` is zero).
fn relative_change(before: &[[f64; 3]], now: &[[f64; 3]], iterations: usize) -> f64 {
    if iterations == 0 {
        return 0.0;
    }
    let (mut change, mut size) = (0.0, 0.0);
    for (b, p) in before.iter().zip(now) {
        for c in 0..3 {
            change += (p[c] - b[c]).powi(2);
            size += p[c].powi(2);
        }
    }
    if size > 0.0 {
        (change / size).sqrt()
    } else {
        0.0
    }
}

/// The assignment's `fast_mass_springs_step_dense` (50 iterations).
///
/// # Errors
/// As [`fast_mass_springs_step`].
pub fn fast_mass_springs_step_dense(
    system: &mut MassSpringSystem<Dense>,
    f_ext: &[[f64; 3]],
    u_prev: &[[f64; 3]],
    u_cur: &[[f64; 3]],
    u_next: &mut [[f64; 3]],
) -> Result<StepReport, SimulationError> {
    fast_mass_springs_step(system, ITERATIONS, f_ext, u_prev, u_cur, u_next)
}

/// The assignment's `fast_mass_springs_step_sparse` (50 iterations).
///
/// # Errors
/// As [`fast_mass_springs_step`].
pub fn fast_mass_springs_step_sparse(
    system: &mut MassSpringSystem<Sparse>,
    f_ext: &[[f64; 3]],
    u_prev: &[[f64; 3]],
    u_cur: &[[f64; 3]],
    u_next: &mut [[f64; 3]],
) -> Result<StepReport, SimulationError> {
    fast_mass_springs_step(system, ITERATIONS, f_ext, u_prev, u_cur, u_next)
}
