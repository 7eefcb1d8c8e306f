//! `masssprings generate grid N | examples [--out DIR]`: writes procedural
//! scenes (JSON + OBJ, and PNG textures) into `DIR` (default `.`).
//!
//! Each file is written all or nothing: into a temporary file in `DIR`,
//! renamed into place once complete (`masssprings::files::write_file`).

use super::args::{Args, CommandSpec, Flag};
use super::limits::check_grid;
use super::render::encode::write_png;
use super::suggest::nearest;
use super::AppError;
use masssprings::files::{remove_stale_temporaries, write_file};
use masssprings::mesh::procedural::{self, GeneratedScene};
use std::fs;
use std::path::{Path, PathBuf};

/// `generate`'s operands and flags.
pub static COMMAND: CommandSpec = CommandSpec {
    name: "generate",
    operands: "grid N | examples",
    summary: "Write the benchmark cloth grid-N, or the five bundled scenes.",
    details: "\
generate grid N writes DIR/grid-N.json and .obj: the N×N cloth of the
benchmarks, the same bytes as the reference tool's `ref grid N`.
generate examples writes the five teaching scenes (single-spring-horizontal,
horizontal-chain, net, flag, skirt) and their PNG textures, as in data/.",
    flags: &[Flag::value(
        "out",
        "DIR",
        "Folder to write into (default .).",
    )],
    shorts: &[],
    run,
};

pub fn run(args: &[String]) -> Result<(), AppError> {
    let options = Args::parse(args, &COMMAND)?;
    let scenes = match options.positionals() {
        [what, n] if what == "grid" => {
            let n = grid_size(n)?;
            check_grid(n)?;
            vec![procedural::grid(n)]
        }
        [what] if what == "grid" => {
            return Err(AppError::Usage(
                "generate grid needs N, the grid's side".into(),
            ))
        }
        [what] if what == "examples" => procedural::examples(),
        [] => {
            return Err(AppError::Usage(
                "generate what? `grid N` or `examples`".into(),
            ))
        }
        [what, _, extra, ..] if what == "grid" => {
            return Err(AppError::Usage(format!("unexpected argument '{extra}'")))
        }
        [what, extra, ..] if what == "examples" => {
            return Err(AppError::Usage(format!("unexpected argument '{extra}'")))
        }
        [other, ..] => {
            let hint = nearest(other, ["grid", "examples"])
                .map(|word| format!("; did you mean {word}?"))
                .unwrap_or_default();
            return Err(AppError::Usage(format!(
                "generate {other}: expected `grid N` or `examples`{hint}"
            )));
        }
    };
    let folder = PathBuf::from(options.text("out").unwrap_or("."));
    super::check_output_folder(&folder, "generate writes scene files into a folder")?;
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
            "generate grid expects N, a whole number ≥ 2, got '{text}'"
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
