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
//! Starting at `t = 1` (the full quasi-Newton or Newton step): if it holds,
//! the *expanding* search doubles `t` while the energy keeps falling (up to
//! `t = 64`), because on cloth the L-BFGS step is often far too short; the
//! *backtracking* search (Newton's, whose full step is right near the
//! minimiser) keeps `t = 1`. If it does not hold, `t` halves until it does,
//! and the search fails below `t = 10⁻¹⁰`: the energy cannot be lowered
//! along `d` to rounding, and the method has stalled. Very close to the
//! minimiser the decrease to expect, `|s|`, falls below the rounding of the
//! energy difference itself (`10⁻¹³ |E(p) − E(p⁰)|`); the energy can then
//! no longer judge a step, and the full step is taken.
//!
//! Energies are the cancellation-free differences `E(·) − E(p⁰)` of
//! [`energy`](crate::sim::energy), so that differences near rounding of `E`
//! itself can still be compared.
//!
//! Cost: one energy evaluation, `O(m + n)`, per trial length.
//!
//! Source: J. Nocedal & S. J. Wright, *Numerical Optimization*, 2nd ed.,
//! 2006, §3.1 (Armijo, backtracking); the expansion as in the project's
//! prototype (`shared/tools/convergence-prototype`).

use super::block_vector::moved;
use crate::sim::energy::StepEnergy;

/// Armijo's sufficient-decrease constant `c`.
pub const ARMIJO: f64 = 1e-4;
/// The longest step the expanding search tries.
pub const LONGEST_STEP: f64 = 64.0;
/// Below this step length the search gives up.
pub const SHORTEST_STEP: f64 = 1e-10;

/// Relative size of the rounding of an energy difference `E(p) − E(p⁰)`.
pub const ROUNDING: f64 = 1e-13;

/// Whether an accepted full step may grow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Search {
    Expanding,
    Backtracking,
}

/// The step length `t` along `d` from `p` and the energy difference there,
/// or `None` when no `t ≥ 10⁻¹⁰` satisfies Armijo's condition. `energy` is
/// `E(p) − E(p⁰)`; `trial` is scratch space.
pub fn line_search(
    energy: &StepEnergy<'_>,
    search: Search,
    p: &[[f64; 3]],
    d: &[[f64; 3]],
    slope: f64,
    energy_at_p: f64,
    trial: &mut [[f64; 3]],
) -> Option<(f64, f64)> {
    let mut energy_at = |t: f64| {
        moved(p, t, d, trial);
        energy.change(trial).total()
    };
    let mut t = 1.0;
    let mut e = energy_at(t);
    if -slope <= ROUNDING * energy_at_p.abs() {
        // The decrease to expect is below the rounding of the energy: the
        // energy cannot judge the step, so take it whole.
        return Some((t, e));
    }
    if e <= energy_at_p + ARMIJO * slope {
        while search == Search::Expanding && t < LONGEST_STEP {
            let longer = energy_at(2.0 * t);
            if longer >= e {
                break;
            }
            t *= 2.0;
            e = longer;
        }
        return Some((t, e));
    }
    while t > SHORTEST_STEP {
        t *= 0.5;
        e = energy_at(t);
        if e <= energy_at_p + ARMIJO * t * slope {
            return Some((t, e));
        }
    }
    None
}
