//! Line plots as PNG images: a figure of panels side by side, each with
//! linear or log₁₀ axes, nice ticks, a grid, a legend and labels, drawn by
//! the renderer's own pieces (the supersampled `Canvas`, `draw_line_2d`,
//! `draw_disc`, the bitmap font of `text.rs`) and written all or nothing.
//!
//! **Axis mapping.** An axis shows `[lo, hi]` on the screen interval
//! `[p₀, p₁]` (for y, `p₀` is the bottom). With `T(v) = v` (linear) or
//! `T(v) = log₁₀ v` (log),
//!
//! ```text
//! p(v) = p₀ + (T(v) − T(lo)) / (T(hi) − T(lo)) · (p₁ − p₀),
//! ```
//!
//! so `lo ↦ p₀`, `hi ↦ p₁`, and on a log axis every decade (10 → 100, or
//! 1e-6 → 1e-5) is the same distance. Values a scale cannot show
//! (non-finite; zero or negative on a log axis) are skipped: they break a
//! series' line into pieces and do not enter the automatic ranges.
//!
//! **Nice ticks (Heckbert).** `nice(x)` is the number `f · 10ᵉ`, `f ∈ {1, 2,
//! 5, 10}`, nearest `x` (rounding) or the smallest at least `x` (ceiling).
//! For `n` ticks on `[lo, hi]`, the step is `nice(nice⌈hi − lo⌉ / (n − 1))`
//! rounded, and the ticks are the step's multiples inside the range; an
//! automatic range is first widened to the step's multiples around the data
//! ("loose" labelling). A log axis is widened to whole decades and labelled
//! at the decades `10ᵏ` (every `m`-th one when there are too many), with
//! minor ticks at `2…9 · 10ᵏ`.
//!
//! **Clipping.** Each segment of a series is cut to the plot rectangle by
//! the Liang–Barsky parametric test: with `p(t) = a + t (b − a)`, each of the
//! four edges bounds `t` from below or above; the segment survives when the
//! bounds leave `t₀ ≤ t₁` in `[0, 1]`.
//!
//! Cost: `O(width × height)` samples for the canvas and the box filter,
//! plus `O(length)` per segment.
//!
//! Sources: P. S. Heckbert, "Nice numbers for graph labels", *Graphics
//! Gems*, Academic Press, 1990, pp. 61–63 and 657–659; Y.-D. Liang and
//! B. A. Barsky, "A new concept and method for line clipping", *ACM TOG* 3(1),
//! 1984.

// The callers (`bench`, `converge`, `spy`) land in other branches; until
// then nothing in the binary uses this module.
#![allow(dead_code)]

use super::canvas::Canvas;
use super::discs::{draw_disc, DiscStyle};
use super::encode;
use super::lines::{draw_line_2d, flat_point};
use super::look::{hex, Rgb, SUPERSAMPLING};
use super::text::{draw_text, draw_text_vertical, text_height, text_width, Align};
use crate::app::error::AppError;
use masssprings::files::write_file;
use masssprings::mesh::procedural::RgbImage;
use std::path::Path;

/// How an axis maps values to the screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    #[default]
    Linear,
    /// Decades equally spaced; only positive values are shown.
    Log10,
}

/// One curve: its legend label (empty: not in the legend), its points in
/// data coordinates, and whether each point gets a marker.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub markers: bool,
}

/// One plot: titles, axis scales, curves, and optional fixed ranges
/// (`None`: from the data).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    pub series: Vec<Series>,
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
}

/// Panels side by side under a title, above a caption; `width × height`
/// output pixels.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub title: String,
    pub caption: String,
    pub panels: Vec<Panel>,
    pub width: usize,
    pub height: usize,
}

impl Default for Figure {
    fn default() -> Self {
        Figure {
            title: String::new(),
            caption: String::new(),
            panels: Vec::new(),
            width: 960,
            height: 540,
        }
    }
}

impl Series {
    /// A series drawn as a line without markers.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            points,
            markers: false,
        }
    }

    /// The same series with a marker on every point.
    pub fn with_markers(self) -> Series {
        Series {
            markers: true,
            ..self
        }
    }
}

/// The colours of series 0, 1, 2, … (cycling): the "category10" palette.
pub const PALETTE: [u32; 8] = [
    0x1f77b4, 0xd62728, 0x2ca02c, 0xff7f0e, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf,
];

/// The colour (`0xRRGGBB`) of a panel's `i`-th series.
pub fn series_colour(i: usize) -> u32 {
    PALETTE[i % PALETTE.len()]
}

const WHITE: Rgb = hex(0xffffff);
const INK: Rgb = hex(0x222222);
const AXIS: Rgb = hex(0x555555);
const GRID: Rgb = hex(0xd8d8d8);
const GRID_MINOR: Rgb = hex(0xededed);
const LEGEND_BORDER: Rgb = hex(0xaaaaaa);

/// Sizes, in samples (`SUPERSAMPLING` per output pixel).
const S: usize = SUPERSAMPLING;
/// Samples per font dot: small text (ticks, labels, legend) and titles.
const SMALL: usize = 3;
const LARGE: usize = 4;
/// Space around and between things.
const PAD: f64 = (6 * S) as f64;
/// Tick marks' length, and lines' widths.
const TICK: f64 = (4 * S) as f64;
const LINE_WIDTH: usize = 3;
const MARKER_RADIUS: f32 = 2.5 * S as f32;

/// An axis-aligned rectangle in samples.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Rect {
    left: f64,
    top: f64,
    right: f64,
    bottom: f64,
}

impl Rect {
    fn width(&self) -> f64 {
        self.right - self.left
    }

    fn height(&self) -> f64 {
        self.bottom - self.top
    }

    fn contains(&self, [x, y]: [f64; 2]) -> bool {
        (self.left..=self.right).contains(&x) && (self.top..=self.bottom).contains(&y)
    }
}

/// `T(v)`: the value itself, or its log₁₀; `None` when the scale cannot
/// show it.
fn transform(scale: Scale, v: f64) -> Option<f64> {
    match scale {
        Scale::Linear => v.is_finite().then_some(v),
        Scale::Log10 => (v.is_finite() && v > 0.0).then(|| v.log10()),
    }
}

/// An axis: the range `[lo, hi]` shown on the screen from `from` to `to`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Axis {
    scale: Scale,
    lo: f64,
    hi: f64,
    from: f64,
    to: f64,
}

impl Axis {
    /// `p(v)`, or `None` for a value the scale cannot show.
    fn position(&self, v: f64) -> Option<f64> {
        let (t, a, b) = (
            transform(self.scale, v)?,
            transform(self.scale, self.lo)?,
            transform(self.scale, self.hi)?,
        );
        let p = self.from + (t - a) / (b - a) * (self.to - self.from);
        p.is_finite().then_some(p)
    }
}

/// Heckbert's nice number: `f · 10ᵉ` with `f ∈ {1, 2, 5, 10}`, nearest `x`
/// when `round`, else the smallest at least `x`.
fn nice_number(x: f64, round: bool) -> f64 {
    let power = 10f64.powf(x.log10().floor());
    let f = x / power;
    let nice = if round {
        match f {
            f if f < 1.5 => 1.0,
            f if f < 3.0 => 2.0,
            f if f < 7.0 => 5.0,
            _ => 10.0,
        }
    } else {
        match f {
            f if f <= 1.0 => 1.0,
            f if f <= 2.0 => 2.0,
            f if f <= 5.0 => 5.0,
            _ => 10.0,
        }
    };
    nice * power
}

/// The 1-2-5 step for about `target` ticks on `[lo, hi]`.
fn tick_step(lo: f64, hi: f64, target: usize) -> f64 {
    let range = nice_number(hi - lo, false);
    nice_number(range / (target.max(2) - 1) as f64, true)
}

/// The multiples of the 1-2-5 step inside `[lo, hi]`.
fn linear_ticks(lo: f64, hi: f64, target: usize) -> Vec<f64> {
    let step = tick_step(lo, hi, target);
    if !(step.is_finite() && step > 0.0) {
        return Vec::new();
    }
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let snap = |v: f64| if v.abs() < 1e-9 * step { 0.0 } else { v };
    (first..=last.min(first + 1000))
        .map(|i| snap(i as f64 * step))
        .collect()
}

/// The labelled decades `10ᵏ` in `[lo, hi]` (every `m`-th, for at most
/// `target`), and the minor ticks: `2…9 · 10ᵏ`, or the skipped decades.
fn log_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, Vec<f64>) {
    let first = (lo.log10() - 1e-9).ceil() as i32;
    let last = (hi.log10() + 1e-9).floor() as i32;
    if last < first + 1 {
        let ticks = linear_ticks(lo, hi, target)
            .into_iter()
            .filter(|&v| v > 0.0);
        return (ticks.collect(), Vec::new());
    }
    let every = ((last - first + 1) as usize).div_ceil(target.max(2)) as i32;
    let decade = |k: i32| 10f64.powi(k);
    let (mut major, mut minor) = (Vec::new(), Vec::new());
    for k in first..=last {
        let list = if k.rem_euclid(every) == 0 {
            &mut major
        } else {
            &mut minor
        };
        list.push(decade(k));
    }
    if every == 1 {
        let inside = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
        minor = (first - 1..=last)
            .flat_map(|k| (2..10).map(move |m| f64::from(m) * decade(k)))
            .filter(inside)
            .collect();
    }
    (major, minor)
}

/// The smallest and largest of `values` that `scale` can show.
fn data_range(values: impl Iterator<Item = f64>, scale: Scale) -> Option<(f64, f64)> {
    values
        .filter(|&v| transform(scale, v).is_some())
        .fold(None, |range, v| match range {
            None => Some((v, v)),
            Some((lo, hi)) => Some((v.min(lo), v.max(hi))),
        })
}

/// The data range widened to the step's multiples (linear) or to whole
/// decades (log); a default when there is no data.
fn nice_range(range: Option<(f64, f64)>, scale: Scale, target: usize) -> (f64, f64) {
    match (scale, range) {
        (Scale::Linear, None) => (0.0, 1.0),
        (Scale::Log10, None) => (1.0, 10.0),
        (Scale::Linear, Some((lo, hi))) => {
            let margin = if lo == hi {
                lo.abs().max(1.0) * 0.1
            } else {
                0.0
            };
            let (lo, hi) = (lo - margin, hi + margin);
            let step = tick_step(lo, hi, target);
            ((lo / step).floor() * step, (hi / step).ceil() * step)
        }
        (Scale::Log10, Some((lo, hi))) => {
            let low = lo.log10().floor().clamp(-300.0, 299.0);
            let high = hi.log10().ceil().clamp(low + 1.0, 300.0);
            (10f64.powf(low), 10f64.powf(high))
        }
    }
}

/// The explicit range when the scale can show it, else the nice range of
/// `values`.
fn axis_range(
    explicit: Option<(f64, f64)>,
    values: impl Iterator<Item = f64>,
    scale: Scale,
    target: usize,
) -> (f64, f64) {
    let shows = |v| transform(scale, v).is_some();
    match explicit {
        Some((lo, hi)) if shows(lo) && shows(hi) && lo < hi => (lo, hi),
        _ => nice_range(data_range(values, scale), scale, target),
    }
}

/// `v` with as many decimals as the step needs, or in `1.5e-7` form when
/// very large or small.
fn linear_label(v: f64, step: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let step_exponent = step.abs().log10().floor();
    if v.abs() >= 1e5 || v.abs() < 1e-3 {
        let digits = (v.abs().log10().floor() - step_exponent).max(0.0) as usize;
        return trim_mantissa(&format!("{:.*e}", digits, v));
    }
    format!("{:.*}", (-step_exponent).max(0.0) as usize, v)
}

/// `2.50e4` → `2.5e4`, `1.0e-6` → `1e-6`.
fn trim_mantissa(text: &str) -> String {
    match text.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{mantissa}e{exponent}")
        }
        _ => text.into(),
    }
}

/// A log axis' tick label: `0.01` … `1000` plainly, else `1e-6`.
fn log_label(v: f64) -> String {
    let k = v.log10().round();
    if (v / 10f64.powf(k) - 1.0).abs() > 1e-9 {
        return linear_label(v, v);
    }
    match k as i32 {
        k @ -2..=3 => linear_label(10f64.powi(k), 10f64.powi(k)),
        k => format!("1e{k}"),
    }
}

/// An axis' ticks and their labels.
struct Ticks {
    major: Vec<f64>,
    minor: Vec<f64>,
    labels: Vec<String>,
}

/// The ticks of `[lo, hi]` on `scale`, about `target` of them.
fn ticks(scale: Scale, (lo, hi): (f64, f64), target: usize) -> Ticks {
    let (major, minor) = match scale {
        Scale::Linear => (linear_ticks(lo, hi, target), Vec::new()),
        Scale::Log10 => log_ticks(lo, hi, target),
    };
    let step = tick_step(lo, hi, target);
    let labels = match scale {
        Scale::Linear => major.iter().map(|&v| linear_label(v, step)).collect(),
        Scale::Log10 => major.iter().map(|&v| log_label(v)).collect(),
    };
    Ticks {
        major,
        minor,
        labels,
    }
}

/// The part `[t₀, t₁]` of segment `a → b` inside `rect` (Liang–Barsky), or
/// `None` when it misses.
fn clip_segment(a: [f64; 2], b: [f64; 2], rect: &Rect) -> Option<([f64; 2], [f64; 2])> {
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let bounds = [
        (-d[0], a[0] - rect.left),
        (d[0], rect.right - a[0]),
        (-d[1], a[1] - rect.top),
        (d[1], rect.bottom - a[1]),
    ];
    for (p, q) in bounds {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    let at = |t: f64| [a[0] + t * d[0], a[1] + t * d[1]];
    (t0 <= t1).then(|| (at(t0), at(t1)))
}

/// Fills `rect` with `colour` at `opacity`.
fn fill_rect(canvas: &mut Canvas, rect: &Rect, colour: Rgb, opacity: f32) {
    let clamp = |v: f64, size: usize| v.round().clamp(0.0, size as f64) as usize;
    for y in clamp(rect.top, canvas.height)..clamp(rect.bottom, canvas.height) {
        for x in clamp(rect.left, canvas.width)..clamp(rect.right, canvas.width) {
            let i = canvas.index(x, y);
            canvas.blend(i, colour, opacity);
        }
    }
}

/// A straight line from `a` to `b`, `width` samples wide.
fn line(canvas: &mut Canvas, a: [f64; 2], b: [f64; 2], width: usize, colour: Rgb) {
    let f = |p: [f64; 2]| [p[0] as f32, p[1] as f32];
    draw_line_2d(canvas, f(a), f(b), width, colour, 1.0);
}

/// The outline of `rect`, `width` samples wide.
fn stroke_rect(canvas: &mut Canvas, rect: &Rect, width: usize, colour: Rgb) {
    let (l, t, r, b) = (rect.left, rect.top, rect.right, rect.bottom);
    let h = width as f64 / 2.0;
    line(canvas, [l - h, t], [r + h, t], width, colour);
    line(canvas, [l - h, b], [r + h, b], width, colour);
    line(canvas, [l, t - h], [l, b + h], width, colour);
    line(canvas, [r, t - h], [r, b + h], width, colour);
}

/// Text at `(x, top)` in samples.
fn label(canvas: &mut Canvas, text: &str, (x, top): (f64, f64), scale: usize, align: Align) {
    let at = (x.round() as isize, top.round() as isize);
    draw_text(canvas, text, at, scale, align, INK);
}

/// A marker (disc) of `colour` centred on `p`.
fn marker(canvas: &mut Canvas, p: [f64; 2], colour: Rgb) {
    let style = DiscStyle {
        fill: colour,
        radius: MARKER_RADIUS,
        outline: Some((WHITE, 1.0)),
    };
    draw_disc(canvas, flat_point(p[0] as f32, p[1] as f32), &style);
}

/// `0xRRGGBB` of series `i` as an [`Rgb`].
fn colour_of(i: usize) -> Rgb {
    hex(series_colour(i))
}

impl Figure {
    /// Draws the figure: title on top, the panels side by side, caption at
    /// the bottom.
    pub fn draw(&self) -> RgbImage {
        let (width, height) = (self.width.max(1) * S, self.height.max(1) * S);
        let mut canvas = Canvas::new(width, height);
        canvas.clear(WHITE, WHITE);
        let mut area = Rect {
            left: 0.0,
            top: 2.0 * PAD,
            right: width as f64,
            bottom: height as f64 - PAD,
        };
        if !self.title.is_empty() {
            label(
                &mut canvas,
                &self.title,
                (area.right / 2.0, area.top),
                LARGE,
                Align::Centre,
            );
            area.top += text_height(LARGE) as f64 + 2.0 * PAD;
        }
        if !self.caption.is_empty() {
            area.bottom -= text_height(SMALL) as f64;
            let at = (area.right / 2.0, area.bottom);
            label(&mut canvas, &self.caption, at, SMALL, Align::Centre);
            area.bottom -= PAD;
        }
        let n = self.panels.len().max(1);
        let column = area.width() / n as f64;
        for (i, panel) in self.panels.iter().enumerate() {
            let left = area.left + i as f64 * column;
            let cell = Rect {
                left,
                right: left + column,
                ..area
            };
            panel.draw(&mut canvas, cell);
        }
        canvas.downsample(S)
    }

    /// Draws the figure and writes it as a PNG, all or nothing (a temporary
    /// file renamed into place).
    ///
    /// # Errors
    /// The first I/O error, with `path` in the message.
    pub fn write_png(&self, path: &Path) -> Result<(), AppError> {
        let image = self.draw();
        write_file(path, |out| encode::write_png(out, &image))?;
        Ok(())
    }
}

/// A panel's plot rectangle and its two axes.
struct Plot {
    rect: Rect,
    x: Axis,
    y: Axis,
}

impl Plot {
    /// The screen point of a data point, or `None` when an axis cannot
    /// show it.
    fn at(&self, (x, y): (f64, f64)) -> Option<[f64; 2]> {
        Some([self.x.position(x)?, self.y.position(y)?])
    }
}

impl Panel {
    /// The points of every series that both axes can show.
    fn visible_points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        let shows = |&(x, y): &(f64, f64)| {
            transform(self.x_scale, x).is_some() && transform(self.y_scale, y).is_some()
        };
        self.series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(shows)
    }

    /// Draws the panel inside `cell`.
    fn draw(&self, canvas: &mut Canvas, cell: Rect) {
        let small = text_height(SMALL) as f64;
        let mut top = cell.top;
        if !self.title.is_empty() {
            let at = ((cell.left + cell.right) / 2.0, top);
            label(canvas, &self.title, at, SMALL, Align::Centre);
            top += small + PAD;
        }
        let ([x_range, y_range], [x_ticks, y_ticks]) = self.ranges_and_ticks(&cell);
        let widest = y_ticks
            .labels
            .iter()
            .map(|l| text_width(l, SMALL))
            .max()
            .unwrap_or(0);
        let y_label_room = if self.y_label.is_empty() {
            0.0
        } else {
            small + PAD
        };
        let x_label_room = if self.x_label.is_empty() {
            0.0
        } else {
            small + 2.0 * PAD
        };
        let rect = Rect {
            left: cell.left + 2.0 * PAD + y_label_room + widest as f64 + TICK,
            top: top + small / 2.0,
            right: cell.right - 3.0 * PAD,
            bottom: cell.bottom - x_label_room - small - PAD - TICK,
        };
        if rect.width() < 2.0 || rect.height() < 2.0 {
            return;
        }
        let axis = |scale, (lo, hi), from, to| Axis {
            scale,
            lo,
            hi,
            from,
            to,
        };
        let plot = Plot {
            rect,
            x: axis(self.x_scale, x_range, rect.left, rect.right),
            y: axis(self.y_scale, y_range, rect.bottom, rect.top),
        };
        draw_grid(canvas, &plot, &x_ticks, &y_ticks);
        for (i, series) in self.series.iter().enumerate() {
            draw_series(canvas, &plot, series, colour_of(i));
        }
        stroke_rect(canvas, &rect, S, AXIS);
        draw_x_ticks(canvas, &plot, &x_ticks);
        draw_y_ticks(canvas, &plot, &y_ticks);
        self.draw_axis_labels(canvas, &plot, cell);
        draw_legend(canvas, &rect, &self.series);
    }

    /// The ranges of both axes in `cell` and their ticks: about one tick
    /// per 70 pixels across and per 45 up, 2 to 10 each.
    fn ranges_and_ticks(&self, cell: &Rect) -> ([(f64, f64); 2], [Ticks; 2]) {
        let x_target = ((cell.width() / (70 * S) as f64) as usize).clamp(2, 10);
        let y_target = ((cell.height() / (45 * S) as f64) as usize).clamp(2, 10);
        let x_range = axis_range(
            self.x_range,
            self.visible_points().map(|p| p.0),
            self.x_scale,
            x_target,
        );
        let y_range = axis_range(
            self.y_range,
            self.visible_points().map(|p| p.1),
            self.y_scale,
            y_target,
        );
        let x_ticks = ticks(self.x_scale, x_range, x_target);
        let y_ticks = ticks(self.y_scale, y_range, y_target);
        ([x_range, y_range], [x_ticks, y_ticks])
    }

    /// The x label under the tick labels, the y label turned up at the
    /// cell's left.
    fn draw_axis_labels(&self, canvas: &mut Canvas, plot: &Plot, cell: Rect) {
        let rect = &plot.rect;
        let small = text_height(SMALL) as f64;
        let x_at = (
            (rect.left + rect.right) / 2.0,
            rect.bottom + TICK + small + 2.5 * PAD,
        );
        label(canvas, &self.x_label, x_at, SMALL, Align::Centre);
        let y_at = (cell.left + PAD, (rect.top + rect.bottom) / 2.0);
        let at = (y_at.0.round() as isize, y_at.1.round() as isize);
        draw_text_vertical(canvas, &self.y_label, at, SMALL, Align::Centre, INK);
    }
}

/// Grid lines: light at the minor ticks, darker at the major ones.
fn draw_grid(canvas: &mut Canvas, plot: &Plot, x: &Ticks, y: &Ticks) {
    let rect = &plot.rect;
    for (ticks, colour) in [(&x.minor, GRID_MINOR), (&x.major, GRID)] {
        for p in ticks.iter().filter_map(|&v| plot.x.position(v)) {
            line(canvas, [p, rect.top], [p, rect.bottom], S, colour);
        }
    }
    for (ticks, colour) in [(&y.minor, GRID_MINOR), (&y.major, GRID)] {
        for p in ticks.iter().filter_map(|&v| plot.y.position(v)) {
            line(canvas, [rect.left, p], [rect.right, p], S, colour);
        }
    }
}

/// How many labels to step over so that neighbours (centred at
/// `positions`, `widths` wide) keep `PAD` apart: 1 when they all fit.
fn label_stride(positions: &[f64], widths: &[f64]) -> usize {
    let fits = |stride: usize| {
        let kept: Vec<usize> = (0..positions.len()).step_by(stride).collect();
        kept.windows(2).all(|w| {
            let gap = (positions[w[1]] - positions[w[0]]).abs();
            gap >= (widths[w[0]] + widths[w[1]]) / 2.0 + PAD
        })
    };
    (1..=positions.len().max(1)).find(|&s| fits(s)).unwrap_or(1)
}

/// Tick marks under the x axis and their labels, thinned where they would
/// touch.
fn draw_x_ticks(canvas: &mut Canvas, plot: &Plot, ticks: &Ticks) {
    let bottom = plot.rect.bottom;
    for p in ticks.minor.iter().filter_map(|&v| plot.x.position(v)) {
        line(canvas, [p, bottom], [p, bottom + TICK / 2.0], S, AXIS);
    }
    let positions: Vec<f64> = ticks
        .major
        .iter()
        .filter_map(|&v| plot.x.position(v))
        .collect();
    let widths: Vec<f64> = ticks
        .labels
        .iter()
        .map(|l| text_width(l, SMALL) as f64)
        .collect();
    let stride = label_stride(&positions, &widths);
    for (k, (&p, text)) in positions.iter().zip(&ticks.labels).enumerate() {
        line(canvas, [p, bottom], [p, bottom + TICK], S, AXIS);
        if k % stride == 0 {
            label(
                canvas,
                text,
                (p, bottom + TICK + PAD / 2.0),
                SMALL,
                Align::Centre,
            );
        }
    }
}

/// Tick marks left of the y axis and their labels, right-aligned.
fn draw_y_ticks(canvas: &mut Canvas, plot: &Plot, ticks: &Ticks) {
    let left = plot.rect.left;
    for p in ticks.minor.iter().filter_map(|&v| plot.y.position(v)) {
        line(canvas, [left - TICK / 2.0, p], [left, p], S, AXIS);
    }
    let half = text_height(SMALL) as f64 / 2.0;
    let positions: Vec<f64> = ticks
        .major
        .iter()
        .filter_map(|&v| plot.y.position(v))
        .collect();
    let heights = vec![2.0 * half; positions.len()];
    let stride = label_stride(&positions, &heights);
    for (k, (&p, text)) in positions.iter().zip(&ticks.labels).enumerate() {
        line(canvas, [left - TICK, p], [left, p], S, AXIS);
        if k % stride == 0 {
            label(
                canvas,
                text,
                (left - TICK - PAD / 2.0, p - half),
                SMALL,
                Align::End,
            );
        }
    }
}

/// A series as a polyline clipped to the plot rectangle (broken where a
/// point cannot be shown), with markers on the points inside it.
fn draw_series(canvas: &mut Canvas, plot: &Plot, series: &Series, colour: Rgb) {
    let points: Vec<Option<[f64; 2]>> = series.points.iter().map(|&p| plot.at(p)).collect();
    for pair in points.windows(2) {
        if let [Some(a), Some(b)] = *pair {
            if let Some((a, b)) = clip_segment(a, b, &plot.rect) {
                line(canvas, a, b, LINE_WIDTH, colour);
            }
        }
    }
    if series.markers {
        for p in points
            .into_iter()
            .flatten()
            .filter(|&p| plot.rect.contains(p))
        {
            marker(canvas, p, colour);
        }
    }
}

/// The legend: a box in the plot's top-right corner with a line (and
/// marker) and the label of each labelled series.
fn draw_legend(canvas: &mut Canvas, rect: &Rect, series: &[Series]) {
    let entries: Vec<(usize, &Series)> = series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.label.is_empty())
        .collect();
    let widest = entries
        .iter()
        .map(|(_, s)| text_width(&s.label, SMALL))
        .max();
    let Some(widest) = widest else { return };
    let (swatch, row) = ((12 * S) as f64, text_height(SMALL) as f64 + PAD);
    let width = swatch + widest as f64 + 3.0 * PAD;
    let height = entries.len() as f64 * row + PAD;
    let right = rect.right - PAD;
    let frame = Rect {
        left: right - width,
        top: rect.top + PAD,
        right,
        bottom: rect.top + PAD + height,
    };
    fill_rect(canvas, &frame, WHITE, 0.85);
    stroke_rect(canvas, &frame, S / 2 + 1, LEGEND_BORDER);
    for (k, (i, s)) in entries.iter().enumerate() {
        let top = frame.top + PAD + k as f64 * row;
        let middle = top + text_height(SMALL) as f64 / 2.0;
        let (a, b) = (
            [frame.left + PAD, middle],
            [frame.left + PAD + swatch, middle],
        );
        line(canvas, a, b, LINE_WIDTH, colour_of(*i));
        if s.markers {
            marker(canvas, [(a[0] + b[0]) / 2.0, middle], colour_of(*i));
        }
        label(canvas, &s.label, (b[0] + PAD, top), SMALL, Align::Start);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
    }

    fn all_close(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(&x, &y)| close(x, y))
    }

    #[test]
    fn nice_numbers_are_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(nice_number(0.13, true), 0.1);
        assert_eq!(nice_number(2.9, true), 2.0);
        assert_eq!(nice_number(3.1, true), 5.0);
        assert_eq!(nice_number(7.5, true), 10.0);
        assert_eq!(nice_number(1.2, false), 2.0);
        assert_eq!(nice_number(4000.0, false), 5000.0);
    }

    #[test]
    fn linear_ticks_step_by_one_two_or_five_and_stay_inside() {
        assert!(all_close(
            &linear_ticks(0.0, 1.0, 6),
            &[0.0, 0.2, 0.4, 0.6, 0.8, 1.0]
        ));
        assert!(all_close(
            &linear_ticks(-3.0, 7.0, 6),
            &[-2.0, 0.0, 2.0, 4.0, 6.0]
        ));
        assert!(all_close(
            &linear_ticks(0.0, 0.001, 3),
            &[0.0, 0.0005, 0.001]
        ));
        assert!(all_close(
            &linear_ticks(12.0, 97.0, 5),
            &[20.0, 40.0, 60.0, 80.0]
        ));
        // No rounding noise at zero.
        assert!(linear_ticks(-0.3, 0.3, 7).contains(&0.0));
    }

    #[test]
    fn automatic_linear_ranges_widen_to_the_step_and_handle_one_value() {
        let range = nice_range(Some((0.13, 0.87)), Scale::Linear, 5);
        assert!(close(range.0, 0.0) && close(range.1, 1.0), "{range:?}");
        let (lo, hi) = nice_range(Some((5.0, 5.0)), Scale::Linear, 5);
        assert!(lo < 5.0 && hi > 5.0);
        assert_eq!(nice_range(None, Scale::Linear, 5), (0.0, 1.0));
    }

    #[test]
    fn log_ranges_are_whole_decades_with_decade_ticks_and_minor_ticks() {
        let (lo, hi) = nice_range(Some((3e-7, 0.02)), Scale::Log10, 6);
        assert!(close(lo, 1e-7) && close(hi, 0.1), "{lo} {hi}");
        let (major, minor) = log_ticks(1.0, 1000.0, 6);
        assert!(all_close(&major, &[1.0, 10.0, 100.0, 1000.0]));
        assert_eq!(minor.len(), 3 * 8);
        assert!(minor.iter().any(|&v| close(v, 20.0)) && minor.iter().any(|&v| close(v, 900.0)));
        // Thirteen decades for at most four labels: every fourth one.
        let (major, minor) = log_ticks(1e-12, 1.0, 4);
        assert!(all_close(&major, &[1e-12, 1e-8, 1e-4, 1.0]), "{major:?}");
        assert_eq!(minor.len(), 9);
        assert_eq!(
            nice_range(Some((10.0, 10.0)), Scale::Log10, 5),
            (10.0, 100.0)
        );
    }

    #[test]
    fn labels_are_short() {
        assert_eq!(linear_label(0.4, 0.2), "0.4");
        assert_eq!(linear_label(20.0, 20.0), "20");
        assert_eq!(linear_label(250000.0, 50000.0), "2.5e5");
        assert_eq!(linear_label(0.0005, 0.0005), "5e-4");
        assert_eq!(log_label(1e-6), "1e-6");
        assert_eq!(log_label(0.01), "0.01");
        assert_eq!(log_label(1000.0), "1000");
        assert_eq!(log_label(1e4), "1e4");
    }

    #[test]
    fn axes_map_their_ends_to_the_rectangle_and_decades_evenly() {
        let x = Axis {
            scale: Scale::Linear,
            lo: -1.0,
            hi: 3.0,
            from: 10.0,
            to: 90.0,
        };
        assert_eq!(x.position(-1.0), Some(10.0));
        assert_eq!(x.position(3.0), Some(90.0));
        assert_eq!(x.position(1.0), Some(50.0));
        let y = Axis {
            scale: Scale::Log10,
            lo: 1.0,
            hi: 1000.0,
            from: 300.0,
            to: 0.0,
        };
        assert_eq!(y.position(1.0), Some(300.0));
        assert_eq!(y.position(1000.0), Some(0.0));
        let decade = y.position(10.0).unwrap() - y.position(100.0).unwrap();
        assert!(close(decade, 100.0), "{decade}");
        assert_eq!(y.position(0.0), None);
        assert_eq!(y.position(-5.0), None);
        assert_eq!(x.position(f64::NAN), None);
    }

    #[test]
    fn segments_are_clipped_to_the_rectangle() {
        let rect = Rect {
            left: 0.0,
            top: 0.0,
            right: 10.0,
            bottom: 10.0,
        };
        let inside = clip_segment([1.0, 1.0], [9.0, 9.0], &rect);
        assert_eq!(inside, Some(([1.0, 1.0], [9.0, 9.0])));
        let crossing = clip_segment([-5.0, 5.0], [15.0, 5.0], &rect);
        assert_eq!(crossing, Some(([0.0, 5.0], [10.0, 5.0])));
        let diagonal = clip_segment([-10.0, -10.0], [20.0, 20.0], &rect);
        assert_eq!(diagonal, Some(([0.0, 0.0], [10.0, 10.0])));
        assert_eq!(clip_segment([-5.0, 11.0], [15.0, 11.0], &rect), None);
        assert_eq!(clip_segment([-5.0, 4.0], [4.0, -5.0], &rect), None);
    }

    /// How many pixels of `image` have exactly the colour `rgb`.
    fn count(image: &RgbImage, rgb: u32) -> usize {
        let want = [(rgb >> 16) as u8, (rgb >> 8) as u8, rgb as u8];
        image.pixels.chunks(3).filter(|p| *p == want).count()
    }

    fn figure(series: Vec<Series>, x_scale: Scale, y_scale: Scale) -> Figure {
        let panel = Panel {
            x_scale,
            y_scale,
            series,
            ..Panel::default()
        };
        Figure {
            panels: vec![panel],
            width: 300,
            height: 200,
            ..Figure::default()
        }
    }

    #[test]
    fn a_series_is_drawn_in_its_palette_colour() {
        let flat = Series::new("", vec![(0.0, 1.0), (10.0, 1.0)]);
        let blank = figure(Vec::new(), Scale::Linear, Scale::Linear).draw();
        assert_eq!(count(&blank, series_colour(0)), 0);
        let image = figure(vec![flat], Scale::Linear, Scale::Linear).draw();
        assert_eq!((image.width, image.height), (300, 200));
        // An unlabelled series has no legend: the colour is the line's own.
        assert!(
            count(&image, series_colour(0)) > 150,
            "{}",
            count(&image, series_colour(0))
        );
    }

    #[test]
    fn unshowable_points_and_tiny_or_empty_figures_do_not_panic() {
        let points = vec![
            (f64::NAN, 1.0),
            (1.0, f64::INFINITY),
            (-1.0, 0.0),
            (0.0, -3.0),
            (2.0, 5.0),
            (1e300, 1e-300),
            (3.0, 7.0),
        ];
        let series = || vec![Series::new("a", points.clone()).with_markers()];
        for (x, y) in [
            (Scale::Linear, Scale::Log10),
            (Scale::Log10, Scale::Log10),
            (Scale::Linear, Scale::Linear),
        ] {
            let image = figure(series(), x, y).draw();
            assert!(count(&image, series_colour(0)) > 0);
        }
        let all_bad = vec![Series::new("bad", vec![(f64::NAN, -1.0), (0.0, 0.0)])];
        figure(all_bad, Scale::Log10, Scale::Log10).draw();
        let tiny = Figure {
            width: 1,
            height: 1,
            ..figure(series(), Scale::Log10, Scale::Linear)
        };
        assert_eq!(tiny.draw().pixels.len(), 3);
        Figure::default().draw();
    }

    #[test]
    fn explicit_ranges_are_kept_and_bad_ones_ignored() {
        let values = [2.0, 3.0];
        assert_eq!(
            axis_range(Some((0.0, 10.0)), values.into_iter(), Scale::Linear, 5),
            (0.0, 10.0)
        );
        let fallback = axis_range(Some((0.0, 10.0)), values.into_iter(), Scale::Log10, 5);
        assert_eq!(fallback, (1.0, 10.0));
        let reversed = axis_range(Some((5.0, 1.0)), values.into_iter(), Scale::Linear, 5);
        assert!(reversed.0 <= 2.0 && reversed.1 >= 3.0);
    }

    #[test]
    fn writing_a_png_leaves_the_file_or_nothing() {
        let folder = std::env::temp_dir().join(format!("masssprings-plot-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let path = folder.join("plot.png");
        figure(Vec::new(), Scale::Linear, Scale::Linear)
            .write_png(&path)
            .unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let missing = folder.join("no-such-folder").join("plot.png");
        assert!(Figure::default().write_png(&missing).is_err());
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
