//! The elimination tree of a symmetric matrix.
//!
//! In the Cholesky factor `L` of `A`, the parent of column `j` is the row of
//! the first off-diagonal nonzero of `L(:, j)`:
//! `parent(j) = min { i > j : L(i, j) ≠ 0 }`. The tree says which columns
//! must be finished before which, and everything in the symbolic analysis
//! (postorder, column counts, the pattern of `L`, supernodes) is read off it.
//!
//! Liu's algorithm finds it from `A` alone, without `L`: process the columns
//! `k` in order; for every `A(i, k) ≠ 0` with `i < k`, climb from `i` to the
//! root of the tree built so far and hang that root under `k`. A second array
//! `ancestor` short-cuts the climb (path compression), so the whole run is
//! `O(nnz(A) · α(n))`, nearly linear.
//!
//! Source: Liu, "The role of elimination trees in sparse factorization",
//! SIAM J. Matrix Anal. Appl. 11(1), 1990; Davis 2006, §4.1 (`cs_etree`).

use super::pattern::ColumnPattern;

/// `parent[j]`: the parent of column `j` in the elimination tree of the
/// symmetric matrix whose **upper** triangle is `upper` (column `k` holds
/// the rows `i ≤ k`, in any order; others are skipped); `None` for a root.
pub fn elimination_tree(upper: &impl ColumnPattern) -> Vec<Option<usize>> {
    let n = upper.ncols();
    let mut parent = vec![None; n];
    // ancestor[i]: a (compressed) path up from i toward its current root
    let mut ancestor: Vec<Option<usize>> = vec![None; n];
    for k in 0..n {
        for row in upper.rows(k) {
            let mut i = row;
            while i < k {
                let next = ancestor[i];
                ancestor[i] = Some(k); // path compression: jump straight to k next time
                match next {
                    None => {
                        parent[i] = Some(k); // i was a root: k adopts it
                        break;
                    }
                    Some(up) => i = up,
                }
            }
        }
    }
    parent
}
