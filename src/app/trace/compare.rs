//! `masssprings trace --compare DIR OTHER`: a student's files (`OTHER`,
//! any subset of the names `trace` writes) against ours (`DIR`), one line
//! per quantity in the handout's order:
//!
//! ```text
//! quantity  result     relative   tolerance  where
//! A         note                  exact      another spring order (allowed): 12362 of your 12442 springs in other rows, 6280 reversed; …
//! y         DIFFERS    1.43e-1    1e-8       vertex 3121, x (file row 3122, column 1): ours -0.359, yours 1.202, relative to the row's largest |ours|, 10.9
//! d_1       agrees     2.58e-16   1e-8       your spring 718 = (173, 212), our spring 715 = (173, 212), y (file row 719, column 2): …
//! ```
//!
//! "relative" is the largest `|ours − yours| / s` of the quantity, with
//! `s` the largest of `|ours|`, `|yours|` and what the entry is held to
//! (its row's largest `|ours|`, `b`'s terms, `√(Q'ₖₖ Q'ₗₗ)` for `L`),
//! named under "where" (see [`entries`]). Vertices, springs and pins are
//! counted from 0 as in the handout and Eigen, the file's row and column
//! from 1 beside them. At a vertex quantity the place shown is the
//! largest difference at a free vertex, unless only a pin differs.
//!
//! The handout's freedoms are accepted: the springs in any order and
//! orientation ([`springs`]: `r` and `d` are compared through the matching
//! of the student's `A`), any ordering `P` ([`factor`]: `L` is checked as
//! `L Lᵀ = P Q Pᵀ`), sparse or dense files, a vector as a row or a column,
//! `M` as its diagonal.
//!
//! The first `DIFFERS` line is the first quantity to fix: everything after
//! it is computed from it and may differ because of it. The diagnosis
//! ([`diagnosis`]) then says what went wrong there: the mistake of the
//! gallery whose numbers the student's are, or the nearest proven hint;
//! [`report`] prints it all as a table or, with `--json`, one JSON object.

mod diagnosis;
mod entries;
mod factor;
mod order;
mod place;
mod report;
mod springs;
mod sum;

pub use factor::inverse;

use super::manifest::{read_manifest, Manifest, MANIFEST};
use super::quantities::{quantities, Axis, Check, Quantity};
use crate::app::error::AppError;
use crate::app::file_plan::start_holds;
use entries::{
    conform, dense_difference, sparse_difference, to_dense, to_sparse, Largest, RowKind,
};
use masssprings::files::{escaped, shown};
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::CscMatrix;
use masssprings::matrix_market::{read, MatrixMarket};
use masssprings::sim::ITERATIONS;
use order::in_their_order;
use place::{Context, Place};
use report::{Outcome, Report};
use std::borrow::Cow;
use std::path::Path;

/// Compares `theirs` with `ours` and reports, as a table or as JSON.
pub fn run(ours: &Path, theirs: &Path, json: bool) -> Result<(), AppError> {
    let manifest = read_manifest(ours)?;
    check_manifest(&manifest, ours)?;
    check_one_trace(&manifest, ours)?;
    if !theirs.is_dir() {
        return Err(AppError::Failed(format!(
            "{}: not a folder; --compare DIR OTHER compares two folders of files",
            shown(theirs)
        )));
    }
    let all = quantities(manifest.iterations);
    let [a, q, p, c] = ["A.mtx", "Q.mtx", "P.mtx", "C.mtx"].map(|name| read_ours(ours, name));
    let mut context = Context::new(manifest.k, [&a?, &q?, &p?, &c?])
        .map_err(|e| AppError::Failed(format!("{}: {e}", shown(ours))))?;
    let mut findings = Vec::with_capacity(all.len());
    for quantity in &all {
        let outcome = compare_one(quantity, ours, theirs, &mut context)?;
        findings.push((*quantity, outcome));
    }
    let verdicts: Vec<diagnosis::Finding> = findings
        .iter()
        .map(|(quantity, outcome)| diagnosis::Finding {
            quantity: *quantity,
            given: !matches!(outcome, Outcome::NotGiven),
            differs: matches!(outcome, Outcome::Differs(..)),
        })
        .collect();
    let inputs = diagnosis::inputs::Inputs {
        ours,
        theirs,
        context: &context,
        iterations: manifest.iterations,
        read: Default::default(),
    };
    let report = Report {
        heading: format!(
            "comparing {} with {} ({}, step {}, {} iteration(s), {} ordering){}{}",
            shown(theirs),
            shown(ours),
            escaped(&manifest.scene),
            manifest.step,
            manifest.iterations,
            escaped(&manifest.ordering),
            mistake_in(theirs, theirs_manifest(theirs).as_ref(), ""),
            mistake_in(ours, Some(&manifest), ", not the correct quantities"),
        ),
        diagnosis: diagnosis::diagnose(&inputs, &verdicts),
        findings,
        ignored: report::ignored(theirs, &all),
        context: &context,
        iterations: manifest.iterations,
    };
    match json {
        true => report.print_json(),
        false => report.print_text(),
    }
    report.conclude(theirs)
}

/// Refuses a manifest whose iterations `trace` cannot have written,
/// before anything is allocated for them (a list of files per iteration).
fn check_manifest(manifest: &Manifest, ours: &Path) -> Result<(), AppError> {
    if (1..=ITERATIONS).contains(&manifest.iterations) && manifest.step >= 1 {
        return Ok(());
    }
    Err(AppError::Failed(format!(
        "{}: iterations {} and step {}: trace writes 1 to {ITERATIONS} iterations of a step from 1 \
         (run masssprings trace again to write it)",
        shown(&ours.join(MANIFEST)),
        manifest.iterations,
        manifest.step
    )))
}

/// Refuses our folder when one of its files is not of the trace its
/// manifest describes (each carries the trace's fingerprint): a trace
/// stopped while its files were moved in leaves such a mixture.
fn check_one_trace(manifest: &Manifest, ours: &Path) -> Result<(), AppError> {
    let Some(id) = &manifest.trace else {
        return Ok(());
    };
    for name in &manifest.files {
        let path = ours.join(name);
        if path.exists() && !start_holds(&path, id, 1024) {
            return Err(AppError::Failed(format!(
                "{}: not of the trace {} describes (it does not carry the trace's fingerprint \
                 {id}): a trace was stopped while its files were moved in, or the file came \
                 from another; run masssprings trace again",
                shown(&path),
                shown(&ours.join(MANIFEST))
            )));
        }
    }
    Ok(())
}

/// The manifest in the student's folder, when there is one that reads (a
/// folder `trace --mistake` wrote).
fn theirs_manifest(theirs: &Path) -> Option<Manifest> {
    let regular = std::fs::symlink_metadata(theirs.join(MANIFEST)).is_ok_and(|m| m.is_file());
    regular.then(|| read_manifest(theirs).ok()).flatten()
}

/// "; FOLDER holds a trace with the mistake NAME …" when the `manifest`
/// of `folder` records one, followed by `remark`; nothing otherwise.
fn mistake_in(folder: &Path, manifest: Option<&Manifest>, remark: &str) -> String {
    match manifest.and_then(|m| m.mistake.as_deref()) {
        Some(name) => format!(
            "; {} holds a trace with the mistake {} (written by trace --mistake){remark}",
            shown(folder),
            escaped(name)
        ),
        None => String::new(),
    }
}

/// One quantity: ours against the student's, when given. A file that
/// cannot be compared (unreadable, another shape, too large to convert)
/// differs, with the reason and the file's name.
fn compare_one(
    quantity: &Quantity,
    ours: &Path,
    theirs: &Path,
    context: &mut Context,
) -> Result<Outcome, AppError> {
    let file = quantity.file_name();
    let path = theirs.join(&file);
    match std::fs::symlink_metadata(&path) {
        Err(_) => return Ok(Outcome::NotGiven),
        Ok(_) if !path.exists() => return Ok(Outcome::Differs(None, broken_link(&path))),
        Ok(_) => {}
    }
    let their = match read(&path) {
        Ok(their) => their,
        Err(error) => return Ok(Outcome::Differs(None, format!("unreadable: {error}"))),
    };
    let outcome = match quantity.spec.check {
        Check::Incidence => incidence(their, context),
        Check::Entries { tolerance } => {
            let our = read_ours(ours, &file)?;
            entries(quantity, &our, their, tolerance, None, context)
        }
        Check::Sum { tolerance } => {
            let iteration = quantity.iteration.expect("b is per iteration");
            let (b, d) = (
                read_ours(ours, &file)?,
                read_ours(ours, &format!("d_{iteration}.mtx"))?,
            );
            let y = read_ours(ours, "y.mtx")?;
            let terms = sum::term_sizes(&b, &d, &y, context)
                .map_err(|e| AppError::Failed(format!("{}: {e}", shown(ours))))?;
            entries(quantity, &b, their, tolerance, Some(&terms), context)
        }
        Check::Ordering => ordering(their, context),
        Check::Factor { tolerance } => factor(their, context, tolerance),
    };
    let named = |reason| Outcome::Differs(None, format!("{}: {reason}", shown(&path)));
    Ok(outcome.unwrap_or_else(named))
}

/// Why the link at `path` gives no file: it loops, or points to nothing.
fn broken_link(path: &Path) -> String {
    match std::fs::read_link(path) {
        Ok(target) if std::fs::metadata(path).is_err_and(|e| e.raw_os_error() == Some(40)) => {
            format!(
                "{}: a link that loops (to {}, and round again)",
                shown(path),
                shown(&target)
            )
        }
        Ok(target) => format!(
            "{}: a link to {}, which does not exist",
            shown(path),
            shown(&target)
        ),
        Err(error) => format!("{}: {error}", shown(path)),
    }
}

/// Our file `name` in `ours`, which `trace` wrote.
fn read_ours(ours: &Path, name: &str) -> Result<MatrixMarket, AppError> {
    read(&ours.join(name))
        .map_err(|e| AppError::Failed(format!("{e} (run masssprings trace again to write it)")))
}

/// The student's `A`: a spring per row, the same springs as ours in any
/// order and orientation. Its matching is kept for `r` and `d`.
fn incidence(their: MatrixMarket, context: &mut Context) -> Result<Outcome, String> {
    let a = to_sparse(&their)?;
    let (m, n) = (context.our_springs.len(), context.a.ncols());
    if a.ncols() != n {
        return Err(format!(
            "shape {} × {}, ours {m} × {n} (a column per vertex)",
            a.nrows(),
            a.ncols()
        ));
    }
    let theirs = springs::springs_of(&a)?;
    let matching = springs::match_springs(&context.our_springs, &theirs)?;
    let outcome = match springs::mismatch(&context.our_springs, &theirs, &matching) {
        Some(reason) => Outcome::Differs(None, reason),
        None if matching.is_identity() => Outcome::Agrees(
            None,
            "the same springs in the same order and orientation".into(),
        ),
        None => {
            let (moved, reversed) = matching.moved_and_reversed();
            Outcome::Note(format!(
                "another spring order (allowed): {moved} of your {m} springs in other rows, \
                 {reversed} reversed; r and d are compared through it"
            ))
        }
    };
    if matching.theirs_of.iter().any(Option::is_some) {
        context.their_springs = Some((theirs, matching));
    }
    Ok(outcome)
}

/// Entry by entry, after bringing ours to the student's spring order (for
/// `r` and `d`) and the student's file to our shape and kind, each entry
/// held to its row's largest `|ours|` or, when given, `reference`'s entry.
fn entries(
    quantity: &Quantity,
    our: &MatrixMarket,
    their: MatrixMarket,
    tolerance: f64,
    reference: Option<&DenseMatrix>,
    context: &Context,
) -> Result<Outcome, String> {
    let spec = quantity.spec;
    let spring_rows = matches!(spec.rows, Axis::Spring | Axis::SpringVector);
    let (our, kinds, remark) = match context.matching().filter(|_| spring_rows) {
        Some(matching) => {
            let oriented = spec.rows == Axis::SpringVector;
            let (our, kinds) = in_their_order(&to_dense(our)?, matching, oriented);
            (
                Cow::Owned(MatrixMarket::Dense(our)),
                Cow::Owned(kinds),
                matched_remark(matching),
            )
        }
        None => (
            Cow::Borrowed(our),
            Cow::Borrowed(context.kinds(spec.rows)),
            String::new(),
        ),
    };
    let dense = matches!(*our, MatrixMarket::Dense(_));
    let shape = entries::shape(&our);
    let their = conform(their, shape, dense, spec.symbol == "M").map_err(|e| {
        joined(
            &format!("{e} ({})", spec.shape),
            shape_hint(spring_rows, context),
        )
    })?;
    let largest = match (&*our, &their) {
        (MatrixMarket::Dense(a), MatrixMarket::Dense(b)) => {
            dense_difference(a, b, reference, &kinds)
        }
        (our, their) => sparse_difference(&to_sparse(our)?, &to_sparse(their)?, &kinds),
    };
    let mut outcome = verdict(largest, tolerance, remark);
    if let Outcome::Differs(_, reason) = &mut outcome {
        *reason = joined(reason, order_hint(spring_rows, context));
    }
    Ok(outcome)
}

/// Says when springs were compared through a matching that is not all of
/// them.
fn matched_remark(matching: &springs::Matching) -> String {
    let matched = matching.ours_of.iter().filter(|m| m.is_some()).count();
    match matching.is_permutation() {
        true => String::new(),
        false => format!("over the {matched} springs your A shares with ours"),
    }
}

/// For a spring quantity compared in our order: how to compare in yours.
fn order_hint(spring_rows: bool, context: &Context) -> &'static str {
    match spring_rows && context.matching().is_none() {
        true => "compared in our spring order: give your A.mtx to compare in yours",
        false => "",
    }
}

/// For a spring quantity of another shape: what its rows must be.
fn shape_hint(spring_rows: bool, context: &Context) -> &'static str {
    match (spring_rows, context.matching()) {
        (true, Some(_)) => "ours in your spring order: a row per spring of your A",
        _ => order_hint(spring_rows, context),
    }
}

/// `first; second`, or whichever is not empty.
fn joined(first: &str, second: &str) -> String {
    match (first.is_empty(), second.is_empty()) {
        (_, true) => first.to_string(),
        (true, false) => second.to_string(),
        (false, false) => format!("{first}; {second}"),
    }
}

/// Agrees or differs, by the largest difference anywhere; the place shown
/// is a free row's unless only a pin is outside the tolerance.
fn verdict(largest: Largest, tolerance: f64, mut remark: String) -> Outcome {
    let shown = largest.shown(tolerance);
    if let (Some(shown), Some(pinned)) = (shown, largest.pinned) {
        if shown != pinned && pinned.relative > shown.relative {
            let within = match pinned.within(tolerance) {
                true => ", within the tolerance",
                false => " too",
            };
            let pins = format!("at the pins up to {:.2e}{within}", pinned.relative);
            remark = match remark.is_empty() {
                true => pins,
                false => format!("{remark}; {pins}"),
            };
        }
    }
    let place = shown.map(Place::Entry);
    match largest.overall() {
        Some(d) if !d.within(tolerance) => Outcome::Differs(place, remark),
        _ => Outcome::Agrees(place, remark),
    }
}

/// The student's matrix, sparse, if it is `n × n`; else why not.
fn square(their: &MatrixMarket, n: usize) -> Result<CscMatrix, String> {
    let a = to_sparse(their)?;
    match (a.nrows(), a.ncols()) == (n, n) {
        true => Ok(a),
        false => Err(format!(
            "shape {} × {}, ours {n} × {n}",
            a.nrows(),
            a.ncols()
        )),
    }
}

/// The student's `P`: any permutation (another one than ours is noted).
fn ordering(their: MatrixMarket, context: &mut Context) -> Result<Outcome, String> {
    let p = square(&their, context.our_perm.len())?;
    let perm = match factor::permutation_of(&p) {
        Ok(perm) => perm,
        Err(reason) => return Err(format!("not a permutation matrix: {reason}")),
    };
    let same = perm == context.our_perm;
    context.their_perm = Some(perm);
    Ok(match same {
        true => Outcome::Agrees(None, "the same ordering as ours".into()),
        false => Outcome::Note("another ordering than ours (allowed); L is checked with it".into()),
    })
}

/// The student's `L`: lower triangular, and `L Lᵀ = P Q Pᵀ` with their
/// `P` (or its transpose), or without one, ours or the natural order.
fn factor(their: MatrixMarket, context: &Context, tolerance: f64) -> Result<Outcome, String> {
    let l = square(&their, context.our_perm.len())?;
    if let Some((i, j, v)) = factor::above_diagonal(&l) {
        return Err(format!(
            "not lower triangular: entry ({}, {}) = {v}",
            i + 1,
            j + 1
        ));
    }
    if let Some((j, v)) = factor::first_pivot_not_positive(&l) {
        return Err(format!(
            "not a Cholesky factor: its diagonal must be positive, and pivot {} (entry ({0}, {0})) \
             is {}",
            j + 1,
            masssprings::files::number(v)
        ));
    }
    let mut first = None;
    for (label, perm) in orderings(context) {
        let kinds: Vec<RowKind> = perm.iter().map(|&v| context.vertex_kinds[v]).collect();
        let largest = factor::product_difference(&l, &context.q, &perm, &kinds)?;
        let shown = largest
            .shown(tolerance)
            .map(|d| Place::Product(d, perm.clone()));
        if largest.overall().is_none_or(|d| d.within(tolerance)) {
            return Ok(Outcome::Agrees(shown, label));
        }
        first.get_or_insert((shown, label));
    }
    let (place, label) = first.expect("at least one ordering is tried");
    Ok(Outcome::Differs(place, format!("L Lᵀ ≠ P Q Pᵀ {label}")))
}

/// The orderings to try `L` with, labelled: the student's `P` and its
/// transpose, or ours and the natural one.
fn orderings(context: &Context) -> Vec<(String, Vec<usize>)> {
    match &context.their_perm {
        Some(perm) => vec![
            ("with your P".into(), perm.clone()),
            ("with the transpose of your P".into(), inverse(perm)),
        ],
        None => vec![
            (
                "with our P (no P.mtx given)".into(),
                context.our_perm.clone(),
            ),
            (
                "in the natural order (no P.mtx given)".into(),
                (0..context.our_perm.len()).collect(),
            ),
        ],
    }
}
