//! faer's sparse Cholesky timed on one matrix: the faer column of
//! `benches/peers/compare.sh` (`docs/performance.md`).
//!
//!     faer_peer MATRIX.mtx [REPEATS] [--json] [--threads N]
//!
//! `MATRIX.mtx` is a symmetric Matrix Market coordinate file (one triangle
//! stored); `MATRIX.b.mtx`, when it exists, is the n×3 right-hand side
//! (else a fixed synthetic block, the one `masssprings analyze` uses). For
//! each of faer's two LLᵀ methods (supernodal and simplicial, forced with
//! `SupernodalThreshold`), single-threaded (`Par::Seq`) or with `--threads
//! N` on faer's own parallel code (`Par::rayon(N)`, a rayon pool of N
//! threads), 32-bit indices:
//! the symbolic analysis (AMD ordering included), a numeric refactorization
//! into the same storage, and a solve of the n×3 block in place with its
//! workspace reused. Each time is the median of `REPEATS` runs (default
//! 11). faer 0.24, `faer::sparse::linalg::cholesky`.
//!
//! This is a separate crate: masssprings does not depend on it or on faer.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::prelude::*;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Side};
use std::time::Instant;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let json = args.iter().any(|a| a == "--json");
    let threads = take_threads(&mut args);
    let par = match threads {
        1 => Par::Seq,
        n => Par::rayon(n),
    };
    let positional: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let Some(path) = positional.first() else {
        eprintln!("usage: faer_peer MATRIX.mtx [REPEATS] [--json] [--threads N]");
        std::process::exit(2);
    };
    let repeats: usize = positional
        .get(1)
        .map(|r| r.parse().expect("REPEATS must be a positive integer"))
        .unwrap_or(11);
    let (n, entries) = read_symmetric(path);
    let lower = lower_triangle(n, &entries);
    let rhs = read_rhs(path, n);
    let mut report = vec![
        ("n".to_string(), n as f64),
        ("nnz_lower".to_string(), lower.compute_nnz() as f64),
        ("threads".to_string(), threads as f64),
    ];
    for (name, threshold) in [
        ("supernodal", SupernodalThreshold::FORCE_SUPERNODAL),
        ("simplicial", SupernodalThreshold::FORCE_SIMPLICIAL),
    ] {
        for (key, value) in measure(&lower, &rhs, threshold, par, repeats) {
            report.push((format!("{name}_{key}"), value));
        }
    }
    if json {
        let fields: Vec<String> = report
            .iter()
            .map(|(k, v)| format!("\"{k}\":{v:e}"))
            .collect();
        println!("{{{}}}", fields.join(","));
    } else {
        for (k, v) in &report {
            println!("{k:<24}{v:e}");
        }
    }
}

/// `--threads N` taken out of `args` (default 1).
fn take_threads(args: &mut Vec<String>) -> usize {
    let Some(at) = args.iter().position(|a| a == "--threads") else {
        return 1;
    };
    let value = args
        .get(at + 1)
        .and_then(|v| v.parse().ok())
        .filter(|&n: &usize| n >= 1);
    let Some(threads) = value else {
        eprintln!("faer_peer: --threads takes a whole number of at least 1");
        std::process::exit(2);
    };
    args.drain(at..at + 2);
    threads
}

/// Symbolic, numeric and solve times (medians), the factor's stored
/// entries and the relative residual, for one method, with the
/// parallelism `par`.
fn measure(
    lower: &SparseColMat<u32, f64>,
    rhs: &Mat<f64>,
    threshold: SupernodalThreshold,
    par: Par,
    repeats: usize,
) -> Vec<(&'static str, f64)> {
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: threshold,
        ..Default::default()
    };
    let analyse = || {
        factorize_symbolic_cholesky(
            lower.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            params,
        )
        .expect("symbolic analysis")
    };
    let symbolic_s = median_seconds(repeats, || {
        std::hint::black_box(analyse());
    });
    let symbolic = analyse();
    let mut values = vec![0.0f64; symbolic.len_val()];
    let mut factor_memory =
        MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
    let mut factor = |values: &mut [f64]| {
        symbolic
            .factorize_numeric_llt(
                values,
                lower.as_ref(),
                Side::Lower,
                LltRegularization::default(),
                par,
                MemStack::new(&mut factor_memory),
                Default::default(),
            )
            .map(|_| ())
            .expect("positive definite");
    };
    factor(&mut values); // allocates nothing more; the timed runs refactor
    let numeric_s = median_seconds(repeats, || factor(&mut values));
    let llt = symbolic
        .factorize_numeric_llt(
            &mut values,
            lower.as_ref(),
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut factor_memory),
            Default::default(),
        )
        .expect("positive definite");
    let mut solve_memory = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par));
    let mut x = rhs.clone();
    let solve_s = median_seconds(repeats, || {
        x.copy_from(rhs);
        llt.solve_in_place_with_conj(Conj::No, x.as_mut(), par, MemStack::new(&mut solve_memory));
    });
    vec![
        ("symbolic_s", symbolic_s),
        ("numeric_s", numeric_s),
        ("solve_s", solve_s),
        ("stored_l", symbolic.len_val() as f64),
        ("residual", relative_residual(lower, &x, rhs)),
    ]
}

fn median_seconds(repeats: usize, mut work: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let t = Instant::now();
            work();
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let m = times.len();
    if m % 2 == 1 {
        times[m / 2]
    } else {
        0.5 * (times[m / 2 - 1] + times[m / 2])
    }
}

/// `‖A X − B‖_F / ‖B‖_F`, `A` symmetric given by its lower triangle.
fn relative_residual(lower: &SparseColMat<u32, f64>, x: &Mat<f64>, b: &Mat<f64>) -> f64 {
    let mut ax = Mat::<f64>::zeros(b.nrows(), b.ncols());
    let col_ptr = lower.symbolic().col_ptr();
    let row_idx = lower.symbolic().row_idx();
    let values = lower.val();
    for j in 0..lower.ncols() {
        for p in col_ptr[j] as usize..col_ptr[j + 1] as usize {
            let i = row_idx[p] as usize;
            for c in 0..b.ncols() {
                ax[(i, c)] += values[p] * x[(j, c)];
                if i != j {
                    ax[(j, c)] += values[p] * x[(i, c)];
                }
            }
        }
    }
    let (mut error, mut norm) = (0.0, 0.0);
    for c in 0..b.ncols() {
        for i in 0..b.nrows() {
            error += (ax[(i, c)] - b[(i, c)]).powi(2);
            norm += b[(i, c)].powi(2);
        }
    }
    (error / norm).sqrt()
}

/// Lines of a Matrix Market file that carry data (no comments, no blanks).
fn data_lines(text: &str) -> impl Iterator<Item = &str> {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('%'))
}

/// The numbers of the size line (the first data line).
fn size_line<'a>(lines: &mut impl Iterator<Item = &'a str>) -> Vec<usize> {
    lines
        .next()
        .expect("size line")
        .split_whitespace()
        .map(|t| t.parse().expect("size"))
        .collect()
}

/// `(n, entries)` of a square symmetric coordinate file, 0-based.
fn read_symmetric(path: &str) -> (usize, Vec<(usize, usize, f64)>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let header = text.lines().next().unwrap_or("").to_lowercase();
    assert!(
        header.contains("coordinate") && header.contains("symmetric"),
        "{path}: expected a symmetric coordinate Matrix Market file"
    );
    let mut lines = data_lines(&text);
    let size = size_line(&mut lines);
    assert!(
        size.len() == 3 && size[0] == size[1],
        "{path}: square matrix expected"
    );
    let entries = lines
        .map(|line| {
            let mut t = line.split_whitespace();
            let i: usize = t.next().unwrap().parse().unwrap();
            let j: usize = t.next().unwrap().parse().unwrap();
            let v: f64 = t.next().unwrap().parse().unwrap();
            (i - 1, j - 1, v)
        })
        .collect();
    (size[0], entries)
}

/// The lower triangle (each stored entry moved below the diagonal).
fn lower_triangle(n: usize, entries: &[(usize, usize, f64)]) -> SparseColMat<u32, f64> {
    let triplets: Vec<Triplet<u32, u32, f64>> = entries
        .iter()
        .map(|&(i, j, v)| Triplet::new(i.max(j) as u32, i.min(j) as u32, v))
        .collect();
    SparseColMat::try_new_from_triplets(n, n, &triplets).expect("valid matrix")
}

/// `MATRIX.b.mtx` (an n×3 array) when it exists, else the synthetic block
/// of `masssprings analyze`.
fn read_rhs(path: &str, n: usize) -> Mat<f64> {
    let b_path = path.strip_suffix(".mtx").unwrap_or(path).to_string() + ".b.mtx";
    match std::fs::read_to_string(&b_path) {
        Ok(text) => {
            let mut lines = data_lines(&text);
            let size = size_line(&mut lines);
            assert!(size == [n, 3], "{b_path}: expected an {n}×3 array");
            let values: Vec<f64> = lines.map(|l| l.parse().expect("number")).collect();
            Mat::from_fn(n, 3, |i, c| values[c * n + i]) // column-major
        }
        Err(_) => Mat::from_fn(n, 3, |i, c| {
            let t = i as f64;
            [
                1.0 + (t * 0.37).sin(),
                (t * 0.11).cos(),
                0.5 - (t * 0.23).sin(),
            ][c]
        }),
    }
}
