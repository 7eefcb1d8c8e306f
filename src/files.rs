//! Files: errors that say where a problem is (file and line), reading that
//! never runs away or hangs, and writing that never destroys what the user
//! gave.
//!
//! Every reader of the crate (Matrix Market matrices, OBJ + JSON scenes,
//! textures) reports bad input as a [`FileError`], displayed
//! `path:line: problem`, so a user can go straight to the place. Every
//! reader gets its bytes from [`read_text`] or [`read_bytes`], which apply
//! the same rules to all of them:
//!
//! * **size**: at most [`max_input_bytes`] (an eighth of the memory limit of
//!   [`crate::memory`]: parsing holds the text and builds structures a few
//!   times its size). A regular file is measured before it is opened for
//!   reading; anything else (a pipe, `/dev/zero`) is read in chunks and
//!   dropped as soon as it passes the limit, so nothing unbounded is
//!   buffered.
//! * **time**: anything that is not a regular file (a FIFO, a terminal) is
//!   opened without blocking and waited for at most
//!   [`patient::PATIENCE`] without a byte ([`patient`]), so a FIFO nobody
//!   writes to fails instead of hanging.
//! * **text**: UTF-8 (an invalid byte is reported with its line) without NUL
//!   bytes (reported at once with their line: `/dev/zero` fails on its first
//!   chunk); **binary** files may be required to start with their format's
//!   signature ([`read_bytes_of_format`]: a PNG), checked on the first
//!   chunk.
//! * **byte-order mark**: a UTF-8 BOM (`EF BB BF`) at the very start is
//!   skipped (editors on Windows write one), so the first line reads as
//!   written in every format.
//!
//! A reader that takes a [`Source`] reads the same way from files held in
//! memory ([`InMemory`]: a page in a browser has no file system), with the
//! same messages.
//!
//! Every output (matrices, frames, scenes, images, CSV) is written by
//! [`outputs`], which keeps one rule: a file is replaced by renaming a
//! temporary from its own folder over it, the folder synced after; a
//! folder is never replaced, exchanged or removed, unless the command made
//! it in this run and left it empty; an old file is removed only once
//! everything that replaces it is in place; and a file the command did not
//! write is never removed, whenever it appeared. A command checks its
//! [`FilePlan`] first (no output is an input or another output, `plan`).
//!
//! This module sits below every layer and knows nothing about what the
//! files contain.

mod in_memory;
mod lock;
pub mod outputs;
pub mod patient;
mod plan;
mod temporaries;

pub use in_memory::InMemory;
pub use lock::{FolderLock, LOCK_FILE};
pub use outputs::{write_file, Expect, Held, OutputFolder};
pub use plan::{follow_links, resolve, same_file, FilePlan};
pub use temporaries::{is_reserved, temporary, temporary_owner, Kind, Leftover, Owner, Temporary};

use std::borrow::Cow;
use std::fmt;
use std::fs;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

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
    /// An operation on the file failed: what it was ("rename it to …").
    Os(String, io::Error),
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

    /// The operation `operation` (a phrase after "cannot": "replace it by
    /// …", "make the folder") on the file at `path` failed with `error`.
    pub fn os(path: &Path, operation: impl Into<String>, error: io::Error) -> Self {
        FileError {
            path: Some(path.to_path_buf()),
            line: None,
            problem: Problem::Os(operation.into(), error),
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
            Problem::Os(_, error) => Some(error),
            Problem::Invalid(_) => None,
        }
    }
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.path, self.line) {
            (Some(path), Some(line)) => write!(f, "{}:{line}: ", shown(path))?,
            (Some(path), None) => write!(f, "{}: ", shown(path))?,
            (None, Some(line)) => write!(f, "line {line}: ")?,
            (None, None) => {}
        }
        match &self.problem {
            Problem::Unreadable(error) => write!(f, "cannot read the file: {error}"),
            Problem::Unwritable(error) => write!(f, "cannot write the file: {error}"),
            Problem::Os(operation, error) => write!(f, "cannot {operation}: {error}"),
            Problem::Invalid(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for FileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.io_error().map(|error| error as _)
    }
}

/// `text` as it may be printed: every control character (a line break, a
/// tab, the escape that starts a terminal's colour codes) written as
/// Rust's escape for it (`\n`, `\t`, `\u{1b}`), so that a name or a line
/// read from a file can neither break a message's line nor drive the
/// terminal. Everything else, accents and all, is kept.
pub fn escaped(text: &str) -> Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// A path as messages show it: [`escaped`], bytes that are not UTF-8 as
/// `\u{fffd}` (`�`).
pub fn shown(path: &Path) -> String {
    escaped(&path.to_string_lossy()).into_owned()
}

/// `x` as a message shows it: the shortest decimal that reads back to the
/// same `f64`, in exponent form when it would take more than 16 digits
/// before the point or 4 zeros after it (`1e308`, not 309 digits;
/// `2.5e-7`), else as a plain decimal (`500`, `0.03333333333333333`).
pub fn number(x: f64) -> String {
    let plain = x == 0.0 || (1e-4..1e16).contains(&x.abs());
    if plain || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A fingerprint of `words` that a file can carry to say what it was
/// written from (a frame, its scene's rest positions; a trace's file, the
/// trace): 64-bit FNV-1a of the words (each as 8 little-endian bytes) and
/// their count, `fnv1a64:0123456789abcdef of N`. Two lists that differ
/// give two fingerprints but for one chance in 2⁶⁴.
pub fn fingerprint(words: impl IntoIterator<Item = u64>) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut count = 0u64;
    for word in words {
        for byte in word.to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
        count += 1;
    }
    format!("fnv1a64:{hash:016x} of {count}")
}

/// The largest file the readers read: an eighth of the memory limit
/// ([`crate::memory::limit`]), because a reader holds the whole text while
/// it builds structures several times its size.
pub fn max_input_bytes() -> u64 {
    crate::memory::limit().bytes / 8
}

/// The UTF-8 byte-order mark, skipped at the start of every text file.
const BYTE_ORDER_MARK: char = '\u{feff}';

/// The text of the file at `path`, checked as described in the module
/// header: at most [`max_input_bytes`], UTF-8, no NUL byte, a leading
/// byte-order mark removed.
///
/// # Errors
/// [`FileError`] naming the path (and the line, for a NUL or a byte that is
/// not UTF-8) when the file cannot be read, is too large, or is not text.
pub fn read_text(path: &Path) -> Result<String, FileError> {
    text_of(path, read_limited(path, Content::Text)?)
}

/// The text of `bytes`, the checked content of the file at `path`: UTF-8
/// (a byte that is not is reported with its line), a leading byte-order
/// mark removed.
fn text_of(path: &Path, bytes: Vec<u8>) -> Result<String, FileError> {
    let text = String::from_utf8(bytes).map_err(|error| {
        let bytes = error.as_bytes();
        let valid = error.utf8_error().valid_up_to();
        FileError::invalid(format!(
            "the file is not UTF-8 text: byte {:#04x} at byte offset {valid} is not valid UTF-8",
            bytes[valid]
        ))
        .at_line(line_of_offset(bytes, valid))
        .in_file(path)
    })?;
    match text.strip_prefix(BYTE_ORDER_MARK) {
        Some(rest) => Ok(rest.to_owned()),
        None => Ok(text),
    }
}

/// The bytes of the file at `path`, at most [`max_input_bytes`].
///
/// # Errors
/// [`FileError`] naming the path when the file cannot be read or is larger.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, FileError> {
    read_limited(path, Content::Bytes)
}

/// The bytes of the file at `path` (at most [`max_input_bytes`]), which must
/// start with `signature`, the mark of the `format` it must be in (a PNG's
/// eight bytes): checked on the first chunk, so `/dev/zero` or a text file
/// is refused at once, not after reading the whole limit.
///
/// # Errors
/// [`FileError`] naming the path when the file cannot be read, is larger,
/// or does not start with the signature.
pub fn read_bytes_of_format(
    path: &Path,
    signature: &[u8],
    format: &str,
) -> Result<Vec<u8>, FileError> {
    read_limited(path, Content::Format(signature, format))
}

/// Where the readers get their files: the file system ([`Disk`]), or files
/// held in memory ([`InMemory`]: those a page in a browser was given).
/// Both apply the rules of the module header but the waiting (a file in
/// memory is all there), so a file gets the same message from each.
pub trait Source {
    /// The text of the file at `path`, as [`read_text`] reads it.
    ///
    /// # Errors
    /// As [`read_text`].
    fn text(&self, path: &Path) -> Result<String, FileError>;

    /// The bytes of the file at `path`, which must start with `signature`,
    /// as [`read_bytes_of_format`] reads them.
    ///
    /// # Errors
    /// As [`read_bytes_of_format`].
    fn bytes_of_format(
        &self,
        path: &Path,
        signature: &[u8],
        format: &str,
    ) -> Result<Vec<u8>, FileError>;
}

/// The file system, read by [`read_text`] and [`read_bytes_of_format`].
#[derive(Debug, Clone, Copy, Default)]
pub struct Disk;

impl Source for Disk {
    fn text(&self, path: &Path) -> Result<String, FileError> {
        read_text(path)
    }

    fn bytes_of_format(
        &self,
        path: &Path,
        signature: &[u8],
        format: &str,
    ) -> Result<Vec<u8>, FileError> {
        read_bytes_of_format(path, signature, format)
    }
}

/// What a reader expects of the bytes.
#[derive(Clone, Copy)]
enum Content<'a> {
    Bytes,
    /// UTF-8 text without NUL bytes.
    Text,
    /// A binary format: its signature and name.
    Format(&'a [u8], &'a str),
}

/// Opens `path` for reading: a regular file the ordinary way, anything else
/// without blocking ([`patient::PatientReader`]); a folder is refused.
fn open_input(path: &Path) -> Result<(Box<dyn Read>, Option<u64>), FileError> {
    let unreadable = |error| FileError::unreadable(path, error);
    if path.as_os_str().is_empty() {
        return Err(FileError::invalid("an empty file name names no file"));
    }
    let metadata = fs::metadata(path).map_err(unreadable)?;
    if metadata.is_dir() {
        return Err(unreadable(io::Error::new(
            io::ErrorKind::InvalidInput,
            "this is a folder, not a file",
        )));
    }
    if metadata.is_file() {
        let file = fs::File::open(path).map_err(unreadable)?;
        let length = file.metadata().map_err(unreadable)?.len();
        return Ok((Box::new(file), Some(length)));
    }
    let reader = patient::PatientReader::open(path, is_fifo(&metadata)).map_err(unreadable)?;
    Ok((Box::new(reader), None))
}

#[cfg(unix)]
fn is_fifo(metadata: &fs::Metadata) -> bool {
    use std::os::unix::fs::FileTypeExt;
    metadata.file_type().is_fifo()
}

#[cfg(not(unix))]
fn is_fifo(_: &fs::Metadata) -> bool {
    false
}

/// The file's bytes, refusing it once it passes the limit (and, for text,
/// at its first NUL byte; for a format, on a wrong signature) without
/// reading further.
fn read_limited(path: &Path, content: Content) -> Result<Vec<u8>, FileError> {
    let unreadable = |error| FileError::unreadable(path, error);
    let max = max_input_bytes();
    let (file, length) = open_input(path).map_err(|e| e.in_file(path))?;
    if let Some(length) = length {
        check_length(path, length)?;
    }
    let mut reader = file.take(max.saturating_add(1));
    let mut bytes = Vec::new();
    let mut chunk = vec![0u8; 64 * 1024];
    loop {
        let count = match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(count) => count,
            Err(error) if error.kind() == io::ErrorKind::Interrupted => continue,
            Err(error) => return Err(unreadable(error)),
        };
        let before = bytes.len();
        bytes.extend_from_slice(&chunk[..count]);
        check_read(content, &bytes, before).map_err(|e| e.in_file(path))?;
        check_length(path, bytes.len() as u64)?;
    }
    check_whole(content, &bytes).map_err(|e| e.in_file(path))?;
    Ok(bytes)
}

/// Refuses a file of `length` bytes, the declared or the read length of
/// the file at `path`, beyond [`max_input_bytes`].
fn check_length(path: &Path, length: u64) -> Result<(), FileError> {
    let max = max_input_bytes();
    if length <= max {
        return Ok(());
    }
    Err(FileError::invalid(format!(
        "the file is larger than {max} bytes, the most read here (an eighth of the memory \
         limit, see docs/reliability.md)"
    ))
    .in_file(path))
}

/// Checks `bytes[from..]`, just read, as `content` requires: no NUL byte in
/// a text (its offset and line named), a format's signature so far.
fn check_read(content: Content, bytes: &[u8], from: usize) -> Result<(), FileError> {
    match content {
        Content::Bytes => Ok(()),
        Content::Text => match bytes[from..].iter().position(|&byte| byte == 0) {
            None => Ok(()),
            Some(position) => {
                let offset = from + position;
                Err(FileError::invalid(format!(
                    "a NUL byte at byte offset {offset}: this is not a text file"
                ))
                .at_line(line_of_offset(bytes, offset)))
            }
        },
        Content::Format(signature, format) => {
            let checked = bytes.len().min(signature.len());
            if bytes[..checked] == signature[..checked] {
                return Ok(());
            }
            Err(FileError::invalid(format!(
                "this is not a {format} file (it does not start with the {format} signature)"
            )))
        }
    }
}

/// Checks the whole of a file's `bytes` as `content` requires: a format's
/// file at least as long as its signature.
fn check_whole(content: Content, bytes: &[u8]) -> Result<(), FileError> {
    match content {
        Content::Format(signature, format) if bytes.len() < signature.len() => {
            Err(FileError::invalid(format!(
                "this is not a {format} file (shorter than the {format} signature)"
            )))
        }
        _ => Ok(()),
    }
}

/// The 1-based line of the byte at `offset`.
fn line_of_offset(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset.min(bytes.len())]
        .iter()
        .filter(|&&byte| byte == b'\n')
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_printed_without_control_characters() {
        assert_eq!(escaped("plain é"), "plain é");
        assert_eq!(escaped("a\nb\u{1b}[31m"), "a\\nb\\u{1b}[31m");
        let error = FileError::invalid("x").in_file(Path::new("evil\nname"));
        assert_eq!(error.to_string(), "evil\\nname: x");
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(number(1e308), "1e308");
        assert_eq!(number(-2.5e-7), "-2.5e-7");
        assert_eq!(number(500.0), "500");
        assert_eq!(number(1.0 / 30.0), "0.03333333333333333");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(f64::INFINITY), "inf");
        assert_eq!(number(f64::MAX), "1.7976931348623157e308");
    }

    #[test]
    fn line_of_offset_counts_line_breaks_before_it() {
        assert_eq!(line_of_offset(b"ab\ncd\n", 0), 1);
        assert_eq!(line_of_offset(b"ab\ncd\n", 3), 2);
        assert_eq!(line_of_offset(b"ab\ncd\n", 99), 3);
    }
}
