//! Permutations of `0..n`, as used by fill-reducing orderings.
//!
//! A permutation is stored both ways:
//!
//! * `perm[new] = old`: position `new` of the reordered problem is
//!   position `old` of the original (Davis 2006 calls this `p`);
//! * `inverse[old] = new` (Davis: `pinv`).
//!
//! As a matrix, `P` has a 1 at `(new, perm[new])`, so `(P x)[new] = x[perm[new]]`
//! and `(P A Pᵀ)(k, l) = A(perm[k], perm[l])`.

use crate::linalg::error::LinalgError;

/// A permutation of `0..n` together with its inverse.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Permutation {
    perm: Vec<usize>,
    inverse: Vec<usize>,
}

impl Permutation {
    /// The permutation that changes nothing.
    pub fn identity(n: usize) -> Self {
        Permutation {
            perm: (0..n).collect(),
            inverse: (0..n).collect(),
        }
    }

    /// Wraps `perm` (`perm[new] = old`) after checking that it is a permutation.
    ///
    /// # Errors
    /// [`LinalgError::InvalidStructure`] when an entry is out of range or repeated.
    pub fn from_perm(perm: Vec<usize>) -> Result<Self, LinalgError> {
        let n = perm.len();
        let mut inverse = vec![usize::MAX; n];
        for (new, &old) in perm.iter().enumerate() {
            if old >= n || inverse[old] != usize::MAX {
                return Err(LinalgError::InvalidStructure(format!(
                    "not a permutation of 0..{n}: entry {old} at position {new}"
                )));
            }
            inverse[old] = new;
        }
        Ok(Permutation { perm, inverse })
    }

    /// Number of elements permuted.
    pub fn len(&self) -> usize {
        self.perm.len()
    }

    /// Is this the permutation of nothing?
    pub fn is_empty(&self) -> bool {
        self.perm.is_empty()
    }

    /// `perm[new] = old`.
    pub fn perm(&self) -> &[usize] {
        &self.perm
    }

    /// `inverse[old] = new`.
    pub fn inverse(&self) -> &[usize] {
        &self.inverse
    }

    /// First reorder by `self`, then reorder the result by `then`:
    /// `combined[k] = self.perm[then.perm[k]]`.
    ///
    /// # Panics
    /// When the two lengths differ.
    pub fn followed_by(&self, then: &Permutation) -> Permutation {
        assert_eq!(self.len(), then.len(), "permutations of different lengths");
        let perm = then.perm.iter().map(|&k| self.perm[k]).collect();
        Permutation::from_perm(perm).expect("a composition of permutations is a permutation")
    }
}
