//! `masssprings export-q SCENE.json -o Q.mtx`: the scene's system matrix
//! `Q = k AᵀA + M/Δt² + w CᵀC`, exactly as the simulation builds it, as a
//! Matrix Market file (`coordinate real symmetric`, lower triangle), so that
//! `masssprings analyze Q.mtx` (and any other sparse solver) can be tried
//! on any scene.

use super::args::Args;
use super::spy::{required_out, scene_q, short_out};
use super::AppError;
use masssprings::files::write_file;
use masssprings::linalg::matrix_market::{write_coordinate, Symmetry};
use masssprings::linalg::sparse::Triangle;
use masssprings::mesh::load_scene;
use masssprings::sim::PIN_WEIGHT;
use std::path::PathBuf;

pub fn run(args: &[String]) -> Result<(), AppError> {
    let args = Args::parse(&short_out(args), &["out"], &[])?;
    let scene_path = PathBuf::from(args.single_positional("SCENE.json")?);
    let out = required_out(&args, "export-q", "Q.mtx")?;
    let scene = load_scene(&scene_path)?;
    let q = scene_q(&scene)?;
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
    println!(
        "{}: n = {}, nnz(lower triangle of Q) = {}",
        out.display(),
        q.ncols(),
        q.triangle(Triangle::Lower).nnz()
    );
    Ok(())
}
