//! A 256-colour palette for a whole animation by median cut, and the
//! mapping of every pixel to its nearest palette colour (a GIF stores at
//! most 256 colours).
//!
//! **Histogram.** The distinct colours of all frames, each with the number
//! of pixels that have it.
//!
//! **Median cut** (Heckbert 1982). Start from one box around all colours.
//! Repeatedly take the box with the largest `pixels × longest side`, sort
//! its colours along that side and split it at the pixel-weighted median,
//! until there are 256 boxes (or no box holds two colours). Each box's
//! palette colour is the pixel-weighted mean of its colours. The score
//! favours boxes that hold many pixels (the background's gradient gets
//! enough shades not to show bands) and boxes that span many colours (the
//! small red masses keep their own colour).
//!
//! **Mapping.** Each distinct colour is mapped once to the nearest palette
//! colour (squared RGB distance); a pixel is then looked up by its colour.
//! No dithering: it would add noise that moves from frame to frame and makes
//! the GIF larger. Cost: `O(pixels + colours · (log colours + 256))`.
//!
//! Source: P. Heckbert, *Color image quantization for frame buffer
//! display*, SIGGRAPH 1982.

use masssprings::mesh::procedural::RgbImage;
use std::collections::HashMap;

/// The colours of an animation and the lookup from a pixel to one of them.
#[derive(Debug, Clone)]
pub struct Palette {
    /// At most 256 colours.
    pub colours: Vec<[u8; 3]>,
    /// Per colour of the images, the index of its nearest palette colour.
    nearest: HashMap<[u8; 3], u8>,
}

/// A box of the median cut: distinct colours and the pixels of each.
struct ColourBox {
    /// (colour, pixels) pairs.
    colours: Vec<([u8; 3], u64)>,
    pixels: u64,
    /// The channel along which the box is longest, and that length.
    longest_side: (usize, u8),
}

impl ColourBox {
    fn new(colours: Vec<([u8; 3], u64)>) -> ColourBox {
        let pixels = colours.iter().map(|&(_, n)| n).sum();
        let longest_side = (0..3)
            .map(|k| {
                let values = colours.iter().map(|(colour, _)| colour[k]);
                let (low, high) = values.fold((u8::MAX, 0), |(lo, hi), v| (lo.min(v), hi.max(v)));
                (k, high.saturating_sub(low))
            })
            .max_by_key(|&(_, length)| length)
            .expect("three channels");
        ColourBox {
            colours,
            pixels,
            longest_side,
        }
    }

    /// Splits the box at the pixel-weighted median of its longest side.
    fn split(mut self) -> (ColourBox, ColourBox) {
        let channel = self.longest_side.0;
        self.colours
            .sort_unstable_by_key(|(colour, _)| colour[channel]);
        let mut below = 0;
        let mut at = 1;
        for (i, &(_, n)) in self.colours.iter().enumerate() {
            below += n;
            if 2 * below >= self.pixels {
                at = i + 1;
                break;
            }
        }
        let at = at.clamp(1, self.colours.len() - 1);
        let upper = self.colours.split_off(at);
        (ColourBox::new(self.colours), ColourBox::new(upper))
    }

    /// The pixel-weighted mean colour.
    fn mean(&self) -> [u8; 3] {
        std::array::from_fn(|k| {
            let sum: u64 = self.colours.iter().map(|&(c, n)| u64::from(c[k]) * n).sum();
            ((sum + self.pixels / 2) / self.pixels) as u8
        })
    }
}

/// The pixels of `image` as colours.
fn pixels(image: &RgbImage) -> impl Iterator<Item = [u8; 3]> + '_ {
    image
        .pixels
        .chunks_exact(3)
        .map(|rgb| [rgb[0], rgb[1], rgb[2]])
}

impl Palette {
    /// The median-cut palette of at most `max_colours` (2 to 256) colours
    /// for all pixels of `images`.
    ///
    /// # Panics
    /// If there are no pixels, or `max_colours` is outside 2..=256.
    pub fn median_cut(images: &[RgbImage], max_colours: usize) -> Palette {
        assert!((2..=256).contains(&max_colours));
        let mut histogram: HashMap<[u8; 3], u64> = HashMap::new();
        for image in images {
            // Runs of one colour (the background's rows) cost one look-up.
            let mut run: Option<([u8; 3], u64)> = None;
            for colour in pixels(image) {
                match &mut run {
                    Some((c, n)) if *c == colour => *n += 1,
                    _ => {
                        if let Some((c, n)) = run {
                            *histogram.entry(c).or_default() += n;
                        }
                        run = Some((colour, 1));
                    }
                }
            }
            if let Some((c, n)) = run {
                *histogram.entry(c).or_default() += n;
            }
        }
        assert!(!histogram.is_empty(), "no pixels to make a palette of");
        // Sorted, so that the same images always give the same palette.
        let mut colours: Vec<([u8; 3], u64)> = histogram.iter().map(|(&c, &n)| (c, n)).collect();
        colours.sort_unstable();
        let mut boxes = vec![ColourBox::new(colours)];
        while boxes.len() < max_colours {
            let widest = boxes
                .iter()
                .enumerate()
                .filter(|(_, b)| b.colours.len() > 1)
                .max_by_key(|(_, b)| b.pixels * u64::from(b.longest_side.1));
            let Some((i, _)) = widest else { break };
            let (low, high) = boxes.swap_remove(i).split();
            boxes.push(low);
            boxes.push(high);
        }
        let colours: Vec<[u8; 3]> = boxes.iter().map(ColourBox::mean).collect();
        let nearest = histogram
            .into_keys()
            .map(|c| (c, nearest_colour(&colours, c)))
            .collect();
        Palette { colours, nearest }
    }

    /// `image`, whose colours must be among those the palette was made
    /// from, as palette indices, one byte per pixel.
    ///
    /// # Panics
    /// For a colour the palette was not made from.
    pub fn indices(&self, image: &RgbImage) -> Vec<u8> {
        let mut last: Option<([u8; 3], u8)> = None;
        pixels(image)
            .map(|colour| match last {
                Some((c, index)) if c == colour => index,
                _ => {
                    let index = self.nearest[&colour];
                    last = Some((colour, index));
                    index
                }
            })
            .collect()
    }
}

/// The index of the colour of `colours` nearest to `target`.
fn nearest_colour(colours: &[[u8; 3]], target: [u8; 3]) -> u8 {
    let distance = |c: &[u8; 3]| -> i32 {
        (0..3)
            .map(|k| (i32::from(c[k]) - i32::from(target[k])).pow(2))
            .sum()
    };
    (0..colours.len())
        .min_by_key(|&i| distance(&colours[i]))
        .expect("a non-empty palette") as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(pixels: &[[u8; 3]]) -> RgbImage {
        RgbImage {
            width: pixels.len() as u32,
            height: 1,
            pixels: pixels.concat(),
        }
    }

    #[test]
    fn few_colours_are_kept_exactly() {
        let colours = [[255, 0, 0], [0, 128, 0], [10, 20, 200], [240, 240, 240]];
        let palette = Palette::median_cut(&[image(&colours)], 256);
        assert_eq!(palette.colours.len(), 4);
        let indices = palette.indices(&image(&colours));
        for (c, i) in colours.iter().zip(indices) {
            assert_eq!(palette.colours[i as usize], *c);
        }
    }

    #[test]
    fn many_colours_are_cut_to_the_limit_and_map_to_near_ones() {
        let pixels: Vec<[u8; 3]> = (0..4096)
            .map(|i| {
                [
                    (i % 16 * 16) as u8,
                    (i / 16 % 16 * 16) as u8,
                    (i / 256 * 16) as u8,
                ]
            })
            .collect();
        let palette = Palette::median_cut(&[image(&pixels)], 16);
        assert_eq!(palette.colours.len(), 16);
        let indices = palette.indices(&image(&pixels));
        for (p, i) in pixels.iter().zip(indices) {
            let found = palette.colours[i as usize];
            let error: i32 = (0..3)
                .map(|k| (i32::from(found[k]) - i32::from(p[k])).abs())
                .max()
                .unwrap();
            assert!(error <= 128, "{p:?} → {found:?}");
        }
    }
}
