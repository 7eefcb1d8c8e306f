//! The sparse Cholesky pipeline on one matrix, timed step by step and its
//! solution checked: what `analyze` prints for a Matrix Market file and
//! `bench` for each grid it generates.
//!
//! On more than one thread the numeric factorization and the solve are
//! timed on those threads and on one, in interleaved rounds, and the two
//! solutions compared bit for bit: the speedup, and the proof that it
//! changed nothing.

use super::timing::{interleaved_medians, median_seconds, Repeats};
use masssprings::linalg::sparse::{
    CscMatrix, Method, Ordering, Permutation, Relaxation, SparseCholesky, SymbolicCholesky,
};
use masssprings::linalg::LinalgError;

/// What `analyze` measured (the keys of its `--json` output).
#[derive(Debug, serde::Serialize)]
pub struct Analysis {
    pub n: usize,
    /// Entries of the lower triangle of `A`, diagonal included.
    pub nnz_a: usize,
    /// Nonzeros of the exact `L`, diagonal included.
    pub nnz_l: usize,
    /// Entries stored, explicit zeros of relaxed supernodes included.
    pub nnz_l_stored: usize,
    pub flops: f64,
    pub ordering_s: f64,
    pub symbolic_s: f64,
    pub numeric_s: f64,
    pub solve_s: f64,
    /// `‖A X − B‖_F / ‖B‖_F`.
    pub residual: f64,
    /// The normwise backward error of the solve, `max_c ‖r_c‖∞ /
    /// (‖A‖∞ ‖x_c‖∞ + ‖b_c‖∞)` over the three columns.
    pub backward_error: f64,
    pub ordering: &'static str,
    pub method: &'static str,
    /// Runs behind each median: ordering, symbolic, numeric, solve.
    pub runs: [usize; 4],
    /// The threads the numeric factorization and the solve ran on (1 for
    /// the simplicial method, which has no other).
    pub threads: usize,
    /// The same on one thread, when `threads` is more than one.
    pub one_thread: Option<OneThread>,
    /// The supernodes by width (columns), and their share of the stored
    /// entries of `L`: narrow ones read a gathered row of `x` per entry,
    /// which bounds the solve's bandwidth (`docs/performance.md`).
    pub supernodes_by_width: Vec<WidthClass>,
}

/// The numeric factorization and the solve on one thread, timed in rounds
/// interleaved with those on [`Analysis::threads`].
#[derive(Debug, serde::Serialize, serde::Deserialize, Clone, Copy)]
pub struct OneThread {
    pub numeric_s: f64,
    pub solve_s: f64,
    /// One thread's time over the threads' time.
    pub numeric_speedup: f64,
    pub solve_speedup: f64,
    /// Are the two solutions the same to the bit? (They must be.)
    pub same_bits: bool,
}

/// The supernodes of `widest` columns or fewer (`None`: any number) and
/// more than the class before, how many there are and their share of `L`'s
/// stored entries.
#[derive(Debug, serde::Serialize)]
pub struct WidthClass {
    pub widest: Option<usize>,
    pub supernodes: usize,
    pub share_of_l: f64,
}

/// Upper bounds of the width classes; the last takes every wider one.
const WIDTH_CLASSES: [Option<usize>; 6] = [Some(1), Some(4), Some(16), Some(64), Some(256), None];

/// The supernodes of `symbolic` in [`WIDTH_CLASSES`].
fn supernodes_by_width(symbolic: &SymbolicCholesky) -> Vec<WidthClass> {
    let (supernodes, col_ptr) = (symbolic.supernodes(), symbolic.col_ptr());
    let mut classes: Vec<WidthClass> = WIDTH_CLASSES
        .iter()
        .map(|&widest| WidthClass {
            widest,
            supernodes: 0,
            share_of_l: 0.0,
        })
        .collect();
    for s in 0..supernodes.len() {
        let columns = supernodes.columns(s);
        let entries = col_ptr[columns.end] - col_ptr[columns.start];
        let class = classes
            .iter_mut()
            .find(|c| c.widest.is_none_or(|widest| columns.len() <= widest))
            .expect("the last class takes every width");
        class.supernodes += 1;
        class.share_of_l += entries as f64 / symbolic.nnz_l() as f64;
    }
    classes
}

/// How `analyze` factors: the ordering, the method, the supernodes and
/// the threads.
#[derive(Debug, Clone, Copy)]
pub struct HowFactored {
    pub ordering: Ordering,
    pub method: Method,
    pub relaxation: Relaxation,
    pub threads: usize,
}

/// Times each step of the pipeline on the lower triangle `lower` and
/// checks the solution.
pub fn analyze(
    lower: &CscMatrix,
    rhs: &[[f64; 3]],
    how: HowFactored,
    repeats: Repeats,
) -> Result<Analysis, String> {
    let (ordering, method) = (how.ordering, how.method);
    let failed = |e: LinalgError| e.to_string();
    let perm = ordering.permutation(lower).map_err(failed)?;
    let (ordering_s, ordering_runs) = median_seconds(repeats, || {
        ordering.permutation(lower).expect("ordered once already");
    });
    let (symbolic, symbolic_s, symbolic_runs) =
        timed_symbolic(lower, &perm, method, &how.relaxation, repeats).map_err(failed)?;
    let nnz_l_stored = symbolic.nnz_l();
    let nnz_l = nnz_l_stored - symbolic.explicit_zeros();
    let flops = symbolic.flops();
    let by_width = match method {
        Method::Supernodal => supernodes_by_width(&symbolic),
        Method::Simplicial => Vec::new(),
    };
    let Solved {
        x,
        seconds: [numeric_s, solve_s],
        runs: [numeric_runs, solve_runs],
        threads,
        one_thread,
    } = timed_factor_and_solve(lower, symbolic, method, how.threads, rhs, repeats)
        .map_err(failed)?;
    let (residual, backward_error) = (
        relative_residual(lower, &x, rhs),
        backward_error(lower, &x, rhs),
    );
    refuse_non_finite(&x, residual, backward_error)?;
    Ok(Analysis {
        n: lower.ncols(),
        nnz_a: lower.nnz(),
        nnz_l,
        nnz_l_stored,
        flops,
        ordering_s,
        symbolic_s,
        numeric_s,
        solve_s,
        residual,
        backward_error,
        ordering: ordering.name(),
        method: match method {
            Method::Supernodal => "supernodal",
            Method::Simplicial => "simplicial",
        },
        runs: [ordering_runs, symbolic_runs, numeric_runs, solve_runs],
        threads,
        one_thread,
        supernodes_by_width: by_width,
    })
}

/// The symbolic analysis in the order `perm`, and its median time and
/// runs (the supernodal method relaxes its supernodes: part of the
/// analysis).
fn timed_symbolic(
    lower: &CscMatrix,
    perm: &Permutation,
    method: Method,
    relaxation: &Relaxation,
    repeats: Repeats,
) -> Result<(SymbolicCholesky, f64, usize), LinalgError> {
    let symbolic_for = |method: Method| {
        let exact = SymbolicCholesky::with_permutation(lower, perm)?;
        Ok::<_, LinalgError>(match method {
            Method::Supernodal => exact.relaxed(relaxation),
            Method::Simplicial => exact,
        })
    };
    let symbolic = symbolic_for(method)?;
    let (seconds, runs) = median_seconds(repeats, || {
        symbolic_for(method).expect("analysed once already");
    });
    Ok((symbolic, seconds, runs))
}

/// The solution of a timed solve, and the median seconds and the runs of
/// the numeric factorization and of the solve, on how many threads, and
/// on one.
struct Solved {
    x: Vec<[f64; 3]>,
    seconds: [f64; 2],
    runs: [usize; 2],
    threads: usize,
    one_thread: Option<OneThread>,
}

/// The numeric factorization and the 3-column solve of `rhs` on `threads`
/// threads, timed (and on one, interleaved, when the factor has more).
fn timed_factor_and_solve(
    lower: &CscMatrix,
    symbolic: SymbolicCholesky,
    method: Method,
    threads: usize,
    rhs: &[[f64; 3]],
    repeats: Repeats,
) -> Result<Solved, LinalgError> {
    let mut cholesky =
        SparseCholesky::factor_with_threads(symbolic.clone(), lower, method, threads)?;
    let threads = cholesky.threads();
    if threads == 1 {
        drop(symbolic);
        let (numeric_s, numeric_runs) = median_seconds(repeats, || {
            cholesky.refactor(lower).expect("factored once already");
        });
        let mut x = rhs.to_vec();
        let (solve_s, solve_runs) = median_seconds(repeats, || solve(&mut cholesky, rhs, &mut x));
        return Ok(Solved {
            x,
            seconds: [numeric_s, solve_s],
            runs: [numeric_runs, solve_runs],
            threads,
            one_thread: None,
        });
    }
    let mut alone = SparseCholesky::factor(symbolic, lower, method)?;
    let ([numeric_1, numeric_s], numeric_runs) = interleaved_medians(
        repeats,
        || alone.refactor(lower).expect("factored once already"),
        || cholesky.refactor(lower).expect("factored once already"),
    );
    let (mut x, mut x_1) = (rhs.to_vec(), rhs.to_vec());
    let ([solve_1, solve_s], solve_runs) = interleaved_medians(
        repeats,
        || solve(&mut alone, rhs, &mut x_1),
        || solve(&mut cholesky, rhs, &mut x),
    );
    let same_bits = x
        .iter()
        .flatten()
        .map(|v| v.to_bits())
        .eq(x_1.iter().flatten().map(|v| v.to_bits()));
    Ok(Solved {
        x,
        seconds: [numeric_s, solve_s],
        runs: [numeric_runs, solve_runs],
        threads,
        one_thread: Some(OneThread {
            numeric_s: numeric_1,
            solve_s: solve_1,
            numeric_speedup: numeric_1 / numeric_s,
            solve_speedup: solve_1 / solve_s,
            same_bits,
        }),
    })
}

/// `x ← A⁻¹ b` with the factor, `x` first set to `rhs`.
fn solve(cholesky: &mut SparseCholesky, rhs: &[[f64; 3]], x: &mut [[f64; 3]]) {
    x.copy_from_slice(rhs);
    cholesky.solve_points_in_place(x);
}

/// A solution with an infinite or NaN entry, or a residual that is not a
/// number, is a failure, not a result to report.
fn refuse_non_finite(x: &[[f64; 3]], residual: f64, backward_error: f64) -> Result<(), String> {
    let entries = x
        .iter()
        .enumerate()
        .flat_map(|(i, row)| (0..3).map(move |c| (i, c, row[c])));
    if let Some((i, c, value)) = entries.into_iter().find(|(_, _, v)| !v.is_finite()) {
        return Err(format!(
            "the solve gave a solution that is not finite (x[{}, {}] = {value}): the matrix \
             is too close to singular, or its entries too large or too small, for f64",
            i + 1,
            c + 1
        ));
    }
    if !residual.is_finite() || !backward_error.is_finite() {
        return Err(format!(
            "the residual of the solve is not a number (relative residual {residual}, \
             backward error {backward_error}): the right-hand side is zero or the matrix's \
             entries overflow f64"
        ));
    }
    Ok(())
}

/// `A X` for the symmetric `A` with lower triangle `lower`:
/// `(lower + lowerᵀ − diag) X`.
fn symmetric_mul_points(lower: &CscMatrix, x: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let n = lower.ncols();
    let (mut below, mut above) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
    lower.mul_points(x, &mut below).expect("square");
    lower.transpose_mul_points(x, &mut above).expect("square");
    let diagonal = lower.diagonal();
    for (i, row) in below.iter_mut().enumerate() {
        *row = std::array::from_fn(|c| row[c] + above[i][c] - diagonal[i] * x[i][c]);
    }
    below
}

/// `‖A X − B‖_F / ‖B‖_F` for the symmetric `A` with lower triangle `lower`.
fn relative_residual(lower: &CscMatrix, x: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let ax = symmetric_mul_points(lower, x);
    let (mut error, mut norm) = (0.0, 0.0);
    for (ax, b) in ax.iter().zip(b) {
        for c in 0..3 {
            error += (ax[c] - b[c]).powi(2);
            norm += b[c].powi(2);
        }
    }
    (error / norm).sqrt()
}

/// The normwise backward error of the solve `A x = b`, column by column,
/// the largest of the three:
///
/// ```text
/// η = ‖A x − b‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)
/// ```
///
/// the smallest relative change of `A` and `b` for which `x` is the exact
/// solution (Rigal & Gaches 1967). A backward-stable solver such as
/// Cholesky leaves it at a small multiple of the unit roundoff whatever the
/// matrix. The relative residual `‖A x − b‖ / ‖b‖` is that times
/// `(‖A‖ ‖x‖ + ‖b‖) / ‖b‖`, which on `Q` can be 10⁶ (the pins put
/// `w = 10¹⁰` on the diagonal): 10⁻¹⁰ on grid-316 with a right-hand side
/// that is O(1) on the pinned rows, from our solve and from SuperLU's alike.
///
/// Source: N. J. Higham, *Accuracy and Stability of Numerical Algorithms*,
/// 2nd ed., 2002, Theorem 7.1.
fn backward_error(lower: &CscMatrix, x: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let ax = symmetric_mul_points(lower, x);
    // ‖A‖∞: the largest row sum of |A|, from the lower triangle's columns
    // (column j of the lower triangle is row j of the upper one)
    let mut row_sums = vec![0.0; lower.ncols()];
    for j in 0..lower.ncols() {
        let (rows, values) = lower.column(j);
        for (&i, &a) in rows.iter().zip(values) {
            row_sums[i] += a.abs();
            if i != j {
                row_sums[j] += a.abs();
            }
        }
    }
    let norm_a = row_sums.iter().fold(0.0_f64, |m, &s| m.max(s));
    let largest = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0_f64, |m, a| m.max(a.abs()));
    (0..3)
        .map(|c| {
            let r = largest(&mut ax.iter().zip(b).map(|(ax, b)| ax[c] - b[c]));
            let x_norm = largest(&mut x.iter().map(|x| x[c]));
            let b_norm = largest(&mut b.iter().map(|b| b[c]));
            r / (norm_a * x_norm + b_norm)
        })
        .fold(0.0, f64::max)
}
