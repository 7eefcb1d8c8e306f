//! Matrices shared by the benchmarks.
#![allow(dead_code)]

use masssprings::linalg::sparse::{CscMatrix, TripletMatrix};

/// The grid-N cloth matrix of `shared/anchors.md` (lower triangle):
/// `Q = k AᵀA + M/Δt² + w CᵀC` for an N×N grid, every quad with its six
/// corner pairs as springs, k = 1e4, m = 1/N², Δt = 1/30, w = 1e10, the two
/// top corners pinned. Vertex `(i, j)` is `j·N + i`; the springs of a quad
/// couple each vertex with its eight neighbours.
pub fn grid_matrix(side: usize) -> CscMatrix {
    let n = side * side;
    let (k, mass, dt, w) = (1e4, 1.0 / n as f64, 1.0 / 30.0, 1e10);
    let mut t = TripletMatrix::with_capacity(n, n, 5 * n);
    for j in 0..side {
        for i in 0..side {
            let v = j * side + i;
            t.push(v, v, mass / (dt * dt)).unwrap();
            // springs to the neighbours after v: right, and the row below
            let neighbours = [(1, 0), (-1, 1), (0, 1), (1, 1)];
            for (di, dj) in neighbours {
                let (ii, jj) = (i as i64 + di, j as i64 + dj);
                if (0..side as i64).contains(&ii) && (jj as usize) < side {
                    let u = jj as usize * side + ii as usize;
                    t.push(v, v, k).unwrap();
                    t.push(u, u, k).unwrap();
                    t.push(u.max(v), u.min(v), -k).unwrap();
                }
            }
        }
    }
    for pinned in [0, side - 1] {
        t.push(pinned, pinned, w).unwrap();
    }
    t.to_csc()
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

/// A fixed, varied n×3 right-hand side.
pub fn right_hand_side(n: usize) -> Vec<[f64; 3]> {
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
