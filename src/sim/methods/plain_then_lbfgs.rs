//! Plain iterations while they are fast, then L-BFGS from the better of
//! two starts: the step of `--accuracy assignment`.
//!
//! The accuracy asks for every step to end at least as low as the
//! assignment's 50 plain iterations from `pᵗ` would, `E₅₀`. A rule cannot
//! run those 50 iterations to learn `E₅₀` (that is what it saves), so it
//! bounds it from below by what it can measure cheaply. With `δⱼ = E(xⱼ₋₁)
//! − E(xⱼ)` the decrease of plain's `j`-th iteration and `ρⱼ = δⱼ / δⱼ₋₁`:
//!
//! * **Plain is fast** (`ρ` small: a spring, a chain, a cloth at rest):
//!   50 plain iterations reach the minimiser to rounding, nothing can do
//!   better than reach it too, and plain itself gets there in a few
//!   iterations, cheaper than L-BFGS's.
//! * **Plain is slow** (`ρ` near 1: the flag, the skirt): 50 plain
//!   iterations leave most of the step's decrease undone, and L-BFGS passes
//!   their energy in a few iterations, once it knows where to stop.
//!
//! So each step begins with plain iterations from `pᵗ`, and after iteration
//! `j`:
//!
//! ```text
//! δⱼ ≤ 0                               stop: the energy no longer falls (rounding)
//! (N − j) δⱼ ≤ max(10⁻⁹ (E₀ − Eⱼ), η)   stop: plain-N can take off at most that more
//! j ≥ 3 and ρⱼ > 0.2                   hand over, with the floor F = Eⱼ − (N − j) δⱼ
//! ```
//!
//! `η` is the rounding of an energy difference
//! ([`StepEnergy::rounding`](crate::sim::energy::StepEnergy::rounding)).
//! The floor rests on the premise of `--at-least-plain`: while plain's
//! decrease per iteration does not grow, plain-`N` takes off at most `(N −
//! j) δⱼ` after iteration `j`, so `F ≤ E₅₀`.
//!
//! **Why not after the first iteration.** Plain's first decrease is
//! dominated by the stiff modes (springs pulled back to their lengths),
//! which die within an iteration or two; after them plain's decrease
//! settles at the pace of the slow modes. `E₁ − 49 δ₁` therefore lies far
//! below `E₅₀` on a cloth that moves smoothly: along the accuracy's own run
//! of the flag a median 3.9 times plain-50's whole decrease below it, up to
//! 13 times, often below the minimum itself, and L-BFGS chasing it ran to
//! its budget on nearly every step. After the third iteration the floor
//! lies a median 0.28 of that decrease below `E₅₀` (`masssprings converge
//! data/flag.json --steps 100 --accuracy assignment --oracle F.png`
//! measures both, and what a rule spends against an oracle that knows
//! `E₅₀`). The second iteration shows the slow modes' pace, and the third
//! whether that pace grows ([`FEWEST_PLAIN`]).
//!
//! **Two starts.** Where the cloth moves smoothly, the inertial prediction
//! `ŷ = 2pᵗ − pᵗ⁻¹` is already close to the minimiser, often below `E₅₀`
//! itself. So the descent starts from the lower of the plain iterate `xⱼ`
//! and `ŷ` (its energy costs one pass over the springs, made before the
//! plain iterations).
//!
//! **The energy rule above the floor.** The premise fails where the cloth
//! buckles or swings through: plain's decreases grow again after a few
//! iterations (`ρ > 1`), and plain-50 ends far below any floor its first
//! iterations predict (the skirt's swing: `masssprings converge
//! data/skirt.json --step 10 --methods plain --iterations 200`). Most such
//! steps look like any
//! other in their first iterations. What tells them apart is L-BFGS
//! itself: where the energy still falls steeply, its decreases stay large.
//! So the descent stops only past the floor *and* at an iteration that
//! takes off at most [`ASSIGNMENT_ENERGY_TOLERANCE`] of what the descent
//! has gained since it began. Where a plain decrease already grew before
//! the hand-over, the premise has failed in plain sight, and the energy
//! rule also waits for a decrease no larger than plain's last, `δⱼ` (a
//! pace that plain-50 itself keeps, or passes). And the descent stops,
//! floor or not, at an iteration that takes off at most [`CONVERGED`] of
//! the step's decrease, or once its next direction `d` promises at most
//! [`ROUNDING_SHARE`] of `η` (`−∇Eᵀd`): it is then at the minimiser, which
//! plain-`N` cannot pass.
//!
//! The hand-over ratio [`HANDOVER`] comes from the cost: at a rate `ρ`,
//! plain needs about `ln(2·10⁻¹¹) / ln ρ` iterations for the second rule
//! (from `δ₁ ≈ E₀ − E₁` to `10⁻⁹ / 50` of it), 15 at `ρ = 0.2`, a third
//! of plain-50; slower than that, L-BFGS is cheaper.
//!
//! Source: the floor and the energy rule of `Monitor::after`; L-BFGS of
//! [`lbfgs`]; the inertial start of projective dynamics
//! (Bouaziz et al. 2014, Algorithm 1); the plain iteration of Liu et al.
//! 2013.
//!
//! [`ASSIGNMENT_ENERGY_TOLERANCE`]: crate::sim::control::ASSIGNMENT_ENERGY_TOLERANCE

use super::lbfgs;
use crate::sim::backend::LinearAlgebra;
use crate::sim::control::{Outcome, StepControl, StepMethod, Stop, ITERATIONS};
use crate::sim::global_step::StepContext;
use crate::sim::monitor::{Gradient, Monitor};

/// The plain decrease ratio `ρⱼ = δⱼ / δⱼ₋₁` above which L-BFGS takes over.
pub const HANDOVER: f64 = 0.2;

/// The plain iterations before L-BFGS may take over: the first one's
/// decrease is the stiff modes', the second shows the slow modes' pace, the
/// third whether that pace grows (this file's header).
pub const FEWEST_PLAIN: usize = 3;

/// How much of the step's decrease plain-50 may still take off when plain
/// stops early: the accuracy's own margin.
pub const PLAIN_MARGIN: f64 = 1e-9;

/// An L-BFGS iteration taking off at most this fraction of the step's
/// decrease ends the step: converging at a rate `ρ`, the energy left after
/// an iteration that took off `δ` is `δ ρ / (1 − ρ)`, within
/// [`PLAIN_MARGIN`] of the decrease for any `ρ ≤ 0.99`.
pub const CONVERGED: f64 = 1e-11;

/// An L-BFGS direction `d` whose slope promises at most this share of the
/// energy's rounding `η` ([`StepEnergy::rounding`]), `−∇Eᵀd ≤ 0.1 η`, also
/// ends the step: a quadratic model along it has `−∇Eᵀd / 2` left to take
/// off, below what any comparison of energies can see. The test is on the
/// slope, not on a decrease: a decrease measured between two energies is
/// itself rounded to about `η`, and one that looks like nothing can stop a
/// step a few `η` short of plain-50. (A share of 1 lets the line search,
/// which accepts a step it cannot judge, wander up by rounding before the
/// stop.)
///
/// [`StepEnergy::rounding`]: crate::sim::energy::StepEnergy::rounding
pub const ROUNDING_SHARE: f64 = 0.1;

/// How the plain iterations ended.
enum Plain {
    /// The step is done.
    Done(Outcome),
    /// The descent takes over after `iterations`, at energy `energy`, with
    /// the floor `floor`.
    HandOver {
        iterations: usize,
        energy: f64,
        floor: f64,
        /// The last plain iteration's decrease `δⱼ`, when some decrease
        /// grew on the way (`ρᵢ > 1`: the floor's premise fails).
        grew: Option<f64>,
    },
}

/// Iterates from `p` (in place): plain while it is fast, then L-BFGS from
/// the lower of the plain iterate and the inertial prediction, by the
/// rules of this file's header.
pub(crate) fn solve<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    work: &mut lbfgs::Workspace,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    let rounding = context.rounding();
    let inertial = inertial_energy(context, p);
    let (iterations, energy, floor, grew) = match plain_while_fast(context, p, monitor, rounding) {
        Plain::Done(outcome) => return outcome.ran_by(StepMethod::Plain),
        Plain::HandOver {
            iterations,
            energy,
            floor,
            grew,
        } => (iterations, energy, floor, grew),
    };
    if let Some(decrease) = grew {
        monitor.keep_pace_with(decrease);
    }
    let energy = if inertial < energy {
        p.copy_from_slice(context.energy.inertial_target);
        context.global.hold_pins(p);
        inertial
    } else {
        energy
    };
    monitor.stop_when_converged(CONVERGED, ROUNDING_SHARE * rounding);
    monitor.set_floor(floor);
    monitor.restart_at(energy);
    context.start_energy = energy;
    context.start_measured = false; // L-BFGS makes ∇E at p itself
    let outcome = lbfgs::solve(context, control, work, p, monitor);
    Outcome {
        iterations: iterations + outcome.iterations,
        ..outcome
    }
}

/// `E(ŷ) − E(pᵗ)` at the inertial prediction `ŷ = 2pᵗ − pᵗ⁻¹` with the
/// pins held, measured in `p`, which holds `pᵗ` and is given back so (the
/// pass measures only: the local step made at `pᵗ` stays in place).
fn inertial_energy<B: LinearAlgebra>(context: &StepContext<'_, B>, p: &mut [[f64; 3]]) -> f64 {
    p.copy_from_slice(context.energy.inertial_target);
    context.global.hold_pins(p);
    let energy = context.energy.change(p).total();
    p.copy_from_slice(context.energy.start);
    context.global.hold_pins(p);
    energy
}

/// Plain iterations from `p` (in place), by the rules of this file's
/// header, at most [`ITERATIONS`].
fn plain_while_fast<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
    rounding: f64,
) -> Plain {
    let start = context.local_step_at_start(p, None);
    let (mut energy, mut last_decrease) = (start, f64::INFINITY);
    let mut grew = false;
    for j in 1..=ITERATIONS {
        context.global_step(p);
        let new_energy = context.local_step_measuring(p, None);
        // No floor yet: the monitor only shows the iterate, or says the
        // step was cancelled.
        let cancelled = monitor.after(j, context, p, Gradient::Unknown, Some(new_energy));
        let decrease = energy - new_energy;
        energy = new_energy;
        if cancelled == Some(Stop::Cancelled) {
            return Plain::Done(Outcome::measured(j, Stop::Cancelled, energy));
        }
        let left = (ITERATIONS - j) as f64 * decrease;
        if decrease <= 0.0 {
            return Plain::Done(Outcome::measured(j, Stop::Stalled, energy));
        }
        if left <= (PLAIN_MARGIN * (start - energy)).max(rounding) {
            return Plain::Done(Outcome::measured(j, Stop::AtLeastPlain, energy));
        }
        grew |= decrease > last_decrease;
        if j >= FEWEST_PLAIN && decrease > HANDOVER * last_decrease {
            return Plain::HandOver {
                iterations: j,
                energy,
                floor: energy - left,
                grew: grew.then_some(decrease),
            };
        }
        last_decrease = decrease;
    }
    Plain::Done(Outcome::measured(ITERATIONS, Stop::Iterations, energy))
}
