//! Nothing of a user's destroyed by the folders the commands write
//! (`docs/reliability.md`, "Output folders"): `trace -o`, `simulate --out`
//! and `generate --out` replace only their own files (or refuse, naming the
//! others, unless `--force`) and never an input; files named like
//! temporaries are a user's unless a lock record proves otherwise; a re-run
//! replaces the earlier result only once it is complete, so a run that
//! fails or is killed leaves it whole. (One run at a time per folder:
//! `tests/app/resume.rs`.)
use crate::cli;

use cli::{
    assert_fails, blow_up_scene, copy_scene, data, masssprings, masssprings_in, names_in as names,
    stderr, stdout, temp_folder,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// Runs the binary with `args` in `folder` (its current folder).
fn run_in(folder: &Path, args: &[&str]) -> Output {
    masssprings_in(folder, args)
}

fn succeeded(output: &Output) {
    assert!(output.status.success(), "{}", stderr(output));
}

/// Every file under `folder` (not following links) and its bytes, or where
/// a link points.
fn snapshot(folder: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(folder) else {
        return files;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let kind = entry.file_type().unwrap();
        if kind.is_symlink() {
            let target = std::fs::read_link(&path).unwrap();
            files.insert(path, target.to_string_lossy().as_bytes().to_vec());
        } else if kind.is_dir() {
            files.insert(path.clone(), b"(folder)".to_vec());
            files.extend(snapshot(&path));
        } else {
            files.insert(path.clone(), std::fs::read(&path).unwrap());
        }
    }
    files
}

/// Asserts that two snapshots are the same, naming the paths that differ.
fn assert_same(now: &BTreeMap<PathBuf, Vec<u8>>, before: &BTreeMap<PathBuf, Vec<u8>>, what: &str) {
    let differ: Vec<&PathBuf> = now
        .keys()
        .chain(before.keys())
        .filter(|path| now.get(*path) != before.get(*path))
        .collect();
    assert!(differ.is_empty(), "{what}: {differ:?} differ");
}

/// The id of a process that has ended.
fn dead_pid() -> u32 {
    let mut child = Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

// ------------------------------------------------------------ trace -o --

#[test]
fn trace_never_writes_the_scenes_obj_or_texture() {
    let folder = temp_folder("trace-inputs");
    let scene = copy_scene(&folder, "flag").display().to_string();
    let out = folder.join("out");
    std::fs::create_dir(&out).unwrap();
    std::os::unix::fs::symlink("../flag.obj", out.join("A.mtx")).unwrap();
    std::os::unix::fs::symlink("../flag.png", out.join("r.mtx")).unwrap();
    let before = snapshot(&folder);
    let linked = masssprings(&["trace", &scene, "-o", text(&out)]);
    assert_fails(
        &linked,
        &["A.mtx", "is the scene's OBJ", "would destroy an input"],
    );
    let forced = masssprings(&["trace", &scene, "-o", text(&out), "--force"]);
    assert_fails(&forced, &["would destroy an input"]);
    std::fs::remove_file(out.join("A.mtx")).unwrap();
    let texture = masssprings(&["trace", &scene, "-o", text(&out), "--force"]);
    assert_fails(&texture, &["r.mtx", "is the scene's texture"]);
    std::os::unix::fs::symlink("../flag.obj", out.join("A.mtx")).unwrap();
    assert_same(&snapshot(&folder), &before, "nothing written");
    // an OBJ named README.md, traced into its own folder
    let named = temp_folder("trace-readme-obj");
    std::fs::copy(data("net.obj"), named.join("README.md")).unwrap();
    std::fs::write(
        named.join("s.json"),
        r#"{"obj": "README.md", "k": 500, "b": [1], "m": 1}"#,
    )
    .unwrap();
    let before = snapshot(&named);
    let output = run_in(&named, &["trace", "s.json", "-o", ".", "--force"]);
    assert_fails(&output, &["README.md is the scene's OBJ"]);
    assert_same(&snapshot(&named), &before, "unchanged");
}

#[test]
fn trace_refuses_a_folder_of_files_it_did_not_write_unless_forced() {
    let folder = temp_folder("trace-users");
    copy_scene(&folder, "net");
    std::fs::write(folder.join("README.md"), "# my project\n").unwrap();
    std::fs::write(folder.join(".notes.2024-06.tmp"), "notes").unwrap();
    let before = snapshot(&folder);
    let output = run_in(&folder, &["trace", "net.json", "-o", "."]);
    assert_fails(
        &output,
        &[
            "-o .: .notes.2024-06.tmp, README.md, net.json",
            "not written by masssprings trace",
            "--force",
        ],
    );
    assert_same(&snapshot(&folder), &before, "nothing written or removed");
    let forced = run_in(&folder, &["trace", "net.json", "-o", ".", "--force"]);
    succeeded(&forced);
    let readme = std::fs::read_to_string(folder.join("README.md")).unwrap();
    assert!(
        readme.starts_with("# Every quantity of the handout"),
        "replaced, as forced"
    );
    for kept in [".notes.2024-06.tmp", "net.json", "net.obj"] {
        assert_eq!(
            std::fs::read(folder.join(kept)).unwrap(),
            before[&folder.join(kept)],
            "{kept}"
        );
    }
    // a link to a folder not made yet: made at the link's end, the link kept
    std::os::unix::fs::symlink("made-later", folder.join("later")).unwrap();
    succeeded(&run_in(&folder, &["trace", "net.json", "-o", "later"]));
    assert!(folder.join("made-later/trace.json").exists());
    assert!(std::fs::symlink_metadata(folder.join("later"))
        .unwrap()
        .file_type()
        .is_symlink());
    // a trace folder and its own README are trace's: a re-run needs no --force
    let out = folder.join("out");
    succeeded(&run_in(&folder, &["trace", "net.json", "-o", "out"]));
    succeeded(&run_in(&folder, &["trace", "net.json", "-o", "out"]));
    // forced among a link: the link is replaced, never written through
    let linked = folder.join("linked");
    std::fs::create_dir(&linked).unwrap();
    std::fs::write(folder.join("precious.txt"), "keep me").unwrap();
    std::os::unix::fs::symlink("../precious.txt", linked.join("r.mtx")).unwrap();
    let refused = run_in(&folder, &["trace", "net.json", "-o", "linked"]);
    assert_fails(&refused, &["r.mtx is not written by masssprings trace"]);
    succeeded(&run_in(
        &folder,
        &["trace", "net.json", "-o", "linked", "--force"],
    ));
    assert_eq!(
        std::fs::read_to_string(folder.join("precious.txt")).unwrap(),
        "keep me"
    );
    assert!(std::fs::symlink_metadata(linked.join("r.mtx"))
        .unwrap()
        .is_file());
    // a student's own file put among ours is not
    std::fs::write(
        out.join("d_9.mtx"),
        "%%MatrixMarket matrix array real general\n",
    )
    .unwrap();
    assert_fails(
        &run_in(&folder, &["trace", "net.json", "-o", "out"]),
        &["d_9.mtx"],
    );
}

/// A scene whose trace fails in the middle (after its folder is prepared):
/// vertices at ±1e308, whose rest lengths overflow.
fn failing_scene(folder: &Path) -> String {
    std::fs::write(
        folder.join("huge.obj"),
        "v -1e308 0 0\nv 1e308 0 0\nv 0 1e308 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        folder.join("huge.json"),
        r#"{"obj": "huge.obj", "k": 1, "b": [1], "m": 1}"#,
    )
    .unwrap();
    folder.join("huge.json").display().to_string()
}

/// Staging folders of `trace -o out` beside it: `.out.masssprings-…`.
fn staged_beside(folder: &Path) -> Vec<String> {
    names(folder)
        .into_iter()
        .filter(|name| name.starts_with(".out.masssprings-"))
        .collect()
}

#[test]
fn a_second_trace_replaces_the_first_only_once_complete() {
    let folder = temp_folder("trace-rerun");
    let out = folder.join("out");
    let net = data("net.json");
    succeeded(&masssprings(&[
        "trace",
        &net,
        "-o",
        text(&out),
        "--iterations",
        "3",
    ]));
    let first = snapshot(&out);
    // failing part-way
    let huge = failing_scene(&folder);
    let failed = masssprings(&["trace", &huge, "-o", text(&out)]);
    assert_eq!(failed.status.code(), Some(1), "{}", stderr(&failed));
    assert_same(&snapshot(&out), &first, "the first trace is whole");
    assert!(staged_beside(&folder).is_empty(), "{:?}", names(&folder));
    // killed part-way, on a larger scene
    succeeded(&masssprings(&[
        "generate",
        "grid",
        "150",
        "--out",
        text(&folder),
    ]));
    let grid = folder.join("grid-150.json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(["trace", text(&grid), "-o", text(&out), "--step", "40"])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while staged_beside(&folder).is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no staging folder"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    std::thread::sleep(Duration::from_millis(200));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the trace ended before it was killed"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    let mut after = snapshot(&out);
    let record = after.remove(&out.join(".masssprings-lock"));
    assert!(
        record.is_some(),
        "the killed run's record is left in its lock file"
    );
    assert_same(&after, &first, "the first trace is whole after a kill");
    assert_eq!(
        staged_beside(&folder).len(),
        1,
        "the killed run's staging folder"
    );
    // the next trace removes it (its owner is in out's lock) and replaces the first
    succeeded(&masssprings(&[
        "trace",
        &net,
        "-o",
        text(&out),
        "--iterations",
        "1",
    ]));
    assert!(staged_beside(&folder).is_empty(), "{:?}", names(&folder));
    assert!(out.join("p_1.mtx").exists() && !out.join("p_3.mtx").exists());
    assert!(!out.join(".masssprings-lock").exists());
    let compared = masssprings(&["trace", "--compare", text(&out), text(&out)]);
    succeeded(&compared);
}

// ------------------------------------------------------- simulate --out --

#[test]
fn a_forced_rerun_that_fails_leaves_the_earlier_frames_whole() {
    let folder = temp_folder("simulate-rerun");
    let out = folder.join("out");
    succeeded(&masssprings(&[
        "simulate",
        &data("net.json"),
        "--steps",
        "3",
        "--out",
        text(&out),
    ]));
    let first = snapshot(&out);
    let scene = blow_up_scene(&folder);
    let output = masssprings(&["simulate", text(&scene), "--out", text(&out), "--force"]);
    assert_fails(
        &output,
        &["step 1: the step produced a non-finite position"],
    );
    assert_same(
        &snapshot(&out),
        &first,
        "the earlier frames, whole, and nothing else",
    );
    // one that succeeds replaces them
    let net = data("net.json");
    succeeded(&masssprings(&[
        "simulate",
        &net,
        "--steps",
        "1",
        "--out",
        text(&out),
        "--force",
    ]));
    assert_eq!(names(&out), ["frame-000000.obj", "frame-000001.obj"]);
}

#[test]
fn the_frames_material_and_texture_copy_replace_only_their_own() {
    let folder = temp_folder("simulate-extras");
    let scene = copy_scene(&folder, "flag").display().to_string();
    let out = folder.join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("flag.mtl"), "newmtl mine\n").unwrap();
    let before = snapshot(&folder);
    let refused = masssprings(&["simulate", &scene, "--steps", "1", "--out", text(&out)]);
    assert_fails(
        &refused,
        &["flag.mtl is not written by masssprings simulate", "--force"],
    );
    assert_same(&snapshot(&folder), &before, "unchanged");
    std::fs::remove_file(out.join("flag.mtl")).unwrap();
    std::fs::write(out.join("flag.png"), "my picture").unwrap();
    let refused = masssprings(&["simulate", &scene, "--steps", "1", "--out", text(&out)]);
    assert_fails(
        &refused,
        &["flag.png is not written by masssprings simulate"],
    );
    let forced = masssprings(&[
        "simulate",
        &scene,
        "--steps",
        "1",
        "--out",
        text(&out),
        "--force",
    ]);
    succeeded(&forced);
    assert_eq!(
        std::fs::read(out.join("flag.png")).unwrap(),
        std::fs::read(data("flag.png")).unwrap()
    );
    // its own material and copy are replaced without --force (they are simulate's)
    std::fs::remove_file(out.join("frame-000000.obj")).unwrap();
    std::fs::remove_file(out.join("frame-000001.obj")).unwrap();
    succeeded(&masssprings(&[
        "simulate",
        &scene,
        "--steps",
        "1",
        "--out",
        text(&out),
    ]));
}

// ------------------------------------------------------- generate --out --

#[test]
fn generate_keeps_edited_scenes_unless_forced() {
    let folder = temp_folder("generate-edited");
    let out = folder.join("g");
    succeeded(&masssprings(&["generate", "examples", "--out", text(&out)]));
    let again = masssprings(&["generate", "examples", "--out", text(&out)]);
    succeeded(&again);
    assert!(
        stdout(&again).starts_with("unchanged "),
        "{}",
        stdout(&again)
    );
    let net = out.join("net.json");
    let edited = std::fs::read_to_string(&net)
        .unwrap()
        .replace("\"k\"", "\"k\" ");
    std::fs::write(&net, &edited).unwrap();
    let before = snapshot(&out);
    let refused = masssprings(&["generate", "examples", "--out", text(&out)]);
    assert_fails(
        &refused,
        &["net.json is not written by masssprings generate", "--force"],
    );
    assert_same(&snapshot(&out), &before, "nothing written");
    succeeded(&masssprings(&[
        "generate",
        "examples",
        "--out",
        text(&out),
        "--force",
    ]));
    assert_eq!(
        std::fs::read(&net).unwrap(),
        std::fs::read(data("net.json")).unwrap()
    );
    // forced over a link: the link goes, its target stays
    std::fs::write(folder.join("precious.txt"), "keep me").unwrap();
    std::fs::remove_file(out.join("flag.json")).unwrap();
    std::os::unix::fs::symlink("../precious.txt", out.join("flag.json")).unwrap();
    let refused = masssprings(&["generate", "examples", "--out", text(&out)]);
    assert_fails(
        &refused,
        &["flag.json is not written by masssprings generate"],
    );
    succeeded(&masssprings(&[
        "generate",
        "examples",
        "--out",
        text(&out),
        "--force",
    ]));
    assert_eq!(
        std::fs::read_to_string(folder.join("precious.txt")).unwrap(),
        "keep me"
    );
    std::fs::remove_file(folder.join("precious.txt")).unwrap();
    // the default --out . with a user's file of the same name
    std::fs::write(folder.join("grid-3.obj"), "my own mesh").unwrap();
    std::fs::write(folder.join(".notes.2024-06.tmp"), "notes").unwrap();
    let dead = format!(".x.{}-0.tmp", dead_pid());
    std::fs::write(folder.join(&dead), "mine").unwrap();
    let refused = run_in(&folder, &["generate", "grid", "3"]);
    assert_fails(
        &refused,
        &["grid-3.obj is not written by masssprings generate"],
    );
    assert_eq!(
        std::fs::read_to_string(folder.join("grid-3.obj")).unwrap(),
        "my own mesh"
    );
    std::fs::remove_file(folder.join("grid-3.obj")).unwrap();
    succeeded(&run_in(&folder, &["generate", "grid", "3"]));
    for kept in [".notes.2024-06.tmp", dead.as_str()] {
        assert!(folder.join(kept).exists(), "{kept} is a user's file");
    }
}
