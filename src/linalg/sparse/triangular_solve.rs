//! Forward and back substitution with the sparse factor `L`.
//!
//! With `L` stored by columns (diagonal first), both triangles are solved
//! with one sweep over `L`:
//!
//! ```text
//! L y = b  (forward):  for j = 0, 1, …:   y_j = b_j / L_jj;  b_i −= L_ij y_j  for i > j
//! Lᵀ x = y (backward): for j = n−1, …, 0: x_j = (y_j − Σ_{i>j} L_ij x_i) / L_jj
//! ```
//!
//! The right-hand side is a block of `W` columns stored row by row
//! (`[[f64; W]]`): `W = 1` for a vector, `W = 3` for the x, y, z
//! coordinates of the simulation. Every entry of `L` is then loaded once
//! and used for all `W` columns, instead of sweeping `L` once per column
//! (which is what Eigen does, and why this solve is about three times
//! cheaper in memory traffic).
//!
//! Cost `2 · nnz(L) · W` multiply-adds; memory-bound for large `L`.
//! Source: Davis 2006, §3.1 (`cs_lsolve`, `cs_ltsolve`).

/// Solves `L y = b` in place (`x` holds `b` on entry, `y` on return).
pub fn forward_substitution<const W: usize>(
    col_ptr: &[usize],
    row_idx: &[u32],
    values: &[f64],
    x: &mut [[f64; W]],
) {
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

/// Solves `Lᵀ x = y` in place (`x` holds `y` on entry, `x` on return).
pub fn back_substitution<const W: usize>(
    col_ptr: &[usize],
    row_idx: &[u32],
    values: &[f64],
    x: &mut [[f64; W]],
) {
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
