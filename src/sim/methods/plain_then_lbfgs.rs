//! Plain iterations while they are fast, then L-BFGS: the step of
//! `--accuracy assignment`.
//!
//! The accuracy asks for every step to end at least as low as the
//! assignment's 50 plain iterations from `pᵗ` would. What that takes
//! depends on how fast plain converges on the step. With `δⱼ = E(xⱼ₋₁) −
//! E(xⱼ)` the decrease of plain's `j`-th iteration and `ρⱼ = δⱼ / δⱼ₋₁`:
//!
//! * **Plain is slow** (`ρ` near 1: the flag, the skirt): 50 plain
//!   iterations leave most of the step's error, and L-BFGS passes their
//!   energy in a few iterations.
//! * **Plain is fast** (`ρ` small: a spring, a chain, a cloth at rest):
//!   50 plain iterations reach the minimiser to rounding, and nothing can
//!   do better than reach it too; plain itself gets there in a few
//!   iterations, cheaper than L-BFGS's.
//!
//! So each step begins with plain iterations, measuring `δⱼ`, and after
//! iteration `j`:
//!
//! ```text
//! δⱼ ≤ 0                               stop: the energy no longer falls (rounding)
//! (N − j) δⱼ ≤ max(10⁻⁹ (E₀ − Eⱼ), η)   stop: plain-N can take off at most that more
//! ρⱼ > 0.2                             hand over to L-BFGS, floor Eⱼ − (N − j) δⱼ
//! ```
//!
//! with `ρ₁`, before there is a `δ₀`, predicted from the first step's
//! curvature ([`first_rate`]). When that hands over (the flag, the skirt),
//! L-BFGS starts from `pᵗ` as it would without plain first: the plain
//! iteration was the first trial of its first line search, so one plain
//! iteration is all the hybrid costs there.
//!
//! `η` is the rounding of an energy difference
//! ([`StepEnergy::rounding`](crate::sim::energy::StepEnergy::rounding)):
//! on a cloth near rest a step's whole decrease can be `10⁻⁹` or less, and
//! `10⁻⁹` of it is far below what the energy can resolve.
//!
//! The first two rest on the premise of `--at-least-plain` (plain's
//! decrease per iteration does not grow from here on: true near a
//! minimiser, where plain is a linear iteration and `ρⱼ` rises toward its
//! rate from below, `Monitor::after`): then plain-`N` takes off at most `(N
//! − j) δⱼ` after iteration `j`. A plain iteration never raises the
//! energy, so a computed rise is rounding: plain-`N` goes no lower than
//! that either. L-BFGS takes over from `xⱼ` with the floor moved to
//! what plain-`N` can reach by the same premise from `j`, `Eⱼ − (N − j)
//! δⱼ`, the energy rule above it, and one more stop: an iteration that
//! takes off at most [`CONVERGED`] of the step's decrease or
//! [`ROUNDING_SHARE`] of `η`, floor or not (L-BFGS is then at the
//! minimiser to well within `10⁻⁹` of the decrease, or to rounding, and
//! plain-`N` cannot go below the minimiser).
//!
//! The energy rule then weighs L-BFGS's decreases against what it has
//! gained since `xⱼ` (the whole step's gain is mostly plain's first
//! iteration, which took off the stiff modes, and against it any later
//! decrease looks small), and it also waits for a decrease no larger
//! than plain's last, `δⱼ`: until then L-BFGS is still moving faster than
//! plain was, and where plain speeds up after `j`, against the premise,
//! plain-`N` would pass it. (A 64 × 64 cloth with `k` ×0.1 buckles in its
//! steps 3–12; on step 3 plain's decreases grow sixteenfold from the sixth
//! iteration on. Without these two, four of its steps ended above
//! plain-50's energy.)
//!
//! The hand-over ratio [`HANDOVER`] comes from the cost: at a rate `ρ`,
//! plain needs about `ln(2·10⁻¹¹) / ln ρ` iterations for the second rule
//! (from `δ₁ ≈ E₀ − E₁` to `10⁻⁹ / 50` of it), 15 at `ρ = 0.2`, a third
//! of plain-50; slower than that, L-BFGS is cheaper.
//!
//! Source: the floor and the energy rule of `Monitor::after`; L-BFGS of
//! [`lbfgs`](super::lbfgs); the plain iteration of Liu et al. 2013.

use super::lbfgs;
use crate::sim::backend::LinearAlgebra;
use crate::sim::control::{Outcome, StepControl, StepMethod, Stop, ITERATIONS};
use crate::sim::global_step::StepContext;
use crate::sim::monitor::{Gradient, Monitor};

/// The plain decrease ratio `ρⱼ = δⱼ / δⱼ₋₁` above which L-BFGS takes over.
pub const HANDOVER: f64 = 0.2;

/// How much of the step's decrease plain-50 may still take off when plain
/// stops early: the accuracy's own margin.
pub const PLAIN_MARGIN: f64 = 1e-9;

/// An L-BFGS iteration taking off at most this fraction of the step's
/// decrease ends the step: converging at a rate `ρ`, the energy left after
/// an iteration that took off `δ` is `δ ρ / (1 − ρ)`, within
/// [`PLAIN_MARGIN`] of the decrease for any `ρ ≤ 0.99`.
pub const CONVERGED: f64 = 1e-11;

/// An L-BFGS iteration taking off at most this share of the energy's
/// rounding `η` ([`StepEnergy::rounding`]) also ends the step: at a rate
/// up to 0.9 what is left after it is at most nine times its decrease,
/// below `η`, where no comparison of energies can see it. (Stopping at
/// `η` itself left steps of cloths near rest a few `η` above plain-50's.)
///
/// [`StepEnergy::rounding`]: crate::sim::energy::StepEnergy::rounding
pub const ROUNDING_SHARE: f64 = 0.1;

/// How the plain iterations ended.
enum Plain {
    /// The step is done.
    Done(Outcome),
    /// L-BFGS takes over after `iterations`, at energy `energy`, with the
    /// floor `floor`.
    HandOver {
        iterations: usize,
        energy: f64,
        floor: f64,
        /// The last plain iteration's decrease `δⱼ`.
        decrease: f64,
    },
}

/// Iterates from `p` (in place): plain while it is fast, then L-BFGS.
pub(crate) fn solve<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    work: &mut lbfgs::Workspace,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    let (start_energy, start_measured) = (context.start_energy, context.start_measured);
    let rounding = context.rounding();
    let (iterations, energy, floor, decrease) =
        match plain_while_fast(context, p, monitor, rounding) {
            Plain::Done(outcome) => return outcome.ran_by(StepMethod::Plain),
            Plain::HandOver {
                iterations,
                energy,
                floor,
                decrease,
            } => (iterations, energy, floor, decrease),
        };
    monitor.stop_when_converged(CONVERGED, ROUNDING_SHARE * rounding);
    if iterations == 1 {
        // Slow from the first step on: L-BFGS from the first iterate, as
        // without plain first (its first trial is this plain iterate, and
        // it sets the floor from it).
        p.copy_from_slice(context.energy.start);
        context.global.hold_pins(p);
        (context.start_energy, context.start_measured) = (start_energy, start_measured);
        monitor.restart_at(start_energy);
    } else {
        monitor.set_floor(floor);
        monitor.restart_at(energy);
        monitor.keep_pace_with(decrease);
        context.start_energy = energy;
        context.start_measured = false; // L-BFGS makes ∇E at p itself
    }
    let outcome = lbfgs::solve(context, control, work, p, monitor);
    Outcome {
        iterations: iterations + outcome.iterations,
        ..outcome
    }
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
    let (mut energy, mut last_decrease) = (start, 0.0);
    for j in 1..=ITERATIONS {
        context.global_step(p);
        let new_energy = context.local_step_measuring(p, None);
        monitor.after(j, context, p, Gradient::Unknown, Some(new_energy)); // no floor yet: observed only
        let decrease = energy - new_energy;
        energy = new_energy;
        let left = (ITERATIONS - j) as f64 * decrease;
        if decrease <= 0.0 {
            return Plain::Done(Outcome::measured(j, Stop::Stalled, energy));
        }
        if left <= (PLAIN_MARGIN * (start - energy)).max(rounding) {
            return Plain::Done(Outcome::measured(j, Stop::AtLeastPlain, energy));
        }
        let rate = match j {
            1 => first_rate(context, monitor, p, decrease),
            _ => decrease / last_decrease,
        };
        if rate > HANDOVER {
            let floor = energy - left;
            return Plain::HandOver {
                iterations: j,
                energy,
                floor,
                decrease,
            };
        }
        last_decrease = decrease;
    }
    Plain::Done(Outcome::measured(ITERATIONS, Stop::Iterations, energy))
}

/// The rate `δ₂ / δ₁` plain's first decrease `decrease` predicts, before
/// a second iteration: the first step `s = x₁ − x₀ = −Q⁻¹∇E(x₀)` has the
/// slope `∇E(x₀)ᵀs = −sᵀQs`, and where `E` is quadratic along `s`, `δ₁ =
/// sᵀQs − ½ sᵀHs`; so `λ = sᵀHs / sᵀQs = 2 (1 − δ₁ / sᵀQs)`, and plain
/// shrinks that component by `1 − λ` an iteration, its energy by `(1 −
/// λ)²`. Near 1 where `Q` is much stiffer than `E` along `s` (the flag);
/// 0 where `Q` is its Hessian. `∇E(x₀)` is in the monitor's room: a step
/// with a stopping rule measures it where it starts, at `pᵗ`. `0` (no
/// prediction) when the slope is not a descent.
fn first_rate<B: LinearAlgebra>(
    context: &StepContext<'_, B>,
    monitor: &Monitor<'_, '_>,
    p: &[[f64; 3]],
    decrease: f64,
) -> f64 {
    let start = context.energy.start;
    let gradient = monitor.start_gradient();
    let mut slope = 0.0;
    for ((g, x), x0) in gradient.iter().zip(p).zip(start) {
        slope += (0..3).map(|c| g[c] * (x[c] - x0[c])).sum::<f64>();
    }
    if slope >= 0.0 || !slope.is_finite() {
        return 0.0;
    }
    let lambda = 2.0 * (1.0 - decrease / -slope);
    (1.0 - lambda) * (1.0 - lambda)
}
