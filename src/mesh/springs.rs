//! The springs `E` of a scene, from the faces of its OBJ.
//!
//! Two kinds of file, told apart by the number of corners per face:
//!
//! * **2-corner faces are springs.** `f i j` is the spring `(i, j)`; the
//!   springs are listed in file order and a pair written twice is two springs
//!   (the assignment keeps them).
//! * **Faces of 3 or more corners are polygons,** and every pair of corners
//!   of a face is joined by a spring: a triangle gives its 3 sides, a quad its
//!   4 sides and both diagonals (the shear springs), a `c`-gon `c(c−1)/2`
//!   springs. A pair shared by two faces (a common edge) is one spring. The
//!   springs are the nonzeros `(r, c)`, `r < c`, of the upper triangle of the
//!   symmetric adjacency matrix, listed in its column-major order: by column
//!   `c` ascending, then row `r` ascending. That is how the assignment lists
//!   them (libigl's `edges`, read off a sparse adjacency matrix); the order
//!   only changes rounding, but keeping it keeps our results comparable with
//!   the assignment's to the last bits.
//!
//! A face that repeats a vertex gives no spring from that vertex to itself
//! (it would sit on the adjacency matrix's diagonal) in the polygon case; a
//! 2-corner face `f i i` is kept as written, like every 2-corner face.
//!
//! Cost: `O(p log p)` for the `p = F · c(c−1)/2` corner pairs of `F` faces
//! of `c` corners (one sort); `O(F)` for 2-corner faces.
//!
//! **Memory.** A `c`-gon gives `c(c−1)/2` springs, so one face of 20,000
//! corners would give 2×10⁸ of them. [`check_spring_memory`] counts the
//! corner pairs (an upper bound on the springs) before any is made and
//! refuses a mesh whose springs would need more than the memory limit of
//! [`crate::memory`], at [`BYTES_PER_SPRING`] each.
//!
//! Source: the assignment's `read_json` (2-corner faces as edges, otherwise
//! `igl::edges`); the scene format in `data/README.md`.

use super::SceneError;
use crate::memory;

/// What one spring costs, from the faces to the factorized system: the
/// corner pair sorted here (16 bytes) and the spring itself (16), two
/// entries of the incidence matrix `A` and its transpose (64), four
/// triplets of `k AᵀA` (96), its rest length and direction `r`, `d` (32),
/// with room for the fill of the factor: a deliberately generous 256 bytes.
pub const BYTES_PER_SPRING: u64 = 256;

/// At most how many springs `faces` give: one per 2-corner face, else
/// `c(c−1)/2` per `c`-gon (pairs shared by two faces counted twice),
/// saturating.
pub fn corner_pairs(faces: &[Vec<usize>]) -> u64 {
    let corners = faces.first().map_or(0, Vec::len) as u64;
    let per_face = if corners == 2 {
        1
    } else {
        corners.saturating_mul(corners.saturating_sub(1)) / 2
    };
    (faces.len() as u64).saturating_mul(per_face)
}

/// Refuses faces whose springs would not fit in memory (see the module
/// header), before any spring is made.
///
/// # Errors
/// A [`SceneError`] (without a file; the caller adds it) with the estimate,
/// the limit and the advice to split large polygons.
pub fn check_spring_memory(faces: &[Vec<usize>]) -> Result<(), SceneError> {
    let pairs = corner_pairs(faces);
    let corners = faces.first().map_or(0, Vec::len);
    memory::check(
        memory::bytes_for(pairs, BYTES_PER_SPRING),
        || {
            format!(
                "the {} face(s) of {} corners give up to {} springs (every pair of corners of a \
                 polygon is joined), which",
                memory::thousands(faces.len() as u64),
                memory::thousands(corners as u64),
                memory::thousands(pairs)
            )
        },
        "split large polygons into triangles or quads",
    )
    .map_err(|too_large| SceneError::invalid(too_large.to_string()))
}

/// The springs `(i, j)` (0-based) of the faces, as described above.
///
/// # Errors
/// A [`SceneError`] (without a file; the caller adds it) when the faces give
/// no spring at all: there are no faces, or only polygons whose corners are
/// all one vertex.
///
/// # Panics
/// If the faces do not all have the same number of corners (the OBJ reader
/// guarantees they do).
pub fn springs_from_faces(faces: &[Vec<usize>]) -> Result<Vec<[usize; 2]>, SceneError> {
    let corners = faces.first().map_or(0, Vec::len);
    assert!(
        faces.iter().all(|face| face.len() == corners),
        "all faces must have the same number of corners"
    );
    let springs = if corners == 2 {
        faces.iter().map(|face| [face[0], face[1]]).collect()
    } else {
        polygon_springs(faces)
    };
    if springs.is_empty() {
        return Err(SceneError::invalid(
            "the mesh gives no springs: it needs 2-corner faces (springs) or polygons (`f` lines)",
        ));
    }
    Ok(springs)
}

/// Every distinct pair of corners of every face, in the column-major order
/// of the upper triangle of the adjacency matrix.
fn polygon_springs(faces: &[Vec<usize>]) -> Vec<[usize; 2]> {
    // Each pair as (column, row) = (larger, smaller): sorting these tuples is
    // walking the upper triangle column by column, rows ascending.
    let mut column_row: Vec<(usize, usize)> = Vec::new();
    for face in faces {
        for (a, &first) in face.iter().enumerate() {
            for &second in &face[a + 1..] {
                if first != second {
                    column_row.push((first.max(second), first.min(second)));
                }
            }
        }
    }
    column_row.sort_unstable();
    column_row.dedup();
    column_row
        .into_iter()
        .map(|(column, row)| [row, column])
        .collect()
}
