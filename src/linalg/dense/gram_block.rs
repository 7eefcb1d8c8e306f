//! The dense kernel under the supernodal factorization: a block of `X Xᵀ`.
//!
//! Both the updates a supernode receives from its descendants and the
//! updates between panels inside a supernode are products `X Xᵀ`, where `X`
//! is a set of columns of `L` restricted to some rows. This kernel computes
//! one block of four columns of that product:
//!
//! ```text
//! block[t][r] = Σ_k X(first + r, k) · X(first + t, k)      t = 0..4, r = 0..rows
//! ```
//!
//! `X` is addressed column by column: row `p` of column `k` is
//! `values[column_base[k] + p]` (the columns of a supernode in CSC are
//! contiguous but each starts at its own offset). The block is stored by
//! columns: `block[t * rows + r]`.
//!
//! Register blocking: a tile of eight rows by four columns of the block
//! stays in registers while `k` runs, so each value of `X` loaded from
//! memory serves four multiply-adds. On a CPU with AVX2 and FMA (checked at
//! run time) the tile is eight 256-bit registers and the loop is written
//! with those instructions directly: left to itself the compiler keeps the
//! tile in scalars and spills it to the stack. Elsewhere a plain loop,
//! [`gram_block_portable`], computes the same sums; it can be called
//! directly on any CPU, and the tests check that both versions agree.
//!
//! Prefetching: the tile walks across the columns of `X`, one 64-byte line
//! of each, and the columns start at uneven offsets, so the processor's
//! own prefetcher cannot guess the next address and every line is a wait
//! on the cache below. When `X` has many columns (64 or more: the large
//! supernodes near the root, whose columns no longer fit in L2) the tile
//! asks for the line of the column sixteen ahead while it works on this
//! one. That made the numeric factorization of grid-1000 11% faster
//! (1.14 against 1.29 s, `masssprings analyze grid-1000.mtx`, interleaved),
//! and changed nothing measurable on the smaller matrices.
//!
//! Cost `4 · rows · ncols(X)` multiply-adds per call. Source: the
//! register-blocked micro-kernel of Goto & van de Geijn, "Anatomy of
//! high-performance matrix multiplication", ACM TOMS 34(3), 2008, reduced to
//! its simplest form.

/// Columns of the product computed per call.
pub const BLOCK_COLUMNS: usize = 4;

/// `block[t * rows + r] = Σ_k X(first + r, k) · X(first + t, k)` for
/// `r in 0..rows`, `t in 0..4`, with `X(p, k) = values[column_base[k] + p]`.
/// Columns `t ≥ width` of the block are zero. `rows_of_y` is a work buffer
/// with room for one entry per column of `X`. Runs the AVX2 + FMA version
/// when the CPU has those instructions, [`gram_block_portable`] otherwise.
///
/// # Panics
/// When `width > 4`, `rows < width`, `block` holds fewer than `4 · rows`
/// values, `rows_of_y` is shorter than `column_base`, or a column of `X`
/// does not reach row `first + rows`.
pub fn gram_block(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    width: usize,
    rows: usize,
    block: &mut [f64],
    rows_of_y: &mut [[f64; BLOCK_COLUMNS]],
) {
    let (ys, block) = prepare(values, column_base, first, width, rows, block, rows_of_y);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports the features the function is compiled for.
        unsafe { avx2::gram_block(values, column_base, first, rows, ys, block) };
        return;
    }
    plain_sums(values, column_base, first, rows, ys, block);
}

/// [`gram_block`] computed by the plain loop on every CPU: the same sums,
/// one multiply-add at a time, without fused multiply-add.
///
/// # Panics
/// As [`gram_block`].
pub fn gram_block_portable(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    width: usize,
    rows: usize,
    block: &mut [f64],
    rows_of_y: &mut [[f64; BLOCK_COLUMNS]],
) {
    let (ys, block) = prepare(values, column_base, first, width, rows, block, rows_of_y);
    plain_sums(values, column_base, first, rows, ys, block);
}

/// Checks the shapes and fills `Y(k) = X(first .. first + width, k)`,
/// padded with zeros to four values; returns `Y` and the block's
/// `4 · rows` values.
fn prepare<'y, 'b>(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    width: usize,
    rows: usize,
    block: &'b mut [f64],
    rows_of_y: &'y mut [[f64; BLOCK_COLUMNS]],
) -> (&'y [[f64; BLOCK_COLUMNS]], &'b mut [f64]) {
    assert!(width <= BLOCK_COLUMNS && rows >= width && block.len() >= BLOCK_COLUMNS * rows);
    assert!(rows_of_y.len() >= column_base.len());
    for (y, &base) in rows_of_y.iter_mut().zip(column_base) {
        *y = [0.0; BLOCK_COLUMNS];
        y[..width].copy_from_slice(&values[base + first..base + first + width]);
    }
    (
        &rows_of_y[..column_base.len()],
        &mut block[..BLOCK_COLUMNS * rows],
    )
}

/// The sums, one entry at a time.
fn plain_sums(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    rows: usize,
    ys: &[[f64; BLOCK_COLUMNS]],
    block: &mut [f64],
) {
    block.fill(0.0);
    for (&base, y) in column_base.iter().zip(ys) {
        let x = &values[base + first..base + first + rows];
        for t in 0..BLOCK_COLUMNS {
            let column = &mut block[t * rows..(t + 1) * rows];
            for (b, &x_r) in column.iter_mut().zip(x) {
                *b += x_r * y[t];
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::BLOCK_COLUMNS;
    use std::arch::x86_64::*;

    /// Columns of `X` at and above which the tiles prefetch.
    const LONG: usize = 64;
    /// How many columns ahead they prefetch.
    const AHEAD: usize = 16;

    /// Tiles of eight rows (two registers per column), then the last rows
    /// one at a time.
    #[target_feature(enable = "avx2,fma")]
    pub fn gram_block(
        values: &[f64],
        column_base: &[usize],
        first: usize,
        rows: usize,
        ys: &[[f64; BLOCK_COLUMNS]],
        block: &mut [f64],
    ) {
        for &base in column_base {
            assert!(
                base + first + rows <= values.len(),
                "a column of X is too short"
            );
        }
        let prefetch = column_base.len() >= LONG;
        let mut r = 0;
        while r + 8 <= rows {
            // SAFETY: every column reaches row first + rows (checked above),
            // and the tile's stores stay inside block (4 · rows values).
            unsafe {
                if prefetch {
                    tile_of_eight::<true>(values, column_base, first + r, ys, block, rows, r)
                } else {
                    tile_of_eight::<false>(values, column_base, first + r, ys, block, rows, r)
                }
            };
            r += 8;
        }
        for r in r..rows {
            let mut sum = [0.0; BLOCK_COLUMNS];
            for (&base, y) in column_base.iter().zip(ys) {
                let x = values[base + first + r];
                for t in 0..BLOCK_COLUMNS {
                    sum[t] = x.mul_add(y[t], sum[t]);
                }
            }
            for t in 0..BLOCK_COLUMNS {
                block[t * rows + r] = sum[t];
            }
        }
    }

    /// `block[t·rows + r .. + 8] = Σ_k X(row .. row + 8, k) · Y(k)[t]`.
    ///
    /// # Safety
    /// Rows `row .. row + 8` exist in every column of `X`, and
    /// `r + 8 ≤ rows`.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn tile_of_eight<const PREFETCH: bool>(
        values: &[f64],
        column_base: &[usize],
        row: usize,
        ys: &[[f64; BLOCK_COLUMNS]],
        block: &mut [f64],
        rows: usize,
        r: usize,
    ) {
        let v = values.as_ptr();
        let mut acc = [[_mm256_setzero_pd(); 2]; BLOCK_COLUMNS];
        for (k, (&base, y)) in column_base.iter().zip(ys).enumerate() {
            if PREFETCH {
                // the tile's rows of the column AHEAD columns on (two lines:
                // eight values may straddle them); nothing past the last
                let ahead = column_base[(k + AHEAD).min(column_base.len() - 1)];
                _mm_prefetch::<_MM_HINT_T0>(v.wrapping_add(ahead + row).cast());
                _mm_prefetch::<_MM_HINT_T0>(v.wrapping_add(ahead + row + 7).cast());
            }
            let x_low = _mm256_loadu_pd(v.add(base + row));
            let x_high = _mm256_loadu_pd(v.add(base + row + 4));
            for t in 0..BLOCK_COLUMNS {
                let y_t = _mm256_set1_pd(y[t]);
                acc[t][0] = _mm256_fmadd_pd(x_low, y_t, acc[t][0]);
                acc[t][1] = _mm256_fmadd_pd(x_high, y_t, acc[t][1]);
            }
        }
        let out = block.as_mut_ptr();
        for t in 0..BLOCK_COLUMNS {
            _mm256_storeu_pd(out.add(t * rows + r), acc[t][0]);
            _mm256_storeu_pd(out.add(t * rows + r + 4), acc[t][1]);
        }
    }
}
