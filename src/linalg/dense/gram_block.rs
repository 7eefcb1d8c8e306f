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
//! tile in scalars and spills it to the stack. With AVX-512 (also checked
//! at run time) the tiles are sixteen rows, two 512-bit registers per
//! column, so that each load, broadcast and multiply-add instruction does
//! twice the work; the rows that do not fill sixteen go to the AVX2 tiles.
//! Each entry of the block is the same chain of fused multiply-adds, over
//! the columns in order, in both, so the factor's bits do not depend on
//! which one ran (the tests check the bits). On a Zen 4 machine, whose
//! AVX-512 units are 256 bits wide inside, this still made the numeric
//! factorization 13–17% faster on grid-1000 (0.85–0.87 against 0.98–1.03
//! s) and 4–6% on grid-316 (`masssprings analyze grid-N.mtx`, interleaved):
//! the loop is bound by issuing instructions, not by the multipliers.
//! Elsewhere a plain loop,
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
    assert!(rows >= width);
    gram_block_rows(
        values,
        column_base,
        first,
        width,
        first,
        rows,
        block,
        rows_of_y,
    );
}

/// [`gram_block`] for the rows `x_first .. x_first + rows` of `X` against
/// its rows `y_first .. y_first + width`: `block[t * rows + r] = Σ_k
/// X(x_first + r, k) · X(y_first + t, k)`. Each entry is the same sum as
/// `gram_block` makes for it, to the bit, whichever rows are asked for with
/// it: the threads of the parallel factorization each compute their own
/// rows of one block.
///
/// # Panics
/// When `width > 4`, `block` holds fewer than `4 · rows` values,
/// `rows_of_y` is shorter than `column_base`, or a column of `X` does not
/// reach the rows asked for.
#[allow(clippy::too_many_arguments)] // gram_block's, and where its rows start
pub fn gram_block_rows(
    values: &[f64],
    column_base: &[usize],
    y_first: usize,
    width: usize,
    x_first: usize,
    rows: usize,
    block: &mut [f64],
    rows_of_y: &mut [[f64; BLOCK_COLUMNS]],
) {
    let (ys, block) = prepare(values, column_base, y_first, width, rows, block, rows_of_y);
    let first = x_first;
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx512_fma() {
        // SAFETY: the CPU supports the features the function is compiled for.
        unsafe { avx512::gram_block(values, column_base, first, rows, ys, block) };
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2_fma() {
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
    assert!(rows >= width);
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
    assert!(width <= BLOCK_COLUMNS && block.len() >= BLOCK_COLUMNS * rows);
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

/// One tile kernel, for registers of `$lanes` numbers and the
/// instructions that go with them (AVX2: four, AVX-512: eight):
/// `block[t·rows + r .. + 2·lanes] = Σ_k X(row .. row + 2·lanes, k) · Y(k)[t]`,
/// two registers per column of the block, each entry a chain of fused
/// multiply-adds over `k` in order. With `PREFETCH`, the tile's rows of the
/// column `AHEAD` columns on are asked for: one value on each line they
/// may straddle, at the offsets `$lines` (nothing past the last column),
/// written out: computed by a loop in the tile, they cost the AVX-512
/// tile its whole gain.
///
/// The generated function's safety contract: rows `row .. row + 2·lanes`
/// exist in every column of `X`, and `r + 2·lanes ≤ rows`.
#[cfg(target_arch = "x86_64")]
macro_rules! tile {
    ($run:ident, $name:ident, $features:literal, $lanes:expr, $lines:expr, $zero:ident, $load:ident, $set1:ident, $fmadd:ident, $store:ident) => {
        /// The block's rows from `r` on, tile by tile while whole tiles
        /// fit; returns the first row left. The caller has checked the
        /// columns ([`check_columns`](super::avx2::check_columns)).
        #[target_feature(enable = $features)]
        pub fn $run(
            values: &[f64],
            column_base: &[usize],
            first: usize,
            rows: usize,
            ys: &[[f64; BLOCK_COLUMNS]],
            block: &mut [f64],
            mut r: usize,
        ) -> usize {
            let prefetch = column_base.len() >= LONG;
            while r + 2 * $lanes <= rows {
                // SAFETY: every column reaches row first + rows (checked by
                // the caller), and the tile's stores stay inside block
                // (4 · rows values).
                unsafe {
                    if prefetch {
                        $name::<true>(values, column_base, first + r, ys, block, rows, r)
                    } else {
                        $name::<false>(values, column_base, first + r, ys, block, rows, r)
                    }
                };
                r += 2 * $lanes;
            }
            r
        }

        #[target_feature(enable = $features)]
        unsafe fn $name<const PREFETCH: bool>(
            values: &[f64],
            column_base: &[usize],
            row: usize,
            ys: &[[f64; BLOCK_COLUMNS]],
            block: &mut [f64],
            rows: usize,
            r: usize,
        ) {
            const LANES: usize = $lanes;
            let v = values.as_ptr();
            let mut acc = [[$zero(); 2]; BLOCK_COLUMNS];
            for (k, (&base, y)) in column_base.iter().zip(ys).enumerate() {
                if PREFETCH {
                    let ahead = column_base[(k + AHEAD).min(column_base.len() - 1)];
                    for offset in $lines {
                        _mm_prefetch::<_MM_HINT_T0>(v.wrapping_add(ahead + row + offset).cast());
                    }
                }
                let x_low = $load(v.add(base + row));
                let x_high = $load(v.add(base + row + LANES));
                for t in 0..BLOCK_COLUMNS {
                    let y_t = $set1(y[t]);
                    acc[t][0] = $fmadd(x_low, y_t, acc[t][0]);
                    acc[t][1] = $fmadd(x_high, y_t, acc[t][1]);
                }
            }
            let out = block.as_mut_ptr();
            for t in 0..BLOCK_COLUMNS {
                $store(out.add(t * rows + r), acc[t][0]);
                $store(out.add(t * rows + r + LANES), acc[t][1]);
            }
        }
    };
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::BLOCK_COLUMNS;
    use std::arch::x86_64::*;

    /// Columns of `X` at and above which the tiles prefetch.
    pub const LONG: usize = 64;
    /// How many columns ahead they prefetch.
    pub const AHEAD: usize = 16;

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
        check_columns(values, column_base, first, rows);
        tiles_from(values, column_base, first, rows, ys, block, 0);
    }

    /// Panics unless every column of `X` reaches row `first + rows`.
    pub fn check_columns(values: &[f64], column_base: &[usize], first: usize, rows: usize) {
        for &base in column_base {
            assert!(
                base + first + rows <= values.len(),
                "a column of X is too short"
            );
        }
    }

    /// The block's rows from `r` on: tiles of eight, then one at a time.
    /// The caller has checked the columns ([`check_columns`]).
    #[target_feature(enable = "avx2,fma")]
    pub fn tiles_from(
        values: &[f64],
        column_base: &[usize],
        first: usize,
        rows: usize,
        ys: &[[f64; BLOCK_COLUMNS]],
        block: &mut [f64],
        r: usize,
    ) {
        let r = tiles_of_eight(values, column_base, first, rows, ys, block, r);
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

    tile!(
        tiles_of_eight,
        tile_of_eight,
        "avx2,fma",
        4,
        [0, 7],
        _mm256_setzero_pd,
        _mm256_loadu_pd,
        _mm256_set1_pd,
        _mm256_fmadd_pd,
        _mm256_storeu_pd
    );
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::avx2::{check_columns, tiles_from, AHEAD, LONG};
    use super::BLOCK_COLUMNS;
    use std::arch::x86_64::*;

    /// Tiles of sixteen rows (two 512-bit registers per column), then the
    /// AVX2 tiles of eight and the last rows one at a time. Each entry of
    /// the block is the same chain of multiply-adds over `k` in every
    /// version, so all of them give the same bits.
    #[target_feature(enable = "avx512f,avx2,fma")]
    pub fn gram_block(
        values: &[f64],
        column_base: &[usize],
        first: usize,
        rows: usize,
        ys: &[[f64; BLOCK_COLUMNS]],
        block: &mut [f64],
    ) {
        check_columns(values, column_base, first, rows);
        let r = tiles_of_sixteen(values, column_base, first, rows, ys, block, 0);
        tiles_from(values, column_base, first, rows, ys, block, r);
    }

    tile!(
        tiles_of_sixteen,
        tile_of_sixteen,
        "avx512f,avx2,fma",
        8,
        [0, 8, 15],
        _mm512_setzero_pd,
        _mm512_loadu_pd,
        _mm512_set1_pd,
        _mm512_fmadd_pd,
        _mm512_storeu_pd
    );
}
