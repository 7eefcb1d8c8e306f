//! Writing the rendered frames: an animated GIF, or a PNG of one frame.
//!
//! **GIF.** One global palette for the whole animation (`palette.rs`), so
//! colours do not flicker between frames. The first frame is stored whole;
//! each later one stores only the smallest rectangle holding the pixels that
//! changed, drawn over the previous frame (disposal "keep"): the background
//! never changes, so most of each frame costs nothing. The file loops
//! forever (the NETSCAPE2.0 extension).
//!
//! **Timing.** A GIF's delays are whole centiseconds, and the frames are
//! `every × Δt = every/30 s` apart. Frame `i` waits
//! `round(100 (i+1) every/30) − round(100 i every/30)` centiseconds, so the
//! delays alternate (3, 3, 4, … for `every = 1`) and the animation keeps in
//! step with simulated time instead of drifting. The LZW compression is the
//! `gif` crate's.
//!
//! **PNG.** 8-bit RGB, by the `png` crate.
//!
//! Sources: CompuServe, *Graphics Interchange Format version 89a*, 1990;
//! W3C, *PNG Specification*, 2nd ed., 2003.

use super::palette::Palette;
use masssprings::mesh::procedural::RgbImage;
use std::io::{self, Write};

/// The delay after frame `i` in centiseconds, for frames `seconds` apart.
pub fn delay_centiseconds(i: usize, seconds: f64) -> u16 {
    let at = |frame: usize| (100.0 * seconds * frame as f64).round();
    (at(i + 1) - at(i)).clamp(1.0, f64::from(u16::MAX)) as u16
}

/// The smallest rectangle `(left, top, width, height)` holding every pixel
/// where `previous` and `current` (indices of `width`-wide images) differ;
/// `None` when they are the same.
pub fn changed_rectangle(
    previous: &[u8],
    current: &[u8],
    width: usize,
) -> Option<(usize, usize, usize, usize)> {
    let (mut left, mut top, mut right, mut bottom) = (usize::MAX, usize::MAX, 0, 0);
    for (i, (a, b)) in previous.iter().zip(current).enumerate() {
        if a != b {
            let (x, y) = (i % width, i / width);
            left = left.min(x);
            right = right.max(x);
            top = top.min(y);
            bottom = bottom.max(y);
        }
    }
    (left != usize::MAX).then(|| (left, top, right + 1 - left, bottom + 1 - top))
}

/// Writes `frames` (all the same size) as a looping GIF whose frames are
/// `seconds` apart.
///
/// # Errors
/// Any write error; a size beyond the GIF's 65,535 pixels.
pub fn write_gif(out: &mut dyn Write, frames: &[RgbImage], seconds: f64) -> io::Result<()> {
    let Some(first) = frames.first() else {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "no frames"));
    };
    let too_large = |_| io::Error::new(io::ErrorKind::InvalidInput, "image too large for a GIF");
    let width = u16::try_from(first.width).map_err(too_large)?;
    let height = u16::try_from(first.height).map_err(too_large)?;
    let palette = Palette::median_cut(frames, 256);
    let mut encoder = gif::Encoder::new(out, width, height, &palette.colours.concat())
        .map_err(io::Error::other)?;
    encoder
        .set_repeat(gif::Repeat::Infinite)
        .map_err(io::Error::other)?;
    let mut previous: Option<Vec<u8>> = None;
    for (i, image) in frames.iter().enumerate() {
        let indices = palette.indices(image);
        let full = (0, 0, usize::from(width), usize::from(height));
        let (left, top, w, h) = match &previous {
            None => full,
            // Nothing moved: repeat one pixel, to keep the frame's delay.
            Some(previous) => changed_rectangle(previous, &indices, full.2).unwrap_or((0, 0, 1, 1)),
        };
        let mut rectangle = Vec::with_capacity(w * h);
        for y in top..top + h {
            let row = y * usize::from(width);
            rectangle.extend_from_slice(&indices[row + left..row + left + w]);
        }
        let mut frame = gif::Frame::from_indexed_pixels(w as u16, h as u16, rectangle, None);
        frame.left = left as u16;
        frame.top = top as u16;
        frame.delay = delay_centiseconds(i, seconds);
        frame.dispose = gif::DisposalMethod::Keep;
        encoder.write_frame(&frame).map_err(io::Error::other)?;
        previous = Some(indices);
    }
    encoder.into_inner().map_err(io::Error::other)?;
    Ok(())
}

/// Writes `image` as an 8-bit RGB PNG.
///
/// # Errors
/// Any write or encoding error.
pub fn write_png(out: &mut dyn Write, image: &RgbImage) -> io::Result<()> {
    let mut encoder = png::Encoder::new(out, image.width, image.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&image.pixels)?;
    writer.finish()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delays_keep_in_step_with_simulated_time() {
        let delays: Vec<u16> = (0..30).map(|i| delay_centiseconds(i, 1.0 / 30.0)).collect();
        assert_eq!(delays.iter().map(|&d| u32::from(d)).sum::<u32>(), 100);
        assert!(delays.iter().all(|&d| d == 3 || d == 4));
        let two: Vec<u16> = (0..15).map(|i| delay_centiseconds(i, 2.0 / 30.0)).collect();
        assert_eq!(two.iter().map(|&d| u32::from(d)).sum::<u32>(), 100);
    }

    #[test]
    fn the_changed_rectangle_bounds_the_differences() {
        let previous = vec![0u8; 20];
        let mut current = previous.clone();
        assert_eq!(changed_rectangle(&previous, &current, 5), None);
        current[5 + 1] = 1; // (1, 1)
        current[3 * 5 + 3] = 1; // (3, 3)
        assert_eq!(
            changed_rectangle(&previous, &current, 5),
            Some((1, 1, 3, 3))
        );
    }
}
