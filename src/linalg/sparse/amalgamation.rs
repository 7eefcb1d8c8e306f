//! Relaxed supernodes (amalgamation): merge a supernode into its parent
//! when the zeros this stores stay few.
//!
//! [Fundamental supernodes](super::supernodes) only join columns whose
//! patterns nest exactly; on a cloth half of them are single columns, too
//! narrow for the dense kernels. Merging a supernode `s` into the next one,
//! `s + 1`, when `s + 1` is its parent in the supernodal elimination tree,
//! gives one block whose rows are the union of both patterns: every column
//! of `s` then stores the rows it lacked as explicit zeros, the price of
//! wider blocks. Postordered, `s` and `s + 1` are adjacent columns, so the
//! merged columns stay one contiguous range.
//!
//! The rule, CHOLMOD's (`cholmod_super_symbolic.c`, "relaxed
//! amalgamation", with its default parameters): going from the last
//! supernode to the first, `s` (with `c₀` columns and `r₀` rows in its
//! first column) merges into its current parent `s + 1` (`c₁`, `r₁`,
//! already holding `z₁` zeros) when, for the merged node of `c = c₀ + c₁`
//! columns,
//!
//! ```text
//! new zeros   z_new = c₀ (r₁ + c₀ − r₀)
//! size        t     = c (c + 1)/2 + c (r₁ − c₁)
//! fraction    z     = (z₁ + z_new) / t
//! merge  ⇔  c ≤ 4  or  z_new = 0
//!          or (c ≤ 16 and z < 0.8) or (c ≤ 48 and z < 0.1) or z < 0.05
//! ```
//!
//! The merged node has `r = c₀ + r₁` rows: its own columns, then the rows
//! of `s + 1`. So a relaxed supernode's rows are its columns followed by
//! the pattern of the first column of its last fundamental member, and
//! every column keeps the rows from its own diagonal down (the storage of
//! [`supernodal`](super::supernodal) is unchanged).
//!
//! Cost `O(number of supernodes)` for the partition (with path compression
//! when looking up the current parent).
//!
//! Source: Ashcraft & Grimes, "The influence of relaxed supernode
//! partitions on the multifrontal method", ACM TOMS 15(4), 1989; Chen,
//! Davis, Hager, Rajamanickam, "CHOLMOD", ACM TOMS 35(3), 2008 (the rule
//! and its parameters `nrelax = 4, 16, 48`, `zrelax = 0.8, 0.1, 0.05`).

use super::supernode_rows::supernodal_tree;
use super::supernodes::Supernodes;

/// The parameters of the merge rule above.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relaxation {
    /// Column limits: always merge up to `columns[0]`; up to `columns[1]`
    /// and `columns[2]` when the zero fraction is below `zeros[0]` and
    /// `zeros[1]`; any size below `zeros[2]`.
    pub columns: [usize; 3],
    pub zeros: [f64; 3],
}

impl Relaxation {
    /// CHOLMOD's defaults.
    pub const CHOLMOD: Relaxation = Relaxation {
        columns: [4, 16, 48],
        zeros: [0.8, 0.1, 0.05],
    };

    /// Merge a supernode into its parent while the merged node has at most
    /// three columns, whatever zeros it stores; nothing larger. The
    /// simulation's factor: on cloth most fundamental supernodes have one
    /// or two columns, each a call of the dense kernels too small to pay
    /// for itself, and merging them costs little memory (a few per cent
    /// of `L`) where CHOLMOD's wider rule costs a fifth and slows the
    /// solve (`docs/performance.md`, section 3).
    pub const SMALL: Relaxation = Relaxation {
        columns: [3, 0, 0],
        zeros: [0.0, 0.0, 0.0],
    };

    /// No merging at all: the fundamental supernodes (to measure against).
    pub const NONE: Relaxation = Relaxation {
        columns: [0, 0, 0],
        zeros: [0.0, 0.0, 0.0],
    };

    /// Should a node of `columns` columns with this `zero_fraction` be
    /// formed?
    fn allows(&self, columns: usize, zero_fraction: f64) -> bool {
        let [small, medium, large] = self.columns;
        let [loose, tight, tightest] = self.zeros;
        columns <= small
            || (columns <= medium && zero_fraction < loose)
            || (columns <= large && zero_fraction < tight)
            || zero_fraction < tightest
    }
}

/// Which supernodes a supernodal factor uses, by name: the choice the
/// simulation and `analyze --supernodes` offer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SupernodeMerging {
    /// The fundamental supernodes, none merged ([`Relaxation::NONE`]).
    Fundamental,
    /// Merged while at most three columns ([`Relaxation::SMALL`]): the
    /// simulation's default.
    #[default]
    Small,
    /// CHOLMOD's rule ([`Relaxation::CHOLMOD`]).
    Relaxed,
}

impl SupernodeMerging {
    /// The merging rule of this choice.
    pub fn relaxation(self) -> Relaxation {
        match self {
            SupernodeMerging::Fundamental => Relaxation::NONE,
            SupernodeMerging::Small => Relaxation::SMALL,
            SupernodeMerging::Relaxed => Relaxation::CHOLMOD,
        }
    }
}

impl std::str::FromStr for SupernodeMerging {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        match name {
            "fundamental" => Ok(SupernodeMerging::Fundamental),
            "small" => Ok(SupernodeMerging::Small),
            "relaxed" => Ok(SupernodeMerging::Relaxed),
            other => Err(format!(
                "unknown supernodes '{other}' (expected fundamental, small or relaxed)"
            )),
        }
    }
}

impl Default for Relaxation {
    fn default() -> Self {
        Relaxation::CHOLMOD
    }
}

/// The relaxed partition of the fundamental supernodes `fundamental` of a
/// factor with elimination tree `parent` and column counts `count`.
///
/// Returns the relaxed [`Supernodes`] and, for each of them, the first
/// column of its last fundamental member (whose pattern its rows end with).
pub fn relax(
    fundamental: &Supernodes,
    parent: &[Option<usize>],
    count: &[usize],
    rule: &Relaxation,
) -> (Supernodes, Vec<usize>) {
    let nodes = fundamental.len();
    let first = |s: usize| fundamental.columns(s).start;
    let node_parent = supernodal_tree(parent, fundamental);
    let mut merged_into: Vec<Option<usize>> = vec![None; nodes];
    let mut width: Vec<usize> = (0..nodes).map(|s| fundamental.columns(s).len()).collect();
    let mut rows: Vec<usize> = (0..nodes).map(|s| count[first(s)]).collect();
    let mut zeros = vec![0.0f64; nodes];
    for s in (0..nodes.saturating_sub(1)).rev() {
        let Some(p) = node_parent[s] else { continue };
        if current_node(&mut merged_into, p) != s + 1 {
            continue;
        }
        let (c0, c1) = (width[s] as f64, width[s + 1] as f64);
        let (r0, r1) = (rows[s] as f64, rows[s + 1] as f64);
        let c = c0 + c1;
        let new_zeros = c0 * (r1 + c0 - r0);
        let total_zeros = zeros[s + 1] + new_zeros;
        let size = c * (c + 1.0) / 2.0 + c * (r1 - c1);
        let merge = new_zeros == 0.0 || rule.allows(width[s] + width[s + 1], total_zeros / size);
        if merge {
            zeros[s] = total_zeros;
            merged_into[s + 1] = Some(s);
            rows[s] = width[s] + rows[s + 1];
            width[s] += width[s + 1];
        }
    }
    let mut start = Vec::new();
    let mut last_member_first = Vec::new();
    for s in 0..nodes {
        if merged_into[s].is_none() {
            start.push(first(s));
            last_member_first.push(first(s));
        } else if let Some(last) = last_member_first.last_mut() {
            *last = first(s); // a later member of the node opened above
        }
    }
    let n = parent.len();
    if n > 0 {
        start.push(n);
    }
    (Supernodes::from_starts(start, n), last_member_first)
}

/// The live node that `s` has been merged into (itself if none), with
/// path compression.
fn current_node(merged_into: &mut [Option<usize>], s: usize) -> usize {
    let mut root = s;
    while let Some(next) = merged_into[root] {
        root = next;
    }
    let mut node = s;
    while let Some(next) = merged_into[node] {
        merged_into[node] = Some(root);
        node = next;
    }
    root
}
