//! One quantity computed again from the student's own inputs, by the
//! handout's line or by a mistake's (`masssprings::sim::mistakes`, the
//! same functions the gallery's pictures run):
//!
//! ```text
//! A     incidence(mistake, n, the student's springs)       r    step_rest_lengths(mistake, r, U_cur)
//! M     masses(mistake, m, springs, r)                     C    pins(mistake, our pins)
//! Q     q(mistake, k, A, M, Δt, w, C)                      y    inertial_term(mistake, M, f_ext, U_prev, U_cur)
//! d_k   local_step(mistake, springs, r, p_{k−1}, U_cur)    b_k  k, A, w: compute(mistake, d_k, y, w CᵀC V)
//! p_k   Q⁻¹ b_k (the handout's only)
//! ```
//!
//! and held to the student's numbers with the quantity's own tolerance,
//! as `--compare` holds ours.

use super::super::entries::{dense_difference, sparse_difference, to_sparse};
use super::super::sum::term_sizes;
use super::inputs::{rows_of, Inputs};
use crate::app::trace::quantities::{Check, Quantity};
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::CscMatrix;
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::mistakes::precomputation::{incidence, masses, pins, q};
use masssprings::sim::mistakes::step::{
    inertial_term, local_step, step_rest_lengths, RightHandSide,
};
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::precomputation::{mass_matrix, selection_matrix};
use masssprings::sim::{LinearAlgebra, Sparse, DELTA_T, PIN_WEIGHT};

/// A quantity's value.
#[derive(Debug, Clone)]
pub enum Value {
    Dense(DenseMatrix),
    Sparse(CscMatrix),
}

/// `quantity` from the student's inputs under `mistake` (`None`: the
/// handout's line), or `None` when it cannot be computed here (`P`,
/// `L`, the state, an input missing or of another shape).
pub fn recompute(quantity: &Quantity, mistake: Option<Mistake>, inputs: &Inputs) -> Option<Value> {
    let n = inputs.n();
    let springs = inputs.springs();
    let sparse = |a: CscMatrix| Some(Value::Sparse(a));
    match quantity.spec.symbol {
        "A" => sparse(incidence(mistake, n, &their_pairs(inputs)?)),
        "r" => {
            let r = column(&inputs.ours_dense("r.mtx")?);
            let u_cur = inputs.points("U_cur.mtx")?;
            Some(column_value(step_rest_lengths(
                mistake, &r, &springs, &u_cur,
            )))
        }
        "M" => {
            let m = inputs.ours_sparse("M.mtx")?.diagonal();
            let r = column(&inputs.ours_dense("r.mtx")?);
            sparse(mass_matrix::<Sparse>(&masses(mistake, &m, &springs, &r)))
        }
        "C" => sparse(selection_matrix::<Sparse>(
            n,
            &pins(mistake, &inputs.pins()),
        )),
        "Q" => {
            let a = incidence_for(mistake, inputs)?;
            let (m, c) = (inputs.sparse("M.mtx")?, inputs.sparse("C.mtx")?);
            sparse(q(mistake, inputs.k(), &a, &m, DELTA_T, PIN_WEIGHT, &c))
        }
        "y" => {
            let m = inputs.sparse("M.mtx")?;
            let (u_prev, u_cur) = (inputs.points("U_prev.mtx")?, inputs.points("U_cur.mtx")?);
            let gravity = vec![GRAVITY; n];
            points(inertial_term(
                mistake, &m, &gravity, &u_prev, &u_cur, DELTA_T,
            ))
        }
        "d" => local(quantity.iteration?, mistake, inputs),
        "b" => right_hand_side(quantity.iteration?, mistake, inputs),
        "p" if mistake.is_none() => solve(quantity.iteration?, inputs),
        _ => None,
    }
}

/// The student's value of `quantity`, in the shape of ours (their `A`
/// as they wrote it).
pub fn theirs(quantity: &Quantity, inputs: &Inputs) -> Option<Value> {
    let name = quantity.file_name();
    match quantity.spec.symbol {
        "A" => Some(Value::Sparse(to_sparse(&inputs.their_file(&name)?).ok()?)),
        "M" | "C" | "Q" => {
            let ours = inputs.ours_sparse(&name)?;
            let shape = (ours.nrows(), ours.ncols());
            Some(Value::Sparse(inputs.their_sparse(&name, shape)?))
        }
        _ => Some(Value::Dense(inputs.their_dense(&name)?)),
    }
}

/// Whether `value` reproduces the student's `theirs` within the
/// quantity's tolerance (`A` and `C` exactly; `b` to the size of its
/// terms, as `--compare` holds it).
pub fn reproduces(quantity: &Quantity, value: &Value, theirs: &Value, inputs: &Inputs) -> bool {
    let tolerance = match quantity.spec.check {
        Check::Entries { tolerance } | Check::Sum { tolerance } | Check::Factor { tolerance } => {
            tolerance
        }
        Check::Incidence | Check::Ordering => 0.0,
    };
    difference(quantity, value, theirs, inputs).is_some_and(|d| d <= tolerance)
}

/// The largest relative difference between `value` and the student's
/// `theirs`, as `--compare` measures it (`None` for another shape; a NaN
/// is infinite).
pub fn difference(
    quantity: &Quantity,
    value: &Value,
    theirs: &Value,
    inputs: &Inputs,
) -> Option<f64> {
    let largest = match (value, theirs) {
        (Value::Dense(a), Value::Dense(b)) if same_shape(a, b) => {
            let reference = b_terms(quantity, inputs);
            dense_difference(a, b, reference.as_ref(), &[])
        }
        (Value::Sparse(a), Value::Sparse(b))
            if (a.nrows(), a.ncols()) == (b.nrows(), b.ncols()) =>
        {
            sparse_difference(a, b, &[])
        }
        _ => return None,
    };
    let relative = largest.overall().map_or(0.0, |d| d.relative);
    Some(if relative.is_nan() {
        f64::INFINITY
    } else {
        relative
    })
}

fn same_shape(a: &DenseMatrix, b: &DenseMatrix) -> bool {
    (a.nrows(), a.ncols()) == (b.nrows(), b.ncols())
}

/// The sizes of `b`'s terms that `--compare` holds `b` to.
fn b_terms(quantity: &Quantity, inputs: &Inputs) -> Option<DenseMatrix> {
    let k = quantity.iteration.filter(|_| quantity.spec.symbol == "b")?;
    let ours = |name: String| inputs.our_file(&name);
    let (b, d, y) = (
        ours(format!("b_{k}.mtx"))?,
        ours(format!("d_{k}.mtx"))?,
        ours("y.mtx".into())?,
    );
    term_sizes(&b, &d, &y, inputs.context).ok()
}

/// The springs of the student's `A`, whatever its shape: the two vertices
/// of each row (of each column, when it is `n × m`), `+1` first; `None`
/// unless they are our springs, one to one.
fn their_pairs(inputs: &Inputs) -> Option<Vec<[usize; 2]>> {
    let a = to_sparse(&inputs.their_file("A.mtx")?).ok()?;
    let (m, n) = (inputs.context.our_springs.len(), inputs.n());
    let rows = match (a.nrows(), a.ncols()) {
        shape if shape == (m, n) => a.transpose(), // a column per spring
        shape if shape == (n, m) => a,
        _ => return None, // not our springs, whatever they are
    };
    let mut pairs = Vec::with_capacity(rows.ncols());
    for e in 0..rows.ncols() {
        let (vertices, values) = rows.column(e);
        let [(i, vi), (j, _)] = [0, 1].map(|k| (vertices.get(k).copied(), values.get(k).copied()));
        let (Some(i), Some(j), 2) = (i, j, vertices.len()) else {
            return None;
        };
        pairs.push(if vi >= Some(0.0) { [i, j] } else { [j, i] });
    }
    let mut ours: Vec<[usize; 2]> = inputs
        .context
        .our_springs
        .iter()
        .filter_map(|row| match row {
            super::super::springs::Row::Spring([i, j]) => Some([*i.min(j), *i.max(j)]),
            _ => None,
        })
        .collect();
    let mut keys: Vec<[usize; 2]> = pairs.iter().map(|&[i, j]| [i.min(j), i.max(j)]).collect();
    ours.sort_unstable();
    keys.sort_unstable();
    (ours == keys).then_some(pairs)
}

/// The `A` that `Q` and `b` are made from under `mistake`: the student's
/// `n × m` one for `a-transposed`, else `m × n`.
fn incidence_for(mistake: Option<Mistake>, inputs: &Inputs) -> Option<CscMatrix> {
    let a = inputs.incidence()?;
    match mistake {
        Some(Mistake::ATransposed) => Some(a.transpose()),
        _ => Some(a),
    }
}

/// `d_k` from the student's `p_{k−1}` (`U_cur` for the first).
fn local(k: usize, mistake: Option<Mistake>, inputs: &Inputs) -> Option<Value> {
    let springs = inputs.springs();
    let r = column(&inputs.dense("r.mtx")?);
    let u_cur = inputs.points("U_cur.mtx")?;
    let p = match k {
        1 => u_cur.clone(),
        _ => inputs.points(&format!("p_{}.mtx", k - 1))?,
    };
    let r = step_rest_lengths(mistake, &r, &springs, &u_cur);
    let mut d = vec![[0.0; 3]; springs.len()];
    local_step(mistake, &springs, &r, &p, &u_cur, &mut d);
    points(d)
}

/// `b_k` from the student's `d_k` and `y`.
fn right_hand_side(k: usize, mistake: Option<Mistake>, inputs: &Inputs) -> Option<Value> {
    let a = incidence_for(mistake, inputs)?;
    let d = rows_of(&inputs.dense(&format!("d_{k}.mtx"))?);
    let (y, pins) = (inputs.points("y.mtx")?, inputs.pin_term()?);
    let rhs = RightHandSide {
        k: inputs.k(),
        A: &a,
        w: PIN_WEIGHT,
    };
    let mut b = vec![[0.0; 3]; y.len()];
    (d.len() == inputs.springs().len()).then_some(())?;
    rhs.compute(mistake, &d, &y, &pins, &mut b);
    points(b)
}

/// `p_k = Q⁻¹ b_k` from the student's `b_k`, with their `Q` when it has
/// our pattern (else ours).
fn solve(k: usize, inputs: &Inputs) -> Option<Value> {
    let ours = inputs.ours_sparse("Q.mtx")?;
    let q = inputs
        .their_sparse("Q.mtx", (ours.nrows(), ours.ncols()))
        .filter(|theirs| theirs.same_pattern(&ours))
        .unwrap_or(ours);
    let mut factor = Sparse::factor(&q, Default::default()).ok()?;
    let mut p = inputs.points(&format!("b_{k}.mtx"))?;
    Sparse::solve_points(&mut factor, &mut p);
    points(p)
}

fn column(a: &DenseMatrix) -> Vec<f64> {
    a.as_slice().to_vec()
}

fn column_value(values: Vec<f64>) -> Value {
    let rows = values.len();
    Value::Dense(DenseMatrix::from_row_major(rows, 1, values).expect("a column"))
}

fn points(rows: Vec<[f64; 3]>) -> Option<Value> {
    Some(Value::Dense(DenseMatrix::from_rows(&rows).ok()?))
}
