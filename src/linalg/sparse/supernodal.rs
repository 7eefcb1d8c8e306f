//! Supernodal numeric Cholesky (left-looking, dense blocks).
//!
//! Columns of `L` with one shared pattern (a [supernode](super::supernodes))
//! form a dense lower-trapezoidal block. Going through the supernodes in
//! order, each block `S` is
//!
//! 1. **loaded** with its columns of `C = P A Pᵀ` (zeros elsewhere), read
//!    from `A` through the slots of [`FactorLoading`];
//! 2. **updated** by every earlier supernode `D` that has rows in `S`'s
//!    columns (its *descendants*): `S −= X Yᵀ`, where `X` is `D`'s block
//!    from the first of those rows down and `Y` its rows inside `S`'s
//!    column range. The product is dense ([`gram_block`]); it is then
//!    subtracted at the positions its rows have in `S` ("relative
//!    indices");
//! 3. **factored** as a dense block: panel by panel, each panel first
//!    updated by the panels before it (the same kernel), then factored
//!    column by column: `L(k, k) = √pivot`, the column below divided by it.
//!
//! Which descendants update `S`? Each supernode `D` waits in the list of
//! the next supernode its rows reach; after updating it, it moves on to the
//! list of the supernode its next row belongs to (the "linked lists" of
//! left-looking methods). Every list and buffer is sized once, in
//! [`SupernodalWorkspace::new`].
//!
//! Block storage: the CSC storage of `L` already stores each column of a
//! supernode contiguously, from its diagonal down over the shared rows, so
//! row position `p` of the block's column `k` is
//! `values[col_ptr[first + k] − k + p]`. The simplicial code and the
//! triangular solves read the very same arrays.
//!
//! Cost: the same flops as the simplicial method, `Σ_j count[j]²`, but
//! nearly all of them in a register-blocked dense kernel.
//!
//! Source: Ng & Peyton, "Block sparse Cholesky algorithms on advanced
//! uniprocessor computers", SIAM J. Sci. Comput. 14(5), 1993; Chen, Davis,
//! Hager, Rajamanickam, "CHOLMOD", ACM TOMS 35(3), 2008 (`super_numeric`);
//! Davis, Rajamanickam, Sid-Lakhdar, Acta Numerica 2016, §9.

use super::csc::CscMatrix;
use super::factor_loading::FactorLoading;
use super::symbolic::SymbolicCholesky;
use super::up_looking::FailedPivot;
use crate::linalg::dense::gram_block::{gram_block, BLOCK_COLUMNS};

/// Work arrays of the supernodal factorization, sized once per analysis:
/// the lists of waiting supernodes, and one [`Scratch`] per thread.
#[derive(Debug, Clone)]
pub struct SupernodalWorkspace {
    /// `waiting[s]`: first of the supernodes whose next update goes to `s`.
    pub(super) waiting: Vec<Option<usize>>,
    /// `next_waiting[d]`: the supernode after `d` in the same list.
    pub(super) next_waiting: Vec<Option<usize>>,
    /// `next_row[d]`: position in `d`'s rows where its next update starts.
    pub(super) next_row: Vec<usize>,
    /// The buffers of each thread (one without threads).
    pub(super) scratch: Vec<Scratch>,
}

/// The buffers one thread uses for one supernode at a time.
#[derive(Debug, Clone)]
pub(super) struct Scratch {
    /// `position_in_block[row]`: where `row` sits in the current supernode's rows.
    pub(super) position_in_block: Vec<usize>,
    /// Start of each source column, for the kernel (longest supernode).
    pub(super) column_base: Vec<usize>,
    /// One block of four columns of an update (longest row list × 4).
    pub(super) block: Vec<f64>,
    /// The kernel's copy of the four target rows of each source column.
    pub(super) rows_of_y: Vec<[f64; BLOCK_COLUMNS]>,
    /// Positions in the target supernode of a descendant's rows.
    pub(super) relative: Vec<usize>,
}

impl SupernodalWorkspace {
    /// Work arrays for the factor analysed in `symbolic`, for one thread.
    pub fn new(symbolic: &SymbolicCholesky) -> Self {
        Self::for_threads(symbolic, 1)
    }

    /// Work arrays for the factor analysed in `symbolic`, with buffers for
    /// `threads` threads.
    pub fn for_threads(symbolic: &SymbolicCholesky, threads: usize) -> Self {
        let count = symbolic.supernodes().len();
        let scratch = Scratch::new(symbolic);
        SupernodalWorkspace {
            waiting: vec![None; count],
            next_waiting: vec![None; count],
            next_row: vec![0; count],
            scratch: vec![scratch; threads.max(1)],
        }
    }

    /// Bytes held (array lengths).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.next_row.len() * size_of::<usize>()
            + (self.waiting.len() + self.next_waiting.len()) * size_of::<Option<usize>>()
            + self.scratch.iter().map(Scratch::bytes).sum::<usize>()
    }
}

impl Scratch {
    /// Buffers sized for the widest and tallest supernodes of `symbolic`.
    fn new(symbolic: &SymbolicCholesky) -> Self {
        let supernodes = symbolic.supernodes();
        let (widest, tallest) = (0..supernodes.len())
            .map(|s| {
                let columns = supernodes.columns(s);
                (columns.len(), symbolic.column_counts()[columns.start])
            })
            .fold((0, 0), |(w, m), (cw, cm)| (w.max(cw), m.max(cm)));
        Scratch {
            position_in_block: vec![0; symbolic.n()],
            column_base: vec![0; widest],
            block: vec![0.0; BLOCK_COLUMNS * tallest],
            rows_of_y: vec![[0.0; BLOCK_COLUMNS]; widest],
            relative: vec![0; tallest],
        }
    }

    fn bytes(&self) -> usize {
        use std::mem::size_of;
        (self.position_in_block.len() + self.column_base.len() + self.relative.len())
            * size_of::<usize>()
            + std::mem::size_of_val(&self.block[..])
            + std::mem::size_of_val(&self.rows_of_y[..])
    }

    /// `position_in_block[row]` for the rows of supernode `s`.
    pub(super) fn place_rows_of(&mut self, symbolic: &SymbolicCholesky, s: usize) {
        for (position, &row) in block_rows(symbolic, s).iter().enumerate() {
            self.position_in_block[row as usize] = position;
        }
    }
}

/// The values of `L` one run writes: all of them, or the columns of a
/// range of supernodes (`values[0]` is entry `first` of `L`'s values).
pub(super) struct Region<'v> {
    pub(super) values: &'v mut [f64],
    pub(super) first: usize,
}

/// The waiting lists of the supernodes `first .. end` (all of them, or
/// one thread's subtree): `waiting`, `next_waiting` and `next_row` hold
/// theirs. A supernode whose next target lies beyond `end` is put in
/// `outbox` instead, in order, to be put in its list later.
pub(super) struct Lists<'l> {
    pub(super) first: usize,
    pub(super) end: usize,
    pub(super) waiting: &'l mut [Option<usize>],
    pub(super) next_waiting: &'l mut [Option<usize>],
    pub(super) next_row: &'l mut [usize],
    pub(super) outbox: &'l mut [usize],
    /// Supernodes put in `outbox`.
    pub(super) sent: usize,
}

impl Lists<'_> {
    /// Takes the list of supernodes waiting for `s`.
    fn take(&mut self, s: usize) -> Option<usize> {
        self.waiting[s - self.first].take()
    }

    /// The supernode after `d` in its list.
    fn after(&self, d: usize) -> Option<usize> {
        self.next_waiting[d - self.first]
    }

    /// Where `d`'s next update starts in its rows.
    fn next_row(&self, d: usize) -> usize {
        self.next_row[d - self.first]
    }

    /// Puts `d`, whose next update starts at its row position `next`, in
    /// the list of `target` (or in the outbox, when `target` is not one of
    /// these supernodes).
    pub(super) fn push(&mut self, d: usize, next: usize, target: usize) {
        self.next_row[d - self.first] = next;
        if target < self.end {
            self.next_waiting[d - self.first] = self.waiting[target - self.first];
            self.waiting[target - self.first] = Some(d);
        } else {
            self.outbox[self.sent] = d;
            self.sent += 1;
        }
    }
}

/// Fills `values` with `L` for `C = P A Pᵀ`, reading `A` (its lower
/// triangle) through `loading`.
///
/// # Errors
/// The first column whose pivot is not positive and finite.
pub fn factor_supernodal(
    symbolic: &SymbolicCholesky,
    a: &CscMatrix,
    loading: &FactorLoading,
    values: &mut [f64],
    work: &mut SupernodalWorkspace,
) -> Result<(), FailedPivot> {
    work.waiting.fill(None);
    let count = symbolic.supernodes().len();
    let mut lists = Lists {
        first: 0,
        end: count,
        waiting: &mut work.waiting,
        next_waiting: &mut work.next_waiting,
        next_row: &mut work.next_row,
        outbox: &mut [],
        sent: 0,
    };
    let mut region = Region { values, first: 0 };
    let input = Input {
        symbolic,
        a,
        loading,
    };
    factor_range(
        &input,
        0..count,
        &mut region,
        &mut lists,
        &mut work.scratch[0],
    )
}

/// What every factorization reads: the analysis, `A`, and where `A`'s
/// entries go in `L`.
#[derive(Clone, Copy)]
pub(super) struct Input<'a> {
    pub(super) symbolic: &'a SymbolicCholesky,
    pub(super) a: &'a CscMatrix,
    pub(super) loading: &'a FactorLoading,
}

/// The supernodes `supernodes` in order, each loaded, updated by those
/// waiting for it, factored, and put in the list of its first target.
///
/// # Errors
/// The first column whose pivot is not positive and finite.
pub(super) fn factor_range(
    input: &Input,
    supernodes: std::ops::Range<usize>,
    values: &mut Region,
    lists: &mut Lists,
    scratch: &mut Scratch,
) -> Result<(), FailedPivot> {
    let symbolic = input.symbolic;
    for s in supernodes {
        scratch.place_rows_of(symbolic, s);
        load_block(input, s, values);
        apply_waiting_updates(symbolic, s, values, lists, scratch);
        factor_block(symbolic, s, values, scratch)?;
        let width = symbolic.supernodes().columns(s).len();
        wait_for_next_target(symbolic, s, width, lists);
    }
    Ok(())
}

/// The rows of supernode `s`: the pattern of its first column.
pub(super) fn block_rows(symbolic: &SymbolicCholesky, s: usize) -> &[u32] {
    symbolic.supernode_rows(s)
}

/// Where row position 0 of column `k` of the block would be stored, so that
/// position `p ≥ k` is at `base + p` (an index into all of `L`'s values).
pub(super) fn column_base(symbolic: &SymbolicCholesky, s: usize, k: usize) -> usize {
    symbolic.col_ptr()[symbolic.supernodes().columns(s).start + k] - k
}

/// Step 1: the block's columns get `C(:, j)`, zeros elsewhere.
pub(super) fn load_block(input: &Input, s: usize, values: &mut Region) {
    let col_ptr = input.symbolic.col_ptr();
    for j in input.symbolic.supernodes().columns(s) {
        let column = col_ptr[j] - values.first..col_ptr[j + 1] - values.first;
        input
            .loading
            .load_column(input.a, j, &mut values.values[column]);
    }
}

/// Step 2: every supernode waiting for `s` subtracts its update, then moves
/// on to the list of the next supernode its rows reach.
fn apply_waiting_updates(
    symbolic: &SymbolicCholesky,
    s: usize,
    values: &mut Region,
    lists: &mut Lists,
    scratch: &mut Scratch,
) {
    let mut waiting = lists.take(s);
    while let Some(d) = waiting {
        waiting = lists.after(d);
        let targets = targets_in(symbolic, s, d, lists.next_row(d));
        update_from_descendant(symbolic, s, d, targets.clone(), values, scratch);
        wait_for_next_target(symbolic, d, targets.end, lists);
    }
}

/// The row positions of descendant `d`, from `first` on, that fall in the
/// columns of `s`.
pub(super) fn targets_in(
    symbolic: &SymbolicCholesky,
    s: usize,
    d: usize,
    first: usize,
) -> std::ops::Range<usize> {
    let end_column = symbolic.supernodes().columns(s).end;
    let rows = block_rows(symbolic, d);
    first..first + rows[first..].partition_point(|&r| (r as usize) < end_column)
}

/// `S −= X Yᵀ` for descendant `d`, whose row positions `targets` fall in
/// `s`'s columns: four target columns at a time, kernel then scatter.
fn update_from_descendant(
    symbolic: &SymbolicCholesky,
    s: usize,
    d: usize,
    targets: std::ops::Range<usize>,
    values: &mut Region,
    work: &mut Scratch,
) {
    let d_rows = block_rows(symbolic, d);
    let d_width = symbolic.supernodes().columns(d).len();
    for k in 0..d_width {
        work.column_base[k] = column_base(symbolic, d, k) - values.first;
    }
    let s_first_column = symbolic.supernodes().columns(s).start;
    // where each of d's rows from the first target down sits in s
    let below = &d_rows[targets.start..];
    for (relative, &row) in work.relative.iter_mut().zip(below) {
        *relative = work.position_in_block[row as usize];
    }
    let mut first = targets.start;
    while first < targets.end {
        let width = (targets.end - first).min(BLOCK_COLUMNS);
        let rows = d_rows.len() - first;
        gram_block(
            values.values,
            &work.column_base[..d_width],
            first,
            width,
            rows,
            &mut work.block,
            &mut work.rows_of_y,
        );
        let relative = &work.relative[first - targets.start..];
        for t in 0..width {
            let k = d_rows[first + t] as usize - s_first_column; // column in s
            let base = column_base(symbolic, s, k) - values.first;
            let update = &work.block[t * rows + t..(t + 1) * rows];
            let positions = &relative[t..rows];
            subtract_at(&mut values.values[base..], positions, update);
        }
        first += width;
    }
}

/// `target[positions[r]] −= update[r]`; a run of consecutive positions (the
/// common case: a descendant's rows often sit together in the target) is a
/// plain slice subtraction, which the compiler vectorizes.
pub(super) fn subtract_at(target: &mut [f64], positions: &[usize], update: &[f64]) {
    let (Some(&start), Some(&end)) = (positions.first(), positions.last()) else {
        return;
    };
    if end - start + 1 == positions.len() {
        for (t, &u) in target[start..=end].iter_mut().zip(update) {
            *t -= u;
        }
    } else {
        for (&p, &u) in positions.iter().zip(update) {
            target[p] -= u;
        }
    }
}

/// Step 3: dense Cholesky of the block, in panels of four columns.
fn factor_block(
    symbolic: &SymbolicCholesky,
    s: usize,
    values: &mut Region,
    work: &mut Scratch,
) -> Result<(), FailedPivot> {
    let columns = symbolic.supernodes().columns(s);
    let height = block_rows(symbolic, s).len();
    for k in 0..columns.len() {
        work.column_base[k] = column_base(symbolic, s, k) - values.first;
    }
    let values = &mut *values.values;
    let mut first = 0;
    while first < columns.len() {
        let width = (columns.len() - first).min(BLOCK_COLUMNS);
        let rows = height - first;
        if first > 0 {
            // panel −= (earlier columns of the block)(their rows in the panel)ᵀ
            gram_block(
                values,
                &work.column_base[..first],
                first,
                width,
                rows,
                &mut work.block,
                &mut work.rows_of_y,
            );
            for t in 0..width {
                let base = work.column_base[first + t] + first;
                let update = &work.block[t * rows..(t + 1) * rows];
                for r in t..rows {
                    values[base + r] -= update[r];
                }
            }
        }
        factor_panel(&work.column_base, first, width, height, values)
            .map_err(|(k, pivot)| (columns.start + k, pivot))?;
        first += width;
    }
    Ok(())
}

/// Unblocked Cholesky of the panel of columns `first .. first + width` (the
/// earlier columns already subtracted): for each column, subtract the
/// panel's previous columns, then divide by the square root of the pivot.
/// Rows `first .. height` of the panel's columns; `height = first + width`
/// factors the panel's own triangle only.
pub(super) fn factor_panel(
    column_base: &[usize],
    first: usize,
    width: usize,
    height: usize,
    values: &mut [f64],
) -> Result<(), FailedPivot> {
    for k in first..first + width {
        let base_k = column_base[k];
        for &base_j in &column_base[first..k] {
            let l_kj = values[base_j + k];
            for p in k..height {
                values[base_k + p] -= l_kj * values[base_j + p];
            }
        }
        let pivot = values[base_k + k];
        if !(pivot > 0.0 && pivot.is_finite()) {
            return Err((k, pivot));
        }
        let diagonal = pivot.sqrt();
        values[base_k + k] = diagonal;
        let inverse = 1.0 / diagonal; // one division, then multiplications
        for value in &mut values[base_k + k + 1..base_k + height] {
            *value *= inverse;
        }
    }
    Ok(())
}

/// Puts supernode `d` in the list of the supernode holding its row at
/// position `next` (if it has rows left).
pub(super) fn wait_for_next_target(
    symbolic: &SymbolicCholesky,
    d: usize,
    next: usize,
    lists: &mut Lists,
) {
    let rows = block_rows(symbolic, d);
    if next < rows.len() {
        let target = symbolic.supernodes().of_column(rows[next] as usize);
        lists.push(d, next, target);
    }
}
