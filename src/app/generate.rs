//! `masssprings generate grid N | examples [--out DIR]`: writes procedural
//! scenes (JSON + OBJ, and PNG textures) into `DIR` (default `.`).
//!
//! Each file is written all or nothing: into a temporary file in `DIR`,
//! renamed into place once complete (`masssprings::files::write_file`).

use super::draw::encode::write_png;
use super::error::AppError;
use super::flags::whole;
use super::limits::check_grid;
use masssprings::files::{remove_stale_temporaries, write_file};
use masssprings::mesh::procedural::{self, GeneratedScene};
use std::fs;
use std::path::{Path, PathBuf};

/// Write the benchmark cloth grid-N, or the five bundled scenes.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
generate grid N writes DIR/grid-N.json and .obj: the N×N cloth of the
benchmarks, the same bytes as the reference tool's `ref grid N`.
generate examples writes the five teaching scenes (single-spring-horizontal,
horizontal-chain, net, flag, skirt) and their PNG textures, as in data/.")]
pub struct GenerateArgs {
    #[command(subcommand)]
    what: What,
    /// Folder to write into.
    #[arg(short, long, value_name = "DIR", default_value = ".", global = true)]
    out: PathBuf,
}

/// What `generate` writes.
#[derive(clap::Subcommand, Debug)]
enum What {
    /// The N×N cloth of the benchmarks, grid-N.
    Grid {
        /// The grid's side, at least 2.
        #[arg(value_parser = whole(2, usize::MAX))]
        n: usize,
    },
    /// The five teaching scenes and their textures.
    Examples,
}

pub fn run(args: GenerateArgs) -> Result<(), AppError> {
    let scenes = match args.what {
        What::Grid { n } => {
            check_grid(n)?;
            vec![procedural::grid(n)]
        }
        What::Examples => procedural::examples(),
    };
    let folder = args.out;
    super::file_plan::check_output_folder(&folder, "generate writes scene files into a folder")?;
    fs::create_dir_all(&folder)
        .map_err(|e| AppError::Failed(format!("{}: {e}", folder.display())))?;
    remove_stale_temporaries(&folder)?;
    for scene in &scenes {
        write_scene(scene, &folder)?;
    }
    Ok(())
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
