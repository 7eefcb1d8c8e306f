//! One student file through everything `trace --compare` does with a
//! file, against a small trace of ours: read as each quantity's shape
//! (`conform`), compared entry by entry, read as an `A` (its springs
//! matched to ours), as a `P` and as an `L` (`L Lᵀ = P Q Pᵀ`). Shared by
//! the mutation test (`tests/hostile.rs`) and the fuzz target
//! `trace_compare`, which include it beside the binary's files
//! `src/app/trace/compare/{entries,springs,factor}.rs` as they are.
#![allow(dead_code)]

use super::entries::{conform, dense_difference, sparse_difference, to_sparse, RowKind};
use super::factor::{above_diagonal, permutation_of, product_difference};
use super::springs::{match_springs, mismatch, springs_of, Row};
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::{CscMatrix, TripletMatrix};
use masssprings::matrix_market::MatrixMarket;

/// Our small scene: 4 vertices, vertex 0 pinned.
pub const N: usize = 4;
/// Its springs, one of them twice (a scene may repeat a spring).
pub const SPRINGS: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2], [0, 1]];

/// `Q = k AᵀA + I + w CᵀC` of the small scene: symmetric positive definite.
pub fn our_q() -> CscMatrix {
    let mut q = TripletMatrix::new(N, N);
    for [i, j] in SPRINGS {
        for (r, c, v) in [(i, i, 10.0), (j, j, 10.0), (i, j, -10.0), (j, i, -10.0)] {
            q.push(r, c, v).unwrap();
        }
    }
    for v in 0..N {
        q.push(v, v, if v == 0 { 1e10 } else { 1.0 }).unwrap();
    }
    q.to_csc()
}

/// What became of a file: how many of the checks compared it, and how
/// many refused it with a reason.
#[derive(Debug, Default, Clone, Copy)]
pub struct Tally {
    pub compared: usize,
    pub refused: usize,
}

impl Tally {
    fn count<T>(&mut self, result: &Result<T, String>) {
        match result {
            Ok(_) => self.compared += 1,
            Err(reason) => {
                assert!(!reason.is_empty());
                self.refused += 1;
            }
        }
    }
}

/// Every check of `--compare` on `their`; panics only if one does.
pub fn compare_everything(their: &MatrixMarket) -> Tally {
    let mut tally = Tally::default();
    let kinds = [RowKind::Pinned, RowKind::Free, RowKind::Skipped];
    let m = SPRINGS.len();
    for (shape, dense, diagonal) in [
        ((m, 1), true, false),
        ((N, 3), true, false),
        ((N, N), false, true),
    ] {
        let conformed = conform(their.clone(), shape, dense, diagonal);
        tally.count(&conformed);
        match conformed {
            Ok(MatrixMarket::Dense(yours)) => {
                let ours = DenseMatrix::zeros(shape.0, shape.1);
                let largest = dense_difference(&ours, &yours, None, &kinds);
                assert!(largest.overall().is_some());
            }
            Ok(sparse) => {
                let yours = to_sparse(&sparse).unwrap();
                let _ = sparse_difference(&our_q(), &yours, &kinds).shown(1e-12);
            }
            Err(_) => {}
        }
    }
    let Ok(a) = to_sparse(their) else {
        tally.refused += 1;
        return tally;
    };
    springs(&a, &mut tally);
    factor(&a, &mut tally);
    tally
}

/// `a` read as an `A`: its springs matched to ours.
fn springs(a: &CscMatrix, tally: &mut Tally) {
    if a.ncols() != N {
        return;
    }
    let ours: Vec<Row> = SPRINGS.iter().map(|&ends| Row::Spring(ends)).collect();
    let theirs = springs_of(a);
    tally.count(&theirs);
    let Ok(theirs) = theirs else { return };
    assert_eq!(theirs.len(), a.nrows());
    let matching = match_springs(&ours, &theirs);
    tally.count(&matching);
    let Ok(matching) = matching else { return };
    let message = mismatch(&ours, &theirs, &matching);
    assert_eq!(message.is_none(), matching.is_permutation());
    let _ = (matching.is_identity(), matching.moved_and_reversed());
}

/// `a` read as a `P` and as an `L`.
fn factor(a: &CscMatrix, tally: &mut Tally) {
    if (a.nrows(), a.ncols()) != (N, N) {
        return;
    }
    let perm = permutation_of(a);
    tally.count(&perm);
    if above_diagonal(a).is_some() {
        return;
    }
    let kinds = [RowKind::Pinned, RowKind::Free, RowKind::Free, RowKind::Free];
    for perm in [vec![0, 1, 2, 3], vec![3, 1, 0, 2]] {
        let largest = product_difference(a, &our_q(), &perm, &kinds);
        tally.count(&largest);
    }
}
