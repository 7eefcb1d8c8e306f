//! Lighting: two-sided Lambert diffuse plus ambient, with smooth vertex
//! normals.
//!
//! **Brightness.** For a unit normal `n` turned toward the viewer and the
//! unit direction toward the light `l`,
//!
//! ```text
//! brightness = ambient + diffuse · |n·l|     (0.35 + 0.65 · |n·l|)
//! ```
//!
//! Lambert's cosine law: a surface receives light in proportion to the
//! cosine of the angle between its normal and the light. The surface colour
//! (texture or flat) is multiplied by it. Cloth is a thin sheet: the side
//! turned away from the light is lit through it as brightly (`|n·l|`, not
//! `max(0, n·l)`, which left the back of a cloth at the ambient level,
//! nearly black).
//!
//! **Two-sided.** Cloth has no inside: both sides are seen. The normal
//! `n` is flipped when the camera sees the back of the triangle
//! (`triangle.rs` tells which side from the winding on screen), so both
//! sides are lit as fronts and the result does not depend on the mesh's
//! orientation.
//!
//! **Vertex normals.** Each vertex gets the sum of the (unnormalised) normals
//! `(b − a) × (c − a)` of the triangles around it, so larger triangles weigh
//! more, then normalised; interpolated across a triangle (perspective-
//! correct) and renormalised per sample, they shade the folds of a coarse
//! mesh smoothly (Phong's normal interpolation). Cost: `O(faces)` per frame.
//!
//! Sources: Marschner & Shirley, *Fundamentals of Computer Graphics*, 4th ed.
//! (2016), ch. 10 (surface shading: Lambertian, ambient); B. T. Phong,
//! *Illumination for computer generated pictures*, CACM 1975.

use super::look::{AMBIENT, DIFFUSE, TOWARD_LIGHT};
use super::vector::{cross, dot_f32, normalize, sub};
use masssprings::mesh::fan::fan_corners;

/// The unit direction toward the light, in world space.
pub fn toward_light() -> [f32; 3] {
    normalize(TOWARD_LIGHT).map(|v| v as f32)
}

/// `ambient + diffuse · |n·l|` for a unit normal `n` and the unit
/// direction `l` toward the light.
pub fn lambert(normal: [f32; 3], toward_light: [f32; 3]) -> f32 {
    AMBIENT + DIFFUSE * dot_f32(normal, toward_light).abs()
}

/// The normal of the side the camera sees: `normal` on the front, `−normal`
/// on the back.
pub fn toward_viewer(normal: [f32; 3], front_facing: bool) -> [f32; 3] {
    if front_facing {
        normal
    } else {
        normal.map(|v| -v)
    }
}

/// Area-weighted vertex normals of the fan-triangulated `faces` at
/// `positions`, into `normals` (zero for a vertex in no triangle).
pub fn vertex_normals(positions: &[[f64; 3]], faces: &[Vec<usize>], normals: &mut Vec<[f32; 3]>) {
    let mut sums = vec![[0.0f64; 3]; positions.len()];
    for face in faces {
        for corners in fan_corners(face.len()) {
            let [a, b, c] = corners.map(|corner| face[corner]);
            let n = cross(
                sub(positions[b], positions[a]),
                sub(positions[c], positions[a]),
            );
            for v in [a, b, c] {
                for k in 0..3 {
                    sums[v][k] += n[k];
                }
            }
        }
    }
    normals.clear();
    normals.extend(sums.into_iter().map(|n| normalize(n).map(|v| v as f32)));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_sides_of_the_sheet_are_lit_and_edge_on_is_ambient() {
        let l = toward_light();
        assert!((lambert(l, l) - (AMBIENT + DIFFUSE)).abs() < 1e-6);
        assert_eq!(lambert(l.map(|v| -v), l), lambert(l, l));
        let edge_on = normalize(cross([-0.4, 0.8, 0.45], [0.0, 0.0, 1.0])).map(|v| v as f32);
        assert!((lambert(edge_on, l) - AMBIENT).abs() < 1e-6);
    }

    #[test]
    fn two_sided_lighting_does_not_depend_on_the_winding() {
        // The same triangle wound both ways has opposite normals, and the
        // camera sees it from opposite "sides": the light it gets is the same.
        let positions = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.1], [0.3, 1.0, -0.4]];
        let mut normals = Vec::new();
        let mut brightness = Vec::new();
        for (face, front_facing) in [(vec![0, 1, 2], true), (vec![0, 2, 1], false)] {
            vertex_normals(&positions, &[face], &mut normals);
            brightness.push(lambert(
                toward_viewer(normals[0], front_facing),
                toward_light(),
            ));
        }
        assert_eq!(brightness[0], brightness[1]);
        assert!(brightness[0] > AMBIENT);
    }

    #[test]
    fn a_flat_quad_has_its_plane_normal_at_every_vertex() {
        let positions = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mut normals = Vec::new();
        vertex_normals(&positions, &[vec![0, 1, 2, 3]], &mut normals);
        assert!(normals.iter().all(|&n| n == [0.0, 0.0, 1.0]));
        assert_eq!(fan_corners(4).count(), 2);
        assert_eq!(fan_corners(2).count(), 0);
    }
}
