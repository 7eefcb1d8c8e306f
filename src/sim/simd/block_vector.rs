//! The accelerated methods' vector algebra, four numbers per instruction
//! (AVX2).
//!
//! [`block_vector`](crate::sim::methods::block_vector) writes `⟨x, y⟩` as a
//! loop over the `3n` numbers in four lanes (four partial sums, lane `l`
//! adding the numbers `4i + l`) and `y ← y + α x` number by number. Here
//! the four lanes are one 256-bit register: the same products added in the
//! same order, so the same bits (nothing is fused: a multiply, then an
//! add, as in the loop). In L-BFGS's two-loop recursion these are most of
//! the work outside the solve and the energy.
//!
//! Cost `O(n)`. Source: the loops of `block_vector.rs`; Intel's intrinsics
//! guide.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

/// [`dot`](crate::sim::methods::block_vector::dot), its four lanes in one
/// register.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub unsafe fn dot(x: &[[f64; 3]], y: &[[f64; 3]]) -> f64 {
    let (x, y) = (x.as_flattened(), y.as_flattened());
    let quads = x.len().min(y.len()) / 4;
    let mut sums = _mm256_setzero_pd();
    for q in 0..quads {
        // SAFETY: 4q + 3 < len for both slices.
        let (a, b) = unsafe {
            (
                _mm256_loadu_pd(x.as_ptr().add(4 * q)),
                _mm256_loadu_pd(y.as_ptr().add(4 * q)),
            )
        };
        sums = _mm256_add_pd(sums, _mm256_mul_pd(a, b));
    }
    let mut lanes = [0.0; 4];
    // SAFETY: `lanes` holds four numbers.
    unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), sums) };
    let tail: f64 = x[4 * quads..]
        .iter()
        .zip(&y[4 * quads..])
        .map(|(a, b)| a * b)
        .sum();
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

/// [`add_scaled`](crate::sim::methods::block_vector::add_scaled), four
/// numbers at a time.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub unsafe fn add_scaled(y: &mut [[f64; 3]], alpha: f64, x: &[[f64; 3]]) {
    let (y, x) = (y.as_flattened_mut(), x.as_flattened());
    let quads = y.len().min(x.len()) / 4;
    let a = _mm256_set1_pd(alpha);
    for q in 0..quads {
        // SAFETY: 4q + 3 < len for both slices.
        unsafe {
            let yq = y.as_mut_ptr().add(4 * q);
            let xq = _mm256_loadu_pd(x.as_ptr().add(4 * q));
            _mm256_storeu_pd(yq, _mm256_add_pd(_mm256_loadu_pd(yq), _mm256_mul_pd(a, xq)));
        }
    }
    for (b, c) in y[4 * quads..].iter_mut().zip(&x[4 * quads..]) {
        *b += alpha * c;
    }
}
