//! The sparse Cholesky factorization `P A Pᵀ = L Lᵀ`, put together.
//!
//! ```text
//! analyse once   SymbolicCholesky::analyze(&a, Ordering::Amd)   ordering, tree, counts, pattern
//! factor         SparseCholesky::factor(symbolic, &a, method)    values of L
//! refactor       cholesky.refactor(&a_with_new_values)           same pattern, new values
//! solve          cholesky.solve_points_in_place(&mut b)          b ← A⁻¹ b, three columns at once
//! ```
//!
//! A solve is `x = Pᵀ L⁻ᵀ L⁻¹ P b`: permute, forward substitution, back
//! substitution, permute back. It uses a buffer sized at factorization, so
//! it never allocates.
//!
//! Two numeric methods fill the same storage of `L`: [`Method::Simplicial`]
//! (row by row, [`up_looking`](super::up_looking)) and
//! [`Method::Supernodal`] (dense blocks, [`supernodal`](super::supernodal)).
//! The solves follow the method: column by column
//! ([`triangular_solve`]) or supernode by supernode ([`supernodal_solve`]).
//!
//! Threads: [`SparseCholesky::factor_with_threads`] keeps a pool of
//! threads ([`Threads`]) with the factorization; the supernodal method then
//! factors and solves by subtrees of the elimination tree on all of them
//! ([`supernodal_parallel`](super::supernodal_parallel),
//! [`supernodal_solve_parallel`](super::supernodal_solve_parallel)), to the
//! same bits as on one thread. The simplicial method, the textbook's, runs
//! on one thread whatever the pool.
//!
//! Source: Davis 2006, ch. 4 and §8.1 (`cs_cholsol`).

use super::csc::{CscMatrix, Triangle};
use super::factor_loading::FactorLoading;
use super::permutation::Permutation;
use super::permute::PermutedTriangle;
use super::supernodal::{factor_supernodal, Input, SupernodalWorkspace};
use super::supernodal_parallel::{factor_parallel, ParallelFactor};
use super::supernodal_solve;
use super::supernodal_solve_parallel::{ParallelSolve, TeamSolve};
use super::symbolic::SymbolicCholesky;
use super::triangular_solve::{self, FactorView};
use super::up_looking::{factor_up_looking, FailedPivot, UpLookingWorkspace};
use crate::linalg::error::LinalgError;
use crate::linalg::huge_pages::advise_huge_pages;
use crate::linalg::threads::{SharedSlice, Team, Threads};

/// How the numeric factorization is computed (both give the same `L` up to
/// rounding).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// One row at a time, one multiply-add at a time.
    Simplicial,
    /// Columns with a shared pattern as dense blocks, with dense kernels.
    #[default]
    Supernodal,
}

impl Method {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Simplicial => "simplicial",
            Method::Supernodal => "supernodal",
        }
    }
}

impl std::str::FromStr for Method {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        match name {
            "simplicial" => Ok(Method::Simplicial),
            "supernodal" => Ok(Method::Supernodal),
            other => Err(format!(
                "unknown factorization '{other}' (expected simplicial or supernodal)"
            )),
        }
    }
}

/// The work arrays of whichever method is in use, and how it reads `A`:
/// the up-looking method reads `C = P A Pᵀ` by its upper triangle (kept,
/// refilled with each matrix factored); the supernodal one loads its blocks
/// straight from `A` through [`FactorLoading`], with no copy of `C`.
#[derive(Debug, Clone)]
enum Workspace {
    Simplicial(UpLookingWorkspace, PermutedTriangle),
    Supernodal(SupernodalWorkspace, FactorLoading),
}

/// A numeric sparse Cholesky factorization, ready to solve.
///
/// # Examples
///
/// The textbook path (natural order, simplicial) and the fast one (AMD,
/// supernodal) on the `Q = AᵀA + I` of a chain of three unit masses joined
/// by two springs:
///
/// ```
/// use masssprings::linalg::sparse::{Method, Ordering, SparseCholesky, SymbolicCholesky, TripletMatrix};
///
/// let entries = [
///     (0, 0, 2.0), (1, 1, 3.0), (2, 2, 2.0),
///     (1, 0, -1.0), (0, 1, -1.0), (2, 1, -1.0), (1, 2, -1.0),
/// ];
/// let q = TripletMatrix::from_entries(3, 3, entries)?.to_csc();
/// for (ordering, method) in [
///     (Ordering::Natural, Method::Simplicial),
///     (Ordering::Amd, Method::Supernodal),
/// ] {
///     let symbolic = SymbolicCholesky::analyze(&q, ordering)?; // patterns only
///     assert_eq!(symbolic.nnz_l(), 5); // a chain fills in nothing
///     let mut cholesky = SparseCholesky::factor(symbolic, &q, method)?;
///     // b = Q · (1, 2, 3) in each of the three columns x, y, z
///     let mut p = [[0.0; 3], [2.0; 3], [4.0; 3]];
///     cholesky.solve_points_in_place(&mut p); // p = Q⁻¹ b
///     for (i, row) in p.iter().enumerate() {
///         assert!(row.iter().all(|&v| (v - (i + 1) as f64).abs() < 1e-14));
///     }
/// }
/// # Ok::<(), masssprings::linalg::LinalgError>(())
/// ```
#[derive(Debug, Clone)]
pub struct SparseCholesky {
    symbolic: SymbolicCholesky,
    /// Values of `L`, laid out as `symbolic.col_ptr()` / `row_idx()`.
    values: Vec<f64>,
    workspace: Workspace,
    /// Room for `n` rows of four values, for the permuted right-hand side.
    solve_buffer: Vec<f64>,
    /// False after a failed refactorization: the values are not a factor.
    factored: bool,
    /// The threads, when there are more than one, and the supernodal
    /// method's plans for them.
    parallel: Option<Parallel>,
}

/// A pool of threads, and how the supernodal method shares its
/// factorization and its solves among them (the simplicial method runs on
/// one thread and has none).
#[derive(Debug, Clone)]
struct Parallel {
    threads: Threads,
    factor: ParallelFactor,
    solve: ParallelSolve,
}

impl SparseCholesky {
    /// Factors `a` (the matrix analysed by `symbolic`, or one with the same
    /// pattern and new values) with `method`. The supernodal method uses
    /// the supernodes of `symbolic` as they are: fundamental, or relaxed by
    /// [`SymbolicCholesky::relaxed`] (not the default: on cloth matrices
    /// the stored zeros slow the solve more than the wider blocks speed
    /// the factorization, `docs/performance.md`).
    ///
    /// # Errors
    /// [`LinalgError::InvalidStructure`] for the simplicial method with a
    /// relaxed analysis that stores zeros;
    /// [`LinalgError::PatternMismatch`] when `a`'s pattern is not the one
    /// analysed; [`LinalgError::NotPositiveDefinite`] naming the column of
    /// `a` where a pivot was not positive.
    pub fn factor(
        symbolic: SymbolicCholesky,
        a: &CscMatrix,
        method: Method,
    ) -> Result<Self, LinalgError> {
        Self::factor_with_threads(symbolic, a, method, 1)
    }

    /// [`SparseCholesky::factor`] with a pool of `threads` threads kept for
    /// every refactorization and solve: the supernodal method factors and
    /// solves on all of them, to the same bits as on one
    /// ([`crate::linalg::threads`]); `1` spawns none and runs the
    /// single-threaded code, and so does the simplicial method, the
    /// textbook's.
    ///
    /// # Errors
    /// As [`SparseCholesky::factor`].
    pub fn factor_with_threads(
        symbolic: SymbolicCholesky,
        a: &CscMatrix,
        method: Method,
        threads: usize,
    ) -> Result<Self, LinalgError> {
        if method == Method::Simplicial && symbolic.explicit_zeros() > 0 {
            return Err(LinalgError::InvalidStructure(
                "the simplicial method needs the exact pattern of L, not a relaxed one".into(),
            ));
        }
        let n = symbolic.n();
        let mut symbolic = symbolic;
        match method {
            Method::Supernodal => symbolic.store_rows_per_supernode(), // all its blocks and solves read
            Method::Simplicial => symbolic.store_rows_per_column(), // its rows and substitutions read these
        }
        let parallel = Parallel::new(&symbolic, method, threads);
        let count = parallel.as_ref().map_or(1, |p| p.threads.count());
        let workspace = match method {
            Method::Simplicial => Workspace::Simplicial(
                UpLookingWorkspace::new(n),
                PermutedTriangle::new(a, symbolic.permutation(), Triangle::Upper)?,
            ),
            Method::Supernodal => Workspace::Supernodal(
                SupernodalWorkspace::for_threads(&symbolic, count),
                FactorLoading::new(a, &symbolic)?,
            ),
        };
        let mut cholesky = SparseCholesky {
            values: vec![0.0; symbolic.nnz_l()],
            symbolic,
            workspace,
            solve_buffer: vec![0.0; 4 * n],
            factored: false,
            parallel,
        };
        // the arrays every solve streams and gathers from (src/linalg/huge_pages.rs)
        advise_huge_pages(&mut cholesky.values);
        advise_huge_pages(&mut cholesky.solve_buffer);
        cholesky.refactor(a)?;
        Ok(cholesky)
    }

    /// Recomputes `L` for new values of `a`, keeping the analysis (same
    /// pattern required). No allocation.
    ///
    /// # Errors
    /// As [`SparseCholesky::factor`]. After an error the factorization
    /// cannot be used to solve until a refactorization succeeds.
    pub fn refactor(&mut self, a: &CscMatrix) -> Result<(), LinalgError> {
        self.factored = false;
        let outcome = match &mut self.workspace {
            Workspace::Simplicial(work, permuted) => {
                permuted.refill(a)?;
                factor_up_looking(&self.symbolic, permuted.matrix(), &mut self.values, work)
            }
            Workspace::Supernodal(work, loading) => {
                if !loading.fits(a) {
                    return Err(LinalgError::PatternMismatch);
                }
                let input = Input {
                    symbolic: &self.symbolic,
                    a,
                    loading,
                };
                match &mut self.parallel {
                    Some(Parallel {
                        threads,
                        factor: plan,
                        ..
                    }) => factor_parallel(threads, input, &mut self.values, work, plan),
                    _ => factor_supernodal(&self.symbolic, a, loading, &mut self.values, work),
                }
            }
        };
        outcome.map_err(|failed| self.not_positive_definite(failed))?;
        self.factored = true;
        Ok(())
    }

    /// The symbolic analysis this factorization uses.
    pub fn symbolic(&self) -> &SymbolicCholesky {
        &self.symbolic
    }

    /// The number of threads it factors and solves with (1 for the
    /// simplicial method, whatever it was asked for).
    pub fn threads(&self) -> usize {
        self.parallel.as_ref().map_or(1, |p| p.threads.count())
    }

    /// Factors and solves from now on with `threads` threads (a new pool;
    /// `1`: none). The values of `L` stay: the same bits either way.
    pub fn set_threads(&mut self, threads: usize) {
        let method = self.method();
        self.parallel = Parallel::new(&self.symbolic, method, threads);
        let count = self.threads();
        if let Workspace::Supernodal(work, _) = &mut self.workspace {
            *work = SupernodalWorkspace::for_threads(&self.symbolic, count);
        }
    }

    /// Bytes held (array lengths, not capacities): the analysis, the
    /// values of `L`, the permuted `C`, the work arrays and the solve's
    /// buffer, and how `A` is read. The memory figures of `docs/performance.md`.
    pub fn bytes(&self) -> usize {
        let workspace = match &self.workspace {
            Workspace::Simplicial(work, permuted) => work.bytes() + permuted.bytes(),
            Workspace::Supernodal(work, loading) => work.bytes() + loading.bytes(),
        };
        let plans = (self.parallel.as_ref()).map_or(0, |p| p.factor.bytes() + p.solve.bytes());
        self.symbolic.bytes()
            + std::mem::size_of_val(&self.values[..])
            + workspace
            + std::mem::size_of_val(&self.solve_buffer[..])
            + plans
    }

    /// The method in use.
    pub fn method(&self) -> Method {
        match self.workspace {
            Workspace::Simplicial(..) => Method::Simplicial,
            Workspace::Supernodal(..) => Method::Supernodal,
        }
    }

    /// `L` as a CSC matrix, in the permuted numbering (`L Lᵀ = P A Pᵀ`).
    pub fn l(&self) -> CscMatrix {
        let rows = self
            .symbolic
            .row_idx() // every column's, built when kept per supernode
            .iter()
            .map(|&i| i as usize)
            .collect();
        let n = self.symbolic.n();
        CscMatrix::from_parts(
            n,
            n,
            self.symbolic.col_ptr().to_vec(),
            rows,
            self.values.clone(),
        )
        .expect("the symbolic pattern is a valid CSC structure")
    }

    /// The factor `L` of the simplicial method, as the substitutions of
    /// [`triangular_solve`] read it (columns of `P A Pᵀ`, diagonal first);
    /// `None` for the supernodal method, whose rows are kept per
    /// supernode.
    pub fn simplicial_factor(&self) -> Option<FactorView<'_>> {
        let Workspace::Simplicial(..) = self.workspace else {
            return None;
        };
        let std::borrow::Cow::Borrowed(row_idx) = self.symbolic.row_idx() else {
            return None;
        };
        Some(FactorView {
            col_ptr: self.symbolic.col_ptr(),
            row_idx,
            values: &self.values,
        })
    }

    /// `b ← A⁻¹ b` for one vector.
    ///
    /// # Panics
    /// When `b.len() != n`, or after a failed refactorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let (columns, _) = b.as_chunks_mut::<1>();
        self.solve_block::<1, 1>(columns);
    }

    /// `b ← A⁻¹ b` for an n×3 block (x, y, z), in one sweep over `L` per
    /// triangle.
    ///
    /// # Panics
    /// When `b.len() != n`, or after a failed refactorization.
    pub fn solve_points_in_place(&mut self, b: &mut [[f64; 3]]) {
        self.solve_block::<3, 4>(b);
    }

    /// `x ← A⁻¹ b` for an n×3 block whose row `i` is `b_row(i)`: the same
    /// as writing `b` and [`SparseCholesky::solve_points_in_place`], but
    /// each row is made where the solve reads it (already permuted) and the
    /// solution goes straight to `x`, with no pass over a `b` of its own.
    ///
    /// # Panics
    /// When `x.len() != n`, or after a failed refactorization.
    pub fn solve_points_from(
        &mut self,
        b_row: impl Fn(usize) -> [f64; 3] + Sync,
        x: &mut [[f64; 3]],
    ) {
        self.check_ready(x.len());
        if self.parallel_plan().is_some() {
            self.solve_by_team::<3, 4>(&b_row, &SharedSlice::new(x));
            return;
        }
        self.fill_buffer::<3, 4>(b_row);
        self.sweep::<4>();
        self.drain_buffer::<3, 4>(x);
    }

    /// The solve's own buffer of n×3 blocks in the factor's order, and
    /// the permutation `P`: row `r` of the buffer is row `perm[r]` of a
    /// block, as `(x, y, z, 0)`. A caller that keeps its unknowns there
    /// from one solve to the next ([`SparseCholesky::solve_buffer_in_place`])
    /// saves the permuted copies into and out of it (the plain iteration
    /// does: `sim::methods::factor_order`). The buffer holds whatever the
    /// last solve left.
    ///
    /// # Panics
    /// After a failed refactorization.
    pub fn buffer_in_factor_order(&mut self) -> (&Permutation, &mut [[f64; 4]]) {
        let n = self.symbolic.n();
        self.check_ready(n);
        let (buffer, _) = self.solve_buffer[..4 * n].as_chunks_mut::<4>();
        (self.symbolic.permutation(), buffer)
    }

    /// The rows of the factor (the buffer's rows) that thread `thread` of
    /// the team owns in its solves ([`TeamSolve::owned_rows`]); `None`
    /// without a team (one thread, or the simplicial method).
    pub fn rows_of_thread(&self, thread: usize) -> Option<&[std::ops::Range<usize>]> {
        self.parallel_plan().map(|plan| plan.owned_rows(thread))
    }

    /// The solve of the buffer of [`SparseCholesky::buffer_in_factor_order`]
    /// by a team, with the pool that runs it and the permutation, for a
    /// caller that shares its own work among the same threads and keeps
    /// each thread on the rows it owns (the plain iteration,
    /// `sim::methods::factor_order`); `None` with one thread or the
    /// simplicial method.
    ///
    /// # Panics
    /// After a failed refactorization.
    pub fn team_solve(&mut self) -> Option<(TeamSolve<'_, 4>, &Threads, &Permutation)> {
        let n = self.symbolic.n();
        self.check_ready(n);
        let Some(Parallel {
            threads,
            solve: plan,
            ..
        }) = &mut self.parallel
        else {
            return None;
        };
        let (buffer, _) = self.solve_buffer[..4 * n].as_chunks_mut::<4>();
        let solve = TeamSolve::new(&self.symbolic, &self.values, plan, buffer);
        Some((solve, threads, self.symbolic.permutation()))
    }

    /// `x ← L⁻ᵀ L⁻¹ x` for the block `x` in the buffer of
    /// [`SparseCholesky::buffer_in_factor_order`]: the solve with
    /// `P A Pᵀ`, the permuted matrix, with no copy into or out of it. The
    /// padding column (the fourth) stays 0 when it is 0.
    ///
    /// # Panics
    /// After a failed refactorization.
    pub fn solve_buffer_in_place(&mut self) {
        if let Some((solve, threads, _)) = self.team_solve() {
            threads.run(&|team: &Team| solve.sweep(team));
            return;
        }
        self.check_ready(self.symbolic.n());
        self.sweep::<4>();
    }

    /// `b ← Pᵀ L⁻ᵀ L⁻¹ P b` for a block of `W` columns, computed in a
    /// buffer whose rows are padded to `LANES ≥ W` values.
    fn solve_block<const W: usize, const LANES: usize>(&mut self, b: &mut [[f64; W]]) {
        self.check_ready(b.len());
        if self.parallel_plan().is_some() {
            let b = SharedSlice::new(b);
            // SAFETY: each thread reads the rows of `b` it writes back, and
            // no other (`solve_by_team`).
            let b_row = |i: usize| unsafe { b.get(i) };
            self.solve_by_team::<W, LANES>(&b_row, &b);
            return;
        }
        self.fill_buffer::<W, LANES>(|i| b[i]);
        self.sweep::<LANES>();
        self.drain_buffer::<W, LANES>(b);
    }

    /// The supernodal plan for the threads, if any.
    fn parallel_plan(&self) -> Option<&ParallelSolve> {
        self.parallel.as_ref().map(|p| &p.solve)
    }

    /// The whole solve in one run of the team: each thread writes `P b`
    /// into the rows of the buffer it owns, sweeps, and puts its rows of
    /// the solution into `x` (`x[perm[r]]` for its rows `r`: each row of
    /// `b` and of `x` is read and written by one thread).
    ///
    /// # Panics
    /// Without a team plan.
    fn solve_by_team<const W: usize, const LANES: usize>(
        &mut self,
        b_row: &(dyn Fn(usize) -> [f64; W] + Sync),
        x: &SharedSlice<[f64; W]>,
    ) {
        let n = self.symbolic.n();
        let Some(Parallel {
            threads,
            solve: plan,
            ..
        }) = &mut self.parallel
        else {
            unreachable!("solve_by_team runs with a team plan");
        };
        let (buffer, _) = self.solve_buffer[..LANES * n].as_chunks_mut::<LANES>();
        let perm = self.symbolic.permutation().perm();
        let solve = TeamSolve::new(&self.symbolic, &self.values, plan, buffer);
        threads.run(&|team: &Team| {
            let (rows, owned) = (solve.rows(), solve.owned_rows(team.index()));
            for r in owned.iter().flat_map(|range| range.clone()) {
                let mut row = [0.0; LANES];
                row[..W].copy_from_slice(&b_row(perm[r]));
                // SAFETY: row `r` of the buffer is this thread's.
                unsafe { rows.set(r, row) };
            }
            solve.sweep(team);
            for r in owned.iter().flat_map(|range| range.clone()) {
                // SAFETY: row `r` of the buffer is this thread's, and so is
                // row `perm[r]` of `x` (`perm` is one-to-one).
                unsafe {
                    let row = rows.get(r);
                    x.set(perm[r], std::array::from_fn(|c| row[c]));
                }
            }
        });
    }

    /// Panics unless the values are a factor and `rows` is its order.
    fn check_ready(&self, rows: usize) {
        assert!(
            self.factored,
            "solve with a factorization whose last refactor failed"
        );
        let n = self.symbolic.n();
        assert_eq!(rows, n, "right-hand side has {rows} rows, the matrix {n}");
    }

    /// The buffer's row `i` ← `b_row(perm[i])`, padded with zeros: `P b`.
    fn fill_buffer<const W: usize, const LANES: usize>(
        &mut self,
        b_row: impl Fn(usize) -> [f64; W],
    ) {
        let n = self.symbolic.n();
        let (buffer, _) = self.solve_buffer[..LANES * n].as_chunks_mut::<LANES>();
        let perm = self.symbolic.permutation().perm();
        for (row, &old) in buffer.iter_mut().zip(perm) {
            row[..W].copy_from_slice(&b_row(old));
            row[W..].fill(0.0);
        }
    }

    /// `L⁻ᵀ L⁻¹` applied to the buffer, column by column or supernode by
    /// supernode.
    fn sweep<const LANES: usize>(&mut self) {
        let n = self.symbolic.n();
        let (buffer, _) = self.solve_buffer[..LANES * n].as_chunks_mut::<LANES>();
        match self.workspace {
            Workspace::Simplicial(..) => {
                let l = FactorView {
                    col_ptr: self.symbolic.col_ptr(),
                    row_idx: &self.symbolic.row_idx(), // per column: borrowed
                    values: &self.values,
                };
                triangular_solve::solve_in_place(l, buffer)
            }
            Workspace::Supernodal(..) => {
                supernodal_solve::solve_in_place(&self.symbolic, &self.values, buffer)
            }
        }
    }

    /// `x[perm[i]]` ← the buffer's row `i`: `Pᵀ …`.
    fn drain_buffer<const W: usize, const LANES: usize>(&self, x: &mut [[f64; W]]) {
        let n = self.symbolic.n();
        let (buffer, _) = self.solve_buffer[..LANES * n].as_chunks::<LANES>();
        let perm = self.symbolic.permutation().perm();
        for (row, &old) in buffer.iter().zip(perm) {
            x[old].copy_from_slice(&row[..W]);
        }
    }

    fn not_positive_definite(&self, (column, pivot): FailedPivot) -> LinalgError {
        LinalgError::NotPositiveDefinite {
            column: self.symbolic.permutation().perm()[column],
            pivot,
        }
    }
}

impl Parallel {
    /// A pool of `threads` threads and the supernodal method's plans for as
    /// many as the pool has; `None` for one thread or the simplicial method.
    fn new(symbolic: &SymbolicCholesky, method: Method, threads: usize) -> Option<Self> {
        if threads <= 1 || method == Method::Simplicial {
            return None; // the textbook's method runs on one thread
        }
        let threads = Threads::new(threads);
        let count = threads.count();
        if count == 1 {
            return None; // no thread could be made
        }
        Some(Parallel {
            threads,
            factor: ParallelFactor::new(symbolic, count),
            solve: ParallelSolve::new(symbolic, count),
        })
    }
}
