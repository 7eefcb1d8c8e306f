//! The global step, and what a method works with during one step.
//!
//! The plain local/global iteration, written with the names of the
//! handout:
//!
//! ```text
//! dₑ = rₑ (pᵢ − pⱼ) / ‖pᵢ − pⱼ‖          local step (kept as Aᵀd)
//! b  = k Aᵀd + y + w CᵀC V              right-hand side
//! p  = Q⁻¹ b                            two triangular solves with the factor of Q
//! ```
//!
//! [`GlobalStep`] holds what the iteration reads (the springs, `r`, `k`,
//! `y`, `w CᵀC V`, the factorization of `Q`, exact pins if any) and does it
//! in place; it also offers the solves `v ← Q⁻¹ v` and products `Q x` the
//! accelerated methods build on. [`StepContext`] adds the step's energy, so
//! that a method can measure the iterates it makes.
//!
//! This is the fast path's iteration: `b` is made row by row where the
//! solve reads it, and the local step runs four springs at a time on a CPU
//! with AVX2. The same iteration written out as the handout writes it is
//! [`textbook`](super::textbook).
//!
//! Cost per iteration: `O(m)` local step, `O(n)` for `b`, one solve with
//! the prefactored `Q` (`O(nnz(L))`).
//! Source: Liu et al. 2013, Algorithm 1; the assignment, "Step 1–3".

use super::backend::LinearAlgebra;
use super::energy::StepEnergy;
use super::exact_pins::ExactPins;
use super::simd::local_step::project_springs_into_transpose;

/// The global step: the plain iteration `p ← Q⁻¹ b(p)` and solves with the
/// prefactored `Q`.
#[allow(non_snake_case)] // the handout's Q
pub struct GlobalStep<'a, B: LinearAlgebra> {
    pub springs: &'a [[usize; 2]],
    pub r: &'a [f64],
    pub k: f64,
    pub Q: &'a B::Matrix,
    /// `y = M ŷ / Δt² + f_ext`.
    pub y: &'a [[f64; 3]],
    /// `w CᵀC V`.
    pub pin_rhs: &'a [[f64; 3]],
    pub factorization: &'a mut B::Factorization,
    /// The reduced system when pins are exact, and the pins.
    pub exact_pins: Option<&'a mut ExactPins<B>>,
    pub pinned: &'a [usize],
    pub pin_targets: &'a [[f64; 3]],
    /// The last local step's `Aᵀd` (the local step keeps only that of
    /// `d`; with exact pins the global step then turns it into `b`, then
    /// `Q_ff⁻¹ b`).
    pub b: &'a mut [[f64; 3]],
}

impl<B: LinearAlgebra> GlobalStep<'_, B> {
    /// One local/global iteration, in place: `p ← Q⁻¹ (k Aᵀ d(p) + y + w CᵀC V)`
    /// (with exact pins: the free rows from `Q_ff`, the pins at their targets).
    pub fn iterate_in_place(&mut self, p: &mut [[f64; 3]]) {
        // the local step, kept as Aᵀd (one pass, d itself never stored)
        project_springs_into_transpose(self.springs, self.r, p, self.b);
        self.global_step(p);
    }

    /// The global step from the last local step's `Aᵀd` in `b`: `p ← Q⁻¹
    /// (k Aᵀ d + y + w CᵀC V)`.
    pub fn global_step(&mut self, p: &mut [[f64; 3]]) {
        let Some(exact) = self.exact_pins.as_mut() else {
            // b = k Aᵀd + y + w CᵀC V, made row by row as the solve reads it
            let (k, a_t_d, y, pin_rhs) = (self.k, &*self.b, self.y, self.pin_rhs);
            let b_row = |i: usize| -> [f64; 3] {
                std::array::from_fn(|c| k * a_t_d[i][c] + y[i][c] + pin_rhs[i][c])
            };
            B::solve_points_from(self.factorization, b_row, p);
            return;
        };
        for ((b, y), pin) in self.b.iter_mut().zip(self.y).zip(&exact.pin_rhs) {
            *b = std::array::from_fn(|c| self.k * b[c] + y[c] + pin[c]);
        }
        exact.solve(self.b);
        for (&c, &t) in self.pinned.iter().zip(self.pin_targets) {
            self.b[c] = t;
        }
        p.copy_from_slice(self.b);
    }

    /// `v ← Q⁻¹ v` (with exact pins: `Q_ff⁻¹` on the free rows, the pinned
    /// rows 0, so that no direction moves a pin).
    pub fn solve(&mut self, v: &mut [[f64; 3]]) {
        match self.exact_pins.as_mut() {
            None => B::solve_points(self.factorization, v),
            Some(exact) => exact.solve(v),
        }
    }

    /// `out ← Q x` (with exact pins: `(k AᵀA + M/Δt²) x`, pinned rows 0).
    /// `Q` is symmetric, so `Q x = Qᵀ x`: the transposed product sums each
    /// row of `out` in registers, where `Q x` column by column would add
    /// into rows of `out` scattered over memory.
    pub fn mul_q(&self, x: &[[f64; 3]], out: &mut [[f64; 3]]) {
        match self.exact_pins.as_ref() {
            None => B::transpose_mul_points(self.Q, x, out),
            Some(exact) => {
                B::transpose_mul_points(&exact.q_without_pins, x, out);
                for &c in self.pinned {
                    out[c] = [0.0; 3];
                }
            }
        }
    }

    /// With exact pins, puts the pinned rows of `p` back at their targets
    /// (an extrapolation `ω x̂ + (1 − ω) x` rounds them); nothing with the
    /// penalty.
    pub fn hold_pins(&self, p: &mut [[f64; 3]]) {
        if self.exact() {
            for (&c, &t) in self.pinned.iter().zip(self.pin_targets) {
                p[c] = t;
            }
        }
    }

    /// Are the pins exact constraints?
    pub fn exact(&self) -> bool {
        self.exact_pins.is_some()
    }
}

/// Everything a method works with during one step.
pub struct StepContext<'a, B: LinearAlgebra> {
    pub energy: StepEnergy<'a>,
    /// `pinned[i]`: is vertex `i` pinned?
    pub pinned: &'a [bool],
    pub global: GlobalStep<'a, B>,
    /// Did the step make the local step at the first iterate already (its
    /// `Aᵀd` in place, `∇E` there in the monitor's room)? So that the first
    /// iterate's local step shares its pass with the initial gradient (at
    /// `pᵗ`) or with the test of the inertial start
    /// ([`StepContext::local_step_at_start`]).
    pub start_measured: bool,
    /// `E − E(pᵗ)` at the first iterate (0 when it is `pᵗ`).
    pub start_energy: f64,
    /// The step's rounding `η` of an energy difference, once a method has
    /// asked for it ([`StepContext::rounding`]).
    pub rounding: Option<f64>,
}

impl<B: LinearAlgebra> StepContext<'_, B> {
    /// The rounding `η` of the step's energy differences
    /// ([`StepEnergy::rounding`](crate::sim::energy::StepEnergy::rounding)):
    /// a pass over the springs, made once per step and only by the methods
    /// that test their energies against it.
    pub fn rounding(&mut self) -> f64 {
        *self.rounding.get_or_insert_with(|| self.energy.rounding())
    }

    /// [`StepContext::local_step_measuring`] at the first iterate `p`,
    /// unless the step made it already; returns `E(p) − E(pᵗ)`.
    pub fn local_step_at_start(
        &mut self,
        p: &[[f64; 3]],
        gradient: Option<&mut [[f64; 3]]>,
    ) -> f64 {
        if self.start_measured {
            return self.start_energy;
        }
        self.local_step_measuring(p, gradient)
    }

    /// The local step at `p` (kept, as `Aᵀd`, for the next
    /// [`StepContext::global_step`]), returning `E(p) − E(p⁰)`: the local
    /// step's pass over the springs measures the energy on the way
    /// ([`spring_pass`](crate::sim::spring_pass)), so an iterate's energy
    /// costs one more pass over the vertices only. Peng et al. 2018 test
    /// each accelerated iterate this way.
    ///
    /// With `gradient` (the [`Monitor`](super::monitor::Monitor)'s room, when its stopping rule will
    /// test `p`) the same pass also makes `∇E(p)`.
    pub fn local_step_measuring(
        &mut self,
        p: &[[f64; 3]],
        gradient: Option<&mut [[f64; 3]]>,
    ) -> f64 {
        let a_t_d = &mut *self.global.b;
        self.energy
            .change_with_local_step(p, a_t_d, gradient)
            .total()
    }

    /// `out ← G(p)` from the last local step (its `Aᵀd`), made at `p`.
    pub fn global_step(&mut self, out: &mut [[f64; 3]]) {
        self.global.global_step(out);
    }
}
