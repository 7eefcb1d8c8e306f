//! Dense Cholesky factorization `A = L Lᵀ` and the triangular solves that use
//! it.
//!
//! # What it computes
//!
//! A symmetric positive-definite matrix `A` (n×n) has exactly one
//! factorization `A = L Lᵀ` with `L` lower triangular and a positive diagonal.
//! Comparing entry `(i, j)`, `j ≤ i`, of both sides, row by row
//! (the *Cholesky–Banachiewicz* order), gives every entry of `L` from entries
//! already known:
//!
//! ```text
//! l_jj = √(a_jj − Σ_{k<j} l_jk²)
//! l_ij = (a_ij − Σ_{k<j} l_ik l_jk) / l_jj        for i > j
//! ```
//!
//! Only the lower triangle of `A` is read. The number under the square root is
//! the *pivot* of column `j`. It is positive for every `j` exactly when `A` is
//! positive definite, so the factorization doubles as the test: the first
//! pivot that is not `> 0` (or not finite, for NaN or infinite input) stops it
//! with [`LinalgError::NotPositiveDefinite`] naming that column.
//!
//! Solving `A x = b` is then two triangular solves,
//!
//! ```text
//! L y = b    forward substitution:  y_i = (b_i − Σ_{k<i} l_ik y_k) / l_ii,  i = 0, 1, …
//! Lᵀ x = y   back substitution:     x_i = (y_i − Σ_{k>i} u_ik x_k) / u_ii,  i = n−1, …, 0
//! ```
//!
//! with `U = Lᵀ` (`u_ik = l_ki`). This is the assignment's pseudo-code
//! `p = back_substitution(transpose(L), forward_substitution(L, b))`, with its
//! names and the suffix `_dense` the handout gives its dense functions:
//! [`forward_substitution_dense`] and [`back_substitution_dense`] work on any
//! lower and upper triangular matrix, and [`DenseCholesky`] keeps `Lᵀ` next to
//! `L` (computed once when factoring) so that a solve is exactly that line.
//! (The sparse ones, for a factor in compressed columns, are
//! [`forward_substitution_sparse`](crate::linalg::sparse::triangular_solve::forward_substitution_sparse)
//! and
//! [`back_substitution_sparse`](crate::linalg::sparse::triangular_solve::back_substitution_sparse).)
//!
//! # Cost
//!
//! Factoring costs about `n³/3` flops (and `n` square roots); it is done once
//! for the whole simulation, since `Q` does not change. Each triangular solve
//! costs about `n²` flops, so a solve costs `2n²` per right-hand side. A solve
//! allocates nothing: it overwrites the right-hand side with the solution.
//!
//! # Sources
//!
//! Golub & Van Loan, *Matrix Computations*, 4th ed., §4.2 (Cholesky) and §3.1
//! (triangular systems); Trefethen & Bau, *Numerical Linear Algebra*,
//! lecture 23 (Cholesky) and lecture 17 (back substitution).
//!
//! # Conventions
//!
//! As in [`DenseMatrix`]: a right-hand side of the wrong length is an error
//! ([`LinalgError::DimensionMismatch`]), never a panic, and is left untouched.

use super::matrix::{dot, DenseMatrix};
use crate::linalg::cancel::Cancel;
use crate::linalg::error::LinalgError;

/// The Cholesky factorization `A = L Lᵀ` of a symmetric positive-definite
/// matrix, ready to solve `A x = b` for as many `b` as needed.
///
/// # Examples
///
/// ```
/// use masssprings::linalg::dense::{
///     back_substitution_dense, forward_substitution_dense, DenseCholesky, DenseMatrix,
/// };
///
/// let a = DenseMatrix::from_rows(&[[4.0, 2.0], [2.0, 10.0]])?;
/// let cholesky = DenseCholesky::factor(&a)?;
/// assert_eq!(cholesky.l(), &DenseMatrix::from_rows(&[[2.0, 0.0], [1.0, 3.0]])?);
///
/// let mut x = [6.0, 12.0]; // b = A (1, 1)
/// cholesky.solve_in_place(&mut x)?;
/// assert_eq!(x, [1.0, 1.0]);
///
/// // the handout's p = back_substitution(transpose(L), forward_substitution(L, b))
/// let mut p = [6.0, 12.0];
/// forward_substitution_dense(cholesky.l(), &mut p)?;
/// back_substitution_dense(&cholesky.l().transpose(), &mut p)?;
/// assert_eq!(p, [1.0, 1.0]);
///
/// // not positive definite: the error names the column
/// let indefinite = DenseMatrix::from_rows(&[[1.0, 2.0], [2.0, 1.0]])?;
/// assert!(DenseCholesky::factor(&indefinite).is_err());
/// # Ok::<(), masssprings::linalg::LinalgError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct DenseCholesky {
    /// The lower-triangular factor (zeros above the diagonal).
    l: DenseMatrix,
    /// `Lᵀ`, kept so that back substitution reads an upper-triangular matrix
    /// row by row, exactly as it is written.
    l_transpose: DenseMatrix,
}

impl DenseCholesky {
    /// Factors `a = L Lᵀ`, reading only the lower triangle of `a` (the upper
    /// triangle is assumed to mirror it and is never looked at).
    ///
    /// # Errors
    /// * [`LinalgError::NotSquare`] when `a` is not square.
    /// * [`LinalgError::NotPositiveDefinite`] `{ column: j, pivot }` for the
    ///   first column `j` (0-based) whose pivot `a_jj − Σ_{k<j} l_jk²` is not
    ///   `> 0` or not finite; NaN or infinite entries end up there too, in the
    ///   first column whose pivot they reach.
    pub fn factor(a: &DenseMatrix) -> Result<DenseCholesky, LinalgError> {
        Self::factor_cancellable(a, Cancel::NEVER)
    }

    /// [`DenseCholesky::factor`], looking at `cancel` before each row of
    /// `L` and of `Lᵀ` (a row costs at most `n²/2` multiply-adds: on the
    /// skirt's `Q`, n = 9,840, a small fraction of a second).
    ///
    /// # Errors
    /// As [`DenseCholesky::factor`], and [`LinalgError::Cancelled`] once
    /// `cancel` is set (what was factored is dropped).
    pub fn factor_cancellable(
        a: &DenseMatrix,
        cancel: Cancel<'_>,
    ) -> Result<DenseCholesky, LinalgError> {
        if !a.is_square() {
            return Err(LinalgError::NotSquare {
                nrows: a.nrows(),
                ncols: a.ncols(),
            });
        }
        let mut l = DenseMatrix::zeros(a.nrows(), a.ncols());
        for i in 0..a.nrows() {
            cancel.check()?;
            factor_row(a, &mut l, i)?;
        }
        let mut l_transpose = DenseMatrix::zeros(a.nrows(), a.ncols());
        for i in 0..a.nrows() {
            cancel.check()?;
            copy_row_to_column(&l, &mut l_transpose, i);
        }
        Ok(DenseCholesky { l, l_transpose })
    }

    /// Factors `a` again into the storage this factorization already has
    /// (same size), allocating nothing: for small systems solved over and
    /// over, such as the least-squares problem of Anderson acceleration.
    ///
    /// # Errors
    /// As [`DenseCholesky::factor`], plus [`LinalgError::DimensionMismatch`]
    /// (operation `"cholesky refactor"`) when `a` is not `n × n`. After an
    /// error the factorization is not usable until a refactor succeeds.
    pub fn refactor(&mut self, a: &DenseMatrix) -> Result<(), LinalgError> {
        self.check_rows("cholesky refactor", (a.nrows(), a.ncols()))?;
        if !a.is_square() {
            return Err(LinalgError::NotSquare {
                nrows: a.nrows(),
                ncols: a.ncols(),
            });
        }
        for i in 0..a.nrows() {
            factor_row(a, &mut self.l, i)?;
        }
        for i in 0..a.nrows() {
            copy_row_to_column(&self.l, &mut self.l_transpose, i);
        }
        Ok(())
    }

    /// The lower-triangular factor `L` (zeros above the diagonal).
    pub fn l(&self) -> &DenseMatrix {
        &self.l
    }

    /// `Lᵀ`, the upper-triangular factor (zeros below the diagonal), as
    /// back substitution reads it.
    pub fn l_transpose(&self) -> &DenseMatrix {
        &self.l_transpose
    }

    /// The size `n` of the factored `n × n` matrix.
    pub fn dim(&self) -> usize {
        self.l.nrows()
    }

    /// Solves `A x = b` for one right-hand side: `b` is overwritten with `x`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation `"cholesky solve"`) when
    /// `b.len() != n`; `b` is left untouched.
    pub fn solve_in_place(&self, b: &mut [f64]) -> Result<(), LinalgError> {
        self.check_rows("cholesky solve", (b.len(), 1))?;
        self.solve_rows_in_place(b, 1);
        Ok(())
    }

    /// Solves `A X = B` for an n×3 block of points (one point per row): the x,
    /// y and z columns are solved together, in one sweep over `L` and one over
    /// `Lᵀ`. `b` is overwritten with `X`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation
    /// `"cholesky solve_points"`) when `b.len() != n`; `b` is left untouched.
    pub fn solve_points_in_place(&self, b: &mut [[f64; 3]]) -> Result<(), LinalgError> {
        self.check_rows("cholesky solve_points", (b.len(), 3))?;
        self.solve_rows_in_place(b.as_flattened_mut(), 3);
        Ok(())
    }

    /// Solves `A X = B` for the `n × r` matrix `b` of `r` right-hand sides and
    /// returns `X` (`n × r`).
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation
    /// `"cholesky solve_matrix"`) when `b.nrows() != n`.
    pub fn solve_matrix(&self, b: &DenseMatrix) -> Result<DenseMatrix, LinalgError> {
        self.check_rows("cholesky solve_matrix", (b.nrows(), b.ncols()))?;
        let mut x = b.clone();
        self.solve_rows_in_place(x.as_mut_slice(), b.ncols());
        Ok(x)
    }

    /// `L Lᵀ X = B` for `B` stored row-major with `width` columns.
    fn solve_rows_in_place(&self, b: &mut [f64], width: usize) {
        forward_substitution_rows(&self.l, b, width);
        back_substitution_rows(&self.l_transpose, b, width);
    }

    /// `Ok` when a right-hand side of shape `rhs` has `n` rows.
    fn check_rows(&self, operation: &'static str, rhs: (usize, usize)) -> Result<(), LinalgError> {
        let n = self.dim();
        if rhs.0 == n {
            Ok(())
        } else {
            Err(LinalgError::DimensionMismatch {
                operation,
                left: (n, n),
                right: rhs,
            })
        }
    }
}

/// Row `i` of `L`: entries `l_i0 … l_ii` from rows `0 … i−1` of `L` (already
/// computed) and row `i` of `A`.
fn factor_row(a: &DenseMatrix, l: &mut DenseMatrix, i: usize) -> Result<(), LinalgError> {
    for j in 0..i {
        let l_ij = (a[(i, j)] - dot(&l.row(i)[..j], &l.row(j)[..j])) / l[(j, j)];
        l[(i, j)] = l_ij;
    }
    let row_i = &l.row(i)[..i];
    let pivot = a[(i, i)] - dot(row_i, row_i);
    if !(pivot > 0.0 && pivot.is_finite()) {
        return Err(LinalgError::NotPositiveDefinite { column: i, pivot });
    }
    l[(i, i)] = pivot.sqrt();
    Ok(())
}

/// Row `i` of the lower-triangular `l`, written into column `i` of `lt`
/// (`Lᵀ`'s upper triangle).
fn copy_row_to_column(l: &DenseMatrix, lt: &mut DenseMatrix, i: usize) {
    for (j, &l_ij) in l.row(i)[..=i].iter().enumerate() {
        lt[(j, i)] = l_ij;
    }
}

/// Solves `L y = b` in place (`b` becomes `y`) for a lower-triangular `L`,
/// reading only its lower triangle, diagonal included.
///
/// The diagonal must be nonzero (it is for a Cholesky factor); a zero on it
/// is not detected and produces infinities or NaN.
///
/// # Errors
/// * [`LinalgError::NotSquare`] when `l` is not square.
/// * [`LinalgError::DimensionMismatch`] (operation `"forward_substitution_dense"`)
///   when `b.len() != n`; `b` is left untouched.
pub fn forward_substitution_dense(l: &DenseMatrix, b: &mut [f64]) -> Result<(), LinalgError> {
    check_triangular_system("forward_substitution_dense", l, b.len())?;
    forward_substitution_rows(l, b, 1);
    Ok(())
}

/// Solves `U x = b` in place (`b` becomes `x`) for an upper-triangular `U`,
/// reading only its upper triangle, diagonal included.
///
/// The diagonal must be nonzero (it is for a Cholesky factor); a zero on it
/// is not detected and produces infinities or NaN.
///
/// # Errors
/// * [`LinalgError::NotSquare`] when `u` is not square.
/// * [`LinalgError::DimensionMismatch`] (operation `"back_substitution_dense"`)
///   when `b.len() != n`; `b` is left untouched.
pub fn back_substitution_dense(u: &DenseMatrix, b: &mut [f64]) -> Result<(), LinalgError> {
    check_triangular_system("back_substitution_dense", u, b.len())?;
    back_substitution_rows(u, b, 1);
    Ok(())
}

/// `Ok` when `t` is square and a vector of length `len` fits it.
fn check_triangular_system(
    operation: &'static str,
    t: &DenseMatrix,
    len: usize,
) -> Result<(), LinalgError> {
    if !t.is_square() {
        return Err(LinalgError::NotSquare {
            nrows: t.nrows(),
            ncols: t.ncols(),
        });
    }
    if len != t.nrows() {
        return Err(LinalgError::DimensionMismatch {
            operation,
            left: (t.nrows(), t.ncols()),
            right: (len, 1),
        });
    }
    Ok(())
}

/// Forward substitution on `width` right-hand sides at once: `b` holds an
/// `n × width` block row-major, and row `i` of the solution is
/// `(row i of b − Σ_{k<i} l_ik · row k of the solution) / l_ii`.
/// Shapes are the caller's to check.
fn forward_substitution_rows(l: &DenseMatrix, b: &mut [f64], width: usize) {
    for i in 0..l.nrows() {
        let (solved, rest) = b.split_at_mut(i * width);
        let row_i = &mut rest[..width];
        for (k, &l_ik) in l.row(i)[..i].iter().enumerate() {
            subtract_scaled(row_i, l_ik, &solved[k * width..(k + 1) * width]);
        }
        divide(row_i, l[(i, i)]);
    }
}

/// Back substitution on `width` right-hand sides at once: `b` holds an
/// `n × width` block row-major, and row `i` of the solution, from the last row
/// up, is `(row i of b − Σ_{k>i} u_ik · row k of the solution) / u_ii`.
/// Shapes are the caller's to check.
fn back_substitution_rows(u: &DenseMatrix, b: &mut [f64], width: usize) {
    for i in (0..u.nrows()).rev() {
        let (unsolved, solved) = b.split_at_mut((i + 1) * width);
        let row_i = &mut unsolved[i * width..];
        for (k, &u_ik) in u.row(i)[i + 1..].iter().enumerate() {
            subtract_scaled(row_i, u_ik, &solved[k * width..(k + 1) * width]);
        }
        divide(row_i, u[(i, i)]);
    }
}

/// `y −= s x`.
fn subtract_scaled(y: &mut [f64], s: f64, x: &[f64]) {
    for (y_c, x_c) in y.iter_mut().zip(x) {
        *y_c -= s * x_c;
    }
}

/// `y /= d`.
fn divide(y: &mut [f64], d: f64) {
    for y_c in y {
        *y_c /= d;
    }
}
