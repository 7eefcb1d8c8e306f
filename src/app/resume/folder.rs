//! The folder `simulate --out DIR` (or `--resume DIR`) writes its frames
//! into, held for the whole run:
//!
//! * **one run at a time**: the folder's lock
//!   ([`FolderLock`](masssprings::files::FolderLock)) is taken before
//!   anything is read or written there, so a second run into the same
//!   folder, or a `--resume` beside a live run, is refused instead of
//!   mixing its frames with the first one's; the lock also removes the
//!   temporaries of a killed run;
//! * **frames of an earlier run** (`frame-*.obj`) are refused, unless
//!   `--force`: then the new frames are written into a staging folder
//!   inside `DIR` and take the old ones' place only once the run is
//!   complete ([`FrameFolder::commit`]); a run that fails or is killed
//!   leaves the old frames whole (its staging folder is removed, or, after
//!   a kill, by the next run);
//! * **the material and the texture copy** (`NAME.mtl`, the texture's
//!   name) are replaced only when they are this command's: a material
//!   whose first line is the one `simulate` writes, a copy holding the
//!   texture's bytes; anything else there is refused unless `--force`
//!   (`file_plan`).

use super::frames::{frame_step, is_frame_name};
use crate::app::error::AppError;
use crate::app::file_plan::{holds_bytes, occupied, refuse_foreign, starts_with_line};
use masssprings::files::{read_bytes, same_file, temporary_folder, FolderLock};
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

/// The locked folder of a run's frames.
#[derive(Debug)]
pub struct FrameFolder {
    lock: FolderLock,
    /// Where the new frames go until [`FrameFolder::commit`], when they
    /// replace the frames of an earlier run.
    staging: Option<PathBuf>,
}

impl FrameFolder {
    /// Locks `folder` (made if missing) and checks what is in it for a run
    /// of `how`: frames of another run and files in the way of `extras`.
    ///
    /// # Errors
    /// Another run holds the folder; a file named like a frame that is not
    /// a regular file; frames of another run or files not written by
    /// `simulate` in the way, without `--force`.
    pub fn open(folder: &Path, how: Use, extras: &Extras) -> Result<FrameFolder, AppError> {
        if how == Use::Resume && !folder.is_dir() {
            return Err(not_a_folder(folder));
        }
        let lock = FolderLock::acquire(folder, "simulate")?;
        let force = how == (Use::Fresh { force: true });
        refuse_foreign(
            &format!("--out {}", folder.display()),
            "simulate",
            &foreign_extras(extras),
            force,
        )?;
        let earlier = earlier_frames(folder)?;
        let odd = earlier
            .iter()
            .find_map(|path| Some((path, not_a_file(path)?)));
        if let (Use::Fresh { .. }, Some((path, kind))) = (how, odd) {
            return Err(AppError::Failed(format!(
                "{}: this is {kind}, named like a frame; move it away first",
                path.display()
            )));
        }
        let staging = match (how, earlier.first()) {
            (Use::Fresh { force: false }, Some(first)) => {
                return Err(AppError::Failed(format!(
                    "--out {0}: the folder already holds {1} frame(s) of an earlier run ({2}, \
                     ...); give --force to replace them once the new run is complete, \
                     --resume {0} to continue that run, or choose another folder",
                    folder.display(),
                    earlier.len(),
                    first.file_name().unwrap_or_default().to_string_lossy()
                )))
            }
            (Use::Fresh { force: true }, Some(_)) => Some(
                temporary_folder(&folder.join("frames"))
                    .map_err(|e| AppError::Failed(format!("{}: {e}", folder.display())))?,
            ),
            _ => None,
        };
        Ok(FrameFolder { lock, staging })
    }

    /// The folder itself.
    pub fn folder(&self) -> &Path {
        self.lock.folder()
    }

    /// Where the frames go now: the folder, or the staging folder while
    /// they are to replace an earlier run's.
    pub fn frames(&self) -> &Path {
        self.staging.as_deref().unwrap_or(self.folder())
    }

    /// The run is complete: its staged frames replace the earlier run's
    /// (those are removed, then the new ones moved in).
    ///
    /// # Errors
    /// A frame could not be removed or moved (the message names it).
    pub fn commit(mut self) -> Result<(), AppError> {
        let Some(staging) = self.staging.clone() else {
            return Ok(());
        };
        let folder = self.folder().to_path_buf();
        let failed =
            |path: &Path, e: std::io::Error| AppError::Failed(format!("{}: {e}", path.display()));
        for frame in earlier_frames(&folder)? {
            fs::remove_file(&frame).map_err(|e| failed(&frame, e))?;
        }
        let mut staged: Vec<PathBuf> = fs::read_dir(&staging)
            .map_err(|e| failed(&staging, e))?
            .flatten()
            .map(|entry| entry.path())
            .filter(|path| {
                path.file_name()
                    .and_then(|n| n.to_str())
                    .and_then(frame_step)
                    .is_some()
            })
            .collect();
        staged.sort();
        for frame in staged {
            let name = frame.file_name().unwrap_or_default();
            fs::rename(&frame, folder.join(name)).map_err(|e| failed(&frame, e))?;
        }
        fs::remove_dir(&staging).map_err(|e| failed(&staging, e))?;
        self.staging = None;
        Ok(())
    }
}

impl Drop for FrameFolder {
    fn drop(&mut self) {
        // not committed: the run failed, and the earlier frames stay
        if let Some(staging) = self.staging.take() {
            let _ = fs::remove_dir_all(staging);
        }
    }
}

/// The files of `extras` in the way that `simulate` did not write.
fn foreign_extras(extras: &Extras) -> Vec<PathBuf> {
    let mut foreign = Vec::new();
    if let Some((material, first_line)) = &extras.material {
        if occupied(material) && !starts_with_line(material, first_line) {
            foreign.push(material.clone());
        }
    }
    if let Some((texture, copy)) = &extras.texture {
        let ours =
            || same_file(texture, copy) || read_bytes(texture).is_ok_and(|b| holds_bytes(copy, &b));
        if occupied(copy) && !ours() {
            foreign.push(copy.clone());
        }
    }
    foreign
}

/// The refusal of a `--resume` folder that is none: missing, or a file.
pub fn not_a_folder(folder: &Path) -> AppError {
    let what = match fs::symlink_metadata(folder) {
        Ok(_) => "this is not a folder",
        Err(_) => "no such folder",
    };
    AppError::Failed(format!("--resume {}: {what}", folder.display()))
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
        Err(error) => return Err(AppError::Failed(format!("{}: {error}", folder.display()))),
    };
    let mut frames: Vec<PathBuf> = entries
        .flatten()
        .filter(|entry| entry.file_name().to_str().is_some_and(is_frame_name))
        .map(|entry| entry.path())
        .collect();
    frames.sort();
    Ok(frames)
}
