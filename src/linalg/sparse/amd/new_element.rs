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
//! [`compress`]), keeping the parts of the
//! lists not yet read.
//!
//! **Cost.** `O(|Ap| + Σ_{e ∈ Ep} |Le|)`; every entry read belongs to a
//! list that is freed here, so over the whole ordering this is `O(nnz(A))`
//! plus the sizes of the elements formed.
//!
//! **Source.** Amestoy, Davis & Duff 1996, Algorithm 2 (steps "select pivot"
//! and "construct Lp", "element absorption"); SuiteSparse AMD `amd_2.c`
//! ("get pivot of minimum degree", "construct new element"); Davis 2006, §7.1.

use super::quotient_graph::{compress, QuotientGraph};
use super::NONE;

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
        self.degree_lists.pop_min(&mut self.links)
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
        let n = self.n;
        let begin = self.start[p] as usize;
        let list = &mut self.lists[begin..begin + self.length[p] as usize];
        let (size, degree) = (&mut self.size[..n], &self.degree[..n]);
        let mut kept = 0;
        let mut element_degree = 0;
        for k in 0..list.len() {
            let i = list[k];
            let size_i = size[i as usize];
            if size_i > 0 {
                // Principal and not yet in Lp: flag it, unlink it, keep it.
                size[i as usize] = -size_i;
                self.degree_lists
                    .remove(&mut self.links, i, degree[i as usize]);
                element_degree += size_i;
                list[kept] = i;
                kept += 1;
            }
        }
        (begin, begin + kept, element_degree)
    }

    /// `Lp = Ap ∪ ⋃ Le` written at the free end of the workspace; each
    /// `e ∈ Ep` is absorbed into `p`. Returns `(start, end, |Lp|)`.
    fn construct_in_free_space(&mut self, p: usize) -> (usize, usize, i32) {
        let n = self.n;
        let QuotientGraph {
            lists,
            workspace_len,
            start,
            length,
            element_count,
            size,
            degree,
            parent,
            flag,
            degree_lists,
            links,
            counters,
            ..
        } = self;
        let (start, length, size) = (&mut start[..n], &mut length[..n], &mut size[..n]);
        let (degree, parent, flag) = (&degree[..n], &mut parent[..n], &mut flag[..n]);
        let element_total = element_count[p] as usize;
        let variable_total = length[p] as usize - element_total;
        let mut read = start[p] as usize;
        let mut element_start = lists.len();
        let mut element_degree = 0;
        // Visit each element of Ep, then p itself (its variables Ap).
        for visited in 0..=element_total {
            let (source, mut at, count) = if visited < element_total {
                let e = lists[read] as usize;
                read += 1;
                (e, start[e] as usize, length[e] as usize)
            } else {
                (p, read, variable_total)
            };
            for taken in 1..=count {
                let i = lists[at];
                at += 1;
                let size_i = size[i as usize];
                if size_i <= 0 {
                    continue; // not principal, or already in Lp
                }
                if lists.len() == *workspace_len {
                    // Workspace full: keep only what is still unread, compress.
                    let unread_of_p = element_total + variable_total - (visited + 1);
                    let unread = [(p, read, unread_of_p), (source, at, count - taken)];
                    element_start = compress_unread(lists, start, length, element_start, unread);
                    counters.garbage_collections += 1;
                    at = start[source] as usize;
                    read = start[p] as usize;
                }
                // Flag i as in Lp, unlink it from its degree list, append it.
                size[i as usize] = -size_i;
                degree_lists.remove(links, i, degree[i as usize]);
                element_degree += size_i;
                lists.push(i);
            }
            absorb(source, p, parent, start, flag);
        }
        (element_start, lists.len(), element_degree)
    }
}

/// Element absorption: an element `e` of Ep (`e ⊆ Lp`) is absorbed into
/// the new element `p`, which becomes its parent; `e` is gone. (`p`'s own
/// list, read last, is no element of Ep.)
fn absorb(e: usize, p: usize, parent: &mut [i32], start: &mut [i32], flag: &mut [i32]) {
    if e != p {
        parent[e] = p as i32;
        start[e] = NONE;
        flag[e] = 0;
    }
}

/// Compresses the workspace when it is full in the middle of reading
/// lists: each `(owner, at, len)` of `unread` says that only `len` entries
/// from `at` of `owner`'s list are still to be read, so only those are
/// kept. Returns where the new element's list now starts.
fn compress_unread(
    lists: &mut Vec<i32>,
    start: &mut [i32],
    length: &mut [i32],
    element_start: usize,
    unread: [(usize, usize, usize); 2],
) -> usize {
    for (owner, at, len) in unread {
        set_unread(start, length, owner, at, len);
    }
    compress(lists, start, length, element_start)
}

/// Before a compression: the list of `owner` is now `len` entries from
/// `at` (no list at all when empty).
fn set_unread(start: &mut [i32], length: &mut [i32], owner: usize, at: usize, len: usize) {
    start[owner] = if len == 0 { NONE } else { at as i32 };
    length[owner] = len as i32;
}
