//! Triplets → CSC, checked against dense accumulation in nalgebra.
use crate::common;

use common::*;
use masssprings::linalg::sparse::TripletMatrix;
use masssprings::linalg::LinalgError;
use nalgebra::DMatrix;
use proptest::prelude::*;

fn entries(
    max_rows: usize,
    max_cols: usize,
    max_count: usize,
) -> impl Strategy<Value = (usize, usize, Vec<(usize, usize, f64)>)> {
    (1..=max_rows, 1..=max_cols).prop_flat_map(move |(nrows, ncols)| {
        (
            Just(nrows),
            Just(ncols),
            // few distinct rows/cols make repeats likely
            prop::collection::vec((0..nrows, 0..ncols, -1.0f64..1.0), 0..=max_count),
        )
    })
}

proptest! {
    #![proptest_config(proptest_config(256))]

    #[test]
    fn compression_equals_dense_accumulation((nrows, ncols, list) in entries(12, 12, 80)) {
        let mut oracle = DMatrix::<f64>::zeros(nrows, ncols);
        for &(i, j, v) in &list { oracle[(i, j)] += v; }
        let csc = TripletMatrix::from_entries(nrows, ncols, list.clone()).unwrap().to_csc();
        assert_close(&csc_to_nalgebra(&csc), &oracle, 1e-14);
    }

    #[test]
    fn compressed_columns_are_sorted_without_repeats((nrows, ncols, list) in entries(12, 12, 80)) {
        let csc = TripletMatrix::from_entries(nrows, ncols, list.clone()).unwrap().to_csc();
        let distinct: std::collections::BTreeSet<(usize, usize)> =
            list.iter().map(|&(i, j, _)| (j, i)).collect();
        prop_assert_eq!(csc.nnz(), distinct.len());
        for j in 0..ncols {
            let (rows, _) = csc.column(j);
            prop_assert!(rows.windows(2).all(|w| w[0] < w[1]));
        }
    }
}

#[test]
fn pushing_outside_the_matrix_is_an_error_and_pushes_nothing() {
    let mut t = TripletMatrix::new(3, 2);
    assert_eq!(
        t.push(3, 0, 1.0),
        Err(LinalgError::IndexOutOfBounds {
            row: 3,
            col: 0,
            nrows: 3,
            ncols: 2
        })
    );
    assert!(matches!(
        t.push(0, 2, 1.0),
        Err(LinalgError::IndexOutOfBounds { col: 2, .. })
    ));
    assert!(t.is_empty());
}

#[test]
fn building_from_entries_rejects_the_first_bad_index() {
    let result = TripletMatrix::from_entries(2, 2, [(0, 0, 1.0), (1, 5, 2.0)]);
    assert!(matches!(
        result,
        Err(LinalgError::IndexOutOfBounds { row: 1, col: 5, .. })
    ));
}

#[test]
fn repeats_that_cancel_keep_their_position() {
    let t = TripletMatrix::from_entries(2, 2, [(1, 0, 1.0), (1, 0, -1.0)]).unwrap();
    let csc = t.to_csc();
    assert_eq!(csc.nnz(), 1);
    assert_eq!(csc.get(1, 0), 0.0);
}
