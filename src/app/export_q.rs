//! `masssprings export-q SCENE.json -o Q.mtx`: the scene's system matrix
//! `Q = k AᵀA + M/Δt² + w CᵀC`, exactly as the simulation builds it, as a
//! Matrix Market file (`coordinate real symmetric`, lower triangle), so that
//! `masssprings analyze Q.mtx` (and any other sparse solver) can be tried
//! on any scene.

use super::error::AppError;
use super::file_plan::{plan_scene_inputs, report};
use super::matrix_input::scene_q;
use masssprings::files::{write_file, FilePlan};
use masssprings::linalg::sparse::Triangle;
use masssprings::matrix_market::{write_coordinate, Symmetry};
use masssprings::mesh::load_scene;
use masssprings::sim::PIN_WEIGHT;
use std::path::PathBuf;

/// Write a scene's Q as a Matrix Market file, for analyze.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Writes the scene's Q = k AᵀA + M/Δt² + w CᵀC, as the simulation builds it,
as a Matrix Market file (lower triangle) that analyze reads.")]
pub struct ExportQArgs {
    /// The scene: JSON that names an OBJ (data/README.md).
    #[arg(value_name = "SCENE.json")]
    scene: PathBuf,
    /// The file to write.
    #[arg(short, long, value_name = "Q.mtx", required = true)]
    out: PathBuf,
}

pub fn run(args: ExportQArgs) -> Result<(), AppError> {
    let (scene_path, out) = (args.scene, args.out);
    let scene = load_scene(&scene_path)?;
    let mut plan = FilePlan::default();
    plan_scene_inputs(&mut plan, &scene_path, &scene);
    plan.output("-o", &out).check()?;
    let q = scene_q(&scene, &scene_path)?;
    let comment = format!(
        "Q = k A'A + M/dt^2 + w C'C of {} ({} vertices, {} springs, {} pins, k = {}, dt = 1/30, w = {PIN_WEIGHT:e})\n\
         lower triangle; written by masssprings export-q",
        scene_path.display(),
        scene.vertices.len(),
        scene.springs.len(),
        scene.pinned.len(),
        scene.k,
    );
    write_file(&out, |file| {
        write_coordinate(file, &q, Symmetry::Symmetric, &comment)
    })?;
    let line = format!(
        "{}: n = {}, nnz(lower triangle of Q) = {}",
        out.display(),
        q.ncols(),
        q.triangle(Triangle::Lower).nnz()
    );
    report(&out, &line);
    Ok(())
}
