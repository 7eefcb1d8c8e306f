//! `masssprings trace --compare DIR OTHER`: a student's files (`OTHER`,
//! any subset of the names `trace` writes) against ours (`DIR`), one line
//! per quantity in the handout's order:
//!
//! ```text
//! quantity  result    difference  tolerance  where
//! A         DIFFERS   2           exact      row 18, column 5: spring 17 = (4, 9), vertex 4; ours -1, yours 1
//! r         agrees    1.1e-16     1e-12      row 35: spring 34 = (12, 13)
//! ```
//!
//! The difference is the largest `|ours − yours| / s` of the quantity,
//! with `s` the largest of `|ours|`, `|yours|` and the largest `|ours|` in
//! the row (see [`Check`]); the place is given 1-based as in the files,
//! and named by what the row and column stand for, 0-based as in `V`, `E`
//! and `b`. A student's file may be sparse where ours is dense and the
//! reverse; a vector may be a row or a column; `M` may be its diagonal.
//! `P` may be any permutation, and `L` is checked as `L Lᵀ = P Q Pᵀ` (see
//! [`factor`](super::compare::factor)).
//!
//! The first `DIFFERS` line is the first quantity to fix: everything after
//! it is computed from it and may differ because of it.

mod factor;
mod place;
mod sum;

pub use factor::inverse;

use super::quantities::{quantities, Check, Quantity};
use super::read_manifest;
use crate::app::error::AppError;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::{CscMatrix, TripletMatrix};
use masssprings::matrix_market::{read, MatrixMarket, SparseFile, Symmetry};
use place::{Context, Place};
use std::path::Path;

/// What a comparison found for one quantity.
#[derive(Debug)]
enum Outcome {
    /// Not in the student's folder.
    NotGiven,
    /// Within the tolerance; the largest difference, if any, and a remark.
    Agrees(Option<Place>, String),
    /// Outside the tolerance (at `Place`), or the file could not be
    /// compared at all (the reason).
    Differs(Option<Place>, String),
    /// Allowed, but worth saying (a different ordering `P`).
    Note(String),
}

/// The largest difference of a quantity and where it is.
#[derive(Debug, Clone, Copy)]
pub struct Difference {
    /// `|ours − yours| / s`.
    pub relative: f64,
    pub row: usize,
    pub col: usize,
    pub ours: f64,
    pub yours: f64,
}

pub fn run(ours: &Path, theirs: &Path) -> Result<(), AppError> {
    let manifest = read_manifest(ours)?;
    if !theirs.is_dir() {
        return Err(AppError::Failed(format!(
            "{}: not a folder; --compare DIR OTHER compares two folders of files",
            theirs.display()
        )));
    }
    let all = quantities(manifest.iterations);
    let [a, q, p] = ["A.mtx", "Q.mtx", "P.mtx"].map(|name| read_ours(ours, name));
    let mut context = Context::new(&a?, manifest.k, &q?, &p?)
        .map_err(|e| AppError::Failed(format!("{}: {e}", ours.display())))?;
    println!(
        "comparing {} with {} ({}, step {}, {} iteration(s), {} ordering)\n\
         rows and columns count from 1 as in the files; vertices, springs and pins from 0 as in V, E and b\n",
        theirs.display(),
        ours.display(),
        manifest.scene,
        manifest.step,
        manifest.iterations,
        manifest.ordering
    );
    println!(
        "{:<9} {:<9} {:<11} {:<10} where",
        "quantity", "result", "difference", "tolerance"
    );
    let (mut given, mut first_wrong, mut wrong) = (0, None, 0);
    for quantity in &all {
        let outcome = compare_one(quantity, ours, theirs, &mut context)?;
        print_line(quantity, &outcome, &context);
        given += usize::from(!matches!(outcome, Outcome::NotGiven));
        if let Outcome::Differs(place, reason) = outcome {
            wrong += 1;
            first_wrong.get_or_insert((*quantity, place, reason));
        }
    }
    print_ignored(theirs, &all, manifest.iterations);
    conclude(theirs, given, wrong, first_wrong, &context)
}

/// The closing line, and the exit status: an error when anything differs
/// or nothing was given.
fn conclude(
    theirs: &Path,
    given: usize,
    wrong: usize,
    first_wrong: Option<(Quantity, Option<Place>, String)>,
    context: &Context,
) -> Result<(), AppError> {
    if given == 0 {
        return Err(AppError::Failed(format!(
            "{} holds none of the files trace writes (A.mtx, r.mtx, M.mtx, …): nothing was compared",
            theirs.display()
        )));
    }
    let Some((quantity, place, reason)) = first_wrong else {
        println!("\nall {given} quantities given agree");
        return Ok(());
    };
    let at = match place {
        Some(place) => format!("at {}", context.describe(quantity.spec, &place)),
        None => reason,
    };
    println!(
        "\nfirst wrong quantity: {} ({}), {at}",
        quantity.name(),
        quantity.file_name()
    );
    Err(AppError::Failed(format!(
        "{wrong} of the {given} quantities given differ; the first is {}",
        quantity.name()
    )))
}

/// One quantity: ours against the student's, when given.
fn compare_one(
    quantity: &Quantity,
    ours: &Path,
    theirs: &Path,
    context: &mut Context,
) -> Result<Outcome, AppError> {
    let file = quantity.file_name();
    let our = read_ours(ours, &file)?;
    let path = theirs.join(&file);
    if !path.exists() {
        return Ok(Outcome::NotGiven);
    }
    let their = match read(&path) {
        Ok(their) => their,
        Err(error) => return Ok(Outcome::Differs(None, format!("unreadable: {error}"))),
    };
    Ok(match quantity.spec.check {
        Check::Entries { tolerance } => entries(quantity, &our, their, tolerance, None),
        Check::Sum { tolerance } => {
            let d = format!("d_{}.mtx", quantity.iteration.expect("b is per iteration"));
            let (d, y) = (read_ours(ours, &d)?, read_ours(ours, "y.mtx")?);
            let terms = sum::term_sizes(&to_dense(&our), &d, &y, context)
                .map_err(|e| AppError::Failed(format!("{}: {e}", ours.display())))?;
            entries(quantity, &our, their, tolerance, Some(&terms))
        }
        Check::Ordering => factor::ordering(their, context),
        Check::Factor { tolerance } => factor::factor(their, context, tolerance),
    })
}

/// Our file `name` in `ours`, which `trace` wrote.
fn read_ours(ours: &Path, name: &str) -> Result<MatrixMarket, AppError> {
    read(&ours.join(name))
        .map_err(|e| AppError::Failed(format!("{e} (run masssprings trace again to write it)")))
}

/// Entry by entry, after bringing the student's file to our shape and
/// kind, each entry scaled as [`Largest::consider`] says, with its row's
/// largest `|ours|` or, for a dense quantity, `scale`'s entry.
fn entries(
    quantity: &Quantity,
    our: &MatrixMarket,
    their: MatrixMarket,
    tolerance: f64,
    scale: Option<&DenseMatrix>,
) -> Outcome {
    let their = match conform(quantity, our, their) {
        Ok(their) => their,
        Err(reason) => return Outcome::Differs(None, reason),
    };
    let largest = match (our, &their) {
        (MatrixMarket::Dense(a), MatrixMarket::Dense(b)) => dense_difference(a, b, scale),
        _ => sparse_difference(&to_sparse(our), &to_sparse(&their)),
    };
    match largest {
        Some(d) if d.relative > tolerance => Outcome::Differs(Some(Place::Entry(d)), String::new()),
        largest => Outcome::Agrees(largest.map(Place::Entry), String::new()),
    }
}

/// The student's matrix in our shape and kind (dense or sparse): a
/// vector transposed, `M`'s diagonal made a matrix; a different shape is
/// the reason it differs.
fn conform(
    quantity: &Quantity,
    our: &MatrixMarket,
    their: MatrixMarket,
) -> Result<MatrixMarket, String> {
    let (rows, cols) = shape(our);
    let (their_rows, their_cols) = shape(&their);
    let vector = their_rows.min(their_cols) == 1;
    let their = if vector && (their_rows, their_cols) == (cols, rows) {
        let values = to_dense(&their).as_slice().to_vec(); // a vector's values, in order
        MatrixMarket::Dense(DenseMatrix::from_row_major(rows, cols, values).expect("a vector"))
    } else if quantity.spec.symbol == "M" && vector && their_rows.max(their_cols) == rows {
        sparse_file(CscMatrix::from_diagonal(to_dense(&their).as_slice()))
    } else {
        their
    };
    let (their_rows, their_cols) = shape(&their);
    if (their_rows, their_cols) != (rows, cols) {
        return Err(format!(
            "shape {their_rows} × {their_cols}, ours {rows} × {cols} ({})",
            quantity.spec.shape
        ));
    }
    Ok(match our {
        MatrixMarket::Dense(_) => MatrixMarket::Dense(to_dense(&their)),
        MatrixMarket::Sparse(_) => their,
    })
}

/// Rows and columns of a file's matrix.
fn shape(a: &MatrixMarket) -> (usize, usize) {
    match a {
        MatrixMarket::Sparse(file) => (file.matrix.nrows(), file.matrix.ncols()),
        MatrixMarket::Dense(a) => (a.nrows(), a.ncols()),
    }
}

/// The largest scaled difference of two dense matrices of one shape,
/// each entry scaled by its row's largest `|ours|`, or by `scale`'s entry.
fn dense_difference(
    ours: &DenseMatrix,
    yours: &DenseMatrix,
    scale: Option<&DenseMatrix>,
) -> Option<Difference> {
    let mut largest = Largest::default();
    for i in 0..ours.nrows() {
        let row_scale = ours.row(i).iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        for (j, (&a, &b)) in ours.row(i).iter().zip(yours.row(i)).enumerate() {
            largest.consider(i, j, a, b, scale.map_or(row_scale, |s| s[(i, j)]));
        }
    }
    largest.0
}

/// The largest scaled difference of two sparse matrices of one shape,
/// over the union of their patterns.
fn sparse_difference(ours: &CscMatrix, yours: &CscMatrix) -> Option<Difference> {
    let mut scale = vec![0.0_f64; ours.nrows()];
    for (&i, &v) in ours.row_idx().iter().zip(ours.values()) {
        scale[i] = scale[i].max(v.abs());
    }
    let mut largest = Largest::default();
    union_entries(ours, yours, |i, j, a, b| {
        largest.consider(i, j, a, b, scale[i])
    });
    largest.0
}

/// Calls `f(i, j, ours, yours)` for every position stored in either
/// matrix (a missing entry is 0), column by column.
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

/// The largest scaled difference seen so far.
#[derive(Default)]
pub struct Largest(pub Option<Difference>);

impl Largest {
    /// Takes `(i, j)` into account, `ours` and `yours` scaled by the
    /// largest of `|ours|`, `|yours|` and `row_scale`.
    pub fn consider(&mut self, row: usize, col: usize, ours: f64, yours: f64, row_scale: f64) {
        let s = ours.abs().max(yours.abs()).max(row_scale);
        let difference = (ours - yours).abs();
        let relative = if difference == 0.0 {
            0.0
        } else {
            difference / s
        };
        if self.0.is_none_or(|d| relative > d.relative) {
            self.0 = Some(Difference {
                relative,
                row,
                col,
                ours,
                yours,
            });
        }
    }
}

/// One line of the table.
fn print_line(quantity: &Quantity, outcome: &Outcome, context: &Context) {
    let tolerance = match quantity.spec.check {
        Check::Entries { tolerance } | Check::Factor { tolerance } | Check::Sum { tolerance }
            if tolerance > 0.0 =>
        {
            format!("{tolerance:e}")
        }
        Check::Entries { .. } => "exact".into(),
        Check::Ordering => "any".into(),
        Check::Factor { .. } | Check::Sum { .. } => "exact".into(),
    };
    let (result, place, remark) = match outcome {
        Outcome::NotGiven => ("not given", None, ""),
        Outcome::Agrees(place, remark) => ("agrees", place.as_ref(), remark.as_str()),
        Outcome::Differs(place, reason) => ("DIFFERS", place.as_ref(), reason.as_str()),
        Outcome::Note(remark) => ("note", None, remark.as_str()),
    };
    let place = place.filter(|p| p.relative() > 0.0); // no place for no difference
    let difference = match (place, outcome) {
        (Some(place), _) => format!("{:.2e}", place.relative()),
        (None, Outcome::Agrees(..)) if quantity.spec.check != Check::Ordering => "0".into(),
        _ => String::new(),
    };
    let mut at = place
        .map(|p| context.describe(quantity.spec, p))
        .unwrap_or_default();
    if !remark.is_empty() {
        at = if at.is_empty() {
            remark.to_string()
        } else {
            format!("{at} ({remark})")
        };
    }
    let tolerance = if matches!(outcome, Outcome::NotGiven) {
        String::new()
    } else {
        tolerance
    };
    let line = format!(
        "{:<9} {result:<9} {difference:<11} {tolerance:<10} {at}",
        quantity.name()
    );
    println!("{}", line.trim_end());
}

/// The `.mtx` files of `theirs` that are not quantities of this trace.
fn print_ignored(theirs: &Path, all: &[Quantity], iterations: usize) {
    let Ok(entries) = std::fs::read_dir(theirs) else {
        return;
    };
    let mut ignored: Vec<String> = entries
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".mtx") && !all.iter().any(|q| q.file_name() == *name))
        .collect();
    ignored.sort();
    if !ignored.is_empty() {
        println!(
            "\nignored (not a file of this trace of {iterations} iteration(s)): {}",
            ignored.join(", ")
        );
    }
}

/// A file's matrix as a sparse one (a dense file's zeros dropped).
pub fn to_sparse(a: &MatrixMarket) -> CscMatrix {
    match a {
        MatrixMarket::Sparse(file) => file.matrix.clone(),
        MatrixMarket::Dense(a) => {
            let mut triplets = TripletMatrix::new(a.nrows(), a.ncols());
            for i in 0..a.nrows() {
                for (j, &v) in a.row(i).iter().enumerate().filter(|(_, v)| **v != 0.0) {
                    triplets.push(i, j, v).expect("inside the matrix");
                }
            }
            triplets.to_csc()
        }
    }
}

/// A file's matrix as a dense one.
fn to_dense(a: &MatrixMarket) -> DenseMatrix {
    match a {
        MatrixMarket::Sparse(file) => file.matrix.to_dense(),
        MatrixMarket::Dense(a) => a.clone(),
    }
}

fn sparse_file(matrix: CscMatrix) -> MatrixMarket {
    MatrixMarket::Sparse(SparseFile {
        matrix,
        symmetry: Symmetry::General,
    })
}
