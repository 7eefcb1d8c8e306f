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
//! ([`local_step_measuring`](crate::sim::global_step::StepContext::local_step_measuring)),
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
use crate::linalg::dense::{DenseCholesky, DenseMatrix};
use crate::sim::backend::LinearAlgebra;
use crate::sim::control::{Outcome, StepControl, Stop, MAX_WINDOW};
use crate::sim::global_step::StepContext;
use crate::sim::monitor::{Gradient, Monitor};

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
    /// right-hand side) is formed, in one pass over the vectors.
    fn push(&mut self, x: &[[f64; 3]]) {
        if !self.have_previous {
            subtract(&self.g, x, &mut self.f);
        } else {
            let slot = self.next_slot;
            self.next_slot = (slot + 1) % self.window();
            self.held = (self.held + 1).min(self.window());
            self.differences_and_inner_products(x, slot);
        }
        std::mem::swap(&mut self.f, &mut self.previous_f);
        // `g` becomes `previous_g` when the iteration ends ([`Workspace::retire_g`])
        self.have_previous = true;
    }

    /// `f ← g − x`, `Δf ← f − f_prev`, `Δg ← g − g_prev` (into `slot`),
    /// and, from the new values while they are in registers, the Gram row
    /// `Δf_slot · Δf_j` and `Δf_j · f` for every held `j`: one pass that
    /// reads each vector once. The vectors are read as flat arrays four
    /// values at a time, each product summed in four lanes (as
    /// [`dot`](super::block_vector::dot) does), so that the additions run
    /// four to an instruction and do not wait on each other. (With the
    /// differences formed in a pass of their own, then the products, the
    /// two took 7.7% of Anderson's run on the flag; fused, 6.3%; `perf
    /// record`.) `f` is left in `previous_f`'s
    /// place by [`Workspace::push`].
    fn differences_and_inner_products(&mut self, x: &[[f64; 3]], slot: usize) {
        let (held, window) = (self.held, self.window());
        let x = x.as_flattened();
        let len = x.len();
        // slices of one length, so that the loops run without bounds checks
        let (g, f) = (
            &self.g.as_flattened()[..len],
            &mut self.f.as_flattened_mut()[..len],
        );
        let previous_f = &self.previous_f.as_flattened()[..len];
        let previous_g = &self.previous_g.as_flattened()[..len];
        let delta_g = &mut self.delta_g[slot].as_flattened_mut()[..len];
        let (before, rest) = self.delta_f.split_at_mut(slot);
        let (newest, after) = rest.split_first_mut().expect("slot < window");
        let newest = &mut newest.as_flattened_mut()[..len];
        // the other held columns, and where each one's products go
        let (others, count) = held_columns(before, after, slot, (held, window), len);
        // four lanes of (Δf_slot · Δf_j, Δf_j · f) for each j
        let mut lanes = [[[0.0; 4]; 2]; MAX_WINDOW];
        let quads = len / 4;
        for q in (0..4 * quads).step_by(4) {
            let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
            for lane in 0..4 {
                let i = q + lane;
                b[lane] = g[i] - x[i];
                a[lane] = b[lane] - previous_f[i];
                f[i] = b[lane];
                newest[i] = a[lane];
                delta_g[i] = g[i] - previous_g[i];
            }
            let own = &mut lanes[slot];
            for lane in 0..4 {
                own[0][lane] += a[lane] * a[lane];
                own[1][lane] += a[lane] * b[lane];
            }
            for &(j, column) in &others[..count] {
                let (sums, d) = (&mut lanes[j], &column[q..q + 4]);
                for lane in 0..4 {
                    sums[0][lane] += a[lane] * d[lane];
                    sums[1][lane] += d[lane] * b[lane];
                }
            }
        }
        for i in 4 * quads..len {
            f[i] = g[i] - x[i];
            newest[i] = f[i] - previous_f[i];
            delta_g[i] = g[i] - previous_g[i];
        }
        let products = Products {
            lanes: &lanes,
            tail: 4 * quads,
            slot,
            newest,
            f,
            others: &others[..count],
        };
        products.store(&mut self.gram, &mut self.delta_f_dot_f);
    }

    /// At the end of an iteration: `gₖ` becomes `gₖ₋₁` (by trading buffers:
    /// the next global step overwrites `g`).
    fn retire_g(&mut self) {
        std::mem::swap(&mut self.g, &mut self.previous_g);
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
        if iteration == 1 {
            monitor.plain_first(energy); // no history yet: p = G(p⁰)
        }
        // the last local step was made at `p`
        if let Some(stop) = monitor.after(iteration, context, p, Gradient::InRoom, Some(energy)) {
            return Outcome::measured(iteration, stop, energy);
        }
    }
    Outcome::measured(control.iterations, Stop::Iterations, energy)
}

/// The held columns of `ΔF` other than `slot` (of `window`, the first
/// `held` in use), each with its number, as slices of length `len`; and
/// how many there are.
fn held_columns<'a>(
    before: &'a [Vec<[f64; 3]>],
    after: &'a [Vec<[f64; 3]>],
    slot: usize,
    (held, window): (usize, usize),
    len: usize,
) -> ([(usize, &'a [f64]); MAX_WINDOW], usize) {
    let mut others: [(usize, &[f64]); MAX_WINDOW] = [(0, &[]); MAX_WINDOW];
    let columns = before
        .iter()
        .chain(after.iter())
        .map(|c| &c.as_flattened()[..len]);
    let numbers = (0..slot).chain(slot + 1..window);
    let mut count = 0;
    for (j, column) in numbers.zip(columns).filter(|&(j, _)| j < held) {
        others[count] = (j, column);
        count += 1;
    }
    (others, count)
}

/// The inner products of the newest `Δf` as four lanes each, finished
/// with the values past the last full four.
struct Products<'a> {
    /// `(Δf_j · Δf_slot, Δf_j · f)` in four lanes, for every column `j`.
    lanes: &'a [[[f64; 4]; 2]; MAX_WINDOW],
    /// The first value the lanes did not take.
    tail: usize,
    slot: usize,
    newest: &'a [f64],
    f: &'a [f64],
    others: &'a [(usize, &'a [f64])],
}

impl Products<'_> {
    /// `l₀ + l₁ + l₂ + l₃` plus `x · y` over the tail.
    fn total(&self, l: [f64; 4], x: &[f64], y: &[f64]) -> f64 {
        let tail: f64 = x[self.tail..]
            .iter()
            .zip(&y[self.tail..])
            .map(|(u, v)| u * v)
            .sum();
        (l[0] + l[1]) + (l[2] + l[3]) + tail
    }

    /// Into the Gram matrix `ΔFᵀΔF` (row and column `slot`) and `ΔFᵀf`.
    fn store(&self, gram: &mut DenseMatrix, delta_f_dot_f: &mut [f64]) {
        let (slot, newest, f) = (self.slot, self.newest, self.f);
        gram[(slot, slot)] = self.total(self.lanes[slot][0], newest, newest);
        delta_f_dot_f[slot] = self.total(self.lanes[slot][1], newest, f);
        for &(j, column) in self.others {
            let product = self.total(self.lanes[j][0], newest, column);
            gram[(slot, j)] = product;
            gram[(j, slot)] = product;
            delta_f_dot_f[j] = self.total(self.lanes[j][1], column, f);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Workspace;

    /// Numbers in [−1, 1) from a fixed seed (a linear congruential
    /// generator: the test needs variety, not quality).
    fn numbers(seed: &mut u64, n: usize) -> Vec<[f64; 3]> {
        let mut next = || {
            *seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
        (0..n).map(|_| [next(), next(), next()]).collect()
    }

    fn dot(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .map(|(x, y)| x * y)
            .sum()
    }

    /// After every push, the history, the Gram matrix and `ΔFᵀf` are
    /// those of their definitions, while the ring fills and wraps (seven
    /// vertices: 21 numbers, so the four-lane pass has a tail).
    #[test]
    fn push_keeps_the_history_and_its_inner_products() {
        let (n, window) = (7, 3);
        let mut work = Workspace::new(n, window);
        let mut seed = 1;
        let (mut f_before, mut g_before): (Vec<[f64; 3]>, Vec<[f64; 3]>) = (vec![], vec![]);
        for k in 0..8 {
            let (x, g) = (numbers(&mut seed, n), numbers(&mut seed, n));
            work.g.copy_from_slice(&g);
            let slot = work.next_slot;
            work.push(&x);
            let f: Vec<[f64; 3]> = (0..n)
                .map(|i| std::array::from_fn(|c| g[i][c] - x[i][c]))
                .collect();
            assert_eq!(work.previous_f, f, "f at push {k}");
            if k > 0 {
                let delta = |a: &[[f64; 3]], b: &[[f64; 3]]| -> Vec<[f64; 3]> {
                    (0..n)
                        .map(|i| std::array::from_fn(|c| a[i][c] - b[i][c]))
                        .collect()
                };
                assert_eq!(work.delta_f[slot], delta(&f, &f_before), "Δf at push {k}");
                assert_eq!(work.delta_g[slot], delta(&g, &g_before), "Δg at push {k}");
                assert_eq!(work.held, k.min(window));
                for i in 0..work.held {
                    let want = dot(&work.delta_f[i], &f);
                    assert!(
                        (work.delta_f_dot_f[i] - want).abs() <= 1e-13,
                        "Δf·f {i}, push {k}"
                    );
                    for j in 0..work.held {
                        let want = dot(&work.delta_f[i], &work.delta_f[j]);
                        assert!(
                            (work.gram[(i, j)] - want).abs() <= 1e-13,
                            "gram {i} {j}, push {k}"
                        );
                    }
                }
            }
            work.retire_g();
            (f_before, g_before) = (f, g);
        }
    }
}
