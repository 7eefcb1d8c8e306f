//! The dense kernel under the supernodal factorization: a block of `X Xᵀ`.
//!
//! Both the updates a supernode receives from its descendants and the
//! updates between panels inside a supernode are products `X Xᵀ`, where `X`
//! is a set of columns of `L` restricted to some rows. This kernel computes
//! one block of four columns of that product:
//!
//! ```text
//! block[r][t] = Σ_k X(first + r, k) · X(first + t, k)      t = 0..4, r = 0..rows
//! ```
//!
//! `X` is addressed column by column: row `p` of column `k` is
//! `values[column_base[k] + p]` (the columns of a supernode in CSC are
//! contiguous but each starts at its own offset).
//!
//! Register blocking: eight rows by four columns of `block` stay in
//! registers while `k` runs, so each value of `X` loaded from memory is
//! used for four multiply-adds. Where the CPU has AVX2 and FMA (checked at
//! run time), the same code is compiled with those instructions; elsewhere
//! it runs as plain portable Rust.
//!
//! Cost `4 · rows · ncols(X)` multiply-adds per call. Source: the
//! register-blocked micro-kernel of Goto & van de Geijn, "Anatomy of
//! high-performance matrix multiplication", ACM TOMS 34(3), 2008, reduced to
//! its simplest form.

/// Columns of the product computed per call.
pub const BLOCK_COLUMNS: usize = 4;
const BLOCK_ROWS: usize = 8;

/// `block[r * 4 + t] = Σ_k X(first + r, k) · X(first + t, k)` for
/// `r in 0..rows`, with `X(p, k) = values[column_base[k] + p]`. Columns
/// `t ≥ width` of the block are set to zero.
///
/// # Panics
/// When `width > 4`, `block` holds fewer than `4 · rows` values, `rows <
/// width`, or a column of `X` does not reach row `first + rows`.
pub fn gram_block(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    width: usize,
    rows: usize,
    block: &mut [f64],
) {
    assert!(width <= BLOCK_COLUMNS && rows >= width && block.len() >= BLOCK_COLUMNS * rows);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports the features the function is compiled for.
        unsafe { gram_block_avx2(values, column_base, first, width, rows, block) };
        return;
    }
    gram_block_portable::<false>(values, column_base, first, width, rows, block);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn gram_block_avx2(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    width: usize,
    rows: usize,
    block: &mut [f64],
) {
    gram_block_portable::<true>(values, column_base, first, width, rows, block);
}

/// `a · b + c`, fused into one rounding where the CPU has FMA.
#[inline(always)]
fn multiply_add<const FUSED: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FUSED {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

#[inline(always)]
fn gram_block_portable<const FUSED: bool>(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    width: usize,
    rows: usize,
    block: &mut [f64],
) {
    let mut r = 0;
    while r + BLOCK_ROWS <= rows {
        let tile = gram_tile::<FUSED, BLOCK_ROWS>(values, column_base, first, width, first + r);
        store_tile(&tile, &mut block[r * BLOCK_COLUMNS..]);
        r += BLOCK_ROWS;
    }
    while r < rows {
        let tile = gram_tile::<FUSED, 1>(values, column_base, first, width, first + r);
        store_tile(&tile, &mut block[r * BLOCK_COLUMNS..]);
        r += 1;
    }
}

/// `tile[t][i] = Σ_k X(row + i, k) · X(first + t, k)` for `R` rows.
#[inline(always)]
fn gram_tile<const FUSED: bool, const R: usize>(
    values: &[f64],
    column_base: &[usize],
    first: usize,
    width: usize,
    row: usize,
) -> [[f64; R]; BLOCK_COLUMNS] {
    let mut tile = [[0.0; R]; BLOCK_COLUMNS];
    for &base in column_base {
        let x: &[f64; R] = values[base + row..base + row + R].try_into().unwrap();
        let mut y = [0.0; BLOCK_COLUMNS];
        y[..width].copy_from_slice(&values[base + first..base + first + width]);
        for t in 0..BLOCK_COLUMNS {
            for i in 0..R {
                tile[t][i] = multiply_add::<FUSED>(x[i], y[t], tile[t][i]);
            }
        }
    }
    tile
}

/// Writes a tile into the row-major block (`4` values per row).
#[inline(always)]
fn store_tile<const R: usize>(tile: &[[f64; R]; BLOCK_COLUMNS], block: &mut [f64]) {
    for i in 0..R {
        for t in 0..BLOCK_COLUMNS {
            block[i * BLOCK_COLUMNS + t] = tile[t][i];
        }
    }
}
