//! The spring pass, four springs per instruction (AVX2).
//!
//! [`Springs::measure`] is [`Springs::measure_portable`] (the energy sum,
//! `d`, `Aᵀd` and the springs' gradient in one pass over the springs; the
//! formulas are in [`spring_pass`](crate::sim::spring_pass)) with the
//! springs four at a time, one per lane, on a CPU with AVX2; elsewhere it
//! is the portable pass. `d` and `Aᵀd` are the same bits as the local
//! step's; the energy sum agrees to rounding (the lanes add it in another
//! order).
//!
//! Cost `O(m)`: one square root per spring and, when `d` or the gradient
//! is asked for, three divisions, four springs to an instruction.
//! Source: Peng et al. 2018, §4 (the energy as a by-product of the local
//! step).

use crate::sim::spring_pass::{Outputs, Springs};

impl Springs<'_> {
    /// One pass at `p`: returns `S` (the springs' energy change is `½ k S`)
    /// and fills the outputs asked for.
    ///
    /// # Panics
    /// When the slices do not have one entry per spring (or per vertex), or
    /// a spring names a vertex beyond `p`.
    pub fn measure(&self, p: &[[f64; 3]], outputs: Outputs<'_>) -> f64 {
        let m = self.springs.len();
        assert!(self.r.len() == m && self.start_lengths.len() == m);
        assert!(outputs.d.as_ref().is_none_or(|d| d.len() == m));
        assert!(outputs.gradient.as_ref().is_none_or(|g| g.len() == p.len()));
        assert!(outputs
            .transpose
            .as_ref()
            .is_none_or(|t| t.len() == p.len()));
        #[cfg(target_arch = "x86_64")]
        if crate::linalg::kernels::avx2() {
            // SAFETY: the CPU supports the features the function is compiled for.
            return unsafe { avx2::measure(self, p, outputs) };
        }
        self.measure_portable(p, outputs, 0)
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use crate::sim::simd::local_step::avx2::{add_group_rows, add_row, directions, spring_vectors};
    use crate::sim::spring_pass::{Outputs, Springs};
    use std::arch::x86_64::*;

    /// [`Springs::measure`] four springs per instruction, the last `m mod 4`
    /// one at a time.
    #[target_feature(enable = "avx2")]
    pub fn measure(springs: &Springs<'_>, p: &[[f64; 3]], mut outputs: Outputs<'_>) -> f64 {
        let o = &mut outputs;
        let asked = (o.d.is_some(), o.gradient.is_some(), o.transpose.is_some());
        let (head, done) = match asked {
            (false, false, false) => groups::<false, false, false>(springs, p, o),
            (false, false, true) => groups::<false, false, true>(springs, p, o),
            (false, true, false) => groups::<false, true, false>(springs, p, o),
            (false, true, true) => groups::<false, true, true>(springs, p, o),
            (true, false, false) => groups::<true, false, false>(springs, p, o),
            (true, false, true) => groups::<true, false, true>(springs, p, o),
            (true, true, false) => groups::<true, true, false>(springs, p, o),
            (true, true, true) => groups::<true, true, true>(springs, p, o),
        };
        head + springs.measure_portable(p, outputs, done)
    }

    /// The pass for springs `0 .. 4·⌊m/4⌋`, compiled once for each set of
    /// outputs asked for (`D`: `d`, `G`: the gradient, `T`: `Aᵀd`), so that
    /// no group tests what it must write; returns `S` over those springs
    /// and how many springs it did. `dₑ` and the forces are added to their
    /// rows as the plain local step adds `dₑ`, `x` and `y` in one 128-bit
    /// addition. (One general loop that tested its outputs at every group
    /// and added one coordinate at a time cost Chebyshev's iteration on the
    /// skirt 30% of a plain iteration's time, against 26% now and plain's
    /// own local step's 25%; `perf record`.) Each set of outputs is its
    /// own function, not inlined: inlined, all eight into one, the
    /// transpose-only loop ran 4–7% slower. L-BFGS's pass (the gradient
    /// only) took 7% less time than in the general loop.
    #[target_feature(enable = "avx2")]
    #[inline(never)]
    fn groups<const D: bool, const G: bool, const T: bool>(
        springs: &Springs<'_>,
        p: &[[f64; 3]],
        outputs: &mut Outputs<'_>,
    ) -> (f64, usize) {
        let (list, k) = (springs.springs, springs.k);
        let groups = list.len() / 4;
        // the outputs as plain slices for the loop (empty when not asked)
        let d_out = outputs.d.as_deref_mut().unwrap_or_default();
        let t = outputs.transpose.as_deref_mut().unwrap_or_default();
        let g = outputs.gradient.as_deref_mut().unwrap_or_default();
        let mut sums = _mm256_setzero_pd();
        for group in 0..groups {
            let e = 4 * group;
            let s = &list[e..e + 4];
            let (v, length) = spring_vectors!(s, p);
            assert!(e + 4 <= springs.r.len() && e + 4 <= springs.start_lengths.len());
            // SAFETY: e + 4 ≤ r.len(), start_lengths.len() (just checked).
            let (rest, start) = unsafe {
                (
                    _mm256_loadu_pd(springs.r.as_ptr().add(e)),
                    _mm256_loadu_pd(springs.start_lengths.as_ptr().add(e)),
                )
            };
            // the energy term (l − l⁰)((l − r) + (l⁰ − r))
            let term = _mm256_mul_pd(
                _mm256_sub_pd(length, start),
                _mm256_add_pd(_mm256_sub_pd(length, rest), _mm256_sub_pd(start, rest)),
            );
            sums = _mm256_add_pd(sums, term);
            if !(D || G || T) {
                continue;
            }
            // d = r (v / l), as the local step makes it
            let d = directions!(v, length, rest);
            if D {
                let lanes = lanes_of(d);
                for lane in 0..4 {
                    d_out[e + lane] = [lanes[0][lane], lanes[1][lane], lanes[2][lane]];
                }
            }
            if T {
                add_group_rows!(s, d, &mut *t, true);
            }
            if G {
                let force: [__m256d; 3] = std::array::from_fn(|c| {
                    _mm256_mul_pd(_mm256_set1_pd(k), _mm256_sub_pd(v[c], d[c]))
                });
                add_group_rows!(s, force, &mut *g, false);
            }
        }
        let [lanes] = lanes_of([sums]);
        ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3]), 4 * groups)
    }

    /// The lanes of each register, as plain numbers.
    #[target_feature(enable = "avx2")]
    fn lanes_of<const N: usize>(registers: [__m256d; N]) -> [[f64; 4]; N] {
        let mut out = [[0.0; 4]; N];
        for (lanes, register) in out.iter_mut().zip(registers) {
            // SAFETY: `lanes` holds four f64.
            unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), register) };
        }
        out
    }
}
