//! Random spring networks for property tests, and an independent
//! evaluation of a step's energy (written from the handout, with no
//! cancellation care: for well-scaled tests only).

use masssprings::sim::{DELTA_T, PIN_WEIGHT};
use nalgebra::DMatrix;
use proptest::prelude::*;

/// A small random spring network: positions, springs (no self-loops),
/// masses and pins.
#[derive(Debug, Clone)]
pub struct Network {
    pub v: Vec<[f64; 3]>,
    pub springs: Vec<[usize; 2]>,
    pub masses: Vec<f64>,
    pub pinned: Vec<usize>,
    pub k: f64,
}

pub fn network(max_n: usize) -> impl Strategy<Value = Network> {
    (2..=max_n).prop_flat_map(|n| {
        (
            prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), n),
            prop::collection::vec((0..n, 1..n), 1..3 * n),
            prop::collection::vec(0.1f64..2.0, n),
            prop::collection::vec(0..n, 0..3),
            10.0f64..1000.0,
        )
            .prop_map(move |(v, pairs, masses, pinned, k)| Network {
                v,
                // (i, i + offset mod n) never joins a vertex to itself
                springs: pairs
                    .iter()
                    .map(|&(i, offset)| [i, (i + offset) % n])
                    .collect(),
                masses,
                pinned,
                k,
            })
    })
}

pub fn points_to_nalgebra(points: &[[f64; 3]]) -> DMatrix<f64> {
    DMatrix::from_fn(points.len(), 3, |i, c| points[i][c])
}

/// The objective E(p) of one step (spring energy,
/// inertia, external work, pins), the quantity the local/global iteration
/// decreases.
pub fn step_energy(
    net: &Network,
    f_ext: &[[f64; 3]],
    u_prev: &[[f64; 3]],
    u_cur: &[[f64; 3]],
    p: &[[f64; 3]],
) -> f64 {
    let dt2 = DELTA_T * DELTA_T;
    let mut energy = 0.0;
    for &[i, j] in &net.springs {
        let rest = norm(sub(net.v[i], net.v[j]));
        let length = norm(sub(p[i], p[j]));
        energy += 0.5 * net.k * (length - rest).powi(2);
    }
    for i in 0..p.len() {
        let inertial = [0, 1, 2].map(|c| p[i][c] - 2.0 * u_cur[i][c] + u_prev[i][c]);
        energy += 0.5 * net.masses[i] * dot(inertial, inertial) / dt2;
        energy -= dot(p[i], f_ext[i]);
    }
    for &i in &net.pinned {
        let off = sub(p[i], net.v[i]);
        energy += 0.5 * PIN_WEIGHT * dot(off, off);
    }
    energy
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// `x y z` per line (blank lines skipped): a reference trajectory or a
/// saved state.
///
/// # Panics
/// Naming the file, when it cannot be read or a line is not three numbers.
pub fn read_points(path: &std::path::Path) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let v: Vec<f64> = line
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}
