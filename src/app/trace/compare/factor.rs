//! `P` and `L`, which depend on the ordering: any permutation `P` is a
//! valid ordering, and `L` is unique once `P` is chosen. So `P` is only
//! checked to be a permutation (a different one is reported, not failed),
//! and `L` is checked through what it must satisfy,
//!
//! ```text
//! L Lᵀ = P Q Pᵀ        entry (k, l) within tolerance · √(Q'ₖₖ Q'ₗₗ),  Q' = P Q Pᵀ
//! ```
//!
//! with the student's `P` (as written, or transposed: `P` and `Pᵀ` are
//! easily confused, and the check says which one fitted), or, without
//! one, ours or none (the natural order). The scale `√(Q'ₖₖ Q'ₗₗ)` bounds
//! `(|L| |Lᵀ|)ₖₗ`, the size of the rounding a Cholesky factorization
//! leaves in `L Lᵀ` (Higham 2002, Thm. 10.3), so the tolerance is a few
//! hundred units in the last place whatever the pins' `w`.

use super::place::{permutation_of, Context, Place};
use super::{to_sparse, union_entries, Largest, Outcome};
use masssprings::linalg::sparse::{CscMatrix, Permutation, TripletMatrix};
use masssprings::matrix_market::MatrixMarket;

/// The student's matrix, sparse, if it is `n × n`; else why it differs.
fn square(their: &MatrixMarket, n: usize) -> Result<CscMatrix, Outcome> {
    let a = to_sparse(their);
    match (a.nrows(), a.ncols()) == (n, n) {
        true => Ok(a),
        false => Err(Outcome::Differs(
            None,
            format!("shape {} × {}, ours {n} × {n}", a.nrows(), a.ncols()),
        )),
    }
}

/// The student's `P` against ours.
pub fn ordering(their: MatrixMarket, context: &mut Context) -> Outcome {
    let p = match square(&their, context.our_perm.len()) {
        Ok(p) => p,
        Err(differs) => return differs,
    };
    match permutation_of(&p) {
        Err(reason) => Outcome::Differs(None, format!("not a permutation matrix: {reason}")),
        Ok(perm) => {
            let same = perm == context.our_perm;
            context.their_perm = Some(perm);
            match same {
                true => Outcome::Agrees(None, "the same ordering as ours".into()),
                false => Outcome::Note(
                    "another ordering than ours (allowed); L is checked with it".into(),
                ),
            }
        }
    }
}

/// The student's `L`: lower triangular, and `L Lᵀ = P Q Pᵀ`.
pub fn factor(their: MatrixMarket, context: &Context, tolerance: f64) -> Outcome {
    let l = match square(&their, context.our_perm.len()) {
        Ok(l) => l,
        Err(differs) => return differs,
    };
    if let Some((i, j, v)) = above_diagonal(&l) {
        return Outcome::Differs(
            None,
            format!("not lower triangular: entry ({}, {}) = {v}", i + 1, j + 1),
        );
    }
    let llt = l.mul(&l.transpose()).expect("square matrices of one size");
    let mut first = None;
    for (label, perm) in orderings(context) {
        let largest = product_difference(&llt, &context.q, &perm);
        let place = largest.map(|d| Place::Product(d, perm.clone()));
        if largest.is_none_or(|d| d.relative <= tolerance) {
            return Outcome::Agrees(place, label);
        }
        first.get_or_insert((place, label));
    }
    let (place, label) = first.expect("at least one ordering is tried");
    Outcome::Differs(place, format!("L Lᵀ ≠ P Q Pᵀ {label}"))
}

/// The first entry above the diagonal that is not zero.
fn above_diagonal(l: &CscMatrix) -> Option<(usize, usize, f64)> {
    (0..l.ncols()).find_map(|j| {
        let (rows, values) = l.column(j);
        rows.iter()
            .zip(values)
            .find(|(&i, &v)| i < j && v != 0.0)
            .map(|(&i, &v)| (i, j, v))
    })
}

/// The orderings to try `L` with, labelled: the student's `P` and its
/// transpose, or ours and the natural one.
fn orderings(context: &Context) -> Vec<(String, Vec<usize>)> {
    match &context.their_perm {
        Some(perm) => {
            let inverse = inverse(perm);
            vec![
                ("with your P".into(), perm.clone()),
                ("with the transpose of your P".into(), inverse),
            ]
        }
        None => vec![
            (
                "with our P (no P.mtx given)".into(),
                context.our_perm.clone(),
            ),
            (
                "in the natural order (no P.mtx given)".into(),
                (0..context.our_perm.len()).collect(),
            ),
        ],
    }
}

/// The largest entry of `L Lᵀ − P Q Pᵀ`, scaled by `√(Q'ₖₖ Q'ₗₗ)`.
fn product_difference(llt: &CscMatrix, q: &CscMatrix, perm: &[usize]) -> Option<super::Difference> {
    let inverse = inverse(perm);
    let mut triplets = TripletMatrix::with_capacity(q.nrows(), q.ncols(), q.nnz());
    for j in 0..q.ncols() {
        let (rows, values) = q.column(j);
        for (&i, &v) in rows.iter().zip(values) {
            triplets
                .push(inverse[i], inverse[j], v)
                .expect("inside the matrix");
        }
    }
    let pqp = triplets.to_csc();
    let diagonal = pqp.diagonal();
    let mut largest = Largest::default();
    union_entries(&pqp, llt, |k, l, ours, yours| {
        largest.consider(k, l, ours, yours, (diagonal[k] * diagonal[l]).abs().sqrt());
    });
    largest.0
}

/// `inverse[old] = new` of a permutation `perm[new] = old`.
pub fn inverse(perm: &[usize]) -> Vec<usize> {
    let permutation = Permutation::from_perm(perm.to_vec()).expect("checked to be a permutation");
    permutation.inverse().to_vec()
}
