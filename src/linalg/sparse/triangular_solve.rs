//! Forward and back substitution with the sparse factor `L`: the textbook
//! solves of the simplicial method.
//!
//! With `L` stored by columns (diagonal first), both triangles are solved
//! with one sweep over `L`:
//!
//! ```text
//! L y = b  (forward):  for j = 0, 1, …:   y_j = b_j / L_jj;  b_i −= L_ij y_j  for i > j
//! Lᵀ x = y (backward): for j = n−1, …, 0: x_j = (y_j − Σ_{i>j} L_ij x_i) / L_jj
//! ```
//!
//! [`forward_substitution_sparse`] and [`back_substitution_sparse`] are
//! those two loops, as written, and the simplicial solve
//! ([`solve_in_place`]) runs them. Beside them,
//! [`back_substitution_sparse_two_sums`] is a faster variant of the back
//! sweep: it accumulates the sum in two partial sums (even and odd
//! entries) so that consecutive multiply-adds do not wait on each other; it
//! rounds differently, and the tests check it against the plain loop. The
//! supernodal solves are in [`supernodal_solve`](super::supernodal_solve).
//! The dense substitutions are
//! [`forward_substitution_dense`](crate::linalg::dense::forward_substitution_dense)
//! and [`back_substitution_dense`](crate::linalg::dense::back_substitution_dense).
//!
//! The right-hand side is a block of `W` columns stored row by row
//! (`[[f64; W]]`): `W = 1` for a vector, `W = 3` for the x, y, z
//! coordinates of the simulation. Every entry of `L` is then loaded once
//! and used for all `W` columns, instead of sweeping `L` once per column
//! (which is what Eigen does, and why this solve is about three times
//! cheaper in memory traffic).
//!
//! For the three coordinates the caller pads each row to four lanes
//! (`[x, y, z, 0]`), so that on a CPU with AVX2 one 256-bit instruction
//! updates a whole row; the same loops are compiled a second time with AVX2
//! and FMA enabled and chosen at run time.
//!
//! Cost `2 · nnz(L) · W` multiply-adds; memory-bound for large `L`.
//! Source: Davis 2006, §3.1 (`cs_lsolve`, `cs_ltsolve`).

/// The factor `L` in CSC form: column pointers, 32-bit rows (diagonal
/// first in each column), values.
#[derive(Debug, Clone, Copy)]
pub struct FactorView<'a> {
    pub col_ptr: &'a [usize],
    pub row_idx: &'a [u32],
    pub values: &'a [f64],
}

/// Solves `L y = b` and then `Lᵀ x = y` in place with the textbook loops:
/// `x` holds `b` on entry and `x = (L Lᵀ)⁻¹ b` on return.
pub fn solve_in_place<const W: usize>(l: FactorView, x: &mut [[f64; W]]) {
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2_fma() {
        // SAFETY: the CPU supports the features the function is compiled for.
        unsafe { solve_in_place_avx2(l, x) };
        return;
    }
    forward_substitution_sparse(l, x);
    back_substitution_sparse(l, x);
}

/// The same loops, compiled with AVX2 and FMA enabled.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn solve_in_place_avx2<const W: usize>(l: FactorView, x: &mut [[f64; W]]) {
    forward_substitution_sparse(l, x);
    back_substitution_sparse(l, x);
}

/// Solves `L y = b` in place (`x` holds `b` on entry, `y` on return):
/// for each column `j`, `y_j = b_j / L_jj`, then `b_i −= L_ij y_j` below it.
#[inline(always)]
pub fn forward_substitution_sparse<const W: usize>(l: FactorView, x: &mut [[f64; W]]) {
    let FactorView {
        col_ptr,
        row_idx,
        values,
    } = l;
    for j in 0..x.len() {
        let (start, end) = (col_ptr[j], col_ptr[j + 1]);
        let diagonal = values[start];
        let xj = x[j].map(|value| value / diagonal);
        x[j] = xj;
        for (&i, &l_ij) in row_idx[start + 1..end].iter().zip(&values[start + 1..end]) {
            let xi = &mut x[i as usize];
            for c in 0..W {
                xi[c] -= l_ij * xj[c];
            }
        }
    }
}

/// Solves `Lᵀ x = y` in place (`x` holds `y` on entry, `x` on return):
/// from the last column up, `x_j = (y_j − Σ_{i>j} L_ij x_i) / L_jj`, one
/// sum accumulated entry by entry.
#[inline(always)]
pub fn back_substitution_sparse<const W: usize>(l: FactorView, x: &mut [[f64; W]]) {
    let FactorView {
        col_ptr,
        row_idx,
        values,
    } = l;
    for j in (0..x.len()).rev() {
        let (start, end) = (col_ptr[j], col_ptr[j + 1]);
        let mut sum = x[j];
        for (&i, &l_ij) in row_idx[start + 1..end].iter().zip(&values[start + 1..end]) {
            let xi = x[i as usize];
            for c in 0..W {
                sum[c] -= l_ij * xi[c];
            }
        }
        let diagonal = values[start];
        x[j] = sum.map(|value| value / diagonal);
    }
}

/// [`back_substitution_sparse`] with the sum split in two partial sums
/// (even and odd entries of each column), so that consecutive multiply-adds
/// do not wait on each other: faster on long columns, rounded differently.
#[inline(always)]
pub fn back_substitution_sparse_two_sums<const W: usize>(l: FactorView, x: &mut [[f64; W]]) {
    let FactorView {
        col_ptr,
        row_idx,
        values,
    } = l;
    for j in (0..x.len()).rev() {
        let (start, end) = (col_ptr[j], col_ptr[j + 1]);
        let rows = &row_idx[start + 1..end];
        let column = &values[start + 1..end];
        let mut even = x[j];
        let mut odd = [0.0; W];
        let pairs = rows.len() / 2;
        for p in 0..pairs {
            let (x0, x1) = (x[rows[2 * p] as usize], x[rows[2 * p + 1] as usize]);
            for c in 0..W {
                even[c] -= column[2 * p] * x0[c];
                odd[c] -= column[2 * p + 1] * x1[c];
            }
        }
        if rows.len() % 2 == 1 {
            let last = x[rows[rows.len() - 1] as usize];
            for c in 0..W {
                even[c] -= column[rows.len() - 1] * last[c];
            }
        }
        let diagonal = values[start];
        x[j] = std::array::from_fn(|c| (even[c] + odd[c]) / diagonal);
    }
}
