//! The CSC operations, each checked against nalgebra on random matrices.
use crate::common;

use common::*;
use masssprings::linalg::sparse::{CscMatrix, Permutation, PermutedTriangle, Triangle};
use masssprings::linalg::LinalgError;
use nalgebra::DMatrix;
use proptest::prelude::*;

fn points_to_nalgebra(points: &[[f64; 3]]) -> DMatrix<f64> {
    DMatrix::from_fn(points.len(), 3, |i, c| points[i][c])
}

fn random_points(n: usize) -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), n)
}

/// A random matrix and a random `ncols`-vector.
fn matrix_and_vector() -> impl Strategy<Value = (CscMatrix, Vec<f64>)> {
    random_csc(12, 12, 60).prop_flat_map(|a| {
        let n = a.ncols();
        (Just(a), prop::collection::vec(-1.0f64..1.0, n))
    })
}

fn matrix_and_points(transposed: bool) -> impl Strategy<Value = (CscMatrix, Vec<[f64; 3]>)> {
    random_csc(12, 12, 60).prop_flat_map(move |a| {
        let n = if transposed { a.nrows() } else { a.ncols() };
        (Just(a), random_points(n))
    })
}

/// Two random matrices of the same shape.
fn same_shape_pair() -> impl Strategy<Value = (CscMatrix, CscMatrix)> {
    (1..=10usize, 1..=10usize).prop_flat_map(|(m, n)| {
        let entries = move || prop::collection::vec((0..m, 0..n, -1.0f64..1.0), 0..40);
        (entries(), entries()).prop_map(move |(a, b)| {
            let build = |e: Vec<(usize, usize, f64)>| {
                masssprings::linalg::sparse::TripletMatrix::from_entries(m, n, e)
                    .unwrap()
                    .to_csc()
            };
            (build(a), build(b))
        })
    })
}

/// Two random matrices with `A.ncols == B.nrows`.
fn product_pair() -> impl Strategy<Value = (CscMatrix, CscMatrix)> {
    (1..=10usize, 1..=10usize, 1..=10usize).prop_flat_map(|(m, k, n)| {
        let a = prop::collection::vec((0..m, 0..k, -1.0f64..1.0), 0..40);
        let b = prop::collection::vec((0..k, 0..n, -1.0f64..1.0), 0..40);
        (a, b).prop_map(move |(a, b)| {
            let t = masssprings::linalg::sparse::TripletMatrix::from_entries;
            (t(m, k, a).unwrap().to_csc(), t(k, n, b).unwrap().to_csc())
        })
    })
}

fn random_permutation(n: usize) -> impl Strategy<Value = Permutation> {
    Just((0..n).collect::<Vec<_>>())
        .prop_shuffle()
        .prop_map(|p| Permutation::from_perm(p).unwrap())
}

proptest! {
    #![proptest_config(proptest_config(256))]

    #[test]
    fn transpose_matches_nalgebra(a in random_csc(12, 12, 60)) {
        let t = a.transpose();
        prop_assert_eq!(csc_to_nalgebra(&t), csc_to_nalgebra(&a).transpose());
        prop_assert_eq!(t.transpose(), a);
    }

    #[test]
    fn matrix_vector_product_matches_nalgebra((a, x) in matrix_and_vector()) {
        let mut y = vec![0.0; a.nrows()];
        a.mul_vec(&x, &mut y).unwrap();
        let oracle = csc_to_nalgebra(&a) * DMatrix::from_column_slice(x.len(), 1, &x);
        assert_close(&DMatrix::from_column_slice(y.len(), 1, &y), &oracle, 1e-14);
    }

    #[test]
    fn matrix_points_product_matches_nalgebra((a, x) in matrix_and_points(false)) {
        let mut y = vec![[0.0; 3]; a.nrows()];
        a.mul_points(&x, &mut y).unwrap();
        let oracle = csc_to_nalgebra(&a) * points_to_nalgebra(&x);
        assert_close(&points_to_nalgebra(&y), &oracle, 1e-14);
    }

    #[test]
    fn transpose_points_product_matches_nalgebra((a, x) in matrix_and_points(true)) {
        let mut y = vec![[0.0; 3]; a.ncols()];
        a.transpose_mul_points(&x, &mut y).unwrap();
        let oracle = csc_to_nalgebra(&a).transpose() * points_to_nalgebra(&x);
        assert_close(&points_to_nalgebra(&y), &oracle, 1e-14);
    }

    #[test]
    fn scaled_sum_matches_nalgebra((a, b) in same_shape_pair(), alpha in -2.0f64..2.0, beta in -2.0f64..2.0) {
        let c = a.add_scaled(alpha, &b, beta).unwrap();
        let oracle = csc_to_nalgebra(&a) * alpha + csc_to_nalgebra(&b) * beta;
        assert_close(&csc_to_nalgebra(&c), &oracle, 1e-14);
        let union: std::collections::BTreeSet<_> = [&a, &b].iter()
            .flat_map(|m| (0..m.ncols()).flat_map(move |j| m.column(j).0.iter().map(move |&i| (i, j))))
            .collect();
        prop_assert_eq!(c.nnz(), union.len());
    }

    #[test]
    fn scaling_matches_nalgebra(a in random_csc(12, 12, 60), s in -3.0f64..3.0) {
        assert_close(&csc_to_nalgebra(&a.scale(s)), &(csc_to_nalgebra(&a) * s), 1e-15);
    }

    #[test]
    fn sparse_product_matches_nalgebra((a, b) in product_pair()) {
        let c = a.mul(&b).unwrap();
        assert_close(&csc_to_nalgebra(&c), &(csc_to_nalgebra(&a) * csc_to_nalgebra(&b)), 1e-14);
        for j in 0..c.ncols() {
            prop_assert!(c.column(j).0.windows(2).all(|w| w[0] < w[1]));
        }
    }

    #[test]
    fn gram_product_matches_nalgebra(a in random_csc(12, 12, 60)) {
        let dense = csc_to_nalgebra(&a);
        assert_close(&csc_to_nalgebra(&a.transpose_mul_self()), &(dense.transpose() * &dense), 1e-14);
    }

    #[test]
    fn diagonal_and_dense_copy_match_nalgebra(a in random_csc(12, 12, 60)) {
        let dense = csc_to_nalgebra(&a);
        let square = a.nrows().min(a.ncols());
        let oracle: Vec<f64> = (0..square).map(|i| dense[(i, i)]).collect();
        prop_assert_eq!(a.diagonal(), oracle);
        prop_assert_eq!(dense_to_nalgebra(&a.to_dense()), dense);
    }

    #[test]
    fn symmetric_permutation_matches_nalgebra(
        (a, p) in random_spd(12, 40).prop_flat_map(|a| { let n = a.ncols(); (Just(a), random_permutation(n)) }),
        upper_target in any::<bool>(),
    ) {
        let target = if upper_target { Triangle::Upper } else { Triangle::Lower };
        let c = PermutedTriangle::new(&a.triangle(Triangle::Lower), &p, target).unwrap();
        let dense = csc_to_nalgebra(&a);
        let n = a.ncols();
        let oracle = DMatrix::from_fn(n, n, |i, j| {
            if target.contains(i, j) { dense[(p.perm()[i], p.perm()[j])] } else { 0.0 }
        });
        prop_assert_eq!(csc_to_nalgebra(c.matrix()), oracle);
    }

    #[test]
    fn refilling_a_permuted_triangle_equals_permuting_afresh(
        (a, p) in random_spd(10, 30).prop_flat_map(|a| { let n = a.ncols(); (Just(a), random_permutation(n)) }),
        s in 0.5f64..2.0,
    ) {
        let lower = a.triangle(Triangle::Lower);
        let mut c = PermutedTriangle::new(&lower, &p, Triangle::Upper).unwrap();
        let scaled = lower.scale(s);
        c.refill(&scaled).unwrap();
        let fresh = PermutedTriangle::new(&scaled, &p, Triangle::Upper).unwrap();
        prop_assert_eq!(c.matrix(), fresh.matrix());
    }
}

#[test]
fn products_with_wrong_shapes_are_errors() {
    let a = CscMatrix::identity(3);
    let mismatch =
        |r: Result<(), LinalgError>| matches!(r, Err(LinalgError::DimensionMismatch { .. }));
    assert!(mismatch(a.mul_vec(&[1.0; 2], &mut [0.0; 3])));
    assert!(mismatch(a.mul_points(&[[0.0; 3]; 3], &mut [[0.0; 3]; 4])));
    assert!(mismatch(
        a.transpose_mul_points(&[[0.0; 3]; 4], &mut [[0.0; 3]; 3])
    ));
    assert!(matches!(
        a.add(&CscMatrix::identity(4)),
        Err(LinalgError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        a.mul(&CscMatrix::zeros(4, 2)),
        Err(LinalgError::DimensionMismatch { .. })
    ));
}

#[test]
fn permuting_needs_a_square_matrix_and_a_permutation_of_its_size() {
    let rectangular = CscMatrix::zeros(2, 3);
    assert!(matches!(
        PermutedTriangle::new(&rectangular, &Permutation::identity(3), Triangle::Lower),
        Err(LinalgError::NotSquare { nrows: 2, ncols: 3 })
    ));
    assert!(matches!(
        PermutedTriangle::new(
            &CscMatrix::identity(3),
            &Permutation::identity(2),
            Triangle::Lower
        ),
        Err(LinalgError::DimensionMismatch { .. })
    ));
}

#[test]
fn refilling_with_another_pattern_is_an_error() {
    let mut c = PermutedTriangle::new(
        &CscMatrix::identity(3),
        &Permutation::identity(3),
        Triangle::Lower,
    )
    .unwrap();
    assert_eq!(
        c.refill(&CscMatrix::zeros(3, 3)),
        Err(LinalgError::PatternMismatch)
    );
}

#[test]
fn invalid_csc_arrays_are_rejected() {
    let bad_pointer = CscMatrix::from_parts(2, 2, vec![0, 1], vec![0], vec![1.0]);
    assert!(matches!(bad_pointer, Err(LinalgError::InvalidStructure(_))));
    let unsorted = CscMatrix::from_parts(2, 1, vec![0, 2], vec![1, 0], vec![1.0, 2.0]);
    assert!(matches!(unsorted, Err(LinalgError::InvalidStructure(_))));
    let out_of_range = CscMatrix::from_parts(2, 1, vec![0, 1], vec![2], vec![1.0]);
    assert!(matches!(
        out_of_range,
        Err(LinalgError::IndexOutOfBounds { row: 2, .. })
    ));
    let not_a_permutation = Permutation::from_perm(vec![0, 0]);
    assert!(matches!(
        not_a_permutation,
        Err(LinalgError::InvalidStructure(_))
    ));
}
