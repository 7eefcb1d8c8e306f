//! `--accuracy assignment`: every step at least as low in energy as the
//! assignment's 50 plain iterations from the same state (checked in the
//! library on the first steps of the net and the flag); without the flag the
//! frames are the plain ones, bit for bit; the flags it chooses are refused
//! beside it; `converge --accuracy` prints its comparison.
use crate::cli;

use cli::{data, masssprings, stderr, stdout, temp_folder};
use masssprings::mesh::load_scene;
use masssprings::sim::{Accuracy, Simulation, SimulationOptions, Sparse, StepControl, StepMethod};

/// Runs `steps` steps of `scene` by `--accuracy assignment`; before each,
/// solves the same step from the same state by plain-50 on a copy, and
/// asserts the accuracy's step ended at or below its energy (to `10⁻⁹` of
/// its decrease). Returns how many steps plain iterations finished alone.
fn at_or_below_plain_50(scene: &str, steps: usize) -> usize {
    let scene = load_scene(std::path::Path::new(&cli::data(scene))).unwrap();
    let options = SimulationOptions {
        step: StepControl::for_accuracy(Accuracy::Assignment),
        ..SimulationOptions::default()
    };
    let mut fast = Simulation::<Sparse>::from_scene(&scene, options).unwrap();
    let plain_50 = StepControl {
        measure: true,
        ..StepControl::default()
    };
    let mut plain_alone = 0;
    for step in 1..=steps {
        let mut plain = fast.clone();
        let plain_report = plain.step_with(&plain_50, None).unwrap();
        let report = fast.step().unwrap();
        match report.method {
            StepMethod::Plain => plain_alone += 1,
            StepMethod::Lbfgs => {}
            other => panic!("step {step}: {other} is neither of the accuracy's methods"),
        }
        let (decrease, plain_decrease) = (
            report.energy_decrease.expect("L-BFGS measures its energy"),
            plain_report.energy_decrease.expect("asked to measure"),
        );
        assert!(
            decrease >= plain_decrease - 1e-9 * plain_decrease.abs(),
            "step {step}: decrease {decrease:e} below plain-50's {plain_decrease:e} \
             ({} iterations, {:?})",
            report.iterations,
            report.stop
        );
    }
    plain_alone
}

#[test]
fn the_first_ten_steps_of_the_net_end_at_or_below_plain_50s_energy() {
    at_or_below_plain_50("net.json", 10);
}

#[test]
fn the_first_ten_steps_of_the_flag_end_at_or_below_plain_50s_energy_by_l_bfgs() {
    assert_eq!(
        at_or_below_plain_50("flag.json", 10),
        0,
        "plain is slow there"
    );
}

#[test]
fn plain_alone_finishes_the_steps_of_a_chain_where_it_converges_fast() {
    let plain_alone = at_or_below_plain_50("horizontal-chain.json", 20);
    assert!(plain_alone >= 8, "{plain_alone} of 20 steps by plain alone");
}

#[test]
fn the_accuracy_names_its_own_control_and_nothing_else_does() {
    let control = StepControl::for_accuracy(Accuracy::Assignment);
    assert_eq!(Accuracy::of(&control), Some(Accuracy::Assignment));
    assert_eq!(Accuracy::of(&StepControl::default()), None);
    assert_eq!("assignment".parse::<Accuracy>(), Ok(Accuracy::Assignment));
    assert!("exact".parse::<Accuracy>().is_err());
}

/// The frames `simulate` writes for `flags` over 5 steps of the flag.
fn frames(name: &str, flags: &[&str]) -> Vec<Vec<u8>> {
    let folder = temp_folder(name);
    let out = folder.join("frames");
    let scene = data("flag.json");
    let mut args = vec!["simulate", &scene, "--steps", "5", "--out"];
    args.push(out.to_str().unwrap());
    args.extend_from_slice(flags);
    let output = masssprings(&args);
    assert!(output.status.success(), "{}", stderr(&output));
    (0..=5)
        .map(|i| std::fs::read(out.join(format!("frame-{i:06}.obj"))).unwrap())
        .collect()
}

#[test]
fn without_the_flag_the_frames_are_plain_50s_and_with_it_they_differ() {
    let default = frames("accuracy-default", &[]);
    let plain = frames(
        "accuracy-plain",
        &["--method", "plain", "--iterations", "50"],
    );
    assert_eq!(default, plain, "the default is plain-50, bit for bit");
    let fast = frames("accuracy-fast", &["--accuracy", "assignment"]);
    // the frames' second line records the run's flags, which differ
    let positions = |frame: &[u8]| -> Vec<u8> {
        let text = String::from_utf8_lossy(frame);
        let lines: Vec<&str> = text
            .lines()
            .filter(|l| !l.starts_with("# masssprings run"))
            .collect();
        lines.join("\n").into_bytes()
    };
    assert_eq!(
        positions(&fast[0]),
        positions(&default[0]),
        "the rest shape"
    );
    assert_ne!(fast[5], default[5], "another method, another trajectory");
}

#[test]
fn simulate_json_says_what_the_steps_ran() {
    let scene = data("net.json");
    let args = [
        "simulate",
        &scene,
        "--steps",
        "3",
        "--json",
        "--accuracy",
        "assignment",
    ];
    let output = masssprings(&args);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(summary["accuracy"], "assignment");
    assert_eq!(summary["method"], "lbfgs");
    assert_eq!(summary["at_least_plain"], 50.0);
    let stops = summary["stops"].as_object().unwrap();
    assert_eq!(stops.values().map(|n| n.as_u64().unwrap()).sum::<u64>(), 3);
    assert!(summary["iterations_max"].as_u64().unwrap() >= 1);
}

#[test]
fn the_flags_accuracy_chooses_are_refused_beside_it() {
    let scene = data("net.json");
    let folder = temp_folder("accuracy-refused");
    let out = folder.join("never.png");
    let out = out.to_str().unwrap();
    for (command, more) in [
        ("simulate", &[][..]),
        ("render", &["-o", out][..]),
        ("view", &[]),
    ] {
        for (flag, value) in [
            ("--method", "plain"),
            ("--tolerance", "0.5"),
            ("--energy-tolerance", "0.1"),
            ("--at-least-plain", "10"),
        ] {
            let mut args = vec![command, &scene, "--accuracy", "assignment", flag, value];
            args.extend_from_slice(more);
            let output = masssprings(&args);
            assert_eq!(output.status.code(), Some(2), "{command} {flag}");
            let message = stderr(&output);
            assert!(
                message.contains("--accuracy") && message.contains(flag),
                "{command} {flag}: {message}"
            );
        }
    }
    assert!(!std::path::Path::new(out).exists(), "nothing rendered");
    let output = masssprings(&["simulate", &scene, "--accuracy", "fastest"]);
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(
        message.contains("--accuracy")
            && message.contains("'fastest'")
            && message.contains("assignment"),
        "{message}"
    );
}

#[test]
fn converge_compares_the_accuracy_with_plain_50_over_steps() {
    let folder = temp_folder("accuracy-converge");
    let png = folder.join("steps.png");
    let scene = data("net.json");
    let args = [
        "converge",
        &scene,
        "--steps",
        "5",
        "--accuracy",
        "assignment",
        "--plot",
        png.to_str().unwrap(),
    ];
    let output = masssprings(&args);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    let lines = [
        "--accuracy assignment (lbfgs) against plain-50",
        "each on its own (what a user gets): plain-50 ",
        "along its own trajectory, against plain-50 from each of its states: 0 of 5 steps above",
        "the two trajectories apart (largest over the steps): max vertex ",
        "from the same states (each step of both from plain-50's state): plain-50 ",
        "0 of 5 steps above plain-50's energy (by more than 1e-9 of its decrease and its rounding)",
    ];
    let mut at = 0;
    for line in lines {
        let found = text[at..].find(line);
        assert!(
            found.is_some(),
            "missing '{line}' (after byte {at}: own run first) in\n{text}"
        );
        at += found.unwrap();
    }
    assert_eq!(&std::fs::read(&png).unwrap()[..4], b"\x89PNG");
    let refused = masssprings(&["converge", &scene, "--accuracy", "assignment"]);
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
}

#[test]
fn converge_measures_the_rule_against_an_oracle_and_draws_the_motion() {
    let folder = temp_folder("accuracy-oracle");
    let (oracle, motion) = (folder.join("oracle.png"), folder.join("motion.png"));
    let scene = data("net.json");
    for (flag, png) in [("--oracle", &oracle), ("--motion", &motion)] {
        let args = [
            "converge",
            &scene,
            "--steps",
            "4",
            "--accuracy",
            "assignment",
            flag,
            png.to_str().unwrap(),
        ];
        let output = masssprings(&args);
        assert!(output.status.success(), "{flag}: {}", stderr(&output));
        assert_eq!(&std::fs::read(png).unwrap()[..4], b"\x89PNG", "{flag}");
        let text = stdout(&output);
        let expected = match flag {
            "--oracle" => "oracle, along the accuracy's own run: the rule's median step ",
            _ => "plain-50: mean kinetic energy ",
        };
        assert!(
            text.contains(expected),
            "{flag}: missing '{expected}' in\n{text}"
        );
    }
    let table = std::fs::read_to_string(folder.join("oracle.csv")).unwrap();
    let rows: Vec<&str> = table.lines().collect();
    assert!(
        rows[0].starts_with("trajectory,step,plain_50_energy"),
        "{}",
        rows[0]
    );
    assert_eq!(
        rows.len(),
        1 + 2 * 4,
        "a row per step of each trajectory:\n{table}"
    );
    for row in &rows[1..] {
        let cells: Vec<&str> = row.split(',').collect();
        let (energy, rule): (f64, f64) = (cells[2].parse().unwrap(), cells[6].parse().unwrap());
        assert!(energy <= 0.0, "plain-50 lowers the energy: {row}");
        let slack = 1e-9 * energy.abs() + 1e-12;
        assert!(
            rule <= energy + slack,
            "the rule ends at or below plain-50: {row}"
        );
    }
}
