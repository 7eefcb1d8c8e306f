//! Files: errors that say where a problem is (file and line), and writing a
//! file all or nothing.
//!
//! Every reader of the crate (Matrix Market matrices, OBJ + JSON scenes)
//! reports bad input as a [`FileError`], displayed `path:line: problem`, so
//! a user can go straight to the place. Every writer (matrices, frames,
//! scenes, images) goes through [`write_file`]: the content is written to a
//! temporary file beside the destination, flushed to disk and renamed into
//! place, so a failure never leaves a half-written file behind.
//!
//! This module sits below every layer and knows nothing about what the
//! files contain.

use std::fmt;
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A file that could not be read, written or understood: which file, which
/// line, and what went wrong. Displays as `path:line: problem`.
#[derive(Debug)]
pub struct FileError {
    path: Option<PathBuf>,
    line: Option<usize>,
    problem: Problem,
}

#[derive(Debug)]
enum Problem {
    Unreadable(io::Error),
    Unwritable(io::Error),
    Invalid(String),
}

impl FileError {
    /// A problem with the content, not yet placed in a file or on a line.
    pub fn invalid(message: impl Into<String>) -> Self {
        FileError {
            path: None,
            line: None,
            problem: Problem::Invalid(message.into()),
        }
    }

    /// The file at `path` could not be read.
    pub fn unreadable(path: &Path, error: io::Error) -> Self {
        FileError {
            path: Some(path.to_path_buf()),
            line: None,
            problem: Problem::Unreadable(error),
        }
    }

    /// The file at `path` could not be written.
    pub fn unwritable(path: &Path, error: io::Error) -> Self {
        FileError {
            path: Some(path.to_path_buf()),
            line: None,
            problem: Problem::Unwritable(error),
        }
    }

    /// Places the problem on a 1-based line.
    pub fn at_line(mut self, line: usize) -> Self {
        self.line = Some(line);
        self
    }

    /// Names the file, unless one is named already.
    pub fn in_file(mut self, path: &Path) -> Self {
        self.path.get_or_insert_with(|| path.to_path_buf());
        self
    }

    /// The file the problem is in, when known.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The 1-based line of the problem, when there is one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// The underlying I/O error, when reading or writing failed.
    pub fn io_error(&self) -> Option<&io::Error> {
        match &self.problem {
            Problem::Unreadable(error) | Problem::Unwritable(error) => Some(error),
            Problem::Invalid(_) => None,
        }
    }
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.path, self.line) {
            (Some(path), Some(line)) => write!(f, "{}:{line}: ", path.display())?,
            (Some(path), None) => write!(f, "{}: ", path.display())?,
            (None, Some(line)) => write!(f, "line {line}: ")?,
            (None, None) => {}
        }
        match &self.problem {
            Problem::Unreadable(error) => write!(f, "cannot read the file: {error}"),
            Problem::Unwritable(error) => write!(f, "cannot write the file: {error}"),
            Problem::Invalid(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for FileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.io_error().map(|error| error as _)
    }
}

/// The text of the file at `path`.
///
/// # Errors
/// [`FileError`] naming the path when the file cannot be read or is not UTF-8.
pub fn read_text(path: &Path) -> Result<String, FileError> {
    fs::read_to_string(path).map_err(|error| FileError::unreadable(path, error))
}

/// Creates (or replaces) the file at `path` with what `write` produces, all
/// or nothing.
///
/// `write` fills a temporary file in the same folder, which is flushed to
/// disk and then renamed to `path`; if `write` or any step fails, the
/// temporary is removed and `path` is left as it was.
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
/// `path` in the message.
pub fn write_file(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), FileError> {
    let temporary = temporary_path(path).map_err(|e| FileError::unwritable(path, e))?;
    let result = write_then_rename(&temporary, path, write);
    if result.is_err() {
        // The temporary may not exist (creation failed, or it was renamed); either is fine.
        let _ = fs::remove_file(&temporary);
    }
    result.map_err(|e| FileError::unwritable(path, e))
}

fn write_then_rename(
    temporary: &Path,
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let file = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(temporary)?;
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    let file = out.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()?;
    fs::rename(temporary, path)
}

/// `.NAME.PID-COUNTER.tmp` beside `path`: unique per process and per call, so
/// concurrent writers never share a temporary.
fn temporary_path(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("`{}` does not name a file", path.display()),
        )
    })?;
    let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
    let temporary = format!(
        ".{}.{}-{unique}.tmp",
        name.to_string_lossy(),
        std::process::id()
    );
    Ok(path.with_file_name(temporary))
}
