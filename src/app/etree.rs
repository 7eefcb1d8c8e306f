//! `masssprings etree MATRIX.mtx|SCENE.json [--ordering amd|natural]
//! [--size WxH] -o OUT.png`: the elimination tree of `Q` (or of a Matrix
//! Market matrix) in the order the factorization uses, each supernode in
//! its own colour, its columns joined by a band. Prints `n`, the height of
//! the tree and the number of supernodes.

use super::draw::encode::write_png;
use super::draw::sparsity::{depths, draw_elimination_tree, TREE_SUPERSAMPLING};
use super::error::AppError;
use super::flags::{size, Size};
use super::limits::{check_picture, picture_bytes};
use super::matrix_input::{file_name, load_lower, PatternArgs};
use masssprings::files::{write_file, FilePlan};
use masssprings::linalg::sparse::SymbolicCholesky;

/// Larger trees are a smudge at any size; `spy` suits them better.
const MAX_COLUMNS: usize = 4096;

/// Draw the elimination tree of Q with its supernodes.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Draws the elimination tree of Q in the order the factorization uses, each
supernode in its own colour (at most 4096 columns). Prints the tree's
height and the number of supernodes.")]
pub struct EtreeArgs {
    #[command(flatten)]
    pattern: PatternArgs,
    /// Picture size in pixels.
    #[arg(long, value_name = "WxH", default_value = "720x360", value_parser = size(64, 4096))]
    size: Size,
}

pub fn run(args: EtreeArgs) -> Result<(), AppError> {
    let PatternArgs {
        matrix: path,
        out,
        ordering,
    } = args.pattern;
    let ordering = ordering.ordering;
    let Size { width, height } = args.size;
    check_picture(picture_bytes(width, height, TREE_SUPERSAMPLING), || {
        format!("an elimination tree of {width}×{height} pixels")
    })?;
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
    let image = draw_elimination_tree(parent, &supernode_of, (width, height), &caption);
    write_file(&out, |file| write_png(file, &image))?;
    super::file_plan::report(&out, &caption.join("; "));
    Ok(())
}
