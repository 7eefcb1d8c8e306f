//! One frame of a scene: the surfaces, then the springs, then the point
//! masses, on a canvas that starts as the background gradient; the canvas
//! is then filtered down to the output image.
//!
//! For each frame's positions:
//!
//! 1. project every vertex once (`camera.rs`);
//! 2. if the faces have 3 or more corners, compute the vertex normals
//!    (`lighting.rs`), fan-triangulate every face and fill each triangle
//!    (`triangle.rs`), shading each sample with the texture colour at its
//!    perspective-correct `(u, v)` (`texture.rs`), or the cloth blue, times
//!    the two-sided Lambert brightness of its interpolated normal;
//! 3. draw every spring as a line (`lines.rs`);
//! 4. draw every vertex as a disc, pinned vertices last, in silver
//!    (`discs.rs`);
//! 5. average the supersamples into pixels (`canvas.rs`).
//!
//! Scenes whose faces are 2-corner springs (a single spring, a chain, a net)
//! have no surfaces: steps 3 and 4 draw them. On a cloth, thousands of
//! springs and masses a few pixels apart would hide the surface entirely, so
//! there steps 3 and 4 are the viewer's `L` key (`--springs`): off by
//! default, when only the pinned vertices are drawn. Cost: `O(samples +
//! faces + springs + vertices)`, plus the samples the primitives cover.

use super::camera::{Camera, ScreenPoint};
use super::canvas::Canvas;
use super::discs::{draw_disc, DiscStyle};
use super::lighting::{lambert, toward_light, toward_viewer, vertex_normals};
use super::lines::draw_line;
use super::look::{
    mass_radius, Rgb, AMBIENT, BACKGROUND_BOTTOM, BACKGROUND_TOP, CLOTH, MASS, MASS_RADIUS,
    MASS_RADIUS_LIMITS, PIN, PIN_OUTLINE, PIN_OUTLINE_WIDTH, PIN_RADIUS, SPRING, SPRING_OPACITY,
    SPRING_WIDTH, SUPERSAMPLING,
};
use super::texture::Texture;
use super::triangle::{fill_triangle, Fragment};
use super::vector::{combine, normalize_f32};
use masssprings::mesh::fan::fan_corners;
use masssprings::mesh::procedural::RgbImage;
use masssprings::mesh::Scene;

/// Draws frames of one scene through one camera, reusing its buffers.
pub struct FrameRenderer<'a> {
    scene: &'a Scene,
    texture: Option<Texture>,
    camera: Camera,
    canvas: Canvas,
    /// Per vertex: where it lands on the canvas (this frame).
    projected: Vec<ScreenPoint>,
    /// Per vertex: the unit normal (this frame).
    normals: Vec<[f32; 3]>,
    is_pinned: Vec<bool>,
    /// Draw every spring and point mass, not only the pinned vertices?
    springs: bool,
    /// The point masses' radius in world units, from the mesh spacing
    /// (0: a fixed [`MASS_RADIUS`] on screen, for a scene of springs).
    mass_radius: f64,
}

impl<'a> FrameRenderer<'a> {
    /// A renderer of `width × height` images of `scene` seen by `camera`
    /// (a camera made for the supersampled size
    /// `SUPERSAMPLING · width × SUPERSAMPLING · height`), textured with
    /// `texture` when the scene has texture coordinates. The springs and
    /// the point masses are drawn when the scene has no surfaces, or when
    /// `springs` asks for them; the pinned vertices always are.
    pub fn new(
        scene: &'a Scene,
        texture: Option<Texture>,
        camera: Camera,
        (width, height): (usize, usize),
        springs: bool,
    ) -> FrameRenderer<'a> {
        let mut is_pinned = vec![false; scene.vertices.len()];
        for &v in &scene.pinned {
            is_pinned[v] = true;
        }
        FrameRenderer {
            scene,
            texture: texture.filter(|_| !scene.face_texture_coords.is_empty()),
            camera,
            canvas: Canvas::new(SUPERSAMPLING * width, SUPERSAMPLING * height),
            projected: Vec::with_capacity(scene.vertices.len()),
            normals: Vec::with_capacity(scene.vertices.len()),
            is_pinned,
            springs: springs || !has_surfaces(scene),
            mass_radius: if has_surfaces(scene) {
                mass_radius(&scene.vertices, &scene.springs)
            } else {
                0.0
            },
        }
    }

    /// The image of the scene with its vertices at `positions`.
    pub fn render(&mut self, positions: &[[f64; 3]]) -> RgbImage {
        self.canvas.clear(BACKGROUND_TOP, BACKGROUND_BOTTOM);
        self.projected.clear();
        self.projected
            .extend(positions.iter().map(|&p| self.camera.project(p)));
        self.draw_surfaces(positions);
        if self.springs {
            self.draw_springs();
        }
        self.draw_masses();
        self.canvas.downsample(SUPERSAMPLING)
    }

    /// Fills the fan triangles of every face of 3 or more corners.
    fn draw_surfaces(&mut self, positions: &[[f64; 3]]) {
        if !has_surfaces(self.scene) {
            return;
        }
        vertex_normals(positions, &self.scene.faces, &mut self.normals);
        let light = toward_light();
        for (f, face) in self.scene.faces.iter().enumerate() {
            for corners in fan_corners(face.len()) {
                let vertices = corners.map(|corner| face[corner]);
                let normals = vertices.map(|v| self.normals[v]);
                let uvs = self.texture.as_ref().map(|_| {
                    corners.map(|corner| {
                        let uv =
                            self.scene.texture_coords[self.scene.face_texture_coords[f][corner]];
                        [uv[0] as f32, uv[1] as f32]
                    })
                });
                let texture = self.texture.as_ref();
                let shade = |fragment: &Fragment| -> Rgb {
                    let base = match (texture, uvs) {
                        (Some(texture), Some(uvs)) => {
                            texture.sample(combine(fragment.weights, uvs))
                        }
                        _ => CLOTH,
                    };
                    // A degenerate spot (normals cancelling) gets ambient light only.
                    let brightness = normalize_f32(combine(fragment.weights, normals))
                        .map_or(AMBIENT, |n| {
                            lambert(toward_viewer(n, fragment.front_facing), light)
                        });
                    base.map(|c| c * brightness)
                };
                fill_triangle(&mut self.canvas, vertices.map(|v| self.projected[v]), shade);
            }
        }
    }

    /// Every spring as a line.
    fn draw_springs(&mut self) {
        let width = (SPRING_WIDTH * SUPERSAMPLING as f32).round() as usize;
        for &[i, j] in &self.scene.springs {
            draw_line(
                &mut self.canvas,
                self.projected[i],
                self.projected[j],
                width,
                SPRING,
                SPRING_OPACITY,
            );
        }
    }

    /// Every vertex as a disc (only the pinned ones unless `springs`);
    /// pinned ones last, so they stay on top.
    fn draw_masses(&mut self) {
        let scale = SUPERSAMPLING as f32;
        let mass = DiscStyle {
            fill: MASS,
            radius: MASS_RADIUS * scale,
            outline: None,
        };
        let pin = DiscStyle {
            fill: PIN,
            radius: PIN_RADIUS * scale,
            outline: Some((PIN_OUTLINE, PIN_OUTLINE_WIDTH * scale)),
        };
        let kinds: &[bool] = if self.springs {
            &[false, true]
        } else {
            &[true]
        };
        let [least, most] = MASS_RADIUS_LIMITS.map(|r| r * scale);
        let focal = self.camera.focal() as f32;
        for &pinned in kinds {
            for (v, &centre) in self.projected.iter().enumerate() {
                if self.is_pinned[v] != pinned {
                    continue;
                }
                if pinned {
                    draw_disc(&mut self.canvas, centre, &pin);
                } else if self.mass_radius > 0.0 {
                    // Sized to the mesh: nearer dots are larger.
                    let radius = self.mass_radius as f32 * focal * centre.inv_depth;
                    let style = DiscStyle {
                        radius: radius.clamp(least, most),
                        ..mass
                    };
                    draw_disc(&mut self.canvas, centre, &style);
                } else {
                    draw_disc(&mut self.canvas, centre, &mass);
                }
            }
        }
    }
}

/// Are the scene's faces polygons (3 or more corners), not springs?
pub fn has_surfaces(scene: &Scene) -> bool {
    scene.faces.first().is_some_and(|face| face.len() >= 3)
}
