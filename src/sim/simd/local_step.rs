//! The local step, four springs per instruction (AVX2).
//!
//! [`local_step::project_springs`]
//! is the formula, one spring at a time. On a CPU with AVX2 (checked at run
//! time) [`project_springs`] here takes the springs four at a time instead, one per lane of a 256-bit register, so that the
//! square roots and divisions, the slow part, run four to an instruction.
//! The arithmetic is the same, lane by lane, as for one spring, and the
//! tests check that both versions agree on every machine.
//!
//! Four springs' vectors `pᵢ − pⱼ` are gathered row by row: each row of
//! `p` is loaded as one 256-bit register (its three coordinates and the
//! next row's first, unused; so only when a next row exists, the last
//! vertex taking the slower way, coordinate by coordinate), the four
//! differences subtracted as rows, and then turned into one register per
//! coordinate by a 4 × 4 transpose: eight loads and eight shuffles where
//! building each coordinate's register from four scalars took some sixty
//! instructions. The same subtractions, so the same bits; 2–4% off a step
//! on the flag and the skirt. Going back, each `dₑ` is added to its rows
//! of `Aᵀd` with `x` and `y` in one 128-bit addition (the same additions):
//! 1–2% more.
//!
//! [`project_springs_into_transpose`] does the same for the local step
//! fused with `Aᵀd` (the plain iteration's pass). Without AVX2 both fall
//! back to the one-spring-at-a-time functions of
//! [`local_step`], whose bits they reproduce.
//!
//! Cost `O(m)`: one square root and three divisions per spring, four to an
//! instruction.
//! Source: Liu et al. 2013, §3 (the local step); Intel's intrinsics guide
//! for the instructions.

use crate::sim::local_step::{self, add_springs_to_transpose};

/// [`local_step::project_springs`], four springs per instruction on a CPU
/// with AVX2: the same bits.
///
/// # Panics
/// When `r` or `d` does not have one entry per spring, or a spring names a
/// vertex beyond `p`.
pub fn project_springs(springs: &[[usize; 2]], r: &[f64], p: &[[f64; 3]], d: &mut [[f64; 3]]) {
    assert!(r.len() == springs.len() && d.len() == springs.len());
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2() {
        // SAFETY: the CPU supports the features the function is compiled for.
        let done = unsafe { avx2::project_groups_of_four(springs, r, p, d) };
        for e in done..springs.len() {
            d[e] = local_step::project_spring(springs[e], r[e], p);
        }
        return;
    }
    local_step::project_springs(springs, r, p, d);
}

/// [`local_step::project_springs_into_transpose`], four springs per
/// instruction on a CPU with AVX2: the same bits.
///
/// # Panics
/// When `r` does not have one entry per spring, or a spring names a
/// vertex beyond `p` or `out`.
pub fn project_springs_into_transpose<const L: usize>(
    springs: &[[usize; 2]],
    r: &[f64],
    p: &[[f64; L]],
    out: &mut [[f64; 3]],
) {
    const { assert!(L == 3 || L == 4, "rows of x, y, z, padded or not") };
    assert!(r.len() == springs.len() && out.len() == p.len());
    out.fill([0.0; 3]);
    let done = groups_of_four_into_transpose(springs, r, p, out);
    add_springs_to_transpose(springs, r, p, out, done);
}

/// The springs `0 .. 4·⌊m/4⌋` of [`project_springs_into_transpose`], four
/// per instruction, where the native kernels run with AVX2; returns how
/// many springs it did (none elsewhere).
fn groups_of_four_into_transpose<const L: usize>(
    springs: &[[usize; 2]],
    r: &[f64],
    p: &[[f64; L]],
    out: &mut [[f64; 3]],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2() {
        // SAFETY: the CPU supports the features the function is compiled for.
        return unsafe { avx2::project_groups_of_four_into_transpose(springs, r, p, out) };
    }
    let _ = (springs, r, p, out);
    0
}

/// The number of values in each row of `p`: 3 (x, y, z) or 4 (padded).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) const fn row_length<const L: usize>(_: &[[f64; L]]) -> usize {
    L
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2 {
    use std::arch::x86_64::*;

    /// The same projection for springs `0 .. 4·⌊m/4⌋`, four springs per
    /// instruction (one lane each); returns how many springs it did.
    #[target_feature(enable = "avx2")]
    pub fn project_groups_of_four(
        springs: &[[usize; 2]],
        r: &[f64],
        p: &[[f64; 3]],
        d: &mut [[f64; 3]],
    ) -> usize {
        let groups = springs.len() / 4;
        for g in 0..groups {
            let e = 4 * g;
            let projected = project_group!(&springs[e..e + 4], r, e, p);
            d[e..e + 4].copy_from_slice(&projected);
        }
        4 * groups
    }

    /// [`project_springs_into_transpose`](super::project_springs_into_transpose)
    /// for springs `0 .. 4·⌊m/4⌋`; returns how many springs it did.
    #[target_feature(enable = "avx2")]
    pub fn project_groups_of_four_into_transpose<const L: usize>(
        springs: &[[usize; 2]],
        r: &[f64],
        p: &[[f64; L]],
        out: &mut [[f64; 3]],
    ) -> usize {
        let groups = springs.len() / 4;
        for g in 0..groups {
            let e = 4 * g;
            let s = &springs[e..e + 4];
            let d = project_group_lanes!(s, r, e, p);
            add_group_rows!(s, d, out, true);
        }
        4 * groups
    }

    /// `out[i] += dₑ`, `out[j] −= dₑ` for the four springs `s = (i, j)`
    /// whose `dₑ` are the lanes of `d` (one register per coordinate),
    /// springs in order: with `skip_self`, nothing for a spring from a
    /// vertex to itself (a zero row of `A`: the additions of
    /// [`add_to_transpose`](crate::sim::local_step::add_to_transpose)); without, both (the
    /// gradient's spring forces, as the portable pass adds them). `x` and
    /// `y` go in one 128-bit addition. A macro for the reason given at
    /// `spring_vectors`.
    macro_rules! add_group_rows {
        ($s:expr, $d:expr, $out:expr, $skip_self:expr) => {{
            let (s, out): (&[[usize; 2]], &mut [[f64; 3]]) = ($s, $out);
            let (xy, z) = $crate::sim::simd::local_step::avx2::group_rows!($d);
            for k in 0..4 {
                let [i, j] = s[k];
                if !$skip_self || i != j {
                    add_row(&mut out[i], xy[k], z[k], false);
                    add_row(&mut out[j], xy[k], z[k], true);
                }
            }
        }};
    }
    pub(crate) use add_group_rows;

    /// The four springs' `dₑ` (one register per coordinate) as rows: `(x,
    /// y)` of each spring as one 128-bit half, `z` as numbers. A macro for
    /// the reason given at `spring_vectors`.
    macro_rules! group_rows {
        ($d:expr) => {{
            let [dx, dy, dz]: [__m256d; 3] = $d;
            // [dx₀ dy₀ dx₂ dy₂], [dx₁ dy₁ dx₃ dy₃]
            let (even, odd) = (_mm256_unpacklo_pd(dx, dy), _mm256_unpackhi_pd(dx, dy));
            let xy: [__m128d; 4] = [
                _mm256_castpd256_pd128(even),
                _mm256_castpd256_pd128(odd),
                _mm256_extractf128_pd::<1>(even),
                _mm256_extractf128_pd::<1>(odd),
            ];
            let mut z = [0.0; 4];
            // SAFETY: z holds four f64.
            unsafe { _mm256_storeu_pd(z.as_mut_ptr(), dz) };
            (xy, z)
        }};
    }
    pub(crate) use group_rows;

    /// `row += (xy, z)`, or `row −= (xy, z)`: x and y in one 128-bit
    /// operation, the same additions as coordinate by coordinate.
    #[inline(always)]
    pub(crate) fn add_row(row: &mut [f64; 3], xy: __m128d, z: f64, subtract: bool) {
        // SAFETY: row holds three f64, of which the first two are read
        // and written here.
        unsafe {
            let old = _mm_loadu_pd(row.as_ptr());
            let new = if subtract {
                _mm_sub_pd(old, xy)
            } else {
                _mm_add_pd(old, xy)
            };
            _mm_storeu_pd(row.as_mut_ptr(), new);
        }
        if subtract {
            row[2] -= z;
        } else {
            row[2] += z;
        }
    }

    /// `dₑ` of the four springs `s` numbered from `e`, one register per
    /// coordinate, lane `k` for spring `s[k]`. A macro for the reason given
    /// at `spring_vectors`.
    macro_rules! project_group_lanes {
        ($s:expr, $r:expr, $e:expr, $p:expr) => {{
            let (s, r, e) = ($s, $r, $e);
            let (v, length) = spring_vectors!(s, $p);
            assert!(e + 4 <= r.len());
            // SAFETY: e + 4 ≤ r.len() (just checked).
            let rest = unsafe { _mm256_loadu_pd(r.as_ptr().add(e)) };
            directions!(v, length, rest)
        }};
    }
    use project_group_lanes;

    /// `dₑ = rₑ (vₑ / lₑ)`, lane by lane, from the springs' vectors (one
    /// register per coordinate), lengths and rest lengths; zero-length
    /// springs divide by 1, then multiply by 0. The one definition the
    /// local step and the spring pass both use, so that their `d` are the
    /// same bits. A macro for the reason given at `spring_vectors`.
    macro_rules! directions {
        ($v:expr, $length:expr, $rest:expr) => {{
            let (v, length, rest): ([__m256d; 3], __m256d, __m256d) = ($v, $length, $rest);
            let positive = _mm256_cmp_pd::<_CMP_GT_OQ>(length, _mm256_setzero_pd());
            let divisor = _mm256_blendv_pd(_mm256_set1_pd(1.0), length, positive);
            let keep = _mm256_and_pd(rest, positive);
            let d: [__m256d; 3] =
                std::array::from_fn(|c| _mm256_mul_pd(keep, _mm256_div_pd(v[c], divisor)));
            d
        }};
    }
    pub(crate) use directions;

    /// `[d₀, d₁, d₂, d₃]` for the four springs `s` numbered from `e`.
    macro_rules! project_group {
        ($s:expr, $r:expr, $e:expr, $p:expr) => {{
            let lanes = project_group_lanes!($s, $r, $e, $p);
            let mut out = [[0.0; 4]; 3];
            for c in 0..3 {
                // SAFETY: out[c] holds four f64.
                unsafe { _mm256_storeu_pd(out[c].as_mut_ptr(), lanes[c]) };
            }
            let projected: [[f64; 3]; 4] =
                std::array::from_fn(|k| [out[0][k], out[1][k], out[2][k]]);
            projected
        }};
    }
    use project_group;

    /// `(v, l)`: `vₑ = pᵢ − pⱼ` by coordinate and `‖vₑ‖`, lane `k` for the
    /// spring `s[k]` of four springs `s`. A macro, not a function, so that it
    /// is compiled inside each AVX2 function that uses it (a function would
    /// not be inlined into them, and its intrinsics would become calls).
    macro_rules! spring_vectors {
        ($s:expr, $p:expr) => {{
            let (s, p): (&[[usize; 2]], _) = ($s, $p);
            let stride = $crate::sim::simd::local_step::row_length(p);
            // a row and the next one's x as one load, when a next row
            // exists; a padded row (x, y, z, 0) is one load by itself
            let last = p.len().saturating_sub(1);
            let whole = |i: usize| i < p.len() && (stride == 4 || i < last);
            let v: [__m256d; 3] = if s[..4].iter().all(|&[i, j]| whole(i) && whole(j)) {
                let base = p.as_ptr().cast::<f64>();
                // SAFETY: row i exists and so does row i + 1 unless rows
                // hold four values (checked), so the four values from row
                // i's first lie inside p.
                let row = |i: usize| unsafe { _mm256_loadu_pd(base.add(stride * i)) };
                // [vx, vy, vz, −] of each spring, then the 4 × 4 transpose
                let r: [__m256d; 4] =
                    std::array::from_fn(|k| _mm256_sub_pd(row(s[k][0]), row(s[k][1])));
                let (t0, t1) = (
                    _mm256_unpacklo_pd(r[0], r[1]),
                    _mm256_unpackhi_pd(r[0], r[1]),
                );
                let (t2, t3) = (
                    _mm256_unpacklo_pd(r[2], r[3]),
                    _mm256_unpackhi_pd(r[2], r[3]),
                );
                [
                    _mm256_permute2f128_pd::<0x20>(t0, t2),
                    _mm256_permute2f128_pd::<0x20>(t1, t3),
                    _mm256_permute2f128_pd::<0x31>(t0, t2),
                ]
            } else {
                std::array::from_fn(|c| {
                    let pi =
                        _mm256_set_pd(p[s[3][0]][c], p[s[2][0]][c], p[s[1][0]][c], p[s[0][0]][c]);
                    let pj =
                        _mm256_set_pd(p[s[3][1]][c], p[s[2][1]][c], p[s[1][1]][c], p[s[0][1]][c]);
                    _mm256_sub_pd(pi, pj)
                })
            };
            let squared = _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(v[0], v[0]), _mm256_mul_pd(v[1], v[1])),
                _mm256_mul_pd(v[2], v[2]),
            );
            (v, _mm256_sqrt_pd(squared))
        }};
    }
    pub(crate) use spring_vectors;
}
