//! Scenes: the assignment's JSON + OBJ files turned into the data the
//! simulation needs, and scenes the project generates itself. This layer
//! knows nothing about solvers.
//!
//! A scene file is a small JSON object naming an OBJ mesh
//! (`data/README.md` is the specification):
//!
//! ```text
//! {"obj": "flag.obj", "k": 1e5, "b": [1, 2, 3], "png": "flag.png"}
//! ```
//!
//! [`load_scene`] reads both files and returns a [`Scene`] ([`load_scene_from`]
//! the same from files held in memory, a browser's): the rest
//! positions `V`, the springs `E`, the masses `m`, the pinned vertices `b`
//! and the stiffness `k`, in the assignment's own order, so a student can
//! match every array with the handout. The steps, one file each:
//!
//! * [`obj`]: the Wavefront OBJ reader (`v`, `vt`, `f`).
//! * `scene_file`: the JSON keys (`obj`, `k`, `b`, `m`, `png`).
//! * [`springs`]: the springs `E` from the faces.
//! * [`voronoi_mass`]: the per-vertex masses from the mesh when `m` is absent
//!   (mixed Voronoi areas, Meyer et al. 2003).
//! * [`procedural`]: scenes written by code (the `grid-N` cloth of the
//!   benchmarks, the five teaching examples) and their textures.
//!
//! Every error names the file (the JSON or the OBJ), the 1-based line when
//! there is one, and the problem: `flag.obj:12: face index 0 ...`.
//!
//! Indices: the files are 1-based (OBJ faces, the JSON's `b`); everything in
//! a [`Scene`] is 0-based. Messages quote indices 1-based, as in the files.

use std::path::{Path, PathBuf};

pub use crate::files::FileError;
use crate::files::{Disk, Source};

pub mod bounding_box;
pub mod fan;
pub mod obj;
pub mod procedural;
mod scene_file;
pub mod springs;
pub mod voronoi_mass;

use obj::ObjMesh;
use scene_file::SceneFile;

/// The eight bytes every PNG file starts with: a scene's texture is read
/// as a PNG (`files::read_bytes_of_format`), for display only.
pub const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Everything the simulation needs from a scene, 0-based.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The JSON file's stem (`flag` for `data/flag.json`).
    pub name: String,
    /// `V`: the rest positions, one per OBJ `v` line, in file order.
    pub vertices: Vec<[f64; 3]>,
    /// The OBJ's faces as 0-based vertex indices (for output and display);
    /// all have the same number of corners.
    pub faces: Vec<Vec<usize>>,
    /// The OBJ's `vt` lines `(u, v)`, for display only.
    pub texture_coords: Vec<[f64; 2]>,
    /// Per face, per corner, a 0-based index into `texture_coords`; empty
    /// when the OBJ's faces do not all carry one.
    pub face_texture_coords: Vec<Vec<usize>>,
    /// `E`: the springs `(i, j)`, in the assignment's order (see [`springs`]).
    pub springs: Vec<[usize; 2]>,
    /// `m`: one mass per vertex, the JSON's `m` if given, else the mixed
    /// Voronoi area of the vertex (see [`voronoi_mass`]).
    pub masses: Vec<f64>,
    /// `b`: the pinned vertices, 0-based, in the JSON's order. A pin listed
    /// twice is kept twice (as the assignment does: `C` then has two rows
    /// for that vertex, and `w CᵀC` counts it twice).
    pub pinned: Vec<usize>,
    /// `k`: the stiffness of every spring.
    pub k: f64,
    /// The `png` texture, resolved relative to the JSON's folder (not opened
    /// here).
    pub texture: Option<PathBuf>,
    /// The OBJ the scene was read from, resolved relative to the JSON's
    /// folder; `None` for a scene made in memory.
    pub obj: Option<PathBuf>,
}

/// Reads the scene file at `json_path` and the OBJ it names.
///
/// The OBJ and the texture are found relative to the JSON's folder. Masses
/// come from `m` when it is given, otherwise from the mesh's mixed Voronoi
/// areas.
///
/// # Errors
/// A [`SceneError`] naming the file, the line when there is one, and the
/// problem, for: a file that cannot be read; invalid JSON, a missing or
/// mistyped key, an unknown key, `bc` (not supported), `k` or `m` not a
/// finite number > 0, a pin that is not a vertex; every problem of the OBJ
/// listed at [`obj::parse_obj`]; a mesh without springs (see
/// [`springs::springs_from_faces`]); `m` absent while the faces are 2-corner
/// springs (no area to take masses from); and, with Voronoi masses, a vertex
/// whose mass is zero or not finite (for example a vertex in no face).
pub fn load_scene(json_path: &Path) -> Result<Scene, SceneError> {
    load_scene_from(&Disk, json_path)
}

/// [`load_scene`] from `files`: the file system ([`Disk`]) or files held
/// in memory ([`InMemory`](crate::files::InMemory)), with the same checks
/// and messages.
///
/// # Errors
/// As [`load_scene`].
pub fn load_scene_from(files: &dyn Source, json_path: &Path) -> Result<Scene, SceneError> {
    let settings = scene_file::read_scene_file(files, json_path)?;
    let folder = json_path.parent().unwrap_or(Path::new(""));
    let obj_path = folder.join(&settings.obj);
    let mesh = obj::read_obj_from(files, &obj_path)?;
    springs::check_spring_memory(&mesh.faces).map_err(|e| e.in_file(&obj_path))?;
    let springs = springs::springs_from_faces(&mesh.faces).map_err(|e| e.in_file(&obj_path))?;
    let masses = masses(&settings, &mesh, json_path, &obj_path)?;
    let pinned =
        pinned_vertices(&settings.b, mesh.vertices.len()).map_err(|e| e.in_file(json_path))?;
    Ok(Scene {
        name: file_stem(json_path),
        vertices: mesh.vertices,
        faces: mesh.faces,
        texture_coords: mesh.texture_coords,
        face_texture_coords: mesh.face_texture_coords,
        springs,
        masses,
        pinned,
        k: settings.k,
        texture: settings.png.map(|png| folder.join(png)),
        obj: Some(obj_path),
    })
}

/// The JSON's `m` for every vertex, or the mesh's mixed Voronoi areas.
fn masses(
    settings: &SceneFile,
    mesh: &ObjMesh,
    json_path: &Path,
    obj_path: &Path,
) -> Result<Vec<f64>, SceneError> {
    if let Some(m) = settings.m {
        return Ok(vec![m; mesh.vertices.len()]);
    }
    if mesh.corners_per_face() < 3 {
        return Err(SceneError::invalid(format!(
            "\"m\" is absent, and the faces of {} are 2-corner springs, which have no area to \
             compute masses from: give \"m\"",
            obj_path.display()
        ))
        .in_file(json_path));
    }
    voronoi_mass::voronoi_masses(&mesh.vertices, &mesh.faces).map_err(|problem| {
        SceneError::invalid(problem.to_string())
            .at_line(mesh.vertex_lines[problem.vertex])
            .in_file(obj_path)
    })
}

/// `b` converted to 0-based vertex indices, duplicates kept.
fn pinned_vertices(one_based: &[u64], vertex_count: usize) -> Result<Vec<usize>, SceneError> {
    one_based
        .iter()
        .enumerate()
        .map(|(position, &pin)| match usize::try_from(pin) {
            Ok(index) if (1..=vertex_count).contains(&index) => Ok(index - 1),
            _ => Err(SceneError::invalid(format!(
                "pin b[{position}] = {pin} is not a vertex: pins are 1-based, in 1..={vertex_count}"
            ))),
        })
        .collect()
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|stem| stem.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// A scene that could not be read: which file (the JSON or the OBJ), which
/// line, and what went wrong (see [`FileError`]).
pub type SceneError = FileError;
