//! The folder `trace -o DIR` writes, and how a new trace takes the place of
//! an earlier one.
//!
//! * **Inputs are never written**: the scene's JSON, its OBJ and its
//!   texture are inputs of the run's file plan, and every file `trace`
//!   writes is an output, so a `DIR/A.mtx` that is a link to the OBJ, or
//!   an OBJ named `README.md` in `-o .`, is refused before any work.
//! * **Only its own files are replaced**: `DIR` must be missing, empty, or
//!   hold only what an earlier trace wrote there — `trace.json` (a manifest
//!   that reads), the files it lists (each Matrix Market file saying it was
//!   written by `masssprings trace`) and the `README.md` it wrote. Anything
//!   else (a user's `README.md`, notes, the scene itself, a link) is named
//!   and refused, unless `--force`.
//! * **A new trace replaces an old one once it is complete**: it is
//!   written into a folder beside `DIR` (`.DIR.masssprings-PID-START-N.tmp`)
//!   and then exchanged with `DIR` in one step (Linux's `renameat2`; three
//!   renames elsewhere), and the old trace is removed after. A run that
//!   fails, or is killed, leaves the old trace whole; a killed run's
//!   staging folder is removed by the next trace into `DIR`, which finds
//!   its owner in `DIR`'s lock.
//! * **In place** (no swap) when `--force` writes among files that are not
//!   `trace`'s, when `DIR` is the current folder (whose place a shell holds)
//!   or a mount point (which cannot be renamed), or when the folder above
//!   `DIR` cannot be written: the old manifest is
//!   removed first, so a run that fails there leaves a folder `--compare`
//!   refuses, never a manifest over a mixture.

use super::manifest::{is_trace_file, read_manifest, MANIFEST};
use super::quantities::quantities;
use crate::app::error::AppError;
use crate::app::file_plan::{
    begins_with, plan_scene_inputs, refuse_foreign, start_holds, unlink_link,
};
use masssprings::files::{
    exchange_folders, resolve, same_file, temporary_folder, temporary_owner, FilePlan, FolderLock,
    LOCK_FILE,
};
use masssprings::mesh::Scene;
use masssprings::sim::ITERATIONS;
use std::fs;
use std::path::{Path, PathBuf};

/// The mark of a quantity written by `trace`, in its first lines.
pub const WRITTEN_BY: &str = "written by masssprings trace";

/// The first line of the README `trace` writes.
pub const README_START: &str = "# Every quantity of the handout: ";

/// Where a trace is written, held for the run.
pub struct TraceFolder {
    /// `DIR` with its links followed.
    out: PathBuf,
    _lock: FolderLock,
    /// The folder beside `DIR` that takes its place at the end; `None`:
    /// written in place.
    staging: Option<PathBuf>,
    /// The files of the earlier trace (in place: removed when not written
    /// again).
    earlier: Vec<String>,
}

impl TraceFolder {
    /// Checks and locks `out` for a trace of `scene` (read from
    /// `scene_path`); `force` lets it write among files that are not
    /// `trace`'s.
    ///
    /// # Errors
    /// `out` is a file; a file `trace` writes is an input; another run
    /// holds `out`; files `trace` did not write are there (without
    /// `force`).
    pub fn open(
        out: &Path,
        scene_path: &Path,
        scene: &Scene,
        force: bool,
    ) -> Result<TraceFolder, AppError> {
        if fs::metadata(out).is_ok_and(|m| !m.is_dir()) {
            return Err(AppError::Failed(format!(
                "-o {}: this is a file; trace writes a folder of files (give a new or empty \
                 folder)",
                out.display()
            )));
        }
        plan(out, scene_path, scene)?;
        let failed = |e: std::io::Error| AppError::Failed(format!("-o {}: {e}", out.display()));
        let resolved = resolve(out).map_err(failed)?;
        // a killed trace's staging folder is beside `out`
        let beside: Vec<&Path> = resolved.parent().into_iter().collect();
        let lock = FolderLock::acquire_cleaning(out, "trace", &beside)?;
        let (earlier, foreign) = survey(out);
        refuse_foreign(&format!("-o {}", out.display()), "trace", &foreign, force)?;
        let in_place =
            !foreign.is_empty() || same_file(out, Path::new(".")) || is_mount_point(&resolved);
        let staging = if in_place {
            None
        } else {
            temporary_folder(&resolved).ok()
        };
        Ok(TraceFolder {
            out: resolved,
            _lock: lock,
            staging,
            earlier,
        })
    }

    /// The folder to write the files into now.
    pub fn target(&self) -> &Path {
        self.staging.as_deref().unwrap_or(&self.out)
    }

    /// Before the files are written: in place, the earlier manifest goes
    /// first, so that no manifest stands over a mixture of two traces.
    ///
    /// # Errors
    /// The manifest cannot be removed.
    pub fn begin(&self) -> Result<(), AppError> {
        if self.staging.is_some() {
            return Ok(());
        }
        if self.earlier.iter().any(|name| name == MANIFEST) {
            let manifest = self.out.join(MANIFEST);
            fs::remove_file(&manifest)
                .map_err(|e| AppError::Failed(format!("{}: {e}", manifest.display())))?;
        }
        for name in trace_names() {
            unlink_link(&self.out.join(name))?; // forced: the link goes, not its target
        }
        Ok(())
    }

    /// The new trace (of the files `written`) is complete: it takes the
    /// earlier trace's place (staged: by exchanging the two folders; in
    /// place: the earlier files not written again are removed).
    ///
    /// # Errors
    /// The exchange failed (the earlier trace is then as it was, and the
    /// new one is removed).
    pub fn commit(mut self, written: &[String]) -> Result<(), AppError> {
        let Some(staging) = self.staging.take() else {
            for name in self.earlier.iter().filter(|name| !written.contains(name)) {
                let _ = fs::remove_file(self.out.join(name));
            }
            return Ok(());
        };
        let failed = |e: std::io::Error| {
            let _ = fs::remove_dir_all(&staging);
            AppError::Failed(format!("-o {}: {e}", self.out.display()))
        };
        // the new folder's own lock, held from before the exchange to the end
        let mut new_lock = FolderLock::acquire(&staging, "trace")?;
        exchange_folders(&staging, &self.out).map_err(failed)?;
        new_lock.moved_to(&self.out);
        let _ = fs::remove_dir_all(&staging); // the earlier trace, now at the staging name
        Ok(())
    }
}

impl Drop for TraceFolder {
    fn drop(&mut self) {
        if let Some(staging) = self.staging.take() {
            let _ = fs::remove_dir_all(staging); // a failed run: the earlier trace stays
        }
    }
}

/// Is `folder` the root of a file system of its own (a mount point), which
/// cannot be renamed nor exchanged with a folder beside it?
#[cfg(unix)]
fn is_mount_point(folder: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    let parent = folder.parent().unwrap_or(folder);
    match (fs::metadata(folder), fs::metadata(parent)) {
        (Ok(a), Ok(b)) => a.dev() != b.dev() || a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn is_mount_point(_folder: &Path) -> bool {
    false
}

/// Refuses a trace whose files would be one of the scene's (through a
/// link, or by name: an OBJ called `README.md` in `-o .`).
fn plan(out: &Path, scene_path: &Path, scene: &Scene) -> Result<(), AppError> {
    let mut plan = FilePlan::default();
    plan_scene_inputs(&mut plan, scene_path, scene);
    for name in trace_names() {
        plan.output("trace's file", &out.join(name));
    }
    plan.check()?;
    Ok(())
}

/// Every name `trace` may write: each quantity of the longest trace, the
/// README and the manifest.
fn trace_names() -> Vec<String> {
    let quantities = quantities(ITERATIONS).into_iter().map(|q| q.file_name());
    quantities
        .chain(["README.md".into(), MANIFEST.into()])
        .collect()
}

/// The names of the earlier trace in `out`, and the files there that are
/// not `trace`'s (the lock and temporaries aside).
fn survey(out: &Path) -> (Vec<String>, Vec<PathBuf>) {
    // only a regular file is read (a FIFO would be waited for)
    let manifest_file = fs::symlink_metadata(out.join(MANIFEST)).is_ok_and(|m| m.is_file());
    let manifest = manifest_file.then(|| read_manifest(out).ok()).flatten();
    let listed = |name: &str| {
        manifest
            .as_ref()
            .is_some_and(|m| m.files.iter().any(|f| f == name) && is_trace_file(name))
    };
    let (mut earlier, mut foreign) = (Vec::new(), Vec::new());
    let Ok(entries) = fs::read_dir(out) else {
        return (earlier, foreign);
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = entry.path();
        let regular = entry.file_type().is_ok_and(|kind| kind.is_file());
        let ours = match name.as_str() {
            LOCK_FILE => continue,
            _ if temporary_owner(&name).is_some() => continue,
            MANIFEST => manifest.is_some() && regular,
            "README.md" => manifest.is_some() && regular && begins_with(&path, README_START),
            _ => listed(&name) && regular && start_holds(&path, WRITTEN_BY, 1024),
        };
        if ours {
            earlier.push(name);
        } else {
            foreign.push(path);
        }
    }
    foreign.sort();
    (earlier, foreign)
}
