//! Hostile input (issue 9): every case the issue lists, through the command
//! line as a user meets it (exit code, message, nothing written), and a
//! seeded mutation test of the readers (Matrix Market, scene JSON + OBJ)
//! over the bundled scenes of `data/` and the corpus in `tests/hostile/`:
//! thousands of damaged files, each read to a value or to an error that
//! names the file and, for a problem on a line, the line. (The PNG texture
//! and the HTTP request parser live in the binary; their mutation tests are
//! unit tests in `src/app/render/texture.rs` and `src/app/view/http.rs`.)
#[path = "common/cli.rs"]
mod cli;
#[path = "common/mutate.rs"]
mod mutate;

use cli::{data, temp_folder};
use masssprings::files::FileError;
use masssprings::linalg::matrix_market::{self, write_array, write_coordinate, Symmetry};
use masssprings::linalg::sparse::TripletMatrix;
use masssprings::mesh::load_scene;
use mutate::{mutate, Rng};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Once;
use std::time::{Duration, Instant};

/// The memory limit of the children (GB): fixed, so that the outcomes do
/// not depend on how much memory the machine has free right now; every
/// case of the issue needs far more.
const CHILD_LIMIT_GB: &str = "4";

/// The memory limit of this test process (GB), set before the library
/// reads it: small, so no mutated size line can make a test allocate much.
const OWN_LIMIT_GB: &str = "0.05";

fn small_own_limit() {
    static SET: Once = Once::new();
    // Every test calls this first, before any library call reads the
    // environment.
    SET.call_once(|| std::env::set_var(masssprings::memory::LIMIT_VARIABLE, OWN_LIMIT_GB));
}

/// Runs the binary with the children's memory limit.
fn run(args: &[&str]) -> Output {
    run_with_limit(args, CHILD_LIMIT_GB)
}

fn run_with_limit(args: &[&str], limit_gb: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(args)
        .env(masssprings::memory::LIMIT_VARIABLE, limit_gb)
        .output()
        .expect("the binary runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The path of a file of the hostile corpus.
fn corpus(name: &str) -> String {
    corpus_path(name).display().to_string()
}

fn corpus_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/hostile")
        .join(name)
}

/// Asserts a clean failure: exit code 1 (no panic, no abort) and every
/// piece of `expected` in the message.
fn assert_fails(output: &Output, expected: &[&str]) {
    let message = stderr(output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(!message.contains("panicked"), "{message}");
    for piece in expected {
        assert!(message.contains(piece), "`{piece}` not in: {message}");
    }
}

fn names_in(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = match std::fs::read_dir(folder) {
        Ok(entries) => entries
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    };
    names.sort();
    names
}

// ------------------------------------------ 1. silent wrong answers --

#[test]
fn a_general_matrix_that_is_not_symmetric_is_refused_on_the_line_of_the_entry() {
    let output = run(&["analyze", &corpus("general-not-symmetric.mtx")]);
    assert_fails(
        &output,
        &[
            "general-not-symmetric.mtx:4:",
            "declared `general` but is not symmetric",
            "entry (1, 2) = 100",
            "(2, 1) = 0",
            "1e-12",
        ],
    );
    let symmetric = run(&["analyze", &corpus("general-symmetric.mtx"), "--json"]);
    assert!(symmetric.status.success(), "{}", stderr(&symmetric));
    let report: serde_json::Value =
        serde_json::from_slice(&symmetric.stdout).expect("one JSON object");
    assert_eq!(report["n"], 2);
    assert_eq!(report["nnz_a"], 3, "the lower triangle of the full matrix");
    assert!(report["residual"].as_f64().unwrap() < 1e-14);
}

#[test]
fn the_symmetry_tolerance_is_relative() {
    small_own_limit();
    let text = |mirror: &str| {
        format!(
            "%%MatrixMarket matrix coordinate real general\n2 2 4\n1 1 4e6\n2 1 1e6\n1 2 {mirror}\n2 2 4e6\n"
        )
    };
    assert!(matrix_market::parse_symmetric(&text("1.0000000000001e6")).is_ok());
    let error = matrix_market::parse_symmetric(&text("1.000001e6")).unwrap_err();
    assert_eq!(error.line(), Some(4), "{error}");
}

#[test]
fn a_byte_order_mark_is_skipped_by_every_text_reader() {
    // The OBJ's first vertex is kept: 3 vertices, the spring (1, 2).
    let output = run(&["simulate", &corpus("bom.json"), "--steps", "1", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(
        (summary["n"].as_u64(), summary["springs"].as_u64()),
        (Some(3), Some(1))
    );
    small_own_limit();
    let scene = load_scene(&corpus_path("bom.json")).unwrap();
    assert_eq!(scene.vertices[0], [0.0, 0.0, 0.0]);
    assert_eq!(scene.springs, [[0, 1]]);
    let analyzed = run(&["analyze", &corpus("bom.mtx"), "--json"]);
    assert!(analyzed.status.success(), "{}", stderr(&analyzed));
}

// ------------------------------------ 2. declared sizes and memory --

#[test]
fn a_tiny_matrix_file_declaring_huge_sizes_is_refused_at_its_size_line() {
    let rows = run(&["analyze", &corpus("declares-2147483648-rows.mtx")]);
    assert_fails(
        &rows,
        &[
            "declares-2147483648-rows.mtx:2:",
            "n = 2147483648 needs at least 2147483648 entries",
        ],
    );
    let entries = run(&["analyze", &corpus("declares-100000000-entries.mtx")]);
    assert_fails(
        &entries,
        &[
            "declares-100000000-entries.mtx:2:",
            "declares 100000000 entries, but a file of",
        ],
    );
    // The plain reader (any matrix) refuses the memory of 2³¹ columns.
    small_own_limit();
    let error = matrix_market::read(&corpus_path("declares-2147483648-rows.mtx")).unwrap_err();
    assert_eq!(error.line(), Some(2), "{error}");
    assert!(error.to_string().contains("would need"), "{error}");
    let array = matrix_market::read(&corpus_path("array-declares-too-much.mtx")).unwrap_err();
    assert!(
        array.to_string().contains("declares 10000000000 values"),
        "{array}"
    );
}

#[test]
fn one_face_of_20000_corners_is_refused_before_its_springs_are_made() {
    let folder = temp_folder("polygon");
    let mut obj = String::new();
    for i in 0..20_000 {
        let angle = i as f64 * 1e-4;
        obj.push_str(&format!("v {} {} 0\n", angle.cos(), angle.sin()));
    }
    obj.push('f');
    for i in 1..=20_000 {
        obj.push_str(&format!(" {i}"));
    }
    obj.push('\n');
    std::fs::write(folder.join("polygon.obj"), obj).unwrap();
    std::fs::write(
        folder.join("polygon.json"),
        r#"{"obj": "polygon.obj", "k": 1, "b": [1], "m": 1}"#,
    )
    .unwrap();
    let frames = folder.join("frames");
    let started = Instant::now();
    let output = run(&[
        "simulate",
        folder.join("polygon.json").to_str().unwrap(),
        "--out",
        frames.to_str().unwrap(),
    ]);
    assert_fails(
        &output,
        &[
            "polygon.obj: ",
            "1 face(s) of 20,000 corners give up to 199,990,000 springs",
            "would need 51.2 GB; the limit here is 4.0 GB",
            "split large polygons",
        ],
    );
    assert!(started.elapsed() < Duration::from_secs(10));
    assert!(!frames.exists(), "nothing written");
}

#[test]
fn generate_grid_100000_is_refused_with_its_estimate() {
    let folder = temp_folder("grid-100000");
    let out = folder.join("out");
    let output = run(&["generate", "grid", "100000", "--out", out.to_str().unwrap()]);
    assert_fails(
        &output,
        &[
            "grid 100000 (10,000,000,000 vertices) would need 560 GB",
            "the limit here is 4.0 GB",
        ],
    );
    assert!(!out.exists(), "nothing written");
    let overflow = run(&["generate", "grid", "18446744073709551615"]);
    assert_fails(&overflow, &["overflows 64 bits"]);
}

#[test]
fn a_png_whose_header_claims_100000_by_100000_pixels_is_refused_before_decoding() {
    assert!(
        std::fs::metadata(corpus_path("huge-header.png"))
            .unwrap()
            .len()
            < 100
    );
    let folder = temp_folder("huge-texture");
    let out = folder.join("out.png");
    let output = run(&[
        "render",
        &corpus("huge-texture.json"),
        "-o",
        out.to_str().unwrap(),
        "--steps",
        "1",
    ]);
    assert_fails(
        &output,
        &[
            "texture ",
            "huge-header.png: a 100000×100000 texture would need 160 GB",
        ],
    );
    assert!(names_in(&folder).is_empty(), "nothing written");
}

#[test]
fn the_dense_path_on_300000_vertices_is_refused_with_its_estimate() {
    let folder = temp_folder("dense-300k");
    let generated = run(&["generate", "grid", "548", "--out", folder.to_str().unwrap()]);
    assert!(generated.status.success(), "{}", stderr(&generated));
    let frames = folder.join("frames");
    let output = run(&[
        "simulate",
        folder.join("grid-548.json").to_str().unwrap(),
        "--dense",
        "--out",
        frames.to_str().unwrap(),
    ]);
    assert_fails(
        &output,
        &[
            "the dense path for n = 300,304",
            "would need 6485 GB",
            "use the sparse path (without --dense)",
        ],
    );
    assert!(!frames.exists(), "nothing written");
}

#[test]
fn huge_step_counts_neither_panic_nor_allocate_per_step() {
    // u64::MAX steps: no "capacity overflow"; the scene blows up at step 1.
    let folder = temp_folder("huge-steps");
    let frames = folder.join("frames");
    let output = run(&[
        "simulate",
        &corpus("blows-up.json"),
        "--steps",
        "18446744073709551615",
        "--out",
        frames.to_str().unwrap(),
    ]);
    assert_fails(
        &output,
        &["step 1: the step produced a non-finite position"],
    );
    assert_eq!(names_in(&frames), ["frame-000000.obj"]);
    let beyond = run(&[
        "simulate",
        &corpus("blows-up.json"),
        "--steps",
        "18446744073709551616",
    ]);
    assert_eq!(beyond.status.code(), Some(2), "{}", stderr(&beyond));
    let message = stderr(&beyond);
    assert!(
        message.contains("--steps") && message.contains("18446744073709551616"),
        "{message}"
    );
    // A render that would keep 5·10¹¹ frames is refused before it starts.
    let gif = folder.join("out.gif");
    let render = run(&[
        "render",
        &data("net.json"),
        "-o",
        gif.to_str().unwrap(),
        "--steps",
        "1000000000000",
    ]);
    assert_fails(
        &render,
        &["keeping 500,000,000,001 frames", "draw fewer frames"],
    );
    assert!(!gif.exists());
    // 10¹² steps of a scene that runs: memory stays flat while it steps.
    let mut child = Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(["simulate", &data("net.json"), "--steps", "1000000000000"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let status = std::fs::read_to_string(format!("/proc/{}/status", child.id()));
    let still_running = child.try_wait().unwrap().is_none();
    let _ = child.kill();
    let _ = child.wait();
    assert!(still_running, "the run stopped early");
    if let Ok(status) = status {
        let resident_kb: u64 = status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.split_whitespace().next()?.parse().ok())
            .expect("VmRSS");
        assert!(resident_kb < 200_000, "{resident_kb} kB resident");
    }
}

#[test]
fn inputs_are_read_up_to_a_stated_size_and_dev_zero_fails_at_once() {
    let started = Instant::now();
    let output = run(&["simulate", &corpus("dev-zero.json")]);
    assert_fails(
        &output,
        &["/dev/zero:1: a NUL byte at byte offset 0: this is not a text file"],
    );
    assert!(started.elapsed() < Duration::from_secs(5));
    // A limit of 1 MB reads at most 125,000 bytes: the 450 kB flag is refused.
    let small = run_with_limit(&["simulate", &data("flag.json")], "0.001");
    assert_fails(
        &small,
        &[
            "flag.obj: the file is larger than 125000 bytes, the most read here",
            "docs/reliability.md",
        ],
    );
}

// --------------------------------------------------- 3. minor cases --

#[test]
fn a_scene_that_is_not_positive_definite_is_named() {
    let output = run(&["simulate", &corpus("k-1e308.json")]);
    assert_fails(
        &output,
        &[
            "k-1e308.json: the precomputation failed:",
            "not positive definite",
        ],
    );
}

#[test]
fn an_out_folder_with_frames_of_another_run_is_refused_unless_forced() {
    let folder = temp_folder("out-reuse");
    let out = folder.to_str().unwrap();
    let scene = data("net.json");
    let first = run(&["simulate", &scene, "--steps", "5", "--out", out]);
    assert!(first.status.success(), "{}", stderr(&first));
    assert_eq!(names_in(&folder).len(), 6);
    let before = std::fs::read(folder.join("frame-000005.obj")).unwrap();
    let again = run(&["simulate", &scene, "--steps", "2", "--out", out]);
    assert_fails(
        &again,
        &[
            "the folder already holds 6 frame(s) of another run (frame-000000.obj, ...)",
            "--force",
        ],
    );
    assert_eq!(names_in(&folder).len(), 6, "nothing removed or written");
    assert_eq!(
        std::fs::read(folder.join("frame-000005.obj")).unwrap(),
        before
    );
    // A killed run's temporary (its process is gone) and --force: the old
    // frames and the temporary go, the new frames come.
    let dead = Command::new("true").spawn().unwrap();
    let dead_pid = dead.id();
    let mut dead = dead;
    dead.wait().unwrap();
    let stale = format!(".frame-000009.obj.{dead_pid}-0.tmp");
    std::fs::write(folder.join(&stale), "half a frame").unwrap();
    let forced = run(&["simulate", &scene, "--steps", "2", "--out", out, "--force"]);
    assert!(forced.status.success(), "{}", stderr(&forced));
    assert_eq!(
        names_in(&folder),
        ["frame-000000.obj", "frame-000001.obj", "frame-000002.obj"]
    );
}

// ------------------------------------------------ 4. mutation tests --

/// A problem of the whole file, which has no line of its own.
const WHOLE_FILE_PROBLEMS: &[&str] = &[
    "cannot read the file",
    "has no vertices",
    "gives no springs",
    "would need",
    "\"m\" is absent",
    "is not a vertex",
    "is larger than",
];

/// A reader's error must name `file` and, unless it is about the whole
/// file, a line.
fn assert_names_file_and_line(error: &FileError, file: &Path, input: &[u8]) {
    let message = error.to_string();
    let shown = String::from_utf8_lossy(&input[..input.len().min(300)]).into_owned();
    assert!(!message.is_empty());
    assert_eq!(error.path(), Some(file), "{message}\ninput: {shown:?}");
    assert!(
        message.starts_with(&file.display().to_string()),
        "{message}"
    );
    let whole_file = WHOLE_FILE_PROBLEMS.iter().any(|p| message.contains(p));
    assert!(
        error.line().is_some() || whole_file,
        "no line in: {message}\ninput: {shown:?}"
    );
}

/// Matrix Market seeds: the corpus, and the grid matrix written by our
/// writers in each format.
fn matrix_market_seeds() -> Vec<Vec<u8>> {
    let mut seeds: Vec<Vec<u8>> = [
        "general-not-symmetric.mtx",
        "general-symmetric.mtx",
        "declares-2147483648-rows.mtx",
        "declares-100000000-entries.mtx",
        "array-declares-too-much.mtx",
        "bom.mtx",
    ]
    .iter()
    .map(|name| std::fs::read(corpus_path(name)).unwrap())
    .collect();
    let mut t = TripletMatrix::new(4, 4);
    for (i, j, v) in [
        (0, 0, 4.0),
        (1, 0, -1.0),
        (1, 1, 4.0),
        (2, 2, 2.5),
        (3, 1, 0.5),
        (3, 3, 3.0),
    ] {
        t.push(i, j, v).unwrap();
    }
    let lower = t.to_csc();
    for symmetry in [Symmetry::Symmetric, Symmetry::General] {
        let mut text = Vec::new();
        write_coordinate(&mut text, &lower, symmetry, "a seed").unwrap();
        seeds.push(text);
    }
    let mut array = Vec::new();
    let mut dense = masssprings::linalg::dense::DenseMatrix::zeros(3, 2);
    dense[(2, 1)] = -1.5;
    dense[(0, 0)] = 2.0;
    write_array(&mut array, &dense, "").unwrap();
    seeds.push(array);
    seeds
}

#[test]
fn mutated_matrix_market_files_give_a_matrix_or_an_error_with_file_and_line() {
    small_own_limit();
    let folder = temp_folder("mutated-mtx");
    let path = folder.join("mutated.mtx");
    let seeds = matrix_market_seeds();
    let mut rng = Rng::new(9);
    let started = Instant::now();
    for case in 0..2000 {
        let seed = &seeds[case % seeds.len()];
        let input = mutate(seed, &mut rng);
        std::fs::write(&path, &input).unwrap();
        // Through the file (UTF-8, NUL, BOM, size), both readers.
        if let Err(error) = matrix_market::read(&path) {
            assert_names_file_and_line(&error, &path, &input);
        }
        if let Err(error) = matrix_market::read_symmetric(&path) {
            assert_names_file_and_line(&error, &path, &input);
        }
    }
    assert!(started.elapsed() < Duration::from_secs(30));
}

/// Scene seeds: (JSON, OBJ) of the small bundled scenes and the corpus.
fn scene_seeds() -> Vec<(Vec<u8>, Vec<u8>)> {
    let mut seeds = Vec::new();
    for name in ["single-spring-horizontal", "horizontal-chain", "net"] {
        let json = std::fs::read(data(&format!("{name}.json"))).unwrap();
        let obj = std::fs::read(data(&format!("{name}.obj"))).unwrap();
        seeds.push((json, obj));
    }
    let square = std::fs::read(corpus_path("square.obj")).unwrap();
    seeds.push((
        br#"{"obj": "mesh.obj", "k": 100, "b": [1, 2]}"#.to_vec(),
        square.clone(),
    ));
    seeds.push((std::fs::read(corpus_path("k-1e308.json")).unwrap(), square));
    seeds.push((
        std::fs::read(corpus_path("bom.json")).unwrap(),
        std::fs::read(corpus_path("bom.obj")).unwrap(),
    ));
    seeds
}

/// Points a seed's JSON at `mesh.obj` (each seed names its own OBJ).
fn pointed_at_mesh(json: &[u8]) -> Vec<u8> {
    let text = String::from_utf8_lossy(json);
    let start = text.find("\"obj\"").expect("a seed names its OBJ");
    let rest = &text[start..];
    let value_start = start + rest.find(':').unwrap() + 1;
    let value_end = value_start + text[value_start..].find(',').unwrap();
    format!(
        "{} \"mesh.obj\"{}",
        &text[..value_start],
        &text[value_end..]
    )
    .into_bytes()
}

fn check_scene(folder: &Path, json: &[u8], obj: &[u8]) {
    let json_path = folder.join("scene.json");
    let obj_path = folder.join("mesh.obj");
    std::fs::write(&json_path, json).unwrap();
    std::fs::write(&obj_path, obj).unwrap();
    if let Err(error) = load_scene(&json_path) {
        match error.path() {
            Some(path) if path == obj_path => assert_names_file_and_line(&error, &obj_path, obj),
            Some(path) if path == json_path => assert_names_file_and_line(&error, &json_path, json),
            // A mutated "obj" names another file, which does not exist.
            Some(other) => {
                assert!(error.io_error().is_some(), "{error}");
                assert_names_file_and_line(&error, other, b"");
            }
            None => panic!("no file named: {error}"),
        }
    }
}

#[test]
fn mutated_scenes_give_a_scene_or_an_error_with_file_and_line() {
    small_own_limit();
    let folder = temp_folder("mutated-scenes");
    let seeds: Vec<(Vec<u8>, Vec<u8>)> = scene_seeds()
        .into_iter()
        .map(|(json, obj)| (pointed_at_mesh(&json), obj))
        .collect();
    let mut rng = Rng::new(90);
    let started = Instant::now();
    for case in 0..2000 {
        let (json, obj) = &seeds[case % seeds.len()];
        match rng.below(3) {
            0 => check_scene(&folder, &mutate(json, &mut rng), obj),
            1 => check_scene(&folder, json, &mutate(obj, &mut rng)),
            _ => check_scene(&folder, &mutate(json, &mut rng), &mutate(obj, &mut rng)),
        }
    }
    // The two large bundled cloths, a few times each.
    for name in ["flag", "skirt"] {
        let json = pointed_at_mesh(&std::fs::read(data(&format!("{name}.json"))).unwrap());
        let obj = std::fs::read(data(&format!("{name}.obj"))).unwrap();
        for _ in 0..5 {
            check_scene(&folder, &json, &mutate(&obj, &mut rng));
        }
    }
    assert!(started.elapsed() < Duration::from_secs(30));
}

#[test]
fn the_mutator_is_deterministic_and_changes_its_input() {
    let seed = b"v 0 0 0\nv 1 0 0\nf 1 2\n";
    let (mut a, mut b) = (Rng::new(1), Rng::new(1));
    let changed = (0..100)
        .filter(|_| {
            let (x, y) = (mutate(seed, &mut a), mutate(seed, &mut b));
            assert_eq!(x, y);
            x != seed
        })
        .count();
    assert!(changed > 90, "{changed}");
}
