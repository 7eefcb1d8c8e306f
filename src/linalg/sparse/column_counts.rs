//! Column counts of the Cholesky factor, without forming it.
//!
//! `count[j] = nnz(L(:, j))`, diagonal included. Row `i` of `L` is the set of
//! nodes on the paths from the nonzeros `A(i, j)`, `j < i`, up the
//! elimination tree to `i` (the "row subtree" of `i`), so
//! `count[j]` is the number of row subtrees that contain `j`. Gilbert, Ng
//! and Peyton count them in nearly linear time by visiting the tree in
//! postorder and crediting each column with the row subtrees that *start*
//! at it minus those that *merge* there:
//!
//! * `A(i, j)` with `i > j` only matters if `j` is a *leaf* of the row
//!   subtree of `i` (no earlier descendant of `j` already touched row `i`;
//!   tested with `first_descendant` and `max_first`);
//! * a leaf adds 1 at `j`; if row `i` had an earlier leaf `j′`, the two
//!   paths meet at their least common ancestor `q`, where 1 is taken back.
//!   `q` is found with a disjoint-set forest (`ancestor`, path compression).
//!
//! Summing these differences over each subtree gives the counts.
//! Cost `O(nnz(A) · α(n))`.
//!
//! Source: Gilbert, Ng, Peyton, "An efficient algorithm to compute row and
//! column counts for sparse Cholesky factorization", SIAM J. Matrix Anal.
//! Appl. 15(4), 1994; Davis 2006, §4.5 (`cs_counts`, `cs_leaf`).

use super::pattern::ColumnPattern;

/// Where `j` sits in the row subtree of `i`.
enum Leaf {
    /// `j` is not a leaf of row `i`'s subtree.
    No,
    /// `j` is the first leaf found.
    First,
    /// `j` is a later leaf; its path meets the previous one at this node.
    Later { meets_at: usize },
}

/// `count[j] = nnz(L(:, j))` (diagonal included) for the symmetric matrix
/// whose **lower** triangle is `lower` (column `j` holds rows `i ≥ j`, in
/// any order; rows above the diagonal are skipped), given
/// its elimination tree `parent` and a postorder `post` of that tree.
pub fn column_counts(
    lower: &impl ColumnPattern,
    parent: &[Option<usize>],
    post: &[usize],
) -> Vec<usize> {
    let n = lower.ncols();
    let first_descendant = first_descendants(parent, post);
    // `delta[j]`: subtrees starting at j minus subtrees merging at j
    let mut delta: Vec<isize> = (0..n)
        .map(|j| isize::from(is_leaf_of_etree(j, &first_descendant, post)))
        .collect();
    let mut sets = LeafFinder::new(n);
    for &j in post {
        if let Some(p) = parent[j] {
            delta[p] -= 1; // j's own path continues into its parent
        }
        for i in lower.rows(j) {
            match sets.classify(i, j, &first_descendant) {
                Leaf::No => {}
                Leaf::First => delta[j] += 1,
                Leaf::Later { meets_at } => {
                    delta[j] += 1;
                    delta[meets_at] -= 1;
                }
            }
        }
        if let Some(p) = parent[j] {
            sets.ancestor[j] = p; // j's subtree is done: join it to its parent's set
        }
    }
    sum_over_subtrees(delta, parent)
}

/// `first[j]`: the smallest postorder number in the subtree of `j`.
fn first_descendants(parent: &[Option<usize>], post: &[usize]) -> Vec<usize> {
    let mut first = vec![usize::MAX; parent.len()];
    for (k, &j) in post.iter().enumerate() {
        let mut node = Some(j);
        while let Some(d) = node {
            if first[d] != usize::MAX {
                break;
            }
            first[d] = k;
            node = parent[d];
        }
    }
    first
}

/// A node is a leaf of the tree when its subtree starts at itself.
fn is_leaf_of_etree(j: usize, first: &[usize], post: &[usize]) -> bool {
    post[first[j]] == j
}

/// Adds each node's `delta` into its parent's, children first (a parent is
/// always numbered after its children in an elimination tree).
fn sum_over_subtrees(mut delta: Vec<isize>, parent: &[Option<usize>]) -> Vec<usize> {
    for j in 0..delta.len() {
        if let Some(p) = parent[j] {
            delta[p] += delta[j];
        }
    }
    delta
        .into_iter()
        .map(|c| usize::try_from(c).expect("column counts are positive"))
        .collect()
}

/// The state `cs_leaf` keeps: for every row `i`, the last leaf seen and the
/// largest `first_descendant` seen; and a disjoint-set forest over finished
/// subtrees to find least common ancestors.
struct LeafFinder {
    max_first: Vec<Option<usize>>,
    previous_leaf: Vec<Option<usize>>,
    ancestor: Vec<usize>,
}

impl LeafFinder {
    fn new(n: usize) -> Self {
        LeafFinder {
            max_first: vec![None; n],
            previous_leaf: vec![None; n],
            ancestor: (0..n).collect(),
        }
    }

    /// Is column `j` a leaf of the row subtree of `i`, and if it is a later
    /// one, where does its path meet the previous leaf's?
    fn classify(&mut self, i: usize, j: usize, first: &[usize]) -> Leaf {
        if i <= j || self.max_first[i].is_some_and(|m| first[j] <= m) {
            return Leaf::No; // a descendant of j already reached row i
        }
        self.max_first[i] = Some(first[j]);
        match self.previous_leaf[i].replace(j) {
            None => Leaf::First,
            Some(previous) => Leaf::Later {
                meets_at: self.find_root(previous),
            },
        }
    }

    /// The root of `node`'s set, compressing the path to it.
    fn find_root(&mut self, node: usize) -> usize {
        let mut root = node;
        while self.ancestor[root] != root {
            root = self.ancestor[root];
        }
        let mut s = node;
        while s != root {
            let up = self.ancestor[s];
            self.ancestor[s] = root;
            s = up;
        }
        root
    }
}
