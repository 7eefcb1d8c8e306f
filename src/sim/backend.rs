//! The two kinds of matrices the simulation can run on.
//!
//! The assignment asks for every function twice, dense and sparse. The
//! algorithm is the same; only the matrix type and its factorization differ.
//! So the algorithm is written once, generic over a [`LinearAlgebra`]
//! backend, and the two backends say how to build a matrix from `(i, j, v)`
//! entries, multiply, add, factor and solve:
//!
//! * [`Dense`]: [`DenseMatrix`] and [`DenseCholesky`]. Entries are added into
//!   an n×n array (`A(i, j) += v`), `O(n³)` to factor, `O(n²)` per solve.
//! * [`Sparse`]: [`CscMatrix`] built from a triplet list and
//!   [`SparseCholesky`], with the ordering and the numeric method of a
//!   [`SparseFactorization`]: by default AMD and the supernodal method (the
//!   fast path). `Method::Simplicial` is the textbook factorization, row by
//!   row, with the substitutions of `triangular_solve.rs`: the one
//!   [`textbook`](super::textbook) runs, after AMD as Eigen's
//!   `SimplicialLLT` does (`Ordering::Natural` for none), and the one
//!   `--factorization simplicial` gives the fast path (`--ordering natural`
//!   for no ordering).

use crate::linalg::dense::{DenseCholesky, DenseMatrix};
use crate::linalg::sparse::{
    CscMatrix, Method, Ordering, SparseCholesky, SupernodeMerging, SymbolicCholesky, TripletMatrix,
};
use crate::linalg::{Cancel, LinalgError};

/// How the sparse backend factors `Q`: the fill-reducing ordering, the
/// numeric method, for the supernodal one which supernodes, and on how
/// many threads (the dense backend has one way and ignores it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SparseFactorization {
    /// AMD (default) or the natural order.
    pub ordering: Ordering,
    /// Supernodal (default) or simplicial (row by row).
    pub method: Method,
    /// The supernodal method's supernodes: by default those of at most
    /// three columns merged (`Relaxation::SMALL`).
    pub supernodes: SupernodeMerging,
    /// Threads of the supernodal factorization and solves, kept with the
    /// factor (default 1; the same bits on any number,
    /// [`SparseCholesky::factor_with_threads`]).
    pub threads: usize,
}

impl Default for SparseFactorization {
    fn default() -> Self {
        SparseFactorization {
            ordering: Ordering::default(),
            method: Method::default(),
            supernodes: SupernodeMerging::default(),
            threads: 1,
        }
    }
}

/// Matrix operations the mass-spring solver needs.
pub trait LinearAlgebra {
    /// The matrix type.
    type Matrix: Clone + std::fmt::Debug;
    /// A factorization of a symmetric positive definite matrix.
    type Factorization: Clone + std::fmt::Debug;
    /// `"dense"` or `"sparse"`.
    const NAME: &'static str;

    /// The `nrows × ncols` matrix with `A(i, j) += v` for every entry
    /// (repeated positions add up).
    ///
    /// # Panics
    /// When an entry is outside the matrix (the callers build entries from
    /// a validated scene).
    fn from_entries(
        nrows: usize,
        ncols: usize,
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
    ) -> Self::Matrix;

    /// `AᵀA`.
    fn gram(a: &Self::Matrix) -> Self::Matrix;

    /// [`LinearAlgebra::gram`], given up once `cancel` is set. The dense
    /// product takes `n² m` multiply-adds (minutes on the skirt) and looks
    /// at `cancel` between its rows; the sparse one takes moments and runs
    /// to its end.
    ///
    /// # Errors
    /// [`LinalgError::Cancelled`].
    fn gram_cancellable(a: &Self::Matrix, cancel: Cancel<'_>) -> Result<Self::Matrix, LinalgError> {
        let _ = cancel;
        Ok(Self::gram(a))
    }

    /// `α X + β Y` (same shapes).
    fn combine(alpha: f64, x: &Self::Matrix, beta: f64, y: &Self::Matrix) -> Self::Matrix;

    /// `X / s`, every entry divided by `s` (as `M/Δt²` is written).
    fn divide(x: &Self::Matrix, s: f64) -> Self::Matrix;

    /// `y = A x` for n×3 blocks.
    fn mul_points(a: &Self::Matrix, x: &[[f64; 3]], y: &mut [[f64; 3]]);

    /// `y = Aᵀ x` for n×3 blocks.
    fn transpose_mul_points(a: &Self::Matrix, x: &[[f64; 3]], y: &mut [[f64; 3]]);

    /// Factors the symmetric positive definite `q` (the sparse backend in
    /// the way `how` says).
    ///
    /// # Errors
    /// [`LinalgError::NotPositiveDefinite`] naming the column.
    fn factor(
        q: &Self::Matrix,
        how: SparseFactorization,
    ) -> Result<Self::Factorization, LinalgError>;

    /// [`LinearAlgebra::factor`], given up once `cancel` is set: the dense
    /// factorization (`n³/3`) looks at it between two rows; the sparse one
    /// runs to its end.
    ///
    /// # Errors
    /// As [`LinearAlgebra::factor`], and [`LinalgError::Cancelled`].
    fn factor_cancellable(
        q: &Self::Matrix,
        how: SparseFactorization,
        cancel: Cancel<'_>,
    ) -> Result<Self::Factorization, LinalgError> {
        let _ = cancel;
        Self::factor(q, how)
    }

    /// Factors `q` again, for new values with the same pattern.
    ///
    /// # Errors
    /// As [`LinearAlgebra::factor`].
    fn refactor(
        factorization: &mut Self::Factorization,
        q: &Self::Matrix,
    ) -> Result<(), LinalgError>;

    /// `b ← Q⁻¹ b` for an n×3 block.
    fn solve_points(factorization: &mut Self::Factorization, b: &mut [[f64; 3]]);

    /// `x ← Q⁻¹ b` for the n×3 block `b` whose row `i` is `b_row(i)`. By
    /// default `b` is written into `x` and solved in place; the sparse
    /// backend makes each row where its solve reads it.
    fn solve_points_from(
        factorization: &mut Self::Factorization,
        b_row: impl Fn(usize) -> [f64; 3] + Sync,
        x: &mut [[f64; 3]],
    ) {
        for (i, row) in x.iter_mut().enumerate() {
            *row = b_row(i);
        }
        Self::solve_points(factorization, x);
    }

    /// The sparse Cholesky factorization itself, for the plain iteration
    /// that keeps its unknowns in the factor's order
    /// ([`SparseCholesky::buffer_in_factor_order`]); `None` for the dense
    /// backend, whose factor has no ordering.
    fn as_sparse_cholesky(_factorization: &mut Self::Factorization) -> Option<&mut SparseCholesky> {
        None
    }

    /// The threads a factorization factors and solves with (1 for the
    /// dense one).
    fn threads(_factorization: &Self::Factorization) -> usize {
        1
    }

    /// Bytes a matrix holds (its arrays' lengths), for the memory figures.
    fn matrix_bytes(a: &Self::Matrix) -> usize;

    /// Bytes a factorization holds (its arrays' lengths, work arrays
    /// included).
    fn factorization_bytes(factorization: &Self::Factorization) -> usize;
}

/// Dense matrices and the dense Cholesky factorization.
#[derive(Debug, Clone, Copy)]
pub struct Dense;

/// Sparse (CSC) matrices and the sparse Cholesky factorization.
#[derive(Debug, Clone, Copy)]
pub struct Sparse;

const SHAPES_FIT: &str = "the simulation sizes its own buffers";

impl LinearAlgebra for Dense {
    type Matrix = DenseMatrix;
    type Factorization = DenseCholesky;
    const NAME: &'static str = "dense";

    fn from_entries(
        nrows: usize,
        ncols: usize,
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
    ) -> DenseMatrix {
        let mut matrix = DenseMatrix::zeros(nrows, ncols);
        for (i, j, v) in entries {
            matrix[(i, j)] += v;
        }
        matrix
    }

    fn gram(a: &DenseMatrix) -> DenseMatrix {
        a.transpose_mul_self(Cancel::NEVER)
            .expect("nothing cancels it")
    }

    fn gram_cancellable(a: &DenseMatrix, cancel: Cancel<'_>) -> Result<DenseMatrix, LinalgError> {
        a.transpose_mul_self(cancel)
    }

    fn combine(alpha: f64, x: &DenseMatrix, beta: f64, y: &DenseMatrix) -> DenseMatrix {
        x.scale(alpha).scaled_add(beta, y).expect(SHAPES_FIT)
    }

    fn divide(x: &DenseMatrix, s: f64) -> DenseMatrix {
        let mut quotient = x.clone();
        for entry in quotient.as_mut_slice() {
            *entry /= s;
        }
        quotient
    }

    fn mul_points(a: &DenseMatrix, x: &[[f64; 3]], y: &mut [[f64; 3]]) {
        a.mul_points(x, y).expect(SHAPES_FIT)
    }

    fn transpose_mul_points(a: &DenseMatrix, x: &[[f64; 3]], y: &mut [[f64; 3]]) {
        a.transpose_mul_points(x, y).expect(SHAPES_FIT)
    }

    fn factor(q: &DenseMatrix, _: SparseFactorization) -> Result<DenseCholesky, LinalgError> {
        DenseCholesky::factor(q)
    }

    fn factor_cancellable(
        q: &DenseMatrix,
        _: SparseFactorization,
        cancel: Cancel<'_>,
    ) -> Result<DenseCholesky, LinalgError> {
        DenseCholesky::factor_cancellable(q, cancel)
    }

    fn refactor(factorization: &mut DenseCholesky, q: &DenseMatrix) -> Result<(), LinalgError> {
        *factorization = DenseCholesky::factor(q)?;
        Ok(())
    }

    fn solve_points(factorization: &mut DenseCholesky, b: &mut [[f64; 3]]) {
        factorization.solve_points_in_place(b).expect(SHAPES_FIT)
    }

    fn matrix_bytes(a: &DenseMatrix) -> usize {
        a.nrows() * a.ncols() * std::mem::size_of::<f64>()
    }

    fn factorization_bytes(factorization: &DenseCholesky) -> usize {
        let n = factorization.dim();
        2 * n * n * std::mem::size_of::<f64>() // L and Lᵀ
    }
}

impl LinearAlgebra for Sparse {
    type Matrix = CscMatrix;
    type Factorization = SparseCholesky;
    const NAME: &'static str = "sparse";

    fn from_entries(
        nrows: usize,
        ncols: usize,
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
    ) -> CscMatrix {
        TripletMatrix::from_entries(nrows, ncols, entries)
            .expect("entries come from a validated scene")
            .to_csc()
    }

    fn gram(a: &CscMatrix) -> CscMatrix {
        a.transpose_mul_self()
    }

    fn combine(alpha: f64, x: &CscMatrix, beta: f64, y: &CscMatrix) -> CscMatrix {
        x.add_scaled(alpha, y, beta).expect(SHAPES_FIT)
    }

    fn divide(x: &CscMatrix, s: f64) -> CscMatrix {
        let mut quotient = x.clone();
        for entry in quotient.values_mut() {
            *entry /= s;
        }
        quotient
    }

    fn mul_points(a: &CscMatrix, x: &[[f64; 3]], y: &mut [[f64; 3]]) {
        a.mul_points(x, y).expect(SHAPES_FIT)
    }

    fn transpose_mul_points(a: &CscMatrix, x: &[[f64; 3]], y: &mut [[f64; 3]]) {
        a.transpose_mul_points(x, y).expect(SHAPES_FIT)
    }

    fn factor(q: &CscMatrix, how: SparseFactorization) -> Result<SparseCholesky, LinalgError> {
        let symbolic = SymbolicCholesky::analyze(q, how.ordering)?;
        let symbolic = match how.method {
            Method::Supernodal => symbolic.relaxed(&how.supernodes.relaxation()),
            Method::Simplicial => symbolic,
        };
        SparseCholesky::factor_with_threads(symbolic, q, how.method, how.threads)
    }

    fn refactor(factorization: &mut SparseCholesky, q: &CscMatrix) -> Result<(), LinalgError> {
        factorization.refactor(q)
    }

    fn solve_points(factorization: &mut SparseCholesky, b: &mut [[f64; 3]]) {
        factorization.solve_points_in_place(b)
    }

    fn solve_points_from(
        factorization: &mut SparseCholesky,
        b_row: impl Fn(usize) -> [f64; 3] + Sync,
        x: &mut [[f64; 3]],
    ) {
        factorization.solve_points_from(b_row, x)
    }

    fn as_sparse_cholesky(factorization: &mut SparseCholesky) -> Option<&mut SparseCholesky> {
        Some(factorization)
    }

    fn threads(factorization: &SparseCholesky) -> usize {
        factorization.threads()
    }

    fn matrix_bytes(a: &CscMatrix) -> usize {
        std::mem::size_of_val(a.col_ptr())
            + std::mem::size_of_val(a.row_idx())
            + std::mem::size_of_val(a.values())
    }

    fn factorization_bytes(factorization: &SparseCholesky) -> usize {
        factorization.bytes()
    }
}
