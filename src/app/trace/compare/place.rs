//! Where a difference is, in words a student reads without the manual:
//! what the row and column stand for, counted from 0 as the handout and
//! Eigen count vertices, springs and pins, with the file's own 1-based row
//! and column beside them, and what the difference was divided by:
//!
//! ```text
//! vertex 6, y (file row 7, column 2): ours -9.8, yours -9.7, relative to |ours|
//! your spring 40 = (9, 4), our spring 17 = (4, 9) reversed: ours negated, y (file row 41, column 2): …
//! ```
//!
//! And what `--compare` knows of our trace to say so: the springs, the
//! pins, `Q` and our ordering, and the student's springs and ordering once
//! read.

use super::entries::{to_sparse, Difference, RowKind, ScaleOf};
use super::factor::permutation_of;
use super::springs::{spring_name, springs_of, Matching, Row};
use crate::app::trace::quantities::{Axis, Check, Spec};
use masssprings::linalg::sparse::CscMatrix;
use masssprings::matrix_market::MatrixMarket;

/// Where the largest difference of a quantity is.
#[derive(Debug, Clone)]
pub enum Place {
    /// An entry of the quantity (in the student's rows).
    Entry(Difference),
    /// An entry of `L Lᵀ − P Q Pᵀ` (in the factor's order), with the
    /// permutation `perm` of `P` it was formed with (`ours` is `P Q Pᵀ`,
    /// `yours` is `L Lᵀ`).
    Product(Difference, Vec<usize>),
}

impl Place {
    /// The scaled difference.
    pub fn relative(&self) -> f64 {
        match self {
            Place::Entry(d) | Place::Product(d, _) => d.relative,
        }
    }
}

/// What `--compare` reads of our trace before it compares, and learns of
/// the student's as it goes.
#[derive(Debug)]
pub struct Context {
    /// Our springs, read off the rows of our `A`.
    pub our_springs: Vec<Row>,
    /// The student's springs and which of ours each is, once their `A`
    /// was read and shares at least one spring with ours.
    pub their_springs: Option<(Vec<Row>, Matching)>,
    /// Our `A`, and the stiffness `k`.
    pub a: CscMatrix,
    pub k: f64,
    pub q: CscMatrix,
    /// Each vertex: pinned (a column of `C`) or free.
    pub vertex_kinds: Vec<RowKind>,
    /// Our `perm` (`perm[new] = old`).
    pub our_perm: Vec<usize>,
    /// The student's, once their `P.mtx` was read and is a permutation.
    pub their_perm: Option<Vec<usize>>,
}

impl Context {
    /// From our `A`, `Q`, `P` and `C`.
    ///
    /// # Errors
    /// When they do not fit one another (a trace folder edited by hand).
    pub fn new(k: f64, [a, q, p, c]: [&MatrixMarket; 4]) -> Result<Self, String> {
        let [a, q, p, c] = [a, q, p, c].map(to_sparse);
        let (a, q, p, c) = (a?, q?, p?, c?);
        let our_perm = permutation_of(&p)?;
        let n = our_perm.len();
        if (q.nrows(), q.ncols(), a.ncols(), c.ncols()) != (n, n, n, n) {
            return Err(format!(
                "A ({} × {}), Q ({} × {}), P ({n} × {n}) and C ({} × {}) do not fit one another",
                a.nrows(),
                a.ncols(),
                q.nrows(),
                q.ncols(),
                c.nrows(),
                c.ncols()
            ));
        }
        let mut vertex_kinds = vec![RowKind::Free; n];
        for vertex in 0..n {
            if !c.column(vertex).0.is_empty() {
                vertex_kinds[vertex] = RowKind::Pinned;
            }
        }
        Ok(Context {
            our_springs: springs_of(&a)?,
            their_springs: None,
            a,
            k,
            q,
            vertex_kinds,
            our_perm,
            their_perm: None,
        })
    }

    /// The kinds of the rows of a quantity whose rows are `axis`, in our
    /// order: pinned or free vertices, or all free.
    pub fn kinds(&self, axis: Axis) -> &[RowKind] {
        match axis {
            Axis::Vertex => &self.vertex_kinds,
            _ => &[],
        }
    }

    /// The student's spring matching, when their `A` gave one.
    pub fn matching(&self) -> Option<&Matching> {
        self.their_springs.as_ref().map(|(_, matching)| matching)
    }

    /// `vertex 6, y (file row 7, column 2): ours -9.8, yours -9.7, relative to |ours|`.
    pub fn describe(&self, spec: &Spec, place: &Place) -> String {
        match place {
            Place::Entry(d) => {
                let names = [self.name(spec.rows, d.row), self.name(spec.columns, d.col)];
                let names: Vec<String> = names.into_iter().flatten().collect();
                let position = match spec.columns {
                    Axis::Single => format!("file row {}", d.row + 1),
                    _ => format!("file row {}, column {}", d.row + 1, d.col + 1),
                };
                format!("{} ({position}): {}", names.join(", "), values(d, spec.check))
            }
            Place::Product(d, perm) => format!(
                "factor positions {}, {} = vertices {}, {} (file row {}, column {} of L Lᵀ − P Q Pᵀ): \
                 P Q Pᵀ {}, L Lᵀ {}, relative to {}",
                d.row,
                d.col,
                perm[d.row],
                perm[d.col],
                d.row + 1,
                d.col + 1,
                number(d.ours),
                number(d.yours),
                scale(d, spec.check)
            ),
        }
    }

    /// What index `k` (0-based) of `axis` stands for; for springs, the
    /// student's spring `k` and ours beside it when their order is not ours.
    fn name(&self, axis: Axis, k: usize) -> Option<String> {
        Some(match axis {
            Axis::Spring | Axis::SpringVector => self.spring(k, axis == Axis::SpringVector),
            Axis::Vertex => match self.vertex_kinds.get(k) {
                Some(RowKind::Pinned) => format!("vertex {k} (pinned)"),
                _ => format!("vertex {k}"),
            },
            Axis::Pin => format!("pin {k}"),
            Axis::Coordinate => ["x", "y", "z"]
                .get(k)
                .map_or(format!("column {k}"), |c| c.to_string()),
            Axis::FactorOrder => match self.our_perm.get(k) {
                Some(v) => format!("factor position {k} (vertex {v} in our order)"),
                None => format!("factor position {k}"),
            },
            Axis::Single => return None,
        })
    }

    /// The student's spring `e` (a row of their file), and ours beside it.
    fn spring(&self, e: usize, oriented: bool) -> String {
        let Some((theirs, matching)) = &self.their_springs else {
            return spring_name(e, self.our_springs.get(e));
        };
        match matching.ours_of.get(e).copied().flatten() {
            Some((ours, false)) if ours == e => spring_name(e, theirs.get(e)),
            Some((ours, reversed)) => {
                let flip = match (reversed, oriented) {
                    (true, true) => " reversed: ours negated",
                    (true, false) => " reversed",
                    (false, _) => "",
                };
                let our = spring_name(ours, self.our_springs.get(ours));
                format!("your {}, our {our}{flip}", spring_name(e, theirs.get(e)))
            }
            None => format!("your {}", spring_name(e, theirs.get(e))),
        }
    }
}

/// `ours -9.8, yours -9.7, relative to |ours|`.
fn values(d: &Difference, check: Check) -> String {
    format!(
        "ours {}, yours {}, relative to {}",
        number(d.ours),
        number(d.yours),
        scale(d, check)
    )
}

/// What the difference was divided by, in words.
fn scale(d: &Difference, check: Check) -> String {
    match (d.scale_of, check) {
        (ScaleOf::Ours, _) => "|ours|".into(),
        (ScaleOf::Yours, _) => "|yours|".into(),
        (ScaleOf::Reference, Check::Sum { .. }) => {
            format!("the size of b's terms there, {}", number(d.scale))
        }
        (ScaleOf::Reference, Check::Factor { .. }) => {
            format!("√(Q'ₖₖ Q'ₗₗ) = {}", number(d.scale))
        }
        (ScaleOf::Reference, _) => format!("the row's largest |ours|, {}", number(d.scale)),
    }
}

/// A value as a person reads it: plain when moderate, else scientific.
pub fn number(v: f64) -> String {
    if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}
