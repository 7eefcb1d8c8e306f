//! Scenes the project generates itself, as the text of their files.
//!
//! * [`grid`]: the `grid-N` cloth of the benchmarks (`../shared/anchors.md`),
//!   byte for byte what the reference tool's `ref grid N` writes.
//! * [`examples`]: our own versions of the assignment's five teaching scenes
//!   (a single spring, a hanging chain, a net, a flag, a skirt), built by
//!   code to play the same roles, with the same vertex counts where it
//!   matters for benchmarks (flag 3,200 vertices, skirt 9,840).
//! * [`textures`]: the flag's design and a tartan, as RGB pixels.
//!
//! A [`GeneratedScene`] holds the mesh and the settings; it writes its OBJ
//! ([`GeneratedScene::write_obj`]) and its JSON ([`GeneratedScene::json_text`]);
//! the application layer puts them (and the PNG texture) on disk.

use std::io::{self, Write};

mod cloth;
mod grid;
mod spring_networks;
pub mod text;
pub mod textures;

pub use cloth::{flag, skirt};
pub use grid::grid;
pub use spring_networks::{horizontal_chain, net, single_spring_horizontal};
pub use textures::RgbImage;

/// A mesh as it will be written, 0-based, faces stored flat.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GeneratedMesh {
    /// `v x y z`.
    pub vertices: Vec<[f64; 3]>,
    /// `vt u v` (may be empty).
    pub texture_coords: Vec<[f64; 2]>,
    /// The number of corners of every face (2 for springs).
    pub corners_per_face: usize,
    /// Face `f` is `faces[f·c .. (f+1)·c]` for `c = corners_per_face`.
    pub faces: Vec<usize>,
    /// The texture coordinate of each face corner, laid out like `faces`;
    /// empty when the mesh has none.
    pub face_texture_coords: Vec<usize>,
}

impl GeneratedMesh {
    /// The number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len() / self.corners_per_face.max(1)
    }
}

/// A texture image and the file name the scene refers to it by.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratedTexture {
    /// `flag.png`: written beside the scene.
    pub file_name: String,
    pub image: RgbImage,
}

/// A scene ready to be written: `NAME.obj`, `NAME.json` and maybe a texture.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratedScene {
    /// The file stem of the scene's files.
    pub name: String,
    /// What the scene shows, written as a comment at the top of the OBJ
    /// (none for `grid-N`, whose files must match the reference tool's).
    /// ASCII, so the files are plain ASCII.
    pub description: Option<String>,
    pub mesh: GeneratedMesh,
    /// `k`.
    pub k: f64,
    /// `m`, or `None` for Voronoi masses.
    pub uniform_mass: Option<f64>,
    /// `b`, 0-based here (written 1-based).
    pub pinned: Vec<usize>,
    pub texture: Option<GeneratedTexture>,
}

impl GeneratedScene {
    /// `NAME.obj`.
    pub fn obj_file_name(&self) -> String {
        format!("{}.obj", self.name)
    }

    /// `NAME.json`.
    pub fn json_file_name(&self) -> String {
        format!("{}.json", self.name)
    }

    /// Writes the OBJ file's text to `out` (streamed: a `grid-1000` OBJ is
    /// about 60 MB).
    ///
    /// # Errors
    /// The first error of `out`.
    pub fn write_obj(&self, out: &mut dyn Write) -> io::Result<()> {
        text::write_obj(&self.mesh, self.description.as_deref(), out)
    }

    /// The OBJ file's text.
    pub fn obj_text(&self) -> String {
        let mut bytes = Vec::new();
        self.write_obj(&mut bytes)
            .expect("writing to memory cannot fail");
        String::from_utf8(bytes).expect("the OBJ text is ASCII")
    }

    /// The JSON scene file's text (one line).
    pub fn json_text(&self) -> String {
        text::scene_json(self)
    }
}

/// The five teaching scenes, in the assignment's order: single spring,
/// horizontal chain, net, flag, skirt.
pub fn examples() -> Vec<GeneratedScene> {
    vec![
        single_spring_horizontal(),
        horizontal_chain(),
        net(),
        flag(),
        skirt(),
    ]
}
