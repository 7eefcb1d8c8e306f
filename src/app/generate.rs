//! `masssprings generate grid N | examples [--out DIR]`: writes procedural
//! scenes (JSON + OBJ, and PNG textures) into `DIR` (default `.`).
//!
//! Each file is written all or nothing: into a temporary file in `DIR`,
//! renamed into place once complete (`masssprings::files::write_file`).

use super::args::Args;
use super::limits::check_grid;
use super::render::encode::write_png;
use super::AppError;
use masssprings::files::{remove_stale_temporaries, write_file};
use masssprings::mesh::procedural::{self, GeneratedScene};
use std::fs;
use std::path::{Path, PathBuf};

pub fn run(args: &[String]) -> Result<(), AppError> {
    let (scenes, options) = match args.first().map(String::as_str) {
        Some("grid") => {
            let options = Args::parse(&args[1..], &["out"], &[])?;
            let n = grid_size(options.single_positional("N (the grid's side)")?)?;
            check_grid(n)?;
            (vec![procedural::grid(n)], options)
        }
        Some("examples") => {
            // The only positional argument must be `examples` itself.
            let options = Args::parse(args, &["out"], &[])?;
            options.single_positional("examples")?;
            (procedural::examples(), options)
        }
        Some(other) => {
            return Err(AppError::Usage(format!(
                "generate {other}: expected `grid N` or `examples`"
            )))
        }
        None => {
            return Err(AppError::Usage(
                "generate what? `grid N` or `examples`".into(),
            ))
        }
    };
    let folder = PathBuf::from(options.value_or("out", ".".to_string())?);
    fs::create_dir_all(&folder)
        .map_err(|e| AppError::Failed(format!("{}: {e}", folder.display())))?;
    remove_stale_temporaries(&folder)?;
    for scene in &scenes {
        write_scene(scene, &folder)?;
    }
    Ok(())
}

/// `N` of `grid N`: an integer ≥ 2.
fn grid_size(text: &str) -> Result<usize, AppError> {
    match text.parse::<usize>() {
        Ok(n) if n >= 2 => Ok(n),
        _ => Err(AppError::Usage(format!(
            "grid {text}: N must be an integer ≥ 2"
        ))),
    }
}

/// Writes `NAME.obj`, `NAME.json` and the texture, if any, into `folder`.
fn write_scene(scene: &GeneratedScene, folder: &Path) -> Result<(), AppError> {
    let obj_path = folder.join(scene.obj_file_name());
    write_file(&obj_path, |out| scene.write_obj(out))?;
    let json_path = folder.join(scene.json_file_name());
    write_file(&json_path, |out| {
        out.write_all(scene.json_text().as_bytes())
    })?;
    let mut written = vec![obj_path, json_path];
    if let Some(texture) = &scene.texture {
        let png_path = folder.join(&texture.file_name);
        write_file(&png_path, |out| write_png(out, &texture.image))?;
        written.push(png_path);
    }
    let names: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    println!("wrote {}", names.join(", "));
    Ok(())
}
