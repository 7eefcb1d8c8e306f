//! The matrix that `analyze`, `spy`, `etree` and `export-q` work on: the
//! lower triangle of a symmetric Matrix Market file, or the `Q` that the
//! simulation builds for a scene, with the files it read planned as inputs.

use super::error::AppError;
use super::file_plan::plan_scene_inputs;
use super::flags::OrderingFlag;
use masssprings::files::{shown, FilePlan};
use masssprings::linalg::sparse::{CscMatrix, Triangle};
use masssprings::matrix_market;
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::precomputation::{self, DELTA_T};
use std::path::{Path, PathBuf};

/// A picture of `Q`'s structure (`spy`, `etree`): the matrix, the picture,
/// and the order the factorization uses.
#[derive(clap::Args, Debug)]
pub struct PatternArgs {
    /// A symmetric Matrix Market matrix, or a scene whose Q to draw.
    #[arg(value_name = "MATRIX.mtx|SCENE.json")]
    pub matrix: PathBuf,
    /// The picture to write.
    #[arg(short, long, value_name = "OUT.png", required = true)]
    pub out: PathBuf,
    #[command(flatten)]
    pub ordering: OrderingFlag,
}

/// The lower triangle of the symmetric sparse matrix in `path` (a `general`
/// file is checked for symmetry, see `matrix_market::read_symmetric`).
pub fn read_symmetric_lower(path: &Path) -> Result<CscMatrix, AppError> {
    let lower = matrix_market::read_symmetric(path)?.triangle(Triangle::Lower);
    if lower.ncols() == 0 {
        return Err(AppError::Failed(format!(
            "{}: the matrix is 0 × 0: there is nothing to factor or draw",
            path.display()
        )));
    }
    Ok(lower)
}

/// The lower triangle of a Matrix Market file's matrix, or of the `Q` the
/// simulation builds for a scene (`.json`); the files it read are added to
/// `plan` as inputs.
pub fn load_lower(path: &Path, plan: &mut FilePlan) -> Result<CscMatrix, AppError> {
    if path.extension().is_some_and(|e| e == "json") {
        let scene = load_scene(path)?;
        plan_scene_inputs(plan, path, &scene);
        Ok(scene_q(&scene, path)?.triangle(Triangle::Lower))
    } else {
        plan.input("the matrix", path);
        read_symmetric_lower(path)
    }
}

/// `Q = k AᵀA + M/Δt² + w CᵀC` of `scene`, as the simulation assembles it
/// (both triangles), without factoring it; a `Q` that would overflow is
/// refused first, naming the quantity.
pub fn scene_q(scene: &Scene, scene_path: &Path) -> Result<CscMatrix, AppError> {
    precomputation::check_q_fits(&scene.springs, &scene.masses, scene.k, DELTA_T)
        .map_err(|why| AppError::Failed(format!("{}: {why}", shown(scene_path))))?;
    Ok(precomputation::scene_q(scene, DELTA_T))
}

/// The file name of `path`, for captions.
pub fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}
