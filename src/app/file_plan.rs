//! The files around a command: the scene it reads (checked to be one), the
//! inputs a [`FilePlan`] must not overwrite, the `--out` folder it writes
//! into, the files it may replace there, and where its one-line report
//! goes.
//!
//! The files a command writes into a folder by names the user did not
//! type (`simulate --out`'s material and texture copy, `generate`'s scenes,
//! `trace -o`'s quantities) are each either the command's own — written by
//! it or an earlier run of it, and recognisable as such by their first
//! line or their very bytes ([`starts_with_line`], [`begins_with`],
//! [`start_holds`], [`writes_same`]) — or refused, naming them, unless
//! `--force` ([`refuse_foreign`]). A file the user named on the command
//! line (`-o picture.png`) is the user's choice and is replaced, as any
//! program replaces its named output; the [`FilePlan`] still refuses it
//! when it is an input.

use super::error::AppError;
use masssprings::files::patient::open_regular;
use masssprings::files::{shown, FilePlan};
use masssprings::mesh::Scene;
use std::fs;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

/// Reads a scene, first making sure the file is one: a scene is JSON that
/// names an OBJ, and an OBJ (or anything else) given in its place gets a
/// sentence saying so rather than a JSON parser's complaint.
///
/// # Errors
/// That sentence, or the scene reader's error (file, line, problem).
pub fn load_scene(path: &Path) -> Result<Scene, AppError> {
    if !looks_like_json(path) {
        return Err(AppError::Failed(format!(
            "{} is not a scene file: scenes are JSON that name an OBJ; see data/README.md",
            shown(path)
        )));
    }
    Ok(masssprings::mesh::load_scene(path)?)
}

/// The files of `scene` (read from `scene_path`): its JSON, its OBJ and
/// its texture, as inputs of `plan`.
pub fn plan_scene_inputs(plan: &mut FilePlan, scene_path: &Path, scene: &Scene) {
    plan.input("the scene", scene_path);
    if let Some(obj) = &scene.obj {
        plan.input("the scene's OBJ", obj);
    }
    if let Some(texture) = &scene.texture {
        plan.input("the scene's texture", texture);
    }
}

/// Refuses an `--out` folder that names nothing, standard output (`-`) or a
/// file; `writes` says what the command puts there, for the message.
///
/// # Errors
/// A usage error for an empty name or `-`, a failure for a file.
pub fn check_output_folder(folder: &Path, writes: &str) -> Result<(), AppError> {
    if folder == Path::new("-") || folder.as_os_str().is_empty() {
        return Err(AppError::Usage(format!(
            "--out '{}': {writes}; name a folder",
            shown(folder)
        )));
    }
    if std::fs::metadata(folder).is_ok_and(|m| !m.is_dir()) {
        return Err(AppError::Failed(format!(
            "--out {}: this is a file, not a folder; {writes}",
            shown(folder)
        )));
    }
    Ok(())
}

/// Prints a command's one-line report on standard output, or on standard
/// error when its output file is `-` (standard output carries the file).
pub fn report(out: &Path, line: &str) {
    if out == Path::new("-") {
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
}

/// Does the file start (after white space and a byte-order mark) with `{`?
/// True when it cannot be read, is empty or is not a regular file (a FIFO
/// is read once, by the scene reader, which then says what is wrong).
fn looks_like_json(path: &Path) -> bool {
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return true;
    }
    let mut start = [0u8; 512];
    let Ok(read) = std::fs::File::open(path).and_then(|mut file| file.read(&mut start)) else {
        return true;
    };
    let text = start[..read]
        .strip_prefix(b"\xef\xbb\xbf")
        .unwrap_or(&start[..read]);
    match text.iter().find(|byte| !byte.is_ascii_whitespace()) {
        None => true,
        Some(&first) => first == b'{',
    }
}

/// Is the first line of the file at `path` exactly `line` (a file written
/// by this crate with that header)? False for anything that is not a
/// regular file.
pub fn starts_with_line(path: &Path, line: &str) -> bool {
    let mut start = vec![0u8; line.len() + 2];
    let read = match open_regular(path) {
        Some(file) => read_up_to(file, &mut start),
        None => return false,
    };
    let text = &start[..read];
    let text = text.strip_prefix(line.as_bytes()).unwrap_or(b"x");
    text.is_empty() || text.starts_with(b"\n") || text.starts_with(b"\r\n")
}

/// Does the start of the regular file at `path` (its first `bytes` bytes)
/// hold `text`? False for anything that is not a regular file.
pub fn start_holds(path: &Path, text: &str, bytes: usize) -> bool {
    let mut start = vec![0u8; bytes];
    let read = match open_regular(path) {
        Some(file) => read_up_to(file, &mut start),
        None => return false,
    };
    let needle = text.as_bytes();
    start[..read].windows(needle.len()).any(|w| w == needle)
}

/// Does the regular file at `path` begin with `prefix`?
pub fn begins_with(path: &Path, prefix: &str) -> bool {
    let mut start = vec![0u8; prefix.len()];
    match open_regular(path) {
        Some(file) => read_up_to(file, &mut start) == prefix.len() && start == prefix.as_bytes(),
        None => false,
    }
}

/// Does the regular file at `path` hold exactly `bytes`?
pub fn holds_bytes(path: &Path, bytes: &[u8]) -> bool {
    let Some(file) = open_regular(path) else {
        return false;
    };
    if !file.metadata().is_ok_and(|m| m.len() == bytes.len() as u64) {
        return false;
    }
    let mut content = vec![0u8; bytes.len()];
    read_up_to(file, &mut content) == bytes.len() && content == bytes
}

/// Would `write` write exactly what the regular file at `path` holds?
/// Compared as it writes, chunk by chunk, so nothing the size of the file
/// is held.
pub fn writes_same(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> bool {
    let Some(file) = open_regular(path) else {
        return false;
    };
    let mut compare = Comparison {
        file: io::BufReader::new(file),
        chunk: Vec::new(),
    };
    if write(&mut compare).is_err() {
        return false;
    }
    let mut rest = [0u8; 1];
    matches!(compare.file.read(&mut rest), Ok(0))
}

/// A writer that compares what is written with a file, failing at the
/// first difference.
struct Comparison {
    file: io::BufReader<fs::File>,
    chunk: Vec<u8>,
}

impl Write for Comparison {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.chunk.resize(bytes.len(), 0);
        self.file.read_exact(&mut self.chunk)?;
        if self.chunk != bytes {
            return Err(io::Error::other("differs"));
        }
        Ok(bytes.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// Reads into `buffer` until it is full or the file ends; how many bytes.
pub fn read_up_to(mut file: fs::File, buffer: &mut [u8]) -> usize {
    let mut filled = 0;
    while filled < buffer.len() {
        match file.read(&mut buffer[filled..]) {
            Ok(0) | Err(_) => break,
            Ok(count) => filled += count,
        }
    }
    filled
}

/// Is there anything at `path` (also a link to nothing)?
pub fn occupied(path: &Path) -> bool {
    fs::symlink_metadata(path).is_ok()
}

/// Refuses, unless `force`, to replace the `foreign` files (those in the
/// way that the command did not write): `flag` is the option and folder
/// (`--out frames`), `command` the command's name.
///
/// # Errors
/// A failure naming the first few files and the way out.
pub fn refuse_foreign(
    flag: &str,
    command: &str,
    foreign: &[PathBuf],
    force: bool,
) -> Result<(), AppError> {
    if foreign.is_empty() || force {
        return Ok(());
    }
    let mut names: Vec<String> = foreign
        .iter()
        .take(3)
        .map(|path| {
            path.file_name()
                .map_or(shown(path), |n| shown(std::path::Path::new(n)))
        })
        .collect();
    if foreign.len() > 3 {
        names.push(format!("and {} more", foreign.len() - 3));
    }
    Err(AppError::Failed(format!(
        "{flag}: {} {} not written by masssprings {command} and would be replaced; give \
         --force to replace {}, or choose another folder",
        names.join(", "),
        if foreign.len() == 1 { "is" } else { "are" },
        if foreign.len() == 1 { "it" } else { "them" },
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_recognised_by_its_first_line_or_its_bytes() {
        let folder = std::env::temp_dir().join(format!("masssprings-own-{}", std::process::id()));
        fs::create_dir_all(&folder).unwrap();
        let file = folder.join("net.mtl");
        fs::write(&file, "# net — masssprings frames\nnewmtl net\n").unwrap();
        assert!(starts_with_line(&file, "# net — masssprings frames"));
        assert!(!starts_with_line(&file, "# net — masssprings"));
        assert!(!starts_with_line(&folder, "x"), "a folder is not a file");
        let text = "# net — masssprings frames\nnewmtl net\n";
        assert!(holds_bytes(&file, text.as_bytes()));
        assert!(!holds_bytes(&file, b"# net"));
        assert!(writes_same(&file, |out| out.write_all(text.as_bytes())));
        assert!(!writes_same(&file, |out| out.write_all(b"# net")));
        let longer = |out: &mut dyn Write| write!(out, "{text}more");
        assert!(!writes_same(&file, longer));
        let refusal = refuse_foreign("--out f", "simulate", std::slice::from_ref(&file), false);
        let message = match refusal {
            Err(AppError::Failed(message)) => message,
            _ => panic!("refused"),
        };
        assert!(
            message.starts_with("--out f: net.mtl is not written by masssprings simulate"),
            "{message}"
        );
        assert!(refuse_foreign("--out f", "simulate", &[file], true).is_ok());
        fs::remove_dir_all(&folder).unwrap();
    }
}
