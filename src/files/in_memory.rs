//! Files held in memory: what a page in a browser was given (a scene's
//! JSON, its OBJ and its PNG, dropped on the page), read by the same
//! readers as files on disk, with the same messages.
//!
//! A file is put in by name before it is read, in two moves, so that no
//! byte is copied twice: [`InMemory::reserve`] checks the declared length
//! against [`max_input_bytes`](super::max_input_bytes) (an eighth of the
//! memory limit) *before* allocating room for it, and the caller fills the
//! room (a page copies the file's bytes into the WebAssembly memory). Read
//! through [`Source`], a file gets the checks of the module above: text
//! without NUL bytes, UTF-8, a byte-order mark skipped, a format's
//! signature. A name that was not given is "cannot read the file", as a
//! missing file is on disk.

use super::{check_length, check_read, check_whole, text_of, Content, FileError, Source};
use std::io;
use std::path::{Path, PathBuf};

/// Files by name, held in memory.
#[derive(Debug, Clone, Default)]
pub struct InMemory {
    files: Vec<(PathBuf, Vec<u8>)>,
}

impl InMemory {
    /// No files.
    pub fn new() -> Self {
        InMemory::default()
    }

    /// Room for the `length` bytes of the file `path` (zeros, for the
    /// caller to fill), replacing a file of that name.
    ///
    /// # Errors
    /// [`FileError`] naming `path` when `length` passes the input limit;
    /// nothing is allocated then.
    pub fn reserve(&mut self, path: &Path, length: u64) -> Result<&mut [u8], FileError> {
        check_length(path, length)?;
        let length = usize::try_from(length).expect("a length within the limit fits in memory");
        self.files.retain(|(name, _)| name != path);
        self.files.push((path.to_path_buf(), vec![0; length]));
        Ok(&mut self.files.last_mut().expect("just pushed").1)
    }

    /// Puts in the file `path` with its `bytes`.
    ///
    /// # Errors
    /// As [`InMemory::reserve`].
    pub fn insert(&mut self, path: &Path, bytes: &[u8]) -> Result<(), FileError> {
        self.reserve(path, bytes.len() as u64)?
            .copy_from_slice(bytes);
        Ok(())
    }

    /// The names of the files, in the order they were put in.
    pub fn names(&self) -> impl Iterator<Item = &Path> {
        self.files.iter().map(|(name, _)| name.as_path())
    }

    /// The bytes of the file `path`, checked as `content` requires.
    fn read(&self, path: &Path, content: Content) -> Result<&[u8], FileError> {
        let Some((_, bytes)) = self.files.iter().find(|(name, _)| name == path) else {
            let missing = io::Error::new(io::ErrorKind::NotFound, "no file of this name was given");
            return Err(FileError::unreadable(path, missing));
        };
        check_length(path, bytes.len() as u64)?;
        check_read(content, bytes, 0).map_err(|e| e.in_file(path))?;
        check_whole(content, bytes).map_err(|e| e.in_file(path))?;
        Ok(bytes)
    }
}

impl Source for InMemory {
    fn text(&self, path: &Path) -> Result<String, FileError> {
        text_of(path, self.read(path, Content::Text)?.to_vec())
    }

    fn bytes_of_format(
        &self,
        path: &Path,
        signature: &[u8],
        format: &str,
    ) -> Result<Vec<u8>, FileError> {
        Ok(self
            .read(path, Content::Format(signature, format))?
            .to_vec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::files::max_input_bytes;

    #[test]
    fn a_file_in_memory_is_checked_as_one_on_disk() {
        let mut files = InMemory::new();
        files
            .insert(Path::new("a.obj"), b"\xef\xbb\xbfv 0 0 0\n")
            .unwrap();
        files.insert(Path::new("b.obj"), b"v 0 0 0\nv 1\0").unwrap();
        files.insert(Path::new("c.png"), b"\x89PNG").unwrap();
        assert_eq!(files.text(Path::new("a.obj")).unwrap(), "v 0 0 0\n");
        let nul = files.text(Path::new("b.obj")).unwrap_err().to_string();
        assert_eq!(
            nul,
            "b.obj:2: a NUL byte at byte offset 11: this is not a text file"
        );
        let short = files.bytes_of_format(Path::new("c.png"), b"\x89PNG\r\n\x1a\n", "PNG");
        assert_eq!(
            short.unwrap_err().to_string(),
            "c.png: this is not a PNG file (shorter than the PNG signature)"
        );
        let missing = files.text(Path::new("d.obj")).unwrap_err().to_string();
        assert_eq!(
            missing,
            "d.obj: cannot read the file: no file of this name was given"
        );
        let names: Vec<_> = files.names().collect();
        assert_eq!(
            names,
            [Path::new("a.obj"), Path::new("b.obj"), Path::new("c.png")]
        );
    }

    #[test]
    fn a_file_past_the_limit_is_refused_before_room_is_made() {
        let mut files = InMemory::new();
        let refused = files.reserve(Path::new("huge.obj"), max_input_bytes() + 1);
        assert!(refused
            .unwrap_err()
            .to_string()
            .starts_with("huge.obj: the file is larger than"));
        assert_eq!(files.names().count(), 0);
    }
}
