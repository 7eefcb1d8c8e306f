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
//! precomputation; the three columns x, y, z are solved together.
//!
//! That is the `plain` method of [`methods`](super::methods); the step can
//! instead run an accelerated one, and stop at a tolerance on the relative
//! gradient of the step's [`energy`](super::energy), or on the energy's
//! progress, instead of after a fixed count ([`StepControl`]). It reports
//! the iterations it ran, the energy it took off and the relative gradient
//! where it stopped. After a method's first step, a step allocates nothing.
//!
//! The iterations start at `pᵗ` (the assignment's start) or, with
//! `--start inertial`, at the inertial prediction `2pᵗ − pᵗ⁻ᐞᵗ` when its
//! energy is lower ([`Start`]). The initial gradient `∇E(pᵗ)` (the rule's
//! yardstick) and the local step at the first iterate share passes over the
//! springs, and a method that measured the energy of its last iterate hands
//! it to the report, so that a short step (a few iterations to a tolerance)
//! does not pay twice for its ends.
//!
//! Cost per iteration: `O(m)` local step, `O(m + n)` for `b`,
//! `O(nnz(L))` for the solve (sparse; `O(n²)` dense).
//! Source: Liu et al. 2013, Algorithm 1 (§4); the assignment
//! (`fast_mass_springs_step_dense.cpp` / `_sparse.cpp`, "Step 1–3").

use super::backend::{Dense, LinearAlgebra, Sparse};
use super::energy::{free_norm, start_lengths, StepEnergy};
use super::methods::{
    anderson, chebyshev, factor_order, lbfgs, newton, plain, GlobalStep, Gradient, Monitor,
    Observer, Outcome, Start, StepContext, StepControl, StepMethod, Stop,
};
use super::precomputation::{mass_mul_points, MassSpringSystem};
use super::SimulationError;

/// The assignment's number of local/global iterations per step.
pub const ITERATIONS: usize = 50;

/// What a step did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    /// The method that solved it.
    pub method: StepMethod,
    /// Iterations run.
    pub iterations: usize,
    /// Why it stopped.
    pub stop: Stop,
    /// `E(p⁰) − E(p)`: how much energy the step took off (≥ 0 for every
    /// method, since none accepts a rise).
    pub energy_decrease: f64,
    /// `‖∇E(p)‖ / ‖∇E(p⁰)‖` over the free vertices where it stopped: how
    /// far from the minimiser.
    pub relative_gradient: f64,
}

/// Computes `u_next` from `u_cur` and `u_prev` under the forces `f_ext`,
/// with the assignment's plain iteration run `iterations` times.
///
/// # Errors
/// As [`solve_step`].
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
    let control = StepControl {
        iterations,
        ..StepControl::default()
    };
    solve_step(system, &control, f_ext, u_prev, u_cur, u_next, None)
}

/// Computes `u_next` from `u_cur` and `u_prev` under the forces `f_ext`, by
/// the method and stopping rule of `control`; `observer`, if any, sees
/// every iterate (iteration 0 is `u_cur`).
///
/// # Errors
/// [`SimulationError::NotFinite`] when the new positions hold NaN or
/// infinity, [`SimulationError::EnergyNotFinite`] when the energy or
/// gradient there does (reported, not propagated: `u_next` is then not a
/// state to continue from); an error of Newton's first factorization.
///
/// # Panics
/// When a slice does not have one row per vertex.
pub fn solve_step<B: LinearAlgebra>(
    system: &mut MassSpringSystem<B>,
    control: &StepControl,
    f_ext: &[[f64; 3]],
    u_prev: &[[f64; 3]],
    u_cur: &[[f64; 3]],
    u_next: &mut [[f64; 3]],
    observer: Option<Observer<'_>>,
) -> Result<StepReport, SimulationError> {
    let n = system.n();
    assert!(f_ext.len() == n && u_prev.len() == n && u_cur.len() == n && u_next.len() == n);
    prepare_workspace(system, control)?;
    inertial_term(system, f_ext, u_prev, u_cur);
    u_next.copy_from_slice(u_cur);
    let MassSpringSystem {
        r,
        m,
        Q,
        prefactorization,
        springs,
        k,
        delta_t,
        w,
        pin_rhs,
        pinned,
        pin_targets,
        is_pinned,
        buffers,
        exact_pins,
        ..
    } = system;
    start_lengths(springs, u_cur, &mut buffers.start_lengths);
    let energy = StepEnergy {
        springs,
        r,
        k: *k,
        m,
        delta_t: *delta_t,
        w: if exact_pins.is_some() { 0.0 } else { *w },
        pinned,
        pin_targets,
        inertial_target: &buffers.inertia,
        f_ext,
        start: u_cur,
        start_lengths: &buffers.start_lengths,
    };
    let first = first_iterate(
        &energy,
        control.start,
        exact_pins.is_some(),
        is_pinned,
        u_next,
        &mut buffers.b,
        &mut buffers.gradient,
    );
    let mut context = StepContext {
        energy,
        pinned: is_pinned,
        global: GlobalStep::<B> {
            springs,
            r,
            k: *k,
            Q,
            y: &buffers.y,
            pin_rhs,
            factorization: prefactorization,
            exact_pins: exact_pins.as_mut(),
            pinned,
            pin_targets,
            b: &mut buffers.b,
        },
        start_measured: first.measured,
        start_energy: first.energy,
    };
    let mut monitor = Monitor::new(
        control,
        first.initial_gradient,
        &mut buffers.gradient,
        observer,
    );
    let start = match first.measured {
        true => Gradient::InRoom, // ∇E at the first iterate is in the room
        false => Gradient::Unknown,
    };
    monitor.after(0, &context, u_next, start, Some(first.energy));
    let workspaces = &mut buffers.methods;
    let outcome: Outcome = match control.method {
        StepMethod::Plain => {
            let work = workspaces.factor_order.as_ref();
            plain::solve(&mut context, control, work, u_next, &mut monitor)
        }
        StepMethod::Chebyshev => {
            let work = workspaces.chebyshev.as_mut().expect("prepared");
            chebyshev::solve(&mut context, control, work, u_next, &mut monitor)
        }
        StepMethod::Anderson => {
            let work = workspaces.anderson.as_mut().expect("prepared");
            anderson::solve(&mut context, control, work, u_next, &mut monitor)
        }
        StepMethod::Lbfgs => {
            let work = workspaces.lbfgs.as_mut().expect("prepared");
            lbfgs::solve(&mut context, control, work, u_next, &mut monitor)
        }
        StepMethod::Newton => {
            let work = workspaces.newton.as_mut().expect("prepared");
            newton::solve(&mut context, control, work, u_next, &mut monitor)
        }
    };
    if let Some(vertex) = u_next.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return Err(SimulationError::NotFinite { vertex });
    }
    let relative_gradient =
        monitor.final_relative_gradient(&context.energy, context.pinned, u_next);
    let energy_decrease = -outcome
        .energy
        .unwrap_or_else(|| context.energy.change(u_next).total());
    if !(energy_decrease.is_finite() && relative_gradient.is_finite()) {
        return Err(SimulationError::EnergyNotFinite);
    }
    Ok(StepReport {
        method: control.method,
        iterations: outcome.iterations,
        stop: outcome.stop,
        energy_decrease,
        relative_gradient,
    })
}

/// What [`first_iterate`] knows when the iterations begin.
struct FirstIterate {
    /// `‖∇E(pᵗ)‖` over the free vertices: the stopping rule's yardstick.
    initial_gradient: f64,
    /// Is the local step at the first iterate made (its `Aᵀd` in place, its
    /// gradient in the monitor's room)?
    measured: bool,
    /// `E − E(pᵗ)` at the first iterate.
    energy: f64,
}

/// Sets `u_next` (holding `pᵗ`) to the first iterate: `pᵗ`, or with
/// [`Start::Inertial`] the inertial prediction `ŷ` (the energy's
/// `inertial_target`) when its energy is below `pᵗ`'s; exact pins at their
/// targets.
///
/// The passes are shared: with the assignment's start and penalty pins,
/// one pass makes `∇E(pᵗ)` and the local step at `pᵗ`; the inertial start
/// tests `ŷ` with the pass that makes the local step there.
fn first_iterate(
    energy: &StepEnergy<'_>,
    start: Start,
    exact_pins: bool,
    is_pinned: &[bool],
    u_next: &mut [[f64; 3]],
    a_t_d: &mut [[f64; 3]],
    gradient: &mut [[f64; 3]],
) -> FirstIterate {
    let hold_pins = |p: &mut [[f64; 3]]| {
        if exact_pins {
            for (&c, &t) in energy.pinned.iter().zip(energy.pin_targets) {
                p[c] = t;
            }
        }
    };
    if start == Start::Current && !exact_pins {
        energy.change_with_local_step(energy.start, a_t_d, Some(gradient));
        return FirstIterate {
            initial_gradient: free_norm(gradient, is_pinned),
            measured: true,
            energy: 0.0,
        };
    }
    energy.gradient(energy.start, gradient);
    let initial_gradient = free_norm(gradient, is_pinned);
    if start == Start::Inertial {
        u_next.copy_from_slice(energy.inertial_target);
        hold_pins(u_next);
        let change = energy.change_with_local_step(u_next, a_t_d, Some(gradient));
        if change.total() < 0.0 {
            return FirstIterate {
                initial_gradient,
                measured: true,
                energy: change.total(),
            };
        }
        u_next.copy_from_slice(energy.start);
    }
    hold_pins(u_next); // exact pins start at their (maybe moved) targets
    FirstIterate {
        initial_gradient,
        measured: false,
        energy: match exact_pins {
            true => energy.change(u_next).total(),
            false => 0.0, // u_next = pᵗ
        },
    }
}

/// Makes the work arrays of `control`'s method the first time it runs (or
/// when the history window changed).
fn prepare_workspace<B: LinearAlgebra>(
    system: &mut MassSpringSystem<B>,
    control: &StepControl,
) -> Result<(), SimulationError> {
    let n = system.n();
    let workspaces = &mut system.buffers.methods;
    match control.method {
        StepMethod::Plain => {
            // the loop in the factor's order runs with penalty pins and
            // no tolerance (and no observer, known only later)
            let in_factor_order = system.exact_pins.is_none() && !control.has_stopping_rule();
            if in_factor_order && workspaces.factor_order.is_none() {
                if let Some(cholesky) = B::as_sparse_cholesky(&mut system.prefactorization) {
                    let new_index = cholesky.symbolic().permutation().inverse();
                    let work = factor_order::Workspace::new(&system.springs, new_index);
                    workspaces.factor_order = Some(work);
                }
            }
        }
        StepMethod::Chebyshev => {
            workspaces
                .chebyshev
                .get_or_insert_with(|| chebyshev::Workspace::new(n));
        }
        StepMethod::Anderson => {
            if workspaces
                .anderson
                .as_ref()
                .is_none_or(|w| w.window() != control.window.max(1))
            {
                workspaces.anderson = Some(anderson::Workspace::new(n, control.window));
            }
        }
        StepMethod::Lbfgs => {
            if workspaces
                .lbfgs
                .as_ref()
                .is_none_or(|w| w.window() != control.window.max(1))
            {
                workspaces.lbfgs = Some(lbfgs::Workspace::new(n, control.window));
            }
        }
        StepMethod::Newton => {
            if workspaces.newton.is_none() {
                workspaces.newton = Some(newton::Workspace::new(n, &system.springs)?);
            }
        }
    }
    Ok(())
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
    mass_mul_points(&system.m, &buffers.inertia, &mut buffers.y); // M (2 U_cur − U_prev)
    let dt2 = system.delta_t * system.delta_t;
    for (y, f) in buffers.y.iter_mut().zip(f_ext) {
        *y = std::array::from_fn(|c| y[c] / dt2 + f[c]);
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
