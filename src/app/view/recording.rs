//! A student's own animation beside ours: `view SCENE --frames DIR` reads
//! the OBJ files a program wrote, one per step from rest, and plays them
//! back as the second simulation of a comparison, one frame a step, while
//! ours steps beside it; the plot shows the distance between the two at
//! each step.
//!
//! The files are `frame-000000.obj`, `frame-000001.obj`, … as `simulate
//! --out` names them, or any numbered `*.obj` (`cloth_0.obj`, `cloth_1.obj`,
//! …; the numbering helper is the frames' own, `resume::frames`), read by
//! the crate's OBJ reader (`mesh::obj`): only their `v` lines count. Before
//! anything is drawn, the folder is refused, with a sentence saying why,
//! when it holds no numbered OBJ, numbered OBJs of two kinds, two files of
//! one number or a gap in the numbering, or a frame whose vertex count is
//! not the scene's; and the frames go through the memory rule before they
//! are read (`limits::check_frames`: frames × n × 24 bytes).
//!
//! A recording computes nothing: its step shows the next frame, and once
//! the frames run out it stays on the last one, saying so. What the status
//! asks of a simulation (its energy, its options) comes from a *mirror*:
//! a simulation of the scene held at the recording's state, so that both
//! energies are the same formula.

use super::solver::Run;
use crate::app::error::AppError;
use crate::app::limits::check_frames;
use crate::app::resume::frames::numbered_obj;
use masssprings::memory::{bytes_for, thousands};
use masssprings::mesh::obj::read_obj;
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{SimulationError, StepControl, StepMethod, StepReport, Stop};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The name a comparison with the recording goes by (`compare` and the
/// status).
pub const RECORDING: &str = "frames";

/// A program's frames, read and checked.
#[derive(Debug)]
pub struct Frames {
    /// The folder, as given.
    pub folder: PathBuf,
    /// The names of the first and the last file.
    pub first: String,
    pub last: String,
    /// The positions of each frame: step 0 (rest), 1, 2, …
    pub positions: Vec<Vec<[f64; 3]>>,
}

/// Reads the frames in `folder` for `scene` (read from `scene_path`).
///
/// # Errors
/// A failure naming the folder or the file and what is wrong: no numbered
/// OBJ, two kinds of names, two files of one number, a gap, a vertex count
/// other than the scene's (both counts), the memory rule's refusal, the
/// OBJ reader's errors.
pub fn read_frames(folder: &Path, scene: &Scene, scene_path: &Path) -> Result<Frames, AppError> {
    let names = numbered_names(folder)?;
    let n = scene.vertices.len();
    check_frames(
        names.len() as u64,
        bytes_for(n as u64, 24),
        "keep fewer frames in the folder",
    )?;
    let mut positions = Vec::with_capacity(names.len());
    for name in &names {
        let path = folder.join(name);
        let mesh = read_obj(&path).map_err(|error| AppError::Failed(error.to_string()))?;
        if mesh.vertices.len() != n {
            return Err(AppError::Failed(format!(
                "{}: {} vertices, but the scene {} has {}: these frames are not of this scene",
                path.display(),
                thousands(mesh.vertices.len() as u64),
                scene_path.display(),
                thousands(n as u64)
            )));
        }
        positions.push(mesh.vertices);
    }
    Ok(Frames {
        folder: folder.to_path_buf(),
        first: names[0].clone(),
        last: names[names.len() - 1].clone(),
        positions,
    })
}

/// The numbered OBJ files of `folder`, in the order of their numbers:
/// one kind of name, every number once, none missing.
fn numbered_names(folder: &Path) -> Result<Vec<String>, AppError> {
    let failed = |why: String| Err(AppError::Failed(format!("{}: {why}", folder.display())));
    let entries = match std::fs::read_dir(folder) {
        Ok(entries) => entries,
        Err(error) => return failed(format!("cannot read the folder: {error}")),
    };
    // The numbered names of each kind (the part before the number).
    let mut kinds: BTreeMap<String, BTreeMap<usize, Vec<String>>> = BTreeMap::new();
    for entry in entries.flatten() {
        let Ok(name) = entry.file_name().into_string() else {
            continue;
        };
        if let Some((prefix, number)) = numbered_obj(&name) {
            let numbers = kinds.entry(prefix.to_string()).or_default();
            numbers.entry(number).or_default().push(name);
        }
    }
    let mut kinds = kinds.into_iter();
    let (Some((_, numbers)), None) = (kinds.next(), kinds.next()) else {
        let found = kinds_found(folder)?;
        return failed(match found.is_empty() {
            true => "no numbered OBJ files (frame-000000.obj, frame-000001.obj, …: one per \
                     step from rest)"
                .into(),
            false => format!(
                "numbered OBJ files of {} kinds ({}): keep one animation in the folder",
                found.len(),
                found.join(", ")
            ),
        });
    };
    in_sequence(numbers).or_else(failed)
}

/// The kinds of numbered names in `folder`, as `frame-N.obj`.
fn kinds_found(folder: &Path) -> Result<Vec<String>, AppError> {
    let mut kinds: Vec<String> = std::fs::read_dir(folder)?
        .flatten()
        .filter_map(|entry| entry.file_name().into_string().ok())
        .filter_map(|name| numbered_obj(&name).map(|(prefix, _)| format!("{prefix}N.obj")))
        .collect();
    kinds.sort();
    kinds.dedup();
    Ok(kinds)
}

/// The names of `numbers` in order, or why they are not one frame a step.
fn in_sequence(numbers: BTreeMap<usize, Vec<String>>) -> Result<Vec<String>, String> {
    let mut names = Vec::with_capacity(numbers.len());
    let mut previous: Option<(usize, String)> = None;
    for (number, mut files) in numbers {
        if files.len() > 1 {
            files.sort();
            let all = if files.len() == 2 { "both" } else { "all" };
            return Err(format!(
                "{} {all} number step {number}",
                files.join(" and ")
            ));
        }
        let name = files.remove(0);
        if let Some((before, before_name)) = &previous {
            if number != before + 1 {
                return Err(format!(
                    "a gap in the numbering: {name} follows {before_name} (steps {} to {} are \
                     missing); write one frame per step",
                    before + 1,
                    number - 1
                ));
            }
        }
        previous = Some((number, name.clone()));
        names.push(name);
    }
    Ok(names)
}

/// The frames played back as a simulation.
pub struct Recording {
    frames: Arc<Frames>,
    /// A simulation of the scene held at the recording's state.
    mirror: Box<dyn Run>,
    steps: usize,
}

impl Recording {
    /// The recording of `frames` at step 0, its status kept by `mirror` (a
    /// simulation of the same scene).
    pub fn new(frames: Arc<Frames>, mirror: Box<dyn Run>) -> Recording {
        let mut recording = Recording {
            frames,
            mirror,
            steps: 0,
        };
        recording.show();
        recording
    }

    /// Puts the mirror at the frame of the current step (the last frame
    /// once they run out), moving from the one before.
    fn show(&mut self) {
        let frames = &self.frames.positions;
        let at = |step: usize| &frames[step.min(frames.len() - 1)];
        let (previous, current) = (at(self.steps.saturating_sub(1)), at(self.steps));
        self.mirror.set_state(previous, current, self.steps);
    }
}

impl Run for Recording {
    fn step(&mut self) -> Result<StepReport, SimulationError> {
        self.steps += 1;
        self.show();
        Ok(StepReport {
            method: StepMethod::Plain,
            iterations: 0,
            stop: Stop::Iterations,
            energy_decrease: None,
            relative_gradient: None,
        })
    }
    fn positions(&self) -> &[[f64; 3]] {
        self.mirror.positions()
    }
    fn previous_positions(&self) -> &[[f64; 3]] {
        self.mirror.previous_positions()
    }
    fn rest_positions(&self) -> &[[f64; 3]] {
        self.mirror.rest_positions()
    }
    fn pinned(&self) -> &[usize] {
        self.mirror.pinned()
    }
    fn steps(&self) -> usize {
        self.steps
    }
    fn time(&self) -> f64 {
        self.mirror.time()
    }
    fn options(&self) -> &SimulationOptions {
        self.mirror.options()
    }
    fn k(&self) -> f64 {
        self.mirror.k()
    }
    fn mass_scale(&self) -> f64 {
        self.mirror.mass_scale()
    }
    fn mechanical_energy(&self) -> f64 {
        self.mirror.mechanical_energy()
    }
    fn set_wind(&mut self, wind: bool) {
        self.mirror.set_wind(wind);
    }
    /// The mirror's, so that the energy is measured with ours' `k` and
    /// masses; the frames stay what they are.
    fn set_parameters(&mut self, k: f64, delta_t: f64, mass_scale: f64) -> Result<(), String> {
        self.mirror.set_parameters(k, delta_t, mass_scale)
    }
    fn set_step(&mut self, _: StepControl) -> Result<(), String> {
        Ok(())
    }
    /// A recording's state is its step: the positions are its frames'.
    fn set_state(&mut self, _: &[[f64; 3]], _: &[[f64; 3]], steps: usize) {
        self.steps = steps;
        self.show();
    }
    fn set_time(&mut self, time: f64) {
        self.mirror.set_time(time);
    }
    fn reset(&mut self) -> Result<(), String> {
        self.set_state(&[], &[], 0);
        Ok(())
    }
    /// Nothing pulls a recording: a drag moves ours only.
    fn start_drag(&mut self, _: usize, _: [f64; 3]) -> Result<(), String> {
        Ok(())
    }
    fn drag_to(&mut self, _: [f64; 3]) -> Result<(), String> {
        Ok(())
    }
    fn end_drag(&mut self) -> Result<(), String> {
        Ok(())
    }
    fn dragged(&self) -> Option<usize> {
        None
    }
    fn past_its_end(&self) -> bool {
        self.steps >= self.frames.positions.len()
    }
    fn solver_name(&self) -> Option<&'static str> {
        Some(RECORDING)
    }
    fn path(&self) -> String {
        format!(
            "your program's frames, read from {}: {} … {} ({} steps)",
            self.frames.folder.display(),
            self.frames.first,
            self.frames.last,
            self.frames.positions.len() - 1
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbers(names: &[&str]) -> BTreeMap<usize, Vec<String>> {
        let mut numbers: BTreeMap<usize, Vec<String>> = BTreeMap::new();
        for name in names {
            let (_, number) = numbered_obj(name).unwrap();
            numbers.entry(number).or_default().push(name.to_string());
        }
        numbers
    }

    #[test]
    fn frames_must_be_one_a_step() {
        let fine = in_sequence(numbers(&["c1.obj", "c2.obj", "c3.obj"])).unwrap();
        assert_eq!(fine, ["c1.obj", "c2.obj", "c3.obj"]);
        let gap = in_sequence(numbers(&["c0.obj", "c1.obj", "c5.obj"])).unwrap_err();
        assert!(gap.contains("c5.obj follows c1.obj (steps 2 to 4"), "{gap}");
        let twice = in_sequence(numbers(&["c1.obj", "c01.obj"])).unwrap_err();
        assert!(
            twice.contains("c01.obj and c1.obj both number step 1"),
            "{twice}"
        );
    }
}
