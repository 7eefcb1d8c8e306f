//! The folder `trace -o DIR` writes, and how a new trace takes the place of
//! an earlier one, file by file (`masssprings::files::outputs`: the rule
//! every output keeps).
//!
//! * **Inputs are never written**: the scene's JSON, its OBJ and its
//!   texture are inputs of the run's file plan, and every file `trace`
//!   writes is an output, so a `DIR/A.mtx` that is a link to the OBJ, or
//!   an OBJ named `README.md` in `-o .`, is refused before any work.
//! * **Only its own names, only its own files**: `trace` writes the
//!   quantities' files, `README.md` and `trace.json`, and nothing else in
//!   `DIR` is read, moved or removed. At those names, a file an earlier
//!   trace wrote (a quantity saying `written by masssprings trace` in its
//!   first lines, the README it writes, a manifest that reads) is
//!   replaced; anything else (a user's `README.md`, a link, a student's
//!   `d_9.mtx`) is named and refused, unless `--force`.
//! * **A mistake is never written over a correct trace** (nor over another
//!   mistake's) without `--force`: `trace.json` says which a trace is.
//! * **A new trace replaces an old one once it is complete**: every file
//!   is staged beside its place, then all are moved in (the manifest
//!   last), and only then are the earlier trace's files that the new one
//!   does not have removed. A run that fails leaves the earlier trace as
//!   it was; a run killed while its files are moved in leaves a folder
//!   whose files do not all carry the manifest's `trace` fingerprint, which
//!   `--compare` refuses, naming the file; the next trace into `DIR`
//!   settles what a killed run staged.

use super::manifest::{read_manifest, MANIFEST};
use super::quantities::quantities;
use crate::app::error::AppError;
use crate::app::file_plan::{begins_with, plan_scene_inputs, refuse_foreign, start_holds};
use masssprings::files::{shown, Expect, FilePlan, OutputFolder};
use masssprings::mesh::Scene;
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::ITERATIONS;
use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

/// The mark of a quantity written by `trace`, in its first lines.
pub const WRITTEN_BY: &str = "written by masssprings trace";

/// The first line of the README `trace` writes.
pub const README_START: &str = "# Every quantity of the handout: ";

/// What one of trace's names held when the run started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    /// A file an earlier trace wrote.
    Own,
    /// Something else, to be replaced because of `--force`.
    Other,
}

/// Where a trace is written, held for the run.
pub struct TraceFolder {
    out: OutputFolder,
    /// What trace's names held when the run started (a name not here held
    /// nothing).
    found: BTreeMap<String, Found>,
    /// The files staged so far, in order, and their names.
    staged: Vec<(PathBuf, String)>,
}

impl TraceFolder {
    /// Checks and locks `out` for a trace of `scene` (read from
    /// `scene_path`), with `mistake` if one is made on purpose; `force`
    /// lets it replace files that are not `trace`'s, and a trace of
    /// another kind.
    ///
    /// # Errors
    /// `out` is `-` or a file; a file `trace` writes is an input; another
    /// run holds `out`; files `trace` did not write are at its names, or
    /// the trace there is of another kind (without `force`).
    pub fn open(
        out: &Path,
        scene_path: &Path,
        scene: &Scene,
        (force, mistake): (bool, Option<Mistake>),
    ) -> Result<TraceFolder, AppError> {
        if out == Path::new("-") {
            return Err(AppError::Usage(
                "-o -: trace writes a folder of files, not one stream; name a folder".into(),
            ));
        }
        if fs::metadata(out).is_ok_and(|m| !m.is_dir()) {
            return Err(AppError::Failed(format!(
                "-o {}: this is a file; trace writes a folder of files (give a new or empty \
                 folder)",
                shown(out)
            )));
        }
        plan(out, scene_path, scene)?;
        let folder = OutputFolder::open(out, "trace")?;
        let found = survey(&folder);
        let foreign: Vec<PathBuf> = found
            .iter()
            .filter(|(_, &found)| found == Found::Other)
            .map(|(name, _)| folder.path(name))
            .collect();
        refuse_foreign(&format!("-o {}", shown(out)), "trace", &foreign, force)?;
        if found.get(MANIFEST) == Some(&Found::Own) && !force {
            refuse_other_kind(out, mistake)?;
        }
        Ok(TraceFolder {
            out: folder,
            found,
            staged: Vec::new(),
        })
    }

    /// Stages the file `name`: written whole beside its place, moved in by
    /// [`TraceFolder::commit`].
    ///
    /// # Errors
    /// Writing failed.
    pub fn write(
        &mut self,
        name: &str,
        write: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
    ) -> Result<(), AppError> {
        let staged = self.out.stage(name, write)?;
        self.staged.push((staged, name.to_string()));
        Ok(())
    }

    /// The new trace is complete: its files take their places in the order
    /// they were written (the manifest last); then the earlier trace's
    /// files it does not have are removed, and what a killed trace staged
    /// is settled.
    ///
    /// # Errors
    /// A file could not be moved in (the folder is then as it was) or an
    /// old one could not be removed; the message names it.
    pub fn commit(mut self) -> Result<(), AppError> {
        let staged = std::mem::take(&mut self.staged);
        let files: Vec<(PathBuf, &str, Expect)> = staged
            .iter()
            .map(|(path, name)| (path.clone(), name.as_str(), self.expect(name)))
            .collect();
        let held = match self.out.place_all(&files) {
            Ok(held) => held,
            Err(error) => {
                for (path, _) in &staged {
                    self.out.discard_staged(path);
                }
                return Err(AppError::Failed(format!(
                    "{error}; the earlier trace in {} is as it was",
                    shown(self.out.folder())
                )));
            }
        };
        let written: Vec<&str> = staged.iter().map(|(_, name)| name.as_str()).collect();
        let earlier = self
            .found
            .iter()
            .filter(|(name, &found)| found == Found::Own && !written.contains(&name.as_str()));
        for (name, _) in earlier {
            self.out.remove_own(name, own_check(name))?;
        }
        self.out.discard(held)?;
        for leftover in self.out.leftovers() {
            if let Some(kept) = self.out.settle(&leftover, &is_any_trace_file) {
                eprintln!(
                    "kept {}: a file a killed run had set aside, not written by masssprings trace",
                    shown(&kept)
                );
            }
        }
        Ok(())
    }

    /// What `name` may hold when the new file is moved there.
    fn expect(&self, name: &str) -> Expect<'static> {
        match self.found.get(name) {
            None => Expect::Nothing,
            Some(Found::Own) => Expect::Own(own_check(name)),
            Some(Found::Other) => Expect::Any,
        }
    }
}

impl Drop for TraceFolder {
    fn drop(&mut self) {
        // not committed: the run failed, and the earlier trace stays
        for (path, _) in &self.staged {
            self.out.discard_staged(path);
        }
    }
}

/// Refuses a trace of one kind over a trace of another: a mistake over a
/// correct trace or over another mistake's.
fn refuse_other_kind(out: &Path, mistake: Option<Mistake>) -> Result<(), AppError> {
    let Some(mistake) = mistake else {
        return Ok(()); // a correct trace may replace any trace
    };
    let earlier = read_manifest(out)?;
    if earlier.mistake.as_deref() == Some(mistake.name()) {
        return Ok(());
    }
    let holds = match &earlier.mistake {
        None => "a correct trace (no mistake)".to_string(),
        Some(other) => format!(
            "a trace with the mistake {}",
            masssprings::files::escaped(other)
        ),
    };
    Err(AppError::Failed(format!(
        "-o {}: the folder holds {holds} of {}; --mistake {} would replace it with a trace with \
         that mistake. Give --force to replace it, or choose another folder",
        shown(out),
        masssprings::files::escaped(&earlier.scene),
        mistake.name()
    )))
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

/// What each of trace's names in `out` holds now: nothing (left out), a
/// file an earlier trace wrote, or something else.
fn survey(out: &OutputFolder) -> BTreeMap<String, Found> {
    let mut found = BTreeMap::new();
    for name in trace_names() {
        let path = out.path(&name);
        if fs::symlink_metadata(&path).is_err() {
            continue;
        }
        let own = fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) && own_check(&name)(&path);
        found.insert(name, if own { Found::Own } else { Found::Other });
    }
    found
}

/// How to tell trace's own file named `name`.
fn own_check(name: &str) -> &'static dyn Fn(&Path) -> bool {
    match name {
        MANIFEST => &is_manifest,
        "README.md" => &is_readme,
        _ => &is_quantity,
    }
}

/// A manifest that reads (only a regular file is read: a FIFO would be
/// waited for).
fn is_manifest(path: &Path) -> bool {
    let regular = fs::symlink_metadata(path).is_ok_and(|m| m.is_file());
    let text = || masssprings::files::read_text(path).ok();
    regular
        && text()
            .is_some_and(|text| serde_json::from_str::<super::manifest::Manifest>(&text).is_ok())
}

/// The README trace writes.
fn is_readme(path: &Path) -> bool {
    begins_with(path, README_START)
}

/// A quantity trace wrote: its mark in the first lines.
fn is_quantity(path: &Path) -> bool {
    start_holds(path, WRITTEN_BY, 1024)
}

/// Any of trace's own files: what a killed trace staged or set aside.
fn is_any_trace_file(path: &Path) -> bool {
    is_quantity(path) || is_readme(path) || is_manifest(path)
}
