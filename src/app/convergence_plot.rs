//! The plot of `masssprings converge`: the energy gap to the best energy
//! found, normalised by the start's gap, against iterations and against
//! milliseconds (drawn once the plotting module is in; until then the
//! command refuses `--plot`).

use super::AppError;
use std::path::Path;

/// Draws the curves `(method, [(iteration, energy, ms)])` into `path`.
pub fn draw(
    _path: &Path,
    _scene: &str,
    _step: usize,
    _curves: &[(String, Vec<(f64, f64, f64)>)],
) -> Result<(), AppError> {
    Err(AppError::Failed("--plot is not available yet".into()))
}
