//! Two dense kernels on blocks of rows: `t += a·x` down a column, and the
//! dot product of a column with a block.
//!
//! A block here is `[[f64; W]]`: rows of `W` values (the supernodal solve's
//! right-hand sides, four lanes for x, y, z and padding). Both kernels are
//! memory-bound loops over contiguous rows:
//!
//! ```text
//! axpy_rows:  t[r] ← t[r] + column[r] · x       for every row r
//! dot_rows:   Σ_r column[r] · t[r]
//! ```
//!
//! The portable versions are plain loops. For four lanes on a CPU with AVX2
//! and FMA, each row is exactly one 256-bit register, and the loops are
//! written with those instructions directly: left to itself the compiler
//! vectorizes across four *rows* and spends most instructions transposing.
//! Callers pass `SIMD = true` only from code that checked the CPU features.
//!
//! Cost `W` multiply-adds per row.

/// `t[r] ← t[r] + column[r] · x` for every row.
///
/// # Panics
/// When `t` and `column` differ in length.
#[inline(always)]
pub fn axpy_rows<const W: usize, const SIMD: bool>(
    t: &mut [[f64; W]],
    column: &[f64],
    x: [f64; W],
) {
    assert_eq!(t.len(), column.len());
    #[cfg(target_arch = "x86_64")]
    if SIMD && W == 4 {
        let (t4, _) = t.as_flattened_mut().as_chunks_mut::<4>();
        let x4 = [x[0], x[1], x[2], x[3]];
        // SAFETY: SIMD is only set by callers compiled for, and run on, AVX2+FMA.
        unsafe { avx2::axpy_rows(t4, column, x4) };
        return;
    }
    for (tr, &a) in t.iter_mut().zip(column) {
        for c in 0..W {
            tr[c] += a * x[c];
        }
    }
}

/// `Σ_r column[r] · t[r]`.
///
/// # Panics
/// When `t` and `column` differ in length.
#[inline(always)]
pub fn dot_rows<const W: usize, const SIMD: bool>(column: &[f64], t: &[[f64; W]]) -> [f64; W] {
    assert_eq!(t.len(), column.len());
    #[cfg(target_arch = "x86_64")]
    if SIMD && W == 4 {
        let (t4, _) = t.as_flattened().as_chunks::<4>();
        // SAFETY: as above.
        let sum = unsafe { avx2::dot_rows(column, t4) };
        return std::array::from_fn(|c| sum[c]);
    }
    // two partial sums, so consecutive terms do not wait on each other
    let (mut even, mut odd) = ([0.0; W], [0.0; W]);
    let mut pairs = column.chunks_exact(2).zip(t.chunks_exact(2));
    for (a, rows) in &mut pairs {
        for c in 0..W {
            even[c] += a[0] * rows[0][c];
            odd[c] += a[1] * rows[1][c];
        }
    }
    if let (Some(&a), Some(row)) = (column.last(), t.last()) {
        if column.len() % 2 == 1 {
            for c in 0..W {
                even[c] += a * row[c];
            }
        }
    }
    std::array::from_fn(|c| even[c] + odd[c])
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;

    #[target_feature(enable = "avx2,fma")]
    pub fn axpy_rows(t: &mut [[f64; 4]], column: &[f64], x: [f64; 4]) {
        // SAFETY (loads/stores): each pointer is to one whole `[f64; 4]` row.
        unsafe {
            let x = _mm256_loadu_pd(x.as_ptr());
            for (row, &a) in t.iter_mut().zip(column) {
                let p = row.as_mut_ptr();
                _mm256_storeu_pd(p, _mm256_fmadd_pd(_mm256_set1_pd(a), x, _mm256_loadu_pd(p)));
            }
        }
    }

    #[target_feature(enable = "avx2,fma")]
    pub fn dot_rows(column: &[f64], t: &[[f64; 4]]) -> [f64; 4] {
        // SAFETY (loads/stores): each pointer is to one whole `[f64; 4]` row.
        unsafe {
            let (mut even, mut odd) = (_mm256_setzero_pd(), _mm256_setzero_pd());
            let mut pairs = column.chunks_exact(2).zip(t.chunks_exact(2));
            for (a, rows) in &mut pairs {
                even = _mm256_fmadd_pd(
                    _mm256_set1_pd(a[0]),
                    _mm256_loadu_pd(rows[0].as_ptr()),
                    even,
                );
                odd = _mm256_fmadd_pd(_mm256_set1_pd(a[1]), _mm256_loadu_pd(rows[1].as_ptr()), odd);
            }
            if column.len() % 2 == 1 {
                let last = column.len() - 1;
                even = _mm256_fmadd_pd(
                    _mm256_set1_pd(column[last]),
                    _mm256_loadu_pd(t[last].as_ptr()),
                    even,
                );
            }
            let mut sum = [0.0; 4];
            _mm256_storeu_pd(sum.as_mut_ptr(), _mm256_add_pd(even, odd));
            sum
        }
    }
}
