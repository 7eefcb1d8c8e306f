//! The size of the terms of `b = k Aᵀd + y + w CᵀC V`, entry by entry,
//! which `b` is compared to:
//!
//! ```text
//! sᵢ = k (|A|ᵀ |d|)ᵢ + |yᵢ| + |(w CᵀC V)ᵢ|        (each of x, y, z)
//! ```
//!
//! A sum's rounding is a few units in the last place of the sum of the
//! sizes of its terms, not of its value (Higham 2002, §4.2): the spring
//! terms `k dₑ`, of size `k r`, cancel at a vertex to an entry of the size
//! of `y`, and at a pinned vertex the pins' `w` (1e10) dwarfs everything,
//! so scaled by its own row a wrong spring term would hide there. The
//! pins' term is read off our own files as `b − k Aᵀd − y`.

use super::place::Context;
use super::to_dense;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::matrix_market::MatrixMarket;

/// `s` for our `b`, from our `d` and `y` and the context's `A` and `k`.
///
/// # Errors
/// When our files do not fit one another (`d` not `m × 3`, `y` not the
/// shape of `b`): a trace folder edited by hand.
pub fn term_sizes(
    b: &DenseMatrix,
    d: &MatrixMarket,
    y: &MatrixMarket,
    context: &Context,
) -> Result<DenseMatrix, String> {
    let (d, y) = (to_dense(d), to_dense(y));
    let (a, k) = (&context.a, context.k);
    let shapes = [
        (b.nrows(), b.ncols()),
        (y.nrows(), y.ncols()),
        (d.nrows(), d.ncols()),
    ];
    if shapes != [(a.ncols(), 3), (a.ncols(), 3), (a.nrows(), 3)] {
        return Err(format!(
            "b, y and d ({shapes:?}) do not fit A ({} × {})",
            a.nrows(),
            a.ncols()
        ));
    }
    let mut sizes = DenseMatrix::zeros(b.nrows(), 3);
    for i in 0..a.ncols() {
        let (springs, signs) = a.column(i); // column i of A: the springs at vertex i
        for c in 0..3 {
            let (mut springs_sum, mut size) = (0.0, 0.0);
            for (&e, &sign) in springs.iter().zip(signs) {
                springs_sum += sign * d[(e, c)];
                size += (sign * d[(e, c)]).abs();
            }
            let pins = b[(i, c)] - k * springs_sum - y[(i, c)];
            sizes[(i, c)] = k * size + y[(i, c)].abs() + pins.abs();
        }
    }
    Ok(sizes)
}
