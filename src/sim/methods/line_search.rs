//! The line search of L-BFGS and Newton: how far to go along a descent
//! direction `d` from `p`.
//!
//! With the slope `s = ∇E(p)ᵀd < 0`, a step length `t` is accepted when it
//! lowers the energy enough (Armijo's sufficient-decrease condition):
//!
//! ```text
//! E(p + t d) − E(p) ≤ c t s,      c = 10⁻⁴
//! ```
//!
//! Starting at `t = 1` (the full quasi-Newton or Newton step), or where
//! the last search ended: if it holds, the *expanding* search looks further
//! (up to `t = 64`), because on cloth the L-BFGS step with `H₀ = Q⁻¹` is
//! often two to eight times too short: it tries the minimum of the parabola
//! fitted to `E(p)`, the slope and the energy at `t` (Nocedal & Wright
//! §3.5), or doubles `t` while the energy keeps falling when that parabola
//! opens downward. The *backtracking* search (Newton's, whose full step is
//! right near the minimiser) keeps `t`. If it does not hold, `t` halves until it does,
//! and the search fails once the decrease to expect, `t |s|`, is below the
//! rounding `η` of the energy difference (or below `t = 10⁻¹⁰`): the energy
//! cannot be lowered along `d` measurably, and the method has stalled. Very
//! close to the minimiser the decrease a full step expects, `|s|`, falls
//! below that rounding itself (`η` of
//! [`StepEnergy::rounding`](crate::sim::energy::StepEnergy::rounding), or
//! `10⁻¹³ |E(p) − E(p⁰)|` if larger); the energy can then no longer judge a
//! step, and the full step is taken. Without `η` a search at a cloth's rest
//! halves `t` some thirty times per iteration, each time paying an energy,
//! to reject steps by their rounding.
//!
//! Energies are the cancellation-free differences `E(·) − E(p⁰)` of
//! [`energy`](crate::sim::energy), so that differences near rounding of `E`
//! itself can still be compared.
//!
//! Cost: one energy evaluation, `O(m + n)`, per trial length; L-BFGS's
//! usually needs one or two.
//!
//! Source: J. Nocedal & S. J. Wright, *Numerical Optimization*, 2nd ed.,
//! 2006, §3.1 (Armijo, backtracking), §3.5 (interpolation); the expansion
//! as in an independent numpy prototype of the step.

use super::block_vector::moved;
use crate::sim::energy::StepEnergy;

/// Armijo's sufficient-decrease constant `c`.
pub const ARMIJO: f64 = 1e-4;
/// The longest step the expanding search tries.
pub const LONGEST_STEP: f64 = 64.0;
/// Below this step length the search gives up.
pub const SHORTEST_STEP: f64 = 1e-10;

/// Relative size of the rounding of an energy difference `E(p) − E(p⁰)`,
/// the least rounding assumed whatever `η` says.
pub const ROUNDING: f64 = 1e-13;

/// Whether an accepted full step may grow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Search {
    Expanding,
    Backtracking,
}

/// The step length `t` along `d` from `p` and the energy difference there,
/// or `None` when no `t ≥ 10⁻¹⁰` satisfies Armijo's condition. The search
/// tries `first` (1 for a Newton or quasi-Newton step) first; `slope` is
/// `∇E(p)ᵀd`, `energy_at_p` is `E(p) − E(p⁰)`, `rounding` the step's `η`
/// ([`StepEnergy::rounding`](crate::sim::energy::StepEnergy::rounding)),
/// and `energy_at(t)` evaluates `E(p + t d) − E(p⁰)` (and whatever else the
/// caller wants kept at the trial point, such as its gradient).
pub fn line_search(
    search: Search,
    first: f64,
    slope: f64,
    energy_at_p: f64,
    rounding: f64,
    mut energy_at: impl FnMut(f64) -> f64,
) -> Option<(f64, f64)> {
    let mut t = first;
    let mut e = energy_at(t);
    let rounding = rounding.max(ROUNDING * energy_at_p.abs());
    if -slope <= rounding {
        // The decrease to expect is below the rounding of the energy: the
        // energy cannot judge the step, so take it whole.
        return Some((t, e));
    }
    if e <= energy_at_p + ARMIJO * t * slope {
        if search == Search::Expanding {
            return Some(expand(t, e, slope, energy_at_p, energy_at));
        }
        return Some((t, e));
    }
    while t > SHORTEST_STEP {
        t *= 0.5;
        if -t * slope <= rounding {
            return None; // what is left to expect is rounding
        }
        e = energy_at(t);
        if e <= energy_at_p + ARMIJO * t * slope {
            return Some((t, e));
        }
    }
    None
}

/// From an accepted `t` with energy `e`, a longer step if the energy falls
/// further there. The parabola through `E(p)`, the slope and `e` has its
/// minimum at `t* = −slope / 2c`, `c = (e − E(p) − slope t) / t²`: when that
/// is well beyond `t`, `t*` is tried once (the energy along `d` is close to
/// a parabola, so it usually lands near the minimum); when the parabola
/// opens downward (`c ≤ 0`, the energy falls faster than linearly), `t`
/// doubles while the energy keeps falling. At most [`LONGEST_STEP`].
fn expand(
    mut t: f64,
    mut e: f64,
    slope: f64,
    energy_at_p: f64,
    mut energy_at: impl FnMut(f64) -> f64,
) -> (f64, f64) {
    let curvature = (e - energy_at_p - slope * t) / (t * t);
    if curvature > 0.0 {
        let minimum = (-slope / (2.0 * curvature)).min(LONGEST_STEP);
        if minimum > 1.5 * t {
            let e_minimum = energy_at(minimum);
            if e_minimum < e {
                return (minimum, e_minimum);
            }
        }
        return (t, e);
    }
    while t < LONGEST_STEP {
        let longer = energy_at(2.0 * t);
        if longer >= e {
            break;
        }
        t *= 2.0;
        e = longer;
    }
    (t, e)
}

/// `E(p + t d) − E(p⁰)`, with the trial point built in `trial`: the
/// evaluation of a line search that needs the energy alone.
pub fn energy_along(
    energy: &StepEnergy<'_>,
    p: &[[f64; 3]],
    d: &[[f64; 3]],
    trial: &mut [[f64; 3]],
    t: f64,
) -> f64 {
    moved(p, t, d, trial);
    energy.change(trial).total()
}
