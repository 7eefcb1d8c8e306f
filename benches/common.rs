//! Scenes and matrices shared by the benchmarks, built through the library
//! itself: the grid-N cloth (`masssprings generate grid N`) is generated, written
//! and read back as a scene, and its `Q` comes from the precomputation.

use masssprings::linalg::sparse::{CscMatrix, Triangle};
use masssprings::mesh::procedural::grid;
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::precomputation::scene_q;
use masssprings::sim::DELTA_T;
use std::path::{Path, PathBuf};

/// The grid-N scene (`masssprings generate grid N`), read back from a
/// temporary folder.
pub fn grid_scene(side: usize) -> Scene {
    let folder = std::env::temp_dir().join(format!("masssprings-bench-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let generated = grid(side);
    let obj = folder.join(generated.obj_file_name());
    let json = folder.join(generated.json_file_name());
    generated
        .write_obj(&mut std::fs::File::create(&obj).unwrap())
        .unwrap();
    std::fs::write(&json, generated.json_text()).unwrap();
    let scene = load_scene(&json).unwrap();
    let _ = std::fs::remove_dir_all(&folder);
    scene
}

/// The repository's top folder (this package is its `benches/`).
pub fn repository_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// One of the assignment's scenes from `../shared/original-data/`, if that
/// folder is there; else the project's own version from `data/`.
pub fn assignment_scene(name: &str) -> Scene {
    let root = repository_root();
    let shared = root.join(format!("../shared/original-data/{name}.json"));
    let path: PathBuf = if shared.exists() {
        shared
    } else {
        root.join(format!("data/{name}.json"))
    };
    load_scene(&path).unwrap()
}

/// `Q = k AᵀA + M/Δt² + w CᵀC` of a scene, lower triangle, assembled
/// without factoring it.
pub fn q_matrix(scene: &Scene) -> CscMatrix {
    scene_q(scene, DELTA_T).triangle(Triangle::Lower)
}

/// Grid sizes to run: 32, 100, 316, and 1000 when
/// `MASSSPRINGS_BENCH_LARGE=1`.
pub fn grid_sides() -> Vec<usize> {
    let mut sides = vec![32, 100, 316];
    if std::env::var("MASSSPRINGS_BENCH_LARGE").as_deref() == Ok("1") {
        sides.push(1000);
    }
    sides
}
