//! `masssprings converge` as a user runs it: the CSV has the documented
//! header and one row per method and iteration, iteration 0 included, with
//! energies that start at 0; the plot is a PNG; `--steps` prints medians;
//! `--steps --tolerance` solves every step by the stopping rule and says how
//! many steps reached plain-50's energy; `simulate --start` reports where
//! steps start and refuses a start it does not know.
#[path = "common/cli.rs"]
mod cli;

use cli::{data, masssprings, stderr, stdout, temp_folder};

#[test]
fn converge_writes_one_csv_row_per_method_and_iteration_and_a_png() {
    let folder = temp_folder("converge-csv");
    let (csv, png) = (folder.join("curves.csv"), folder.join("curves.png"));
    let output = masssprings(&[
        "converge",
        &data("net.json"),
        "--step",
        "3",
        "--iterations",
        "20",
        "--methods",
        "plain,chebyshev,anderson,lbfgs",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        png.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("method,iteration,energy,relative_gradient,elapsed_ms")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    for method in ["plain", "chebyshev", "anderson", "lbfgs"] {
        let mine: Vec<&Vec<&str>> = rows.iter().filter(|r| r[0] == method).collect();
        assert_eq!(mine.len(), 21, "{method}: iterations 0..=20");
        for (i, row) in mine.iter().enumerate() {
            assert_eq!(row[1].parse::<usize>().unwrap(), i, "{method}");
            let energy: f64 = row[2].parse().unwrap();
            let gradient: f64 = row[3].parse().unwrap();
            let ms: f64 = row[4].parse().unwrap();
            assert!(
                energy.is_finite() && gradient >= 0.0 && ms >= 0.0,
                "{row:?}"
            );
            if i == 0 {
                assert_eq!(energy, 0.0, "{method} starts at the step's start");
            } else {
                // no method accepts an iterate above the step's start
                assert!(energy <= 0.0, "{method} iteration {i}: {energy}");
            }
        }
    }
    let picture = std::fs::read(&png).unwrap();
    assert_eq!(&picture[..8], b"\x89PNG\r\n\x1a\n");
    assert!(stdout(&output).contains("to plain-50"));
}

#[test]
fn converge_over_steps_prints_a_median_per_method() {
    let output = masssprings(&[
        "converge",
        &data("net.json"),
        "--steps",
        "3",
        "--iterations",
        "60",
        "--methods",
        "plain,lbfgs",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("median over the steps"), "{text}");
    let plain = text.lines().find(|l| l.starts_with("plain")).unwrap();
    // plain reaches its own 50-iteration energy at iteration 50 at the latest
    let fields: Vec<&str> = plain.split_whitespace().collect();
    let iterations: f64 = fields[1].parse().unwrap();
    assert!(iterations <= 50.0, "{plain}");
    // the time against plain-50's own (a separate run: not exactly 1)
    let ratio: f64 = fields[3].parse().unwrap();
    assert!(ratio > 0.0, "{plain}");
}

#[test]
fn converge_with_a_tolerance_solves_each_step_by_the_rule() {
    let output = masssprings(&[
        "converge",
        &data("net.json"),
        "--steps",
        "3",
        "--tolerance",
        "0.000001",
        "--iterations",
        "300",
        "--methods",
        "newton,lbfgs",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    for method in ["newton", "lbfgs"] {
        let line = text
            .lines()
            .find(|l| l.starts_with(method))
            .unwrap_or_else(|| panic!("{text}"));
        // a relative gradient of 1e-6 is far below what 50 plain iterations
        // leave, so every step ends below plain-50's energy
        assert!(line.ends_with("3 of 3"), "{line}");
    }
}

#[test]
fn a_relaxation_outside_its_range_is_a_usage_error() {
    for bad in ["0", "2.5", "fast"] {
        let output = masssprings(&["converge", &data("net.json"), "--relaxation", bad]);
        assert_eq!(output.status.code(), Some(2), "{bad}: {}", stderr(&output));
        assert!(
            stderr(&output).contains("--relaxation expects a number above 0 and at most 2"),
            "{bad}: {}",
            stderr(&output)
        );
    }
}

#[test]
fn a_tolerance_without_steps_is_a_usage_error() {
    for flag in ["--tolerance", "--energy-tolerance"] {
        let output = masssprings(&["converge", &data("net.json"), flag, "0.5"]);
        assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
        assert!(
            stderr(&output).contains("--tolerance and --energy-tolerance need --steps"),
            "{}",
            stderr(&output)
        );
    }
}

#[test]
fn converge_with_an_energy_tolerance_solves_each_step_by_that_rule() {
    let output = masssprings(&[
        "converge",
        &data("flag.json"),
        "--steps",
        "3",
        "--energy-tolerance",
        "0.1",
        "--iterations",
        "200",
        "--methods",
        "chebyshev,lbfgs",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("--energy-tolerance 0.1"), "{text}");
    for method in ["chebyshev", "lbfgs"] {
        let line = text
            .lines()
            .find(|l| l.starts_with(method))
            .unwrap_or_else(|| panic!("{text}"));
        // the rule stops well before the budget of 200 on every step
        let iterations: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert!(iterations < 50.0, "{line}");
    }
}

#[test]
fn an_energy_tolerance_outside_zero_to_one_is_a_usage_error() {
    for bad in ["0", "1", "-0.1", "soon"] {
        let output = masssprings(&[
            "simulate",
            &data("net.json"),
            "--steps",
            "1",
            "--energy-tolerance",
            bad,
        ]);
        assert_eq!(output.status.code(), Some(2), "{bad}: {}", stderr(&output));
        assert!(
            stderr(&output).contains("--energy-tolerance expects a fraction of the decrease"),
            "{bad}: {}",
            stderr(&output)
        );
    }
}

#[test]
fn simulate_reports_where_steps_start_and_refuses_an_unknown_start() {
    let output = masssprings(&[
        "simulate",
        &data("net.json"),
        "--steps",
        "3",
        "--start",
        "inertial",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let report: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(report["start"], "inertial", "{report}");
    let output = masssprings(&["simulate", &data("net.json"), "--start", "momentum"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("--start"), "{}", stderr(&output));
}
