//! Approximate minimum degree (AMD) fill-reducing ordering.
//!
//! **What it computes.** A permutation `P` of a square matrix `A` such that
//! the Cholesky factor of `P (A + Aᵀ) Pᵀ` has few nonzeros. Only the pattern
//! of `A + Aᵀ` with the diagonal ignored matters; values are never read.
//!
//! **The idea.** Minimum degree eliminates, at every step, the variable with
//! the fewest neighbours in the graph of the remaining Schur complement.
//! AMD (Amestoy, Davis & Duff, "An approximate minimum degree ordering
//! algorithm", SIAM J. Matrix Anal. Appl. 17(4):886–905, 1996) makes this
//! cheap:
//!
//! * the Schur complement is kept implicitly as a *quotient graph*: each
//!   eliminated pivot becomes an *element* (a clique stored as a list of its
//!   variables), so the storage never grows beyond that of `A`
//!   (`quotient_graph.rs`, `new_element.rs`);
//! * variables with identical patterns are merged into *supervariables* and
//!   eliminated together (`supervariables.rs`; *mass elimination* in
//!   `degree_update.rs`);
//! * the exact degree is replaced by an upper bound computed from the sizes
//!   `|Le \ Lp|` of the elements seen from the new element `Lp`
//!   (`degree_update.rs`), kept in bucket lists by degree (`degree_lists.rs`);
//! * rows that are "dense" are set aside up front and ordered last;
//! * the elimination forms an *assembly tree* whose postorder gives the final
//!   permutation (`postorder.rs`).
//!
//! **Cost.** `O(nnz(A))` memory (one integer workspace of about
//! `1.2 · nnz(A + Aᵀ) + n` entries plus a dozen `n`-vectors); time at most
//! `O(n · nnz(A))` (the paper's bound), close to linear in `nnz(A)` in
//! practice.
//!
//! **Source.** The paper above, as implemented in SuiteSparse AMD
//! (`amd_aat`, `amd_1`, `amd_2`, `amd_postorder`, `amd_post_tree`), and
//! Davis, *Direct Methods for Sparse Linear Systems* (SIAM 2006), §7.1. The
//! details that decide ties (head insertion into degree lists, the initial
//! degree, the degree bound, the order of children in the postorder) follow
//! `amd_2`, so for a symmetric pattern (full or one triangle) the
//! permutation is the one SuiteSparse's `amd_order` returns (checked on the
//! cloth grids and scenes and on random matrices, with and without
//! aggressive absorption, dense rows and garbage collections). Deviations
//! that do not change the result: a smaller hash table
//! (`supervariables.rs`), and an unsymmetric input's rows of `A + Aᵀ` are
//! sorted (`pattern.rs`); one that can: a negative `dense_threshold` keeps
//! every row (see [`AmdOptions`]).
//!
//! **Integers.** All workspaces are `i32` (half the memory traffic of
//! `usize`, as in SuiteSparse's `int` version); negative values encode
//! "none" and flags. A matrix whose workspace would not fit in `i32` is
//! refused with [`LinalgError::TooLarge`].

mod degree_lists;
mod degree_update;
mod hash_buckets;
mod new_element;
mod pattern;
mod postorder;
mod quotient_graph;
mod supervariables;

use super::csc::CscMatrix;
use super::permutation::Permutation;
use crate::linalg::error::LinalgError;
use quotient_graph::QuotientGraph;

/// "No such index": no list, no parent, end of a linked list.
const NONE: i32 = -1;

/// Options of [`amd`]; `Default` gives SuiteSparse AMD's defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmdOptions {
    /// A row of `A + Aᵀ` with more than `max(16, dense_threshold · √n)`
    /// off-diagonal entries is "dense": it is removed before the ordering
    /// starts and placed last. A negative value (or NaN) turns the detection
    /// off; SuiteSparse would still remove rows that are completely full.
    /// Default 10.
    pub dense_threshold: f64,
    /// Absorb every element `e` whose pattern lies inside the new element
    /// (`|Le \ Lp| = 0`), not only those adjacent to the pivot. Default `true`.
    pub aggressive_absorption: bool,
}

impl Default for AmdOptions {
    fn default() -> Self {
        AmdOptions {
            dense_threshold: 10.0,
            aggressive_absorption: true,
        }
    }
}

/// What the ordering found.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AmdInfo {
    /// Rows removed up front as dense (ordered last).
    pub dense_rows: usize,
    /// Rows with no off-diagonal entry (eliminated first, at no cost).
    pub empty_rows: usize,
    /// Pivot steps, i.e. nodes of the assembly tree (supernodes).
    pub elements: usize,
    /// Variables merged into another supervariable (by hashing).
    pub merged_variables: usize,
    /// Variables eliminated together with a pivot by mass elimination.
    pub mass_eliminated: usize,
    /// Elements absorbed by aggressive absorption.
    pub aggressive_absorptions: usize,
    /// Times the workspace was compacted (SuiteSparse's `ncmpa`).
    pub garbage_collections: usize,
    /// Length of the integer workspace holding the quotient graph.
    pub workspace_len: usize,
    /// Upper bound on `nnz(L)`, diagonal included, as AMD estimates it while
    /// ordering (SuiteSparse's `Info[AMD_LNZ] + n`); the exact count needs
    /// the symbolic analysis.
    pub factor_nnz_estimate: usize,
}

/// Computes the AMD ordering of the pattern of `A + Aᵀ` (diagonal ignored).
///
/// Returns the permutation (`perm[new] = old`, see [`Permutation`]) and
/// statistics. Deterministic: the same pattern gives the same permutation.
///
/// # Errors
/// [`LinalgError::NotSquare`] when `matrix` is not square;
/// [`LinalgError::TooLarge`] when the workspace does not fit 32-bit indices.
pub fn amd(
    matrix: &CscMatrix,
    options: &AmdOptions,
) -> Result<(Permutation, AmdInfo), LinalgError> {
    let n = matrix.nrows();
    if matrix.ncols() != n {
        return Err(LinalgError::NotSquare {
            nrows: n,
            ncols: matrix.ncols(),
        });
    }
    if n == 0 {
        return Ok((Permutation::identity(0), AmdInfo::default()));
    }

    let pattern = pattern::symmetric_pattern(matrix)?;
    let mut graph = QuotientGraph::new(pattern, options.aggressive_absorption);
    graph.set_aside_dense_and_empty_rows(dense_limit(n, options.dense_threshold));

    // One pivot step of the paper: select p, form Lp, update degrees.
    while graph.eliminated < n {
        let pivot_variable = graph.select_pivot();
        let mut pivot = graph.construct_element(pivot_variable);
        graph.compute_external_element_sizes(&pivot);
        graph.update_degrees(&mut pivot);
        graph.detect_supervariables(&pivot);
        graph.finalize_element(&pivot);
    }

    let mut info = graph.info();
    let tree = graph.into_assembly_tree();
    info.elements = tree.size.iter().filter(|&&s| s > 0).count();
    let perm = postorder::permutation_from_assembly_tree(tree);
    let permutation = Permutation::from_perm(perm).expect("AMD produces a permutation");
    Ok((permutation, info))
}

/// Rows with more off-diagonal entries than this are dense:
/// `min(n, max(16, ⌊threshold · √n⌋))`, or no limit for a negative threshold.
fn dense_limit(n: usize, threshold: f64) -> usize {
    if threshold < 0.0 || threshold.is_nan() {
        return n;
    }
    let scaled = (threshold * (n as f64).sqrt()) as usize;
    scaled.max(16).min(n)
}
