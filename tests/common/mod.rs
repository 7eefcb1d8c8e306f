//! Shared helpers for the tests: conversions to nalgebra (the oracle),
//! proptest strategies for random matrices, and relative comparisons.
#![allow(dead_code)]

use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::{CscMatrix, TripletMatrix};
use nalgebra::DMatrix;
use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence};

pub mod network;
pub mod student;
#[allow(unused_imports)] // not every test binary uses the networks
pub use network::*;

/// Proptest settings shared by every property test: failing seeds are kept in
/// a `.proptest-regressions` file beside the test source, committed with it.
pub fn proptest_config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..Config::default()
    }
}

/// The nalgebra copy of a dense matrix.
pub fn dense_to_nalgebra(a: &DenseMatrix) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// The nalgebra (dense) copy of a sparse matrix, built straight from the CSC
/// arrays so it does not depend on any of our own conversions.
pub fn csc_to_nalgebra(a: &CscMatrix) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(a.nrows(), a.ncols());
    for j in 0..a.ncols() {
        for p in a.col_ptr()[j]..a.col_ptr()[j + 1] {
            m[(a.row_idx()[p], j)] += a.values()[p];
        }
    }
    m
}

/// `max |a - b| ≤ tol · max(1, max |b|)`: a relative comparison of whole
/// matrices. Any NaN or infinity in either fails it.
pub fn assert_close(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64) {
    assert_eq!(a.shape(), b.shape(), "shapes differ");
    assert!(
        a.iter().chain(b.iter()).all(|v| v.is_finite()),
        "non-finite entries in {a} or {b}"
    );
    let scale = b.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    let err = (a - b).iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(
        err <= tol * scale,
        "matrices differ by {err:e} (scale {scale:e}, tolerance {tol:e})"
    );
}

/// An `nrows × ncols` triplet list with `count` random entries in `[-1, 1]`,
/// repeats allowed.
pub fn random_triplets(
    max_rows: usize,
    max_cols: usize,
    max_count: usize,
) -> impl Strategy<Value = TripletMatrix> {
    (1..=max_rows, 1..=max_cols).prop_flat_map(move |(nrows, ncols)| {
        prop::collection::vec((0..nrows, 0..ncols, -1.0f64..1.0), 0..=max_count).prop_map(
            move |entries| {
                TripletMatrix::from_entries(nrows, ncols, entries).expect("indices are in range")
            },
        )
    })
}

/// A random sparse `nrows × ncols` matrix.
pub fn random_csc(
    max_rows: usize,
    max_cols: usize,
    max_count: usize,
) -> impl Strategy<Value = CscMatrix> {
    random_triplets(max_rows, max_cols, max_count).prop_map(|t| t.to_csc())
}

/// A random sparse symmetric positive definite matrix `BᵀB + c I` with
/// `B` sparse and `c ∈ [0.1, 2]`, full (both triangles stored).
pub fn random_spd(max_n: usize, max_count: usize) -> impl Strategy<Value = CscMatrix> {
    (1..=max_n).prop_flat_map(move |n| {
        (
            prop::collection::vec((0..n, 0..n, -1.0f64..1.0), 0..=max_count),
            0.1f64..2.0,
        )
            .prop_map(move |(entries, shift)| spd_from_entries(n, &entries, shift))
    })
}

/// `BᵀB + shift·I` for the sparse `B` holding `entries`, computed densely with
/// nalgebra and then stored sparse (so it does not rely on our products).
pub fn spd_from_entries(n: usize, entries: &[(usize, usize, f64)], shift: f64) -> CscMatrix {
    let mut b = DMatrix::<f64>::zeros(n, n);
    for &(i, j, v) in entries {
        b[(i, j)] += v;
    }
    let q = b.transpose() * &b + DMatrix::identity(n, n) * shift;
    let mut t = TripletMatrix::new(n, n);
    for j in 0..n {
        for i in 0..n {
            if q[(i, j)] != 0.0 || i == j {
                t.push(i, j, q[(i, j)]).unwrap();
            }
        }
    }
    t.to_csc()
}

/// The grid-N cloth matrix of `shared/anchors.md`: `Q = k AᵀA + M/Δt² + w CᵀC`
/// for an N×N grid of vertices, one quad per cell with all six corner pairs as
/// springs, k = 1e4, m = 1/N², Δt = 1/30, w = 1e10, the two top corners pinned.
/// Built here by hand from its definition (full, both triangles).
pub fn grid_matrix(n_side: usize) -> CscMatrix {
    let n = n_side * n_side;
    let (k, m, dt, w) = (1e4, 1.0 / (n_side * n_side) as f64, 1.0 / 30.0, 1e10);
    let mut t = TripletMatrix::new(n, n);
    let vertex = |i: usize, j: usize| j * n_side + i;
    let mut springs = std::collections::BTreeSet::new();
    for j in 0..n_side - 1 {
        for i in 0..n_side - 1 {
            let corners = [
                vertex(i, j),
                vertex(i, j + 1),
                vertex(i + 1, j + 1),
                vertex(i + 1, j),
            ];
            for a in 0..4 {
                for b in a + 1..4 {
                    springs.insert((corners[a].min(corners[b]), corners[a].max(corners[b])));
                }
            }
        }
    }
    for &(a, b) in &springs {
        t.push(a, a, k).unwrap();
        t.push(b, b, k).unwrap();
        t.push(a, b, -k).unwrap();
        t.push(b, a, -k).unwrap();
    }
    for v in 0..n {
        t.push(v, v, m / (dt * dt)).unwrap();
    }
    for pinned in [vertex(0, 0), vertex(n_side - 1, 0)] {
        t.push(pinned, pinned, w).unwrap();
    }
    t.to_csc()
}
