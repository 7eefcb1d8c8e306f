//! The supernodal factorization on several threads, to the same bits as on
//! one.
//!
//! [`supernodal`](super::supernodal) goes through the supernodes in order;
//! each is loaded, receives the updates of its descendants in the order
//! they wait in its list, and is factored. Two things fix the bits of a
//! column: the order of its updates, and the arithmetic of each. Both stay
//! here:
//!
//! 1. **Subtrees.** The tree is cut into whole subtrees, each run by one
//!    thread from start to end with the sequential code
//!    ([`subtrees`](super::subtrees)). A supernode's descendants all lie in
//!    its subtree, so a supernode inside a subtree receives the same
//!    updates in the same order as on one thread. A supernode whose next
//!    target lies above its subtree (in the top) is not put in that list
//!    yet but in the subtree's *outbox*, in order.
//! 2. **The top**, after a barrier, in increasing order: for a subtree, its
//!    outbox is put into the lists (so every list of the top receives its
//!    supernodes in the order one thread would have put them there: that
//!    thread meets the subtrees and the top supernodes in this order); a
//!    top supernode is factored by the whole team together when it is large
//!    (else by thread 0): each thread applies every waiting update in list
//!    order, to the rows of the block it owns; then the block is factored
//!    panel by panel, each thread computing its own rows of each panel's
//!    update with the same kernel ([`gram_block_rows`]: each entry the same
//!    chain of multiply-adds), thread 0 the panel's small triangle.
//!
//! So every entry of `L` is the same sum, in the same order, as on one
//! thread, whatever the number of threads and however the tree is cut;
//! the tests compare the bits. A pivot that is not positive is reported at
//! the same column as on one thread: the first in the order above.
//!
//! Source: the subtree-to-thread mapping of Geist & Ng (1989) and of
//! CHOLMOD's GPU and multicore schedules (Chen, Davis, Hager,
//! Rajamanickam, ACM TOMS 35(3), 2008); within a supernode, the row
//! partitioning of a left-looking dense Cholesky (Golub & Van Loan,
//! *Matrix Computations*, 4th ed., §6.5).

use super::subtrees::{Item, SubtreeSchedule};
use super::supernodal::{
    block_rows, column_base, factor_panel, factor_range, load_block, targets_in,
    wait_for_next_target, Input, Lists, Region, Scratch, SupernodalWorkspace,
};
use super::symbolic::SymbolicCholesky;
use super::up_looking::FailedPivot;
use crate::linalg::dense::gram_block::{gram_block_rows, BLOCK_COLUMNS};
use crate::linalg::threads::{even_part, SharedSlice, Team, Threads};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};

/// Multiply-adds per barrier below which a top supernode is factored by
/// thread 0 alone (the others would mostly wait): about a microsecond's
/// work, several times what a barrier costs threads that are running.
const WORK_PER_BARRIER: f64 = 10_000.0;

/// The cut of the tree for the factorization and what a parallel run
/// writes besides `L`, sized once.
#[derive(Debug, Clone)]
pub(super) struct ParallelFactor {
    schedule: SubtreeSchedule,
    /// `together[s]`: is top supernode `s` factored by the whole team?
    together: Vec<bool>,
    /// Each task's outbox (at its supernodes' positions).
    outbox: Vec<usize>,
    /// How many supernodes each task put in its outbox.
    sent: Vec<usize>,
    /// Where each task found a pivot that is not positive.
    failed: Vec<Option<FailedPivot>>,
}

impl ParallelFactor {
    /// The plan for `threads` threads.
    pub(super) fn new(symbolic: &SymbolicCholesky, threads: usize) -> Self {
        let weight = factor_work(symbolic);
        let schedule = SubtreeSchedule::new(symbolic, threads, &weight, 1.25 / threads as f64);
        let mut together = vec![false; weight.len()];
        for item in schedule.items() {
            if let &Item::Top(s) = item {
                let panels = symbolic
                    .supernodes()
                    .columns(s)
                    .len()
                    .div_ceil(BLOCK_COLUMNS);
                // a barrier after loading, one after the updates, one a panel
                together[s] = weight[s] >= WORK_PER_BARRIER * (2 + panels) as f64;
            }
        }
        ParallelFactor {
            together,
            outbox: vec![0; weight.len()],
            sent: vec![0; schedule.task_count()],
            failed: vec![None; schedule.task_count()],
            schedule,
        }
    }

    /// The number of threads it was made for.
    pub(super) fn threads(&self) -> usize {
        self.schedule.threads()
    }

    /// Bytes held (arrays' lengths).
    pub(super) fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        self.schedule.bytes()
            + size_of_val(&self.together[..])
            + size_of_val(&self.outbox[..])
            + size_of_val(&self.sent[..])
            + size_of_val(&self.failed[..])
    }
}

/// The multiply-adds each supernode receives from its descendants and
/// spends on its own block: the weights of the cut.
fn factor_work(symbolic: &SymbolicCholesky) -> Vec<f64> {
    let supernodes = symbolic.supernodes();
    let mut work = vec![0.0; supernodes.len()];
    for d in 0..supernodes.len() {
        let rows = block_rows(symbolic, d);
        let width = supernodes.columns(d).len();
        work[d] += (width * width) as f64 * rows.len() as f64 / 3.0;
        let mut next = width;
        while next < rows.len() {
            let s = supernodes.of_column(rows[next] as usize);
            let targets = targets_in(symbolic, s, d, next);
            work[s] += (width * targets.len() * (rows.len() - next)) as f64;
            next = targets.end;
        }
    }
    work
}

/// Everything the team shares during one factorization.
struct Shared<'a> {
    input: Input<'a>,
    plan: &'a SubtreeSchedule,
    together: &'a [bool],
    values: SharedSlice<'a, f64>,
    waiting: SharedSlice<'a, Option<usize>>,
    next_waiting: SharedSlice<'a, Option<usize>>,
    next_row: SharedSlice<'a, usize>,
    outbox: SharedSlice<'a, usize>,
    sent: SharedSlice<'a, usize>,
    failed: SharedSlice<'a, Option<FailedPivot>>,
    scratch: SharedSlice<'a, Scratch>,
    /// The list of the top supernode being factored together.
    head: SharedSlice<'a, Option<usize>>,
    /// Thread 0's outcome.
    outcome: SharedSlice<'a, Option<FailedPivot>>,
    /// Set by thread 0 when it stops at a failed pivot the others do not
    /// see (in a subtree, or a supernode it factors alone).
    stop: AtomicBool,
}

/// Fills `values` with `L` as [`factor_supernodal`](super::supernodal::factor_supernodal)
/// does, with the threads of `threads` and the plan of `parallel`.
///
/// # Errors
/// The first column, in the order one thread would meet it, whose pivot is
/// not positive and finite.
pub(super) fn factor_parallel(
    threads: &Threads,
    input: Input,
    values: &mut [f64],
    work: &mut SupernodalWorkspace,
    parallel: &mut ParallelFactor,
) -> Result<(), FailedPivot> {
    assert_eq!(threads.count(), parallel.threads(), "the plan's threads");
    assert!(
        work.scratch.len() >= threads.count(),
        "one scratch per thread"
    );
    work.waiting.fill(None);
    let mut head = [None];
    let mut outcome = [None];
    let shared = Shared {
        input,
        plan: &parallel.schedule,
        together: &parallel.together,
        values: SharedSlice::new(values),
        waiting: SharedSlice::new(&mut work.waiting),
        next_waiting: SharedSlice::new(&mut work.next_waiting),
        next_row: SharedSlice::new(&mut work.next_row),
        outbox: SharedSlice::new(&mut parallel.outbox),
        sent: SharedSlice::new(&mut parallel.sent),
        failed: SharedSlice::new(&mut parallel.failed),
        scratch: SharedSlice::new(&mut work.scratch),
        head: SharedSlice::new(&mut head),
        outcome: SharedSlice::new(&mut outcome),
        stop: AtomicBool::new(false),
    };
    threads.run(&|team: &Team| {
        run_subtrees(&shared, team);
        team.barrier();
        if team.leads() {
            let result = lead_top(&shared, team);
            // SAFETY: only thread 0 writes the outcome; read after the run.
            unsafe { shared.outcome.set(0, result.err()) };
        } else {
            follow_top(&shared, team);
        }
    });
    match outcome[0] {
        Some(failed) => Err(failed),
        None => Ok(()),
    }
}

/// This thread's scratch buffers.
#[allow(clippy::mut_from_ref)] // each thread its own, by its number
fn scratch<'s>(shared: &'s Shared, team: &Team) -> &'s mut Scratch {
    let i = team.index();
    // SAFETY: thread `i` alone uses scratch `i`, for the whole run.
    unsafe { &mut shared.scratch.slice_mut(i..i + 1)[0] }
}

/// The subtrees of this thread, each by the sequential code on its own
/// columns and lists.
fn run_subtrees(shared: &Shared, team: &Team) {
    let scratch = scratch(shared, team);
    let (symbolic, supernodes) = (shared.input.symbolic, shared.input.symbolic.supernodes());
    for &t in shared.plan.tasks_of(team.index()) {
        let range = shared.plan.task(t);
        let columns = supernodes.columns(range.start).start..supernodes.columns(range.end - 1).end;
        let entries = symbolic.col_ptr()[columns.start]..symbolic.col_ptr()[columns.end];
        // SAFETY: the tasks are disjoint ranges of supernodes, so of
        // columns, of values and of lists; each is run by one thread, and
        // nothing else is touched until the barrier after this phase.
        let (mut values, mut lists) = unsafe {
            (
                Region {
                    values: shared.values.slice_mut(entries.clone()),
                    first: entries.start,
                },
                task_lists(shared, range.clone()),
            )
        };
        let result = factor_range(&shared.input, range, &mut values, &mut lists, scratch);
        // SAFETY: entry `t` of these is this task's alone.
        unsafe {
            shared.sent.set(t, lists.sent);
            shared.failed.set(t, result.err());
        }
    }
}

/// The lists of the supernodes `range`, and their outbox.
///
/// # Safety
/// No other thread touches these entries while the lists are used.
unsafe fn task_lists<'s>(shared: &'s Shared, range: Range<usize>) -> Lists<'s> {
    // SAFETY: the caller's promise.
    unsafe {
        Lists {
            first: range.start,
            end: range.end,
            waiting: shared.waiting.slice_mut(range.clone()),
            next_waiting: shared.next_waiting.slice_mut(range.clone()),
            next_row: shared.next_row.slice_mut(range.clone()),
            outbox: shared.outbox.slice_mut(range),
            sent: 0,
        }
    }
}

/// Thread 0's part of the top: every item in order; each top supernode
/// alone or with the team.
fn lead_top(shared: &Shared, team: &Team) -> Result<(), FailedPivot> {
    let mut remaining = shared.together.iter().filter(|&&t| t).count();
    let scratch = scratch(shared, team);
    for &item in shared.plan.items() {
        let outcome = match item {
            Item::Task(t) => replay_outbox(shared, t),
            Item::Top(s) if shared.together[s] => {
                remaining -= 1;
                factor_together(shared, team, s, scratch)?; // the others stop too
                Ok(())
            }
            Item::Top(s) => factor_alone(shared, s, scratch),
        };
        if let Err(failed) = outcome {
            // the others wait at the start of the next supernode they share
            shared.stop.store(true, Ordering::SeqCst);
            if remaining > 0 {
                team.barrier();
            }
            return Err(failed);
        }
    }
    Ok(())
}

/// The other threads' part of the top: the supernodes factored together.
///
/// A follower learns that thread 0 stopped only at the first barrier of the
/// next supernode they share, where thread 0 waits for it
/// ([`factor_together`]); it never looks at `stop` anywhere else: between
/// two shared supernodes it could see thread 0's `stop` early and leave
/// while thread 0 waits for it at that barrier.
fn follow_top(shared: &Shared, team: &Team) {
    let scratch = scratch(shared, team);
    for &item in shared.plan.items() {
        let Item::Top(s) = item else { continue };
        if !shared.together[s] {
            continue; // thread 0's alone
        }
        match factor_together(shared, team, s, scratch) {
            Ok(Together::Done) => {}
            // thread 0 stopped before `s`, or a pivot of `s` failed (every
            // thread found it, at the same panel)
            Ok(Together::Stopped) | Err(_) => return,
        }
    }
}

/// How the team's work on a top supernode ended.
enum Together {
    /// Factored.
    Done,
    /// Not started: thread 0 had stopped at a failed pivot before it.
    Stopped,
}

/// Task `t`'s outbox into the lists, in order (or its failed pivot).
fn replay_outbox(shared: &Shared, t: usize) -> Result<(), FailedPivot> {
    // SAFETY: the others wait at a barrier; the tasks are done.
    let (failed, sent) = unsafe { (shared.failed.get(t), shared.sent.get(t)) };
    if let Some(failed) = failed {
        return Err(failed);
    }
    let start = shared.plan.task(t).start;
    // SAFETY: thread 0 alone touches the lists between barriers.
    let mut lists = unsafe { task_lists(shared, 0..shared.waiting.len()) };
    let symbolic = shared.input.symbolic;
    for i in start..start + sent {
        let d = lists.outbox[i];
        let next = lists.next_row[d];
        let target = symbolic
            .supernodes()
            .of_column(block_rows(symbolic, d)[next] as usize);
        lists.push(d, next, target);
    }
    Ok(())
}

/// Top supernode `s` by thread 0 alone, as on one thread.
fn factor_alone(shared: &Shared, s: usize, scratch: &mut Scratch) -> Result<(), FailedPivot> {
    // SAFETY: the others wait at a barrier (or are done): thread 0 alone
    // touches the values and the lists.
    let (mut values, mut lists) = unsafe {
        (
            Region {
                values: shared.values.slice_mut(0..shared.values.len()),
                first: 0,
            },
            task_lists(shared, 0..shared.waiting.len()),
        )
    };
    factor_range(&shared.input, s..s + 1, &mut values, &mut lists, scratch)
}

/// Top supernode `s` by the whole team: thread 0 loads it; each thread
/// applies every waiting update to its rows; the team factors the block;
/// thread 0 moves the descendants on to their next lists.
///
/// `stop` is read right after the first barrier, where every thread sees
/// the same value: thread 0 sets it before that barrier, and cannot set it
/// again before every thread has passed the next one.
///
/// # Errors
/// A pivot of `s` that is not positive (every thread finds it).
fn factor_together(
    shared: &Shared,
    team: &Team,
    s: usize,
    scratch: &mut Scratch,
) -> Result<Together, FailedPivot> {
    if team.leads() {
        load_alone(shared, s);
    }
    team.barrier();
    if shared.stop.load(Ordering::SeqCst) {
        return Ok(Together::Stopped); // thread 0 stopped before this supernode
    }
    scratch.place_rows_of(shared.input.symbolic, s);
    apply_updates_to_rows(shared, team, s, scratch);
    team.barrier();
    factor_block_together(shared, team, s, scratch)?;
    if team.leads() {
        move_descendants_on(shared, s);
    }
    Ok(Together::Done)
}

/// Thread 0, before the team starts on `s`: its columns loaded with `C`,
/// its list taken and published.
fn load_alone(shared: &Shared, s: usize) {
    let symbolic = shared.input.symbolic;
    let columns = symbolic.supernodes().columns(s);
    let entries = symbolic.col_ptr()[columns.start]..symbolic.col_ptr()[columns.end];
    // SAFETY: the others wait at the barrier that follows.
    unsafe {
        let mut region = Region {
            values: shared.values.slice_mut(entries.clone()),
            first: entries.start,
        };
        load_block(&shared.input, s, &mut region);
        shared.head.set(0, shared.waiting.get(s));
        shared.waiting.set(s, None);
    }
}

/// Thread 0, after the team has factored `s`: each supernode of its list
/// goes to the list of its next target, then `s` to its first.
fn move_descendants_on(shared: &Shared, s: usize) {
    let symbolic = shared.input.symbolic;
    // SAFETY: the others are past the last barrier of `s` and touch the
    // lists again only after the next barrier, which thread 0 reaches
    // after this.
    let (mut lists, mut waiting) = unsafe {
        (
            task_lists(shared, 0..shared.waiting.len()),
            shared.head.get(0),
        )
    };
    while let Some(d) = waiting {
        waiting = lists.next_waiting[d];
        let targets = targets_in(symbolic, s, d, lists.next_row[d]);
        wait_for_next_target(symbolic, d, targets.end, &mut lists);
    }
    let width = symbolic.supernodes().columns(s).len();
    wait_for_next_target(symbolic, s, width, &mut lists);
}

/// The row positions of supernode `s` this thread owns while its
/// descendants update it: consecutive ranges of about equal work (row
/// position `p` receives updates to `min(p + 1, width)` columns).
fn owned_positions(height: usize, width: usize, team: &Team) -> Range<usize> {
    let weight = |p: usize| (p + 1).min(width) as f64;
    let total: f64 = (0..height).map(weight).sum();
    let boundary = |i: usize| {
        let goal = total * i as f64 / team.size() as f64;
        let mut sum = 0.0;
        (0..height)
            .position(|p| {
                sum += weight(p);
                sum > goal
            })
            .unwrap_or(height)
    };
    let start = if team.index() == 0 {
        0
    } else {
        boundary(team.index())
    };
    let end = if team.index() + 1 == team.size() {
        height
    } else {
        boundary(team.index() + 1)
    };
    start..end.max(start)
}

/// Every update waiting for `s`, in list order, to this thread's rows.
fn apply_updates_to_rows(shared: &Shared, team: &Team, s: usize, scratch: &mut Scratch) {
    let symbolic = shared.input.symbolic;
    let (width, height) = (
        symbolic.supernodes().columns(s).len(),
        block_rows(symbolic, s).len(),
    );
    let owned = owned_positions(height, width, team);
    // SAFETY: thread 0 wrote the head and the lists before the barrier;
    // nobody writes them until the next.
    let mut waiting = unsafe { shared.head.get(0) };
    while let Some(d) = waiting {
        // SAFETY: as above.
        let (after, first) = unsafe { (shared.next_waiting.get(d), shared.next_row.get(d)) };
        waiting = after;
        let targets = targets_in(symbolic, s, d, first);
        update_rows(shared, s, d, targets, owned.clone(), scratch);
    }
}

/// `S −= X Yᵀ` for descendant `d` (row positions `targets` in `s`'s
/// columns), on the rows of `s` at positions `owned` only.
fn update_rows(
    shared: &Shared,
    s: usize,
    d: usize,
    targets: Range<usize>,
    owned: Range<usize>,
    work: &mut Scratch,
) {
    let symbolic = shared.input.symbolic;
    let d_rows = block_rows(symbolic, d);
    let Range { start: a, end: b } = rows_landing_in(work, &d_rows[targets.start..], owned);
    let (a, b) = (targets.start + a, targets.start + b);
    if a == b {
        return;
    }
    for (relative, row) in work.relative.iter_mut().zip(&d_rows[a..b]) {
        *relative = work.position_in_block[*row as usize];
    }
    let d_columns = symbolic.supernodes().columns(d);
    let entries = symbolic.col_ptr()[d_columns.start]..symbolic.col_ptr()[d_columns.end];
    for k in 0..d_columns.len() {
        work.column_base[k] = column_base(symbolic, d, k) - entries.start;
    }
    // SAFETY: `d` is factored; nobody writes its columns any more.
    let x = unsafe { shared.values.slice(entries) };
    let mut first = targets.start;
    while first < targets.end && first < b {
        let width = (targets.end - first).min(BLOCK_COLUMNS);
        let x_first = first.max(a);
        let rows = b - x_first;
        let columns = &work.column_base[..d_columns.len()];
        gram_block_rows(
            x,
            columns,
            first,
            width,
            x_first,
            rows,
            &mut work.block,
            &mut work.rows_of_y,
        );
        for t in 0..width {
            let k = d_rows[first + t] as usize - symbolic.supernodes().columns(s).start;
            let from = x_first.max(first + t);
            if from < b {
                let update = &work.block[t * rows + from - x_first..(t + 1) * rows];
                let positions = &work.relative[from - a..b - a];
                subtract_at_shared(
                    &shared.values,
                    column_base(symbolic, s, k),
                    positions,
                    update,
                );
            }
        }
        first += width;
    }
}

/// The positions in `below` (a descendant's rows from its first target
/// on) of the rows that land in the owned positions `owned` of the
/// supernode placed in `work` (they land in order).
fn rows_landing_in(work: &Scratch, below: &[u32], owned: Range<usize>) -> Range<usize> {
    let position = |row: &u32| work.position_in_block[*row as usize];
    below.partition_point(|row| position(row) < owned.start)
        ..below.partition_point(|row| position(row) < owned.end)
}

/// `values[base + positions[r]] −= update[r]`, as
/// [`subtract_at`](super::supernodal::subtract_at) does it.
fn subtract_at_shared(values: &SharedSlice<f64>, base: usize, positions: &[usize], update: &[f64]) {
    let (Some(&start), Some(&end)) = (positions.first(), positions.last()) else {
        return;
    };
    if end - start + 1 == positions.len() {
        // SAFETY: these rows of this column are this thread's alone until
        // the next barrier.
        let target = unsafe { values.slice_mut(base + start..base + end + 1) };
        for (t, &u) in target.iter_mut().zip(update) {
            *t -= u;
        }
    } else {
        for (&p, &u) in positions.iter().zip(update) {
            // SAFETY: as above.
            unsafe { values.set(base + p, values.get(base + p) - u) };
        }
    }
}

/// The rows below the triangle of panel `first .. first + width` (of a
/// block of `height` rows) that this thread finishes: equal shares.
fn panel_rows(first: usize, width: usize, height: usize, team: &Team) -> Range<usize> {
    let below = first + width..height;
    let share = even_part(below.len(), team.size(), team.index());
    below.start + share.start..below.start + share.end
}

/// The panel's triangle, a copy: column `c` at `BLOCK_COLUMNS · c`.
type Triangle = [f64; BLOCK_COLUMNS * BLOCK_COLUMNS];

/// The dense Cholesky of block `s` (updated already), panel by panel, by
/// the team, one barrier a panel: each thread factors the panel's small
/// triangle on a copy of its own (the same operations on the same numbers
/// in every thread), subtracts the earlier columns from its share of the
/// rows below it, and finishes them with its copy. Thread 0 writes the
/// triangle back after the barrier, when no thread reads it any more.
///
/// # Errors
/// The first pivot that is not positive (every thread finds it).
fn factor_block_together(
    shared: &Shared,
    team: &Team,
    s: usize,
    work: &mut Scratch,
) -> Result<(), FailedPivot> {
    let symbolic = shared.input.symbolic;
    let columns = symbolic.supernodes().columns(s);
    let height = block_rows(symbolic, s).len();
    for k in 0..columns.len() {
        work.column_base[k] = column_base(symbolic, s, k);
    }
    let mut pending = None;
    let mut first = 0;
    while first < columns.len() {
        let width = (columns.len() - first).min(BLOCK_COLUMNS);
        if let Some((at, triangle)) = pending.take() {
            write_triangle(shared, work, at, &triangle);
        }
        let triangle = factor_triangle(shared, work, first, width)
            .map_err(|(k, pivot)| (columns.start + first + k, pivot))?;
        let rows = panel_rows(first, width, height, team);
        if first > 0 && !rows.is_empty() {
            let update = earlier_columns(shared, work, first, width, rows.clone());
            subtract_update(shared, work, first, width, rows.clone(), update);
        }
        finish_rows(shared, work, first, width, rows, &triangle);
        if team.leads() {
            pending = Some(((first, width), triangle));
        }
        team.barrier();
        first += width;
    }
    if let Some((at, triangle)) = pending {
        write_triangle(shared, work, at, &triangle); // nobody reads it now
    }
    Ok(())
}

/// `rows` of the product of the block's earlier columns (`0 .. first`)
/// with their rows in the panel `first .. first + width`
/// ([`gram_block_rows`]), into `work.block`; returns the number of rows
/// it holds per column.
fn earlier_columns(
    shared: &Shared,
    work: &mut Scratch,
    first: usize,
    width: usize,
    rows: Range<usize>,
) -> usize {
    // the earlier columns, from the block's first entry on (`relative` is
    // long enough: a block has at least as many rows as columns)
    let start = work.column_base[0];
    for k in 0..first {
        work.relative[k] = work.column_base[k] - start;
    }
    let end = work.column_base[first] + first;
    // SAFETY: the block's earlier columns are final; a panel's phase
    // writes the panel's columns only.
    let x = unsafe { shared.values.slice(start..end) };
    let count = rows.len();
    let bases = &work.relative[..first];
    gram_block_rows(
        x,
        bases,
        first,
        width,
        rows.start,
        count,
        &mut work.block,
        &mut work.rows_of_y,
    );
    count
}

/// This thread's `rows` of the panel's columns minus the product
/// [`earlier_columns`] left in `work.block` (`count` rows a column).
fn subtract_update(
    shared: &Shared,
    work: &Scratch,
    first: usize,
    width: usize,
    rows: Range<usize>,
    count: usize,
) {
    for t in 0..width {
        let base = work.column_base[first + t];
        // SAFETY: these rows of the panel's columns are this thread's.
        let target = unsafe { shared.values.slice_mut(base + rows.start..base + rows.end) };
        let update = &work.block[t * count..t * count + rows.len()];
        for (value, &u) in target.iter_mut().zip(update) {
            *value -= u;
        }
    }
}

/// The panel's triangle, updated by the earlier columns and factored on a
/// copy ([`factor_panel`]: the same operations on the same numbers as on
/// one thread).
///
/// # Errors
/// `(k, pivot)` for the panel's column `first + k`.
fn factor_triangle(
    shared: &Shared,
    work: &mut Scratch,
    first: usize,
    width: usize,
) -> Result<Triangle, FailedPivot> {
    let mut triangle = [0.0; BLOCK_COLUMNS * BLOCK_COLUMNS];
    for c in 0..width {
        let base = work.column_base[first + c];
        // SAFETY: the triangle is written back only after the barrier
        // that ends this panel's phase.
        let column = unsafe { shared.values.slice(base + first + c..base + first + width) };
        triangle[BLOCK_COLUMNS * c + c..BLOCK_COLUMNS * c + width].copy_from_slice(column);
    }
    if first > 0 {
        let count = earlier_columns(shared, work, first, width, first..first + width);
        for c in 0..width {
            for r in c..width {
                triangle[BLOCK_COLUMNS * c + r] -= work.block[c * count + r];
            }
        }
    }
    let bases: [usize; BLOCK_COLUMNS] = std::array::from_fn(|c| BLOCK_COLUMNS * c);
    factor_panel(&bases, 0, width, width, &mut triangle)?;
    Ok(triangle)
}

/// Thread 0: the factored triangle of the panel `(first, width)` back in
/// `L`.
fn write_triangle(
    shared: &Shared,
    work: &Scratch,
    (first, width): (usize, usize),
    triangle: &Triangle,
) {
    for c in 0..width {
        let base = work.column_base[first + c];
        // SAFETY: no thread reads or writes the triangle of an earlier
        // panel (the next panels read the rows below it).
        let column = unsafe {
            shared
                .values
                .slice_mut(base + first + c..base + first + width)
        };
        column.copy_from_slice(&triangle[BLOCK_COLUMNS * c + c..BLOCK_COLUMNS * c + width]);
    }
}

/// This thread's `rows` below the panel's triangle, as [`factor_panel`]
/// treats them: for each column of the panel, the panel's earlier columns
/// subtracted (their entries in the triangle from `triangle`), then the
/// division by the pivot.
fn finish_rows(
    shared: &Shared,
    work: &Scratch,
    first: usize,
    width: usize,
    rows: Range<usize>,
    triangle: &Triangle,
) {
    if rows.is_empty() {
        return;
    }
    for k in 0..width {
        let base_k = work.column_base[first + k];
        for j in 0..k {
            let base_j = work.column_base[first + j];
            let l_kj = triangle[BLOCK_COLUMNS * j + k];
            // SAFETY: these rows of the panel's columns are this thread's.
            let (source, target) = unsafe {
                (
                    shared.values.slice(base_j + rows.start..base_j + rows.end),
                    shared
                        .values
                        .slice_mut(base_k + rows.start..base_k + rows.end),
                )
            };
            for (value, &x) in target.iter_mut().zip(source) {
                *value -= l_kj * x;
            }
        }
        let inverse = 1.0 / triangle[BLOCK_COLUMNS * k + k];
        // SAFETY: as above.
        let target = unsafe {
            shared
                .values
                .slice_mut(base_k + rows.start..base_k + rows.end)
        };
        for value in target {
            *value *= inverse;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::sparse::{CscMatrix, Method, Ordering, Relaxation, SparseCholesky};
    use crate::linalg::LinalgError;

    /// The `Q` of a scene of `data/` and the simulation's analysis of it.
    fn analysed(name: &str) -> (CscMatrix, SymbolicCholesky) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data")
            .join(name);
        let scene = crate::mesh::load_scene(&path).unwrap();
        let q = crate::sim::precomputation::scene_q(&scene, crate::sim::DELTA_T);
        let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd)
            .unwrap()
            .relaxed(&Relaxation::SMALL);
        (q, symbolic)
    }

    /// The first column of a supernode of each kind the plan has: in a
    /// subtree, in the top alone, in the top together.
    fn columns_of_each_kind(
        symbolic: &SymbolicCholesky,
        plan: &ParallelFactor,
    ) -> [Option<usize>; 3] {
        let first = |s: usize| symbolic.supernodes().columns(s).start;
        let items = plan.schedule.items();
        let task = items.iter().find_map(|i| match i {
            Item::Task(t) => Some(first(plan.schedule.task(*t).start)),
            _ => None,
        });
        let top = |together: bool| {
            items.iter().find_map(|i| match i {
                Item::Top(s) if plan.together[*s] == together => Some(first(*s)),
                _ => None,
            })
        };
        [task, top(false), top(true)]
    }

    /// `a` with its diagonal entry at `vertex` made very negative.
    fn spoiled(a: &CscMatrix, vertex: usize) -> CscMatrix {
        let mut bad = a.clone();
        let slot = bad.col_ptr()[vertex]
            + bad
                .column(vertex)
                .0
                .iter()
                .position(|&i| i == vertex)
                .unwrap();
        bad.values_mut()[slot] = -1e12;
        bad
    }

    #[test]
    fn every_kind_of_supernode_fails_at_the_column_one_thread_reports() {
        let mut tried = [false; 3];
        for name in ["flag.json", "skirt.json"] {
            let (q, symbolic) = analysed(name);
            for threads in [2, 3, 4] {
                let plan = ParallelFactor::new(&symbolic, threads);
                for (kind, column) in columns_of_each_kind(&symbolic, &plan)
                    .into_iter()
                    .enumerate()
                {
                    let Some(column) = column else { continue };
                    tried[kind] = true;
                    let vertex = symbolic.permutation().perm()[column];
                    let bad = spoiled(&q, vertex);
                    let one = SparseCholesky::factor(symbolic.clone(), &bad, Method::Supernodal);
                    let many = SparseCholesky::factor_with_threads(
                        symbolic.clone(),
                        &bad,
                        Method::Supernodal,
                        threads,
                    );
                    // the columns before it are untouched: it fails there
                    let (one, many) = (one.unwrap_err(), many.unwrap_err());
                    assert!(
                        matches!(one, LinalgError::NotPositiveDefinite { column: c, .. } if c == vertex),
                        "{one:?}"
                    );
                    assert_eq!(one, many, "{name}, column {column} on {threads} threads");
                }
            }
        }
        assert_eq!(tried, [true; 3], "a kind of supernode was never tried");
    }

    #[test]
    fn thread_0_stopping_before_a_shared_supernode_never_leaves_it_waiting() {
        // a pivot fails in a subtree or a top supernode thread 0 factors
        // alone, with supernodes the team shares after it: the followers
        // must leave at the barrier where thread 0 tells them, never
        // before it (a follower that read the flag between two shared
        // supernodes could leave thread 0 waiting there for ever; the race
        // is rare, so the failure is repeated, on more threads than cores
        // too, and every refactorization must end with the same error)
        let (q, symbolic) = analysed("skirt.json");
        let mut tried = 0;
        for threads in [2, 3, 4, 8] {
            let plan = ParallelFactor::new(&symbolic, threads);
            let items = plan.schedule.items();
            let shared_after = |i: usize| {
                (items[i..].iter()).any(|later| matches!(later, Item::Top(t) if plan.together[*t]))
            };
            // a subtree or a supernode thread 0 factors alone, before one
            // the team shares
            let stops_before_shared = items.iter().enumerate().find_map(|(i, item)| match item {
                Item::Task(t) if shared_after(i) => Some(plan.schedule.task(*t).start),
                Item::Top(s) if !plan.together[*s] && shared_after(i) => Some(*s),
                _ => None,
            });
            let Some(s) = stops_before_shared else {
                continue;
            };
            tried += 1;
            let column = symbolic.supernodes().columns(s).start;
            let bad = spoiled(&q, symbolic.permutation().perm()[column]);
            let mut factor = SparseCholesky::factor_with_threads(
                symbolic.clone(),
                &q,
                Method::Supernodal,
                threads,
            )
            .unwrap();
            let expected =
                SparseCholesky::factor(symbolic.clone(), &bad, Method::Supernodal).unwrap_err();
            for _ in 0..200 {
                assert_eq!(
                    factor.refactor(&bad).unwrap_err(),
                    expected,
                    "{threads} threads"
                );
            }
        }
        assert!(tried > 0, "no thread count had such a supernode");
    }
}
