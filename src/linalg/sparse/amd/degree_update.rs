//! Approximate degrees of the variables of the new element `Lp`.
//!
//! **What it computes.** After pivot `p`, only the variables `i ∈ Lp` change
//! degree. The exact external degree `|Ai ∪ ⋃_{e ∈ Ei} Le| − |i|` would need
//! a set union per variable; AMD uses the upper bound (Amestoy, Davis & Duff
//! 1996, §3; every `|·|` counts variables, i.e. sums supervariable sizes)
//!
//! ```text
//! d̄i = min( n − k − |i|,                          k variables eliminated so far
//!           d̄i_old + |Lp \ i|,                      the old bound grows by Lp at most
//!           |Ai \ Lp| + |Lp \ i| + Σ_{e ∈ Ei, e ≠ p} |Le \ Lp| )
//! ```
//!
//! in two scans over `Lp`:
//!
//! * **Scan 1** computes `|Le \ Lp|` for every element `e` adjacent to some
//!   `i ∈ Lp`: start from `|Le|` the first time `e` is met and subtract `|i|`
//!   for each `i ∈ Le ∩ Lp` met. It lives in `flag[e] − flag_mark`, so no
//!   clearing is needed.
//! * **Scan 2** sums the bound for each `i`, pruning its lists as it goes:
//!   absorbed elements and non-principal variables leave, as do variables
//!   of `Lp` (now covered by element `p`), and `p` is put first in `Ei`.
//!   An element with `|Le \ Lp| = 0` is inside `Lp` and is absorbed into `p`
//!   (*aggressive absorption*). A variable left with nothing but `p` is
//!   indistinguishable from the pivot and is eliminated with it (*mass
//!   elimination*). Every other `i` gets a hash of its lists for
//!   [`supervariables`](super::supervariables).
//! * **Finalize** adds `|Lp \ i|` now that `|Lp|` is final, clamps by
//!   `n − k − |i|`, puts each variable back at the head of its degree list,
//!   and drops merged variables from `Lp`.
//!
//! **Cost.** Both scans read each `i ∈ Lp`'s lists once:
//! `O(Σ_{i ∈ Lp} (|Ei| + |Ai|))`, the dominant cost of AMD.
//!
//! **Source.** Amestoy, Davis & Duff 1996, §3 (Algorithms 2–3, "|Le \ Lp|",
//! "degree update", "element absorption"); SuiteSparse AMD `amd_2.c`
//! ("Scan 1", "Scan 2", "restore degree lists", "finalize the new element");
//! Davis 2006, §7.1.

use super::new_element::Pivot;
use super::quotient_graph::QuotientGraph;
use super::NONE;

impl QuotientGraph {
    /// Scan 1: `flag[e] − flag_mark = |Le \ Lp|` for every live element `e`
    /// adjacent to a variable of `Lp`.
    pub fn compute_external_element_sizes(&mut self, pivot: &Pivot) {
        self.reset_flags_if_needed();
        let mark = self.flag_mark;
        // Slices of length n: one bounds check per index serves them all.
        let n = self.n;
        let (start, element_count, size) =
            (&self.start[..n], &self.element_count[..n], &self.size[..n]);
        let (flag, degree) = (&mut self.flag[..n], &self.degree[..n]);
        for &i in &self.lists[pivot.pattern_start..pivot.pattern_end] {
            let i = i as usize;
            let elements = element_count[i] as usize;
            if elements == 0 {
                continue;
            }
            // In Lp, so size[i] is negated.
            let size_i = -size[i];
            let begin = start[i] as usize;
            for &e in &self.lists[begin..begin + elements] {
                let e = e as usize;
                let seen = flag[e];
                if seen >= mark {
                    flag[e] = seen - size_i; // met again: remove i
                } else if seen != 0 {
                    flag[e] = degree[e] + mark - size_i; // first time: |Le| − |i|
                }
            }
        }
    }

    /// Scan 2: the degree bound (without `|Lp|`) of each `i ∈ Lp`, with
    /// pruning of its lists, aggressive absorption, mass elimination and
    /// hashing.
    pub fn update_degrees(&mut self, pivot: &mut Pivot) {
        for k in pivot.pattern_start..pivot.pattern_end {
            let i = self.lists[k];
            match self.prune_and_bound(i, pivot.element) {
                Some((partial_degree, hash)) => {
                    let v = i as usize;
                    self.degree[v] = self.degree[v].min(partial_degree);
                    self.hash_buckets.insert(&mut self.links, i, hash);
                }
                None => self.mass_eliminate(i, pivot),
            }
        }
        let p = pivot.element as usize;
        self.degree[p] = pivot.degree;
        // Every flag value set by scan 1 is now below the mark.
        self.max_element_degree = self.max_element_degree.max(pivot.degree);
        self.flag_mark += self.max_element_degree;
        self.reset_flags_if_needed();
    }

    /// For `i ∈ Lp`: rewrite its lists as `[p, Ei \ absorbed, Ai \ Lp]`
    /// (only principal variables kept) and return
    /// `(|Ai \ Lp| + Σ |Le \ Lp|, hash of the kept lists)`, or `None` when
    /// nothing but `p` is left (mass elimination).
    fn prune_and_bound(&mut self, i: i32, element: i32) -> Option<(i32, u32)> {
        let v = i as usize;
        let (n, mark, aggressive) = (self.n, self.flag_mark, self.aggressive);
        let begin = self.start[v] as usize;
        let element_total = self.element_count[v] as usize;
        let list = &mut self.lists[begin..begin + self.length[v] as usize];
        let (flag, size) = (&mut self.flag[..n], &self.size[..n]);
        let (parent, start) = (&mut self.parent[..n], &mut self.start[..n]);
        let mut kept = 0;
        let mut degree = 0;
        let mut hash = 0u32;

        // Elements: add |Le \ Lp|; absorb those inside Lp.
        for k in 0..element_total {
            let e = list[k];
            let seen = flag[e as usize];
            if seen == 0 {
                continue; // absorbed earlier
            }
            let external = seen - mark;
            if external > 0 || !aggressive {
                degree += external;
                list[kept] = e;
                kept += 1;
                hash = hash.wrapping_add(e as u32);
            } else {
                // Aggressive absorption: Le ⊆ Lp.
                parent[e as usize] = element;
                start[e as usize] = NONE;
                flag[e as usize] = 0;
                self.counters.aggressive_absorptions += 1;
            }
        }
        let first_variable = kept;

        // Variables: keep those principal and outside Lp (size > 0).
        for k in element_total..list.len() {
            let j = list[k];
            let size_j = size[j as usize];
            if size_j > 0 {
                degree += size_j;
                list[kept] = j;
                kept += 1;
                hash = hash.wrapping_add(j as u32);
            }
        }

        if first_variable == 0 && kept == 0 {
            return None;
        }
        // Put p first: the first variable moves to the end, the first
        // element to the end of the element part.
        list[kept] = list[first_variable];
        list[first_variable] = list[0];
        list[0] = element;
        self.element_count[v] = first_variable as i32 + 1;
        self.length[v] = kept as i32 + 1;
        Some((degree, hash))
    }

    /// Mass elimination: `i` is adjacent to nothing but `p`, so it joins the
    /// pivot block (its rows leave `Lp` for the pivots).
    fn mass_eliminate(&mut self, i: i32, pivot: &mut Pivot) {
        let v = i as usize;
        let size_i = -self.size[v];
        self.parent[v] = pivot.element;
        self.start[v] = NONE;
        self.size[v] = 0;
        self.element_count[v] = NONE;
        pivot.degree -= size_i;
        pivot.pivots += size_i;
        self.eliminated += size_i as usize;
        self.counters.mass_eliminated += size_i as usize;
    }

    /// Finalize: complete each degree with `|Lp \ i|`, clamp it by the
    /// variables left, put the variable back at the head of its degree list,
    /// and keep only principal variables in `Lp`.
    pub fn finalize_element(&mut self, pivot: &Pivot) {
        let n = self.n;
        let left = (n - self.eliminated) as i32;
        let (size, degree) = (&mut self.size[..n], &mut self.degree[..n]);
        let pattern = &mut self.lists[pivot.pattern_start..pivot.pattern_end];
        let mut kept = 0;
        for k in 0..pattern.len() {
            let i = pattern[k];
            let v = i as usize;
            let size_i = -size[v];
            if size_i <= 0 {
                continue; // merged into another supervariable, or mass eliminated
            }
            size[v] = size_i;
            let d = (degree[v] + pivot.degree - size_i).min(left - size_i);
            self.degree_lists.insert(&mut self.links, i, d);
            degree[v] = d;
            pattern[kept] = i;
            kept += 1;
        }
        let kept = pivot.pattern_start + kept;

        let p = pivot.element as usize;
        self.size[p] = pivot.pivots;
        self.length[p] = (kept - pivot.pattern_start) as i32;
        if kept == pivot.pattern_start {
            // Lp is empty: p is a root of the assembly tree.
            self.start[p] = NONE;
            self.flag[p] = 0;
        }
        if pivot.built_in_free_space {
            // Merged variables left Lp: give their slots back.
            self.lists.truncate(kept);
        }
        let (f, r) = (
            pivot.pivots as u64,
            (pivot.degree as usize + self.counters.dense_rows) as u64,
        );
        self.counters.lower_nnz_estimate += f * r + f * (f - 1) / 2;
    }
}
