//! The scene's texture: a PNG decoded into colours, sampled at texture
//! coordinates `(u, v)` with bilinear filtering.
//!
//! **Coordinates.** `u` runs left to right and `v` bottom to top (the OBJ
//! convention: `v = 1` is the image's top row), repeating outside `[0, 1]`.
//! Texel `(i, j)` (column `i`, row `j` from the top) has its centre at
//! `s = i + ½`, `t = j + ½` where `s = u · width` and `t = (1 − v) · height`.
//!
//! **Bilinear filtering.** The colour at `(s, t)` blends the four texel
//! centres around it, weighted by the fractions `f_s = s − ½ − ⌊s − ½⌋` and
//! `f_t` likewise:
//! `(1−f_s)(1−f_t) T₀₀ + f_s(1−f_t) T₁₀ + (1−f_s) f_t T₀₁ + f_s f_t T₁₁`,
//! so magnified textures look smooth instead of blocky. (No mipmaps: a
//! texture shrunk a lot may shimmer.) Cost: `O(1)` per sample.
//!
//! Source: Marschner & Shirley, *Fundamentals of Computer Graphics*, 4th ed.
//! (2016), ch. 11 (texture lookups, bilinear interpolation). Decoding is
//! the `png` crate's.
//!
//! **Hostile files.** The size in the PNG header is checked against the
//! memory limit (`masssprings::memory`, [`TEXEL_BYTES`] a pixel) before the
//! image is decoded, and the decoder's own allocations are capped at the
//! same limit, so a 100-byte file claiming 100000×100000 pixels is refused
//! with the estimate instead of aborting the process.

use super::look::Rgb;
use masssprings::memory;
use std::io::{BufRead, Cursor, Seek};
use std::path::Path;

pub use masssprings::mesh::PNG_SIGNATURE;

/// The bytes of the PNG file at `path`, read as every input is
/// (`masssprings::files`: at most the input limit, a pipe waited for a few
/// seconds at most) and refused at its first bytes when they are not a
/// PNG's signature (`/dev/zero`, a text file).
///
/// # Errors
/// A message naming the texture's file and the problem.
pub fn read_png_file(path: &Path) -> Result<Vec<u8>, String> {
    masssprings::files::read_bytes_of_format(path, PNG_SIGNATURE, "PNG")
        .map_err(|e| format!("texture {e}"))
}

/// What one pixel costs while decoding: up to 4 bytes of the decoded frame
/// and the 12 bytes of its [`Rgb`] texel.
pub const TEXEL_BYTES: u64 = 16;

/// A decoded image, rows from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    texels: Vec<Rgb>,
}

impl Texture {
    /// A `width × height` texture from colours, rows from the top.
    ///
    /// # Panics
    /// If `texels` does not hold `width × height` colours, or the size is 0.
    pub fn new(width: usize, height: usize, texels: Vec<Rgb>) -> Texture {
        assert!(width > 0 && height > 0 && texels.len() == width * height);
        Texture {
            width,
            height,
            texels,
        }
    }

    /// Reads the PNG at `path` (grey or colour, with or without alpha, any
    /// bit depth; alpha is ignored).
    ///
    /// # Errors
    /// A message naming the file for an unreadable or invalid PNG, or one
    /// whose pixels would not fit in memory.
    pub fn read_png(path: &Path) -> Result<Texture, String> {
        let bytes = read_png_file(path)?;
        Texture::decode_png(Cursor::new(bytes), memory::limit())
            .map_err(|problem| format!("texture {}: {problem}", path.display()))
    }

    /// Decodes a PNG from `input`, as [`Texture::read_png`] does, within
    /// the memory `limit`.
    ///
    /// # Errors
    /// The problem (without a file name) for an invalid PNG, or one whose
    /// pixels would not fit in memory.
    pub fn decode_png(input: impl BufRead + Seek, limit: memory::Limit) -> Result<Texture, String> {
        let failed = |e: &dyn std::fmt::Display| e.to_string();
        let mut decoder = png::Decoder::new_with_limits(
            input,
            png::Limits {
                bytes: usize::try_from(limit.bytes).unwrap_or(usize::MAX),
            },
        );
        decoder.set_transformations(png::Transformations::normalize_to_color8());
        let header = decoder.read_header_info().map_err(|e| failed(&e))?;
        let (width, height) = (header.width, header.height);
        let pixels = u64::from(width) * u64::from(height);
        memory::check_against(
            limit,
            memory::bytes_for(pixels, TEXEL_BYTES),
            || format!("a {width}×{height} texture"),
            "use a smaller image",
        )
        .map_err(|e| failed(&e))?;
        let mut reader = decoder.read_info().map_err(|e| failed(&e))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| failed(&"image too large"))?;
        let mut bytes = vec![0; size];
        let info = reader.next_frame(&mut bytes).map_err(|e| failed(&e))?;
        let channels = match info.color_type {
            png::ColorType::Grayscale => 1,
            png::ColorType::GrayscaleAlpha => 2,
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            png::ColorType::Indexed => return Err(failed(&"indexed colours were not expanded")),
        };
        let (width, height) = (info.width as usize, info.height as usize);
        if width == 0 || height == 0 {
            return Err(failed(&"empty image"));
        }
        if bytes.len() < width * height * channels {
            return Err(failed(&"the frame is larger than the decoded image"));
        }
        let texels = (0..width * height)
            .map(|i| {
                let texel = &bytes[i * channels..];
                let channel = |k: usize| f32::from(texel[if channels < 3 { 0 } else { k }]) / 255.0;
                [channel(0), channel(1), channel(2)]
            })
            .collect();
        Ok(Texture::new(width, height, texels))
    }

    /// The bilinearly filtered colour at `(u, v)`, repeating the image
    /// outside `[0, 1]²`.
    pub fn sample(&self, uv: [f32; 2]) -> Rgb {
        let s = uv[0] * self.width as f32 - 0.5;
        let t = (1.0 - uv[1]) * self.height as f32 - 0.5;
        let (s0, t0) = (s.floor(), t.floor());
        let (fs, ft) = (s - s0, t - t0);
        let column = |offset: f32| (s0 + offset).rem_euclid(self.width as f32) as usize;
        let row = |offset: f32| (t0 + offset).rem_euclid(self.height as f32) as usize;
        let texel = |i: usize, j: usize| self.texels[j * self.width + i];
        let (i0, i1, j0, j1) = (column(0.0), column(1.0), row(0.0), row(1.0));
        let (t00, t10, t01, t11) = (texel(i0, j0), texel(i1, j0), texel(i0, j1), texel(i1, j1));
        std::array::from_fn(|k| {
            (1.0 - ft) * ((1.0 - fs) * t00[k] + fs * t10[k])
                + ft * ((1.0 - fs) * t01[k] + fs * t11[k])
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mutate;

    /// 2 × 2: red, green on the top row; blue, white below.
    fn checker() -> Texture {
        Texture::new(
            2,
            2,
            vec![
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
            ],
        )
    }

    #[test]
    fn texel_centres_give_their_own_colour_and_v_runs_up() {
        let texture = checker();
        assert_eq!(texture.sample([0.25, 0.75]), [1.0, 0.0, 0.0]);
        assert_eq!(texture.sample([0.75, 0.75]), [0.0, 1.0, 0.0]);
        assert_eq!(texture.sample([0.25, 0.25]), [0.0, 0.0, 1.0]);
    }

    #[test]
    fn between_centres_the_colours_blend_and_the_image_repeats() {
        let texture = checker();
        assert_eq!(texture.sample([0.5, 0.75]), [0.5, 0.5, 0.0]);
        assert_eq!(texture.sample([1.25, 1.75]), texture.sample([0.25, 0.75]));
        assert_eq!(texture.sample([-0.75, -0.25]), texture.sample([0.25, 0.75]));
    }

    #[test]
    fn the_bundled_flag_texture_decodes() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/flag.png");
        let texture = Texture::read_png(&path).unwrap();
        assert_eq!((texture.width, texture.height), (320, 160));
        assert!(Texture::read_png(Path::new("no-such.png")).is_err());
    }

    /// A small limit for the tests: no mutated header can make them
    /// allocate much.
    const TEST_LIMIT: memory::Limit = memory::Limit {
        bytes: 64 << 20,
        source: "the tests' limit",
    };

    fn corpus(name: &str) -> Vec<u8> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        std::fs::read(root.join(name)).unwrap()
    }

    #[test]
    fn a_header_claiming_100000_by_100000_pixels_is_refused_before_decoding() {
        let bytes = corpus("tests/hostile/huge-header.png");
        let problem = Texture::decode_png(std::io::Cursor::new(bytes), TEST_LIMIT).unwrap_err();
        assert!(
            problem.starts_with(
                "a 100000×100000 texture would need 160 GB; the limit here is 0.067 GB"
            ),
            "{problem}"
        );
    }

    #[test]
    fn mutated_pngs_decode_or_fail_cleanly() {
        let seeds = [
            corpus("data/flag.png"),
            corpus("data/tartan.png"),
            corpus("tests/hostile/huge-header.png"),
        ];
        let mut rng = mutate::Rng::new(2013);
        let mut decoded = 0;
        for case in 0..3000 {
            let input = mutate::mutate(&seeds[case % seeds.len()], &mut rng);
            match Texture::decode_png(std::io::Cursor::new(&input), TEST_LIMIT) {
                Ok(texture) => {
                    assert_eq!(texture.texels.len(), texture.width * texture.height);
                    decoded += 1;
                }
                Err(problem) => assert!(!problem.is_empty()),
            }
        }
        assert!(decoded > 0, "no mutation kept a decodable image");
    }
}
