//! Matrix Market reading and writing: exact round trips (checked against
//! nalgebra copies), one test per error with its line number, what the
//! reader tolerates, and all-or-nothing file writing.
use crate::common;

use common::*;
use masssprings::files::write_file;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::{CscMatrix, TripletMatrix};
use masssprings::matrix_market::{
    parse, read, write_array, write_coordinate, MatrixMarket, MatrixMarketError, SparseFile,
    Symmetry,
};
use proptest::prelude::*;
use std::io::{self, Write};
use std::path::PathBuf;

// ------------------------------------------------------------- helpers --

/// Any finite `f64`, of either sign, across the whole exponent range.
fn finite_f64() -> impl Strategy<Value = f64> {
    use prop::num::f64::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO
}

/// A random sparse `nrows × ncols` matrix with finite values of any magnitude.
fn sparse_matrix(
    max_rows: usize,
    max_cols: usize,
    max_count: usize,
) -> impl Strategy<Value = CscMatrix> {
    (1..=max_rows, 1..=max_cols).prop_flat_map(move |(nrows, ncols)| {
        prop::collection::vec((0..nrows, 0..ncols, finite_f64()), 0..=max_count).prop_map(
            move |entries| {
                // Only the last value at a position is kept, so no sum can overflow.
                let unique: std::collections::BTreeMap<_, _> =
                    entries.into_iter().map(|(i, j, v)| ((i, j), v)).collect();
                let entries = unique.into_iter().map(|((i, j), v)| (i, j, v));
                TripletMatrix::from_entries(nrows, ncols, entries)
                    .unwrap()
                    .to_csc()
            },
        )
    })
}

/// A random symmetric matrix, both triangles stored: random lower entries
/// mirrored above the diagonal.
fn symmetric_matrix(max_n: usize, max_count: usize) -> impl Strategy<Value = CscMatrix> {
    (1..=max_n).prop_flat_map(move |n| {
        prop::collection::vec((0..n, 0..n, finite_f64()), 0..=max_count).prop_map(move |entries| {
            let lower: std::collections::BTreeMap<_, _> = entries
                .into_iter()
                .map(|(i, j, v)| ((i.max(j), i.min(j)), v))
                .collect();
            let mut t = TripletMatrix::new(n, n);
            for (&(i, j), &v) in &lower {
                t.push(i, j, v).unwrap();
                if i != j {
                    t.push(j, i, v).unwrap();
                }
            }
            t.to_csc()
        })
    })
}

fn dense_matrix(max_rows: usize, max_cols: usize) -> impl Strategy<Value = DenseMatrix> {
    (0..=max_rows, 0..=max_cols).prop_flat_map(|(nrows, ncols)| {
        prop::collection::vec(finite_f64(), nrows * ncols).prop_map(move |values| {
            let mut a = DenseMatrix::zeros(nrows, ncols);
            a.as_mut_slice().copy_from_slice(&values);
            a
        })
    })
}

fn coordinate_text(a: &CscMatrix, symmetry: Symmetry) -> String {
    let mut bytes = Vec::new();
    write_coordinate(&mut bytes, a, symmetry, "written by a test\nsecond line").unwrap();
    String::from_utf8(bytes).unwrap()
}

fn array_text(a: &DenseMatrix) -> String {
    let mut bytes = Vec::new();
    write_array(&mut bytes, a, "written by a test").unwrap();
    String::from_utf8(bytes).unwrap()
}

fn sparse(result: Result<MatrixMarket, MatrixMarketError>) -> SparseFile {
    match result.unwrap() {
        MatrixMarket::Sparse(file) => file,
        MatrixMarket::Dense(_) => panic!("expected a coordinate file"),
    }
}

fn dense(result: Result<MatrixMarket, MatrixMarketError>) -> DenseMatrix {
    match result.unwrap() {
        MatrixMarket::Dense(a) => a,
        MatrixMarket::Sparse(_) => panic!("expected an array file"),
    }
}

/// Bitwise equality of the stored values (so -0.0 and 0.0 differ).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Parses `text`, expects an error at `line` whose message contains `needle`.
fn assert_error(text: &str, line: usize, needle: &str) {
    let error = parse(text).expect_err("the text should be rejected");
    let message = error.to_string();
    assert_eq!(error.line(), Some(line), "wrong line in `{message}`");
    assert!(
        message.starts_with(&format!("line {line}: ")),
        "`{message}` should start with the line"
    );
    assert!(
        message.contains(needle),
        "`{message}` should mention `{needle}`"
    );
}

/// A fresh, empty folder under the system's temporary folder.
fn temp_folder(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!(
        "masssprings-matrix-market-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

fn folder_entries(folder: &std::path::Path) -> Vec<String> {
    std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

const GENERAL: &str = "%%MatrixMarket matrix coordinate real general\n";
const SYMMETRIC: &str = "%%MatrixMarket matrix coordinate real symmetric\n";
const ARRAY: &str = "%%MatrixMarket matrix array real general\n";

// --------------------------------------------------------- round trips --

proptest! {
    #![proptest_config(proptest_config(256))]

    #[test]
    fn general_coordinate_round_trips_exactly(a in sparse_matrix(12, 12, 60)) {
        let back = sparse(parse(&coordinate_text(&a, Symmetry::General)));
        prop_assert_eq!(back.symmetry, Symmetry::General);
        prop_assert!(back.matrix.same_pattern(&a));
        prop_assert!(same_bits(back.matrix.values(), a.values()));
        prop_assert_eq!(csc_to_nalgebra(&back.matrix), csc_to_nalgebra(&a));
    }

    #[test]
    fn symmetric_coordinate_reads_back_expanded(a in symmetric_matrix(12, 60)) {
        let text = coordinate_text(&a, Symmetry::Symmetric);
        let lower_entries = a.col_ptr().windows(2).enumerate()
            .map(|(j, w)| a.row_idx()[w[0]..w[1]].iter().filter(|&&i| i >= j).count())
            .sum::<usize>();
        let size_line = text.lines().find(|l| !l.starts_with('%')).unwrap();
        prop_assert_eq!(size_line, format!("{} {} {}", a.nrows(), a.ncols(), lower_entries));

        let back = sparse(parse(&text));
        prop_assert_eq!(back.symmetry, Symmetry::Symmetric);
        prop_assert!(back.matrix.same_pattern(&a));
        prop_assert!(same_bits(back.matrix.values(), a.values()));
        let full = csc_to_nalgebra(&back.matrix);
        prop_assert_eq!(&full, &full.transpose());
        prop_assert_eq!(full, csc_to_nalgebra(&a));
    }

    #[test]
    fn dense_array_round_trips_exactly(a in dense_matrix(7, 7)) {
        let back = dense(parse(&array_text(&a)));
        prop_assert_eq!((back.nrows(), back.ncols()), (a.nrows(), a.ncols()));
        prop_assert!(same_bits(back.as_slice(), a.as_slice()));
        prop_assert_eq!(dense_to_nalgebra(&back), dense_to_nalgebra(&a));
    }
}

#[test]
fn array_values_are_column_major() {
    let text = format!("{ARRAY}2 3\n1\n2\n3\n4\n5\n6\n");
    let a = dense(parse(&text));
    let expected = nalgebra::DMatrix::from_column_slice(2, 3, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert_eq!(dense_to_nalgebra(&a), expected);

    let mut written = Vec::new();
    write_array(&mut written, &a, "").unwrap();
    let values: Vec<f64> = String::from_utf8(written)
        .unwrap()
        .lines()
        .skip(2)
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
}

#[test]
fn symmetric_writer_keeps_the_lower_triangle_only() {
    let a = spd_from_entries(3, &[(0, 1, 1.0), (2, 0, 0.5)], 1.0);
    let text = coordinate_text(&a, Symmetry::Symmetric);
    for entry in text.lines().filter(|l| !l.starts_with('%')).skip(1) {
        let mut fields = entry
            .split_ascii_whitespace()
            .map(|f| f.parse::<usize>().unwrap_or(0));
        let (i, j) = (fields.next().unwrap(), fields.next().unwrap());
        assert!(i >= j, "entry line `{entry}` is above the diagonal");
    }
}

#[test]
fn values_are_written_with_17_significant_digits() {
    let a = CscMatrix::from_diagonal(&[0.1, -1.0 / 3.0]);
    let text = coordinate_text(&a, Symmetry::General);
    assert!(text.contains("1 1 1.0000000000000001e-1\n"), "{text}");
    assert!(text.contains("2 2 -3.3333333333333331e-1\n"), "{text}");
}

#[test]
fn comment_lines_follow_the_banner() {
    let text = coordinate_text(&CscMatrix::identity(2), Symmetry::General);
    let lines: Vec<&str> = text.lines().take(4).collect();
    assert_eq!(
        lines,
        [
            "%%MatrixMarket matrix coordinate real general",
            "% written by a test",
            "% second line",
            "2 2 2"
        ]
    );
}

#[test]
fn grid_matrix_round_trips_through_a_file() {
    let q = grid_matrix(100);
    let folder = temp_folder("grid");
    let path = folder.join("grid-100.mtx");
    write_file(&path, |out| {
        write_coordinate(out, &q, Symmetry::Symmetric, "grid-100")
    })
    .unwrap();
    let back = sparse(read(&path));
    assert_eq!(back.symmetry, Symmetry::Symmetric);
    assert_eq!(back.matrix, q);
    std::fs::remove_dir_all(folder).unwrap();
}

// -------------------------------------------------------- what is read --

#[test]
fn tolerates_comments_blank_lines_crlf_whitespace_and_exponents() {
    let text = "%%MatrixMarket matrix coordinate real general\r\n\
                % a comment\r\n\
                \r\n\
                %another comment\r\n\
                \t 2   3  3 \r\n\
                1 1 1e-3\r\n\
                \r\n\
                % a comment between entries\r\n\
                  2\t3   -1E+10  \r\n\
                1 2 .5";
    let a = sparse(parse(text)).matrix;
    assert_eq!((a.nrows(), a.ncols(), a.nnz()), (2, 3, 3));
    assert_eq!(a.get(0, 0), 1e-3);
    assert_eq!(a.get(1, 2), -1e10);
    assert_eq!(a.get(0, 1), 0.5);
}

#[test]
fn duplicate_entries_are_summed() {
    let a = sparse(parse(&format!(
        "{GENERAL}2 2 3\n1 2 1.5\n2 2 1\n1 2 2.25\n"
    )))
    .matrix;
    assert_eq!(a.nnz(), 2);
    assert_eq!(a.get(0, 1), 3.75);
}

#[test]
fn symmetric_diagonal_is_not_doubled() {
    let a = sparse(parse(&format!("{SYMMETRIC}2 2 3\n1 1 4\n2 1 -1\n2 2 5\n"))).matrix;
    let expected = nalgebra::DMatrix::from_row_slice(2, 2, &[4.0, -1.0, -1.0, 5.0]);
    assert_eq!(csc_to_nalgebra(&a), expected);
}

#[test]
fn integer_field_is_read_as_real_and_keywords_ignore_case() {
    let a = sparse(parse(
        "%%MatrixMarket MATRIX Coordinate Integer General\n1 2 2\n1 1 3\n1 2 -4\n",
    ))
    .matrix;
    assert_eq!((a.get(0, 0), a.get(0, 1)), (3.0, -4.0));
}

#[test]
fn pattern_entries_are_read_as_ones() {
    let file = sparse(parse(
        "%%MatrixMarket matrix coordinate pattern symmetric\n3 3 3\n1 1\n3 1\n2 2\n",
    ));
    assert_eq!(file.symmetry, Symmetry::Symmetric);
    let a = file.matrix;
    assert_eq!(a.nnz(), 4);
    assert_eq!((a.get(2, 0), a.get(0, 2), a.get(1, 1)), (1.0, 1.0, 1.0));
}

#[test]
fn empty_matrices_are_read() {
    let a = sparse(parse(&format!("{GENERAL}0 0 0\n"))).matrix;
    assert_eq!((a.nrows(), a.ncols(), a.nnz()), (0, 0, 0));
    let b = sparse(parse(&format!("{GENERAL}4 5 0\n"))).matrix;
    assert_eq!((b.nrows(), b.ncols(), b.nnz()), (4, 5, 0));
    let c = dense(parse(&format!("{ARRAY}0 3\n")));
    assert_eq!((c.nrows(), c.ncols()), (0, 3));
}

// -------------------------------------------------------------- errors --

#[test]
fn empty_file() {
    assert_error("", 1, "empty");
    assert_error(" \n\r\n\t\n", 1, "empty");
}

#[test]
fn missing_banner() {
    assert_error("3 3 1\n1 1 1\n", 1, "missing banner");
    assert_error(
        "% comment\n%%MatrixMarket matrix coordinate real general\n1 1 0\n",
        1,
        "missing banner",
    );
    assert_error(
        "%%matrixmarket matrix coordinate real general\n1 1 0\n",
        1,
        "missing banner",
    );
}

#[test]
fn invalid_banner() {
    assert_error(
        "%%MatrixMarket matrix coordinate real\n1 1 0\n",
        1,
        "invalid banner",
    );
    assert_error(
        "%%MatrixMarket matrix coordinate real general extra\n1 1 0\n",
        1,
        "invalid banner",
    );
}

#[test]
fn unsupported_object() {
    assert_error(
        "%%MatrixMarket vector coordinate real general\n1 0\n",
        1,
        "unsupported object `vector`",
    );
}

#[test]
fn unsupported_format() {
    assert_error(
        "%%MatrixMarket matrix sparse real general\n1 1 0\n",
        1,
        "unsupported format `sparse`",
    );
}

#[test]
fn unsupported_field() {
    assert_error(
        "%%MatrixMarket matrix coordinate complex general\n1 1 0\n",
        1,
        "unsupported field `complex`",
    );
    assert_error(
        "%%MatrixMarket matrix array pattern general\n1 1\n",
        1,
        "`pattern`",
    );
}

#[test]
fn unsupported_symmetry() {
    assert_error(
        "%%MatrixMarket matrix coordinate real hermitian\n1 1 0\n",
        1,
        "unsupported symmetry `hermitian`",
    );
    assert_error(
        "%%MatrixMarket matrix coordinate real skew-symmetric\n1 1 0\n",
        1,
        "unsupported symmetry `skew-symmetric`",
    );
    assert_error(
        "%%MatrixMarket matrix array real symmetric\n1 1\n1\n",
        1,
        "array symmetric",
    );
}

#[test]
fn missing_size_line() {
    assert_error(
        &format!("{GENERAL}% only comments\n%\n"),
        3,
        "missing size line",
    );
    assert_error(GENERAL, 1, "missing size line");
}

#[test]
fn malformed_size_line() {
    assert_error(
        &format!("{GENERAL}% comment\n3 3\n"),
        3,
        "malformed size line `3 3`",
    );
    assert_error(&format!("{GENERAL}3 3 x\n"), 2, "malformed size line");
    assert_error(&format!("{GENERAL}3 -3 1\n"), 2, "malformed size line");
    assert_error(&format!("{ARRAY}3 3 9\n"), 2, "malformed size line");
}

#[test]
fn not_a_number() {
    assert_error(
        &format!("{GENERAL}3 3 2\n1 1 1.0\n2 2 abc\n"),
        4,
        "`abc` is not a number",
    );
    assert_error(
        &format!("{ARRAY}2 1\n1.0\n1,5\n"),
        4,
        "`1,5` is not a number",
    );
    assert_error(
        &format!("{GENERAL}3 3 1\n1.5 1 1.0\n"),
        3,
        "row index `1.5` is not a positive integer",
    );
    assert_error(
        &format!("{GENERAL}3 3 1\n1 -1 1.0\n"),
        3,
        "column index `-1`",
    );
}

#[test]
fn wrong_number_of_fields() {
    assert_error(
        &format!("{GENERAL}3 3 2\n1 1 1.0\n2 2\n"),
        4,
        "expected 3 fields",
    );
    assert_error(
        &format!("{GENERAL}3 3 1\n1 1 1.0 7\n"),
        3,
        "found 4 field(s)",
    );
    assert_error(&format!("{ARRAY}1 2\n1.0 2.0\n"), 3, "expected 1 field");
    assert_error(
        "%%MatrixMarket matrix coordinate pattern general\n2 2 1\n1 1 1.0\n",
        3,
        "expected 2 fields",
    );
}

#[test]
fn index_zero() {
    assert_error(
        &format!("{GENERAL}3200 3200 1\n0 1 1.0\n"),
        3,
        "row index 0 is out of range 1..=3200",
    );
    assert_error(
        &format!("{GENERAL}3 4 1\n1 0 1.0\n"),
        3,
        "column index 0 is out of range 1..=4",
    );
}

#[test]
fn index_beyond_the_size() {
    assert_error(
        &format!("{GENERAL}3 4 2\n1 1 1\n4 1 1.0\n"),
        4,
        "row index 4 is out of range 1..=3",
    );
    assert_error(
        &format!("{GENERAL}3 4 1\n1 5 1.0\n"),
        3,
        "column index 5 is out of range 1..=4",
    );
}

#[test]
fn upper_triangle_entry_in_a_symmetric_file() {
    assert_error(
        &format!("{SYMMETRIC}3 3 2\n2 1 1.0\n1 2 1.0\n"),
        4,
        "entry (1, 2) lies above the diagonal",
    );
}

#[test]
fn fewer_entries_than_declared() {
    assert_error(
        &format!("{GENERAL}3 3 3\n1 1 1\n2 2 1\n% trailing comment\n"),
        5,
        "ends after 2 entries",
    );
    assert_error(&format!("{ARRAY}2 2\n1\n2\n3"), 5, "ends after 3 entries");
}

#[test]
fn more_entries_than_declared() {
    assert_error(
        &format!("{GENERAL}3 3 1\n1 1 1\n\n2 2 1\n"),
        5,
        "more entries than the 1",
    );
    assert_error(&format!("{ARRAY}1 1\n1\n2\n"), 4, "more entries than the 1");
}

#[test]
fn symmetric_file_that_is_not_square() {
    assert_error(
        &format!("{SYMMETRIC}% c\n3 4 1\n1 1 1\n"),
        3,
        "must be square, the size line says 3×4",
    );
}

#[test]
fn non_finite_values() {
    assert_error(
        &format!("{GENERAL}3 3 2\n1 1 1\n2 2 NaN\n"),
        4,
        "value `NaN` is not finite",
    );
    assert_error(
        &format!("{GENERAL}3 3 1\n1 1 -inf\n"),
        3,
        "value `-inf` is not finite",
    );
    assert_error(
        &format!("{ARRAY}1 1\n1e400\n"),
        3,
        "value `1e400` is not finite",
    );
}

#[test]
fn missing_file_is_an_io_error_naming_the_path() {
    let folder = temp_folder("missing");
    let path = folder.join("absent.mtx");
    let error = read(&path).expect_err("the file does not exist");
    assert_eq!(
        error.io_error().map(|e| e.kind()),
        Some(io::ErrorKind::NotFound)
    );
    assert_eq!(error.line(), None);
    assert_eq!(error.path(), Some(path.as_path()));
    assert!(
        error
            .to_string()
            .starts_with(&format!("{}: ", path.display())),
        "{error}"
    );
    assert!(std::error::Error::source(&error).is_some());
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn errors_in_a_file_name_the_file_and_line() {
    let folder = temp_folder("bad");
    let path = folder.join("Q.mtx");
    std::fs::write(
        &path,
        format!("{SYMMETRIC}% comment\n3200 3200 2\n1 1 1\n0 1 2\n"),
    )
    .unwrap();
    let error = read(&path).expect_err("index 0 is invalid");
    assert_eq!(
        error.to_string(),
        format!("{}:5: row index 0 is out of range 1..=3200", path.display())
    );
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn writers_refuse_what_the_reader_would_reject() {
    let nan = CscMatrix::from_diagonal(&[1.0, f64::NAN]);
    let mut out = Vec::new();
    let error = write_coordinate(&mut out, &nan, Symmetry::General, "").unwrap_err();
    assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
    assert!(out.is_empty(), "nothing is written before the check");

    let rectangular = CscMatrix::zeros(2, 3);
    let error = write_coordinate(&mut out, &rectangular, Symmetry::Symmetric, "").unwrap_err();
    assert_eq!(error.kind(), io::ErrorKind::InvalidInput);

    let mut infinite = DenseMatrix::zeros(1, 1);
    infinite[(0, 0)] = f64::INFINITY;
    assert!(write_array(&mut out, &infinite, "").is_err());
    assert!(out.is_empty());
}

// --------------------------------------------------- all-or-nothing write --

/// A writer that gives up after some bytes, like a full disk.
fn fail_midway(out: &mut dyn Write) -> io::Result<()> {
    out.write_all(b"%%MatrixMarket matrix coordinate real general\n3 3 3\n1 1 1\n")?;
    Err(io::Error::other("disk full (simulated)"))
}

#[test]
fn a_failed_write_leaves_no_file_behind() {
    let folder = temp_folder("failed-write");
    let path = folder.join("Q.mtx");
    let error = write_file(&path, fail_midway).expect_err("the writer fails");
    assert!(error.to_string().contains("disk full"), "{error}");
    assert_eq!(error.path(), Some(path.as_path()));
    assert!(!path.exists(), "the destination must not exist");
    assert!(
        folder_entries(&folder).is_empty(),
        "stray files: {:?}",
        folder_entries(&folder)
    );
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn a_failed_write_keeps_the_previous_file() {
    let folder = temp_folder("failed-rewrite");
    let path = folder.join("Q.mtx");
    let identity = CscMatrix::identity(3);
    write_file(&path, |out| {
        write_coordinate(out, &identity, Symmetry::Symmetric, "")
    })
    .unwrap();
    let before = std::fs::read(&path).unwrap();

    write_file(&path, fail_midway).expect_err("the writer fails");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(folder_entries(&folder), ["Q.mtx"]);
    assert_eq!(sparse(read(&path)).matrix, identity);
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn a_successful_write_replaces_the_file_and_leaves_nothing_else() {
    let folder = temp_folder("rewrite");
    let path = folder.join("B.mtx");
    let mut b = DenseMatrix::zeros(3, 2);
    write_file(&path, |out| write_array(out, &b, "")).unwrap();
    b[(2, 1)] = 7.5;
    write_file(&path, |out| write_array(out, &b, "")).unwrap();
    assert_eq!(dense(read(&path)), b);
    assert_eq!(folder_entries(&folder), ["B.mtx"]);
    std::fs::remove_dir_all(folder).unwrap();
}

#[test]
fn writing_into_a_missing_folder_fails_cleanly() {
    let folder = temp_folder("no-folder");
    let path = folder.join("absent").join("Q.mtx");
    let error = write_file(&path, |out| write_array(out, &DenseMatrix::zeros(1, 1), ""))
        .expect_err("the folder does not exist");
    assert_eq!(
        error.io_error().map(|e| e.kind()),
        Some(io::ErrorKind::NotFound)
    );
    std::fs::remove_dir_all(folder).unwrap();
}
