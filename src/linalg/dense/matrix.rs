//! A dense, row-major matrix of `f64`, and the few operations the mass-spring
//! solver is built from.
//!
//! Entry `(i, j)` of an `nrows × ncols` matrix lives at `data[i * ncols + j]`.
//! Row-major matches how the simulation stores positions: an n×3 block is n
//! points, one per row, so each point's x, y, z are adjacent in memory.
//!
//! The system matrix of Liu et al. (2013) is assembled from these pieces,
//!
//! ```text
//! Q = k AᵀA + M/Δt² + w CᵀC
//! ```
//!
//! with [`mul`](DenseMatrix::mul), [`transpose`](DenseMatrix::transpose),
//! [`transpose_mul_self`](DenseMatrix::transpose_mul_self) (`AᵀA`),
//! [`scale`](DenseMatrix::scale) and [`scaled_add`](DenseMatrix::scaled_add),
//! and each time step multiplies matrices with the n×3 block of positions:
//! [`mul_points`](DenseMatrix::mul_points) computes `A p`, and
//! [`transpose_mul_points`](DenseMatrix::transpose_mul_points) computes `Aᵀ d`
//! without ever forming `Aᵀ`.
//!
//! Cost, for an `m × n` matrix: a product with a vector or a block of points
//! costs `2mn` (respectively `6mn`) flops, a product with an `n × r` matrix
//! `2mnr`, a sum or a scaling `mn`. All loops are the textbook ones (Golub &
//! Van Loan, *Matrix Computations*, 4th ed., §1.1), written for clarity, not
//! speed.
//!
//! # Conventions
//!
//! * Shapes that do not fit are an error of the data, not of the program: every
//!   operation taking two operands checks their shapes and returns
//!   [`LinalgError::DimensionMismatch`] (see each `# Errors` section). The
//!   check costs a few comparisons per call, nothing next to the product.
//! * An index out of range is a programmer error and panics (see `# Panics`).
//! * The products with vectors and points write into a buffer the caller
//!   provides and allocate nothing, so they can run in a time-step loop.

use crate::linalg::cancel::Cancel;
use crate::linalg::error::LinalgError;

/// Rows of `A` that [`DenseMatrix::transpose_mul_self`] works through
/// between two looks at its [`Cancel`].
pub const ROWS_BETWEEN_LOOKS: usize = 256;

/// A dense `nrows × ncols` matrix stored row by row.
///
/// # Examples
///
/// ```
/// use masssprings::linalg::dense::DenseMatrix;
///
/// let a = DenseMatrix::from_rows(&[[1.0, -1.0]])?; // one spring, A = [1 −1]
/// let ata = a.transpose().mul(&a)?;
/// assert_eq!(ata, DenseMatrix::from_rows(&[[1.0, -1.0], [-1.0, 1.0]])?);
/// assert_eq!(ata[(0, 1)], -1.0);
///
/// let q = ata.add(&DenseMatrix::identity(2))?; // AᵀA + M with unit masses
/// let mut y = [[0.0; 3]; 2];
/// q.mul_points(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &mut y)?;
/// assert_eq!(y, [[2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]]);
/// # Ok::<(), masssprings::linalg::LinalgError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct DenseMatrix {
    nrows: usize,
    ncols: usize,
    data: Vec<f64>,
}

impl DenseMatrix {
    /// The `nrows × ncols` matrix of zeros.
    pub fn zeros(nrows: usize, ncols: usize) -> Self {
        DenseMatrix {
            nrows,
            ncols,
            data: vec![0.0; nrows * ncols],
        }
    }

    /// The `n × n` identity matrix.
    pub fn identity(n: usize) -> Self {
        Self::from_diagonal(&vec![1.0; n])
    }

    /// The square matrix with `diagonal` on its diagonal and zeros elsewhere.
    pub fn from_diagonal(diagonal: &[f64]) -> Self {
        let n = diagonal.len();
        let mut matrix = Self::zeros(n, n);
        for (i, &value) in diagonal.iter().enumerate() {
            matrix[(i, i)] = value;
        }
        matrix
    }

    /// The matrix whose rows are `rows` (any slice of rows: `&[Vec<f64>]`,
    /// `&[[f64; 3]]`, `&[&[f64]]`, …). No rows gives the 0×0 matrix.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation `"from_rows"`) when the
    /// rows do not all have the length of the first one; `left` is the first
    /// row's shape `1 × ncols`, `right` the shape of the first row that differs.
    pub fn from_rows<R: AsRef<[f64]>>(rows: &[R]) -> Result<Self, LinalgError> {
        let ncols = rows.first().map_or(0, |row| row.as_ref().len());
        let mut data = Vec::with_capacity(rows.len() * ncols);
        for row in rows {
            let row = row.as_ref();
            if row.len() != ncols {
                return Err(LinalgError::DimensionMismatch {
                    operation: "from_rows",
                    left: (1, ncols),
                    right: (1, row.len()),
                });
            }
            data.extend_from_slice(row);
        }
        Ok(DenseMatrix {
            nrows: rows.len(),
            ncols,
            data,
        })
    }

    /// The `nrows × ncols` matrix whose entries, row by row, are `data`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation `"from_row_major"`) when
    /// `data.len() != nrows * ncols`; `left` is `(nrows, ncols)`, `right` is
    /// `(data.len(), 1)`.
    pub fn from_row_major(nrows: usize, ncols: usize, data: Vec<f64>) -> Result<Self, LinalgError> {
        if data.len() != nrows * ncols {
            return Err(LinalgError::DimensionMismatch {
                operation: "from_row_major",
                left: (nrows, ncols),
                right: (data.len(), 1),
            });
        }
        Ok(DenseMatrix { nrows, ncols, data })
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Is the matrix square?
    pub fn is_square(&self) -> bool {
        self.nrows == self.ncols
    }

    /// The entries, row by row.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// The entries, row by row, for writing.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.data
    }

    /// Row `i`: the entries `(i, 0), …, (i, ncols − 1)`.
    ///
    /// # Panics
    /// When `i >= nrows`.
    pub fn row(&self, i: usize) -> &[f64] {
        assert!(i < self.nrows, "row {i} out of range ({} rows)", self.nrows);
        &self.data[i * self.ncols..(i + 1) * self.ncols]
    }

    /// Row `i`, for writing.
    ///
    /// # Panics
    /// When `i >= nrows`.
    pub fn row_mut(&mut self, i: usize) -> &mut [f64] {
        assert!(i < self.nrows, "row {i} out of range ({} rows)", self.nrows);
        &mut self.data[i * self.ncols..(i + 1) * self.ncols]
    }

    /// The diagonal `(A₀₀, A₁₁, …)`, of length `min(nrows, ncols)`.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.nrows.min(self.ncols))
            .map(|i| self[(i, i)])
            .collect()
    }

    /// The transpose `Aᵀ`: entry `(j, i)` of the result is entry `(i, j)` of
    /// `self`.
    pub fn transpose(&self) -> DenseMatrix {
        let mut transposed = DenseMatrix::zeros(self.ncols, self.nrows);
        for i in 0..self.nrows {
            for (j, &value) in self.row(i).iter().enumerate() {
                transposed[(j, i)] = value;
            }
        }
        transposed
    }

    /// The product `C = A B` of `self` (`m × n`) and `other` (`n × r`).
    ///
    /// Row by row: row `i` of `C` is `Σ_k a_ik · (row k of B)`, which walks
    /// both row-major matrices in memory order.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation `"mul"`) when
    /// `self.ncols() != other.nrows()`.
    pub fn mul(&self, other: &DenseMatrix) -> Result<DenseMatrix, LinalgError> {
        self.check_shape("mul", self.ncols == other.nrows, other.shape())?;
        let mut product = DenseMatrix::zeros(self.nrows, other.ncols);
        for i in 0..self.nrows {
            let product_row = product.row_mut(i);
            for (k, &a_ik) in self.row(i).iter().enumerate() {
                for (c, &b) in product_row.iter_mut().zip(other.row(k)) {
                    *c += a_ik * b;
                }
            }
        }
        Ok(product)
    }

    /// The Gram matrix `AᵀA` (`ncols × ncols`) of `self` (`m × n`), without
    /// forming `Aᵀ`: row `i` of the product is `Σ_k a_ki · (row k of A)`,
    /// the sum [`mul`](DenseMatrix::mul) forms for `Aᵀ · A`, in the same
    /// order (so the same bits). `n² m` multiply-adds, each row of the
    /// product reading all of `A`; `cancel` is looked at every
    /// [`ROWS_BETWEEN_LOOKS`] rows of `A` (a row of the product reads the
    /// skirt's 3 GB `A` once: too long to wait for).
    ///
    /// # Errors
    /// [`LinalgError::Cancelled`] once `cancel` is set (the partial product
    /// is dropped).
    pub fn transpose_mul_self(&self, cancel: Cancel<'_>) -> Result<DenseMatrix, LinalgError> {
        let mut product = DenseMatrix::zeros(self.ncols, self.ncols);
        for i in 0..self.ncols {
            let product_row = product.row_mut(i);
            for k in 0..self.nrows {
                if k % ROWS_BETWEEN_LOOKS == 0 {
                    cancel.check()?;
                }
                let a_ki = self[(k, i)];
                for (c, &a) in product_row.iter_mut().zip(self.row(k)) {
                    *c += a_ki * a;
                }
            }
        }
        Ok(product)
    }

    /// `y = A x` for a vector `x` of length `ncols`; `y` (length `nrows`) is
    /// overwritten.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] with operation `"mul_vec"` when
    /// `x.len() != ncols`, and `"mul_vec (output y)"` when `y.len() != nrows`;
    /// `y` is left untouched.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) -> Result<(), LinalgError> {
        self.check_shape("mul_vec", x.len() == self.ncols, (x.len(), 1))?;
        self.check_shape("mul_vec (output y)", y.len() == self.nrows, (y.len(), 1))?;
        for (i, y_i) in y.iter_mut().enumerate() {
            *y_i = dot(self.row(i), x);
        }
        Ok(())
    }

    /// `y = A x` for an `ncols × 3` block of points `x` (one point per row);
    /// `y` (`nrows` points) is overwritten. The x, y and z columns are
    /// multiplied in one sweep over `A`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] with operation `"mul_points"` when
    /// `x.len() != ncols`, and `"mul_points (output y)"` when
    /// `y.len() != nrows`; `y` is left untouched.
    pub fn mul_points(&self, x: &[[f64; 3]], y: &mut [[f64; 3]]) -> Result<(), LinalgError> {
        self.check_shape("mul_points", x.len() == self.ncols, (x.len(), 3))?;
        self.check_shape("mul_points (output y)", y.len() == self.nrows, (y.len(), 3))?;
        for (i, y_i) in y.iter_mut().enumerate() {
            *y_i = [0.0; 3];
            for (&a_ij, x_j) in self.row(i).iter().zip(x) {
                add_scaled_point(y_i, a_ij, x_j);
            }
        }
        Ok(())
    }

    /// `y = Aᵀ x` for an `nrows × 3` block of points `x`, without forming
    /// `Aᵀ`; `y` (`ncols` points) is overwritten.
    ///
    /// `y_j = Σ_i a_ij x_i`: each row `i` of `A` scatters `a_ij x_i` into every
    /// `y_j`, so `A` is still read row by row.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] with operation
    /// `"transpose_mul_points"` when `x.len() != nrows`, and
    /// `"transpose_mul_points (output y)"` when `y.len() != ncols`; `y` is left
    /// untouched.
    pub fn transpose_mul_points(
        &self,
        x: &[[f64; 3]],
        y: &mut [[f64; 3]],
    ) -> Result<(), LinalgError> {
        let operation = "transpose_mul_points";
        self.check_shape(operation, x.len() == self.nrows, (x.len(), 3))?;
        let output = "transpose_mul_points (output y)";
        self.check_shape(output, y.len() == self.ncols, (y.len(), 3))?;
        y.fill([0.0; 3]);
        for (i, x_i) in x.iter().enumerate() {
            for (&a_ij, y_j) in self.row(i).iter().zip(y.iter_mut()) {
                add_scaled_point(y_j, a_ij, x_i);
            }
        }
        Ok(())
    }

    /// The sum `A + B`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation `"add"`) when the shapes
    /// differ.
    pub fn add(&self, other: &DenseMatrix) -> Result<DenseMatrix, LinalgError> {
        self.check_shape("add", self.shape() == other.shape(), other.shape())?;
        Ok(self.zip_with(other, |a, b| a + b))
    }

    /// `A + s B`: the sum with a scaled matrix, as in
    /// `Q = k AᵀA + M/Δt² + w CᵀC`.
    ///
    /// # Errors
    /// [`LinalgError::DimensionMismatch`] (operation `"scaled_add"`) when the
    /// shapes differ.
    pub fn scaled_add(&self, s: f64, other: &DenseMatrix) -> Result<DenseMatrix, LinalgError> {
        let same_shape = self.shape() == other.shape();
        self.check_shape("scaled_add", same_shape, other.shape())?;
        Ok(self.zip_with(other, |a, b| a + s * b))
    }

    /// `s A`: every entry multiplied by `s`.
    pub fn scale(&self, s: f64) -> DenseMatrix {
        DenseMatrix {
            nrows: self.nrows,
            ncols: self.ncols,
            data: self.data.iter().map(|a| s * a).collect(),
        }
    }

    /// `(nrows, ncols)`.
    fn shape(&self) -> (usize, usize) {
        (self.nrows, self.ncols)
    }

    /// `Ok` when `fits`, else the `DimensionMismatch` of `operation` between
    /// `self` and an operand of shape `other`.
    fn check_shape(
        &self,
        operation: &'static str,
        fits: bool,
        other: (usize, usize),
    ) -> Result<(), LinalgError> {
        if fits {
            Ok(())
        } else {
            Err(LinalgError::DimensionMismatch {
                operation,
                left: self.shape(),
                right: other,
            })
        }
    }

    /// The matrix of `f(a_ij, b_ij)`, for two matrices of the same shape.
    fn zip_with(&self, other: &DenseMatrix, f: impl Fn(f64, f64) -> f64) -> DenseMatrix {
        assert_eq!(self.shape(), other.shape());
        DenseMatrix {
            nrows: self.nrows,
            ncols: self.ncols,
            data: self
                .data
                .iter()
                .zip(&other.data)
                .map(|(&a, &b)| f(a, b))
                .collect(),
        }
    }
}

/// `Σ_k a_k b_k` over two slices of the same length.
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `y += s x` for one point.
fn add_scaled_point(y: &mut [f64; 3], s: f64, x: &[f64; 3]) {
    for (y_c, x_c) in y.iter_mut().zip(x) {
        *y_c += s * x_c;
    }
}

impl std::ops::Index<(usize, usize)> for DenseMatrix {
    type Output = f64;
    /// # Panics
    /// When `(i, j)` is outside the matrix.
    fn index(&self, (i, j): (usize, usize)) -> &f64 {
        assert!(
            i < self.nrows && j < self.ncols,
            "index ({i}, {j}) out of range"
        );
        &self.data[i * self.ncols + j]
    }
}

impl std::ops::IndexMut<(usize, usize)> for DenseMatrix {
    /// # Panics
    /// When `(i, j)` is outside the matrix.
    fn index_mut(&mut self, (i, j): (usize, usize)) -> &mut f64 {
        assert!(
            i < self.nrows && j < self.ncols,
            "index ({i}, {j}) out of range"
        );
        &mut self.data[i * self.ncols + j]
    }
}
