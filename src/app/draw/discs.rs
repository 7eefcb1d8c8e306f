//! Point masses as small discs, optionally outlined, depth-tested like the
//! springs (`lines.rs`).
//!
//! A sample belongs to the disc of centre `c` and radius `r` when its centre
//! `p` has `|p − c| ≤ r`; it shows the outline colour when
//! `|p − c| > r − outline width`. The disc is drawn at the depth of its
//! vertex, slightly in front (`DEPTH_BIAS`), so a mass behind the cloth is
//! hidden. Cost: `O(r²)` samples.
//!
//! Source: Marschner & Shirley, *Fundamentals of Computer Graphics*, 4th ed.
//! (2016), ch. 8 (implicit shapes tested per sample).

use super::camera::ScreenPoint;
use super::canvas::Canvas;
use super::lines::visible;
use super::look::Rgb;

/// A disc's look: fill colour, radius in samples, and an optional outline
/// (colour, width in samples).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscStyle {
    pub fill: Rgb,
    pub radius: f32,
    pub outline: Option<(Rgb, f32)>,
}

/// Draws a disc of `style` centred on `centre`.
pub fn draw_disc(canvas: &mut Canvas, centre: ScreenPoint, style: &DiscStyle) {
    if centre.inv_depth <= 0.0 {
        return;
    }
    let r = style.radius;
    let range = |c: f32, size: usize| {
        let first = (c - r - 0.5).ceil().max(0.0);
        let last = (c + r - 0.5).floor().min(size as f32 - 1.0);
        first as usize..(last + 1.0).max(first) as usize
    };
    for y in range(centre.y, canvas.height) {
        for x in range(centre.x, canvas.width) {
            let (dx, dy) = (x as f32 + 0.5 - centre.x, y as f32 + 0.5 - centre.y);
            let distance = (dx * dx + dy * dy).sqrt();
            let i = canvas.index(x, y);
            if distance > r || !visible(canvas, i, centre.inv_depth) {
                continue;
            }
            canvas.colour[i] = match style.outline {
                Some((colour, width)) if distance > r - width => colour,
                _ => style.fill,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_disc_covers_the_samples_within_its_radius_with_an_outline_ring() {
        let mut canvas = Canvas::new(10, 10);
        canvas.clear([0.0; 3], [0.0; 3]);
        let style = DiscStyle {
            fill: [1.0, 0.0, 0.0],
            radius: 3.0,
            outline: Some(([0.0, 0.0, 1.0], 1.0)),
        };
        let centre = ScreenPoint {
            x: 5.0,
            y: 5.0,
            inv_depth: 1.0,
        };
        draw_disc(&mut canvas, centre, &style);
        for y in 0..10 {
            for x in 0..10 {
                let d = ((x as f32 + 0.5 - 5.0).powi(2) + (y as f32 + 0.5 - 5.0).powi(2)).sqrt();
                let expected = if d > 3.0 {
                    [0.0; 3]
                } else if d > 2.0 {
                    [0.0, 0.0, 1.0]
                } else {
                    [1.0, 0.0, 0.0]
                };
                assert_eq!(canvas.colour[canvas.index(x, y)], expected, "({x}, {y})");
            }
        }
    }
}
