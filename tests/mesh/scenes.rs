//! The mesh layer: reading scenes (JSON + OBJ), springs, Voronoi masses,
//! procedural scenes. Every rejection is triggered once and its message
//! checked for the file, the line and the reason.

use crate::common;

use masssprings::files::InMemory;
use masssprings::mesh::fan::fan_triangles;
use masssprings::mesh::procedural::text::format_17_significant;
use masssprings::mesh::procedural::{self, GeneratedScene};
use masssprings::mesh::springs::springs_from_faces;
use masssprings::mesh::voronoi_mass::{triangle_mass_shares, voronoi_masses};
use masssprings::mesh::{load_scene, load_scene_from, Scene, SceneError};
use proptest::prelude::*;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

// ------------------------------------------------------------ helpers --

/// A fresh folder under the system's temporary folder, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> TempDir {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!(
            "masssprings-tests-mesh-{}-{unique}",
            std::process::id()
        ));
        fs::create_dir_all(&path).unwrap();
        TempDir(path)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.0.join(name);
        fs::write(&path, text).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

/// Writes `scene.json` and `mesh.obj` and loads the scene; the same two
/// files held in memory (as a browser's page is given them) must give the
/// same scene or the same message, so every test here checks both readers.
fn load(json: &str, obj: &str) -> Result<Scene, SceneError> {
    let dir = TempDir::new();
    let obj_path = dir.write("mesh.obj", obj);
    let json_path = dir.write("scene.json", json);
    let from_disk = load_scene(&json_path);
    let mut files = InMemory::new();
    files.insert(&json_path, json.as_bytes()).unwrap();
    files.insert(&obj_path, obj.as_bytes()).unwrap();
    let from_memory = load_scene_from(&files, &json_path);
    match (&from_disk, &from_memory) {
        (Ok(disk), Ok(memory)) => assert_eq!(disk, memory, "the scene read from memory"),
        (Err(disk), Err(memory)) => assert_eq!(disk.to_string(), memory.to_string()),
        _ => panic!("from disk: {from_disk:?}; from memory: {from_memory:?}"),
    }
    from_disk
}

fn load_ok(json: &str, obj: &str) -> Scene {
    load(json, obj).unwrap_or_else(|e| panic!("the scene should load: {e}"))
}

/// The error of loading the scene; the test fails if it loads.
fn load_err(json: &str, obj: &str) -> SceneError {
    match load(json, obj) {
        Ok(_) => panic!("the scene should be rejected"),
        Err(error) => error,
    }
}

/// Checks that `error` names `file`, the `line` (or none), and says `reason`.
fn assert_problem(error: &SceneError, file: &str, line: Option<usize>, reason: &str) {
    let message = error.to_string();
    let path = error.path().expect("the error names a file");
    assert_eq!(path.file_name().unwrap(), file, "file in: {message}");
    assert_eq!(error.line(), line, "line in: {message}");
    let place = match line {
        Some(line) => format!("{file}:{line}: "),
        None => format!("{file}: "),
    };
    assert!(message.contains(&place), "`{place}` not in: {message}");
    assert!(message.contains(reason), "`{reason}` not in: {message}");
}

const PIN_FIRST: &str = r#"{"obj": "mesh.obj", "k": 100, "b": [1], "m": 1}"#;
const VORONOI: &str = r#"{"obj": "mesh.obj", "k": 100, "b": [1]}"#;
const UNIT_SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

fn obj_error(obj: &str) -> SceneError {
    load_err(PIN_FIRST, obj)
}

fn json_error(json: &str) -> SceneError {
    load_err(json, UNIT_SQUARE)
}

fn relative_difference(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs())
}

/// The area of a polygon mesh, from cross products of its fan triangles
/// (independent of the Heron formula the masses use).
fn mesh_area(vertices: &[[f64; 3]], faces: &[Vec<usize>]) -> f64 {
    fan_triangles(faces)
        .map(|[a, b, c]| {
            let u = sub(vertices[b], vertices[a]);
            let v = sub(vertices[c], vertices[a]);
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
        })
        .sum()
}

fn sub(p: [f64; 3], q: [f64; 3]) -> [f64; 3] {
    [p[0] - q[0], p[1] - q[1], p[2] - q[2]]
}

// ---------------------------------------------------- OBJ rejections --

#[test]
fn vertex_with_two_numbers_is_rejected_with_its_line() {
    let error = obj_error("v 0 0 0\nv 1 0\nv 1 1 0\nf 1 2 3\n");
    assert_problem(&error, "mesh.obj", Some(2), "needs 3 numbers");
}

#[test]
fn vertex_with_a_word_or_a_non_finite_number_is_rejected() {
    for bad in ["v 0 x 0", "v 0 nan 0", "v inf 0 0", "v 0 0 1e999"] {
        let error = obj_error(&format!("v 0 0 0\n# comment\n{bad}\nv 1 1 0\nf 1 2 3\n"));
        assert_problem(&error, "mesh.obj", Some(3), "is not a finite number");
    }
}

#[test]
fn vertex_with_a_w_value_is_accepted() {
    let scene = load_ok(PIN_FIRST, "v 0 0 0 1\nv 1 0 0 1\nv 1 1 0 1\nf 1 2 3\n");
    assert_eq!(scene.vertices[2], [1.0, 1.0, 0.0]);
}

#[test]
fn malformed_face_corners_are_rejected() {
    for corner in ["1/x", "a", "1/2/3/4", "1.5", "/2"] {
        let error = obj_error(&format!("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 {corner}\n"));
        assert_problem(&error, "mesh.obj", Some(4), "malformed face corner");
    }
}

#[test]
fn face_without_corners_is_rejected() {
    let error = obj_error("v 0 0 0\nv 1 0 0\nf\n");
    assert_problem(&error, "mesh.obj", Some(3), "no corners");
}

#[test]
fn face_of_one_corner_is_rejected() {
    let error = obj_error("v 0 0 0\nv 1 0 0\nf 1\n");
    assert_problem(&error, "mesh.obj", Some(3), "a face of 1 corner");
}

#[test]
fn face_index_zero_is_rejected() {
    let error = obj_error("v 0 0 0\nv 1 0 0\nv 1 1 0\n\nf 1 0 3\n");
    assert_problem(&error, "mesh.obj", Some(5), "index 0");
}

#[test]
fn face_index_beyond_the_vertices_is_rejected() {
    let error = obj_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 2 4\n");
    assert_problem(
        &error,
        "mesh.obj",
        Some(5),
        "vertex index 4 is out of range",
    );
}

#[test]
fn negative_index_before_the_first_vertex_is_rejected() {
    let error = obj_error("v 0 0 0\nv 1 0 0\nf -1 -3 1\nv 1 1 0\n");
    assert_problem(
        &error,
        "mesh.obj",
        Some(3),
        "counts back past the first vertex",
    );
}

#[test]
fn texture_index_beyond_the_texture_coords_is_rejected() {
    let error = obj_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/2\n");
    assert_problem(&error, "mesh.obj", Some(5), "texture coordinate index 2");
}

#[test]
fn mixed_face_sizes_report_the_first_face_that_differs() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3 4\nf 1 2 3\nf 1 2\n";
    let error = obj_error(obj);
    assert_problem(&error, "mesh.obj", Some(7), "this face has 3 corners");
    assert!(error.to_string().contains("have 4 (line 5)"), "{error}");
}

#[test]
fn obj_without_vertices_is_rejected() {
    let error = obj_error("# nothing here\n");
    assert_problem(&error, "mesh.obj", None, "no vertices");
}

#[test]
fn obj_without_faces_has_no_springs_and_is_rejected() {
    let error = obj_error("v 0 0 0\nv 1 0 0\n");
    assert_problem(&error, "mesh.obj", None, "no springs");
}

// --------------------------------------------------- JSON rejections --

#[test]
fn invalid_json_is_rejected_with_serde_line() {
    let error = json_error("{\n  \"obj\": \"mesh.obj\",\n  \"k\": 100\n  \"b\": [1]\n}\n");
    assert_problem(&error, "scene.json", Some(4), "expected `,` or `}`");
}

#[test]
fn missing_key_is_rejected() {
    let error = json_error("{\"obj\": \"mesh.obj\",\n \"b\": [1]}");
    assert_problem(&error, "scene.json", Some(2), "missing field `k`");
}

#[test]
fn mistyped_keys_are_rejected_naming_the_key() {
    let cases = [
        (
            "{\"obj\": \"mesh.obj\",\n\"k\": \"100\", \"b\": [1]}",
            "\"k\"",
        ),
        ("{\n\"obj\": 3, \"k\": 100, \"b\": [1]}", "\"obj\""),
        (
            "{\"obj\": \"mesh.obj\",\n\"k\": 100, \"b\": [1], \"m\": [1]}",
            "\"m\"",
        ),
        (
            "{\"obj\": \"mesh.obj\",\n\"k\": 100, \"b\": [1], \"png\": 1}",
            "\"png\"",
        ),
        (
            "{\"obj\": \"mesh.obj\",\n\"k\": 100, \"b\": [1.5]}",
            "\"b\"",
        ),
        (
            "{\"obj\": \"mesh.obj\",\n\"k\": 100, \"b\": 1}",
            "a sequence",
        ),
    ];
    for (json, key) in cases {
        let error = json_error(json);
        assert_problem(&error, "scene.json", Some(2), "invalid type");
        assert!(error.to_string().contains(key), "{key} not in: {error}");
    }
}

#[test]
fn top_level_that_is_not_an_object_is_rejected() {
    let error = json_error("[1, 2]");
    assert_problem(&error, "scene.json", Some(1), "expected a scene");
}

#[test]
fn unknown_key_is_rejected() {
    let error = json_error("{\"obj\": \"mesh.obj\", \"k\": 100,\n \"b\": [1],\n \"kk\": 3}");
    assert_problem(&error, "scene.json", Some(3), "unknown field `kk`");
}

#[test]
fn repeated_key_is_rejected() {
    let error = json_error("{\"obj\": \"mesh.obj\", \"k\": 100,\n \"b\": [1], \"k\": 3}");
    assert_problem(&error, "scene.json", Some(2), "duplicate field `k`");
}

#[test]
fn boundary_conditions_bc_are_refused_clearly() {
    let error = json_error("{\"obj\": \"mesh.obj\", \"k\": 100, \"b\": [1],\n \"bc\": [[1, 0]]}");
    assert_problem(
        &error,
        "scene.json",
        Some(2),
        "boundary conditions \"bc\" are not supported",
    );
}

#[test]
fn pin_zero_or_negative_is_rejected_with_its_line() {
    for pin in ["0", "-2"] {
        let error = json_error(&format!(
            "{{\"obj\": \"mesh.obj\", \"k\": 100,\n \"b\": [1, {pin}]}}"
        ));
        assert_problem(&error, "scene.json", Some(2), "1-based vertex index");
    }
}

#[test]
fn pin_beyond_the_vertices_is_rejected() {
    let error = json_error(r#"{"obj": "mesh.obj", "k": 100, "b": [1, 5]}"#);
    assert_problem(&error, "scene.json", None, "pin b[1] = 5 is not a vertex");
    assert!(error.to_string().contains("1..=4"), "{error}");
}

#[test]
fn stiffness_and_mass_must_be_finite_and_positive() {
    let cases = [
        ("\"k\": 0, \"b\": [1]", "\"k\""),
        ("\"k\": -1e3, \"b\": [1]", "\"k\""),
        ("\"k\": 10, \"m\": 0, \"b\": [1]", "\"m\""),
        ("\"k\": 10, \"m\": -0.5, \"b\": [1]", "\"m\""),
    ];
    for (keys, key) in cases {
        let error = json_error(&format!("{{\"obj\": \"mesh.obj\",\n {keys}}}"));
        assert_problem(&error, "scene.json", Some(2), "a finite number > 0");
        assert!(error.to_string().contains(key), "{key} not in: {error}");
    }
    // JSON has no infinity; a number too large for f64 is refused by the parser.
    let error = json_error("{\"obj\": \"mesh.obj\",\n \"k\": 1e999, \"b\": [1]}");
    assert_problem(&error, "scene.json", Some(2), "number out of range");
}

#[test]
fn missing_obj_file_is_named() {
    let dir = TempDir::new();
    let json = dir.write("scene.json", r#"{"obj": "nowhere.obj", "k": 1, "b": []}"#);
    let error = load_scene(&json).unwrap_err();
    assert_problem(&error, "nowhere.obj", None, "cannot read the file");
    assert!(error.io_error().is_some());
    assert_eq!(error.path(), Some(dir.0.join("nowhere.obj").as_path()));
}

#[test]
fn a_file_not_given_to_the_page_is_named_as_a_missing_one() {
    let mut files = InMemory::new();
    files
        .insert(Path::new("scene.json"), PIN_FIRST.as_bytes())
        .unwrap();
    let error = load_scene_from(&files, Path::new("scene.json")).unwrap_err();
    assert_problem(&error, "mesh.obj", None, "cannot read the file");
    assert!(error.io_error().is_some());
}

#[test]
fn the_bundled_scenes_read_from_memory_are_the_scenes_read_from_disk() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    for name in [
        "flag",
        "skirt",
        "net",
        "horizontal-chain",
        "single-spring-horizontal",
    ] {
        let json = data.join(format!("{name}.json"));
        let from_disk = load_scene(&json).unwrap();
        let mut files = InMemory::new();
        for path in [
            Some(&json),
            from_disk.obj.as_ref(),
            from_disk.texture.as_ref(),
        ] {
            let path = path.unwrap_or(&json);
            files.insert(path, &fs::read(path).unwrap()).unwrap();
        }
        assert_eq!(load_scene_from(&files, &json).unwrap(), from_disk, "{name}");
    }
}

#[test]
fn missing_scene_file_is_named() {
    let error = load_scene(Path::new("/nonexistent/folder/scene.json")).unwrap_err();
    assert_problem(&error, "scene.json", None, "cannot read the file");
}

// ------------------------------------------------- mass rejections --

#[test]
fn unreferenced_vertex_without_m_is_rejected_naming_it() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\n# a stray vertex\nv 5 5 5\nf 1 2 3\n";
    let error = load_err(VORONOI, obj);
    assert_problem(&error, "mesh.obj", Some(5), "vertex 4 has zero mass");
    // with a uniform mass the same mesh is fine
    assert_eq!(load_ok(PIN_FIRST, obj).masses, vec![1.0; 4]);
}

#[test]
fn degenerate_face_without_m_gives_a_non_finite_mass_and_is_rejected() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 1 2\nf 1 2 3\n";
    let error = load_err(VORONOI, obj);
    assert_problem(
        &error,
        "mesh.obj",
        Some(1),
        "vertex 1 has a non-finite mass",
    );
}

#[test]
fn springs_without_m_are_rejected_in_the_scene_file() {
    let error = load_err(VORONOI, "v 0 0 0\nv 1 0 0\nf 1 2\n");
    assert_problem(&error, "scene.json", None, "2-corner springs");
}

// ---------------------------------------------------------- accepted --

#[test]
fn decorated_obj_loads_like_the_plain_one() {
    let plain = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0.25\nv 2 1 0.25\n\
                 f 1 2 3 4\nf 2 5 6 3\n";
    let decorated = "# a comment\r\nmtllib cloth.mtl\r\no cloth\r\ng part\r\n\
                     v 0 0 0\r\nv 1 0 0   # trailing comment\r\nv 1 1 0\r\nv 0 1 0\r\n\
                     vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvn 0 0 1\r\n\r\n  \r\n\
                     usemtl red\r\ns off\r\n\
                     f 1/1/1 2/2/1 -2/3/1 4//1\r\n\
                     v 2 0 0.25\r\nv\t2 1 0.25\r\nf -5//1 -2 6/1 -4\r\n";
    let plain_scene = load_ok(VORONOI, plain);
    let decorated_scene = load_ok(VORONOI, decorated);
    assert_eq!(decorated_scene.vertices, plain_scene.vertices);
    assert_eq!(decorated_scene.faces, plain_scene.faces);
    assert_eq!(decorated_scene.springs, plain_scene.springs);
    assert_eq!(decorated_scene.masses, plain_scene.masses);
    assert_eq!(decorated_scene.pinned, plain_scene.pinned);
    // only some corners have a texture index: none are kept
    assert!(decorated_scene.face_texture_coords.is_empty());
    assert_eq!(decorated_scene.texture_coords.len(), 3);
}

#[test]
fn texture_indices_are_kept_when_every_corner_has_one() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0.5 1\nf 1/1 2/2 3/-1\n";
    let scene = load_ok(PIN_FIRST, obj);
    assert_eq!(scene.face_texture_coords, vec![vec![0, 1, 2]]);
    assert_eq!(scene.texture_coords[2], [0.5, 1.0]);
}

#[test]
fn scene_fields_follow_the_files() {
    let dir = TempDir::new();
    fs::create_dir_all(dir.0.join("meshes")).unwrap();
    dir.write("meshes/square.obj", UNIT_SQUARE);
    let json = r#"{"obj": "meshes/square.obj", "k": 2.5e3, "b": [4, 1, 4], "png": "cloth.png"}"#;
    let scene = load_scene(&dir.write("cloth.json", json)).unwrap();
    assert_eq!(scene.name, "cloth");
    assert_eq!(scene.k, 2500.0);
    assert_eq!(
        scene.pinned,
        vec![3, 0, 3],
        "pins 0-based, in order, repeats kept"
    );
    assert_eq!(scene.texture, Some(dir.0.join("cloth.png")));
    assert_eq!(scene.faces, vec![vec![0, 1, 2, 3]]);
    assert_eq!(scene.masses.iter().sum::<f64>(), 1.0);
}

#[test]
fn error_displays_as_path_line_problem() {
    let error = obj_error("v 0 0 0\nf 1 0\n");
    let message = error.to_string();
    let path = error.path().unwrap().display().to_string();
    assert!(message.starts_with(&format!("{path}:2: ")), "{message}");
}

// ------------------------------------------------------------ springs --

#[test]
fn a_quad_gives_its_four_sides_and_two_diagonals() {
    let springs = springs_from_faces(&[vec![0, 1, 2, 3]]).unwrap();
    assert_eq!(
        springs,
        vec![[0, 1], [0, 2], [1, 2], [0, 3], [1, 3], [2, 3]]
    );
}

#[test]
fn two_quads_sharing_an_edge_give_eleven_springs() {
    let springs = springs_from_faces(&[vec![0, 1, 4, 3], vec![1, 2, 5, 4]]).unwrap();
    assert_eq!(springs.len(), 11);
}

#[test]
fn two_corner_faces_keep_file_order_and_duplicates() {
    let faces = vec![vec![2, 0], vec![0, 1], vec![2, 0], vec![1, 1]];
    let springs = springs_from_faces(&faces).unwrap();
    assert_eq!(springs, vec![[2, 0], [0, 1], [2, 0], [1, 1]]);
}

#[test]
fn polygon_springs_come_in_column_major_order_of_the_adjacency_matrix() {
    // Pairs: face 1 gives {1,3}, {3,4}, {1,4}; face 2 gives {1,5}, {0,1}, {0,5}.
    // Column by column (the larger index), rows ascending:
    // column 1: (0,1); column 3: (1,3); column 4: (1,4), (3,4); column 5: (0,5), (1,5).
    let springs = springs_from_faces(&[vec![3, 1, 4], vec![1, 5, 0]]).unwrap();
    assert_eq!(
        springs,
        vec![[0, 1], [1, 3], [1, 4], [3, 4], [0, 5], [1, 5]]
    );
}

#[test]
fn repeated_corners_give_no_self_spring_and_no_duplicate() {
    let springs = springs_from_faces(&[vec![0, 1, 0, 2]]).unwrap();
    assert_eq!(springs, vec![[0, 1], [0, 2], [1, 2]]);
}

#[test]
fn polygons_of_one_repeated_vertex_give_no_springs() {
    let error = springs_from_faces(&[vec![2, 2, 2]]).unwrap_err();
    assert!(error.to_string().contains("no springs"), "{error}");
}

// ------------------------------------------------------ Voronoi masses --

/// Meyer et al.'s Voronoi area of each corner of a non-obtuse triangle:
/// `(|PQ|² cot R + |PR|² cot Q) / 8` for corner P and the other two Q, R.
fn cotangent_voronoi_areas(p: [[f64; 3]; 3]) -> [f64; 3] {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cot = |at: usize| {
        let (u, v) = (sub(p[(at + 1) % 3], p[at]), sub(p[(at + 2) % 3], p[at]));
        let cos = dot(u, v);
        let sin = (dot(u, u) * dot(v, v) - cos * cos).sqrt();
        cos / sin
    };
    let squared = |a: usize, b: usize| dot(sub(p[a], p[b]), sub(p[a], p[b]));
    [0, 1, 2].map(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        (squared(i, j) * cot(k) + squared(i, k) * cot(j)) / 8.0
    })
}

fn assert_shares(actual: [f64; 3], expected: [f64; 3]) {
    for (a, e) in actual.iter().zip(expected) {
        assert!(
            (a - e).abs() <= 1e-14 * e.abs().max(1.0),
            "{actual:?} != {expected:?}"
        );
    }
}

#[test]
fn right_triangle_gives_half_to_the_right_angle_and_a_quarter_to_the_others() {
    // legs 3 and 4, area 6; the circumcenter is the middle of the hypotenuse
    let p = [[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
    assert_shares(triangle_mass_shares(p), [3.0, 1.5, 1.5]);
    assert_shares(cotangent_voronoi_areas(p), [3.0, 1.5, 1.5]);
}

#[test]
fn obtuse_triangle_gives_half_to_the_obtuse_corner() {
    // angle at (1, 1) is obtuse: (−1,−1)·(3,−1) = −2 < 0; area = 4·1/2 = 2
    let p = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
    assert_shares(triangle_mass_shares(p), [0.5, 0.5, 1.0]);
}

#[test]
fn equilateral_triangle_gives_a_third_to_each_corner() {
    let h = 3f64.sqrt();
    let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, h, 0.0]];
    let third = h / 3.0; // area √3, split evenly
    assert_shares(triangle_mass_shares(p), [third; 3]);
}

#[test]
fn acute_triangle_matches_the_cotangent_formula() {
    let p = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [1.0, 3.0, 0.5]];
    assert_shares(triangle_mass_shares(p), cotangent_voronoi_areas(p));
}

#[test]
fn fan_triangulated_quad_masses_sum_to_its_area() {
    // a trapezoid: parallel sides 4 and 2, height 1.5, area 4.5
    let vertices = [
        [0.0, 0.0, 0.0],
        [4.0, 0.0, 0.0],
        [3.0, 1.5, 0.0],
        [1.0, 1.5, 0.0],
    ];
    let faces = vec![vec![0, 1, 2, 3]];
    let triangles: Vec<[usize; 3]> = fan_triangles(&faces).collect();
    assert_eq!(triangles, vec![[0, 1, 2], [0, 2, 3]]);
    let masses = voronoi_masses(&vertices, &faces).unwrap();
    assert!((masses.iter().sum::<f64>() - 4.5).abs() < 1e-14);
}

#[test]
fn pentagon_fans_from_its_first_corner() {
    let triangles: Vec<[usize; 3]> = fan_triangles(&[vec![5, 6, 7, 8, 9]]).collect();
    assert_eq!(triangles, vec![[5, 6, 7], [5, 7, 8], [5, 8, 9]]);
}

/// A `columns × rows` grid of quads with each vertex moved by up to a third
/// of the spacing (in x, y and z), so every triangle is non-degenerate.
fn perturbed_grid() -> impl Strategy<Value = (Vec<[f64; 3]>, Vec<Vec<usize>>)> {
    (2usize..8, 2usize..8).prop_flat_map(|(columns, rows)| {
        prop::collection::vec(prop::array::uniform3(-0.33f64..0.33), columns * rows).prop_map(
            move |offsets| {
                let vertex = |i: usize, j: usize| j * columns + i;
                let vertices = offsets
                    .iter()
                    .enumerate()
                    .map(|(v, d)| {
                        let (i, j) = ((v % columns) as f64, (v / columns) as f64);
                        [i + d[0], j + d[1], d[2]]
                    })
                    .collect();
                let mut faces = Vec::new();
                for j in 0..rows - 1 {
                    for i in 0..columns - 1 {
                        faces.push(vec![
                            vertex(i, j),
                            vertex(i + 1, j),
                            vertex(i + 1, j + 1),
                            vertex(i, j + 1),
                        ]);
                    }
                }
                (vertices, faces)
            },
        )
    })
}

proptest! {
    #![proptest_config(common::proptest_config(256))]

    #[test]
    fn total_voronoi_mass_equals_total_area((vertices, faces) in perturbed_grid()) {
        let masses = voronoi_masses(&vertices, &faces).unwrap();
        let total: f64 = masses.iter().sum();
        let area = mesh_area(&vertices, &faces);
        prop_assert!(relative_difference(total, area) <= 1e-12, "{} vs {}", total, area);
        prop_assert!(masses.iter().all(|&m| m > 0.0));
    }
}

// ---------------------------------------- the assignment's own scenes --

/// `../shared/original-data/NAME.json`, or `None` (and a visible note) when
/// the shared folder is not there.
fn original_scene(name: &str) -> Option<Scene> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/original-data");
    if !folder.is_dir() {
        println!("skipped: ../shared not found ({})", folder.display());
        return None;
    }
    Some(load_scene(&folder.join(format!("{name}.json"))).unwrap())
}

/// Springs listed by column (larger index) then row, each pair once.
fn assert_column_major(springs: &[[usize; 2]]) {
    for s in springs {
        assert!(s[0] < s[1], "{s:?}");
    }
    for w in springs.windows(2) {
        assert!((w[0][1], w[0][0]) < (w[1][1], w[1][0]), "{w:?}");
    }
}

#[test]
fn original_flag_has_the_assignments_counts_and_masses() {
    let Some(flag) = original_scene("flag") else {
        return;
    };
    assert_eq!(flag.vertices.len(), 3200);
    assert_eq!(flag.faces.len(), 3081);
    assert!(flag.faces.iter().all(|f| f.len() == 4));
    assert_eq!(flag.springs.len(), 12442);
    assert_eq!(flag.pinned, (0..40).collect::<Vec<_>>());
    assert_eq!(flag.k, 1e5);
    assert_column_major(&flag.springs);
    // `ref info` reports: sum 2, min 0.000162285, max 0.00064914
    let total: f64 = flag.masses.iter().sum();
    assert!(relative_difference(total, 2.0) < 1e-12, "{total}");
    assert!(relative_difference(total, mesh_area(&flag.vertices, &flag.faces)) < 1e-12);
    let min = flag.masses.iter().copied().fold(f64::INFINITY, f64::min);
    let max = flag.masses.iter().copied().fold(0.0, f64::max);
    assert!(relative_difference(min, 0.000162285) < 1e-5, "{min}");
    assert!(relative_difference(max, 0.00064914) < 1e-5, "{max}");
    assert_eq!(flag.texture_coords.len(), 3200);
    assert_eq!(flag.face_texture_coords.len(), 3081);
    assert_eq!(flag.texture.unwrap().file_name().unwrap(), "flag.png");
}

#[test]
fn original_skirt_has_the_assignments_counts_and_masses() {
    let Some(skirt) = original_scene("skirt") else {
        return;
    };
    assert_eq!(skirt.vertices.len(), 9840);
    assert_eq!(skirt.faces.len(), 9600);
    assert_eq!(skirt.springs.len(), 38640);
    assert_eq!(skirt.pinned.len(), 240);
    assert_column_major(&skirt.springs);
    let total: f64 = skirt.masses.iter().sum();
    assert!(relative_difference(total, mesh_area(&skirt.vertices, &skirt.faces)) < 1e-12);
    assert!(relative_difference(total, 5.02597) < 1e-5, "{total}");
    assert_eq!(skirt.texture.unwrap().file_name().unwrap(), "tartan.png");
}

#[test]
fn original_spring_scenes_keep_their_springs_in_file_order() {
    let Some(chain) = original_scene("horizontal-chain") else {
        return;
    };
    assert_eq!(chain.vertices.len(), 10);
    assert_eq!(
        chain.springs,
        (0..9).map(|i| [i, i + 1]).collect::<Vec<_>>()
    );
    assert_eq!(chain.pinned, vec![0, 9]);
    assert_eq!(chain.masses, vec![1.0; 10]);
    let single = original_scene("single-spring-horizontal").unwrap();
    assert_eq!(single.springs, vec![[0, 1]]);
    assert_eq!(single.pinned, vec![0]);
    let net = original_scene("net").unwrap();
    assert_eq!((net.vertices.len(), net.springs.len()), (61, 156));
    assert_eq!(net.pinned, vec![0, 4, 34, 60, 56, 26]);
    assert_eq!(net.k, 300.0);
}

// ------------------------------------------------------- generated scenes --

/// Writes a generated scene (and an empty stand-in for its texture) into a
/// temporary folder and loads it back.
fn write_and_load(scene: &GeneratedScene) -> Scene {
    let dir = TempDir::new();
    dir.write(&scene.obj_file_name(), &scene.obj_text());
    let json = dir.write(&scene.json_file_name(), &scene.json_text());
    load_scene(&json).unwrap_or_else(|e| panic!("{}: {e}", scene.name))
}

#[test]
fn seventeen_digit_numbers_read_like_printf() {
    let cases = [
        (0.0, "0"),
        (1.0, "1"),
        (10000.0, "10000"),
        (0.0625, "0.0625"),
        (0.1, "0.10000000000000001"),
        (1.0 / 3.0, "0.33333333333333331"),
        (2.0 / 3.0, "0.66666666666666663"),
        (1.0 - 1.0 / 3.0, "0.66666666666666674"),
        (1e-5, "1.0000000000000001e-05"),
        (1.0 / (316.0 * 316.0), "1.00144207659029e-05"),
        (0.0001, "0.0001"),
        (1e17, "1e+17"),
        (-2.5, "-2.5"),
    ];
    for (value, text) in cases {
        assert_eq!(format_17_significant(value), text);
        assert_eq!(text.parse::<f64>().unwrap(), value);
    }
}

#[test]
fn grid_files_have_the_reference_layout() {
    let grid = procedural::grid(4);
    assert_eq!(
        grid.json_text(),
        "{\"obj\":\"grid-4.obj\",\"k\":10000,\"m\":0.0625,\"b\":[1,4]}\n"
    );
    let obj = grid.obj_text();
    let lines: Vec<&str> = obj.lines().collect();
    assert_eq!(lines.len(), 16 + 9);
    assert_eq!(lines[0], "v 0 1 0");
    assert_eq!(lines[1], "v 0.33333333333333331 1 0");
    assert_eq!(lines[4], "v 0 0.66666666666666674 0");
    assert_eq!(lines[16], "f 1 5 6 2");
    assert_eq!(lines[24], "f 11 15 16 12");
}

#[test]
fn grid_scene_has_the_anchor_structure() {
    for n in [2, 5, 32] {
        let scene = write_and_load(&procedural::grid(n));
        assert_eq!(scene.name, format!("grid-{n}"));
        assert_eq!(scene.vertices.len(), n * n);
        assert_eq!(scene.faces.len(), (n - 1) * (n - 1));
        assert_eq!(scene.springs.len(), 2 * n * (n - 1) + 2 * (n - 1) * (n - 1));
        assert_eq!(scene.pinned, vec![0, n - 1]);
        assert_eq!(scene.k, 1e4);
        assert!(scene.masses.iter().all(|&m| m == 1.0 / (n * n) as f64));
        assert_eq!(scene.vertices[n - 1], [1.0, 1.0, 0.0]);
        assert_eq!(scene.vertices[n * n - 1], [1.0, 0.0, 0.0]);
        assert_column_major(&scene.springs);
    }
}

#[test]
fn example_scenes_load_with_their_intended_shape() {
    // name, vertices, faces, springs, pins, uniform mass?
    let expected = [
        ("single-spring-horizontal", 2, 1, 1, 1, true),
        ("horizontal-chain", 11, 10, 10, 2, true),
        ("net", 81, 144, 144, 8, true),
        ("flag", 3200, 3081, 12442, 40, false),
        ("skirt", 9840, 9600, 38640, 240, false),
    ];
    let examples = procedural::examples();
    assert_eq!(examples.len(), expected.len());
    for (generated, (name, vertices, faces, springs, pins, uniform)) in
        examples.iter().zip(expected)
    {
        let scene = write_and_load(generated);
        assert_eq!(scene.name, name);
        assert_eq!(scene.vertices.len(), vertices, "{name}");
        assert_eq!(scene.faces.len(), faces, "{name}");
        assert_eq!(scene.springs.len(), springs, "{name}");
        assert_eq!(scene.pinned.len(), pins, "{name}");
        assert!(
            scene.masses.iter().all(|&m| m.is_finite() && m > 0.0),
            "{name}"
        );
        if uniform {
            assert!(scene.masses.iter().all(|&m| m == 1.0), "{name}");
        } else {
            let total: f64 = scene.masses.iter().sum();
            let area = mesh_area(&scene.vertices, &scene.faces);
            assert!(
                relative_difference(total, area) < 1e-12,
                "{name}: {total} vs {area}"
            );
            assert_eq!(scene.face_texture_coords.len(), faces, "{name}");
            assert!(scene.texture.is_some(), "{name}");
            let all_in_unit_square = scene
                .texture_coords
                .iter()
                .all(|t| t.iter().all(|&c| (-1e-12..=1.0 + 1e-12).contains(&c)));
            assert!(all_in_unit_square, "{name}");
        }
    }
}

#[test]
fn example_pins_hold_what_they_should() {
    let flag = write_and_load(&procedural::flag());
    assert!(
        flag.pinned.iter().all(|&p| flag.vertices[p][0] == 0.0),
        "the pole"
    );
    let skirt = write_and_load(&procedural::skirt());
    for &p in &skirt.pinned {
        let [x, y, z] = skirt.vertices[p];
        assert!((x.hypot(z) - 0.3).abs() < 1e-12 && y == 0.0, "the waist");
    }
    let chain = write_and_load(&procedural::horizontal_chain());
    assert_eq!(chain.pinned, vec![0, 10]);
}

#[test]
fn textures_have_their_sizes_and_the_tartan_tiles() {
    let flag = procedural::flag().texture.unwrap();
    assert_eq!(flag.file_name, "flag.png");
    assert_eq!((flag.image.width, flag.image.height), (320, 160));
    assert_eq!(flag.image.pixels.len(), 320 * 160 * 3);
    let tartan = procedural::skirt().texture.unwrap();
    assert_eq!(tartan.file_name, "tartan.png");
    let image = tartan.image;
    assert_eq!(
        (image.width, image.height, image.pixels.len()),
        (512, 512, 512 * 512 * 3)
    );
    for (x, y) in [(0, 0), (17, 301), (200, 5), (383, 383)] {
        assert_eq!(image.pixel(x, y), image.pixel(x + 128, y), "repeats across");
        assert_eq!(image.pixel(x, y), image.pixel(x, y + 128), "repeats down");
    }
}

#[test]
fn bundled_data_is_what_the_generator_writes() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    for scene in procedural::examples() {
        let obj = fs::read_to_string(data.join(scene.obj_file_name())).unwrap();
        let json = fs::read_to_string(data.join(scene.json_file_name())).unwrap();
        assert!(
            obj == scene.obj_text(),
            "data/{} is stale: run `masssprings generate examples --out data`",
            scene.obj_file_name()
        );
        assert_eq!(
            json,
            scene.json_text(),
            "data/{} is stale",
            scene.json_file_name()
        );
    }
}

#[test]
fn a_generated_scene_in_memory_is_the_scene_its_files_load_as() {
    let mut scenes = vec![procedural::grid(2), procedural::grid(7)];
    scenes.extend(procedural::examples());
    for generated in scenes {
        let mut from_files = write_and_load(&generated);
        let in_memory = generated.to_scene().unwrap();
        from_files.texture = None; // nothing was written for it to name
        from_files.obj = None; // a scene in memory was read from no file
        assert_eq!(in_memory, from_files, "{}", generated.name);
    }
}
