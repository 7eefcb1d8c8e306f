//! Outputs that cannot destroy inputs: before a command does any work, it
//! lists the files it reads and the files it writes in a [`FilePlan`], and
//! [`FilePlan::check`] refuses the run when
//!
//! * an output is one of the inputs (`export-q net.json -o net.json`),
//! * two outputs are one file (`--csv same.png --plot same.png`),
//! * a file the command writes into an output folder is one of the inputs
//!   or of the other outputs (a texture named `frame-000002.obj` beside
//!   the frames),
//! * an output names a folder, or nothing at all (`--out ''`),
//! * an output has a name the crate keeps for itself: a folder's lock
//!   (`.masssprings-lock`) or a temporary's (`.NAME.masssprings-PID-START-N.tmp`,
//!   `.staged`), which a texture named so would otherwise become beside
//!   the frames.
//!
//! "Is one file" means the same device and inode once every symbolic link
//! is followed (so a link to the input, `./x` and `x`, or a hard link, are
//! all caught), or, for files that do not exist yet, the same path once
//! the links of its folders are followed. Two outputs that are the same
//! character device (`/dev/null` twice) are allowed: writing a device twice
//! loses nothing. Standard output, `-`, is one file too: a command that
//! prints its report there lists it as an output, so `--csv -` beside the
//! report is refused rather than mixed into it.

use super::temporaries::is_reserved;
use super::FileError;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// `path` with the symbolic links at its end followed (a link to a link
/// to a file: the file), also when the last of them points to nothing yet,
/// and kept as relative as it was given: a link's relative target is
/// joined to the link's folder as written. The folders above are left to
/// the kernel, so the path never grows beyond what was given plus the
/// links' targets (a working folder deeper than `PATH_MAX` still works).
///
/// # Errors
/// A loop of links (more than 40), or a link that cannot be read.
pub fn follow_links(path: &Path) -> io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    for _ in 0..40 {
        match fs::symlink_metadata(&path) {
            Ok(metadata) if metadata.file_type().is_symlink() => {
                let target = fs::read_link(&path)?;
                path = match path.parent() {
                    Some(folder) if target.is_relative() => folder.join(target),
                    _ => target,
                };
            }
            _ => return Ok(path),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        "a loop of symbolic links (more than 40 links to follow)",
    ))
}

/// The path `path` names once every symbolic link is followed, also when
/// the file (or its last links) does not exist yet: the links are followed
/// as far as they go and the rest is kept as written.
///
/// # Errors
/// The current folder cannot be read (for a relative path), or a loop of
/// links.
pub fn resolve(path: &Path) -> io::Result<PathBuf> {
    let mut path = std::path::absolute(path)?;
    for _ in 0..40 {
        if let Ok(resolved) = fs::canonicalize(&path) {
            return Ok(resolved);
        }
        match fs::symlink_metadata(&path) {
            Ok(metadata) if metadata.file_type().is_symlink() => {
                let target = fs::read_link(&path)?;
                let folder = path.parent().unwrap_or(Path::new("/")).to_path_buf();
                path = folder.join(target);
            }
            _ => {
                let (Some(folder), Some(name)) = (path.parent(), path.file_name()) else {
                    return Ok(path);
                };
                return Ok(resolve(folder)?.join(name));
            }
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

/// Do `a` and `b` name the same file ([`FilePlan`]'s test: device and
/// inode, or the resolved path of a file that does not exist)?
pub fn same_file(a: &Path, b: &Path) -> bool {
    Identity::of(a).same_file(&Identity::of(b))
}

/// What a path is, for comparing it with others.
#[derive(Debug)]
struct Identity {
    /// Device and inode, when the file exists.
    inode: Option<(u64, u64)>,
    /// The path with its links followed ([`resolve`]); `-` for standard output.
    resolved: PathBuf,
    character_device: bool,
}

impl Identity {
    fn of(path: &Path) -> Identity {
        if path == Path::new("-") {
            // Standard output is whatever it was opened on: `>> net.json`
            // makes it the scene.
            let metadata = fs::metadata("/dev/stdout").ok();
            return Identity {
                inode: metadata.as_ref().and_then(device_and_inode),
                resolved: path.to_path_buf(),
                character_device: metadata.is_some_and(|m| is_character_device(&m)),
            };
        }
        let metadata = fs::metadata(path).ok();
        Identity {
            inode: metadata.as_ref().and_then(device_and_inode),
            resolved: resolve(path).unwrap_or_else(|_| path.to_path_buf()),
            character_device: metadata.is_some_and(|m| is_character_device(&m)),
        }
    }

    fn same_file(&self, other: &Identity) -> bool {
        match (self.inode, other.inode) {
            (Some(a), Some(b)) => a == b,
            _ => self.resolved == other.resolved,
        }
    }
}

#[cfg(unix)]
fn device_and_inode(metadata: &fs::Metadata) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    Some((metadata.dev(), metadata.ino()))
}

#[cfg(not(unix))]
fn device_and_inode(_: &fs::Metadata) -> Option<(u64, u64)> {
    None
}

#[cfg(unix)]
fn is_character_device(metadata: &fs::Metadata) -> bool {
    use std::os::unix::fs::FileTypeExt;
    metadata.file_type().is_char_device()
}

#[cfg(not(unix))]
fn is_character_device(_: &fs::Metadata) -> bool {
    false
}

/// A file of a command and what names it in messages: `the scene`,
/// `--csv`, `-o`.
#[derive(Debug)]
struct Named {
    what: String,
    path: PathBuf,
}

impl Named {
    fn shown(&self) -> String {
        if self.path == Path::new("-") {
            format!("{} (-, standard output)", self.what)
        } else {
            format!("{} {}", self.what, super::shown(&self.path))
        }
    }
}

/// The files a command writes into a folder, by a rule on their names.
struct FolderWrites {
    what: String,
    folder: PathBuf,
    /// The files, for messages: "its frames frame-NNNNNN.obj".
    files: String,
    names: Box<dyn Fn(&str) -> bool>,
}

/// The files one command reads and writes; [`FilePlan::check`] refuses a
/// run whose outputs would destroy one of its inputs or each other.
///
/// ```no_run
/// # use masssprings::files::FilePlan;
/// # use std::path::Path;
/// let mut plan = FilePlan::default();
/// plan.input("the matrix", Path::new("q.mtx"));
/// plan.output("-o", Path::new("q.mtx"));
/// assert!(plan.check().is_err());
/// ```
#[derive(Default)]
pub struct FilePlan {
    inputs: Vec<Named>,
    outputs: Vec<Named>,
    folders: Vec<FolderWrites>,
}

impl FilePlan {
    /// A file the command reads (`what` names it in messages).
    pub fn input(&mut self, what: &str, path: &Path) -> &mut Self {
        self.inputs.push(Named {
            what: what.into(),
            path: path.to_path_buf(),
        });
        self
    }

    /// A file the command writes (`-`: standard output).
    pub fn output(&mut self, what: &str, path: &Path) -> &mut Self {
        self.outputs.push(Named {
            what: what.into(),
            path: path.to_path_buf(),
        });
        self
    }

    /// Files the command writes into `folder`, or removes from it: those
    /// whose name `names` accepts (`files` describes them in messages).
    pub fn writes_into(
        &mut self,
        what: &str,
        folder: &Path,
        files: &str,
        names: impl Fn(&str) -> bool + 'static,
    ) -> &mut Self {
        self.folders.push(FolderWrites {
            what: what.into(),
            folder: folder.to_path_buf(),
            files: files.into(),
            names: Box::new(names),
        });
        self
    }

    /// Refuses the plan when an output is empty, a folder, one of the
    /// inputs, or another output, or when a file written into an output
    /// folder is an input or another output.
    ///
    /// # Errors
    /// A [`FileError`] naming both files and the flags that gave them.
    pub fn check(&self) -> Result<(), FileError> {
        for output in &self.outputs {
            refuse_unusable(output)?;
        }
        let inputs: Vec<Identity> = self.inputs.iter().map(|n| Identity::of(&n.path)).collect();
        let outputs: Vec<Identity> = self.outputs.iter().map(|n| Identity::of(&n.path)).collect();
        for (o, output) in outputs.iter().enumerate() {
            if let Some(i) = inputs.iter().position(|input| input.same_file(output)) {
                return Err(FileError::invalid(format!(
                    "{} is {}: writing it would destroy an input; choose another name",
                    self.outputs[o].shown(),
                    self.inputs[i].shown()
                )));
            }
            for (p, other) in outputs.iter().enumerate().skip(o + 1) {
                let devices = output.character_device && other.character_device;
                if output.resolved == Path::new("-") && other.resolved == Path::new("-") {
                    return Err(FileError::invalid(format!(
                        "{} and {} would both go to standard output (-); name a file for {}",
                        self.outputs[o].what, self.outputs[p].what, self.outputs[o].what
                    )));
                }
                if output.same_file(other) && !devices {
                    return Err(FileError::invalid(format!(
                        "{} and {} name the same file: one would overwrite the other; choose \
                         two names",
                        self.outputs[o].shown(),
                        self.outputs[p].shown()
                    )));
                }
            }
        }
        for writes in &self.folders {
            self.refuse_folder_clash(writes, &inputs, &outputs)?;
        }
        Ok(())
    }

    fn refuse_folder_clash(
        &self,
        writes: &FolderWrites,
        inputs: &[Identity],
        outputs: &[Identity],
    ) -> Result<(), FileError> {
        let folder = resolve(&writes.folder).unwrap_or_else(|_| writes.folder.clone());
        let files = self.inputs.iter().zip(inputs).map(|f| (f, "an input"));
        let files = files.chain(self.outputs.iter().zip(outputs).map(|f| (f, "an output")));
        for ((named, identity), kind) in files {
            let path = &identity.resolved;
            let inside = path.parent() == Some(folder.as_path());
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if inside && (writes.names)(name) {
                return Err(FileError::invalid(format!(
                    "{} ({kind}) is one of {} that {} {} writes or removes: choose another \
                     folder or rename the file",
                    named.shown(),
                    writes.files,
                    writes.what,
                    super::shown(&writes.folder)
                )));
            }
        }
        Ok(())
    }
}

/// Refuses an output that names nothing, names a folder, or has a name
/// the crate keeps for itself.
fn refuse_unusable(output: &Named) -> Result<(), FileError> {
    if output.path.as_os_str().is_empty() {
        return Err(FileError::invalid(format!(
            "{} is empty: it must name a file",
            output.what
        )));
    }
    let name = output.path.file_name().and_then(|n| n.to_str());
    if let Some(name) = name.filter(|name| is_reserved(name)) {
        return Err(FileError::invalid(format!(
            "{}: the name {name} is one masssprings keeps for itself (a folder's lock, or \
             a file it is writing); choose another name",
            output.shown()
        )));
    }
    if output.path != Path::new("-") && fs::metadata(&output.path).is_ok_and(|m| m.is_dir()) {
        return Err(FileError::invalid(format!(
            "{} is a folder: name a file in it, e.g. {}",
            output.shown(),
            super::shown(&output.path.join("out"))
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_resolves_through_its_folders_also_when_it_does_not_exist() {
        let here = std::env::current_dir().unwrap().canonicalize().unwrap();
        assert_eq!(
            resolve(Path::new("no-such-file")).unwrap(),
            here.join("no-such-file")
        );
        assert_eq!(
            resolve(Path::new("./no-such-file")).unwrap(),
            resolve(Path::new("no-such-file")).unwrap()
        );
        assert_eq!(
            resolve(Path::new("no/such/file")).unwrap(),
            here.join("no/such/file")
        );
    }

    #[test]
    fn an_empty_output_and_two_outputs_of_one_name_are_refused() {
        let mut plan = FilePlan::default();
        plan.output("--csv", Path::new(""));
        let message = plan.check().unwrap_err().to_string();
        assert_eq!(message, "--csv is empty: it must name a file");
        let mut plan = FilePlan::default();
        plan.output("--csv", Path::new("a.png"));
        plan.output("--plot", Path::new("./a.png"));
        let message = plan.check().unwrap_err().to_string();
        assert!(message.starts_with("--csv a.png and --plot ./a.png name the same file"));
        let mut plan = FilePlan::default();
        plan.output("the report", Path::new("-"));
        plan.output("--csv", Path::new("-"));
        assert!(plan.check().is_err());
        let mut plan = FilePlan::default();
        plan.output("--csv", Path::new("/dev/null"));
        plan.output("--plot", Path::new("/dev/null"));
        assert!(plan.check().is_ok(), "a device may be written twice");
    }

    #[test]
    fn links_are_followed_and_relative_paths_stay_relative() {
        let folder =
            std::env::temp_dir().join(format!("masssprings-follow-{}", std::process::id()));
        let _ = fs::remove_dir_all(&folder);
        fs::create_dir_all(&folder).unwrap();
        std::os::unix::fs::symlink("b", folder.join("a")).unwrap();
        std::os::unix::fs::symlink("sub/c", folder.join("b")).unwrap();
        assert_eq!(
            follow_links(&folder.join("a")).unwrap(),
            folder.join("sub/c")
        );
        assert_eq!(follow_links(Path::new("x/y")).unwrap(), Path::new("x/y"));
        std::os::unix::fs::symlink("loop", folder.join("loop")).unwrap();
        assert!(follow_links(&folder.join("loop")).is_err());
        fs::remove_dir_all(&folder).unwrap();
    }

    #[test]
    fn reserved_names_are_no_outputs() {
        for name in [
            ".masssprings-lock",
            ".q.mtx.masssprings-1-2-3.tmp",
            ".a.masssprings-1-2-3.staged",
        ] {
            let mut plan = FilePlan::default();
            plan.output("-o", &Path::new("out").join(name));
            let message = plan.check().unwrap_err().to_string();
            assert!(message.contains("keeps for itself"), "{message}");
        }
    }

    #[test]
    fn a_file_in_an_output_folder_that_the_command_writes_is_refused() {
        let mut plan = FilePlan::default();
        plan.input("the texture", Path::new("frames/frame-000002.obj"));
        plan.writes_into("--out", Path::new("frames"), "the frames", |name| {
            name.starts_with("frame-")
        });
        let message = plan.check().unwrap_err().to_string();
        assert!(
            message.starts_with(
                "the texture frames/frame-000002.obj (an input) is one of the frames that \
                 --out frames writes or removes"
            ),
            "{message}"
        );
        let mut plan = FilePlan::default();
        plan.input("the texture", Path::new("other/frame-000002.obj"));
        plan.writes_into("--out", Path::new("frames"), "the frames", |_| true);
        assert!(plan.check().is_ok());
    }
}
