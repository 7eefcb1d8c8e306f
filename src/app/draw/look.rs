//! The shared look: every colour, size and angle of a rendered frame, in one
//! place. The WebGL viewer (`masssprings view`) uses the same numbers, so a
//! GIF looks like the viewer's window.
//!
//! Colours are 0–1 RGB triples, used as they are (no gamma handling: the
//! arithmetic of shading and blending is done on the stored sRGB values, as
//! classic OpenGL does).

/// A colour: red, green, blue in `[0, 1]`.
pub type Rgb = [f32; 3];

/// `0xRRGGBB` as an [`Rgb`].
pub const fn hex(rgb: u32) -> Rgb {
    [
        ((rgb >> 16) & 0xff) as f32 / 255.0,
        ((rgb >> 8) & 0xff) as f32 / 255.0,
        (rgb & 0xff) as f32 / 255.0,
    ]
}

/// Background: a vertical gradient from this colour at the top…
pub const BACKGROUND_TOP: Rgb = hex(0xf4f6f8);
/// …to this one at the bottom.
pub const BACKGROUND_BOTTOM: Rgb = hex(0xdde3ea);

/// The mesh's colour when the scene has no texture (a cloth blue).
pub const CLOTH: Rgb = hex(0x5b8fd6);

/// Direction toward the light (upper left front), in world space; normalised
/// where it is used.
pub const TOWARD_LIGHT: [f64; 3] = [-0.4, 0.8, 0.45];
/// Light that reaches every surface whatever its orientation.
pub const AMBIENT: f32 = 0.35;
/// Weight of the two-sided Lambert term `|n·l|` (see `lighting.rs`).
pub const DIFFUSE: f32 = 0.65;

/// Springs: colour, opacity and width in output pixels.
pub const SPRING: Rgb = hex(0x33414f);
pub const SPRING_OPACITY: f32 = 0.5;
pub const SPRING_WIDTH: f32 = 1.0;

/// Point masses: discs of this colour and radius (output pixels).
pub const MASS: Rgb = hex(0xc0392b);
pub const MASS_RADIUS: f32 = 2.0;
/// In a mesh, a point mass's radius is this fraction of the median spring
/// rest length (so neighbouring dots never touch), in world units, kept
/// between these radii in output pixels.
pub const MASS_RADIUS_PER_SPACING: f64 = 0.2;
pub const MASS_RADIUS_LIMITS: [f32; 2] = [1.0, 6.0];

/// The world radius of the point masses of a mesh with springs
/// `springs` over `vertices`: [`MASS_RADIUS_PER_SPACING`] of the median
/// rest length (0 without springs).
pub fn mass_radius(vertices: &[[f64; 3]], springs: &[[usize; 2]]) -> f64 {
    let mut lengths: Vec<f64> = springs
        .iter()
        .map(|&[i, j]| {
            let (a, b) = (vertices[i], vertices[j]);
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        })
        .collect();
    if lengths.is_empty() {
        return 0.0;
    }
    let middle = lengths.len() / 2;
    let (_, median, _) = lengths.select_nth_unstable_by(middle, f64::total_cmp);
    MASS_RADIUS_PER_SPACING * *median
}
/// Pinned vertices: silver discs with a darker outline.
pub const PIN: Rgb = hex(0xc8ccd0);
pub const PIN_OUTLINE: Rgb = hex(0x7f8c8d);
pub const PIN_RADIUS: f32 = 3.0;
pub const PIN_OUTLINE_WIDTH: f32 = 1.0;

/// Camera: the bounding box's centre seen from this azimuth (degrees from
/// +z toward +x) and elevation (degrees above the horizontal plane)…
pub const AZIMUTH_DEGREES: f64 = 30.0;
pub const ELEVATION_DEGREES: f64 = 20.0;
/// …through a lens of this vertical field of view (degrees)…
pub const FIELD_OF_VIEW_DEGREES: f64 = 35.0;
/// …from a distance at which the box fills at most `1 / MARGIN` of the
/// half-width and half-height of the image (a 10% margin).
pub const MARGIN: f64 = 1.1;

/// Samples per output pixel along each axis (2 → 4 samples per pixel,
/// averaged: see `canvas.rs`).
pub const SUPERSAMPLING: usize = 2;
