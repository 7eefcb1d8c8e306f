//! The few 3-vector operations the renderer needs, on `[f64; 3]` (geometry)
//! and `[f32; 3]` (per-pixel shading).

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a / |a|`, or `a` itself when it is zero.
pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let length = dot(a, a).sqrt();
    if length > 0.0 {
        [a[0] / length, a[1] / length, a[2] / length]
    } else {
        a
    }
}

/// `a / |a|` in single precision, or `None` when `a` is (nearly) zero.
pub fn normalize_f32(a: [f32; 3]) -> Option<[f32; 3]> {
    let length = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    (length > 1e-20).then(|| [a[0] / length, a[1] / length, a[2] / length])
}

pub fn dot_f32(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `Σ weights[i] · values[i]`: a barycentric combination of three corners.
pub fn combine<const N: usize>(weights: [f32; 3], values: [[f32; N]; 3]) -> [f32; N] {
    std::array::from_fn(|k| {
        weights[0] * values[0][k] + weights[1] * values[1][k] + weights[2] * values[2][k]
    })
}
