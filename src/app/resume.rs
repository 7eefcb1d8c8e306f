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
//!   first line ([`frames`]); a rounded frame would continue a
//!   slightly different run.
//!
//! Some methods also carry something from one step to the next: Chebyshev
//! its estimate of `ρ`, Newton its damping. Each frame's second line, the
//! run's record, holds it as it was after the frame's step, with what the
//! run must share with the run it continues: the vertex count, `k`, `Δt`,
//! the rest positions, the springs, the masses, the pins and the flags
//! that decide the step (all that makes the trajectory). A resume whose
//! scene or flags differ in any of them is refused, naming each; so is a
//! folder holding the frames of two runs (each record names its run).
//!
//! With all of it, `Simulation::set_state(U_prev, U_cur, step)` and
//! `Simulation::carry` put the simulation where the run stopped, and the
//! next step gives the same bits as a run that never stopped
//! (`tests/app/resume.rs`, every method). Step 0 alone resumes as the start:
//! before step 0 the cloth was at rest, `U_prev = U_cur`.

pub mod folder;
pub mod frames;

use super::error::AppError;
use folder::{earlier_frames, head, not_a_file, not_a_folder};
use frames::{check_carried, frame_name, frame_step, parse_frame, RunRecord};
use masssprings::files::{read_text, shown};
use masssprings::mesh::Scene;
use masssprings::sim::methods::Carried;
use std::fs;
use std::path::Path;

/// The state a run stopped in.
pub struct Resumed {
    /// The last frame's step.
    pub step: usize,
    /// The positions one step before it.
    pub u_prev: Vec<[f64; 3]>,
    /// The last frame's positions.
    pub u_cur: Vec<[f64; 3]>,
    /// What the step's methods carried after the last frame's step.
    pub carried: Carried,
    /// The run the frames are of (its record's `run`; `None` for frames
    /// that do not say).
    pub run: Option<String>,
}

/// The state of the run whose frames are in `folder`: its last frame and
/// the one a step before it, both exact frames of `scene` written by a run
/// whose record is `record` (the resumed run's, before any step).
///
/// # Errors
/// A sentence naming the folder or the frame: no folder, no frames, a
/// frame that is not a regular file, the frame a step before the last
/// missing (written with `--every K > 1`), a rounded frame (written with
/// `--precision`), a frame of another scene, step or run (another `k`,
/// `Δt`, rest positions, springs, masses, pins or flags, each named),
/// frames of two runs in the folder, or the OBJ reader's error (file,
/// line).
pub fn last_state(folder: &Path, scene: &Scene, record: &RunRecord) -> Result<Resumed, AppError> {
    if !folder.is_dir() {
        return Err(not_a_folder(folder));
    }
    let frames = earlier_frames(folder)?;
    let last = frames.iter().filter_map(|path| step_of(path)).max();
    let Some(step) = last else {
        return Err(AppError::Failed(format!(
            "--resume {}: no frames (frame-NNNNNN.obj) to continue from",
            shown(folder)
        )));
    };
    refuse_two_runs(folder, &frames)?;
    let last = read_exact_frame(folder, step, scene, record)?;
    let (u_cur, carried, run) = (last.positions, last.carried, last.run);
    let u_prev = match step.checked_sub(1) {
        None => u_cur.clone(),
        Some(before) => {
            let path = folder.join(frame_name(before));
            if fs::symlink_metadata(&path).is_err() {
                return Err(AppError::Failed(format!(
                    "--resume {}: {} is missing: a step needs the last frame ({}) and the one a \
                     step before it; a run written with --every K > 1 keeps only every K-th step \
                     and cannot be resumed exactly",
                    shown(folder),
                    frame_name(before),
                    frame_name(step)
                )));
            }
            read_exact_frame(folder, before, scene, record)?.positions
        }
    };
    Ok(Resumed {
        step,
        u_prev,
        u_cur,
        carried,
        run,
    })
}

/// Refuses a folder whose frames are of two runs (by their records'
/// `run`): continuing the last would leave a mixture.
fn refuse_two_runs(folder: &Path, frames: &[std::path::PathBuf]) -> Result<(), AppError> {
    let mut runs: Vec<(Option<String>, Vec<usize>)> = Vec::new();
    for path in frames {
        let Some(head) = head(path) else { continue };
        let run = head.record.and_then(|r| r.run);
        match runs.iter_mut().find(|(r, _)| *r == run) {
            Some((_, steps)) => steps.push(head.step),
            None => runs.push((run, vec![head.step])),
        }
    }
    if runs.len() < 2 {
        return Ok(());
    }
    let described: Vec<String> = runs
        .iter()
        .map(|(run, steps)| {
            let (first, last) = (steps.iter().min(), steps.iter().max());
            let who = run
                .as_deref()
                .map_or("a run that does not say which".into(), |r| {
                    format!("run {}", masssprings::files::escaped(r))
                });
            format!(
                "{} frame(s) of {who} (steps {} to {})",
                steps.len(),
                first.unwrap_or(&0),
                last.unwrap_or(&0)
            )
        })
        .collect();
    Err(AppError::Failed(format!(
        "--resume {}: the folder holds the frames of {} runs: {}; move away the frames of the          run not to continue (or run again with --force)",
        shown(folder),
        runs.len(),
        described.join("; ")
    )))
}

/// The last step of a run resumed at `step` for `more` steps.
///
/// # Errors
/// When it would pass the largest step a frame can be numbered with
/// (`usize::MAX`), before any work.
pub fn last_step(folder: &Path, step: usize, more: usize) -> Result<usize, AppError> {
    step.checked_add(more).ok_or_else(|| {
        let room = match usize::MAX - step {
            0 => "the run cannot go on".to_string(),
            left => format!("give --steps {left} or fewer"),
        };
        AppError::Failed(format!(
            "--resume {}: the run is at step {step}; --steps {more} would pass the largest \
             step number a frame can carry, {}; {room}",
            shown(folder),
            usize::MAX,
        ))
    })
}

/// The positions of frame `step` in `folder` and what the methods carried
/// after its step, if it is a regular file, an exact frame of `scene`'s
/// run with `record`, and has one position per vertex.
fn read_exact_frame(
    folder: &Path,
    step: usize,
    scene: &Scene,
    record: &RunRecord,
) -> Result<ExactFrame, AppError> {
    let path = folder.join(frame_name(step));
    let refuse = |why: String| Err(AppError::Failed(format!("{}: {why}", shown(&path))));
    if let Some(kind) = not_a_file(&path) {
        return refuse(format!("this is {kind}, not a frame"));
    }
    let text = read_text(&path)?;
    let frame = parse_frame(&text).map_err(|e| e.in_file(&path))?;
    if frame.scene != scene.name || frame.step != step {
        return refuse(format!(
            "a frame of another scene or step ({} at step {}), not of {} at step {step}",
            masssprings::files::escaped(&frame.scene),
            frame.step,
            masssprings::files::escaped(&scene.name)
        ));
    }
    if frame.precision.is_some() {
        return refuse(
            "its positions are rounded (written with --precision), so the run cannot be resumed \
             exactly; write frames without --precision to resume"
                .into(),
        );
    }
    let Some(written) = frame.record else {
        return refuse(
            "it has no run record on its second line, so nothing says which k, Δt, \
                       rest positions, masses, pins and flags the run had"
                .into(),
        );
    };
    if let Err(why) = check_record(&written, record) {
        return refuse(why);
    }
    if frame.positions.len() != scene.vertices.len() {
        return refuse(format!(
            "{} vertices, but the scene {} has {}",
            frame.positions.len(),
            scene.name,
            scene.vertices.len()
        ));
    }
    Ok(ExactFrame {
        positions: frame.positions,
        carried: written.carried,
        run: written.run,
    })
}

/// Refuses a frame's run record `written` that another run wrote (other
/// settings than `record`'s, each named) or that no run writes.
fn check_record(written: &RunRecord, record: &RunRecord) -> Result<(), String> {
    let differences = written.differences(record);
    if !differences.is_empty() {
        return Err(format!(
            "the frames are of a run with other settings: {}; resume with the scene and the \
             flags of that run",
            differences.join(", ")
        ));
    }
    check_carried(&written.carried).map_err(|problem| {
        format!("its run record holds what no run carries: {problem} (the file was edited?)")
    })
}

/// A frame read back exactly: its positions, what the methods carried
/// after its step, and the run it names.
struct ExactFrame {
    positions: Vec<[f64; 3]>,
    carried: Carried,
    run: Option<String>,
}

/// The step of the frame at `path` (`frame-000012.obj`: 12).
fn step_of(path: &Path) -> Option<usize> {
    frame_step(path.file_name()?.to_str()?)
}
