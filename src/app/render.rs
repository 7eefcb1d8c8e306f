//! `masssprings render SCENE.json -o OUT.gif|OUT.png`: simulate a scene and
//! draw it with the software renderer of `draw/`, which has the viewer's
//! look, into an animated GIF or a PNG of the last frame.
//!
//! The pipeline:
//!
//! 1. simulate `N` steps, keeping the positions of step 0 and every `K`-th
//!    step (for a PNG: of step `N` only);
//! 2. frame them all with one camera (`draw/camera.rs`): the bounding box
//!    of the rest shape and of every kept frame, so the picture does not
//!    jump;
//! 3. draw each frame (`draw/frame.rs`);
//! 4. encode (`draw/encode.rs`) and write the file all or nothing (a
//!    temporary file renamed into place, `masssprings::files::write_file`).
//!
//! Nothing is written unless every step succeeds.

mod mistake;

use super::draw::camera::{BoundingBox, Camera};
use super::draw::encode;
use super::draw::frame::FrameRenderer;
use super::draw::look::SUPERSAMPLING;
use super::draw::texture::Texture;
use super::error::AppError;
use super::file_plan::{load_scene, plan_scene_inputs};
use super::flags::{choice, size, whole, JsonFlag, SimulationFlags, Size};
use super::limits::{check_frames, check_picture, picture_bytes, precompute};
use super::progress::Progress;
use super::timing::median;
use masssprings::files::{write_file, FilePlan};
use masssprings::mesh::procedural::RgbImage;
use masssprings::mesh::Scene;
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Sparse};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The largest width or height accepted by `--size`.
const MAX_SIDE: usize = 2048;

/// What to write.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    /// An animation of every `every`-th step.
    Gif,
    /// The last step only.
    Png,
}

/// The command line of `render`, checked.
struct Request {
    scene: PathBuf,
    out: PathBuf,
    format: Format,
    steps: usize,
    every: usize,
    width: usize,
    height: usize,
    dense: bool,
    /// How the simulation runs (wind, method, tolerance).
    options: SimulationOptions,
    springs: bool,
    /// Which positions the camera frames: `rest`, `last` or `all`.
    fit: String,
    json: bool,
    /// Draw the handout's step beside this mistake's (`mistake.rs`).
    mistake: Option<Mistake>,
}

/// What `render --json` prints.
#[derive(Debug, serde::Serialize)]
struct Summary {
    out: String,
    frames: usize,
    width: usize,
    height: usize,
    steps: usize,
    bytes: u64,
    simulation_s: f64,
    render_frame_median_s: f64,
    encode_s: f64,
    fit: String,
}

/// Draw a simulated scene into a looping GIF, or its last step into a PNG.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Simulates N steps and draws step 0 and every K-th step with the viewer's
look into a looping GIF that plays in real time, or draws the last step into
a PNG. Cloths show their surface and pins; --springs adds every spring and
point mass (always drawn for scenes made only of springs). Shows progress
on standard error (none with --json).

With --mistake NAME, draws the handout's step (left) beside the same step with
one of the usual mistakes made in it (right), in one picture of --size:
docs/mistakes.md shows every one and what it looks like. With --json too, prints
the mistake's entry and the figures of the two runs that the gallery quotes
(lowest point, farthest move, pins moved, extent, distance apart, swing, first
bottom, first step not finite).")]
pub struct RenderArgs {
    /// The scene: JSON that names an OBJ (data/README.md).
    #[arg(value_name = "SCENE.json")]
    scene: PathBuf,
    /// The picture: .gif (an animation) or .png (the last step).
    #[arg(short, long, value_name = "OUT", required = true)]
    out: PathBuf,
    /// Time steps to simulate.
    #[arg(long, value_name = "N", default_value = "100", value_parser = whole(0, usize::MAX))]
    steps: usize,
    /// Draw every K-th step into the GIF.
    #[arg(long, value_name = "K", default_value = "1", value_parser = whole(1, usize::MAX))]
    every: usize,
    /// Picture size in pixels.
    #[arg(long, value_name = "WxH", default_value = "480x360", value_parser = size(1, MAX_SIDE))]
    size: Size,
    /// Add the assignment viewer's wind to gravity.
    #[arg(long)]
    wind: bool,
    /// Draw every spring and point mass too.
    #[arg(long)]
    springs: bool,
    /// What the camera frames: the rest shape, the last step drawn, or the rest shape and every step drawn.
    #[arg(long, value_name = "F", default_value = "all", value_parser = ["rest", "last", "all"])]
    fit: String,
    /// Draw the handout's step beside the same step with one of the usual mistakes in it (docs/mistakes.md).
    #[arg(long, value_name = "NAME", value_parser = choice::<Mistake>(&Mistake::ALL.map(Mistake::name)), conflicts_with_all = ["fit", "dense"])]
    mistake: Option<Mistake>,
    #[command(flatten)]
    json: JsonFlag,
    #[command(flatten)]
    simulation: SimulationFlags,
}

/// Simulates, frames, draws, writes and reports: `render`'s steps.
pub fn run(args: RenderArgs) -> Result<(), AppError> {
    let request = parse(args)?;
    let scene = load_scene(&request.scene)?;
    check_files(&request, &scene)?;
    let texture = read_texture(&scene)?;
    if let Some(mistake) = request.mistake {
        return mistake::run(&picture(&request), &scene, texture, mistake);
    }
    let started = Instant::now();
    let frames = if request.dense {
        simulate::<Dense>(&scene, &request)?
    } else {
        simulate::<Sparse>(&scene, &request)?
    };
    let simulation_s = started.elapsed().as_secs_f64();
    let camera = frame_camera(&request, &scene, &frames);
    let (images, mut frame_times) = draw_frames(&request, &scene, texture, camera, &frames);
    let started = Instant::now();
    write(&request, &images)?;
    let summary = Summary {
        out: request.out.display().to_string(),
        frames: images.len(),
        width: request.width,
        height: request.height,
        steps: request.steps,
        bytes: std::fs::metadata(&request.out).map_or(0, |m| m.len()),
        simulation_s,
        render_frame_median_s: median(&mut frame_times),
        encode_s: started.elapsed().as_secs_f64(),
        fit: request.fit.clone(),
    };
    print_summary(&request, &summary);
    Ok(())
}

/// Refuses an output that would overwrite an input, and a run whose kept
/// frames would not fit in memory, before any work is done.
fn check_files(request: &Request, scene: &Scene) -> Result<(), AppError> {
    let mut plan = FilePlan::default();
    plan_scene_inputs(&mut plan, &request.scene, scene);
    plan.output("-o", &request.out).check()?;
    check_memory(request, scene.vertices.len())
}

/// The scene's texture, when it has one and texture coordinates to use it.
fn read_texture(scene: &Scene) -> Result<Option<Texture>, AppError> {
    match &scene.texture {
        Some(path) if !scene.face_texture_coords.is_empty() => {
            Ok(Some(Texture::read_png(path).map_err(AppError::Failed)?))
        }
        _ => Ok(None),
    }
}

/// One camera for every frame (`--fit`): it frames the rest shape, the last
/// step drawn, or both and every step drawn, so the picture does not jump.
fn frame_camera(request: &Request, scene: &Scene, frames: &[Vec<[f64; 3]>]) -> Camera {
    let mut bounds = BoundingBox::empty();
    if request.fit != "last" {
        bounds.include(&scene.vertices);
    }
    match request.fit.as_str() {
        "rest" => {}
        "last" => bounds.include(frames.last().expect("at least one frame")),
        _ => {
            for positions in frames {
                bounds.include(positions);
            }
        }
    }
    let (width, height) = (
        SUPERSAMPLING * request.width,
        SUPERSAMPLING * request.height,
    );
    Camera::framing(&bounds, width, height)
}

/// Draws every frame; returns the pictures and the seconds each took.
fn draw_frames(
    request: &Request,
    scene: &Scene,
    texture: Option<Texture>,
    camera: Camera,
    frames: &[Vec<[f64; 3]>],
) -> (Vec<RgbImage>, Vec<f64>) {
    let size = (request.width, request.height);
    let mut renderer = FrameRenderer::new(scene, texture.as_ref(), camera, size, request.springs);
    let mut images = Vec::with_capacity(frames.len());
    let mut frame_times = Vec::with_capacity(frames.len());
    for positions in frames {
        let t = Instant::now();
        images.push(renderer.render(positions));
        frame_times.push(t.elapsed().as_secs_f64());
    }
    (images, frame_times)
}

/// Prints what was written and how long each part took (`--json`: as JSON).
fn print_summary(request: &Request, summary: &Summary) {
    if request.json {
        println!(
            "{}",
            serde_json::to_string(summary).expect("plain numbers serialise")
        );
        return;
    }
    let (width, height, frames) = (summary.width, summary.height, summary.frames);
    println!(
        "wrote {} ({frames} frame{} of {width}×{height}, {:.0} KiB)",
        request.out.display(),
        if frames == 1 { "" } else { "s" },
        summary.bytes as f64 / 1024.0
    );
    println!(
        "simulation {:.2} s, rendering {:.1} ms/frame (median), encoding {:.2} s",
        summary.simulation_s,
        1e3 * summary.render_frame_median_s,
        summary.encode_s
    );
}

/// How `args` asks the simulation to run.
pub(super) fn options(args: &RenderArgs) -> SimulationOptions {
    let mut options = SimulationOptions {
        wind: args.wind,
        ..SimulationOptions::default()
    };
    args.simulation.apply(&mut options);
    options
}

/// Checks the command line: usage errors before any work is done.
fn parse(args: RenderArgs) -> Result<Request, AppError> {
    let format = output_format(&args.out)?;
    let options = options(&args);
    Ok(Request {
        scene: args.scene,
        out: args.out,
        format,
        steps: args.steps,
        every: args.every,
        width: args.size.width,
        height: args.size.height,
        dense: args.simulation.backend.dense,
        options,
        springs: args.springs,
        fit: args.fit,
        json: args.json.json,
        mistake: args.mistake,
    })
}

/// What `render --mistake` draws, from the request.
fn picture(request: &Request) -> mistake::Picture<'_> {
    mistake::Picture {
        scene_path: &request.scene,
        out: &request.out,
        gif: request.format == Format::Gif,
        steps: request.steps,
        every: request.every,
        size: (request.width, request.height),
        options: request.options,
        springs: request.springs,
        json: request.json,
    }
}

impl Request {
    /// The runs drawn: one, or two beside a mistake.
    fn runs(&self) -> u128 {
        if self.mistake.is_some() {
            2
        } else {
            1
        }
    }

    /// The frames kept for the whole run: step 0 and every `every`-th step
    /// (GIF), or the last step (PNG); twice that beside a mistake; `None`
    /// past 64 bits.
    fn kept_frames(&self) -> Option<u64> {
        let runs = self.runs() as u64;
        let one_run = match self.format {
            Format::Gif => ((self.steps / self.every) as u64).checked_add(1)?,
            Format::Png => 1,
        };
        one_run.checked_mul(runs)
    }
}

/// Refuses, before any work, a run whose kept frames (of `n` vertices each)
/// or whose drawing canvas would not fit in memory.
fn check_memory(request: &Request, n: usize) -> Result<(), AppError> {
    let kept = request.kept_frames().ok_or_else(|| {
        AppError::Failed(format!(
            "--steps {} --every {}: {} frames to keep (step 0, then one every {} steps), \
             more than 64 bits count; draw fewer frames",
            request.steps,
            request.every,
            ((request.steps / request.every) as u128 + 1) * request.runs(),
            request.every
        ))
    })?;
    check_frames(
        kept,
        frame_bytes(n, request.width, request.height),
        "draw fewer frames (fewer --steps, a larger --every, or a .png of the last step)",
    )?;
    let (width, height) = (request.width, request.height);
    check_picture(picture_bytes(width, height, SUPERSAMPLING), || {
        format!("drawing a {width}×{height} frame")
    })?;
    Ok(())
}

/// The bytes one kept frame costs: its positions (24 bytes a vertex) and its
/// picture (3 bytes a pixel, and as much again for the palette indices and
/// the encoder).
fn frame_bytes(n: usize, width: usize, height: usize) -> u64 {
    (n as u64).saturating_mul(24) + (width * height * 6) as u64
}

/// GIF or PNG, from the output file's extension.
fn output_format(out: &Path) -> Result<Format, AppError> {
    let extension = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("gif") => Ok(Format::Gif),
        Some("png") => Ok(Format::Png),
        _ => Err(AppError::Usage(format!(
            "-o {}: the output must end in .gif (an animation) or .png (the last frame)",
            out.display()
        ))),
    }
}

/// Runs the simulation and returns the positions to draw: step 0 and every
/// `every`-th step for a GIF, step `steps` for a PNG.
fn simulate<B: LinearAlgebra>(
    scene: &Scene,
    request: &Request,
) -> Result<Vec<Vec<[f64; 3]>>, AppError> {
    let mut simulation = precompute::<B>(scene, &request.scene, request.options)?;
    let keep = |step: usize| match request.format {
        Format::Gif => step.is_multiple_of(request.every),
        Format::Png => step == request.steps,
    };
    let mut frames = Vec::new();
    let mut progress = Progress::new(request.steps, !request.json);
    for step in 0..=request.steps {
        if step > 0 {
            simulation
                .step()
                .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
        }
        if keep(step) {
            frames.push(simulation.positions().to_vec());
        }
        if step > 0 {
            progress.step_done(step);
        }
    }
    progress.finish();
    Ok(frames)
}

/// Writes the GIF of `images`, or the PNG of the last one, all or nothing.
fn write(request: &Request, images: &[RgbImage]) -> Result<(), AppError> {
    let seconds_apart = request.every as f64 * SimulationOptions::default().delta_t;
    write_file(&request.out, |out| match request.format {
        Format::Gif => encode::write_gif(out, images, seconds_apart),
        Format::Png => encode::write_png(out, images.last().expect("at least one frame")),
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extension_chooses_the_format() {
        assert_eq!(output_format(Path::new("a/b.GIF")).unwrap(), Format::Gif);
        assert_eq!(output_format(Path::new("b.png")).unwrap(), Format::Png);
        assert!(output_format(Path::new("b.bmp")).is_err());
        assert!(output_format(Path::new("gif")).is_err());
    }
}
