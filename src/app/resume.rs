//! `simulate SCENE.json --resume DIR`: continue a run from its frames.
//!
//! A step of the method needs two states, not one: the inertial term is
//! `y = M (2 U_cur − U_prev) / Δt²` (Liu et al. 2013, §3; the assignment's
//! `fast_mass_springs_step`), so the run's velocity lives in the pair
//! (`U_prev`, `U_cur`). A run's frames hold that pair when
//!
//! * its last two frames are one step apart (`frame-000099.obj` and
//!   `frame-000100.obj`): a run written with `--every K > 1` has only every
//!   K-th step, and the velocity between them is lost;
//! * their numbers are exact: without `--precision` each coordinate is the
//!   shortest decimal that reads back to the same `f64`, so parsing it
//!   gives back the very bits. The frame writer says which on each frame's
//!   first line ([`frame_header`]); a rounded frame would continue a
//!   slightly different run.
//!
//! With both, `Simulation::set_state(U_prev, U_cur, step)` puts the
//! simulation where the run stopped, and the next step gives the same bits
//! as a run that never stopped (`tests/cli.rs`). Step 0 alone resumes as
//! the start: before step 0 the cloth was at rest, `U_prev = U_cur`.
//!
//! The options are not in the frames: give `--resume` the flags of the run
//! it continues.

use super::error::AppError;
use masssprings::files::read_text;
use masssprings::mesh::obj::parse_obj;
use masssprings::mesh::Scene;
use std::io;
use std::path::{Path, PathBuf};

/// The state a run stopped in.
pub struct Resumed {
    /// The last frame's step.
    pub step: usize,
    /// The positions one step before it.
    pub u_prev: Vec<[f64; 3]>,
    /// The last frame's positions.
    pub u_cur: Vec<[f64; 3]>,
}

/// The first line of a frame: the scene, the step, and whether its
/// positions are exact (`precision` `None`) or rounded to `precision`
/// digits after the point.
pub fn frame_header(scene: &str, step: usize, precision: Option<usize>) -> String {
    match precision {
        None => format!("# {scene} — masssprings frame, step {step}, exact positions"),
        Some(digits) => format!(
            "# {scene} — masssprings frame, step {step}, positions rounded to {digits} digits after the point"
        ),
    }
}

/// The state of the run whose frames are in `folder`: its last frame and
/// the one a step before it, both exact frames of `scene`.
///
/// # Errors
/// A sentence naming the folder or the frame: no folder, no frames, the frame a step
/// before the last missing (written with `--every K > 1`), a rounded frame
/// (written with `--precision`), a frame of another scene or step, a
/// vertex count unlike the scene's, or the OBJ reader's error (file, line).
pub fn last_state(folder: &Path, scene: &Scene) -> Result<Resumed, AppError> {
    if !folder.is_dir() {
        return Err(AppError::Failed(format!(
            "--resume {}: no such folder",
            folder.display()
        )));
    }
    let frames = earlier_frames(folder)?;
    let Some(step) = frames.iter().filter_map(|path| frame_step(path)).max() else {
        return Err(AppError::Failed(format!(
            "--resume {}: no frames (frame-NNNNNN.obj) to continue from",
            folder.display()
        )));
    };
    let u_cur = read_exact_frame(folder, step, scene)?;
    let u_prev = match step.checked_sub(1) {
        None => u_cur.clone(),
        Some(before) => {
            if !folder.join(frame_name(before)).is_file() {
                return Err(AppError::Failed(format!(
                    "--resume {}: {} is missing: a step needs the last frame ({}) and the one a \
                     step before it; a run written with --every K > 1 keeps only every K-th step \
                     and cannot be resumed exactly",
                    folder.display(),
                    frame_name(before),
                    frame_name(step)
                )));
            }
            read_exact_frame(folder, before, scene)?
        }
    };
    Ok(Resumed {
        step,
        u_prev,
        u_cur,
    })
}

/// `frame-NNNNNN.obj`, the name the frame writer gives `step`.
pub fn frame_name(step: usize) -> String {
    format!("frame-{step:06}.obj")
}

/// The positions of frame `step` in `folder`, if the frame says they are
/// exact and it has one per vertex of `scene`.
fn read_exact_frame(folder: &Path, step: usize, scene: &Scene) -> Result<Vec<[f64; 3]>, AppError> {
    let path = folder.join(frame_name(step));
    let text = read_text(&path)?;
    let first = text.lines().next().unwrap_or("");
    let expected = frame_header(&scene.name, step, None);
    if first != expected {
        let why = if first.contains("positions rounded to") {
            "its positions are rounded (written with --precision), so the run cannot be resumed \
             exactly; write frames without --precision to resume"
                .to_string()
        } else {
            format!("its first line is not `{expected}` (a frame of another scene or program)")
        };
        return Err(AppError::Failed(format!("{}: {why}", path.display())));
    }
    let mesh = parse_obj(&text).map_err(|e| e.in_file(&path))?;
    if mesh.vertices.len() != scene.vertices.len() {
        return Err(AppError::Failed(format!(
            "{}: {} vertices, but the scene {} has {}",
            path.display(),
            mesh.vertices.len(),
            scene.name,
            scene.vertices.len()
        )));
    }
    Ok(mesh.vertices)
}

/// Is `name` a frame of the frame writer, `frame-NNNNNN.obj` (6 digits or more)?
pub(super) fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame-")
        .and_then(|rest| rest.strip_suffix(".obj"))
        .is_some_and(|digits| digits.len() >= 6 && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// The step of the frame at `path` (`frame-000012.obj`: 12).
fn frame_step(path: &Path) -> Option<usize> {
    let name = path.file_name()?.to_str()?;
    if !is_frame_name(name) {
        return None;
    }
    name["frame-".len()..name.len() - ".obj".len()].parse().ok()
}

/// The frames already in `folder` (none when it does not exist), sorted.
pub(super) fn earlier_frames(folder: &Path) -> Result<Vec<PathBuf>, AppError> {
    let entries = match std::fs::read_dir(folder) {
        Ok(entries) => entries,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(error) => return Err(AppError::Failed(format!("{}: {error}", folder.display()))),
    };
    let mut frames: Vec<PathBuf> = entries
        .flatten()
        .filter(|entry| entry.file_name().to_str().is_some_and(is_frame_name))
        .map(|entry| entry.path())
        .collect();
    frames.sort();
    Ok(frames)
}
