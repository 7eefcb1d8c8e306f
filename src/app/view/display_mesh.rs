//! The scene as the page draws it: triangles, texture coordinates, springs
//! and pins, indexed so that the page only has to copy positions each frame.
//!
//! WebGL gives each vertex one texture coordinate, but an OBJ corner can
//! pair a vertex with different `vt`s in different faces (a seam). So the
//! page draws *display vertices*, one per distinct (vertex, `vt`) pair, each
//! knowing the simulated vertex whose position it takes. Faces of three or
//! more corners are fan-triangulated (`a b c d` → `a b c`, `a c d`, as the
//! mass computation does); two-corner faces are springs and draw nothing
//! here (the springs are drawn as lines).

use super::super::draw::look::mass_radius;
use super::facing::{beside_offset, facing_azimuth};
use masssprings::mesh::bounding_box::BoundingBox;
use masssprings::mesh::fan::fan_corners;
use masssprings::mesh::Scene;
use std::collections::HashMap;

/// What `/api/scene` sends: everything about the scene that does not move.
#[derive(Debug, serde::Serialize)]
pub struct DisplayMesh {
    /// The scene's name (`flag`).
    pub name: String,
    /// `"dense"` or `"sparse"`.
    pub backend: &'static str,
    /// Number of simulated vertices (the frame has 3n floats).
    pub n: usize,
    /// Springs as pairs of vertex indices, flattened `[i0, j0, i1, j1, …]`.
    pub springs: Vec<u32>,
    /// Pinned vertices (drawn silver, cannot be dragged).
    pub pinned: Vec<u32>,
    /// For each display vertex, the simulated vertex it shows.
    pub display_vertices: Vec<u32>,
    /// For each display vertex, `(u, v)` flattened; empty without texture.
    pub texture_coords: Vec<f32>,
    /// Triangles over display vertices, flattened `[a0, b0, c0, …]`.
    pub triangles: Vec<u32>,
    /// Where the page gets the texture, when there is one.
    pub texture: Option<&'static str>,
    /// Center and diagonal of the rest shape's bounding box (the camera's
    /// initial target and distance).
    pub center: [f64; 3],
    pub diagonal: f64,
    /// The camera's first azimuth (radians, from `+z` toward `+x`): facing
    /// the cloth as it will hang ([`facing_azimuth`]).
    pub azimuth: f64,
    /// Where a compared simulation is drawn beside the first: its offset
    /// ([`beside_offset`]), to the right for that camera.
    pub beside: [f64; 3],
    /// The point masses' radius in world units (key L), from the mesh
    /// spacing as `render` draws them; 0 for a scene of a few springs,
    /// whose masses keep a fixed size on screen.
    pub mass_radius: f64,
}

/// The path the texture is served at.
pub const TEXTURE_PATH: &str = "/texture.png";

/// Builds the display mesh of `scene`, textured when `textured` (the
/// texture could be read) and the OBJ has texture coordinates.
pub fn display_mesh(scene: &Scene, textured: bool, backend: &'static str) -> DisplayMesh {
    let textured = textured && !scene.face_texture_coords.is_empty();
    let mut display_vertices = Vec::new();
    let mut texture_coords = Vec::new();
    let mut index_of_pair: HashMap<(usize, usize), u32> = HashMap::new();
    // The display vertex of corner `corner` of face `face`, made on first use.
    let mut display_index = |face: usize, corner: usize| -> u32 {
        let vertex = scene.faces[face][corner];
        let uv = if textured {
            scene.face_texture_coords[face][corner]
        } else {
            usize::MAX
        };
        *index_of_pair.entry((vertex, uv)).or_insert_with(|| {
            display_vertices.push(vertex as u32);
            if textured {
                let [u, v] = scene.texture_coords[uv];
                texture_coords.extend([u as f32, v as f32]);
            }
            (display_vertices.len() - 1) as u32
        })
    };
    let mut triangles = Vec::new();
    for (face, corners) in scene.faces.iter().enumerate() {
        for triangle in fan_corners(corners.len()) {
            for corner in triangle {
                triangles.push(display_index(face, corner));
            }
        }
    }
    let bounds = BoundingBox::of(&scene.vertices);
    let (center, diagonal) = (bounds.centre(), bounds.diagonal());
    let azimuth = facing_azimuth(scene);
    DisplayMesh {
        name: scene.name.clone(),
        backend,
        n: scene.vertices.len(),
        springs: scene.springs.iter().flatten().map(|&i| i as u32).collect(),
        pinned: scene.pinned.iter().map(|&i| i as u32).collect(),
        display_vertices,
        texture_coords,
        triangles,
        texture: textured.then_some(TEXTURE_PATH),
        center,
        diagonal,
        azimuth,
        beside: beside_offset(scene, azimuth),
        mass_radius: if scene.faces.first().is_some_and(|f| f.len() >= 3) {
            mass_radius(&scene.vertices, &scene.springs)
        } else {
            0.0
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two quads side by side, `0 1 4 3` and `1 2 5 4`, with a texture seam
    /// on the shared edge (vertex 1 and 4 have two `vt`s each).
    fn two_quads(with_uv: bool) -> Scene {
        let vertices = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [2.0, 1.0, 0.0],
        ];
        let uv: Vec<[f64; 2]> = (0..8).map(|i| [i as f64 / 8.0, 0.5]).collect();
        Scene {
            name: "two".into(),
            vertices,
            faces: vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]],
            texture_coords: if with_uv { uv } else { Vec::new() },
            face_texture_coords: if with_uv {
                vec![vec![0, 1, 2, 3], vec![4, 5, 6, 7]]
            } else {
                Vec::new()
            },
            springs: vec![[0, 1]],
            masses: vec![1.0; 6],
            pinned: vec![0],
            k: 1.0,
            texture: None,
            obj: None,
        }
    }

    #[test]
    fn quads_become_two_fan_triangles_each() {
        let mesh = display_mesh(&two_quads(false), false, "sparse");
        assert_eq!(mesh.triangles, vec![0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2]);
        assert_eq!(mesh.display_vertices, vec![0, 1, 4, 3, 2, 5]);
        assert!(mesh.texture_coords.is_empty());
        assert_eq!(mesh.texture, None);
    }

    #[test]
    fn a_texture_seam_splits_its_vertices() {
        let mesh = display_mesh(&two_quads(true), true, "sparse");
        assert_eq!(mesh.display_vertices, vec![0, 1, 4, 3, 1, 2, 5, 4]);
        assert_eq!(mesh.texture_coords.len(), 2 * 8);
        assert_eq!(mesh.texture, Some(TEXTURE_PATH));
        assert_eq!((mesh.center, mesh.diagonal), ([1.0, 0.5, 0.0], 5f64.sqrt()));
    }
}
