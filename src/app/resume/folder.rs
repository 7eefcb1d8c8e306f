//! The folder `simulate --out DIR` (or `--resume DIR`) writes its frames
//! into, held for the whole run, written by the rule every output keeps
//! (`masssprings::files::outputs`):
//!
//! * **one run at a time**: the folder's lock is taken before anything is
//!   read or written there, so a second run into the same folder, or a
//!   `--resume` beside a live run, is refused instead of mixing its frames
//!   with the first one's;
//! * **a frame is never written over a file**: a new run's frames, and a
//!   resumed run's, go to names that are free, and a file that appears at
//!   one of them while the run goes on is kept and stops the run;
//! * **frames of an earlier run** (`frame-*.obj`) are refused, unless
//!   `--force`: then the new frames are *staged* beside their places
//!   (`.frame-NNNNNN.obj.masssprings-PID-START-N.staged`) and moved in only
//!   once the run is complete ([`FrameFolder::commit`]); then the earlier
//!   run's frames that no new frame replaced are removed (each checked to
//!   be a frame `simulate` wrote, of another run), the new run's last frame
//!   moved in last. A run that fails leaves the old frames whole and its
//!   staged frames are removed; a run killed, or one whose frames cannot
//!   be moved in, leaves them staged, and `--resume DIR` moves them in
//!   and goes on ([`FrameFolder::resume_killed_run`]), or refuses and says
//!   where they are;
//! * **the material and the texture copy** (`NAME.mtl`, the texture's
//!   name) are replaced only when they are this command's: a material
//!   whose first line is the one `simulate` writes, a copy holding the
//!   texture's bytes; anything else there is refused unless `--force`
//!   (`file_plan`).
//!
//! The frames of a run that replaces another's name their run in their
//! record (`masssprings-PID-START` of the process that started it; a
//! resumed run keeps the name): that is how the frames of the two runs are
//! told apart in one folder, while a killed replacement is completed.
//! Other runs' frames name none, so that a run and the same run resumed
//! write the same bytes.

use super::frames::{frame_name, frame_step, is_frame_name, parse_head, Head, RunRecord};
use crate::app::error::AppError;
use crate::app::file_plan::{holds_bytes, occupied, read_up_to, refuse_foreign, starts_with_line};
use masssprings::files::patient::open_regular;
use masssprings::files::{read_bytes, same_file, shown, Expect, FileError, Leftover, OutputFolder};
use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// What a run does with its folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Use {
    /// A new run (`--out`); `force`: replace what is in the way.
    Fresh { force: bool },
    /// The run continues there (`--resume`).
    Resume,
}

/// The files besides the frames that a run writes into its folder, each
/// with the content it writes (to tell its own from a user's).
pub struct Extras<'a> {
    /// `NAME.mtl` and the first line `simulate` writes there.
    pub material: Option<(PathBuf, String)>,
    /// The texture and where its copy goes.
    pub texture: Option<(&'a Path, PathBuf)>,
}

/// What a name held when the run started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    /// The command's own file (a frame `simulate` wrote, its material, the
    /// texture's very bytes).
    Own,
    /// Something else, to be replaced because of `--force`.
    Other,
}

/// How an extra file is told to be `simulate`'s own, again when it is
/// replaced.
#[derive(Debug, Clone)]
enum OwnExtra {
    /// The material: its first line.
    Material(String),
    /// The texture's copy: the texture's very bytes.
    Copy(PathBuf),
}

impl OwnExtra {
    fn holds(&self, path: &Path) -> bool {
        match self {
            OwnExtra::Material(first_line) => starts_with_line(path, first_line),
            OwnExtra::Copy(texture) => {
                same_file(texture, path) || read_bytes(texture).is_ok_and(|b| holds_bytes(path, &b))
            }
        }
    }
}

/// The locked folder of a run's frames.
#[derive(Debug)]
pub struct FrameFolder {
    out: OutputFolder,
    /// What the names of the frames and extras held at the start.
    found: BTreeMap<String, Found>,
    /// How each extra is told to be `simulate`'s, by its name.
    extras: BTreeMap<String, OwnExtra>,
    /// `--force` over an earlier run's frames: the frames staged so far,
    /// by step, moved in by [`FrameFolder::commit`].
    staged: Option<Vec<(usize, PathBuf)>>,
}

impl FrameFolder {
    /// Locks `folder` (made if missing) and checks what is in it for a run
    /// of `how`: frames of another run and files in the way of `extras`.
    ///
    /// # Errors
    /// Another run holds the folder; a file named like a frame that is not
    /// a regular file; frames of another run (placed or staged) or files
    /// not written by `simulate` in the way, without `--force`.
    pub fn open(folder: &Path, how: Use, extras: &Extras) -> Result<FrameFolder, AppError> {
        if how == Use::Resume && !folder.is_dir() {
            return Err(not_a_folder(folder));
        }
        let out = OutputFolder::open(folder, "simulate")?;
        let force = how == (Use::Fresh { force: true });
        let own_extras = own_extras(extras);
        let mut found = survey_extras(&own_extras, extras);
        let foreign: Vec<PathBuf> = found
            .iter()
            .filter(|(_, &found)| found == Found::Other)
            .map(|(name, _)| out.path(name))
            .collect();
        let flag = format!("--out {}", shown(folder));
        refuse_foreign(&flag, "simulate", &foreign, force)?;
        let earlier = earlier_frames(folder)?;
        if let Use::Fresh { force } = how {
            refuse_odd(&earlier)?;
            let staged = frame_leftovers(&out);
            if !force {
                refuse_earlier(folder, &earlier, &staged)?;
            }
        }
        for path in &earlier {
            let own = head(path).is_some();
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            found.insert(
                name.into_owned(),
                if own { Found::Own } else { Found::Other },
            );
        }
        // forced over frames, or over what a stopped run staged: staged
        // too, so that the stopped run's frames are settled once this
        // run's are in
        let replaces = !earlier.is_empty() || !frame_leftovers(&out).is_empty();
        let staged = (force && replaces).then(Vec::new);
        Ok(FrameFolder {
            out,
            found,
            extras: own_extras,
            staged,
        })
    }

    /// Do this run's frames replace an earlier run's (`--force`)? Then
    /// they must name their run, to be told from the earlier run's.
    pub fn replaces(&self) -> bool {
        self.staged.is_some()
    }

    /// The folder itself.
    pub fn folder(&self) -> &Path {
        self.out.folder()
    }

    /// Writes the frame of `step`: at once, at a name that must be free,
    /// or staged while the frames are to replace an earlier run's.
    ///
    /// # Errors
    /// Writing failed, or a file appeared at the frame's name (kept).
    pub fn write_frame(
        &mut self,
        step: usize,
        write: impl FnOnce(&mut dyn io::Write) -> io::Result<()>,
    ) -> Result<(), AppError> {
        let name = frame_name(step);
        match &mut self.staged {
            Some(staged) => staged.push((step, self.out.stage(&name, write)?)),
            None => self.out.write(&name, Expect::Nothing, write)?,
        }
        Ok(())
    }

    /// Writes `path` (the material or the texture's copy, in the folder),
    /// replacing what was there only when it was `simulate`'s or the run
    /// is forced.
    ///
    /// # Errors
    /// Writing failed, or the name holds what may not be replaced (kept).
    pub fn write_extra(
        &self,
        path: &Path,
        write: impl FnOnce(&mut dyn io::Write) -> io::Result<()>,
    ) -> Result<(), AppError> {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let own = |path: &Path| {
            self.extras
                .get(name.as_ref())
                .is_some_and(|e| e.holds(path))
        };
        let expect = match self.found.get(name.as_ref()) {
            None => Expect::Nothing,
            Some(Found::Own) => Expect::Own(&own),
            Some(Found::Other) => Expect::Any,
        };
        self.out.write(&name, expect, write)?;
        Ok(())
    }

    /// The run is complete: its staged frames replace the earlier run's
    /// (`run`: this run's name in the frames' records), and what killed
    /// runs staged is settled.
    ///
    /// # Errors
    /// A frame could not be moved in or an old one removed (the message
    /// names it, and where the new frames are staged).
    pub fn commit(mut self, run: &str) -> Result<(), AppError> {
        let Some(staged) = self.staged.take() else {
            return Ok(());
        };
        let found = &self.found;
        let expect = |name: &str| match found.get(name) {
            None => Expect::Nothing,
            Some(Found::Own) => Expect::Own(&is_frame),
            Some(Found::Other) => Expect::Any,
        };
        move_in(&self.out, &staged, run, expect)?;
        for leftover in frame_leftovers(&self.out) {
            settle(&self.out, &leftover); // a killed run's: replaced by this one
        }
        Ok(())
    }

    /// `--resume`: moves in the frames a killed `simulate --force` staged
    /// here (when they continue the run of `record`), removing the earlier
    /// run's frames they replace, so that the run resumed is the latest.
    ///
    /// # Errors
    /// Frames staged by two killed runs, or by a run with other settings
    /// than `record` (each named with where they are), or a frame that
    /// cannot be moved in.
    pub fn resume_killed_run(&self, record: &RunRecord) -> Result<(), AppError> {
        let leftovers = frame_leftovers(&self.out);
        let Some(first) = leftovers.first() else {
            return Ok(());
        };
        let owner = first.temporary.owner;
        if let Some(other) = leftovers.iter().find(|l| l.temporary.owner != owner) {
            return Err(staged_refusal(
                self.folder(),
                &leftovers,
                &format!(
                    "they were staged by two runs that were stopped (processes {} and {})",
                    owner.pid, other.temporary.owner.pid
                ),
            ));
        }
        let run = owner.tag();
        let mut new: Vec<(usize, PathBuf)> = Vec::new();
        for leftover in &leftovers {
            match head(&leftover.path) {
                Some(head) if head.record.as_ref().and_then(|r| r.run.as_deref()) == Some(&run) => {
                    refuse_other_settings(self.folder(), &leftovers, &head, record)?;
                    new.push((head.step, leftover.path.clone()));
                }
                _ => {} // an old file the killed run had set aside
            }
        }
        new.sort();
        if !new.is_empty() {
            move_in(&self.out, &new, &run, |_| Expect::Own(&is_frame))?;
            eprintln!(
                "moved in {} frame(s) a stopped `simulate --force` had staged in {}, which \
                 replace the earlier run's; resuming that run",
                new.len(),
                shown(self.folder())
            );
        }
        for leftover in frame_leftovers(&self.out) {
            settle(&self.out, &leftover);
        }
        Ok(())
    }
}

impl Drop for FrameFolder {
    fn drop(&mut self) {
        // not committed: the run failed, and the earlier frames stay
        for (_, path) in self.staged.iter().flatten() {
            self.out.discard_staged(path);
        }
    }
}

/// Moves the `staged` frames of `run` in (sorted by step): all but the
/// last, then the earlier frames of other runs are removed, then the last
/// (so that while any is left staged, the staged run is the latest), and
/// the old frames they replaced are removed.
///
/// # Errors
/// A frame could not be moved in (those before it are put back) or an old
/// one removed; the message says where the staged frames are.
fn move_in<'a>(
    out: &OutputFolder,
    staged: &[(usize, PathBuf)],
    run: &str,
    expect: impl Fn(&str) -> Expect<'a>,
) -> Result<(), AppError> {
    let names: Vec<String> = staged.iter().map(|(step, _)| frame_name(*step)).collect();
    let files: Vec<(PathBuf, &str, Expect)> = staged
        .iter()
        .zip(&names)
        .map(|((_, path), name)| (path.clone(), name.as_str(), expect(name)))
        .collect();
    let Some((last, rest)) = files.split_last() else {
        return Ok(());
    };
    let stuck = |error: FileError| {
        AppError::Failed(format!(
            "{error}; the run's {} frames are staged in {} (.frame-NNNNNN.obj.masssprings-…\
             .staged): once that is fixed, simulate --resume {} moves them in",
            staged.len(),
            shown(out.folder()),
            shown(out.folder())
        ))
    };
    let held = out.place_all(rest).map_err(stuck)?;
    let other_run = |path: &Path| {
        head(path).is_some_and(|h| h.record.and_then(|r| r.run).as_deref() != Some(run))
    };
    for path in earlier_frames(out.folder())? {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        if !names.iter().any(|n| *n == name) {
            out.remove_own(&name, &other_run).map_err(stuck)?;
        }
    }
    let held = held.join(out.place_all(std::slice::from_ref(last)).map_err(stuck)?);
    out.discard(held).map_err(stuck)?;
    Ok(())
}

/// Settles a frame a killed run staged or set aside: removed when it is a
/// frame `simulate` wrote, otherwise put back where it came from; says so
/// when it is kept.
fn settle(out: &OutputFolder, leftover: &Leftover) {
    if let Some(kept) = out.settle(leftover, &is_frame) {
        eprintln!(
            "kept {}: a file a stopped run had set aside, not a frame simulate wrote",
            shown(&kept)
        );
    }
}

/// Refuses staged frames of a run with other settings than `record`.
fn refuse_other_settings(
    folder: &Path,
    leftovers: &[Leftover],
    head: &Head,
    record: &RunRecord,
) -> Result<(), AppError> {
    let Some(theirs) = &head.record else {
        return Ok(());
    };
    let differences = theirs.differences(record);
    if differences.is_empty() {
        return Ok(());
    }
    Err(staged_refusal(
        folder,
        leftovers,
        &format!(
            "they are of a run with other settings: {}; resume with that run's scene and flags \
             to move them in and go on",
            differences.join(", ")
        ),
    ))
}

/// The refusal of staged frames that `--resume` cannot move in: where
/// they are, and why.
fn staged_refusal(folder: &Path, leftovers: &[Leftover], why: &str) -> AppError {
    let first = leftovers.first().map(|l| &l.path);
    let last = leftovers.last().map(|l| &l.path);
    let (first, last) = (first.map(|p| shown(p)), last.map(|p| shown(p)));
    AppError::Failed(format!(
        "--resume {}: {} frame(s) that a stopped `simulate --force` staged are there ({} … {}), \
         not moved in: {why}; or move them away (they are whole frames) to resume the frames \
         in place",
        shown(folder),
        leftovers.len(),
        first.unwrap_or_default(),
        last.unwrap_or_default()
    ))
}

/// How each of the extras is told to be `simulate`'s, by its name.
fn own_extras(extras: &Extras) -> BTreeMap<String, OwnExtra> {
    let mut own = BTreeMap::new();
    let name = |path: &Path| {
        path.file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned()
    };
    if let Some((material, first_line)) = &extras.material {
        own.insert(name(material), OwnExtra::Material(first_line.clone()));
    }
    if let Some((texture, copy)) = &extras.texture {
        own.insert(name(copy), OwnExtra::Copy(texture.to_path_buf()));
    }
    own
}

/// What the extras' names held: `simulate`'s own file or another
/// (missing names left out).
fn survey_extras(own: &BTreeMap<String, OwnExtra>, extras: &Extras) -> BTreeMap<String, Found> {
    let paths = [
        extras.material.as_ref().map(|(path, _)| path),
        extras.texture.as_ref().map(|(_, copy)| copy),
    ];
    let mut found = BTreeMap::new();
    for path in paths.into_iter().flatten().filter(|path| occupied(path)) {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let ours = own.get(name.as_ref()).is_some_and(|e| e.holds(path));
        found.insert(
            name.into_owned(),
            if ours { Found::Own } else { Found::Other },
        );
    }
    found
}

/// Refuses a file named like a frame that is not a regular file.
fn refuse_odd(earlier: &[PathBuf]) -> Result<(), AppError> {
    match earlier
        .iter()
        .find_map(|path| Some((path, not_a_file(path)?)))
    {
        Some((path, kind)) => Err(AppError::Failed(format!(
            "{}: this is {kind}, named like a frame; move it away first",
            shown(path)
        ))),
        None => Ok(()),
    }
}

/// Refuses a new run (not forced) into a folder with frames of an
/// earlier run, placed or staged.
fn refuse_earlier(folder: &Path, earlier: &[PathBuf], staged: &[Leftover]) -> Result<(), AppError> {
    if let Some(first) = earlier.first() {
        let also = match staged.len() {
            0 => String::new(),
            n => format!(
                " and {n} a stopped `simulate --force` staged to replace them (--resume moves \
                 those in first)"
            ),
        };
        return Err(AppError::Failed(format!(
            "--out {0}: the folder already holds {1} frame(s) of an earlier run ({2}, ...){also}; \
             give --force to replace them once the new run is complete, --resume {0} to continue \
             that run, or choose another folder",
            shown(folder),
            earlier.len(),
            shown(Path::new(first.file_name().unwrap_or_default()))
        )));
    }
    if let Some(first) = staged.first() {
        return Err(AppError::Failed(format!(
            "--out {0}: the folder holds {1} frame(s) that a stopped `simulate --force` staged \
             ({2}, ...); --resume {0} moves them in and continues that run; give --force to \
             replace them, or choose another folder",
            shown(folder),
            staged.len(),
            shown(&first.path)
        )));
    }
    Ok(())
}

/// The staged files of killed runs in the folder that are to become
/// frames.
fn frame_leftovers(out: &OutputFolder) -> Vec<Leftover> {
    let mut frames: Vec<Leftover> = out
        .leftovers()
        .into_iter()
        .filter(|l| {
            l.temporary
                .destination
                .as_deref()
                .is_some_and(is_frame_name)
        })
        .collect();
    frames.sort_by_key(|l| l.temporary.destination.as_deref().and_then(frame_step));
    frames
}

/// The first two lines of the regular file at `path`, if it is a frame.
pub fn head(path: &Path) -> Option<Head> {
    if !fs::symlink_metadata(path).is_ok_and(|m| m.is_file()) {
        return None; // a link is no frame simulate wrote
    }
    let file = open_regular(path)?;
    let mut start = vec![0u8; 16 * 1024];
    let read = read_up_to(file, &mut start);
    parse_head(&String::from_utf8_lossy(&start[..read]))
}

/// Is the file at `path` a frame `simulate` wrote (its first line)?
fn is_frame(path: &Path) -> bool {
    head(path).is_some()
}

/// The refusal of a `--resume` folder that is none: missing, or a file.
pub fn not_a_folder(folder: &Path) -> AppError {
    let what = match fs::symlink_metadata(folder) {
        Ok(_) => "this is not a folder",
        Err(_) => "no such folder",
    };
    AppError::Failed(format!("--resume {}: {what}", shown(folder)))
}

/// What is at `path` when it is not a regular file (through links): "a
/// folder", "a FIFO", ...
pub fn not_a_file(path: &Path) -> Option<&'static str> {
    let kind = fs::metadata(path).ok()?.file_type();
    if kind.is_file() {
        return None;
    }
    if kind.is_dir() {
        return Some("a folder");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return Some("a FIFO (a named pipe)");
        }
        if kind.is_char_device() || kind.is_block_device() {
            return Some("a device");
        }
        if kind.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a regular file")
}

/// The entries of `folder` named like frames (none when it does not
/// exist), sorted.
pub fn earlier_frames(folder: &Path) -> Result<Vec<PathBuf>, AppError> {
    let entries = match fs::read_dir(folder) {
        Ok(entries) => entries,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(error) => {
            return Err(FileError::os(folder, "list the folder", error).into());
        }
    };
    let mut frames: Vec<PathBuf> = entries
        .flatten()
        .filter(|entry| entry.file_name().to_str().is_some_and(is_frame_name))
        .map(|entry| entry.path())
        .collect();
    frames.sort();
    Ok(frames)
}
