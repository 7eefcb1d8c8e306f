//! Anderson acceleration of the local/global iteration, with an energy
//! safeguard.
//!
//! The plain iteration looks for a fixed point `x = G(x)`. Anderson (type
//! II) keeps the last `m` residuals `fₖ = G(xₖ) − xₖ` and images `G(xₖ)`,
//! and takes the combination of them whose residual is smallest:
//!
//! ```text
//! gₖ = G(xₖ),  fₖ = gₖ − xₖ
//! ΔF = [fₖ₋ₘ₊₁ − fₖ₋ₘ, …, fₖ − fₖ₋₁],   ΔG likewise from the gⱼ
//! γ  = argmin ‖fₖ − ΔF γ‖              (m unknowns: normal equations
//!                                        (ΔFᵀΔF + λI) γ = ΔFᵀ fₖ)
//! xₖ₊₁ = gₖ − ΔG γ
//! ```
//!
//! It is a multisecant quasi-Newton method on `f(x) = 0`. Far from the
//! minimiser the extrapolation can raise the energy, so (Peng et al. 2018)
//! the accelerated iterate is accepted only if its energy is not above the
//! last accepted one; otherwise the plain iterate `gₖ` is taken (its energy
//! never rises) and the history is cleared.
//!
//! The `m × m` normal equations are factored by the crate's dense Cholesky
//! ([`DenseCholesky::refactor`], no allocation); the Gram matrix `ΔFᵀΔF` is
//! updated by one row per iteration, `m` inner products. `λ` is `10⁻¹⁰` of
//! its mean diagonal, a Tikhonov term that keeps nearly parallel columns
//! from blowing `γ` up.
//!
//! The energy of a candidate is measured by the local step made at it
//! ([`local_step_measuring`](super::StepContext::local_step_measuring)),
//! which the next global step needs anyway: testing costs a pass over the
//! vertices, and a rejection one more local step.
//!
//! Cost per iteration: one plain iteration, one pass over the vertices for
//! the energy (and a second local step after a rejection), and `O(m n)`
//! for the inner products and the combination. With a tolerance, the same
//! local step also makes the gradient the rule tests (its spring forces
//! added on the way, one more pass over the vertices).
//!
//! Sources: D. G. Anderson, "Iterative procedures for nonlinear integral
//! equations", J. ACM 12(4), 1965; H. F. Walker & P. Ni, "Anderson
//! acceleration for fixed-point iterations", SIAM J. Numer. Anal. 49(4),
//! 2011 (type II form); Y. Peng, B. Deng, J. Zhang, F. Geng, W. Qin,
//! L. Liu, "Anderson Acceleration for Geometry Optimization and Physics
//! Simulation", ACM TOG 37(4), 2018, Algorithm 1 (the energy safeguard).

use super::block_vector::subtract;
use super::{Gradient, Monitor, Outcome, StepContext, StepControl, Stop, MAX_WINDOW};
use crate::linalg::dense::{DenseCholesky, DenseMatrix};
use crate::sim::backend::LinearAlgebra;

/// Anderson's history and work arrays.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// The ring of the last `m` differences `Δf` and `Δg`.
    delta_f: Vec<Vec<[f64; 3]>>,
    delta_g: Vec<Vec<[f64; 3]>>,
    /// Where the next difference goes, and how many are held.
    next_slot: usize,
    held: usize,
    /// `fₖ₋₁`, `gₖ₋₁` (valid when `have_previous`).
    previous_f: Vec<[f64; 3]>,
    previous_g: Vec<[f64; 3]>,
    have_previous: bool,
    /// `gₖ`, `fₖ`.
    g: Vec<[f64; 3]>,
    f: Vec<[f64; 3]>,
    /// `ΔFᵀΔF` of the held columns (by slot), and the normal equations.
    gram: DenseMatrix,
    normal: DenseMatrix,
    cholesky: DenseCholesky,
    gamma: Vec<f64>,
    /// `Δfⱼ · fₖ` of the held columns (by slot).
    delta_f_dot_f: Vec<f64>,
}

impl Workspace {
    pub fn new(n: usize, window: usize) -> Self {
        let window = window.clamp(1, MAX_WINDOW);
        Workspace {
            delta_f: vec![vec![[0.0; 3]; n]; window],
            delta_g: vec![vec![[0.0; 3]; n]; window],
            next_slot: 0,
            held: 0,
            previous_f: vec![[0.0; 3]; n],
            previous_g: vec![[0.0; 3]; n],
            have_previous: false,
            g: vec![[0.0; 3]; n],
            f: vec![[0.0; 3]; n],
            gram: DenseMatrix::zeros(window, window),
            normal: DenseMatrix::zeros(window, window),
            cholesky: DenseCholesky::factor(&DenseMatrix::identity(window))
                .expect("the identity is positive definite"),
            gamma: vec![0.0; window],
            delta_f_dot_f: vec![0.0; window],
        }
    }

    pub(crate) fn window(&self) -> usize {
        self.delta_f.len()
    }

    fn clear(&mut self) {
        self.held = 0;
        self.next_slot = 0;
        self.have_previous = false;
    }

    /// Records `fₖ = gₖ − xₖ` (with `gₖ` in `g`): the differences with
    /// `fₖ₋₁`, `gₖ₋₁` join the history (the oldest leaves when it is full),
    /// the Gram matrix gains their row, and `ΔFᵀfₖ` (the normal equations'
    /// right-hand side) is formed, in two passes over the vectors.
    fn push(&mut self, x: &[[f64; 3]]) {
        if !self.have_previous {
            subtract(&self.g, x, &mut self.f);
        } else {
            let slot = self.next_slot;
            self.differences(x, slot);
            self.next_slot = (slot + 1) % self.window();
            self.held = (self.held + 1).min(self.window());
            self.inner_products(slot);
        }
        std::mem::swap(&mut self.f, &mut self.previous_f);
        // `g` becomes `previous_g` when the iteration ends ([`Workspace::retire_g`])
        self.have_previous = true;
    }

    /// `f ← g − x`, `Δf ← f − f_prev`, `Δg ← g − g_prev` (into `slot`), in one
    /// pass; `f` is left in `previous_f`'s place by [`Workspace::push`].
    fn differences(&mut self, x: &[[f64; 3]], slot: usize) {
        let n = x.len();
        // slices of one length, so that the loop runs without bounds checks
        let (f, g) = (&mut self.f[..n], &self.g[..n]);
        let (previous_f, previous_g) = (&self.previous_f[..n], &self.previous_g[..n]);
        let (delta_f, delta_g) = (&mut self.delta_f[slot][..n], &mut self.delta_g[slot][..n]);
        for i in 0..n {
            for c in 0..3 {
                f[i][c] = g[i][c] - x[i][c];
                delta_f[i][c] = f[i][c] - previous_f[i][c];
                delta_g[i][c] = g[i][c] - previous_g[i][c];
            }
        }
    }

    /// At the end of an iteration: `gₖ` becomes `gₖ₋₁` (by trading buffers:
    /// the next global step overwrites `g`).
    fn retire_g(&mut self) {
        std::mem::swap(&mut self.g, &mut self.previous_g);
    }

    /// The Gram row `Δf_slot · Δf_j` and `Δf_j · f` for every held `j`, in
    /// one pass that reads each `Δf_j` once. The vectors are read as flat
    /// arrays four values at a time, each product summed in four lanes
    /// (as [`dot`](super::block_vector::dot) does), so that the additions
    /// run four to an instruction and do not wait on each other.
    fn inner_products(&mut self, slot: usize) {
        let held = self.held;
        let (newest, f) = (self.delta_f[slot].as_flattened(), self.f.as_flattened());
        let columns: [&[f64]; MAX_WINDOW] = std::array::from_fn(|j| {
            if j < held {
                self.delta_f[j].as_flattened()
            } else {
                &[]
            }
        });
        // four lanes of (Δf_slot · Δf_j, Δf_j · f) for each j
        let mut lanes = [[[0.0; 4]; 2]; MAX_WINDOW];
        let quads = newest.len() / 4;
        for q in (0..4 * quads).step_by(4) {
            let (a, b) = (&newest[q..q + 4], &f[q..q + 4]);
            for (sums, column) in lanes.iter_mut().zip(&columns[..held]) {
                let d = &column[q..q + 4];
                for lane in 0..4 {
                    sums[0][lane] += a[lane] * d[lane];
                    sums[1][lane] += d[lane] * b[lane];
                }
            }
        }
        // the lanes added, and the last values that did not fill four
        let total = |l: [f64; 4], x: &[f64], y: &[f64]| -> f64 {
            let tail: f64 = x[4 * quads..]
                .iter()
                .zip(&y[4 * quads..])
                .map(|(u, v)| u * v)
                .sum();
            (l[0] + l[1]) + (l[2] + l[3]) + tail
        };
        for (j, [with_newest, with_f]) in lanes.into_iter().take(held).enumerate() {
            let product = total(with_newest, newest, columns[j]);
            self.gram[(slot, j)] = product;
            self.gram[(j, slot)] = product;
            self.delta_f_dot_f[j] = total(with_f, columns[j], f);
        }
    }

    /// Solves for `γ` and writes `gₖ − ΔG γ` into `out`; false when the
    /// normal equations could not be factored.
    fn extrapolate(&mut self, out: &mut [[f64; 3]]) -> bool {
        let (window, held) = (self.window(), self.held);
        let mean_diagonal = (0..held).map(|j| self.gram[(j, j)]).sum::<f64>() / held as f64;
        let lambda = 1e-10 * mean_diagonal;
        for i in 0..window {
            for j in 0..window {
                self.normal[(i, j)] = match (i < held && j < held, i == j) {
                    (true, true) => self.gram[(i, j)] + lambda,
                    (true, false) => self.gram[(i, j)],
                    (false, true) => 1.0, // the identity beyond the history
                    (false, false) => 0.0,
                };
            }
            self.gamma[i] = if i < held { self.delta_f_dot_f[i] } else { 0.0 };
        }
        if self.cholesky.refactor(&self.normal).is_err()
            || self.cholesky.solve_in_place(&mut self.gamma).is_err()
        {
            return false;
        }
        self.combine(out);
        out.iter().flatten().all(|x| x.is_finite())
    }

    /// `out ← g − Σⱼ γⱼ Δgⱼ`, in one pass.
    fn combine(&self, out: &mut [[f64; 3]]) {
        let held = &self.delta_g[..self.held];
        for (i, o) in out.iter_mut().enumerate() {
            let mut sum = self.g[i];
            for (delta_g, &gamma) in held.iter().zip(&self.gamma) {
                for c in 0..3 {
                    sum[c] -= gamma * delta_g[i][c];
                }
            }
            *o = sum;
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
    work.clear();
    // The local step at each accepted iterate is made when it is accepted
    // (it measures the energy that decides), and used by the next global step.
    let mut energy = context.local_step_at_start(p, monitor.room_for_gradient());
    for iteration in 1..=control.iterations {
        context.global_step(&mut work.g);
        work.push(p);
        let accelerated = work.held > 0 && work.extrapolate(p);
        let accepted = accelerated && {
            context.global.hold_pins(p);
            let candidate = context.local_step_measuring(p, monitor.room_for_gradient());
            let lower = candidate <= energy;
            if lower {
                energy = candidate;
            }
            lower
        };
        if !accepted {
            // the safeguard: the plain iterate (whose energy cannot be
            // higher), and a fresh history
            p.copy_from_slice(&work.g);
            energy = context.local_step_measuring(p, monitor.room_for_gradient());
            if accelerated {
                work.clear();
            }
        }
        work.retire_g();
        // the last local step was made at `p`
        if monitor.after(iteration, context, p, Gradient::InRoom) {
            return Outcome::measured(iteration, Stop::Tolerance, energy);
        }
    }
    Outcome::measured(control.iterations, Stop::Iterations, energy)
}
