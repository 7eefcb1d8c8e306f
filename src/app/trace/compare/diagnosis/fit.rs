//! Coefficients fitted to a student's numbers, and named: the least
//! squares `c` of `yours ≈ Σ cᵢ tᵢ` over the values of the terms `tᵢ`
//! (dense, or sparse over the union of their patterns), by the normal
//! equations of at most three terms, each term scaled to unit norm:
//!
//! ```text
//! G c' = g,   Gᵢⱼ = ⟨tᵢ, tⱼ⟩ / (‖tᵢ‖ ‖tⱼ‖),   gᵢ = ⟨tᵢ, yours⟩ / ‖tᵢ‖,   cᵢ = c'ᵢ / ‖tᵢ‖
//! ```
//!
//! A coefficient within 10⁻⁶ of one a hint names (`2`, `½`, `k`, `1/Δt`,
//! `w`, their negatives, …) is taken as that one, so that a claim is made
//! of the exact value.

use super::recompute::Value;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::CscMatrix;
use masssprings::sim::{DELTA_T, PIN_WEIGHT};

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
pub fn snapped(c: f64, k: f64) -> f64 {
    let close = |value: f64| (c - value).abs() <= 1e-6 * value.abs().max(1e-300);
    let signed = names(k).into_iter().flat_map(|(value, _)| [value, -value]);
    signed.into_iter().find(|&value| close(value)).unwrap_or(c)
}

/// `c`, in words: `−1`, `2`, `½`, `k`, `1/Δt`, …, or its digits.
pub fn named(c: f64, k: f64) -> String {
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
pub fn flat_over(value: &Value, terms: &[Value]) -> Vec<f64> {
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
pub fn scale(value: &Value, c: f64) -> Value {
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

pub fn scaled(a: &CscMatrix, c: f64) -> CscMatrix {
    let mut scaled = a.clone();
    scaled.values_mut().iter_mut().for_each(|x| *x *= c);
    scaled
}

/// `a + b`, of one kind and shape.
pub fn add(a: &Value, b: &Value) -> Option<Value> {
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
pub fn solve(terms: &[Vec<f64>], target: &[f64]) -> Option<Vec<f64>> {
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
