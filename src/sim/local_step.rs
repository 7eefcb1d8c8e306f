//! The local step: project every spring onto its rest length.
//!
//! For fixed positions `p`, the spring energy `½ k (‖pᵢ − pⱼ‖ − rᵢⱼ)²`
//! equals `min ½ k ‖(pᵢ − pⱼ) − dᵢⱼ‖²` over vectors `dᵢⱼ` of length `rᵢⱼ`,
//! and the minimiser is the current spring vector rescaled to the rest
//! length:
//!
//! ```text
//! dᵢⱼ = rᵢⱼ (pᵢ − pⱼ) / ‖pᵢ − pⱼ‖
//! ```
//!
//! Each spring is independent of the others. A spring squeezed to zero
//! length has no direction; its `d` is set to zero (it then pulls its ends
//! together like a zero-length spring until they separate).
//!
//! Written as the formula reads, `r · (v / ‖v‖)`, so that its rounding
//! matches a direct transcription (Eigen's `r * v.normalized()`):
//! [`project_spring`] for one spring, [`project_springs`] for all of them,
//! one at a time (what the handout's step, [`textbook`](super::textbook),
//! runs).
//!
//! The plain iteration needs `d` only to form `Aᵀd` (the global step's
//! right-hand side), so [`project_springs_into_transpose`] adds each `dₑ`
//! to its two vertices' rows of `Aᵀd` as soon as it is made, instead of
//! writing `d` and reading it back in a second pass over the springs: the
//! same sums in the same order, the same bits.
//!
//! The fast path runs the same formulas four springs per instruction on a
//! CPU with AVX2: [`simd::local_step`](super::simd::local_step), tested bit
//! for bit against these.
//!
//! Cost `O(m)`: one square root and three divisions per spring.
//! Source: Liu et al. 2013, §3 ("local step"); the assignment, "Step 1 (local)".

/// One spring `(i, j)`: `dᵢⱼ = r (pᵢ − pⱼ) / ‖pᵢ − pⱼ‖`, zero for a
/// zero-length spring (rows of `p` hold x, y, z, and possibly a padding
/// value, not read).
#[inline(always)]
pub fn project_spring<const L: usize>(
    [i, j]: [usize; 2],
    rest_length: f64,
    p: &[[f64; L]],
) -> [f64; 3] {
    let v = [p[i][0] - p[j][0], p[i][1] - p[j][1], p[i][2] - p[j][2]];
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if length > 0.0 {
        v.map(|x| rest_length * (x / length))
    } else {
        [0.0; 3]
    }
}

/// The local step: `d[e] = r[e] (p[i] − p[j]) / ‖p[i] − p[j]‖` for every
/// spring `e = (i, j)`, one spring at a time.
///
/// # Panics
/// When `r` or `d` does not have one entry per spring, or a spring names a
/// vertex beyond `p`.
pub fn project_springs(springs: &[[usize; 2]], r: &[f64], p: &[[f64; 3]], d: &mut [[f64; 3]]) {
    assert!(r.len() == springs.len() && d.len() == springs.len());
    for ((&spring, &rest_length), d_e) in springs.iter().zip(r).zip(d.iter_mut()) {
        *d_e = project_spring(spring, rest_length, p);
    }
}

/// The local step and `Aᵀd` in one pass over the springs: `out = Aᵀ d`
/// for the `d` that [`project_springs`] makes, each `dₑ` added to row `i`
/// and subtracted from row `j` as soon as it is made, springs in
/// increasing order (the same sums in the same order as
/// [`incidence_transpose_mul_points`](super::signed_incidence::incidence_transpose_mul_points)
/// after [`project_springs`], so the same bits), without writing `d`.
/// Rows of `p` may be padded to four values.
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
    assert!(r.len() == springs.len() && out.len() == p.len());
    out.fill([0.0; 3]);
    add_springs_to_transpose(springs, r, p, out, 0);
}

/// [`project_springs_into_transpose`] for springs `first..` into `out`
/// as it is (not cleared): what the four-at-a-time version leaves over.
pub fn add_springs_to_transpose<const L: usize>(
    springs: &[[usize; 2]],
    r: &[f64],
    p: &[[f64; L]],
    out: &mut [[f64; 3]],
    first: usize,
) {
    for e in first..springs.len() {
        add_to_transpose(springs[e], project_spring(springs[e], r[e], p), out);
    }
}

/// `out[i] += dₑ`, `out[j] −= dₑ` for spring `e = (i, j)`, nothing for a
/// spring from a vertex to itself (a zero row of `A`).
#[inline(always)]
pub fn add_to_transpose([i, j]: [usize; 2], d_e: [f64; 3], out: &mut [[f64; 3]]) {
    if i != j {
        for c in 0..3 {
            out[i][c] += d_e[c];
            out[j][c] -= d_e[c];
        }
    }
}
