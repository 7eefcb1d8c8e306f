//! Sparse Cholesky on the grid-N cloth matrices: symbolic analysis, numeric
//! factorization (simplicial and supernodal) and the 3-column solve.
//!
//! `cargo bench --bench cholesky`; add `MASSSPRINGS_BENCH_LARGE=1` for
//! grid-1000. Compare with the peers (`benches/peers/`, `eigen-ref bench`)
//! run in the same session; `docs/performance.md` has the figures.

mod common;

use common::{grid_matrix, grid_sides, right_hand_side};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use masssprings::linalg::sparse::{Method, Ordering, SparseCholesky, SymbolicCholesky};
use std::hint::black_box;
use std::time::Duration;

fn configure(group: &mut criterion::BenchmarkGroup<criterion::measurement::WallTime>, side: usize) {
    if side >= 316 {
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(if side >= 1000 { 60 } else { 10 }));
    }
}

fn symbolic(c: &mut Criterion) {
    let mut group = c.benchmark_group("symbolic");
    for side in grid_sides() {
        let q = grid_matrix(side);
        let perm = Ordering::Amd.permutation(&q).unwrap();
        configure(&mut group, side);
        group.bench_function(BenchmarkId::from_parameter(format!("grid-{side}")), |b| {
            b.iter(|| SymbolicCholesky::with_permutation(black_box(&q), &perm).unwrap())
        });
    }
    group.finish();
}

fn numeric(c: &mut Criterion) {
    let mut group = c.benchmark_group("numeric");
    for side in grid_sides() {
        let q = grid_matrix(side);
        let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
        configure(&mut group, side);
        for (name, method) in [
            ("supernodal", Method::Supernodal),
            ("simplicial", Method::Simplicial),
        ] {
            if side >= 1000 && method == Method::Simplicial {
                continue; // minutes per sample; the ratio is clear from grid-316
            }
            let mut cholesky = SparseCholesky::factor(symbolic.clone(), &q, method).unwrap();
            group.bench_function(BenchmarkId::new(name, format!("grid-{side}")), |b| {
                b.iter(|| cholesky.refactor(black_box(&q)).unwrap())
            });
        }
    }
    group.finish();
}

fn solve(c: &mut Criterion) {
    let mut group = c.benchmark_group("solve_3_columns");
    for side in grid_sides() {
        let q = grid_matrix(side);
        let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
        let mut cholesky = SparseCholesky::factor(symbolic, &q, Method::Supernodal).unwrap();
        let rhs = right_hand_side(q.ncols());
        let mut x = rhs.clone();
        configure(&mut group, side);
        group.bench_function(BenchmarkId::from_parameter(format!("grid-{side}")), |b| {
            b.iter(|| {
                x.copy_from_slice(&rhs);
                cholesky.solve_points_in_place(black_box(&mut x));
            })
        });
    }
    group.finish();
}

criterion_group!(benches, symbolic, numeric, solve);
criterion_main!(benches);
