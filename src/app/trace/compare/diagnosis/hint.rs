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
//! The coefficients are fitted by least squares (the normal equations of
//! at most three terms), then the fit is held to the student's numbers
//! like any recomputed value.

use super::super::entries::to_sparse;
use super::inputs::{rows_of, Inputs};
use super::recompute::{reproduces, Value};
use crate::app::trace::quantities::Quantity;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::CscMatrix;
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

/// The coefficients a hint names, with their words.
fn names(k: f64) -> [(f64, &'static str); 13] {
    let dt = DELTA_T;
    [
        (1.0, "1"),
        (0.0, "0 (left out)"),
        (2.0, "2"),
        (0.5, "½"),
        (3.0, "3"),
        (k, "k"),
        (1.0 / k, "1/k"),
        (dt, "Δt"),
        (1.0 / dt, "1/Δt"),
        (dt * dt, "Δt²"),
        (1.0 / (dt * dt), "1/Δt²"),
        (PIN_WEIGHT, "w"),
        (1.0 / PIN_WEIGHT, "1/w"),
    ]
}

/// The named coefficient (or its negative) within 10⁻⁶ of the fitted
/// `c`, else `c`: the claim is then checked with the exact value, as the
/// least squares leave a few units of rounding in each coefficient.
fn snapped(c: f64, k: f64) -> f64 {
    let close = |value: f64| (c - value).abs() <= 1e-6 * value.abs().max(1e-300);
    let signed = names(k).into_iter().flat_map(|(value, _)| [value, -value]);
    signed.into_iter().find(|&value| close(value)).unwrap_or(c)
}

/// `c`, in words: `−1`, `2`, `½`, `k`, `1/Δt`, …, or its digits.
fn named(c: f64, k: f64) -> String {
    for (value, name) in names(k) {
        if c == value {
            return name.to_string();
        }
        if c == -value && value != 0.0 {
            return format!("−{name}");
        }
    }
    format!("{c:.6e}")
}

/// The values of a dense value, or of a sparse one over its own pattern.
fn flat(value: &Value) -> Vec<f64> {
    match value {
        Value::Dense(a) => a.as_slice().to_vec(),
        Value::Sparse(a) => a.values().to_vec(),
    }
}

/// `value`'s entries at every position stored in any of `terms` (and in
/// `value`), in one order for all.
fn flat_over(value: &Value, terms: &[Value]) -> Vec<f64> {
    let Value::Sparse(a) = value else {
        return flat(value);
    };
    let mut positions: Vec<(usize, usize)> = Vec::new();
    for matrix in terms.iter().chain([value]) {
        if let Value::Sparse(m) = matrix {
            for j in 0..m.ncols() {
                positions.extend(m.column(j).0.iter().map(|&i| (j, i)));
            }
        }
    }
    positions.sort_unstable();
    positions.dedup();
    positions.iter().map(|&(j, i)| a.get(i, j)).collect()
}

/// `c · value`.
fn scale(value: &Value, c: f64) -> Value {
    match value {
        Value::Dense(a) => {
            let values = a.as_slice().iter().map(|x| c * x).collect();
            Value::Dense(
                DenseMatrix::from_row_major(a.nrows(), a.ncols(), values).expect("same shape"),
            )
        }
        Value::Sparse(a) => Value::Sparse(scaled(a, c)),
    }
}

fn scaled(a: &CscMatrix, c: f64) -> CscMatrix {
    let mut scaled = a.clone();
    scaled.values_mut().iter_mut().for_each(|x| *x *= c);
    scaled
}

/// `a + b`, of one kind and shape.
fn add(a: &Value, b: &Value) -> Option<Value> {
    match (a, b) {
        (Value::Dense(a), Value::Dense(b)) if a.as_slice().len() == b.as_slice().len() => {
            let values = a
                .as_slice()
                .iter()
                .zip(b.as_slice())
                .map(|(x, y)| x + y)
                .collect();
            Some(Value::Dense(
                DenseMatrix::from_row_major(a.nrows(), a.ncols(), values).ok()?,
            ))
        }
        (Value::Sparse(a), Value::Sparse(b)) => {
            Some(Value::Sparse(a.add_scaled(1.0, b, 1.0).ok()?))
        }
        _ => None,
    }
}

/// The least-squares `c` of `target ≈ Σ cᵢ termsᵢ`, by the normal
/// equations; `None` when the terms are (nearly) dependent.
fn solve(terms: &[Vec<f64>], target: &[f64]) -> Option<Vec<f64>> {
    let j = terms.len();
    if terms.iter().any(|t| t.len() != target.len()) {
        return None;
    }
    // each term scaled to unit norm, so the pivots compare
    let norms: Vec<f64> = terms
        .iter()
        .map(|t| t.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    if norms.iter().any(|&s| s == 0.0 || !s.is_finite()) {
        return None;
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut g = vec![vec![0.0; j + 1]; j];
    for r in 0..j {
        for c in 0..j {
            g[r][c] = dot(&terms[r], &terms[c]) / (norms[r] * norms[c]);
        }
        g[r][j] = dot(&terms[r], target) / norms[r];
    }
    for col in 0..j {
        let pivot = (col..j).max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))?;
        if g[pivot][col].abs() < 1e-9 {
            return None; // dependent terms: no single answer
        }
        g.swap(col, pivot);
        for row in 0..j {
            if row != col {
                let f = g[row][col] / g[col][col];
                for c in col..=j {
                    g[row][c] -= f * g[col][c];
                }
            }
        }
    }
    Some((0..j).map(|r| g[r][j] / g[r][r] / norms[r]).collect())
}
