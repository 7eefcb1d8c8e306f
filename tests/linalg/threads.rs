//! The supernodal factorization and its solves on 1, 2, 3, 4 and 8
//! threads (more than this machine's cores): the same bits, every entry of
//! `L` and of every solution, and the same error at the same column.
use crate::common;

use common::*;
use masssprings::linalg::sparse::{
    CscMatrix, Method, Ordering, Permutation, Relaxation, SparseCholesky, SymbolicCholesky,
    TripletMatrix,
};
use masssprings::linalg::LinalgError;
use masssprings::mesh::load_scene;
use masssprings::sim::precomputation::scene_q;
use masssprings::sim::DELTA_T;
use proptest::prelude::*;

/// The thread counts every check runs: one, as many as the cores of a
/// small machine and more, and more than most machines have.
const THREADS: [usize; 5] = [1, 2, 3, 4, 8];

/// The `Q` of a scene of `data/`.
fn data_q(name: &str) -> CscMatrix {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name);
    scene_q(&load_scene(&path).unwrap(), DELTA_T)
}

/// The bits of a list of numbers.
fn bits<'a>(values: impl IntoIterator<Item = &'a f64>) -> Vec<u64> {
    values.into_iter().map(|v| v.to_bits()).collect()
}

/// What a factorization gives, as bits: `L`, and the solutions of every
/// solve entry point for a fixed right-hand side.
fn results(cholesky: &mut SparseCholesky) -> Vec<Vec<u64>> {
    let n = cholesky.symbolic().n();
    let b: Vec<[f64; 3]> = (0..n)
        .map(|i| [(i as f64 * 0.37).sin(), 1.0, (i as f64).sqrt()])
        .collect();
    let mut points = b.clone();
    cholesky.solve_points_in_place(&mut points);
    let mut column: Vec<f64> = b.iter().map(|row| row[0]).collect();
    cholesky.solve_in_place(&mut column);
    let mut from = vec![[0.0; 3]; n];
    cholesky.solve_points_from(|i| b[i], &mut from);
    let (perm, buffer) = cholesky.buffer_in_factor_order();
    let perm = perm.perm().to_vec();
    for (row, &old) in buffer.iter_mut().zip(&perm) {
        *row = [b[old][0], b[old][1], b[old][2], 0.0];
    }
    cholesky.solve_buffer_in_place();
    let (_, buffer) = cholesky.buffer_in_factor_order();
    let in_place = bits(buffer.iter().flatten());
    vec![
        bits(cholesky.l().values()),
        bits(points.iter().flatten()),
        bits(&column),
        bits(from.iter().flatten()),
        in_place,
    ]
}

/// Factors `a` as analysed in `symbolic` on each of [`THREADS`] and checks
/// that every result is the one-thread result, bit for bit.
fn same_bits_on_any_threads(a: &CscMatrix, symbolic: &SymbolicCholesky, what: &str) {
    let mut reference = None;
    for threads in THREADS {
        let mut cholesky =
            SparseCholesky::factor_with_threads(symbolic.clone(), a, Method::Supernodal, threads)
                .unwrap();
        assert_eq!(cholesky.threads(), threads, "{what}");
        cholesky.refactor(a).unwrap(); // a refactorization too
        let got = results(&mut cholesky);
        match &reference {
            None => reference = Some(got),
            Some(expected) => {
                for (k, (got, expected)) in got.iter().zip(expected).enumerate() {
                    assert!(
                        got == expected,
                        "{what}: result {k} differs on {threads} threads"
                    );
                }
            }
        }
    }
}

#[test]
fn the_assignments_scenes_factor_and_solve_to_the_same_bits_on_any_threads() {
    for name in ["flag.json", "skirt.json"] {
        let q = data_q(name);
        let exact = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
        // the simulation's supernodes, the fundamental ones, CHOLMOD's: the
        // skirt's top supernodes are large enough to be factored by the
        // whole team together, the flag's are not
        for rule in [Relaxation::SMALL, Relaxation::NONE, Relaxation::CHOLMOD] {
            let symbolic = exact.clone().relaxed(&rule);
            same_bits_on_any_threads(&q, &symbolic, &format!("{name} {rule:?}"));
        }
    }
}

#[test]
fn a_grid_in_its_own_order_factors_to_the_same_bits_on_any_threads() {
    // the natural order makes a tall, thin tree with wide supernodes
    let a = grid_matrix(30);
    for ordering in [Ordering::Natural, Ordering::Amd] {
        let symbolic = SymbolicCholesky::analyze(&a, ordering).unwrap();
        same_bits_on_any_threads(&a, &symbolic, &format!("grid-30 {ordering:?}"));
    }
}

#[test]
fn a_matrix_of_many_pieces_factors_to_the_same_bits_on_any_threads() {
    // four grids side by side, not joined: a forest of four trees
    let piece = grid_matrix(12);
    let m = piece.ncols();
    let mut t = TripletMatrix::new(4 * m, 4 * m);
    for block in 0..4 {
        for j in 0..m {
            let (rows, values) = piece.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                t.push(block * m + i, block * m + j, v).unwrap();
            }
        }
    }
    let a = t.to_csc();
    let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
    same_bits_on_any_threads(&a, &symbolic, "four grids");
}

#[test]
fn tiny_and_empty_matrices_factor_on_any_threads() {
    for n in [0, 1, 2, 5] {
        let a = CscMatrix::from_diagonal(&vec![2.0; n]);
        let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
        same_bits_on_any_threads(&a, &symbolic, &format!("diagonal of {n}"));
    }
}

#[test]
fn a_pivot_that_fails_is_reported_at_the_same_column_on_any_threads() {
    // the skirt with one diagonal entry made negative, at vertices spread
    // over the factor's order: in a subtree, in a supernode of the top
    // factored by one thread, in one factored by the whole team
    let q = data_q("skirt.json");
    let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd)
        .unwrap()
        .relaxed(&Relaxation::SMALL);
    let n = q.ncols();
    let supernodes = symbolic.supernodes();
    let mut columns = vec![0, n / 3, n / 2, 2 * n / 3, n - 1];
    for s in supernodes.len().saturating_sub(8)..supernodes.len() {
        columns.push(supernodes.columns(s).start);
    }
    for column in columns {
        let vertex = symbolic.permutation().perm()[column];
        let mut bad = q.clone();
        let (rows, _) = bad.column(vertex);
        let at = rows.iter().position(|&i| i == vertex).unwrap();
        let slot = bad.col_ptr()[vertex] + at;
        bad.values_mut()[slot] = -1e12;
        let errors: Vec<LinalgError> = THREADS
            .iter()
            .map(|&threads| {
                SparseCholesky::factor_with_threads(
                    symbolic.clone(),
                    &bad,
                    Method::Supernodal,
                    threads,
                )
                .unwrap_err()
            })
            .collect();
        assert!(
            errors.iter().all(|e| *e == errors[0]),
            "column {column}: {errors:?}"
        );
        assert!(matches!(errors[0], LinalgError::NotPositiveDefinite { .. }));
    }
}

#[test]
fn a_failed_refactorization_on_threads_can_be_followed_by_a_good_one() {
    let q = data_q("flag.json");
    let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
    let mut one = SparseCholesky::factor(symbolic.clone(), &q, Method::Supernodal).unwrap();
    let mut three =
        SparseCholesky::factor_with_threads(symbolic, &q, Method::Supernodal, 3).unwrap();
    let mut bad = q.clone();
    for value in bad.values_mut() {
        *value = -value.abs();
    }
    assert_eq!(one.refactor(&bad), three.refactor(&bad));
    three.refactor(&q).unwrap();
    one.refactor(&q).unwrap();
    assert_eq!(results(&mut one), results(&mut three));
}

#[test]
fn changing_the_threads_keeps_the_bits() {
    let q = data_q("skirt.json");
    let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
    let mut cholesky = SparseCholesky::factor(symbolic, &q, Method::Supernodal).unwrap();
    let expected = results(&mut cholesky);
    for threads in [4, 2, 1] {
        cholesky.set_threads(threads);
        assert_eq!(cholesky.threads(), threads);
        cholesky.refactor(&q).unwrap();
        assert!(results(&mut cholesky) == expected, "{threads} threads");
    }
}

#[test]
fn the_simplicial_method_runs_on_one_thread_whatever_it_is_given() {
    let q = data_q("flag.json");
    let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
    let cholesky =
        SparseCholesky::factor_with_threads(symbolic, &q, Method::Simplicial, 4).unwrap();
    assert_eq!(cholesky.threads(), 1);
}

proptest! {
    #![proptest_config(proptest_config(48))]

    /// Random matrices under random orderings: shapes of tree the cloth
    /// never makes.
    #[test]
    fn random_matrices_factor_to_the_same_bits_on_any_threads(
        a in random_spd(40, 120),
        seed in any::<u64>(),
    ) {
        let n = a.ncols();
        let mut perm: Vec<usize> = (0..n).collect();
        let mut state = seed;
        for i in (1..n).rev() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            perm.swap(i, (state >> 33) as usize % (i + 1));
        }
        let p = Permutation::from_perm(perm).unwrap();
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        same_bits_on_any_threads(&a, &symbolic, "random");
    }
}
