//! Writing outputs: the one code path by which the crate writes, replaces
//! or removes a file it is asked to produce, and the one rule it keeps.
//!
//! 1. **A file is replaced by rename, one at a time**: its new content is
//!    written to a temporary in the same folder (`temporaries`), flushed
//!    to disk, and renamed over the file's name; the folder is synced
//!    after, so that the rename survives a power cut. A reader sees the old
//!    file or the new one, never a mixture, and a failure leaves the old
//!    one as it was.
//! 2. **A folder is never replaced, exchanged or removed**, unless the
//!    command made it in this run and left nothing in it
//!    ([`FolderLock`]). Files are written into the folder the user named,
//!    in place: its mode, its owner, a shell open in it, a mount on it and
//!    every other file in it stay as they were.
//! 3. **An old file is removed only after everything that replaces it is in
//!    place.** A result of many files (a trace, the frames of a run that
//!    replaces another) is *staged* first: each file written whole beside
//!    its place (`.NAME.masssprings-PID-START-N.staged`), then moved in by
//!    rename ([`OutputFolder::place_all`]), and only then are the old files
//!    that nothing replaced removed. A staged file survives a kill; the next
//!    run of the command finds it ([`OutputFolder::leftovers`]) and moves it
//!    in, or removes it as its own old file, or puts it back.
//! 4. **A file the command did not write is never removed, whenever it
//!    appeared.** What a name holds is checked at the moment it is
//!    replaced, not from an earlier look at the folder ([`Expect`]): a
//!    name that was free must still be free (Linux's `renameat2` with
//!    `RENAME_NOREPLACE`, or a hard link, which fails on an existing
//!    name); a name that held the command's own file is *exchanged* with
//!    the new file in one step (`RENAME_EXCHANGE`) and what came out is
//!    checked, then removed if it is the command's and exchanged back if
//!    not. A file is removed the same way: renamed aside, checked, and
//!    removed or renamed back ([`OutputFolder::remove_own`]). Only with
//!    `--force` does a command replace, at the names it writes, the files
//!    that were there when it started that are not its own.
//!
//! Where the file system cannot rename with these flags (some network and
//! user-space file systems), the check is made just before a plain rename:
//! the same rule, with a moment between the two.
//!
//! A named output (`-o picture.png`) is [`write_file`]: rule 1, through a
//! symbolic link to its target, and written into as it is when it is a
//! FIFO or a device. A folder of outputs with names the user did not type
//! (`simulate --out`, `trace -o`, `generate --out`) is an
//! [`OutputFolder`]: rules 1 to 4, under the folder's lock.
//!
//! Every error names the operation and the file it concerns
//! (`frames/frame-000003.obj: cannot replace it by renaming
//! .frame-000003.obj.masssprings-…staged over it: Operation not permitted`).
//! Paths are used as given: a relative path stays relative, so that a
//! working folder deeper than the 4,096 bytes an absolute path may have
//! still works.

use super::plan::follow_links;
use super::temporaries::{is_reserved, staged_leftovers, temporary_path, Kind, Leftover, Owner};
use super::{is_fifo, patient, shown, FileError, FolderLock};
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes what `write` produces to `path`, a file the user named: a
/// regular file (or nothing yet) is created or replaced all or nothing,
/// through a symbolic link to its target, keeping its permissions; a FIFO
/// or a device is written to directly (a FIFO waits at most
/// [`patient::PATIENCE`] for its reader); `-` is standard output.
///
/// A regular file is filled as a temporary in the same folder, flushed to
/// disk, renamed to `path`, and the folder synced; if `write` or any step
/// fails, the temporary is removed and `path` is left as it was.
///
/// ```no_run
/// # use masssprings::files::write_file;
/// # use std::io::Write;
/// write_file("hello.txt".as_ref(), |out| writeln!(out, "hello"))?;
/// # Ok::<(), masssprings::files::FileError>(())
/// ```
///
/// # Errors
/// The first I/O error (from `write`, creating, syncing or renaming), with
/// the operation and the path in the message; a folder at `path` is
/// refused.
pub fn write_file(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), FileError> {
    if path == Path::new("-") {
        let mut out = BufWriter::new(io::stdout().lock());
        return write(&mut out)
            .and_then(|()| out.flush())
            .map_err(|e| FileError::os(path, "write to standard output", e));
    }
    match fs::metadata(path) {
        Ok(metadata) if metadata.is_dir() => Err(FileError::unwritable(
            path,
            io::Error::new(
                io::ErrorKind::InvalidInput,
                "this is a folder; name a file in it",
            ),
        )),
        Ok(metadata) if !metadata.is_file() => write_directly(path, is_fifo(&metadata), write)
            .map_err(|e| FileError::unwritable(path, e)),
        // A regular file, or nothing (or a link to nothing) yet: replaced
        // at the end of its links, with the permissions it had.
        Ok(_) | Err(_) => {
            let target = follow_links(path).map_err(|e| FileError::os(path, "follow it", e))?;
            let permissions = fs::metadata(&target).ok().map(|m| m.permissions());
            let temporary = fill(&target, Kind::Partial, permissions, write)?;
            if let Err(error) = fs::rename(&temporary, &target) {
                let _ = fs::remove_file(&temporary);
                return Err(FileError::os(&target, renaming_over(&temporary), error));
            }
            sync_folder(&target)
        }
    }
}

/// Writes into a FIFO or a device as it is: no temporary, no rename.
fn write_directly(
    path: &Path,
    fifo: bool,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let file: Box<dyn Write> = if fifo {
        Box::new(patient::PatientWriter::open(path)?)
    } else {
        Box::new(fs::OpenOptions::new().write(true).open(path)?)
    };
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    out.flush()
}

/// A new temporary of `kind` beside `destination`, filled by `write`,
/// given `permissions` and flushed to disk; removed again on any error.
fn fill(
    destination: &Path,
    kind: Kind,
    permissions: Option<fs::Permissions>,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<PathBuf, FileError> {
    let temporary = temporary_path(destination, kind)
        .map_err(|e| FileError::os(destination, "name a temporary for it", e))?;
    let file = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temporary)
        .map_err(|e| {
            let name = temporary.file_name().map(Path::new).unwrap_or(&temporary);
            let operation = format!("create the temporary {} beside it", shown(name));
            FileError::os(destination, operation, e)
        })?;
    let filled = (|| {
        let mut out = BufWriter::new(file);
        write(&mut out)?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        if let Some(permissions) = permissions {
            file.set_permissions(permissions)?;
        }
        file.sync_all()
    })();
    match filled {
        Ok(()) => Ok(temporary),
        Err(error) => {
            let _ = fs::remove_file(&temporary);
            Err(FileError::os(destination, "write the file", error))
        }
    }
}

/// "replace it by renaming .X.masssprings-….tmp over it": the operation
/// in a message about the file replaced.
fn renaming_over(source: &Path) -> String {
    let name = source.file_name().map(Path::new).unwrap_or(source);
    format!("replace it by renaming {} over it", shown(name))
}

/// Syncs the folder that holds `path`, so that a rename in it is on disk.
fn sync_folder(path: &Path) -> Result<(), FileError> {
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => sync(folder),
        _ => sync(Path::new(".")),
    }
}

/// Syncs `folder`. A file system that cannot sync a folder (it says so
/// with `EINVAL`) is left as it is.
fn sync(folder: &Path) -> Result<(), FileError> {
    let synced = fs::File::open(folder).and_then(|f| f.sync_all());
    match synced {
        Err(error) if error.kind() != io::ErrorKind::InvalidInput => {
            Err(FileError::os(folder, "sync the folder", error))
        }
        _ => Ok(()),
    }
}

/// What a name in an [`OutputFolder`] may hold when a file is placed
/// there, checked at that moment.
#[derive(Clone, Copy)]
pub enum Expect<'a> {
    /// Nothing: a file that appeared there since is kept and the placing
    /// refused.
    Nothing,
    /// Nothing, or a regular file the check says is the command's own
    /// (an earlier run's): anything else there is kept and the placing
    /// refused.
    Own(&'a dyn Fn(&Path) -> bool),
    /// Anything but a folder (`--force`, for a name the user was told about
    /// when the command started): it is replaced; a link, itself.
    Any,
}

/// A folder a command writes files into by names the user did not type,
/// held under its lock for the run (rules 1 to 4 of the module header).
#[derive(Debug)]
pub struct OutputFolder {
    lock: FolderLock,
    command: String,
}

/// An old file moved out of its place by [`OutputFolder::place_all`],
/// kept at a staged name until [`OutputFolder::discard`] removes it.
#[derive(Debug)]
#[must_use = "an old file held aside stays until it is discarded"]
pub struct Held(Vec<PathBuf>);

impl Held {
    /// Nothing held.
    pub fn none() -> Held {
        Held(Vec::new())
    }

    /// Adds what `other` holds.
    pub fn join(mut self, other: Held) -> Held {
        self.0.extend(other.0);
        self
    }
}

impl OutputFolder {
    /// Locks `folder` (made if missing) for `command` (`FolderLock`: one
    /// run at a time; a killed run's partial files removed).
    ///
    /// # Errors
    /// The lock's: another run holds it, or the folder cannot be made.
    pub fn open(folder: &Path, command: &str) -> Result<OutputFolder, FileError> {
        Ok(OutputFolder {
            lock: FolderLock::acquire(folder, command)?,
            command: command.to_string(),
        })
    }

    /// The folder, as given.
    pub fn folder(&self) -> &Path {
        self.lock.folder()
    }

    /// The path of `name` in the folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.folder().join(name)
    }

    /// Writes `name` now: a temporary filled by `write`, then placed as
    /// `expect` allows.
    ///
    /// # Errors
    /// Writing failed (the temporary is removed), or the name holds what
    /// `expect` does not allow (kept).
    pub fn write(
        &self,
        name: &str,
        expect: Expect,
        write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<(), FileError> {
        let destination = self.checked_path(name)?;
        let temporary = fill(&destination, Kind::Partial, None, write)?;
        let placed = self.place_all(&[(temporary.clone(), name, expect)]);
        if placed.is_err() {
            let _ = fs::remove_file(&temporary);
        }
        self.discard(placed?)
    }

    /// Writes `name` whole into a staged file beside its place, to be
    /// moved in by [`OutputFolder::place_all`]; returns the staged file.
    /// Written as a partial file first, so that a staged file is always
    /// complete, also after a kill.
    ///
    /// # Errors
    /// Writing failed (nothing is left).
    pub fn stage(
        &self,
        name: &str,
        write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<PathBuf, FileError> {
        let destination = self.checked_path(name)?;
        let partial = fill(&destination, Kind::Partial, None, write)?;
        let staged = temporary_path(&destination, Kind::Staged)
            .map_err(|e| FileError::os(&destination, "name a temporary for it", e))?;
        if let Err(error) = rename_exclusively(&partial, &staged) {
            let _ = fs::remove_file(&partial);
            return Err(FileError::os(
                &partial,
                "rename it to its staged name",
                error,
            ));
        }
        Ok(staged)
    }

    /// The path of `name`, refused when it is one the crate keeps for
    /// itself or not a plain name.
    fn checked_path(&self, name: &str) -> Result<PathBuf, FileError> {
        let plain = Path::new(name).file_name() == Some(name.as_ref());
        if is_reserved(name) || !plain {
            return Err(FileError::invalid(format!(
                "{name} is not a name masssprings writes into a folder (a lock's or a temporary's \
                 name, or not a plain name)"
            ))
            .in_file(&self.path(name)));
        }
        Ok(self.path(name))
    }

    /// Moves each file `(source, name, expect)` to `name`, in order, each
    /// by one rename (module header, rule 4), and syncs the folder. The old
    /// files they replace are held at the sources' names (returned), to be
    /// removed by [`OutputFolder::discard`] once the caller has all it
    /// needs in place.
    ///
    /// # Errors
    /// The first file that cannot be placed: a name holds what its
    /// `expect` does not allow, or the rename failed. The files placed
    /// before it are put back first (where the file system exchanges
    /// names; elsewhere they stay placed), so the folder is as it was and
    /// the sources hold the new files again.
    pub fn place_all(&self, files: &[(PathBuf, &str, Expect)]) -> Result<Held, FileError> {
        let mut done: Vec<(&Path, PathBuf, Moved)> = Vec::new();
        for (source, name, expect) in files {
            let destination = self.path(name);
            match self.place(source, &destination, *expect) {
                Ok(moved) => done.push((source, destination, moved)),
                Err(error) => {
                    for (source, destination, moved) in done.iter().rev() {
                        undo(source, destination, *moved);
                    }
                    return Err(error);
                }
            }
        }
        sync(self.folder())?;
        let held = done
            .into_iter()
            .filter(|(_, _, moved)| *moved == Moved::Exchanged)
            .map(|(source, _, _)| source.to_path_buf());
        Ok(Held(held.collect()))
    }

    /// Removes the old files `held` (after [`OutputFolder::place_all`]).
    ///
    /// # Errors
    /// One could not be removed (it stays, at its staged name).
    pub fn discard(&self, held: Held) -> Result<(), FileError> {
        for old in held.0 {
            fs::remove_file(&old).map_err(|e| FileError::os(&old, "remove it", e))?;
        }
        sync(self.folder())
    }

    /// Removes this run's own staged file `staged` (a run that failed).
    pub fn discard_staged(&self, staged: &Path) {
        let name = staged.file_name().and_then(|n| n.to_str());
        let ours = name
            .and_then(super::temporary)
            .is_some_and(|t| t.owner == Owner::this_process());
        if ours {
            let _ = fs::remove_file(staged);
        }
    }

    /// Moves `source` to `destination` as `expect` allows: one rename.
    fn place(&self, source: &Path, destination: &Path, expect: Expect) -> Result<Moved, FileError> {
        let replace_failed = |error| FileError::os(destination, renaming_over(source), error);
        let occupied = fs::symlink_metadata(destination).is_ok();
        if let (Expect::Nothing, _) | (Expect::Own(_), false) = (expect, occupied) {
            return match rename_exclusively(source, destination) {
                Ok(()) => Ok(Moved::Renamed),
                Err(error) if error.kind() == io::ErrorKind::AlreadyExists => {
                    Err(self.appeared(destination))
                }
                Err(error) => Err(replace_failed(error)),
            };
        }
        match exchange(source, destination) {
            Ok(()) => {
                // what came out of `destination` is now at `source`
                let out = fs::symlink_metadata(source);
                let fits = match expect {
                    Expect::Own(own) => out.is_ok_and(|m| m.is_file()) && own(source),
                    _ => out.is_ok_and(|m| !m.is_dir()),
                };
                if fits {
                    return Ok(Moved::Exchanged);
                }
                undo(source, destination, Moved::Exchanged);
                Err(self.not_its_own(destination))
            }
            Err(error) if error.kind() == io::ErrorKind::NotFound => {
                // the old file went meanwhile: its place is free
                self.place(source, destination, Expect::Nothing)
            }
            Err(error) if !unsupported(&error) => Err(replace_failed(error)),
            Err(_) => {
                let fits = match expect {
                    Expect::Own(own) => fs::symlink_metadata(destination)
                        .is_ok_and(|m| m.is_file() && own(destination)),
                    _ => !destination.is_dir(),
                };
                if !fits {
                    return Err(self.not_its_own(destination));
                }
                fs::rename(source, destination).map_err(replace_failed)?;
                Ok(Moved::Replaced)
            }
        }
    }

    fn appeared(&self, destination: &Path) -> FileError {
        FileError::invalid(format!(
            "a file appeared here while masssprings {} ran (another program wrote it?); it is \
             kept, not replaced",
            self.command
        ))
        .in_file(destination)
    }

    fn not_its_own(&self, destination: &Path) -> FileError {
        FileError::invalid(format!(
            "this is not a file masssprings {} wrote (it changed while the run went on, or is a \
             folder); it is kept, not replaced",
            self.command
        ))
        .in_file(destination)
    }

    /// Removes the file `name` if `own` says it is the command's: it is
    /// renamed aside first, checked there, and removed, or renamed back
    /// when it is not (module header, rule 4). Returns whether it was
    /// removed (`false`: nothing there, or kept).
    ///
    /// # Errors
    /// The rename or the removal failed; or the file was not the command's
    /// and another took its name meanwhile: it is kept at the staged name
    /// the error gives.
    pub fn remove_own(&self, name: &str, own: &dyn Fn(&Path) -> bool) -> Result<bool, FileError> {
        let path = self.path(name);
        if !fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
            return Ok(false);
        }
        let aside = temporary_path(&path, Kind::Staged)
            .map_err(|e| FileError::os(&path, "name a temporary for it", e))?;
        match rename_exclusively(&path, &aside) {
            Ok(()) => {}
            Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(false),
            Err(error) => return Err(FileError::os(&path, "move it aside to remove it", error)),
        }
        if fs::symlink_metadata(&aside).is_ok_and(|m| m.is_file()) && own(&aside) {
            fs::remove_file(&aside).map_err(|e| FileError::os(&aside, "remove it", e))?;
            sync_folder(&path)?;
            return Ok(true);
        }
        self.put_back(&aside, &path)?;
        Ok(false)
    }

    /// Renames `aside` back to `path`, unless a file took that name.
    fn put_back(&self, aside: &Path, path: &Path) -> Result<(), FileError> {
        rename_exclusively(aside, path).map_err(|error| {
            FileError::os(
                path,
                format!(
                    "put back the file masssprings {} had moved aside (it is kept as {})",
                    self.command,
                    shown(aside)
                ),
                error,
            )
        })
    }

    /// The staged files left in the folder by runs that no longer run
    /// (killed while they staged, placed or removed files).
    pub fn leftovers(&self) -> Vec<Leftover> {
        staged_leftovers(self.folder())
    }

    /// Settles `leftover`: removed when `own` says it is the command's
    /// (an old file set aside, or a result this run replaces), otherwise
    /// renamed back to the name it came from, when that name is free.
    /// Returns where it is now (`None`: removed).
    pub fn settle(&self, leftover: &Leftover, own: &dyn Fn(&Path) -> bool) -> Option<PathBuf> {
        if own(&leftover.path) && fs::remove_file(&leftover.path).is_ok() {
            return None;
        }
        let back = leftover
            .temporary
            .destination
            .as_deref()
            .map(|name| self.path(name));
        match back {
            Some(back) if self.put_back(&leftover.path, &back).is_ok() => Some(back),
            _ => Some(leftover.path.clone()),
        }
    }
}

/// How a file was moved in: by a rename to a free name, by exchanging it
/// with the old file (now at the source's name), or by a plain rename over
/// the old file (where names cannot be exchanged: the old file is gone).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Moved {
    Renamed,
    Exchanged,
    Replaced,
}

/// Puts a placed file back: exchanged back, or renamed back to `source`;
/// one that replaced an old file it could not hold stays placed (moving it
/// back would leave the name empty).
fn undo(source: &Path, destination: &Path, moved: Moved) {
    let _ = match moved {
        Moved::Exchanged => exchange(source, destination),
        Moved::Renamed => rename_exclusively(destination, source),
        Moved::Replaced => Ok(()),
    };
}

/// Does this error say the file system cannot rename with flags?
fn unsupported(error: &io::Error) -> bool {
    matches!(
        error.kind(),
        io::ErrorKind::InvalidInput | io::ErrorKind::Unsupported
    ) || error.raw_os_error() == Some(38) // ENOSYS
}

/// Renames `from` to `to` unless `to` exists (then `AlreadyExists`):
/// `RENAME_NOREPLACE`, or where that is not there, a hard link (which
/// fails on an existing name) and the removal of `from`, or last a check
/// and a plain rename.
fn rename_exclusively(from: &Path, to: &Path) -> io::Result<()> {
    match renameat2(from, to, RENAME_NOREPLACE) {
        Err(error) if unsupported(&error) => {}
        other => return other,
    }
    match fs::hard_link(from, to) {
        Ok(()) => return fs::remove_file(from),
        Err(error) if error.kind() == io::ErrorKind::AlreadyExists => return Err(error),
        Err(_) => {}
    }
    if fs::symlink_metadata(to).is_ok() {
        return Err(io::Error::from(io::ErrorKind::AlreadyExists));
    }
    fs::rename(from, to)
}

/// Exchanges the names `a` and `b` in one step (`RENAME_EXCHANGE`).
fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    renameat2(a, b, RENAME_EXCHANGE)
}

/// `RENAME_NOREPLACE` and `RENAME_EXCHANGE` of `<linux/fs.h>`.
const RENAME_NOREPLACE: u32 = 1;
const RENAME_EXCHANGE: u32 = 2;

#[cfg(target_os = "linux")]
fn renameat2(from: &Path, to: &Path, flags: u32) -> io::Result<()> {
    use std::ffi::{c_char, c_int, c_uint, CString};
    use std::os::unix::ffi::OsStrExt;
    /// `AT_FDCWD` of `<fcntl.h>`: paths relative to the working folder.
    const AT_FDCWD: c_int = -100;
    extern "C" {
        fn renameat2(
            old_folder: c_int,
            old: *const c_char,
            new_folder: c_int,
            new: *const c_char,
            flags: c_uint,
        ) -> c_int;
    }
    let c_path = |p: &Path| {
        CString::new(p.as_os_str().as_bytes())
            .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "a NUL byte in a path"))
    };
    let (from, to) = (c_path(from)?, c_path(to)?);
    // SAFETY: both are NUL-terminated strings that live across the call;
    // renameat2 only reads them.
    let result = unsafe { renameat2(AT_FDCWD, from.as_ptr(), AT_FDCWD, to.as_ptr(), flags) };
    if result == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn renameat2(_from: &Path, _to: &Path, _flags: u32) -> io::Result<()> {
    Err(io::Error::from(io::ErrorKind::Unsupported))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let folder = std::env::temp_dir().join(format!(
            "masssprings-outputs-test-{}-{name}",
            std::process::id()
        ));
        let _ = fs::remove_dir_all(&folder);
        folder
    }

    fn names(folder: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(folder)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    fn ours(path: &Path) -> bool {
        fs::read_to_string(path).is_ok_and(|text| text.starts_with("ours"))
    }

    #[test]
    fn a_name_that_was_free_is_never_taken_from_a_file_that_appeared() {
        let folder = folder("appeared");
        let out = OutputFolder::open(&folder, "test").unwrap();
        out.write("a", Expect::Nothing, |w| w.write_all(b"ours 1"))
            .unwrap();
        let refused = out.write("a", Expect::Nothing, |w| w.write_all(b"ours 2"));
        assert!(refused.unwrap_err().to_string().contains("appeared"));
        assert_eq!(fs::read_to_string(folder.join("a")).unwrap(), "ours 1");
        assert_eq!(
            names(&folder),
            [".masssprings-lock", "a"],
            "no temporary left"
        );
        drop(out);
        fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn an_own_file_is_replaced_and_a_users_is_kept() {
        let folder = folder("own");
        let out = OutputFolder::open(&folder, "test").unwrap();
        fs::write(folder.join("a"), "ours, old").unwrap();
        fs::write(folder.join("b"), "the user's").unwrap();
        let a = out.stage("a", |w| w.write_all(b"ours, new")).unwrap();
        let b = out.stage("b", |w| w.write_all(b"ours, new")).unwrap();
        let files = [
            (a.clone(), "a", Expect::Own(&ours)),
            (b.clone(), "b", Expect::Own(&ours)),
        ];
        let refused = out.place_all(&files).unwrap_err().to_string();
        assert!(
            refused.contains("not a file masssprings test wrote"),
            "{refused}"
        );
        assert_eq!(
            fs::read_to_string(folder.join("a")).unwrap(),
            "ours, old",
            "put back"
        );
        assert_eq!(fs::read_to_string(folder.join("b")).unwrap(), "the user's");
        assert_eq!(fs::read_to_string(&a).unwrap(), "ours, new");
        let held = out.place_all(&files[..1]).unwrap();
        assert_eq!(fs::read_to_string(folder.join("a")).unwrap(), "ours, new");
        out.discard(held).unwrap();
        assert!(!a.exists());
        // forced: the user's file goes, a link is replaced itself
        fs::write(folder.join("target"), "keep").unwrap();
        std::os::unix::fs::symlink("target", folder.join("c")).unwrap();
        let c = out.stage("c", |w| w.write_all(b"ours")).unwrap();
        let held = out
            .place_all(&[(b.clone(), "b", Expect::Any), (c, "c", Expect::Any)])
            .unwrap();
        out.discard(held).unwrap();
        assert_eq!(fs::read_to_string(folder.join("b")).unwrap(), "ours, new");
        assert!(fs::symlink_metadata(folder.join("c")).unwrap().is_file());
        assert_eq!(fs::read_to_string(folder.join("target")).unwrap(), "keep");
        assert_eq!(
            names(&folder),
            [".masssprings-lock", "a", "b", "c", "target"]
        );
        drop(out);
        fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn only_own_files_are_removed_and_others_put_back() {
        let folder = folder("remove");
        let out = OutputFolder::open(&folder, "test").unwrap();
        fs::write(folder.join("a"), "ours").unwrap();
        fs::write(folder.join("b"), "the user's").unwrap();
        assert!(out.remove_own("a", &ours).unwrap());
        assert!(!out.remove_own("b", &ours).unwrap());
        assert!(!out.remove_own("c", &ours).unwrap(), "nothing there");
        assert_eq!(names(&folder), [".masssprings-lock", "b"]);
        assert_eq!(fs::read_to_string(folder.join("b")).unwrap(), "the user's");
        drop(out);
        fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn a_dead_runs_staged_files_are_settled_by_content() {
        let folder = folder("leftovers");
        fs::create_dir_all(&folder).unwrap();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let theirs = format!(".a.masssprings-{pid}-1-0.staged");
        let users = format!(".b.masssprings-{pid}-1-1.staged");
        fs::write(folder.join(&theirs), "ours").unwrap();
        fs::write(folder.join(&users), "the user's, set aside").unwrap();
        let out = OutputFolder::open(&folder, "test").unwrap();
        let leftovers = out.leftovers();
        assert_eq!(leftovers.len(), 2);
        let now: Vec<Option<PathBuf>> = leftovers.iter().map(|l| out.settle(l, &ours)).collect();
        assert_eq!(now, [None, Some(folder.join("b"))]);
        assert_eq!(names(&folder), [".masssprings-lock", "b"]);
        drop(out);
        fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn a_named_output_is_replaced_through_its_link_and_keeps_its_mode() {
        use std::os::unix::fs::PermissionsExt;
        let folder = folder("named");
        fs::create_dir_all(&folder).unwrap();
        let target = folder.join("target.txt");
        fs::write(&target, "old").unwrap();
        fs::set_permissions(&target, fs::Permissions::from_mode(0o600)).unwrap();
        std::os::unix::fs::symlink("target.txt", folder.join("link.txt")).unwrap();
        write_file(&folder.join("link.txt"), |w| w.write_all(b"new")).unwrap();
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
        let mode = fs::metadata(&target).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600);
        assert!(fs::symlink_metadata(folder.join("link.txt"))
            .unwrap()
            .file_type()
            .is_symlink());
        fs::remove_dir_all(&folder).unwrap();
    }
}
