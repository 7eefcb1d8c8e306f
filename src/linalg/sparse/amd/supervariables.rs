//! Supervariable detection: merging variables of `Lp` with identical lists.
//!
//! **What it computes.** Two variables `i, j ∈ Lp` are *indistinguishable*
//! when they have the same adjacent elements and the same adjacent
//! variables (`Ei = Ej`, `Ai = Aj`, after scan 2 pruned both). They will
//! have the same pattern from now on, so `j` is merged into `i`: `i`'s size
//! grows by `|j|` and `j` becomes non-principal, its parent `i`. Only
//! variables of `Lp` can newly become indistinguishable, so only they are
//! checked.
//!
//! **The idea.** Scan 2 gave each `i` the hash `Σ Ei + Σ Ai`; equal
//! lists give equal hashes, so only variables in the same hash bucket are
//! compared. For the first variable `i` of a bucket its list is flagged in
//! `flag`, then every later `j` of the bucket with the same list lengths is
//! compared entry by entry; then the next unmerged variable of the bucket
//! takes `i`'s role. The bucket order (most recent first) decides which
//! variable stays principal, exactly as in SuiteSparse, so the outcome does
//! not depend on the hash function itself.
//!
//! **Cost.** Expected `O(Σ_{i ∈ Lp} |list of i|)` when the hash spreads
//! well; a bucket of `b` distinct lists costs `O(b²)` list comparisons in
//! the worst case.
//!
//! **Source.** Amestoy, Davis & Duff 1996, §3 ("supervariable
//! detection"); SuiteSparse AMD `amd_2.c` ("supervariable detection");
//! Davis 2006, §7.1.

use super::new_element::Pivot;
use super::quotient_graph::QuotientGraph;
use super::NONE;

impl QuotientGraph {
    /// Supervariable detection among the variables of `Lp`.
    pub fn detect_supervariables(&mut self, pivot: &Pivot) {
        for k in pivot.pattern_start..pivot.pattern_end {
            let i = self.lists[k];
            // Still principal and in Lp (not mass eliminated, not merged).
            if self.size[i as usize] < 0 {
                let first = self.hash_buckets.take_bucket_of(&self.links, i);
                // Only a bucket of two or more variables can merge anything.
                if first != NONE && self.links[first as usize].next != NONE {
                    self.merge_bucket(first);
                }
            }
        }
    }

    /// Compares every pair `(i, j)`, `i` before `j`, of the bucket starting
    /// at `first`, merging `j` into `i` when their lists are equal.
    fn merge_bucket(&mut self, first: i32) {
        let mut i = first;
        while i != NONE && self.links[i as usize].next != NONE {
            self.flag_list_of(i);
            let mut previous = i;
            let mut j = self.links[i as usize].next;
            while j != NONE {
                let after = self.links[j as usize].next;
                if self.has_flagged_list(i, j) {
                    self.merge_into(j, i);
                    self.links[previous as usize].next = after;
                } else {
                    previous = j;
                }
                j = after;
            }
            // A fresh mark unflags i's list for the next comparison.
            self.flag_mark += 1;
            i = self.links[i as usize].next;
        }
    }

    /// Flags every entry of `i`'s list but the first (which is `p` for all
    /// variables of `Lp`).
    fn flag_list_of(&mut self, i: i32) {
        let begin = self.start[i as usize] as usize;
        let end = begin + self.length[i as usize] as usize;
        for &x in &self.lists[begin + 1..end] {
            self.flag[x as usize] = self.flag_mark;
        }
    }

    /// Does `j` have the same list lengths as `i` and only flagged entries
    /// (hence the same lists)?
    fn has_flagged_list(&self, i: i32, j: i32) -> bool {
        let (i, j) = (i as usize, j as usize);
        if self.length[j] != self.length[i] || self.element_count[j] != self.element_count[i] {
            return false;
        }
        let begin = self.start[j] as usize;
        let end = begin + self.length[j] as usize;
        self.lists[begin + 1..end]
            .iter()
            .all(|&x| self.flag[x as usize] == self.flag_mark)
    }

    /// `j` joins supervariable `i` (both in `Lp`, so both sizes are negated).
    fn merge_into(&mut self, j: i32, i: i32) {
        let (j, i) = (j as usize, i as usize);
        self.parent[j] = i as i32;
        self.start[j] = NONE;
        self.size[i] += self.size[j];
        self.size[j] = 0;
        self.element_count[j] = NONE;
        self.counters.merged_variables += 1;
    }
}
