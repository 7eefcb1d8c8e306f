//! The camera: where the eye is, where it looks, and on which pixel a world
//! point lands (a pinhole camera with perspective projection).
//!
//! **Frame.** The camera looks at the target `c` (the centre of the scene's
//! bounding box) from the direction
//! `back = (cos e · sin a, sin e, cos e · cos a)`, azimuth `a` measured from
//! +z toward +x and elevation `e` above the horizontal plane (world y is
//! up). Its right-handed orthonormal basis is
//! `right = normalise(y × back)`, `up = back × right`, `back`. The eye sits at
//! `eye = c + D · back`.
//!
//! **Projection.** A point `p` has camera coordinates
//! `x = (p − eye)·right`, `y = (p − eye)·up` and depth
//! `z = (eye − p)·back > 0` in front of the eye. By similar triangles it
//! lands on the pixel
//!
//! ```text
//! px = W/2 + f · x / z,   py = H/2 − f · y / z,   f = (H/2) / tan(fov/2)
//! ```
//!
//! (pixel rows go down, hence the minus). The depth kept for each projected
//! point is `1/z`, not `z`: `1/z` is an affine function of `(px, py)` over a
//! triangle, so it interpolates linearly on the screen (`triangle.rs`), and
//! larger means nearer.
//!
//! **Framing.** The distance `D` is the smallest at which all eight corners
//! of the bounding box fit with the margin `M = 1.1`: a corner at offset `o`
//! from `c` has `x = o·right`, `y = o·up` and depth `D − o·back`, and fits
//! when `M |x| ≤ (D − o·back) tan(fov_x/2)` and likewise for `y`, so
//! `D = max over corners of o·back + M · max(|x| / tan(fov_x/2), |y| / tan(fov_y/2))`.
//! The box is the union of every frame's (`mod.rs`), so the camera holds
//! still through the animation. Cost: `O(1)` per projected point.
//!
//! Source: Marschner & Shirley, *Fundamentals of Computer Graphics*, 4th ed.
//! (2016), ch. 7 (viewing: camera frame, perspective projection).

pub use masssprings::mesh::bounding_box::BoundingBox;

use super::look::{AZIMUTH_DEGREES, ELEVATION_DEGREES, FIELD_OF_VIEW_DEGREES, MARGIN};
use super::vector::{cross, dot, normalize, sub};

/// A point on the screen: pixel coordinates (x right, y down, pixel `(i, j)`
/// covers `[i, i+1) × [j, j+1)`) and `1/z`, the inverse of its depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenPoint {
    pub x: f32,
    pub y: f32,
    pub inv_depth: f32,
}

/// Where an orbit camera is ([`Camera::orbit`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    pub target: [f64; 3],
    pub azimuth: f64,
    pub elevation: f64,
    pub distance: f64,
    pub fov_y: f64,
    pub shift: [f64; 2],
}

/// A pinhole camera looking at a target, for an image of a given size.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    eye: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    back: [f64; 3],
    /// `f`: pixels per unit of `x/z`.
    focal: f64,
    /// Where the line of sight meets the image: its centre, unless the
    /// camera's lens is shifted ([`Camera::orbit`]).
    centre: [f64; 2],
}

/// The camera's axes `[right, up, back]` (back: from the target toward the
/// eye) for a view from the direction of `azimuth` and `elevation`
/// (radians, as in the module header).
fn axes(azimuth: f64, elevation: f64) -> [[f64; 3]; 3] {
    let back = [
        elevation.cos() * azimuth.sin(),
        elevation.sin(),
        elevation.cos() * azimuth.cos(),
    ];
    let right = normalize(cross([0.0, 1.0, 0.0], back));
    [right, cross(back, right), back]
}

impl Camera {
    /// The camera of the shared look (azimuth 30°, elevation 20°, vertical
    /// field of view 35°) at the smallest distance from which `bounds` fits
    /// in a `width × height` image with a 10% margin.
    pub fn framing(bounds: &BoundingBox, width: usize, height: usize) -> Camera {
        let [right, up, back] = axes(AZIMUTH_DEGREES.to_radians(), ELEVATION_DEGREES.to_radians());
        let (width, height) = (width as f64, height as f64);
        let tan_y = (0.5 * FIELD_OF_VIEW_DEGREES.to_radians()).tan();
        let tan_x = tan_y * width / height;

        // A box of no size (a single point) gets a unit of room around it.
        let bounds = if bounds.radius() > 0.0 {
            *bounds
        } else {
            let c = bounds.centre();
            BoundingBox {
                min: c.map(|v| v - 0.5),
                max: c.map(|v| v + 0.5),
            }
        };
        let target = bounds.centre();
        let mut distance: f64 = 0.0;
        for corner in bounds.corners() {
            let offset = sub(corner, target);
            let (x, y, toward_eye) = (dot(offset, right), dot(offset, up), dot(offset, back));
            distance = distance.max(toward_eye + MARGIN * (x.abs() / tan_x).max(y.abs() / tan_y));
        }
        // Keep every corner well in front of the eye, even for a flat box
        // seen edge-on (moving back only shrinks the picture).
        distance = distance.max(1.5 * bounds.radius());
        Camera {
            eye: std::array::from_fn(|k| target[k] + distance * back[k]),
            right,
            up,
            back,
            focal: 0.5 * height / tan_y,
            centre: [0.5 * width, 0.5 * height],
        }
    }

    /// The camera of an orbit around `view.target`, as the viewer's page
    /// keeps it: from the direction of `azimuth` and `elevation` (radians,
    /// as in the module header), `distance` away, with the vertical field
    /// of view `fov_y` (radians), for a `width × height` image whose centre
    /// of view is moved by `shift` (a fraction of the half width and half
    /// height, right and up: the page frames the scene in the free part of
    /// its window).
    pub fn orbit(view: &Orbit, width: usize, height: usize) -> Camera {
        let [right, up, back] = axes(view.azimuth, view.elevation);
        let (width, height) = (width as f64, height as f64);
        Camera {
            eye: std::array::from_fn(|k| view.target[k] + view.distance * back[k]),
            right,
            up,
            back,
            focal: 0.5 * height / (0.5 * view.fov_y).tan(),
            centre: [
                0.5 * width * (1.0 + view.shift[0]),
                0.5 * height * (1.0 - view.shift[1]),
            ],
        }
    }

    /// Samples per world unit at unit depth (a length `l` at depth `z`
    /// spans `focal · l / z` samples).
    pub fn focal(&self) -> f64 {
        self.focal
    }

    /// The eye's position.
    #[cfg(test)]
    pub fn eye(&self) -> [f64; 3] {
        self.eye
    }

    /// Where `p` lands on the screen. `inv_depth ≤ 0` means the point is at
    /// or behind the eye (never the case for points of the framed box).
    pub fn project(&self, p: [f64; 3]) -> ScreenPoint {
        let from_eye = sub(p, self.eye);
        let (x, y, z) = (
            dot(from_eye, self.right),
            dot(from_eye, self.up),
            -dot(from_eye, self.back),
        );
        ScreenPoint {
            x: (self.centre[0] + self.focal * x / z) as f32,
            y: (self.centre[1] - self.focal * y / z) as f32,
            inv_depth: (1.0 / z) as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests_common::proptest_config;
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn the_target_projects_to_the_centre_of_the_image() {
        let mut bounds = BoundingBox::empty();
        bounds.include(&[[-1.0, 2.0, 0.5], [3.0, 4.0, 1.5]]);
        let camera = Camera::framing(&bounds, 400, 300);
        let centre = camera.project(bounds.centre());
        assert!((centre.x - 200.0).abs() < 1e-3 && (centre.y - 150.0).abs() < 1e-3);
        assert!(centre.inv_depth > 0.0);
    }

    #[test]
    fn world_up_points_up_on_the_screen_and_the_eye_is_in_front_upper_right() {
        let mut bounds = BoundingBox::empty();
        bounds.include(&[[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]);
        let camera = Camera::framing(&bounds, 200, 200);
        let below = camera.project([0.0, -0.5, 0.0]);
        let above = camera.project([0.0, 0.5, 0.0]);
        assert!(above.y < below.y);
        let eye = camera.eye();
        assert!(eye[0] > 0.0 && eye[1] > 0.0 && eye[2] > 0.0);
        assert!(eye[2] > eye[0], "azimuth 30° is closer to +z than to +x");
    }

    #[test]
    fn a_single_point_is_framed_too() {
        let mut bounds = BoundingBox::empty();
        bounds.include(&[[1.0, 1.0, 1.0]]);
        let p = Camera::framing(&bounds, 100, 80).project([1.0, 1.0, 1.0]);
        assert!((p.x - 50.0).abs() < 1e-3 && (p.y - 40.0).abs() < 1e-3 && p.inv_depth > 0.0);
    }

    proptest! {
        #![proptest_config(proptest_config(200))]

        /// Every corner of the box lands inside the image, within the 10%
        /// margin, and at least one touches that margin (the fit is snug
        /// unless the box is flat and seen nearly edge-on).
        #[test]
        fn the_camera_maps_the_bounding_box_into_the_viewport(
            centre in prop::array::uniform3(-50.0f64..50.0),
            half in prop::array::uniform3(0.01f64..20.0),
            width in 16usize..1200,
            height in 16usize..1200,
        ) {
            let bounds = BoundingBox {
                min: std::array::from_fn(|k| centre[k] - half[k]),
                max: std::array::from_fn(|k| centre[k] + half[k]),
            };
            let camera = Camera::framing(&bounds, width, height);
            let (w, h) = (width as f64, height as f64);
            let mut largest: f64 = 0.0;
            for corner in bounds.corners() {
                let p = camera.project(corner);
                prop_assert!(p.inv_depth > 0.0);
                let across = (f64::from(p.x) - 0.5 * w).abs() / (0.5 * w);
                let down = (f64::from(p.y) - 0.5 * h).abs() / (0.5 * h);
                prop_assert!(across <= 1.0 / MARGIN + 1e-4, "x {} of {}", p.x, w);
                prop_assert!(down <= 1.0 / MARGIN + 1e-4, "y {} of {}", p.y, h);
                largest = largest.max(across).max(down);
            }
            prop_assert!(largest > 0.5 / MARGIN, "the box fills too little: {largest}");
        }
    }
}
