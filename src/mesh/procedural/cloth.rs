//! The two textured cloth scenes: quad meshes with texture coordinates,
//! stiff springs (`k = 1e5`) and Voronoi masses (no `m`: each vertex weighs
//! its share of the cloth's area, so the total mass is the area).
//!
//! * `flag`: 80 × 40 vertices (3,200), a 2 × 1 sheet hanging from its pole:
//!   the 40 vertices of the edge `x = 0` are pinned. It lies in the vertical
//!   plane `z = 0` but for a gentle ripple `z = 0.03 sin(2π x / 0.8)` (zero
//!   at the pole), so that gravity alone folds it instead of letting it sag
//!   in its plane. Texture coordinates stretch the image over the sheet.
//! * `skirt`: a ring of 240 × 41 vertices (9,840), a shallow cone from the
//!   waist (radius 0.3, `y = 0`) out and down to the hem (radius 1.3,
//!   `y = −0.3`); the 240 vertices of the waist are pinned. Like a circle
//!   skirt cut from flat fabric, its texture coordinates are the vertex's
//!   position seen from above, `(u, v) = (0.5 + x/2.6, 0.5 + z/2.6)`, so the
//!   tartan's checks run straight across it.
//!
//! Vertex orders: the flag column by column from the pole, so the pins are
//! vertices 1..=40; the skirt ring by ring from the waist, so the pins are
//! vertices 1..=240. Quads are listed counter-clockwise seen from the side
//! their normal points to (`+z` for the flag, up and out for the skirt).
//!
//! The counts match the assignment's flag (3,200 vertices, 3,081 quads,
//! 12,442 springs) and skirt (9,840 vertices, 9,600 quads), so that these
//! scenes load the solver the same way in benchmarks.
//!
//! Cost: `O(vertices)`.

use std::f64::consts::PI;

use super::textures::{flag_design, tartan};
use super::{example_description, GeneratedMesh, GeneratedScene, GeneratedTexture};

/// The flag scene (texture `flag.png`).
pub fn flag() -> GeneratedScene {
    let (columns, rows) = (80, 40); // along the fly, along the pole
    let (width, height) = (2.0, 1.0);
    let vertex = |column: usize, row: usize| column * rows + row;
    let mut vertices = Vec::with_capacity(columns * rows);
    let mut texture_coords = Vec::with_capacity(columns * rows);
    for column in 0..columns {
        for row in 0..rows {
            let u = column as f64 / (columns - 1) as f64;
            let v = row as f64 / (rows - 1) as f64;
            let x = width * u;
            vertices.push([x, height * v, 0.03 * (2.0 * PI * x / 0.8).sin()]);
            texture_coords.push([u, v]);
        }
    }
    let mut faces = Vec::with_capacity(4 * (columns - 1) * (rows - 1));
    for column in 0..columns - 1 {
        for row in 0..rows - 1 {
            faces.extend([
                vertex(column, row),
                vertex(column + 1, row),
                vertex(column + 1, row + 1),
                vertex(column, row + 1),
            ]);
        }
    }
    textured_cloth(
        "flag",
        "a 2 x 1 flag of 80 x 40 vertices pinned along its pole (x = 0)",
        vertices,
        texture_coords,
        faces,
        (0..rows).map(|row| vertex(0, row)).collect(),
        GeneratedTexture {
            file_name: "flag.png".into(),
            image: flag_design(320, 160),
        },
    )
}

/// The skirt scene (texture `tartan.png`).
pub fn skirt() -> GeneratedScene {
    let (around, rings) = (240, 41);
    let (waist_radius, hem_radius, drop) = (0.3, 1.3, 0.3);
    let vertex = |ring: usize, step: usize| ring * around + step % around;
    let mut vertices = Vec::with_capacity(around * rings);
    let mut texture_coords = Vec::with_capacity(around * rings);
    for ring in 0..rings {
        let t = ring as f64 / (rings - 1) as f64; // 0 at the waist, 1 at the hem
        let radius = waist_radius + t * (hem_radius - waist_radius);
        for step in 0..around {
            let angle = 2.0 * PI * step as f64 / around as f64;
            let (x, z) = (radius * angle.cos(), radius * angle.sin());
            vertices.push([x, 0.0 - drop * t, z]); // 0.0 - …: no "-0" at the waist
            let span = 2.0 * hem_radius;
            texture_coords.push([0.5 + x / span, 0.5 + z / span]);
        }
    }
    let mut faces = Vec::with_capacity(4 * around * (rings - 1));
    for ring in 0..rings - 1 {
        for step in 0..around {
            faces.extend([
                vertex(ring, step),
                vertex(ring, step + 1),
                vertex(ring + 1, step + 1),
                vertex(ring + 1, step),
            ]);
        }
    }
    textured_cloth(
        "skirt",
        "a circle skirt: a ring of 240 x 41 vertices, a shallow cone pinned at its waist",
        vertices,
        texture_coords,
        faces,
        (0..around).map(|step| vertex(0, step)).collect(),
        GeneratedTexture {
            file_name: "tartan.png".into(),
            image: tartan(512),
        },
    )
}

/// A quad cloth whose texture coordinates are numbered like its vertices.
fn textured_cloth(
    name: &str,
    description: &str,
    vertices: Vec<[f64; 3]>,
    texture_coords: Vec<[f64; 2]>,
    faces: Vec<usize>,
    pinned: Vec<usize>,
    texture: GeneratedTexture,
) -> GeneratedScene {
    GeneratedScene {
        name: name.to_string(),
        description: Some(example_description(name, description)),
        mesh: GeneratedMesh {
            vertices,
            texture_coords,
            corners_per_face: 4,
            face_texture_coords: faces.clone(),
            faces,
        },
        k: 1e5,
        uniform_mass: None,
        pinned,
        texture: Some(texture),
    }
}
