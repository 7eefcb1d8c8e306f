//! The local step: project every spring onto its rest length.
//!
//! For fixed positions `p`, the spring energy `½ k (‖pᵢ − pⱼ‖ − rᵢⱼ)²`
//! equals `min ½ k ‖(pᵢ − pⱼ) − dᵢⱼ‖²` over vectors `dᵢⱼ` of length `rᵢⱼ`,
//! and the minimiser is the current spring vector rescaled to the rest
//! length:
//!
//! ```text
//! dᵢⱼ = rᵢⱼ (pᵢ − pⱼ) / ‖pᵢ − pⱼ‖
//! ```
//!
//! Each spring is independent of the others. A spring squeezed to zero
//! length has no direction; its `d` is set to zero (it then pulls its ends
//! together like a zero-length spring until they separate).
//!
//! Written as the formula reads, `r · (v / ‖v‖)`, so that its rounding
//! matches a direct transcription (Eigen's `r * v.normalized()`).
//!
//! Cost `O(m)`: one square root and three divisions per spring.
//! Source: Liu et al. 2013, §3 ("local step"); the assignment, "Step 1 (local)".

/// `d[e] = r[e] (p[i] − p[j]) / ‖p[i] − p[j]‖` for every spring `e = (i, j)`.
pub fn project_springs(springs: &[[usize; 2]], r: &[f64], p: &[[f64; 3]], d: &mut [[f64; 3]]) {
    for ((&[i, j], &rest_length), d_e) in springs.iter().zip(r).zip(d.iter_mut()) {
        let v = [p[i][0] - p[j][0], p[i][1] - p[j][1], p[i][2] - p[j][2]];
        let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let direction = if length > 0.0 {
            v.map(|x| x / length)
        } else {
            [0.0; 3]
        };
        *d_e = direction.map(|x| rest_length * x);
    }
}
