//! Newton's method on the exact Hessian, damped when it is indefinite.
//!
//! Each iteration solves with the Hessian `H = ∇²E(p)` of
//! [`hessian`](crate::sim::hessian) (`3n × 3n`) and searches along the
//! Newton direction:
//!
//! ```text
//! H d = −∇E(p)                 sparse Cholesky, refactored every iteration
//! p ← p + t d                  t by backtracking from 1 (Armijo)
//! ```
//!
//! Near the minimiser `t = 1` and the error squares every iteration, which
//! makes it the reference the other methods are judged by. Far from it `H`
//! is indefinite (compressed springs), and its Cholesky factorization meets
//! a pivot that is not positive. Then the factorization is retried with
//! `H + μ diag(H)` (Levenberg–Marquardt), `μ` growing tenfold per failure
//! from `10⁻⁶`; after an iteration that took the full step, `μ` shrinks
//! tenfold (to 0 below `10⁻¹²`), so it adapts from step to step.
//! (Projecting each spring's block to positive semi-definite instead
//! crawled in the project's prototype.)
//!
//! The ordering and symbolic analysis are done once: `H`'s pattern is `Q`'s
//! with every entry a `3 × 3` block, and its ordering is `Q`'s AMD ordering
//! applied block by block. Every iteration then only refactors
//! numerically, on a factor about 9 times the size of `Q`'s.
//!
//! Cost per iteration: the Hessian `O(m + n)`, one numeric factorization of
//! the `3n × 3n` matrix (about 27 × the flops of `Q`'s), one solve, a
//! gradient and one or more energies.
//!
//! Source: J. Nocedal & S. J. Wright, *Numerical Optimization*, 2nd ed.,
//! 2006, §3.4 (Newton with Hessian modification), §10.3
//! (Levenberg–Marquardt); Davis 2006, ch. 4 (the factorization).

use super::block_vector::{dot, moved, scale};
use super::line_search::{energy_along, line_search, Search};
use crate::linalg::sparse::{Method, Ordering, SparseCholesky, SymbolicCholesky};
use crate::linalg::LinalgError;
use crate::sim::backend::LinearAlgebra;
use crate::sim::control::{Outcome, StepControl, Stop};
use crate::sim::energy::StepEnergy;
use crate::sim::error::SimulationError;
use crate::sim::global_step::StepContext;
use crate::sim::hessian::{expanded_permutation, vertex_pattern, Hessian};
use crate::sim::monitor::{Gradient, Monitor};

/// The first damping tried when `H` is not positive definite.
pub const FIRST_DAMPING: f64 = 1e-6;
/// Below this the damping is dropped.
pub const SMALLEST_DAMPING: f64 = 1e-12;
/// Above this the factorization is given up (the Hessian is not finite).
pub const LARGEST_DAMPING: f64 = 1e12;

/// Newton's Hessian, its factorization and work arrays.
#[derive(Debug, Clone)]
pub struct Workspace {
    hessian: Hessian,
    cholesky: SparseCholesky,
    /// `H`'s diagonal before damping.
    diagonal: Vec<f64>,
    /// The diagonal of `Q ⊗ I₃` (`H` with every spring at rest length),
    /// the scale of the damping.
    damping_scale: Vec<f64>,
    /// The Levenberg–Marquardt `μ`, kept from iteration to iteration and
    /// from step to step.
    pub damping: f64,
    gradient: Vec<[f64; 3]>,
    direction: Vec<[f64; 3]>,
    trial: Vec<[f64; 3]>,
}

impl Workspace {
    /// The pattern, ordering and symbolic analysis of `H` for `n` vertices
    /// joined by `springs`.
    ///
    /// # Errors
    /// From the ordering or the analysis (a network too large for 32-bit
    /// row indices).
    pub fn new(n: usize, springs: &[[usize; 2]]) -> Result<Self, SimulationError> {
        let hessian = Hessian::new(n, springs);
        let vertex_ordering = Ordering::Amd.permutation(&vertex_pattern(n, springs))?;
        let symbolic = SymbolicCholesky::with_permutation(
            &hessian.matrix,
            &expanded_permutation(&vertex_ordering),
        )?;
        // A first factorization of the identity on H's pattern sizes
        // everything; each iteration refactors.
        let mut identity = hessian.matrix.clone();
        for i in 0..3 * n {
            let index = hessian.diagonal_index(i / 3, i % 3);
            identity.values_mut()[index] = 1.0;
        }
        let cholesky = SparseCholesky::factor(symbolic, &identity, Method::Supernodal)?;
        Ok(Workspace {
            hessian,
            cholesky,
            diagonal: vec![0.0; 3 * n],
            damping_scale: vec![0.0; 3 * n],
            damping: 0.0,
            gradient: vec![[0.0; 3]; n],
            direction: vec![[0.0; 3]; n],
            trial: vec![[0.0; 3]; n],
        })
    }

    /// Factors `H + μ diag(H)`, raising `μ` until that is positive definite;
    /// false when even `μ = 10¹²` fails.
    fn factor_damped(&mut self) -> bool {
        for (i, d) in self.diagonal.iter_mut().enumerate() {
            *d = self.hessian.matrix.values()[self.hessian.diagonal_index(i / 3, i % 3)];
        }
        loop {
            for (i, (&d, &scale)) in self.diagonal.iter().zip(&self.damping_scale).enumerate() {
                let index = self.hessian.diagonal_index(i / 3, i % 3);
                self.hessian.matrix.values_mut()[index] = d + self.damping * scale;
            }
            match self.cholesky.refactor(&self.hessian.matrix) {
                Ok(()) => return true,
                Err(LinalgError::NotPositiveDefinite { .. }) if self.damping < LARGEST_DAMPING => {
                    self.damping = (10.0 * self.damping).max(FIRST_DAMPING);
                }
                Err(_) => return false,
            }
        }
    }

    /// `damping_scale = diag(Q ⊗ I₃)`: `mᵢ/Δt² + k·(springs at i)`, plus `w`
    /// at a pin, for each coordinate.
    fn set_damping_scale(&mut self, energy: &StepEnergy<'_>) {
        let inverse_dt2 = 1.0 / (energy.delta_t * energy.delta_t);
        let mut vertex_scale = |i: usize, value: f64| {
            for c in 0..3 {
                self.damping_scale[3 * i + c] += value;
            }
        };
        for (i, &mi) in energy.m.iter().enumerate() {
            vertex_scale(i, mi * inverse_dt2);
        }
        for &[i, j] in energy.springs {
            vertex_scale(i, energy.k);
            vertex_scale(j, energy.k);
        }
        for &c in energy.pinned {
            vertex_scale(c, energy.w);
        }
    }

    /// After an iteration: a full step means the model was good, so damp less.
    fn relax(&mut self, step_length: f64) {
        if step_length == 1.0 {
            self.damping *= 0.1;
            if self.damping < SMALLEST_DAMPING {
                self.damping = 0.0;
            }
        }
    }
}

impl Workspace {
    /// `direction = −H⁻¹ ∇E(p)` with the factored (damped) `H`, zero at
    /// the pinned vertices when the pins are exact.
    fn newton_direction(&mut self, pinned: &[bool], exact_pins: bool) {
        self.direction.copy_from_slice(&self.gradient);
        self.cholesky
            .solve_in_place(self.direction.as_flattened_mut());
        scale(&mut self.direction, -1.0);
        for (d, &pinned) in self.direction.iter_mut().zip(pinned) {
            if pinned && exact_pins {
                *d = [0.0; 3];
            }
        }
    }
}

/// Iterates from `p` (in place) until the control says stop.
pub(crate) fn solve<B: LinearAlgebra>(
    context: &mut StepContext<'_, B>,
    control: &StepControl,
    work: &mut Workspace,
    p: &mut [[f64; 3]],
    monitor: &mut Monitor<'_, '_>,
) -> Outcome {
    context.energy.gradient(p, &mut work.gradient);
    work.damping_scale.fill(0.0);
    work.set_damping_scale(&context.energy);
    let mut energy = context.start_energy; // E(p) − E(p⁰)
    if monitor.wants_plain_first() {
        // the plain iterate G(p⁰) = p⁰ − Q⁻¹ ∇E(p⁰), for the floor
        work.direction.copy_from_slice(&work.gradient);
        context.global.solve(&mut work.direction);
        scale(&mut work.direction, -1.0);
        let plain = energy_along(&context.energy, p, &work.direction, &mut work.trial, 1.0);
        monitor.plain_first(plain);
    }
    for iteration in 1..=control.iterations {
        work.hessian.assemble(&context.energy, p);
        if context.global.exact() {
            work.hessian.constrain(context.pinned);
        }
        if !work.factor_damped() {
            return Outcome::new(iteration - 1, Stop::Stalled);
        }
        work.newton_direction(context.pinned, context.global.exact());
        let slope = dot(&work.gradient, &work.direction);
        if slope.is_nan() || slope >= 0.0 {
            return Outcome::new(iteration - 1, Stop::Stalled);
        }
        let (direction, trial) = (&work.direction, &mut work.trial);
        let rounding = context.rounding();
        let Some((t, new_energy)) =
            line_search(Search::Backtracking, 1.0, slope, energy, rounding, |t| {
                energy_along(&context.energy, p, direction, trial, t)
            })
        else {
            return Outcome::new(iteration - 1, Stop::Stalled);
        };
        moved(p, t, &work.direction, &mut work.trial);
        p.copy_from_slice(&work.trial);
        energy = new_energy;
        work.relax(t);
        context.energy.gradient(p, &mut work.gradient);
        let gradient = Gradient::Given(&work.gradient);
        if let Some(stop) = monitor.after(iteration, context, p, gradient, Some(energy)) {
            return Outcome::measured(iteration, stop, energy);
        }
    }
    Outcome::new(control.iterations, Stop::Iterations)
}
