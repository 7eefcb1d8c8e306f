//! Nothing of a user's destroyed by the folders the commands write
//! (`docs/reliability.md`, "Output folders" and "The one rule"): `trace
//! -o`, `simulate --out` and `generate --out` replace only their own files
//! (or refuse, naming the others, unless `--force`) and never an input;
//! they write into the folder in place, file by file, and never touch
//! another file there, whenever it appeared; files named like temporaries
//! are a user's unless a lock record proves otherwise; a re-run replaces
//! the earlier result only once it is complete, so a run that fails leaves
//! it whole, and what a killed run staged is moved in or settled, never
//! lost. (One run at a time per folder: `tests/app/resume.rs`.)
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
            "-o .: README.md is not written by masssprings trace",
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

/// The temporaries (partial or staged) in `folder`.
fn temporaries(folder: &Path) -> Vec<String> {
    names(folder)
        .into_iter()
        .filter(|name| name.contains(".masssprings-") && name != ".masssprings-lock")
        .collect()
}

/// Waits until `ready` holds, at most a minute.
fn wait_for(what: &str, mut ready: impl FnMut() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(start.elapsed() < Duration::from_secs(60), "{what}");
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// Starts the binary with `args`, its output discarded.
fn start(args: &[&str]) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// The device and inode of `path`: the same folder, not one put in its
/// place.
fn inode(path: &Path) -> (u64, u64) {
    use std::os::unix::fs::MetadataExt;
    let metadata = std::fs::metadata(path).unwrap();
    (metadata.dev(), metadata.ino())
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
    // killed while it computes, on a larger scene
    succeeded(&masssprings(&[
        "generate",
        "grid",
        "150",
        "--out",
        text(&folder),
    ]));
    let grid = folder.join("grid-150.json");
    let mut child = start(&["trace", text(&grid), "-o", text(&out), "--step", "40"]);
    wait_for("no lock", || out.join(".masssprings-lock").exists());
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
    // files a killed trace staged or set aside: its own are settled, a
    // user's file it had set aside is put back
    let dead = format!("masssprings-{}-1", dead_pid());
    std::fs::copy(
        out.join("A.mtx"),
        out.join(format!(".A.mtx.{dead}-0.staged")),
    )
    .unwrap();
    std::fs::write(out.join(format!(".notes.txt.{dead}-1.staged")), "mine").unwrap();
    // the next trace replaces the first
    succeeded(&masssprings(&[
        "trace",
        &net,
        "-o",
        text(&out),
        "--iterations",
        "1",
    ]));
    assert!(temporaries(&out).is_empty(), "{:?}", names(&out));
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(out.join("p_1.mtx").exists() && !out.join("p_3.mtx").exists());
    assert!(!out.join(".masssprings-lock").exists());
    let compared = masssprings(&["trace", "--compare", text(&out), text(&out)]);
    succeeded(&compared);
}

#[test]
fn trace_writes_in_place_and_leaves_every_other_file_alone() {
    use std::os::unix::fs::PermissionsExt;
    let folder = temp_folder("trace-in-place");
    let out = folder.join("out");
    let net = data("net.json");
    succeeded(&masssprings(&["trace", &net, "-o", text(&out)]));
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o700)).unwrap();
    let folder_itself = inode(&out);
    succeeded(&masssprings(&[
        "generate",
        "grid",
        "150",
        "--out",
        text(&folder),
    ]));
    let grid = folder.join("grid-150.json");
    let args = ["trace", text(&grid), "-o", text(&out), "--step", "20"];
    // files that appear while it runs, one by a command that takes no lock
    let child = start(&args);
    wait_for("no lock", || out.join(".masssprings-lock").exists());
    std::fs::write(out.join("notes.txt"), "my notes").unwrap();
    succeeded(&masssprings(&[
        "export-q",
        &net,
        "-o",
        text(&out.join("q.mtx")),
    ]));
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "my notes"
    );
    assert!(text_of(&out.join("q.mtx")).contains("%%MatrixMarket"));
    let mode = std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o700, "the folder's mode is kept");
    assert_eq!(
        inode(&out),
        folder_itself,
        "the same folder, never exchanged"
    );
    // one of its own files replaced meanwhile by another program: kept,
    // and the trace moves nothing in
    let before = snapshot(&out);
    let child = start(&args);
    wait_for("no lock", || out.join(".masssprings-lock").exists());
    std::thread::sleep(Duration::from_millis(300)); // after it has looked
    succeeded(&masssprings(&[
        "export-q",
        &net,
        "-o",
        text(&out.join("Q.mtx")),
    ]));
    let theirs = std::fs::read(out.join("Q.mtx")).unwrap();
    let output = child.wait_with_output().unwrap();
    assert_fails(
        &output,
        &[
            "Q.mtx: this is not a file masssprings trace wrote",
            "it is kept",
            "the earlier trace",
        ],
    );
    assert_eq!(std::fs::read(out.join("Q.mtx")).unwrap(), theirs);
    let mut now = snapshot(&out);
    let mut was = before;
    now.remove(&out.join("Q.mtx"));
    was.remove(&out.join("Q.mtx"));
    assert_same(&now, &was, "every other file as it was");
    let compared = masssprings(&["trace", "--compare", text(&out), text(&out)]);
    assert_fails(
        &compared,
        &["Q.mtx: not of the trace", "run masssprings trace again"],
    );
}

fn text_of(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
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

/// The steps of the frames in `folder`, and of the staged frames.
fn frames_and_staged(folder: &Path) -> (Vec<String>, Vec<String>) {
    let all = names(folder);
    let frames = all.iter().filter(|n| n.starts_with("frame-")).cloned();
    let staged = all.iter().filter(|n| n.ends_with(".staged")).cloned();
    (frames.collect(), staged.collect())
}

/// The run a frame's record names, if any.
fn run_of(frame: &Path) -> Option<String> {
    let text = text_of(frame);
    let record = text.lines().nth(1)?.strip_prefix("# masssprings run ")?;
    let json: serde_json::Value = serde_json::from_str(record).unwrap();
    json.get("run")?.as_str().map(String::from)
}

#[test]
fn a_forced_run_whose_frames_cannot_replace_the_old_ones_keeps_both() {
    let folder = temp_folder("simulate-stuck");
    let out = folder.join("out");
    succeeded(&masssprings(&[
        "generate",
        "grid",
        "40",
        "--out",
        text(&folder),
    ]));
    let grid = folder.join("grid-40.json");
    let net = data("net.json");
    succeeded(&masssprings(&[
        "simulate",
        &net,
        "--steps",
        "4",
        "--out",
        text(&out),
    ]));
    let first = snapshot(&out);
    // an old frame replaced by another program while the forced run goes on
    let args = [
        "simulate",
        &net,
        "--steps",
        "400",
        "--out",
        text(&out),
        "--force",
    ];
    let child = start(&args);
    wait_for("nothing staged", || !frames_and_staged(&out).1.is_empty());
    std::fs::write(out.join("frame-000002.obj"), "my notes").unwrap();
    let output = child.wait_with_output().unwrap();
    assert_fails(
        &output,
        &[
            "frame-000002.obj: this is not a file masssprings simulate wrote",
            "it is kept",
            "the run's 401 frames are staged in",
            "simulate --resume",
        ],
    );
    let (frames, staged) = frames_and_staged(&out);
    assert_eq!(staged.len(), 401, "every new frame is kept, staged");
    assert_eq!(frames.len(), 5);
    assert_eq!(text_of(&out.join("frame-000002.obj")), "my notes");
    for step in [0, 1, 3, 4] {
        let frame = out.join(format!("frame-00000{step}.obj"));
        assert_eq!(std::fs::read(&frame).unwrap(), first[&frame], "{step}");
    }
    // a new run is told about them; --resume moves them in once the way is clear
    let refused = masssprings(&["simulate", &net, "--out", text(&out)]);
    assert_fails(&refused, &["--resume"]);
    std::fs::remove_file(out.join("frame-000002.obj")).unwrap();
    let resumed = masssprings(&["simulate", &net, "--steps", "2", "--resume", text(&out)]);
    succeeded(&resumed);
    assert!(
        stderr(&resumed).contains("moved in 401 frame(s)"),
        "{}",
        stderr(&resumed)
    );
    let (frames, staged) = frames_and_staged(&out);
    assert!(staged.is_empty(), "{staged:?}");
    assert_eq!(frames.len(), 403);
    let run = run_of(&out.join("frame-000000.obj")).expect("a replacing run names itself");
    assert_eq!(
        run_of(&out.join("frame-000402.obj")),
        Some(run),
        "resumed: the same run"
    );
    // an old frame that cannot be replaced at all (immutable: root on a
    // file system with attributes, such as ext4)
    let immutable = Command::new("chattr")
        .args(["+i", text(&out.join("frame-000001.obj"))])
        .output()
        .is_ok_and(|o| o.status.success());
    if immutable {
        let before = snapshot(&out);
        let output = masssprings(&[
            "simulate",
            text(&grid),
            "--steps",
            "3",
            "--out",
            text(&out),
            "--force",
        ]);
        let _ = Command::new("chattr")
            .args(["-i", text(&out.join("frame-000001.obj"))])
            .status();
        assert_fails(
            &output,
            &["frame-000001.obj: cannot replace it by renaming", "staged"],
        );
        let mut now = snapshot(&out);
        now.retain(|path, _| !path.to_string_lossy().ends_with(".staged"));
        assert_same(&now, &before, "every old frame, whole");
        assert_eq!(frames_and_staged(&out).1.len(), 4);
    }
}

#[test]
fn frames_a_killed_forced_run_staged_are_moved_in_by_resume() {
    let folder = temp_folder("simulate-killed-force");
    let out = folder.join("out");
    succeeded(&masssprings(&[
        "generate",
        "grid",
        "40",
        "--out",
        text(&folder),
    ]));
    let grid = folder.join("grid-40.json");
    let grid = text(&grid);
    succeeded(&masssprings(&[
        "simulate",
        grid,
        "--steps",
        "3",
        "--out",
        text(&out),
    ]));
    let first = snapshot(&out);
    let mut child = start(&[
        "simulate",
        grid,
        "--steps",
        "100000",
        "--out",
        text(&out),
        "--force",
    ]);
    wait_for("too few staged", || frames_and_staged(&out).1.len() >= 20);
    child.kill().unwrap();
    child.wait().unwrap();
    let mut now = snapshot(&out);
    now.retain(|path, _| {
        path.file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .starts_with("frame-")
    });
    let mut was = first.clone();
    was.retain(|path, _| {
        path.file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .starts_with("frame-")
    });
    assert_same(&now, &was, "the old frames, whole after the kill");
    let staged = frames_and_staged(&out).1.len();
    assert!(staged >= 20, "{staged}");
    // a new run without --force is told; the resume moves them in
    let refused = masssprings(&["simulate", grid, "--out", text(&out)]);
    assert_fails(&refused, &["already holds 4 frame(s)"]);
    let resumed = masssprings(&["simulate", grid, "--steps", "1", "--resume", text(&out)]);
    succeeded(&resumed);
    let (frames, staged_now) = frames_and_staged(&out);
    assert!(staged_now.is_empty(), "{staged_now:?}");
    assert!(
        frames.len() >= staged,
        "{} frames for {staged} staged",
        frames.len()
    );
    let run = run_of(&out.join("frame-000000.obj"));
    for frame in &frames {
        assert_eq!(run_of(&out.join(frame)), run, "{frame}: one run");
    }
}

#[test]
fn a_move_in_stopped_half_way_is_completed_by_resume() {
    let folder = temp_folder("simulate-half-moved");
    let (x, out) = (folder.join("x"), folder.join("out"));
    let net = data("net.json");
    // X: a run that replaced another (its frames name their run), whose
    // process has ended
    succeeded(&masssprings(&[
        "simulate",
        &net,
        "--steps",
        "1",
        "--out",
        text(&x),
    ]));
    succeeded(&masssprings(&[
        "simulate",
        &net,
        "--steps",
        "6",
        "--out",
        text(&x),
        "--force",
    ]));
    let run = run_of(&x.join("frame-000000.obj")).unwrap();
    // the folder as a kill during X's move-in into `out` left it: an older
    // run's frames 0 to 9, X's frames 0 to 3 moved in, 4 to 6 still staged,
    // and an old frame exchanged out and not yet removed
    succeeded(&masssprings(&[
        "simulate",
        &net,
        "--steps",
        "9",
        "--out",
        text(&out),
    ]));
    let old_frame_2 = std::fs::read(out.join("frame-000002.obj")).unwrap();
    for step in 0..=6 {
        let name = format!("frame-00000{step}.obj");
        let to = match step {
            0..=3 => name.clone(),
            _ => format!(".{name}.{run}-{step}.staged"),
        };
        std::fs::copy(x.join(&name), out.join(to)).unwrap();
    }
    std::fs::write(
        out.join(format!(".frame-000002.obj.{run}-20.staged")),
        old_frame_2,
    )
    .unwrap();
    let resumed = masssprings(&["simulate", &net, "--steps", "2", "--resume", text(&out)]);
    succeeded(&resumed);
    assert!(
        stderr(&resumed).contains("moved in 3 frame(s)"),
        "{}",
        stderr(&resumed)
    );
    let (frames, staged) = frames_and_staged(&out);
    assert!(staged.is_empty(), "{staged:?}");
    assert_eq!(frames.len(), 9, "X's 0 to 6, and 7, 8 resumed: {frames:?}");
    // the same as X run on for two steps
    succeeded(&masssprings(&[
        "simulate",
        &net,
        "--steps",
        "2",
        "--resume",
        text(&x),
    ]));
    for frame in &frames {
        assert_eq!(
            text_of(&out.join(frame)),
            text_of(&x.join(frame)),
            "{frame}"
        );
    }
}

#[test]
fn a_file_that_appears_where_a_frame_goes_is_kept() {
    let folder = temp_folder("simulate-appeared");
    let out = folder.join("out");
    succeeded(&masssprings(&[
        "generate",
        "grid",
        "40",
        "--out",
        text(&folder),
    ]));
    let grid = folder.join("grid-40.json");
    let child = start(&[
        "simulate",
        text(&grid),
        "--steps",
        "400",
        "--out",
        text(&out),
    ]);
    wait_for("no frame", || out.join("frame-000001.obj").exists());
    std::fs::write(out.join("frame-000300.obj"), "mine").unwrap();
    let output = child.wait_with_output().unwrap();
    assert_fails(
        &output,
        &[
            "frame-000300.obj: a file appeared here while masssprings simulate ran",
            "it is kept",
        ],
    );
    assert_eq!(text_of(&out.join("frame-000300.obj")), "mine");
    assert!(temporaries(&out).is_empty(), "{:?}", temporaries(&out));
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
