//! The vertices' part of the step's energy, four vertices per instruction
//! (AVX2).
//!
//! `StepEnergy::vertex_sums` (in [`energy`](crate::sim::energy)) adds, over
//! the vertices, `mᵢ (pᵢ − p⁰ᵢ)·((pᵢ − ŷᵢ) + (p⁰ᵢ − ŷᵢ))` and
//! `(pᵢ − p⁰ᵢ)·fᵢ`. Here the first `4·⌊n/4⌋` vertices go four at a time;
//! the caller adds the rest one at a time. The sums agree with the
//! one-at-a-time ones to rounding (the lanes add in another order).
//!
//! Cost `O(n)`. Source: the energy of `energy.rs`; Intel's intrinsics guide.

/// The rows the sums read: `p⁰`, `ŷ`, `f_ext`, `m`, one per vertex.
#[derive(Debug, Clone, Copy)]
pub struct Vertices<'a> {
    pub start: &'a [[f64; 3]],
    pub inertial_target: &'a [[f64; 3]],
    pub f_ext: &'a [[f64; 3]],
    pub m: &'a [f64],
}

/// The two sums over vertices `0 .. 4·⌊n/4⌋` at `p`, and how many vertices
/// that is: four at a time on a CPU with AVX2, none (`([0, 0], 0)`)
/// elsewhere.
pub fn vertex_sums(vertices: &Vertices<'_>, p: &[[f64; 3]]) -> ([f64; 2], usize) {
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2() {
        // SAFETY: the CPU supports the features the function is compiled for.
        return unsafe { avx2::vertex_sums(vertices, p) };
    }
    let _ = (vertices, p);
    ([0.0; 2], 0)
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::Vertices;
    use std::arch::x86_64::*;

    /// `StepEnergy::vertex_sums` for vertices `0 .. 4·⌊n/4⌋`; returns
    /// the sums and how many vertices it did. Four vertices are twelve
    /// numbers, three registers of each of `p`, `p⁰`, `ŷ` and `f` read as
    /// flat arrays; the four masses are spread to match, `[m₀ m₀ m₀ m₁]`,
    /// `[m₁ m₁ m₂ m₂]`, `[m₂ m₃ m₃ m₃]`, and every product is summed in
    /// its own register's lanes. In Chebyshev's run on the flag the pass
    /// took 2.3% of the time, against 5.3% one vertex at a time in scalar
    /// arithmetic (`perf record`).
    #[target_feature(enable = "avx2")]
    pub fn vertex_sums(vertices: &Vertices<'_>, p: &[[f64; 3]]) -> ([f64; 2], usize) {
        let groups = p.len() / 4;
        let flat = |rows: &[[f64; 3]]| rows[..4 * groups].as_flattened().as_ptr();
        let (p, p0, y, f) = (
            flat(p),
            flat(vertices.start),
            flat(vertices.inertial_target),
            flat(vertices.f_ext),
        );
        let m = vertices.m[..4 * groups].as_ptr();
        let mut inertia = [_mm256_setzero_pd(); 3];
        let mut external = [_mm256_setzero_pd(); 3];
        for group in 0..groups {
            // SAFETY: the twelve numbers from 12·group and the four masses
            // from 4·group lie inside the slices taken above.
            unsafe {
                let masses = _mm256_loadu_pd(m.add(4 * group));
                let spread = [
                    _mm256_permute4x64_pd::<0b01_00_00_00>(masses),
                    _mm256_permute4x64_pd::<0b10_10_01_01>(masses),
                    _mm256_permute4x64_pd::<0b11_11_11_10>(masses),
                ];
                for k in 0..3 {
                    let at = 12 * group + 4 * k;
                    let (pk, p0k, yk) = (
                        _mm256_loadu_pd(p.add(at)),
                        _mm256_loadu_pd(p0.add(at)),
                        _mm256_loadu_pd(y.add(at)),
                    );
                    let moved = _mm256_sub_pd(pk, p0k);
                    let sum = _mm256_add_pd(_mm256_sub_pd(pk, yk), _mm256_sub_pd(p0k, yk));
                    let term = _mm256_mul_pd(spread[k], _mm256_mul_pd(moved, sum));
                    inertia[k] = _mm256_add_pd(inertia[k], term);
                    let force = _mm256_loadu_pd(f.add(at));
                    external[k] = _mm256_add_pd(external[k], _mm256_mul_pd(moved, force));
                }
            }
        }
        let total = |registers: [__m256d; 3]| {
            let sum = _mm256_add_pd(_mm256_add_pd(registers[0], registers[1]), registers[2]);
            let mut lanes = [0.0; 4];
            // SAFETY: lanes holds four f64.
            unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), sum) };
            (lanes[0] + lanes[1]) + (lanes[2] + lanes[3])
        };
        ([total(inertia), total(external)], 4 * groups)
    }
}
