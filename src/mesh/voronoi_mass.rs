//! Per-vertex masses from a surface mesh: mixed Voronoi areas.
//!
//! When a scene gives no uniform mass `m`, each vertex weighs the area of the
//! piece of surface closest to it, so a cloth of unit density has total mass
//! equal to its area (the diagonal of libigl's `massmatrix` with
//! `MASSMATRIX_TYPE_VORONOI`, which the assignment uses).
//!
//! Polygons are first cut into triangles as a fan from their first corner:
//! `a b c d → (a b c), (a c d)`. In each triangle, with corners 0, 1, 2,
//! `lᵢ` the length of the side opposite corner `i`, `cᵢ` the cosine of the
//! angle at corner `i` (law of cosines) and `A` the area:
//!
//! * The circumcenter splits the triangle into three sub-triangles, one on
//!   each side; the one on side `i` has area `partᵢ = wᵢ A` with
//!   `wᵢ = cᵢ lᵢ / (c₀ l₀ + c₁ l₁ + c₂ l₂)` (the circumcenter's barycentric
//!   coordinates).
//! * **No obtuse angle** (the circumcenter is inside): each corner gets half
//!   of the two sub-triangles it touches, its Voronoi cell within the
//!   triangle: corner 0 gets `(part₁ + part₂)/2`, corner 1
//!   `(part₂ + part₀)/2`, corner 2 `(part₀ + part₁)/2`.
//! * **An obtuse angle at corner `j`** (`cⱼ < 0`; the circumcenter is
//!   outside and Voronoi cells would spill over): corner `j` gets `A/2`, the
//!   other two `A/4` each.
//!
//! Either way a triangle's three shares sum to its area, so the masses sum
//! to the area of the mesh. `A` comes from Kahan's form of Heron's formula,
//! `A = ¼ √((a+(b+c))(c−(a−b))(c+(a−b))(a+(b−c)))` with `a ≥ b ≥ c`, which
//! stays accurate for needle-like triangles. The masses are summed corner by
//! corner (every triangle's first corner, then every second, then every
//! third), the order in which libigl's triplet list adds them up, so that
//! they agree with the assignment's to the last bit.
//!
//! Cost: `O(T)` for `T` triangles.
//!
//! Source: Meyer, Desbrun, Schröder, Barr, "Discrete Differential-Geometry
//! Operators for Triangulated 2-Manifolds", VisMath 2002 (published 2003),
//! §3.3 and Fig. 4 ("mixed area"); Kahan, "Miscalculating Area and Angles of
//! a Needle-like Triangle", 2014; the scene format in `data/README.md`.

use super::fan::fan_triangles;
use std::fmt;

/// A vertex whose mass cannot be used: zero (it is in no triangle of nonzero
/// area) or not finite (a degenerate triangle around it), and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProblem {
    /// The vertex, 0-based (messages print it 1-based, as in the OBJ).
    pub vertex: usize,
    /// Its computed mass.
    pub mass: f64,
    /// Why, as far as the corners of its faces tell.
    pub cause: MassCause,
}

/// Why a vertex's mass is zero or not finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MassCause {
    /// Two corners of a face around it are one point.
    RepeatedCorner,
    /// Two corners of a face around it are this far apart (in one
    /// coordinate): the area's product of four lengths overflows `f64`.
    TooFar(f64),
    /// Two distinct corners of a face around it are at most this far apart:
    /// the squared lengths underflow to 0.
    TooClose(f64),
    /// It is in no face of nonzero area (or its faces are flat otherwise).
    NoArea,
}

/// The longest side the mass computation takes: its area multiplies four
/// lengths, which overflows `f64` (1.8e308) past about 1e77.
pub const LONGEST_SIDE: f64 = 1e76;
/// The shortest side it takes: four lengths multiplied underflow to 0 below
/// about 1e-77.
pub const SHORTEST_SIDE: f64 = 1e-76;

impl fmt::Display for MassProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let vertex = self.vertex + 1;
        let mass = if self.mass.is_finite() {
            "zero mass".to_string()
        } else {
            format!("a non-finite mass ({})", self.mass)
        };
        match self.cause {
            MassCause::RepeatedCorner => write!(
                f,
                "vertex {vertex} has {mass}: a face around it has two corners at one point (a \
                 repeated corner)"
            ),
            MassCause::TooFar(apart) => write!(
                f,
                "vertex {vertex} has {mass}: corners of a face around it are {apart:e} apart, \
                 which overflows f64 in the area (sides up to {LONGEST_SIDE:e} work); scale \
                 the mesh down"
            ),
            MassCause::TooClose(apart) => write!(
                f,
                "vertex {vertex} has {mass}: corners of a face around it are only {apart:e} \
                 apart, which underflows f64 in the area (sides down to {SHORTEST_SIDE:e} \
                 work); scale the mesh up"
            ),
            MassCause::NoArea if self.mass.is_finite() => write!(
                f,
                "vertex {vertex} has zero mass: it is in no face of nonzero area (an unused \
                 vertex?); give a uniform mass \"m\" in the scene file or remove the vertex"
            ),
            MassCause::NoArea => write!(
                f,
                "vertex {vertex} has {mass}: a face around it is degenerate (flat)"
            ),
        }
    }
}

/// Why `vertex` got no usable mass: the farthest-apart and the closest
/// corners of the triangles around it.
fn cause_at(vertex: usize, vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> MassCause {
    let (mut farthest, mut closest) = (0.0_f64, f64::INFINITY);
    for triangle in triangles.iter().filter(|t| t.contains(&vertex)) {
        for i in 0..3 {
            let (p, q) = (vertices[triangle[i]], vertices[triangle[(i + 1) % 3]]);
            let apart = (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max);
            farthest = farthest.max(apart);
            closest = closest.min(apart);
        }
    }
    if farthest > LONGEST_SIDE {
        MassCause::TooFar(farthest)
    } else if closest == 0.0 {
        MassCause::RepeatedCorner
    } else if closest < SHORTEST_SIDE {
        MassCause::TooClose(closest)
    } else {
        MassCause::NoArea
    }
}

/// The mixed Voronoi mass of every vertex of the polygons `faces` (0-based
/// indices into `vertices`, 3 or more corners each).
///
/// # Errors
/// The first vertex (lowest index) whose mass is zero or not finite.
///
/// # Panics
/// If a face index is not a vertex.
pub fn voronoi_masses(
    vertices: &[[f64; 3]],
    faces: &[Vec<usize>],
) -> Result<Vec<f64>, MassProblem> {
    let triangles: Vec<[usize; 3]> = fan_triangles(faces).collect();
    let shares: Vec<[f64; 3]> = triangles
        .iter()
        .map(|t| triangle_mass_shares([vertices[t[0]], vertices[t[1]], vertices[t[2]]]))
        .collect();
    let mut masses = vec![0.0; vertices.len()];
    for corner in 0..3 {
        for (triangle, share) in triangles.iter().zip(&shares) {
            masses[triangle[corner]] += share[corner];
        }
    }
    match masses.iter().position(|&m| !(m.is_finite() && m > 0.0)) {
        Some(vertex) => Err(MassProblem {
            vertex,
            mass: masses[vertex],
            cause: cause_at(vertex, vertices, &triangles),
        }),
        None => Ok(masses),
    }
}

/// The share of the triangle `corners` that goes to each of its corners
/// (mixed Voronoi rule, above); the three sum to its area.
pub fn triangle_mass_shares(corners: [[f64; 3]; 3]) -> [f64; 3] {
    // side i is opposite corner i: it joins corners i+1 and i+2
    let side = |i: usize| distance(corners[(i + 1) % 3], corners[(i + 2) % 3]);
    let lengths = [side(0), side(1), side(2)];
    let area = triangle_area(lengths);
    let cosines = [0, 1, 2].map(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let [li, lj, lk] = [lengths[i], lengths[j], lengths[k]];
        (lk * lk + lj * lj - li * li) / (lj * lk * 2.0)
    });
    let obtuse_corner = (0..3).rev().find(|&i| cosines[i] < 0.0); // at most one
    if let Some(j) = obtuse_corner {
        let mut shares = [area / 4.0; 3];
        shares[j] = area / 2.0;
        return shares;
    }
    // parts[i]: the sub-triangle between the circumcenter and side i
    let weights = [0, 1, 2].map(|i| cosines[i] * lengths[i]);
    let sum = weights[0] + (weights[1] + weights[2]);
    let parts = weights.map(|w| w / sum * area);
    [0, 1, 2].map(|i| (parts[(i + 1) % 3] + parts[(i + 2) % 3]) * 0.5)
}

/// The area of a triangle from its side lengths (Kahan's stable Heron); 0
/// when rounding makes the lengths violate the triangle inequality.
pub fn triangle_area(lengths: [f64; 3]) -> f64 {
    let mut sorted = lengths;
    sorted.sort_by(|x, y| y.total_cmp(x));
    let [a, b, c] = sorted; // a ≥ b ≥ c
    let product = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    let area = product.sqrt() / 4.0;
    if area.is_nan() {
        0.0
    } else {
        area
    }
}

fn distance(p: [f64; 3], q: [f64; 3]) -> f64 {
    let (dx, dy, dz) = (p[0] - q[0], p[1] - q[1], p[2] - q[2]);
    (dx * dx + dy * dy + dz * dz).sqrt()
}
