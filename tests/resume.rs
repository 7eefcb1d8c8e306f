//! `simulate --resume DIR`: a run continued from its frames gives the same
//! bits as a run that never stopped, and frames that cannot give back the
//! state exactly are refused with a sentence naming them.
#[path = "common/cli.rs"]
mod cli;

use cli::{data, masssprings, stderr, temp_folder};
use std::path::Path;

/// Runs `simulate` with `args` and asserts that it succeeded.
fn simulate(args: &[&str]) {
    let mut all = vec!["simulate"];
    all.extend_from_slice(args);
    let output = masssprings(&all);
    assert!(output.status.success(), "{all:?}: {}", stderr(&output));
}

/// The names of the files in `folder`, sorted.
fn names(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Six steps in one run, and three then three more resumed: the same
/// files, byte for byte. With the wind, whose force depends on the
/// simulated time, so that the step count is carried over too.
#[test]
fn resuming_gives_the_bits_of_a_run_that_never_stopped() {
    for (scene, extra) in [("flag.json", &[][..]), ("net.json", &["--wind"][..])] {
        let scene = data(scene);
        let whole = temp_folder("resume-whole");
        let halves = temp_folder("resume-halves");
        let (whole_dir, halves_dir) = (whole.to_str().unwrap(), halves.to_str().unwrap());
        let run = |more: &[&str]| {
            let mut args = vec![scene.as_str(), "--json"];
            args.extend_from_slice(extra);
            args.extend_from_slice(more);
            simulate(&args);
        };
        run(&["--steps", "6", "--out", whole_dir, "--force"]);
        run(&["--steps", "3", "--out", halves_dir, "--force"]);
        run(&["--steps", "3", "--resume", halves_dir]);
        assert_eq!(names(&whole), names(&halves), "{scene}");
        assert!(names(&halves).contains(&"frame-000006.obj".to_string()));
        for name in names(&whole) {
            let (a, b) = (whole.join(&name), halves.join(&name));
            assert!(
                std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
                "{scene} {extra:?}: {name} differs after resuming"
            );
        }
    }
}

/// A run of zero steps has only its start: resuming it is starting.
#[test]
fn resuming_from_step_zero_is_starting() {
    let scene = data("net.json");
    let (fresh, resumed) = (temp_folder("resume-fresh"), temp_folder("resume-zero"));
    simulate(&[
        &scene,
        "--steps",
        "2",
        "--out",
        fresh.to_str().unwrap(),
        "--force",
    ]);
    simulate(&[
        &scene,
        "--steps",
        "0",
        "--out",
        resumed.to_str().unwrap(),
        "--force",
    ]);
    simulate(&[
        &scene,
        "--steps",
        "2",
        "--resume",
        resumed.to_str().unwrap(),
    ]);
    for name in ["frame-000001.obj", "frame-000002.obj"] {
        assert_eq!(
            std::fs::read(fresh.join(name)).unwrap(),
            std::fs::read(resumed.join(name)).unwrap(),
            "{name}"
        );
    }
}

/// Runs `simulate SCENE --resume FOLDER` and returns its error, asserting
/// exit code `code`.
fn resume_error(scene: &str, folder: &Path, more: &[&str], code: i32) -> String {
    let mut args = vec!["simulate", scene, "--resume", folder.to_str().unwrap()];
    args.extend_from_slice(more);
    let output = masssprings(&args);
    assert_eq!(output.status.code(), Some(code), "{}", stderr(&output));
    stderr(&output)
}

#[test]
fn frames_that_cannot_resume_exactly_are_named() {
    let net = data("net.json");
    let every = temp_folder("resume-every");
    let every_dir = every.to_str().unwrap();
    simulate(&[
        &net, "--steps", "4", "--every", "2", "--out", every_dir, "--force",
    ]);
    let error = resume_error(&net, &every, &[], 1);
    assert!(
        error.contains("frame-000003.obj is missing") && error.contains("--every"),
        "{error}"
    );
    let rounded = temp_folder("resume-rounded");
    let rounded_dir = rounded.to_str().unwrap();
    simulate(&[
        &net,
        "--steps",
        "2",
        "--precision",
        "9",
        "--out",
        rounded_dir,
        "--force",
    ]);
    let error = resume_error(&net, &rounded, &[], 1);
    assert!(
        error.contains("frame-000002.obj") && error.contains("rounded"),
        "{error}"
    );
    // another scene's frames
    let error = resume_error(&data("flag.json"), &every, &[], 1);
    assert!(
        error.contains("frame-000004.obj") && error.contains("another scene"),
        "{error}"
    );
    let error = resume_error(&net, &every.join("none"), &[], 1);
    assert!(error.contains("no such folder"), "{error}");
    let empty = temp_folder("resume-empty");
    let error = resume_error(&net, &empty, &[], 1);
    assert!(error.contains("no frames"), "{error}");
    // nothing was written by the refused runs
    assert_eq!(names(&every).len(), 3, "{:?}", names(&every));
    assert!(names(&empty).is_empty());
}

#[test]
fn resume_refuses_out_and_force() {
    let net = data("net.json");
    let folder = temp_folder("resume-flags");
    simulate(&[
        &net,
        "--steps",
        "1",
        "--out",
        folder.to_str().unwrap(),
        "--force",
    ]);
    for more in [&["--out", "elsewhere"][..], &["--force"][..]] {
        let error = resume_error(&net, &folder, more, 2);
        assert!(error.contains(more[0]), "{error}");
    }
    assert_eq!(names(&folder), ["frame-000000.obj", "frame-000001.obj"]);
}
