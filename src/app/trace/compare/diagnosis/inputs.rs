//! What the diagnosis computes a quantity from: each input the student
//! gave (their file, read again and brought to our shape), else ours, in
//! the crate's types. Springs are the student's when their `A` holds our
//! springs in some order and orientation, so that `r` and `d` are worked
//! in the student's rows; vertices are the same for both.
//!
//! ```text
//! springs   the rows of the student's A (else ours)      r, d: in those rows
//! k, Δt, w  the trace's (k from trace.json)                pins: w CᵀC V = b − k Aᵀd − y, ours
//! ```

use super::super::entries::{conform, to_dense, to_sparse};
use super::super::order::in_their_order;
use super::super::place::Context;
use super::super::springs::Row;
use crate::app::trace::quantities::{quantities, Axis, Quantity};
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::CscMatrix;
use masssprings::matrix_market::{read, MatrixMarket};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The two folders, and what `--compare` learnt of them.
pub struct Inputs<'a> {
    pub ours: &'a Path,
    pub theirs: &'a Path,
    pub context: &'a Context,
    pub iterations: usize,
    /// Each file read so far (`None`: missing or unreadable), by path: the
    /// walk computes a quantity under every mistake from the same files.
    pub read: RefCell<HashMap<PathBuf, Option<MatrixMarket>>>,
}

impl Inputs<'_> {
    /// `k`.
    pub fn k(&self) -> f64 {
        self.context.k
    }

    /// The number of vertices.
    pub fn n(&self) -> usize {
        self.context.q.nrows()
    }

    /// The springs the student's rows stand for: theirs when their `A`
    /// matched ours one to one, else ours.
    pub fn springs(&self) -> Vec<[usize; 2]> {
        let rows = match &self.context.their_springs {
            Some((theirs, matching)) if matching.is_permutation() => theirs,
            _ => &self.context.our_springs,
        };
        rows.iter()
            .map(|row| match row {
                Row::Spring(ends) => *ends,
                Row::NotASpring(_) => [0, 0],
            })
            .collect()
    }

    /// Our pinned vertices, in the order of our `C`'s rows.
    pub fn pins(&self) -> Vec<usize> {
        let c = self.ours_sparse("C.mtx");
        let mut pinned = vec![0; c.as_ref().map_or(0, CscMatrix::nrows)];
        if let Some(c) = &c {
            for vertex in 0..c.ncols() {
                for &pin in c.column(vertex).0 {
                    pinned[pin] = vertex;
                }
            }
        }
        pinned
    }

    /// Our file `name`.
    pub fn our_file(&self, name: &str) -> Option<MatrixMarket> {
        self.file(self.ours.join(name))
    }

    /// The student's file `name`, if given and readable.
    pub fn their_file(&self, name: &str) -> Option<MatrixMarket> {
        self.file(self.theirs.join(name))
    }

    /// The file at `path`, read once.
    fn file(&self, path: PathBuf) -> Option<MatrixMarket> {
        let mut files = self.read.borrow_mut();
        let file = files.entry(path).or_insert_with_key(|path| read(path).ok());
        file.clone()
    }

    /// Our sparse file `name`.
    pub fn ours_sparse(&self, name: &str) -> Option<CscMatrix> {
        to_sparse(&self.our_file(name)?).ok()
    }

    /// The student's sparse `rows × cols` file `name` (`M` may be its
    /// diagonal), if given and of that shape.
    pub fn their_sparse(&self, name: &str, shape: (usize, usize)) -> Option<CscMatrix> {
        let conformed = conform(self.their_file(name)?, shape, false, name == "M.mtx").ok()?;
        to_sparse(&conformed).ok()
    }

    /// The student's sparse file, else ours.
    pub fn sparse(&self, name: &str) -> Option<CscMatrix> {
        let ours = self.ours_sparse(name)?;
        let shape = (ours.nrows(), ours.ncols());
        self.their_sparse(name, shape).or(Some(ours))
    }

    /// The student's `A` as an `m × n` matrix (transposed back when they
    /// wrote it `n × m`), else ours.
    pub fn incidence(&self) -> Option<CscMatrix> {
        let ours = self.ours_sparse("A.mtx")?;
        let Some(theirs) = self.their_file("A.mtx").and_then(|a| to_sparse(&a).ok()) else {
            return Some(ours);
        };
        match (theirs.nrows(), theirs.ncols()) {
            (_, n) if n == ours.ncols() => Some(theirs),
            (n, _) if n == ours.ncols() => Some(theirs.transpose()),
            _ => Some(ours),
        }
    }

    /// Our dense file `name`, in the student's spring rows when its rows
    /// are springs.
    pub fn ours_dense(&self, name: &str) -> Option<DenseMatrix> {
        let ours = to_dense(&self.our_file(name)?).ok()?;
        let spec = quantity_named(name, self.iterations)?.spec;
        let spring_rows = matches!(spec.rows, Axis::Spring | Axis::SpringVector);
        match self
            .context
            .matching()
            .filter(|m| spring_rows && m.is_permutation())
        {
            Some(matching) => {
                Some(in_their_order(&ours, matching, spec.rows == Axis::SpringVector).0)
            }
            None => Some(ours),
        }
    }

    /// The student's dense file `name` of ours' shape (in their rows),
    /// if given.
    pub fn their_dense(&self, name: &str) -> Option<DenseMatrix> {
        let ours = self.ours_dense(name)?;
        let shape = (ours.nrows(), ours.ncols());
        to_dense(&conform(self.their_file(name)?, shape, true, false).ok()?).ok()
    }

    /// The student's dense file, else ours.
    pub fn dense(&self, name: &str) -> Option<DenseMatrix> {
        self.their_dense(name).or_else(|| self.ours_dense(name))
    }

    /// The student's `n × 3` file as points, else ours.
    pub fn points(&self, name: &str) -> Option<Vec<[f64; 3]>> {
        self.dense(name).map(|a| rows_of(&a))
    }

    /// `w CᵀC V`, the pins' part of our `b_1`: `b − k Aᵀd − y` at the
    /// pinned vertices, 0 elsewhere.
    pub fn pin_term(&self) -> Option<Vec<[f64; 3]>> {
        let read = |name: &str| Some(rows_of(&to_dense(&self.our_file(name)?).ok()?));
        let (b, d, y) = (read("b_1.mtx")?, read("d_1.mtx")?, read("y.mtx")?);
        let a = self.ours_sparse("A.mtx")?;
        let mut springs = vec![[0.0; 3]; b.len()];
        a.transpose_mul_points(&d, &mut springs).ok()?;
        let mut pins = vec![[0.0; 3]; b.len()];
        for i in self.pins() {
            pins[i] = std::array::from_fn(|c| b[i][c] - self.k() * springs[i][c] - y[i][c]);
        }
        Some(pins)
    }
}

/// The rows of an `n × 3` matrix.
pub fn rows_of(a: &DenseMatrix) -> Vec<[f64; 3]> {
    (0..a.nrows())
        .map(|i| std::array::from_fn(|c| a.row(i).get(c).copied().unwrap_or(0.0)))
        .collect()
}

/// The quantity whose file is `name`.
pub fn quantity_named(name: &str, iterations: usize) -> Option<Quantity> {
    quantities(iterations)
        .into_iter()
        .find(|q| q.file_name() == name)
}
