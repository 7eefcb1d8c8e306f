//! Sparse Cholesky on the `Q` of the flag, the skirt and the grid-N
//! cloths: symbolic analysis, numeric factorization (simplicial and
//! supernodal) and the 3-column solve.
//!
//! `cargo bench -p masssprings-benches --bench cholesky`; add `MASSSPRINGS_BENCH_LARGE=1` for
//! grid-1000. Compare with the peers (`benches/peers/`, `eigen-ref bench`)
//! run in the same session; `docs/performance.md` has the figures.

use bench_common::{assignment_scene, grid_scene, grid_sides, q_matrix};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use masssprings::linalg::benchmark_right_hand_side as right_hand_side;
use masssprings::linalg::sparse::{Method, Ordering, SparseCholesky, SymbolicCholesky};
use std::hint::black_box;
use std::time::Duration;

/// The matrices to run: flag, skirt, then the grids.
fn matrices() -> Vec<(String, usize, masssprings::linalg::sparse::CscMatrix)> {
    let mut list = vec![];
    for name in ["flag", "skirt"] {
        list.push((name.to_string(), 0, q_matrix(&assignment_scene(name))));
    }
    for side in grid_sides() {
        list.push((format!("grid-{side}"), side, q_matrix(&grid_scene(side))));
    }
    list
}

fn configure(group: &mut criterion::BenchmarkGroup<criterion::measurement::WallTime>, side: usize) {
    if side >= 316 {
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(if side >= 1000 { 60 } else { 10 }));
    }
}

fn symbolic(c: &mut Criterion) {
    let mut group = c.benchmark_group("symbolic");
    for (name, side, q) in matrices() {
        let perm = Ordering::Amd.permutation(&q).unwrap();
        configure(&mut group, side);
        group.bench_function(BenchmarkId::from_parameter(&name), |b| {
            b.iter(|| SymbolicCholesky::with_permutation(black_box(&q), &perm).unwrap())
        });
    }
    group.finish();
}

fn numeric(c: &mut Criterion) {
    let mut group = c.benchmark_group("numeric");
    for (name, side, q) in matrices() {
        let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
        configure(&mut group, side);
        for (method_name, method) in [
            ("supernodal", Method::Supernodal),
            ("simplicial", Method::Simplicial),
        ] {
            if side >= 1000 && method == Method::Simplicial {
                continue; // minutes per sample; the ratio is clear from grid-316
            }
            let mut cholesky = SparseCholesky::factor(symbolic.clone(), &q, method).unwrap();
            group.bench_function(BenchmarkId::new(method_name, &name), |b| {
                b.iter(|| cholesky.refactor(black_box(&q)).unwrap())
            });
        }
    }
    group.finish();
}

fn solve(c: &mut Criterion) {
    let mut group = c.benchmark_group("solve_3_columns");
    for (name, side, q) in matrices() {
        let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
        let rhs = right_hand_side(q.ncols());
        let mut x = rhs.clone();
        configure(&mut group, side);
        // the supernodal solve sweeps panels of columns, the simplicial one
        // column by column (docs/performance.md compares them)
        for (method_name, method) in [
            ("supernodal", Method::Supernodal),
            ("simplicial", Method::Simplicial),
        ] {
            let mut cholesky = SparseCholesky::factor(symbolic.clone(), &q, method).unwrap();
            group.bench_function(BenchmarkId::new(method_name, &name), |b| {
                b.iter(|| {
                    x.copy_from_slice(&rhs);
                    cholesky.solve_points_in_place(black_box(&mut x));
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, symbolic, numeric, solve);
criterion_main!(benches);
