//! External forces: gravity, and the assignment viewer's wind.
//!
//! Gravity is `(0, −9.8, 0)` applied to **every vertex as a force**, not
//! multiplied by its mass, as the assignment's `main.cpp` does (so light
//! vertices fall faster; with uniform masses the difference is a scale).
//!
//! The wind adds, per vertex, with `x = U_x / (bounding-box diagonal)` and
//! `φ = x + t`:
//!
//! ```text
//! f_x += 3 + 1.5 (1 + cos 5φ)     f_y += 1 + cos(0.3 + φ)     f_z += sin φ
//! ```
//!
//! Unlike the assignment, whose `t` is wall-clock time, `t` here is the
//! simulated time (the sum of the steps' Δt), so that a run with wind
//! repeats exactly.
//!
//! Source: the assignment's `main.cpp`; the scene format in `data/README.md`.

use crate::mesh::bounding_box::BoundingBox;

/// Gravity, per vertex.
pub const GRAVITY: [f64; 3] = [0.0, -9.8, 0.0];

/// `f_ext` for the current positions `u` at simulated time `time`, with or
/// without wind. `scale` is the diagonal of the rest shape's bounding box.
pub fn external_forces(u: &[[f64; 3]], time: f64, wind: bool, scale: f64, f_ext: &mut [[f64; 3]]) {
    for (f, p) in f_ext.iter_mut().zip(u) {
        *f = GRAVITY;
        if wind {
            let phi = p[0] / scale + time;
            f[0] += 3.0 + 1.5 * (1.0 + (5.0 * phi).cos());
            f[1] += 1.0 + (0.3 + phi).cos();
            f[2] += phi.sin();
        }
    }
}

/// The length of the diagonal of the axis-aligned box around `points`
/// (1 for fewer than two distinct points, so it can divide safely).
pub fn bounding_box_diagonal(points: &[[f64; 3]]) -> f64 {
    let diagonal = BoundingBox::of(points).diagonal();
    if diagonal > 0.0 && diagonal.is_finite() {
        diagonal
    } else {
        1.0
    }
}
