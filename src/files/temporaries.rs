//! Temporaries: the files (and folders) a command fills before they take
//! their place, named so that no file of a user is ever taken for one.
//!
//! A temporary is named `.NAME.masssprings-PID-START-N.tmp`: the name of
//! what it becomes (cut to 64 bytes), then its *owner*, the process that
//! made it (its process id `PID` and `START`, when that process started,
//! in clock ticks after boot, from `/proc/PID/stat`: together they name
//! one process, also after its id is reused), and a counter `N`. Nobody
//! names a file like that by chance, and the owner is part of the name, so
//! a temporary is removed later only by a run that can prove whose it is:
//! the run that takes over the output folder's lock
//! ([`FolderLock`](super::FolderLock)) finds the owner of the last run that
//! held it in the lock file, a record only this crate writes, and removes
//! that owner's temporaries and no other file, once that process no longer
//! runs ([`remove_temporaries_of`]).
//!
//! Where the processes cannot be looked up (no `/proc`), every owner counts
//! as running and nothing is ever removed.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// The word that marks every temporary (and the lock) of the crate.
const MARK: &str = "masssprings";

/// A process that made temporaries: its id and when it started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Owner {
    /// The process id.
    pub pid: u32,
    /// When it started, in clock ticks after boot (0 where unknown).
    pub start: u64,
}

impl Owner {
    /// This process.
    pub fn this_process() -> Owner {
        static THIS: OnceLock<Owner> = OnceLock::new();
        *THIS.get_or_init(|| {
            let pid = std::process::id();
            Owner {
                pid,
                start: start_ticks(pid).unwrap_or(0),
            }
        })
    }

    /// `masssprings-PID-START`, the owner's part of a temporary's name and
    /// the lock's record.
    pub fn tag(&self) -> String {
        format!("{MARK}-{}-{}", self.pid, self.start)
    }

    /// Parses [`Owner::tag`]'s `PID-START` (without the mark).
    fn parse(text: &str) -> Option<Owner> {
        let (pid, start) = text.split_once('-')?;
        Some(Owner {
            pid: digits(pid)?.parse().ok()?,
            start: digits(start)?.parse().ok()?,
        })
    }

    /// Does this process still run? True where that cannot be told (no
    /// `/proc`), so that nothing of a live process is ever removed.
    pub fn is_running(&self) -> bool {
        if !Path::new("/proc/self/stat").exists() {
            return true;
        }
        match start_ticks(self.pid) {
            None => false, // no such process
            Some(start) => self.start == 0 || start == self.start,
        }
    }
}

/// `s` if it is one or more ASCII digits.
fn digits(s: &str) -> Option<&str> {
    (!s.is_empty() && s.bytes().all(|b| b.is_ascii_digit())).then_some(s)
}

/// When process `pid` started (field 22 of `/proc/PID/stat`, after the
/// command name in parentheses, which may hold spaces and parentheses).
fn start_ticks(pid: u32) -> Option<u64> {
    let stat = fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let after_name = &stat[stat.rfind(')')? + 1..];
    // after the name come field 3 (the state) and on: 22 is the 20th
    after_name.split_whitespace().nth(19)?.parse().ok()
}

/// The longest part of the destination's name kept in a temporary's name,
/// so that the temporary's name stays within the 255 bytes a name may have.
const NAME_BYTES: usize = 64;

/// `.NAME.masssprings-PID-START-N.tmp` beside `path`: unique per process and
/// per call, so concurrent writers never share a temporary.
///
/// # Errors
/// `path` does not end in a name.
pub fn temporary_path(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("`{}` does not name a file", path.display()),
        )
    })?;
    let name = name.to_string_lossy();
    let mut end = name.len().min(NAME_BYTES);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tag = Owner::this_process().tag();
    Ok(path.with_file_name(format!(".{}.{tag}-{unique}.tmp", &name[..end])))
}

/// The owner of the temporary named `name`, if it is one
/// (`.NAME.masssprings-PID-START-N.tmp`).
pub fn temporary_owner(name: &str) -> Option<Owner> {
    let stem = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (_, owned) = stem.rsplit_once(&format!(".{MARK}-"))?;
    let (owner, counter) = owned.rsplit_once('-')?;
    digits(counter)?;
    Owner::parse(owner)
}

/// Removes from `folder` the temporaries of `owner`, a process that no
/// longer runs (nothing when it still does): files, and folders holding
/// only files (a staged result), each named as [`temporary_path`] names
/// them with that owner. Every other file is left alone. Returns how many
/// were removed; one that cannot be removed is skipped.
pub fn remove_temporaries_of(folder: &Path, owner: Owner) -> usize {
    if owner.is_running() {
        return 0;
    }
    let Ok(entries) = fs::read_dir(folder) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        if name.to_str().and_then(temporary_owner) != Some(owner) {
            continue;
        }
        let path = entry.path();
        let gone = match entry.file_type() {
            Ok(kind) if kind.is_dir() => remove_staged_folder(&path),
            Ok(_) => fs::remove_file(&path).is_ok(),
            Err(_) => false,
        };
        removed += usize::from(gone);
    }
    removed
}

/// Removes a staged folder: its files (never a folder inside it, which
/// this crate does not make there), then the folder if that emptied it.
fn remove_staged_folder(folder: &Path) -> bool {
    if let Ok(entries) = fs::read_dir(folder) {
        for entry in entries.flatten() {
            if entry.file_type().is_ok_and(|kind| !kind.is_dir()) {
                let _ = fs::remove_file(entry.path());
            }
        }
    }
    fs::remove_dir(folder).is_ok()
}

/// Makes a new, empty temporary folder beside `path` (named as
/// [`temporary_path`] names a file), where a result is staged before it
/// takes `path`'s place.
///
/// # Errors
/// The folder cannot be made (the folder above is not writable, say).
pub fn temporary_folder(path: &Path) -> io::Result<PathBuf> {
    let folder = temporary_path(path)?;
    fs::create_dir(&folder)?;
    Ok(folder)
}

/// Puts the folder `new` in the place of the folder `old`, and `old`'s
/// content at `new`'s name (to be removed then): at once where the kernel
/// can exchange two names (Linux's `renameat2` with `RENAME_EXCHANGE`),
/// otherwise by three renames, between which `old` is missing for a moment.
///
/// # Errors
/// A rename failed (the two are on different file systems, say); both are
/// then as they were.
pub fn exchange_folders(new: &Path, old: &Path) -> io::Result<()> {
    if exchange(new, old).is_ok() {
        return Ok(());
    }
    let aside = temporary_path(old)?;
    fs::rename(old, &aside)?;
    if let Err(error) = fs::rename(new, old) {
        let _ = fs::rename(&aside, old);
        return Err(error);
    }
    fs::rename(&aside, new)
}

#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    use std::ffi::{c_char, c_int, c_uint, CString};
    use std::os::unix::ffi::OsStrExt;
    /// `AT_FDCWD` and `RENAME_EXCHANGE` of `<fcntl.h>` and `<stdio.h>`.
    const AT_FDCWD: c_int = -100;
    const RENAME_EXCHANGE: c_uint = 2;
    extern "C" {
        fn renameat2(
            old_folder: c_int,
            old: *const c_char,
            new_folder: c_int,
            new: *const c_char,
            flags: c_uint,
        ) -> c_int;
    }
    let c_path = |p: &Path| CString::new(p.as_os_str().as_bytes()).map_err(io::Error::other);
    let (a, b) = (c_path(a)?, c_path(b)?);
    // SAFETY: both are NUL-terminated strings that live across the call;
    // renameat2 only reads them.
    let result = unsafe { renameat2(AT_FDCWD, a.as_ptr(), AT_FDCWD, b.as_ptr(), RENAME_EXCHANGE) };
    if result == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_a: &Path, _b: &Path) -> io::Result<()> {
    Err(io::Error::from(io::ErrorKind::Unsupported))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporaries_are_recognised_by_their_name_and_owner() {
        let owner = Owner {
            pid: 4242,
            start: 77,
        };
        let name = ".frame-000001.obj.masssprings-4242-77-7.tmp";
        assert_eq!(temporary_owner(name), Some(owner));
        assert_eq!(
            temporary_owner(".a.b.masssprings-1-2-0.tmp"),
            Some(Owner { pid: 1, start: 2 })
        );
        for other in [
            "frame-000001.obj",
            ".notes.2024-06.tmp",
            ".frame-000001.obj.4242-7.tmp",
            ".x.masssprings-1-2.tmp",
            ".x.masssprings-1-2-.tmp",
            ".x.masssprings-a-2-3.tmp",
            "x.masssprings-1-2-3.tmp",
            ".x.masssprings-1-2-3.tmpx",
        ] {
            assert_eq!(temporary_owner(other), None, "{other}");
        }
    }

    #[test]
    fn a_temporary_names_its_destination_its_owner_and_stays_short() {
        let path = temporary_path(Path::new("out/frame-000001.obj")).unwrap();
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(name.starts_with(".frame-000001.obj.masssprings-"), "{name}");
        assert_eq!(temporary_owner(name), Some(Owner::this_process()));
        assert_eq!(path.parent(), Some(Path::new("out")));
        let long = "é".repeat(120);
        let path = temporary_path(Path::new(&long)).unwrap();
        assert!(path.as_os_str().len() < 120, "{}", path.display());
    }

    #[test]
    fn this_process_runs_and_a_finished_one_does_not() {
        assert!(Owner::this_process().is_running());
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let gone = Owner { pid, start: 1 };
        assert!(!gone.is_running());
    }
}
