//! The Hessian of the step's energy: a `3n × 3n` sparse matrix of `3 × 3`
//! blocks, for Newton's method.
//!
//! Differentiating the gradient of [`energy`](super::energy) once more, with
//! `vₑ = pᵢ − pⱼ`, `l = ‖vₑ‖` and `u = vₑ / l`, each spring contributes
//!
//! ```text
//! Kₑ = k [ (1 − r/l) I + (r/l) u uᵀ ]        (3 × 3)
//! H_ii += Kₑ,  H_jj += Kₑ,  H_ij −= Kₑ,  H_ji −= Kₑ
//! ```
//!
//! and each vertex `mᵢ/Δt² I` on its diagonal block (plus `w I` when
//! pinned). A stretched spring (`l > r`) has a positive definite `Kₑ`; a
//! compressed one (`l < r`) has the negative eigenvalue `k (1 − r/l)` twice,
//! across the spring: cloth under compression makes `H` indefinite, which
//! Newton's method must handle ([`newton`](super::methods::newton)). Compare
//! `Q = k AᵀA + M/Δt² + w CᵀC`: it is `H` with every spring at rest
//! length (`Kₑ = k I`), block for block (`Q ⊗ I₃`).
//!
//! **Pattern.** Vertex block `(i, j)` is there exactly where `Q` has entry
//! `(i, j)`, so `H`'s pattern is `Q`'s with every entry expanded to a
//! `3 × 3` block. Unknown `(i, c)` (vertex `i`, coordinate `c`) is number
//! `3i + c`, the layout of an `n × 3` block of points read as a vector. Column
//! `3j + c` holds rows `3i + a` for the vertices `i` of column `j` of `Q`'s
//! pattern, so entry `(3i + a, 3j + c)` sits at
//!
//! ```text
//! 9 start(j) + 3 c count(j) + 3 pos(i in column j) + a
//! ```
//!
//! and the positions of each spring's and each vertex's blocks are found
//! once, when the pattern is built. Assembling the values is then `O(m + n)`
//! and allocates nothing.
//!
//! Source: the energy of the assignment; the Hessian of a spring as in
//! A. Witkin & D. Baraff, "Physically Based Modeling", SIGGRAPH 2001 course
//! notes, "Implicit methods" (§5); Liu et al. 2013, §3 (`Q` as the rest-length
//! Hessian).

use super::energy::{difference, norm, StepEnergy};
use crate::linalg::sparse::{CscMatrix, Permutation, TripletMatrix};

/// `H`'s pattern and values, and where each block lives.
#[derive(Debug, Clone)]
pub struct Hessian {
    /// The `3n × 3n` matrix (both triangles stored).
    pub matrix: CscMatrix,
    /// `start(j)` and `count(j)` of the vertex pattern's columns.
    vertex_start: Vec<usize>,
    vertex_count: Vec<usize>,
    /// Position of vertex `i` in its own column of the vertex pattern.
    diagonal_position: Vec<usize>,
    /// For spring `(i, j)`: position of `i` in column `j`, and of `j` in
    /// column `i`.
    spring_positions: Vec<[usize; 2]>,
}

impl Hessian {
    /// The pattern for `n` vertices joined by `springs` (values zero).
    pub fn new(n: usize, springs: &[[usize; 2]]) -> Self {
        let vertices = vertex_pattern(n, springs);
        let vertex_start = vertices.col_ptr()[..n].to_vec();
        let vertex_count: Vec<usize> = (0..n).map(|j| vertices.column(j).0.len()).collect();
        let position = |i: usize, j: usize| {
            let rows = vertices.column(j).0;
            rows.binary_search(&i)
                .expect("the pattern holds every spring and diagonal")
        };
        let diagonal_position = (0..n).map(|i| position(i, i)).collect();
        let spring_positions = springs
            .iter()
            .map(|&[i, j]| [position(i, j), position(j, i)])
            .collect();
        let matrix = expanded_pattern(&vertices);
        Hessian {
            matrix,
            vertex_start,
            vertex_count,
            diagonal_position,
            spring_positions,
        }
    }

    /// Index in the values of entry `(3i + a, 3j + c)`, with `i` at
    /// `position` in vertex column `j`.
    fn index(&self, position: usize, a: usize, j: usize, c: usize) -> usize {
        9 * self.vertex_start[j] + 3 * c * self.vertex_count[j] + 3 * position + a
    }

    /// Index of diagonal entry `(3i + c, 3i + c)`.
    pub fn diagonal_index(&self, i: usize, c: usize) -> usize {
        self.index(self.diagonal_position[i], c, i, c)
    }

    /// Fills the values with `∇²E(p)`.
    ///
    /// # Panics
    /// When `energy` is not for the network this pattern was made for.
    pub fn assemble(&mut self, energy: &StepEnergy<'_>, p: &[[f64; 3]]) {
        assert_eq!(energy.springs.len(), self.spring_positions.len());
        self.matrix.values_mut().fill(0.0);
        let inverse_dt2 = 1.0 / (energy.delta_t * energy.delta_t);
        for (i, &mi) in energy.m.iter().enumerate() {
            self.add_diagonal(i, mi * inverse_dt2);
        }
        for &c in energy.pinned {
            self.add_diagonal(c, energy.w);
        }
        for (e, (&[i, j], &rest)) in energy.springs.iter().zip(energy.r).enumerate() {
            let block = spring_block(energy.k, rest, difference(p[i], p[j]));
            let [i_in_j, j_in_i] = self.spring_positions[e];
            self.add_block(self.diagonal_position[i], i, &block, 1.0);
            self.add_block(self.diagonal_position[j], j, &block, 1.0);
            self.add_block(i_in_j, j, &block, -1.0);
            self.add_block(j_in_i, i, &block, -1.0);
        }
    }

    /// Makes the rows and columns of the vertices with `pinned[i]` those of
    /// the identity (exact pins: those vertices are not unknowns).
    pub fn constrain(&mut self, pinned: &[bool]) {
        let n = self.vertex_count.len();
        for j in 0..n {
            let start = 9 * self.vertex_start[j];
            let count = self.vertex_count[j];
            for c in 0..3 {
                let column = 3 * c * count + start;
                for slot in 0..3 * count {
                    let i = self.matrix.row_idx()[column + slot];
                    if pinned[i / 3] || pinned[j] {
                        let identity = i == 3 * j + c;
                        self.matrix.values_mut()[column + slot] = if identity { 1.0 } else { 0.0 };
                    }
                }
            }
        }
    }

    /// `H_ii += value · I`.
    fn add_diagonal(&mut self, i: usize, value: f64) {
        for c in 0..3 {
            let index = self.diagonal_index(i, c);
            self.matrix.values_mut()[index] += value;
        }
    }

    /// Adds `sign · block` to the vertex block at `position` in column `j`.
    fn add_block(&mut self, position: usize, j: usize, block: &[[f64; 3]; 3], sign: f64) {
        for c in 0..3 {
            for a in 0..3 {
                let index = self.index(position, a, j, c);
                self.matrix.values_mut()[index] += sign * block[a][c];
            }
        }
    }
}

/// `Kₑ = k [(1 − r/l) I + (r/l) u uᵀ]` for the spring vector `v` (`k I`, the
/// rest-length block, for a spring of zero length).
pub fn spring_block(k: f64, rest: f64, v: [f64; 3]) -> [[f64; 3]; 3] {
    let length = norm(v);
    if length == 0.0 {
        return std::array::from_fn(|a| std::array::from_fn(|c| if a == c { k } else { 0.0 }));
    }
    let ratio = rest / length;
    let u = v.map(|x| x / length);
    std::array::from_fn(|a| {
        std::array::from_fn(|c| {
            let identity = if a == c { 1.0 } else { 0.0 };
            k * ((1.0 - ratio) * identity + ratio * u[a] * u[c])
        })
    })
}

/// The `n × n` pattern of `Q`: the diagonal and both `(i, j)` and `(j, i)`
/// of every spring.
pub fn vertex_pattern(n: usize, springs: &[[usize; 2]]) -> CscMatrix {
    let diagonal = (0..n).map(|i| (i, i, 1.0));
    let off_diagonal = springs
        .iter()
        .flat_map(|&[i, j]| [(i, j, 1.0), (j, i, 1.0)]);
    TripletMatrix::from_entries(n, n, diagonal.chain(off_diagonal))
        .expect("springs join vertices of the network")
        .to_csc()
}

/// Every entry of `vertices` expanded into a `3 × 3` block (values zero).
fn expanded_pattern(vertices: &CscMatrix) -> CscMatrix {
    let n = vertices.ncols();
    let mut col_ptr = Vec::with_capacity(3 * n + 1);
    let mut row_idx = Vec::with_capacity(9 * vertices.nnz());
    col_ptr.push(0);
    for j in 0..n {
        let rows = vertices.column(j).0;
        for _c in 0..3 {
            row_idx.extend(rows.iter().flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2]));
            col_ptr.push(row_idx.len());
        }
    }
    let nnz = row_idx.len();
    CscMatrix::from_parts(3 * n, 3 * n, col_ptr, row_idx, vec![0.0; nnz])
        .expect("an expanded valid pattern is valid")
}

/// The ordering of `Q` applied block by block: unknown `3 perm[k] + c` is
/// placed at `3k + c`.
pub fn expanded_permutation(vertex_ordering: &Permutation) -> Permutation {
    let perm = vertex_ordering
        .perm()
        .iter()
        .flat_map(|&old| [3 * old, 3 * old + 1, 3 * old + 2])
        .collect();
    Permutation::from_perm(perm).expect("an expanded permutation is a permutation")
}
