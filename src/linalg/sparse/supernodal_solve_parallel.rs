//! The supernodal solve on several threads, to the same bits as on one.
//!
//! The sweeps of [`supernodal_solve`](super::supernodal_solve) change
//! `x_i` in a fixed order: forward, each supernode (in order) subtracts
//! its update from the rows below it; backward, each column's sum runs over
//! its rows in order. Here the tree is cut into whole subtrees, one thread
//! each ([`subtrees`](super::subtrees), weighted by the entries of `L`),
//! and the top above them is swept by thread 0:
//!
//! ```text
//! forward    each thread, its subtrees in order, the rows inside them
//!            only: a subtree's supernodes leave their rows in the top alone
//! ─ barrier ─
//! top        thread 0, in increasing order: for a subtree, the updates of
//!            its supernodes to their rows in the top, computed now from the
//!            subtree's solved values; a top supernode swept
//!            then the back sweep over the top supernodes, in decreasing order
//! ─ barrier ─
//! backward   each thread, its subtrees: they read the top's rows, final now
//! ```
//!
//! A row of the top receives the same updates as on one thread, in the
//! same order (thread 0 meets the subtrees and the top supernodes in the
//! order one thread would), and every update and every sum is computed by
//! the same code from the same numbers (a column's value is final once its
//! panel is swept). So the solution is the same, to the bit.
//!
//! Thread 0 computes the subtrees' updates of the top rather than receive
//! them: written by one core into a buffer that another core read the
//! solve before, every line of it waited for the other core (on a 2-vCPU
//! EPYC machine that made the flag's solve twice as slow on two threads
//! as on one); read-only entries of `L` and a few solved values cross
//! between the cores instead.
//!
//! Each row of `x` belongs to one thread: the rows of a subtree's columns
//! to its thread, the top's to thread 0. A thread that also writes the
//! right-hand side of its own rows before the sweeps and reads its own
//! rows of the solution after them ([`TeamSolve`]) needs no barrier for
//! either, and finds those rows in its own cache: written by another core,
//! every row is a wait for a cache line (on the flag that made one thread's
//! forward sweep four times slower than the other's).
//!
//! Source: the subtree-to-thread mapping of Geist & Ng (1989), applied to
//! the triangular solves as in Davis, Rajamanickam & Sid-Lakhdar, "A
//! survey of direct methods for sparse linear systems", Acta Numerica 25
//! (2016), §12.

use super::subtrees::{Item, SubtreeSchedule};
use super::supernodal_solve::{
    backward_supernode, forward_supernode, forward_supernode_tail, SupernodalView, Unknowns,
};
use super::symbolic::SymbolicCholesky;
use crate::linalg::threads::{SharedSlice, Team};
use std::ops::Range;

/// The cut of the tree for the solves, made once.
#[derive(Debug, Clone)]
pub(super) struct ParallelSolve {
    schedule: SubtreeSchedule,
    /// For each supernode of a subtree, how many of its rows (its last)
    /// lie in the top; 0 for the top's.
    top_rows: Vec<usize>,
    /// The rows of `x` each thread owns, as ranges.
    owned: Vec<Vec<Range<usize>>>,
}

impl ParallelSolve {
    /// The plan for `threads` threads.
    pub(super) fn new(symbolic: &SymbolicCholesky, threads: usize) -> Self {
        let (supernodes, col_ptr) = (symbolic.supernodes(), symbolic.col_ptr());
        let weight: Vec<f64> = (0..supernodes.len())
            .map(|s| {
                (col_ptr[supernodes.columns(s).end] - col_ptr[supernodes.columns(s).start]) as f64
            })
            .collect();
        let schedule = SubtreeSchedule::new(symbolic, threads, &weight, 1.0);
        ParallelSolve {
            top_rows: rows_in_the_top(symbolic, &schedule),
            owned: owned_rows(symbolic, &schedule),
            schedule,
        }
    }

    /// The rows of `x` thread `thread` owns.
    pub(super) fn owned_rows(&self, thread: usize) -> &[Range<usize>] {
        &self.owned[thread]
    }

    /// Bytes held (arrays' lengths).
    pub(super) fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        self.schedule.bytes()
            + size_of_val(&self.top_rows[..])
            + self
                .owned
                .iter()
                .map(|o| size_of_val(&o[..]))
                .sum::<usize>()
    }
}

/// For each supernode of a subtree, how many of its rows lie above the
/// subtree (its last rows: they are sorted).
fn rows_in_the_top(symbolic: &SymbolicCholesky, schedule: &SubtreeSchedule) -> Vec<usize> {
    let supernodes = symbolic.supernodes();
    let mut top_rows = vec![0; supernodes.len()];
    for t in 0..schedule.task_count() {
        let task = schedule.task(t);
        let end_column = supernodes.columns(task.end - 1).end;
        for s in task {
            let rows = symbolic.supernode_rows(s);
            top_rows[s] = rows.len() - rows.partition_point(|&r| (r as usize) < end_column);
        }
    }
    top_rows
}

/// The rows (columns) of each thread: its subtrees', and the top's for
/// thread 0; adjacent ranges joined.
fn owned_rows(symbolic: &SymbolicCholesky, schedule: &SubtreeSchedule) -> Vec<Vec<Range<usize>>> {
    let supernodes = symbolic.supernodes();
    let columns =
        |s: Range<usize>| supernodes.columns(s.start).start..supernodes.columns(s.end - 1).end;
    let mut owned = vec![Vec::new(); schedule.threads()];
    for t in 0..schedule.threads() {
        for &task in schedule.tasks_of(t) {
            owned[t].push(columns(schedule.task(task)));
        }
    }
    for &item in schedule.items() {
        if let Item::Top(s) = item {
            owned[0].push(supernodes.columns(s));
        }
    }
    for ranges in &mut owned {
        ranges.sort_by_key(|r| r.start);
        let mut joined: Vec<Range<usize>> = Vec::with_capacity(ranges.len());
        for range in ranges.drain(..) {
            match joined.last_mut() {
                Some(last) if last.end == range.start => last.end = range.end,
                _ => joined.push(range),
            }
        }
        *ranges = joined;
    }
    owned
}

/// A solve shared by a team, on a block of `W` columns: what every thread
/// of a run needs to sweep it, and which rows each one owns. A caller's
/// own run ([`Threads::run`](crate::linalg::threads::Threads::run)) writes
/// the right-hand side of each thread's rows ([`TeamSolve::owned_rows`])
/// in [`TeamSolve::rows`], calls [`TeamSolve::sweep`] on every thread, and
/// reads each thread's rows of the solution, with no barrier between.
pub struct TeamSolve<'a, const W: usize> {
    l: SupernodalView<'a>,
    plan: &'a ParallelSolve,
    x: SharedSlice<'a, [f64; W]>,
}

impl<'a, const W: usize> TeamSolve<'a, W> {
    /// The solve of `x` (in the factor's order) with the factor `values`
    /// analysed in `symbolic`, by the plan `plan`.
    pub(super) fn new(
        symbolic: &'a SymbolicCholesky,
        values: &'a [f64],
        plan: &'a ParallelSolve,
        x: &'a mut [[f64; W]],
    ) -> Self {
        assert_eq!(x.len(), symbolic.n());
        TeamSolve {
            l: SupernodalView {
                symbolic,
                col_ptr: symbolic.col_ptr(),
                values,
            },
            plan,
            x: SharedSlice::new(x),
        }
    }

    /// The number of threads the solve is planned for.
    pub fn threads(&self) -> usize {
        self.plan.schedule.threads()
    }

    /// The rows of `x`, shared by the team.
    pub fn rows(&self) -> &SharedSlice<'a, [f64; W]> {
        &self.x
    }

    /// The rows thread `thread` owns: it alone writes them, in the sweeps
    /// and before and after them.
    pub fn owned_rows(&self, thread: usize) -> &[Range<usize>] {
        self.plan.owned_rows(thread)
    }

    /// `x ← L⁻ᵀ L⁻¹ x`, called by every thread of a team of
    /// [`TeamSolve::threads`]; each thread's rows of `x` must hold the
    /// right-hand side, and hold the solution when it returns (the other
    /// rows after a barrier).
    ///
    /// # Panics
    /// When the team is not the size the solve is planned for.
    pub fn sweep(&self, team: &Team) {
        assert_eq!(team.size(), self.threads(), "the plan's threads");
        #[cfg(target_arch = "x86_64")]
        if crate::linalg::kernels::avx2_fma() {
            // SAFETY: the CPU supports the features the function is compiled for.
            unsafe { team_solve_avx2(self, team) };
            return;
        }
        team_solve::<W, false>(self, team);
    }
}

/// The rows of `x` as a thread of the team reaches them: its start and
/// length held here, not read through the shared array at every row.
struct TeamRows<const W: usize> {
    start: *mut [f64; W],
    len: usize,
}

impl<const W: usize> TeamRows<W> {
    fn of(x: &SharedSlice<[f64; W]>) -> Self {
        TeamRows {
            start: x.as_mut_ptr(),
            len: x.len(),
        }
    }

    /// Asks for the cache lines of `rows` to write, all at once: lines that
    /// another core read since this one wrote them must be taken back from
    /// it, and asked for one store at a time each would wait for the other
    /// core in turn.
    #[inline(always)]
    fn prefetch_for_writing(&self, rows: Range<usize>) {
        #[cfg(target_arch = "x86_64")]
        {
            let end = rows.end.min(self.len);
            let step = (64 / std::mem::size_of::<[f64; W]>()).max(1);
            for i in (rows.start..end).step_by(step) {
                // SAFETY: a prefetch reads and writes nothing, and is a
                // hint (a CPU without `prefetchw` takes it for a no-op);
                // `i` is inside `x`.
                unsafe {
                    std::arch::asm!(
                        "prefetchw [{line}]",
                        line = in(reg) self.start.add(i),
                        options(nostack, preserves_flags, readonly)
                    );
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = rows;
    }
}

impl<const W: usize> Unknowns<W> for TeamRows<W> {
    #[inline(always)]
    fn row(&self, i: usize) -> [f64; W] {
        assert!(i < self.len);
        // SAFETY: inside `x` (checked); in every phase a thread reads only
        // rows that no other thread writes in that phase (the module's
        // schedule).
        unsafe { self.start.add(i).read() }
    }

    #[inline(always)]
    fn row_mut(&mut self, i: usize) -> &mut [f64; W] {
        assert!(i < self.len);
        // SAFETY: inside `x` (checked); in every phase a thread writes only
        // the rows of its own subtrees' columns (thread 0 in the top phase:
        // any), which no other thread reads or writes in that phase.
        unsafe { &mut *self.start.add(i) }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn team_solve_avx2<const W: usize>(shared: &TeamSolve<W>, team: &Team) {
    team_solve::<W, true>(shared, team);
}

/// One thread's part of the solve: its subtrees forward, the top (thread
/// 0), its subtrees backward.
#[inline(always)]
fn team_solve<const W: usize, const FUSED: bool>(shared: &TeamSolve<W>, team: &Team) {
    forward_subtrees::<W, FUSED>(shared, team);
    team.barrier();
    if team.leads() {
        sweep_top::<W, FUSED>(shared);
    }
    team.barrier();
    backward_subtrees::<W, FUSED>(shared, team);
}

/// This thread's subtrees, forward, their rows in the top left out.
#[inline(always)]
fn forward_subtrees<const W: usize, const FUSED: bool>(shared: &TeamSolve<W>, team: &Team) {
    let (plan, mut x) = (shared.plan, TeamRows::of(&shared.x));
    for &t in plan.schedule.tasks_of(team.index()) {
        for s in plan.schedule.task(t) {
            forward_supernode::<W, FUSED, _>(&shared.l, s, &mut x, plan.top_rows[s]);
        }
    }
}

/// Thread 0: the top, forward in increasing order (a subtree's updates of
/// its rows in the top where one thread would have made them), then
/// backward in decreasing order.
#[inline(always)]
fn sweep_top<const W: usize, const FUSED: bool>(shared: &TeamSolve<W>) {
    let (plan, mut x) = (shared.plan, TeamRows::of(&shared.x));
    for &item in plan.schedule.items() {
        if let Item::Top(s) = item {
            x.prefetch_for_writing(shared.l.symbolic.supernodes().columns(s));
        }
    }
    for &item in plan.schedule.items() {
        match item {
            Item::Task(t) => {
                for s in plan.schedule.task(t) {
                    let tail = plan.top_rows[s];
                    if tail > 0 {
                        forward_supernode_tail::<W, FUSED, _>(&shared.l, s, &mut x, tail);
                    }
                }
            }
            Item::Top(s) => forward_supernode::<W, FUSED, _>(&shared.l, s, &mut x, 0),
        }
    }
    for &item in plan.schedule.items().iter().rev() {
        if let Item::Top(s) = item {
            backward_supernode::<W, FUSED, _>(&shared.l, s, &mut x);
        }
    }
}

/// This thread's subtrees, backward (the top's rows are final).
#[inline(always)]
fn backward_subtrees<const W: usize, const FUSED: bool>(shared: &TeamSolve<W>, team: &Team) {
    let (plan, mut x) = (shared.plan, TeamRows::of(&shared.x));
    for &t in plan.schedule.tasks_of(team.index()) {
        for s in plan.schedule.task(t) {
            if plan.top_rows[s] > 0 {
                x.prefetch_for_writing(shared.l.symbolic.supernodes().columns(s));
            }
        }
    }
    for &t in plan.schedule.tasks_of(team.index()).iter().rev() {
        for s in plan.schedule.task(t).rev() {
            backward_supernode::<W, FUSED, _>(&shared.l, s, &mut x);
        }
    }
}
