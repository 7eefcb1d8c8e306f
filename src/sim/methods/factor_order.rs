//! The plain iteration with its unknowns kept in the factor's order.
//!
//! The sparse solve works on `P b`, the right-hand side with its rows in
//! the order of the fill-reducing permutation `P` (row `r` is row
//! `perm[r]`), padded to four values per row, and gives `P p`. The textbook
//! loop of [`plain`](super::plain) therefore permutes twice per iteration:
//! it gathers `b = k Aᵀd + y + w CᵀC V` into the solve's buffer
//! (`buffer[r] = b[perm[r]]`) and scatters the solution back
//! (`p[perm[r]] = buffer[r]`). On the flag those two passes, through rows
//! scattered over memory, were 7% of a step (`perf`, docs/performance.md).
//!
//! Renumbering the vertices into the factor's order removes them. The
//! springs are renumbered once per system, `(i, j) → (pinv[i], pinv[j])`
//! (the ordering never changes: a refactorization keeps its analysis), and
//! `y` is permuted once per step; then every
//! iteration reads and writes the buffer directly:
//!
//! ```text
//! x = P p                                      once per step, padded rows
//! repeat N times:
//!     (P Aᵀd)[pinv i] += dₑ, [pinv j] −= dₑ     local step, springs in order,
//!                                              read from x
//!     x[r] = k (P Aᵀd)[r] + (P y)[r] + (P w CᵀC V)[r]    in row order
//!     x = L⁻ᵀ L⁻¹ x                              the solve, P Q Pᵀ x = P b
//! p = Pᵀ x                                     once per step
//! ```
//!
//! Nothing else changes: the springs are visited in the same order, each
//! row of `Aᵀd` receives the same additions in the same order, `b`'s rows
//! are the same sums (`(k a + y) + pin`), and the solve sees the same
//! buffer. So the positions are the same bits as the textbook loop's, which
//! the tests check. `w CᵀC V` is `+0.0` outside the pinned rows (as
//! `precomputation::pin_right_hand_side` makes it), so it is read only
//! there, and each free row adds `+0.0`, exactly what adding its zero row
//! did.
//!
//! Used by `plain` with the sparse backend and penalty pins when nothing
//! watches the iterates (no tolerance, no observer): the loop never forms
//! `p` in the vertices' order until the step ends. The textbook loop stays
//! in `GlobalStep::iterate_in_place` (`global_step.rs`),
//! used with a tolerance, by `masssprings converge`, by the dense backend
//! and by exact pins.
//!
//! Memory: the renumbered springs, 16 bytes per spring, made the first
//! time a plain step runs with penalty pins and no tolerance; `P y` lives in the room the stopping rule keeps
//! for a gradient, which a step with no tolerance does not use until it
//! ends. Two leaner variants were slower on the flag (`simulate --steps
//! 100`, medians of 16 interleaved runs on Zen 3): looking each end up in
//! `pinv` as the springs are visited (no copy of the springs) was 1% slower
//! than the textbook loop, and 32-bit renumbered springs 2.5% slower than
//! these (this version: 3–4% faster than the textbook loop on the flag
//! and the skirt).
//!
//! Source: the permuted solve of Davis, *Direct Methods for Sparse Linear
//! Systems* (2006), §8.1 (`x = Pᵀ (L⁻ᵀ (L⁻¹ (P b)))`), with the
//! permutations moved out of the loop.

use crate::linalg::sparse::SparseCholesky;
use crate::sim::simd::local_step::project_springs_into_transpose;

/// The springs renumbered into the factor's order, made once per
/// system (the factor's ordering never changes: a refactorization keeps
/// its analysis).
#[derive(Debug, Clone)]
pub struct Workspace {
    /// `(pinv[i], pinv[j])` for every spring `(i, j)`, in the springs' order.
    springs: Vec<[usize; 2]>,
}

impl Workspace {
    /// `springs` renumbered by `new_index` (`new_index[old] = new`).
    ///
    /// # Panics
    /// When a spring names a vertex beyond `new_index`.
    pub fn new(springs: &[[usize; 2]], new_index: &[usize]) -> Self {
        Workspace {
            springs: springs
                .iter()
                .map(|&[i, j]| [new_index[i], new_index[j]])
                .collect(),
        }
    }

    /// Bytes held (arrays' lengths).
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(&self.springs[..])
    }
}

/// The step's data the loop reads, in the vertices' order.
pub struct PlainProblem<'a> {
    pub r: &'a [f64],
    pub k: f64,
    /// `y = M ŷ / Δt² + f_ext`.
    pub y: &'a [[f64; 3]],
    /// `w CᵀC V`, `+0.0` outside the pinned rows.
    pub pin_rhs: &'a [[f64; 3]],
    /// The pinned vertices (the rows where `w CᵀC V` is read).
    pub pinned: &'a [usize],
}

/// `iterations` plain iterations from `p`, in place, in the factor's order;
/// `a_t_d` is room for `P Aᵀd` and `room` for `P y`.
///
/// # Panics
/// When a slice does not have one row per vertex (or per spring), or after
/// a failed refactorization.
pub fn iterate(
    work: &Workspace,
    cholesky: &mut SparseCholesky,
    problem: &PlainProblem<'_>,
    a_t_d: &mut [[f64; 3]],
    room: &mut [[f64; 3]],
    p: &mut [[f64; 3]],
    iterations: usize,
) {
    debug_assert!(free_rows_are_zero(problem.pin_rhs, problem.pinned));
    let (permutation, x) = cholesky.buffer_in_factor_order();
    let perm = permutation.perm();
    let n = perm.len();
    assert!(p.len() == n && problem.y.len() == n && a_t_d.len() == n && room.len() == n);
    assert_eq!(
        work.springs.len(),
        problem.r.len(),
        "one rest length per spring"
    );
    let y = room;
    for ((row, y_row), &old) in x.iter_mut().zip(y.iter_mut()).zip(perm) {
        *row = pad(p[old]);
        *y_row = problem.y[old];
    }
    for _ in 0..iterations {
        let (permutation, x) = cholesky.buffer_in_factor_order();
        project_springs_into_transpose(&work.springs, problem.r, x, a_t_d);
        right_hand_side(problem, y, a_t_d, permutation.inverse(), x);
        cholesky.solve_buffer_in_place();
    }
    let (permutation, x) = cholesky.buffer_in_factor_order();
    for (row, &old) in x.iter().zip(permutation.perm()) {
        p[old] = [row[0], row[1], row[2]];
    }
}

/// `x[r] = k (P Aᵀd)[r] + (P y)[r] + (P w CᵀC V)[r]`, padded with 0: the
/// rows of `b` in the factor's order, the same sums as the textbook's `b`.
fn right_hand_side(
    problem: &PlainProblem<'_>,
    y: &[[f64; 3]],
    a_t_d: &[[f64; 3]],
    inverse: &[usize],
    x: &mut [[f64; 4]],
) {
    let k = problem.k;
    let row = |a: [f64; 3], y: [f64; 3], pin: [f64; 3]| -> [f64; 4] {
        let [x, y, z] = std::array::from_fn(|c| k * a[c] + y[c] + pin[c]);
        [x, y, z, 0.0]
    };
    for ((out, &a), &y) in x.iter_mut().zip(a_t_d).zip(y) {
        *out = row(a, y, [0.0; 3]);
    }
    for &old in problem.pinned {
        let new = inverse[old];
        x[new] = row(a_t_d[new], y[new], problem.pin_rhs[old]);
    }
}

/// Is every row of `w CᵀC V` outside `pinned` exactly `+0.0`? (Checked in
/// debug builds: what the loop relies on.)
fn free_rows_are_zero(pin_rhs: &[[f64; 3]], pinned: &[usize]) -> bool {
    let free = |i: &usize| !pinned.contains(i);
    (0..pin_rhs.len())
        .filter(free)
        .all(|i| pin_rhs[i].iter().all(|v| v.to_bits() == 0))
}

/// `(x, y, z, 0)`.
fn pad([x, y, z]: [f64; 3]) -> [f64; 4] {
    [x, y, z, 0.0]
}
