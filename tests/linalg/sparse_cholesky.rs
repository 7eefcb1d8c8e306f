//! The sparse Cholesky pipeline: structure (elimination tree, postorder,
//! column counts, pattern, supernodes) against a boolean-elimination
//! oracle, numbers against nalgebra's dense Cholesky.
use crate::common;

use common::*;
use masssprings::linalg::sparse::amalgamation::relax;
use masssprings::linalg::sparse::column_counts::column_counts;
use masssprings::linalg::sparse::etree::elimination_tree;
use masssprings::linalg::sparse::pattern::{permuted_triangles, ColumnPattern};
use masssprings::linalg::sparse::postorder::postorder;
use masssprings::linalg::sparse::row_pattern::RowPattern;
use masssprings::linalg::sparse::supernode_rows::supernode_rows;
use masssprings::linalg::sparse::PermutedTriangle;
use masssprings::linalg::sparse::{
    CscMatrix, Method, Ordering, Permutation, Relaxation, SparseCholesky, SymbolicCholesky,
    Triangle,
};
use masssprings::linalg::LinalgError;
use nalgebra::DMatrix;
use proptest::prelude::*;

/// A random SPD matrix and a random permutation of its size.
fn spd_and_permutation(
    max_n: usize,
    max_count: usize,
) -> impl Strategy<Value = (CscMatrix, Permutation)> {
    random_spd(max_n, max_count).prop_flat_map(|a| {
        let n = a.ncols();
        let perm = Just((0..n).collect::<Vec<_>>())
            .prop_shuffle()
            .prop_map(|p| Permutation::from_perm(p).unwrap());
        (Just(a), perm)
    })
}

fn any_method() -> impl Strategy<Value = Method> {
    prop_oneof![Just(Method::Simplicial), Just(Method::Supernodal)]
}

/// `P A Pᵀ` densely, for the permutation the analysis settled on.
fn permuted_dense(a: &CscMatrix, p: &Permutation) -> DMatrix<f64> {
    let dense = csc_to_nalgebra(a);
    let n = a.ncols();
    DMatrix::from_fn(n, n, |i, j| dense[(p.perm()[i], p.perm()[j])])
}

/// The pattern of `L` by plain boolean elimination on the dense pattern:
/// eliminating `k` connects every pair of its later neighbours. `O(n³)`,
/// obviously right.
fn eliminated_pattern(c: &DMatrix<f64>) -> Vec<Vec<bool>> {
    let n = c.nrows();
    let mut nonzero: Vec<Vec<bool>> = (0..n)
        .map(|i| (0..n).map(|j| c[(i, j)] != 0.0 || i == j).collect())
        .collect();
    for k in 0..n {
        let later: Vec<usize> = (k + 1..n).filter(|&i| nonzero[i][k]).collect();
        for &i in &later {
            for &j in &later {
                nonzero[i][j] = true;
            }
        }
    }
    nonzero
}

fn factor(a: &CscMatrix, p: &Permutation, method: Method) -> SparseCholesky {
    let symbolic = SymbolicCholesky::with_permutation(a, p).unwrap();
    SparseCholesky::factor(symbolic, a, method).unwrap()
}

proptest! {
    #![proptest_config(proptest_config(200))]

    #[test]
    fn elimination_tree_parents_come_after_their_children((a, p) in spd_and_permutation(30, 80)) {
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        for (j, parent) in symbolic.elimination_tree().iter().enumerate() {
            if let Some(parent) = parent {
                prop_assert!(*parent > j);
            }
        }
    }

    #[test]
    fn elimination_tree_is_the_first_subdiagonal_nonzero_of_each_column((a, p) in spd_and_permutation(30, 80)) {
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let pattern = eliminated_pattern(&permuted_dense(&a, symbolic.permutation()));
        let n = a.ncols();
        for j in 0..n {
            let expected = (j + 1..n).find(|&i| pattern[i][j]);
            prop_assert_eq!(symbolic.elimination_tree()[j], expected);
        }
    }

    #[test]
    fn postorder_is_a_permutation_with_children_before_parents((a, p) in spd_and_permutation(30, 80)) {
        // the analysis folds a postorder into its permutation, so the
        // postorder of the tree it reports must be the identity
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let tree = symbolic.elimination_tree();
        let post = masssprings::linalg::sparse::postorder::postorder(tree);
        prop_assert!(Permutation::from_perm(post.clone()).is_ok());
        prop_assert_eq!(post, (0..a.ncols()).collect::<Vec<_>>());
        // and on the tree of an arbitrary ordering, a real postorder
        let upper = masssprings::linalg::sparse::PermutedTriangle::new(&a, &p, Triangle::Upper).unwrap();
        let parent = masssprings::linalg::sparse::etree::elimination_tree(upper.matrix());
        let post = masssprings::linalg::sparse::postorder::postorder(&parent);
        let position = Permutation::from_perm(post).unwrap();
        for (j, parent) in parent.iter().enumerate() {
            if let Some(parent) = parent {
                prop_assert!(position.inverse()[j] < position.inverse()[*parent]);
            }
        }
    }

    #[test]
    fn column_counts_and_pattern_equal_boolean_elimination((a, p) in spd_and_permutation(30, 80)) {
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let pattern = eliminated_pattern(&permuted_dense(&a, symbolic.permutation()));
        let n = a.ncols();
        for j in 0..n {
            let rows: Vec<u32> = (j..n).filter(|&i| pattern[i][j]).map(|i| i as u32).collect();
            let stored = &symbolic.row_idx()[symbolic.col_ptr()[j]..symbolic.col_ptr()[j + 1]];
            prop_assert_eq!(symbolic.column_counts()[j], rows.len());
            prop_assert_eq!(stored, rows.as_slice());
        }
        let flops: f64 = symbolic.column_counts().iter().map(|&c| (c * c) as f64).sum();
        prop_assert_eq!(symbolic.flops(), flops);
    }

    #[test]
    fn supernodes_are_runs_of_columns_with_nested_patterns((a, p) in spd_and_permutation(30, 80)) {
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let supernodes = symbolic.supernodes();
        let column = |j: usize| symbolic.column_rows(j);
        let mut covered = 0;
        for s in 0..supernodes.len() {
            let columns = supernodes.columns(s);
            prop_assert_eq!(columns.start, covered);
            covered = columns.end;
            for j in columns.start + 1..columns.end {
                prop_assert_eq!(column(j), &column(j - 1)[1..]);
                prop_assert_eq!(supernodes.of_column(j), s);
            }
        }
        prop_assert_eq!(covered, a.ncols());
    }

    #[test]
    fn the_analysis_reads_both_strict_triangles_of_the_permuted_matrix((a, p) in spd_and_permutation(30, 80)) {
        let (upper, lower) = permuted_triangles(&a, p.inverse());
        for (pattern, triangle) in [(&upper, Triangle::Upper), (&lower, Triangle::Lower)] {
            let sorted = PermutedTriangle::new(&a, &p, triangle).unwrap();
            prop_assert_eq!(ColumnPattern::ncols(pattern), a.ncols());
            for j in 0..a.ncols() {
                let mut rows: Vec<usize> = pattern.rows(j).collect();
                rows.sort_unstable();
                let strict: Vec<usize> = sorted.matrix().column(j).0.iter().copied().filter(|&i| i != j).collect();
                prop_assert_eq!(rows, strict);
            }
        }
    }

    #[test]
    fn tree_and_counts_from_the_unsorted_pattern_equal_those_from_the_sorted_triangles((a, p) in spd_and_permutation(30, 80)) {
        let (upper, lower) = permuted_triangles(&a, p.inverse());
        let sorted_upper = PermutedTriangle::new(&a, &p, Triangle::Upper).unwrap();
        let sorted_lower = PermutedTriangle::new(&a, &p, Triangle::Lower).unwrap();
        let parent = elimination_tree(&upper);
        prop_assert_eq!(&parent, &elimination_tree(sorted_upper.matrix()));
        let post = postorder(&parent);
        prop_assert_eq!(column_counts(&lower, &parent, &post), column_counts(sorted_lower.matrix(), &parent, &post));
    }

    #[test]
    fn column_counts_hold_every_nonzero_of_nalgebras_factor((a, p) in spd_and_permutation(30, 80)) {
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let oracle = nalgebra::Cholesky::new(permuted_dense(&a, symbolic.permutation())).expect("SPD").l();
        for j in 0..a.ncols() {
            let rows = symbolic.column_rows(j);
            let nonzero = (j..a.ncols()).filter(|&i| oracle[(i, j)] != 0.0);
            prop_assert!(nonzero.clone().all(|i| rows.contains(&(i as u32))));
            prop_assert!(nonzero.count() <= symbolic.column_counts()[j]);
        }
    }

    #[test]
    fn supernode_rows_are_the_row_patterns_of_each_first_column((a, p) in spd_and_permutation(30, 80)) {
        // the old way: every column's rows, row by row with ereach
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let upper = PermutedTriangle::new(&a, symbolic.permutation(), Triangle::Upper).unwrap();
        let n = a.ncols();
        let mut columns: Vec<Vec<u32>> = (0..n).map(|j| vec![j as u32]).collect();
        let mut pattern = RowPattern::new(n);
        for k in 0..n {
            for &j in pattern.of_row(upper.matrix(), symbolic.elimination_tree(), k) {
                columns[j].push(k as u32);
            }
        }
        for j in 0..n {
            columns[j].sort_unstable();
            prop_assert_eq!(symbolic.column_rows(j), columns[j].as_slice());
        }
        // on a relaxed partition, the walk gives the relaxed rows directly
        let relaxed = symbolic.relaxed(&Relaxation::CHOLMOD);
        let walked = supernode_rows(upper.matrix(), relaxed.elimination_tree(), relaxed.supernodes(), relaxed.column_counts());
        for s in 0..relaxed.supernodes().len() {
            prop_assert_eq!(&walked.rows[walked.start[s]..walked.start[s + 1]], relaxed.supernode_rows(s));
        }
    }

    #[test]
    fn relaxed_supernodes_hold_the_exact_pattern_and_stay_nested((a, p) in spd_and_permutation(30, 80)) {
        let exact = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let relaxed = exact.clone().relaxed(&Relaxation::CHOLMOD);
        let rows = |s: &SymbolicCholesky, j: usize| s.row_idx()[s.col_ptr()[j]..s.col_ptr()[j + 1]].to_vec();
        // the relaxed pattern stores every exact entry, plus the zeros it counts
        for j in 0..a.ncols() {
            let wide = rows(&relaxed, j);
            prop_assert!(rows(&exact, j).iter().all(|i| wide.contains(i)));
            prop_assert_eq!(wide[0] as usize, j);
            prop_assert!(wide.windows(2).all(|w| w[0] < w[1]));
            prop_assert_eq!(relaxed.column_counts()[j], wide.len());
        }
        prop_assert_eq!(relaxed.nnz_l() - relaxed.explicit_zeros(), exact.nnz_l());
        // each relaxed supernode is one dense trapezoid, no wider than needed
        let supernodes = relaxed.supernodes();
        prop_assert!(supernodes.len() <= exact.supernodes().len());
        let mut covered = 0;
        for s in 0..supernodes.len() {
            let columns = supernodes.columns(s);
            prop_assert_eq!(columns.start, covered);
            covered = columns.end;
            for j in columns.start + 1..columns.end {
                prop_assert_eq!(rows(&relaxed, j), rows(&relaxed, j - 1)[1..].to_vec());
                prop_assert_eq!(supernodes.of_column(j), s);
            }
        }
        prop_assert_eq!(covered, a.ncols());
        // relaxing twice changes nothing; no relaxation is the exact analysis
        let twice = relaxed.clone().relaxed(&Relaxation::NONE);
        prop_assert_eq!(twice.row_idx(), relaxed.row_idx());
        let none = exact.clone().relaxed(&Relaxation::NONE);
        prop_assert_eq!(none.row_idx(), exact.row_idx());
        prop_assert_eq!(none.supernodes(), exact.supernodes());
        // which `relaxed` returns without asking the rule: it merges nothing
        let (merged, _) = relax(exact.supernodes(), exact.elimination_tree(), exact.column_counts(), &Relaxation::NONE);
        prop_assert_eq!(&merged, exact.supernodes());
    }

    #[test]
    fn rows_kept_per_supernode_are_every_columns_rows((a, p) in spd_and_permutation(30, 80)) {
        let exact = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        for mut per_column in [exact.clone(), exact.relaxed(&Relaxation::CHOLMOD)] {
            let mut per_supernode = per_column.clone();
            per_column.store_rows_per_column();
            per_supernode.store_rows_per_supernode();
            prop_assert!(per_supernode.rows_per_supernode() && !per_column.rows_per_supernode());
            prop_assert_eq!(per_supernode.row_idx(), per_column.row_idx());
            for j in 0..a.ncols() {
                prop_assert_eq!(per_supernode.column_rows(j), per_column.column_rows(j));
            }
            for s in 0..per_column.supernodes().len() {
                prop_assert_eq!(per_supernode.supernode_rows(s), per_column.supernode_rows(s));
            }
            prop_assert_eq!(per_supernode.nnz_l(), per_column.nnz_l());
            prop_assert!(per_supernode.bytes() <= per_column.bytes() + 8 * (a.ncols() + 1));
            // relaxing keeps rows per supernode, whichever way they were kept
            let relaxed = per_supernode.relaxed(&Relaxation::CHOLMOD);
            prop_assert!(relaxed.rows_per_supernode());
            let again = per_column.clone().relaxed(&Relaxation::CHOLMOD);
            prop_assert_eq!(relaxed.row_idx(), again.row_idx());
        }
    }

    #[test]
    fn relaxed_factor_equals_nalgebra_cholesky((a, p) in spd_and_permutation(30, 80)) {
        let symbolic = SymbolicCholesky::with_permutation(&a, &p).unwrap().relaxed(&Relaxation::CHOLMOD);
        let cholesky = SparseCholesky::factor(symbolic, &a, Method::Supernodal).unwrap();
        let c = permuted_dense(&a, cholesky.symbolic().permutation());
        let oracle = nalgebra::Cholesky::new(c).expect("SPD").l();
        assert_close(&csc_to_nalgebra(&cholesky.l()), &oracle, 1e-10);
    }

    #[test]
    fn fundamental_and_relaxed_supernodal_factors_agree((a, p) in spd_and_permutation(40, 150)) {
        let exact = SymbolicCholesky::with_permutation(&a, &p).unwrap();
        let fundamental = SparseCholesky::factor(exact.clone().relaxed(&Relaxation::NONE), &a, Method::Supernodal).unwrap();
        let relaxed = SparseCholesky::factor(exact.relaxed(&Relaxation::CHOLMOD), &a, Method::Supernodal).unwrap();
        assert_close(&csc_to_nalgebra(&relaxed.l()), &csc_to_nalgebra(&fundamental.l()), 1e-12);
    }

    #[test]
    fn factor_times_transpose_reproduces_the_permuted_matrix((a, p) in spd_and_permutation(30, 80), method in any_method()) {
        let cholesky = factor(&a, &p, method);
        let l = csc_to_nalgebra(&cholesky.l());
        let c = permuted_dense(&a, cholesky.symbolic().permutation());
        assert_close(&(&l * l.transpose()), &c, 1e-12);
        let column_sizes: Vec<usize> = (0..a.ncols()).map(|j| cholesky.l().column(j).0.len()).collect();
        prop_assert_eq!(column_sizes.as_slice(), cholesky.symbolic().column_counts());
    }

    #[test]
    fn factor_equals_nalgebra_cholesky((a, p) in spd_and_permutation(30, 80), method in any_method()) {
        let cholesky = factor(&a, &p, method);
        let c = permuted_dense(&a, cholesky.symbolic().permutation());
        let oracle = nalgebra::Cholesky::new(c).expect("SPD").l();
        assert_close(&csc_to_nalgebra(&cholesky.l()), &oracle, 1e-10);
    }

    #[test]
    fn solves_match_nalgebra((a, p) in spd_and_permutation(30, 80), method in any_method(), seed in 0u64..1000) {
        let mut cholesky = factor(&a, &p, method);
        let n = a.ncols();
        let b: Vec<[f64; 3]> = (0..n).map(|i| {
            let t = (i as f64 + 1.0) * (seed as f64 + 0.5);
            [t.sin(), t.cos(), (0.3 * t).sin() + 0.1]
        }).collect();
        let dense = csc_to_nalgebra(&a);
        let b_dense = DMatrix::from_fn(n, 3, |i, c| b[i][c]);
        let oracle = nalgebra::Cholesky::new(dense.clone()).unwrap().solve(&b_dense);
        let mut x = b.clone();
        cholesky.solve_points_in_place(&mut x);
        let x_dense = DMatrix::from_fn(n, 3, |i, c| x[i][c]);
        assert_close(&x_dense, &oracle, 1e-9);
        let residual = (&dense * &x_dense - &b_dense).norm() / b_dense.norm();
        prop_assert!(residual < 1e-12, "relative residual {residual:e}");
        // a right-hand side made row by row gives the same, bit for bit
        let mut from_rows = vec![[f64::NAN; 3]; n];
        cholesky.solve_points_from(|i| b[i], &mut from_rows);
        prop_assert!(from_rows.iter().flatten().zip(x.iter().flatten()).all(|(u, v)| u.to_bits() == v.to_bits()));
        // one column at a time gives the same as three at once
        for c in 0..3 {
            let mut column: Vec<f64> = b.iter().map(|row| row[c]).collect();
            cholesky.solve_in_place(&mut column);
            for i in 0..n {
                prop_assert!((column[i] - x[i][c]).abs() <= 1e-14 * (1.0 + x[i][c].abs()));
            }
        }
    }

    #[test]
    fn supernodal_and_simplicial_factors_agree((a, p) in spd_and_permutation(40, 150)) {
        let simplicial = factor(&a, &p, Method::Simplicial).l();
        let supernodal = factor(&a, &p, Method::Supernodal).l();
        assert_close(&csc_to_nalgebra(&supernodal), &csc_to_nalgebra(&simplicial), 1e-12);
    }

    #[test]
    fn refactoring_new_values_equals_factoring_afresh((a, p) in spd_and_permutation(30, 80), shift in 0.5f64..3.0, method in any_method()) {
        let mut cholesky = factor(&a, &p, method);
        // same pattern, new values: scale and strengthen the diagonal
        let diagonal = CscMatrix::from_diagonal(&vec![shift; a.ncols()]);
        let changed = a.scale(1.5).add(&diagonal).unwrap();
        prop_assert!(changed.same_pattern(&a));
        cholesky.refactor(&changed).unwrap();
        let fresh = factor(&changed, &p, method);
        assert_close(&csc_to_nalgebra(&cholesky.l()), &csc_to_nalgebra(&fresh.l()), 1e-14);
    }
}

#[test]
fn the_simplicial_method_refuses_a_relaxed_pattern() {
    let a = grid_matrix(8);
    let relaxed = SymbolicCholesky::analyze(&a, Ordering::Amd)
        .unwrap()
        .relaxed(&Relaxation::CHOLMOD);
    assert!(relaxed.explicit_zeros() > 0);
    let error = SparseCholesky::factor(relaxed, &a, Method::Simplicial).unwrap_err();
    assert!(matches!(error, LinalgError::InvalidStructure(_)), "{error}");
}

#[test]
fn relaxed_grid_solves_have_small_residuals() {
    let a = grid_matrix(100);
    let n = a.ncols();
    // the right-hand side of a smooth displacement of the cloth, as in a
    // time step (a random one would weigh the near-null modes of the
    // springs, where no solver gets a small relative residual)
    let side = 100;
    let smooth: Vec<[f64; 3]> = (0..n)
        .map(|v| {
            let (i, j) = ((v % side) as f64 / 99.0, (v / side) as f64 / 99.0);
            [i, 1.0 - j, 0.1 * (3.0 * i).sin() * j]
        })
        .collect();
    let mut b = vec![[0.0; 3]; n];
    a.mul_points(&smooth, &mut b).unwrap();
    for rule in [Relaxation::NONE, Relaxation::CHOLMOD] {
        let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd)
            .unwrap()
            .relaxed(&rule);
        let mut cholesky = SparseCholesky::factor(symbolic, &a, Method::Supernodal).unwrap();
        let mut x = b.clone();
        cholesky.solve_points_in_place(&mut x);
        let (mut ax, mut error, mut norm) = (vec![[0.0; 3]; n], 0.0, 0.0);
        a.mul_points(&x, &mut ax).unwrap();
        for i in 0..n {
            for c in 0..3 {
                error += (ax[i][c] - b[i][c]).powi(2);
                norm += b[i][c].powi(2);
            }
        }
        let residual = (error / norm).sqrt();
        assert!(residual < 1e-12, "{rule:?}: relative residual {residual:e}");
    }
}

#[test]
fn only_the_lower_triangle_is_read() {
    let a = grid_matrix(6);
    let p = Permutation::identity(a.ncols());
    let full = factor(&a, &p, Method::Supernodal).l();
    let lower = factor(&a.triangle(Triangle::Lower), &p, Method::Supernodal).l();
    assert_eq!(full, lower);
}

#[test]
fn grid_factor_is_right_with_both_methods() {
    // a cloth grid has wide supernodes near the root: exercises the panels
    let a = grid_matrix(24);
    let n = a.ncols();
    let p = Permutation::identity(n);
    let dense = csc_to_nalgebra(&a);
    for method in [Method::Simplicial, Method::Supernodal] {
        let mut cholesky = factor(&a, &p, method);
        let b: Vec<[f64; 3]> = (0..n).map(|i| [1.0, i as f64, (i as f64).sqrt()]).collect();
        let mut x = b.clone();
        cholesky.solve_points_in_place(&mut x);
        let x_dense = DMatrix::from_fn(n, 3, |i, c| x[i][c]);
        let b_dense = DMatrix::from_fn(n, 3, |i, c| b[i][c]);
        let residual = (&dense * &x_dense - &b_dense).norm() / b_dense.norm();
        assert!(
            residual < 1e-12,
            "{method:?}: relative residual {residual:e}"
        );
    }
}

#[test]
fn an_indefinite_matrix_is_reported_at_its_column() {
    // diag(1, 2, -1, 3) has its bad pivot in column 2 whatever the ordering
    let a = CscMatrix::from_diagonal(&[1.0, 2.0, -1.0, 3.0]);
    for perm in [vec![0, 1, 2, 3], vec![3, 2, 1, 0], vec![2, 0, 3, 1]] {
        for method in [Method::Simplicial, Method::Supernodal] {
            let symbolic = SymbolicCholesky::with_permutation(
                &a,
                &Permutation::from_perm(perm.clone()).unwrap(),
            )
            .unwrap();
            let error = SparseCholesky::factor(symbolic, &a, method).unwrap_err();
            assert_eq!(
                error,
                LinalgError::NotPositiveDefinite {
                    column: 2,
                    pivot: -1.0
                },
                "{perm:?} {method:?}"
            );
        }
    }
}

#[test]
fn a_semidefinite_matrix_is_reported_where_the_pivot_vanishes() {
    // [[1, 1], [1, 1]] is singular: the second pivot is 1 - 1 = 0
    let a = masssprings::linalg::sparse::TripletMatrix::from_entries(
        2,
        2,
        [(0, 0, 1.0), (1, 0, 1.0), (0, 1, 1.0), (1, 1, 1.0)],
    )
    .unwrap()
    .to_csc();
    for method in [Method::Simplicial, Method::Supernodal] {
        let symbolic = SymbolicCholesky::with_permutation(&a, &Permutation::identity(2)).unwrap();
        let error = SparseCholesky::factor(symbolic, &a, method).unwrap_err();
        assert_eq!(
            error,
            LinalgError::NotPositiveDefinite {
                column: 1,
                pivot: 0.0
            }
        );
    }
}

#[test]
fn nan_in_the_matrix_is_reported_not_propagated() {
    let a = CscMatrix::from_diagonal(&[1.0, f64::NAN, 1.0]);
    for method in [Method::Simplicial, Method::Supernodal] {
        let symbolic = SymbolicCholesky::with_permutation(&a, &Permutation::identity(3)).unwrap();
        let error = SparseCholesky::factor(symbolic, &a, method).unwrap_err();
        assert!(
            matches!(error, LinalgError::NotPositiveDefinite { column: 1, .. }),
            "{error}"
        );
    }
}

#[test]
fn a_failed_refactorization_can_be_followed_by_a_good_one() {
    let a = grid_matrix(5);
    let mut cholesky = factor(&a, &Permutation::identity(a.ncols()), Method::Supernodal);
    let broken = a.scale(-1.0);
    assert!(matches!(
        cholesky.refactor(&broken),
        Err(LinalgError::NotPositiveDefinite { .. })
    ));
    cholesky.refactor(&a).unwrap();
    let fresh = factor(&a, &Permutation::identity(a.ncols()), Method::Supernodal);
    assert_eq!(cholesky.l(), fresh.l());
}

#[test]
fn refactoring_with_another_pattern_is_an_error() {
    let a = grid_matrix(4);
    let mut cholesky = factor(&a, &Permutation::identity(a.ncols()), Method::Simplicial);
    let other = CscMatrix::identity(a.ncols());
    assert_eq!(cholesky.refactor(&other), Err(LinalgError::PatternMismatch));
}

#[test]
fn analysis_rejects_non_square_matrices_and_wrong_permutations() {
    assert!(matches!(
        SymbolicCholesky::with_permutation(&CscMatrix::zeros(2, 3), &Permutation::identity(3)),
        Err(LinalgError::NotSquare { .. })
    ));
    assert!(matches!(
        SymbolicCholesky::with_permutation(&CscMatrix::identity(3), &Permutation::identity(4)),
        Err(LinalgError::DimensionMismatch { .. })
    ));
}

#[test]
fn an_empty_matrix_factors_and_solves_to_nothing() {
    let a = CscMatrix::zeros(0, 0);
    let mut cholesky = factor(&a, &Permutation::identity(0), Method::Supernodal);
    cholesky.solve_points_in_place(&mut []);
    assert_eq!(cholesky.symbolic().nnz_l(), 0);
}

#[test]
fn grid_316_analysis_and_factor_stay_within_their_memory_budget() {
    // Counted from the structures' lengths (`SparseCholesky::bytes`), not
    // from the process. docs/performance.md itemises the figure.
    // nnz(L) = 4,364,229 values (8 bytes): 34.9 MB; the rows kept once per
    // supernode, 780,309 of them (32-bit) and a pointer for each of the
    // 50,326 supernodes: 3.5 MB (every column's rows took 17.5 MB); the
    // slots of Q's 497,386 lower entries in L (two u32 each), 4.8 MB (the
    // permuted copy of Q it replaced took 12.7 MB); the analysis' n-arrays
    // (permutation, tree, counts, pointers, supernodes), the work arrays and
    // the solve's buffer: 12 MB. Was 77.2 MB, then 69.2 MB.
    const BUDGET: usize = 55_300_000;
    let a = grid_matrix(316);
    let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
    let cholesky = SparseCholesky::factor(symbolic, &a, Method::Supernodal).unwrap();
    let bytes = cholesky.bytes();
    eprintln!(
        "grid-316: {bytes} bytes, nnz(L) stored {}",
        cholesky.symbolic().nnz_l()
    );
    assert!(
        bytes <= BUDGET,
        "grid-316 holds {bytes} bytes, budget {BUDGET}"
    );
}
