//! `masssprings etree MATRIX.mtx|SCENE.json [--ordering amd|natural]
//! [--size WxH] -o OUT.png`: the elimination tree of `Q` (or of a Matrix
//! Market matrix) in the order the factorization uses, each supernode in
//! its own colour, its columns joined by a band. Prints `n`, the height of
//! the tree and the number of supernodes.

use super::args::{Args, CommandSpec, Flag};
use super::render::encode::write_png;
use super::render::sparsity::{depths, elimination_tree};
use super::spy::{file_name, load_lower, required_out};
use super::AppError;
use masssprings::files::{write_file, FilePlan};
use masssprings::linalg::sparse::{Ordering, SymbolicCholesky};
use std::path::PathBuf;

/// Larger trees are a smudge at any size; `spy` suits them better.
const MAX_COLUMNS: usize = 4096;

/// `etree`'s operands and flags.
pub static COMMAND: CommandSpec = CommandSpec {
    name: "etree",
    operands: "MATRIX.mtx|SCENE.json -o OUT.png",
    summary: "Draw the elimination tree of Q with its supernodes.",
    details: "\
Draws the elimination tree of Q in the order the factorization uses, each
supernode in its own colour (at most 4096 columns). Prints the tree's
height and the number of supernodes.",
    flags: &[
        Flag::value("out", "OUT.png", "The picture to write (required)."),
        Flag::value("ordering", "amd|natural", "The ordering (default amd)."),
        Flag::value("size", "WxH", "Picture size (default 720x360)."),
    ],
    shorts: &[('o', "out")],
    run,
};

pub fn run(args: &[String]) -> Result<(), AppError> {
    let args = Args::parse(args, &COMMAND)?;
    let path = PathBuf::from(args.single_positional("MATRIX.mtx|SCENE.json")?);
    let out = required_out(&args, "etree", "OUT.png")?;
    let (width, height) = parse_size(args.text("size").unwrap_or("720x360"))?;
    let ordering: Ordering = args.parsed("ordering", Ordering::Amd, "amd or natural")?;
    let mut plan = FilePlan::default();
    let lower = load_lower(&path, &mut plan)?;
    plan.output("-o", &out).check()?;
    if lower.ncols() > MAX_COLUMNS {
        return Err(AppError::Failed(format!(
            "{}: {} columns; etree draws at most {MAX_COLUMNS} (try spy)",
            path.display(),
            lower.ncols()
        )));
    }
    let symbolic = SymbolicCholesky::analyze(&lower, ordering)
        .map_err(|e| AppError::Failed(format!("{}: {e}", path.display())))?;
    let parent = symbolic.elimination_tree();
    let supernodes = symbolic.supernodes();
    let supernode_of: Vec<usize> = (0..symbolic.n()).map(|j| supernodes.of_column(j)).collect();
    let height_of_tree = depths(parent).iter().max().map_or(0, |d| d + 1);
    let caption = [
        format!(
            "elimination tree of {}, {} order",
            file_name(&path),
            ordering.name()
        ),
        format!(
            "n = {}, height {height_of_tree}, {} supernodes, nnz(L) = {}",
            symbolic.n(),
            supernodes.len(),
            symbolic.nnz_l()
        ),
    ];
    let image = elimination_tree(parent, &supernode_of, (width, height), &caption);
    write_file(&out, |file| write_png(file, &image))?;
    super::report(&out, &caption.join("; "));
    Ok(())
}

/// `WxH` in pixels, each 64 to 4096.
fn parse_size(text: &str) -> Result<(usize, usize), AppError> {
    let bad = || {
        AppError::Usage(format!(
            "--size {text}: expected WxH, 64 to 4096 pixels each"
        ))
    };
    let (w, h) = text.split_once('x').ok_or_else(bad)?;
    let (w, h): (usize, usize) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if (64..=4096).contains(&w) && (64..=4096).contains(&h) {
        Ok((w, h))
    } else {
        Err(bad())
    }
}
