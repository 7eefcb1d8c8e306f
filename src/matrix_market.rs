//! Reading and writing Matrix Market files.
//!
//! The Matrix Market exchange format (Boisvert, Pozo, Remington, *The Matrix
//! Market Exchange Formats: Initial Design*, NISTIR 5935, NIST 1996;
//! <https://math.nist.gov/MatrixMarket/formats.html>) is plain text:
//!
//! ```text
//! %%MatrixMarket matrix coordinate real symmetric    <- banner: object format field symmetry
//! % any number of comment lines                      <- start with %
//! 3 3 4                                              <- rows, columns, entries
//! 1 1 4.0                                            <- row, column, value (1-based)
//! 2 1 -1.0
//! 2 2 4.0
//! 3 3 2.5e-1
//! ```
//!
//! * `coordinate` files list the entries `i j value`, one per line, in any
//!   order; here they become a [`CscMatrix`]. Repeated positions are *summed*
//!   (as [`TripletMatrix`] does).
//! * `array` files list all `rows × columns` values, one per line, column by
//!   column (column-major); here they become a [`DenseMatrix`]. The size line
//!   has two numbers, `rows columns`.
//! * `symmetric` files store one triangle only, the lower one (`i ≥ j`); the
//!   reader returns the matrix *expanded* (both triangles stored) and rejects
//!   an entry above the diagonal.
//!
//! What is accepted: fields `real`, `double` and `integer` (read as `f64`),
//! and `pattern` (coordinate only: entries without a value, read as 1.0, so
//! the pattern-only matrices of the SuiteSparse collection can feed an
//! ordering); symmetries `general` and `symmetric` (the latter for coordinate
//! files only). The keywords after `%%MatrixMarket` are case-insensitive.
//! `complex` fields, `vector` objects and `hermitian` / `skew-symmetric`
//! symmetries are rejected with an error that says so, as are non-finite
//! values (`nan`, `inf`). Comment lines (`%`) and blank lines may appear
//! anywhere after the banner, lines may end in CRLF, and fields may be
//! separated by any ASCII whitespace.
//!
//! Every error names the file (when there is one), the 1-based line and the
//! problem, e.g. `Q.mtx:7: row index 0 is out of range 1..=3200`.
//!
//! **Sizes are checked before anything is allocated for them.** The size
//! line is compared with the file: the entries it declares (`rows × columns`
//! values for an array) must fit in the bytes that follow (each takes a line
//! of at least 2 bytes), and the memory of the matrix to build (the column
//! pointers and the counting-sort workspace grow with `rows + columns`, see
//! [`coordinate_bytes`]) must fit in the limit of [`crate::memory`]. So a
//! 60-byte file that declares 2³¹ rows or 10⁸ entries is refused at its size
//! line, without allocating.
//!
//! **A symmetric positive definite matrix** (what `analyze` factors) is read
//! with [`read_symmetric`]: `symmetric` files as above; a `general` file must
//! then be square, list a diagonal entry for every column (so at least `n`
//! entries), and be symmetric: every entry must match its mirror to a
//! relative tolerance of [`SYMMETRY_TOLERANCE`],
//! `|a_ij − a_ji| ≤ 1e-12 · max(|a_ij|, |a_ji|)`, (an entry whose mirror is
//! missing is a mismatch). A `general` file that is not symmetric is refused
//! with the line of the first mismatched entry, never read as its lower
//! triangle.
//!
//! The writers print values with 17 significant digits, enough for every
//! `f64` to read back bit for bit. [`write_file`](crate::files::write_file) writes through a temporary
//! file in the destination's folder and renames it into place, so a failed
//! write never leaves a half-written file behind.

use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::files::{read_text, FileError};
use crate::linalg::dense::DenseMatrix;
use crate::linalg::sparse::{CscMatrix, Triangle, TripletMatrix};
use crate::memory;

/// Which part of the matrix a file stores.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symmetry {
    /// Every entry is listed.
    General,
    /// `A = Aᵀ`; only the lower triangle (`i ≥ j`) is listed.
    Symmetric,
}

/// A matrix read from a `coordinate` file.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseFile {
    /// The matrix; for a symmetric file, both triangles are stored.
    pub matrix: CscMatrix,
    /// What the file's banner declared.
    pub symmetry: Symmetry,
}

/// The content of a Matrix Market file.
#[derive(Debug, Clone, PartialEq)]
pub enum MatrixMarket {
    /// A `coordinate` file.
    Sparse(SparseFile),
    /// An `array` file.
    Dense(DenseMatrix),
}

/// A Matrix Market file that could not be read or written: which file,
/// which line, and what went wrong (see [`FileError`]).
pub type MatrixMarketError = FileError;

type ParseResult<T> = Result<T, MatrixMarketError>;

/// A problem placed on a 1-based line.
fn at_line(line: usize, message: String) -> MatrixMarketError {
    FileError::invalid(message).at_line(line)
}

// ---------------------------------------------------------------- reading --

/// Reads the Matrix Market file at `path`.
///
/// # Errors
/// As [`parse`], with the path in the message; an I/O error when the file
/// cannot be read (or is not UTF-8).
pub fn read(path: &Path) -> Result<MatrixMarket, MatrixMarketError> {
    let text = read_text(path)?;
    parse(&text).map_err(|e| e.in_file(path))
}

/// Reads the square symmetric matrix at `path` (both triangles stored), as a
/// factorization needs it: see the module header for what is checked.
///
/// # Errors
/// As [`read`]; and an array file, a matrix that is not square, a size line
/// declaring fewer entries than columns, or a `general` file that is not
/// symmetric (the line of the first entry that differs from its mirror).
pub fn read_symmetric(path: &Path) -> Result<CscMatrix, MatrixMarketError> {
    let text = read_text(path)?;
    parse_symmetric(&text).map_err(|e| e.in_file(path))
}

/// [`read_symmetric`] on a text.
///
/// # Errors
/// As [`read_symmetric`], without a file name.
pub fn parse_symmetric(text: &str) -> Result<CscMatrix, MatrixMarketError> {
    match parse_checked(text, Expect::SymmetricSquare)? {
        MatrixMarket::Sparse(file) => {
            if file.symmetry == Symmetry::General {
                check_symmetric(&file.matrix, text)?;
            }
            Ok(file.matrix)
        }
        MatrixMarket::Dense(_) => Err(at_line(
            1,
            "expected a sparse (coordinate) matrix, found an array".into(),
        )),
    }
}

/// The relative tolerance of the symmetry check of a `general` file read by
/// [`read_symmetric`]: `|a_ij − a_ji| ≤ SYMMETRY_TOLERANCE · max(|a_ij|, |a_ji|)`.
/// A matrix computed in floating point as a sum of symmetric products is
/// symmetric to the last bit; this leaves room for a file written by a
/// program that rounded the two triangles separately.
pub const SYMMETRY_TOLERANCE: f64 = 1e-12;

/// What the caller needs of the matrix, checked at the size line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Expect {
    /// Any matrix.
    Any,
    /// A square matrix with a diagonal entry in every column.
    SymmetricSquare,
}

/// Refuses a `general` matrix that differs from its transpose (beyond
/// [`SYMMETRY_TOLERANCE`]), on the line of the first such entry.
fn check_symmetric(a: &CscMatrix, text: &str) -> ParseResult<()> {
    let transposed = a.transpose();
    for j in 0..a.ncols() {
        let (rows, values) = a.column(j);
        let (mirror_rows, mirror_values) = transposed.column(j);
        let value_at = |rows: &[usize], values: &[f64], i: usize| {
            rows.binary_search(&i).map_or(0.0, |p| values[p])
        };
        for &i in rows.iter().chain(mirror_rows) {
            let a_ij = value_at(rows, values, i);
            let a_ji = value_at(mirror_rows, mirror_values, i);
            if (a_ij - a_ji).abs() > SYMMETRY_TOLERANCE * a_ij.abs().max(a_ji.abs()) {
                // Name the larger entry first: the one the file lists.
                let ((r, c, x), (_, _, y)) = if a_ij.abs() >= a_ji.abs() {
                    ((i, j, a_ij), (j, i, a_ji))
                } else {
                    ((j, i, a_ji), (i, j, a_ij))
                };
                return Err(at_line(
                    line_of_entry(text, i, j),
                    format!(
                        "the matrix is declared `general` but is not symmetric: entry ({}, {}) = {x} \
                         but its mirror ({}, {}) = {y}, beyond the relative tolerance \
                         {SYMMETRY_TOLERANCE:e}; a symmetric matrix is needed here (or write the \
                         file `symmetric`, lower triangle only)",
                        r + 1,
                        c + 1,
                        c + 1,
                        r + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The line of the first entry at `(i, j)` or `(j, i)` (0-based); the size
/// line is skipped because it has three integers too.
fn line_of_entry(text: &str, i: usize, j: usize) -> usize {
    let mut lines = DataLines::new(text);
    lines.banner();
    let size_line = lines.next();
    let wanted = [(i + 1, j + 1), (j + 1, i + 1)];
    lines
        .find(|(_, line)| {
            let mut words = line.split_ascii_whitespace().map(str::parse::<usize>);
            let position = (words.next(), words.next());
            matches!(position, (Some(Ok(r)), Some(Ok(c))) if wanted.contains(&(r, c)))
        })
        .or(size_line)
        .map_or(1, |(line, _)| line)
}

/// The bytes a coordinate matrix costs while it is built: the triplets, the
/// counting sorts (three arrays of `rows + 1` and of `columns + 1` indices,
/// then the column pointers of the result) and the result's row indices and
/// values, `64` bytes per entry in all.
pub fn coordinate_bytes(nrows: usize, ncols: usize, entries: usize) -> u64 {
    let indices = (nrows as u64)
        .saturating_add(ncols as u64)
        .saturating_add(2);
    memory::bytes_for(indices, 4 * 8).saturating_add(memory::bytes_for(entries as u64, 64))
}

/// Parses the text of a Matrix Market file.
///
/// A `coordinate` file gives [`MatrixMarket::Sparse`], with repeated
/// positions summed and a symmetric file expanded to both triangles; an
/// `array` file gives [`MatrixMarket::Dense`].
///
/// # Errors
/// A [`MatrixMarketError`] with the line number for: an empty text, a
/// missing or invalid banner, an unsupported object, format, field or
/// symmetry, a missing or malformed size line, a symmetric size that is not
/// square, an entry line with the wrong number of fields, an index that is
/// not in `1..=size`, a value that is not a finite number, an entry above
/// the diagonal in a symmetric file, and fewer or more entries than the size
/// line declares.
pub fn parse(text: &str) -> Result<MatrixMarket, MatrixMarketError> {
    parse_checked(text, Expect::Any)
}

fn parse_checked(text: &str, expect: Expect) -> ParseResult<MatrixMarket> {
    if text.trim().is_empty() {
        return Err(at_line(1, "the file is empty".into()));
    }
    let mut lines = DataLines::new(text);
    let header = Header::parse(lines.banner())?;
    match header.format {
        Format::Coordinate => {
            parse_coordinate(&header, &mut lines, expect).map(MatrixMarket::Sparse)
        }
        Format::Array => parse_array(&mut lines).map(MatrixMarket::Dense),
    }
}

/// The lines after the banner that carry data: comments (`%`) and blank
/// lines skipped, surrounding whitespace (and a CR) trimmed, numbered from 1.
struct DataLines<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    /// Length of the whole text in bytes.
    text_len: usize,
    /// Number of the last line taken, blank or not: where the text ended
    /// once the iterator is exhausted.
    last_line: usize,
}

impl<'a> DataLines<'a> {
    fn new(text: &'a str) -> Self {
        DataLines {
            lines: text.lines().enumerate(),
            text_len: text.len(),
            last_line: 0,
        }
    }

    /// An upper bound on the entries the text can hold (each takes at least
    /// a character and a line break): a size line declaring more is refused.
    fn max_entries(&self) -> usize {
        self.text_len / 2 + 1
    }

    /// Refuses a size line (on `line`) declaring more `declared` entries
    /// than the text can hold.
    fn check_declared(&self, line: usize, declared: usize, what: &str) -> ParseResult<()> {
        if declared <= self.max_entries() {
            return Ok(());
        }
        Err(at_line(
            line,
            format!(
                "the size line declares {declared} {what}, but a file of {} bytes can hold at \
                 most {} (each takes a line of at least 2 bytes)",
                self.text_len,
                self.max_entries()
            ),
        ))
    }

    /// The first line, whatever it holds.
    fn banner(&mut self) -> (usize, &'a str) {
        let (index, line) = self.lines.next().unwrap_or((0, ""));
        self.last_line = index + 1;
        (index + 1, line.trim())
    }
}

impl<'a> Iterator for DataLines<'a> {
    type Item = (usize, &'a str);

    fn next(&mut self) -> Option<(usize, &'a str)> {
        for (index, line) in self.lines.by_ref() {
            self.last_line = index + 1;
            let line = line.trim();
            if !line.is_empty() && !line.starts_with('%') {
                return Some((index + 1, line));
            }
        }
        None
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Coordinate,
    Array,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Field {
    /// `real`, `double` or `integer`: one number per entry.
    Number,
    /// No value: every listed entry is 1.
    Pattern,
}

/// What the banner `%%MatrixMarket object format field symmetry` declares.
struct Header {
    format: Format,
    field: Field,
    symmetry: Symmetry,
}

const BANNER: &str = "%%MatrixMarket";

impl Header {
    fn parse((line, text): (usize, &str)) -> ParseResult<Header> {
        let at_banner = |message: String| at_line(line, message);
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        if words.first() != Some(&BANNER) {
            return Err(at_banner(format!(
                "missing banner: the first line must start with {BANNER}"
            )));
        }
        let [_, object, format, field, symmetry] = words[..] else {
            return Err(at_banner(format!(
                "invalid banner: expected `{BANNER} matrix <format> <field> <symmetry>`, found `{text}`"
            )));
        };
        if !object.eq_ignore_ascii_case("matrix") {
            return Err(at_banner(format!(
                "unsupported object `{object}`: only `matrix` is read"
            )));
        }
        let header = Header {
            format: parse_format(format).map_err(at_banner)?,
            field: parse_field(field).map_err(at_banner)?,
            symmetry: parse_symmetry(symmetry).map_err(at_banner)?,
        };
        header.check_combination().map_err(at_banner)?;
        Ok(header)
    }

    fn check_combination(&self) -> Result<(), String> {
        if self.format == Format::Array && self.field == Field::Pattern {
            return Err("an `array` file cannot have the field `pattern`".into());
        }
        if self.format == Format::Array && self.symmetry == Symmetry::Symmetric {
            return Err("unsupported `array symmetric`: only `array general` is read".into());
        }
        Ok(())
    }
}

fn parse_format(word: &str) -> Result<Format, String> {
    match word.to_ascii_lowercase().as_str() {
        "coordinate" => Ok(Format::Coordinate),
        "array" => Ok(Format::Array),
        _ => Err(format!(
            "unsupported format `{word}`: expected `coordinate` or `array`"
        )),
    }
}

fn parse_field(word: &str) -> Result<Field, String> {
    match word.to_ascii_lowercase().as_str() {
        "real" | "double" | "integer" => Ok(Field::Number),
        "pattern" => Ok(Field::Pattern),
        _ => Err(format!(
            "unsupported field `{word}`: expected `real`, `integer` or `pattern`"
        )),
    }
}

fn parse_symmetry(word: &str) -> Result<Symmetry, String> {
    match word.to_ascii_lowercase().as_str() {
        "general" => Ok(Symmetry::General),
        "symmetric" => Ok(Symmetry::Symmetric),
        _ => Err(format!(
            "unsupported symmetry `{word}`: expected `general` or `symmetric`"
        )),
    }
}

/// The size line: `rows columns` (array) or `rows columns entries` (coordinate).
fn parse_size_line<const N: usize>(lines: &mut DataLines) -> ParseResult<(usize, [usize; N])> {
    let Some((line, text)) = lines.next() else {
        return Err(at_line(
            lines.last_line,
            "missing size line: the file ends after the banner and comments".into(),
        ));
    };
    let malformed = || {
        let expected = if N == 3 {
            "rows columns entries"
        } else {
            "rows columns"
        };
        at_line(
            line,
            format!("malformed size line `{text}`: expected `{expected}` (non-negative integers)"),
        )
    };
    let words: [&str; N] = split_fields(text).ok_or_else(malformed)?;
    let mut sizes = [0; N];
    for (size, word) in sizes.iter_mut().zip(words) {
        *size = word.parse().map_err(|_| malformed())?;
    }
    Ok((line, sizes))
}

/// The `N` whitespace-separated fields of `text`, or `None` if it has another number.
fn split_fields<const N: usize>(text: &str) -> Option<[&str; N]> {
    let mut words = text.split_ascii_whitespace();
    let mut fields = [""; N];
    for field in &mut fields {
        *field = words.next()?;
    }
    words.next().is_none().then_some(fields)
}

fn wrong_field_count(line: usize, text: &str, expected: &str) -> MatrixMarketError {
    let found = text.split_ascii_whitespace().count();
    at_line(
        line,
        format!("expected {expected}, found {found} field(s): `{text}`"),
    )
}

/// A 1-based index in `1..=bound`, returned 0-based.
fn parse_index(word: &str, what: &str, bound: usize, line: usize) -> ParseResult<usize> {
    let index: usize = word.parse().map_err(|_| {
        at_line(
            line,
            format!("{what} index `{word}` is not a positive integer"),
        )
    })?;
    if index == 0 || index > bound {
        return Err(at_line(
            line,
            format!("{what} index {index} is out of range 1..={bound}"),
        ));
    }
    Ok(index - 1)
}

/// A finite number.
fn parse_value(word: &str, line: usize) -> ParseResult<f64> {
    let value: f64 = word
        .parse()
        .map_err(|_| at_line(line, format!("`{word}` is not a number")))?;
    if !value.is_finite() {
        return Err(at_line(line, format!("value `{word}` is not finite")));
    }
    Ok(value)
}

/// Row, column (both 0-based) and value of a coordinate entry line.
fn parse_entry(
    (line, text): (usize, &str),
    field: Field,
    nrows: usize,
    ncols: usize,
) -> ParseResult<(usize, usize, f64)> {
    let (row, col, value) = match field {
        Field::Number => {
            let [row, col, value] = split_fields(text)
                .ok_or_else(|| wrong_field_count(line, text, "3 fields (row column value)"))?;
            (row, col, parse_value(value, line)?)
        }
        Field::Pattern => {
            let [row, col] = split_fields(text)
                .ok_or_else(|| wrong_field_count(line, text, "2 fields (row column)"))?;
            (row, col, 1.0)
        }
    };
    let row = parse_index(row, "row", nrows, line)?;
    let col = parse_index(col, "column", ncols, line)?;
    Ok((row, col, value))
}

fn parse_coordinate(
    header: &Header,
    lines: &mut DataLines,
    expect: Expect,
) -> ParseResult<SparseFile> {
    let (size_line, [nrows, ncols, declared]) = parse_size_line(lines)?;
    let symmetric = header.symmetry == Symmetry::Symmetric;
    let at_size_line = |message: String| at_line(size_line, message);
    if (symmetric || expect == Expect::SymmetricSquare) && nrows != ncols {
        return Err(at_size_line(format!(
            "a symmetric matrix must be square, the size line says {nrows}×{ncols}"
        )));
    }
    if expect == Expect::SymmetricSquare && declared < ncols {
        return Err(at_size_line(format!(
            "a symmetric positive definite matrix has a diagonal entry in every column: \
             n = {ncols} needs at least {ncols} entries, the size line declares {declared}"
        )));
    }
    lines.check_declared(size_line, declared, "entries")?;
    let capacity = declared * if symmetric { 2 } else { 1 };
    memory::check(
        coordinate_bytes(nrows, ncols, capacity),
        || format!("a {nrows}×{ncols} sparse matrix with {declared} entries"),
        "",
    )
    .map_err(|e| at_size_line(e.to_string()))?;
    let mut triplets = TripletMatrix::with_capacity(nrows, ncols, capacity);
    let mut count = 0;
    for numbered_line in lines.by_ref() {
        if count == declared {
            return Err(too_many_entries(numbered_line.0, declared, size_line));
        }
        let (row, col, value) = parse_entry(numbered_line, header.field, nrows, ncols)?;
        if symmetric && row < col {
            return Err(at_line(numbered_line.0, format!(
                    "entry ({}, {}) lies above the diagonal: a symmetric file lists the lower triangle only (row ≥ column)",
                    row + 1,
                    col + 1
                ),
            ));
        }
        push_checked(&mut triplets, row, col, value);
        if symmetric && row != col {
            push_checked(&mut triplets, col, row, value);
        }
        count += 1;
    }
    if count < declared {
        return Err(too_few_entries(lines.last_line, count, declared, size_line));
    }
    Ok(SparseFile {
        matrix: triplets.to_csc(),
        symmetry: header.symmetry,
    })
}

/// Pushes an entry whose indices were already checked against the size line.
fn push_checked(triplets: &mut TripletMatrix, row: usize, col: usize, value: f64) {
    triplets
        .push(row, col, value)
        .expect("indices were checked against the size line");
}

fn too_many_entries(line: usize, declared: usize, size_line: usize) -> MatrixMarketError {
    at_line(
        line,
        format!("more entries than the {declared} the size line (line {size_line}) declares"),
    )
}

fn too_few_entries(
    line: usize,
    found: usize,
    declared: usize,
    size_line: usize,
) -> MatrixMarketError {
    at_line(line, format!(
            "the file ends after {found} entries, the size line (line {size_line}) declares {declared}"
        ),
    )
}

fn parse_array(lines: &mut DataLines) -> ParseResult<DenseMatrix> {
    let (size_line, [nrows, ncols]) = parse_size_line(lines)?;
    let declared = nrows
        .checked_mul(ncols)
        .ok_or_else(|| at_line(size_line, format!("a {nrows}×{ncols} array is too large")))?;
    lines.check_declared(size_line, declared, "values (rows × columns)")?;
    let mut column_major = Vec::with_capacity(declared);
    for (line, text) in lines.by_ref() {
        if column_major.len() == declared {
            return Err(too_many_entries(line, declared, size_line));
        }
        let [value] =
            split_fields(text).ok_or_else(|| wrong_field_count(line, text, "1 field (a value)"))?;
        column_major.push(parse_value(value, line)?);
    }
    if column_major.len() < declared {
        return Err(too_few_entries(
            lines.last_line,
            column_major.len(),
            declared,
            size_line,
        ));
    }
    let mut dense = DenseMatrix::zeros(nrows, ncols);
    for (k, &value) in column_major.iter().enumerate() {
        dense[(k % nrows, k / nrows)] = value;
    }
    Ok(dense)
}

// ---------------------------------------------------------------- writing --

/// Writes `a` as a `coordinate real` file, 1-based indices, column by column.
///
/// With [`Symmetry::Symmetric`] only the lower triangle (`i ≥ j`) is written
/// and the upper one is ignored (not checked against the lower one).
/// `comment` goes after the banner, each of its lines behind a `%`.
///
/// # Errors
/// An `InvalidInput` I/O error, before anything is written, when `a` holds a
/// non-finite value or is not square but `Symmetric` was asked for; any error
/// of `out`.
pub fn write_coordinate(
    out: impl Write,
    a: &CscMatrix,
    symmetry: Symmetry,
    comment: &str,
) -> io::Result<()> {
    check_finite(a.values())?;
    let lower;
    let stored = match symmetry {
        Symmetry::General => a,
        Symmetry::Symmetric => {
            if a.nrows() != a.ncols() {
                return Err(invalid_input(format!(
                    "a symmetric file needs a square matrix, this one is {}×{}",
                    a.nrows(),
                    a.ncols()
                )));
            }
            lower = a.triangle(Triangle::Lower);
            &lower
        }
    };
    let symmetry_word = match symmetry {
        Symmetry::General => "general",
        Symmetry::Symmetric => "symmetric",
    };
    let mut out = BufWriter::new(out);
    write_header(&mut out, "coordinate", symmetry_word, comment)?;
    writeln!(
        out,
        "{} {} {}",
        stored.nrows(),
        stored.ncols(),
        stored.nnz()
    )?;
    for j in 0..stored.ncols() {
        let (rows, values) = stored.column(j);
        for (&i, &v) in rows.iter().zip(values) {
            writeln!(out, "{} {} {v:.16e}", i + 1, j + 1)?;
        }
    }
    out.flush()
}

/// Writes `a` as an `array real general` file: the size, then every value,
/// column by column (column-major, as the format requires).
///
/// # Errors
/// An `InvalidInput` I/O error, before anything is written, when `a` holds a
/// non-finite value; any error of `out`.
pub fn write_array(out: impl Write, a: &DenseMatrix, comment: &str) -> io::Result<()> {
    check_finite(a.as_slice())?;
    let mut out = BufWriter::new(out);
    write_header(&mut out, "array", "general", comment)?;
    writeln!(out, "{} {}", a.nrows(), a.ncols())?;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            writeln!(out, "{:.16e}", a[(i, j)])?;
        }
    }
    out.flush()
}

fn write_header(
    out: &mut impl Write,
    format: &str,
    symmetry: &str,
    comment: &str,
) -> io::Result<()> {
    writeln!(out, "{BANNER} matrix {format} real {symmetry}")?;
    for line in comment.lines() {
        writeln!(out, "% {line}")?;
    }
    Ok(())
}

/// The reader rejects non-finite values, so the writers refuse to write them.
fn check_finite(values: &[f64]) -> io::Result<()> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(invalid_input(format!(
            "cannot write the non-finite value {v} (the format is read back as finite numbers only)"
        ))),
        None => Ok(()),
    }
}

fn invalid_input(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}
