//! `masssprings etree MATRIX.mtx|SCENE.json [--ordering amd|natural]
//! [--size WxH] -o OUT.png`: the elimination tree of `Q` (or of a Matrix
//! Market matrix) in the order the factorization uses, each supernode in
//! its own colour, its columns joined by a band. Prints `n`, the height of
//! the tree and the number of supernodes.

use super::args::Args;
use super::render::encode::write_png;
use super::render::sparsity::{depths, elimination_tree};
use super::spy::{file_name, load_lower, required_out, short_out};
use super::AppError;
use masssprings::files::write_file;
use masssprings::linalg::sparse::{Ordering, SymbolicCholesky};
use std::path::PathBuf;

/// Larger trees are a smudge at any size; `spy` suits them better.
const MAX_COLUMNS: usize = 4096;

pub fn run(args: &[String]) -> Result<(), AppError> {
    let args = Args::parse(&short_out(args), &["ordering", "out", "size"], &[])?;
    let path = PathBuf::from(args.single_positional("MATRIX.mtx|SCENE.json")?);
    let out = required_out(&args, "etree", "OUT.png")?;
    let (width, height) = parse_size(&args.value_or("size", "720x360".to_string())?)?;
    let ordering: Ordering = args.value_or("ordering", Ordering::Amd)?;
    let lower = load_lower(&path)?;
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
    println!("{}", caption.join("; "));
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
