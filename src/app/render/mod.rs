//! `masssprings render SCENE.json -o OUT.gif|OUT.png`: simulate a scene and
//! draw it with a small software renderer that has the viewer's look
//! (`look.rs`), into an animated GIF or a PNG of the last frame.
//!
//! The pipeline, one file per step:
//!
//! 1. simulate `N` steps, keeping the positions of step 0 and every `K`-th
//!    step (for a PNG: of step `N` only);
//! 2. frame them all with one camera (`camera.rs`): the bounding box of the
//!    rest shape and of every kept frame, so the picture does not jump;
//! 3. draw each frame (`frame.rs`): background (`canvas.rs`), surfaces
//!    (`triangle.rs`, `lighting.rs`, `texture.rs`), springs (`lines.rs`),
//!    point masses (`discs.rs`), at 2× and filtered down;
//! 4. encode (`palette.rs`, `encode.rs`) and write the file all or nothing
//!    (a temporary file renamed into place, `masssprings::files::write_file`).
//!
//! Nothing is written unless every step succeeds. This is teaching code:
//! a rasterizer in a few hundred lines, written for reading, not a
//! production renderer (no clipping against the near plane: the camera
//! keeps the whole scene in front of it; no mipmaps; no shadows).

mod camera;
mod canvas;
mod discs;
pub(super) mod encode;
mod frame;
mod lighting;
mod lines;
mod look;
mod palette;
pub(super) mod plot;
pub(super) mod sparsity;
mod text;
mod texture;
mod triangle;
mod vector;

#[cfg(test)]
#[path = "../../../tests/common/mod.rs"]
mod tests_common;

use super::args::Args;
use super::convergence_flags;
use super::timing::median;
use super::AppError;
use camera::{BoundingBox, Camera};
use frame::FrameRenderer;
use look::SUPERSAMPLING;
use masssprings::files::write_file;
use masssprings::mesh::procedural::RgbImage;
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Simulation, Sparse};
use std::path::{Path, PathBuf};
use std::time::Instant;
use texture::Texture;

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
}

pub fn run(args: &[String]) -> Result<(), AppError> {
    let request = parse(args)?;
    let scene = load_scene(&request.scene)?;
    let texture = match &scene.texture {
        Some(path) if !scene.face_texture_coords.is_empty() => {
            Some(Texture::read_png(path).map_err(AppError::Failed)?)
        }
        _ => None,
    };
    let started = Instant::now();
    let frames = if request.dense {
        simulate::<Dense>(&scene, &request)?
    } else {
        simulate::<Sparse>(&scene, &request)?
    };
    let simulation_s = started.elapsed().as_secs_f64();

    let mut bounds = BoundingBox::empty();
    bounds.include(&scene.vertices);
    for positions in &frames {
        bounds.include(positions);
    }
    let (width, height) = (request.width, request.height);
    let camera = Camera::framing(&bounds, SUPERSAMPLING * width, SUPERSAMPLING * height);
    let mut renderer =
        FrameRenderer::new(&scene, texture, camera, (width, height), request.springs);
    let mut images = Vec::with_capacity(frames.len());
    let mut frame_times = Vec::with_capacity(frames.len());
    for positions in &frames {
        let t = Instant::now();
        images.push(renderer.render(positions));
        frame_times.push(t.elapsed().as_secs_f64());
    }

    let started = Instant::now();
    write(&request, &images)?;
    let bytes = std::fs::metadata(&request.out).map_or(0, |m| m.len());
    println!(
        "wrote {} ({} frame{} of {width}×{height}, {:.0} KiB)",
        request.out.display(),
        images.len(),
        if images.len() == 1 { "" } else { "s" },
        bytes as f64 / 1024.0
    );
    println!(
        "simulation {simulation_s:.2} s, rendering {:.1} ms/frame (median), encoding {:.2} s",
        1e3 * median(&mut frame_times),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Checks the command line: usage errors before any work is done.
fn parse(args: &[String]) -> Result<Request, AppError> {
    // `-o FILE` is the short form of `--out FILE`.
    let args: Vec<String> = args
        .iter()
        .map(|a| if a == "-o" { "--out".into() } else { a.clone() })
        .collect();
    let mut options = vec!["steps", "every", "size", "out"];
    options.extend(convergence_flags::OPTIONS);
    let args = Args::parse(&args, &options, &["dense", "wind", "springs"])?;
    let mut simulation_options = SimulationOptions {
        wind: args.switch("wind"),
        ..SimulationOptions::default()
    };
    convergence_flags::apply(&args, &mut simulation_options)?;
    let scene = PathBuf::from(args.single_positional("SCENE.json")?);
    let out = PathBuf::from(args.value_or("out", String::new())?);
    if out.as_os_str().is_empty() {
        return Err(AppError::Usage("missing -o OUT.gif or -o OUT.png".into()));
    }
    let format = output_format(&out)?;
    let every = args.value_or("every", 2usize)?;
    if every == 0 {
        return Err(AppError::Usage("--every must be at least 1".into()));
    }
    let (width, height) = parse_size(&args.value_or("size", "480x360".to_string())?)?;
    Ok(Request {
        scene,
        out,
        format,
        steps: args.value_or("steps", 100usize)?,
        every,
        width,
        height,
        dense: args.switch("dense"),
        options: simulation_options,
        springs: args.switch("springs"),
    })
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

/// `WxH` (or `W×H`), each side from 1 to `MAX_SIDE`.
fn parse_size(text: &str) -> Result<(usize, usize), AppError> {
    let side = |s: &str| {
        s.trim()
            .parse::<usize>()
            .ok()
            .filter(|n| (1..=MAX_SIDE).contains(n))
    };
    let parts = text.split_once(['x', 'X', '×']);
    match parts.and_then(|(w, h)| Some((side(w)?, side(h)?))) {
        Some(size) => Ok(size),
        None => Err(AppError::Usage(format!(
            "--size {text}: expected WIDTHxHEIGHT, each from 1 to {MAX_SIDE} (e.g. 480x360)"
        ))),
    }
}

/// Runs the simulation and returns the positions to draw: step 0 and every
/// `every`-th step for a GIF, step `steps` for a PNG.
fn simulate<B: LinearAlgebra>(
    scene: &Scene,
    request: &Request,
) -> Result<Vec<Vec<[f64; 3]>>, AppError> {
    let mut simulation = Simulation::<B>::from_scene(scene, request.options)?;
    let keep = |step: usize| match request.format {
        Format::Gif => step.is_multiple_of(request.every),
        Format::Png => step == request.steps,
    };
    let mut frames = Vec::new();
    let mut last_report = Instant::now();
    for step in 0..=request.steps {
        if step > 0 {
            simulation
                .step()
                .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
        }
        if keep(step) {
            frames.push(simulation.positions().to_vec());
        }
        if last_report.elapsed().as_secs_f64() > 1.0 {
            eprintln!("step {step}/{}", request.steps);
            last_report = Instant::now();
        }
    }
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
    fn sizes_parse_with_either_cross_and_reject_zero_or_huge_sides() {
        assert_eq!(parse_size("480x360").unwrap(), (480, 360));
        assert_eq!(parse_size("3×2").unwrap(), (3, 2));
        for bad in ["0x10", "10x0", "480", "x", "10x99999", "axb", "-1x4"] {
            assert!(matches!(parse_size(bad), Err(AppError::Usage(_))), "{bad}");
        }
    }

    #[test]
    fn the_extension_chooses_the_format() {
        assert_eq!(output_format(Path::new("a/b.GIF")).unwrap(), Format::Gif);
        assert_eq!(output_format(Path::new("b.png")).unwrap(), Format::Png);
        assert!(output_format(Path::new("b.bmp")).is_err());
        assert!(output_format(Path::new("gif")).is_err());
    }
}
