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
//! Source: Davis 2006, ch. 4 and §8.1 (`cs_cholsol`).

use super::csc::{CscMatrix, Triangle};
use super::factor_loading::FactorLoading;
use super::permutation::Permutation;
use super::permute::PermutedTriangle;
use super::supernodal::{factor_supernodal, SupernodalWorkspace};
use super::supernodal_solve;
use super::symbolic::SymbolicCholesky;
use super::triangular_solve::{self, FactorView};
use super::up_looking::{factor_up_looking, FailedPivot, UpLookingWorkspace};
use crate::linalg::error::LinalgError;
use crate::linalg::huge_pages::advise_huge_pages;

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
        let workspace = match method {
            Method::Simplicial => Workspace::Simplicial(
                UpLookingWorkspace::new(n),
                PermutedTriangle::new(a, symbolic.permutation(), Triangle::Upper)?,
            ),
            Method::Supernodal => Workspace::Supernodal(
                SupernodalWorkspace::new(&symbolic),
                FactorLoading::new(a, &symbolic)?,
            ),
        };
        let mut cholesky = SparseCholesky {
            values: vec![0.0; symbolic.nnz_l()],
            symbolic,
            workspace,
            solve_buffer: vec![0.0; 4 * n],
            factored: false,
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
                factor_supernodal(&self.symbolic, a, loading, &mut self.values, work)
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

    /// Bytes held (array lengths, not capacities): the analysis, the
    /// values of `L`, the permuted `C`, the work arrays and the solve's
    /// buffer, and how `A` is read. The memory figures of `docs/performance.md`.
    pub fn bytes(&self) -> usize {
        let workspace = match &self.workspace {
            Workspace::Simplicial(work, permuted) => work.bytes() + permuted.bytes(),
            Workspace::Supernodal(work, loading) => work.bytes() + loading.bytes(),
        };
        self.symbolic.bytes()
            + std::mem::size_of_val(&self.values[..])
            + workspace
            + std::mem::size_of_val(&self.solve_buffer[..])
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
    pub fn solve_points_from(&mut self, b_row: impl Fn(usize) -> [f64; 3], x: &mut [[f64; 3]]) {
        self.check_ready(x.len());
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

    /// `x ← L⁻ᵀ L⁻¹ x` for the block `x` in the buffer of
    /// [`SparseCholesky::buffer_in_factor_order`]: the solve with
    /// `P A Pᵀ`, the permuted matrix, with no copy into or out of it. The
    /// padding column (the fourth) stays 0 when it is 0.
    ///
    /// # Panics
    /// After a failed refactorization.
    pub fn solve_buffer_in_place(&mut self) {
        self.check_ready(self.symbolic.n());
        self.sweep::<4>();
    }

    /// `b ← Pᵀ L⁻ᵀ L⁻¹ P b` for a block of `W` columns, computed in a
    /// buffer whose rows are padded to `LANES ≥ W` values.
    fn solve_block<const W: usize, const LANES: usize>(&mut self, b: &mut [[f64; W]]) {
        self.check_ready(b.len());
        self.fill_buffer::<W, LANES>(|i| b[i]);
        self.sweep::<LANES>();
        self.drain_buffer::<W, LANES>(b);
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
