//! The command line as a new user meets it: help for every command in every
//! spelling, the version, "did you mean", errors in plain words, a busy
//! port, a file that is not a scene, frame files with a precision and a
//! material.
use crate::cli;

use cli::{data, masssprings, stderr, stdout, temp_folder, COMMANDS};
use std::net::TcpListener;

/// The run failed with a usage error (exit code 2) whose message contains
/// each of `expected` (the meaning: the flag, the value, the range; not
/// the parser's exact wording).
fn usage_error(args: &[&str], expected: &[&str]) {
    let output = masssprings(args);
    assert_eq!(
        output.status.code(),
        Some(2),
        "{args:?}: {}",
        stderr(&output)
    );
    for part in expected {
        assert!(
            stderr(&output).contains(part),
            "{args:?}: expected {part:?} in {:?}",
            stderr(&output)
        );
    }
}

#[test]
fn every_command_has_the_same_help_in_every_spelling() {
    let top = masssprings(&["--help"]);
    assert!(top.status.success());
    for command in COMMANDS {
        assert!(
            stdout(&top).contains(&format!("\n  {command} ")),
            "{command} missing from {}",
            stdout(&top)
        );
        let help = stdout(&masssprings(&["help", command]));
        assert!(
            help.contains(&format!("Usage: masssprings {command} ")),
            "{help}"
        );
        assert!(help.contains("-h, --help"), "{help}");
        for spelling in ["--help", "-h"] {
            let output = masssprings(&[command, spelling]);
            assert!(output.status.success(), "{command} {spelling}");
            assert_eq!(stdout(&output), help, "{command} {spelling}");
        }
        // Help wins over anything else on the line, even wrong arguments.
        assert_eq!(stdout(&masssprings(&[command, "x", "--bogus", "-h"])), help);
    }
    for spelling in [&["help"][..], &["-h"][..]] {
        assert_eq!(stdout(&masssprings(spelling)), stdout(&top));
    }
}

#[test]
fn the_help_lists_the_flags_each_command_accepts() {
    let simulate = stdout(&masssprings(&["simulate", "--help"]));
    for flag in [
        "--steps <N>",
        "--every <K>",
        "-o, --out <DIR>",
        "--precision <D>",
        "--dense",
        "--wind",
        "--json",
    ] {
        assert!(simulate.contains(flag), "{flag} in {simulate}");
    }
    let render = stdout(&masssprings(&["render", "--help"]));
    assert!(render.contains("-o, --out <OUT>"), "{render}");
    let view = stdout(&masssprings(&["view", "--help"]));
    assert!(view.contains("--port <P>"), "{view}");
    // every command that factors, solves or steps takes --threads
    for command in ["simulate", "render", "view", "converge", "analyze", "bench"] {
        let help = stdout(&masssprings(&[command, "--help"]));
        assert!(help.contains("--threads <N>"), "{command}: {help}");
    }
    // internal flags stay out of the help
    let bench = stdout(&masssprings(&["bench", "--help"]));
    assert!(!bench.contains("--one"), "{bench}");
    // every command that writes a file takes -o
    for command in [
        "simulate", "render", "converge", "bench", "export-q", "spy", "etree", "trace", "generate",
    ] {
        let help = stdout(&masssprings(&[command, "--help"]));
        assert!(help.contains("  -o, --"), "{command}: {help}");
    }
}

#[test]
fn the_version_is_the_packages() {
    for spelling in ["--version", "-V", "version"] {
        let output = masssprings(&[spelling]);
        assert!(output.status.success());
        assert_eq!(
            stdout(&output),
            format!("masssprings {}\n", env!("CARGO_PKG_VERSION"))
        );
    }
}

#[test]
fn typos_get_a_suggestion() {
    usage_error(&["simulte"], &["'simulte'", "'simulate'"]);
    usage_error(&["frobnicate"], &["'frobnicate'"]);
    usage_error(&["help", "rendr"], &["'rendr'"]);
    usage_error(
        &["simulate", &data("net.json"), "--step", "3"],
        &["'--step'", "'--steps'"],
    );
    usage_error(
        &["render", &data("net.json"), "-o", "x.gif", "--sprigs"],
        &["'--springs'"],
    );
    usage_error(
        &["analyze", "a.mtx", "--ordering", "amf"],
        &["--ordering", "'amf'", "amd, natural", "'amd'"],
    );
    usage_error(&["generate", "gird", "3"], &["'grid'"]);
    usage_error(&["simulate", "x.json", "--bogus"], &["--help"]);
}

#[test]
fn bad_values_are_explained_in_plain_words() {
    let net = data("net.json");
    usage_error(
        &["simulate", &net, "--steps", "ten"],
        &["--steps", "a whole number ≥ 0", "'ten'"],
    );
    usage_error(
        &["simulate", &net, "--every", "0"],
        &["--every", "a whole number ≥ 1", "0 is out of range"],
    );
    // converge's --steps selects the mode over steps: 0 is refused, not
    // taken as "one step"
    for extra in [&[][..], &["--tolerance", "0.9"][..]] {
        let mut args = vec!["converge", &net, "--steps", "0"];
        args.extend(extra);
        usage_error(
            &args,
            &["--steps", "a whole number ≥ 1", "0 is out of range"],
        );
    }
    usage_error(
        &["analyze", "a.mtx", "--repeats", "0"],
        &["--repeats", "a whole number ≥ 1", "0 is out of range"],
    );
    usage_error(
        &["view", &net, "--port", "99999"],
        &[
            "--port",
            "a whole number from 0 to 65535",
            "99999 is out of range",
        ],
    );
    usage_error(
        &["view", &net, "--address", "nowhere"],
        &["--address", "an IP address", "'nowhere'"],
    );
    usage_error(
        &["simulate", &net, "--precision", "40"],
        &[
            "--precision",
            "a whole number from 0 to 17",
            "40 is out of range",
        ],
    );
    usage_error(
        &["render", &net, "-o", "x.gif", "--size", "9000x10"],
        &["--size", "1 to 2048", "'9000x10'"],
    );
    usage_error(
        &["simulate", &net, "--steps"],
        &["--steps", "value is required"],
    );
    usage_error(&["simulate"], &["<SCENE.json>", "required"]);
}

#[test]
fn the_parser_enforces_which_flags_go_together() {
    let net = data("net.json");
    // --force means something only with --out
    usage_error(&["simulate", &net, "--force"], &["--out", "required"]);
    // --accuracy chooses the method and the rules itself
    usage_error(
        &[
            "simulate",
            &net,
            "--accuracy",
            "assignment",
            "--method",
            "newton",
        ],
        &["--accuracy", "--method", "cannot be used with"],
    );
    usage_error(
        &[
            "render",
            &net,
            "-o",
            "x.png",
            "--dense",
            "--ordering",
            "natural",
        ],
        &["--dense", "--ordering", "cannot be used with"],
    );
    // the resumed run's folder is its own output
    usage_error(
        &["simulate", &net, "--resume", "a", "--out", "b"],
        &["--resume", "--out", "cannot be used with"],
    );
}

#[test]
fn shells_get_completions() {
    for shell in ["bash", "zsh", "fish"] {
        let output = masssprings(&["completions", shell]);
        assert!(output.status.success(), "{shell}: {}", stderr(&output));
        let script = stdout(&output);
        for word in ["masssprings", "simulate", "--factorization", "--supernodes"] {
            assert!(script.contains(word), "{shell}: {word} missing");
        }
    }
    usage_error(&["completions", "tcsh"], &["'tcsh'", "bash"]);
}

#[test]
fn a_busy_port_suggests_port_0() {
    let taken = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let output = masssprings(&["view", &data("net.json"), "--port", &port]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains(&format!("port {port} is in use")),
        "{}",
        stderr(&output)
    );
    assert!(
        stderr(&output).contains("try --port 0"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn an_obj_given_as_the_scene_is_named_for_what_it_is() {
    for command in [
        &["simulate"][..],
        &["view"][..],
        &["render", "-o", "never-written.png"][..],
    ] {
        let obj = data("flag.obj");
        let mut args = command.to_vec();
        args.insert(1, &obj);
        let output = masssprings(&args);
        assert_eq!(output.status.code(), Some(1), "{args:?}");
        assert!(
            stderr(&output).contains(&format!(
                "{obj} is not a scene file: scenes are JSON that name an OBJ; see data/README.md"
            )),
            "{}",
            stderr(&output)
        );
    }
    assert!(!std::path::Path::new("never-written.png").exists());
}

#[test]
fn frames_carry_the_precision_asked_and_the_texture_as_a_material() {
    let folder = temp_folder("precision");
    let output = masssprings(&[
        "simulate",
        &data("flag.json"),
        "--steps",
        "2",
        "--every",
        "2",
        "--precision",
        "4",
        "--out",
        folder.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stdout(&output).contains("total "), "{}", stdout(&output));
    let frame = std::fs::read_to_string(folder.join("frame-000002.obj")).unwrap();
    let positions: Vec<&str> = frame.lines().filter(|l| l.starts_with("v ")).collect();
    assert_eq!(positions.len(), 3200);
    for line in &positions {
        for number in line.split_whitespace().skip(1) {
            let (_, decimals) = number.split_once('.').expect("a decimal point");
            assert_eq!(decimals.len(), 4, "{line}");
            assert_ne!(number, "-0.0000", "{line}");
        }
    }
    assert!(frame.lines().any(|l| l == "mtllib flag.mtl"));
    let usemtl = frame.lines().position(|l| l == "usemtl flag").unwrap();
    let first_face = frame.lines().position(|l| l.starts_with("f ")).unwrap();
    assert!(usemtl < first_face, "the material comes before the faces");
    let material = std::fs::read_to_string(folder.join("flag.mtl")).unwrap();
    assert!(material.contains("newmtl flag") && material.contains("map_Kd flag.png"));
    assert_eq!(
        std::fs::read(folder.join("flag.png")).unwrap(),
        std::fs::read(data("flag.png")).unwrap()
    );
}

#[test]
fn progress_is_plain_lines_off_a_terminal_and_absent_with_json() {
    let output = masssprings(&["simulate", &data("net.json"), "--steps", "5"]);
    assert!(output.status.success());
    assert!(
        !stderr(&output).contains('\r'),
        "no carriage returns into a pipe: {:?}",
        stderr(&output)
    );
    let output = masssprings(&["simulate", &data("net.json"), "--steps", "5", "--json"]);
    assert_eq!(stderr(&output), "");
    let summary: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
    assert!(summary["total_s"].as_f64().unwrap() > 0.0);
}

#[test]
fn render_frames_what_fit_asks_and_reports_json() {
    let folder = temp_folder("render-fit");
    let mut sizes = Vec::new();
    for fit in ["rest", "last", "all"] {
        let out = folder.join(format!("{fit}.png"));
        let output = masssprings(&[
            "render",
            &data("net.json"),
            "-o",
            out.to_str().unwrap(),
            "--steps",
            "20",
            "--size",
            "64x48",
            "--fit",
            fit,
            "--json",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let summary: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
        assert_eq!(summary["fit"], fit);
        assert_eq!(
            (summary["frames"].clone(), summary["steps"].clone()),
            (1.into(), 20.into())
        );
        assert_eq!(
            summary["bytes"].as_u64().unwrap(),
            std::fs::metadata(&out).unwrap().len()
        );
        sizes.push(std::fs::read(&out).unwrap());
    }
    assert_ne!(
        sizes[0], sizes[1],
        "framing the rest shape or the last step differs"
    );
    usage_error(
        &[
            "render",
            &data("net.json"),
            "-o",
            "x.png",
            "--fit",
            "everything",
        ],
        &["--fit", "'everything'", "rest, last, all"],
    );
}
