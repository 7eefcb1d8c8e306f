//! Pivot selection and construction of the new element `Lp`.
//!
//! **What it computes.** The supervariable `p` of minimum approximate degree
//! is turned into the element `p`, whose pattern is
//!
//! ```text
//! Lp = (Ap ∪ ⋃_{e ∈ Ep} Le) \ {p}
//! ```
//!
//! (its remaining variables plus the patterns of all elements adjacent to
//! it), keeping principal variables only. Every element `e ∈ Ep` is
//! *absorbed* into `p`: its clique is contained in the new one, so it
//! disappears from the graph and `p` becomes its parent in the assembly tree.
//! Each variable of `Lp` is unlinked from its degree list (its degree is
//! about to change) and flagged by negating its `size`.
//!
//! **Where.** If `p` is adjacent to no element, `Lp ⊆ Ap` and the element
//! overwrites `p`'s own list. Otherwise it is written at the free end of the
//! workspace; should that fill, the workspace is compressed first (see
//! [`QuotientGraph::compress`]), keeping the parts of the lists not yet read.
//!
//! **Cost.** `O(|Ap| + Σ_{e ∈ Ep} |Le|)`; every entry read belongs to a
//! list that is freed here, so over the whole ordering this is `O(nnz(A))`
//! plus the sizes of the elements formed.
//!
//! **Source.** Amestoy, Davis & Duff 1996, Algorithm 2 (steps "select pivot"
//! and "construct Lp", "element absorption"); SuiteSparse AMD `amd_2.c`
//! ("get pivot of minimum degree", "construct new element"); Davis 2006, §7.1.

use super::quotient_graph::{QuotientGraph, NONE};

/// The element being formed in the current pivot step.
pub(super) struct Pivot {
    /// The pivot supervariable, now the element (SuiteSparse `me`).
    pub element: i32,
    /// Was `p` adjacent to elements (so `Lp` sits at the free end)?
    pub built_in_free_space: bool,
    /// `Lp` is `lists[pattern_start .. pattern_end]`.
    pub pattern_start: usize,
    pub pattern_end: usize,
    /// Pivots eliminated in this step (grows with mass elimination).
    pub pivots: i32,
    /// `|Lp|` counted in variables, not supervariables (SuiteSparse `degme`).
    pub degree: i32,
}

impl QuotientGraph {
    /// Select pivot: a supervariable of minimum approximate degree, removed
    /// from its degree list.
    pub fn select_pivot(&mut self) -> i32 {
        self.degree_lists.pop_min()
    }

    /// Construct `Lp` for the pivot supervariable `pivot` and absorb the
    /// elements adjacent to it.
    pub fn construct_element(&mut self, pivot: i32) -> Pivot {
        let p = pivot as usize;
        let pivots = self.size[p];
        self.eliminated += pivots as usize;
        // The pivot is in Lp's flag set so it never enters its own pattern.
        self.size[p] = -pivots;

        let built_in_free_space = self.element_count[p] != 0;
        let (pattern_start, pattern_end, degree) = if built_in_free_space {
            self.construct_in_free_space(p)
        } else {
            self.construct_in_place(p)
        };

        self.degree[p] = degree;
        self.start[p] = pattern_start as i32;
        self.length[p] = (pattern_end - pattern_start) as i32;
        Pivot {
            element: pivot,
            built_in_free_space,
            pattern_start,
            pattern_end,
            pivots,
            degree,
        }
    }

    /// `Lp = Ap`: keep the principal variables of `p`'s own list, in place.
    /// Returns `(start, end, |Lp|)`.
    fn construct_in_place(&mut self, p: usize) -> (usize, usize, i32) {
        let begin = self.start[p] as usize;
        let end = begin + self.length[p] as usize;
        let mut kept = begin;
        let mut degree = 0;
        for k in begin..end {
            let i = self.lists[k];
            if self.add_to_pattern(i) {
                degree += self.size[i as usize].abs();
                self.lists[kept] = i;
                kept += 1;
            }
        }
        (begin, kept, degree)
    }

    /// `Lp = Ap ∪ ⋃ Le` written at the free end of the workspace; each
    /// `e ∈ Ep` is absorbed into `p`. Returns `(start, end, |Lp|)`.
    fn construct_in_free_space(&mut self, p: usize) -> (usize, usize, i32) {
        let element_total = self.element_count[p] as usize;
        let variable_total = self.length[p] as usize - element_total;
        let mut read = self.start[p] as usize;
        let mut element_start = self.free;
        let mut degree = 0;

        // Visit each element of Ep, then p itself (its variables Ap).
        for visited in 0..=element_total {
            let (source, mut at, count) = if visited < element_total {
                let e = self.lists[read];
                read += 1;
                (
                    e as usize,
                    self.start[e as usize] as usize,
                    self.length[e as usize] as usize,
                )
            } else {
                (p, read, variable_total)
            };
            for taken in 1..=count {
                let i = self.lists[at];
                at += 1;
                if self.size[i as usize] <= 0 {
                    continue; // not principal, or already in Lp
                }
                if self.free >= self.lists.len() {
                    // Workspace full: keep only what is still unread, compress.
                    self.set_unread(p, read, self.length[p] as usize - (visited + 1));
                    self.set_unread(source, at, count - taken);
                    element_start = self.compress(element_start);
                    at = self.start[source] as usize;
                    read = self.start[p] as usize;
                }
                self.add_to_pattern(i);
                degree += self.size[i as usize].abs();
                self.lists[self.free] = i;
                self.free += 1;
            }
            if source != p {
                // Element absorption: e ⊆ Lp, and p is e's parent.
                self.parent[source] = p as i32;
                self.start[source] = NONE;
                self.flag[source] = 0;
            }
        }
        (element_start, self.free, degree)
    }

    /// Before a compression: the list of `owner` is now `length` entries
    /// from `at` (no list at all when empty).
    fn set_unread(&mut self, owner: usize, at: usize, length: usize) {
        self.start[owner] = if length == 0 { NONE } else { at as i32 };
        self.length[owner] = length as i32;
    }

    /// If `i` is a principal variable not yet in `Lp`: flag it (negate its
    /// size), unlink it from its degree list, and return `true`.
    #[inline]
    fn add_to_pattern(&mut self, i: i32) -> bool {
        let v = i as usize;
        let size = self.size[v];
        if size <= 0 {
            return false;
        }
        self.size[v] = -size;
        self.degree_lists.remove(i, self.degree[v]);
        true
    }
}
