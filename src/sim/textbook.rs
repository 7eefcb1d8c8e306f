//! The handout's functions, written out: start reading here.
//!
//! The assignment asks for three functions, each dense and sparse:
//! `signed_incidence_matrix` ([`signed_incidence`](super::signed_incidence)),
//! the precomputation and the step. Here are the last two, as the handout
//! writes them, on the crate's textbook kernels:
//!
//! ```text
//! precomputation (once):
//!     rᵢⱼ = ‖Vᵢ − Vⱼ‖                      rest lengths
//!     M = diag(m), A (signed incidence), C (selection of the pinned vertices)
//!     Q = k AᵀA + M/Δt² + w CᵀC             w = 1e10, the pins' penalty
//!     L Lᵀ = P Q Pᵀ                         factored once (up-looking Cholesky; P: AMD)
//!
//! step (every frame), from p = U_cur:
//!     y = M (2 U_cur − U_prev)/Δt² + f_ext
//!     repeat 50 times:
//!         dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)/‖pᵢ − pⱼ‖        local step, one spring at a time
//!         b = k Aᵀd + y + w CᵀC V             right-hand side
//!         p = back_substitution(Lᵀ, forward_substitution(L, b))
//!     U_next = p
//! ```
//!
//! Nothing else happens on this path: no energy, no stopping rule, no SIMD,
//! no reuse of buffers across steps. `masssprings simulate --textbook`
//! (and `render`, `view`) runs exactly these functions. The sparse `L` is
//! the simplicial factor of `P Q Pᵀ`, with `P` the fill-reducing ordering
//! (AMD, as Eigen's `SimplicialLLT` does; `--ordering natural` for none),
//! so the solve permutes `b` before the substitutions and `p` after.
//!
//! The fast path ([`step`](super::step), what the program runs by default)
//! computes the same iterates with the supernodal factor and four springs
//! per instruction; `tests/sim/textbook.rs` holds one step of the two within
//! 1e-11 of each other (the largest distance of a vertex) on every bundled
//! scene, 1e-12 on the dense path.
//!
//! Cost: precomputation `O(nnz(L))` memory and the factorization's flops
//! (dense: `O(n³)`); each iteration `O(m)` for `d`, `O(m + n)` for `b` and
//! `O(nnz(L))` for the two substitutions (dense: `O(n²)`).
//! Source: the assignment (github.com/alecjacobson/computer-graphics-mass-spring-systems),
//! `fast_mass_springs_precomputation_{dense,sparse}.cpp` and
//! `fast_mass_springs_step_{dense,sparse}.cpp`; Liu et al. 2013, §3–4.

#![allow(non_snake_case)] // the handout's names: M, A, C, Q, L

use super::backend::{Dense, LinearAlgebra, Sparse, SparseFactorization};
use super::control::ITERATIONS;
use super::error::SimulationError;
use super::local_step::project_springs;
use super::precomputation::{
    assemble_q_cancellable, check_inputs, check_pins, check_q_fits, mass_matrix, rest_lengths,
    selection_matrix, PIN_WEIGHT,
};
use super::signed_incidence::signed_incidence_matrix;
use crate::linalg::dense::{back_substitution_dense, forward_substitution_dense};
use crate::linalg::sparse::triangular_solve::{
    back_substitution_sparse, forward_substitution_sparse,
};
use crate::linalg::sparse::{Method, Ordering};
use crate::linalg::Cancel;
use std::sync::atomic::{AtomicBool, Ordering as MemoryOrder};
use std::sync::Arc;

/// The handout's precomputation: its inputs the step reads again, and its
/// outputs `r`, `M`, `A`, `C` and the factorization of `Q`.
#[derive(Debug, Clone)]
pub struct Precomputation<B: LinearAlgebra> {
    /// `V`: the rest positions (the pins' targets are `C V`).
    pub V: Vec<[f64; 3]>,
    /// `E`: the springs `(i, j)`, 0-based.
    pub springs: Vec<[usize; 2]>,
    /// Spring stiffness `k`.
    pub k: f64,
    /// The pinned vertices (the handout's `b`).
    pub pinned: Vec<usize>,
    /// Time step `Δt`.
    pub delta_t: f64,
    /// The pins' penalty weight `w`.
    pub w: f64,
    /// `r`: rest length of every spring.
    pub r: Vec<f64>,
    /// `M = diag(m)`.
    pub M: B::Matrix,
    /// `A`: the signed incidence matrix (`m × n`).
    pub A: B::Matrix,
    /// `C`: the selection matrix of the pinned vertices.
    pub C: B::Matrix,
    /// `Q = k AᵀA + M/Δt² + w CᵀC`, kept to be looked at (the step only
    /// solves with its factorization).
    pub Q: B::Matrix,
    /// `L Lᵀ = Q` (sparse: `L Lᵀ = P Q Pᵀ`, simplicial).
    pub prefactorization: B::Factorization,
    /// Local/global iterations per step: the handout's 50.
    pub iterations: usize,
    /// Not the handout's: once this flag is set, a step stops before its
    /// next iteration and leaves `U_next` as it was (the viewer's stop
    /// button; `None` everywhere else).
    pub stop: Option<Arc<AtomicBool>>,
}

/// The handout's `fast_mass_springs_precomputation_sparse`: `Q` ordered
/// by AMD and factored row by row (up-looking, simplicial).
///
/// # Errors
/// [`SimulationError::InvalidInput`] for inconsistent sizes, indices or
/// masses; [`SimulationError::Linalg`] when `Q` is not positive definite.
pub fn fast_mass_springs_precomputation_sparse(
    V: &[[f64; 3]],
    springs: &[[usize; 2]],
    k: f64,
    m: &[f64],
    pinned: &[usize],
    delta_t: f64,
) -> Result<Precomputation<Sparse>, SimulationError> {
    precomputation_ordered(V, springs, k, m, pinned, delta_t, Ordering::Amd)
}

/// [`fast_mass_springs_precomputation_sparse`] with the fill-reducing
/// `ordering` of your choice (`Ordering::Natural`: none at all).
///
/// # Errors
/// As [`fast_mass_springs_precomputation_sparse`].
pub fn precomputation_ordered(
    V: &[[f64; 3]],
    springs: &[[usize; 2]],
    k: f64,
    m: &[f64],
    pinned: &[usize],
    delta_t: f64,
    ordering: Ordering,
) -> Result<Precomputation<Sparse>, SimulationError> {
    let how = factored_as_eigen(ordering);
    precomputation::<Sparse>(V, springs, k, m, pinned, delta_t, how, Cancel::NEVER)
}

/// How the handout factors `Q` (Eigen's `SimplicialLLT`): row by row
/// (simplicial), after the fill-reducing `ordering`.
pub(crate) fn factored_as_eigen(ordering: Ordering) -> SparseFactorization {
    SparseFactorization {
        ordering,
        method: Method::Simplicial,
        ..SparseFactorization::default()
    }
}

/// The handout's `fast_mass_springs_precomputation_dense`.
///
/// # Errors
/// As [`fast_mass_springs_precomputation_sparse`].
pub fn fast_mass_springs_precomputation_dense(
    V: &[[f64; 3]],
    springs: &[[usize; 2]],
    k: f64,
    m: &[f64],
    pinned: &[usize],
    delta_t: f64,
) -> Result<Precomputation<Dense>, SimulationError> {
    let how = SparseFactorization::default(); // the dense factor has one way
    precomputation::<Dense>(V, springs, k, m, pinned, delta_t, how, Cancel::NEVER)
}

/// The precomputation on either kind of matrix, as the handout writes it;
/// not the handout's: given up once `cancel` is set (the viewer's stop
/// button: the dense `AᵀA` and factorization take minutes on the skirt).
///
/// # Errors
/// As [`fast_mass_springs_precomputation_sparse`];
/// [`SimulationError::Cancelled`].
#[allow(clippy::too_many_arguments)] // the handout's six inputs, how Q is factored, what stops it
pub(crate) fn precomputation<B: LinearAlgebra>(
    V: &[[f64; 3]],
    springs: &[[usize; 2]],
    k: f64,
    m: &[f64],
    pinned: &[usize],
    delta_t: f64,
    how: SparseFactorization,
    cancel: Cancel<'_>,
) -> Result<Precomputation<B>, SimulationError> {
    let n = V.len();
    check_inputs(V, springs, m)?;
    check_pins(n, pinned, pinned.len())?;
    check_q_fits(springs, m, k, delta_t)?; // k, m/Δt² each within f64
    let w = PIN_WEIGHT;
    let r = rest_lengths(V, springs); // rᵢⱼ = ‖Vᵢ − Vⱼ‖
    let M = mass_matrix::<B>(m); // M = diag(m)
    let A = signed_incidence_matrix::<B>(n, springs);
    let C = selection_matrix::<B>(n, pinned);
    let Q = assemble_q_cancellable::<B>(k, &A, &M, delta_t, w, &C, cancel)?; // k AᵀA + M/Δt² + w CᵀC
    let prefactorization = B::factor_cancellable(&Q, how, cancel)?; // L Lᵀ = P Q Pᵀ (dense: Q), once
    Ok(Precomputation {
        V: V.to_vec(),
        springs: springs.to_vec(),
        k,
        pinned: pinned.to_vec(),
        delta_t,
        w,
        r,
        M,
        A,
        C,
        Q,
        prefactorization,
        iterations: ITERATIONS,
        stop: None,
    })
}

/// Has someone asked the step in progress to stop (`Precomputation::stop`)?
fn stop_requested<B: LinearAlgebra>(pre: &Precomputation<B>) -> bool {
    pre.stop
        .as_ref()
        .is_some_and(|flag| flag.load(MemoryOrder::Relaxed))
}

const SIZES: &str = "the precomputation fixed every size";

/// The handout's `fast_mass_springs_step_sparse`: `U_next` from `U_cur`
/// and `U_prev` under the forces `f_ext`.
///
/// # Panics
/// When a slice does not have one row per vertex, or `pre` was not
/// factored by the simplicial method.
pub fn fast_mass_springs_step_sparse(
    pre: &Precomputation<Sparse>,
    f_ext: &[[f64; 3]],
    U_prev: &[[f64; 3]],
    U_cur: &[[f64; 3]],
    U_next: &mut [[f64; 3]],
) {
    let n = U_cur.len();
    let y = inertial_term(pre, f_ext, U_prev, U_cur); // M (2 U_cur − U_prev)/Δt² + f_ext
    let pins = pin_term(pre); // w CᵀC V
    let (mut d, mut b) = (vec![[0.0; 3]; pre.springs.len()], vec![[0.0; 3]; n]);
    let (mut p, mut x) = (U_cur.to_vec(), vec![[0.0; 3]; n]);
    for _ in 0..pre.iterations {
        if stop_requested(pre) {
            return; // not the handout's: the viewer's stop button
        }
        project_springs(&pre.springs, &pre.r, &p, &mut d); // local step
        right_hand_side(pre, &d, &y, &pins, &mut b); // b = k Aᵀd + y + w CᵀC V
        solve_sparse(pre, &b, &mut x, &mut p); // p = back_substitution(Lᵀ, forward_substitution(L, b))
    }
    U_next.copy_from_slice(&p);
}

/// The global step of [`fast_mass_springs_step_sparse`]: `p = Q⁻¹ b`,
/// computed as `p = Pᵀ L⁻ᵀ L⁻¹ P b` with the simplicial factor (`x`
/// holds `P b` on the way, then the substitutions' results).
///
/// # Panics
/// When a slice does not have one row per vertex, or `pre` was not
/// factored by the simplicial method.
pub fn solve_sparse(
    pre: &Precomputation<Sparse>,
    b: &[[f64; 3]],
    x: &mut [[f64; 3]],
    p: &mut [[f64; 3]],
) {
    let L = pre
        .prefactorization
        .simplicial_factor()
        .expect("a simplicial factor");
    let perm = pre.prefactorization.symbolic().permutation().perm(); // row r of P b is b[perm[r]]
    assert!(b.len() == perm.len() && x.len() == perm.len() && p.len() == perm.len());
    for (row, &i) in x.iter_mut().zip(perm) {
        *row = b[i]; // x = P b
    }
    forward_substitution_sparse(L, x); // x = L⁻¹ x
    back_substitution_sparse(L, x); // x = L⁻ᵀ x
    for (row, &i) in x.iter().zip(perm) {
        p[i] = *row; // p = Pᵀ x
    }
}

/// The handout's `fast_mass_springs_step_dense`: the same iteration, the
/// three columns x, y, z of `b` solved one after another.
///
/// # Panics
/// When a slice does not have one row per vertex.
pub fn fast_mass_springs_step_dense(
    pre: &Precomputation<Dense>,
    f_ext: &[[f64; 3]],
    U_prev: &[[f64; 3]],
    U_cur: &[[f64; 3]],
    U_next: &mut [[f64; 3]],
) {
    let n = U_cur.len();
    let y = inertial_term(pre, f_ext, U_prev, U_cur); // M (2 U_cur − U_prev)/Δt² + f_ext
    let pins = pin_term(pre); // w CᵀC V
    let (L, Lt) = (pre.prefactorization.l(), pre.prefactorization.l_transpose());
    let (mut d, mut b) = (vec![[0.0; 3]; pre.springs.len()], vec![[0.0; 3]; n]);
    let (mut p, mut column) = (U_cur.to_vec(), vec![0.0; n]);
    for _ in 0..pre.iterations {
        if stop_requested(pre) {
            return; // not the handout's: the viewer's stop button
        }
        project_springs(&pre.springs, &pre.r, &p, &mut d); // local step
        right_hand_side(pre, &d, &y, &pins, &mut b); // b = k Aᵀd + y + w CᵀC V
        for c in 0..3 {
            for (value, row) in column.iter_mut().zip(&b) {
                *value = row[c]; // column c of b
            }
            forward_substitution_dense(L, &mut column).expect(SIZES); // L⁻¹ b
            back_substitution_dense(Lt, &mut column).expect(SIZES); // L⁻ᵀ L⁻¹ b
            for (row, &value) in p.iter_mut().zip(&column) {
                row[c] = value;
            }
        }
    }
    U_next.copy_from_slice(&p);
}

/// `y = M (2 U_cur − U_prev) / Δt² + f_ext`.
pub fn inertial_term<B: LinearAlgebra>(
    pre: &Precomputation<B>,
    f_ext: &[[f64; 3]],
    U_prev: &[[f64; 3]],
    U_cur: &[[f64; 3]],
) -> Vec<[f64; 3]> {
    let inertia: Vec<[f64; 3]> = U_cur
        .iter()
        .zip(U_prev)
        .map(|(cur, prev)| std::array::from_fn(|c| 2.0 * cur[c] - prev[c]))
        .collect();
    let mut y = vec![[0.0; 3]; U_cur.len()];
    B::mul_points(&pre.M, &inertia, &mut y); // M (2 U_cur − U_prev)
    let dt2 = pre.delta_t * pre.delta_t;
    for (y, f) in y.iter_mut().zip(f_ext) {
        *y = std::array::from_fn(|c| y[c] / dt2 + f[c]);
    }
    y
}

/// `w CᵀC V`, the pins' part of `b` (the same in every iteration).
pub fn pin_term<B: LinearAlgebra>(pre: &Precomputation<B>) -> Vec<[f64; 3]> {
    let mut pinned_rest = vec![[0.0; 3]; pre.pinned.len()];
    B::mul_points(&pre.C, &pre.V, &mut pinned_rest); // C V
    let mut term = vec![[0.0; 3]; pre.V.len()];
    B::transpose_mul_points(&pre.C, &pinned_rest, &mut term); // Cᵀ C V
    for row in &mut term {
        *row = row.map(|x| pre.w * x);
    }
    term
}

/// `b = k Aᵀd + y + w CᵀC V`.
pub fn right_hand_side<B: LinearAlgebra>(
    pre: &Precomputation<B>,
    d: &[[f64; 3]],
    y: &[[f64; 3]],
    pins: &[[f64; 3]],
    b: &mut [[f64; 3]],
) {
    B::transpose_mul_points(&pre.A, d, b); // Aᵀd
    for ((b, y), pin) in b.iter_mut().zip(y).zip(pins) {
        *b = std::array::from_fn(|c| pre.k * b[c] + y[c] + pin[c]);
    }
}
