//! `masssprings analyze MATRIX.mtx`: the sparse Cholesky pipeline on one
//! matrix, timed step by step.

use super::analysis::{analyze, Analysis, HowFactored};
use super::error::AppError;
use super::flags::{whole, FactorFlags, JsonFlag};
use super::matrix_input::read_symmetric_lower;
use super::timing::Repeats;
use masssprings::linalg::benchmark_right_hand_side;
use masssprings::matrix_market::{self, MatrixMarket};
use std::path::{Path, PathBuf};

/// Sparse Cholesky of a Matrix Market matrix, timed step by step.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Sparse Cholesky of a symmetric positive definite Matrix Market matrix: n,
nnz, nnz(L), flops, median times of ordering, symbolic analysis, numeric
factorization and a 3-column solve, its relative residual and its backward
error (the relative residual can be large for an accurate solve of a matrix
with huge entries, such as the pins' w = 1e10; the backward error cannot),
and for the supernodal factorization the supernodes by width with their
share of L. On more than one thread (--threads, default: the cores
available) the numeric factorization and the solve are also timed on one,
in interleaved rounds: the speedup, and whether the two solutions are the
same to the bit (they are). The right-hand side is MATRIX.b.mtx (an n×3
array) when it exists.")]
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
    let how = HowFactored {
        ordering: args.factor.ordering.ordering,
        method: args.factor.factorization,
        relaxation,
        threads: args.factor.threads.count(),
    };
    let analysis = analyze(&lower, &rhs, how, repeats)
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

/// The threads, and with more than one the speedups over one thread.
fn threads_line(a: &Analysis) -> String {
    match &a.one_thread {
        None => a.threads.to_string(),
        Some(one) => format!(
            "{}  (over 1 thread: numeric {:.2}×, solve {:.2}×; same bits: {})",
            a.threads,
            one.numeric_speedup,
            one.solve_speedup,
            if one.same_bits { "yes" } else { "NO" }
        ),
    }
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
        ("threads", threads_line(a)),
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
