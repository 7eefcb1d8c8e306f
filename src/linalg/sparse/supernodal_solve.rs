//! Forward and back substitution, a few columns of a supernode at a time.
//!
//! The same two sweeps as [`triangular_solve`](super::triangular_solve),
//! but the columns of a supernode share one list of rows, so they can be
//! swept together. The columns are taken in *panels* of up to four. For a
//! panel `c₀ … c₃` and every row `i` below it:
//!
//! ```text
//! forward (L y = b):   x_i ← x_i − (L_i,c₀ x_c₀ + … + L_i,c₃ x_c₃)     one update of x_i
//! back (Lᵀ x = y):     s_c ← s_c + L_i,c x_i  for c = c₀ … c₃           one read of x_i
//! ```
//!
//! Column by column, each of those rows would be read and written (or
//! gathered) once per column, and its row index loaded once per entry; a
//! panel does both once per row. Inside the panel (its small dense
//! triangle) the sweep goes column by column as usual.
//!
//! The back sweep splits each column's sum `s_c` into two partial sums
//! (four for a single column), over alternate rows, added at the end: a
//! multiply-add takes four cycles to give its result, and one running sum
//! would make every row wait for the one before it. While `L` fits in cache
//! that wait is what bounds the sweep: on the skirt this made the solve 7%
//! faster (0.50 to 0.47 ms). (Dividing by the diagonal as a multiplication
//! by a stored `1 / L_jj` gained 7% more, but it rounds differently from
//! the division; the skirt's buckling amplifies that about 25× per step,
//! which failed the trajectory check at step 10 that the one-step checks
//! of `tests/sim/fidelity.rs` have since replaced. The division stays until it
//! is measured again.)
//!
//! As there, the right-hand side is a block of `W` columns stored row by
//! row (padded to four lanes for x, y, z), and the loops are compiled a
//! second time with AVX2 and FMA, chosen at run time.
//!
//! Cost `2 · nnz(L) · W` multiply-adds, as column by column; fewer loads and
//! stores. Source: Davis 2006, §4.6 and §8.1; the supernodal triangular
//! solves of CHOLMOD (Chen, Davis, Hager, Rajamanickam, ACM TOMS 35(3),
//! 2008), here without a dense work block.

use super::symbolic::SymbolicCholesky;

/// The factor as the supernodal sweeps read it: the column pointers of its
/// values, each supernode's rows (kept once per supernode), the values.
#[derive(Clone, Copy)]
pub(super) struct SupernodalView<'a> {
    pub(super) symbolic: &'a SymbolicCholesky,
    pub(super) col_ptr: &'a [usize],
    pub(super) values: &'a [f64],
}

/// How a sweep reaches the rows of `x`: a slice (one thread), or the rows
/// a team shares ([`supernodal_solve_parallel`](super::supernodal_solve_parallel)).
pub(super) trait Unknowns<const W: usize> {
    /// Row `i`.
    fn row(&self, i: usize) -> [f64; W];
    /// Row `i`, to change.
    fn row_mut(&mut self, i: usize) -> &mut [f64; W];
}

impl<const W: usize> Unknowns<W> for [[f64; W]] {
    #[inline(always)]
    fn row(&self, i: usize) -> [f64; W] {
        self[i]
    }

    #[inline(always)]
    fn row_mut(&mut self, i: usize) -> &mut [f64; W] {
        &mut self[i]
    }
}

/// Columns swept together.
pub(super) const PANEL: usize = 4;

/// Solves `L Lᵀ x = b` in place, supernode by supernode, for the factor
/// analysed in `symbolic` with values `values`.
pub fn solve_in_place<const W: usize>(
    symbolic: &SymbolicCholesky,
    values: &[f64],
    x: &mut [[f64; W]],
) {
    let l = SupernodalView {
        symbolic,
        col_ptr: symbolic.col_ptr(),
        values,
    };
    #[cfg(target_arch = "x86_64")]
    if crate::linalg::kernels::avx2_fma() {
        // SAFETY: the CPU supports the features the function is compiled for.
        unsafe { solve_in_place_avx2(l, x) };
        return;
    }
    forward::<W, false>(l, x);
    backward::<W, false>(l, x);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn solve_in_place_avx2<const W: usize>(l: SupernodalView, x: &mut [[f64; W]]) {
    forward::<W, true>(l, x);
    backward::<W, true>(l, x);
}

/// A supernode as the sweeps need it: its first column and its rows.
#[derive(Clone, Copy)]
struct Supernode<'a> {
    first: usize,
    rows: &'a [u32],
}

/// A panel: up to four consecutive columns of one supernode, the rows they
/// share, and where each column's entry for row position `p` is stored.
struct Panel<'a, const P: usize> {
    /// The first column (its unknown is `x[first]`).
    first: usize,
    /// The supernode's rows by position (diagonal block first).
    rows: &'a [u32],
    /// Position of the panel's first column in the supernode.
    offset: usize,
    /// `values[base[c] + p]` is the entry of column `first + c` at row
    /// position `p` (valid for `p ≥ offset + c`).
    base: [usize; P],
}

impl<'a, const P: usize> Panel<'a, P> {
    fn new(l: &SupernodalView<'a>, node: Supernode<'a>, offset: usize) -> Self {
        let col_ptr = l.col_ptr;
        let rows = node.rows;
        let first = node.first + offset;
        Panel {
            first,
            rows,
            offset,
            base: std::array::from_fn(|c| col_ptr[first + c] - (offset + c)),
        }
    }

    /// The rows below the panel, and each panel column's entries for them
    /// (all of one length, so the loops over them need no bounds checks).
    #[inline(always)]
    fn below<'v>(&self, values: &'v [f64]) -> (&'a [u32], [&'v [f64]; P]) {
        let start = self.offset + P;
        let rows = &self.rows[start..];
        let columns = std::array::from_fn(|c| {
            let base = self.base[c];
            &values[base + start..base + self.rows.len()]
        });
        (rows, columns)
    }
}

/// `a · b + c`, fused into one rounding in the AVX2 + FMA build.
#[inline(always)]
fn multiply_add<const FUSED: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FUSED {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// `L y = b`: supernodes in order, panels in order.
#[inline(always)]
fn forward<const W: usize, const FUSED: bool>(l: SupernodalView, x: &mut [[f64; W]]) {
    for s in 0..l.symbolic.supernodes().len() {
        forward_supernode::<W, FUSED, _>(&l, s, x, 0);
    }
}

/// The forward sweep over supernode `s`, panel by panel, leaving out the
/// updates of its last `later` rows: those [`forward_supernode_tail`]
/// makes later (a thread's subtree leaves its rows in the top to the
/// thread that sweeps the top, `supernodal_solve_parallel.rs`).
#[inline(always)]
pub(super) fn forward_supernode<const W: usize, const FUSED: bool, X: Unknowns<W> + ?Sized>(
    l: &SupernodalView,
    s: usize,
    x: &mut X,
    later: usize,
) {
    for (node, offset, width) in Panels::of(l, s) {
        match width {
            1 => forward_panel::<W, 1, FUSED, X>(l, node, offset, x, later),
            2 => forward_panel::<W, 2, FUSED, X>(l, node, offset, x, later),
            3 => forward_panel::<W, 3, FUSED, X>(l, node, offset, x, later),
            _ => forward_panel::<W, 4, FUSED, X>(l, node, offset, x, later),
        }
    }
}

/// The updates [`forward_supernode`] left out, of the last `tail` rows of
/// supernode `s`, from its columns' values in `x` (final: the forward
/// sweep changes a column's row only before its panel), panel by panel:
/// the same sums, subtracted in the same order.
#[inline(always)]
pub(super) fn forward_supernode_tail<const W: usize, const FUSED: bool, X: Unknowns<W> + ?Sized>(
    l: &SupernodalView,
    s: usize,
    x: &mut X,
    tail: usize,
) {
    for (node, offset, width) in Panels::of(l, s) {
        match width {
            1 => forward_panel_tail::<W, 1, FUSED, X>(l, node, offset, x, tail),
            2 => forward_panel_tail::<W, 2, FUSED, X>(l, node, offset, x, tail),
            3 => forward_panel_tail::<W, 3, FUSED, X>(l, node, offset, x, tail),
            _ => forward_panel_tail::<W, 4, FUSED, X>(l, node, offset, x, tail),
        }
    }
}

/// The panels of a supernode, in order: `(supernode, offset, width)`.
/// (An iterator, not a function taking a closure: a closure need not be
/// inlined into the AVX2 sweeps, and compiled apart from them it would
/// make every fused multiply-add a call.)
struct Panels<'a> {
    node: Supernode<'a>,
    offset: usize,
    width: usize,
}

impl<'a> Panels<'a> {
    #[inline(always)]
    fn of(l: &SupernodalView<'a>, s: usize) -> Self {
        let columns = l.symbolic.supernodes().columns(s);
        Panels {
            node: Supernode {
                first: columns.start,
                rows: l.symbolic.supernode_rows(s),
            },
            offset: 0,
            width: columns.len(),
        }
    }
}

impl<'a> Iterator for Panels<'a> {
    type Item = (Supernode<'a>, usize, usize);

    #[inline(always)]
    fn next(&mut self) -> Option<Self::Item> {
        if self.offset >= self.width {
            return None;
        }
        let (offset, width) = (self.offset, (self.width - self.offset).min(PANEL));
        self.offset += width;
        Some((self.node, offset, width))
    }
}

/// Forward sweep over one panel of `P` columns, but for the updates of the
/// last `later` rows.
#[inline(always)]
fn forward_panel<const W: usize, const P: usize, const FUSED: bool, X: Unknowns<W> + ?Sized>(
    l: &SupernodalView,
    node: Supernode,
    offset: usize,
    x: &mut X,
    later: usize,
) {
    let panel = Panel::<P>::new(l, node, offset);
    let values = l.values;
    // the panel's own triangle, column by column
    let mut x_panel = [[0.0; W]; P];
    for c in 0..P {
        let diagonal = values[panel.base[c] + offset + c];
        let xc = x.row(panel.first + c).map(|v| v / diagonal);
        *x.row_mut(panel.first + c) = xc;
        x_panel[c] = xc;
        for r in c + 1..P {
            let l_rc = values[panel.base[c] + offset + r];
            let xr = x.row_mut(panel.first + r);
            for lane in 0..W {
                xr[lane] -= l_rc * xc[lane];
            }
        }
    }
    // every row below the panel: x_i ← x_i − Σ_c L_ic x_c
    let (rows, columns) = panel.below(values);
    subtract_updates::<W, P, FUSED, X>(&columns, rows, 0..rows.len() - later, &x_panel, x);
}

/// The updates of the last `tail` rows below one panel, from the panel's
/// values in `x`.
#[inline(always)]
fn forward_panel_tail<
    const W: usize,
    const P: usize,
    const FUSED: bool,
    X: Unknowns<W> + ?Sized,
>(
    l: &SupernodalView,
    node: Supernode,
    offset: usize,
    x: &mut X,
    tail: usize,
) {
    let panel = Panel::<P>::new(l, node, offset);
    let x_panel: [[f64; W]; P] = std::array::from_fn(|c| x.row(panel.first + c));
    let (rows, columns) = panel.below(l.values);
    let from = rows.len() - tail;
    subtract_updates::<W, P, FUSED, X>(&columns, rows, from..rows.len(), &x_panel, x);
}

/// `x_i ← x_i − Σ_c L_ic x_c` for the rows below a panel at positions
/// `positions`, in order.
#[inline(always)]
fn subtract_updates<const W: usize, const P: usize, const FUSED: bool, X: Unknowns<W> + ?Sized>(
    columns: &[&[f64]; P],
    rows: &[u32],
    positions: std::ops::Range<usize>,
    x_panel: &[[f64; W]; P],
    x: &mut X,
) {
    for q in positions {
        let update = panel_update::<W, P, FUSED>(columns, q, x_panel);
        let xi = x.row_mut(rows[q] as usize);
        for lane in 0..W {
            xi[lane] -= update[lane];
        }
    }
}

/// `Σ_c L_ic x_c` over the panel's columns, for the row at position `q`
/// below the panel.
#[inline(always)]
fn panel_update<const W: usize, const P: usize, const FUSED: bool>(
    columns: &[&[f64]; P],
    q: usize,
    x_panel: &[[f64; W]; P],
) -> [f64; W] {
    let mut update = [0.0; W];
    for c in 0..P {
        let l_ic = columns[c][q];
        for lane in 0..W {
            update[lane] = multiply_add::<FUSED>(l_ic, x_panel[c][lane], update[lane]);
        }
    }
    update
}

/// `Lᵀ x = y`: supernodes in reverse order, panels in reverse order.
#[inline(always)]
fn backward<const W: usize, const FUSED: bool>(l: SupernodalView, x: &mut [[f64; W]]) {
    for s in (0..l.symbolic.supernodes().len()).rev() {
        backward_supernode::<W, FUSED, _>(&l, s, x);
    }
}

/// The back sweep over supernode `s`, its panels last one first.
#[inline(always)]
pub(super) fn backward_supernode<const W: usize, const FUSED: bool, X: Unknowns<W> + ?Sized>(
    l: &SupernodalView,
    s: usize,
    x: &mut X,
) {
    let columns = l.symbolic.supernodes().columns(s);
    let node = Supernode {
        first: columns.start,
        rows: l.symbolic.supernode_rows(s),
    };
    // the same panels as the forward sweep, last one first
    let mut offset = (columns.len() - 1) / PANEL * PANEL;
    loop {
        // partial sums per column: four for a single column, two otherwise
        match (columns.len() - offset).min(PANEL) {
            1 => backward_panel::<W, 1, 4, FUSED, X>(l, node, offset, x),
            2 => backward_panel::<W, 2, 2, FUSED, X>(l, node, offset, x),
            3 => backward_panel::<W, 3, 2, FUSED, X>(l, node, offset, x),
            _ => backward_panel::<W, 4, 2, FUSED, X>(l, node, offset, x),
        }
        if offset == 0 {
            break;
        }
        offset -= PANEL;
    }
}

/// Back sweep over one panel of `P` columns, each column's sum over the
/// rows below split into `S` partial sums (rows `q ≡ k mod S` go to sum
/// `k`), added together at the end.
#[inline(always)]
fn backward_panel<
    const W: usize,
    const P: usize,
    const S: usize,
    const FUSED: bool,
    X: Unknowns<W> + ?Sized,
>(
    l: &SupernodalView,
    node: Supernode,
    offset: usize,
    x: &mut X,
) {
    let panel = Panel::<P>::new(l, node, offset);
    let values = l.values;
    // s_c = Σ_i L_ic x_i over every row below the panel, each x_i read once
    let mut partial = [[[0.0; W]; P]; S];
    let (rows, columns) = panel.below(values);
    let mut q = 0;
    while q + S <= rows.len() {
        for (k, sums) in partial.iter_mut().enumerate() {
            add_row::<W, P, FUSED>(sums, &columns, q + k, x.row(rows[q + k] as usize));
        }
        q += S;
    }
    for (k, sums) in partial.iter_mut().enumerate().take(rows.len() - q) {
        add_row::<W, P, FUSED>(sums, &columns, q + k, x.row(rows[q + k] as usize));
    }
    let sums: [[f64; W]; P] = std::array::from_fn(|c| {
        std::array::from_fn(|lane| partial.iter().map(|sums| sums[c][lane]).sum())
    });
    // the panel's own triangle, last column first
    for c in (0..P).rev() {
        let mut sum = sums[c];
        for r in c + 1..P {
            let l_rc = values[panel.base[c] + offset + r];
            let xr = x.row(panel.first + r);
            for lane in 0..W {
                sum[lane] += l_rc * xr[lane];
            }
        }
        let diagonal = values[panel.base[c] + offset + c];
        let xc = x.row_mut(panel.first + c);
        *xc = std::array::from_fn(|lane| (xc[lane] - sum[lane]) / diagonal);
    }
}

/// `s_c ← s_c + L_ic x_i` for the panel's columns `c`, at row position `q`.
#[inline(always)]
fn add_row<const W: usize, const P: usize, const FUSED: bool>(
    sums: &mut [[f64; W]; P],
    columns: &[&[f64]; P],
    q: usize,
    xi: [f64; W],
) {
    for c in 0..P {
        let l_ic = columns[c][q];
        for lane in 0..W {
            sums[c][lane] = multiply_add::<FUSED>(l_ic, xi[lane], sums[c][lane]);
        }
    }
}
