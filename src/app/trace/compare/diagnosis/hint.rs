//! When no mistake of the gallery reproduces a student's quantity, the
//! nearest thing that can be proven of it: each hint is a claim that the
//! student's numbers satisfy within the quantity's tolerance, or it is not
//! made.
//!
//! ```text
//! a factor      yours = c · the handout's (from your inputs), c named: −1, 2, ½, k, Δt, 1/Δt², w, …
//! swapped       yours = the handout's with two of x, y, z swapped
//! its terms     yours = c₁ t₁ + c₂ t₂ + c₃ t₃, the handout's terms, with other coefficients:
//!                 Q = k AᵀA + M/Δt² + w CᵀC      y = 2 M U_cur/Δt² − M U_prev/Δt² + f_ext
//!                 b = k Aᵀd + y + w CᵀC V
//! transposed    your file is ours' shape transposed, and its transpose is the handout's
//! ```
//!
//! The coefficients are fitted by least squares ([`fit`](super::fit)), then
//! the fit is held to the student's numbers like any recomputed value.

use super::super::entries::to_sparse;
use super::fit::{add, flat_over, named, scale, scaled, snapped, solve};
use super::inputs::{rows_of, Inputs};
use super::recompute::{reproduces, Value};
use crate::app::trace::quantities::Quantity;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::matrix_market::MatrixMarket;
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::{LinearAlgebra, Sparse, DELTA_T, PIN_WEIGHT};

/// The hint for a quantity whose numbers no mistake reproduces.
pub fn hint(quantity: &Quantity, handout: &Value, theirs: &Value, inputs: &Inputs) -> String {
    let found = factor(quantity, handout, theirs, inputs)
        .or_else(|| swapped(quantity, handout, theirs, inputs))
        .or_else(|| terms(quantity, theirs, inputs));
    found.unwrap_or_else(|| {
        "it is not the handout's times a factor, nor with two columns swapped, nor its terms \
         with other coefficients"
            .into()
    })
}

/// For a file of another shape than ours: whether it is the handout's
/// transposed.
pub fn shape(quantity: &Quantity, handout: &Value, inputs: &Inputs) -> String {
    let name = quantity.file_name();
    let raw = inputs
        .their_file(&name)
        .and_then(|file| to_sparse(&file).ok());
    let transposed = raw.map(|a| Value::Sparse(a.transpose()));
    let handout_sparse = match handout {
        Value::Sparse(a) => Some(Value::Sparse(a.clone())),
        Value::Dense(a) => to_sparse(&MatrixMarket::Dense(a.clone()))
            .ok()
            .map(Value::Sparse),
    };
    match (transposed, handout_sparse) {
        (Some(t), Some(h)) if reproduces(quantity, &h, &t, inputs) => format!(
            "your {} is the handout's transposed (the handout's is {})",
            quantity.name(),
            quantity.spec.shape
        ),
        _ => format!("its shape is not the handout's, {}", quantity.spec.shape),
    }
}

/// For an `L` with `L Lᵀ ≠ P Q Pᵀ` (`Q` right): whether it is upper
/// triangular, a transposed factor.
pub fn triangle(inputs: &Inputs) -> String {
    let l = inputs
        .their_file("L.mtx")
        .and_then(|file| to_sparse(&file).ok());
    let upper = l.is_some_and(|l| {
        (0..l.ncols()).all(|j| l.column(j).0.iter().all(|&i| i <= j))
            && (0..l.ncols()).any(|j| l.column(j).0.iter().any(|&i| i < j))
    });
    match upper {
        true => "your L is upper triangular: the transpose of a factor (write the lower \
                 factor, Eigen's matrixL())"
            .into(),
        false => "L Lᵀ is not P Q Pᵀ: factor the Q you wrote, and write P and L of that one \
                  factorization"
            .into(),
    }
}

/// `yours = c · handout`, `c` named.
fn factor(quantity: &Quantity, handout: &Value, theirs: &Value, inputs: &Inputs) -> Option<String> {
    let both = [handout.clone(), theirs.clone()];
    let (h, t) = (flat_over(handout, &both), flat_over(theirs, &both));
    let c = snapped(solve(&[h], &t)?[0], inputs.k());
    let scaled = scale(handout, c);
    let claim = reproduces(quantity, &scaled, theirs, inputs) && c != 1.0;
    claim.then(|| {
        format!(
            "yours is the handout's times {} (computed from your own inputs)",
            named(c, inputs.k())
        )
    })
}

/// `yours = handout` with two of x, y, z swapped.
fn swapped(
    quantity: &Quantity,
    handout: &Value,
    theirs: &Value,
    inputs: &Inputs,
) -> Option<String> {
    let Value::Dense(h) = handout else {
        return None;
    };
    if h.ncols() != 3 {
        return None;
    }
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let rows: Vec<[f64; 3]> = rows_of(h)
            .into_iter()
            .map(|mut row| {
                row.swap(a, b);
                row
            })
            .collect();
        let swapped = Value::Dense(DenseMatrix::from_rows(&rows).ok()?);
        if reproduces(quantity, &swapped, theirs, inputs) {
            let names = ["x", "y", "z"];
            return Some(format!(
                "yours is the handout's with its columns {} and {} swapped",
                names[a], names[b]
            ));
        }
    }
    None
}

/// The quantity's terms, each with its coefficient in the handout.
fn terms(quantity: &Quantity, theirs: &Value, inputs: &Inputs) -> Option<String> {
    let (terms, names, expected) = match quantity.spec.symbol {
        "Q" => q_terms(inputs)?,
        "y" => y_terms(inputs)?,
        "b" => b_terms(quantity.iteration?, inputs)?,
        _ => return None,
    };
    let flats: Vec<Vec<f64>> = terms.iter().map(|t| flat_over(t, &terms)).collect();
    let c: Vec<f64> = solve(&flats, &flat_over(theirs, &terms))?
        .into_iter()
        .map(|c| snapped(c, inputs.k()))
        .collect();
    let mut sum = scale(&terms[0], c[0]);
    for (term, &ci) in terms.iter().zip(&c).skip(1) {
        sum = add(&sum, &scale(term, ci))?;
    }
    if !reproduces(quantity, &sum, theirs, inputs) {
        return None;
    }
    let k = inputs.k();
    let wrong: Vec<String> = (0..c.len())
        .filter(|&i| (c[i] - expected[i]).abs() > 1e-6 * expected[i].abs())
        .map(|i| {
            format!(
                "{} has the coefficient {} where the handout has {}",
                names[i],
                named(c[i], k),
                named(expected[i], k)
            )
        })
        .collect();
    let written: Vec<String> = (0..c.len())
        .map(|i| match named(c[i], k).as_str() {
            "1" => names[i].to_string(),
            "−1" => format!("−{}", names[i]),
            factor => format!("{factor} {}", names[i]),
        })
        .collect();
    Some(format!(
        "yours is {} = {} (from your own inputs): {}",
        quantity.name(),
        written.join(" + "),
        wrong.join("; ")
    ))
}

type Terms = (Vec<Value>, [&'static str; 3], [f64; 3]);

fn q_terms(inputs: &Inputs) -> Option<Terms> {
    let a = inputs.incidence()?;
    let (m, c) = (inputs.sparse("M.mtx")?, inputs.sparse("C.mtx")?);
    let springs = scaled(&Sparse::gram(&a), inputs.k());
    let mass = Sparse::divide(&m, DELTA_T * DELTA_T);
    let pins = scaled(&Sparse::gram(&c), PIN_WEIGHT);
    let terms = [springs, mass, pins].map(Value::Sparse).to_vec();
    Some((terms, ["k AᵀA", "M/Δt²", "w CᵀC"], [1.0; 3]))
}

fn y_terms(inputs: &Inputs) -> Option<Terms> {
    let m = inputs.sparse("M.mtx")?;
    let inertia = |name: &str| -> Option<Value> {
        let u = inputs.points(name)?;
        let mut mu = vec![[0.0; 3]; u.len()];
        Sparse::mul_points(&m, &u, &mut mu);
        let rows: Vec<[f64; 3]> = mu
            .iter()
            .map(|r| r.map(|x| x / (DELTA_T * DELTA_T)))
            .collect();
        Some(Value::Dense(DenseMatrix::from_rows(&rows).ok()?))
    };
    let gravity = vec![GRAVITY; inputs.n()];
    let terms = vec![
        inertia("U_cur.mtx")?,
        inertia("U_prev.mtx")?,
        Value::Dense(DenseMatrix::from_rows(&gravity).ok()?),
    ];
    Some((
        terms,
        ["M U_cur/Δt²", "M U_prev/Δt²", "f_ext"],
        [2.0, -1.0, 1.0],
    ))
}

fn b_terms(k: usize, inputs: &Inputs) -> Option<Terms> {
    let a = inputs.incidence()?;
    let d = rows_of(&inputs.dense(&format!("d_{k}.mtx"))?);
    let mut springs = vec![[0.0; 3]; inputs.n()];
    a.transpose_mul_points(&d, &mut springs).ok()?;
    let springs: Vec<[f64; 3]> = springs.iter().map(|r| r.map(|x| inputs.k() * x)).collect();
    let dense = |rows: &[[f64; 3]]| Some(Value::Dense(DenseMatrix::from_rows(rows).ok()?));
    let terms = vec![
        dense(&springs)?,
        dense(&inputs.points("y.mtx")?)?,
        dense(&inputs.pin_term()?)?,
    ];
    Some((terms, ["k Aᵀd", "y", "w CᵀC V"], [1.0; 3]))
}
