//! Writing generated scenes as text: numbers as C's `%.17g`, the OBJ, the
//! JSON.
//!
//! Seventeen significant digits are enough for any `f64` to read back bit for
//! bit, and `%.17g` is what the reference tool (`tools/eigen-ref`) prints, so
//! a scene generated here and one generated there are the same bytes. `%g`
//! picks between fixed (`0.10000000000000001`) and scientific
//! (`1.0000000000000001e-05`) notation by the decimal exponent `X` of the
//! rounded value: scientific when `X < −4` or `X ≥ 17`; trailing zeros (and
//! a bare decimal point) are dropped.
//!
//! Cost: linear in the size of the output.
//!
//! Source: ISO C11 §7.21.6.1 (the `g` conversion).

use std::io::{self, Write};

use super::{GeneratedMesh, GeneratedScene};

/// `value` formatted as C's `printf("%.17g", value)`.
pub fn format_17_significant(value: f64) -> String {
    if !value.is_finite() {
        return if value.is_nan() {
            "nan".into()
        } else if value > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    // Rust's `{:.16e}` rounds correctly to 17 significant digits and gives
    // the exponent X of the rounded value.
    let scientific = format!("{value:.16e}");
    let (mantissa, exponent) = scientific
        .split_once('e')
        .expect("`{:e}` always writes an exponent");
    let exponent: i32 = exponent.parse().expect("the exponent is an integer");
    if (-4..17).contains(&exponent) {
        let decimals = (16 - exponent) as usize;
        trim_fraction_zeros(&format!("{value:.decimals$}")).to_string()
    } else {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!(
            "{}e{sign}{:02}",
            trim_fraction_zeros(mantissa),
            exponent.unsigned_abs()
        )
    }
}

/// `1.2500` → `1.25`, `3.000` → `3`; text without a decimal point is kept.
fn trim_fraction_zeros(number: &str) -> &str {
    if number.contains('.') {
        number.trim_end_matches('0').trim_end_matches('.')
    } else {
        number
    }
}

/// Writes `mesh` as OBJ text: an optional comment line, `v x y z`, then
/// `vt u v`, then the faces `f a b c …` (1-based), as `a/t` when the mesh has
/// texture coordinates.
pub(super) fn write_obj(
    mesh: &GeneratedMesh,
    comment: Option<&str>,
    out: &mut dyn Write,
) -> io::Result<()> {
    if let Some(comment) = comment {
        for line in comment.lines() {
            writeln!(out, "# {line}")?;
        }
    }
    for [x, y, z] in &mesh.vertices {
        let [x, y, z] = [x, y, z].map(|c| format_17_significant(*c));
        writeln!(out, "v {x} {y} {z}")?;
    }
    for [u, v] in &mesh.texture_coords {
        let [u, v] = [u, v].map(|c| format_17_significant(*c));
        writeln!(out, "vt {u} {v}")?;
    }
    let textured = !mesh.face_texture_coords.is_empty();
    for (face, corners) in mesh.faces.chunks_exact(mesh.corners_per_face).enumerate() {
        out.write_all(b"f")?;
        for (corner, vertex) in corners.iter().enumerate() {
            if textured {
                let t = mesh.face_texture_coords[face * mesh.corners_per_face + corner];
                write!(out, " {}/{}", vertex + 1, t + 1)?;
            } else {
                write!(out, " {}", vertex + 1)?;
            }
        }
        out.write_all(b"\n")?;
    }
    Ok(())
}

/// The scene file of `scene` on one line, keys in the order
/// `obj, k, m, b, png` (`m` and `png` only when set), pins 1-based.
pub(super) fn scene_json(scene: &GeneratedScene) -> String {
    let mut json = format!(
        "{{\"obj\":{},\"k\":{}",
        json_string(&scene.obj_file_name()),
        format_17_significant(scene.k)
    );
    if let Some(m) = scene.uniform_mass {
        json += &format!(",\"m\":{}", format_17_significant(m));
    }
    let pins: Vec<String> = scene.pinned.iter().map(|p| (p + 1).to_string()).collect();
    json += &format!(",\"b\":[{}]", pins.join(","));
    if let Some(texture) = &scene.texture {
        json += &format!(",\"png\":{}", json_string(&texture.file_name));
    }
    json + "}\n"
}

fn json_string(text: &str) -> String {
    serde_json::to_string(text).expect("a string always serialises")
}
