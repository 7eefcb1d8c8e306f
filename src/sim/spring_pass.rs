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
            if let Outputs {
                d: None,
                gradient: None,
                transpose: Some(t),
            } = outputs
            {
                // the local step as the plain iteration makes it, and S
                // SAFETY: the CPU supports the features the function is compiled for.
                let (head, done) = unsafe { avx2::measure_into_transpose(self, p, t) };
                let rest = Outputs {
                    transpose: Some(t),
                    ..Outputs::default()
                };
                return head + self.measure_portable(p, rest, done);
            }
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
    use super::{add_force, add_to_transpose, Outputs, Springs};
    use crate::sim::local_step::avx2::{
        add_group_to_transpose, add_row, directions, spring_vectors,
    };
    use std::arch::x86_64::*;

    /// [`Springs::measure`] four springs per instruction, the last `m mod 4`
    /// one at a time.
    #[target_feature(enable = "avx2")]
    pub fn measure(springs: &Springs<'_>, p: &[[f64; 3]], mut outputs: Outputs<'_>) -> f64 {
        let (list, k) = (springs.springs, springs.k);
        let groups = list.len() / 4;
        let want_d = outputs.want_d();
        let mut sums = _mm256_setzero_pd();
        for group in 0..groups {
            let e = 4 * group;
            let s = &list[e..e + 4];
            let (v, length, rest, term) = group_measures!(springs, s, e, p);
            sums = _mm256_add_pd(sums, term);
            if !want_d {
                continue;
            }
            // d = r (v / l), as the local step makes it
            let d_lanes = directions!(v, length, rest);
            if outputs.d.is_some() || outputs.transpose.is_some() {
                let d = lanes_of(d_lanes);
                let d_of = |lane: usize| [d[0][lane], d[1][lane], d[2][lane]];
                if let Some(out) = outputs.d.as_deref_mut() {
                    for lane in 0..4 {
                        out[e + lane] = d_of(lane);
                    }
                }
                if let Some(t) = outputs.transpose.as_deref_mut() {
                    for (lane, &spring) in s.iter().enumerate() {
                        add_to_transpose(spring, d_of(lane), t);
                    }
                }
            }
            if let Some(g) = outputs.gradient.as_deref_mut() {
                let force = lanes_of::<3>(std::array::from_fn(|c| {
                    _mm256_mul_pd(_mm256_set1_pd(k), _mm256_sub_pd(v[c], d_lanes[c]))
                }));
                for (lane, &[i, j]) in s.iter().enumerate() {
                    add_force(g, i, j, [force[0][lane], force[1][lane], force[2][lane]]);
                }
            }
        }
        let [lanes] = lanes_of([sums]);
        let head = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
        head + springs.measure_portable(p, outputs, 4 * groups)
    }

    /// [`Springs::measure`] with `Aᵀd` its only output, for springs
    /// `0 .. 4·⌊m/4⌋`: the plain local step's loop
    /// ([`project_groups_of_four_into_transpose`](crate::sim::local_step::avx2::project_groups_of_four_into_transpose),
    /// the same `d` added in the same way) with the energy term beside it.
    /// Returns `S` over those springs and how many springs it did. Kept
    /// apart from [`measure`] because the general pass, which tests at each
    /// group which outputs it has and adds `dₑ` one coordinate at a time,
    /// cost Chebyshev's iteration on the skirt 30% of a plain iteration's
    /// time, this one 26% (plain's own local step: 25%; `perf record`).
    #[target_feature(enable = "avx2")]
    pub fn measure_into_transpose(
        springs: &Springs<'_>,
        p: &[[f64; 3]],
        out: &mut [[f64; 3]],
    ) -> (f64, usize) {
        let list = springs.springs;
        let groups = list.len() / 4;
        let mut sums = _mm256_setzero_pd();
        for group in 0..groups {
            let e = 4 * group;
            let s = &list[e..e + 4];
            let (v, length, rest, term) = group_measures!(springs, s, e, p);
            sums = _mm256_add_pd(sums, term);
            let d = directions!(v, length, rest);
            add_group_to_transpose!(s, d, out);
        }
        let [lanes] = lanes_of([sums]);
        ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3]), 4 * groups)
    }

    /// `(v, l, r, term)` of the four springs `s` numbered from `e`: their
    /// vectors (one register per coordinate), lengths, rest lengths and
    /// [`energy_term`](super::energy_term)s, lane `k` for spring `s[k]`. A
    /// macro for the reason given at `spring_vectors`.
    macro_rules! group_measures {
        ($springs:expr, $s:expr, $e:expr, $p:expr) => {{
            let (springs, s, e): (&Springs<'_>, &[[usize; 2]], usize) = ($springs, $s, $e);
            let (v, length) = spring_vectors!(s, $p);
            assert!(e + 4 <= springs.r.len() && e + 4 <= springs.start_lengths.len());
            // SAFETY: e + 4 ≤ r.len(), start_lengths.len() (just checked).
            let (rest, start) = unsafe {
                (
                    _mm256_loadu_pd(springs.r.as_ptr().add(e)),
                    _mm256_loadu_pd(springs.start_lengths.as_ptr().add(e)),
                )
            };
            let term = _mm256_mul_pd(
                _mm256_sub_pd(length, start),
                _mm256_add_pd(_mm256_sub_pd(length, rest), _mm256_sub_pd(start, rest)),
            );
            (v, length, rest, term)
        }};
    }
    use group_measures;

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
