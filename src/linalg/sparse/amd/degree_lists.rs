//! Degree lists: the supervariables bucketed by approximate degree.
//!
//! **What it computes.** For every degree `d`, a doubly linked list of the
//! supervariables whose approximate external degree is `d`, and the smallest
//! `d` whose list may be non-empty. Selecting a pivot of minimum degree is
//! then "take the head of the first non-empty list".
//!
//! **The idea.** Degrees lie in `0..n`, so an array of list heads indexed by
//! degree (a bucket sort that stays sorted under updates) replaces a
//! priority queue. A variable whose degree changes is unlinked in `O(1)` and
//! pushed at the *head* of its new list, so among equal degrees the most
//! recently updated variable is chosen first. That tie-breaking rule is
//! SuiteSparse's, and it is part of why AMD's orderings are good.
//!
//! **Cost.** `O(1)` per insertion and removal; the scan for the minimum is
//! amortised over the pivot steps (the minimum only falls when a degree is
//! inserted below it).
//!
//! **Source.** Amestoy, Davis & Duff 1996, §3 ("degree lists"); SuiteSparse
//! AMD `amd_2.c` (`Head`, `Next`, `Last`); Davis 2006, §7.1.

use super::NONE;

/// The neighbours of a supervariable in the one list it is in: a degree
/// list, or (while it is in `Lp`) a hash bucket of
/// [`hash_buckets`](super::hash_buckets). Side by side so that one cache
/// line holds both (SuiteSparse's `Next` and `Last`).
#[derive(Clone, Copy)]
pub(super) struct Link {
    /// Next supervariable in the same list, or [`NONE`].
    pub next: i32,
    /// Degree list: previous supervariable, or [`NONE`] at the head.
    /// Hash bucket: the bucket's number.
    pub previous: i32,
}

impl Link {
    /// In no list.
    pub const UNLINKED: Link = Link {
        next: NONE,
        previous: NONE,
    };
}

/// Heads of the degree lists; the links live in a `[Link]` shared with the
/// hash buckets.
pub(super) struct DegreeLists {
    /// `head[d]`: first supervariable of degree `d`, or [`NONE`].
    head: Vec<i32>,
    /// No list below this degree is non-empty.
    min_degree: usize,
}

impl DegreeLists {
    /// `n` empty lists for degrees `0..n`.
    pub fn new(n: usize) -> Self {
        DegreeLists {
            head: vec![NONE; n],
            min_degree: 0,
        }
    }

    /// Pushes `variable` at the head of the list of `degree`.
    #[inline]
    pub fn insert(&mut self, links: &mut [Link], variable: i32, degree: i32) {
        let d = degree as usize;
        let old_head = self.head[d];
        if old_head != NONE {
            links[old_head as usize].previous = variable;
        }
        links[variable as usize] = Link {
            next: old_head,
            previous: NONE,
        };
        self.head[d] = variable;
        self.min_degree = self.min_degree.min(d);
    }

    /// Unlinks `variable` from the list of `degree` (its current degree).
    #[inline]
    pub fn remove(&mut self, links: &mut [Link], variable: i32, degree: i32) {
        let Link { next, previous } = links[variable as usize];
        if next != NONE {
            links[next as usize].previous = previous;
        }
        if previous != NONE {
            links[previous as usize].next = next;
        } else {
            self.head[degree as usize] = next;
        }
    }

    /// Removes and returns the head of the lowest non-empty list (a variable
    /// of minimum approximate degree).
    ///
    /// # Panics
    /// When every list is empty (the caller knows variables remain).
    pub fn pop_min(&mut self, links: &mut [Link]) -> i32 {
        let degree = (self.min_degree..self.head.len())
            .find(|&d| self.head[d] != NONE)
            .expect("a variable remains to be eliminated");
        self.min_degree = degree;
        let variable = self.head[degree];
        self.remove(links, variable, degree as i32);
        variable
    }
}
