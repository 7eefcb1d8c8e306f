//! Time of the AMD ordering on the `Q` of the flag, the skirt and the
//! grid-N cloths (N = 32, 100, 316; N = 1000 too when
//! `MASSSPRINGS_BENCH_LARGE=1`), next to the natural ordering (the identity
//! permutation) as the floor.
//!
//! Run with `cargo bench -p masssprings-benches --bench ordering`; SuiteSparse AMD on the same
//! matrices: `benches/peers/cholmod_peer` (`docs/performance.md`).

use bench_common::{assignment_scene, grid_scene, grid_sides, q_matrix};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use masssprings::linalg::sparse::amd::{amd, AmdOptions};
use masssprings::linalg::sparse::Permutation;
use std::hint::black_box;

fn ordering(c: &mut Criterion) {
    let mut group = c.benchmark_group("ordering");
    let mut matrices: Vec<(String, usize)> = vec![("flag".into(), 0), ("skirt".into(), 0)];
    matrices.extend(
        grid_sides()
            .into_iter()
            .map(|side| (format!("grid-{side}"), side)),
    );
    for (name, side) in matrices {
        let scene = if side == 0 {
            assignment_scene(&name)
        } else {
            grid_scene(side)
        };
        let a = q_matrix(&scene);
        if side >= 316 {
            group.sample_size(20);
        }
        group.bench_with_input(BenchmarkId::new("amd", &name), &a, |b, a| {
            b.iter(|| amd(black_box(a), &AmdOptions::default()).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("natural", &name), &a, |b, a| {
            b.iter(|| Permutation::identity(black_box(a).ncols()))
        });
    }
    group.finish();
}

criterion_group!(benches, ordering);
criterion_main!(benches);
