//! `GET /api/image`: the latest frame drawn by the crate's own renderer
//! (the one `masssprings render` uses, `src/app/render`), as a PNG, for a
//! page whose browser has no WebGL. The page sends its camera, so that
//! orbiting, zooming, panning and picking work as with WebGL:
//!
//! | parameter | meaning |
//! |---|---|
//! | `w`, `h` | the image's size in pixels, 16 to 2048 each |
//! | `tx`, `ty`, `tz` | the camera's target |
//! | `az`, `el` | its azimuth and elevation, radians |
//! | `d` | its distance from the target |
//! | `fov` | the vertical field of view, radians |
//! | `sx`, `sy` | the lens shift, a fraction of the half width and height (−1 to 1) |
//! | `springs` | `1`: draw the springs and point masses (key L) |
//! | `ox`, `oz` | when comparing, how far along x and z the second simulation is drawn beside the first (`0`: over it) |
//!
//! A missing or malformed parameter is a `400` naming it. Drawing the flag
//! at 800 × 450 takes a few tens of milliseconds; the page asks for the
//! next image only when the last one has arrived.

use super::http::Response;
use super::simulation_thread::Shared;
use crate::app::draw::camera::{Camera, Orbit};
use crate::app::draw::encode::write_png;
use crate::app::draw::frame::FrameRenderer;
use crate::app::draw::look::SUPERSAMPLING;
use masssprings::files::{escaped, number};
use masssprings::mesh::Scene;

/// The largest width or height asked for.
const MAX_SIDE: f64 = 2048.0;

/// The most pixels an image may have: drawn at 2 × 2 samples of 16 bytes,
/// 128 MB while it is drawn. One image is drawn at a time
/// ([`Shared::drawing`]); the page asks for at most 1.5 million.
const MAX_PIXELS: usize = 2_000_000;

/// What the page asks to see.
#[derive(Debug)]
struct View {
    width: usize,
    height: usize,
    orbit: Orbit,
    springs: bool,
    /// Where the second simulation is drawn, from the first: along x, z.
    offset: [f64; 2],
}

/// The PNG of the latest frame seen as `query` says, a `400` naming what
/// is wrong with the query, or a `503` while another image is drawn.
pub fn respond(shared: &Shared, query: Option<&str>) -> Response {
    let view = match parse(query.unwrap_or("")) {
        Ok(view) => view,
        Err(why) => return Response::error(400, &why),
    };
    let Ok(_drawing) = shared.drawing.try_lock() else {
        return Response::error(503, "another image is being drawn; ask again");
    };
    let (scene, texture) = {
        let assets = Shared::lock(&shared.scene);
        (std::sync::Arc::clone(&assets.scene), assets.decoded.clone())
    };
    let (first, second) = {
        let frame = Shared::lock(&shared.frame);
        (frame.positions(0), frame.positions(1))
    };
    let Some(mut positions) = first.filter(|p| p.len() == scene.vertices.len()) else {
        return Response::error(503, "the scene is changing; ask again");
    };
    let doubled;
    let scene: &Scene = match second {
        Some(second) if second.len() == positions.len() => {
            doubled = side_by_side(&scene);
            let [x, z] = view.offset;
            let shift = |p: [f64; 3]| [p[0] + x, p[1], p[2] + z];
            positions.extend(second.into_iter().map(shift));
            &doubled
        }
        _ => &scene,
    };
    let camera = Camera::orbit(
        &view.orbit,
        SUPERSAMPLING * view.width,
        SUPERSAMPLING * view.height,
    );
    let size = (view.width, view.height);
    let mut renderer = FrameRenderer::new(scene, texture.as_deref(), camera, size, view.springs);
    let image = renderer.render(&positions);
    let mut png = Vec::new();
    write_png(&mut png, &image).expect("writing to memory does not fail");
    Response::new(200, "image/png", png)
}

/// `scene` twice, the copy's vertices numbered after the original's: the
/// two simulations of a comparison in one picture.
fn side_by_side(scene: &Scene) -> Scene {
    let n = scene.vertices.len();
    let shifted = |indices: &[usize]| indices.iter().map(|i| i + n).collect::<Vec<_>>();
    let mut both = scene.clone();
    both.vertices.extend_from_within(..);
    both.masses.extend_from_within(..);
    both.faces
        .extend(scene.faces.iter().map(|face| shifted(face)));
    both.face_texture_coords.extend_from_within(..);
    both.springs
        .extend(scene.springs.iter().map(|&[i, j]| [i + n, j + n]));
    both.pinned.extend(shifted(&scene.pinned));
    both
}

/// The number the parameter `name` has in `query`, `None` when it is
/// not there; refused when it is not a finite number or given twice.
fn parameter(query: &str, name: &str) -> Result<Option<f64>, String> {
    let mut given = query
        .split('&')
        .filter_map(|pair| pair.strip_prefix(name)?.strip_prefix('='));
    let Some(text) = given.next() else {
        return Ok(None);
    };
    if given.next().is_some() {
        return Err(format!(
            "the parameter {name} is given more than once; give it once"
        ));
    }
    let x = text.parse::<f64>().ok().filter(|x| x.is_finite());
    x.map(Some)
        .ok_or_else(|| format!("{name}={}: expected a finite number", escaped(text)))
}

/// The view `query` asks for.
fn parse(query: &str) -> Result<View, String> {
    let value = |name: &str| {
        parameter(query, name)?.ok_or_else(|| format!("the image needs the parameter {name}"))
    };
    let within = |name: &str, low: f64, high: f64| -> Result<f64, String> {
        let x = value(name)?;
        if (low..=high).contains(&x) {
            return Ok(x);
        }
        let [x, low, high] = [x, low, high].map(number);
        Err(format!("{name}={x}: expected from {low} to {high}"))
    };
    // a parameter the page may leave out: 0 then
    let optional = |name: &str| parameter(query, name).map(|x| x.unwrap_or(0.0));
    let side = |name: &str| within(name, 16.0, MAX_SIDE).map(|x| x.round() as usize);
    let (width, height) = (side("w")?, side("h")?);
    if width * height > MAX_PIXELS {
        return Err(format!(
            "{width} × {height} pixels: expected at most {MAX_PIXELS}"
        ));
    }
    let orbit = Orbit {
        target: [value("tx")?, value("ty")?, value("tz")?],
        azimuth: value("az")?,
        elevation: within("el", -1.6, 1.6)?,
        distance: within("d", 1e-9, 1e12)?,
        fov_y: within("fov", 0.01, 3.0)?,
        shift: [within("sx", -1.0, 1.0)?, within("sy", -1.0, 1.0)?],
    };
    Ok(View {
        width,
        height,
        orbit,
        springs: within("springs", 0.0, 1.0)? > 0.5,
        offset: [optional("ox")?, optional("oz")?],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const QUERY: &str =
        "w=320&h=200&tx=0&ty=1&tz=0&az=0.5&el=0.3&d=4&fov=0.6&sx=0.1&sy=0&springs=0";

    #[test]
    fn the_view_is_read_from_the_query_and_refused_when_out_of_range() {
        let view = parse(QUERY).unwrap();
        assert_eq!((view.width, view.height, view.springs), (320, 200, false));
        assert_eq!(view.orbit.target, [0.0, 1.0, 0.0]);
        assert_eq!(view.orbit.shift, [0.1, 0.0]);
        assert_eq!(view.offset, [0.0, 0.0]);
        let missing = parse("w=320").unwrap_err();
        assert!(missing.contains("h"), "{missing}");
        let huge = parse(&QUERY.replace("w=320", "w=99999")).unwrap_err();
        assert!(huge.contains("w=99999"), "{huge}");
        let many = parse(&QUERY.replace("w=320&h=200", "w=2000&h=2000")).unwrap_err();
        assert!(many.contains("at most 2000000"), "{many}");
        assert!(parse(&QUERY.replace("d=4", "d=nan")).is_err());
    }

    #[test]
    fn a_repeated_parameter_is_refused_and_numbers_are_short() {
        let twice = parse(&format!("{QUERY}&w=16")).unwrap_err();
        assert_eq!(
            twice,
            "the parameter w is given more than once; give it once"
        );
        let far = parse(&QUERY.replace("d=4", "d=1e308")).unwrap_err();
        assert_eq!(far, "d=1e308: expected from 1e-9 to 1000000000000");
        let offset = parse(&format!("{QUERY}&ox=1&ox=2")).unwrap_err();
        assert!(offset.contains("ox"), "{offset}");
    }
}
