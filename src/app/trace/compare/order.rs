//! Our rows of a spring quantity (`r`, `d`) brought to the student's
//! spring order, through the matching of their `A` to ours
//! ([`springs`](super::springs)):
//!
//! ```text
//! row e′ of ours-in-their-order = ± our row of their spring e′   (− where it runs the other way and the quantity is oriented, d)
//! ```
//!
//! Rows of their springs that are not ours are left at zero and skipped.

use super::entries::RowKind;
use super::springs::Matching;
use masssprings::linalg::dense::DenseMatrix;

/// Ours in the student's spring order: row `e′` is our row of their
/// spring `e′`, negated when `oriented` and the spring is reversed; rows
/// of springs that are not ours are skipped.
pub fn in_their_order(
    our: &DenseMatrix,
    matching: &Matching,
    oriented: bool,
) -> (DenseMatrix, Vec<RowKind>) {
    let mut ordered = DenseMatrix::zeros(matching.ours_of.len(), our.ncols());
    let mut kinds = vec![RowKind::Skipped; matching.ours_of.len()];
    for (e, matched) in matching.ours_of.iter().enumerate() {
        let Some((ours, reversed)) = *matched else {
            continue;
        };
        let sign = if oriented && reversed { -1.0 } else { 1.0 };
        for (to, from) in ordered.row_mut(e).iter_mut().zip(our.row(ours)) {
            *to = sign * from;
        }
        kinds[e] = RowKind::Free;
    }
    (ordered, kinds)
}
