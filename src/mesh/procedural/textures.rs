//! Procedural textures for the cloth scenes, as 8-bit RGB pixels (the
//! application layer encodes them as PNG).
//!
//! * [`flag_design`]: our own flag: a deep blue field crossed by a golden
//!   zigzag (a spring) that runs from a white disk (a mass) at the hoist to
//!   the fly.
//! * [`tartan`]: a tartan: a sett (a symmetric sequence of coloured stripes)
//!   repeated in both directions and woven as a 2/2 twill, where each pixel
//!   shows the warp thread (the vertical stripe) or the weft thread (the
//!   horizontal one) along diagonal steps of two. The sett is 128 pixels
//!   long, so a tile whose size is a multiple of 128 wraps seamlessly.
//!
//! Rows run top to bottom (image order); texture coordinate `v = 1` is the
//! top row.
//!
//! Cost: `O(width × height)`.

/// An 8-bit RGB image: `pixels[3 (y·width + x) + channel]`, rows top to
/// bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

impl RgbImage {
    /// The image whose pixel `(x, y)` is `color(x, y)`.
    pub fn from_fn(width: u32, height: u32, color: impl Fn(u32, u32) -> [u8; 3]) -> RgbImage {
        let mut pixels = Vec::with_capacity(3 * width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                pixels.extend(color(x, y));
            }
        }
        RgbImage {
            width,
            height,
            pixels,
        }
    }

    /// The colour of pixel `(x, y)`.
    ///
    /// # Panics
    /// If `(x, y)` is outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        assert!(x < self.width && y < self.height, "pixel outside the image");
        let start = 3 * (y as usize * self.width as usize + x as usize);
        [
            self.pixels[start],
            self.pixels[start + 1],
            self.pixels[start + 2],
        ]
    }
}

const NAVY: [u8; 3] = [22, 36, 92];
const GOLD: [u8; 3] = [236, 178, 38];
const WHITE: [u8; 3] = [246, 244, 236];

/// The flag design, `width × height` pixels (best at 2 : 1).
pub fn flag_design(width: u32, height: u32) -> RgbImage {
    let h = f64::from(height);
    let disk_center = (0.5 * h, 0.5 * h);
    let disk_radius = 0.28 * h;
    let zigzag_period = 0.25 * h;
    let zigzag_amplitude = 0.18 * h;
    let stroke = 0.05 * h;
    RgbImage::from_fn(width, height, |x, y| {
        let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let from_disk = (px - disk_center.0).hypot(py - disk_center.1);
        if from_disk <= disk_radius {
            return WHITE;
        }
        // triangle wave in [-1, 1] along x
        let phase = (px / zigzag_period).fract();
        let wave = 4.0 * (phase - 0.5).abs() - 1.0;
        let zigzag_y = 0.5 * h + zigzag_amplitude * wave;
        if px > disk_center.0 && (py - zigzag_y).abs() <= stroke {
            GOLD
        } else {
            NAVY
        }
    })
}

/// One half of the tartan's sett, `(colour, threads)`, mirrored to make the
/// whole sett (64 + 64 = 128 threads).
const HALF_SETT: [([u8; 3], u32); 7] = [
    ([24, 34, 76], 20),  // navy
    ([178, 28, 40], 4),  // red
    ([24, 34, 76], 4),   // navy
    ([28, 86, 52], 24),  // green
    ([18, 18, 22], 4),   // black
    ([226, 196, 72], 2), // yellow
    ([18, 18, 22], 6),   // black
];

/// The tartan as a `size × size` tile; seamless when `size` is a multiple
/// of 128.
pub fn tartan(size: u32) -> RgbImage {
    RgbImage::from_fn(size, size, |x, y| {
        // 2/2 twill: the warp shows for two steps, then the weft for two,
        // shifted by one each row, which draws the diagonals of the weave.
        if (x + y) % 4 < 2 {
            sett_colour(x)
        } else {
            sett_colour(y)
        }
    })
}

/// The colour of thread `position` of the repeating, mirrored sett.
fn sett_colour(position: u32) -> [u8; 3] {
    let half: u32 = HALF_SETT.iter().map(|&(_, threads)| threads).sum();
    let in_sett = position % (2 * half);
    let mirrored = if in_sett < half {
        in_sett
    } else {
        2 * half - 1 - in_sett
    };
    let mut start = 0;
    for &(colour, threads) in &HALF_SETT {
        if mirrored < start + threads {
            return colour;
        }
        start += threads;
    }
    unreachable!("the position falls within the half sett")
}
