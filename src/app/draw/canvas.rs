//! The canvas: a colour buffer and a depth buffer (the z-buffer) at
//! `SUPERSAMPLING ×` the output resolution, the background gradient they
//! start from, and the box filter that turns them into the output image.
//!
//! **Z-buffer.** Each sample keeps the `1/z` of the nearest surface drawn on
//! it so far (0 = nothing: infinitely far). A new fragment is kept only when
//! its `1/z` is larger, i.e. nearer, so surfaces may be drawn in any order
//! (Catmull 1974).
//!
//! **Supersampling.** Drawing at `s ×` the resolution and averaging each
//! `s × s` block of samples into one pixel (a box filter) smooths the
//! staircase along every edge, line and disc; `s = 2` gives 4 samples per
//! pixel for 4× the drawing work. Cost of the filter: `O(samples)`.
//!
//! Source: Marschner & Shirley, *Fundamentals of Computer Graphics*, 4th ed.
//! (2016), ch. 8 (z-buffer) and ch. 9 (antialiasing by supersampling and box
//! filtering); E. Catmull, *A subdivision algorithm for computer display of
//! curved surfaces*, PhD thesis, Utah, 1974 (the z-buffer).

use super::look::Rgb;
use masssprings::mesh::procedural::RgbImage;

/// Colour and depth samples, row by row from the top.
#[derive(Debug, Clone)]
pub struct Canvas {
    pub width: usize,
    pub height: usize,
    pub colour: Vec<Rgb>,
    /// `1/z` of the nearest surface per sample; 0 where there is none.
    pub depth: Vec<f32>,
}

impl Canvas {
    /// A `width × height` canvas of samples, black and empty.
    pub fn new(width: usize, height: usize) -> Canvas {
        Canvas {
            width,
            height,
            colour: vec![[0.0; 3]; width * height],
            depth: vec![0.0; width * height],
        }
    }

    /// Paints a vertical gradient from `top` to `bottom` and empties the
    /// z-buffer.
    pub fn clear(&mut self, top: Rgb, bottom: Rgb) {
        for y in 0..self.height {
            let t = y as f32 / (self.height.max(2) - 1) as f32;
            let colour: Rgb = std::array::from_fn(|k| (1.0 - t) * top[k] + t * bottom[k]);
            self.colour[y * self.width..(y + 1) * self.width].fill(colour);
        }
        self.depth.fill(0.0);
    }

    /// The index of sample `(x, y)`.
    pub fn index(&self, x: usize, y: usize) -> usize {
        y * self.width + x
    }

    /// Mixes `colour` into sample `i` with weight `opacity` (the "over"
    /// operator: `c ← (1 − α) c + α colour`).
    pub fn blend(&mut self, i: usize, colour: Rgb, opacity: f32) {
        let old = self.colour[i];
        self.colour[i] = std::array::from_fn(|k| (1.0 - opacity) * old[k] + opacity * colour[k]);
    }

    /// The image of `factor × factor` blocks of samples, each averaged into
    /// one pixel (a box filter), rounded to 8 bits.
    pub fn downsample(&self, factor: usize) -> RgbImage {
        let (width, height) = (self.width / factor, self.height / factor);
        let weight = 255.0 / (factor * factor) as f32;
        let mut pixels = Vec::with_capacity(3 * width * height);
        for y in 0..height {
            for x in 0..width {
                let mut sum = [0.0f32; 3];
                for sy in 0..factor {
                    let row = (factor * y + sy) * self.width;
                    for sx in 0..factor {
                        let sample = self.colour[row + factor * x + sx];
                        for k in 0..3 {
                            sum[k] += sample[k];
                        }
                    }
                }
                pixels.extend(sum.map(|s| (s * weight).round().clamp(0.0, 255.0) as u8));
            }
        }
        RgbImage {
            width: width as u32,
            height: height as u32,
            pixels,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gradient_runs_from_top_to_bottom_and_the_depth_is_empty() {
        let mut canvas = Canvas::new(3, 5);
        canvas.clear([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(canvas.colour[canvas.index(1, 0)], [1.0, 0.0, 0.0]);
        assert_eq!(canvas.colour[canvas.index(2, 4)], [0.0, 0.0, 1.0]);
        assert_eq!(canvas.colour[canvas.index(0, 2)], [0.5, 0.0, 0.5]);
        assert!(canvas.depth.iter().all(|&d| d == 0.0));
    }

    #[test]
    fn downsampling_averages_each_block() {
        let mut canvas = Canvas::new(4, 2);
        canvas.clear([0.0; 3], [0.0; 3]);
        let i = canvas.index(0, 0);
        canvas.colour[i] = [1.0, 1.0, 1.0];
        let image = canvas.downsample(2);
        assert_eq!((image.width, image.height), (2, 1));
        assert_eq!(image.pixels, vec![64, 64, 64, 0, 0, 0]);
    }
}
