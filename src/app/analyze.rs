//! `masssprings analyze MATRIX.mtx`: the sparse Cholesky pipeline on one
//! matrix, timed step by step.

use super::args::Args;
use super::timing::{median_seconds, Repeats};
use super::AppError;
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
    pub residual: f64,
    ordering: &'static str,
    method: &'static str,
    /// Runs behind each median: ordering, symbolic, numeric, solve.
    runs: [usize; 4],
}

pub fn run(args: &[String]) -> Result<(), AppError> {
    let args = Args::parse(args, &["ordering", "method", "relax", "repeats"], &["json"])?;
    let path = PathBuf::from(args.single_positional("MATRIX.mtx")?);
    let ordering: Ordering = args.value_or("ordering", Ordering::Amd)?;
    let method = parse_method(&args)?;
    let relaxation = match args.value_or("relax", "none".to_string())?.as_str() {
        "cholmod" => Relaxation::CHOLMOD,
        "none" => Relaxation::NONE,
        other => {
            return Err(AppError::Usage(format!(
                "--relax {other}: expected cholmod or none"
            )))
        }
    };
    let repeats = match args.value_or("repeats", 0usize)? {
        0 => Repeats::Adaptive,
        count => Repeats::Exactly(count),
    };
    let lower = read_symmetric_lower(&path)?;
    let rhs = read_or_make_rhs(&path, lower.ncols())?;
    let analysis = analyze(&lower, &rhs, ordering, method, relaxation, repeats)
        .map_err(|e| AppError::Failed(format!("{}: {e}", path.display())))?;
    if args.switch("json") {
        println!(
            "{}",
            serde_json::to_string(&analysis).expect("plain numbers serialise")
        );
    } else {
        print_table(&path, &analysis);
    }
    Ok(())
}

fn parse_method(args: &Args) -> Result<Method, AppError> {
    match args.value_or("method", "supernodal".to_string())?.as_str() {
        "supernodal" => Ok(Method::Supernodal),
        "simplicial" => Ok(Method::Simplicial),
        other => Err(AppError::Usage(format!(
            "--method {other}: expected supernodal or simplicial"
        ))),
    }
}

/// The lower triangle of the square sparse matrix in `path`.
pub(super) fn read_symmetric_lower(path: &Path) -> Result<CscMatrix, AppError> {
    match matrix_market::read(path)? {
        MatrixMarket::Sparse(file) if file.matrix.nrows() == file.matrix.ncols() => {
            Ok(file.matrix.triangle(Triangle::Lower))
        }
        MatrixMarket::Sparse(file) => Err(AppError::Failed(format!(
            "{}: the matrix must be square, it is {}×{}",
            path.display(),
            file.matrix.nrows(),
            file.matrix.ncols()
        ))),
        MatrixMarket::Dense(_) => Err(AppError::Failed(format!(
            "{}: expected a sparse (coordinate) matrix, found an array",
            path.display()
        ))),
    }
}

/// `MATRIX.b.mtx` next to `MATRIX.mtx` when it exists (an n×3 array), else
/// a fixed, varied right-hand side.
fn read_or_make_rhs(path: &Path, n: usize) -> Result<Vec<[f64; 3]>, AppError> {
    let rhs_path = path.with_extension("b.mtx");
    if !rhs_path.exists() {
        return Ok(varied_rhs(n));
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

/// A fixed, varied n×3 right-hand side.
pub(super) fn varied_rhs(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            [
                1.0 + (t * 0.37).sin(),
                (t * 0.11).cos(),
                0.5 - (t * 0.23).sin(),
            ]
        })
        .collect()
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
) -> Result<Analysis, masssprings::linalg::LinalgError> {
    let perm = ordering.permutation(lower)?;
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
    let symbolic = symbolic_for(method)?;
    let (symbolic_s, symbolic_runs) = median_seconds(repeats, || {
        symbolic_for(method).expect("analysed once already");
    });
    let nnz_l_stored = symbolic.nnz_l();
    let nnz_l = nnz_l_stored - symbolic.explicit_zeros();
    let flops = symbolic.flops();
    let mut cholesky = SparseCholesky::factor(symbolic, lower, method)?;
    let (numeric_s, numeric_runs) = median_seconds(repeats, || {
        cholesky.refactor(lower).expect("factored once already");
    });
    let mut x = rhs.to_vec();
    let (solve_s, solve_runs) = median_seconds(repeats, || {
        x.copy_from_slice(rhs);
        cholesky.solve_points_in_place(&mut x);
    });
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
        residual: relative_residual(lower, &x, rhs),
        ordering: ordering.name(),
        method: match method {
            Method::Supernodal => "supernodal",
            Method::Simplicial => "simplicial",
        },
        runs: [ordering_runs, symbolic_runs, numeric_runs, solve_runs],
    })
}

/// `‖A X − B‖_F / ‖B‖_F` for the symmetric `A` with lower triangle `lower`:
/// `A X = (lower + lowerᵀ − diag) X`.
fn relative_residual(lower: &CscMatrix, x: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let n = lower.ncols();
    let (mut below, mut above) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
    lower.mul_points(x, &mut below).expect("square");
    lower.transpose_mul_points(x, &mut above).expect("square");
    let diagonal = lower.diagonal();
    let (mut error, mut norm) = (0.0, 0.0);
    for i in 0..n {
        for c in 0..3 {
            let ax = below[i][c] + above[i][c] - diagonal[i] * x[i][c];
            error += (ax - b[i][c]).powi(2);
            norm += b[i][c].powi(2);
        }
    }
    (error / norm).sqrt()
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
    ];
    for (label, value) in rows {
        println!("{label:<19}{value}");
    }
    let [ordering, symbolic, numeric, solve] = a.runs;
    println!("(medians of {ordering}, {symbolic}, {numeric} and {solve} runs)");
}
