//! Vectors of the step's unknowns: `n × 3` blocks (one point per row) read
//! as one vector of `3n` numbers.
//!
//! The accelerated methods combine whole iterates (`x ← x + α s`, `sᵀy`),
//! which is ordinary vector algebra on `ℝ³ⁿ`: the Frobenius inner product
//! `⟨X, Y⟩ = tr(XᵀY) = Σᵢ Σ_c X_ic Y_ic`. Each function is one loop, `O(n)`,
//! and allocates nothing.

/// `⟨x, y⟩ = Σ xᵢ·yᵢ`, summed in four interleaved partial sums (one
/// running sum would make every addition wait for the one before; four let
/// the CPU overlap them, and vectorise). On a CPU with AVX2 the four lanes
/// are one register ([`simd::block_vector`](crate::sim::simd::block_vector)),
/// to the same bits.
pub fn dot(x: &[[f64; 3]], y: &[[f64; 3]]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2() {
        // SAFETY: the CPU supports the features the function is compiled for.
        return unsafe { crate::sim::simd::block_vector::dot(x, y) };
    }
    dot_lanes(x, y)
}

/// The loop of [`dot`], one number at a time.
pub fn dot_lanes(x: &[[f64; 3]], y: &[[f64; 3]]) -> f64 {
    assert_eq!(x.len(), y.len());
    let (x, y) = (x.as_flattened(), y.as_flattened());
    let mut sums = [0.0; 4];
    let (x_quads, y_quads) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = x_quads
        .remainder()
        .iter()
        .zip(y_quads.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in x_quads.zip(y_quads) {
        for lane in 0..4 {
            sums[lane] += a[lane] * b[lane];
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

/// `‖x‖ = √⟨x, x⟩`.
pub fn norm(x: &[[f64; 3]]) -> f64 {
    dot(x, x).sqrt()
}

/// `y ← y + α x` (four numbers per instruction where the CPU has AVX2, as
/// [`dot`]).
pub fn add_scaled(y: &mut [[f64; 3]], alpha: f64, x: &[[f64; 3]]) {
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2() {
        // SAFETY: the CPU supports the features the function is compiled for.
        return unsafe { crate::sim::simd::block_vector::add_scaled(y, alpha, x) };
    }
    add_scaled_lanes(y, alpha, x);
}

/// The loop of [`add_scaled`], one number at a time.
pub fn add_scaled_lanes(y: &mut [[f64; 3]], alpha: f64, x: &[[f64; 3]]) {
    assert_eq!(x.len(), y.len());
    for (a, b) in y.as_flattened_mut().iter_mut().zip(x.as_flattened()) {
        *a += alpha * b;
    }
}

/// `out ← x − y`.
pub fn subtract(x: &[[f64; 3]], y: &[[f64; 3]], out: &mut [[f64; 3]]) {
    assert!(x.len() == y.len() && y.len() == out.len());
    for ((o, a), b) in out.iter_mut().zip(x).zip(y) {
        *o = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    }
}

/// `out ← x + α d`.
pub fn moved(x: &[[f64; 3]], alpha: f64, d: &[[f64; 3]], out: &mut [[f64; 3]]) {
    assert!(x.len() == d.len() && d.len() == out.len());
    for ((o, a), b) in out.iter_mut().zip(x).zip(d) {
        *o = [
            a[0] + alpha * b[0],
            a[1] + alpha * b[1],
            a[2] + alpha * b[2],
        ];
    }
}

/// `x ← α x`.
pub fn scale(x: &mut [[f64; 3]], alpha: f64) {
    for a in x.as_flattened_mut() {
        *a *= alpha;
    }
}
