//! Every quantity of the handout on one scene, computed by the handout's
//! own functions in the handout's order (`sim::textbook`):
//!
//! ```text
//! precomputation: A, r, M, C, Q, and P, L with L Lᵀ = P Q Pᵀ
//! state:          U_prev = U_cur = V, then K − 1 steps of fast_mass_springs_step_sparse
//! step K:         y = inertial_term(U_prev, U_cur)
//!                 p = U_cur; for k = 1..N: d_k = project_springs(p)
//!                                          b_k = right_hand_side(d_k)
//!                                          p_k = solve_sparse(b_k)
//! ```
//!
//! The loop is the body of `fast_mass_springs_step_sparse`, the same three
//! calls, stopped after `N` iterations with every iterate kept: so `p_N`
//! is the handout's step with `iterations = N`, to the last bit (the tests
//! check it).

use super::quantities::{quantities, Quantity};
use crate::app::error::AppError;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::{CscMatrix, Ordering};
use masssprings::mesh::Scene;
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::local_step::project_springs;
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::textbook::{
    fast_mass_springs_step_sparse, inertial_term, pin_term, precomputation_ordered,
    right_hand_side, solve_sparse, Precomputation,
};
use masssprings::sim::{Sparse, DELTA_T};

/// Which step, how many of its iterations, the factor's ordering, and
/// the mistake to make (a student's folder, written by `mistaken.rs`).
#[derive(Debug, Clone, Copy)]
pub struct TraceOptions {
    /// 1-based step `K`.
    pub step: usize,
    /// Iterations `N` of step `K` to keep.
    pub iterations: usize,
    pub ordering: Ordering,
    pub mistake: Option<Mistake>,
}

/// A quantity's value, as it is written.
#[derive(Debug, Clone)]
pub enum Value {
    Sparse(CscMatrix),
    Dense(DenseMatrix),
}

/// Every quantity of a trace, in the order of [`quantities`].
pub fn trace(scene: &Scene, options: TraceOptions) -> Result<Vec<Value>, AppError> {
    let pre = precomputation_ordered(
        &scene.vertices,
        &scene.springs,
        scene.k,
        &scene.masses,
        &scene.pinned,
        DELTA_T,
        options.ordering,
    )
    .map_err(|e| AppError::Failed(format!("{}: {e}", scene.name)))?;
    let mut values = precomputed(&pre);
    let f_ext = vec![GRAVITY; scene.vertices.len()];
    let (u_prev, u_cur) = state_before(&pre, &f_ext, options.step);
    let y = inertial_term(&pre, &f_ext, &u_prev, &u_cur); // M (2 U_cur − U_prev)/Δt² + f_ext
    values.extend([&u_prev, &u_cur, &y].map(|rows| points(rows)));
    let pins = pin_term(&pre); // w CᵀC V
    let n = u_cur.len();
    let (mut d, mut b) = (vec![[0.0; 3]; pre.springs.len()], vec![[0.0; 3]; n]);
    let (mut p, mut x) = (u_cur.clone(), vec![[0.0; 3]; n]);
    for _ in 0..options.iterations {
        project_springs(&pre.springs, &pre.r, &p, &mut d); // local step
        right_hand_side(&pre, &d, &y, &pins, &mut b); // b = k Aᵀd + y + w CᵀC V
        solve_sparse(&pre, &b, &mut x, &mut p); // p = Q⁻¹ b
        values.extend([&d, &b, &p].map(|rows| points(rows)));
    }
    assert_eq!(values.len(), quantities(options.iterations).len());
    Ok(values)
}

/// `A`, `r`, `M`, `C`, `Q`, `P`, `L`, in the order of the table.
pub fn precomputed(pre: &Precomputation<Sparse>) -> Vec<Value> {
    let r = DenseMatrix::from_row_major(pre.r.len(), 1, pre.r.clone())
        .expect("one rest length per row");
    vec![
        Value::Sparse(pre.A.clone()),
        Value::Dense(r),
        Value::Sparse(pre.M.clone()),
        Value::Sparse(pre.C.clone()),
        Value::Sparse(pre.Q.clone()),
        Value::Sparse(permutation_matrix(
            pre.prefactorization.symbolic().permutation().perm(),
        )),
        Value::Sparse(pre.prefactorization.l()),
    ]
}

/// `(U_prev, U_cur)` at the start of `step` (1-based): at rest for the
/// first, then one handout step after another.
pub fn state_before(
    pre: &Precomputation<Sparse>,
    f_ext: &[[f64; 3]],
    step: usize,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let (mut u_prev, mut u_cur) = (pre.V.clone(), pre.V.clone());
    let mut u_next = vec![[0.0; 3]; u_cur.len()];
    for _ in 1..step {
        fast_mass_springs_step_sparse(pre, f_ext, &u_prev, &u_cur, &mut u_next);
        std::mem::swap(&mut u_prev, &mut u_cur); // U_prev ← U_cur
        std::mem::swap(&mut u_cur, &mut u_next); // U_cur ← U_next
    }
    (u_prev, u_cur)
}

/// The permutation matrix `P` of `perm` (`perm[new] = old`): a 1 at
/// `(new, perm[new])`, so that `(P x)[new] = x[perm[new]]`.
pub fn permutation_matrix(perm: &[usize]) -> CscMatrix {
    let n = perm.len();
    let row_of_column = super::compare::inverse(perm); // column old holds its 1 in row new
    CscMatrix::from_parts(n, n, (0..=n).collect(), row_of_column, vec![1.0; n])
        .expect("a permutation has one entry per column")
}

/// An `n × 3` block of points as a dense matrix.
pub fn points(rows: &[[f64; 3]]) -> Value {
    Value::Dense(DenseMatrix::from_rows(rows).expect("rows of three"))
}

/// The quantities with their values, for writing.
pub fn labelled(values: Vec<Value>, iterations: usize) -> Vec<(Quantity, Value)> {
    quantities(iterations).into_iter().zip(values).collect()
}
