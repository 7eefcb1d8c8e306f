//! A dense, row-major matrix of `f64`.
//!
//! Entry `(i, j)` of an `nrows × ncols` matrix lives at `data[i * ncols + j]`.
//! Row-major matches how the simulation stores positions: an n×3 block is n
//! points, one per row, so each point's x, y, z are adjacent in memory.

/// A dense `nrows × ncols` matrix stored row by row.
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

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// The entries, row by row.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// The entries, row by row, for writing.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.data
    }
}

impl std::ops::Index<(usize, usize)> for DenseMatrix {
    type Output = f64;
    /// # Panics
    /// When `(i, j)` is outside the matrix.
    fn index(&self, (i, j): (usize, usize)) -> &f64 {
        assert!(i < self.nrows && j < self.ncols, "index ({i}, {j}) out of range");
        &self.data[i * self.ncols + j]
    }
}

impl std::ops::IndexMut<(usize, usize)> for DenseMatrix {
    /// # Panics
    /// When `(i, j)` is outside the matrix.
    fn index_mut(&mut self, (i, j): (usize, usize)) -> &mut f64 {
        assert!(i < self.nrows && j < self.ncols, "index ({i}, {j}) out of range");
        &mut self.data[i * self.ncols + j]
    }
}
