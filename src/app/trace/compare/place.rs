//! Where a difference is, in words: the row and column of the file
//! (1-based) and what they stand for (0-based, as in `V`, `E` and `b`), and
//! what `--compare` knows of our trace to say so and to check `L`.

use super::{to_sparse, Difference};
use crate::app::trace::quantities::{Axis, Spec};
use masssprings::linalg::sparse::CscMatrix;
use masssprings::matrix_market::MatrixMarket;

/// Where the largest difference of a quantity is.
#[derive(Debug, Clone)]
pub enum Place {
    /// An entry of the quantity.
    Entry(Difference),
    /// An entry of `L Lᵀ − P Q Pᵀ` (in the factor's order), with the
    /// permutation `perm` of `P` it was formed with (`ours` is `P Q Pᵀ`,
    /// `yours` is `L Lᵀ`).
    Product(Difference, Vec<usize>),
}

impl Place {
    /// The scaled difference.
    pub fn relative(&self) -> f64 {
        match self {
            Place::Entry(d) | Place::Product(d, _) => d.relative,
        }
    }
}

/// What `--compare` reads of our trace before it compares: the springs
/// (from `A`), `Q` and our ordering, and the student's ordering once read.
#[derive(Debug)]
pub struct Context {
    /// Spring `e` as `(i, j)`, read off row `e` of `A` (`None` for a
    /// spring from a vertex to itself, an empty row).
    springs: Vec<Option<[usize; 2]>>,
    /// Our `A`, and the stiffness `k`.
    pub a: CscMatrix,
    pub k: f64,
    pub q: CscMatrix,
    /// Our `perm` (`perm[new] = old`).
    pub our_perm: Vec<usize>,
    /// The student's, once their `P.mtx` was read and is a permutation.
    pub their_perm: Option<Vec<usize>>,
}

impl Context {
    /// From our `A`, `Q` and `P`.
    pub fn new(
        a: &MatrixMarket,
        k: f64,
        q: &MatrixMarket,
        p: &MatrixMarket,
    ) -> Result<Self, String> {
        let a = to_sparse(a);
        let mut ends = vec![[None, None]; a.nrows()];
        for j in 0..a.ncols() {
            let (rows, values) = a.column(j);
            for (&e, &v) in rows.iter().zip(values) {
                ends[e][usize::from(v < 0.0)] = Some(j); // +1 at i, −1 at j
            }
        }
        let springs = ends.into_iter().map(|[i, j]| Some([i?, j?])).collect();
        let (q, our_perm) = (to_sparse(q), permutation_of(&to_sparse(p))?);
        let n = our_perm.len();
        if (q.nrows(), q.ncols(), a.ncols()) != (n, n, n) {
            return Err(format!(
                "A ({} × {}), Q ({} × {}) and P ({n} × {n}) do not fit one another",
                a.nrows(),
                a.ncols(),
                q.nrows(),
                q.ncols()
            ));
        }
        Ok(Context {
            springs,
            a,
            k,
            q,
            our_perm,
            their_perm: None,
        })
    }

    /// `row 18, column 5: spring 17 = (4, 9), vertex 4; ours -1, yours 1`.
    pub fn describe(&self, spec: &Spec, place: &Place) -> String {
        match place {
            Place::Entry(d) => {
                let names = [self.name(spec.rows, d.row), self.name(spec.columns, d.col)];
                let names: Vec<String> = names.into_iter().flatten().collect();
                let position = match spec.columns {
                    Axis::Single => format!("row {}", d.row + 1),
                    _ => format!("row {}, column {}", d.row + 1, d.col + 1),
                };
                format!(
                    "{position}: {}; ours {}, yours {}",
                    names.join(", "),
                    number(d.ours),
                    number(d.yours)
                )
            }
            Place::Product(d, perm) => format!(
                "row {}, column {} of L Lᵀ − P Q Pᵀ: vertices {}, {}; P Q Pᵀ {}, L Lᵀ {}",
                d.row + 1,
                d.col + 1,
                perm[d.row],
                perm[d.col],
                number(d.ours),
                number(d.yours)
            ),
        }
    }

    /// What index `k` (0-based) of `axis` stands for.
    fn name(&self, axis: Axis, k: usize) -> Option<String> {
        Some(match axis {
            Axis::Spring => match self.springs.get(k).copied().flatten() {
                Some([i, j]) => format!("spring {k} = ({i}, {j})"),
                None => format!("spring {k}"),
            },
            Axis::Vertex => format!("vertex {k}"),
            Axis::Pin => format!("pin {k}"),
            Axis::Coordinate => ["x", "y", "z"]
                .get(k)
                .map_or(format!("column {k}"), |c| c.to_string()),
            Axis::FactorOrder => match self.our_perm.get(k) {
                Some(v) => format!("factor position {k} (vertex {v} in our order)"),
                None => format!("factor position {k}"),
            },
            Axis::Single => return None,
        })
    }
}

/// `perm` of a permutation matrix `P` (a 1 at `(new, perm[new])`), or why
/// `p` is not one.
pub fn permutation_of(p: &CscMatrix) -> Result<Vec<usize>, String> {
    let n = p.ncols();
    if p.nrows() != n {
        return Err(format!("shape {} × {n}, not square", p.nrows()));
    }
    let mut perm = vec![usize::MAX; n];
    for j in 0..n {
        let (rows, values) = p.column(j);
        let ones: Vec<usize> = rows
            .iter()
            .zip(values)
            .filter(|(_, &v)| v != 0.0)
            .map(|(&r, _)| r)
            .collect();
        match ones[..] {
            [r] if values.iter().all(|&v| v == 0.0 || v == 1.0) && perm[r] == usize::MAX => {
                perm[r] = j
            }
            [r] if perm[r] != usize::MAX => return Err(format!("row {} has two ones", r + 1)),
            [_] => return Err(format!("column {} holds a value other than 1", j + 1)),
            _ => {
                return Err(format!(
                    "column {} has {} nonzeros, not one",
                    j + 1,
                    ones.len()
                ))
            }
        }
    }
    Ok(perm)
}

/// A value as a person reads it: plain when moderate, else scientific.
pub fn number(v: f64) -> String {
    if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}
