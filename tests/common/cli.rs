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
