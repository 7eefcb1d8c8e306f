//! The nonzero pattern of one row of the Cholesky factor (`ereach`).
//!
//! Row `k` of `L` has a nonzero in column `j < k` exactly when `j` lies on
//! a path in the elimination tree from some `i` with `A(i, k) ≠ 0`, `i < k`,
//! up toward `k`. So the pattern is found by climbing the tree from each
//! such `i`, stopping at nodes already visited for this row. Each path is
//! stored so that descendants come before ancestors (a topological order),
//! the order in which the up-looking factorization must use the columns.
//!
//! Cost `O(nnz(L(k, :)))`: proportional to the answer.
//!
//! Source: Davis 2006, §4.2 (`cs_ereach`).

use super::csc::CscMatrix;

/// Reusable workspace for [`RowPattern::of_row`]; holds `O(n)` memory so
/// that no call allocates.
#[derive(Debug, Clone)]
pub struct RowPattern {
    /// `visited[j] == k`: `j` is already in the pattern of row `k`.
    visited: Vec<usize>,
    /// The answer is `stack[top..]`; a path is gathered at the front first.
    stack: Vec<usize>,
}

impl RowPattern {
    /// Bytes held (array lengths).
    pub fn bytes(&self) -> usize {
        (self.visited.len() + self.stack.len()) * std::mem::size_of::<usize>()
    }

    /// A workspace for `n × n` matrices.
    pub fn new(n: usize) -> Self {
        RowPattern {
            visited: vec![usize::MAX; n],
            stack: vec![0; n],
        }
    }

    /// Columns `j < k` with `L(k, j) ≠ 0`, descendants before ancestors, for
    /// the matrix whose **upper** triangle is `upper`, with elimination
    /// tree `parent`.
    pub fn of_row(&mut self, upper: &CscMatrix, parent: &[Option<usize>], k: usize) -> &[usize] {
        let n = self.stack.len();
        let mut top = n;
        self.visited[k] = k;
        for &i in upper.column(k).0 {
            let mut node = i;
            let mut path_length = 0;
            while self.visited[node] != k {
                self.stack[path_length] = node;
                path_length += 1;
                self.visited[node] = k;
                node = parent[node].expect("A(i, k) ≠ 0 makes k an ancestor of i");
            }
            // move the path to the top of the stack, keeping its order
            while path_length > 0 {
                path_length -= 1;
                top -= 1;
                self.stack[top] = self.stack[path_length];
            }
        }
        &self.stack[top..]
    }
}
