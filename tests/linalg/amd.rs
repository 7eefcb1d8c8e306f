//! AMD ordering: it is a permutation, it depends only on the pattern of
//! `A + Aᵀ`, it treats dense rows as SuiteSparse does, and its fill matches
//! SuiteSparse AMD's on the cloth grids.
//!
//! The fill `nnz(L)` of an ordering is counted by an independent oracle in
//! this file (elimination tree by Liu's algorithm, then the row-subtree walk
//! of every row), itself checked against dense symbolic elimination.
use crate::common;

use common::*;
use masssprings::linalg::sparse::amd::{amd, AmdInfo, AmdOptions};
use masssprings::linalg::sparse::{CscMatrix, Permutation, Triangle, TripletMatrix};
use masssprings::linalg::LinalgError;
use proptest::prelude::*;

// ---------------------------------------------------------------------------
// The fill oracle
// ---------------------------------------------------------------------------

const NONE: usize = usize::MAX;

/// For the reordered `C = P (A + Aᵀ) Pᵀ`: for every `k`, the `i < k` with
/// `C(i, k) ≠ 0` (repeats allowed).
fn lower_neighbours(a: &CscMatrix, perm: &Permutation) -> Vec<Vec<usize>> {
    let n = a.ncols();
    let inverse = perm.inverse();
    let mut lower = vec![Vec::new(); n];
    for j in 0..n {
        for &i in a.column(j).0 {
            if i != j {
                let (x, y) = (inverse[i], inverse[j]);
                lower[x.max(y)].push(x.min(y));
            }
        }
    }
    lower
}

/// Elimination tree of `C` (Liu's algorithm with path compression).
fn elimination_tree(lower: &[Vec<usize>]) -> Vec<usize> {
    let n = lower.len();
    let mut parent = vec![NONE; n];
    let mut ancestor = vec![NONE; n];
    for (k, neighbours) in lower.iter().enumerate() {
        for &start in neighbours {
            let mut i = start;
            while i != NONE && i < k {
                let next = ancestor[i];
                ancestor[i] = k;
                if next == NONE {
                    parent[i] = k;
                }
                i = next;
            }
        }
    }
    parent
}

/// `nnz(L)`, diagonal included, of the Cholesky factor of `P (A + Aᵀ) Pᵀ`:
/// row `k` of `L` is the set of nodes on the tree paths from each `i` with
/// `C(k, i) ≠ 0`, `i < k`, up to `k` (Davis 2006, §4.1 "ereach").
fn factor_nnz(a: &CscMatrix, perm: &Permutation) -> usize {
    let lower = lower_neighbours(a, perm);
    let parent = elimination_tree(&lower);
    let n = lower.len();
    let mut mark = vec![NONE; n];
    let mut count = n;
    for (k, neighbours) in lower.iter().enumerate() {
        mark[k] = k;
        for &start in neighbours {
            let mut i = start;
            while mark[i] != k {
                mark[i] = k;
                count += 1;
                i = parent[i];
            }
        }
    }
    count
}

/// The same count by dense boolean elimination, `O(n³)`: the oracle's oracle.
fn factor_nnz_dense(a: &CscMatrix, perm: &Permutation) -> usize {
    let n = a.ncols();
    let inverse = perm.inverse();
    let mut filled = vec![vec![false; n]; n];
    for j in 0..n {
        for &i in a.column(j).0 {
            let (x, y) = (inverse[i], inverse[j]);
            filled[x][y] = true;
            filled[y][x] = true;
        }
    }
    let mut count = 0;
    for k in 0..n {
        let below: Vec<usize> = (k + 1..n).filter(|&i| filled[i][k]).collect();
        count += 1 + below.len();
        for &i in &below {
            for &j in &below {
                filled[i][j] = true;
            }
        }
    }
    count
}

// ---------------------------------------------------------------------------
// Matrices
// ---------------------------------------------------------------------------

/// The `n × n` matrix with the given pattern, every value `value(i, j)`.
fn from_pattern(
    n: usize,
    entries: &[(usize, usize)],
    value: impl Fn(usize, usize) -> f64,
) -> CscMatrix {
    let mut t = TripletMatrix::new(n, n);
    for &(i, j) in entries {
        t.push(i, j, value(i, j)).unwrap();
    }
    t.to_csc()
}

/// The pattern of `A + Aᵀ`, diagonal kept, as a full matrix of ones.
fn symmetrized(a: &CscMatrix) -> CscMatrix {
    let n = a.ncols();
    let mut entries = Vec::new();
    for j in 0..n {
        for &i in a.column(j).0 {
            entries.push((i, j));
            entries.push((j, i));
        }
    }
    from_pattern(n, &entries, |_, _| 1.0)
}

/// An `n × n` pattern of one of several kinds (see [`pattern`]).
#[derive(Debug, Clone)]
struct Pattern {
    n: usize,
    entries: Vec<(usize, usize)>,
}

/// Random unsymmetric entries, sparse or dense.
fn random_entries(max_n: usize) -> impl Strategy<Value = Pattern> {
    (0..=max_n, 0..=4usize).prop_flat_map(|(n, density)| {
        let side = n.max(1);
        let count = n * density * density;
        prop::collection::vec((0..side, 0..side), 0..=count).prop_map(move |entries| Pattern {
            n,
            entries: if n == 0 { Vec::new() } else { entries },
        })
    })
}

/// The diagonal only.
fn diagonal_only(max_n: usize) -> impl Strategy<Value = Pattern> {
    (0..=max_n).prop_map(|n| Pattern {
        n,
        entries: (0..n).map(|i| (i, i)).collect(),
    })
}

/// Random sparse entries plus one full row and column.
fn with_dense_row(max_n: usize) -> impl Strategy<Value = Pattern> {
    (random_entries(max_n), any::<prop::sample::Index>()).prop_map(|(mut p, which)| {
        if p.n > 0 {
            let d = which.index(p.n);
            p.entries.extend((0..p.n).flat_map(|k| [(d, k), (k, d)]));
        }
        p
    })
}

/// Several disconnected random blocks, their indices shuffled together.
fn components(max_n: usize) -> impl Strategy<Value = Pattern> {
    prop::collection::vec(random_entries(max_n / 3), 1..=4)
        .prop_flat_map(|blocks| {
            let n: usize = blocks.iter().map(|b| b.n).sum();
            (
                Just(blocks),
                Just((0..n).collect::<Vec<_>>()).prop_shuffle(),
            )
        })
        .prop_map(|(blocks, relabel)| {
            let mut entries = Vec::new();
            let mut offset = 0;
            for b in &blocks {
                entries.extend(
                    b.entries
                        .iter()
                        .map(|&(i, j)| (relabel[offset + i], relabel[offset + j])),
                );
                offset += b.n;
            }
            Pattern { n: offset, entries }
        })
}

/// Any of the kinds above.
fn pattern(max_n: usize) -> impl Strategy<Value = Pattern> {
    prop_oneof![
        3 => random_entries(max_n),
        1 => diagonal_only(max_n),
        2 => with_dense_row(max_n),
        2 => components(max_n),
    ]
}

/// A reproducible random symmetric pattern (full, diagonal included): each
/// column gets `per_column` off-diagonal entries at rows drawn by xorshift.
fn random_symmetric(n: usize, per_column: usize, seed: u64) -> CscMatrix {
    let mut state = seed | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut entries: Vec<(usize, usize)> = (0..n).map(|i| (i, i)).collect();
    for j in 0..n {
        for _ in 0..per_column {
            let i = (next() % n as u64) as usize;
            entries.extend([(i, j), (j, i)]);
        }
    }
    from_pattern(n, &entries, |_, _| 1.0)
}

fn order(a: &CscMatrix) -> (Permutation, AmdInfo) {
    amd(a, &AmdOptions::default()).expect("square input")
}

/// nnz(L) of `A` under AMD and under the natural order.
fn amd_and_natural_fill(a: &CscMatrix) -> (usize, usize) {
    let (perm, _) = order(a);
    (
        factor_nnz(a, &perm),
        factor_nnz(a, &Permutation::identity(a.ncols())),
    )
}

// ---------------------------------------------------------------------------
// Properties on random patterns
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(proptest_config(512))]

    #[test]
    fn fill_oracle_matches_dense_symbolic_elimination(p in pattern(24), seed in any::<u64>()) {
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let mut perm: Vec<usize> = (0..p.n).collect();
        // a cheap deterministic shuffle from the seed
        let mut s = seed | 1;
        for k in (1..p.n).rev() {
            s ^= s << 13; s ^= s >> 7; s ^= s << 17;
            perm.swap(k, (s % (k as u64 + 1)) as usize);
        }
        let perm = Permutation::from_perm(perm).unwrap();
        prop_assert_eq!(factor_nnz(&a, &perm), factor_nnz_dense(&a, &perm));
    }

    #[test]
    fn amd_returns_a_permutation(p in pattern(60)) {
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let (perm, info) = order(&a);
        prop_assert_eq!(perm.len(), p.n);
        prop_assert!(info.dense_rows + info.empty_rows <= p.n);
        // every non-dense variable is in some element's block
        prop_assert!(info.elements <= p.n);
    }

    #[test]
    fn amd_is_deterministic(p in pattern(60)) {
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        prop_assert_eq!(order(&a), order(&a.clone()));
    }

    #[test]
    fn amd_ignores_the_values(p in pattern(60)) {
        let ones = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let varied = from_pattern(p.n, &p.entries, |i, j| (i as f64 - 2.5 * j as f64).sin());
        prop_assert_eq!(order(&ones).0, order(&varied).0);
    }

    #[test]
    fn amd_ignores_the_diagonal(p in pattern(60)) {
        let without: Vec<(usize, usize)> = p.entries.iter().copied().filter(|&(i, j)| i != j).collect();
        let mut with = without.clone();
        with.extend((0..p.n).map(|i| (i, i)));
        prop_assert_eq!(
            order(&from_pattern(p.n, &without, |_, _| 1.0)).0,
            order(&from_pattern(p.n, &with, |_, _| 1.0)).0
        );
    }

    #[test]
    fn amd_orders_the_pattern_of_a_plus_a_transpose(p in pattern(60)) {
        // Unsymmetric A, full A + Aᵀ and either triangle of it: one ordering.
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let full = symmetrized(&a);
        let expected = order(&full).0;
        prop_assert_eq!(&order(&a).0, &expected);
        prop_assert_eq!(&order(&full.triangle(Triangle::Lower)).0, &expected);
        prop_assert_eq!(&order(&full.triangle(Triangle::Upper)).0, &expected);
    }

    #[test]
    fn amd_fill_estimate_bounds_the_exact_fill(p in pattern(60)) {
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let (perm, info) = order(&a);
        prop_assert!(factor_nnz(&a, &perm) <= info.factor_nnz_estimate);
    }

    #[test]
    fn amd_without_aggressive_absorption_returns_a_permutation(p in pattern(60)) {
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let options = AmdOptions { aggressive_absorption: false, ..AmdOptions::default() };
        let (perm, info) = amd(&a, &options).unwrap();
        prop_assert_eq!(perm.len(), p.n);
        prop_assert_eq!(info.aggressive_absorptions, 0);
        prop_assert!(factor_nnz(&a, &perm) <= info.factor_nnz_estimate);
    }

    #[test]
    fn amd_orders_the_dense_rows_last_by_increasing_index(p in pattern(60)) {
        // Threshold 0: rows with more than 16 off-diagonal entries are dense.
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let full = symmetrized(&a);
        let dense: Vec<usize> = (0..p.n)
            .filter(|&j| full.column(j).0.iter().filter(|&&i| i != j).count() > 16)
            .collect();
        let options = AmdOptions { dense_threshold: 0.0, ..AmdOptions::default() };
        let (perm, info) = amd(&a, &options).unwrap();
        prop_assert_eq!(info.dense_rows, dense.len());
        prop_assert_eq!(&perm.perm()[p.n - dense.len()..], &dense[..]);
        prop_assert!(factor_nnz(&a, &perm) <= info.factor_nnz_estimate);
    }

    #[test]
    fn amd_without_dense_rows_returns_a_permutation(p in pattern(60)) {
        let a = from_pattern(p.n, &p.entries, |_, _| 1.0);
        let options = AmdOptions { dense_threshold: -1.0, ..AmdOptions::default() };
        let (perm, info) = amd(&a, &options).unwrap();
        prop_assert_eq!(perm.len(), p.n);
        prop_assert_eq!(info.dense_rows, 0);
    }
}

// ---------------------------------------------------------------------------
// Structure
// ---------------------------------------------------------------------------

#[test]
fn amd_rejects_a_non_square_matrix() {
    let a = CscMatrix::zeros(3, 4);
    assert_eq!(
        amd(&a, &AmdOptions::default()).unwrap_err(),
        LinalgError::NotSquare { nrows: 3, ncols: 4 }
    );
}

#[test]
fn amd_of_the_empty_matrix_is_the_empty_permutation() {
    let (perm, info) = order(&CscMatrix::zeros(0, 0));
    assert!(perm.is_empty());
    assert_eq!(info, AmdInfo::default());
}

#[test]
fn amd_of_a_diagonal_matrix_is_the_identity() {
    let (perm, info) = order(&CscMatrix::identity(7));
    assert_eq!(perm, Permutation::identity(7));
    assert_eq!(info.empty_rows, 7);
}

/// A path `0 – 1 – … – (n−1)` plus one row/column `hub` full.
fn path_with_full_row(n: usize, hub: usize) -> CscMatrix {
    let mut entries: Vec<(usize, usize)> = (0..n).map(|i| (i, i)).collect();
    entries.extend((1..n).flat_map(|i| [(i - 1, i), (i, i - 1)]));
    entries.extend((0..n).flat_map(|k| [(hub, k), (k, hub)]));
    from_pattern(n, &entries, |_, _| 1.0)
}

#[test]
fn amd_orders_a_dense_row_last() {
    // n = 400: the hub has 399 > max(16, 10·√400 = 200) off-diagonal entries.
    let a = path_with_full_row(400, 137);
    let (perm, info) = order(&a);
    assert_eq!(info.dense_rows, 1);
    assert_eq!(perm.perm()[399], 137);
    // Without the hub, two paths (397 edges) order with no fill; the hub row is full.
    assert_eq!(factor_nnz(&a, &perm), 399 + 397 + 400);
}

#[test]
fn amd_orders_the_dense_rows_of_an_arrowhead_last() {
    // Two full rows of an arrowhead matrix, both dense: last, by increasing index.
    let n = 500;
    let mut entries: Vec<(usize, usize)> = (0..n).map(|i| (i, i)).collect();
    for hub in [3, 250] {
        entries.extend((0..n).map(|k| (hub, k)));
    }
    let a = from_pattern(n, &entries, |_, _| 1.0);
    let (perm, info) = order(&a);
    assert_eq!(info.dense_rows, 2);
    assert_eq!(&perm.perm()[n - 2..], &[3, 250]);
}

#[test]
fn amd_with_dense_detection_off_keeps_the_full_row() {
    let a = path_with_full_row(400, 137);
    let options = AmdOptions {
        dense_threshold: -1.0,
        ..AmdOptions::default()
    };
    let (perm, info) = amd(&a, &options).unwrap();
    assert_eq!(info.dense_rows, 0);
    // Minimum degree still leaves the hub to the end: no fill beyond its row.
    assert_eq!(factor_nnz(&a, &perm), 399 + 397 + 400);
}

#[test]
fn amd_without_aggressive_absorption_orders_a_grid_well() {
    let a = grid_matrix(32);
    let options = AmdOptions {
        aggressive_absorption: false,
        ..AmdOptions::default()
    };
    let (perm, info) = amd(&a, &options).unwrap();
    assert_eq!(info.aggressive_absorptions, 0);
    let fill = factor_nnz(&a, &perm);
    let natural_fill = factor_nnz(&a, &Permutation::identity(a.ncols()));
    assert!(fill < natural_fill, "{fill} ≥ natural {natural_fill}");
}

// ---------------------------------------------------------------------------
// Quality on the cloth grids
// ---------------------------------------------------------------------------

#[test]
fn amd_fill_is_at_most_the_natural_fill_on_grids() {
    for side in [10, 32, 100] {
        let (amd_fill, natural_fill) = amd_and_natural_fill(&grid_matrix(side));
        assert!(
            amd_fill <= natural_fill,
            "grid-{side}: AMD {amd_fill} > natural {natural_fill}"
        );
    }
}

/// `nnz(L)` within 2 % of SuiteSparse AMD 3.x's (amd_order, default options).
fn assert_within_two_percent_of_suitesparse(side: usize, suitesparse: usize) {
    let a = grid_matrix(side);
    let (perm, _) = order(&a);
    let fill = factor_nnz(&a, &perm);
    let ratio = fill as f64 / suitesparse as f64;
    assert!(
        (0.98..=1.02).contains(&ratio),
        "grid-{side}: nnz(L) = {fill}, SuiteSparse {suitesparse} (ratio {ratio:.4})"
    );
}

#[test]
fn amd_fill_is_within_two_percent_of_suitesparse_on_grid_100() {
    assert_within_two_percent_of_suitesparse(100, 306_189);
}

#[test]
fn amd_fill_is_within_two_percent_of_suitesparse_on_grid_316() {
    assert_within_two_percent_of_suitesparse(316, 4_364_229);
}

/// SuiteSparse AMD's permutation of grid-10 (`amd_order`, default options),
/// which ours reproduces exactly, ties included.
const SUITESPARSE_GRID_10: [usize; 100] = [
    46, 45, 79, 99, 98, 97, 89, 88, 87, 78, 77, 59, 49, 58, 48, 68, 69, 67, 3, 2, 0, 10, 20, 21, 1,
    11, 12, 13, 22, 23, 5, 15, 9, 19, 29, 7, 17, 8, 18, 28, 27, 6, 16, 26, 25, 4, 14, 24, 53, 43,
    70, 90, 91, 92, 80, 81, 82, 71, 72, 50, 40, 51, 41, 60, 61, 42, 62, 52, 63, 65, 95, 94, 85, 84,
    75, 64, 74, 83, 93, 73, 30, 31, 32, 33, 34, 35, 37, 38, 39, 44, 47, 54, 55, 56, 57, 66, 76, 86,
    96, 36,
];

#[test]
fn amd_reproduces_the_suitesparse_permutation_on_grid_10() {
    let grid = grid_matrix(10);
    assert_eq!(order(&grid).0.perm(), &SUITESPARSE_GRID_10);
    // The same from the lower triangle alone.
    assert_eq!(
        order(&grid.triangle(Triangle::Lower)).0.perm(),
        &SUITESPARSE_GRID_10
    );
}

#[test]
fn amd_fill_matches_suitesparse_through_garbage_collections() {
    // Random sparse patterns fill up the 20 % elbow room several times.
    // SuiteSparse (3 and 1 compressions) gives the same permutations.
    for (n, per_column, seed, suitesparse) in [(2000, 3, 7, 313_702), (300, 8, 11, 23_133)] {
        let a = random_symmetric(n, per_column, seed);
        let (perm, info) = order(&a);
        assert!(info.garbage_collections >= 1, "no compression: {info:?}");
        let fill = factor_nnz(&a, &perm);
        let ratio = fill as f64 / suitesparse as f64;
        assert!(
            (0.98..=1.02).contains(&ratio),
            "n = {n}: nnz(L) = {fill}, SuiteSparse {suitesparse}"
        );
    }
}

#[test]
#[ignore = "writes matrices and permutations to /tmp/amdc for comparison with SuiteSparse"]
fn dump_for_suitesparse_comparison() {
    let mut matrices: Vec<(String, CscMatrix)> = [10, 32, 100, 316]
        .iter()
        .map(|&s| (format!("{s}"), grid_matrix(s)))
        .collect();
    matrices.push(("random2000".into(), random_symmetric(2000, 3, 7)));
    matrices.push(("random300".into(), random_symmetric(300, 8, 11)));
    for (name, a) in &matrices {
        let (perm, info) = order(a);
        let text: String = perm.perm().iter().map(|p| format!("{p}\n")).collect();
        std::fs::write(format!("/tmp/amdc/rust{name}.txt"), text).unwrap();
        let lower = a.triangle(Triangle::Lower);
        let mut mtx = format!(
            "%%MatrixMarket matrix coordinate real symmetric\n{0} {0} {1}\n",
            a.ncols(),
            lower.nnz()
        );
        for j in 0..a.ncols() {
            for &i in lower.column(j).0 {
                mtx.push_str(&format!("{} {} 1\n", i + 1, j + 1));
            }
        }
        std::fs::write(format!("/tmp/amdc/{name}.mtx"), mtx).unwrap();
        eprintln!("{name}: nnz(L) = {}, {info:?}", factor_nnz(a, &perm));
    }
}
