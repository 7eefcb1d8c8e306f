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
//! Source: the assignment's `read_json` (2-corner faces as edges, otherwise
//! `igl::edges`); `../shared/design/scene-format.md`.

use super::SceneError;

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
