//! The local step and `Aᵀd` on several threads, to the same bits as on
//! one.
//!
//! Row `i` of `Aᵀd` is a sum over the springs at vertex `i`:
//!
//! ```text
//! (Aᵀd)ᵢ = Σₑ ±dₑ     e = (i, j): +dₑ;  e = (j, i): −dₑ;  springs in increasing order
//! ```
//!
//! [`project_springs_into_transpose`](super::local_step::project_springs_into_transpose)
//! forms it by going through the springs once, adding each `dₑ` to its two
//! rows. Shared among threads that way, two threads could add to one row
//! at once, and in an order that changes from run to run. So here each
//! thread owns a *block* of rows, and goes through every spring at one of
//! its vertices, in increasing order, adding `dₑ` to the rows it owns
//! only: every row receives the same additions in the same order as on one
//! thread. A spring whose ends lie in two blocks is projected twice, once
//! by each thread, to the same bits (the same formula on the same
//! numbers).
//!
//! The blocks are those of the parallel solve (each thread's rows of the
//! factor, [`TeamSolve::owned_rows`](crate::linalg::sparse::supernodal_solve_parallel::TeamSolve::owned_rows)):
//! a thread then forms `b` on the rows it solves first, in its own cache.
//! A block's springs are kept as a list of their own (renumbered into the
//! factor's order, as the one-thread loop keeps them), with the number of
//! each spring, for its rest length, and which of its ends the block owns.
//!
//! Cost: the springs once, plus those between two blocks a second time.
//! Source: the "owner computes" rule of data-parallel programs (Fox et
//! al., *Solving Problems on Concurrent Processors*, 1988), with the
//! springs at a block's boundary computed by both owners.

use super::local_step::project_spring;
use crate::linalg::threads::SharedSlice;
use std::ops::Range;

/// The springs of each block, in increasing order.
#[derive(Debug, Clone)]
pub struct SpringBlocks {
    /// `(new[i], new[j])` for each spring of each block.
    pub(crate) springs: Vec<[usize; 2]>,
    /// The number of each of them among all springs (its rest length).
    pub(crate) numbers: Vec<u32>,
    /// Bit 0: the block owns the first end's row; bit 1: the second's.
    pub(crate) owns: Vec<u8>,
    /// Block `b` is `start[b] .. start[b + 1]`.
    start: Vec<usize>,
    /// The rows of each block.
    rows: Vec<Vec<Range<usize>>>,
}

/// The springs of one block.
#[derive(Debug, Clone, Copy)]
pub struct Block<'a> {
    pub springs: &'a [[usize; 2]],
    pub numbers: &'a [u32],
    pub owns: &'a [u8],
}

/// The first end's row is the block's.
pub(crate) const FIRST: u8 = 1;
/// The second end's row is the block's.
pub(crate) const SECOND: u8 = 2;

impl SpringBlocks {
    /// The blocks of rows `rows` (block `b` owns `rows[b]`, in the numbering
    /// `new_index[old] = new`) and their springs. Springs from a vertex to
    /// itself add nothing to `Aᵀd` and are left out.
    ///
    /// # Panics
    /// When a spring names a vertex beyond `new_index`, a row is in no
    /// block, or there are 2³² springs or more.
    pub fn new(springs: &[[usize; 2]], new_index: &[usize], rows: Vec<Vec<Range<usize>>>) -> Self {
        assert!(
            u32::try_from(springs.len()).is_ok(),
            "32-bit spring numbers"
        );
        let mut owner = vec![usize::MAX; new_index.len()];
        for (b, ranges) in rows.iter().enumerate() {
            for range in ranges {
                owner[range.clone()].fill(b);
            }
        }
        assert!(
            owner.iter().all(|&b| b != usize::MAX),
            "every row in a block"
        );
        let mut lists = vec![Vec::new(); rows.len()];
        for (e, &[i, j]) in springs.iter().enumerate() {
            let (i, j) = (new_index[i], new_index[j]);
            if i == j {
                continue;
            }
            let (a, b) = (owner[i], owner[j]);
            let both = if a == b { FIRST | SECOND } else { FIRST };
            lists[a].push(([i, j], e as u32, both));
            if a != b {
                lists[b].push(([i, j], e as u32, SECOND));
            }
        }
        let mut blocks = SpringBlocks {
            springs: Vec::new(),
            numbers: Vec::new(),
            owns: Vec::new(),
            start: vec![0],
            rows,
        };
        for list in lists {
            for (spring, number, owns) in list {
                blocks.springs.push(spring);
                blocks.numbers.push(number);
                blocks.owns.push(owns);
            }
            blocks.start.push(blocks.springs.len());
        }
        blocks
    }

    /// The number of blocks.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Are there none?
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The rows of block `b`.
    pub fn rows(&self, b: usize) -> &[Range<usize>] {
        &self.rows[b]
    }

    /// The springs of block `b`.
    pub fn block(&self, b: usize) -> Block<'_> {
        let range = self.start[b]..self.start[b + 1];
        Block {
            springs: &self.springs[range.clone()],
            numbers: &self.numbers[range.clone()],
            owns: &self.owns[range],
        }
    }

    /// Bytes held (arrays' lengths).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.springs[..])
            + size_of_val(&self.numbers[..])
            + size_of_val(&self.owns[..])
            + size_of_val(&self.start[..])
            + self.rows.iter().map(|r| size_of_val(&r[..])).sum::<usize>()
    }
}

/// The local step of `block`'s springs from spring `first` on, one at a
/// time: `dₑ` (rest lengths `r`, positions `p`) added to the first end's
/// row of `out` and subtracted from the second's, where the block owns
/// them.
///
/// # Safety
/// No other thread reads or writes the block's rows of `out` meanwhile.
pub unsafe fn add_owned_springs<const L: usize>(
    block: Block,
    r: &[f64],
    p: &[[f64; L]],
    out: &SharedSlice<[f64; 3]>,
    first: usize,
) {
    for e in first..block.springs.len() {
        let [i, j] = block.springs[e];
        let d = project_spring([i, j], r[block.numbers[e] as usize], p);
        // SAFETY: rows the block owns (the caller's promise).
        unsafe {
            if block.owns[e] & FIRST != 0 {
                let row = &mut out.slice_mut(i..i + 1)[0];
                for c in 0..3 {
                    row[c] += d[c];
                }
            }
            if block.owns[e] & SECOND != 0 {
                let row = &mut out.slice_mut(j..j + 1)[0];
                for c in 0..3 {
                    row[c] -= d[c];
                }
            }
        }
    }
}
