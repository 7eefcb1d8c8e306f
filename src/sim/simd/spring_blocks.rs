//! A block's local step and `Aᵀd`, four springs per instruction (AVX2).
//!
//! [`spring_blocks::add_owned_springs`] is the formula, one spring at a
//! time. On a CPU with AVX2 [`add_owned_springs`] here takes the block's
//! springs four at a time, one per lane, as
//! [`local_step`](super::local_step) does for all springs: the same
//! arithmetic lane by lane, so the same bits, which the tests check
//! against one thread's `Aᵀd`. Each `dₑ` is then added to the rows the
//! block owns, `x` and `y` in one 128-bit addition, as there.
//!
//! Cost `O(springs of the block)`. Source: Liu et al. 2013, §3 (the local
//! step); Intel's intrinsics guide for the instructions.

use crate::linalg::threads::SharedSlice;
use crate::sim::spring_blocks::{self, Block};

/// [`spring_blocks::add_owned_springs`] for all of `block`'s springs,
/// four per instruction on a CPU with AVX2: the same bits.
///
/// # Safety
/// No other thread reads or writes the block's rows of `out` meanwhile.
///
/// # Panics
/// When a spring names a vertex beyond `p` or `out`, or a number beyond `r`.
pub unsafe fn add_owned_springs<const L: usize>(
    block: Block,
    r: &[f64],
    p: &[[f64; L]],
    out: &SharedSlice<[f64; 3]>,
) {
    const { assert!(L == 3 || L == 4, "rows of x, y, z, padded or not") };
    assert!(block.springs.len() == block.numbers.len() && block.owns.len() == block.numbers.len());
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2() {
        // SAFETY: the CPU supports the features the function is compiled
        // for; the rows as the caller promises.
        let done = unsafe { avx2::groups_of_four(block, r, p, out) };
        // SAFETY: the caller's promise.
        unsafe { spring_blocks::add_owned_springs(block, r, p, out, done) };
        return;
    }
    // SAFETY: the caller's promise.
    unsafe { spring_blocks::add_owned_springs(block, r, p, out, 0) };
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use crate::linalg::threads::SharedSlice;
    use crate::sim::simd::local_step::avx2::{add_row, directions, group_rows, spring_vectors};
    use crate::sim::spring_blocks::{Block, FIRST, SECOND};
    use std::arch::x86_64::*;

    /// The block's springs `0 .. 4·⌊m/4⌋`, four per instruction; returns
    /// how many it did.
    ///
    /// # Safety
    /// As [`add_owned_springs`](super::add_owned_springs).
    #[target_feature(enable = "avx2")]
    pub unsafe fn groups_of_four<const L: usize>(
        block: Block,
        r: &[f64],
        p: &[[f64; L]],
        out: &SharedSlice<[f64; 3]>,
    ) -> usize {
        let groups = block.springs.len() / 4;
        let rows = out.as_mut_ptr();
        for g in 0..groups {
            let e = 4 * g;
            let s = &block.springs[e..e + 4];
            let (v, length) = spring_vectors!(s, p);
            let rest: [f64; 4] = std::array::from_fn(|k| r[block.numbers[e + k] as usize]);
            // SAFETY: `rest` holds four f64.
            let rest = unsafe { _mm256_loadu_pd(rest.as_ptr()) };
            let (xy, z) = group_rows!(directions!(v, length, rest));
            for k in 0..4 {
                let ([i, j], owns) = (s[k], block.owns[e + k]);
                assert!(i < out.len() && j < out.len());
                // SAFETY: inside `out` (checked); rows the block owns (the
                // caller's promise).
                unsafe {
                    if owns & FIRST != 0 {
                        add_row(&mut *rows.add(i), xy[k], z[k], false);
                    }
                    if owns & SECOND != 0 {
                        add_row(&mut *rows.add(j), xy[k], z[k], true);
                    }
                }
            }
        }
        4 * groups
    }
}
