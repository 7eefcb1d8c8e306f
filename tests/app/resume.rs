//! `simulate --resume DIR`: a run continued from its frames gives the same
//! bits as a run that never stopped, and frames that cannot give back the
//! state exactly are refused with a sentence naming them.
use crate::cli;

use cli::{data, masssprings, names_in as names, stderr, temp_folder};
use std::path::Path;

/// Runs `simulate` with `args` and asserts that it succeeded.
fn simulate(args: &[&str]) {
    let mut all = vec!["simulate"];
    all.extend_from_slice(args);
    let output = masssprings(&all);
    assert!(output.status.success(), "{all:?}: {}", stderr(&output));
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

/// Six steps in one run, and three then three more resumed, for every
/// method and the rules that make a step stop early: the same frames, to
/// the bit. Chebyshev carries its estimate of ρ from step to step (with a
/// tolerance, the estimate spans several steps and is cut by the resume),
/// Newton its damping: both come back from the frames' run record.
#[test]
fn every_method_resumes_to_the_bits_of_a_run_that_never_stopped() {
    let net = data("net.json");
    for flags in [
        &["--method", "chebyshev"][..],
        &["--method", "chebyshev", "--tolerance", "1e-3"][..],
        &["--method", "anderson", "--tolerance", "1e-6"][..],
        &["--method", "lbfgs"][..],
        &["--method", "newton", "--tolerance", "1e-9"][..],
        &["--accuracy", "assignment"][..],
        &["--start", "inertial", "--pins", "exact"][..],
        &["--textbook", "--iterations", "7"][..],
        &["--dense"][..],
    ] {
        let whole = temp_folder("resume-method-whole");
        let halves = temp_folder("resume-method-halves");
        let run = |folder: &Path, steps: &str, how: &str| {
            let folder = folder.to_str().unwrap();
            let mut args = vec![net.as_str(), "--json", "--steps", steps, how, folder];
            args.extend_from_slice(flags);
            simulate(&args);
        };
        run(&whole, "6", "--out");
        run(&halves, "3", "--out");
        run(&halves, "3", "--resume");
        assert_eq!(names(&whole), names(&halves), "{flags:?}");
        for name in names(&whole) {
            assert!(
                std::fs::read(whole.join(&name)).unwrap()
                    == std::fs::read(halves.join(&name)).unwrap(),
                "{flags:?}: {name} differs after resuming"
            );
        }
    }
}

/// A copy of the bundled net (JSON and OBJ) in `folder`, its JSON text
/// changed by `edit`; returns the JSON's path.
fn net_copy(folder: &Path, name: &str, edit: impl Fn(&str) -> String) -> String {
    let text = std::fs::read_to_string(data("net.json")).unwrap();
    std::fs::copy(data("net.obj"), folder.join("net.obj")).unwrap();
    let json = folder.join(format!("{name}.json"));
    std::fs::write(&json, edit(&text)).unwrap();
    json.to_str().unwrap().to_string()
}

/// The frames record what the run was: a resume with another `k`, other
/// masses or pins, or other flags, is refused, naming each difference.
#[test]
fn frames_of_another_k_masses_pins_or_flags_are_refused() {
    let folder = temp_folder("resume-other");
    let scenes = temp_folder("resume-other-scenes");
    let net = net_copy(&scenes, "net", |text| text.to_string());
    simulate(&[&net, "--steps", "2", "--out", folder.to_str().unwrap()]);
    let before = names(&folder);
    let original = std::fs::read_to_string(data("net.json")).unwrap();
    let value: serde_json::Value = serde_json::from_str(&original).unwrap();
    let with = |key: &str, new: serde_json::Value| {
        let mut value = value.clone();
        value[key] = new;
        value.to_string()
    };
    for (key, new, named) in [
        ("k", serde_json::json!(123.0), "k (the frames': "),
        ("m", serde_json::json!(0.5), "the masses"),
        ("b", serde_json::json!([1]), "the pins"),
    ] {
        let changed = net_copy(&scenes, "net", |_| with(key, new.clone()));
        let error = resume_error(&changed, &folder, &[], 1);
        assert!(
            error.contains(named) && error.contains("frame-000002.obj"),
            "{key}: {error}"
        );
    }
    let net = net_copy(&scenes, "net", |text| text.to_string());
    for (flags, named) in [
        (
            &["--method", "chebyshev"][..],
            "--method (the frames': plain; now: chebyshev)",
        ),
        (&["--wind"][..], "--wind (the frames': false; now: true)"),
        (
            &["--iterations", "20"][..],
            "--iterations (the frames': 50; now: 20)",
        ),
        (&["--dense"][..], "--dense (the frames': false; now: true)"),
    ] {
        let error = resume_error(&net, &folder, flags, 1);
        assert!(error.contains(named), "{flags:?}: {error}");
    }
    assert_eq!(
        names(&folder),
        before,
        "nothing written by a refused resume"
    );
}

/// A run at the last step numbers can hold is not wrapped around to
/// frame 0: more steps are refused before any work.
#[test]
fn the_step_counter_never_wraps() {
    let folder = temp_folder("resume-wrap");
    let net = data("net.json");
    simulate(&[&net, "--steps", "1", "--out", folder.to_str().unwrap()]);
    for (step, name) in [(0usize, "frame-000000.obj"), (1, "frame-000001.obj")] {
        let text = std::fs::read_to_string(folder.join(name)).unwrap();
        let last = usize::MAX - 1 + step;
        let text = text.replacen(&format!("step {step},"), &format!("step {last},"), 1);
        std::fs::write(folder.join(format!("frame-{last:06}.obj")), text).unwrap();
        std::fs::remove_file(folder.join(name)).unwrap();
    }
    let before = names(&folder);
    let error = resume_error(&net, &folder, &["--steps", "1"], 1);
    assert!(
        error.contains("the run is at step 18446744073709551615")
            && error.contains("would pass the largest step number")
            && error.contains("the run cannot go on"),
        "{error}"
    );
    assert_eq!(
        names(&folder),
        before,
        "no frame-000000.obj, nothing written"
    );
}

/// A FIFO or a folder where a frame should be is named as what it is.
#[test]
fn a_fifo_or_folder_named_like_a_frame_is_named_as_such() {
    let folder = temp_folder("resume-odd");
    let net = data("net.json");
    simulate(&[&net, "--steps", "2", "--out", folder.to_str().unwrap()]);
    std::fs::remove_file(folder.join("frame-000001.obj")).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(folder.join("frame-000001.obj"))
        .status()
        .unwrap();
    assert!(made.success());
    let error = resume_error(&net, &folder, &[], 1);
    assert!(
        error.contains("frame-000001.obj: this is a FIFO (a named pipe), not a frame"),
        "{error}"
    );
    std::fs::create_dir(folder.join("frame-000003.obj")).unwrap();
    let error = resume_error(&net, &folder, &[], 1);
    assert!(
        error.contains("frame-000003.obj: this is a folder, not a frame"),
        "{error}"
    );
}

/// Runs `simulate` with `args` in the background.
fn spawn_simulate(args: &[&str]) -> std::process::Child {
    std::process::Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .arg("simulate")
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap()
}

/// Waits (at most a minute) until `path` exists.
fn wait_for(path: &Path) {
    let start = std::time::Instant::now();
    while !path.exists() {
        assert!(
            start.elapsed().as_secs() < 60,
            "{} never came",
            path.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// One run at a time per folder: a second `--out` or a `--resume` beside a
/// live run is refused, naming it; once that run is killed, the folder is
/// free and the killed run's temporaries go, and its frames resume.
#[test]
fn a_second_run_into_a_folder_is_refused_while_the_first_runs() {
    let folder = temp_folder("resume-live");
    let dir = folder.to_str().unwrap();
    let skirt = data("skirt.json");
    let mut live = spawn_simulate(&[&skirt, "--steps", "100000", "--out", dir, "--json"]);
    wait_for(&folder.join("frame-000002.obj"));
    let pid = live.id();
    for args in [
        vec!["simulate", skirt.as_str(), "--steps", "1", "--out", dir],
        vec![
            "simulate",
            skirt.as_str(),
            "--steps",
            "1",
            "--out",
            dir,
            "--force",
        ],
        vec!["simulate", skirt.as_str(), "--steps", "1", "--resume", dir],
    ] {
        let output = masssprings(&args);
        assert_eq!(output.status.code(), Some(1), "{args:?}");
        assert!(
            stderr(&output).contains(&format!(
                "another masssprings run (simulate, process {pid}) is writing into this folder"
            )),
            "{args:?}: {}",
            stderr(&output)
        );
    }
    live.kill().unwrap();
    live.wait().unwrap();
    // what the killed run left: its lock's record, perhaps a temporary
    let record = std::fs::read_to_string(folder.join(".masssprings-lock")).unwrap();
    let tag = record.split_whitespace().nth(2).unwrap().to_string();
    assert!(tag.starts_with(&format!("masssprings-{pid}-")), "{record}");
    let temporary = folder.join(format!(".frame-999999.obj.{tag}-9.tmp"));
    std::fs::write(&temporary, "half a frame").unwrap();
    let users = folder.join(".notes.2024-06.tmp");
    std::fs::write(&users, "a user's notes").unwrap();
    simulate(&[&skirt, "--steps", "1", "--resume", dir, "--json"]);
    assert!(!temporary.exists(), "the killed run's temporary is removed");
    assert!(users.exists(), "a file named like a temporary is not");
    assert!(!folder.join(".masssprings-lock").exists());
}

/// A record edited to carry what no run carries is refused, and a file
/// given as the folder is named as one.
#[test]
fn a_record_that_no_run_wrote_and_a_file_for_a_folder_are_refused() {
    let folder = temp_folder("resume-edited");
    let net = data("net.json");
    let chebyshev = ["--method", "chebyshev"];
    let dir = folder.to_str().unwrap();
    simulate(&[
        &net,
        "--steps",
        "2",
        "--out",
        dir,
        chebyshev[0],
        chebyshev[1],
    ]);
    let last = folder.join("frame-000002.obj");
    let text = std::fs::read_to_string(&last).unwrap();
    let start = text.find("\"rho\":").unwrap() + "\"rho\":".len();
    let end = start + text[start..].find(',').unwrap();
    std::fs::write(&last, format!("{}5.0{}", &text[..start], &text[end..])).unwrap();
    let error = resume_error(&net, &folder, &chebyshev, 1);
    assert!(
        error.contains("Chebyshev's ρ = 5 is outside [0, 0.995]"),
        "{error}"
    );
    let error = resume_error(&net, &folder.join("frame-000000.obj"), &[], 1);
    assert!(error.contains("this is not a folder"), "{error}");
}

/// The bundled `net` scene copied into `folder` with its OBJ's vertices
/// changed by `edit` (each `v` line's three numbers) and its JSON by
/// `json` (the same name, so that only the record tells them apart).
fn net_variant(
    folder: &Path,
    edit: impl Fn([f64; 3]) -> [f64; 3],
    json: impl Fn(String) -> String,
) -> String {
    std::fs::create_dir_all(folder).unwrap();
    let obj = std::fs::read_to_string(data("net.obj")).unwrap();
    let moved: Vec<String> = obj
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(numbers) => {
                let p: Vec<f64> = numbers
                    .split_whitespace()
                    .map(|x| x.parse().unwrap())
                    .collect();
                let [x, y, z] = edit([p[0], p[1], p[2]]);
                format!("v {x} {y} {z}")
            }
            None => line.to_string(),
        })
        .collect();
    std::fs::write(folder.join("net.obj"), moved.join("\n") + "\n").unwrap();
    let scene = std::fs::read_to_string(data("net.json")).unwrap();
    std::fs::write(folder.join("net.json"), json(scene)).unwrap();
    folder.join("net.json").display().to_string()
}

#[test]
fn a_moved_or_stiffer_scene_is_another_run() {
    let net = data("net.json");
    let folder = temp_folder("resume-moved");
    let frames = folder.join("frames");
    simulate(&[&net, "--steps", "2", "--out", frames.to_str().unwrap()]);
    let before = names(&frames);
    // the same scene moved 5 m: its pins would jump back in one step
    let moved = net_variant(
        &folder.join("moved"),
        |[x, y, z]| [x + 5.0, y, z],
        |json| json,
    );
    let error = resume_error(&moved, &frames, &[], 1);
    assert!(
        error.contains("the rest positions (the scene moved or reshaped)"),
        "{error}"
    );
    assert!(!error.contains("the masses"), "only what differs: {error}");
    // k written short, not in 301 digits
    let stiff = net_variant(
        &folder.join("stiff"),
        |p| p,
        |json| {
            let value: serde_json::Value = serde_json::from_str(&json).unwrap();
            let mut value = value;
            value["k"] = serde_json::json!(1e300);
            value.to_string()
        },
    );
    let error = resume_error(&stiff, &frames, &[], 1);
    assert!(error.contains("now: 1e300)"), "{error}");
    assert!(error.len() < 400, "{error}");
    assert_eq!(names(&frames), before, "nothing written");
}

#[test]
fn frames_of_two_runs_are_not_continued() {
    let net = data("net.json");
    let folder = temp_folder("resume-two-runs");
    let (a, b) = (folder.join("a"), folder.join("b"));
    simulate(&[&net, "--steps", "4", "--out", a.to_str().unwrap()]);
    // b: a run that replaced another, so its frames name their run
    simulate(&[&net, "--steps", "1", "--out", b.to_str().unwrap()]);
    simulate(&[
        &net,
        "--steps",
        "2",
        "--out",
        b.to_str().unwrap(),
        "--force",
    ]);
    for step in [3, 4] {
        let name = format!("frame-00000{step}.obj");
        std::fs::copy(a.join(&name), b.join(&name)).unwrap();
    }
    let error = resume_error(&net, &b, &[], 1);
    assert!(
        error.contains("the frames of 2 runs") && error.contains("(steps 0 to 2)"),
        "{error}"
    );
}
