//! Hash buckets: the variables of the new element `Lp`, grouped by a hash
//! of their lists, so that only variables in the same bucket are compared
//! when looking for supervariables (`supervariables.rs`).
//!
//! **The idea.** Two variables with identical adjacency lists have equal
//! hashes, so a bucket holds every candidate partner of a variable. The
//! buckets are singly linked lists threaded through the same [`Link`]
//! array as the degree lists (a variable of `Lp` is in no degree list).
//!
//! **Cost.** `O(1)` per insertion; emptying a bucket is `O(1)`.
//!
//! **Source.** Amestoy, Davis & Duff 1996, §3 ("supervariable
//! detection"); SuiteSparse AMD `amd_2.c` (`Head` reused as hash heads).

use super::degree_lists::Link;
use super::NONE;

/// Hash buckets of the variables of `Lp`, keyed by the hash of their lists.
/// A variable of `Lp` is in no degree list, so its [`Link`] chains the
/// bucket instead (`next`), and remembers the bucket number (`previous`).
///
/// SuiteSparse uses `n` buckets (`hash mod n`). Since the outcome does not
/// depend on the hash function, a power of two no larger than
/// [`MAX_BUCKETS`] is used instead: the bucket heads then stay in the L1
/// cache, and `mod` becomes a mask. Only the variables of one `Lp` are in
/// the buckets at a time, so collisions stay rare.
pub(super) struct HashBuckets {
    /// `head[h]`: most recently inserted variable of bucket `h`, or [`NONE`].
    head: Vec<i32>,
    /// `head.len() − 1`.
    mask: u32,
}

/// Upper bound on the number of hash buckets (4 KiB of heads).
const MAX_BUCKETS: usize = 1024;

impl HashBuckets {
    /// Buckets for `n` variables.
    pub fn new(n: usize) -> Self {
        let buckets = n.clamp(1, MAX_BUCKETS).next_power_of_two();
        HashBuckets {
            head: vec![NONE; buckets],
            mask: buckets as u32 - 1,
        }
    }

    /// Pushes `variable` at the head of the bucket of `hash`.
    #[inline]
    pub fn insert(&mut self, links: &mut [Link], variable: i32, hash: u32) {
        let bucket = (hash & self.mask) as usize;
        links[variable as usize] = Link {
            next: self.head[bucket],
            previous: bucket as i32,
        };
        self.head[bucket] = variable;
    }

    /// Empties the bucket `variable` was put in and returns its first
    /// variable ([`NONE`] if the bucket was already taken).
    pub fn take_bucket_of(&mut self, links: &[Link], variable: i32) -> i32 {
        let bucket = links[variable as usize].previous as usize;
        std::mem::replace(&mut self.head[bucket], NONE)
    }
}
