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
//! [`Springs::measure_portable`] is the pass one spring at a time. The
//! fast path's `Springs::measure` (in
//! [`simd::spring_pass`](super::simd::spring_pass)) takes four springs at a
//! time on a CPU with AVX2, one per lane, as in the local step; the two
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
    pub(crate) fn want_d(&self) -> bool {
        self.d.is_some() || self.gradient.is_some() || self.transpose.is_some()
    }
}

impl Springs<'_> {
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
