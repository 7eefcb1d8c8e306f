//! Time of the AMD ordering on the grid-N cloth matrices (N = 32, 100, 316;
//! N = 1000 too when `MASSSPRINGS_BENCH_LARGE=1`), next to the natural
//! ordering (the identity permutation) as the floor.
//!
//! Run with `cargo bench --bench ordering`. SuiteSparse AMD's anchors on the
//! reference machine: 0.5 ms for n = 3,200, 14 ms for grid-316.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use masssprings::linalg::sparse::amd::{amd, AmdOptions};
use masssprings::linalg::sparse::{CscMatrix, Permutation, TripletMatrix};
use std::hint::black_box;

/// The pattern of the grid-N cloth matrix (`tests/common::grid_matrix`):
/// vertex `(i, j)` is `j·N + i` and is coupled to its 8 neighbours (the six
/// springs of every quad) and to itself. Values are irrelevant to AMD.
fn grid_pattern(side: usize) -> CscMatrix {
    let n = side * side;
    let mut t = TripletMatrix::with_capacity(n, n, 9 * n);
    for j in 0..side {
        for i in 0..side {
            for dj in -1i64..=1 {
                for di in -1i64..=1 {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    if (0..side as i64).contains(&ii) && (0..side as i64).contains(&jj) {
                        let neighbour = jj as usize * side + ii as usize;
                        t.push(neighbour, j * side + i, 1.0).unwrap();
                    }
                }
            }
        }
    }
    t.to_csc()
}

fn sides() -> Vec<usize> {
    let mut sides = vec![32, 100, 316];
    if std::env::var("MASSSPRINGS_BENCH_LARGE").as_deref() == Ok("1") {
        sides.push(1000);
    }
    sides
}

fn ordering(c: &mut Criterion) {
    let mut group = c.benchmark_group("ordering");
    for side in sides() {
        let a = grid_pattern(side);
        if side >= 316 {
            group.sample_size(20);
        }
        group.bench_with_input(
            BenchmarkId::new("amd", format!("grid-{side}")),
            &a,
            |b, a| b.iter(|| amd(black_box(a), &AmdOptions::default()).unwrap()),
        );
        group.bench_with_input(
            BenchmarkId::new("natural", format!("grid-{side}")),
            &a,
            |b, a| b.iter(|| Permutation::identity(black_box(a).ncols())),
        );
    }
    group.finish();
}

criterion_group!(benches, ordering);
criterion_main!(benches);
