//! Five ways to solve one time step, and what they share.
//!
//! A step minimises the energy `E` of [`energy`](super::energy). The
//! assignment runs 50 local/global iterations and stops; each method here
//! instead iterates until the relative gradient over the free vertices,
//! `‖∇E(p)‖ / ‖∇E(p⁰)‖`, falls below a tolerance (or an iteration lowers
//! the energy by at most a given fraction of the step's decrease so far:
//! the energy tolerance), or a budget of iterations is spent. A floor can
//! hold those rules back until the energy has fallen by `N` times the
//! first plain iteration's decrease (`at_least_plain`, see
//! `Monitor::after`):
//!
//! | method | one iteration | file |
//! |---|---|---|
//! | `plain` | `p ← Q⁻¹ b(p)`, the assignment's local/global step | [`plain`] |
//! | `chebyshev` | the same, extrapolated by Chebyshev weights `ω` | [`chebyshev`] |
//! | `anderson` | the same, extrapolated from the last `m` iterates | [`anderson`] |
//! | `lbfgs` | a quasi-Newton step with `Q` as the initial Hessian, line search | [`lbfgs`] |
//! | (`lbfgs`, plain first) | plain while it converges fast, then L-BFGS | [`plain_then_lbfgs`] |
//! | `newton` | the exact Hessian, factored every iteration, line search | [`newton`] |
//!
//! All of them reuse the one factorization of `Q` from the precomputation
//! (Newton factors its own Hessian). A method's work arrays are sized the
//! first time it runs and reused after, so no step after a method's first
//! allocates.
//!
//! This file is the registry: it makes each method's work arrays
//! ([`MethodWorkspaces`], [`prepare`]) and hands a step to its method
//! ([`solve`]). What every method uses lives below this folder:
//! [`GlobalStep`](super::global_step::GlobalStep) (the plain iteration and
//! solves with `Q`) and [`Monitor`] (the stopping
//! rules and the observer). [`factor_order`] runs `plain`'s iterations, to
//! the bit, with the positions kept in the sparse factor's order, when
//! nothing watches them.

pub mod anderson;
pub mod block_vector;
pub mod chebyshev;
pub mod factor_order;
pub mod lbfgs;
pub mod line_search;
pub mod newton;
pub mod plain;
pub mod plain_then_lbfgs;

use super::backend::LinearAlgebra;
use super::control::{Outcome, StepControl, StepMethod};
use super::error::SimulationError;
use super::global_step::StepContext;
use super::monitor::Monitor;

/// What the methods carry from one step to the next besides the two
/// states every step starts from: Chebyshev's estimate of `ρ` and Newton's
/// damping `μ`. A run continued from its last two frames takes it up
/// ([`Simulation::carry`](crate::sim::Simulation::carry)), so that its
/// next step gives the same bits as in a run that never stopped.
#[derive(Debug, Default, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Carried {
    pub chebyshev: chebyshev::Carried,
    pub newton_damping: f64,
}

/// The work arrays of each method, made the first time it runs.
#[derive(Debug, Clone, Default)]
pub struct MethodWorkspaces {
    /// `plain`'s springs in the factor's order (sparse backend only).
    pub factor_order: Option<factor_order::Workspace>,
    pub chebyshev: Option<chebyshev::Workspace>,
    pub anderson: Option<anderson::Workspace>,
    pub lbfgs: Option<lbfgs::Workspace>,
    pub newton: Option<newton::Workspace>,
    /// What an earlier run carried ([`MethodWorkspaces::carry`]), for the
    /// workspaces made after it was taken up.
    carried: Carried,
}

impl MethodWorkspaces {
    /// What the methods carry to the next step.
    pub fn carried(&self) -> Carried {
        let mut carried = self.carried;
        if let Some(work) = &self.chebyshev {
            carried.chebyshev = work.carried();
        }
        if let Some(work) = &self.newton {
            carried.newton_damping = work.damping;
        }
        carried
    }

    /// Takes up what an earlier run carried ([`MethodWorkspaces::carried`]).
    pub fn carry(&mut self, carried: Carried) {
        self.carried = carried;
        if let Some(work) = &mut self.chebyshev {
            work.carry(carried.chebyshev);
        }
        if let Some(work) = &mut self.newton {
            work.damping = carried.newton_damping;
        }
    }

    /// Bytes held by `plain`'s renumbered springs (the other methods'
    /// arrays are not counted: `docs/performance.md`, memory).
    pub fn bytes(&self) -> usize {
        self.factor_order.as_ref().map_or(0, |w| w.bytes())
    }
}

/// What [`prepare`] needs to know of the system.
pub struct Problem<'a, B: LinearAlgebra> {
    /// The number of vertices.
    pub n: usize,
    /// The springs `(i, j)`.
    pub springs: &'a [[usize; 2]],
    /// The factorization of `Q` (its ordering numbers `plain`'s springs).
    pub factorization: &'a mut B::Factorization,
    /// Are the pins exact constraints (not the penalty)?
    pub exact_pins: bool,
}

/// Makes the work arrays of `control`'s method the first time it runs (or
/// when the history window changed).
///
/// # Errors
/// An error of Newton's symbolic analysis of its Hessian.
pub fn prepare<B: LinearAlgebra>(
    workspaces: &mut MethodWorkspaces,
    problem: Problem<'_, B>,
    control: &StepControl,
) -> Result<(), SimulationError> {
    let n = problem.n;
    match control.method {
        StepMethod::Plain => prepare_plain::<B>(workspaces, problem, control),
        StepMethod::Chebyshev => {
            let carried = workspaces.carried.chebyshev;
            workspaces.chebyshev.get_or_insert_with(|| {
                let mut work = chebyshev::Workspace::new(n);
                work.carry(carried);
                work
            });
        }
        StepMethod::Anderson => {
            let window = control.window.max(1);
            if workspaces
                .anderson
                .as_ref()
                .is_none_or(|w| w.window() != window)
            {
                workspaces.anderson = Some(anderson::Workspace::new(n, control.window));
            }
        }
        StepMethod::Lbfgs => {
            let window = control.window.max(1);
            if workspaces
                .lbfgs
                .as_ref()
                .is_none_or(|w| w.window() != window)
            {
                workspaces.lbfgs = Some(lbfgs::Workspace::new(n, control.window));
            }
        }
        StepMethod::Newton => {
            if workspaces.newton.is_none() {
                let mut work = newton::Workspace::new(n, problem.springs)?;
                work.damping = workspaces.carried.newton_damping;
                workspaces.newton = Some(work);
            }
        }
    }
    Ok(())
}

/// `plain`'s springs in the factor's order (in blocks, one per thread,
/// when the factorization has threads), made once, when its loop can run
/// there: the sparse backend, penalty pins, no stopping rule (an observer,
/// known only later, sends it back to the textbook loop).
fn prepare_plain<B: LinearAlgebra>(
    workspaces: &mut MethodWorkspaces,
    problem: Problem<'_, B>,
    control: &StepControl,
) {
    let in_factor_order = !problem.exact_pins && !control.has_stopping_rule();
    if !in_factor_order {
        return;
    }
    if let Some(cholesky) = B::as_sparse_cholesky(problem.factorization) {
        // made once (again only if the factorization's threads changed)
        if let Some(work) = &workspaces.factor_order {
            if work.fits(cholesky) {
                return;
            }
        }
        let new_index = cholesky.symbolic().permutation().inverse();
        let work = factor_order::Workspace::new(problem.springs, new_index, cholesky);
        workspaces.factor_order = Some(work);
    }
}

const PREPARED: &str = "the step prepares its method's workspace first";

/// Solves the step of `context` from `p` (in place) by `control`'s method,
/// with the work arrays [`prepare`] made.
///
/// # Panics
/// When the method's workspace was not prepared.
pub fn solve<B: LinearAlgebra>(
    workspaces: &mut MethodWorkspaces,
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    match control.method {
        StepMethod::Plain => {
            let work = workspaces.factor_order.as_ref();
            plain::solve(context, control, work, p, monitor)
        }
        StepMethod::Chebyshev => {
            let work = workspaces.chebyshev.as_mut().expect(PREPARED);
            chebyshev::solve(context, control, work, p, monitor)
        }
        StepMethod::Anderson => {
            let work = workspaces.anderson.as_mut().expect(PREPARED);
            anderson::solve(context, control, work, p, monitor)
        }
        StepMethod::Lbfgs if control.plain_first => {
            let work = workspaces.lbfgs.as_mut().expect(PREPARED);
            plain_then_lbfgs::solve(context, control, work, p, monitor)
        }
        StepMethod::Lbfgs => {
            let work = workspaces.lbfgs.as_mut().expect(PREPARED);
            lbfgs::solve(context, control, work, p, monitor)
        }
        StepMethod::Newton => {
            let work = workspaces.newton.as_mut().expect(PREPARED);
            newton::solve(context, control, work, p, monitor)
        }
    }
}
