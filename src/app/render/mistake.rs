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
//! because the mistake throws it that far. When a mistaken step
//! makes a position infinite or NaN, the right panel keeps its last finite
//! frame and says from which step it stopped.
//!
//! `--size` is the size of the whole picture; each panel is half as wide.
//! Cost: two simulations and twice the frames of a plain `render`.

use super::camera::{BoundingBox, Camera};
use super::canvas::Canvas;
use super::frame::FrameRenderer;
use super::look::{Rgb, SPRING, SUPERSAMPLING};
use super::text::{draw_text, text_height, Align};
use super::texture::Texture;
use super::{Format, Request};
use crate::app::limits::{check_frames, precompute};
use crate::app::progress::Progress;
use crate::app::AppError;
use masssprings::files::write_file;
use masssprings::mesh::procedural::RgbImage;
use masssprings::mesh::Scene;
use masssprings::sim::mistakes::precomputation::precomputation;
use masssprings::sim::mistakes::step::StudentSimulation;
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::Sparse;

/// The positions to draw, step 0 and every `every`-th step (a PNG: the
/// last), of both runs; and the step from which the student's was no
/// longer finite, if it stopped.
struct Runs {
    handout: Vec<Vec<[f64; 3]>>,
    student: Vec<Vec<[f64; 3]>>,
    stopped: Option<usize>,
}

/// Draws the handout's step and `mistake` side by side into `request.out`.
///
/// # Errors
/// A scene that cannot be read or precomputed (the student's precomputation
/// too: `pins-one-based` on a scene that pins its last vertex names a
/// vertex past the end), a picture that would not fit in memory, a write
/// error.
pub fn run(request: &Request, mistake: Mistake) -> Result<(), AppError> {
    if request.width < 2 {
        return Err(AppError::Usage(
            "--size: the picture holds two panels side by side; give a width of 2 or more".into(),
        ));
    }
    let scene = super::super::load_scene(&request.scene)?;
    let mut plan = masssprings::files::FilePlan::default();
    super::super::plan_scene_inputs(&mut plan, &request.scene, &scene);
    plan.output("-o", &request.out).check()?;
    let panel = (request.width / 2, request.height);
    check_frames(
        2 * request.kept_frames(),
        super::frame_bytes(scene.vertices.len(), panel.0, panel.1),
        "draw fewer frames (fewer --steps, a larger --every, or a .png of the last step)",
    )?;
    let runs = simulate(&scene, request, mistake)?;
    let images = draw(&scene, request, &runs, mistake, panel)?;
    let seconds_apart = request.every as f64 * SimulationOptions::default().delta_t;
    write_file(&request.out, |out| match request.format {
        Format::Gif => super::encode::write_gif(out, &images, seconds_apart),
        Format::Png => super::encode::write_png(out, images.last().expect("a frame")),
    })?;
    let bytes = std::fs::metadata(&request.out).map_or(0, |m| m.len());
    println!(
        "wrote {} ({} frame(s) of {}×{}: the handout's step | {mistake}, {:.0} KiB)",
        request.out.display(),
        images.len(),
        request.width,
        request.height,
        bytes as f64 / 1024.0
    );
    println!(
        "the mistake: {} where the handout has {}",
        mistake.wrong(),
        mistake.right()
    );
    if let Some(step) = runs.stopped {
        println!("the step with the mistake {mistake} made a position infinite or NaN at step {step}: its panel holds the last finite one");
    }
    Ok(())
}

/// Runs the handout's step and the student's from rest, keeping the
/// frames to draw.
fn simulate(scene: &Scene, request: &Request, mistake: Mistake) -> Result<Runs, AppError> {
    let handout_options = SimulationOptions {
        textbook: true,
        ..request.options
    };
    let mut handout = precompute::<Sparse>(scene, &request.scene, handout_options)?;
    let mut student = student_simulation(scene, request, mistake)?;
    let keep = |step: usize| match request.format {
        Format::Gif => step.is_multiple_of(request.every),
        Format::Png => step == request.steps,
    };
    let mut runs = Runs {
        handout: Vec::new(),
        student: Vec::new(),
        stopped: None,
    };
    let mut last_finite = student.positions().to_vec();
    let mut progress = Progress::new(request.steps, !request.json);
    for step in 0..=request.steps {
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
            progress.step_done(step);
        }
        if keep(step) {
            runs.handout.push(handout.positions().to_vec());
            runs.student.push(last_finite.clone());
        }
    }
    progress.finish();
    Ok(runs)
}

/// The student's simulation of `scene`: the mistaken precomputation (its
/// failure named after the scene file), at rest.
fn student_simulation(
    scene: &Scene,
    request: &Request,
    mistake: Mistake,
) -> Result<StudentSimulation, AppError> {
    let pre = precomputation(
        mistake,
        &scene.vertices,
        &scene.springs,
        scene.k,
        &scene.masses,
        &scene.pinned,
        request.options.delta_t,
        request.options.ordering,
    )
    .map_err(|e| {
        AppError::Failed(format!(
            "{}: the precomputation with the mistake {mistake} failed: {e}",
            request.scene.display()
        ))
    })?;
    Ok(StudentSimulation::new(mistake, pre, request.options.wind))
}

/// Every frame: the two panels side by side, labelled.
fn draw(
    scene: &Scene,
    request: &Request,
    runs: &Runs,
    mistake: Mistake,
    (width, height): (usize, usize),
) -> Result<Vec<RgbImage>, AppError> {
    let camera = frame_both(scene, runs, width, height);
    let renderer = |texture| {
        FrameRenderer::new(
            scene,
            texture,
            camera.clone(),
            (width, height),
            request.springs,
        )
    };
    let mut left = renderer(texture(scene)?);
    let mut right = renderer(texture(scene)?);
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
        let late = runs.stopped.filter(|&s| i * request.every >= s);
        side_by_side(&panels, &labels, late.and(stopped.as_deref()))
    });
    Ok(images.collect())
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

/// The scene's texture, when it has one to show.
fn texture(scene: &Scene) -> Result<Option<Texture>, AppError> {
    match &scene.texture {
        Some(path) if !scene.face_texture_coords.is_empty() => {
            Ok(Some(Texture::read_png(path).map_err(AppError::Failed)?))
        }
        _ => Ok(None),
    }
}

/// Ink of the labels.
const LABEL: Rgb = SPRING;

/// `panels[0] | panels[1]` (the same height), each with its label at the
/// top left, a one-pixel rule between them, and `warning` at the bottom of
/// the right one.
fn side_by_side(panels: &[RgbImage; 2], labels: &[String; 2], warning: Option<&str>) -> RgbImage {
    let (width, height) = (panels[0].width as usize, panels[0].height as usize);
    let mut canvas = Canvas::new(2 * width, height);
    for (k, panel) in panels.iter().enumerate() {
        for (i, rgb) in panel.pixels.chunks_exact(3).enumerate() {
            let at = canvas.index(k * width + i % width, i / width);
            canvas.colour[at] = std::array::from_fn(|c| f32::from(rgb[c]) / 255.0);
        }
        let x = (k * width + 4) as isize;
        draw_text(&mut canvas, &labels[k], (x, 4), 1, Align::Start, LABEL);
    }
    for y in 0..height {
        let at = canvas.index(width, y);
        canvas.colour[at] = LABEL;
    }
    if let Some(warning) = warning {
        let top = height.saturating_sub(text_height(1) + 4) as isize;
        let x = (width + 4) as isize;
        draw_text(&mut canvas, warning, (x, top), 1, Align::Start, LABEL);
    }
    canvas.downsample(1)
}
