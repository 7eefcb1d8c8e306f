//! Hostile input: every hostile case of `docs/reliability.md`, through the
//! command line as a user meets it (exit code, message, nothing written or
//! destroyed: outputs that would replace inputs, FIFOs and links as inputs
//! and outputs, limits on every path, degenerate numbers), a seeded
//! mutation test of the output paths, and one of the readers (Matrix
//! Market, scene JSON + OBJ) over the bundled scenes of `data/` and the
//! corpus in `tests/hostile/`: thousands of damaged files, each read to a
//! value or to an error that names the file and, for a problem on a line,
//! the line. FIFOs and links are made in temporary folders. (The PNG texture
//! and the HTTP request parser live in the binary; their mutation tests are
//! unit tests in `src/app/draw/texture.rs` and `src/app/view/http.rs`.)
//! A student's file as `trace --compare` reads it goes through the
//! binary's comparison files, included here as they are.
#[path = "common/cli.rs"]
mod cli;
#[allow(dead_code)]
#[path = "../src/app/trace/compare/entries.rs"]
mod entries;
#[allow(dead_code)]
#[path = "../src/app/trace/compare/factor.rs"]
mod factor;
#[path = "common/mutate.rs"]
mod mutate;
#[allow(dead_code)]
#[path = "../src/app/trace/compare/springs.rs"]
mod springs;
#[path = "common/student_file.rs"]
mod student_file;

use cli::{assert_fails, copy_scene, data, names_in, temp_folder};
use masssprings::files::FileError;
use masssprings::linalg::sparse::TripletMatrix;
use masssprings::matrix_market::{self, write_array, write_coordinate, Symmetry};
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
        "--every",
        "2",
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
fn a_stiffness_or_mass_that_overflows_q_is_named_with_its_bound() {
    for command in [&["simulate"][..], &["export-q", "-o", "/dev/null"][..]] {
        let mut args = command.to_vec();
        let scene = corpus("k-1e308.json");
        args.insert(1, &scene);
        assert_fails(
            &run(&args),
            &[
                "k-1e308.json: k = 1e308 overflows Q: its diagonal holds k × 3",
                "Q fits with k up to 2.9e307 here",
            ],
        );
    }
    let folder = temp_folder("mass-overflow");
    std::fs::copy(corpus_path("square.obj"), folder.join("square.obj")).unwrap();
    let square = |name: &str, k: &str, m: &str| {
        let json = format!(r#"{{"obj": "square.obj", "k": {k}, "b": [1], "m": {m}}}"#);
        std::fs::write(folder.join(name), json).unwrap();
        run_in(&folder, &["simulate", name])
    };
    assert_fails(
        &square("m.json", "1", "1e308"),
        &[
            "m.json: the mass 1e308 of vertex 1 overflows Q",
            "m / Δt² = m × 900",
            "Q fits with masses up to 9.9e304",
        ],
    );
    // At the bound, Q is factored and the handout's step runs: it computes
    // no energy, and its positions are finite. A step that measures its
    // energy (a stopping rule) names the energy's overflow instead.
    let at_bound = square("k.json", "2.9e307", "1");
    assert_eq!(at_bound.status.code(), Some(0), "{}", stderr(&at_bound));
    let ruled = {
        let args = ["simulate", "k.json", "--energy-tolerance", "0.1"];
        run_in(&folder, &args)
    };
    assert_fails(
        &ruled,
        &["step 1: the step's energy or gradient is not finite"],
    );
}

#[test]
fn degenerate_matrices_are_refused_not_reported() {
    let folder = temp_folder("degenerate-matrices");
    let write = |name: &str, text: &str| {
        std::fs::write(folder.join(name), text).unwrap();
        text_of(&folder.join(name))
    };
    let tiny = write(
        "tiny.mtx",
        "%%MatrixMarket matrix coordinate real symmetric\n1 1 1\n1 1 5e-324\n",
    );
    assert_fails(
        &run(&["analyze", &tiny]),
        &[
            "tiny.mtx: the solve gave a solution that is not finite (x[1, 1] = inf)",
            "too close to singular",
        ],
    );
    let empty = write(
        "empty.mtx",
        "%%MatrixMarket matrix coordinate real symmetric\n0 0 0\n",
    );
    for args in [
        vec!["analyze", &empty],
        vec!["spy", &empty, "-o", "spy.png"],
        vec!["etree", &empty, "-o", "etree.png"],
    ] {
        assert_fails(
            &run(&args),
            &["empty.mtx: the matrix is 0 × 0: there is nothing to factor or draw"],
        );
    }
}

#[test]
fn coordinates_too_large_or_too_small_for_f64_are_named_as_such() {
    let folder = temp_folder("extreme-coordinates");
    let scene = |name: &str, side: &str| {
        let obj = format!("v 0 0 0\nv {side} 0 0\nv 0 {side} 0\nv {side} {side} 0\nf 1 2 4 3\n");
        std::fs::write(folder.join(format!("{name}.obj")), obj).unwrap();
        let json = format!(r#"{{"obj": "{name}.obj", "k": 1, "b": [1]}}"#);
        std::fs::write(folder.join(format!("{name}.json")), json).unwrap();
        text_of(&folder.join(format!("{name}.json")))
    };
    assert_fails(
        &run(&["simulate", &scene("large", "1e200")]),
        &[
            "large.obj:1: vertex 1 has a non-finite mass",
            "corners of a face around it are 1e200 apart, which overflows f64",
            "sides up to 1e76 work); scale the mesh down",
        ],
    );
    assert_fails(
        &run(&["simulate", &scene("small", "1e-200")]),
        &[
            "small.obj:1: vertex 1 has",
            "only 1e-200 apart, which underflows f64",
            "scale the mesh up",
        ],
    );
    for side in ["1e70", "1e-70"] {
        let output = run(&["simulate", &scene("fits", side), "--steps", "0"]);
        assert!(output.status.success(), "{side}: {}", stderr(&output));
    }
    let repeated = folder.join("repeated.obj");
    std::fs::write(&repeated, "v 0 0 0\nv 0 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        folder.join("repeated.json"),
        r#"{"obj": "repeated.obj", "k": 1, "b": [1]}"#,
    )
    .unwrap();
    assert_fails(
        &run(&["simulate", &text_of(&folder.join("repeated.json"))]),
        &["two corners at one point (a repeated corner)"],
    );
}

fn text_of(path: &Path) -> String {
    path.display().to_string()
}

#[test]
fn generate_grid_blames_the_extra_argument_not_n() {
    let output = run(&["generate", "grid", "3", "4"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("unexpected argument '4'"),
        "{}",
        stderr(&output)
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
            "the folder already holds 6 frame(s) of an earlier run (frame-000000.obj, ...)",
            "--force",
            "--resume",
        ],
    );
    assert_eq!(names_in(&folder).len(), 6, "nothing removed or written");
    assert_eq!(
        std::fs::read(folder.join("frame-000005.obj")).unwrap(),
        before
    );
    // A file named as temporaries used to be, whose "process" is gone, is
    // a user's file now; --force replaces the old frames (once the new run
    // is complete) and leaves it.
    let dead = Command::new("true").spawn().unwrap();
    let dead_pid = dead.id();
    let mut dead = dead;
    dead.wait().unwrap();
    let users = format!(".frame-000009.obj.{dead_pid}-0.tmp");
    std::fs::write(folder.join(&users), "a user's file").unwrap();
    let forced = run(&["simulate", &scene, "--steps", "2", "--out", out, "--force"]);
    assert!(forced.status.success(), "{}", stderr(&forced));
    assert_eq!(
        names_in(&folder),
        [
            users.as_str(),
            "frame-000000.obj",
            "frame-000001.obj",
            "frame-000002.obj"
        ]
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

/// Student file seeds for `trace --compare`: an `A` of the small scene of
/// `student_file` in another order and orientation, its `r`, a `y`, `M`'s
/// diagonal, a `P` and an `L`, written by our writers, and what the fuzz
/// target found (an array of 5555555555555 rows and no column).
fn student_file_seeds() -> Vec<Vec<u8>> {
    let n = student_file::N;
    let mut a = TripletMatrix::new(student_file::SPRINGS.len(), n);
    for (e, [i, j]) in student_file::SPRINGS.iter().rev().enumerate() {
        let (plus, minus) = if e % 2 == 0 { (*j, *i) } else { (*i, *j) };
        a.push(e, plus, 1.0).unwrap();
        a.push(e, minus, -1.0).unwrap();
    }
    let mut p = TripletMatrix::new(n, n);
    let mut l = TripletMatrix::new(n, n);
    for (k, old) in [3, 1, 0, 2].into_iter().enumerate() {
        p.push(k, old, 1.0).unwrap();
        l.push(k, k, 2.0 + k as f64).unwrap();
        l.push(n - 1, k, 0.5).unwrap();
    }
    let mut seeds = vec![std::fs::read(corpus_path("array-5555555555555-by-0.mtx")).unwrap()];
    for sparse in [a.to_csc(), p.to_csc(), l.to_csc()] {
        let mut text = Vec::new();
        write_coordinate(&mut text, &sparse, Symmetry::General, "").unwrap();
        seeds.push(text);
    }
    let dense = masssprings::linalg::dense::DenseMatrix::from_row_major;
    for (rows, cols) in [(student_file::SPRINGS.len(), 1), (n, 3), (n, 1), (1, n)] {
        let values = (0..rows * cols).map(|v| 0.25 * v as f64 - 1.0).collect();
        let mut text = Vec::new();
        write_array(&mut text, &dense(rows, cols, values).unwrap(), "").unwrap();
        seeds.push(text);
    }
    seeds
}

#[test]
fn mutated_student_files_are_compared_or_refused_by_trace_compare() {
    small_own_limit();
    let seeds = student_file_seeds();
    let mut rng = Rng::new(37);
    let mut tally = student_file::Tally::default();
    let started = Instant::now();
    for case in 0..20_000 {
        let input = mutate(&seeds[case % seeds.len()], &mut rng);
        let Ok(file) = matrix_market::parse(&String::from_utf8_lossy(&input)) else {
            continue;
        };
        let one = student_file::compare_everything(&file);
        tally.compared += one.compared;
        tally.refused += one.refused;
    }
    assert!(tally.compared > 3000 && tally.refused > 3000, "{tally:?}");
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

// ------------------------------ 5. outputs that never destroy inputs --

fn text(path: &Path) -> String {
    path.display().to_string()
}

/// Makes a FIFO at `path` (with the system's `mkfifo`).
fn mkfifo(path: &Path) {
    let made = Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
}

fn is_fifo(path: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo())
}

/// Runs the binary in `folder` (its current folder).
fn run_in(folder: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(args)
        .current_dir(folder)
        .env(masssprings::memory::LIMIT_VARIABLE, CHILD_LIMIT_GB)
        .output()
        .expect("the binary runs")
}

#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let folder = temp_folder("output-is-input");
    let scene = copy_scene(&folder, "net");
    let obj = folder.join("net.obj");
    let q = folder.join("q.mtx");
    let exported = run(&["export-q", &text(&scene), "-o", &text(&q)]);
    assert!(exported.status.success(), "{}", stderr(&exported));
    std::os::unix::fs::symlink("net.json", folder.join("link.json")).unwrap();
    std::fs::hard_link(&q, folder.join("hard.mtx")).unwrap();
    let before: Vec<Vec<u8>> = [&scene, &obj, &q]
        .iter()
        .map(|p| std::fs::read(p).unwrap())
        .collect();
    let cases: [(&[&str], &str); 10] = [
        (
            &["converge", "net.json", "--csv", "net.json"],
            "--csv net.json is the scene net.json",
        ),
        (
            &["converge", "net.json", "--plot", "net.json"],
            "--plot net.json is the scene net.json",
        ),
        (
            &["converge", "net.json", "--csv", "net.obj", "--steps", "1"],
            "--csv net.obj is the scene's OBJ",
        ),
        (
            &["export-q", "net.json", "-o", "net.json"],
            "-o net.json is the scene net.json",
        ),
        (
            &["export-q", "net.json", "-o", "./net.obj"],
            "-o ./net.obj is the scene's OBJ",
        ),
        (
            &["export-q", "net.json", "-o", "link.json"],
            "-o link.json is the scene net.json",
        ),
        (
            &["spy", "q.mtx", "-o", "q.mtx"],
            "-o q.mtx is the matrix q.mtx",
        ),
        (
            &["etree", "q.mtx", "-o", "hard.mtx"],
            "-o hard.mtx is the matrix q.mtx",
        ),
        (
            &["spy", "net.json", "-o", "net.obj"],
            "-o net.obj is the scene's OBJ",
        ),
        (
            &["render", "link.json", "-o", "net.json.gif", "--steps", "1"],
            "",
        ),
    ];
    for (args, expected) in &cases[..9] {
        let output = run_in(&folder, args);
        assert_fails(
            &output,
            &[
                expected,
                "writing it would destroy an input; choose another name",
            ],
        );
    }
    // A different name in the same folder is no clash.
    let render = run_in(&folder, cases[9].0);
    assert!(render.status.success(), "{}", stderr(&render));
    let after: Vec<Vec<u8>> = [&scene, &obj, &q]
        .iter()
        .map(|p| std::fs::read(p).unwrap())
        .collect();
    assert!(before == after, "an input changed");
    assert!(std::fs::symlink_metadata(folder.join("link.json"))
        .unwrap()
        .file_type()
        .is_symlink());
}

#[test]
fn two_outputs_of_one_name_are_refused_before_any_work() {
    let folder = temp_folder("two-outputs");
    copy_scene(&folder, "net");
    let started = Instant::now();
    let converge = run_in(
        &folder,
        &[
            "converge",
            "net.json",
            "--csv",
            "same.png",
            "--plot",
            "./same.png",
        ],
    );
    assert_fails(
        &converge,
        &["--csv same.png and --plot ./same.png name the same file: one would overwrite the other"],
    );
    let bench = run_in(
        &folder,
        &["bench", "--sizes", "2", "--csv", "b.csv", "--plot", "b.csv"],
    );
    assert_fails(&bench, &["--csv b.csv and --plot b.csv name the same file"]);
    assert!(
        started.elapsed() < Duration::from_secs(10),
        "no work was done"
    );
    assert_eq!(
        names_in(&folder),
        ["net.json", "net.obj"],
        "nothing written"
    );
}

#[test]
fn files_written_into_the_out_folder_never_replace_the_scenes_files() {
    let folder = temp_folder("out-folder-clash");
    let flag = copy_scene(&folder, "flag");
    let json = std::fs::read_to_string(&flag).unwrap();
    let scene_with_texture = |name: &str, png: &str| {
        let path = folder.join(name);
        std::fs::write(&path, json.replace("\"flag.png\"", &format!("\"{png}\""))).unwrap();
        std::fs::copy(folder.join("flag.png"), folder.join(png)).unwrap();
        path
    };
    // The texture named like the material the run writes, NAME.mtl.
    let a = scene_with_texture("a.json", "a.mtl");
    let texture = std::fs::read(folder.join("a.mtl")).unwrap();
    let output = run_in(
        &folder,
        &["simulate", "a.json", "--steps", "2", "--out", "."],
    );
    assert_fails(
        &output,
        &["the frames' material ./a.mtl is the scene's texture a.mtl"],
    );
    let into = folder.join("frames-a");
    let output = run(&["simulate", &text(&a), "--steps", "2", "--out", &text(&into)]);
    assert_fails(
        &output,
        &[
            "the frames' material",
            "and the frames' copy of the texture",
            "name the same file",
        ],
    );
    assert!(!into.exists(), "nothing written");
    // The texture named like a frame, in the folder the frames go to (even
    // with --force, which would remove it).
    scene_with_texture("b.json", "frame-000002.obj");
    for force in [false, true] {
        let mut args = vec!["simulate", "b.json", "--steps", "2", "--out", "."];
        if force {
            args.push("--force");
        }
        let output = run_in(&folder, &args);
        assert_fails(
            &output,
            &[
                "the scene's texture frame-000002.obj (an input) is one of the frames \
                 frame-NNNNNN.obj that --out . writes or removes",
            ],
        );
    }
    let output = run_in(
        &folder,
        &["simulate", "b.json", "--steps", "2", "--out", "c"],
    );
    assert_fails(
        &output,
        &["the frames' copy of the texture c/frame-000002.obj (an output) is one of the frames"],
    );
    assert_eq!(std::fs::read(folder.join("a.mtl")).unwrap(), texture);
    assert_eq!(
        std::fs::read(folder.join("frame-000002.obj")).unwrap(),
        texture
    );
    // Frames beside the scene: the texture is already there, not copied
    // onto itself.
    let beside = temp_folder("out-beside");
    copy_scene(&beside, "flag");
    let output = run_in(
        &beside,
        &["simulate", "flag.json", "--steps", "1", "--out", "."],
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(std::fs::read(beside.join("flag.png")).unwrap(), texture);
    assert!(beside.join("frame-000001.obj").exists());
}

#[test]
fn an_output_link_is_written_through_and_stays_a_link() {
    let folder = temp_folder("output-links");
    copy_scene(&folder, "net");
    std::fs::write(folder.join("old.mtx"), "old").unwrap();
    std::os::unix::fs::symlink("old.mtx", folder.join("link.mtx")).unwrap();
    std::os::unix::fs::symlink("sub/new.mtx", folder.join("dangling.mtx")).unwrap();
    std::fs::create_dir(folder.join("sub")).unwrap();
    for link in ["link.mtx", "dangling.mtx"] {
        let output = run_in(&folder, &["export-q", "net.json", "-o", link]);
        assert!(output.status.success(), "{}", stderr(&output));
        let metadata = std::fs::symlink_metadata(folder.join(link)).unwrap();
        assert!(metadata.file_type().is_symlink(), "{link} is still a link");
    }
    for target in ["old.mtx", "sub/new.mtx"] {
        let written = std::fs::read_to_string(folder.join(target)).unwrap();
        assert!(written.starts_with("%%MatrixMarket"), "{target}: {written}");
    }
}

#[test]
fn an_output_fifo_or_device_is_written_into_not_replaced() {
    let folder = temp_folder("output-fifo");
    copy_scene(&folder, "net");
    let fifo = folder.join("q.fifo");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let output = run_in(&folder, &["export-q", "net.json", "-o", "q.fifo"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let received = reader.join().unwrap();
    assert!(received.starts_with("%%MatrixMarket"), "{received}");
    assert!(is_fifo(&fifo), "still a FIFO");
    // Nobody reads: a clear failure after a few seconds, the FIFO kept.
    let started = Instant::now();
    let unread = run_in(&folder, &["export-q", "net.json", "-o", "q.fifo"]);
    assert_fails(
        &unread,
        &["q.fifo: cannot write the file: no program opened the FIFO"],
    );
    assert!(started.elapsed() < Duration::from_secs(10));
    assert!(is_fifo(&fifo));
    // Devices are written as they are: /dev/null swallows, /dev/full fails.
    let null = run_in(&folder, &["export-q", "net.json", "-o", "/dev/null"]);
    assert!(null.status.success(), "{}", stderr(&null));
    let full = run_in(&folder, &["spy", "net.json", "-o", "/dev/full"]);
    assert_fails(&full, &["/dev/full: cannot write the file"]);
    use std::os::unix::fs::FileTypeExt;
    for device in ["/dev/null", "/dev/full"] {
        let kind = std::fs::symlink_metadata(device).unwrap().file_type();
        assert!(kind.is_char_device(), "{device}");
    }
    assert_eq!(names_in(&folder), ["net.json", "net.obj", "q.fifo"]);
}

#[test]
fn a_dash_is_standard_output_where_nothing_else_prints_there() {
    let folder = temp_folder("output-dash");
    copy_scene(&folder, "net");
    let output = run_in(&folder, &["export-q", "net.json", "-o", "-"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(String::from_utf8_lossy(&output.stdout).starts_with("%%MatrixMarket"));
    assert!(
        stderr(&output).contains("-: n = 81"),
        "the report goes to stderr"
    );
    // Standard output appended to the scene: `-o -` would write into it.
    let appended = std::fs::OpenOptions::new()
        .append(true)
        .open(folder.join("net.json"))
        .unwrap();
    let before = std::fs::read(folder.join("net.json")).unwrap();
    let into_input = Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(["export-q", "net.json", "-o", "-"])
        .current_dir(&folder)
        .stdout(appended)
        .output()
        .unwrap();
    assert_fails(
        &into_input,
        &["-o (-, standard output) is the scene net.json"],
    );
    assert_eq!(std::fs::read(folder.join("net.json")).unwrap(), before);
    let converge = run_in(&folder, &["converge", "net.json", "--csv", "-"]);
    assert_fails(
        &converge,
        &["--csv and the table would both go to standard output (-); name a file for --csv"],
    );
    let simulate = run_in(&folder, &["simulate", "net.json", "--out", "-"]);
    assert_eq!(simulate.status.code(), Some(2), "{}", stderr(&simulate));
    assert!(stderr(&simulate).contains("simulate writes a folder of frames"));
    assert_eq!(
        names_in(&folder),
        ["net.json", "net.obj"],
        "no file named -"
    );
}

#[test]
fn empty_names_and_folders_given_as_files_are_named_as_such() {
    let folder = temp_folder("output-names");
    copy_scene(&folder, "net");
    let empty_out = run_in(&folder, &["export-q", "net.json", "-o", ""]);
    assert_eq!(empty_out.status.code(), Some(2));
    let message = stderr(&empty_out);
    assert!(
        message.contains("--out <Q.mtx>") && message.contains("value is required"),
        "{message}"
    );
    // an empty path is refused by the parser, naming the flag
    for args in [
        &["converge", "net.json", "--csv", ""][..],
        &["simulate", "net.json", "--out", ""][..],
        &["generate", "grid", "3", "--out", ""][..],
    ] {
        let empty = run_in(&folder, args);
        assert_eq!(empty.status.code(), Some(2), "{args:?}");
        let flag = args[args.len() - 2];
        assert!(
            stderr(&empty).contains(flag) && stderr(&empty).contains("value is required"),
            "{args:?}: {}",
            stderr(&empty)
        );
    }
    let generate = run_in(&folder, &["generate", "grid", "3", "--out", "-"]);
    assert_eq!(generate.status.code(), Some(2));
    assert!(stderr(&generate).contains("generate writes scene files into a folder"));
    let onto_a_file = run_in(&folder, &["generate", "grid", "3", "--out", "net.obj"]);
    assert_fails(
        &onto_a_file,
        &["--out net.obj: this is a file, not a folder"],
    );
    std::fs::create_dir(folder.join("pictures")).unwrap();
    let into_folder = run_in(&folder, &["spy", "net.json", "-o", "pictures"]);
    assert_fails(
        &into_folder,
        &["-o pictures is a folder: name a file in it, e.g. pictures/out"],
    );
    std::fs::write(
        folder.join("empty-obj.json"),
        r#"{"obj": "", "k": 1, "b": [1]}"#,
    )
    .unwrap();
    let empty_obj = run_in(&folder, &["simulate", "empty-obj.json"]);
    assert_fails(
        &empty_obj,
        &[
            "empty-obj.json:1:",
            "a file name (a non-empty string) for \"obj\"",
        ],
    );
    assert_eq!(
        names_in(&folder),
        ["empty-obj.json", "net.json", "net.obj", "pictures"]
    );
}

/// Output paths made from the names of the inputs, written in other ways
/// (`./`, `sub/../`, through a link to the folder, a link or hard link to
/// an input) and mutated as the readers' inputs are: each run of
/// `export-q net.json -o PATH` must refuse exactly the paths that reach an
/// input (same device and inode), and no input may change.
#[test]
fn mutated_output_paths_never_replace_an_input() {
    use std::os::unix::fs::MetadataExt;
    let folder = temp_folder("mutated-outputs");
    copy_scene(&folder, "net");
    std::fs::create_dir(folder.join("sub")).unwrap();
    std::os::unix::fs::symlink("net.json", folder.join("link.json")).unwrap();
    std::os::unix::fs::symlink(".", folder.join("up")).unwrap();
    std::fs::hard_link(folder.join("net.obj"), folder.join("hard.obj")).unwrap();
    let inputs = ["net.json", "net.obj"].map(|name| folder.join(name));
    let identity = |path: &Path| std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()));
    let input_ids = inputs.clone().map(|path| identity(&path).unwrap());
    let before = inputs.clone().map(|path| std::fs::read(path).unwrap());
    let names = [
        "net.json",
        "net.obj",
        "link.json",
        "hard.obj",
        "q.mtx",
        "sub",
        "up",
    ];
    let prefixes = ["", "./", "sub/../", "up/", "up/up/", ".//", "sub/./../up/"];
    let mut rng = Rng::new(29);
    let (mut refused, mut written) = (0, 0);
    for _ in 0..150 {
        let name = names[rng.below(names.len())].as_bytes();
        let name = if rng.below(3) == 0 {
            mutate(name, &mut rng)
        } else {
            name.to_vec()
        };
        let Ok(name) = String::from_utf8(name) else {
            continue;
        };
        let path = format!("{}{name}", prefixes[rng.below(prefixes.len())]);
        if path.contains('\0') || path.is_empty() || path.starts_with('-') {
            continue;
        }
        let clashes = identity(&folder.join(&path)).is_some_and(|id| input_ids.contains(&id));
        let output = run_in(&folder, &["export-q", "net.json", "-o", &path]);
        let message = stderr(&output);
        assert!(!message.contains("panicked"), "{path:?}: {message}");
        if clashes {
            assert_fails(&output, &["would destroy an input"]);
            refused += 1;
        } else if output.status.success() {
            written += 1;
        }
        let after = inputs.clone().map(|path| std::fs::read(path).unwrap());
        assert!(after == before, "{path:?} changed an input");
    }
    assert!(std::fs::symlink_metadata(folder.join("link.json"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(
        refused > 20 && written > 20,
        "{refused} refused, {written} written"
    );
}

// ------------------------------------ 6. reads that never hang --

#[test]
fn a_fifo_scene_obj_or_texture_that_nobody_writes_fails_within_seconds() {
    let folder = temp_folder("input-fifos");
    let flag = copy_scene(&folder, "flag");
    let json = std::fs::read_to_string(&flag).unwrap();
    mkfifo(&folder.join("scene.json"));
    mkfifo(&folder.join("mesh.obj"));
    mkfifo(&folder.join("texture.png"));
    std::fs::write(
        folder.join("obj.json"),
        json.replace("flag.obj", "mesh.obj"),
    )
    .unwrap();
    std::fs::write(
        folder.join("png.json"),
        json.replace("flag.png", "texture.png"),
    )
    .unwrap();
    let cases = [
        (
            vec!["simulate", "scene.json"],
            "scene.json: cannot read the file: nothing was written",
        ),
        (
            vec!["converge", "obj.json"],
            "mesh.obj: cannot read the file: nothing was written",
        ),
        (
            vec!["render", "png.json", "-o", "out.png", "--steps", "1"],
            "texture texture.png: cannot read the file: nothing was written",
        ),
        (
            vec!["simulate", "png.json", "--steps", "1", "--out", "frames"],
            "texture texture.png: cannot read the file: nothing was written",
        ),
    ];
    let started = Instant::now();
    let runs: Vec<_> = cases
        .into_iter()
        .map(|(args, expected)| {
            let folder = folder.clone();
            let run = std::thread::spawn(move || run_in(&folder, &args));
            (run, expected)
        })
        .collect();
    for (run, expected) in runs {
        assert_fails(&run.join().unwrap(), &[expected]);
    }
    assert!(
        started.elapsed() < Duration::from_secs(15),
        "{:?}",
        started.elapsed()
    );
    // A FIFO that is written is read as a file.
    let writer = {
        let folder = folder.clone();
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(500));
            std::fs::write(
                folder.join("mesh.obj"),
                std::fs::read(folder.join("flag.obj")).unwrap(),
            )
        })
    };
    let output = run_in(&folder, &["simulate", "obj.json", "--steps", "1", "--json"]);
    writer.join().unwrap().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
}

#[test]
fn a_texture_that_is_not_a_png_is_refused_by_every_command_at_once() {
    let folder = temp_folder("texture-not-png");
    let flag = copy_scene(&folder, "flag");
    let json = std::fs::read_to_string(&flag).unwrap();
    std::fs::write(folder.join("words.txt"), "root:x:0:0:root:/root:/bin/sh\n").unwrap();
    for (name, png, problem) in [
        (
            "zero.json",
            "/dev/zero",
            "texture /dev/zero: this is not a PNG file",
        ),
        (
            "text.json",
            "words.txt",
            "texture words.txt: this is not a PNG file",
        ),
    ] {
        std::fs::write(folder.join(name), json.replace("flag.png", png)).unwrap();
        let started = Instant::now();
        let simulate = run_in(
            &folder,
            &["simulate", name, "--steps", "1", "--out", "frames"],
        );
        assert_fails(&simulate, &[problem]);
        let render = run_in(&folder, &["render", name, "-o", "out.gif", "--steps", "1"]);
        assert_fails(&render, &[problem]);
        assert!(started.elapsed() < Duration::from_secs(10));
    }
    assert!(!folder.join("frames").exists() && !folder.join("out.gif").exists());
}

// ------------------------------------ 7. one memory rule on every path --

#[test]
fn converge_refuses_iterations_and_steps_it_could_not_keep() {
    let started = Instant::now();
    let net = data("net.json");
    let huge = run(&["converge", &net, "--iterations", "1000000000"]);
    assert_fails(
        &huge,
        &[
            "keeping 6,000,000,006 iterates of 64 bytes each would need 384 GB",
            "use fewer --iterations",
        ],
    );
    let wrapping = run(&["converge", &net, "--iterations", "18446744073709551615"]);
    assert_fails(&wrapping, &["iterates", "overflows 64 bits"]);
    let steps = run(&["converge", &net, "--steps", "1000000000000"]);
    assert_fails(
        &steps,
        &["keeping 6,000,000,000,000 step rows", "use fewer --steps"],
    );
    assert!(started.elapsed() < Duration::from_secs(10));
}

#[test]
fn bench_sizes_are_checked_as_generate_grid_is() {
    for args in [["bench", "--sizes", "100000"], ["bench", "--one", "100000"]] {
        let output = run(&args);
        assert_fails(
            &output,
            &[
                "grid 100000 (10,000,000,000 vertices) would need 560 GB",
                "choose a smaller N",
            ],
        );
    }
}

#[test]
fn the_memory_limit_heeds_the_address_space_limit() {
    // 4 GB of address space: the skirt's dense path (6.9 GB) is refused
    // with the reason, instead of aborting on its first allocation.
    let program = env!("CARGO_BIN_EXE_masssprings");
    let output = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 4000000 && exec {program} simulate {} --dense --steps 1",
            data("skirt.json")
        ))
        .env_remove(masssprings::memory::LIMIT_VARIABLE)
        .output()
        .unwrap();
    assert_fails(
        &output,
        &[
            "the dense path for n = 9,840",
            "would need 6.9 GB",
            "half of what the address-space limit, ulimit -v, leaves",
        ],
    );
    // The variable does not lift the process's own limit.
    let lifted = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 4000000 && exec {program} simulate {} --dense --steps 1",
            data("skirt.json")
        ))
        .env(masssprings::memory::LIMIT_VARIABLE, "100")
        .output()
        .unwrap();
    assert_fails(&lifted, &["ulimit -v"]);
}

#[test]
fn the_viewer_takes_as_many_iterations_from_the_command_line_as_from_its_page() {
    let output = run(&["view", &data("net.json"), "--iterations", "1000000000000"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("--iterations 1000000000000: the viewer takes at most 1000"));
}

// ------------------------------------ 8. counts, pictures, messages --

#[test]
fn render_steps_past_64_bits_of_frames_are_refused_not_wrapped() {
    let folder = temp_folder("render-steps");
    let out = folder.join("x.gif");
    let output = run(&[
        "render",
        &data("net.json"),
        "--steps",
        "18446744073709551615",
        "-o",
        &text(&out),
    ]);
    assert_fails(
        &output,
        &[
            "18446744073709551616 frames to keep",
            "more than 64 bits count",
        ],
    );
    let every = run(&[
        "render",
        &data("net.json"),
        "--steps",
        "18446744073709551615",
        "--every",
        "2",
        "-o",
        &text(&out),
    ]);
    assert_fails(&every, &["keeping 9,223,372,036,854,775,808 frames"]);
    assert!(names_in(&folder).is_empty());
}

#[test]
fn pictures_go_through_the_memory_rule() {
    let folder = temp_folder("pictures");
    let out = folder.join("p.png");
    for (command, needs) in [("etree", "would need 2.6 GB"), ("spy", "would need 0.3")] {
        let output = run_with_limit(
            &[
                command,
                &data("net.json"),
                "--size",
                "4096x4096",
                "-o",
                &text(&out),
            ],
            "0.2",
        );
        assert_fails(
            &output,
            &["4096×4096 pixels", needs, "choose a smaller --size"],
        );
    }
    let render = run_with_limit(
        &[
            "render",
            &data("net.json"),
            "--size",
            "2048x2048",
            "--steps",
            "1",
            "-o",
            &text(&out),
        ],
        "0.2",
    );
    assert_fails(&render, &["drawing a 2048×2048 frame would need"]);
    assert!(names_in(&folder).is_empty());
}

#[test]
fn arguments_that_are_not_utf8_are_read_not_panicked_on() {
    use std::os::unix::ffi::OsStrExt;
    let folder = temp_folder("not-utf8");
    let name = std::ffi::OsStr::from_bytes(b"sc\xffene.json");
    std::fs::copy(data("net.obj"), folder.join("net.obj")).unwrap();
    std::fs::copy(data("net.json"), folder.join(name)).unwrap();
    let binary = env!("CARGO_BIN_EXE_masssprings");
    let output = Command::new(binary)
        .arg("simulate")
        .arg(name)
        .args(["--steps", "1", "--json"])
        .current_dir(&folder)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let bad_value = Command::new(binary)
        .args(["simulate", "net.json", "--method"])
        .arg(std::ffi::OsStr::from_bytes(b"\xff"))
        .current_dir(&folder)
        .output()
        .unwrap();
    assert_eq!(bad_value.status.code(), Some(2), "{}", stderr(&bad_value));
    assert!(!stderr(&bad_value).contains("panicked"));
}

#[test]
fn a_memory_limit_that_is_not_a_number_of_gb_is_refused() {
    for (value, why) in [
        ("3GB", "3, not 3GB"),
        ("2,5", "not a comma"),
        ("0", "above 0"),
        ("-1", "above 0"),
        ("nan", "finite"),
        ("abc", "not a number"),
    ] {
        let output = run_with_limit(&["simulate", &data("net.json"), "--steps", "1"], value);
        assert_fails(
            &output,
            &[&format!("MASSSPRINGS_MEMORY_LIMIT_GB=\"{value}\""), why],
        );
    }
}

#[test]
fn each_message_names_the_real_problem() {
    // no step: no median of nothing
    let none = run(&["simulate", &data("net.json"), "--steps", "0"]);
    assert!(none.status.success(), "{}", stderr(&none));
    let report = String::from_utf8_lossy(&none.stdout);
    assert!(
        !report.contains("NaN") && report.contains("no step was run"),
        "{report}"
    );
    // 2³² × 2³² vertices, exactly
    let grid = run(&["generate", "grid", "4294967296", "--out", "/nonexistent/x"]);
    assert_fails(&grid, &["(18,446,744,073,709,551,616 vertices)"]);
    // a pin no vertex can have
    let folder = temp_folder("messages");
    std::fs::copy(data("net.obj"), folder.join("net.obj")).unwrap();
    std::fs::write(
        folder.join("s.json"),
        r#"{"obj": "net.obj", "k": 1, "m": 1, "b": [18446744073709551615]}"#,
    )
    .unwrap();
    let pin = run(&["simulate", &text(&folder.join("s.json"))]);
    assert_fails(&pin, &["pin b[0] = 18446744073709551615 is not a vertex"]);
    std::fs::write(
        folder.join("s.json"),
        r#"{"obj": "net.obj", "k": 1, "m": 1, "b": [1e30]}"#,
    )
    .unwrap();
    let pin = run(&["simulate", &text(&folder.join("s.json"))]);
    assert_fails(&pin, &["s.json:1:", "larger than any vertex index"]);
    // --textbook refuses what it would ignore
    for flags in [
        &["--supernodes", "relaxed"][..],
        &["--rho", "0.5"][..],
        &["--relaxation", "1"][..],
        &["--window", "3"][..],
        &["--factorization", "simplicial"][..],
        &["--tolerance", "0.1"][..],
    ] {
        let mut args = vec!["simulate", "--textbook"];
        let net = data("net.json");
        args.push(&net);
        args.extend_from_slice(flags);
        let output = run(&args);
        assert_eq!(output.status.code(), Some(2), "{flags:?}");
        assert!(
            stderr(&output).contains("'--textbook' cannot be used with")
                && stderr(&output).contains(flags[0]),
            "{flags:?}: {}",
            stderr(&output)
        );
    }
}

// ------------------------- 6. the one rule of outputs, under attack --

#[test]
fn names_masssprings_keeps_for_itself_are_no_outputs() {
    small_own_limit();
    let folder = temp_folder("reserved");
    copy_scene(&folder, "flag");
    for reserved in [".masssprings-lock", ".x.masssprings-1-2-3.tmp"] {
        // a texture of that name would be copied over the frames' lock
        std::fs::copy(folder.join("flag.png"), folder.join(reserved)).unwrap();
        let scene = std::fs::read_to_string(folder.join("flag.json"))
            .unwrap()
            .replace("flag.png", reserved);
        std::fs::write(folder.join("r.json"), scene).unwrap();
        let out = folder.join("out");
        std::fs::create_dir_all(&out).unwrap();
        let output = run_in(
            &folder,
            &[
                "simulate", "r.json", "--steps", "1", "--out", "out", "--force",
            ],
        );
        assert_fails(&output, &[reserved, "one masssprings keeps for itself"]);
        assert!(names_in(&out).is_empty(), "{:?}", names_in(&out));
        let named = run_in(&folder, &["export-q", "r.json", "-o", reserved]);
        assert_fails(&named, &["keeps for itself"]);
        assert_eq!(
            std::fs::read(folder.join(reserved)).unwrap(),
            std::fs::read(folder.join("flag.png")).unwrap()
        );
    }
}

#[test]
fn a_working_folder_deeper_than_an_absolute_path_may_be_works() {
    small_own_limit();
    let folder = temp_folder("deep");
    let name = "d".repeat(200);
    // made and entered one level at a time: no path here is longer than 4 KB
    let script = format!(
        "set -e; for i in $(seq 22); do mkdir {name}; cd {name}; done; \
         cp '{net}.json' '{net}.obj' .; M='{bin}'; \
         \"$M\" export-q net.json -o q.mtx; \"$M\" trace net.json -o T; \"$M\" trace net.json -o T; \
         \"$M\" simulate net.json --steps 2 --out F; \"$M\" simulate net.json --steps 1 --out F --force; \
         \"$M\" generate grid 3 --out G; test -f q.mtx; test -f T/trace.json; \
         test -f F/frame-000001.obj; test ! -e F/frame-000002.obj; test -f G/grid-3.obj; \
         test $(pwd | wc -c) -gt 4096; echo deep-ok",
        net = data("net"),
        bin = env!("CARGO_BIN_EXE_masssprings"),
    );
    // bash: dash's cd makes the path absolute, and fails past 4 KB
    let output = Command::new("bash")
        .args(["-c", &script])
        .current_dir(&folder)
        .env(masssprings::memory::LIMIT_VARIABLE, CHILD_LIMIT_GB)
        .output()
        .unwrap();
    assert!(
        String::from_utf8_lossy(&output.stdout).contains("deep-ok"),
        "{}",
        stderr(&output)
    );
    assert!(
        !stderr(&output).contains("File name too long"),
        "{}",
        stderr(&output)
    );
    // removed by the folder's clean-up (std's remove_dir_all goes down by
    // file descriptors, not by paths)
}

#[test]
fn a_trace_into_a_mount_point_or_the_current_folder_is_written_in_place() {
    small_own_limit();
    let folder = temp_folder("mounted");
    copy_scene(&folder, "net");
    let (source, mounted) = (folder.join("source"), folder.join("mounted"));
    std::fs::create_dir_all(&source).unwrap();
    std::fs::create_dir_all(&mounted).unwrap();
    // a bind mount where the test may mount (root with CAP_SYS_ADMIN);
    // elsewhere the same folder, unmounted: what is checked either way is
    // that the folder is written in place, never renamed nor exchanged,
    // which is what lets a mount point (EBUSY) or an overlay (EXDEV) work
    let bound = Command::new("mount")
        .args(["--bind", &text(&source), &text(&mounted)])
        .output()
        .is_ok_and(|o| o.status.success());
    let inode = |path: &Path| {
        use std::os::unix::fs::MetadataExt;
        let m = std::fs::metadata(path).unwrap();
        (m.dev(), m.ino())
    };
    let before = inode(&mounted);
    for _ in 0..2 {
        let output = run_in(&folder, &["trace", "net.json", "-o", "mounted"]);
        assert!(
            output.status.success(),
            "bound {bound}: {}",
            stderr(&output)
        );
        let forced = run_in(&folder, &["trace", "net.json", "-o", "mounted", "--force"]);
        assert!(forced.status.success(), "{}", stderr(&forced));
    }
    assert_eq!(inode(&mounted), before);
    if bound {
        assert!(
            source.join("trace.json").exists(),
            "written through the mount"
        );
        let _ = Command::new("umount").arg(&mounted).status();
    }
    // the current folder, where a shell may be
    let here = inode(&folder);
    for _ in 0..2 {
        let output = run_in(&folder, &["trace", "net.json", "-o", ".", "--force"]);
        assert!(output.status.success(), "{}", stderr(&output));
    }
    assert_eq!(inode(&folder), here);
    let dash = run_in(&folder, &["trace", "net.json", "-o", "-"]);
    assert_eq!(dash.status.code(), Some(2), "{}", stderr(&dash));
    assert!(
        stderr(&dash).contains("-o -: trace writes a folder"),
        "{}",
        stderr(&dash)
    );
    assert!(!folder.join("-").exists());
}

#[test]
fn trace_compare_names_links_pivots_mistakes_and_escapes() {
    small_own_limit();
    let folder = temp_folder("compare-messages");
    copy_scene(&folder, "net");
    let ours_ok = run_in(&folder, &["trace", "net.json", "-o", "ours"]);
    assert!(ours_ok.status.success(), "{}", stderr(&ours_ok));
    let theirs = folder.join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    let compare = || run_in(&folder, &["trace", "--compare", "ours", "theirs"]);
    // L with its first column negated: L Lᵀ is the same, L is no Cholesky factor
    let l = std::fs::read_to_string(folder.join("ours/L.mtx")).unwrap();
    let negated: Vec<String> = l
        .lines()
        .map(|line| {
            let parts: Vec<&str> = line.split_whitespace().collect();
            match parts.as_slice() {
                [i, "1", v] if !line.starts_with('%') => match v.strip_prefix('-') {
                    Some(positive) => format!("{i} 1 {positive}"),
                    None => format!("{i} 1 -{v}"),
                },
                _ => line.to_string(),
            }
        })
        .collect();
    std::fs::write(theirs.join("L.mtx"), negated.join("\n") + "\n").unwrap();
    std::fs::copy(folder.join("ours/P.mtx"), theirs.join("P.mtx")).unwrap();
    let output = compare();
    let out = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        out.contains("its diagonal must be positive, and pivot 1 (entry (1, 1)) is -"),
        "{out}"
    );
    assert!(
        out.contains("theirs/L.mtx: not a Cholesky factor"),
        "with its folder: {out}"
    );
    // links that dangle or loop are named as such, not "not given"
    std::fs::remove_file(theirs.join("L.mtx")).unwrap();
    std::os::unix::fs::symlink("nowhere.mtx", theirs.join("L.mtx")).unwrap();
    std::os::unix::fs::symlink("y.mtx", theirs.join("y.mtx")).unwrap();
    let out = String::from_utf8_lossy(&compare().stdout).into_owned();
    assert!(
        out.contains("a link to nowhere.mtx, which does not exist"),
        "{out}"
    );
    assert!(out.contains("y.mtx: a link that loops"), "{out}");
    // names from the folder escaped: no line broken, no terminal driven
    std::fs::write(theirs.join("evil\n\u{1b}[31m.mtx"), "x").unwrap();
    let out = String::from_utf8_lossy(&compare().stdout).into_owned();
    assert!(out.contains("evil\\n\\u{1b}[31m.mtx"), "{out}");
    assert!(!out.contains('\u{1b}'), "{out}");
    // a mistake's trace: refused over a correct one, named when compared
    let refused = run_in(
        &folder,
        &[
            "trace",
            "net.json",
            "-o",
            "ours",
            "--mistake",
            "mass-doubled",
        ],
    );
    assert_fails(&refused, &["holds a correct trace (no mistake)", "--force"]);
    let made = run_in(
        &folder,
        &[
            "trace",
            "net.json",
            "-o",
            "mistaken",
            "--mistake",
            "mass-doubled",
        ],
    );
    assert!(made.status.success(), "{}", stderr(&made));
    let other = run_in(
        &folder,
        &["trace", "net.json", "-o", "mistaken", "--mistake", "a-sign"],
    );
    assert_fails(&other, &["holds a trace with the mistake mass-doubled"]);
    let compared = run_in(&folder, &["trace", "--compare", "ours", "mistaken"]);
    let first = String::from_utf8_lossy(&compared.stdout)
        .lines()
        .next()
        .unwrap_or("")
        .to_string();
    assert!(
        first.contains("mistaken holds a trace with the mistake mass-doubled"),
        "{first}"
    );
    let compared = run_in(&folder, &["trace", "--compare", "mistaken", "ours"]);
    let first = String::from_utf8_lossy(&compared.stdout)
        .lines()
        .next()
        .unwrap_or("")
        .to_string();
    assert!(first.contains("not the correct quantities"), "{first}");
}

#[test]
fn converge_keeps_a_users_file_beside_its_oracle_plot() {
    small_own_limit();
    let folder = temp_folder("oracle-csv");
    copy_scene(&folder, "net");
    std::fs::write(folder.join("res.csv"), "my table\n").unwrap();
    let args = [
        "converge",
        "net.json",
        "--steps",
        "1",
        "--accuracy",
        "assignment",
        "--oracle",
        "res.png",
    ];
    let output = run_in(&folder, &args);
    assert_fails(
        &output,
        &["res.csv, which holds something else", "would be replaced"],
    );
    assert_eq!(
        std::fs::read_to_string(folder.join("res.csv")).unwrap(),
        "my table\n"
    );
    assert!(!folder.join("res.png").exists());
}

#[test]
fn the_library_refuses_a_q_that_would_overflow() {
    small_own_limit();
    use masssprings::sim::precomputation::MassSpringSystem;
    use masssprings::sim::{SimulationError, Sparse};
    let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let springs = [[0, 1], [1, 2], [1, 2]];
    let refused = MassSpringSystem::<Sparse>::new(&v, &springs, 1e308, &[1.0; 3], &[0], 0.03);
    match refused {
        Err(SimulationError::QOverflow(why)) => assert!(
            why.contains("k × 3 (the springs at vertex 2)")
                && why.contains("Q fits with k up to 2.9e307"),
            "{why}"
        ),
        other => panic!("{:?}", other.map(|_| ())),
    }
    let heavy =
        MassSpringSystem::<Sparse>::new(&v, &springs[..1], 1.0, &[1.0, 1e308, 1.0], &[0], 0.03);
    assert!(
        matches!(&heavy, Err(SimulationError::QOverflow(why)) if why.contains("the mass 1e308 of vertex 2")),
        "{:?}",
        heavy.map(|_| ())
    );
}
