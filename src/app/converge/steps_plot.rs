//! The plot of `masssprings converge --steps S --plot`: each method's
//! steps 1…S beside plain-50's, one point per step.
//!
//! With a stopping rule (`--tolerance`, `--energy-tolerance`,
//! `--at-least-plain`) each method solves every step by the rule, and the
//! two panels show, per step,
//!
//! ```text
//! left:   t(step) / t_plain-50(step)                   its cost
//! right:  (E(p) − E(pᵗ)) / (E(p_plain-50) − E(pᵗ))     its decrease, ≥ 1: at least as low
//! ```
//!
//! Without a rule, the left panel shows the time to first reach plain-50's
//! energy over plain-50's time, and the right one the iterations it took
//! (steps where a method never got there are left out). Plain-50 itself is
//! the line at 1 in both panels of the first kind.
//!
//! Drawn by the project's own plotter ([`super::draw::plot`]).

use crate::app::draw::plot::{Figure, Panel, Scale, Series};
use crate::app::error::AppError;
use std::path::Path;

/// A method's name and its points `(step, left value, right value)`.
pub type StepSeries = (String, Vec<(f64, f64, f64)>);

/// What the two panels show.
pub struct StepPlot<'a> {
    pub title: String,
    pub caption: String,
    /// Title, y label and scale of the left and the right panel.
    pub left: (&'a str, &'a str, Scale),
    pub right: (&'a str, &'a str, Scale),
    /// Draw plain-50 as the line at 1 in both panels.
    pub plain_50_line: bool,
}

/// Draws `series` into `path` as a PNG.
///
/// # Errors
/// When the file cannot be written.
pub fn draw(path: &Path, plot: &StepPlot<'_>, series: &[StepSeries]) -> Result<(), AppError> {
    let steps = series
        .iter()
        .flat_map(|(_, points)| points.iter().map(|p| p.0))
        .fold(1.0, f64::max);
    let panel = |(title, y_label, y_scale): (&str, &str, Scale),
                 value: fn(&(f64, f64, f64)) -> f64| {
        let mut lines: Vec<Series> = series
            .iter()
            .map(|(name, points)| {
                let points = points.iter().map(|p| (p.0, value(p))).collect();
                Series::new(name.clone(), points).with_markers()
            })
            .collect();
        if plot.plain_50_line {
            lines.push(Series::new("plain-50", vec![(1.0, 1.0), (steps, 1.0)]));
        }
        Panel {
            title: title.into(),
            x_label: "step".into(),
            y_label: y_label.into(),
            x_scale: Scale::Linear,
            y_scale,
            series: lines,
            ..Panel::default()
        }
    };
    let figure = Figure {
        title: plot.title.clone(),
        caption: plot.caption.clone(),
        panels: vec![panel(plot.left, |p| p.1), panel(plot.right, |p| p.2)],
        width: 1200,
        height: 520,
    };
    figure.write_png(path)
}
