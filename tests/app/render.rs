//! `masssprings render`, run as a user runs it: the GIF and PNG it writes,
//! decoded back, and the failures that must leave no file behind.
//!
//! The rasterizer's own pieces (edge functions, barycentric weights, the
//! z-buffer, the camera's framing, two-sided lighting, the palette) are
//! tested beside their code in `src/app/draw/`, since the renderer
//! belongs to the command line, not to the library.
#![cfg(feature = "app")]

use crate::cli;

use cli::{data, masssprings, stderr, temp_folder};
use std::fs::{self, File};
use std::path::{Path, PathBuf};

/// The names of the files in `folder` (temporary files included).
fn files_in(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(folder)
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A GIF decoded into whole RGB frames (each later frame drawn over the
/// previous one, as a viewer shows it), with the frames' delays.
struct Animation {
    width: usize,
    height: usize,
    frames: Vec<Vec<[u8; 3]>>,
    delays: Vec<u16>,
}

fn decode_gif(path: &Path) -> Animation {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(File::open(path).unwrap()).unwrap();
    let (width, height) = (usize::from(decoder.width()), usize::from(decoder.height()));
    let mut screen = vec![[0u8; 3]; width * height];
    let (mut frames, mut delays) = (Vec::new(), Vec::new());
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        let (left, top) = (usize::from(frame.left), usize::from(frame.top));
        for y in 0..usize::from(frame.height) {
            for x in 0..usize::from(frame.width) {
                let rgba = &frame.buffer[4 * (y * usize::from(frame.width) + x)..];
                screen[(top + y) * width + left + x] = [rgba[0], rgba[1], rgba[2]];
            }
        }
        frames.push(screen.clone());
        delays.push(frame.delay);
    }
    Animation {
        width,
        height,
        frames,
        delays,
    }
}

/// A PNG decoded to `(width, height, RGB pixels)`.
fn decode_png(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut bytes = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut bytes).unwrap();
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgb, png::BitDepth::Eight)
    );
    let pixels = bytes.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    (info.width, info.height, pixels)
}

/// The shared look's point-mass red, #c0392b, give or take the palette and
/// the antialiasing.
fn is_mass_red(p: [u8; 3]) -> bool {
    p[0] > 150 && p[1] < 90 && p[2] < 80
}

/// The background gradient runs from #f4f6f8 to #dde3ea: light and greyish.
fn is_background(p: [u8; 3]) -> bool {
    p.iter().all(|&c| c >= 0xdc)
}

#[test]
fn a_gif_of_the_net_has_one_frame_per_kept_step_and_every_frame_shows_it() {
    let folder = temp_folder("net-gif");
    let out = folder.join("net.gif");
    let output = masssprings(&[
        "render",
        &data("net.json"),
        "--steps",
        "4",
        "--every",
        "2",
        "--size",
        "160x120",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(&fs::read(&out).unwrap()[..6], b"GIF89a");
    let animation = decode_gif(&out);
    assert_eq!((animation.width, animation.height), (160, 120));
    assert_eq!(animation.frames.len(), 3, "steps 0, 2 and 4");
    // Frames are 2/30 s apart: 6 or 7 centiseconds, 20 over three frames.
    assert_eq!(
        animation.delays.iter().map(|&d| u32::from(d)).sum::<u32>(),
        20
    );
    for (i, frame) in animation.frames.iter().enumerate() {
        let drawn = frame.iter().filter(|&&p| !is_background(p)).count();
        assert!(
            drawn > 200,
            "frame {i} is nearly blank: {drawn} pixels drawn"
        );
        assert!(
            frame.iter().any(|&p| is_mass_red(p)),
            "frame {i}: no masses"
        );
    }
    assert_ne!(animation.frames[0], animation.frames[2], "the net moves");
    assert_eq!(files_in(&folder), ["net.gif"]);
}

#[test]
fn a_png_has_the_requested_size_and_the_flag_shows_its_texture() {
    let folder = temp_folder("flag-png");
    let out = folder.join("flag.png");
    let output = masssprings(&[
        "render",
        &data("flag.json"),
        "--steps",
        "0",
        "--size",
        "120x90",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let (width, height, pixels) = decode_png(&out);
    assert_eq!((width, height), (120, 90));
    // The texture's navy field (22, 36, 92) and golden zigzag, lit.
    let navy = |p: &[u8; 3]| p[2] > 40 && p[0] < 60 && i32::from(p[2]) - i32::from(p[0]) > 20;
    let gold = |p: &[u8; 3]| p[0] > 120 && p[1] > 80 && p[2] < 60;
    assert!(pixels.iter().filter(|p| navy(p)).count() > 500);
    assert!(pixels.iter().any(gold));
    assert_eq!(files_in(&folder), ["flag.png"]);
}

/// A 2 × 1 strip of two quads without a texture, pinned at its left end.
fn write_strip_scene(folder: &Path) -> PathBuf {
    let obj = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n";
    fs::write(folder.join("strip.obj"), obj).unwrap();
    let json = folder.join("strip.json");
    fs::write(&json, r#"{"obj": "strip.obj", "k": 100, "b": [1, 4]}"#).unwrap();
    json
}

#[test]
fn an_untextured_cloth_is_cloth_blue_and_springs_show_only_on_request() {
    let folder = temp_folder("strip");
    let scene = write_strip_scene(&folder);
    let render = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "--steps",
            "0",
            "--size",
            "160x120",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let output = masssprings(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        decode_png(out).2
    };
    let plain = render(&folder.join("plain.png"), &[]);
    // #5b8fd6 times a brightness between 0.35 and 1: blue dominates.
    let blue = |p: &&[u8; 3]| p[2] > p[1] && p[1] > p[0] && p[2] > 60;
    assert!(plain.iter().filter(blue).count() > 2000);
    assert!(
        !plain.iter().any(|&p| is_mass_red(p)),
        "masses hidden by default"
    );
    let springs = render(&folder.join("springs.png"), &["--springs"]);
    assert!(
        springs.iter().any(|&p| is_mass_red(p)),
        "--springs shows masses"
    );
}

#[test]
fn a_wrong_extension_or_size_is_a_usage_error_and_writes_nothing() {
    let folder = temp_folder("usage");
    for (out, extra, named) in [
        ("net.bmp", vec![], ".gif"),
        ("net.gif", vec!["--size", "0x10"], "--size"),
        ("net.gif", vec!["--size", "480y360"], "--size"),
        ("net.gif", vec!["--every", "0"], "--every"),
        ("net.png", vec!["--frames", "3"], "--frames"),
    ] {
        let out = folder.join(out);
        let mut args = vec!["render", "--steps", "2", "-o", out.to_str().unwrap()];
        let net = data("net.json");
        args.push(&net);
        args.extend(extra.iter().copied());
        let output = masssprings(&args);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{args:?}: {}",
            stderr(&output)
        );
        assert!(stderr(&output).contains(named), "{}", stderr(&output));
    }
    let missing_out = masssprings(&["render", &data("net.json")]);
    assert_eq!(missing_out.status.code(), Some(2));
    assert!(files_in(&folder).is_empty(), "{:?}", files_in(&folder));
}

#[test]
fn a_bad_scene_fails_with_one_and_writes_nothing() {
    let folder = temp_folder("bad-scene");
    let bad = folder.join("bad.json");
    fs::write(&bad, r#"{"obj": "missing.obj", "k": 1, "b": [1]}"#).unwrap();
    for scene in [bad.clone(), folder.join("absent.json")] {
        for out in ["out.gif", "out.png"] {
            let out = folder.join(out);
            let output = masssprings(&[
                "render",
                scene.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ]);
            assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
            assert!(stderr(&output).contains("error"));
        }
    }
    assert_eq!(files_in(&folder), ["bad.json"]);
}

#[test]
fn a_missing_texture_fails_with_one_and_writes_nothing() {
    let folder = temp_folder("no-texture");
    let obj =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    fs::write(folder.join("quad.obj"), obj).unwrap();
    let json = folder.join("quad.json");
    fs::write(
        &json,
        r#"{"obj": "quad.obj", "k": 10, "b": [1, 2, 3, 4], "png": "gone.png"}"#,
    )
    .unwrap();
    let out = folder.join("quad.png");
    let output = masssprings(&[
        "render",
        json.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("gone.png"), "{}", stderr(&output));
    assert!(!out.exists());
}
