//! The command line, run as a user runs it: outputs, exit codes, errors.
use crate::cli;
use crate::common;

use cli::{blow_up_scene, data, masssprings, stderr, stdout, temp_folder};

use common::grid_matrix;
use masssprings::files::write_file;
use masssprings::linalg::sparse::{Ordering, Relaxation, SymbolicCholesky};
use masssprings::matrix_market::{write_coordinate, Symmetry};
use std::path::Path;
use std::process::Output;

fn json(output: &Output) -> serde_json::Value {
    assert!(output.status.success(), "failed: {}", stderr(output));
    serde_json::from_str(stdout(output).trim()).expect("one JSON object on stdout")
}

#[test]
fn analyze_reports_every_key_and_a_small_residual() {
    let folder = temp_folder("analyze");
    let path = folder.join("grid-12.mtx");
    let q = grid_matrix(12);
    write_file(&path, |out| {
        write_coordinate(out, &q, Symmetry::Symmetric, "grid-12")
    })
    .unwrap();
    let report = json(&masssprings(&[
        "analyze",
        path.to_str().unwrap(),
        "--json",
        "--repeats",
        "3",
    ]));
    for key in [
        "n",
        "nnz_a",
        "nnz_l",
        "flops",
        "ordering_s",
        "symbolic_s",
        "numeric_s",
        "solve_s",
        "residual",
        "backward_error",
    ] {
        assert!(report.get(key).is_some(), "missing {key} in {report}");
    }
    let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
    assert_eq!(report["n"], 144);
    assert_eq!(report["nnz_l"], symbolic.nnz_l());
    assert_eq!(
        report["nnz_a"],
        q.triangle(masssprings::linalg::sparse::Triangle::Lower)
            .nnz()
    );
    assert!(report["residual"].as_f64().unwrap() < 1e-12, "{report}");
    // the supernodes by width (by default small ones merged, as in the
    // simulation): every supernode in one class, all of L
    let merged = symbolic.relaxed(&Relaxation::SMALL);
    let classes = report["supernodes_by_width"].as_array().unwrap();
    let count: u64 = classes
        .iter()
        .map(|c| c["supernodes"].as_u64().unwrap())
        .sum();
    let share: f64 = classes
        .iter()
        .map(|c| c["share_of_l"].as_f64().unwrap())
        .sum();
    assert_eq!(count as usize, merged.supernodes().len(), "{report}");
    assert!((share - 1.0).abs() < 1e-12, "{report}");
    assert_eq!(classes[0]["widest"], 1);
    assert_eq!(classes.last().unwrap()["widest"], serde_json::Value::Null);
    // Cholesky is backward stable: a few units of roundoff (2⁻⁵³ ≈ 1.1e-16)
    let backward_error = report["backward_error"].as_f64().unwrap();
    assert!((0.0..1e-15).contains(&backward_error), "{report}");
    let natural = json(&masssprings(&[
        "analyze",
        path.to_str().unwrap(),
        "--json",
        "--ordering",
        "natural",
        "--repeats",
        "1",
    ]));
    assert!(natural["nnz_l"].as_u64() >= report["nnz_l"].as_u64());
    let human = masssprings(&[
        "analyze",
        path.to_str().unwrap(),
        "--repeats",
        "1",
        "--factorization",
        "simplicial",
        "--supernodes",
        "relaxed",
    ]);
    assert!(human.status.success(), "{}", stderr(&human));
    assert!(stdout(&human).contains("nnz(L)"));
    // the old names are refused with a pointer to the new ones
    for (old, value, new) in [
        ("--method", "simplicial", "--factorization"),
        ("--relax", "cholmod", "--supernodes"),
    ] {
        let output = masssprings(&["analyze", path.to_str().unwrap(), old, value]);
        assert_eq!(output.status.code(), Some(2), "{old}");
        assert!(stderr(&output).contains(new), "{old}: {}", stderr(&output));
    }
}

#[test]
fn analyze_times_the_simulations_factor_with_supernodes_small() {
    let folder = temp_folder("analyze-small");
    let path = folder.join("grid-12.mtx");
    write_file(&path, |out| {
        write_coordinate(out, &grid_matrix(12), Symmetry::Symmetric, "grid-12")
    })
    .unwrap();
    let report = |supernodes: &str| {
        let path = path.to_str().unwrap();
        let args = [
            "analyze",
            path,
            "--json",
            "--repeats",
            "1",
            "--supernodes",
            supernodes,
        ];
        json(&masssprings(&args))
    };
    let supernode_count = |r: &serde_json::Value| -> u64 {
        let classes = r["supernodes_by_width"].as_array().unwrap();
        classes
            .iter()
            .map(|c| c["supernodes"].as_u64().unwrap())
            .sum()
    };
    let (fundamental, small) = (report("fundamental"), report("small"));
    // the same L, fewer and wider supernodes, some zeros stored
    assert_eq!(small["nnz_l"], fundamental["nnz_l"]);
    assert!(supernode_count(&small) < supernode_count(&fundamental));
    assert!(small["nnz_l_stored"].as_u64() > fundamental["nnz_l_stored"].as_u64());
    assert!(small["backward_error"].as_f64().unwrap() < 1e-15, "{small}");
}

#[test]
fn analyze_uses_the_right_hand_side_file_when_there_is_one() {
    let folder = temp_folder("analyze-rhs");
    let path = folder.join("q.mtx");
    let q = grid_matrix(5);
    write_file(&path, |out| {
        write_coordinate(out, &q, Symmetry::Symmetric, "q")
    })
    .unwrap();
    std::fs::write(
        folder.join("q.b.mtx"),
        "%%MatrixMarket matrix array real general\n2 3\n1\n2\n3\n4\n5\n6\n",
    )
    .unwrap();
    let output = masssprings(&["analyze", path.to_str().unwrap(), "--json"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("q.b.mtx"), "{}", stderr(&output));
}

#[test]
fn analyze_names_the_file_and_line_of_a_bad_matrix() {
    let folder = temp_folder("analyze-bad");
    let path = folder.join("bad.mtx");
    std::fs::write(
        &path,
        "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 4\n2 x 1\n",
    )
    .unwrap();
    let output = masssprings(&["analyze", path.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("bad.mtx:4"), "{}", stderr(&output));
    let missing = masssprings(&["analyze", folder.join("missing.mtx").to_str().unwrap()]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(stderr(&missing).contains("missing.mtx"));
}

#[test]
fn analyze_reports_a_matrix_that_is_not_positive_definite() {
    let folder = temp_folder("analyze-indefinite");
    let path = folder.join("indefinite.mtx");
    std::fs::write(
        &path,
        "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 1\n2 2 -2\n3 3 1\n",
    )
    .unwrap();
    let output = masssprings(&["analyze", path.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("not positive definite"),
        "{}",
        stderr(&output)
    );
    assert!(stderr(&output).contains("column 1"), "{}", stderr(&output));
}

#[test]
fn usage_errors_exit_with_two() {
    for args in [
        vec![],
        vec!["frobnicate"],
        vec!["analyze"],
        vec!["analyze", "a.mtx", "--ordering", "metis"],
        vec!["analyze", "a.mtx", "--bogus"],
        vec!["simulate", "scene.json", "--steps", "many"],
        vec!["simulate", "scene.json", "--every", "0"],
    ] {
        let output = masssprings(&args);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{args:?}: {}",
            stderr(&output)
        );
        assert!(!stderr(&output).is_empty());
    }
    assert!(masssprings(&["help"]).status.success());
}

#[test]
fn simulate_writes_frames_that_read_back_exactly() {
    let folder = temp_folder("frames");
    let output = masssprings(&[
        "simulate",
        &data("net.json"),
        "--steps",
        "7",
        "--every",
        "3",
        "--out",
        folder.to_str().unwrap(),
        "--json",
    ]);
    let summary = json(&output);
    for key in ["n", "springs", "steps", "precompute_s", "step_median_s"] {
        assert!(summary.get(key).is_some(), "missing {key} in {summary}");
    }
    assert_eq!(summary["steps"], 7);
    let mut names: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["frame-000000.obj", "frame-000003.obj", "frame-000006.obj"]
    );
    // a frame is a scene mesh: the original JSON pointed at a frame loads
    let frame = std::fs::read_to_string(folder.join("frame-000006.obj")).unwrap();
    let vertices = frame.lines().filter(|l| l.starts_with("v ")).count();
    assert_eq!(serde_json::Value::from(vertices), summary["n"]);
    // the same run through the library gives exactly the written numbers
    let scene = masssprings::mesh::load_scene(Path::new(&data("net.json"))).unwrap();
    let mut sim = masssprings::sim::Simulation::<masssprings::sim::Sparse>::from_scene(
        &scene,
        Default::default(),
    )
    .unwrap();
    for _ in 0..6 {
        sim.step().unwrap();
    }
    let written: Vec<[f64; 3]> = frame
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    assert_eq!(written.as_slice(), sim.positions());
}

#[test]
fn simulate_runs_the_portable_kernels_on_request_and_says_which_ran() {
    let flag = data("flag.json");
    let run = |kernels: &str| {
        let args = [
            "simulate",
            &flag,
            "--steps",
            "2",
            "--kernels",
            kernels,
            "--json",
        ];
        json(&masssprings(&args))
    };
    assert_eq!(run("portable")["kernels"], "portable");
    assert_eq!(run("native")["kernels"], "native");
    let refused = masssprings(&["simulate", &flag, "--kernels", "fast"]);
    assert_eq!(refused.status.code(), Some(2));
    let message = stderr(&refused);
    assert!(
        message.contains("native") && message.contains("portable"),
        "{message}"
    );
}

#[test]
fn simulate_writes_the_same_frames_on_any_number_of_threads() {
    let flag = data("flag.json");
    let frames = |threads: &str, kernels: &str| {
        let folder = temp_folder(&format!("threads-{threads}-{kernels}"));
        let args = [
            "simulate",
            &flag,
            "--steps",
            "6",
            "--every",
            "6",
            "--threads",
            threads,
            "--kernels",
            kernels,
            "--out",
            folder.to_str().unwrap(),
            "--json",
        ];
        let summary = json(&masssprings(&args));
        assert_eq!(summary["threads"].as_u64(), Some(threads.parse().unwrap()));
        std::fs::read(folder.join("frame-000006.obj")).unwrap()
    };
    for kernels in ["native", "portable"] {
        let one = frames("1", kernels);
        for threads in ["2", "3", "4"] {
            assert!(
                frames(threads, kernels) == one,
                "{threads} threads, {kernels} kernels"
            );
        }
    }
    // the textbook path runs on one thread, and says so
    let args = [
        "simulate",
        &flag,
        "--steps",
        "1",
        "--textbook",
        "--threads",
        "3",
        "--json",
    ];
    assert_eq!(json(&masssprings(&args))["threads"], 1);
    let refused = masssprings(&["simulate", &flag, "--threads", "0"]);
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
}

#[test]
fn analyze_on_threads_reports_the_speedup_over_one_thread_and_the_same_bits() {
    let folder = temp_folder("analyze-threads");
    let path = folder.join("grid-40.mtx");
    write_file(&path, |out| {
        write_coordinate(out, &grid_matrix(40), Symmetry::Symmetric, "grid-40")
    })
    .unwrap();
    let file = path.to_str().unwrap();
    let args = [
        "analyze",
        file,
        "--json",
        "--repeats",
        "3",
        "--threads",
        "3",
    ];
    let report = json(&masssprings(&args));
    assert_eq!(report["threads"], 3, "{report}");
    let one = &report["one_thread"];
    assert_eq!(one["same_bits"], true, "{report}");
    for key in ["numeric_s", "solve_s", "numeric_speedup", "solve_speedup"] {
        assert!(one[key].as_f64().unwrap() > 0.0, "{key} in {report}");
    }
    let alone = json(&masssprings(&[
        "analyze",
        file,
        "--json",
        "--repeats",
        "1",
        "--threads",
        "1",
    ]));
    assert_eq!(alone["threads"], 1);
    assert!(alone["one_thread"].is_null(), "{alone}");
}

#[test]
fn simulate_dense_and_sparse_both_run() {
    for backend in [&["--dense"][..], &[][..]] {
        let mut args = vec![
            "simulate",
            "data/single-spring-horizontal.json",
            "--steps",
            "3",
            "--json",
        ];
        let path = data("single-spring-horizontal.json");
        args[1] = &path;
        args.extend_from_slice(backend);
        let summary = json(&masssprings(&args));
        assert_eq!(summary["n"], 2);
        assert_eq!(summary["springs"], 1);
    }
}

#[test]
fn simulate_names_the_file_and_line_of_a_bad_scene() {
    let folder = temp_folder("bad-scene");
    std::fs::write(
        folder.join("s.json"),
        r#"{"obj": "s.obj", "k": 1, "b": [1], "m": 1}"#,
    )
    .unwrap();
    std::fs::write(folder.join("s.obj"), "v 0 0 0\nv 1 0 0\nf 1 3\n").unwrap();
    let output = masssprings(&[
        "simulate",
        folder.join("s.json").to_str().unwrap(),
        "--out",
        folder.join("frames").to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("s.obj:3"), "{}", stderr(&output));
    assert!(
        !folder.join("frames").exists(),
        "no output for a scene that did not load"
    );
}

#[test]
fn a_step_that_blows_up_is_reported_and_leaves_only_whole_frames() {
    let folder = temp_folder("blow-up");
    let scene = blow_up_scene(&folder);
    let frames = folder.join("frames");
    let output = masssprings(&[
        "simulate",
        scene.to_str().unwrap(),
        "--out",
        frames.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("step 1: the step produced a non-finite position"),
        "{}",
        stderr(&output)
    );
    let names: Vec<String> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        ["frame-000000.obj"],
        "only the whole frame of step 0, no temporary"
    );
}

/// Least-squares slope of `ln y` on `ln x`.
fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let count = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / count;
    let sxy: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let sxx: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    sxy / sxx
}

#[test]
fn bench_reports_every_key_and_slopes_fitted_to_its_own_figures() {
    let folder = temp_folder("bench");
    let csv = folder.join("bench.csv");
    let plot = folder.join("bench.png");
    let report = json(&masssprings(&[
        "bench",
        "--sizes",
        "4,6,9",
        "--steps",
        "2",
        "--json",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
        "--threads",
        "2",
    ]));
    let png = std::fs::read(&plot).unwrap();
    assert!(png.starts_with(b"\x89PNG"), "not a PNG");
    assert!(report["triad_gbps"].as_f64().unwrap() > 0.0, "{report}");
    let sizes = report["sizes"].as_array().expect("sizes");
    assert_eq!(sizes.len(), 3);
    let times = ["ordering_s", "symbolic_s", "numeric_s", "solve_s", "step_s"];
    for (size, side) in sizes.iter().zip([4, 6, 9]) {
        assert_eq!(size["n"], side * side, "{size}");
        for key in ["nnz_q", "nnz_l", "flops", "peak_bytes", "solve_gbps"] {
            assert!(size[key].as_f64().unwrap() > 0.0, "{key} in {size}");
        }
        for key in times {
            assert!(size[key].as_f64().unwrap() > 0.0, "{key} in {size}");
        }
        // the solve, the local step and Aᵀd as shares of one iteration (step / 50)
        let iteration = size["step_s"].as_f64().unwrap() / 50.0;
        for (time, share) in [
            ("solve_s", "solve_share"),
            ("local_step_s", "local_step_share"),
            ("atd_s", "atd_share"),
            ("springs_pass_s", "springs_pass_share"),
        ] {
            let (time, share) = (size[time].as_f64().unwrap(), size[share].as_f64().unwrap());
            assert!(time > 0.0, "{size}");
            assert!((share - time / iteration).abs() <= 1e-9 * share, "{size}");
        }
        assert!(size["nnz_l"].as_u64() <= size["nnz_l_stored"].as_u64());
        assert!(size["residual"].as_f64().unwrap() < 1e-12, "{size}");
        assert!(size["backward_error"].as_f64().unwrap() < 1e-15, "{size}");
    }
    for key in times.iter().chain(&["peak_bytes"]) {
        let points: Vec<(f64, f64)> = sizes
            .iter()
            .map(|s| (s["n"].as_f64().unwrap(), s[*key].as_f64().unwrap()))
            .collect();
        let printed = report["slopes"][*key].as_f64().expect(key);
        let fitted = log_log_slope(&points);
        assert!(
            (printed - fitted).abs() <= 1e-9 * (1.0 + fitted.abs()),
            "{key}: printed {printed}, fitted from the printed sizes {fitted}"
        );
    }
    // on more than one thread, one thread's times beside them
    for size in sizes {
        let threads = size["threads"].as_u64().unwrap();
        for key in [
            "numeric_one_thread_s",
            "solve_one_thread_s",
            "step_one_thread_s",
        ] {
            assert_eq!(
                size[key].as_f64().is_some_and(|t| t > 0.0),
                threads > 1,
                "{key} in {size}"
            );
        }
    }
    let table = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(table.lines().count(), 4, "{table}");
    assert!(table.starts_with("side,n,nnz_q,nnz_l,"), "{table}");
}

#[test]
fn bench_rejects_a_grid_side_below_two() {
    let output = masssprings(&["bench", "--sizes", "32,1"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    let error = stderr(&output);
    assert!(
        error.contains("--sizes") && error.contains("≥ 2") && error.contains("1 is out of range"),
        "{error}"
    );
}

#[test]
fn a_reader_that_goes_away_ends_a_command_quietly_not_with_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    // `masssprings converge net.json | head -0`: the pipe's reader is gone
    // before the command prints its first line
    let mut child = Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(["converge", &data("net.json"), "--methods", "plain"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let errors = String::from_utf8_lossy(&output.stderr);
    assert!(!errors.contains("panicked"), "{errors}");
    assert_eq!(
        output.status.signal(),
        Some(13),
        "ended by SIGPIPE, as `cat` would be: {:?}",
        output.status
    );
}
