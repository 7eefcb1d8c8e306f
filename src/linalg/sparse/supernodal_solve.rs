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
struct SupernodalView<'a> {
    symbolic: &'a SymbolicCholesky,
    col_ptr: &'a [usize],
    values: &'a [f64],
}

/// Columns swept together.
const PANEL: usize = 4;

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
    let supernodes = l.symbolic.supernodes();
    for s in 0..supernodes.len() {
        let columns = supernodes.columns(s);
        let node = Supernode {
            first: columns.start,
            rows: l.symbolic.supernode_rows(s),
        };
        let mut offset = 0;
        while offset < columns.len() {
            let width = (columns.len() - offset).min(PANEL);
            match width {
                1 => forward_panel::<W, 1, FUSED>(&l, node, offset, x),
                2 => forward_panel::<W, 2, FUSED>(&l, node, offset, x),
                3 => forward_panel::<W, 3, FUSED>(&l, node, offset, x),
                _ => forward_panel::<W, 4, FUSED>(&l, node, offset, x),
            }
            offset += width;
        }
    }
}

/// Forward sweep over one panel of `P` columns.
#[inline(always)]
fn forward_panel<const W: usize, const P: usize, const FUSED: bool>(
    l: &SupernodalView,
    node: Supernode,
    offset: usize,
    x: &mut [[f64; W]],
) {
    let panel = Panel::<P>::new(l, node, offset);
    let values = l.values;
    // the panel's own triangle, column by column
    let mut x_panel = [[0.0; W]; P];
    for c in 0..P {
        let diagonal = values[panel.base[c] + offset + c];
        let xc = x[panel.first + c].map(|v| v / diagonal);
        x[panel.first + c] = xc;
        x_panel[c] = xc;
        for r in c + 1..P {
            let l_rc = values[panel.base[c] + offset + r];
            let xr = &mut x[panel.first + r];
            for lane in 0..W {
                xr[lane] -= l_rc * xc[lane];
            }
        }
    }
    // every row below the panel: x_i ← x_i − Σ_c L_ic x_c
    let (rows, columns) = panel.below(values);
    for (q, &row) in rows.iter().enumerate() {
        let mut update = [0.0; W];
        for c in 0..P {
            let l_ic = columns[c][q];
            for lane in 0..W {
                update[lane] = multiply_add::<FUSED>(l_ic, x_panel[c][lane], update[lane]);
            }
        }
        let xi = &mut x[row as usize];
        for lane in 0..W {
            xi[lane] -= update[lane];
        }
    }
}

/// `Lᵀ x = y`: supernodes in reverse order, panels in reverse order.
#[inline(always)]
fn backward<const W: usize, const FUSED: bool>(l: SupernodalView, x: &mut [[f64; W]]) {
    let supernodes = l.symbolic.supernodes();
    for s in (0..supernodes.len()).rev() {
        let columns = supernodes.columns(s);
        let node = Supernode {
            first: columns.start,
            rows: l.symbolic.supernode_rows(s),
        };
        // the same panels as the forward sweep, last one first
        let mut offset = (columns.len() - 1) / PANEL * PANEL;
        loop {
            // partial sums per column: four for a single column, two otherwise
            match (columns.len() - offset).min(PANEL) {
                1 => backward_panel::<W, 1, 4, FUSED>(&l, node, offset, x),
                2 => backward_panel::<W, 2, 2, FUSED>(&l, node, offset, x),
                3 => backward_panel::<W, 3, 2, FUSED>(&l, node, offset, x),
                _ => backward_panel::<W, 4, 2, FUSED>(&l, node, offset, x),
            }
            if offset == 0 {
                break;
            }
            offset -= PANEL;
        }
    }
}

/// Back sweep over one panel of `P` columns, each column's sum over the
/// rows below split into `S` partial sums (rows `q ≡ k mod S` go to sum
/// `k`), added together at the end.
#[inline(always)]
fn backward_panel<const W: usize, const P: usize, const S: usize, const FUSED: bool>(
    l: &SupernodalView,
    node: Supernode,
    offset: usize,
    x: &mut [[f64; W]],
) {
    let panel = Panel::<P>::new(l, node, offset);
    let values = l.values;
    // s_c = Σ_i L_ic x_i over every row below the panel, each x_i read once
    let mut partial = [[[0.0; W]; P]; S];
    let (rows, columns) = panel.below(values);
    let mut q = 0;
    while q + S <= rows.len() {
        for (k, sums) in partial.iter_mut().enumerate() {
            add_row::<W, P, FUSED>(sums, &columns, q + k, x[rows[q + k] as usize]);
        }
        q += S;
    }
    for (k, sums) in partial.iter_mut().enumerate().take(rows.len() - q) {
        add_row::<W, P, FUSED>(sums, &columns, q + k, x[rows[q + k] as usize]);
    }
    let sums: [[f64; W]; P] = std::array::from_fn(|c| {
        std::array::from_fn(|lane| partial.iter().map(|sums| sums[c][lane]).sum())
    });
    // the panel's own triangle, last column first
    for c in (0..P).rev() {
        let mut sum = sums[c];
        for r in c + 1..P {
            let l_rc = values[panel.base[c] + offset + r];
            let xr = x[panel.first + r];
            for lane in 0..W {
                sum[lane] += l_rc * xr[lane];
            }
        }
        let diagonal = values[panel.base[c] + offset + c];
        let xc = &mut x[panel.first + c];
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
