//! `masssprings simulate SCENE.json`: run the simulation headless, write
//! OBJ frames, report timings.
//!
//! `--out DIR` is held by one run at a time, and refuses a folder that
//! already holds frames (`frame-*.obj`, from another run: mixing the two
//! would be wrong without a warning) unless `--force` is given, whose new
//! frames replace those once the run is complete (`super::resume::folder`).
//! Each frame is written all or nothing, at a name that is free, with the
//! run's record on its second line (`super::resume::frames`); the partial
//! files of a run that was killed are removed by the next run into the
//! same folder, and the frames a killed `--force` run staged are moved in
//! by `--resume` (`super::resume::folder`). No frame is written
//! before the precomputation succeeds. Memory does not grow with `--steps`: the
//! median step time comes from a bounded sample. Nor does the scene stay in
//! memory beside the simulation: its faces are dropped before the
//! precomputation when no frames are written, and its vertices, springs
//! and masses once the simulation holds its own (at a million vertices the
//! scene held ~170 MB, `docs/performance.md`).
//!
//! `--resume DIR` continues the run whose frames are in `DIR` from its last
//! two (`super::resume`), numbering the new frames on.
//!
//! Every file goes through `masssprings::files::outputs`, the one rule of
//! every output (docs/reliability.md).

use super::draw::texture::{read_png_file, Texture};
use super::error::AppError;
use super::file_plan::load_scene;
use super::flags::{whole, JsonFlag, SimulationFlags};
use super::limits::precompute;
use super::progress::{duration, Progress};
use super::resume::folder::{not_a_folder, Extras, FrameFolder, Use};
use super::resume::frames::{header as frame_header, is_frame_name, RunRecord};
use super::resume::{self, Resumed};
use super::timing::BoundedSample;
use masssprings::files::{same_file, shown, FilePlan, Owner};
use masssprings::mesh::Scene;
use masssprings::sim::methods::Carried;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Accuracy, Dense, LinearAlgebra, Simulation, Sparse};
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
    /// Wall-clock time of the whole run: precomputation, steps, frames.
    total_s: f64,
    backend: &'static str,
    /// How each step was solved, and how well.
    method: &'static str,
    tolerance: Option<f64>,
    energy_tolerance: Option<f64>,
    at_least_plain: Option<f64>,
    /// Where each step's iterations started (`current` or `inertial`).
    start: &'static str,
    /// The accuracy whose method and rules these are (`--accuracy`), if any.
    accuracy: Option<&'static str>,
    iterations_median: f64,
    iterations_max: usize,
    /// How many steps each rule stopped, by the rule's name in snake case
    /// (`iterations`, `energy_tolerance`, …: `Stop::name`).
    stops: std::collections::BTreeMap<String, usize>,
    /// `None` when the steps did not measure it (the plain fixed-count
    /// step does not).
    relative_gradient_median: Option<f64>,
    /// Which code ran the steps: `fast` or `textbook` (the handout's
    /// functions as written).
    path: &'static str,
    /// The threads the steps ran on (1 on the textbook path, with --dense
    /// or the simplicial factorization).
    threads: usize,
    /// The kernels that ran (`native` or `portable`: `--kernels`).
    kernels: &'static str,
    /// The step the run continued from (`--resume`), if any.
    resumed_from: Option<usize>,
}

/// What to do besides stepping.
struct Run {
    steps: usize,
    every: usize,
    out: Option<PathBuf>,
    /// Digits after the decimal point in frame files; `None`: the shortest
    /// form that reads back to the same `f64`.
    precision: Option<usize>,
    /// Replace the frames already in `out` instead of refusing.
    force: bool,
    progress: bool,
    /// What the frames' second line records (`super::resume::frames`).
    record: RunRecord,
}

/// Run a scene headless, write OBJ frames, report timings.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Runs the simulation (sparse unless --dense) for N steps. With --out, writes
DIR/frame-NNNNNN.obj for step 0 and every K-th step (with DIR/NAME.mtl and
the texture when the scene has one, so Blender shows it). Shows progress on
standard error (none with --json); ends with n, springs, precomputation
time, the median step time and the total time.")]
pub struct SimulateArgs {
    /// The scene: JSON that names an OBJ (data/README.md).
    #[arg(value_name = "SCENE.json")]
    scene: PathBuf,
    /// Time steps to run.
    #[arg(long, value_name = "N", default_value = "100", value_parser = whole(0, usize::MAX))]
    steps: usize,
    #[command(flatten)]
    frames: FrameOutput,
    /// Continue the run whose frames are in DIR from its last frame and the one a step before it (written without --precision), adding N more frames there; give the flags of that run.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["out", "force"])]
    resume: Option<PathBuf>,
    /// Add the assignment viewer's wind to gravity.
    #[arg(long)]
    wind: bool,
    #[command(flatten)]
    json: JsonFlag,
    #[command(flatten)]
    simulation: SimulationFlags,
}

/// Where frames go: `simulate`'s output.
#[derive(clap::Args, Debug)]
struct FrameOutput {
    /// Write OBJ frames into DIR.
    #[arg(short, long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Replace the frames of an earlier run in --out once the new run is complete, and files in the way not written by simulate (otherwise such a folder is refused).
    #[arg(long, requires = "out")]
    force: bool,
    /// Write every K-th step.
    #[arg(long, value_name = "K", default_value = "1", value_parser = whole(1, usize::MAX))]
    every: usize,
    /// Digits after the decimal point of the positions in the frames, 0 to 17 (default: as many as it takes to read back the same f64).
    #[arg(long, value_name = "D", value_parser = whole(0, 17))]
    precision: Option<usize>,
}

pub fn run(args: SimulateArgs) -> Result<(), AppError> {
    let scene_path = args.scene;
    let scene = load_scene(&scene_path)?;
    let mut options = SimulationOptions {
        wind: args.wind,
        ..SimulationOptions::default()
    };
    args.simulation.apply(&mut options);
    let dense = args.simulation.backend.dense;
    let mut run = Run {
        steps: args.steps,
        every: args.frames.every,
        out: args.resume.clone().or(args.frames.out),
        precision: args.frames.precision,
        force: args.frames.force,
        progress: !args.json.json,
        record: RunRecord::new(&scene, &options, dense),
    };
    if let Some(folder) = args.resume.as_deref().filter(|folder| !folder.is_dir()) {
        return Err(not_a_folder(folder));
    }
    check_files(&scene_path, &scene, run.out.as_deref())?;
    let (mut frames, resumed) = open_frames(&run, &scene, args.resume.as_deref())?;
    // the run the frames are of: a resumed run's, or this process's when
    // they replace another run's (to be told apart from those)
    let replaces = frames.as_ref().is_some_and(FrameFolder::replaces);
    run.record.run = match &resumed {
        Some(state) => state.run.clone(),
        None => replaces.then(|| Owner::this_process().tag()),
    };
    let written = (frames.as_mut(), resumed);
    let summary = if dense {
        simulate::<Dense>(scene, &scene_path, options, &run, written)?
    } else {
        simulate::<Sparse>(scene, &scene_path, options, &run, written)?
    };
    if let Some(frames) = frames {
        frames.commit(run.record.run.as_deref().unwrap_or_default())?;
    }
    if args.json.json {
        println!(
            "{}",
            serde_json::to_string(&summary).expect("plain numbers serialise")
        );
    } else {
        print_summary(&scene_path, &summary);
    }
    Ok(())
}

/// The frames' folder, locked and checked, and with `--resume` (that
/// folder) the state its run stopped in, checked against the run to come.
fn open_frames(
    run: &Run,
    scene: &Scene,
    resume: Option<&Path>,
) -> Result<(Option<FrameFolder>, Option<Resumed>), AppError> {
    let Some(out) = &run.out else {
        return Ok((None, None));
    };
    let frames = open_frame_folder(out, scene, run, resume.is_some())?;
    let resumed = match resume {
        Some(folder) => {
            frames.resume_killed_run(&run.record)?;
            let state = resume::last_state(folder, scene, &run.record)?;
            resume::last_step(folder, state.step, run.steps)?;
            Some(state)
        }
        None => None,
    };
    Ok((Some(frames), resumed))
}

/// Locks the frames' folder and checks what is in it ([`FrameFolder`]).
fn open_frame_folder(
    folder: &Path,
    scene: &Scene,
    run: &Run,
    resume: bool,
) -> Result<FrameFolder, AppError> {
    let how = if resume {
        Use::Resume
    } else {
        Use::Fresh { force: run.force }
    };
    let textured = texture_copy(folder, scene);
    let extras = Extras {
        material: textured.as_ref().map(|_| {
            let path = folder.join(format!("{}.mtl", scene.name));
            (path, material_header(&scene.name))
        }),
        texture: textured,
    };
    FrameFolder::open(folder, how, &extras)
}

/// Precompute, then step (on from `resumed`, if given), writing frames
/// into `frames` and reporting progress.
fn simulate<B: LinearAlgebra>(
    mut scene: Scene,
    scene_path: &Path,
    options: SimulationOptions,
    run: &Run,
    (mut frames, resumed): (Option<&mut FrameFolder>, Option<Resumed>),
) -> Result<Summary, AppError> {
    let (n, springs) = (scene.vertices.len(), scene.springs.len());
    if run.out.is_none() {
        keep_only(&mut scene, Keep::Physics);
    }
    let texture = match &run.out {
        Some(folder) => read_texture(folder, &scene)?,
        None => None,
    };
    let started = Instant::now();
    let mut simulation = precompute::<B>(&scene, scene_path, options)?;
    let precompute_s = started.elapsed().as_secs_f64();
    keep_only(&mut scene, Keep::Frames); // the simulation holds its own copies
    let resumed_from = resumed.as_ref().map(|state| state.step);
    if let Some(state) = resumed {
        simulation.set_state(&state.u_prev, &state.u_cur, state.step)?;
        simulation.carry(state.carried);
    }
    let resumed = resumed_from.is_some();
    let material = start_frames(
        frames.as_deref_mut(),
        run,
        &scene,
        texture,
        &simulation,
        resumed,
    )?;
    let first = resumed_from.unwrap_or(0);
    let written = (frames, material.as_deref());
    let tally = run_steps(&mut simulation, &scene, run, first, written)?;
    let times = [precompute_s, started.elapsed().as_secs_f64()];
    let shape = [n, springs, run.steps, simulation.threads()];
    let summary = summarize(tally, &options, B::NAME, shape, times);
    Ok(Summary {
        resumed_from,
        ..summary
    })
}

/// Readies the frames' folder (locked and checked already,
/// [`FrameFolder`]): it gets the material, and a new run's frames get
/// frame 0; a resumed run's frames number on. Returns the material's name,
/// if any.
fn start_frames<B: LinearAlgebra>(
    frames: Option<&mut FrameFolder>,
    run: &Run,
    scene: &Scene,
    texture: Option<(Vec<u8>, PathBuf)>,
    simulation: &Simulation<B>,
    resumed: bool,
) -> Result<Option<String>, AppError> {
    let Some(frames) = frames else {
        return Ok(None);
    };
    let material = write_material(frames, scene, texture)?;
    if !resumed {
        let frame = (0, simulation.positions(), simulation.carried());
        write_frame(frames, frame, scene, run, material.as_deref())?;
    }
    Ok(material)
}

/// What the steps report, gathered for the summary.
struct Tally {
    step_times: BoundedSample,
    iterations: BoundedSample,
    gradients: BoundedSample,
    iterations_max: usize,
    stops: std::collections::BTreeMap<String, usize>,
}

/// Steps `run.steps` times on from step `first`, writing every
/// `run.every`-th frame into `frames` (with `material`) and showing
/// progress.
fn run_steps<B: LinearAlgebra>(
    simulation: &mut Simulation<B>,
    scene: &Scene,
    run: &Run,
    first: usize,
    (mut frames, material): (Option<&mut FrameFolder>, Option<&str>),
) -> Result<Tally, AppError> {
    let mut tally = Tally {
        step_times: BoundedSample::new(),
        iterations: BoundedSample::new(),
        gradients: BoundedSample::new(),
        iterations_max: 0,
        stops: std::collections::BTreeMap::new(),
    };
    let mut progress = Progress::new(run.steps, run.progress);
    for done in 1..=run.steps {
        let step = first + done;
        let t = Instant::now();
        let report = simulation
            .step()
            .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
        tally.step_times.push(t.elapsed().as_secs_f64());
        tally.iterations.push(report.iterations as f64);
        tally.iterations_max = tally.iterations_max.max(report.iterations);
        let key = report.stop.name().replace('-', "_");
        *tally.stops.entry(key).or_insert(0) += 1;
        if let Some(gradient) = report.relative_gradient {
            tally.gradients.push(gradient);
        }
        if let Some(frames) = frames.as_deref_mut() {
            if step.is_multiple_of(run.every) {
                let frame = (step, simulation.positions(), simulation.carried());
                write_frame(frames, frame, scene, run, material)?;
            }
        }
        progress.step_done(done);
    }
    progress.finish();
    Ok(tally)
}

/// The summary of a run (not resumed): `[n, springs, steps]` and the
/// seconds of `[precomputation, whole run]`.
fn summarize(
    mut tally: Tally,
    options: &SimulationOptions,
    backend: &'static str,
    [n, springs, steps, threads]: [usize; 4],
    [precompute_s, total_s]: [f64; 2],
) -> Summary {
    let step = &options.step;
    Summary {
        n,
        springs,
        steps,
        precompute_s,
        step_median_s: tally.step_times.median(),
        total_s,
        backend,
        method: step.method.name(),
        tolerance: step.tolerance,
        energy_tolerance: step.energy_tolerance,
        at_least_plain: step.at_least_plain,
        start: step.start.name(),
        accuracy: Accuracy::of(step).map(Accuracy::name),
        iterations_median: tally.iterations.median(),
        iterations_max: tally.iterations_max,
        stops: tally.stops,
        relative_gradient_median: Some(tally.gradients.median()).filter(|m| !m.is_nan()),
        path: if options.textbook { "textbook" } else { "fast" },
        threads,
        kernels: options.kernels.name(),
        resumed_from: None,
    }
}

/// What of a scene is still needed.
enum Keep {
    /// What the precomputation reads: vertices, springs, masses, pins.
    Physics,
    /// What the frames are written from: the name, faces, texture.
    Frames,
}

/// Frees the parts of `scene` that `keep` does not name.
fn keep_only(scene: &mut Scene, keep: Keep) {
    match keep {
        Keep::Physics => {
            scene.faces = Vec::new();
            scene.texture_coords = Vec::new();
            scene.face_texture_coords = Vec::new();
        }
        Keep::Frames => {
            scene.vertices = Vec::new();
            scene.springs = Vec::new();
            scene.masses = Vec::new();
        }
    }
}

/// Refuses, before any work, a run whose files clash (`masssprings::files::FilePlan`):
/// the frames, the material or the copy of the texture in the `--out`
/// folder would be one of the scene's files, or one another.
fn check_files(scene_path: &Path, scene: &Scene, out: Option<&Path>) -> Result<(), AppError> {
    let mut plan = FilePlan::default();
    super::file_plan::plan_scene_inputs(&mut plan, scene_path, scene);
    if let Some(folder) = out {
        super::file_plan::check_output_folder(folder, "simulate writes a folder of frames")?;
        plan.writes_into(
            "--out",
            folder,
            "the frames frame-NNNNNN.obj",
            is_frame_name,
        );
        if let Some((texture, copy)) = texture_copy(folder, scene) {
            let material = folder.join(format!("{}.mtl", scene.name));
            plan.output("the frames' material", &material);
            if !same_file(texture, &copy) {
                plan.output("the frames' copy of the texture", &copy);
            }
        }
    }
    plan.check()?;
    Ok(())
}

/// The scene's texture and where the frames' copy of it goes, when the
/// frames have a material (a texture and texture coordinates).
fn texture_copy<'a>(folder: &Path, scene: &'a Scene) -> Option<(&'a Path, PathBuf)> {
    let texture = scene.texture.as_deref()?;
    if scene.face_texture_coords.is_empty() {
        return None;
    }
    Some((texture, folder.join(texture.file_name()?)))
}

/// The texture the frames' material needs (its bytes, and where they are
/// copied), read and checked as `render` checks it (a PNG that decodes)
/// before any work; `None` when the frames have no material.
fn read_texture(folder: &Path, scene: &Scene) -> Result<Option<(Vec<u8>, PathBuf)>, AppError> {
    let Some((texture, copy)) = texture_copy(folder, scene) else {
        return Ok(None);
    };
    let bytes = read_png_file(texture).map_err(AppError::Failed)?;
    Texture::decode_png(io::Cursor::new(&bytes[..]), masssprings::memory::limit())
        .map_err(|problem| AppError::Failed(format!("texture {}: {problem}", shown(texture))))?;
    Ok(Some((bytes, copy)))
}

/// The material of the frames, when they have a `texture` ([`read_texture`]):
/// writes `NAME.mtl` (one material, `map_Kd` the texture) and the copy of
/// the texture beside it in the frames' folder (not copied when the
/// texture is in the folder already), and returns the material's name.
fn write_material(
    frames: &FrameFolder,
    scene: &Scene,
    texture: Option<(Vec<u8>, PathBuf)>,
) -> Result<Option<String>, AppError> {
    let Some((bytes, copy)) = texture else {
        return Ok(None);
    };
    if !scene
        .texture
        .as_deref()
        .is_some_and(|t| same_file(t, &copy))
    {
        frames.write_extra(&copy, |out| out.write_all(&bytes))?;
    }
    let texture_name = copy.file_name().unwrap_or_default().to_owned();
    let name = scene.name.clone();
    let material = frames.folder().join(format!("{name}.mtl"));
    frames.write_extra(&material, |out| {
        writeln!(out, "{}", material_header(&name))?;
        writeln!(out, "newmtl {name}")?;
        writeln!(out, "Kd 1 1 1")?;
        writeln!(out, "map_Kd {}", texture_name.to_string_lossy())
    })?;
    Ok(Some(name))
}

/// The first line of the frames' material `NAME.mtl`.
fn material_header(name: &str) -> String {
    format!("# {name} — masssprings frames")
}

/// `folder/frame-NNNNNN.obj` of `step`: the header, the run's record with
/// what the methods `carried` after the step, the positions and the
/// scene's faces, written all or nothing.
fn write_frame(
    frames: &mut FrameFolder,
    (step, positions, carried): (usize, &[[f64; 3]], Carried),
    scene: &Scene,
    run: &Run,
    material: Option<&str>,
) -> Result<(), AppError> {
    let header = frame_header(&scene.name, step, run.precision);
    let mut record = run.record.clone();
    record.carried = carried;
    frames.write_frame(step, |out| {
        writeln!(out, "{header}")?;
        writeln!(out, "{}", record.line())?;
        write_obj(out, scene, positions, run.precision, material)
    })?;
    Ok(())
}

/// An OBJ (after its first two lines, [`frame_header`] and the record) with `v` lines for
/// `positions` (with `precision` digits after the point, or the shortest
/// decimal form that reads back to the same `f64`), the scene's `vt` lines,
/// the material, and the faces (with texture indices when the scene has
/// them).
fn write_obj(
    out: &mut dyn Write,
    scene: &Scene,
    positions: &[[f64; 3]],
    precision: Option<usize>,
    material: Option<&str>,
) -> io::Result<()> {
    if let Some(material) = material {
        writeln!(out, "mtllib {material}.mtl")?;
    }
    for p in positions {
        match precision {
            None => writeln!(out, "v {} {} {}", p[0], p[1], p[2])?,
            Some(d) => {
                let [x, y, z] = p.map(|x| without_negative_zero(x, d));
                writeln!(out, "v {x:.d$} {y:.d$} {z:.d$}")?;
            }
        }
    }
    for uv in &scene.texture_coords {
        writeln!(out, "vt {} {}", uv[0], uv[1])?;
    }
    if let Some(material) = material {
        writeln!(out, "usemtl {material}")?;
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

/// `x`, or 0 when it rounds to zero at `digits` digits (no `-0.000`).
fn without_negative_zero(x: f64, digits: usize) -> f64 {
    if x.abs() < 0.5 * 10f64.powi(-(digits as i32)) {
        0.0
    } else {
        x
    }
}

/// The iterations of the steps and where they stopped.
fn print_iterations(s: &Summary) {
    let stops: Vec<String> = s
        .stops
        .iter()
        .map(|(key, n)| format!("{} {n}", key.replace('_', "-")))
        .collect();
    println!(
        "iterations       {} per step (median), at most {}; stopped by {}",
        s.iterations_median,
        s.iterations_max,
        stops.join(", ")
    );
    match s.relative_gradient_median {
        Some(median) => println!("rel. gradient    {median:.3e} at the end of a step (median)"),
        None => println!("rel. gradient    not measured (no stopping rule asked for it)"),
    }
}

fn print_summary(scene_path: &Path, s: &Summary) {
    println!("scene            {}", shown(scene_path));
    println!("vertices         {}", s.n);
    println!("springs          {}", s.springs);
    println!("backend          {}", s.backend);
    println!("precomputation   {:.6} s", s.precompute_s);
    println!("steps            {}", s.steps);
    if let Some(step) = s.resumed_from {
        println!("resumed from     step {step}");
    }
    if s.steps == 0 {
        println!("step (median)    none: no step was run");
    } else {
        println!("step (median)    {:.6} s", s.step_median_s);
    }
    let tolerance = s.tolerance.map_or("none".into(), |t| format!("{t:e}"));
    let energy_tolerance = s
        .energy_tolerance
        .map_or(String::new(), |t| format!(", energy tolerance {t:e}"));
    let at_least_plain = s
        .at_least_plain
        .map_or(String::new(), |n| format!(", at least plain-{n}"));
    println!(
        "method           {} (tolerance {tolerance}{energy_tolerance}{at_least_plain}, start {})",
        s.method, s.start
    );
    if let Some(accuracy) = s.accuracy {
        println!("accuracy         {accuracy}");
    }
    if s.steps > 0 {
        print_iterations(s);
    }
    println!("path             {}", s.path);
    println!("threads          {}", s.threads);
    println!("total            {}", duration(s.total_s));
}
