//! Entry by entry: a student's matrix brought to the shape and kind of
//! ours, then the largest difference between the two, each entry scaled:
//!
//! ```text
//! relative difference = |ours − yours| / s,    s = max(|ours|, |yours|, reference)
//! ```
//!
//! where `reference` is what the entry is held to beside its own size: the
//! largest `|ours|` in its row (a zero next to large entries is held to
//! their scale), the size of `b`'s terms, or `√(Q'ₖₖ Q'ₗₗ)` for `L Lᵀ`.
//! Each row is of a kind: a free vertex, a pinned vertex (whose largest
//! difference is kept apart, so that the place shown is a free vertex's
//! unless only a pin differs), or skipped (a spring of the student's that
//! is not one of ours).
//!
//! This file uses the library only (no part of the command line), so that
//! the fuzz target `trace_compare` includes it as it is. The reader of a
//! file checks the memory its size line declares; every conversion here
//! (dense to sparse and back) checks its own against the same limit
//! (`masssprings::memory`) before it allocates.

use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::{CscMatrix, TripletMatrix};
use masssprings::matrix_market::{coordinate_bytes, MatrixMarket, SparseFile, Symmetry};
use masssprings::memory;

/// The largest difference of a quantity and where it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Difference {
    /// `|ours − yours| / scale`.
    pub relative: f64,
    pub row: usize,
    pub col: usize,
    pub ours: f64,
    pub yours: f64,
    /// The `s` the difference was divided by, and which of the three it was.
    pub scale: f64,
    pub scale_of: ScaleOf,
}

impl Difference {
    /// Within `tolerance` (a NaN is not).
    pub fn within(&self, tolerance: f64) -> bool {
        self.relative <= tolerance
    }
}

/// Which of `|ours|`, `|yours|` and the reference was the largest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScaleOf {
    Ours,
    Yours,
    Reference,
}

/// What a row stands for, for the place of the largest difference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    Free,
    /// A pinned vertex: its values are of the size of `w` (`Q`, `b`) or
    /// held still (`p`), so its difference is kept apart.
    Pinned,
    /// Not compared (a spring of the student's that is not one of ours).
    Skipped,
}

/// The kind of row `i` in `kinds` (rows past its end are free).
pub fn kind_of(kinds: &[RowKind], i: usize) -> RowKind {
    kinds.get(i).copied().unwrap_or(RowKind::Free)
}

/// The largest scaled differences seen so far, at free rows and at pins.
#[derive(Debug, Default, Clone, Copy)]
pub struct Largest {
    pub free: Option<Difference>,
    pub pinned: Option<Difference>,
}

impl Largest {
    /// Takes entry `(row, col)` into account, scaled by the largest of
    /// `|ours|`, `|yours|` and `reference`.
    pub fn consider(
        &mut self,
        kind: RowKind,
        at: (usize, usize),
        ours: f64,
        yours: f64,
        reference: f64,
    ) {
        let (scale, scale_of) = if ours.abs() >= yours.abs().max(reference) {
            (ours.abs(), ScaleOf::Ours)
        } else if yours.abs() >= reference {
            (yours.abs(), ScaleOf::Yours)
        } else {
            (reference, ScaleOf::Reference)
        };
        let difference = (ours - yours).abs();
        let relative = if difference == 0.0 {
            0.0
        } else {
            difference / scale
        };
        let slot = match kind {
            RowKind::Free => &mut self.free,
            RowKind::Pinned => &mut self.pinned,
            RowKind::Skipped => return,
        };
        if slot.is_none_or(|d| relative > d.relative || relative.is_nan()) {
            *slot = Some(Difference {
                relative,
                row: at.0,
                col: at.1,
                ours,
                yours,
                scale,
                scale_of,
            });
        }
    }

    /// The largest difference anywhere, which decides whether the quantity
    /// agrees (a NaN counts as larger than anything).
    pub fn overall(&self) -> Option<Difference> {
        match (self.free, self.pinned) {
            (Some(f), Some(p)) if p.relative > f.relative || p.relative.is_nan() => Some(p),
            (Some(f), _) => Some(f),
            (None, p) => p,
        }
    }

    /// The place to show: the free rows' largest, unless only a pin is
    /// outside `tolerance` (or there are only pins).
    pub fn shown(&self, tolerance: f64) -> Option<Difference> {
        let outside = |d: Difference| !d.within(tolerance);
        match (self.free, self.pinned) {
            (Some(f), Some(p)) if outside(p) && !outside(f) => Some(p),
            (Some(f), _) => Some(f),
            (None, p) => p,
        }
    }
}

/// Rows and columns of a file's matrix.
pub fn shape(a: &MatrixMarket) -> (usize, usize) {
    match a {
        MatrixMarket::Sparse(file) => (file.matrix.nrows(), file.matrix.ncols()),
        MatrixMarket::Dense(a) => (a.nrows(), a.ncols()),
    }
}

/// A file's matrix as a dense one, once its `rows × cols × 8` bytes are
/// known to fit.
///
/// # Errors
/// The memory rule's refusal.
pub fn to_dense(a: &MatrixMarket) -> Result<DenseMatrix, String> {
    match a {
        MatrixMarket::Dense(a) => Ok(a.clone()),
        MatrixMarket::Sparse(file) => {
            let (rows, cols) = (file.matrix.nrows(), file.matrix.ncols());
            let cells = (rows as u64).saturating_mul(cols as u64);
            memory::check(
                memory::bytes_for(cells, 8),
                || format!("a {rows} × {cols} matrix made dense"),
                "",
            )
            .map_err(|e| e.to_string())?;
            Ok(file.matrix.to_dense())
        }
    }
}

/// A file's matrix as a sparse one (a dense file's zeros dropped), once
/// it is known to fit: its nonzeros and, for the counting sorts that build
/// it, its rows and columns, as the reader counts a coordinate file's. (An
/// array of 5555555555555 × 0 holds no value, and its rows alone would
/// cost 178 TB.)
///
/// # Errors
/// The memory rule's refusal.
pub fn to_sparse(a: &MatrixMarket) -> Result<CscMatrix, String> {
    let a = match a {
        MatrixMarket::Sparse(file) => return Ok(file.matrix.clone()),
        MatrixMarket::Dense(a) => a,
    };
    let entries = a.as_slice().iter().filter(|v| **v != 0.0).count();
    memory::check(
        coordinate_bytes(a.nrows(), a.ncols(), entries),
        || {
            format!(
                "a {} × {} array with {entries} nonzeros made sparse",
                a.nrows(),
                a.ncols()
            )
        },
        "",
    )
    .map_err(|e| e.to_string())?;
    let mut triplets = TripletMatrix::with_capacity(a.nrows(), a.ncols(), entries);
    for i in 0..a.nrows() {
        for (j, &v) in a.row(i).iter().enumerate().filter(|(_, v)| **v != 0.0) {
            triplets.push(i, j, v).expect("inside the matrix");
        }
    }
    Ok(triplets.to_csc())
}

/// A sparse matrix as a file's content.
pub fn sparse_file(matrix: CscMatrix) -> MatrixMarket {
    MatrixMarket::Sparse(SparseFile {
        matrix,
        symmetry: Symmetry::General,
    })
}

/// The student's matrix as a `rows × cols` one, dense when `dense`: a
/// vector transposed, and when `diagonal` (`M`), a vector of `rows` values
/// read as a diagonal matrix.
///
/// # Errors
/// A shape that is not ours (`shape 3 × 1, ours 4 × 1`), or the memory
/// rule's refusal.
pub fn conform(
    their: MatrixMarket,
    (rows, cols): (usize, usize),
    dense: bool,
    diagonal: bool,
) -> Result<MatrixMarket, String> {
    let (their_rows, their_cols) = shape(&their);
    let vector = their_rows.min(their_cols) == 1;
    let their = if vector && (their_rows, their_cols) == (cols, rows) && (rows, cols) != (1, 1) {
        let values = to_dense(&their)?.as_slice().to_vec(); // a vector's values, in order
        MatrixMarket::Dense(DenseMatrix::from_row_major(rows, cols, values).expect("a vector"))
    } else if diagonal && vector && their_rows.max(their_cols) == rows && rows == cols {
        sparse_file(CscMatrix::from_diagonal(to_dense(&their)?.as_slice()))
    } else {
        their
    };
    let (their_rows, their_cols) = shape(&their);
    if (their_rows, their_cols) != (rows, cols) {
        return Err(format!(
            "shape {their_rows} × {their_cols}, ours {rows} × {cols}"
        ));
    }
    Ok(match dense {
        true => MatrixMarket::Dense(to_dense(&their)?),
        false => their,
    })
}

/// The largest scaled differences of two dense matrices of one shape,
/// each entry held to its row's largest `|ours|`, or to `reference`'s
/// entry when given.
pub fn dense_difference(
    ours: &DenseMatrix,
    yours: &DenseMatrix,
    reference: Option<&DenseMatrix>,
    kinds: &[RowKind],
) -> Largest {
    let mut largest = Largest::default();
    for i in 0..ours.nrows() {
        let row_scale = ours.row(i).iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        for (j, (&a, &b)) in ours.row(i).iter().zip(yours.row(i)).enumerate() {
            let scale = reference.map_or(row_scale, |s| s[(i, j)]);
            largest.consider(kind_of(kinds, i), (i, j), a, b, scale);
        }
    }
    largest
}

/// The largest scaled differences of two sparse matrices of one shape,
/// over the union of their patterns, each entry held to its row's largest
/// `|ours|`.
pub fn sparse_difference(ours: &CscMatrix, yours: &CscMatrix, kinds: &[RowKind]) -> Largest {
    let mut scale = vec![0.0_f64; ours.nrows()];
    for (&i, &v) in ours.row_idx().iter().zip(ours.values()) {
        scale[i] = scale[i].max(v.abs());
    }
    let mut largest = Largest::default();
    union_entries(ours, yours, |i, j, a, b| {
        largest.consider(kind_of(kinds, i), (i, j), a, b, scale[i])
    });
    largest
}

/// Calls `f(i, j, ours, yours)` for every position stored in either of
/// two matrices of one shape (a missing entry is 0), column by column.
pub fn union_entries(
    ours: &CscMatrix,
    yours: &CscMatrix,
    mut f: impl FnMut(usize, usize, f64, f64),
) {
    let mut values = vec![[0.0; 2]; ours.nrows()];
    let mut seen = vec![false; ours.nrows()];
    let mut touched = Vec::new();
    for j in 0..ours.ncols() {
        for (side, matrix) in [ours, yours].into_iter().enumerate() {
            let (rows, column) = matrix.column(j);
            for (&i, &v) in rows.iter().zip(column) {
                values[i][side] += v;
                if !std::mem::replace(&mut seen[i], true) {
                    touched.push(i);
                }
            }
        }
        for i in touched.drain(..) {
            f(i, j, values[i][0], values[i][1]);
            values[i] = [0.0; 2];
            seen[i] = false;
        }
    }
}
