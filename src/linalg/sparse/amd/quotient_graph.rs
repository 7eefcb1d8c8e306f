//! The quotient graph: variables and elements in one integer workspace.
//!
//! **What it stores.** Eliminating a variable `p` from the graph of a
//! symmetric matrix joins all its neighbours into a clique. Storing cliques
//! edge by edge would grow without bound; the quotient graph stores each
//! clique once, as an *element* `e` named after its pivot, holding the list
//! `Le` of its variables. A variable `i` then stores two lists, back to back
//! in the workspace:
//!
//! ```text
//! lists[start[i] ..][.. element_count[i]]   the elements Ei adjacent to i
//! lists[.. start[i] + length[i]]            the variables Ai still adjacent to i
//! ```
//!
//! and its pattern in the Schur complement is `Ai ∪ ⋃_{e ∈ Ei} Le`. Because
//! every new element absorbs the elements it covers, the total storage never
//! exceeds that of `A` (Amestoy, Davis & Duff 1996, §2; George & Liu 1989).
//!
//! Variables with the same pattern are merged into a *supervariable* named
//! after one *principal* variable; `size[i]` counts its members and is 0 for
//! a non-principal (or dense) variable.
//!
//! **Garbage collection.** New elements are written at the end of the used
//! part of the workspace. When it is full, the live lists are slid to the
//! front ([`compress`]), `O(workspace)` each time, rare with
//! the 20 % elbow room of [`pattern`](super::pattern).
//!
//! **Source.** Amestoy, Davis & Duff 1996, §2–3; SuiteSparse AMD `amd_2.c`
//! (arrays `Iw`, `Pe`, `Len`, `Elen`, `Nv`, `Degree`, `W`, and its
//! compression step); Davis 2006, §7.1.

use super::degree_lists::{DegreeLists, Link};
use super::hash_buckets::HashBuckets;
use super::pattern::SymmetricPattern;
use super::{AmdInfo, NONE};

/// Counters reported in [`AmdInfo`].
#[derive(Default)]
pub(super) struct Counters {
    pub dense_rows: usize,
    pub empty_rows: usize,
    pub merged_variables: usize,
    pub mass_eliminated: usize,
    pub aggressive_absorptions: usize,
    pub garbage_collections: usize,
    /// Strictly lower entries of `L` as AMD estimates them (SuiteSparse `lnz`).
    pub lower_nnz_estimate: u64,
}

/// Variables, elements and the bookkeeping of the elimination.
pub(super) struct QuotientGraph {
    /// Order of the matrix.
    pub n: usize,
    /// The workspace holding every list (SuiteSparse `Iw`); its length is
    /// the part in use (SuiteSparse `pfree`), new elements are pushed into
    /// its spare capacity.
    pub lists: Vec<i32>,
    /// Capacity of `lists` (SuiteSparse `iwlen`): compress when reached.
    pub workspace_len: usize,
    /// Where the list of a live variable or element starts, or [`NONE`].
    pub start: Vec<i32>,
    /// Length of that list (elements and variables together for a variable).
    pub length: Vec<i32>,
    /// For a variable: how many entries at the front of its list are elements.
    pub element_count: Vec<i32>,
    /// Supervariable size (number of pivots for an element); 0 for a
    /// non-principal or dense variable; negated while the variable is in the
    /// pattern of the element being built.
    pub size: Vec<i32>,
    /// Variable: approximate external degree. Element: `|Le|` when formed.
    pub degree: Vec<i32>,
    /// The element or supervariable that absorbed this one, or [`NONE`].
    pub parent: Vec<i32>,
    /// Element: 0 once absorbed, else `flag[e] - flag_mark = |Le \ Lp|`
    /// after scan 1. Variable: `== flag_mark` while marked.
    pub flag: Vec<i32>,
    /// Current value meaning "marked"; raised instead of clearing `flag`.
    pub flag_mark: i32,
    /// Largest `|Le|` of any element so far (SuiteSparse `lemax`).
    pub max_element_degree: i32,
    /// Variables eliminated so far, dense ones included.
    pub eliminated: usize,
    /// Is aggressive absorption on?
    pub aggressive: bool,
    pub degree_lists: DegreeLists,
    pub hash_buckets: HashBuckets,
    /// List links of every supervariable (degree list or hash bucket).
    pub links: Vec<Link>,
    pub counters: Counters,
}

impl QuotientGraph {
    /// The quotient graph of `A + Aᵀ` before any elimination: no elements,
    /// every variable its own supervariable of degree `|Ai|`.
    pub fn new(pattern: SymmetricPattern, aggressive: bool) -> Self {
        let n = pattern.start.len();
        QuotientGraph {
            n,
            workspace_len: pattern.workspace_len,
            lists: pattern.lists,
            degree: pattern.length.clone(),
            start: pattern.start,
            length: pattern.length,
            element_count: vec![0; n],
            size: vec![1; n],
            parent: vec![NONE; n],
            flag: vec![1; n],
            flag_mark: 2,
            max_element_degree: 0,
            eliminated: 0,
            aggressive,
            degree_lists: DegreeLists::new(n),
            hash_buckets: HashBuckets::new(n),
            links: vec![Link::UNLINKED; n],
            counters: Counters::default(),
        }
    }

    /// Initialisation: a row with no off-diagonal entry is an element at
    /// once; a row with more than `dense_limit` entries is dense, taken out
    /// of the graph (size 0, no parent) to be ordered last; every other row
    /// goes into the degree list of its degree, in increasing order.
    pub fn set_aside_dense_and_empty_rows(&mut self, dense_limit: usize) {
        for i in 0..self.n {
            let degree = self.degree[i];
            if degree == 0 {
                self.counters.empty_rows += 1;
                self.eliminated += 1;
                self.start[i] = NONE;
                self.flag[i] = 0;
            } else if degree as usize > dense_limit {
                self.counters.dense_rows += 1;
                self.eliminated += 1;
                self.size[i] = 0;
                self.start[i] = NONE;
            } else {
                self.degree_lists.insert(&mut self.links, i as i32, degree);
            }
        }
    }

    /// Makes sure `flag_mark + n` cannot overflow: when the mark gets too
    /// large, every live flag is reset to 1 and the mark to 2 (absorbed
    /// elements keep their 0). Afterwards every flag is below the mark.
    pub fn reset_flags_if_needed(&mut self) {
        let limit = i32::MAX - self.n as i32;
        if self.flag_mark < 2 || self.flag_mark >= limit {
            for f in self.flag.iter_mut().filter(|f| **f != 0) {
                *f = 1;
            }
            self.flag_mark = 2;
        }
    }

    /// The statistics gathered so far (without the tree's node count).
    pub fn info(&self) -> AmdInfo {
        let c = &self.counters;
        let dense = c.dense_rows as u64;
        let dense_block = dense * dense.saturating_sub(1) / 2;
        AmdInfo {
            dense_rows: c.dense_rows,
            empty_rows: c.empty_rows,
            elements: 0,
            merged_variables: c.merged_variables,
            mass_eliminated: c.mass_eliminated,
            aggressive_absorptions: c.aggressive_absorptions,
            garbage_collections: c.garbage_collections,
            workspace_len: self.workspace_len,
            factor_nnz_estimate: (c.lower_nnz_estimate + dense_block) as usize + self.n,
        }
    }

    /// The assembly tree once every variable is eliminated. A node with
    /// `size > 0` is an element (a supernode of `size` pivots); a variable
    /// with size 0 points to the supervariable or element that absorbed it,
    /// or has no parent if it is dense. The front of element `e` has
    /// `size[e] + degree[e]` rows: its pivots plus `|Le|` when it was formed
    /// (mass elimination moves rows from one to the other without changing
    /// the sum). The graph's other `n`-vectors are handed over as workspace.
    pub fn into_assembly_tree(self) -> AssemblyTree {
        let mut front_size = self.degree;
        for (front, &size) in front_size.iter_mut().zip(&self.size) {
            *front = if size > 0 { size + *front } else { 0 };
        }
        AssemblyTree {
            parent: self.parent,
            size: self.size,
            front_size,
            workspace: [self.start, self.length, self.element_count, self.flag],
        }
    }
}

/// The assembly tree of the elimination, see [`QuotientGraph::into_assembly_tree`].
pub(super) struct AssemblyTree {
    /// Parent element or supervariable, or [`NONE`] for a root or dense row.
    pub parent: Vec<i32>,
    /// Pivots of an element; 0 for a variable merged away or dense.
    pub size: Vec<i32>,
    /// Rows of each element's frontal matrix.
    pub front_size: Vec<i32>,
    /// Four spare `n`-vectors.
    pub workspace: [Vec<i32>; 4],
}

/// Garbage collection: slides every live list (those with `start ≥ 0`) to
/// the front of `lists`, then the partial new element `lists[element_start..]`
/// after them, and shortens `lists` to what is in use. Returns where the
/// partial element now starts.
///
/// Each live list's first entry is swapped with `-(owner) - 2` (negative,
/// unlike any index) so the owners can be found in one sweep; the entry
/// itself waits in `start[owner]`.
pub(super) fn compress(
    lists: &mut Vec<i32>,
    start: &mut [i32],
    length: &[i32],
    element_start: usize,
) -> usize {
    for (owner, first) in start.iter_mut().enumerate() {
        if *first >= 0 {
            let at = *first as usize;
            *first = lists[at];
            lists[at] = -(owner as i32) - 2;
        }
    }
    let (mut source, mut target) = (0, 0);
    while source < element_start {
        let owner = -lists[source] - 2;
        source += 1;
        if owner >= 0 {
            // A tagged first entry: copy its list down.
            let owner = owner as usize;
            lists[target] = start[owner];
            start[owner] = target as i32;
            target += 1;
            let rest = length[owner] as usize - 1;
            lists.copy_within(source..source + rest, target);
            source += rest;
            target += rest;
        }
    }
    let element_len = lists.len() - element_start;
    lists.copy_within(element_start.., target);
    lists.truncate(target + element_len);
    target
}
