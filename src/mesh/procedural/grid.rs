//! `grid-N`: the square cloth the benchmarks are measured on.
//!
//! `N × N` vertices on the unit square in the plane `z = 0`: vertex
//! `j·N + i` (row `j` from the top, column `i` from the left) sits at
//! `(i/(N−1), 1 − j/(N−1), 0)`. Each of the `(N−1)²` cells is one quad with
//! corners `(i, j), (i, j+1), (i+1, j+1), (i+1, j)`, which the loader turns
//! into its 4 sides and 2 diagonals. `k = 1e4`, a uniform `m = 1/N²` (total
//! mass 1), and the two top corners (`j = 0`, `i = 0` and `i = N−1`) pinned.
//!
//! The files are byte for byte those of `tools/eigen-ref/ref grid N`
//! (the reference tool that made `tests/fixtures/reference/`): numbers as `%.17g`, no
//! comment, the JSON `{"obj":"grid-N.obj","k":10000,"m":…,"b":[1,N]}`.
//!
//! Cost: `O(N²)`.

use super::{GeneratedMesh, GeneratedScene};

/// The `grid-N` scene.
///
/// # Panics
/// If `n < 2` (a grid needs at least one cell).
pub fn grid(n: usize) -> GeneratedScene {
    assert!(n >= 2, "grid N needs N ≥ 2, got {n}");
    let last = (n - 1) as f64;
    let mut vertices = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            vertices.push([i as f64 / last, 1.0 - j as f64 / last, 0.0]);
        }
    }
    let vertex = |i: usize, j: usize| j * n + i;
    let mut faces = Vec::with_capacity(4 * (n - 1) * (n - 1));
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            faces.extend([
                vertex(i, j),
                vertex(i, j + 1),
                vertex(i + 1, j + 1),
                vertex(i + 1, j),
            ]);
        }
    }
    GeneratedScene {
        name: format!("grid-{n}"),
        description: None,
        mesh: GeneratedMesh {
            vertices,
            corners_per_face: 4,
            faces,
            ..GeneratedMesh::default()
        },
        k: 1e4,
        uniform_mass: Some(1.0 / (n as f64 * n as f64)),
        pinned: vec![vertex(0, 0), vertex(n - 1, 0)],
        texture: None,
    }
}
