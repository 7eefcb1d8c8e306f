//! The files around a command: the scene it reads (checked to be one), the
//! inputs a [`FilePlan`] must not overwrite, the `--out` folder it writes
//! into, and where its one-line report goes.

use super::error::AppError;
use masssprings::files::FilePlan;
use masssprings::mesh::Scene;
use std::io::Read;
use std::path::Path;

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
            path.display()
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
            folder.display()
        )));
    }
    if std::fs::metadata(folder).is_ok_and(|m| !m.is_dir()) {
        return Err(AppError::Failed(format!(
            "--out {}: this is a file, not a folder; {writes}",
            folder.display()
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
