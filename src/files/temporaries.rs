//! Temporaries: the files a command fills before they take their place,
//! named so that no file of a user is ever taken for one.
//!
//! A temporary is named `.NAME.masssprings-PID-START-N.KIND`: the name of
//! the file it becomes (cut to 64 bytes), then its *owner*, the process
//! that made it (its process id `PID` and `START`, when that process
//! started, in clock ticks after boot, from `/proc/PID/stat`: together
//! they name one process, also after its id is reused), a counter `N`, and
//! what it holds:
//!
//! * `.tmp`, **partial**: a file being written. Until it is renamed it is
//!   never anything but what its owner was writing, so once the owner is
//!   gone it is rubbish. It is removed only by a run that can prove whose
//!   it is: the run that takes over the output folder's lock
//!   ([`FolderLock`](super::FolderLock)) finds the owner of the last run
//!   that held it in the lock file, a record only this crate writes, and
//!   removes that owner's partial files and no other file, once that
//!   process no longer runs ([`remove_partials_of`]).
//! * `.staged`, **complete**: a whole file, flushed to disk, waiting to
//!   take its place (or an old file set aside while it is replaced or
//!   removed). A kill does not make it rubbish: nothing here removes one on
//!   its name; the command that finds one left by a process that no longer
//!   runs ([`staged_leftovers`]) reads it and moves it in, removes it as
//!   its own old file, or puts it back where it was.
//!
//! Nobody names a file like that by chance. Where the processes cannot be
//! looked up (no `/proc`), every owner counts as running and nothing is
//! ever removed or taken over.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// The word that marks every temporary (and the lock) of the crate.
const MARK: &str = "masssprings";

/// A process that made temporaries: its id and when it started.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
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

    /// The owner whose [`Owner::tag`] is `tag`.
    pub fn from_tag(tag: &str) -> Option<Owner> {
        Owner::parse(tag.strip_prefix(MARK)?.strip_prefix('-')?)
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

/// What a temporary holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `.tmp`: a file being written (rubbish once its owner is gone).
    Partial,
    /// `.staged`: a whole file waiting to take its place, or an old one
    /// set aside.
    Staged,
}

impl Kind {
    fn suffix(self) -> &'static str {
        match self {
            Kind::Partial => "tmp",
            Kind::Staged => "staged",
        }
    }
}

/// The longest part of the destination's name kept in a temporary's name,
/// so that the temporary's name stays within the 255 bytes a name may have.
const NAME_BYTES: usize = 64;

/// `.NAME.masssprings-PID-START-N.KIND` beside `path`: unique per process
/// and per call, so concurrent writers never share a temporary.
///
/// # Errors
/// `path` does not end in a name.
pub fn temporary_path(path: &Path, kind: Kind) -> io::Result<PathBuf> {
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
    let suffix = kind.suffix();
    Ok(path.with_file_name(format!(".{}.{tag}-{unique}.{suffix}", &name[..end])))
}

/// A temporary read from its name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Temporary {
    /// The process that made it.
    pub owner: Owner,
    pub kind: Kind,
    /// The name of the file it becomes (or was set aside from), when its
    /// name holds the whole of it (names of 64 bytes or more are cut).
    pub destination: Option<String>,
}

/// What the file named `name` is, if it is a temporary
/// (`.NAME.masssprings-PID-START-N.tmp` or `.staged`).
pub fn temporary(name: &str) -> Option<Temporary> {
    let rest = name.strip_prefix('.')?;
    let (stem, kind) = match (rest.strip_suffix(".tmp"), rest.strip_suffix(".staged")) {
        (Some(stem), _) => (stem, Kind::Partial),
        (None, Some(stem)) => (stem, Kind::Staged),
        (None, None) => return None,
    };
    let (destination, owned) = stem.rsplit_once(&format!(".{MARK}-"))?;
    let (owner, counter) = owned.rsplit_once('-')?;
    digits(counter)?;
    Some(Temporary {
        owner: Owner::parse(owner)?,
        kind,
        destination: (destination.len() < NAME_BYTES && !destination.is_empty())
            .then(|| destination.to_string()),
    })
}

/// The owner of the temporary named `name`, if it is one (either kind).
pub fn temporary_owner(name: &str) -> Option<Owner> {
    temporary(name).map(|t| t.owner)
}

/// Is `name` one the crate keeps for itself: the lock, or a temporary's?
/// No output may have it.
pub fn is_reserved(name: &str) -> bool {
    name == super::LOCK_FILE || temporary(name).is_some()
}

/// Removes from `folder` the partial files (`.tmp`) of `owner`, a process
/// that no longer runs (nothing when it still does), each named as
/// [`temporary_path`] names them with that owner. Every other file —
/// staged files, folders, anything else — is left alone. Returns how many
/// were removed; one that cannot be removed is skipped.
pub fn remove_partials_of(folder: &Path, owner: Owner) -> usize {
    if owner.is_running() {
        return 0;
    }
    let Ok(entries) = fs::read_dir(folder) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let partial = name
            .to_str()
            .and_then(temporary)
            .is_some_and(|t| t.owner == owner && t.kind == Kind::Partial);
        let file = entry.file_type().is_ok_and(|kind| kind.is_file());
        if partial && file && fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// A staged file left by a process that no longer runs.
#[derive(Debug, Clone)]
pub struct Leftover {
    pub path: PathBuf,
    pub temporary: Temporary,
}

/// The staged files (`.staged`, regular files) in `folder` whose owner no
/// longer runs, sorted by name.
pub fn staged_leftovers(folder: &Path) -> Vec<Leftover> {
    let Ok(entries) = fs::read_dir(folder) else {
        return Vec::new();
    };
    let mut leftovers: Vec<Leftover> = entries
        .flatten()
        .filter(|entry| entry.file_type().is_ok_and(|kind| kind.is_file()))
        .filter_map(|entry| {
            let temporary = temporary(entry.file_name().to_str()?)?;
            let dead = temporary.kind == Kind::Staged && !temporary.owner.is_running();
            dead.then(|| Leftover {
                path: folder.join(entry.file_name()),
                temporary,
            })
        })
        .collect();
    leftovers.sort_by(|a, b| a.path.cmp(&b.path));
    leftovers
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporaries_are_recognised_by_their_name_owner_and_kind() {
        let owner = Owner {
            pid: 4242,
            start: 77,
        };
        let name = ".frame-000001.obj.masssprings-4242-77-7.tmp";
        assert_eq!(temporary_owner(name), Some(owner));
        assert_eq!(temporary(name).unwrap().kind, Kind::Partial);
        let staged = temporary(".frame-000001.obj.masssprings-4242-77-8.staged").unwrap();
        assert_eq!(staged.kind, Kind::Staged);
        assert_eq!(staged.destination.as_deref(), Some("frame-000001.obj"));
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
            ".x.masssprings-1-2-3.stage",
        ] {
            assert_eq!(temporary_owner(other), None, "{other}");
        }
        assert!(is_reserved(".masssprings-lock"));
        assert!(is_reserved(".x.masssprings-1-2-3.staged"));
        assert!(!is_reserved("masssprings-lock"));
    }

    #[test]
    fn a_temporary_names_its_destination_its_owner_and_stays_short() {
        let path = temporary_path(Path::new("out/frame-000001.obj"), Kind::Staged).unwrap();
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(name.starts_with(".frame-000001.obj.masssprings-"), "{name}");
        assert!(name.ends_with(".staged"), "{name}");
        assert_eq!(temporary_owner(name), Some(Owner::this_process()));
        assert_eq!(path.parent(), Some(Path::new("out")));
        let long = "é".repeat(120);
        let path = temporary_path(Path::new(&long), Kind::Partial).unwrap();
        assert!(path.as_os_str().len() < 120, "{}", path.display());
        let name = path.file_name().unwrap().to_str().unwrap();
        assert_eq!(temporary(name).unwrap().destination, None, "cut: unknown");
    }

    #[test]
    fn this_process_runs_and_a_finished_one_does_not() {
        assert!(Owner::this_process().is_running());
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let gone = Owner { pid, start: 1 };
        assert!(!gone.is_running());
        assert_eq!(Owner::from_tag(&gone.tag()), Some(gone));
    }
}
