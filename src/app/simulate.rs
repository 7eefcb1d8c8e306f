//! `masssprings simulate SCENE.json`: run the simulation headless, write
//! OBJ frames, report timings.

use super::args::Args;
use super::convergence_flags;
use super::factorization_flags;
use super::timing::median;
use super::AppError;
use masssprings::files::write_file;
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Simulation, Sparse};
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
    progress: bool,
}

pub fn run(args: &[String]) -> Result<(), AppError> {
    let mut options = vec!["steps", "every", "out"];
    options.extend(convergence_flags::OPTIONS);
    options.extend(factorization_flags::OPTIONS);
    let args = Args::parse(args, &options, &["dense", "wind", "json"])?;
    let scene_path = PathBuf::from(args.single_positional("SCENE.json")?);
    let run = Run {
        steps: args.value_or("steps", 100usize)?,
        every: args.value_or("every", 1usize)?,
        out: args
            .value_or("out", String::new())
            .map(|s| (!s.is_empty()).then(|| PathBuf::from(s)))?,
        progress: !args.switch("json"),
    };
    if run.every == 0 {
        return Err(AppError::Usage("--every must be at least 1".into()));
    }
    let scene = load_scene(&scene_path)?;
    let mut options = SimulationOptions {
        wind: args.switch("wind"),
        ..SimulationOptions::default()
    };
    convergence_flags::apply(&args, &mut options)?;
    factorization_flags::apply(&args, &mut options)?;
    let summary = if args.switch("dense") {
        simulate::<Dense>(&scene, options, &run)?
    } else {
        simulate::<Sparse>(&scene, options, &run)?
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
    options: SimulationOptions,
    run: &Run,
) -> Result<Summary, AppError> {
    let started = Instant::now();
    let mut simulation = Simulation::<B>::from_scene(scene, options)?;
    let precompute_s = started.elapsed().as_secs_f64();
    if let Some(folder) = &run.out {
        std::fs::create_dir_all(folder)
            .map_err(|e| AppError::Failed(format!("{}: {e}", folder.display())))?;
        write_frame(folder, 0, scene, simulation.positions())?;
    }
    let mut step_times = Vec::new();
    let (mut iterations, mut gradients) = (Vec::new(), Vec::new());
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
                1e3 * step_times.last().copied().unwrap_or(0.0)
            );
            last_report = Instant::now();
        }
    }
    Ok(Summary {
        n: scene.vertices.len(),
        springs: scene.springs.len(),
        steps: run.steps,
        precompute_s,
        step_median_s: median(&mut step_times),
        backend: B::NAME,
        method: options.method.name(),
        tolerance: options.tolerance,
        iterations_median: median(&mut iterations),
        relative_gradient_median: median(&mut gradients),
    })
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
