//! Fan triangulation of a polygon face.
//!
//! A convex face `p₀ p₁ … p_{c−1}` is cut into the triangles
//! `(p₀ p₁ p₂), (p₀ p₂ p₃), …, (p₀ p_{c−2} p_{c−1})`, all sharing the first
//! corner: `c − 2` triangles, none for a face of fewer than three corners
//! (a two-corner face is a spring, not a surface). The assignment's Voronoi
//! masses use exactly this triangulation; the renderer and the viewer draw
//! the same triangles.
//!
//! Cost `O(c)` per face. Source: the assignment's mass computation
//! (`data/README.md`); Marschner & Shirley, *Fundamentals of
//! Computer Graphics*, §12.1.

/// The triangles of a face with `corner_count` corners, as corner positions
/// within the face: `[0, 1, 2], [0, 2, 3], …`.
pub fn fan_corners(corner_count: usize) -> impl Iterator<Item = [usize; 3]> {
    (1..corner_count.saturating_sub(1)).map(|i| [0, i, i + 1])
}

/// The triangles of every face, as vertex indices, in face order.
pub fn fan_triangles(faces: &[Vec<usize>]) -> impl Iterator<Item = [usize; 3]> + '_ {
    faces
        .iter()
        .flat_map(|face| fan_corners(face.len()).map(move |corners| corners.map(|c| face[c])))
}
