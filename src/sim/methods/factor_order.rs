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
//! On several threads ([`SparseCholesky::team_solve`]) the whole loop is one
//! run of the team: each thread owns the rows of its part of the factor
//! and makes, on them alone, the copies in and out, its part of the local
//! step and `Aᵀd` ([`spring_blocks`](crate::sim::spring_blocks): every row
//! the same additions in the same order) and `b`, then sweeps with the
//! others; a barrier after the local step (the next phase overwrites the
//! positions it read) and one after the solve (the next local step reads
//! the neighbours' rows). The same bits again, on any number of threads.
//!
//! Source: the permuted solve of Davis, *Direct Methods for Sparse Linear
//! Systems* (2006), §8.1 (`x = Pᵀ (L⁻ᵀ (L⁻¹ (P b)))`), with the
//! permutations moved out of the loop.

use crate::linalg::sparse::supernodal_solve_parallel::TeamSolve;
use crate::linalg::sparse::SparseCholesky;
use crate::linalg::threads::{SharedSlice, Team};
use crate::sim::simd::local_step::project_springs_into_transpose;
use crate::sim::simd::spring_blocks::add_owned_springs;
use crate::sim::spring_blocks::SpringBlocks;
use std::ops::Range;

/// The springs renumbered into the factor's order, made once per
/// system (the factor's ordering never changes: a refactorization keeps
/// its analysis): in one list, or in the blocks of a team of threads.
#[derive(Debug, Clone)]
pub enum Workspace {
    /// `(pinv[i], pinv[j])` for every spring `(i, j)`, in the springs' order.
    One { springs: Vec<[usize; 2]> },
    /// The springs of each thread's rows ([`SpringBlocks`]).
    Team(SpringBlocks),
}

impl Workspace {
    /// `springs` renumbered by `new_index` (`new_index[old] = new`), for
    /// `cholesky`'s threads: one list, or one block per thread.
    ///
    /// # Panics
    /// When a spring names a vertex beyond `new_index`.
    pub fn new(springs: &[[usize; 2]], new_index: &[usize], cholesky: &SparseCholesky) -> Self {
        match thread_rows(cholesky) {
            Some(rows) => Workspace::Team(SpringBlocks::new(springs, new_index, rows)),
            None => Workspace::One {
                springs: springs
                    .iter()
                    .map(|&[i, j]| [new_index[i], new_index[j]])
                    .collect(),
            },
        }
    }

    /// Is it made for `cholesky`'s threads and their rows? (Allocates
    /// nothing: a step asks.)
    pub fn fits(&self, cholesky: &SparseCholesky) -> bool {
        match self {
            Workspace::One { .. } => cholesky.rows_of_thread(0).is_none(),
            Workspace::Team(blocks) => {
                cholesky.threads() == blocks.len()
                    && (0..blocks.len()).all(|b| cholesky.rows_of_thread(b) == Some(blocks.rows(b)))
            }
        }
    }

    /// Bytes held (arrays' lengths).
    pub fn bytes(&self) -> usize {
        match self {
            Workspace::One { springs } => std::mem::size_of_val(&springs[..]),
            Workspace::Team(blocks) => blocks.bytes(),
        }
    }
}

/// The rows each thread of `cholesky`'s team owns, if it has a team.
fn thread_rows(cholesky: &SparseCholesky) -> Option<Vec<Vec<Range<usize>>>> {
    (0..cholesky.threads())
        .map(|t| cholesky.rows_of_thread(t).map(<[_]>::to_vec))
        .collect()
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
/// When a slice does not have one row per vertex (or per spring), after
/// a failed refactorization, or when `work` was made for other threads.
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
    let n = p.len();
    assert!(problem.y.len() == n && a_t_d.len() == n && room.len() == n);
    match work {
        Workspace::One { springs } => {
            iterate_alone(springs, cholesky, problem, a_t_d, room, p, iterations)
        }
        Workspace::Team(blocks) => {
            // the threads write only their own rows: those of this factor's team
            assert!(
                work.fits(cholesky),
                "the springs' blocks are another team's"
            );
            let (solve, threads, permutation) = cholesky
                .team_solve()
                .expect("the springs' blocks are made for a team");
            let step = TeamStep {
                blocks,
                solve,
                perm: permutation.perm(),
                inverse: permutation.inverse(),
                problem,
                a_t_d: SharedSlice::new(a_t_d),
                y: SharedSlice::new(room),
                p: SharedSlice::new(p),
            };
            threads.run(&|team: &Team| step.iterate(team, iterations));
        }
    }
}

/// The loop on one thread.
fn iterate_alone(
    springs: &[[usize; 2]],
    cholesky: &mut SparseCholesky,
    problem: &PlainProblem<'_>,
    a_t_d: &mut [[f64; 3]],
    room: &mut [[f64; 3]],
    p: &mut [[f64; 3]],
    iterations: usize,
) {
    let (permutation, x) = cholesky.buffer_in_factor_order();
    let perm = permutation.perm();
    assert_eq!(p.len(), perm.len());
    assert_eq!(springs.len(), problem.r.len(), "one rest length per spring");
    let y = room;
    for ((row, y_row), &old) in x.iter_mut().zip(y.iter_mut()).zip(perm) {
        *row = pad(p[old]);
        *y_row = problem.y[old];
    }
    for _ in 0..iterations {
        let (permutation, x) = cholesky.buffer_in_factor_order();
        project_springs_into_transpose(springs, problem.r, x, a_t_d);
        right_hand_side(problem, y, a_t_d, permutation.inverse(), x);
        cholesky.solve_buffer_in_place();
    }
    let (permutation, x) = cholesky.buffer_in_factor_order();
    for (row, &old) in x.iter().zip(permutation.perm()) {
        p[old] = [row[0], row[1], row[2]];
    }
}

/// What the team shares during a step's loop.
struct TeamStep<'a> {
    blocks: &'a SpringBlocks,
    solve: TeamSolve<'a, 4>,
    perm: &'a [usize],
    inverse: &'a [usize],
    problem: &'a PlainProblem<'a>,
    a_t_d: SharedSlice<'a, [f64; 3]>,
    y: SharedSlice<'a, [f64; 3]>,
    p: SharedSlice<'a, [f64; 3]>,
}

impl TeamStep<'_> {
    /// One thread's part of the loop: its rows in, every iteration's local
    /// step, `b` and sweeps, its rows out.
    fn iterate(&self, team: &Team, iterations: usize) {
        let rows = self.blocks.rows(team.index());
        let x = self.solve.rows();
        for r in rows.iter().flat_map(|range| range.clone()) {
            let old = self.perm[r];
            // SAFETY: row `r` of the buffer and of `P y`, and row `old` of
            // `p` (`perm` is one-to-one), are this thread's.
            unsafe {
                x.set(r, pad(self.p.get(old)));
                self.y.set(r, self.problem.y[old]);
            }
        }
        team.barrier(); // the local step reads the neighbours' rows
        for _ in 0..iterations {
            self.local_step(team);
            team.barrier(); // its positions are read: b may take their place
            self.right_hand_side(team);
            self.solve.sweep(team);
            team.barrier(); // every row solved: the next local step reads them
        }
        for r in rows.iter().flat_map(|range| range.clone()) {
            // SAFETY: as above.
            unsafe {
                let row = x.get(r);
                self.p.set(self.perm[r], [row[0], row[1], row[2]]);
            }
        }
    }

    /// `P Aᵀd` on this thread's rows: zeroed, then its block's springs.
    fn local_step(&self, team: &Team) {
        let b = team.index();
        for range in self.blocks.rows(b) {
            // SAFETY: this thread's rows of `P Aᵀd`.
            unsafe { self.a_t_d.slice_mut(range.clone()) }.fill([0.0; 3]);
        }
        // SAFETY: the buffer holds positions until the barrier that follows,
        // and nobody writes it meanwhile; the whole buffer is read.
        let x = unsafe { self.solve.rows().slice(0..self.solve.rows().len()) };
        // SAFETY: the block writes its own rows of `P Aᵀd` only.
        unsafe { add_owned_springs(self.blocks.block(b), self.problem.r, x, &self.a_t_d) };
    }

    /// `b` on this thread's rows, as [`right_hand_side`] makes it.
    fn right_hand_side(&self, team: &Team) {
        let (rows, x) = (self.blocks.rows(team.index()), self.solve.rows());
        let row = |r: usize, pin: [f64; 3]| -> [f64; 4] {
            // SAFETY: row `r` of `P Aᵀd` and `P y` is this thread's.
            let (a, y) = unsafe { (self.a_t_d.get(r), self.y.get(r)) };
            b_row(self.problem.k, a, y, pin)
        };
        for r in rows.iter().flat_map(|range| range.clone()) {
            // SAFETY: row `r` of the buffer is this thread's.
            unsafe { x.set(r, row(r, [0.0; 3])) };
        }
        for &old in self.problem.pinned {
            let new = self.inverse[old];
            if rows.iter().any(|range| range.contains(&new)) {
                // SAFETY: as above.
                unsafe { x.set(new, row(new, self.problem.pin_rhs[old])) };
            }
        }
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
    for ((out, &a), &y) in x.iter_mut().zip(a_t_d).zip(y) {
        *out = b_row(k, a, y, [0.0; 3]);
    }
    for &old in problem.pinned {
        let new = inverse[old];
        x[new] = b_row(k, a_t_d[new], y[new], problem.pin_rhs[old]);
    }
}

/// One row of `b`, `(k a + y) + pin`, padded with 0.
#[inline(always)]
fn b_row(k: f64, a: [f64; 3], y: [f64; 3], pin: [f64; 3]) -> [f64; 4] {
    let [x, y, z] = std::array::from_fn(|c| k * a[c] + y[c] + pin[c]);
    [x, y, z, 0.0]
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
