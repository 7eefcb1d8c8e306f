//! Pins as exact constraints instead of a penalty (`--pins exact`).
//!
//! The assignment pins vertex `c` with the penalty `½ w ‖p_c − t_c‖²`,
//! `w = 1e10`: cheap to write, but the pins drift by `force / w` and `Q`
//! gets entries ten orders of magnitude larger than its others, which
//! costs accuracy in the solves. Instead, the pinned positions can be
//! removed from the unknowns. Split the vertices into free `f` and pinned
//! `p` ones, with `p_p = t` fixed; the global step's system
//! `(k AᵀA + M/Δt²) p = k Aᵀd + y` then reads, on the free rows,
//!
//! ```text
//! Q_ff p_f = (k Aᵀd + y)_f − k (AᵀA)_fp t        Q_ff = k A_fᵀA_f + M_f/Δt²
//! ```
//!
//! with `A_f` the columns of `A` of the free vertices. `Q_ff` is smaller,
//! free of the penalty, and still constant: it is factored once. The
//! coupling `−k AᵀA t̄` (`t̄`: the targets at the pinned rows, 0 elsewhere)
//! is computed once too, and takes the place of `w CᵀC V` in `b`. The
//! energy loses its pin term (`w = 0`) and the methods move only free
//! vertices: a solve `v ← Q⁻¹ v` leaves the pinned rows at 0.
//!
//! Changing the pins (dragging) changes which vertices are free, so it
//! redoes this precomputation, symbolic analysis included.
//!
//! Cost: one extra `n_f × n_f` factorization at precomputation; per solve,
//! a gather and a scatter `O(n)` around the solve with `Q_ff`.
//!
//! Source: the standard elimination of Dirichlet conditions (e.g. Bathe,
//! *Finite Element Procedures*, 1996, §4.2.2); Liu et al. 2013, §4 (the
//! penalty it replaces).

use super::backend::{LinearAlgebra, SparseFactorization};
use super::error::SimulationError;
use super::signed_incidence::{
    incidence_mul_points, incidence_transpose_mul_points, signed_incidence_entries,
    signed_incidence_matrix,
};

/// What the reduced system is made from: the network, its parameters and
/// its pins (all plain inputs, so that the precomputation can call this
/// without lending itself).
#[derive(Debug, Clone, Copy)]
pub struct PinnedNetwork<'a> {
    /// The springs `(i, j)`.
    pub springs: &'a [[usize; 2]],
    /// The masses, one per vertex.
    pub m: &'a [f64],
    /// Spring stiffness.
    pub k: f64,
    /// Time step.
    pub delta_t: f64,
    /// The pinned vertices, and where each is held.
    pub pinned: &'a [usize],
    pub targets: &'a [[f64; 3]],
}

/// The reduced system of the free vertices.
#[derive(Debug, Clone)]
pub struct ExactPins<B: LinearAlgebra> {
    /// The free vertices, in order: reduced unknown `q` is vertex `free[q]`.
    pub free: Vec<usize>,
    /// `k AᵀA + M/Δt²` (`n × n`, no penalty), for products with `Q`.
    pub q_without_pins: B::Matrix,
    /// The factorization of `Q_ff`.
    pub factorization: B::Factorization,
    /// `−k AᵀA t̄`, the pins' constant part of `b`.
    pub pin_rhs: Vec<[f64; 3]>,
    /// Room for the free rows of a right-hand side.
    buffer: Vec<[f64; 3]>,
    /// How `Q_ff` was ordered and factored.
    pub how: SparseFactorization,
}

impl<B: LinearAlgebra> ExactPins<B> {
    /// The reduced system of the network `network` with its pins held at
    /// their targets, `Q_ff` ordered and factored as `how` says.
    ///
    /// # Errors
    /// [`SimulationError::Linalg`] when `Q_ff` is not positive definite.
    pub fn new(
        network: &PinnedNetwork<'_>,
        how: SparseFactorization,
    ) -> Result<Self, SimulationError> {
        let PinnedNetwork {
            springs,
            m,
            k,
            delta_t,
            pinned,
            targets,
        } = *network;
        let n = m.len();
        let mut is_pinned = vec![false; n];
        for &c in pinned {
            is_pinned[c] = true;
        }
        let free: Vec<usize> = (0..n).filter(|&i| !is_pinned[i]).collect();
        let springs_and_mass = |columns: &[usize], a: &B::Matrix| -> B::Matrix {
            let dt2 = delta_t * delta_t;
            let mass = B::from_entries(
                columns.len(),
                columns.len(),
                columns.iter().enumerate().map(|(q, &i)| (q, q, m[i] / dt2)),
            );
            B::combine(k, &B::gram(a), 1.0, &mass)
        };
        let all: Vec<usize> = (0..n).collect();
        let q_without_pins = springs_and_mass(&all, &signed_incidence_matrix::<B>(n, springs));
        let a_free = free_columns::<B>(springs, n, &free);
        let factorization = B::factor(&springs_and_mass(&free, &a_free), how)?;
        let mut reduced = ExactPins {
            buffer: vec![[0.0; 3]; free.len()],
            free,
            q_without_pins,
            factorization,
            pin_rhs: vec![[0.0; 3]; n],
            how,
        };
        reduced.set_targets(springs, k, pinned, targets);
        Ok(reduced)
    }

    /// Moves the pins to `targets`: `pin_rhs = −k Aᵀ (A t̄)`, with `A`
    /// the signed incidence matrix of `springs` (taken from the list).
    pub fn set_targets(
        &mut self,
        springs: &[[usize; 2]],
        k: f64,
        pinned: &[usize],
        targets: &[[f64; 3]],
    ) {
        let n = self.pin_rhs.len();
        let mut t_bar = vec![[0.0; 3]; n];
        for (&c, &t) in pinned.iter().zip(targets) {
            t_bar[c] = t;
        }
        let mut a_t = vec![[0.0; 3]; springs.len()];
        incidence_mul_points(springs, &t_bar, &mut a_t);
        incidence_transpose_mul_points(springs, &a_t, &mut self.pin_rhs);
        for row in &mut self.pin_rhs {
            *row = row.map(|x| -k * x);
        }
    }

    /// `v_f ← Q_ff⁻¹ v_f` on the free rows; the pinned rows become 0.
    pub fn solve(&mut self, v: &mut [[f64; 3]]) {
        for (slot, &i) in self.buffer.iter_mut().zip(&self.free) {
            *slot = v[i];
        }
        B::solve_points(&mut self.factorization, &mut self.buffer);
        v.fill([0.0; 3]);
        for (value, &i) in self.buffer.iter().zip(&self.free) {
            v[i] = *value;
        }
    }
}

/// `A_f`: the signed incidence matrix with only the columns of the `free`
/// vertices (a spring's entry at a pinned end is dropped).
fn free_columns<B: LinearAlgebra>(springs: &[[usize; 2]], n: usize, free: &[usize]) -> B::Matrix {
    let mut new_column = vec![usize::MAX; n];
    for (q, &i) in free.iter().enumerate() {
        new_column[i] = q;
    }
    let entries = signed_incidence_entries(springs)
        .filter(|&(_, i, _)| new_column[i] != usize::MAX)
        .map(|(e, i, v)| (e, new_column[i], v));
    B::from_entries(springs.len(), free.len(), entries)
}
