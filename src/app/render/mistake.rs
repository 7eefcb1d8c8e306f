//! `masssprings render SCENE.json --mistake NAME -o OUT.gif`: the
//! handout's step (left) and a student's step with one of the usual
//! mistakes in it (right, `masssprings::sim::mistakes`), side by side, so
//! that the mistake's symptom shows against what the cloth should do.
//!
//! Both run from rest for the same steps. The left one is the handout's
//! functions as written (`--textbook`); the right one is the same code with
//! the mistake's line changed. One camera frames the rest shape and every
//! drawn step of the handout's run (and of the student's, unless that is
//! more than twice as large), and both panels are seen through it: a cloth
//! that falls out of the right panel, or leaves it in one step, does so
//! because the mistake throws it that far. When a mistaken step makes a
//! position infinite or NaN, the right panel keeps its last finite frame
//! and says from which step it stopped.
//!
//! `--size` is the size of the whole picture; each panel is half as wide
//! (`draw/panels.rs` puts them side by side). With `--json`, the figures
//! of the two runs (`masssprings::sim::mistakes::figures`) are printed
//! with the mistake's entry, as one JSON object: the numbers
//! `docs/mistakes.md` quotes of each picture. Cost: two simulations and
//! twice the frames of a plain `render`.

use crate::app::draw::camera::{BoundingBox, Camera};
use crate::app::draw::encode;
use crate::app::draw::frame::FrameRenderer;
use crate::app::draw::look::SUPERSAMPLING;
use crate::app::draw::panels::side_by_side;
use crate::app::draw::texture::Texture;
use crate::app::error::AppError;
use crate::app::limits::precompute;
use crate::app::progress::Progress;
use masssprings::files::write_file;
use masssprings::mesh::procedural::RgbImage;
use masssprings::mesh::Scene;
use masssprings::sim::mistakes::figures::{Figures, Measuring};
use masssprings::sim::mistakes::precomputation::precomputation;
use masssprings::sim::mistakes::simulation::StudentSimulation;
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::Sparse;
use std::path::Path;

/// What `render` asks of the picture.
pub struct Picture<'a> {
    pub scene_path: &'a Path,
    pub out: &'a Path,
    /// An animation (else a PNG of the last step).
    pub gif: bool,
    pub steps: usize,
    pub every: usize,
    /// The whole picture's size.
    pub size: (usize, usize),
    /// How the handout's simulation runs (wind, ordering, Δt).
    pub options: SimulationOptions,
    pub springs: bool,
    /// Print the entry and the figures as JSON (and no progress).
    pub json: bool,
}

/// The positions to draw, step 0 and every `every`-th step (a PNG: the
/// last), of both runs; and the step from which the student's was no
/// longer finite, if it stopped.
struct Runs {
    handout: Vec<Vec<[f64; 3]>>,
    student: Vec<Vec<[f64; 3]>>,
    stopped: Option<usize>,
    figures: Figures,
}

/// What `render --mistake NAME --json` prints.
#[derive(serde::Serialize)]
struct Report<'a> {
    out: String,
    frames: usize,
    mistake: &'a str,
    wrong: &'a str,
    right: &'a str,
    scene: String,
    steps: usize,
    /// The quantity `trace --compare` names first for it (gallery).
    first: &'a str,
    figures: Figures,
    /// The figure the gallery quotes, and its value in this run.
    quoted: Quoted<'a>,
}

#[derive(serde::Serialize)]
struct Quoted<'a> {
    measure: &'a str,
    words: &'a str,
    value: f64,
}

/// Draws the handout's step and `mistake` side by side into `picture.out`.
///
/// # Errors
/// A picture less than 2 pixels wide; a precomputation that fails (the
/// student's too: `pins-one-based` on a scene that pins its last vertex
/// names a vertex past the end); a write error.
pub fn run(
    picture: &Picture,
    scene: &Scene,
    texture: Option<Texture>,
    mistake: Mistake,
) -> Result<(), AppError> {
    let (width, height) = picture.size;
    if width < 2 {
        return Err(AppError::Usage(
            "--size: the picture holds two panels side by side; give a width of 2 or more".into(),
        ));
    }
    let runs = simulate(picture, scene, mistake)?;
    let images = draw(picture, scene, texture, &runs, mistake);
    let seconds_apart = picture.every as f64 * SimulationOptions::default().delta_t;
    write_file(picture.out, |out| {
        if picture.gif {
            encode::write_gif(out, &images, seconds_apart)
        } else {
            encode::write_png(out, images.last().expect("a frame"))
        }
    })?;
    if picture.json {
        print_json(picture, mistake, &runs, images.len());
        return Ok(());
    }
    let bytes = std::fs::metadata(picture.out).map_or(0, |m| m.len());
    println!(
        "wrote {} ({} frame(s) of {width}×{height}: the handout's step | {mistake}, {:.0} KiB)",
        picture.out.display(),
        images.len(),
        bytes as f64 / 1024.0
    );
    let (wrong, right) = (mistake.wrong(), mistake.right());
    println!("the mistake: {wrong} where the handout has {right}");
    if let Some(step) = runs.stopped {
        println!("the step with the mistake {mistake} made a position infinite or NaN at step {step}: its panel holds the last finite one");
    }
    Ok(())
}

/// The entry and the figures, as one JSON object on standard output.
fn print_json(picture: &Picture, mistake: Mistake, runs: &Runs, frames: usize) {
    let entry = mistake.entry();
    let figure = entry.figure;
    let report = Report {
        out: picture.out.display().to_string(),
        frames,
        mistake: entry.name,
        wrong: entry.wrong,
        right: entry.right,
        scene: picture.scene_path.display().to_string(),
        steps: picture.steps,
        first: entry.first,
        figures: runs.figures,
        quoted: Quoted {
            measure: figure.measure.name(),
            words: figure.quoted,
            value: runs.figures.get(figure.measure),
        },
    };
    let json = serde_json::to_string_pretty(&report).expect("plain values serialise");
    println!("{json}");
}

/// Runs the handout's step and the student's from rest, keeping the
/// frames to draw and measuring the figures.
fn simulate(picture: &Picture, scene: &Scene, mistake: Mistake) -> Result<Runs, AppError> {
    let handout_options = SimulationOptions {
        textbook: true,
        ..picture.options
    };
    let mut handout = precompute::<Sparse>(scene, picture.scene_path, handout_options)?;
    let mut student = student_simulation(picture, scene, mistake)?;
    let keep = |step: usize| {
        if picture.gif {
            step.is_multiple_of(picture.every)
        } else {
            step == picture.steps
        }
    };
    let mut runs = Runs {
        handout: Vec::new(),
        student: Vec::new(),
        stopped: None,
        figures: Measuring::new(&scene.vertices, &scene.pinned).finish(),
    };
    let mut measuring = Measuring::new(&scene.vertices, &scene.pinned);
    let mut last_finite = student.positions().to_vec();
    let mut progress = Progress::new(picture.steps, !picture.json);
    for step in 0..=picture.steps {
        if step > 0 {
            handout
                .step()
                .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
            if runs.stopped.is_none() {
                if student.step() {
                    last_finite.copy_from_slice(student.positions());
                } else {
                    runs.stopped = Some(step);
                }
            }
            measuring.observe(handout.positions(), student.positions());
            progress.step_done(step);
        }
        if keep(step) {
            runs.handout.push(handout.positions().to_vec());
            runs.student.push(last_finite.clone());
        }
    }
    progress.finish();
    runs.figures = measuring.finish();
    Ok(runs)
}

/// The student's simulation of `scene`: the mistaken precomputation (its
/// failure named after the scene file), at rest.
fn student_simulation(
    picture: &Picture,
    scene: &Scene,
    mistake: Mistake,
) -> Result<StudentSimulation, AppError> {
    let options = &picture.options;
    let (v, e, m, b) = (
        &scene.vertices,
        &scene.springs,
        &scene.masses,
        &scene.pinned,
    );
    let pre = precomputation(
        mistake,
        v,
        e,
        scene.k,
        m,
        b,
        options.delta_t,
        options.ordering,
    )
    .map_err(|e| {
        AppError::Failed(format!(
            "{}: the precomputation with the mistake {mistake} failed: {e}",
            picture.scene_path.display()
        ))
    })?;
    Ok(StudentSimulation::new(mistake, pre, options.wind))
}

/// Every frame: the two panels side by side, labelled.
fn draw(
    picture: &Picture,
    scene: &Scene,
    texture: Option<Texture>,
    runs: &Runs,
    mistake: Mistake,
) -> Vec<RgbImage> {
    let (width, height) = (picture.size.0 / 2, picture.size.1);
    let camera = frame_both(scene, runs, width, height);
    let renderer = || {
        FrameRenderer::new(
            scene,
            texture.as_ref(),
            camera.clone(),
            (width, height),
            picture.springs,
        )
    };
    let mut left = renderer();
    let mut right = renderer();
    let stopped = runs
        .stopped
        .map(|step| format!("not finite from step {step}"));
    let labels = [
        "the handout's step".to_string(),
        format!("mistake: {mistake}"),
    ];
    let frames = runs.handout.iter().zip(&runs.student);
    let images = frames.enumerate().map(|(i, (handout, student))| {
        let panels = [left.render(handout), right.render(student)];
        // the warning shows from the first frame drawn after the stop
        let late = runs.stopped.filter(|&s| i * picture.every >= s);
        side_by_side(&panels, &labels, late.and(stopped.as_deref()))
    });
    images.collect()
}

/// The camera both panels share: it frames the rest shape and every drawn
/// step of the handout's run, and the student's too when they stay within
/// twice that box's size (a cloth thrown far away would shrink the
/// handout's to a dot; it leaves the picture instead).
fn frame_both(scene: &Scene, runs: &Runs, width: usize, height: usize) -> Camera {
    let mut bounds = BoundingBox::empty();
    bounds.include(&scene.vertices);
    for positions in &runs.handout {
        bounds.include(positions);
    }
    let mut both = bounds;
    for positions in &runs.student {
        both.include(positions);
    }
    if both.diagonal() <= 2.0 * bounds.diagonal() {
        bounds = both;
    }
    Camera::framing(&bounds, SUPERSAMPLING * width, SUPERSAMPLING * height)
}
