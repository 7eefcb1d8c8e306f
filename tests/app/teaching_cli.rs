//! The commands of the student's path, run as a user runs them:
//! `simulate --textbook` (the handout's functions as written) and
//! `--ordering natural --factorization simplicial` against the default
//! path and the reference; `export-q` read back
//! by `analyze`; `spy` and `etree` pictures and the counts they print.
use crate::common;

use crate::cli;
use common::read_points;

use cli::{data, masssprings, stderr, stdout, temp_folder};
use masssprings::linalg::sparse::{Ordering, SymbolicCholesky, Triangle};
use masssprings::matrix_market::{self, MatrixMarket, Symmetry};
use masssprings::mesh::load_scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Simulation, Sparse};
use std::path::Path;
use std::process::Output;

fn succeeded(output: &Output) -> String {
    assert!(output.status.success(), "failed: {}", stderr(output));
    stdout(output)
}

/// The `v x y z` lines of an OBJ frame.
fn obj_positions(path: &Path) -> Vec<[f64; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|line| line.strip_prefix("v "))
        .map(|rest| {
            let v: Vec<f64> = rest
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

#[test]
fn the_textbook_flags_match_the_default_path_and_the_reference() {
    let folder = temp_folder("textbook-flags");
    let (textbook, fast) = (folder.join("textbook"), folder.join("fast"));
    succeeded(&masssprings(&[
        "simulate",
        &data("flag.json"),
        "--steps",
        "10",
        "--every",
        "10",
        "--ordering",
        "natural",
        "--factorization",
        "simplicial",
        "--out",
        textbook.to_str().unwrap(),
    ]));
    succeeded(&masssprings(&[
        "simulate",
        &data("flag.json"),
        "--steps",
        "10",
        "--every",
        "10",
        "--out",
        fast.to_str().unwrap(),
    ]));
    let a = obj_positions(&textbook.join("frame-000010.obj"));
    let b = obj_positions(&fast.join("frame-000010.obj"));
    assert_eq!(a.len(), 3200);
    // the two paths differ only in rounding (docs/README.md)
    let apart = max_distance(&a, &b);
    assert!(apart <= 1e-8, "textbook and default paths {apart:e} apart");
    let reference = read_points(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/reference/flag.step10.txt"),
    );
    let error = max_distance(&a, &reference);
    assert!(error <= 1e-6, "textbook path {error:e} from the reference");
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn simulate_textbook_runs_the_handouts_functions_and_says_so() {
    let folder = temp_folder("textbook-switch");
    let scene = data("net.json");
    let run = |extra: &[&str], out: &Path| {
        let out = out.to_str().unwrap();
        let mut args = vec!["simulate", &scene, "--steps", "10", "--out", out, "--json"];
        args.extend_from_slice(extra);
        succeeded(&masssprings(&args))
    };
    let textbook = run(&["--textbook"], &folder.join("textbook"));
    let dense = run(&["--textbook", "--dense"], &folder.join("dense"));
    let fast = run(&[], &folder.join("fast"));
    for (json, path) in [
        (&textbook, "textbook"),
        (&dense, "textbook"),
        (&fast, "fast"),
    ] {
        let summary: serde_json::Value = serde_json::from_str(json.trim()).unwrap();
        assert_eq!(summary["path"], path, "{json}");
    }
    let frame = |run: &str| obj_positions(&folder.join(run).join("frame-000010.obj"));
    for run in ["textbook", "dense"] {
        let apart = max_distance(&frame(run), &frame("fast"));
        assert!(apart <= 1e-8, "{run}: {apart:e} from the fast path");
    }
    // the handout's step has no other method, rule or kind of pin
    let refused = masssprings(&[
        "simulate",
        &data("net.json"),
        "--textbook",
        "--method",
        "lbfgs",
    ]);
    assert_ne!(refused.status.code(), Some(0));
    assert!(
        stderr(&refused).contains("textbook"),
        "{}",
        stderr(&refused)
    );
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn unknown_ordering_or_factorization_is_a_usage_error() {
    for (flag, value) in [("--ordering", "metis"), ("--factorization", "ldlt")] {
        let output = masssprings(&["simulate", &data("net.json"), flag, value]);
        assert_eq!(output.status.code(), Some(2), "{flag} {value}");
        assert!(stderr(&output).contains(value), "{}", stderr(&output));
    }
}

#[test]
fn export_q_writes_the_simulations_q_and_analyze_reads_it() {
    let folder = temp_folder("export-q");
    let path = folder.join("flag-q.mtx");
    succeeded(&masssprings(&[
        "export-q",
        &data("flag.json"),
        "-o",
        path.to_str().unwrap(),
    ]));
    // the file holds the lower triangle of the Q the simulation builds, exactly
    let scene = load_scene(Path::new(&data("flag.json"))).unwrap();
    let simulation =
        Simulation::<Sparse>::from_scene(&scene, SimulationOptions::default()).unwrap();
    let q = simulation.system().unwrap().q().triangle(Triangle::Lower);
    let MatrixMarket::Sparse(file) = matrix_market::read(&path).unwrap() else {
        panic!("expected a coordinate file");
    };
    assert_eq!(file.symmetry, Symmetry::Symmetric);
    assert_eq!(file.matrix.triangle(Triangle::Lower), q);
    // analyze reads it: its counts are those of our own analysis
    for (ordering, method) in [("amd", "supernodal"), ("natural", "simplicial")] {
        let report: serde_json::Value = serde_json::from_str(
            succeeded(&masssprings(&[
                "analyze",
                path.to_str().unwrap(),
                "--ordering",
                ordering,
                "--factorization",
                method,
                "--repeats",
                "1",
                "--json",
            ]))
            .trim(),
        )
        .unwrap();
        let symbolic = SymbolicCholesky::analyze(&q, ordering.parse().unwrap()).unwrap();
        assert_eq!(report["n"], 3200);
        assert_eq!(report["nnz_a"], q.nnz());
        assert_eq!(report["nnz_l"], symbolic.nnz_l());
        // w = 1e10 on the pins' diagonal: the natural order's residual is 1.4e-12
        assert!(report["residual"].as_f64().unwrap() < 1e-10, "{report}");
    }
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn export_q_without_an_output_is_a_usage_error() {
    let output = masssprings(&["export-q", &data("net.json")]);
    assert_eq!(output.status.code(), Some(2));
    let error = stderr(&output);
    assert!(
        error.contains("--out <Q.mtx>") && error.contains("required"),
        "{error}"
    );
}

/// Width and height of a PNG file.
fn png_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let reader = decoder.read_info().unwrap();
    (reader.info().width, reader.info().height)
}

/// The number after `key = ` in `text`.
fn number_after(text: &str, key: &str) -> f64 {
    let start = text
        .find(key)
        .unwrap_or_else(|| panic!("no '{key}' in {text}"))
        + key.len();
    text[start..]
        .trim_start()
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn spy_draws_q_and_l_and_prints_the_fill_of_each_ordering() {
    let folder = temp_folder("spy");
    let mut fill = Vec::new();
    for ordering in ["natural", "amd"] {
        let l_png = folder.join(format!("l-{ordering}.png"));
        let printed = succeeded(&masssprings(&[
            "spy",
            &data("flag.json"),
            "--ordering",
            ordering,
            "--factor",
            "-o",
            l_png.to_str().unwrap(),
        ]));
        // 480 pixels a side, a frame, 8 pixels of margin, two caption lines
        let (width, height) = png_size(&l_png);
        assert_eq!(width, 498);
        assert!(height > 498 && height < 600, "{height}");
        let scene = load_scene(Path::new(&data("flag.json"))).unwrap();
        let simulation =
            Simulation::<Sparse>::from_scene(&scene, SimulationOptions::default()).unwrap();
        let q = simulation.system().unwrap().q();
        let symbolic =
            SymbolicCholesky::analyze(&q, ordering.parse::<Ordering>().unwrap()).unwrap();
        assert_eq!(number_after(&printed, "nnz(L) ="), symbolic.nnz_l() as f64);
        fill.push(number_after(&printed, "nnz(tril Q) ="));
    }
    // AMD: less fill than the cloth's own (banded) numbering, 4.9 against 8.5
    assert!(
        fill[1] < fill[0],
        "fill natural {} AMD {}",
        fill[0],
        fill[1]
    );
    let q_png = folder.join("q.png");
    let printed = succeeded(&masssprings(&[
        "spy",
        &data("net.json"),
        "--size",
        "100",
        "-o",
        q_png.to_str().unwrap(),
    ]));
    assert_eq!(png_size(&q_png).0, 118);
    assert_eq!(number_after(&printed, "n ="), 81.0);
    // --size is WxH as everywhere; spy's picture is square
    let spelled = succeeded(&masssprings(&[
        "spy",
        &data("net.json"),
        "--size",
        "100x100",
        "-o",
        q_png.to_str().unwrap(),
    ]));
    assert_eq!((spelled, png_size(&q_png).0), (printed, 118));
    let oblong = masssprings(&["spy", &data("net.json"), "--size", "100x50", "-o", "x.png"]);
    assert_eq!(oblong.status.code(), Some(2));
    assert!(stderr(&oblong).contains("square"), "{}", stderr(&oblong));
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn etree_draws_the_tree_and_counts_its_supernodes() {
    let folder = temp_folder("etree");
    let out = folder.join("tree.png");
    let printed = succeeded(&masssprings(&[
        "etree",
        &data("net.json"),
        "--size",
        "400x200",
        "-o",
        out.to_str().unwrap(),
    ]));
    let (width, height) = png_size(&out);
    assert_eq!(width, 400);
    assert!(height > 200 && height < 300, "{height}");
    let scene = load_scene(Path::new(&data("net.json"))).unwrap();
    let simulation =
        Simulation::<Sparse>::from_scene(&scene, SimulationOptions::default()).unwrap();
    let symbolic =
        SymbolicCholesky::analyze(&simulation.system().unwrap().q(), Ordering::Amd).unwrap();
    assert_eq!(number_after(&printed, "nnz(L) ="), symbolic.nnz_l() as f64);
    assert!(
        printed.contains(&format!("{} supernodes", symbolic.supernodes().len())),
        "{printed}"
    );
    let too_big = masssprings(&["etree", &data("skirt.json"), "-o", out.to_str().unwrap()]);
    assert_eq!(too_big.status.code(), Some(1));
    assert!(stderr(&too_big).contains("at most"), "{}", stderr(&too_big));
    std::fs::remove_dir_all(&folder).unwrap();
}
