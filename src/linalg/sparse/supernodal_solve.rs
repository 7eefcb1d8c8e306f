//! Forward and back substitution, one supernode at a time.
//!
//! The same two sweeps as [`triangular_solve`](super::triangular_solve),
//! but each supernode's columns are handled as a dense block: its diagonal
//! block `L₁₁` (w × w, lower triangular) over the contiguous unknowns
//! `x_s = x[first .. first + w]`, and the block `L₂₁` below it, whose rows
//! `R` are shared by all w columns.
//!
//! ```text
//! forward (L y = b), supernodes in order:      back (Lᵀ x = y), in reverse:
//!   x_s ← L₁₁⁻¹ x_s                              t   ← x[R]             (gather)
//!   t   ← L₂₁ x_s          (dense, into t)       x_s ← x_s − L₂₁ᵀ t     (dense)
//!   x[R] ← x[R] − t        (scatter)             x_s ← L₁₁⁻ᵀ x_s
//! ```
//!
//! Compared with the column-by-column sweep, each row index is read once
//! per supernode rather than once per entry, and each unknown below the
//! block is updated once per supernode rather than once per column. The
//! dense parts run down contiguous columns.
//!
//! As there, the right-hand side is a block of `W` columns stored row by
//! row (padded to four lanes for x, y, z), and the loops are compiled a
//! second time with AVX2 and FMA, chosen at run time.
//!
//! Cost `2 · nnz(L) · W` multiply-adds, plus a gather and a scatter of the
//! rows below each supernode. Source: Davis 2006, §4.6 and §8.1; CHOLMOD's
//! supernodal solve (Chen, Davis, Hager, Rajamanickam, ACM TOMS 35(3), 2008).

use super::supernodes::Supernodes;
use super::triangular_solve::FactorView;
use crate::linalg::dense::row_kernels::{axpy_rows, dot_rows};

/// Solves `L Lᵀ x = b` in place, supernode by supernode; `below` is a work
/// buffer with room for the rows below the tallest supernode.
pub fn solve_in_place<const W: usize>(
    l: FactorView,
    supernodes: &Supernodes,
    x: &mut [[f64; W]],
    below: &mut [[f64; W]],
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports the features the function is compiled for.
        unsafe { solve_in_place_avx2(l, supernodes, x, below) };
        return;
    }
    forward::<W, false>(l, supernodes, x, below);
    backward::<W, false>(l, supernodes, x, below);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn solve_in_place_avx2<const W: usize>(
    l: FactorView,
    supernodes: &Supernodes,
    x: &mut [[f64; W]],
    below: &mut [[f64; W]],
) {
    forward::<W, true>(l, supernodes, x, below);
    backward::<W, true>(l, supernodes, x, below);
}

/// Supernodes at least this wide go through the dense block path; narrower
/// ones are swept column by column (the gather/scatter would cost more
/// than it saves).
const WIDE: usize = 16;

/// One supernode as the solve sees it: its first column, width, and the
/// rows below its diagonal block.
struct Block<'a> {
    first: usize,
    width: usize,
    rows_below: &'a [u32],
}

impl<'a> Block<'a> {
    fn new(l: &FactorView<'a>, supernodes: &Supernodes, s: usize) -> Self {
        let columns = supernodes.columns(s);
        let start = l.col_ptr[columns.start];
        let end = l.col_ptr[columns.start + 1];
        Block {
            first: columns.start,
            width: columns.len(),
            rows_below: &l.row_idx[start + columns.len()..end],
        }
    }

    /// Column `k` of the block from its diagonal down, split into its part
    /// in `L₁₁` (diagonal first) and its part in `L₂₁`.
    fn column<'v>(&self, l: &FactorView<'v>, k: usize) -> (&'v [f64], &'v [f64]) {
        let j = self.first + k;
        l.values[l.col_ptr[j]..l.col_ptr[j + 1]].split_at(self.width - k)
    }
}

/// `L y = b`: supernodes in order.
#[inline(always)]
fn forward<const W: usize, const SIMD: bool>(
    l: FactorView,
    supernodes: &Supernodes,
    x: &mut [[f64; W]],
    below: &mut [[f64; W]],
) {
    for s in 0..supernodes.len() {
        let block = Block::new(&l, supernodes, s);
        if block.width < WIDE {
            forward_narrow(&l, &block, x);
            continue;
        }
        let t = &mut below[..block.rows_below.len()];
        t.fill([0.0; W]);
        for k in 0..block.width {
            let (diagonal_part, below_part) = block.column(&l, k);
            // x_s ← L₁₁⁻¹ x_s, column k
            let xk = x[block.first + k].map(|v| v / diagonal_part[0]);
            x[block.first + k] = xk;
            for (r, &l_rk) in diagonal_part.iter().enumerate().skip(1) {
                let xr = &mut x[block.first + k + r];
                for c in 0..W {
                    xr[c] -= l_rk * xk[c];
                }
            }
            axpy_rows::<W, SIMD>(t, below_part, xk); // t ← t + L₂₁(:, k) x_k
        }
        // x[R] ← x[R] − t
        for (&row, tr) in block.rows_below.iter().zip(t.iter()) {
            let xr = &mut x[row as usize];
            for c in 0..W {
                xr[c] -= tr[c];
            }
        }
    }
}

/// Forward sweep over a narrow supernode, column by column: like the
/// simplicial sweep, but all columns use the one shared list of rows.
#[inline(always)]
fn forward_narrow<const W: usize>(l: &FactorView, block: &Block, x: &mut [[f64; W]]) {
    for k in 0..block.width {
        let (diagonal_part, below_part) = block.column(l, k);
        let xk = x[block.first + k].map(|v| v / diagonal_part[0]);
        x[block.first + k] = xk;
        for (r, &l_rk) in diagonal_part.iter().enumerate().skip(1) {
            let xr = &mut x[block.first + k + r];
            for c in 0..W {
                xr[c] -= l_rk * xk[c];
            }
        }
        for (&row, &l_rk) in block.rows_below.iter().zip(below_part) {
            let xr = &mut x[row as usize];
            for c in 0..W {
                xr[c] -= l_rk * xk[c];
            }
        }
    }
}

/// `Lᵀ x = y`: supernodes in reverse order.
#[inline(always)]
fn backward<const W: usize, const SIMD: bool>(
    l: FactorView,
    supernodes: &Supernodes,
    x: &mut [[f64; W]],
    below: &mut [[f64; W]],
) {
    for s in (0..supernodes.len()).rev() {
        let block = Block::new(&l, supernodes, s);
        if block.width < WIDE {
            backward_narrow(&l, &block, x);
            continue;
        }
        let t = &mut below[..block.rows_below.len()];
        // t ← x[R]
        for (tr, &row) in t.iter_mut().zip(block.rows_below) {
            *tr = x[row as usize];
        }
        for k in (0..block.width).rev() {
            let (diagonal_part, below_part) = block.column(&l, k);
            // x_k ← (x_k − L₂₁(:, k)ᵀ t − L₁₁(k+1.., k)ᵀ x_s(k+1..)) / L_kk
            let mut sum = dot_rows::<W, SIMD>(below_part, t);
            for (r, &l_rk) in diagonal_part.iter().enumerate().skip(1) {
                let xr = x[block.first + k + r];
                for c in 0..W {
                    sum[c] += l_rk * xr[c];
                }
            }
            let xk = &mut x[block.first + k];
            *xk = std::array::from_fn(|c| (xk[c] - sum[c]) / diagonal_part[0]);
        }
    }
}

/// Back sweep over a narrow supernode, column by column, reading `x` at
/// the shared rows directly.
#[inline(always)]
fn backward_narrow<const W: usize>(l: &FactorView, block: &Block, x: &mut [[f64; W]]) {
    for k in (0..block.width).rev() {
        let (diagonal_part, below_part) = block.column(l, k);
        // two partial sums, so consecutive terms do not wait on each other
        let (mut even, mut odd) = ([0.0; W], [0.0; W]);
        let mut pairs = block
            .rows_below
            .chunks_exact(2)
            .zip(below_part.chunks_exact(2));
        for (rows, l_pair) in &mut pairs {
            let (x0, x1) = (x[rows[0] as usize], x[rows[1] as usize]);
            for c in 0..W {
                even[c] += l_pair[0] * x0[c];
                odd[c] += l_pair[1] * x1[c];
            }
        }
        if below_part.len() % 2 == 1 {
            let last = below_part.len() - 1;
            let xr = x[block.rows_below[last] as usize];
            for c in 0..W {
                even[c] += below_part[last] * xr[c];
            }
        }
        for (r, &l_rk) in diagonal_part.iter().enumerate().skip(1) {
            let xr = x[block.first + k + r];
            for c in 0..W {
                even[c] += l_rk * xr[c];
            }
        }
        let xk = &mut x[block.first + k];
        *xk = std::array::from_fn(|c| (xk[c] - even[c] - odd[c]) / diagonal_part[0]);
    }
}
