//! `masssprings converge` as a user runs it: the CSV has the documented
//! header and one row per method and iteration, iteration 0 included, with
//! energies that start at 0; the plot is a PNG; `--steps` prints medians
//! and writes one CSV row per step and method and a per-step plot;
//! `--steps --tolerance` solves every step by the stopping rule and says how
//! many steps reached plain-50's energy, as its CSV rows show; `simulate --start` reports where
//! steps start and refuses a start it does not know.
use crate::cli;

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
    let folder = temp_folder("converge-steps-csv");
    let csv = folder.join("steps.csv");
    let output = masssprings(&[
        "converge",
        &data("net.json"),
        "--steps",
        "3",
        "--iterations",
        "60",
        "--methods",
        "plain,lbfgs",
        "--csv",
        csv.to_str().unwrap(),
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
    // one CSV row per step and method, and the median printed is theirs
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("step,method,iterations_to_plain_50,ms_to_plain_50,plain_50_ms")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 6, "{text}");
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], (1 + i / 2).to_string(), "{text}");
        assert_eq!(row[1], ["plain", "lbfgs"][i % 2], "{text}");
        assert!(row[4].parse::<f64>().unwrap() > 0.0, "{text}");
    }
    let mut plain_iterations: Vec<f64> = rows
        .iter()
        .filter(|r| r[1] == "plain")
        .map(|r| r[2].parse().unwrap())
        .collect();
    plain_iterations.sort_by(f64::total_cmp);
    assert_eq!(plain_iterations[1], iterations, "{text}");
}

#[test]
fn converge_over_steps_draws_each_steps_cost_and_accuracy() {
    let folder = temp_folder("converge-steps-plot");
    for (name, rule) in [("reach.png", None), ("rule.png", Some("0.2"))] {
        let png = folder.join(name);
        let mut args = vec![
            "converge".to_string(),
            data("net.json"),
            "--steps".into(),
            "2".into(),
            "--methods".into(),
            "plain,lbfgs".into(),
            "--plot".into(),
            png.to_str().unwrap().into(),
        ];
        if let Some(fraction) = rule {
            args.extend(["--energy-tolerance".into(), fraction.into()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let output = masssprings(&args);
        assert!(output.status.success(), "{name}: {}", stderr(&output));
        let picture = std::fs::read(&png).unwrap();
        assert_eq!(&picture[..8], b"\x89PNG\r\n\x1a\n", "{name}");
    }
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
            stderr(&output).contains("--relaxation")
                && stderr(&output).contains("a number above 0 and at most 2")
                && stderr(&output).contains(&format!("'{bad}'")),
            "{bad}: {}",
            stderr(&output)
        );
    }
}

#[test]
fn a_tolerance_without_steps_is_a_usage_error() {
    for (flag, value) in [
        ("--tolerance", "0.5"),
        ("--energy-tolerance", "0.5"),
        ("--at-least-plain", "50"),
    ] {
        let output = masssprings(&["converge", &data("net.json"), flag, value]);
        assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
        assert!(
            stderr(&output).contains("--steps") && stderr(&output).contains("required"),
            "{}",
            stderr(&output)
        );
    }
}

#[test]
fn converge_with_an_energy_tolerance_solves_each_step_by_that_rule() {
    let folder = temp_folder("converge-rule-csv");
    let csv = folder.join("rule.csv");
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
        "--csv",
        csv.to_str().unwrap(),
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
        // the CSV's rows agree with the count of steps at plain-50's energy
        let reached = line.split_whitespace().nth(4).unwrap();
        let text = std::fs::read_to_string(&csv).unwrap();
        assert!(
            text.starts_with("step,method,iterations,stop,energy,plain_50_energy,ms,plain_50_ms\n")
        );
        let rows: Vec<Vec<&str>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .filter(|r: &Vec<&str>| r[1] == method)
            .collect();
        assert_eq!(rows.len(), 3, "{text}");
        let at_plain_50 = rows
            .iter()
            .filter(|r| {
                let (energy, target): (f64, f64) = (r[4].parse().unwrap(), r[5].parse().unwrap());
                assert!(energy < 0.0 && target < 0.0, "{r:?}");
                assert!(r[3] == "energy-tolerance" || r[3] == "iterations", "{r:?}");
                energy <= target + 1e-12 * target.abs()
            })
            .count();
        assert_eq!(reached, at_plain_50.to_string(), "{line}\n{text}");
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
            stderr(&output).contains("--energy-tolerance")
                && stderr(&output).contains("between 0 and 1")
                && stderr(&output).contains(&format!("'{bad}'")),
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

#[test]
fn at_least_plain_below_one_or_not_a_number_is_a_usage_error() {
    for bad in ["0.5", "0", "-3", "many", "1e7"] {
        let output = masssprings(&[
            "simulate",
            &data("net.json"),
            "--steps",
            "1",
            "--at-least-plain",
            bad,
        ]);
        assert_eq!(output.status.code(), Some(2), "{bad}: {}", stderr(&output));
        assert!(
            stderr(&output).contains("--at-least-plain")
                && stderr(&output).contains("a number of plain iterations from 1 to 1000000")
                && stderr(&output).contains(&format!("'{bad}'")),
            "{bad}: {}",
            stderr(&output)
        );
    }
}

#[test]
fn converge_with_at_least_plain_stops_each_step_past_the_floor() {
    let folder = temp_folder("converge-floor-csv");
    let csv = folder.join("floor.csv");
    let output = masssprings(&[
        "converge",
        &data("flag.json"),
        "--steps",
        "3",
        "--at-least-plain",
        "10",
        "--iterations",
        "200",
        "--methods",
        "plain,lbfgs",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("--at-least-plain 10"),
        "{}",
        stdout(&output)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 6, "{text}");
    for row in &rows {
        assert_eq!(row[3], "at-least-plain", "{text}");
        let iterations: usize = row[2].parse().unwrap();
        if row[1] == "plain" {
            // ten first decreases take plain at least ten iterations
            assert!(iterations >= 10, "{text}");
        }
    }
}
