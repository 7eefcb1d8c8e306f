//! `masssprings spy MATRIX.mtx|SCENE.json [--ordering amd|natural]
//! [--factor] -o OUT.png`: a picture of the pattern of `Q` (the matrix of a
//! Matrix Market file, or the `Q` a scene's simulation builds) in the order
//! the factorization uses, or with `--factor` of its Cholesky factor `L`,
//! fill-in in its own colour. Prints `n`, `nnz` and the fill
//! `nnz(L) / nnz(lower triangle of Q)`.

use super::draw::encode::write_png;
use super::draw::sparsity::{spy, Mark};
use super::error::AppError;
use super::file_plan::report;
use super::flags::{size, Size};
use super::limits::{check_picture, picture_bytes};
use super::matrix_input::{file_name, load_lower, PatternArgs};
use masssprings::files::{write_file, FilePlan};
use masssprings::linalg::sparse::{
    CscMatrix, Ordering, PermutedTriangle, SymbolicCholesky, Triangle,
};

/// Paper around the matrix, pixels.
const MARGIN: usize = 8;

/// What `spy` draws and prints.
struct Picture {
    label: String,
    ordering: Ordering,
    factor: bool,
}

/// Draw the sparsity pattern of Q or of its Cholesky factor L.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Draws the pattern of Q (a scene's, or a Matrix Market matrix's lower
triangle mirrored) in the order the factorization uses (AMD unless
--ordering natural), or with --factor that of its Cholesky factor L,
fill-in in orange. Prints n, nnz and the fill nnz(L)/nnz(tril Q).")]
pub struct SpyArgs {
    #[command(flatten)]
    pattern: PatternArgs,
    /// Draw L instead of Q.
    #[arg(long)]
    factor: bool,
    /// The matrix's side in pixels, a square: N or NxN, 16 to 4096.
    #[arg(long, value_name = "WxH", default_value = "480x480", value_parser = size(16, 4096))]
    size: Size,
}

pub fn run(args: SpyArgs) -> Result<(), AppError> {
    let PatternArgs {
        matrix: path,
        out,
        ordering,
    } = args.pattern;
    let Size {
        width: size,
        height,
    } = args.size;
    if height != size {
        return Err(AppError::Usage(format!(
            "--size {size}x{height}: spy draws a square matrix; give --size {size}x{size} or --size {size}"
        )));
    }
    let full = size + 2 * MARGIN + 2;
    let marks = (size as u64).saturating_mul(size as u64);
    check_picture(picture_bytes(full, full, 1).saturating_add(marks), || {
        format!("a spy plot of {size}×{size} pixels")
    })?;
    let picture = Picture {
        label: file_name(&path),
        ordering: ordering.ordering,
        factor: args.factor,
    };
    let mut plan = FilePlan::default();
    let lower = load_lower(&path, &mut plan)?;
    plan.output("-o", &out).check()?;
    let symbolic = SymbolicCholesky::analyze(&lower, picture.ordering)
        .map_err(|e| AppError::Failed(format!("{}: {e}", path.display())))?;
    let permuted = PermutedTriangle::new(&lower, symbolic.permutation(), Triangle::Lower)
        .map_err(|e| AppError::Failed(format!("{}: {e}", path.display())))?;
    let c = permuted.matrix();
    let caption = caption(&picture, &symbolic, c);
    let image = if picture.factor {
        spy(
            c.ncols(),
            factor_entries(&symbolic, c),
            size,
            MARGIN,
            &caption,
        )
    } else {
        spy(c.ncols(), symmetric_entries(c), size, MARGIN, &caption)
    };
    write_file(&out, |file| write_png(file, &image))?;
    report(&out, &caption.join("; "));
    Ok(())
}

/// Two lines: what the picture shows, and its counts.
fn caption(picture: &Picture, symbolic: &SymbolicCholesky, c: &CscMatrix) -> Vec<String> {
    let n = c.ncols();
    let nnz_lower = c.nnz();
    let fill = symbolic.nnz_l() as f64 / nnz_lower as f64;
    let order = picture.ordering.name();
    if picture.factor {
        vec![
            format!("L of {}, {order} order", picture.label),
            format!(
                "n = {n}, nnz(L) = {}, fill nnz(L)/nnz(tril Q) = {fill:.2}",
                symbolic.nnz_l()
            ),
        ]
    } else {
        vec![
            format!("Q of {}, {order} order", picture.label),
            format!(
                "n = {n}, nnz(Q) = {}, nnz(tril Q) = {nnz_lower}",
                2 * nnz_lower - n
            ),
        ]
    }
}

/// Both triangles of the symmetric matrix whose lower triangle is `lower`.
fn symmetric_entries(lower: &CscMatrix) -> impl Iterator<Item = (usize, usize, Mark)> + '_ {
    (0..lower.ncols()).flat_map(move |j| {
        lower.column(j).0.iter().flat_map(move |&i| {
            let mirror = (i != j).then_some((j, i, Mark::Entry));
            std::iter::once((i, j, Mark::Entry)).chain(mirror)
        })
    })
}

/// The pattern of `L`: entries of `C = P Q Pᵀ`'s lower triangle, and fill.
fn factor_entries<'a>(
    symbolic: &'a SymbolicCholesky,
    c: &'a CscMatrix,
) -> impl Iterator<Item = (usize, usize, Mark)> + 'a {
    (0..symbolic.n()).flat_map(move |j| {
        let in_c = c.column(j).0;
        symbolic.column_rows(j).iter().map(move |&i| {
            let i = i as usize;
            let mark = if in_c.binary_search(&i).is_ok() {
                Mark::Entry
            } else {
                Mark::Fill
            };
            (i, j, mark)
        })
    })
}
