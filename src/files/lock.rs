//! One run at a time per output folder: a command that writes into a
//! folder (`simulate --out`, `trace -o`, `generate --out`) first takes the
//! folder's lock, `FOLDER/.masssprings-lock`, and a second run into the same
//! folder is refused while the first one runs:
//!
//! ```text
//! masssprings: error: frames: another masssprings run (simulate, process 4242) is writing into this folder; wait for it to end or choose another folder
//! ```
//!
//! The lock is the operating system's (`flock`, through
//! [`std::fs::File::try_lock`]): it belongs to the open file, so it goes
//! with the process however that ends, and a killed run never leaves the
//! folder locked. The lock file holds one line, the holder's record:
//! `masssprings COMMAND masssprings-PID-START`. A run that ends removes the
//! file; a killed one leaves it, and the next run that takes the lock
//! finds there the owner of the partial files the killed run left (its
//! proof that they are the crate's, [`super::temporaries`]) and removes
//! them before it writes anything. Staged files, whole results, are never
//! removed here: the command decides what becomes of them.
//!
//! Taking the lock makes the folder when it does not exist (through a
//! link to a folder not made yet, at the link's end); a run that made it
//! and wrote nothing there removes it again when it releases the lock:
//! the one folder a command ever removes is the empty one it made.

use super::temporaries::{remove_partials_of, Owner};
use super::FileError;
use std::fs::{self, File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The name of the lock file in a locked folder.
pub const LOCK_FILE: &str = ".masssprings-lock";

/// The lock of an output folder, held until dropped.
#[derive(Debug)]
pub struct FolderLock {
    folder: PathBuf,
    path: PathBuf,
    file: File,
    /// The folder the lock made (it did not exist before), at the end of
    /// the links to it.
    made_folder: Option<PathBuf>,
    /// The owner of the last run that held the lock and was killed.
    stale_owner: Option<Owner>,
}

impl FolderLock {
    /// Takes the lock of `folder` (made if missing) for `command` and
    /// removes the partial files of a killed run that held it last.
    ///
    /// # Errors
    /// A [`FileError`] naming the folder: another run holds the lock (its
    /// command and process, when it has written them), or the folder or
    /// its lock file cannot be made.
    pub fn acquire(folder: &Path, command: &str) -> Result<FolderLock, FileError> {
        // a link to a folder not made yet is followed, as for a file; the
        // path stays as given (relative when it was)
        let target =
            super::follow_links(folder).map_err(|e| FileError::os(folder, "follow the link", e))?;
        let made_folder = (!folder.exists()).then(|| target.clone());
        fs::create_dir_all(&target).map_err(|e| FileError::os(&target, "make the folder", e))?;
        let path = folder.join(LOCK_FILE);
        let mut file = lock_file_in(folder, &path).inspect_err(|_| {
            if let Some(made) = &made_folder {
                let _ = fs::remove_dir(made);
            }
        })?;
        let mut previous = String::new();
        let _ = file.read_to_string(&mut previous);
        let stale_owner = parse_record(&previous).filter(|owner| !owner.is_running());
        if let Some(owner) = stale_owner {
            remove_partials_of(folder, owner);
        }
        let record = format!("masssprings {command} {}\n", Owner::this_process().tag());
        file.set_len(0)
            .and_then(|()| file.rewind())
            .and_then(|()| file.write_all(record.as_bytes()))
            .map_err(|error| FileError::os(&path, "write the lock's record", error))?;
        Ok(FolderLock {
            folder: folder.to_path_buf(),
            path,
            file,
            made_folder,
            stale_owner,
        })
    }

    /// The owner of the last run that held this lock and was killed (its
    /// partial files in the folder are gone already; its staged files are
    /// the command's to take over).
    pub fn stale_owner(&self) -> Option<Owner> {
        self.stale_owner
    }

    /// The locked folder.
    pub fn folder(&self) -> &Path {
        &self.folder
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // Removed before it is unlocked (when the file is closed): a run
        // that opened it meanwhile finds it gone and takes a new one.
        if same_inode(&self.file, &self.path) {
            let _ = fs::remove_file(&self.path);
        }
        if let Some(made) = &self.made_folder {
            let _ = fs::remove_dir(made); // only when nothing was written
        }
    }
}

/// Opens and locks the lock file `path` of `folder`; retries when the file
/// was removed (by the run that held it) between the opening and the lock.
fn lock_file_in(folder: &Path, path: &Path) -> Result<File, FileError> {
    for _ in 0..100 {
        refuse_odd_lock_file(path)?;
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(|error| FileError::os(path, "open the lock file", error))?;
        match file.try_lock() {
            Ok(()) if same_inode(&file, path) => return Ok(file),
            Ok(()) => continue, // the holder removed it while it ended
            Err(TryLockError::WouldBlock) => return Err(busy(folder, path)),
            Err(TryLockError::Error(error)) => {
                return Err(FileError::invalid(format!(
                    "cannot lock the folder (so that no other run writes into it at the same \
                     time): {error}"
                ))
                .in_file(folder))
            }
        }
    }
    Err(busy(folder, path))
}

/// Refuses a lock file that is not a regular file (a link, which the lock
/// would write through, a FIFO, a folder): this crate never makes one.
fn refuse_odd_lock_file(path: &Path) -> Result<(), FileError> {
    match fs::symlink_metadata(path) {
        Ok(metadata) if !metadata.file_type().is_file() => Err(FileError::invalid(
            "this is not a lock file of masssprings (a link, a FIFO or a folder has its name); \
             move it away",
        )
        .in_file(path)),
        _ => Ok(()),
    }
}

/// The refusal when another run holds the lock, naming it when it has
/// written its record.
fn busy(folder: &Path, path: &Path) -> FileError {
    let record = fs::read_to_string(path).unwrap_or_default();
    let holder = match (record.split_whitespace().nth(1), parse_record(&record)) {
        (Some(command), Some(owner)) => format!(" ({command}, process {})", owner.pid),
        _ => String::new(),
    };
    FileError::invalid(format!(
        "another masssprings run{holder} is writing into this folder; wait for it to end or \
         choose another folder"
    ))
    .in_file(folder)
}

/// The owner in a lock's record `masssprings COMMAND masssprings-PID-START`.
fn parse_record(record: &str) -> Option<Owner> {
    let mut words = record.split_whitespace();
    if words.next()? != "masssprings" {
        return None;
    }
    let tag = words.nth(1)?;
    // a temporary's name carries the same tag: reuse its parser
    super::temporaries::temporary_owner(&format!(".x.{tag}-0.tmp"))
}

/// Is the open `file` the file at `path` itself (not one made there since,
/// nor one a link there points to)?
#[cfg(unix)]
fn same_inode(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode(_file: &File, path: &Path) -> bool {
    path.exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let folder = std::env::temp_dir().join(format!(
            "masssprings-lock-test-{}-{name}",
            std::process::id()
        ));
        let _ = fs::remove_dir_all(&folder);
        folder
    }

    #[test]
    fn a_second_lock_is_refused_until_the_first_is_released() {
        let folder = folder("twice");
        let first = FolderLock::acquire(&folder, "simulate").unwrap();
        let refused = FolderLock::acquire(&folder, "trace")
            .unwrap_err()
            .to_string();
        assert!(
            refused.contains(&format!("(simulate, process {})", std::process::id()))
                && refused.contains("another masssprings run"),
            "{refused}"
        );
        drop(first);
        assert!(!folder.exists(), "made by the lock, empty: removed");
        let again = FolderLock::acquire(&folder, "trace").unwrap();
        fs::write(folder.join("kept"), "a result").unwrap();
        drop(again);
        assert_eq!(fs::read_dir(&folder).unwrap().count(), 1, "only the result");
        fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn a_lock_file_that_is_a_link_is_refused_and_its_target_kept() {
        let folder = folder("link");
        fs::create_dir_all(&folder).unwrap();
        let target = folder.join("precious");
        fs::write(&target, "keep me").unwrap();
        std::os::unix::fs::symlink("precious", folder.join(LOCK_FILE)).unwrap();
        let refused = FolderLock::acquire(&folder, "trace")
            .unwrap_err()
            .to_string();
        assert!(
            refused.contains("not a lock file of masssprings"),
            "{refused}"
        );
        assert_eq!(fs::read_to_string(&target).unwrap(), "keep me");
        fs::remove_file(folder.join(LOCK_FILE)).unwrap();
        std::os::unix::fs::symlink("nowhere", folder.join(LOCK_FILE)).unwrap();
        assert!(FolderLock::acquire(&folder, "trace").is_err());
        assert!(
            !folder.join("nowhere").exists(),
            "nothing made through the link"
        );
        fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn a_killed_runs_partial_files_go_and_nothing_else() {
        let folder = folder("stale");
        fs::create_dir_all(&folder).unwrap();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let dead = format!("masssprings-{pid}-5");
        fs::write(
            folder.join(LOCK_FILE),
            format!("masssprings simulate {dead}\n"),
        )
        .unwrap();
        let partial = format!(".frame-000001.obj.{dead}-0.tmp");
        let kept = [
            ".notes.2024-06.tmp".to_string(),
            format!(".frame-000001.obj.{pid}-0.tmp"),
            format!(".x.masssprings-{pid}-6-0.tmp"),
            // a whole frame it staged: a result, not rubbish
            format!(".frame-000002.obj.{dead}-1.staged"),
        ];
        for name in kept.iter().chain([&partial]) {
            fs::write(folder.join(name), "text").unwrap();
        }
        // a folder with a temporary's name is nothing this crate makes
        let named_like_one = folder.join(format!(".frames.{dead}-2.tmp"));
        fs::create_dir(&named_like_one).unwrap();
        let lock = FolderLock::acquire(&folder, "simulate").unwrap();
        assert_eq!(
            lock.stale_owner(),
            Some(Owner { pid, start: 5 }),
            "the killed run's record"
        );
        assert!(!folder.join(&partial).exists());
        assert!(named_like_one.is_dir());
        for name in &kept {
            assert!(folder.join(name).exists(), "{name} is kept");
        }
        drop(lock);
        fs::remove_dir_all(&folder).unwrap();
    }
}
