//! The kernels that exist twice, a plain version and a fast one, agree on
//! every machine. The plain versions are called directly here, so they run
//! under `cargo test` even on a CPU with AVX2, where the library would
//! otherwise always choose the fast ones:
//!
//! * `gram_block_portable` against `gram_block` (AVX2 + FMA when present),
//!   both against the sums computed here from their definition;
//! * `sim::local_step::project_springs` (the formula, one spring at a
//!   time) against `sim::simd::local_step::project_springs` (four springs
//!   per AVX2 instruction when present): the same operations lane by lane,
//!   so the same bits;
//! * `project_springs_into_transpose` (the local step and `Aᵀd` in one
//!   pass, what the plain iteration runs), in both versions, against the
//!   local step then `incidence_transpose_mul_points`: the same bits;
//! * the spring pass (`Springs::measure`, AVX2 when present, against
//!   `measure_portable`): `d` the local step's bits, `Aᵀd` the scatter's
//!   bits, the energy sum and the
//!   spring forces against their definitions;
//! * with the portable kernels chosen (`linalg::kernels`), the
//!   dispatchers against the portable versions: the same bits;
//! * `back_substitution_sparse` (one sum, the textbook loop) against
//!   `back_substitution_sparse_two_sums` (two partial sums), and both
//!   sparse substitutions against the dense ones.
use crate::common;

use common::*;
use masssprings::linalg::dense::gram_block::{gram_block, gram_block_portable, BLOCK_COLUMNS};
use masssprings::linalg::dense::{back_substitution_dense, forward_substitution_dense};
use masssprings::linalg::sparse::triangular_solve::{
    back_substitution_sparse, back_substitution_sparse_two_sums, forward_substitution_sparse,
    FactorView,
};
use masssprings::linalg::sparse::{Method, Ordering, SparseCholesky, SymbolicCholesky};
use masssprings::sim::local_step::{
    project_springs as project_springs_portable,
    project_springs_into_transpose as project_springs_into_transpose_portable,
};
use masssprings::sim::signed_incidence::incidence_transpose_mul_points;
use masssprings::sim::simd::local_step::{project_springs, project_springs_into_transpose};
use masssprings::sim::spring_pass::{Outputs, Springs};
use proptest::prelude::*;

/// `gram_block` or `gram_block_portable`.
type GramBlockKernel = fn(&[f64], &[usize], usize, usize, usize, &mut [f64], &mut [[f64; 4]]);

/// The arguments of a `gram_block` call: values of `X`, where each column
/// starts, the first row, the block's width and its number of rows.
#[derive(Debug, Clone)]
struct GramBlockCase {
    values: Vec<f64>,
    column_base: Vec<usize>,
    first: usize,
    width: usize,
    rows: usize,
}

fn gram_block_case() -> impl Strategy<Value = GramBlockCase> {
    // up to 11 columns, or 60 to 99 (the fast kernel prefetches from 64 on)
    let columns = prop_oneof![0usize..12, 60usize..100];
    (1usize..40, 0usize..6, columns).prop_flat_map(|(rows, first, columns)| {
        let width = 1..=rows.min(BLOCK_COLUMNS);
        let gaps = prop::collection::vec(0usize..4, columns);
        (Just(rows), Just(first), width, gaps).prop_flat_map(|(rows, first, width, gaps)| {
            // column k starts after column k − 1 ends, plus a gap
            let mut column_base = Vec::with_capacity(gaps.len());
            let mut next = 0;
            for gap in gaps {
                column_base.push(next + gap);
                next += gap + first + rows;
            }
            prop::collection::vec(-1.0f64..1.0, next).prop_map(move |values| GramBlockCase {
                values,
                column_base: column_base.clone(),
                first,
                width,
                rows,
            })
        })
    })
}

impl GramBlockCase {
    /// The block computed by `kernel` (one of the two versions).
    fn run(&self, kernel: GramBlockKernel) -> Vec<f64> {
        let mut block = vec![f64::NAN; BLOCK_COLUMNS * self.rows];
        let mut rows_of_y = vec![[f64::NAN; BLOCK_COLUMNS]; self.column_base.len()];
        kernel(
            &self.values,
            &self.column_base,
            self.first,
            self.width,
            self.rows,
            &mut block,
            &mut rows_of_y,
        );
        block
    }

    /// `X(p, k)`.
    fn x(&self, p: usize, k: usize) -> f64 {
        self.values[self.column_base[k] + p]
    }

    /// Entry `(r, t)` from the definition, and the sum of the absolute
    /// values of its terms (the scale of its rounding error).
    fn expected(&self, r: usize, t: usize) -> (f64, f64) {
        if t >= self.width {
            return (0.0, 0.0);
        }
        (0..self.column_base.len())
            .map(|k| self.x(self.first + r, k) * self.x(self.first + t, k))
            .fold((0.0, 0.0), |(sum, scale), term| {
                (sum + term, scale + term.abs())
            })
    }
}

/// `Lᵀ`-ready factor of a random SPD matrix, as the simplicial method stores it.
fn simplicial_factor(a: &masssprings::linalg::sparse::CscMatrix) -> SparseCholesky {
    let symbolic = SymbolicCholesky::analyze(a, Ordering::Amd).unwrap();
    SparseCholesky::factor(symbolic, a, Method::Simplicial).unwrap()
}

/// Positions, springs (self-loops and zero lengths included) and rest
/// lengths of a random small network.
#[allow(clippy::type_complexity)]
fn spring_network() -> impl Strategy<Value = (Vec<[f64; 3]>, Vec<[usize; 2]>, Vec<f64>)> {
    (2usize..20)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(prop::array::uniform3(-10.0f64..10.0), n),
                prop::collection::vec(prop::array::uniform2(0..n), 0..40),
                prop::collection::vec(0.0f64..3.0, 40),
            )
        })
        .prop_map(|(p, springs, r)| {
            let m = springs.len();
            (p, springs, r[..m].to_vec())
        })
}

proptest! {
    #![proptest_config(proptest_config(300))]

    /// `⟨x, y⟩` and `y + α x` four numbers per instruction give the bits
    /// of their one-number-at-a-time loops, for any length (the tail after
    /// the last full four included).
    #[test]
    fn block_vector_dot_and_add_scaled_give_the_bits_of_their_loops(
        pairs in prop::collection::vec(
            (prop::array::uniform3(-1e3f64..1e3), prop::array::uniform3(-1e3f64..1e3)),
            0..40,
        ),
        alpha in -10.0f64..10.0,
    ) {
        use masssprings::sim::methods::block_vector::{add_scaled, add_scaled_lanes, dot, dot_lanes};
        let (x, y): (Vec<[f64; 3]>, Vec<[f64; 3]>) = pairs.into_iter().unzip();
        prop_assert_eq!(dot(&x, &y).to_bits(), dot_lanes(&x, &y).to_bits());
        let (mut fast, mut lanes) = (y.clone(), y.clone());
        add_scaled(&mut fast, alpha, &x);
        add_scaled_lanes(&mut lanes, alpha, &x);
        prop_assert_eq!(fast, lanes);
        let exact: f64 = x.iter().zip(&y).map(|(a, b)| (0..3).map(|c| a[c] * b[c]).sum::<f64>()).sum();
        let scale: f64 = x.iter().zip(&y).map(|(a, b)| (0..3).map(|c| (a[c] * b[c]).abs()).sum::<f64>()).sum();
        prop_assert!((dot(&x, &y) - exact).abs() <= 1e-13 * scale.max(1.0));
    }

    #[test]
    fn gram_block_portable_and_fast_agree_with_the_definition(case in gram_block_case()) {
        let portable = case.run(gram_block_portable);
        let fast = case.run(gram_block);
        for t in 0..BLOCK_COLUMNS {
            for r in 0..case.rows {
                let (want, scale) = case.expected(r, t);
                let tolerance = 1e-14 * scale.max(f64::MIN_POSITIVE);
                let (p, f) = (portable[t * case.rows + r], fast[t * case.rows + r]);
                prop_assert!((p - want).abs() <= tolerance, "portable ({r}, {t}): {p} vs {want}");
                prop_assert!((f - want).abs() <= tolerance, "fast ({r}, {t}): {f} vs {want}");
                prop_assert!((p - f).abs() <= tolerance, "({r}, {t}): portable {p}, fast {f}");
            }
        }
        // With FMA, every fast version (AVX-512 tiles of 16 rows, AVX2 tiles
        // of 8, single rows) makes each entry by the same chain of fused
        // multiply-adds over the columns in order: the same bits.
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("fma") {
            for t in 0..BLOCK_COLUMNS {
                for r in 0..case.rows {
                    let chain = case.column_base.iter().fold(0.0f64, |sum, &base| {
                        let y = if t < case.width { case.values[base + case.first + t] } else { 0.0 };
                        case.values[base + case.first + r].mul_add(y, sum)
                    });
                    prop_assert_eq!(fast[t * case.rows + r].to_bits(), chain.to_bits(), "({}, {})", r, t);
                }
            }
        }
    }

    #[test]
    fn spring_projection_portable_and_fast_give_the_same_bits(
        (p, springs, r) in spring_network()
    ) {
        let m = springs.len();
        let (mut portable, mut fast) = (vec![[f64::NAN; 3]; m], vec![[f64::NAN; 3]; m]);
        project_springs_portable(&springs, &r, &p, &mut portable);
        project_springs(&springs, &r, &p, &mut fast);
        for e in 0..m {
            prop_assert_eq!(portable[e], fast[e], "spring {}", e);
            let [i, j] = springs[e];
            let v: [f64; 3] = std::array::from_fn(|c| p[i][c] - p[j][c]);
            let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let d_length = portable[e].iter().map(|x| x * x).sum::<f64>().sqrt();
            let want = if length > 0.0 { r[e] } else { 0.0 };
            prop_assert!((d_length - want).abs() <= 1e-12 * (1.0 + want), "spring {}: |d| = {} vs r = {}", e, d_length, r[e]);
        }
    }

    #[test]
    fn local_step_into_transpose_gives_the_bits_of_the_two_passes(
        (p, springs, r) in spring_network()
    ) {
        let (m, n) = (springs.len(), p.len());
        let mut d = vec![[f64::NAN; 3]; m];
        project_springs_portable(&springs, &r, &p, &mut d);
        let mut two_passes = vec![[f64::NAN; 3]; n];
        incidence_transpose_mul_points(&springs, &d, &mut two_passes);
        let mut one_pass = vec![[f64::NAN; 3]; n]; // it must overwrite these
        project_springs_into_transpose(&springs, &r, &p, &mut one_pass);
        let mut formula = vec![[f64::NAN; 3]; n];
        project_springs_into_transpose_portable(&springs, &r, &p, &mut formula);
        for i in 0..n {
            let bits = |row: [f64; 3]| row.map(f64::to_bits);
            prop_assert_eq!(bits(one_pass[i]), bits(two_passes[i]), "vertex {}", i);
            prop_assert_eq!(bits(formula[i]), bits(two_passes[i]), "vertex {}", i);
        }
    }

    #[test]
    fn spring_pass_portable_and_fast_agree_with_the_local_step_and_the_definitions(
        (p, springs, r, start) in (2usize..20).prop_flat_map(|n| (
            prop::collection::vec(prop::array::uniform3(-10.0f64..10.0), n),
            prop::collection::vec(prop::array::uniform2(0..n), 0..40),
            prop::collection::vec(0.0f64..3.0, 40),
            prop::collection::vec(0.0f64..30.0, 40),
        )).prop_map(|(p, springs, r, start)| {
            let m = springs.len();
            (p, springs, r[..m].to_vec(), start[..m].to_vec())
        }),
        k in 1.0f64..1e5,
    ) {
        let (m, n) = (springs.len(), p.len());
        let pass = Springs { springs: &springs, r: &r, start_lengths: &start, k };
        let mut local = vec![[0.0; 3]; m];
        project_springs_portable(&springs, &r, &p, &mut local);
        let (mut d_portable, mut d_fast) = (vec![[f64::NAN; 3]; m], vec![[f64::NAN; 3]; m]);
        let (mut g_portable, mut g_fast) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        let (mut t_portable, mut t_fast) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        let sum_portable = pass.measure_portable(
            &p,
            Outputs {
                d: Some(&mut d_portable),
                gradient: Some(&mut g_portable),
                transpose: Some(&mut t_portable),
            },
            0,
        );
        let sum_fast = pass.measure(&p, Outputs {
            d: Some(&mut d_fast),
            gradient: Some(&mut g_fast),
            transpose: Some(&mut t_fast),
        });
        prop_assert_eq!(&d_portable, &local);
        prop_assert_eq!(&d_fast, &local);
        // Aᵀd: the bits of the scatter of the local step's d
        let mut a_t_d = vec![[0.0; 3]; n];
        incidence_transpose_mul_points(&springs, &local, &mut a_t_d);
        let bits = |rows: &[[f64; 3]]| rows.iter().map(|row| row.map(f64::to_bits)).collect::<Vec<_>>();
        prop_assert_eq!(bits(&t_portable), bits(&a_t_d));
        prop_assert_eq!(bits(&t_fast), bits(&a_t_d));
        // Aᵀd alone, without d or the gradient: the same bits
        let mut t_alone = vec![[0.0; 3]; n];
        let sum_alone =
            pass.measure(&p, Outputs { transpose: Some(&mut t_alone), ..Outputs::default() });
        prop_assert_eq!(bits(&t_alone), bits(&a_t_d));
        prop_assert_eq!(sum_alone, sum_fast);
        // the gradient alone (L-BFGS's pass): the same bits and sum
        let mut g_alone = vec![[0.0; 3]; n];
        let sum_g = pass.measure(&p, Outputs { gradient: Some(&mut g_alone), ..Outputs::default() });
        prop_assert_eq!(bits(&g_alone), bits(&g_portable));
        prop_assert_eq!(sum_g, sum_fast);
        // the definitions: S = Σ (l − r)² − (l⁰ − r)², g = Σ ±k (v − d)
        let mut sum = 0.0;
        let mut scale = 0.0;
        let mut g = vec![[0.0; 3]; n];
        for (e, &[i, j]) in springs.iter().enumerate() {
            let v: [f64; 3] = std::array::from_fn(|c| p[i][c] - p[j][c]);
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            sum += (l - r[e]).powi(2) - (start[e] - r[e]).powi(2);
            scale += (l - r[e]).powi(2) + (start[e] - r[e]).powi(2);
            for c in 0..3 {
                g[i][c] += k * (v[c] - local[e][c]);
                g[j][c] -= k * (v[c] - local[e][c]);
            }
        }
        let tolerance = 1e-12 * scale.max(1.0);
        prop_assert!((sum_portable - sum).abs() <= tolerance, "portable S {} vs {}", sum_portable, sum);
        prop_assert!((sum_fast - sum).abs() <= tolerance, "fast S {} vs {}", sum_fast, sum);
        // the forces are added in spring order by both: the same bits
        prop_assert_eq!(&g_fast, &g_portable);
        for (ours, want) in g_portable.iter().zip(&g) {
            for c in 0..3 {
                prop_assert!((ours[c] - want[c]).abs() <= 1e-9 * k * (1.0 + want[c].abs() / k));
            }
        }
        // the energy alone: the same sum
        prop_assert_eq!(pass.measure(&p, Outputs::default()), sum_fast);
    }

    /// With the portable kernels chosen (`linalg::kernels`: what a
    /// WebAssembly build runs, `--kernels portable`), every dispatcher runs
    /// its plain loop, on any CPU: the bits of the portable versions, where
    /// the native ones round differently (fused multiply-adds, four lanes).
    #[test]
    fn the_portable_choice_gives_the_bits_of_the_plain_loops(
        case in gram_block_case(),
        p in prop::collection::vec(prop::array::uniform3(-10.0f64..10.0), 8..30),
    ) {
        use masssprings::linalg::kernels::{self, Kernels};
        use masssprings::sim::simd::energy::{vertex_sums, Vertices};
        let portable = case.run(gram_block_portable);
        let chosen = kernels::with(Kernels::Portable, || case.run(gram_block));
        let bits = |values: &[f64]| values.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert_eq!(bits(&chosen), bits(&portable));
        let n = p.len();
        let springs: Vec<[usize; 2]> = (0..n).map(|i| [i, (i * 7 + 3) % n]).collect();
        let (r, start) = (vec![0.5; n], vec![1.0; n]);
        let pass = Springs { springs: &springs, r: &r, start_lengths: &start, k: 100.0 };
        let plain = pass.measure_portable(&p, Outputs::default(), 0);
        let chosen = kernels::with(Kernels::Portable, || pass.measure(&p, Outputs::default()));
        prop_assert_eq!(chosen.to_bits(), plain.to_bits());
        let m = vec![1.0; n];
        let vertices = Vertices { start: &p, inertial_target: &p, f_ext: &p, m: &m };
        let sums = kernels::with(Kernels::Portable, || vertex_sums(&vertices, &p));
        prop_assert_eq!(sums, ([0.0; 2], 0), "the caller sums every vertex one at a time");
    }

    #[test]
    fn back_substitution_one_sum_and_two_sums_agree(
        a in random_spd(40, 160),
        seed in prop::collection::vec(-1.0f64..1.0, 120),
    ) {
        let cholesky = simplicial_factor(&a);
        let l = cholesky.l();
        let row_idx: Vec<u32> = l.row_idx().iter().map(|&i| i as u32).collect();
        let view = FactorView { col_ptr: l.col_ptr(), row_idx: &row_idx, values: l.values() };
        let n = a.ncols();
        let y: Vec<[f64; 3]> = (0..n).map(|i| [seed[i], seed[40 + i], seed[80 + i]]).collect();
        let (mut plain, mut two_sums) = (y.clone(), y.clone());
        back_substitution_sparse(view, &mut plain);
        back_substitution_sparse_two_sums(view, &mut two_sums);
        // against the dense back substitution with U = Lᵀ, column by column
        let u = l.to_dense().transpose();
        for c in 0..3 {
            let mut dense: Vec<f64> = y.iter().map(|row| row[c]).collect();
            back_substitution_dense(&u, &mut dense).unwrap();
            let scale = dense.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            for i in 0..n {
                prop_assert!((plain[i][c] - dense[i]).abs() <= 1e-10 * scale, "plain x[{}][{}]", i, c);
                prop_assert!((two_sums[i][c] - dense[i]).abs() <= 1e-10 * scale, "two sums x[{}][{}]", i, c);
            }
        }
    }

    #[test]
    fn forward_substitution_sparse_matches_the_dense_one(
        a in random_spd(40, 160),
        seed in prop::collection::vec(-1.0f64..1.0, 40),
    ) {
        let cholesky = simplicial_factor(&a);
        let l = cholesky.l();
        let row_idx: Vec<u32> = l.row_idx().iter().map(|&i| i as u32).collect();
        let view = FactorView { col_ptr: l.col_ptr(), row_idx: &row_idx, values: l.values() };
        let n = a.ncols();
        let mut sparse: Vec<[f64; 1]> = (0..n).map(|i| [seed[i]]).collect();
        forward_substitution_sparse(view, &mut sparse);
        let mut dense = seed[..n].to_vec();
        forward_substitution_dense(&l.to_dense(), &mut dense).unwrap();
        let scale = dense.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            prop_assert!((sparse[i][0] - dense[i]).abs() <= 1e-10 * scale, "y[{}]: {} vs {}", i, sparse[i][0], dense[i]);
        }
    }
}
