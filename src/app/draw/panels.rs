//! Two pictures side by side, each with a label at its top left, a
//! one-pixel rule between them, and an optional warning at the bottom of
//! the right one: how `render --mistake` shows the handout's step beside a
//! student's.
//!
//! The panels are copied into a canvas at the output resolution (one sample
//! per pixel), the labels drawn with the plots' bitmap font (`text.rs`) at
//! one sample per dot, and the canvas read back as it is. Cost:
//! `O(pixels)`.

use super::canvas::Canvas;
use super::look::{Rgb, SPRING};
use super::text::{draw_text, text_height, Align};
use masssprings::mesh::procedural::RgbImage;

/// Ink of the labels and the rule.
const LABEL: Rgb = SPRING;

/// `panels[0] | panels[1]` (the same height), each with its label at the
/// top left, a one-pixel rule between them, and `warning` at the bottom of
/// the right one.
pub fn side_by_side(
    panels: &[RgbImage; 2],
    labels: &[String; 2],
    warning: Option<&str>,
) -> RgbImage {
    let (width, height) = (panels[0].width as usize, panels[0].height as usize);
    let mut canvas = Canvas::new(2 * width, height);
    for (k, panel) in panels.iter().enumerate() {
        for (i, rgb) in panel.pixels.chunks_exact(3).enumerate() {
            let at = canvas.index(k * width + i % width, i / width);
            canvas.colour[at] = std::array::from_fn(|c| f32::from(rgb[c]) / 255.0);
        }
        let x = (k * width + 4) as isize;
        draw_text(&mut canvas, &labels[k], (x, 4), 1, Align::Start, LABEL);
    }
    for y in 0..height {
        let at = canvas.index(width, y);
        canvas.colour[at] = LABEL;
    }
    if let Some(warning) = warning {
        let top = height.saturating_sub(text_height(1) + 4) as isize;
        let x = (width + 4) as isize;
        draw_text(&mut canvas, warning, (x, top), 1, Align::Start, LABEL);
    }
    canvas.downsample(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plain(width: u32, height: u32, value: u8) -> RgbImage {
        RgbImage::from_fn(width, height, |_, _| [value; 3])
    }

    #[test]
    fn the_panels_sit_side_by_side_with_a_rule_and_their_labels() {
        let panels = [plain(40, 20, 255), plain(40, 20, 0)];
        let labels = ["a".to_string(), "b".to_string()];
        let image = side_by_side(&panels, &labels, None);
        assert_eq!((image.width, image.height), (80, 20));
        let pixel = |x: usize, y: usize| &image.pixels[3 * (y * 80 + x)..3 * (y * 80 + x) + 3];
        assert_eq!(
            pixel(30, 18),
            [255; 3],
            "the left panel, away from its label"
        );
        assert_eq!(pixel(70, 18), [0; 3], "the right panel");
        let ink = [0x33, 0x41, 0x4f];
        assert_eq!(pixel(40, 10), ink, "the rule");
        let inked = (4..9).flat_map(|x| (4..12).map(move |y| (x, y)));
        assert!(
            inked.clone().any(|(x, y)| pixel(x, y) == ink),
            "the left label"
        );
        assert!(
            inked.clone().any(|(x, y)| pixel(x + 40, y) == ink),
            "the right label"
        );
        let warned = side_by_side(&panels, &labels, Some("w"));
        assert_ne!(warned.pixels, image.pixels, "the warning is drawn");
    }
}
