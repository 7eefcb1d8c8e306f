//! One full time step (50 local/global iterations, the assignment's
//! semantics) on the flag, the skirt, grid-100 and grid-316 (grid-1000 with
//! `MASSSPRINGS_BENCH_LARGE=1`), sparse. Compare with
//! `shared/tools/eigen-ref/ref bench SCENE.json` run in the same session;
//! `docs/performance.md` has the figures.

use bench_common::{assignment_scene, grid_scene};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Simulation, Sparse};
use std::time::Duration;

fn scenes() -> Vec<(String, Scene)> {
    let mut list: Vec<(String, Scene)> = ["flag", "skirt"]
        .into_iter()
        .map(|name| (name.to_string(), assignment_scene(name)))
        .collect();
    let mut sides = vec![100, 316];
    if std::env::var("MASSSPRINGS_BENCH_LARGE").as_deref() == Ok("1") {
        sides.push(1000);
    }
    for side in sides {
        list.push((format!("grid-{side}"), grid_scene(side)));
    }
    list
}

fn full_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    for (name, scene) in scenes() {
        let n = scene.vertices.len();
        if n > 50_000 {
            group.sample_size(10);
            group.measurement_time(Duration::from_secs(if n > 500_000 { 120 } else { 20 }));
        }
        let mut simulation =
            Simulation::<Sparse>::from_scene(&scene, SimulationOptions::default()).unwrap();
        // the cloth keeps moving, so every sample is a real step of a run
        group.bench_function(BenchmarkId::from_parameter(&name), |b| {
            b.iter(|| simulation.step().unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, full_step);
criterion_main!(benches);
