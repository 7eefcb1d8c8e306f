//! `masssprings generate grid N | examples [--out DIR]`: writes procedural
//! scenes (JSON + OBJ, and PNG textures) into `DIR` (default `.`).
//!
//! Each file is written all or nothing: into a temporary file in `DIR`,
//! renamed into place once complete (`masssprings::files::outputs`, the
//! rule every output keeps). One run at a time writes into `DIR` (its
//! lock); a file already there with the very bytes `generate` would write
//! is kept as it is, and one with other bytes (a scene edited since, or a
//! file of the user's that shares the name) is refused, before anything is
//! written, unless `--force` (`super::file_plan`). A file that appears at
//! one of its names while it runs is kept, never replaced.

use super::draw::encode::write_png;
use super::error::AppError;
use super::file_plan::{check_output_folder, occupied, refuse_foreign, writes_same};
use super::flags::whole;
use super::limits::check_grid;
use masssprings::files::{shown, Expect, OutputFolder};
use masssprings::mesh::procedural::{self, GeneratedScene};
use std::io::{self, Write};
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
    /// Replace files of the same names whose content differs (edited scenes, say) instead of refusing.
    #[arg(long, global = true)]
    force: bool,
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
    check_output_folder(&folder, "generate writes scene files into a folder")?;
    let out = OutputFolder::open(&folder, "generate")?;
    let files: Vec<SceneFile> = scenes
        .iter()
        .flat_map(|s| scene_files(s, &folder))
        .collect();
    let same: Vec<bool> = files
        .iter()
        .map(|file| writes_same(&file.path, |out| file.write(out)))
        .collect();
    let foreign: Vec<PathBuf> = files
        .iter()
        .zip(&same)
        .filter(|(file, &same)| occupied(&file.path) && !same)
        .map(|(file, _)| file.path.clone())
        .collect();
    let flag = format!("--out {}", shown(&folder));
    refuse_foreign(&flag, "generate", &foreign, args.force)?;
    let (mut written, mut kept) = (Vec::new(), Vec::new());
    for (file, same) in files.iter().zip(same) {
        if same {
            kept.push(shown(&file.path));
            continue;
        }
        // forced over what was there; nothing replaced that was not
        let expect = match foreign.contains(&file.path) {
            true => Expect::Any,
            false => Expect::Nothing,
        };
        let name = file.path.file_name().unwrap_or_default().to_string_lossy();
        out.write(&name, expect, |w| file.write(w))?;
        written.push(shown(&file.path));
    }
    if !written.is_empty() {
        println!("wrote {}", written.join(", "));
    }
    if !kept.is_empty() {
        println!("unchanged {}", kept.join(", "));
    }
    Ok(())
}

/// One file of a generated scene: where it goes and what it holds.
struct SceneFile<'a> {
    path: PathBuf,
    scene: &'a GeneratedScene,
    part: Part,
}

/// Which file of a scene.
enum Part {
    Obj,
    Json,
    Texture,
}

impl SceneFile<'_> {
    /// Writes the file's content to `out`.
    fn write(&self, out: &mut dyn Write) -> io::Result<()> {
        match self.part {
            Part::Obj => self.scene.write_obj(out),
            Part::Json => out.write_all(self.scene.json_text().as_bytes()),
            Part::Texture => match &self.scene.texture {
                Some(texture) => write_png(out, &texture.image),
                None => Ok(()),
            },
        }
    }
}

/// `NAME.obj`, `NAME.json` and the texture, if any, of `scene` in `folder`.
fn scene_files<'a>(scene: &'a GeneratedScene, folder: &Path) -> Vec<SceneFile<'a>> {
    let file = |name: &str, part| SceneFile {
        path: folder.join(name),
        scene,
        part,
    };
    let mut files = vec![
        file(&scene.obj_file_name(), Part::Obj),
        file(&scene.json_file_name(), Part::Json),
    ];
    if let Some(texture) = &scene.texture {
        files.push(file(&texture.file_name, Part::Texture));
    }
    files
}
