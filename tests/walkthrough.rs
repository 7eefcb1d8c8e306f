//! The worked example of `docs/sparse-cholesky.md`, step by step: every
//! number the chapter shows is checked here, so the chapter cannot drift
//! from the code.

use masssprings::linalg::sparse::column_counts::column_counts;
use masssprings::linalg::sparse::etree::elimination_tree;
use masssprings::linalg::sparse::postorder::postorder;
use masssprings::linalg::sparse::{
    CscMatrix, Method, Ordering, PermutedTriangle, SparseCholesky, SymbolicCholesky, Triangle,
    TripletMatrix,
};

/// A star of four springs around vertex 0, k = 1, m = 1, Δt = 1:
/// `Q = AᵀA + I` (no pins), assembled from triplets.
fn star() -> CscMatrix {
    let springs = [[0, 1], [0, 2], [0, 3], [0, 4]];
    let mut q = TripletMatrix::new(5, 5);
    for [i, j] in springs {
        // k AᵀA: +1 on both diagonals, −1 off the diagonal, per spring
        q.push(i, i, 1.0).unwrap();
        q.push(j, j, 1.0).unwrap();
        q.push(i, j, -1.0).unwrap();
        q.push(j, i, -1.0).unwrap();
    }
    for v in 0..5 {
        q.push(v, v, 1.0).unwrap(); // M/Δt²
    }
    q.to_csc()
}

#[test]
fn step_1_triplets_compress_to_csc() {
    let lower = star().triangle(Triangle::Lower);
    assert_eq!(lower.col_ptr(), [0, 5, 6, 7, 8, 9]);
    assert_eq!(lower.row_idx(), [0, 1, 2, 3, 4, 1, 2, 3, 4]);
    assert_eq!(
        lower.values(),
        [5.0, -1.0, -1.0, -1.0, -1.0, 2.0, 2.0, 2.0, 2.0]
    );
}

#[test]
fn step_2_the_natural_order_fills_in_and_amd_does_not() {
    let q = star();
    let natural = SymbolicCholesky::analyze(&q, Ordering::Natural).unwrap();
    let amd = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
    assert_eq!(natural.nnz_l(), 15); // hub first: L is full
    assert_eq!(amd.nnz_l(), 9); // hub last: no fill at all
    assert_eq!(
        Ordering::Amd.permutation(&q).unwrap().perm(),
        [4, 3, 2, 1, 0]
    );
}

#[test]
fn step_3_to_5_tree_postorder_and_counts() {
    let q = star();
    let p = Ordering::Amd.permutation(&q).unwrap();
    let upper = PermutedTriangle::new(&q, &p, Triangle::Upper).unwrap();
    let lower = PermutedTriangle::new(&q, &p, Triangle::Lower).unwrap();
    // P Q Pᵀ: the hub is now unknown 4
    assert_eq!(lower.matrix().col_ptr(), [0, 2, 4, 6, 8, 9]);
    assert_eq!(lower.matrix().row_idx(), [0, 4, 1, 4, 2, 4, 3, 4, 4]);
    let parent = elimination_tree(upper.matrix());
    assert_eq!(parent, [Some(4), Some(4), Some(4), Some(4), None]);
    let post = postorder(&parent);
    assert_eq!(post, [0, 1, 2, 3, 4]);
    assert_eq!(
        column_counts(lower.matrix(), &parent, &post),
        [2, 2, 2, 2, 1]
    );
}

#[test]
fn step_6_symbolic_analysis_all_at_once() {
    let symbolic = SymbolicCholesky::analyze(&star(), Ordering::Amd).unwrap();
    assert_eq!(symbolic.col_ptr(), [0, 2, 4, 6, 8, 9]);
    assert_eq!(symbolic.row_idx(), [0, 4, 1, 4, 2, 4, 3, 4, 4]);
    assert_eq!(symbolic.flops(), 17.0); // 4·2² + 1²
                                        // the last leaf and the hub share a pattern: one supernode {3, 4}
    assert_eq!(symbolic.supernodes().len(), 4);
    assert_eq!(symbolic.supernodes().columns(3), 3..5);
}

#[test]
fn step_7_numeric_factor_and_solve() {
    let q = star();
    let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
    for method in [Method::Simplicial, Method::Supernodal] {
        let mut cholesky = SparseCholesky::factor(symbolic.clone(), &q, method).unwrap();
        let l = cholesky.l();
        let (s2, s3) = (2f64.sqrt(), 3f64.sqrt());
        let expected = [
            s2,
            -1.0 / s2,
            s2,
            -1.0 / s2,
            s2,
            -1.0 / s2,
            s2,
            -1.0 / s2,
            s3,
        ];
        for (got, want) in l.values().iter().zip(expected) {
            assert!((got - want).abs() < 1e-15, "{method:?}: {got} vs {want}");
        }
        // Q x = b for b = Q·(1, 2, 3, 4, 5): x comes back
        let b = [
            [5.0 - 2.0 - 3.0 - 4.0 - 5.0; 3],
            [4.0 - 1.0; 3],
            [6.0 - 1.0; 3],
            [8.0 - 1.0; 3],
            [10.0 - 1.0; 3],
        ];
        let mut x = b;
        cholesky.solve_points_in_place(&mut x);
        for (i, xi) in x.iter().enumerate() {
            assert!(
                (xi[0] - (i + 1) as f64).abs() < 1e-14,
                "{method:?}: x[{i}] = {xi:?}"
            );
        }
    }
}
