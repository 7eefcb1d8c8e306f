//! The dense matrix and the dense Cholesky factorization, checked against
//! nalgebra on random matrices, plus every error path.
use crate::common;

use common::*;
use masssprings::linalg::dense::{
    back_substitution_dense, forward_substitution_dense, DenseCholesky, DenseMatrix,
};
use masssprings::linalg::{Cancel, LinalgError};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

// ---------------------------------------------------------------------------
// Conversions and strategies
// ---------------------------------------------------------------------------

/// Our copy of an nalgebra matrix, written entry by entry through indexing.
fn dense_from_nalgebra(m: &DMatrix<f64>) -> DenseMatrix {
    let mut a = DenseMatrix::zeros(m.nrows(), m.ncols());
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            a[(i, j)] = m[(i, j)];
        }
    }
    a
}

/// `common::assert_close`, and every entry of `ours` finite: `assert_close`
/// measures differences with `f64::max`, which skips NaN, so a result full of
/// NaN (say, from an output buffer that was never zeroed) would pass it alone.
/// Every oracle here is finite.
fn assert_near(ours: &DMatrix<f64>, oracle: &DMatrix<f64>, tol: f64) {
    assert!(
        ours.iter().all(|v| v.is_finite()),
        "non-finite result: {ours}"
    );
    assert_close(ours, oracle, tol);
}

/// A vector as an nalgebra column.
fn column(v: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(v.len(), 1, v)
}

/// An n×3 block of points as an nalgebra matrix, one point per row.
fn points_to_nalgebra(p: &[[f64; 3]]) -> DMatrix<f64> {
    DMatrix::from_fn(p.len(), 3, |i, c| p[i][c])
}

/// `nrows × ncols` entries in `[-1, 1]`.
fn values(nrows: usize, ncols: usize) -> impl Strategy<Value = DMatrix<f64>> {
    prop::collection::vec(-1.0f64..1.0, nrows * ncols)
        .prop_map(move |v| DMatrix::from_row_slice(nrows, ncols, &v))
}

/// A random matrix of random shape, each side in `0..=max`.
fn matrix(max: usize) -> impl Strategy<Value = DMatrix<f64>> {
    (0..=max, 0..=max).prop_flat_map(|(m, n)| values(m, n))
}

/// Two random matrices of the same random shape.
fn same_shape_pair(max: usize) -> impl Strategy<Value = (DMatrix<f64>, DMatrix<f64>)> {
    (0..=max, 0..=max).prop_flat_map(|(m, n)| (values(m, n), values(m, n)))
}

/// `A` (m×n) and `B` (n×r) that can be multiplied.
fn product_pair(max: usize) -> impl Strategy<Value = (DMatrix<f64>, DMatrix<f64>)> {
    (0..=max, 0..=max, 0..=max).prop_flat_map(|(m, n, r)| (values(m, n), values(n, r)))
}

/// `A` (m×n) and a block of `n` points, for `A x`.
fn matrix_and_points(max: usize) -> impl Strategy<Value = (DMatrix<f64>, Vec<[f64; 3]>)> {
    (0..=max, 0..=max).prop_flat_map(|(m, n)| (values(m, n), points(n)))
}

/// `A` (m×n) and a block of `m` points, for `Aᵀ x`.
fn matrix_and_row_points(max: usize) -> impl Strategy<Value = (DMatrix<f64>, Vec<[f64; 3]>)> {
    (0..=max, 0..=max).prop_flat_map(|(m, n)| (values(m, n), points(m)))
}

/// `count` points with coordinates in `[-10, 10]`.
fn points(count: usize) -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec(prop::array::uniform3(-10.0f64..10.0), count)
}

/// A symmetric positive-definite `BᵀB + c I` with `B` dense random (n×n,
/// `n ∈ 1..=max_n`) and `c ∈ [0.1, 2]`, computed by nalgebra and made exactly
/// symmetric.
fn spd(max_n: usize) -> impl Strategy<Value = DMatrix<f64>> {
    (1..=max_n)
        .prop_flat_map(|n| (values(n, n), 0.1f64..2.0))
        .prop_map(|(b, shift)| {
            let n = b.nrows();
            let q = b.transpose() * &b + DMatrix::identity(n, n) * shift;
            (&q + q.transpose()) * 0.5
        })
}

/// An SPD matrix with `r` right-hand sides (n×r).
fn spd_and_rhs(max_n: usize, r: usize) -> impl Strategy<Value = (DMatrix<f64>, DMatrix<f64>)> {
    spd(max_n).prop_flat_map(move |a| {
        let n = a.nrows();
        (Just(a), values(n, r))
    })
}

/// A lower-triangular n×n matrix with diagonal entries of size in `[0.5, 2]`
/// (well conditioned enough to solve with); its upper triangle holds garbage
/// that a triangular solve must not read.
fn lower_triangular(max_n: usize) -> impl Strategy<Value = DMatrix<f64>> {
    (1..=max_n)
        .prop_flat_map(|n| {
            (
                values(n, n),
                prop::collection::vec(prop_oneof![-2.0f64..-0.5, 0.5f64..2.0], n),
            )
        })
        .prop_map(|(mut t, diagonal)| {
            for (i, d) in diagonal.into_iter().enumerate() {
                t[(i, i)] = d;
            }
            t
        })
}

/// `n` values in `[-1, 1]`, as a vector.
fn rhs_for(n: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1.0f64..1.0, n)
}

// ---------------------------------------------------------------------------
// Matrix operations against nalgebra
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(proptest_config(256))]

    #[test]
    fn transpose_matches_nalgebra(m in matrix(12)) {
        let a = dense_from_nalgebra(&m);
        assert_near(&dense_to_nalgebra(&a.transpose()), &m.transpose(), 0.0);
    }

    #[test]
    fn from_rows_and_row_round_trip(m in matrix(12)) {
        let rows: Vec<Vec<f64>> = m.row_iter().map(|r| r.iter().copied().collect()).collect();
        let a = DenseMatrix::from_rows(&rows).unwrap();
        if m.nrows() > 0 {
            prop_assert_eq!(&a, &dense_from_nalgebra(&m));
        }
        for (i, row) in rows.iter().enumerate() {
            prop_assert_eq!(a.row(i), row.as_slice());
        }
    }

    #[test]
    fn from_row_major_fills_row_by_row(m in matrix(12)) {
        let data: Vec<f64> = m.transpose().iter().copied().collect();
        let a = DenseMatrix::from_row_major(m.nrows(), m.ncols(), data.clone()).unwrap();
        prop_assert_eq!(&a, &dense_from_nalgebra(&m));
        prop_assert_eq!(a.as_slice(), data.as_slice());
    }

    #[test]
    fn product_matches_nalgebra((p, q) in product_pair(12)) {
        let product = dense_from_nalgebra(&p).mul(&dense_from_nalgebra(&q)).unwrap();
        assert_near(&dense_to_nalgebra(&product), &(&p * &q), 1e-13);
    }

    #[test]
    fn gram_matches_nalgebra_and_the_product_with_the_transpose_to_the_bit(m in matrix(12)) {
        let a = dense_from_nalgebra(&m);
        let gram = a.transpose_mul_self(Cancel::NEVER).unwrap();
        assert_near(&dense_to_nalgebra(&gram), &(m.transpose() * &m), 1e-13);
        prop_assert_eq!(gram, a.transpose().mul(&a).unwrap());
    }

    #[test]
    fn matrix_vector_product_matches_nalgebra(
        (m, x) in (0..=12usize, 0..=12usize).prop_flat_map(|(r, c)| (values(r, c), rhs_for(c)))
    ) {
        let mut y = vec![f64::NAN; m.nrows()];
        dense_from_nalgebra(&m).mul_vec(&x, &mut y).unwrap();
        assert_near(&column(&y), &(&m * column(&x)), 1e-13);
    }

    #[test]
    fn point_product_matches_nalgebra((m, x) in matrix_and_points(12)) {
        let mut y = vec![[f64::NAN; 3]; m.nrows()];
        dense_from_nalgebra(&m).mul_points(&x, &mut y).unwrap();
        assert_near(&points_to_nalgebra(&y), &(&m * points_to_nalgebra(&x)), 1e-13);
    }

    #[test]
    fn transposed_point_product_matches_product_with_transpose(
        (m, x) in matrix_and_row_points(12)
    ) {
        let mut y = vec![[f64::NAN; 3]; m.ncols()];
        dense_from_nalgebra(&m).transpose_mul_points(&x, &mut y).unwrap();
        assert_near(&points_to_nalgebra(&y), &(m.transpose() * points_to_nalgebra(&x)), 1e-13);
    }

    #[test]
    fn sum_matches_nalgebra((p, q) in same_shape_pair(12)) {
        let sum = dense_from_nalgebra(&p).add(&dense_from_nalgebra(&q)).unwrap();
        assert_near(&dense_to_nalgebra(&sum), &(&p + &q), 0.0);
    }

    #[test]
    fn scaling_matches_nalgebra(m in matrix(12), s in -100.0f64..100.0) {
        let scaled = dense_from_nalgebra(&m).scale(s);
        assert_near(&dense_to_nalgebra(&scaled), &(&m * s), 0.0);
    }

    #[test]
    fn scaled_sum_matches_nalgebra((p, q) in same_shape_pair(12), s in -100.0f64..100.0) {
        let sum = dense_from_nalgebra(&p).scaled_add(s, &dense_from_nalgebra(&q)).unwrap();
        assert_near(&dense_to_nalgebra(&sum), &(&p + &q * s), 1e-15);
    }

    #[test]
    fn identity_is_neutral_for_the_product(m in matrix(12)) {
        let a = dense_from_nalgebra(&m);
        let left = DenseMatrix::identity(m.nrows());
        let right = DenseMatrix::identity(m.ncols());
        assert_near(&dense_to_nalgebra(&left), &DMatrix::identity(m.nrows(), m.nrows()), 0.0);
        prop_assert_eq!(&left.mul(&a).unwrap(), &a);
        prop_assert_eq!(&a.mul(&right).unwrap(), &a);
    }

    #[test]
    fn diagonal_matches_nalgebra(m in matrix(12)) {
        let n = m.nrows().min(m.ncols());
        let expected: Vec<f64> = (0..n).map(|i| m[(i, i)]).collect();
        prop_assert_eq!(dense_from_nalgebra(&m).diagonal(), expected);
    }

    #[test]
    fn from_diagonal_matches_nalgebra(d in prop::collection::vec(-1.0f64..1.0, 0..=12)) {
        let a = DenseMatrix::from_diagonal(&d);
        assert_near(&dense_to_nalgebra(&a), &DMatrix::from_diagonal(&DVector::from_vec(d.clone())), 0.0);
        prop_assert_eq!(a.diagonal(), d);
    }
}

// ---------------------------------------------------------------------------
// Cholesky against nalgebra
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(proptest_config(256))]

    #[test]
    fn factor_times_transpose_reproduces_matrix(a in spd(12)) {
        let chol = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();
        let l = dense_to_nalgebra(chol.l());
        assert_near(&(&l * l.transpose()), &a, 1e-12);
    }

    #[test]
    fn factor_is_lower_triangular_with_positive_diagonal(a in spd(12)) {
        let chol = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();
        let l = chol.l();
        for i in 0..l.nrows() {
            prop_assert!(l[(i, i)] > 0.0);
            for j in i + 1..l.ncols() {
                prop_assert_eq!(l[(i, j)], 0.0);
            }
        }
    }

    #[test]
    fn factor_matches_nalgebra(a in spd(12)) {
        let chol = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();
        let oracle = nalgebra::Cholesky::new(a.clone()).expect("BᵀB + cI is SPD");
        assert_near(&dense_to_nalgebra(chol.l()), &oracle.l(), 1e-12);
    }

    #[test]
    fn factor_reads_only_the_lower_triangle(a in spd(12), garbage in -1e3f64..1e3) {
        let mut upper_spoiled = dense_from_nalgebra(&a);
        for i in 0..a.nrows() {
            for j in i + 1..a.ncols() {
                upper_spoiled[(i, j)] = if (i + j) % 2 == 0 { f64::NAN } else { garbage };
            }
        }
        let clean = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();
        let spoiled = DenseCholesky::factor(&upper_spoiled).unwrap();
        prop_assert_eq!(clean, spoiled);
    }

    #[test]
    fn solve_matches_nalgebra((a, b) in spd_and_rhs(12, 1)) {
        let chol = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();
        let mut x: Vec<f64> = b.iter().copied().collect();
        chol.solve_in_place(&mut x).unwrap();
        let x = column(&x);
        let residual = (&a * &x - &b).norm();
        prop_assert!(residual <= 1e-10 * b.norm(), "residual {:e}, ‖b‖ {:e}", residual, b.norm());
        let oracle = nalgebra::Cholesky::new(a.clone()).unwrap().solve(&b);
        assert_near(&x, &oracle, 1e-10);
    }

    #[test]
    fn point_solve_matches_nalgebra((a, b) in spd_and_rhs(12, 3)) {
        let chol = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();
        let mut x: Vec<[f64; 3]> = b.row_iter().map(|r| [r[0], r[1], r[2]]).collect();
        chol.solve_points_in_place(&mut x).unwrap();
        let x = points_to_nalgebra(&x);
        let residual = (&a * &x - &b).norm();
        prop_assert!(residual <= 1e-10 * b.norm(), "residual {:e}, ‖b‖ {:e}", residual, b.norm());
        let oracle = nalgebra::Cholesky::new(a.clone()).unwrap().solve(&b);
        assert_near(&x, &oracle, 1e-10);
    }

    #[test]
    fn matrix_solve_matches_nalgebra(
        (a, b) in (0..=5usize).prop_flat_map(|r| spd_and_rhs(12, r))
    ) {
        let chol = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();
        let x = dense_to_nalgebra(&chol.solve_matrix(&dense_from_nalgebra(&b)).unwrap());
        let residual = (&a * &x - &b).norm();
        prop_assert!(residual <= 1e-10 * b.norm(), "residual {:e}, ‖b‖ {:e}", residual, b.norm());
        let oracle = nalgebra::Cholesky::new(a.clone()).unwrap().solve(&b);
        assert_near(&x, &oracle, 1e-10);
    }

    #[test]
    fn all_three_solve_forms_agree((a, b) in spd_and_rhs(12, 3)) {
        let chol = DenseCholesky::factor(&dense_from_nalgebra(&a)).unwrap();

        let by_matrix = dense_to_nalgebra(&chol.solve_matrix(&dense_from_nalgebra(&b)).unwrap());

        let mut points: Vec<[f64; 3]> = b.row_iter().map(|r| [r[0], r[1], r[2]]).collect();
        chol.solve_points_in_place(&mut points).unwrap();
        let by_points = points_to_nalgebra(&points);

        let mut by_columns = b.clone();
        for c in 0..3 {
            let mut x: Vec<f64> = b.column(c).iter().copied().collect();
            chol.solve_in_place(&mut x).unwrap();
            by_columns.set_column(c, &DVector::from_vec(x));
        }

        assert_near(&by_points, &by_matrix, 1e-14);
        assert_near(&by_columns, &by_matrix, 1e-14);
    }

    #[test]
    fn forward_substitution_matches_nalgebra(
        (t, b) in lower_triangular(12).prop_flat_map(|t| { let n = t.nrows(); (Just(t), rhs_for(n)) })
    ) {
        let mut y = b.clone();
        forward_substitution_dense(&dense_from_nalgebra(&t), &mut y).unwrap();
        let oracle = t.solve_lower_triangular(&column(&b)).unwrap();
        assert_near(&column(&y), &oracle, 1e-10);
    }

    #[test]
    fn back_substitution_matches_nalgebra(
        (t, b) in lower_triangular(12).prop_flat_map(|t| { let n = t.nrows(); (Just(t), rhs_for(n)) })
    ) {
        // The transpose of a random lower-triangular matrix with garbage above
        // its diagonal: upper triangular with garbage below.
        let u = t.transpose();
        let mut x = b.clone();
        back_substitution_dense(&dense_from_nalgebra(&u), &mut x).unwrap();
        let oracle = u.solve_upper_triangular(&column(&b)).unwrap();
        assert_near(&column(&x), &oracle, 1e-10);
    }
}

// ---------------------------------------------------------------------------
// Worked examples
// ---------------------------------------------------------------------------

#[test]
fn factor_of_textbook_example_is_exact() {
    // The example of Wikipedia's "Cholesky decomposition" article: every
    // intermediate value is an integer, so the factor is exact.
    let a = DenseMatrix::from_rows(&[
        [4.0, 12.0, -16.0],
        [12.0, 37.0, -43.0],
        [-16.0, -43.0, 98.0],
    ])
    .unwrap();
    let l = DenseMatrix::from_rows(&[[2.0, 0.0, 0.0], [6.0, 1.0, 0.0], [-8.0, 5.0, 3.0]]).unwrap();
    let chol = DenseCholesky::factor(&a).unwrap();
    assert_eq!(chol.l(), &l);

    // b = A (1, 2, 3) = (−20, −43, 192); the solve recovers (1, 2, 3) exactly.
    let x = [1.0, 2.0, 3.0];
    let mut b = [0.0; 3];
    a.mul_vec(&x, &mut b).unwrap();
    assert_eq!(b, [-20.0, -43.0, 192.0]);
    chol.solve_in_place(&mut b).unwrap();
    assert_eq!(b, x);
}

#[test]
fn substitutions_compose_to_the_assignment_pseudo_code() {
    // the handout: p = back_substitution(transpose(L), forward_substitution(L, b))
    let a = DenseMatrix::from_rows(&[[4.0, 2.0], [2.0, 10.0]]).unwrap();
    let chol = DenseCholesky::factor(&a).unwrap();
    let b = [6.0, 12.0];
    let mut p = b;
    forward_substitution_dense(chol.l(), &mut p).unwrap();
    back_substitution_dense(&chol.l().transpose(), &mut p).unwrap();
    let mut direct = b;
    chol.solve_in_place(&mut direct).unwrap();
    assert_eq!(p, direct);
    assert_eq!(p, [1.0, 1.0]);
}

#[test]
fn a_set_flag_stops_the_gram_product_and_the_factorization() {
    use std::sync::atomic::AtomicBool;
    let a = DenseMatrix::from_rows(&[[4.0, 2.0], [2.0, 10.0]]).unwrap();
    let set = AtomicBool::new(true);
    let cancel = Cancel::on(Some(&set));
    assert_eq!(a.transpose_mul_self(cancel), Err(LinalgError::Cancelled));
    assert_eq!(
        DenseCholesky::factor_cancellable(&a, cancel),
        Err(LinalgError::Cancelled)
    );
    let clear = AtomicBool::new(false);
    let running = DenseCholesky::factor_cancellable(&a, Cancel::on(Some(&clear))).unwrap();
    assert_eq!(running, DenseCholesky::factor(&a).unwrap());
}

#[test]
fn empty_matrix_factors_and_solves() {
    let chol = DenseCholesky::factor(&DenseMatrix::zeros(0, 0)).unwrap();
    assert_eq!(chol.dim(), 0);
    chol.solve_in_place(&mut []).unwrap();
    chol.solve_points_in_place(&mut []).unwrap();
    let x = chol.solve_matrix(&DenseMatrix::zeros(0, 4)).unwrap();
    assert_eq!((x.nrows(), x.ncols()), (0, 4));
}

#[test]
fn from_rows_accepts_vectors_arrays_and_slices() {
    let from_vecs = DenseMatrix::from_rows(&[vec![1.0, 2.0], vec![3.0, 4.0]]).unwrap();
    let from_arrays = DenseMatrix::from_rows(&[[1.0, 2.0], [3.0, 4.0]]).unwrap();
    let slices: [&[f64]; 2] = [&[1.0, 2.0], &[3.0, 4.0]];
    let from_slices = DenseMatrix::from_rows(&slices).unwrap();
    assert_eq!(from_vecs, from_arrays);
    assert_eq!(from_vecs, from_slices);
    assert_eq!(from_vecs.row(1), &[3.0, 4.0]);
    let no_rows: [Vec<f64>; 0] = [];
    assert_eq!(
        DenseMatrix::from_rows(&no_rows).unwrap(),
        DenseMatrix::zeros(0, 0)
    );
}

// ---------------------------------------------------------------------------
// Error paths
// ---------------------------------------------------------------------------

#[test]
fn ragged_rows_are_an_error() {
    let rows = [vec![1.0, 2.0, 3.0], vec![4.0, 5.0, 6.0], vec![7.0, 8.0]];
    assert_eq!(
        DenseMatrix::from_rows(&rows),
        Err(LinalgError::DimensionMismatch {
            operation: "from_rows",
            left: (1, 3),
            right: (1, 2)
        })
    );
}

#[test]
fn row_major_data_of_wrong_length_is_an_error() {
    assert_eq!(
        DenseMatrix::from_row_major(2, 3, vec![0.0; 5]),
        Err(LinalgError::DimensionMismatch {
            operation: "from_row_major",
            left: (2, 3),
            right: (5, 1)
        })
    );
}

/// The `operation` of a `DimensionMismatch`, or a panic for anything else.
fn mismatched_operation<T: std::fmt::Debug>(result: Result<T, LinalgError>) -> &'static str {
    match result {
        Err(LinalgError::DimensionMismatch { operation, .. }) => operation,
        other => panic!("expected a DimensionMismatch, got {other:?}"),
    }
}

#[test]
fn products_of_mismatched_shapes_are_errors() {
    let a = DenseMatrix::zeros(2, 3);
    assert_eq!(
        a.mul(&DenseMatrix::zeros(2, 3)),
        Err(LinalgError::DimensionMismatch {
            operation: "mul",
            left: (2, 3),
            right: (2, 3)
        })
    );
    assert_eq!(
        mismatched_operation(a.add(&DenseMatrix::zeros(3, 2))),
        "add"
    );
    let scaled_add = a.scaled_add(2.0, &DenseMatrix::zeros(2, 2));
    assert_eq!(mismatched_operation(scaled_add), "scaled_add");
}

#[test]
fn vector_products_of_mismatched_shapes_are_errors_and_leave_the_output_alone() {
    let a = DenseMatrix::from_rows(&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]).unwrap();

    let mut y = [7.0; 2];
    assert_eq!(
        mismatched_operation(a.mul_vec(&[1.0; 2], &mut y)),
        "mul_vec"
    );
    let wrong_output = a.mul_vec(&[1.0; 3], &mut [0.0; 3]);
    assert_eq!(mismatched_operation(wrong_output), "mul_vec (output y)");
    assert_eq!(y, [7.0; 2]);

    let mut points = [[7.0; 3]; 2];
    let wrong_input = a.mul_points(&[[1.0; 3]; 2], &mut points);
    assert_eq!(mismatched_operation(wrong_input), "mul_points");
    let wrong_output = a.mul_points(&[[1.0; 3]; 3], &mut [[0.0; 3]; 3]);
    assert_eq!(mismatched_operation(wrong_output), "mul_points (output y)");

    let mut points_t = [[7.0; 3]; 3];
    let wrong_input = a.transpose_mul_points(&[[1.0; 3]; 3], &mut points_t);
    assert_eq!(mismatched_operation(wrong_input), "transpose_mul_points");
    let wrong_output = a.transpose_mul_points(&[[1.0; 3]; 2], &mut [[0.0; 3]; 2]);
    assert_eq!(
        mismatched_operation(wrong_output),
        "transpose_mul_points (output y)"
    );

    assert_eq!(points, [[7.0; 3]; 2]);
    assert_eq!(points_t, [[7.0; 3]; 3]);
}

#[test]
#[should_panic(expected = "out of range")]
fn row_out_of_range_panics() {
    DenseMatrix::zeros(2, 2).row(2);
}

#[test]
fn factoring_a_non_square_matrix_is_an_error() {
    assert_eq!(
        DenseCholesky::factor(&DenseMatrix::zeros(2, 3)),
        Err(LinalgError::NotSquare { nrows: 2, ncols: 3 })
    );
}

#[test]
fn indefinite_matrix_names_its_negative_pivot() {
    let a = DenseMatrix::from_diagonal(&[1.0, -1.0, 1.0]);
    assert_eq!(
        DenseCholesky::factor(&a),
        Err(LinalgError::NotPositiveDefinite {
            column: 1,
            pivot: -1.0
        })
    );
}

#[test]
fn indefinite_matrix_with_positive_diagonal_names_the_first_bad_pivot() {
    // Positive diagonal, but [[1, 2], [2, 1]] has eigenvalues 3 and −1:
    // pivot 1 is 1 − 2² = −3.
    let a = DenseMatrix::from_rows(&[[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
    assert_eq!(
        DenseCholesky::factor(&a),
        Err(LinalgError::NotPositiveDefinite {
            column: 1,
            pivot: -3.0
        })
    );
}

#[test]
fn singular_matrix_names_its_zero_pivot() {
    // Rows 0 and 1 are parallel: pivot 1 is 1 − (2/2)² = 0 exactly.
    let a = DenseMatrix::from_rows(&[[4.0, 2.0, 2.0], [2.0, 1.0, 1.0], [2.0, 1.0, 5.0]]).unwrap();
    assert_eq!(
        DenseCholesky::factor(&a),
        Err(LinalgError::NotPositiveDefinite {
            column: 1,
            pivot: 0.0
        })
    );
    assert_eq!(
        DenseCholesky::factor(&DenseMatrix::zeros(2, 2)),
        Err(LinalgError::NotPositiveDefinite {
            column: 0,
            pivot: 0.0
        })
    );
}

/// The column and pivot of a `NotPositiveDefinite`, or a panic for anything
/// else.
fn failed_pivot(a: &DenseMatrix) -> (usize, f64) {
    match DenseCholesky::factor(a) {
        Err(LinalgError::NotPositiveDefinite { column, pivot }) => (column, pivot),
        other => panic!("expected NotPositiveDefinite, got {other:?}"),
    }
}

#[test]
fn nan_entry_is_not_positive_definite() {
    let mut a = DenseMatrix::identity(3);
    a[(0, 0)] = f64::NAN;
    let (column, pivot) = failed_pivot(&a);
    assert_eq!(column, 0);
    assert!(pivot.is_nan());

    // Below the diagonal, a NaN reaches the pivot of its row.
    let mut a = DenseMatrix::identity(3);
    a[(2, 0)] = f64::NAN;
    let (column, pivot) = failed_pivot(&a);
    assert_eq!(column, 2);
    assert!(pivot.is_nan());
}

#[test]
fn infinite_entry_is_not_positive_definite() {
    let mut a = DenseMatrix::identity(3);
    a[(1, 1)] = f64::INFINITY;
    assert_eq!(failed_pivot(&a), (1, f64::INFINITY));

    let mut a = DenseMatrix::identity(3);
    a[(2, 1)] = f64::INFINITY;
    assert_eq!(failed_pivot(&a), (2, f64::NEG_INFINITY));
}

#[test]
fn solving_with_a_right_hand_side_of_wrong_length_is_an_error() {
    let chol = DenseCholesky::factor(&DenseMatrix::identity(3)).unwrap();

    let mut b = [5.0; 2];
    assert_eq!(
        chol.solve_in_place(&mut b),
        Err(LinalgError::DimensionMismatch {
            operation: "cholesky solve",
            left: (3, 3),
            right: (2, 1)
        })
    );
    assert_eq!(b, [5.0; 2]);

    let mut points = [[5.0; 3]; 4];
    let result = chol.solve_points_in_place(&mut points);
    assert_eq!(mismatched_operation(result), "cholesky solve_points");
    assert_eq!(points, [[5.0; 3]; 4]);

    let result = chol.solve_matrix(&DenseMatrix::zeros(2, 3));
    assert_eq!(mismatched_operation(result), "cholesky solve_matrix");
}

#[test]
fn substitution_with_wrong_shapes_is_an_error() {
    let l = DenseMatrix::identity(3);
    assert_eq!(
        forward_substitution_dense(&DenseMatrix::zeros(3, 2), &mut [0.0; 3]),
        Err(LinalgError::NotSquare { nrows: 3, ncols: 2 })
    );
    assert_eq!(
        back_substitution_dense(&DenseMatrix::zeros(2, 3), &mut [0.0; 2]),
        Err(LinalgError::NotSquare { nrows: 2, ncols: 3 })
    );
    let forward = forward_substitution_dense(&l, &mut [0.0; 4]);
    assert_eq!(mismatched_operation(forward), "forward_substitution_dense");
    let back = back_substitution_dense(&l, &mut [0.0; 2]);
    assert_eq!(mismatched_operation(back), "back_substitution_dense");
}
