//! Running the `masssprings` binary from integration tests. Kept apart from
//! `common/mod.rs` (which the renderer's unit tests include too, where the
//! binary's path is not defined); include it with
//! `#[path = "common/cli.rs"] mod cli;`.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Every command of `masssprings --help`.
pub const COMMANDS: [&str; 12] = [
    "simulate",
    "render",
    "view",
    "converge",
    "analyze",
    "bench",
    "export-q",
    "spy",
    "etree",
    "trace",
    "generate",
    "completions",
];

/// Runs the binary with `args` and waits for it.
pub fn masssprings(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// What the run printed on stdout.
pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// What the run printed on stderr.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A fresh, empty folder under the system's temporary folder, unique to
/// this test process and `name`, removed when the test is done with it
/// (kept when the test fails, to look into).
pub fn temp_folder(name: &str) -> TempFolder {
    let folder =
        std::env::temp_dir().join(format!("masssprings-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    TempFolder(folder)
}

/// The folder of [`temp_folder`]; reads as its path.
#[derive(Debug)]
pub struct TempFolder(PathBuf);

impl std::ops::Deref for TempFolder {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.0
    }
}

impl AsRef<Path> for TempFolder {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempFolder {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// The path of a bundled scene file in `data/`.
pub fn data(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name)
        .display()
        .to_string()
}

/// Runs the binary with `args` in `folder` (its current folder).
pub fn masssprings_in(folder: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(args)
        .current_dir(folder)
        .output()
        .expect("the binary runs")
}

/// The names in `folder`, sorted (none when it does not exist).
pub fn names_in(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = match std::fs::read_dir(folder) {
        Ok(entries) => entries
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    };
    names.sort();
    names
}

/// A copy of the bundled `name` scene (JSON and OBJ, and the texture when
/// it has one) in `folder`; returns the JSON's path.
pub fn copy_scene(folder: &Path, name: &str) -> PathBuf {
    for extension in ["json", "obj", "png"] {
        let file = format!("{name}.{extension}");
        if Path::new(&data(&file)).exists() {
            std::fs::copy(data(&file), folder.join(&file)).unwrap();
        }
    }
    folder.join(format!("{name}.json"))
}

/// Asserts a clean failure: exit code 1 (no panic, no abort) and every
/// piece of `expected` in the message.
pub fn assert_fails(output: &Output, expected: &[&str]) {
    let message = stderr(output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(!message.contains("panicked"), "{message}");
    for piece in expected {
        assert!(message.contains(piece), "`{piece}` not in: {message}");
    }
}

/// A scene whose first step blows up, `s.json` and `s.obj` in `folder`:
/// `y = M (2U − U_prev)/Δt²` overflows (1000 · 1e306 · 900 is beyond f64).
/// Returns the JSON's path.
pub fn blow_up_scene(folder: &Path) -> PathBuf {
    std::fs::write(
        folder.join("s.json"),
        r#"{"obj": "s.obj", "k": 1, "b": [1], "m": 1000}"#,
    )
    .unwrap();
    std::fs::write(
        folder.join("s.obj"),
        "v 0 0 0\nv 1e306 0 0\nv 0 1e306 0\nf 1 2\nf 2 3\n",
    )
    .unwrap();
    folder.join("s.json")
}

/// `trace --compare --json ours theirs`: (exit code, the JSON it prints).
pub fn compare_json(ours: &Path, theirs: &Path) -> (Option<i32>, serde_json::Value) {
    let args = [
        "trace",
        "--compare",
        ours.to_str().unwrap(),
        theirs.to_str().unwrap(),
        "--json",
    ];
    let output = masssprings(&args);
    let json = serde_json::from_str(&stdout(&output))
        .unwrap_or_else(|e| panic!("{e}: {}\n{}", stdout(&output), stderr(&output)));
    (output.status.code(), json)
}
