//! One time step on the fast path: the step's work arrays, and the choice
//! of method.
//!
//! With `U_cur = pᵗ` and `U_prev = pᵗ⁻ᐞᵗ`, the positions at `t + Δt`
//! minimise the step's [`energy`](super::energy). The handout finds them by
//! 50 local/global iterations from `pᵗ`; that loop, written out as the
//! handout writes it, is [`textbook`](super::textbook). This file runs the
//! same iteration fast, or one of the methods that accelerate it:
//!
//! ```text
//! y = M (2 U_cur − U_prev) / Δt² + f_ext          once per step (inertial_term)
//! p⁰ = U_cur (or the inertial prediction)        first_iterate
//! p = the method's iterations from p⁰             methods::solve, until the
//!                                                 control's rule or budget stops it
//! ```
//!
//! [`StepWorkspace`] owns every array a step writes (`y`, `Aᵀd`, a
//! gradient, each method's history), sized once, so that after a method's
//! first step a step allocates nothing; the system it reads
//! ([`MassSpringSystem`]) stays constant.
//!
//! A step measures only what someone asks for: with the assignment's plain
//! iteration, a fixed count, no stopping rule and no observer, it computes
//! no energy and no gradient, and its [`StepReport`] says they were not
//! measured (`None`). [`StepControl::measure`] asks for them anyway.
//!
//! Cost per iteration: `O(m)` local step, `O(m + n)` for `b`,
//! `O(nnz(L))` for the solve (sparse; `O(n²)` dense).
//! Source: Liu et al. 2013, Algorithm 1 (§4); the assignment
//! (`fast_mass_springs_step_dense.cpp` / `_sparse.cpp`, "Step 1–3").

use super::backend::LinearAlgebra;
use super::control::{Outcome, Start, StepControl, StepMethod, Stop};
use super::energy::{free_norm, start_lengths, StepEnergy};
use super::error::SimulationError;
use super::global_step::{GlobalStep, StepContext};
use super::methods::{self, MethodWorkspaces, Problem};
use super::monitor::{Gradient, Monitor, Observer};
use super::precomputation::{mass_mul_points, MassSpringSystem};
use std::sync::atomic::AtomicBool;

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
    /// method, since none accepts a rise); `None` when not measured.
    pub energy_decrease: Option<f64>,
    /// `‖∇E(p)‖ / ‖∇E(p⁰)‖` over the free vertices where it stopped: how
    /// far from the minimiser; `None` when not measured.
    pub relative_gradient: Option<f64>,
}

/// The state a step starts from, and the forces during it.
#[derive(Debug, Clone, Copy)]
pub struct StepState<'a> {
    /// `f_ext`, one force per vertex.
    pub f_ext: &'a [[f64; 3]],
    /// `U_prev = pᵗ⁻ᐞᵗ`.
    pub u_prev: &'a [[f64; 3]],
    /// `U_cur = pᵗ`.
    pub u_cur: &'a [[f64; 3]],
}

/// Every array a step writes, sized once for `n` vertices and `m` springs.
#[derive(Debug, Clone)]
pub struct StepWorkspace {
    /// `ŷ = 2 U_cur − U_prev`.
    inertia: Vec<[f64; 3]>,
    /// `y = M ŷ / Δt² + f_ext`.
    y: Vec<[f64; 3]>,
    /// The last local step's `Aᵀd` (the spring directions `d` themselves
    /// are never stored); with exact pins then `b = k Aᵀd + y + w CᵀC V`
    /// and the solution of `Q_ff p = b`.
    b: Vec<[f64; 3]>,
    /// `∇E` where a stopping rule needs it.
    gradient: Vec<[f64; 3]>,
    /// Each spring's length where the step starts.
    start_lengths: Vec<f64>,
    /// The methods' work arrays, made when first used.
    methods: MethodWorkspaces,
}

impl StepWorkspace {
    /// The arrays of a step of `system`.
    pub fn new<B: LinearAlgebra>(system: &MassSpringSystem<B>) -> Self {
        let n = system.n();
        StepWorkspace {
            inertia: vec![[0.0; 3]; n],
            y: vec![[0.0; 3]; n],
            b: vec![[0.0; 3]; n],
            gradient: vec![[0.0; 3]; n],
            start_lengths: vec![0.0; system.springs.len()],
            methods: MethodWorkspaces::default(),
        }
    }

    /// What the methods carry to the next step ([`MethodWorkspaces::carried`]).
    pub fn carried(&self) -> methods::Carried {
        self.methods.carried()
    }

    /// Takes up what an earlier run carried ([`MethodWorkspaces::carry`]).
    pub fn carry(&mut self, carried: methods::Carried) {
        self.methods.carry(carried);
    }

    /// What the workspace holds, in bytes (arrays' lengths), item by item.
    /// The work arrays of a method other than `plain`, made when it first
    /// runs, are not counted; `plain`'s renumbered springs are, once a
    /// step has made them.
    pub fn bytes(&self) -> Vec<(&'static str, usize)> {
        use std::mem::size_of_val as bytes;
        vec![
            (
                "step buffers: inertia, y, b, gradient",
                bytes(&self.inertia[..])
                    + bytes(&self.y[..])
                    + bytes(&self.b[..])
                    + bytes(&self.gradient[..]),
            ),
            (
                "step buffers: start lengths",
                bytes(&self.start_lengths[..]),
            ),
            (
                "springs in the factor's order (plain)",
                self.methods.bytes(),
            ),
        ]
    }
}

/// Computes `u_next` from the state under its forces, by the method and
/// stopping rule of `control`; `observer`, if any, sees every iterate
/// (iteration 0 is the first iterate); `cancel`, if any, stops the step at
/// the first iterate after it is set.
///
/// # Errors
/// [`SimulationError::NotFinite`] when the new positions hold NaN or
/// infinity, [`SimulationError::EnergyNotFinite`] when the energy or
/// gradient there does (reported, not propagated: `u_next` is then not a
/// state to continue from); [`SimulationError::Cancelled`] when `cancel`
/// stopped it; an error of Newton's first factorization.
///
/// # Panics
/// When a slice does not have one row per vertex.
pub fn solve_step<B: LinearAlgebra>(
    system: &mut MassSpringSystem<B>,
    workspace: &mut StepWorkspace,
    control: &StepControl,
    state: StepState<'_>,
    u_next: &mut [[f64; 3]],
    observer: Option<Observer<'_>>,
    cancel: Option<&AtomicBool>,
) -> Result<StepReport, SimulationError> {
    begin(system, workspace, control, state)?; // the method's arrays, y, l⁰
    u_next.copy_from_slice(state.u_cur);
    let measure = measures(control, observer.is_some());
    let StepWorkspace {
        inertia,
        y,
        b,
        gradient,
        start_lengths,
        methods: workspaces,
    } = workspace;
    let (f_ext, u_cur) = (state.f_ext, state.u_cur);
    let parts = Borrowed {
        inertia,
        y,
        start_lengths,
        f_ext,
        u_cur,
    };
    let mut context = step_context(system, parts, b);
    let first = first_iterate(&mut context, control.start, measure, u_next, gradient);
    let mut monitor = Monitor::new(control, first.initial_gradient, gradient, observer);
    monitor.cancel_on(cancel);
    let start = if first.measured {
        Gradient::InRoom
    } else {
        Gradient::Unknown
    };
    monitor.after(0, &context, u_next, start, Some(first.energy));
    let outcome = methods::solve(workspaces, &mut context, control, u_next, &mut monitor);
    if outcome.stop == Stop::Cancelled {
        return Err(SimulationError::Cancelled);
    }
    if let Some(vertex) = u_next.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return Err(SimulationError::NotFinite { vertex });
    }
    let ends = Ends {
        context: &context,
        p: u_next,
    };
    ends.report(control.method, outcome, measure, &mut monitor)
}

/// Before the iterations: the method's work arrays (the first time it
/// runs), `y`, and the springs' lengths at `U_cur`.
fn begin<B: LinearAlgebra>(
    system: &mut MassSpringSystem<B>,
    workspace: &mut StepWorkspace,
    control: &StepControl,
    state: StepState<'_>,
) -> Result<(), SimulationError> {
    let n = system.n();
    let StepState {
        f_ext,
        u_prev,
        u_cur,
    } = state;
    assert!(f_ext.len() == n && u_prev.len() == n && u_cur.len() == n);
    let problem = Problem::<B> {
        n,
        springs: &system.springs,
        factorization: &mut system.prefactorization,
        exact_pins: system.exact_pins.is_some(),
    };
    methods::prepare(&mut workspace.methods, problem, control)?;
    inertial_term(system, workspace, state);
    start_lengths(&system.springs, u_cur, &mut workspace.start_lengths);
    Ok(())
}

/// Where a step ended, to measure for its report.
struct Ends<'c, 'a, B: LinearAlgebra> {
    context: &'c StepContext<'a, B>,
    p: &'c [[f64; 3]],
}

impl<B: LinearAlgebra> Ends<'_, '_, B> {
    /// The step's report: what `outcome` says, and the energy decrease
    /// and relative gradient where the step ended, measured when
    /// `measure`, otherwise only the energy a method measured anyway.
    ///
    /// # Errors
    /// [`SimulationError::EnergyNotFinite`] when a measured one is not
    /// finite.
    fn report(
        &self,
        method: StepMethod,
        outcome: Outcome,
        measure: bool,
        monitor: &mut Monitor<'_, '_>,
    ) -> Result<StepReport, SimulationError> {
        let (energy_decrease, relative_gradient) = match measure {
            false => (outcome.energy.map(|e| -e), None),
            true => {
                let energy = &self.context.energy;
                let change = outcome
                    .energy
                    .unwrap_or_else(|| energy.change(self.p).total());
                let gradient = monitor.final_relative_gradient(energy, self.context.pinned, self.p);
                (Some(-change), gradient)
            }
        };
        let finite = |x: Option<f64>| x.is_none_or(f64::is_finite);
        if !(finite(energy_decrease) && finite(relative_gradient)) {
            return Err(SimulationError::EnergyNotFinite);
        }
        Ok(StepReport {
            method: outcome.method.unwrap_or(method),
            iterations: outcome.iterations,
            stop: outcome.stop,
            energy_decrease,
            relative_gradient,
        })
    }
}

/// Does a step by `control` measure its energy and gradient? Always with a
/// stopping rule, an observer, or when asked; the accelerated methods
/// measure their iterates anyway. Only the assignment's plain, fixed-count
/// step skips them.
fn measures(control: &StepControl, observed: bool) -> bool {
    control.measure
        || observed
        || control.has_stopping_rule()
        || control.method != StepMethod::Plain
}

/// The workspace's arrays and the state that the step's energy and global
/// step read, borrowed while the other arrays are written.
struct Borrowed<'a> {
    inertia: &'a [[f64; 3]],
    y: &'a [[f64; 3]],
    start_lengths: &'a [f64],
    f_ext: &'a [[f64; 3]],
    u_cur: &'a [[f64; 3]],
}

/// The step's energy and global step, over `system` and the workspace's
/// arrays (`b`: room for `Aᵀd`).
#[allow(non_snake_case)] // the handout's Q
fn step_context<'a, B: LinearAlgebra>(
    system: &'a mut MassSpringSystem<B>,
    parts: Borrowed<'a>,
    b: &'a mut [[f64; 3]],
) -> StepContext<'a, B> {
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
        exact_pins,
        ..
    } = system;
    let energy = StepEnergy {
        springs,
        r,
        k: *k,
        m,
        delta_t: *delta_t,
        w: if exact_pins.is_some() { 0.0 } else { *w },
        pinned,
        pin_targets,
        inertial_target: parts.inertia,
        f_ext: parts.f_ext,
        start: parts.u_cur,
        start_lengths: parts.start_lengths,
    };
    let global = GlobalStep::<B> {
        springs,
        r,
        k: *k,
        Q,
        y: parts.y,
        pin_rhs,
        factorization: prefactorization,
        exact_pins: exact_pins.as_mut(),
        pinned,
        pin_targets,
        b,
    };
    StepContext {
        energy,
        pinned: is_pinned,
        global,
        start_measured: false,
        start_energy: 0.0,
        rounding: None,
    }
}

/// What [`first_iterate`] knows when the iterations begin.
struct FirstIterate {
    /// `‖∇E(pᵗ)‖` over the free vertices (the stopping rule's
    /// yardstick), when measured.
    initial_gradient: Option<f64>,
    /// Is the local step at the first iterate made (its `Aᵀd` in place, its
    /// gradient in the monitor's room)?
    measured: bool,
    /// `E − E(pᵗ)` at the first iterate.
    energy: f64,
}

/// Sets `u_next` (holding `pᵗ`) to the first iterate: `pᵗ`, or with
/// [`Start::Inertial`] the inertial prediction `ŷ` (the energy's
/// `inertial_target`) when its energy is below `pᵗ`'s; exact pins at their
/// targets. Records in `context` what it measured there.
///
/// The passes are shared: with the assignment's start and penalty pins,
/// one pass makes `∇E(pᵗ)` and the local step at `pᵗ`; the inertial start
/// tests `ŷ` with the pass that makes the local step there. Without
/// `measure` (the plain fixed-count step) nothing is measured at `pᵗ`.
fn first_iterate<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    start: Start,
    measure: bool,
    u_next: &mut [[f64; 3]],
    gradient: &mut [[f64; 3]],
) -> FirstIterate {
    let exact = context.global.exact();
    let first = match (start, exact, measure) {
        (Start::Current, false, false) => FirstIterate {
            initial_gradient: None,
            measured: false,
            energy: 0.0,
        },
        (Start::Current, false, true) => {
            let energy = &context.energy;
            energy.change_with_local_step(energy.start, context.global.b, Some(gradient));
            FirstIterate {
                initial_gradient: Some(free_norm(gradient, context.pinned)),
                measured: true,
                energy: 0.0,
            }
        }
        _ => moved_start(context, start, u_next, gradient),
    };
    context.start_measured = first.measured;
    context.start_energy = first.energy;
    first
}

/// [`first_iterate`] when the first iterate may not be `pᵗ`: the inertial
/// start, or exact pins moved to their targets.
fn moved_start<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    start: Start,
    u_next: &mut [[f64; 3]],
    gradient: &mut [[f64; 3]],
) -> FirstIterate {
    let energy = &context.energy;
    energy.gradient(energy.start, gradient);
    let initial_gradient = Some(free_norm(gradient, context.pinned));
    if start == Start::Inertial {
        u_next.copy_from_slice(energy.inertial_target);
        context.global.hold_pins(u_next);
        let change = energy.change_with_local_step(u_next, context.global.b, Some(gradient));
        if change.total() < 0.0 {
            return FirstIterate {
                initial_gradient,
                measured: true,
                energy: change.total(),
            };
        }
        u_next.copy_from_slice(energy.start);
    }
    context.global.hold_pins(u_next); // exact pins start at their (maybe moved) targets
    FirstIterate {
        initial_gradient,
        measured: false,
        energy: match context.global.exact() {
            true => energy.change(u_next).total(),
            false => 0.0, // u_next = pᵗ
        },
    }
}

/// `ŷ = 2 U_cur − U_prev` and `y = M ŷ / Δt² + f_ext`, into the workspace.
fn inertial_term<B: LinearAlgebra>(
    system: &MassSpringSystem<B>,
    workspace: &mut StepWorkspace,
    state: StepState<'_>,
) {
    let StepState {
        f_ext,
        u_prev,
        u_cur,
    } = state;
    for ((inertia, cur), prev) in workspace.inertia.iter_mut().zip(u_cur).zip(u_prev) {
        *inertia = std::array::from_fn(|c| 2.0 * cur[c] - prev[c]);
    }
    mass_mul_points(&system.m, &workspace.inertia, &mut workspace.y); // M (2 U_cur − U_prev)
    let dt2 = system.delta_t * system.delta_t;
    for (y, f) in workspace.y.iter_mut().zip(f_ext) {
        *y = std::array::from_fn(|c| y[c] / dt2 + f[c]);
    }
}
