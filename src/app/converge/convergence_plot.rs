//! The plot of `masssprings converge`: for every method, the energy gap to
//! the best energy any method found, normalised by the gap at the step's
//! start,
//!
//! ```text
//! gap(p) = (E(p) − E_best) / (E(p⁰) − E_best)      1 at the start, → 0
//! ```
//!
//! on a log scale against iterations (left) and against milliseconds
//! (right, log scale: Newton's iterations cost 100 of the others'). The
//! best iterate itself has gap 0 and drops off the log axis.

use crate::app::draw::plot::{Figure, Panel, Scale, Series};
use crate::app::error::AppError;
use std::path::Path;

/// A method's name and its points (iteration, energy gap, milliseconds).
pub type PlotCurve = (String, Vec<(f64, f64, f64)>);

/// Draws `curves` — `(method, [(iteration, E(p) − E(p⁰), ms)])` — into
/// `path` as a PNG.
///
/// # Errors
/// When the file cannot be written.
pub fn draw(path: &Path, scene: &str, step: usize, curves: &[PlotCurve]) -> Result<(), AppError> {
    let best = curves
        .iter()
        .flat_map(|(_, points)| points.iter().map(|p| p.1))
        .filter(|e| e.is_finite())
        .fold(0.0, f64::min);
    let start_gap = -best;
    let gap = |energy: f64| (energy - best) / start_gap;
    let series = |x: fn(&(f64, f64, f64)) -> f64| -> Vec<Series> {
        curves
            .iter()
            .map(|(name, points)| {
                Series::new(
                    name.clone(),
                    points.iter().map(|p| (x(p), gap(p.1))).collect(),
                )
            })
            .collect()
    };
    let panel = |title: &str, x_label: &str, x_scale: Scale, series: Vec<Series>| Panel {
        title: title.into(),
        x_label: x_label.into(),
        y_label: "energy gap / gap at start".into(),
        x_scale,
        y_scale: Scale::Log10,
        series,
        ..Panel::default()
    };
    let figure = Figure {
        title: format!("{scene}, step {step}: convergence of one time step"),
        caption: format!(
            "gap = (E(p) - E_best) / (E(start) - E_best), E_best = {best:.6e} relative to the start"
        ),
        panels: vec![
            panel(
                "against iterations",
                "iteration",
                Scale::Linear,
                series(|p| p.0),
            ),
            panel(
                "against wall time",
                "milliseconds (log)",
                Scale::Log10,
                series(|p| p.2),
            ),
        ],
        width: 1200,
        height: 520,
    };
    figure.write_png(path)
}
