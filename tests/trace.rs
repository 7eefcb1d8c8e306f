//! `masssprings trace` and `trace --compare`, run as a student runs them:
//!
//! * the files of every bundled scene read back through our Matrix Market
//!   reader and equal, bit for bit, what the handout's functions compute
//!   (`A`, `r`, `M`, `C`, `Q`, `P`, `L`), and the step's quantities equal
//!   the textbook step's: `U_cur` of step K is the textbook simulation's
//!   after K − 1 steps, `p_N` is `fast_mass_springs_step_sparse` with
//!   `iterations = N` from the files' `U_prev`, `U_cur`;
//! * `--compare` of a trace against itself agrees everywhere; a wrong `M`
//!   or a changed spring of `A` is the first line that fails, with its row;
//!   a student's files in the other format (dense for sparse, a row for a
//!   column, `M` as its diagonal) and another ordering are accepted;
//! * bad input (a file for `-o`, a folder that is no trace, an unreadable
//!   student file, out-of-range flags) is refused with a clear error.
#[path = "common/cli.rs"]
mod cli;

use cli::{data, masssprings, stderr, stdout, temp_folder, TempFolder};
use masssprings::files::write_file;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::linalg::sparse::{CscMatrix, Ordering, TripletMatrix};
use masssprings::matrix_market::{read, write_array, write_coordinate, MatrixMarket, Symmetry};
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::local_step::project_springs;
use masssprings::sim::precomputation::rest_lengths;
use masssprings::sim::textbook::{
    fast_mass_springs_step_sparse, inertial_term, precomputation_ordered, Precomputation,
};
use masssprings::sim::{Simulation, SimulationOptions, Sparse, DELTA_T};
use std::path::{Path, PathBuf};

const SCENES: [&str; 5] = [
    "single-spring-horizontal",
    "horizontal-chain",
    "net",
    "flag",
    "skirt",
];

/// Runs `trace` on a bundled scene into `ours` in a fresh folder (which
/// goes when the result does; its path reads as the result).
fn trace(scene: &str, extra: &[&str], name: &str) -> Traced {
    let parent = temp_folder(name);
    let folder = parent.join("ours");
    let json = data(&format!("{scene}.json"));
    let mut args = vec!["trace", json.as_str(), "-o", folder.to_str().unwrap()];
    args.extend_from_slice(extra);
    let output = masssprings(&args);
    assert!(output.status.success(), "trace failed: {}", stderr(&output));
    Traced {
        _parent: parent,
        ours: folder,
    }
}

/// The folder `trace` wrote, inside the temporary folder it keeps.
struct Traced {
    _parent: TempFolder,
    ours: PathBuf,
}

impl std::ops::Deref for Traced {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.ours
    }
}

fn scene(name: &str) -> Scene {
    load_scene(Path::new(&data(&format!("{name}.json")))).unwrap()
}

fn precomputation(scene: &Scene, ordering: Ordering) -> Precomputation<Sparse> {
    precomputation_ordered(
        &scene.vertices,
        &scene.springs,
        scene.k,
        &scene.masses,
        &scene.pinned,
        DELTA_T,
        ordering,
    )
    .unwrap()
}

fn sparse(folder: &Path, name: &str) -> CscMatrix {
    match read(&folder.join(name)).unwrap() {
        MatrixMarket::Sparse(file) => file.matrix,
        MatrixMarket::Dense(_) => panic!("{name} should be a coordinate file"),
    }
}

fn dense(folder: &Path, name: &str) -> DenseMatrix {
    match read(&folder.join(name)).unwrap() {
        MatrixMarket::Dense(a) => a,
        MatrixMarket::Sparse(_) => panic!("{name} should be an array file"),
    }
}

/// An `n × 3` array file as points.
fn points(folder: &Path, name: &str) -> Vec<[f64; 3]> {
    let a = dense(folder, name);
    assert_eq!(a.ncols(), 3, "{name}");
    (0..a.nrows())
        .map(|i| [a[(i, 0)], a[(i, 1)], a[(i, 2)]])
        .collect()
}

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
    }
}

fn write_sparse(path: &Path, a: &CscMatrix) {
    write_file(path, |out| write_coordinate(out, a, Symmetry::General, "")).unwrap();
}

fn write_dense(path: &Path, a: &DenseMatrix) {
    write_file(path, |out| write_array(out, a, "")).unwrap();
}

/// `a` with the entry at `(row, col)` set to `value` (added if absent).
fn with_entry(a: &CscMatrix, row: usize, col: usize, value: Option<f64>) -> CscMatrix {
    let mut triplets = TripletMatrix::new(a.nrows(), a.ncols());
    for j in 0..a.ncols() {
        let (rows, values) = a.column(j);
        for (&i, &v) in rows.iter().zip(values) {
            if (i, j) != (row, col) {
                triplets.push(i, j, v).unwrap();
            }
        }
    }
    if let Some(value) = value {
        triplets.push(row, col, value).unwrap();
    }
    triplets.to_csc()
}

/// Runs `trace --compare ours theirs`: (success, stdout, stderr).
fn compare(ours: &Path, theirs: &Path) -> (bool, String, String) {
    let output = masssprings(&[
        "trace",
        "--compare",
        ours.to_str().unwrap(),
        theirs.to_str().unwrap(),
    ]);
    (output.status.success(), stdout(&output), stderr(&output))
}

/// The table's line of `quantity`.
fn line<'a>(report: &'a str, quantity: &str) -> &'a str {
    report
        .lines()
        .find(|line| line.split_whitespace().next() == Some(quantity))
        .unwrap_or_else(|| panic!("no line for {quantity} in\n{report}"))
}

/// The quantities whose line says DIFFERS, in order.
fn failing(report: &str) -> Vec<String> {
    report
        .lines()
        .filter(|line| line.split_whitespace().nth(1) == Some("DIFFERS"))
        .map(|line| line.split_whitespace().next().unwrap().to_string())
        .collect()
}

#[test]
fn every_bundled_scene_reads_back_as_the_handouts_precomputation() {
    for name in SCENES {
        let folder = trace(name, &[], &format!("pre-{name}"));
        let scene = scene(name);
        let pre = precomputation(&scene, Ordering::Amd);
        assert_eq!(sparse(&folder, "A.mtx"), pre.A, "{name}: A");
        let r = dense(&folder, "r.mtx");
        assert_eq!(
            r.as_slice(),
            &rest_lengths(&scene.vertices, &scene.springs)[..],
            "{name}: r"
        );
        assert_eq!((r.nrows(), r.ncols()), (scene.springs.len(), 1));
        assert_eq!(sparse(&folder, "M.mtx"), pre.M, "{name}: M");
        assert_eq!(
            sparse(&folder, "M.mtx").diagonal(),
            scene.masses,
            "{name}: M = diag(m)"
        );
        assert_eq!(sparse(&folder, "C.mtx"), pre.C, "{name}: C");
        assert_eq!(sparse(&folder, "Q.mtx"), pre.Q, "{name}: Q");
        assert_eq!(
            sparse(&folder, "L.mtx"),
            pre.prefactorization.l(),
            "{name}: L"
        );
        let p = sparse(&folder, "P.mtx");
        let perm = pre.prefactorization.symbolic().permutation().perm();
        for (new, &old) in perm.iter().enumerate() {
            assert_eq!(
                p.column(old),
                (&[new][..], &[1.0][..]),
                "{name}: P row {new}"
            );
        }
        let readme = std::fs::read_to_string(folder.join("README.md")).unwrap();
        for file in [
            "A.mtx", "r.mtx", "Q.mtx", "L.mtx", "P.mtx", "y.mtx", "d_2.mtx", "b_2.mtx", "p_2.mtx",
        ] {
            assert!(
                readme.contains(&format!("`{file}`")),
                "{name}: README lacks {file}"
            );
        }
    }
}

#[test]
fn the_step_quantities_are_the_textbook_steps_to_the_last_bit() {
    let (name, step, iterations) = ("flag", 3, 4);
    let folder = trace(name, &["--step", "3", "--iterations", "4"], "step");
    let scene = scene(name);
    // U_cur of step K: the textbook simulation after K − 1 steps from rest
    let options = SimulationOptions {
        textbook: true,
        ..SimulationOptions::default()
    };
    let mut simulation = Simulation::<Sparse>::from_scene(&scene, options).unwrap();
    for _ in 1..step {
        simulation.step().unwrap();
    }
    let (u_prev, u_cur) = (points(&folder, "U_prev.mtx"), points(&folder, "U_cur.mtx"));
    assert_eq!(u_cur, simulation.positions());
    assert_eq!(u_prev, simulation.previous_positions());
    assert_ne!(u_cur, u_prev, "the flag moves by step 3");
    // y and the first local step from that state
    let mut pre = precomputation(&scene, Ordering::Amd);
    let f_ext = vec![GRAVITY; u_cur.len()];
    assert_eq!(
        points(&folder, "y.mtx"),
        inertial_term(&pre, &f_ext, &u_prev, &u_cur)
    );
    let mut d = vec![[0.0; 3]; scene.springs.len()];
    project_springs(&pre.springs, &pre.r, &u_cur, &mut d);
    assert_eq!(points(&folder, "d_1.mtx"), d);
    // p after n iterations: the handout's step with iterations = n
    for n in 1..=iterations {
        pre.iterations = n;
        let mut u_next = vec![[0.0; 3]; u_cur.len()];
        fast_mass_springs_step_sparse(&pre, &f_ext, &u_prev, &u_cur, &mut u_next);
        assert_eq!(points(&folder, &format!("p_{n}.mtx")), u_next, "p_{n}");
    }
    assert!(!folder.join("p_5.mtx").exists());
}

#[test]
fn a_trace_compared_with_itself_agrees_everywhere() {
    let ours = trace("flag", &[], "itself");
    let (success, report, _) = compare(&ours, &ours);
    assert!(success, "{report}");
    let names = [
        "A", "r", "M", "C", "Q", "P", "L", "U_prev", "U_cur", "y", "d_1", "b_1", "p_1", "d_2",
        "b_2", "p_2",
    ];
    for name in names {
        let line = line(&report, name);
        assert!(line.contains(" agrees "), "{line}");
    }
    assert!(report.contains("all 16 quantities given agree"), "{report}");
}

#[test]
fn a_wrong_mass_is_the_first_quantity_that_fails_with_its_row() {
    let ours = trace("net", &[], "wrong-m");
    let theirs = ours.parent().unwrap().join("theirs");
    copy_folder(&ours, &theirs);
    // the student's mass of vertex 6 is off by 10%, and so is everything made of it
    let m = sparse(&ours, "M.mtx");
    let wrong = 1.1 * m.get(6, 6);
    write_sparse(&theirs.join("M.mtx"), &with_entry(&m, 6, 6, Some(wrong)));
    let q = sparse(&ours, "Q.mtx");
    let q_66 = q.get(6, 6) + 0.1 * m.get(6, 6) / (DELTA_T * DELTA_T);
    write_sparse(&theirs.join("Q.mtx"), &with_entry(&q, 6, 6, Some(q_66)));
    let mut y = dense(&ours, "y.mtx");
    y[(6, 1)] *= 1.5;
    write_dense(&theirs.join("y.mtx"), &y);
    let (success, report, error) = compare(&ours, &theirs);
    assert!(!success, "{report}");
    assert_eq!(failing(&report), ["M", "Q", "y"], "{report}");
    assert!(
        line(&report, "M").contains("row 7, column 7: vertex 6, vertex 6"),
        "{report}"
    );
    assert!(
        report.contains("first wrong quantity: M (M.mtx), at row 7, column 7"),
        "{report}"
    );
    assert!(
        error.contains("3 of the 16 quantities given differ; the first is M"),
        "{error}"
    );
}

#[test]
fn a_changed_spring_names_a_and_its_row_first() {
    let ours = trace("flag", &[], "wrong-a");
    let theirs = ours.parent().unwrap().join("theirs");
    copy_folder(&ours, &theirs);
    // spring 17 = (i, j) of the student's A ends at j + 1 instead of j
    let a = sparse(&ours, "A.mtx");
    let scene = scene("flag");
    let [i, j] = scene.springs[17];
    let changed = with_entry(&with_entry(&a, 17, j, None), 17, j + 1, Some(-1.0));
    write_sparse(&theirs.join("A.mtx"), &changed);
    // and so the student's Q = k AᵀA + … differs too
    let mut q = sparse(&ours, "Q.mtx");
    q = with_entry(&q, j + 1, i, Some(q.get(j + 1, i) - scene.k));
    write_sparse(&theirs.join("Q.mtx"), &q);
    // and b = k Aᵀd + …: k d₁₇ moves from row j to row j + 1, both pinned
    // rows of size w, where k d₁₇ is a difference of 1e-7 relative to the row
    let (mut b, d) = (dense(&ours, "b_1.mtx"), dense(&ours, "d_1.mtx"));
    assert!(scene.pinned.contains(&j) && scene.pinned.contains(&(j + 1)));
    for c in 0..3 {
        b[(j, c)] += scene.k * d[(17, c)];
        b[(j + 1, c)] -= scene.k * d[(17, c)];
    }
    write_dense(&theirs.join("b_1.mtx"), &b);
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report)[0], "A", "{report}");
    assert_eq!(failing(&report), ["A", "Q", "b_1"], "{report}");
    let b_line = line(&report, "b_1");
    let rows = [j, j + 1].map(|v| format!("vertex {v},"));
    assert!(rows.iter().any(|row| b_line.contains(row)), "{report}");
    let expected = format!(
        "row 18, column {}: spring 17 = ({i}, {j}), vertex {j}",
        j + 1
    );
    assert!(
        line(&report, "A").contains(&expected),
        "{expected} in {report}"
    );
    assert!(
        report.contains("first wrong quantity: A (A.mtx), at row 18"),
        "{report}"
    );
}

#[test]
fn a_sign_flipped_spring_is_found_in_a_and_d() {
    let ours = trace("net", &[], "flipped");
    let theirs = ours.parent().unwrap().join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    let a = sparse(&ours, "A.mtx");
    let [i, j] = scene("net").springs[3];
    let flipped = with_entry(&with_entry(&a, 3, i, Some(-1.0)), 3, j, Some(1.0));
    write_sparse(&theirs.join("A.mtx"), &flipped);
    let mut d = dense(&ours, "d_1.mtx");
    for c in 0..3 {
        d[(3, c)] = -d[(3, c)];
    }
    write_dense(&theirs.join("d_1.mtx"), &d);
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report), ["A", "d_1"], "{report}");
    assert!(line(&report, "d_1").contains("row 4, column"), "{report}");
    assert!(line(&report, "r").contains("not given"), "{report}");
}

#[test]
fn other_formats_and_another_ordering_are_accepted() {
    let ours = trace("net", &[], "formats");
    let natural = trace("net", &["--ordering", "natural"], "formats-natural");
    let theirs = ours.parent().unwrap().join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    // A dense, r as a row, M as its diagonal, y sparse
    write_dense(&theirs.join("A.mtx"), &sparse(&ours, "A.mtx").to_dense());
    write_dense(&theirs.join("r.mtx"), &dense(&ours, "r.mtx").transpose());
    let masses =
        DenseMatrix::from_row_major(scene("net").masses.len(), 1, scene("net").masses).unwrap();
    write_dense(&theirs.join("M.mtx"), &masses);
    let y = dense(&ours, "y.mtx");
    let mut y_sparse = TripletMatrix::new(y.nrows(), 3);
    for i in 0..y.nrows() {
        for c in 0..3 {
            if y[(i, c)] != 0.0 {
                y_sparse.push(i, c, y[(i, c)]).unwrap();
            }
        }
    }
    write_sparse(&theirs.join("y.mtx"), &y_sparse.to_csc());
    // L in the natural order, without P: checked as L Lᵀ = Q
    std::fs::copy(natural.join("L.mtx"), theirs.join("L.mtx")).unwrap();
    std::fs::copy(natural.join("p_2.mtx"), theirs.join("p_2.mtx")).unwrap();
    let (success, report, error) = compare(&ours, &theirs);
    assert!(success, "{report}\n{error}");
    assert!(
        line(&report, "L").contains("in the natural order"),
        "{report}"
    );
    // with the natural P given, L is checked with it
    std::fs::copy(natural.join("P.mtx"), theirs.join("P.mtx")).unwrap();
    let (success, report, _) = compare(&ours, &theirs);
    assert!(success, "{report}");
    assert!(line(&report, "P").contains("note"), "{report}");
    assert!(line(&report, "L").contains("with your P"), "{report}");
}

#[test]
fn a_wrong_factor_fails_whatever_the_ordering() {
    let ours = trace("net", &[], "wrong-l");
    let theirs = ours.parent().unwrap().join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    let l = sparse(&ours, "L.mtx");
    let wrong = with_entry(&l, 5, 5, Some(l.get(5, 5) * (1.0 + 1e-6)));
    write_sparse(&theirs.join("L.mtx"), &wrong);
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report), ["L"], "{report}");
    assert!(
        line(&report, "L").contains("row 6, column 6 of L Lᵀ − P Q Pᵀ"),
        "{report}"
    );
    // an upper triangular "L" is refused as such
    write_sparse(&theirs.join("L.mtx"), &l.transpose());
    let (_, report, _) = compare(&ours, &theirs);
    assert!(
        line(&report, "L").contains("not lower triangular"),
        "{report}"
    );
}

#[test]
fn bad_input_is_refused_with_a_clear_error() {
    let folder = temp_folder("bad-input");
    let file = folder.join("a-file");
    std::fs::write(&file, "not a folder").unwrap();
    let json = data("net.json");
    let output = masssprings(&["trace", &json, "-o", file.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("this is a file"),
        "{}",
        stderr(&output)
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a folder");
    for (flag, value) in [
        ("--iterations", "0"),
        ("--iterations", "51"),
        ("--step", "0"),
    ] {
        let output = masssprings(&["trace", &json, "-o", folder.to_str().unwrap(), flag, value]);
        assert_eq!(output.status.code(), Some(2), "{flag} {value}");
    }
    // a folder that trace did not write
    let output = masssprings(&[
        "trace",
        "--compare",
        folder.to_str().unwrap(),
        folder.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("trace.json"),
        "{}",
        stderr(&output)
    );
    // a student file that does not parse: named, with its line, as the quantity that differs
    let ours = trace("net", &[], "bad-student");
    let theirs = ours.parent().unwrap().join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    std::fs::write(
        theirs.join("r.mtx"),
        "%%MatrixMarket matrix array real general\n2 1\n1.0\nabc\n",
    )
    .unwrap();
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert!(
        line(&report, "r").contains("r.mtx:4: `abc` is not a number"),
        "{report}"
    );
    // our own folder edited by hand so that its files no longer fit: an error, not a panic
    let edited = ours.parent().unwrap().join("edited");
    copy_folder(&ours, &edited);
    write_sparse(&edited.join("Q.mtx"), &CscMatrix::identity(2));
    let (success, _, error) = compare(&edited, &theirs);
    assert!(!success);
    assert!(error.contains("do not fit one another"), "{error}");
    // nothing to compare is an error too
    let empty = ours.parent().unwrap().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let (success, _, error) = compare(&ours, &empty);
    assert!(!success);
    assert!(error.contains("nothing was compared"), "{error}");
}

#[test]
fn a_second_trace_removes_the_iterations_of_the_first() {
    let ours = trace("net", &["--iterations", "3"], "again");
    assert!(ours.join("p_3.mtx").exists());
    let json = data("net.json");
    let output = masssprings(&[
        "trace",
        &json,
        "-o",
        ours.to_str().unwrap(),
        "--iterations",
        "1",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(ours.join("p_1.mtx").exists());
    assert!(!ours.join("p_2.mtx").exists() && !ours.join("d_3.mtx").exists());
}
