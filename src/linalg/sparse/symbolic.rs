//! Symbolic analysis: everything about `L` that depends only on the pattern.
//!
//! Done once per sparsity pattern, before any arithmetic:
//!
//! 1. a fill-reducing permutation `P` (given, e.g. from [AMD](super::amd));
//! 2. the pattern of `C = P A Pᵀ`, both strict triangles, unsorted
//!    ([`pattern`](super::pattern));
//! 3. the elimination tree of `C` ([`elimination_tree`]);
//! 4. its postorder ([`postorder`]), folded into `P`: same fill, but every
//!    subtree becomes a contiguous range of columns;
//! 5. the column counts of `L` ([`column_counts`]), hence `nnz(L)`, the
//!    flop count, and the column pointers of `L`;
//! 6. the supernodes ([`Supernodes`]), read off the tree and the counts;
//! 7. the rows of each supernode ([`supernode_rows`]), walking the
//!    supernodal tree row by row.
//!
//! Steps 3 and 5 run in the numbering of `P`; the postorder then renumbers
//! the tree and the counts (`O(n)`), instead of permuting `A` a second
//! time. A postorder puts every ancestor after its descendants, so the
//! upper triangle of `C` stays the upper triangle once renumbered, and
//! step 7 reads it through the renumbering ([`Relabeled`]).
//!
//! Nowhere is `L`'s full pattern built: the columns of a supernode share
//! the rows of its first column (column `k` of it has them from position
//! `k` on), so one sorted list per supernode describes all of `L`. That is
//! what the supernodal factorization and its solves read: at a million
//! vertices, 7.9 million row indices instead of 56 million (32 MB instead
//! of 225 MB, `docs/performance.md`). The simplicial method reads every
//! column's rows; [`SymbolicCholesky::store_rows_per_column`] writes them
//! out (`O(nnz(L))`) when it is chosen. The values stay one column after
//! another, laid out by the column pointers.
//!
//! For the supernodal factorization, [`SymbolicCholesky::relaxed`] then
//! merges supernodes ([`amalgamation`](super::amalgamation)): the pattern
//! grows by some explicit zeros, each column still stored from its
//! diagonal down. The simplicial method needs the exact pattern.
//!
//! The numeric factorization then only fills in values, into arrays whose
//! size is known here, and can be repeated when the values of `A` change.
//! Nothing here depends on the values of `A`: the analysis holds patterns
//! only.
//!
//! Flop count: eliminating column `j` costs about `count[j]²` multiply-adds,
//! so `flops = Σ_j count[j]²` (the convention of Davis 2006 and CHOLMOD).
//! Cost of the analysis: `O(nnz(A) α(n) + Σ_s count[first(s)])` after the
//! ordering: nearly linear in `A`, plus the size of the supernodes' rows.
//!
//! Source: Davis 2006, ch. 4 (`cs_schol`: §4.1 tree, §4.3 postorder, §4.5
//! counts); Chen, Davis, Hager, Rajamanickam, "CHOLMOD", ACM TOMS 35(3),
//! 2008 (`cholmod_super_symbolic`); George & Liu, *Computer Solution of
//! Large Sparse Positive Definite Systems*, 1981.

use super::amalgamation::{relax, Relaxation};
use super::column_counts::column_counts;
use super::csc::{cumulative_sum, CscMatrix};
use super::etree::elimination_tree;
use super::ordering::Ordering;
use super::pattern::{permuted_triangles, Relabeled};
use super::permutation::Permutation;
use super::permute::check_permutation_fits;
use super::postorder::postorder;
use super::supernode_rows::{supernode_rows, SupernodeRows};
use super::supernodes::Supernodes;
use crate::linalg::error::LinalgError;
use std::borrow::Cow;

/// The result of the symbolic analysis of a symmetric matrix.
///
/// # Examples
///
/// The star of `docs/sparse-cholesky.md`: a hub joined to four leaves.
/// Eliminated first (the natural order), the hub connects every leaf to
/// every other; AMD eliminates it last, and nothing fills in.
///
/// ```
/// use masssprings::linalg::sparse::{Ordering, SymbolicCholesky, TripletMatrix};
///
/// let mut q = TripletMatrix::new(5, 5);
/// q.push(0, 0, 5.0)?;
/// for leaf in 1..5 {
///     q.push(leaf, leaf, 2.0)?;
///     q.push(leaf, 0, -1.0)?;
///     q.push(0, leaf, -1.0)?;
/// }
/// let q = q.to_csc();
/// let natural = SymbolicCholesky::analyze(&q, Ordering::Natural)?;
/// let amd = SymbolicCholesky::analyze(&q, Ordering::Amd)?;
/// assert_eq!((natural.nnz_l(), amd.nnz_l()), (15, 9));
/// assert_eq!(amd.elimination_tree(), [Some(4), Some(4), Some(4), Some(4), None]);
/// assert_eq!(amd.supernodes().len(), 4); // {0}, {1}, {2}, {3, 4}
/// # Ok::<(), masssprings::linalg::LinalgError>(())
/// ```
#[derive(Debug, Clone)]
pub struct SymbolicCholesky {
    /// Fill-reducing ordering followed by the postorder of its tree.
    permutation: Permutation,
    /// Elimination tree of `P A Pᵀ` (postordered: `parent[j] > j`).
    parent: Vec<Option<usize>>,
    /// `nnz(L(:, j))`, diagonal included.
    column_counts: Vec<usize>,
    /// Column `j` of `L` is `col_ptr[j] .. col_ptr[j + 1]` in the values
    /// (and in the rows, when they are kept per column).
    col_ptr: Vec<usize>,
    /// Rows of `L`, sorted in each column, diagonal first.
    rows: FactorRows,
    supernodes: Supernodes,
    /// Zeros stored in the pattern by [`SymbolicCholesky::relaxed`].
    explicit_zeros: usize,
    /// The rule applied by [`SymbolicCholesky::relaxed`], if it was.
    relaxation: Option<Relaxation>,
}

/// The rows of `L`, 32-bit: the triangular solves are memory-bound, and 4
/// bytes less per entry is a quarter less traffic.
#[derive(Debug, Clone)]
enum FactorRows {
    /// Every column's rows, column `j` at `col_ptr[j] .. col_ptr[j + 1]`.
    PerColumn(Vec<u32>),
    /// Each supernode's rows once, supernode `s` at `start[s] ..
    /// start[s + 1]`: those of its first column; its column `k` has the
    /// same rows from position `k` on.
    PerSupernode { start: Vec<usize>, rows: Vec<u32> },
}

impl SymbolicCholesky {
    /// Orders `a` with `ordering`, then analyses it (see
    /// [`SymbolicCholesky::with_permutation`]).
    ///
    /// # Errors
    /// As [`Ordering::permutation`] and [`SymbolicCholesky::with_permutation`].
    pub fn analyze(a: &CscMatrix, ordering: Ordering) -> Result<Self, LinalgError> {
        Self::with_permutation(a, &ordering.permutation(a)?)
    }

    /// Analyses the symmetric matrix `a` (only its lower triangle is read)
    /// for the fill-reducing permutation `ordering`.
    ///
    /// # Errors
    /// [`LinalgError::NotSquare`]; [`LinalgError::DimensionMismatch`] when
    /// the permutation has the wrong length; [`LinalgError::TooLarge`]
    /// when `n` does not fit the factor's 32-bit row indices.
    pub fn with_permutation(a: &CscMatrix, ordering: &Permutation) -> Result<Self, LinalgError> {
        check_permutation_fits(a, ordering)?;
        let n = a.ncols();
        if u32::try_from(n).is_err() {
            return Err(LinalgError::TooLarge { n });
        }
        // tree and counts in the numbering of `ordering`, then renumbered
        let (upper, lower) = permuted_triangles(a, ordering.inverse());
        let tree = elimination_tree(&upper);
        let post = postorder(&tree);
        let counts = column_counts(&lower, &tree, &post);
        drop(lower);
        let post = Permutation::from_perm(post)?;
        let (parent, column_counts) = renumbered(&tree, &counts, &post);
        let col_ptr = cumulative_sum(&column_counts);
        let supernodes = Supernodes::find(&parent, &column_counts);
        // a postorder keeps every ancestor after its descendants, so the
        // upper triangle renumbered is the upper triangle of the new C
        let upper = Relabeled {
            pattern: &upper,
            old: post.perm(),
            new: post.inverse(),
        };
        let SupernodeRows { start, rows } =
            supernode_rows(&upper, &parent, &supernodes, &column_counts);
        Ok(SymbolicCholesky {
            permutation: ordering.followed_by(&post),
            parent,
            column_counts,
            col_ptr,
            rows: FactorRows::PerSupernode { start, rows },
            supernodes,
            explicit_zeros: 0,
            relaxation: None,
        })
    }

    /// The same analysis with relaxed supernodes (see
    /// [`amalgamation`](super::amalgamation)): the column counts, pointers
    /// and rows now describe the wider pattern, explicit zeros included.
    /// A relaxed supernode's rows are its own columns, then the rows of
    /// its last fundamental member's first column (kept once per
    /// supernode, whichever way they were kept before). Relaxing an
    /// analysis twice changes nothing.
    pub fn relaxed(mut self, rule: &Relaxation) -> SymbolicCholesky {
        if self.relaxation.is_some() {
            return self;
        }
        self.relaxation = Some(*rule);
        if *rule == Relaxation::NONE {
            // the rule then merges only where no zero is added, and two
            // fundamental supernodes never nest so (they would be one): the
            // partition would come back unchanged
            return self;
        }
        let (supernodes, last_member_first) =
            relax(&self.supernodes, &self.parent, &self.column_counts, rule);
        if supernodes == self.supernodes {
            return self; // nothing merged: same pattern
        }
        self.store_rows_per_supernode();
        let exact_nnz = self.nnz_l();
        let mut start = Vec::with_capacity(supernodes.len() + 1);
        start.push(0);
        let mut rows = Vec::new();
        for (s, &fc) in last_member_first.iter().enumerate() {
            let columns = supernodes.columns(s);
            rows.extend((columns.start..fc).map(|k| k as u32)); // n fits in u32
            rows.extend_from_slice(self.supernode_rows(self.supernodes.of_column(fc)));
            start.push(rows.len());
            for k in columns.start..fc {
                self.column_counts[k] = (fc - k) + self.column_counts[fc];
            }
        }
        self.col_ptr = cumulative_sum(&self.column_counts);
        self.explicit_zeros = self.nnz_l() - exact_nnz;
        self.rows = FactorRows::PerSupernode { start, rows };
        self.supernodes = supernodes;
        self
    }

    /// The rule of [`SymbolicCholesky::relaxed`], if it was applied.
    pub fn relaxation(&self) -> Option<Relaxation> {
        self.relaxation
    }

    /// Zeros stored by relaxation; `nnz_l() − explicit_zeros()` is the
    /// number of nonzeros of the exact `L`.
    pub fn explicit_zeros(&self) -> usize {
        self.explicit_zeros
    }

    /// Bytes held by this analysis (its arrays' lengths, not capacities):
    /// for the memory figures of `docs/performance.md` and their tests.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        let n = self.n();
        2 * n * size_of::<usize>() // the permutation and its inverse
            + n * size_of::<Option<usize>>()
            + std::mem::size_of_val(&self.column_counts[..])
            + std::mem::size_of_val(&self.col_ptr[..])
            + match &self.rows {
                FactorRows::PerColumn(rows) => std::mem::size_of_val(&rows[..]),
                FactorRows::PerSupernode { start, rows } => {
                    std::mem::size_of_val(&start[..]) + std::mem::size_of_val(&rows[..])
                }
            }
            + self.supernodes.bytes()
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.parent.len()
    }

    /// The permutation `P` of `L Lᵀ = P A Pᵀ` (`perm[new] = old`).
    pub fn permutation(&self) -> &Permutation {
        &self.permutation
    }

    /// Elimination tree of `P A Pᵀ`; `None` marks a root.
    pub fn elimination_tree(&self) -> &[Option<usize>] {
        &self.parent
    }

    /// `nnz(L(:, j))` for every column, diagonal included (stored entries:
    /// explicit zeros of a relaxed analysis count).
    pub fn column_counts(&self) -> &[usize] {
        &self.column_counts
    }

    /// `nnz(L)`, diagonal included (stored entries, see
    /// [`SymbolicCholesky::explicit_zeros`]).
    pub fn nnz_l(&self) -> usize {
        self.col_ptr[self.n()]
    }

    /// Multiply-adds of the factorization, `Σ_j count[j]²`.
    pub fn flops(&self) -> f64 {
        self.column_counts
            .iter()
            .map(|&c| (c as f64) * (c as f64))
            .sum()
    }

    /// Column pointers of `L`.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices of `L`, column after column (laid out by
    /// [`SymbolicCholesky::col_ptr`]), sorted in each column, diagonal
    /// first. Borrowed when they are kept per column; built (`nnz(L)`
    /// indices) when they are kept per supernode.
    pub fn row_idx(&self) -> Cow<'_, [u32]> {
        match &self.rows {
            FactorRows::PerColumn(rows) => Cow::Borrowed(rows),
            FactorRows::PerSupernode { .. } => Cow::Owned(
                (0..self.n())
                    .flat_map(|j| self.column_rows(j))
                    .copied()
                    .collect(),
            ),
        }
    }

    /// The rows of column `j` of `L`, diagonal first.
    #[inline]
    pub fn column_rows(&self, j: usize) -> &[u32] {
        match &self.rows {
            FactorRows::PerColumn(rows) => &rows[self.col_ptr[j]..self.col_ptr[j + 1]],
            FactorRows::PerSupernode { .. } => {
                let s = self.supernodes.of_column(j);
                let k = j - self.supernodes.columns(s).start;
                &self.supernode_rows(s)[k..]
            }
        }
    }

    /// The rows of supernode `s`: those of its first column. (Always
    /// inlined: the solves ask once per supernode, and when it was a call,
    /// which `#[inline]` did not prevent inside the AVX2 solve, the step
    /// took 21–23% longer on the flag and the skirt, `docs/performance.md`.)
    #[inline(always)]
    pub fn supernode_rows(&self, s: usize) -> &[u32] {
        match &self.rows {
            FactorRows::PerColumn(rows) => {
                let first = self.supernodes.columns(s).start;
                &rows[self.col_ptr[first]..self.col_ptr[first + 1]]
            }
            FactorRows::PerSupernode { start, rows } => &rows[start[s]..start[s + 1]],
        }
    }

    /// Are the rows kept once per supernode?
    pub fn rows_per_supernode(&self) -> bool {
        matches!(self.rows, FactorRows::PerSupernode { .. })
    }

    /// Keeps each supernode's rows once (as the analysis makes them):
    /// what the supernodal factorization and solves read, `Σ_s
    /// count[first(s)]` indices instead of `nnz(L)`.
    /// [`SymbolicCholesky::row_idx`] still gives every column's, by
    /// building them.
    pub fn store_rows_per_supernode(&mut self) {
        let FactorRows::PerColumn(_) = &self.rows else {
            return;
        };
        let count = self.supernodes.len();
        let mut start = Vec::with_capacity(count + 1);
        start.push(0);
        let kept: usize = (0..count).map(|s| self.supernode_rows(s).len()).sum();
        let mut rows = Vec::with_capacity(kept);
        for s in 0..count {
            rows.extend_from_slice(self.supernode_rows(s));
            start.push(rows.len());
        }
        self.rows = FactorRows::PerSupernode { start, rows };
    }

    /// Keeps every column's rows, laid out by the column pointers (`nnz(L)`
    /// indices): what the simplicial factorization and its substitutions
    /// read, borrowed from [`SymbolicCholesky::row_idx`].
    pub fn store_rows_per_column(&mut self) {
        if let FactorRows::PerSupernode { .. } = &self.rows {
            self.rows = FactorRows::PerColumn(self.row_idx().into_owned());
        }
    }

    /// The supernodes of `L`: fundamental, or relaxed after
    /// [`SymbolicCholesky::relaxed`].
    pub fn supernodes(&self) -> &Supernodes {
        &self.supernodes
    }
}

/// The tree and the counts found in one numbering, in the numbering that
/// follows it by `post`: node `k` is old node `post.perm()[k]`.
fn renumbered(
    tree: &[Option<usize>],
    counts: &[usize],
    post: &Permutation,
) -> (Vec<Option<usize>>, Vec<usize>) {
    let (old, new) = (post.perm(), post.inverse());
    let parent = old.iter().map(|&j| tree[j].map(|p| new[p])).collect();
    let column_counts = old.iter().map(|&j| counts[j]).collect();
    (parent, column_counts)
}
