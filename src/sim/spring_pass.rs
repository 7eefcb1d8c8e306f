//! One pass over the springs that measures everything the step's methods
//! need at a point `p`: the energy of the springs, the local step's `d` (or
//! `Aᵀd` straight away, which is all the global step reads of it) and the
//! springs' part of the gradient.
//!
//! Each of these reads the same spring vector `vₑ = pᵢ − pⱼ` and its length
//! `lₑ = ‖vₑ‖` (the square root is the slow part), so one pass computes all
//! that is asked for, from one gather of `pᵢ, pⱼ` and one square root per
//! spring:
//!
//! ```text
//! S  = Σₑ (lₑ − l⁰ₑ) ((lₑ − rₑ) + (l⁰ₑ − rₑ))   ½ k S = the springs' E(p) − E(p⁰)
//! dₑ = rₑ (vₑ / lₑ)                            the local step (0 when lₑ = 0)
//! gᵢ += k (vₑ − dₑ),  gⱼ −= k (vₑ − dₑ)        ∇ of ½ k (lₑ − rₑ)², e = (i, j)
//! tᵢ += dₑ,  tⱼ −= dₑ                          t = Aᵀd, the global step's part of b
//! ```
//!
//! The energy term is the difference of two squares written as a difference
//! times a sum, `(l − r)² − (l⁰ − r)² = (l − l⁰)((l − r) + (l⁰ − r))`, with
//! the start's lengths `l⁰` measured once per step: `l − l⁰` is exact to the
//! rounding of `l` itself, so the sum keeps the digits that tell two nearby
//! iterates apart, even though the springs' energy itself is large. `d` is
//! computed exactly as [`local_step`](super::local_step) computes it, bit for
//! bit, and added into `Aᵀd` in the same order as
//! [`incidence_transpose_mul_points`](super::signed_incidence::incidence_transpose_mul_points)
//! adds it (the same bits); the spring force `k (v − d) = k (1 − r/l) v`
//! is the derivative of `½ k (l − r)²` in `v`.
//!
//! On a CPU with AVX2 (checked at run time) the springs go four at a time,
//! one per lane, as in the local step; elsewhere one at a time. The two
//! agree to rounding (the lanes add `S` in a different order); the tests
//! check it.
//!
//! Cost `O(m)`: one square root and, when `d` or the gradient is asked for,
//! three divisions per spring.
//! Sources: Liu et al. 2013, §3 (the local step); the assignment's energy;
//! Peng et al. 2018, §4 (the energy "computed as a by-product of the local
//! step", which is what makes an energy test per iteration affordable).

use super::local_step::add_to_transpose;

/// The springs of one step, and what the pass needs to know about them.
#[derive(Debug, Clone, Copy)]
pub struct Springs<'a> {
    /// `(i, j)` of every spring.
    pub springs: &'a [[usize; 2]],
    /// Rest lengths `r`.
    pub r: &'a [f64],
    /// Lengths `l⁰` at the step's start.
    pub start_lengths: &'a [f64],
    /// Stiffness `k`.
    pub k: f64,
}

/// What the pass writes besides the energy sum.
#[derive(Debug, Default)]
pub struct Outputs<'o> {
    /// `dₑ` of the local step, one row per spring.
    pub d: Option<&'o mut [[f64; 3]]>,
    /// A gradient to which the spring forces are added, one row per vertex.
    pub gradient: Option<&'o mut [[f64; 3]]>,
    /// `Aᵀd`, one row per vertex, to which each `dₑ` is added (at `i`)
    /// and from which it is subtracted (at `j`); start it at zero.
    pub transpose: Option<&'o mut [[f64; 3]]>,
}

impl Outputs<'_> {
    /// Is `d` needed for any of them?
    fn want_d(&self) -> bool {
        self.d.is_some() || self.gradient.is_some() || self.transpose.is_some()
    }
}

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
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports the features the function is compiled for.
            return unsafe { avx2::measure(self, p, outputs) };
        }
        self.measure_portable(p, outputs, 0)
    }

    /// [`Springs::measure`] one spring at a time, from spring `first` on.
    pub fn measure_portable(&self, p: &[[f64; 3]], mut outputs: Outputs<'_>, first: usize) -> f64 {
        let mut sum = 0.0;
        for e in first..self.springs.len() {
            let [i, j] = self.springs[e];
            let v = [p[i][0] - p[j][0], p[i][1] - p[j][1], p[i][2] - p[j][2]];
            let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            sum += energy_term(length, self.start_lengths[e], self.r[e]);
            if !outputs.want_d() {
                continue;
            }
            let d = if length > 0.0 {
                v.map(|x| self.r[e] * (x / length))
            } else {
                [0.0; 3]
            };
            if let Some(out) = outputs.d.as_deref_mut() {
                out[e] = d;
            }
            if let Some(g) = outputs.gradient.as_deref_mut() {
                add_force(g, i, j, std::array::from_fn(|c| self.k * (v[c] - d[c])));
            }
            if let Some(t) = outputs.transpose.as_deref_mut() {
                add_to_transpose([i, j], d, t);
            }
        }
        sum
    }
}

/// `(l − l⁰)((l − r) + (l⁰ − r))`: one spring's `(l − r)² − (l⁰ − r)²`.
#[inline(always)]
pub fn energy_term(length: f64, start_length: f64, rest: f64) -> f64 {
    (length - start_length) * ((length - rest) + (start_length - rest))
}

/// `gᵢ += f`, `gⱼ −= f`.
#[inline(always)]
fn add_force(g: &mut [[f64; 3]], i: usize, j: usize, f: [f64; 3]) {
    for c in 0..3 {
        g[i][c] += f[c];
        g[j][c] -= f[c];
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{Outputs, Springs};
    use crate::sim::local_step::avx2::{add_group_rows, add_row, directions, spring_vectors};
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
