//! `P` and `L`, which depend on the ordering: any permutation `P` is a
//! valid ordering, and `L` is unique once `P` is chosen. So `P` is only
//! checked to be a permutation, and `L` through what it must satisfy,
//!
//! ```text
//! L Lᵀ = P Q Pᵀ        entry (k, l) within tolerance · √(Q'ₖₖ Q'ₗₗ),  Q' = P Q Pᵀ
//! ```
//!
//! The scale `√(Q'ₖₖ Q'ₗₗ)` bounds `(|L| |Lᵀ|)ₖₗ`, the size of the rounding a
//! Cholesky factorization leaves in `L Lᵀ` (Higham 2002, Thm. 10.3), so
//! the tolerance is a few hundred units in the last place whatever the
//! pins' `w`.
//!
//! `L Lᵀ` is never built: a student's `L` may hold any pattern (a 900 KB
//! file whose `L` has a full column and a full row makes `L Lᵀ` dense, an
//! `n × n` matrix of gigabytes). Its lower triangle is formed one column
//! at a time into a dense column of `n`, compared with `Q'`'s and cleared:
//!
//! ```text
//! (L Lᵀ)ᵢⱼ = Σₖ Lᵢₖ Lⱼₖ    for i ≥ j, over the k of row j of L
//! ```
//!
//! so the memory is `L`'s rows (a transposed copy, checked against the
//! limit) and two columns of `n`, and the time `Σₖ cₖ²` (`cₖ` the entries
//! of column `k`), the flops of the factorization that made `L`.
//!
//! This file uses the library only, so that the fuzz target
//! `trace_compare` includes it as it is.

use super::entries::{kind_of, Largest, RowKind};
use masssprings::linalg::sparse::{CscMatrix, Permutation, TripletMatrix};
use masssprings::memory;

/// `perm` of a permutation matrix `P` (a 1 at `(new, perm[new])`), or why
/// `p` is not one.
pub fn permutation_of(p: &CscMatrix) -> Result<Vec<usize>, String> {
    let n = p.ncols();
    if p.nrows() != n {
        return Err(format!("shape {} × {n}, not square", p.nrows()));
    }
    let mut perm = vec![usize::MAX; n];
    for j in 0..n {
        let (rows, values) = p.column(j);
        let mut ones = rows.iter().zip(values).filter(|(_, &v)| v != 0.0);
        let (Some((&r, &v)), None) = (ones.next(), ones.next()) else {
            let count = values.iter().filter(|&&v| v != 0.0).count();
            return Err(format!("column {} has {count} nonzeros, not one", j + 1));
        };
        if v != 1.0 {
            return Err(format!("column {} holds a value other than 1", j + 1));
        }
        if perm[r] != usize::MAX {
            return Err(format!("row {} has two ones", r + 1));
        }
        perm[r] = j;
    }
    Ok(perm)
}

/// `inverse[old] = new` of a permutation `perm[new] = old`.
pub fn inverse(perm: &[usize]) -> Vec<usize> {
    let permutation = Permutation::from_perm(perm.to_vec()).expect("checked to be a permutation");
    permutation.inverse().to_vec()
}

/// The first entry above the diagonal that is not zero.
pub fn above_diagonal(l: &CscMatrix) -> Option<(usize, usize, f64)> {
    (0..l.ncols()).find_map(|j| {
        let (rows, values) = l.column(j);
        rows.iter()
            .zip(values)
            .find(|(&i, &v)| i < j && v != 0.0)
            .map(|(&i, &v)| (i, j, v))
    })
}

/// The first pivot `Lⱼⱼ` that is not positive (a missing one is 0): a
/// Cholesky factor has a positive diagonal, and `L` with a column negated
/// still gives `L Lᵀ = P Q Pᵀ`, so the product alone would not see it.
pub fn first_pivot_not_positive(l: &CscMatrix) -> Option<(usize, f64)> {
    (0..l.ncols()).find_map(|j| {
        let (rows, values) = l.column(j);
        let pivot = rows
            .iter()
            .zip(values)
            .find(|(&i, _)| i == j)
            .map_or(0.0, |(_, &v)| v);
        (pivot.is_nan() || pivot <= 0.0).then_some((j, pivot))
    })
}

/// The lower triangle of `Q' = P Q Pᵀ`: `Q'ₖₗ = Q[perm[k], perm[l]]`.
fn permuted_lower(q: &CscMatrix, perm: &[usize]) -> CscMatrix {
    let new_of = inverse(perm);
    let mut triplets = TripletMatrix::with_capacity(q.nrows(), q.ncols(), q.nnz());
    for j in 0..q.ncols() {
        let (rows, values) = q.column(j);
        for (&i, &v) in rows.iter().zip(values) {
            if new_of[i] >= new_of[j] {
                triplets
                    .push(new_of[i], new_of[j], v)
                    .expect("inside the matrix");
            }
        }
    }
    triplets.to_csc()
}

/// The largest entries of `L Lᵀ − P Q Pᵀ` in the lower triangle, each
/// scaled by `√(Q'ₖₖ Q'ₗₗ)` (`ours` is `P Q Pᵀ`, `yours` `L Lᵀ`), with
/// `kinds` the rows' kinds in the factor's order. `L` is `n × n` and lower
/// triangular, `Q` `n × n`, `perm` a permutation of `n`.
///
/// # Errors
/// The memory rule's refusal of `L`'s transposed copy.
pub fn product_difference(
    l: &CscMatrix,
    q: &CscMatrix,
    perm: &[usize],
    kinds: &[RowKind],
) -> Result<Largest, String> {
    let n = q.ncols();
    let copy = memory::bytes_for(l.nnz() as u64, 16).saturating_add(memory::bytes_for(n as u64, 8));
    memory::check(
        copy,
        || format!("the rows of an L of {} entries", l.nnz()),
        "",
    )
    .map_err(|e| e.to_string())?;
    let rows_of_l = l.transpose(); // column j of Lᵀ: row j of L
    let pqp = permuted_lower(q, perm);
    let diagonal = pqp.diagonal();
    let mut values = vec![[0.0_f64; 2]; n]; // column j of [P Q Pᵀ, L Lᵀ]
    let mut seen = vec![false; n];
    let mut touched = Vec::new();
    let mut largest = Largest::default();
    for j in 0..n {
        let mut add = |i: usize, side: usize, v: f64| {
            values[i][side] += v;
            if !std::mem::replace(&mut seen[i], true) {
                touched.push(i);
            }
        };
        let (rows, column) = pqp.column(j);
        rows.iter().zip(column).for_each(|(&i, &v)| add(i, 0, v));
        let (ks, row_j) = rows_of_l.column(j);
        for (&k, &l_jk) in ks.iter().zip(row_j) {
            let (rows, column) = l.column(k);
            let below = rows.partition_point(|&i| i < j); // (L Lᵀ)ᵢⱼ for i ≥ j only
            for (&i, &l_ik) in rows[below..].iter().zip(&column[below..]) {
                add(i, 1, l_ik * l_jk);
            }
        }
        for i in touched.drain(..) {
            let [ours, yours] = std::mem::take(&mut values[i]);
            let scale = (diagonal[i] * diagonal[j]).abs().sqrt();
            largest.consider(kind_of(kinds, i), (i, j), ours, yours, scale);
            seen[i] = false;
        }
    }
    Ok(largest)
}
