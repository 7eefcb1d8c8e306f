//! Triangle rasterization with a z-buffer: which samples a projected
//! triangle covers, the barycentric weights of each, and its depth there.
//!
//! **Edge functions** (Pineda 1988). For the directed edge `a → b`,
//! `E(a, b, p) = (b.x − a.x)(p.y − a.y) − (b.y − a.y)(p.x − a.x)` is twice
//! the signed area of the triangle `(a, b, p)`: zero on the line through `a`
//! and `b`, of one sign on each side. It is affine in `p`, so moving one
//! sample to the right adds the constant `−(b.y − a.y)`: the loops below
//! update it with one addition per sample.
//!
//! **Barycentric weights.** With `A = E(a, b, c)`, the weights of a sample `p`
//! are `λ_a = E(b, c, p)/A`, `λ_b = E(c, a, p)/A`, `λ_c = E(a, b, p)/A`: they
//! sum to 1, `p = λ_a a + λ_b b + λ_c c`, and the sample is inside the
//! triangle exactly when all three are ≥ 0, whichever way it winds.
//!
//! **Depth and perspective-correct interpolation.** `1/z` is affine on the
//! screen, so the sample's depth is `1/z = Σ λ_i / z_i`. A surface attribute
//! `u` (texture coordinate, normal) is affine in the *world*, not on the
//! screen; `u/z` is affine on the screen, hence
//! `u = (Σ λ_i u_i / z_i) / (Σ λ_i / z_i)`: the weights handed to the shader
//! are `μ_i = (λ_i / z_i) / Σ_j (λ_j / z_j)` (Heckbert & Moreton 1991).
//!
//! **Facing.** A triangle wound counter-clockwise seen from its front (the
//! side its normal `(b − a) × (c − a)` points to) appears clockwise in pixel
//! coordinates, whose y axis points down, so `A < 0` there: the sign of `A`
//! tells the shader which side of the surface the camera sees.
//!
//! Samples are tested at their centres `(x + ½, y + ½)`. A sample exactly on
//! an edge shared by two triangles is claimed by both; the z-buffer keeps the
//! first of equal depths, so nothing is drawn twice in effect (triangles are
//! opaque, so the top-left rule that avoids this is not needed).
//! Cost: `O(area of the triangle's bounding box)` samples.
//!
//! Sources: J. Pineda, *A parallel algorithm for polygon rasterization*,
//! SIGGRAPH 1988; Marschner & Shirley, *Fundamentals of Computer Graphics*,
//! 4th ed. (2016), ch. 8 (rasterization, z-buffer) and ch. 11 (perspective-
//! correct interpolation); P. Heckbert and H. Moreton, *Interpolation for
//! polygon texture mapping and shading*, 1991.

use super::camera::ScreenPoint;
use super::canvas::Canvas;
use super::look::Rgb;

/// What the shader learns about one covered sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fragment {
    /// Perspective-correct weights `μ` of the three corners (sum 1).
    pub weights: [f32; 3],
    /// Does the camera see the triangle's front (counter-clockwise) side?
    pub front_facing: bool,
}

/// `E(a, b, p)`: twice the signed area of the triangle `(a, b, p)`.
pub fn edge_function(a: [f32; 2], b: [f32; 2], p: [f32; 2]) -> f32 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// The barycentric weights `(λ_a, λ_b, λ_c)` of `p` in the triangle
/// `(a, b, c)`; `None` when the triangle has no area.
pub fn barycentric(a: [f32; 2], b: [f32; 2], c: [f32; 2], p: [f32; 2]) -> Option<[f32; 3]> {
    let area = edge_function(a, b, c);
    (area != 0.0).then(|| {
        [
            edge_function(b, c, p) / area,
            edge_function(c, a, p) / area,
            edge_function(a, b, p) / area,
        ]
    })
}

/// The perspective-correct weights `μ_i = (λ_i / z_i) / Σ_j (λ_j / z_j)` from
/// the screen weights `λ` and the corners' `1/z`.
pub fn perspective_correct(screen_weights: [f32; 3], inv_depths: [f32; 3]) -> [f32; 3] {
    let scaled: [f32; 3] = std::array::from_fn(|i| screen_weights[i] * inv_depths[i]);
    let sum = scaled[0] + scaled[1] + scaled[2];
    scaled.map(|s| s / sum)
}

/// Draws the triangle `corners` on `canvas`: every sample whose centre it
/// covers and where it is nearer than what the z-buffer holds gets the
/// colour `shade(fragment)` and the triangle's depth there.
///
/// Triangles with no area, or with a corner at or behind the eye, are
/// skipped.
pub fn fill_triangle(
    canvas: &mut Canvas,
    corners: [ScreenPoint; 3],
    mut shade: impl FnMut(&Fragment) -> Rgb,
) {
    let [a, b, c] = corners.map(|p| [p.x, p.y]);
    let inv_depths = corners.map(|p| p.inv_depth);
    let area = edge_function(a, b, c);
    if area == 0.0 || !area.is_finite() || inv_depths.iter().any(|&w| w <= 0.0) {
        return;
    }
    let front_facing = area < 0.0;
    let Some((x_range, y_range)) = covered_samples(canvas, [a, b, c]) else {
        return;
    };
    // The weights change by these steps per sample to the right: the x
    // coefficients of E(b, c, p)/A, E(c, a, p)/A, E(a, b, p)/A.
    let step_x = [(b, c), (c, a), (a, b)].map(|(from, to)| -(to[1] - from[1]) / area);
    for y in y_range {
        let start = [x_range.start as f32 + 0.5, y as f32 + 0.5];
        let Some(mut weights) = barycentric(a, b, c, start) else {
            return;
        };
        for x in x_range.clone() {
            if weights.iter().all(|&w| w >= 0.0) {
                let inv_depth = weights[0] * inv_depths[0]
                    + weights[1] * inv_depths[1]
                    + weights[2] * inv_depths[2];
                let i = canvas.index(x, y);
                if inv_depth > canvas.depth[i] {
                    canvas.depth[i] = inv_depth;
                    canvas.colour[i] = shade(&Fragment {
                        weights: perspective_correct(weights, inv_depths),
                        front_facing,
                    });
                }
            }
            for k in 0..3 {
                weights[k] += step_x[k];
            }
        }
    }
}

/// The columns and rows of samples whose centres may lie in the triangle:
/// its bounding box, clipped to the canvas; `None` when that is empty.
fn covered_samples(
    canvas: &Canvas,
    corners: [[f32; 2]; 3],
) -> Option<(std::ops::Range<usize>, std::ops::Range<usize>)> {
    let range = |axis: usize, size: usize| {
        let low = corners
            .iter()
            .map(|p| p[axis])
            .fold(f32::INFINITY, f32::min);
        let high = corners
            .iter()
            .map(|p| p[axis])
            .fold(f32::NEG_INFINITY, f32::max);
        // Sample centres i + ½ in [low, high]: i from ⌈low − ½⌉ to ⌊high − ½⌋.
        let first = (low - 0.5).ceil().max(0.0);
        let last = (high - 0.5).floor().min(size as f32 - 1.0);
        (first <= last).then(|| first as usize..last as usize + 1)
    };
    Some((range(0, canvas.width)?, range(1, canvas.height)?))
}

#[cfg(test)]
mod tests {
    use super::super::tests_common::proptest_config;
    use super::*;
    use proptest::prelude::*;

    fn point(x: f32, y: f32, inv_depth: f32) -> ScreenPoint {
        ScreenPoint { x, y, inv_depth }
    }

    /// The samples of `canvas` the triangle wrote to.
    fn covered(canvas: &Canvas) -> Vec<(usize, usize)> {
        let mut samples = Vec::new();
        for y in 0..canvas.height {
            for x in 0..canvas.width {
                if canvas.depth[canvas.index(x, y)] > 0.0 {
                    samples.push((x, y));
                }
            }
        }
        samples
    }

    #[test]
    fn a_right_triangle_covers_the_samples_below_its_diagonal() {
        // Corners (0,0), (4,0), (0,4): centres (x+½, y+½) with x + y + 1 ≤ 4.
        let mut canvas = Canvas::new(6, 6);
        let corners = [
            point(0.0, 0.0, 1.0),
            point(4.0, 0.0, 1.0),
            point(0.0, 4.0, 1.0),
        ];
        fill_triangle(&mut canvas, corners, |_| [1.0, 0.0, 0.0]);
        let mut expected = Vec::new();
        for y in 0..4 {
            for x in 0..4 {
                if x + y < 4 {
                    expected.push((x, y));
                }
            }
        }
        assert_eq!(covered(&canvas), expected);
        assert_eq!(canvas.colour[canvas.index(0, 0)], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn both_windings_cover_the_same_samples_and_report_opposite_sides() {
        let (a, b, c) = (
            point(0.5, 0.2, 1.0),
            point(7.3, 2.0, 1.0),
            point(2.1, 6.6, 1.0),
        );
        let mut sides = Vec::new();
        let mut coverage = Vec::new();
        for corners in [[a, b, c], [a, c, b]] {
            let mut canvas = Canvas::new(8, 8);
            fill_triangle(&mut canvas, corners, |fragment| {
                sides.push(fragment.front_facing);
                [0.0; 3]
            });
            coverage.push(covered(&canvas));
        }
        assert_eq!(coverage[0], coverage[1]);
        let half = sides.len() / 2;
        assert!(sides[..half].iter().all(|&s| s != sides[half]));
    }

    #[test]
    fn the_z_buffer_keeps_the_nearest_whatever_the_order() {
        let square = |inv_depth| {
            [
                point(0.0, 0.0, inv_depth),
                point(8.0, 0.0, inv_depth),
                point(0.0, 8.0, inv_depth),
            ]
        };
        let (near, far) = ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0]);
        for near_first in [true, false] {
            let mut canvas = Canvas::new(8, 8);
            let order = if near_first {
                [(0.5, near), (0.25, far)]
            } else {
                [(0.25, far), (0.5, near)]
            };
            for (inv_depth, colour) in order {
                fill_triangle(&mut canvas, square(inv_depth), |_| colour);
            }
            assert_eq!(canvas.colour[canvas.index(1, 1)], near);
            assert_eq!(canvas.depth[canvas.index(1, 1)], 0.5);
        }
    }

    #[test]
    fn perspective_correct_weights_favour_the_nearer_corner() {
        // Halfway on the screen between a corner at z = 1 and one at z = 3,
        // the surface point is a quarter of the way in the world.
        let mu = perspective_correct([0.5, 0.5, 0.0], [1.0, 1.0 / 3.0, 0.5]);
        assert!((mu[0] - 0.75).abs() < 1e-6 && (mu[1] - 0.25).abs() < 1e-6 && mu[2] == 0.0);
    }

    #[test]
    fn a_triangle_off_the_canvas_or_behind_the_eye_draws_nothing() {
        let mut canvas = Canvas::new(4, 4);
        let outside = [
            point(10.0, 10.0, 1.0),
            point(20.0, 10.0, 1.0),
            point(10.0, 20.0, 1.0),
        ];
        let behind = [
            point(0.0, 0.0, -1.0),
            point(4.0, 0.0, 1.0),
            point(0.0, 4.0, 1.0),
        ];
        fill_triangle(&mut canvas, outside, |_| [1.0; 3]);
        fill_triangle(&mut canvas, behind, |_| [1.0; 3]);
        assert!(covered(&canvas).is_empty());
    }

    proptest! {
        #![proptest_config(proptest_config(256))]

        /// The weights sum to 1 and reproduce the point:
        /// `p = λ_a a + λ_b b + λ_c c`.
        #[test]
        fn barycentric_weights_sum_to_one_and_reproduce_the_point(
            corners in prop::array::uniform3(prop::array::uniform2(-100.0f32..100.0)),
            p in prop::array::uniform2(-100.0f32..100.0),
        ) {
            let [a, b, c] = corners;
            let area = edge_function(a, b, c);
            prop_assume!(area.abs() > 1.0);
            let weights = barycentric(a, b, c, p).unwrap();
            // In f32 a weight is good to about 1e-7 of the largest one: a
            // thin triangle and a far point make them large.
            let scale = 1.0 + weights.iter().map(|w| w.abs()).fold(0.0, f32::max);
            let sum: f32 = weights.iter().sum();
            prop_assert!((sum - 1.0).abs() < 1e-3 * scale, "sum {sum}");
            for k in 0..2 {
                let back = weights[0] * a[k] + weights[1] * b[k] + weights[2] * c[k];
                prop_assert!((back - p[k]).abs() < 1e-2 * scale, "{back} vs {}", p[k]);
            }
        }

        /// The perspective-correct weights sum to 1 too, and stay in [0, 1]
        /// inside the triangle.
        #[test]
        fn perspective_correct_weights_sum_to_one(
            lambda in prop::array::uniform3(0.0f32..1.0),
            inv_depths in prop::array::uniform3(0.01f32..10.0),
        ) {
            let total: f32 = lambda.iter().sum();
            prop_assume!(total > 1e-3);
            let mu = perspective_correct(lambda.map(|l| l / total), inv_depths);
            prop_assert!((mu.iter().sum::<f32>() - 1.0).abs() < 1e-5);
            prop_assert!(mu.iter().all(|&m| (-1e-6..=1.0 + 1e-6).contains(&m)));
        }
    }
}
