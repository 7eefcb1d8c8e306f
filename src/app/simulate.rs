//! `masssprings simulate SCENE.json`: run the simulation headless, write
//! OBJ frames, report timings.
//!
//! `--out DIR` refuses a folder that already holds frames (`frame-*.obj`,
//! from another run: mixing the two would be wrong without a warning)
//! unless `--force` is given, which removes those frames first. Each frame
//! is written all or nothing; the temporaries of a run that was killed are
//! removed by the next run into the same folder. Nothing is written before
//! the precomputation succeeds. Memory does not grow with `--steps`: the
//! median step time comes from a bounded sample.

use super::args::Args;
use super::convergence_flags;
use super::limits::precompute;
use super::timing::BoundedSample;
use super::AppError;
use masssprings::files::{remove_stale_temporaries, write_file};
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Sparse};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The summary `simulate` prints (the keys of its `--json` output).
#[derive(Debug, serde::Serialize)]
struct Summary {
    n: usize,
    springs: usize,
    steps: usize,
    precompute_s: f64,
    step_median_s: f64,
    backend: &'static str,
    /// How each step was solved, and how well.
    method: &'static str,
    tolerance: Option<f64>,
    iterations_median: f64,
    relative_gradient_median: f64,
}

/// What to do besides stepping.
struct Run {
    steps: usize,
    every: usize,
    out: Option<PathBuf>,
    /// Remove the frames already in `out` instead of refusing.
    force: bool,
    progress: bool,
}

pub fn run(args: &[String]) -> Result<(), AppError> {
    let mut options = vec!["steps", "every", "out"];
    options.extend(convergence_flags::OPTIONS);
    let args = Args::parse(args, &options, &["dense", "wind", "json", "force"])?;
    let scene_path = PathBuf::from(args.single_positional("SCENE.json")?);
    let run = Run {
        steps: args.value_or("steps", 100usize)?,
        every: args.value_or("every", 1usize)?,
        out: args
            .value_or("out", String::new())
            .map(|s| (!s.is_empty()).then(|| PathBuf::from(s)))?,
        force: args.switch("force"),
        progress: !args.switch("json"),
    };
    if run.every == 0 {
        return Err(AppError::Usage("--every must be at least 1".into()));
    }
    let scene = load_scene(&scene_path)?;
    if let Some(folder) = &run.out {
        if !run.force {
            refuse_earlier_frames(folder)?;
        }
    }
    let mut options = SimulationOptions {
        wind: args.switch("wind"),
        ..SimulationOptions::default()
    };
    convergence_flags::apply(&args, &mut options)?;
    let summary = if args.switch("dense") {
        simulate::<Dense>(&scene, &scene_path, options, &run)?
    } else {
        simulate::<Sparse>(&scene, &scene_path, options, &run)?
    };
    if args.switch("json") {
        println!(
            "{}",
            serde_json::to_string(&summary).expect("plain numbers serialise")
        );
    } else {
        print_summary(&scene_path, &summary);
    }
    Ok(())
}

/// Precompute, then step, writing frames and reporting progress.
fn simulate<B: LinearAlgebra>(
    scene: &Scene,
    scene_path: &Path,
    options: SimulationOptions,
    run: &Run,
) -> Result<Summary, AppError> {
    let started = Instant::now();
    let mut simulation = precompute::<B>(scene, scene_path, options)?;
    let precompute_s = started.elapsed().as_secs_f64();
    if let Some(folder) = &run.out {
        prepare_out_folder(folder)?;
        write_frame(folder, 0, scene, simulation.positions())?;
    }
    let mut step_times = BoundedSample::new();
    let (mut iterations, mut gradients) = (BoundedSample::new(), BoundedSample::new());
    let mut last_report = Instant::now();
    for step in 1..=run.steps {
        let t = Instant::now();
        let report = simulation
            .step()
            .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
        step_times.push(t.elapsed().as_secs_f64());
        iterations.push(report.iterations as f64);
        gradients.push(report.relative_gradient);
        if let Some(folder) = &run.out {
            if step.is_multiple_of(run.every) {
                write_frame(folder, step, scene, simulation.positions())?;
            }
        }
        if run.progress && last_report.elapsed().as_secs_f64() > 1.0 {
            eprintln!(
                "step {step}/{} ({:.1} ms/step)",
                run.steps,
                1e3 * step_times.last().unwrap_or(0.0)
            );
            last_report = Instant::now();
        }
    }
    Ok(Summary {
        n: scene.vertices.len(),
        springs: scene.springs.len(),
        steps: run.steps,
        precompute_s,
        step_median_s: step_times.median(),
        backend: B::NAME,
        method: options.method.name(),
        tolerance: options.tolerance,
        iterations_median: iterations.median(),
        relative_gradient_median: gradients.median(),
    })
}

/// Is `name` a frame of [`write_frame`], `frame-NNNNNN.obj` (6 digits or more)?
fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame-")
        .and_then(|rest| rest.strip_suffix(".obj"))
        .is_some_and(|digits| digits.len() >= 6 && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// The frames already in `folder` (none when it does not exist), sorted.
fn earlier_frames(folder: &Path) -> Result<Vec<PathBuf>, AppError> {
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

/// Refuses an `--out` folder holding frames of another run (before any
/// work is done).
fn refuse_earlier_frames(folder: &Path) -> Result<(), AppError> {
    let frames = earlier_frames(folder)?;
    match frames.first() {
        None => Ok(()),
        Some(first) => Err(AppError::Failed(format!(
            "--out {}: the folder already holds {} frame(s) of another run ({}, ...); \
             give --force to remove them first, or choose another folder",
            folder.display(),
            frames.len(),
            first.file_name().unwrap_or_default().to_string_lossy()
        ))),
    }
}

/// Creates the `--out` folder, removes the temporaries of killed runs and
/// the frames of an earlier run (with `--force`; without it they were
/// refused already).
fn prepare_out_folder(folder: &Path) -> Result<(), AppError> {
    let failed = |e: &dyn std::fmt::Display| AppError::Failed(format!("{}: {e}", folder.display()));
    std::fs::create_dir_all(folder).map_err(|e| failed(&e))?;
    remove_stale_temporaries(folder)?;
    for frame in earlier_frames(folder)? {
        std::fs::remove_file(&frame).map_err(|e| failed(&e))?;
    }
    Ok(())
}

/// `folder/frame-NNNNNN.obj`: the positions (shortest decimal form that
/// reads back to the same `f64`) and the scene's faces, written all or
/// nothing.
fn write_frame(
    folder: &Path,
    step: usize,
    scene: &Scene,
    positions: &[[f64; 3]],
) -> Result<(), AppError> {
    let path = folder.join(format!("frame-{step:06}.obj"));
    write_file(&path, |out| write_obj(out, scene, positions))?;
    Ok(())
}

/// An OBJ with `v` lines for `positions`, the scene's `vt` lines, and its
/// faces (with texture indices when the scene has them).
fn write_obj(out: &mut dyn Write, scene: &Scene, positions: &[[f64; 3]]) -> io::Result<()> {
    writeln!(out, "# {} — masssprings frame", scene.name)?;
    for p in positions {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2])?;
    }
    for uv in &scene.texture_coords {
        writeln!(out, "vt {} {}", uv[0], uv[1])?;
    }
    let textured = !scene.face_texture_coords.is_empty();
    for (f, face) in scene.faces.iter().enumerate() {
        write!(out, "f")?;
        for (corner, &vertex) in face.iter().enumerate() {
            if textured {
                write!(
                    out,
                    " {}/{}",
                    vertex + 1,
                    scene.face_texture_coords[f][corner] + 1
                )?;
            } else {
                write!(out, " {}", vertex + 1)?;
            }
        }
        writeln!(out)?;
    }
    Ok(())
}

fn print_summary(scene_path: &Path, s: &Summary) {
    println!("scene            {}", scene_path.display());
    println!("vertices         {}", s.n);
    println!("springs          {}", s.springs);
    println!("backend          {}", s.backend);
    println!("precomputation   {:.6} s", s.precompute_s);
    println!("steps            {}", s.steps);
    println!("step (median)    {:.6} s", s.step_median_s);
    let tolerance = s.tolerance.map_or("none".into(), |t| format!("{t:e}"));
    println!("method           {} (tolerance {tolerance})", s.method);
    println!("iterations       {} per step (median)", s.iterations_median);
    println!(
        "rel. gradient    {:.3e} at the end of a step (median)",
        s.relative_gradient_median
    );
}
