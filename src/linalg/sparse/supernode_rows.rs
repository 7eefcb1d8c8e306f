//! The rows of every supernode of `L`, without the pattern of `L`.
//!
//! All the columns of a supernode share the rows of its first column (each
//! from its own diagonal down), so the supernodal factorization and its
//! solves need one sorted row list per supernode, not one per column.
//! Those lists are found on the *supernodal* elimination tree (the parent
//! of supernode `s` is the supernode holding the parent of `s`'s last
//! column), row by row, as `ereach` finds the rows of `L` on the column
//! tree ([`row_pattern`](super::row_pattern)):
//!
//! ```text
//! every supernode s starts with its own columns first(s) .. last(s)
//! for k = 0 .. n − 1:
//!     mark the supernode holding k
//!     for every C(i, k) ≠ 0 with i < k:
//!         s = supernode of i
//!         while s is not marked for k:       row k of L touches s,
//!             append k to the rows of s       and every supernode up to k's
//!             mark s; s = parent(s)
//! ```
//!
//! Row `k` of `L` is nonzero in column `j` exactly when `j` lies on a tree
//! path from some `i` with `C(i, k) ≠ 0` up to `k`; the supernodes along
//! those paths are the ones whose first column has row `k` (their columns
//! below `k`'s share its pattern). Rows are appended in increasing `k`, so
//! each list comes out sorted with no sort; its length is known in advance
//! from the column counts (`count[first(s)]`), so it is written in place.
//! The walk visits each supernode once per row it receives, so the cost is
//! `O(nnz(C) + Σ_s count[first(s)])`, the size of the answer, instead of
//! `O(nnz(L))` for every column's rows.
//!
//! The same walk on a partition of merged supernodes (each a contiguous
//! range that is a connected piece of the tree) gives their rows: their own
//! columns, then the union of their members' rows below them.
//!
//! Source: Chen, Davis, Hager, Rajamanickam, "CHOLMOD", ACM TOMS 35(3),
//! 2008 (`cholmod_super_symbolic`, the `Ls` pattern); Davis 2006, §4.2
//! (`cs_ereach`) for the walk on the column tree.

use super::pattern::ColumnPattern;
use super::supernodes::Supernodes;

/// Each supernode's rows, sorted: supernode `s` has `rows[start[s] ..
/// start[s + 1]]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SupernodeRows {
    pub start: Vec<usize>,
    pub rows: Vec<u32>,
}

/// The rows of the supernodes `supernodes` of the factor of the matrix
/// whose **upper** triangle is `upper` (rows `i < k` of column `k` are
/// read, in any order), with elimination tree `parent` and column counts
/// `count` (those of the columns the supernodes store: `count[first(s)]`
/// rows for supernode `s`).
pub fn supernode_rows(
    upper: &impl ColumnPattern,
    parent: &[Option<usize>],
    supernodes: &Supernodes,
    count: &[usize],
) -> SupernodeRows {
    let nodes = supernodes.len();
    let node_parent = supernodal_tree(parent, supernodes);
    let start = super::csc::cumulative_sum(
        &(0..nodes)
            .map(|s| count[supernodes.columns(s).start])
            .collect::<Vec<_>>(),
    );
    let mut rows = vec![0u32; start[nodes]];
    let mut next = start[..nodes].to_vec();
    for s in 0..nodes {
        for k in supernodes.columns(s) {
            rows[next[s]] = k as u32; // n fits in u32, checked by the analysis
            next[s] += 1;
        }
    }
    let mut marked_for = vec![usize::MAX; nodes];
    for k in 0..parent.len() {
        marked_for[supernodes.of_column(k)] = k;
        for i in upper.rows(k).filter(|&i| i < k) {
            let mut s = supernodes.of_column(i);
            while marked_for[s] != k {
                rows[next[s]] = k as u32;
                next[s] += 1;
                marked_for[s] = k;
                s = node_parent[s].expect("C(i, k) ≠ 0 makes k's supernode an ancestor of i's");
            }
        }
    }
    assert!((0..nodes).all(|s| next[s] == start[s + 1]));
    SupernodeRows { start, rows }
}

/// `node_parent[s]`: the supernode holding the parent of `s`'s last column.
pub fn supernodal_tree(parent: &[Option<usize>], supernodes: &Supernodes) -> Vec<Option<usize>> {
    (0..supernodes.len())
        .map(|s| parent[supernodes.columns(s).end - 1].map(|p| supernodes.of_column(p)))
        .collect()
}
