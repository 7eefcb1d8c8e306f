//! The worked example of `docs/sparse-cholesky.md`, step by step: every
//! number the chapter shows is checked here, so the chapter cannot drift
//! from the code. `Q` is built exactly as the simulation builds it (the
//! precomputation's own steps, and the precomputation itself).

use masssprings::linalg::dense::gram_block::gram_block;
use masssprings::linalg::sparse::column_counts::column_counts;
use masssprings::linalg::sparse::etree::elimination_tree;
use masssprings::linalg::sparse::postorder::postorder;
use masssprings::linalg::sparse::{
    CscMatrix, Method, Ordering, PermutedTriangle, SparseCholesky, SymbolicCholesky, Triangle,
    TripletMatrix,
};
use masssprings::sim::precomputation::MassSpringSystem;
use masssprings::sim::signed_incidence::{
    signed_incidence_entries, signed_incidence_matrix_sparse,
};
use masssprings::sim::{LinearAlgebra, Sparse, PIN_WEIGHT};

/// The star: vertex 0 joined by a spring to each of vertices 1 to 4.
const SPRINGS: [[usize; 2]; 4] = [[0, 1], [0, 2], [0, 3], [0, 4]];
/// Rest positions (they do not enter `Q`).
const REST: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, -1.0, 0.0],
];
/// k = 1, m = 1, Δt = 1.
const K: f64 = 1.0;
const MASSES: [f64; 5] = [1.0; 5];
const DELTA_T: f64 = 1.0;

/// The chapter's §1, in the simulation's own steps (`src/sim/precomputation.rs`):
/// `A` from ±1 triplets, `AᵀA`, `M` and `M/Δt²`, `C` (no pins), then
/// `Q = k AᵀA + M/Δt² + w CᵀC`.
struct Assembly {
    a: CscMatrix,
    ata: CscMatrix,
    m_over_dt2: CscMatrix,
    q: CscMatrix,
}

fn assemble_step_by_step() -> Assembly {
    let a = signed_incidence_matrix_sparse(5, &SPRINGS);
    let ata = a.transpose_mul_self();
    let m = Sparse::from_entries(5, 5, MASSES.iter().enumerate().map(|(i, &mi)| (i, i, mi)));
    let m_over_dt2 = Sparse::divide(&m, DELTA_T * DELTA_T);
    let c = Sparse::from_entries(0, 5, []); // no pins: C has no rows
    let springs_and_mass = Sparse::combine(K, &ata, 1.0, &m_over_dt2);
    let q = Sparse::combine(1.0, &springs_and_mass, PIN_WEIGHT, &Sparse::gram(&c));
    Assembly {
        a,
        ata,
        m_over_dt2,
        q,
    }
}

/// `Q` of the star as the precomputation builds it.
fn star() -> CscMatrix {
    MassSpringSystem::<Sparse>::new(&REST, &SPRINGS, K, &MASSES, &[], DELTA_T)
        .unwrap()
        .Q
}

#[test]
fn step_1_a_comes_from_plus_and_minus_one_triplets() {
    let triplets: Vec<_> = signed_incidence_entries(&SPRINGS).collect();
    assert_eq!(
        triplets,
        [
            (0, 0, 1.0),
            (0, 1, -1.0),
            (1, 0, 1.0),
            (1, 2, -1.0),
            (2, 0, 1.0),
            (2, 3, -1.0),
            (3, 0, 1.0),
            (3, 4, -1.0)
        ]
    );
    let Assembly { a, .. } = assemble_step_by_step();
    assert_eq!((a.nrows(), a.ncols()), (4, 5));
    assert_eq!(a.col_ptr(), [0, 4, 5, 6, 7, 8]);
    assert_eq!(a.row_idx(), [0, 1, 2, 3, 0, 1, 2, 3]);
    assert_eq!(a.values(), [1.0, 1.0, 1.0, 1.0, -1.0, -1.0, -1.0, -1.0]);
    // the same A from a triplet list compressed by hand
    let by_hand = TripletMatrix::from_entries(4, 5, triplets)
        .unwrap()
        .to_csc();
    assert_eq!(by_hand, a);
}

#[test]
fn step_1_q_is_ata_plus_m_over_dt2_plus_w_ctc() {
    let Assembly {
        ata, m_over_dt2, q, ..
    } = assemble_step_by_step();
    // AᵀA: the hub's four springs on its diagonal, one per leaf
    assert_eq!(ata.col_ptr(), [0, 5, 7, 9, 11, 13]);
    assert_eq!(ata.row_idx(), [0, 1, 2, 3, 4, 0, 1, 0, 2, 0, 3, 0, 4]);
    assert_eq!(
        ata.values(),
        [4.0, -1.0, -1.0, -1.0, -1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0]
    );
    assert_eq!(m_over_dt2.values(), [1.0; 5]);
    // Q, both triangles, as the simulation stores it
    assert_eq!(q.col_ptr(), [0, 5, 7, 9, 11, 13]);
    assert_eq!(q.row_idx(), [0, 1, 2, 3, 4, 0, 1, 0, 2, 0, 3, 0, 4]);
    assert_eq!(
        q.values(),
        [5.0, -1.0, -1.0, -1.0, -1.0, -1.0, 2.0, -1.0, 2.0, -1.0, 2.0, -1.0, 2.0]
    );
    // and the precomputation builds exactly this matrix
    assert_eq!(star(), q);
}

#[test]
fn step_1_a_pin_adds_w_to_its_diagonal() {
    let pinned = MassSpringSystem::<Sparse>::new(&REST, &SPRINGS, K, &MASSES, &[2], DELTA_T)
        .unwrap()
        .Q;
    let free = star();
    for j in 0..5 {
        for i in 0..5 {
            let expected = free.get(i, j) + if (i, j) == (2, 2) { PIN_WEIGHT } else { 0.0 };
            assert_eq!(pinned.get(i, j), expected, "Q({i}, {j})");
        }
    }
}

#[test]
fn step_1_the_lower_triangle_in_csc() {
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
    assert_eq!(*symbolic.row_idx(), [0, 4, 1, 4, 2, 4, 3, 4, 4]);
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

#[test]
fn step_7_one_supernodal_update() {
    let q = star();
    let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
    let cholesky = SparseCholesky::factor(symbolic, &q, Method::Supernodal).unwrap();
    let l = cholesky.l();
    // supernode {0} updates supernode {3, 4}: X = L(4..5, 0), its rows from
    // the first one inside {3, 4} down; Y = its rows inside {3, 4} (row 4,
    // column 1 of the block). The kernel computes X Yᵀ = (−1/√2)² = ½.
    let values = l.values();
    let column_base = [l.col_ptr()[0]]; // row position p of column 0 at values[0 + p]
    let (first, width, rows) = (1, 1, 1); // position 1 (row 4), one column, one row
    let mut block = [f64::NAN; 4];
    let mut rows_of_y = [[0.0; 4]; 1];
    gram_block(
        values,
        &column_base,
        first,
        width,
        rows,
        &mut block,
        &mut rows_of_y,
    );
    assert!((block[0] - 0.5).abs() < 1e-15, "{}", block[0]);
    // three such updates (from {0}, {1}, {2}) take C(4, 4) = 5 to 3.5; the
    // block [[2, ·], [−1, 3.5]] then factors densely: √2, −1/√2, √(3.5 − ½)
    let block_after_updates = [2.0, -1.0, 5.0 - 3.0 * block[0]];
    let l33 = block_after_updates[0].sqrt();
    let l43 = block_after_updates[1] / l33;
    let l44 = (block_after_updates[2] - l43 * l43).sqrt();
    let stored = &values[l.col_ptr()[3]..];
    assert!((stored[0] - l33).abs() < 1e-15);
    assert!((stored[1] - l43).abs() < 1e-15);
    assert!((stored[2] - l44).abs() < 1e-15);
    assert!((l44 - 3f64.sqrt()).abs() < 1e-15);
}
