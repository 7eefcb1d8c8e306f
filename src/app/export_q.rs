//! `masssprings export-q SCENE.json -o Q.mtx`: the scene's system matrix
//! `Q = k AᵀA + M/Δt² + w CᵀC`, exactly as the simulation builds it, as a
//! Matrix Market file (`coordinate real symmetric`, lower triangle), so that
//! `masssprings analyze Q.mtx` (and any other sparse solver) can be tried
//! on any scene.

use super::args::{Args, CommandSpec, Flag};
use super::spy::{required_out, scene_q};
use super::{plan_scene_inputs, report, AppError};
use masssprings::files::{write_file, FilePlan};
use masssprings::linalg::matrix_market::{write_coordinate, Symmetry};
use masssprings::linalg::sparse::Triangle;
use masssprings::mesh::load_scene;
use masssprings::sim::PIN_WEIGHT;
use std::path::PathBuf;

/// `export-q`'s operands and flags.
pub static COMMAND: CommandSpec = CommandSpec {
    name: "export-q",
    operands: "SCENE.json -o Q.mtx",
    summary: "Write a scene's Q as a Matrix Market file, for analyze.",
    details: "\
Writes the scene's Q = k AᵀA + M/Δt² + w CᵀC, as the simulation builds it,
as a Matrix Market file (lower triangle) that analyze reads.",
    flags: &[Flag::value("out", "Q.mtx", "The file to write (required).")],
    shorts: &[('o', "out")],
    run,
};

pub fn run(args: &[String]) -> Result<(), AppError> {
    let args = Args::parse(args, &COMMAND)?;
    let scene_path = PathBuf::from(args.single_positional("SCENE.json")?);
    let out = required_out(&args, "export-q", "Q.mtx")?;
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
