//! `masssprings analyze MATRIX.mtx`: the sparse Cholesky pipeline on one
//! matrix, timed step by step.

use super::flags::{whole, FactorFlags, JsonFlag};
use super::timing::{median_seconds, Repeats};
use super::AppError;
use masssprings::linalg::benchmark_right_hand_side;
use masssprings::linalg::matrix_market::{self, MatrixMarket};
use masssprings::linalg::sparse::{
    CscMatrix, Method, Ordering, Relaxation, SparseCholesky, SymbolicCholesky, Triangle,
};
use std::path::{Path, PathBuf};

/// What `analyze` measured (the keys of its `--json` output).
#[derive(Debug, serde::Serialize)]
pub(super) struct Analysis {
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
    ordering: &'static str,
    method: &'static str,
    /// Runs behind each median: ordering, symbolic, numeric, solve.
    runs: [usize; 4],
    /// The supernodes by width (columns), and their share of the stored
    /// entries of `L`: narrow ones read a gathered row of `x` per entry,
    /// which bounds the solve's bandwidth (`docs/performance.md`).
    supernodes_by_width: Vec<WidthClass>,
}

/// The supernodes of `widest` columns or fewer (`None`: any number) and
/// more than the class before, how many there are and their share of `L`'s
/// stored entries.
#[derive(Debug, serde::Serialize)]
pub(super) struct WidthClass {
    widest: Option<usize>,
    supernodes: usize,
    share_of_l: f64,
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

/// Sparse Cholesky of a Matrix Market matrix, timed step by step.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Sparse Cholesky of a symmetric positive definite Matrix Market matrix: n,
nnz, nnz(L), flops, median times of ordering, symbolic analysis, numeric
factorization and a 3-column solve, its relative residual and its backward
error (the relative residual can be large for an accurate solve of a matrix
with huge entries, such as the pins' w = 1e10; the backward error cannot),
and for the supernodal factorization the supernodes by width with their
share of L. The right-hand side is MATRIX.b.mtx (an n×3 array) when it
exists.")]
pub struct AnalyzeArgs {
    /// A symmetric positive definite Matrix Market matrix.
    #[arg(value_name = "MATRIX.mtx")]
    matrix: PathBuf,
    #[command(flatten)]
    factor: FactorFlags,
    /// Runs behind each median (default: at least 5, about a second).
    #[arg(long, value_name = "N", value_parser = whole(1, usize::MAX))]
    repeats: Option<usize>,
    #[command(flatten)]
    json: JsonFlag,
    /// Renamed: the factorization is --factorization.
    #[arg(long, hide = true, value_parser = renamed("--method is the iteration method elsewhere; analyze's is --factorization supernodal|simplicial"))]
    method: Option<String>,
    /// Renamed: supernode merging is --supernodes.
    #[arg(long, hide = true, value_parser = renamed("supernode merging is --supernodes small|fundamental|relaxed (cholmod: relaxed, none: fundamental)"))]
    relax: Option<String>,
}

/// The parser of a flag that was renamed: it refuses every value, saying
/// the new name.
fn renamed(message: &'static str) -> impl Fn(&str) -> Result<String, String> + Clone {
    move |_| Err(message.to_string())
}

pub fn run(args: AnalyzeArgs) -> Result<(), AppError> {
    let path = args.matrix;
    let relaxation = args.factor.supernodes.relaxation();
    let repeats = args.repeats.map_or(Repeats::Adaptive, Repeats::Exactly);
    let lower = read_symmetric_lower(&path)?;
    let rhs = read_or_make_rhs(&path, lower.ncols())?;
    let (ordering, method) = (args.factor.ordering.ordering, args.factor.factorization);
    let analysis = analyze(&lower, &rhs, ordering, method, relaxation, repeats)
        .map_err(|e| AppError::Failed(format!("{}: {e}", path.display())))?;
    if args.json.json {
        println!(
            "{}",
            serde_json::to_string(&analysis).expect("plain numbers serialise")
        );
    } else {
        print_table(&path, &analysis);
    }
    Ok(())
}

/// The lower triangle of the symmetric sparse matrix in `path` (a `general`
/// file is checked for symmetry, see `matrix_market::read_symmetric`).
pub(super) fn read_symmetric_lower(path: &Path) -> Result<CscMatrix, AppError> {
    let lower = matrix_market::read_symmetric(path)?.triangle(Triangle::Lower);
    if lower.ncols() == 0 {
        return Err(AppError::Failed(format!(
            "{}: the matrix is 0 × 0: there is nothing to factor or draw",
            path.display()
        )));
    }
    Ok(lower)
}

/// `MATRIX.b.mtx` next to `MATRIX.mtx` when it exists (an n×3 array), else
/// a fixed, varied right-hand side.
fn read_or_make_rhs(path: &Path, n: usize) -> Result<Vec<[f64; 3]>, AppError> {
    let rhs_path = path.with_extension("b.mtx");
    if !rhs_path.exists() {
        return Ok(benchmark_right_hand_side(n));
    }
    match matrix_market::read(&rhs_path)? {
        MatrixMarket::Dense(b) if b.nrows() == n && b.ncols() == 3 => {
            Ok((0..n).map(|i| [b[(i, 0)], b[(i, 1)], b[(i, 2)]]).collect())
        }
        _ => Err(AppError::Failed(format!(
            "{}: expected an {n}×3 array (the right-hand side)",
            rhs_path.display()
        ))),
    }
}

/// Times each step of the pipeline on the lower triangle `lower` and
/// checks the solution.
pub(super) fn analyze(
    lower: &CscMatrix,
    rhs: &[[f64; 3]],
    ordering: Ordering,
    method: Method,
    relaxation: Relaxation,
    repeats: Repeats,
) -> Result<Analysis, String> {
    let failed = |e: masssprings::linalg::LinalgError| e.to_string();
    let perm = ordering.permutation(lower).map_err(failed)?;
    let (ordering_s, ordering_runs) = median_seconds(repeats, || {
        ordering.permutation(lower).expect("ordered once already");
    });
    // the supernodal method relaxes its supernodes: part of the analysis
    let symbolic_for = |method: Method| {
        let exact = SymbolicCholesky::with_permutation(lower, &perm)?;
        Ok::<_, masssprings::linalg::LinalgError>(match method {
            Method::Supernodal => exact.relaxed(&relaxation),
            Method::Simplicial => exact,
        })
    };
    let symbolic = symbolic_for(method).map_err(failed)?;
    let (symbolic_s, symbolic_runs) = median_seconds(repeats, || {
        symbolic_for(method).expect("analysed once already");
    });
    let nnz_l_stored = symbolic.nnz_l();
    let nnz_l = nnz_l_stored - symbolic.explicit_zeros();
    let flops = symbolic.flops();
    let by_width = match method {
        Method::Supernodal => supernodes_by_width(&symbolic),
        Method::Simplicial => Vec::new(),
    };
    let mut cholesky = SparseCholesky::factor(symbolic, lower, method).map_err(failed)?;
    let (numeric_s, numeric_runs) = median_seconds(repeats, || {
        cholesky.refactor(lower).expect("factored once already");
    });
    let mut x = rhs.to_vec();
    let (solve_s, solve_runs) = median_seconds(repeats, || {
        x.copy_from_slice(rhs);
        cholesky.solve_points_in_place(&mut x);
    });
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
        supernodes_by_width: by_width,
    })
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

fn print_table(path: &Path, a: &Analysis) {
    let rows = [
        ("matrix", path.display().to_string()),
        ("n", a.n.to_string()),
        ("nnz(A lower)", a.nnz_a.to_string()),
        (
            "nnz(L)",
            format!(
                "{}  (fill ratio {:.2}; {} stored)",
                a.nnz_l,
                a.nnz_l as f64 / a.nnz_a as f64,
                a.nnz_l_stored
            ),
        ),
        ("flops", format!("{:.4e}", a.flops)),
        (
            "ordering",
            format!("{:.6} s  ({})", a.ordering_s, a.ordering),
        ),
        ("symbolic", format!("{:.6} s", a.symbolic_s)),
        ("numeric", format!("{:.6} s  ({})", a.numeric_s, a.method)),
        ("solve (3 columns)", format!("{:.6} s", a.solve_s)),
        ("relative residual", format!("{:.3e}", a.residual)),
        ("backward error", format!("{:.3e}", a.backward_error)),
    ];
    for (label, value) in rows {
        println!("{label:<19}{value}");
    }
    let mut narrowest = 1;
    for class in &a.supernodes_by_width {
        let widths = match (narrowest, class.widest) {
            (low, None) => format!("width ≥ {low}"),
            (low, Some(high)) if low == high => format!("width {low}"),
            (low, Some(high)) => format!("width {low}–{high}"),
        };
        println!(
            "{widths:<19}{} supernodes, {:.1}% of L",
            class.supernodes,
            100.0 * class.share_of_l
        );
        narrowest = class.widest.map_or(narrowest, |widest| widest + 1);
    }
    let [ordering, symbolic, numeric, solve] = a.runs;
    println!("(medians of {ordering}, {symbolic}, {numeric} and {solve} runs)");
}
