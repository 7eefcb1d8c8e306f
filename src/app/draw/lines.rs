//! Springs as thin lines: a DDA line, depth-tested against the surfaces
//! and drawn slightly in front of them, blended at partial opacity.
//!
//! **DDA** (digital differential analyser). Along the line's *major* axis
//! (the one in which it is longer, so it has no gaps) visit every sample
//! whose centre lies between the end points; at the centre `m + ½` the line
//! is at parameter `t = (m + ½ − a_major) / Δ_major`, where the minor
//! coordinate is `a_minor + t Δ_minor`. There, `width` samples across the
//! minor axis are drawn (so the width is measured along that axis: a
//! diagonal line looks about 30% thinner than a horizontal one).
//!
//! **Depth.** `1/z` is affine on the screen, so at parameter `t` it is
//! `(1−t)/z_a + t/z_b`. A line sample is drawn when that, enlarged by
//! `DEPTH_BIAS` (0.5% nearer), is at least what the z-buffer holds: a spring
//! lying on the cloth shows, one behind it does not. Lines do not write the
//! z-buffer, so crossing springs all show.
//!
//! **Blending.** Each sample becomes `(1 − α) c + α colour`. Cost: `O(length
//! × width)` samples.
//!
//! Sources: Marschner & Shirley, *Fundamentals of Computer Graphics*, 4th ed.
//! (2016), ch. 8 (line drawing, blending); Pineda 1988 (the incremental view
//! of affine functions on the screen).

use super::camera::ScreenPoint;
use super::canvas::Canvas;
use super::look::Rgb;

/// How much nearer (relatively, in `1/z`) lines and point masses are
/// treated than they are, so that those on a surface are not hidden by it.
pub const DEPTH_BIAS: f32 = 0.005;

/// Is a mark at `inv_depth` visible at sample `i` (in front of, or on, the
/// surface drawn there)?
pub fn visible(canvas: &Canvas, i: usize, inv_depth: f32) -> bool {
    inv_depth * (1.0 + DEPTH_BIAS) >= canvas.depth[i]
}

/// Draws the segment `a → b`, `width` samples wide, in `colour` at
/// `opacity`. Segments shorter than a sample, or with an end at or behind
/// the eye, draw nothing.
pub fn draw_line(
    canvas: &mut Canvas,
    a: ScreenPoint,
    b: ScreenPoint,
    width: usize,
    colour: Rgb,
    opacity: f32,
) {
    if a.inv_depth <= 0.0 || b.inv_depth <= 0.0 {
        return;
    }
    let steep = (b.y - a.y).abs() > (b.x - a.x).abs();
    // (major, minor) coordinates of the ends, and the canvas's size in them.
    let flip = |p: ScreenPoint| if steep { [p.y, p.x] } else { [p.x, p.y] };
    let ([a_major, a_minor], [b_major, b_minor]) = (flip(a), flip(b));
    let (major_size, minor_size) = if steep {
        (canvas.height, canvas.width)
    } else {
        (canvas.width, canvas.height)
    };
    let (low, high) = (a_major.min(b_major), a_major.max(b_major));
    let first = (low - 0.5).ceil().max(0.0);
    let last = (high - 0.5).floor().min(major_size as f32 - 1.0);
    if first.is_nan() || last.is_nan() || first > last {
        return;
    }
    for m in first as usize..=last as usize {
        let t = (m as f32 + 0.5 - a_major) / (b_major - a_major);
        let minor = a_minor + t * (b_minor - a_minor);
        let inv_depth = (1.0 - t) * a.inv_depth + t * b.inv_depth;
        let start = (minor - 0.5 * width as f32).round() as isize;
        for s in start..start + width as isize {
            if s < 0 || s >= minor_size as isize {
                continue;
            }
            let (x, y) = if steep {
                (s as usize, m)
            } else {
                (m, s as usize)
            };
            let i = canvas.index(x, y);
            if visible(canvas, i, inv_depth) {
                canvas.blend(i, colour, opacity);
            }
        }
    }
}

/// A point at depth 1 on the screen, for flat drawings (plots) on a canvas
/// whose z-buffer is empty: every such mark is visible.
pub fn flat_point(x: f32, y: f32) -> ScreenPoint {
    ScreenPoint {
        x,
        y,
        inv_depth: 1.0,
    }
}

/// [`draw_line`] for a flat drawing: the segment `a → b` (sample
/// coordinates) on a canvas whose z-buffer is empty.
pub fn draw_line_2d(
    canvas: &mut Canvas,
    a: [f32; 2],
    b: [f32; 2],
    width: usize,
    colour: Rgb,
    opacity: f32,
) {
    let (a, b) = (flat_point(a[0], a[1]), flat_point(b[0], b[1]));
    draw_line(canvas, a, b, width, colour, opacity);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f32, y: f32) -> ScreenPoint {
        ScreenPoint {
            x,
            y,
            inv_depth: 1.0,
        }
    }

    fn drawn(canvas: &Canvas) -> Vec<(usize, usize)> {
        let mut samples = Vec::new();
        for y in 0..canvas.height {
            for x in 0..canvas.width {
                if canvas.colour[canvas.index(x, y)] != [0.0; 3] {
                    samples.push((x, y));
                }
            }
        }
        samples
    }

    #[test]
    fn a_horizontal_line_two_samples_wide_covers_two_rows() {
        let mut canvas = Canvas::new(8, 6);
        canvas.clear([0.0; 3], [0.0; 3]);
        draw_line(
            &mut canvas,
            point(1.0, 3.0),
            point(5.0, 3.0),
            2,
            [1.0; 3],
            1.0,
        );
        let expected: Vec<_> = (2..4).flat_map(|y| (1..5).map(move |x| (x, y))).collect();
        assert_eq!(drawn(&canvas), expected);
    }

    #[test]
    fn a_steep_line_has_one_sample_per_row_and_no_gaps() {
        let mut canvas = Canvas::new(10, 10);
        canvas.clear([0.0; 3], [0.0; 3]);
        draw_line(
            &mut canvas,
            point(2.0, 0.0),
            point(5.0, 10.0),
            1,
            [1.0; 3],
            1.0,
        );
        let samples = drawn(&canvas);
        assert_eq!(samples.len(), 10);
        assert!(samples.iter().enumerate().all(|(row, &(_, y))| y == row));
    }

    #[test]
    fn a_line_behind_a_surface_is_hidden_and_one_on_it_shows_half_blended() {
        let mut canvas = Canvas::new(8, 4);
        canvas.clear([0.0; 3], [0.0; 3]);
        canvas.depth.fill(1.0);
        let behind = |x, y| ScreenPoint {
            x,
            y,
            inv_depth: 0.5,
        };
        draw_line(
            &mut canvas,
            behind(0.0, 1.5),
            behind(8.0, 1.5),
            1,
            [1.0; 3],
            1.0,
        );
        assert!(drawn(&canvas).is_empty());
        draw_line(
            &mut canvas,
            point(0.0, 1.5),
            point(8.0, 1.5),
            1,
            [1.0; 3],
            0.5,
        );
        assert_eq!(canvas.colour[canvas.index(3, 1)], [0.5; 3]);
    }
}
