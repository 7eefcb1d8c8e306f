//! Fundamental supernodes: runs of columns of `L` that share one pattern.
//!
//! When column `j + 1` is the parent of `j` and `L(:, j)` has exactly one more
//! nonzero (its own diagonal), then
//! `struct(L(:, j)) = {j} ∪ struct(L(:, j + 1))`: the two columns have the
//! same rows below the diagonal block. A maximal run of such columns is a
//! supernode. Its columns form a dense lower-trapezoidal block: the rows are
//! the pattern of its first column, and column `k` of the run holds all of
//! them from its own diagonal down. The supernodal factorization works on
//! these blocks with dense kernels.
//!
//! In the CSC storage of `L` (rows sorted, diagonal first), column `k` of a
//! supernode is exactly its block's column from row position `k` on, stored
//! contiguously, so the supernodal and the simplicial codes share one
//! storage.
//!
//! No amalgamation here: supernodes are only merged when their patterns
//! nest exactly, so `nnz(L)` stays that of the exact pattern. Cost `O(n)`.
//! [`amalgamation`](super::amalgamation) merges them further, storing some
//! zeros, for the supernodal factorization.
//!
//! Source: Liu, Ng, Peyton, "On finding supernodes for sparse matrix
//! computations", SIAM J. Matrix Anal. Appl. 14(1), 1993; Davis 2006, §4.6.

/// The partition of the columns `0..n` into supernodes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Supernodes {
    /// Supernode `s` is the column range `start[s] .. start[s + 1]`.
    start: Vec<usize>,
    /// `of_column[j]`: the supernode that holds column `j`.
    of_column: Vec<usize>,
}

impl Supernodes {
    /// The fundamental supernodes of the factor with elimination tree
    /// `parent` and column counts `count`.
    pub fn find(parent: &[Option<usize>], count: &[usize]) -> Self {
        let n = parent.len();
        let mut start = vec![0];
        for j in 1..n {
            let continues = parent[j - 1] == Some(j) && count[j - 1] == count[j] + 1;
            if !continues {
                start.push(j);
            }
        }
        if n > 0 {
            start.push(n);
        }
        Self::from_starts(start, n)
    }

    /// The partition whose supernode `s` is `start[s] .. start[s + 1]`
    /// (`start` increasing from 0 to `n`, or empty when `n = 0`).
    pub(crate) fn from_starts(start: Vec<usize>, n: usize) -> Self {
        assert!(start.windows(2).all(|w| w[0] < w[1]));
        assert!(start.first().is_none_or(|&s| s == 0) && start.last().is_none_or(|&s| s == n));
        let mut of_column = vec![0; n];
        for s in 0..start.len().saturating_sub(1) {
            of_column[start[s]..start[s + 1]].fill(s);
        }
        Supernodes { start, of_column }
    }

    /// Number of supernodes.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Are there none (an empty matrix)?
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The columns of supernode `s`.
    pub fn columns(&self, s: usize) -> std::ops::Range<usize> {
        self.start[s]..self.start[s + 1]
    }

    /// Bytes held (array lengths).
    pub fn bytes(&self) -> usize {
        (self.start.len() + self.of_column.len()) * std::mem::size_of::<usize>()
    }

    /// The supernode that holds column `j`.
    pub fn of_column(&self, j: usize) -> usize {
        self.of_column[j]
    }
}
