//! `masssprings trace` and `trace --compare`, run as a student runs them:
//!
//! * the files of every bundled scene read back through our Matrix Market
//!   reader and equal, bit for bit, what the handout's functions compute
//!   (`A`, `r`, `M`, `C`, `Q`, `P`, `L`), and the step's quantities equal
//!   the textbook step's: `U_cur` of step K is the textbook simulation's
//!   after K − 1 steps, `p_N` is `fast_mass_springs_step_sparse` with
//!   `iterations = N` from the files' `U_prev`, `U_cur`;
//! * `--compare` of a trace against itself agrees everywhere; so does a
//!   student's solution that made the handout's choices differently: the
//!   springs in another order with some reversed (its `A`, `r` and `d`
//!   written here from the scene's springs and our rows), files in the
//!   other format (dense for sparse, a row for a column, `M` as its
//!   diagonal), another ordering;
//! * each planted mistake is the first line that fails, named with its
//!   place: a missing spring, a repeated one, a changed one, a spring
//!   reversed in `A` but not in `d`, `U_prev` and `U_cur` swapped in `y`
//!   (caught at the default step, hidden at step 1), a wrong mass, the
//!   pins' term forgotten in `Q`, a wrong factor (the student's `Q` and `y`
//!   computed here from our files, not by the code under test);
//! * bad input (a file for `-o`, a folder that is no trace, an unreadable
//!   student file, out-of-range flags, a manifest claiming 10⁸ iterations,
//!   an `A` declaring five million rows) is refused with a clear error, and
//!   an `L` whose `L Lᵀ` would be dense is checked in bounded memory.
use crate::cli;

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
    assert!(line(&report, "A").contains("the same springs in the same order"));
    assert!(report.contains("all 16 quantities given agree"), "{report}");
    assert!(report.contains("step 3, 2 iteration(s)"), "{report}");
}

/// The student's springs: their row `e′` is our spring `.0`, run the
/// other way when `.1`.
type Springs = Vec<(usize, bool)>;

/// Every spring once, in another order (the last first, then every
/// seventh, ...) with every third reversed: a correct solution that made
/// the handout's choices differently.
fn another_order(m: usize) -> Springs {
    let mut order: Vec<usize> = (0..m).rev().collect();
    order.sort_by_key(|e| e % 7); // stable: reversed within each class of e mod 7
    order
        .into_iter()
        .enumerate()
        .map(|(at, e)| (e, at % 3 == 0))
        .collect()
}

/// Writes the student's `A`, `r` and `d_1` … `d_iterations` for `springs`:
/// `A` made here from the scene's springs by the handout's definition
/// (+1 at the first end, −1 at the second), `r` and `d` our rows moved to
/// the student's, `d` negated where the spring is reversed.
fn write_springs(scene: &Scene, ours: &Path, theirs: &Path, springs: &Springs, iterations: usize) {
    let n = scene.vertices.len();
    let mut a = TripletMatrix::new(springs.len(), n);
    for (row, &(e, reversed)) in springs.iter().enumerate() {
        let [i, j] = scene.springs[e];
        let (plus, minus) = if reversed { (j, i) } else { (i, j) };
        a.push(row, plus, 1.0).unwrap();
        a.push(row, minus, -1.0).unwrap();
    }
    write_sparse(&theirs.join("A.mtx"), &a.to_csc());
    let r = dense(ours, "r.mtx");
    let r: Vec<f64> = springs.iter().map(|&(e, _)| r[(e, 0)]).collect();
    write_dense(
        &theirs.join("r.mtx"),
        &DenseMatrix::from_row_major(r.len(), 1, r).unwrap(),
    );
    for k in 1..=iterations {
        let d = points(ours, &format!("d_{k}.mtx"));
        let rows: Vec<[f64; 3]> = springs
            .iter()
            .map(|&(e, reversed)| d[e].map(|x| if reversed { -x } else { x }))
            .collect();
        write_dense(
            &theirs.join(format!("d_{k}.mtx")),
            &DenseMatrix::from_rows(&rows).unwrap(),
        );
    }
}

/// An empty folder `theirs` beside `ours`.
fn empty_beside(ours: &Path) -> PathBuf {
    let theirs = ours.parent().unwrap().join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    theirs
}

/// A folder `theirs` beside `ours` holding a copy of every file of ours.
fn copy_of(ours: &Path) -> PathBuf {
    let theirs = empty_beside(ours);
    copy_folder(ours, &theirs);
    theirs
}

#[test]
fn springs_in_another_order_and_orientation_agree() {
    let ours = trace("flag", &[], "spring-order");
    let theirs = copy_of(&ours);
    let flag = scene("flag");
    let springs = another_order(flag.springs.len());
    write_springs(&flag, &ours, &theirs, &springs, 2);
    let (success, report, error) = compare(&ours, &theirs);
    assert!(success, "{report}\n{error}");
    assert!(report.contains("all 16 quantities given agree"), "{report}");
    let a = line(&report, "A");
    assert!(
        a.contains(" note ") && a.contains("another spring order (allowed)"),
        "{a}"
    );
    let reversed = springs.iter().filter(|s| s.1).count();
    assert!(a.contains(&format!("{reversed} reversed")), "{a}");
    for name in ["r", "d_1", "d_2"] {
        assert!(line(&report, name).contains(" agrees     0 "), "{report}");
    }
}

#[test]
fn a_reversed_spring_must_reverse_its_d_too() {
    let ours = trace("net", &[], "reversed");
    let theirs = empty_beside(&ours);
    let net = scene("net");
    let mut springs: Springs = (0..net.springs.len()).map(|e| (e, false)).collect();
    springs[3].1 = true;
    write_springs(&net, &ours, &theirs, &springs, 1);
    let (success, report, _) = compare(&ours, &theirs);
    assert!(success, "{report}");
    // the same A, but d_1 of spring 3 kept in our orientation
    std::fs::copy(ours.join("d_1.mtx"), theirs.join("d_1.mtx")).unwrap();
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report), ["d_1"], "{report}");
    let [i, j] = net.springs[3];
    let expected =
        format!("your spring 3 = ({j}, {i}), our spring 3 = ({i}, {j}) reversed: ours negated");
    assert!(
        line(&report, "d_1").contains(&expected),
        "{expected} in {report}"
    );
    assert!(
        line(&report, "d_1").contains("(file row 4, column"),
        "{report}"
    );
}

/// `Q` of the student's springs: ours plus `k aₑᵀaₑ` for each spring `e`
/// of `extra` and minus it for each of `missing`, computed here.
fn q_with_springs(ours: &Path, scene: &Scene, extra: &[usize], missing: &[usize]) -> CscMatrix {
    let mut q = sparse(ours, "Q.mtx");
    let changes = extra
        .iter()
        .map(|e| (e, 1.0))
        .chain(missing.iter().map(|e| (e, -1.0)));
    for (&e, sign) in changes {
        let [i, j] = scene.springs[e];
        for (r, c, v) in [(i, i, 1.0), (j, j, 1.0), (i, j, -1.0), (j, i, -1.0)] {
            q = with_entry(&q, r, c, Some(q.get(r, c) + sign * scene.k * v));
        }
    }
    q
}

#[test]
fn a_missing_spring_is_named_first() {
    let ours = trace("flag", &[], "missing");
    let theirs = copy_of(&ours);
    let flag = scene("flag");
    let mut springs = another_order(flag.springs.len());
    let (lost, _) = springs.remove(100);
    write_springs(&flag, &ours, &theirs, &springs, 2);
    write_sparse(
        &theirs.join("Q.mtx"),
        &q_with_springs(&ours, &flag, &[], &[lost]),
    );
    let (success, report, error) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report)[..2], ["A", "Q"], "{report}");
    let [i, j] = flag.springs[lost];
    let expected = format!("our spring {lost} = ({i}, {j}) is in no row of yours");
    assert!(
        line(&report, "A").contains(&expected),
        "{expected} in {report}"
    );
    assert!(
        report.contains("first wrong quantity: A (A.mtx): our spring"),
        "{report}"
    );
    assert!(error.contains("the first is A"), "{error}");
    // r and d agree over the springs the student has
    assert!(
        line(&report, "r").contains("over the 12441 springs your A shares"),
        "{report}"
    );
}

#[test]
fn a_duplicated_spring_is_named_first() {
    let ours = trace("flag", &[], "duplicate");
    let theirs = copy_of(&ours);
    let flag = scene("flag");
    let mut springs = another_order(flag.springs.len());
    let twice = springs[5];
    springs.insert(9, twice);
    write_springs(&flag, &ours, &theirs, &springs, 2);
    write_sparse(
        &theirs.join("Q.mtx"),
        &q_with_springs(&ours, &flag, &[twice.0], &[]),
    );
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report)[..2], ["A", "Q"], "{report}");
    let [i, j] = flag.springs[twice.0];
    let (a, b) = if twice.1 { (j, i) } else { (i, j) };
    let expected = format!(
        "your spring 9 = ({a}, {b}) (file row 10) repeats your spring 5 = ({a}, {b}) (file row 6), \
         our spring {} = ({i}, {j})",
        twice.0
    );
    assert!(
        line(&report, "A").contains(&expected),
        "{expected} in {report}"
    );
}

/// `y = M (2 u_cur − u_prev)/Δt² + f_ext`, computed here from the files.
fn inertial(folder: &Path, u_prev: &str, u_cur: &str) -> DenseMatrix {
    let masses = sparse(folder, "M.mtx").diagonal();
    let (u_prev, u_cur) = (points(folder, u_prev), points(folder, u_cur));
    let rows: Vec<[f64; 3]> = (0..masses.len())
        .map(|i| {
            let f_ext = [0.0, -9.8, 0.0];
            [0, 1, 2].map(|c| {
                masses[i] * (2.0 * u_cur[i][c] - u_prev[i][c]) / (DELTA_T * DELTA_T) + f_ext[c]
            })
        })
        .collect();
    DenseMatrix::from_rows(&rows).unwrap()
}

#[test]
fn swapped_u_prev_and_u_cur_are_named_first_at_the_default_step() {
    // trace's default step: the swap gives another y
    let ours = trace("flag", &[], "swapped");
    let theirs = copy_of(&ours);
    let y = inertial(&ours, "U_cur.mtx", "U_prev.mtx"); // U_prev and U_cur swapped
    write_dense(&theirs.join("y.mtx"), &y);
    let (success, report, error) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report)[0], "y", "{report}");
    assert!(error.contains("the first is y"), "{error}");
    // the same y computed right agrees (so the test's own y is the handout's)
    write_dense(
        &theirs.join("y.mtx"),
        &inertial(&ours, "U_prev.mtx", "U_cur.mtx"),
    );
    let (success, report, _) = compare(&ours, &theirs);
    assert!(success, "{report}");
    // at step 1, U_prev = U_cur = V: the swap hides, as the README says
    let first = trace("flag", &["--step", "1"], "swapped-step-1");
    let theirs = copy_of(&first);
    write_dense(
        &theirs.join("y.mtx"),
        &inertial(&first, "U_cur.mtx", "U_prev.mtx"),
    );
    let (success, report, _) = compare(&first, &theirs);
    assert!(success, "{report}");
    let readme = std::fs::read_to_string(first.join("README.md")).unwrap();
    let warning = "This trace is of step 1: `prev-cur-swapped`, `r-from-deformed`, \
                   `velocity-lost` pass unseen here; trace step 3 too.";
    assert!(readme.contains(warning), "{readme}");
    let swapped = "| `prev-cur-swapped`: `y = M (2 U_prev − U_cur)/Δt² + f_ext` | `y` | cannot";
    assert!(readme.contains(swapped), "{readme}");
}

#[test]
fn a_wrong_mass_is_the_first_quantity_that_fails_with_its_row() {
    let ours = trace("net", &[], "wrong-m");
    let theirs = copy_of(&ours);
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
    let expected = "vertex 6, vertex 6 (file row 7, column 7): ours 1, yours 1.1";
    assert!(line(&report, "M").contains(expected), "{report}");
    assert!(
        line(&report, "M").contains("relative to |yours|"),
        "{report}"
    );
    assert!(
        report.contains("first wrong quantity: M (M.mtx): vertex 6, vertex 6 (file row 7"),
        "{report}"
    );
    assert!(
        error.contains("3 of the 16 quantities given differ; the first is M"),
        "{error}"
    );
}

#[test]
fn a_forgotten_pin_term_in_q_is_named_first() {
    let ours = trace("flag", &[], "no-pins-in-q");
    let theirs = copy_of(&ours);
    // Q without w CᵀC: w = 1e10 less on the diagonal of each pinned vertex
    let (mut q, c) = (sparse(&ours, "Q.mtx"), sparse(&ours, "C.mtx"));
    for v in 0..c.ncols() {
        if !c.column(v).0.is_empty() {
            q = with_entry(&q, v, v, Some(q.get(v, v) - 1e10));
        }
    }
    write_sparse(&theirs.join("Q.mtx"), &q);
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report), ["Q"], "{report}");
    let pinned = scene("flag").pinned;
    let q_line = line(&report, "Q");
    assert!(
        pinned
            .iter()
            .any(|v| q_line.contains(&format!("vertex {v} (pinned), vertex {v} (pinned)"))),
        "{q_line}"
    );
}

#[test]
fn a_changed_spring_names_a_and_its_row_first() {
    let ours = trace("flag", &[], "wrong-a");
    let theirs = copy_of(&ours);
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
    assert_eq!(failing(&report), ["A", "Q", "b_1"], "{report}");
    let b_line = line(&report, "b_1");
    let rows = [j, j + 1].map(|v| format!("vertex {v} (pinned),"));
    assert!(rows.iter().any(|row| b_line.contains(row)), "{report}");
    let expected = format!(
        "your spring 17 = ({i}, {}) (file row 18) is not a spring of ours: none joins vertices \
         {i} and {}; our spring 17 = ({i}, {j}) is in no row of yours",
        j + 1,
        j + 1
    );
    assert!(
        line(&report, "A").contains(&expected),
        "{expected} in {report}"
    );
    assert!(
        report.contains("first wrong quantity: A (A.mtx): your spring 17"),
        "{report}"
    );
    // r and d are compared over the other springs, which agree
    assert!(line(&report, "r").contains("agrees"), "{report}");
}

#[test]
fn other_formats_and_another_ordering_are_accepted() {
    let ours = trace("net", &[], "formats");
    let natural = trace("net", &["--ordering", "natural"], "formats-natural");
    let theirs = empty_beside(&ours);
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
    let theirs = empty_beside(&ours);
    let l = sparse(&ours, "L.mtx");
    let wrong = with_entry(&l, 5, 5, Some(l.get(5, 5) * (1.0 + 1e-6)));
    write_sparse(&theirs.join("L.mtx"), &wrong);
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    assert_eq!(failing(&report), ["L"], "{report}");
    assert!(
        line(&report, "L").contains(", column 6 of L Lᵀ − P Q Pᵀ)"),
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
    let theirs = empty_beside(&ours);
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
    assert!(error.contains("Q.mtx: not of the trace"), "{error}");
    // (without the trace's fingerprint in its manifest, the files are read)
    let manifest = std::fs::read_to_string(edited.join("trace.json")).unwrap();
    let mut manifest: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    manifest.as_object_mut().unwrap().remove("trace");
    std::fs::write(edited.join("trace.json"), manifest.to_string()).unwrap();
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
fn a_spring_quantity_without_its_a_says_how_to_compare_in_your_order() {
    let ours = trace("net", &[], "d-without-a");
    let theirs = empty_beside(&ours);
    let mut d = dense(&ours, "d_1.mtx");
    d[(3, 0)] += 1.0;
    write_dense(&theirs.join("d_1.mtx"), &d);
    let (success, report, _) = compare(&ours, &theirs);
    assert!(!success);
    let d_1 = line(&report, "d_1");
    assert!(
        d_1.contains("(compared in our spring order: give your A.mtx to compare in yours)"),
        "{d_1}"
    );
    assert!(!report.contains("(;"), "{report}");
    // --json goes with --compare only
    let net = data("net.json");
    let output = masssprings(&["trace", &net, "-o", theirs.to_str().unwrap(), "--json"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("give --compare"),
        "{}",
        stderr(&output)
    );
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

/// Runs `trace --compare ours theirs` with a memory limit of `limit_gb`
/// and, when `address_space_kb`, an address-space limit (`ulimit -v`)
/// that an allocation past it would abort on, stopped after 120 s (exit
/// code 124): (exit code, stdout, stderr).
fn compare_limited(
    ours: &Path,
    theirs: &Path,
    limit_gb: &str,
    address_space_kb: Option<u64>,
) -> (Option<i32>, String, String) {
    let binary = env!("CARGO_BIN_EXE_masssprings");
    let (ours, theirs) = (ours.to_str().unwrap(), theirs.to_str().unwrap());
    let ulimit = address_space_kb.map_or(String::new(), |kb| format!("ulimit -v {kb} && "));
    let output = std::process::Command::new("sh")
        .args([
            "-c",
            &format!("{ulimit}exec timeout 120 \"$0\" trace --compare \"$1\" \"$2\""),
        ])
        .args([binary, ours, theirs])
        .env(masssprings::memory::LIMIT_VARIABLE, limit_gb)
        .output()
        .unwrap();
    (output.status.code(), stdout(&output), stderr(&output))
}

#[test]
fn a_manifest_claiming_a_hundred_million_iterations_is_refused() {
    let ours = trace("net", &[], "manifest-1e8");
    let path = ours.join("trace.json");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(
        &path,
        text.replace("\"iterations\": 2", "\"iterations\": 100000000"),
    )
    .unwrap();
    let (code, _, error) = compare_limited(&ours, &ours, "0.05", None);
    assert_eq!(code, Some(1), "{error}");
    let expected = format!("{}: iterations 100000000 and step 3", path.display());
    assert!(error.contains(&expected), "{expected} in {error}");
}

#[test]
fn a_student_a_of_five_million_rows_is_refused_with_its_estimate() {
    let ours = trace("net", &[], "a-5e6-rows");
    let theirs = empty_beside(&ours);
    // 60 bytes that the reader accepts (its rows cost 32 bytes each, 0.16 GB)
    std::fs::write(
        theirs.join("A.mtx"),
        "%%MatrixMarket matrix coordinate real general\n5000000 81 2\n1 1 1\n1 2 -1\n",
    )
    .unwrap();
    std::fs::copy(ours.join("r.mtx"), theirs.join("r.mtx")).unwrap();
    let (code, report, _) = compare_limited(&ours, &theirs, "0.2", None);
    assert_eq!(code, Some(1), "{report}");
    assert_eq!(failing(&report), ["A"], "{report}");
    let a = line(&report, "A");
    assert!(
        a.contains("A.mtx: the springs of an A of 5000000 rows would need 0.480 GB"),
        "{a}"
    );
    assert!(a.contains("the limit here is 0.200 GB"), "{a}");
    // r is then compared in our order, and agrees
    assert!(line(&report, "r").contains("agrees"), "{report}");
}

#[test]
fn a_student_l_whose_product_is_dense_is_checked_in_bounded_memory() {
    // On the skirt (n = 9840), an L with a full first column makes L Lᵀ a
    // dense 9840 × 9840 matrix: 1.5 GB if it were built. Checked column by
    // column, the comparison fits in an address space of 1 GB.
    let ours = trace("skirt", &["--iterations", "1"], "dense-product");
    let theirs = empty_beside(&ours);
    let n = sparse(&ours, "Q.mtx").nrows();
    let mut l = TripletMatrix::new(n, n);
    for k in 0..n {
        l.push(k, 0, 1.0).unwrap(); // column 0, full
        if k > 0 {
            l.push(k, k, 1.0).unwrap();
        }
    }
    write_sparse(&theirs.join("L.mtx"), &l.to_csc());
    assert!(std::fs::metadata(theirs.join("L.mtx")).unwrap().len() < 1_000_000);
    let (code, report, error) = compare_limited(&ours, &theirs, "4", Some(1_000_000));
    assert_eq!(code, Some(1), "{report}\n{error}");
    assert_eq!(failing(&report), ["L"], "{report}");
    assert!(line(&report, "L").contains("L Lᵀ ≠ P Q Pᵀ"), "{report}");
}

#[test]
fn an_array_of_5555555555555_rows_and_no_column_is_refused_at_once() {
    // 56 bytes that hold no value (found by the fuzz target trace_compare):
    // made sparse, its rows alone would cost 178 TB, and looping over them
    // would never end
    let ours = trace("net", &[], "no-columns");
    let theirs = empty_beside(&ours);
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile");
    for name in ["A.mtx", "P.mtx", "L.mtx", "r.mtx"] {
        std::fs::copy(
            corpus.join("array-5555555555555-by-0.mtx"),
            theirs.join(name),
        )
        .unwrap();
    }
    let started = std::time::Instant::now();
    let (code, report, _) = compare_limited(&ours, &theirs, "4", None);
    assert!(started.elapsed() < std::time::Duration::from_secs(20));
    assert_eq!(code, Some(1), "{report}");
    assert_eq!(failing(&report), ["A", "r", "P", "L"], "{report}");
    for name in ["A", "P", "L"] {
        let line = line(&report, name);
        assert!(
            line.contains("a 5555555555555 × 0 array with 0 nonzeros made sparse would need"),
            "{line}"
        );
    }
    assert!(
        line(&report, "r").contains("shape 5555555555555 × 0, ours 144 × 1"),
        "{report}"
    );
}
