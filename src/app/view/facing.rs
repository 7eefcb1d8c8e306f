//! Which way the page's camera looks at a scene first: at the face of the
//! cloth as it will hang, not at its edge.
//!
//! A cloth held by pins along a horizontal line (a curtain, the `grid N`
//! pinned at two corners) hangs in the vertical plane through that line,
//! whatever its rest shape: the camera faces that plane. Otherwise (pins
//! along a vertical pole as the flag's, on a ring as the skirt's, at a
//! point) the cloth's rest face is shown when it stands upright, the sum
//! of its triangles' normals `Σ (b − a) × (c − a)` pointing sideways; a
//! cloth lying flat, curved all round, or made of springs only keeps the
//! look's direction. The camera then turns by the look's azimuth (30°,
//! the renderer's), so that the face is seen a little from the side, as
//! `masssprings render` shows a scene facing `+z`.
//!
//! Cost: `O(pins + faces)`.

use masssprings::mesh::bounding_box::BoundingBox;
use masssprings::mesh::fan::fan_corners;
use masssprings::mesh::Scene;

/// The look's turn from the direction faced, degrees (the renderer's
/// azimuth, from `+z` toward `+x`).
pub const TURN_DEGREES: f64 = 30.0;

/// The camera's azimuth for `scene` (radians, from `+z` toward `+x`).
pub fn facing_azimuth(scene: &Scene) -> f64 {
    let faced = pins_line_normal(scene).or_else(|| upright_face_normal(scene));
    let straight = faced.map_or(0.0, |[x, z]| x.atan2(z));
    straight + TURN_DEGREES.to_radians()
}

/// Where a second simulation is drawn beside the first, for a camera at
/// `azimuth`: to its right on the screen (along `(cos a, 0, −sin a)`, the
/// camera's horizontal right), by a fifth more than the rest shape's width
/// that way, so that the two do not overlap at rest.
pub fn beside_offset(scene: &Scene, azimuth: f64) -> [f64; 3] {
    let right = [azimuth.cos(), 0.0, -azimuth.sin()];
    let across = scene
        .vertices
        .iter()
        .map(|p| p[0] * right[0] + p[2] * right[2]);
    let (low, high) = across.fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), x| {
        (low.min(x), high.max(x))
    });
    let size = BoundingBox::of(&scene.vertices).diagonal();
    let gap = 1.2 * (high - low).max(0.05 * size).max(1e-3);
    right.map(|c| gap * c)
}

/// The horizontal normal `(x, z)` of the vertical plane through the pins,
/// when they lie along a horizontal line: their spread in `x` and `z` is
/// long in one direction (more than a twentieth of the scene's size) and at
/// least three times thinner across.
fn pins_line_normal(scene: &Scene) -> Option<[f64; 2]> {
    let pins: Vec<[f64; 2]> = scene
        .pinned
        .iter()
        .map(|&i| [scene.vertices[i][0], scene.vertices[i][2]])
        .collect();
    let count = pins.len() as f64;
    let mean = pins.iter().fold([0.0, 0.0], |m, p| {
        [m[0] + p[0] / count, m[1] + p[1] / count]
    });
    let [mut xx, mut xz, mut zz] = [0.0; 3];
    for p in &pins {
        let (dx, dz) = (p[0] - mean[0], p[1] - mean[1]);
        xx += dx * dx / count;
        xz += dx * dz / count;
        zz += dz * dz / count;
    }
    // The eigenvalues of [[xx, xz], [xz, zz]] and the long axis.
    let (half_trace, gap) = ((xx + zz) / 2.0, ((xx - zz) / 2.0).hypot(xz));
    let (long, short) = (half_trace + gap, half_trace - gap);
    let size = BoundingBox::of(&scene.vertices).diagonal();
    if !(long.sqrt() > size / 20.0 && long > 9.0 * short.max(0.0)) {
        return None;
    }
    let angle = 0.5 * (2.0 * xz).atan2(xx - zz); // the long axis, from +x toward +z
    let along = [angle.cos(), angle.sin()];
    Some(toward_the_viewer([-along[1], along[0]]))
}

/// The horizontal direction `(x, z)` the cloth's rest face looks to, when
/// it stands upright and flat enough: its triangles' normals add up to at
/// least half of their lengths, less than half of it vertical.
fn upright_face_normal(scene: &Scene) -> Option<[f64; 2]> {
    let v = &scene.vertices;
    let (mut sum, mut total) = ([0.0; 3], 0.0);
    for face in scene.faces.iter().filter(|face| face.len() >= 3) {
        for [a, b, c] in fan_corners(face.len()) {
            let (a, b, c) = (v[face[a]], v[face[b]], v[face[c]]);
            let (u, w) = (sub(b, a), sub(c, a));
            let n = [
                u[1] * w[2] - u[2] * w[1],
                u[2] * w[0] - u[0] * w[2],
                u[0] * w[1] - u[1] * w[0],
            ];
            total += length(n);
            sum = [sum[0] + n[0], sum[1] + n[1], sum[2] + n[2]];
        }
    }
    let flat = total > 0.0 && length(sum) >= 0.5 * total;
    let upright = sum[1].abs() < 0.5 * length(sum);
    (flat && upright).then(|| toward_the_viewer([sum[0], sum[2]]))
}

/// `(x, z)`, unit, turned to face `+z` (or `+x` when across it): of a
/// plane's two sides, the one the look sees by default.
fn toward_the_viewer([x, z]: [f64; 2]) -> [f64; 2] {
    let length = x.hypot(z);
    let (x, z) = (x / length, z / length);
    match z < -1e-9 || (z.abs() <= 1e-9 && x < 0.0) {
        true => [-x, -z],
        false => [x, z],
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn length(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 3 sheet whose vertex `(i, j)` sits at `place(i, j)`, pinned
    /// at `pinned`.
    fn sheet(place: impl Fn(f64, f64) -> [f64; 3], pinned: Vec<usize>) -> Scene {
        let vertices = (0..3)
            .flat_map(|j| (0..3).map(move |i| (i, j)))
            .map(|(i, j)| place(f64::from(i), f64::from(j)))
            .collect();
        let quad = |i: usize, j: usize| {
            vec![
                3 * j + i,
                3 * j + i + 1,
                3 * (j + 1) + i + 1,
                3 * (j + 1) + i,
            ]
        };
        Scene {
            name: "sheet".into(),
            vertices,
            faces: vec![quad(0, 0), quad(1, 0), quad(0, 1), quad(1, 1)],
            texture_coords: Vec::new(),
            face_texture_coords: Vec::new(),
            springs: vec![[0, 1]],
            masses: vec![1.0; 9],
            pinned,
            k: 1.0,
            texture: None,
            obj: None,
        }
    }

    fn degrees(scene: &Scene) -> f64 {
        facing_azimuth(scene).to_degrees()
    }

    #[test]
    fn a_cloth_pinned_along_a_horizontal_line_is_seen_facing_the_plane_it_hangs_in() {
        // Lying flat, pinned along the edge z = 0 (along x): it hangs in
        // the plane z = 0, whose normal is z.
        let along_x = sheet(|i, j| [i, 0.0, j], vec![0, 1, 2]);
        assert!((degrees(&along_x) - TURN_DEGREES).abs() < 1e-9);
        // Pinned along the edge x = 0 (along z): it hangs in the plane
        // x = 0, seen from +x.
        let along_z = sheet(|i, j| [i, 0.0, j], vec![0, 3, 6]);
        assert!((degrees(&along_z) - (90.0 + TURN_DEGREES)).abs() < 1e-9);
    }

    #[test]
    fn an_upright_cloth_on_a_pole_is_seen_facing_its_rest_face() {
        // The flag's way, upright and pinned along a vertical pole: in the
        // plane z = 0, in the plane x = 0, in the plane x = z (facing
        // (−1, 0, 1), 45° from +z toward −x).
        let turned = sheet(|i, j| [i, j, i], vec![0, 3, 6]);
        assert!((degrees(&turned) - (-45.0 + TURN_DEGREES)).abs() < 1e-9);
        let flag = sheet(|i, j| [i, j, 0.0], vec![0, 3, 6]);
        assert!((degrees(&flag) - TURN_DEGREES).abs() < 1e-9);
        let side = sheet(|i, j| [0.0, j, i], vec![0, 3, 6]);
        assert!((degrees(&side) - (90.0 + TURN_DEGREES)).abs() < 1e-9);
    }

    #[test]
    fn the_second_simulation_is_drawn_to_the_right_by_more_than_the_width() {
        let flag = sheet(|i, j| [i, j, 0.0], vec![0, 3, 6]);
        let offset = beside_offset(&flag, 0.0);
        assert!((offset[0] - 2.4).abs() < 1e-12 && offset[1] == 0.0 && offset[2].abs() < 1e-12);
        let turned = beside_offset(&flag, std::f64::consts::FRAC_PI_2);
        assert!(turned[0].abs() < 1e-12 && turned[2] < 0.0, "{turned:?}");
    }

    #[test]
    fn a_flat_lying_cloth_pinned_at_a_point_keeps_the_looks_direction() {
        let lying = sheet(|i, j| [i, 0.0, j], vec![4]);
        assert!((degrees(&lying) - TURN_DEGREES).abs() < 1e-9);
    }
}
