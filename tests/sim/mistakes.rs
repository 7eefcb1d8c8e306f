//! The gallery of mistakes (`docs/mistakes.md`) and the handout's slips
//! (`docs/equations.md`), held to the program so that their claims cannot
//! drift:
//!
//! * every mistake of `sim::mistakes` has a row in the gallery's table, its
//!   picture (a GIF of at most 300 KB) and the line of
//!   `docs/images/mistakes.sh` that draws it on the scene the row names;
//! * for every row, `trace --mistake` at step 3 and `trace --compare` name
//!   first the quantity the row says (only the first name is read, not the
//!   report's layout);
//! * the symptoms the gallery describes: what each mistake does to the
//!   positions, against the handout's step;
//! * each mistake changes only its own line: a mistake of the step leaves
//!   the precomputation the handout's to the bit, a mistake of the
//!   precomputation leaves the step the handout's;
//! * every line of code the slips quote is in the function they name, and
//!   every link into the two pages names a heading there;
//! * a mistake that cannot be made on a scene is refused with a message.

use crate::cli;

use cli::{data, masssprings, stderr, stdout, temp_folder};
use masssprings::linalg::sparse::Ordering;
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::mistakes::precomputation::precomputation;
use masssprings::sim::mistakes::step::{step, StudentSimulation};
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::textbook::{
    fast_mass_springs_step_sparse, precomputation_ordered, Precomputation,
};
use masssprings::sim::{Simulation, SimulationOptions, Sparse, DELTA_T};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(page: &str) -> String {
    std::fs::read_to_string(root().join(page)).unwrap()
}

/// One row of the gallery's table.
#[derive(Debug)]
struct Row {
    mistake: Mistake,
    scene: String,
    first: String,
}

/// The backticked spans of a line, in order.
fn spans(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// The rows of the table under "## Every mistake" in `docs/mistakes.md`.
fn gallery() -> Vec<Row> {
    let page = read("docs/mistakes.md");
    let table = page
        .split("## Every mistake")
        .nth(1)
        .expect("the gallery has its table");
    let rows = table.lines().skip_while(|l| !l.starts_with('|')).skip(2);
    rows.take_while(|l| l.starts_with('|'))
        .map(|line| {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let (name, scene, first) = (spans(cells[1])[0], spans(cells[3])[0], cells[5]);
            Row {
                mistake: Mistake::from_name(name).unwrap_or_else(|| panic!("no mistake {name}")),
                scene: scene.to_string(),
                first: spans(first)[0].to_string(),
            }
        })
        .collect()
}

#[test]
fn every_mistake_has_its_row_its_picture_and_its_line_in_the_script() {
    let rows = gallery();
    let named: Vec<Mistake> = rows.iter().map(|r| r.mistake).collect();
    assert_eq!(
        named,
        Mistake::ALL,
        "the table lists every mistake, in order"
    );
    let script = read("docs/images/mistakes.sh");
    for row in &rows {
        let name = row.mistake.name();
        let line = format!("draw {} {name}\n", row.scene);
        assert!(
            script.contains(&line),
            "mistakes.sh lacks `{}`",
            line.trim()
        );
        let picture = root().join(format!("docs/images/mistakes/{name}.gif"));
        let bytes = std::fs::metadata(&picture).map(|m| m.len());
        let bytes = bytes.unwrap_or_else(|_| panic!("{} is missing", picture.display()));
        assert!(
            bytes <= 300_000,
            "{name}.gif has {bytes} bytes, more than 300 KB"
        );
        let page = read("docs/mistakes.md");
        assert!(page.contains(&format!("(images/mistakes/{name}.gif)")));
        assert!(
            page.contains(&format!("\n### {name}\n")),
            "no section for {name}"
        );
    }
}

/// The quantity a report of `trace --compare` names first: the first
/// quantity's name after the word "first" on a line, wherever the report
/// puts it.
fn first_named(report: &str) -> Option<String> {
    let is_quantity = |t: &str| {
        ["A", "r", "M", "C", "Q", "P", "L", "U_prev", "U_cur", "y"].contains(&t)
            || t.split_once('_')
                .is_some_and(|(s, k)| ["d", "b", "p"].contains(&s) && k.parse::<usize>().is_ok())
    };
    report.lines().find_map(|line| {
        let (_, after) = line.split_once("first")?;
        after
            .split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .find(|t| is_quantity(t))
            .map(str::to_string)
    })
}

/// Runs `args`, which must succeed.
fn run(args: &[&str]) {
    let output = masssprings(args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
}

#[test]
fn compare_names_first_the_quantity_the_gallery_says() {
    let folder = temp_folder("mistakes-compare");
    let mut traced: BTreeMap<String, PathBuf> = BTreeMap::new();
    let step = ["--step", "3", "--iterations", "2"];
    for row in gallery() {
        let scene = data(&format!("{}.json", row.scene));
        let ours = traced.entry(row.scene.clone()).or_insert_with(|| {
            let ours = folder.join(format!("ours-{}", row.scene));
            run(&[&["trace", &scene, "-o", ours.to_str().unwrap()][..], &step].concat());
            ours
        });
        let name = row.mistake.name();
        let theirs = folder.join(name);
        let mistake = ["--mistake", name, "-o", theirs.to_str().unwrap()];
        run(&[&["trace", scene.as_str()][..], &step, &mistake].concat());
        let output = masssprings(&[
            "trace",
            "--compare",
            ours.to_str().unwrap(),
            theirs.to_str().unwrap(),
        ]);
        let report = format!("{}\n{}", stdout(&output), stderr(&output));
        assert!(
            !output.status.success(),
            "{name}: nothing differs\n{report}"
        );
        assert_eq!(
            first_named(&report).as_deref(),
            Some(row.first.as_str()),
            "{name} on {}: the gallery says {} first\n{report}",
            row.scene,
            row.first
        );
    }
}

#[test]
fn first_named_reads_the_name_whatever_the_layout() {
    let reports = [
        ("first wrong quantity: b_1 (b_1.mtx), at row 40", "b_1"),
        (
            "error: 3 of the 16 quantities given differ; the first is M",
            "M",
        ),
        ("the first to differ: U_prev, row 2", "U_prev"),
        ("A agrees\nfirst difference: d_12 at spring 3", "d_12"),
    ];
    for (report, name) in reports {
        assert_eq!(first_named(report).as_deref(), Some(name), "{report}");
    }
    assert_eq!(first_named("all 16 quantities given agree"), None);
}

fn scene(name: &str) -> Scene {
    load_scene(Path::new(&data(&format!("{name}.json")))).unwrap()
}

/// The student's precomputation of `scene` with `mistake`.
fn student(scene: &Scene, mistake: Mistake) -> Precomputation<Sparse> {
    let (v, e, m, b) = (
        &scene.vertices,
        &scene.springs,
        &scene.masses,
        &scene.pinned,
    );
    precomputation(mistake, v, e, scene.k, m, b, DELTA_T, Ordering::Amd).unwrap()
}

/// The handout's precomputation of `scene`.
fn handout(scene: &Scene) -> Precomputation<Sparse> {
    let (v, e, m, b) = (
        &scene.vertices,
        &scene.springs,
        &scene.masses,
        &scene.pinned,
    );
    precomputation_ordered(v, e, scene.k, m, b, DELTA_T, Ordering::Amd).unwrap()
}

/// The positions after each of `steps` steps of the student's code from rest.
fn student_run(scene: &Scene, mistake: Mistake, steps: usize) -> Vec<Vec<[f64; 3]>> {
    let mut simulation = StudentSimulation::new(mistake, student(scene, mistake), false);
    (0..steps)
        .map(|_| {
            simulation.step();
            simulation.positions().to_vec()
        })
        .collect()
}

/// The positions after each of `steps` steps of the handout's code from rest.
fn handout_run(scene: &Scene, steps: usize) -> Vec<Vec<[f64; 3]>> {
    let options = SimulationOptions {
        textbook: true,
        ..SimulationOptions::default()
    };
    let mut simulation = Simulation::<Sparse>::from_scene(scene, options).unwrap();
    (0..steps)
        .map(|_| {
            simulation.step().unwrap();
            simulation.positions().to_vec()
        })
        .collect()
}

fn lowest(positions: &[[f64; 3]]) -> f64 {
    positions.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min)
}

fn farthest(positions: &[[f64; 3]]) -> f64 {
    let norm = |p: &[f64; 3]| p.iter().map(|x| x * x).sum::<f64>().sqrt();
    positions.iter().map(norm).fold(0.0, f64::max)
}

/// The first step (1-based) at which vertex `v` stops going down.
fn first_bottom(run: &[Vec<[f64; 3]>], v: usize) -> usize {
    (1..run.len())
        .find(|&s| run[s][v][1] > run[s - 1][v][1])
        .unwrap()
}

#[test]
fn the_flag_shows_the_symptoms_the_gallery_describes() {
    let flag = scene("flag");
    let after = |mistake, steps| student_run(&flag, mistake, steps).pop().unwrap();
    let handout = handout_run(&flag, 30);
    assert!(lowest(&handout[29]) < -0.9, "the handout's flag hangs");
    // pins-not-in-q: thrown 10⁸ m away in the first step
    assert!(farthest(&after(Mistake::PinsNotInQ, 1)) > 1e7);
    // pins-not-in-b: the pole shrinks to the origin
    let pole = after(Mistake::PinsNotInB, 1);
    assert!(flag.pinned.iter().all(|&i| farthest(&[pole[i]]) < 1e-4));
    // r-from-deformed: stretches down without end (8 m after 60 steps)
    assert!(lowest(&after(Mistake::RFromDeformed, 30)) < -4.0);
    // gravity-times-mass: stays up
    assert!(lowest(&after(Mistake::GravityTimesMass, 30)) > -0.05);
    // a-sign, d-not-normalised: fold into the pole (the cloth reaches 2 m out)
    for mistake in [Mistake::ASign, Mistake::DNotNormalised] {
        let reach = after(mistake, 5)
            .iter()
            .map(|p| p[0].hypot(p[2]))
            .fold(0.0, f64::max);
        assert!(reach < 0.3, "{mistake}: reaches {reach} from the pole");
    }
    // the mistakes of the inertial term hide on the flag
    for mistake in [
        Mistake::MassDoubled,
        Mistake::DtNotSquared,
        Mistake::PrevCurSwapped,
        Mistake::InertiaMinusPrev,
        Mistake::InertiaSign,
        Mistake::InertiaHalfMissing,
    ] {
        let theirs = after(mistake, 30);
        let apart = (0..flag.vertices.len())
            .map(|i| farthest(&[sub(theirs[i], handout[29][i])]))
            .fold(0.0, f64::max);
        assert!(apart < 0.05, "{mistake} is {apart} from the handout's flag");
    }
}

#[test]
fn the_chain_and_the_spring_show_the_symptoms_the_gallery_describes() {
    let (chain, spring) = (scene("horizontal-chain"), scene("single-spring-horizontal"));
    let ours = handout_run(&chain, 90);
    // mass-doubled: bounces √2 times slower; inertia-half-missing moves alike
    let doubled = student_run(&chain, Mistake::MassDoubled, 90);
    let ratio = first_bottom(&doubled, 5) as f64 / first_bottom(&ours, 5) as f64;
    assert!(
        (1.2..1.6).contains(&ratio),
        "the first bottom comes {ratio} times later"
    );
    let half = student_run(&chain, Mistake::InertiaHalfMissing, 90);
    assert!((half[89][5][1] - doubled[89][5][1]).abs() < 1e-6);
    // dt-not-squared: in place within a few steps, then no bounce (ours
    // swings by more than 0.3 over the same steps)
    let light = student_run(&chain, Mistake::DtNotSquared, 90);
    let swing = |run: &[Vec<[f64; 3]>]| {
        let heights = run[8..].iter().map(|p| p[5][1]);
        heights.clone().fold(f64::MIN, f64::max) - heights.fold(f64::MAX, f64::min)
    };
    assert!(swing(&light) < 0.01 && swing(&ours) > 0.3);
    // d-from-u-cur: creeps down, never swings past the vertical
    let creeping = student_run(&spring, Mistake::DFromUCur, 90);
    assert!(creeping.iter().all(|p| p[1][0] > 0.3));
    assert!(handout_run(&spring, 90).iter().any(|p| p[1][0] < -0.5));
    // prev-cur-swapped, inertia-minus-prev: fly off
    assert!(farthest(&student_run(&spring, Mistake::PrevCurSwapped, 20)[19]) > 100.0);
    assert!(farthest(&student_run(&spring, Mistake::InertiaMinusPrev, 10)[9]) > 100.0);
    // pins-one-based: the free end is held, the pinned one swings
    let other_end = student_run(&spring, Mistake::PinsOneBased, 30);
    assert!(farthest(&[sub(other_end[29][1], spring.vertices[1])]) < 1e-6);
    assert!(farthest(&[sub(other_end[29][0], spring.vertices[0])]) > 0.1);
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[test]
fn inertia_sign_cannot_be_factored_where_inertia_outweighs_the_springs() {
    for name in ["single-spring-horizontal", "horizontal-chain", "net"] {
        let s = scene(name);
        let (v, e, m, b) = (&s.vertices, &s.springs, &s.masses, &s.pinned);
        let error = precomputation(
            Mistake::InertiaSign,
            v,
            e,
            s.k,
            m,
            b,
            DELTA_T,
            Ordering::Amd,
        )
        .expect_err(name)
        .to_string();
        assert!(error.contains("not positive definite"), "{name}: {error}");
    }
}

/// The mistakes whose line is in the step, and those whose line is in the
/// precomputation only.
const IN_THE_STEP: [Mistake; 7] = [
    Mistake::PinsNotInB,
    Mistake::RFromDeformed,
    Mistake::PrevCurSwapped,
    Mistake::DNotNormalised,
    Mistake::GravityTimesMass,
    Mistake::DFromUCur,
    Mistake::InertiaMinusPrev,
];
const IN_THE_PRECOMPUTATION: [Mistake; 4] = [
    Mistake::MassDoubled,
    Mistake::ASign,
    Mistake::PinsNotInQ,
    Mistake::PinsOneBased,
];

#[test]
fn each_mistake_changes_only_its_own_line() {
    let net = scene("net");
    let ours = handout(&net);
    for mistake in IN_THE_STEP {
        let theirs = student(&net, mistake);
        assert_eq!(theirs.Q, ours.Q, "{mistake}: Q");
        assert_eq!(
            (&theirs.A, &theirs.M, &theirs.C),
            (&ours.A, &ours.M, &ours.C)
        );
        assert_eq!(theirs.r, ours.r, "{mistake}: r");
    }
    let f_ext = vec![GRAVITY; net.vertices.len()];
    let u_prev = net.vertices.clone();
    let u_cur: Vec<[f64; 3]> = u_prev.iter().map(|p| [p[0], p[1] - 0.01, p[2]]).collect();
    let mut theirs_next = vec![[0.0; 3]; u_cur.len()];
    let mut ours_next = theirs_next.clone();
    for mistake in IN_THE_PRECOMPUTATION {
        let pre = student(&net_or_spring(mistake), mistake);
        let (u_prev, u_cur) = if pre.V.len() == u_cur.len() {
            (u_prev.clone(), u_cur.clone())
        } else {
            (
                pre.V.clone(),
                pre.V.iter().map(|p| [p[0], p[1] - 0.01, p[2]]).collect(),
            )
        };
        let f_ext = &f_ext[..pre.V.len()];
        let (theirs, ours) = (
            &mut theirs_next[..pre.V.len()],
            &mut ours_next[..pre.V.len()],
        );
        step(mistake, &pre, f_ext, &u_prev, &u_cur, theirs);
        fast_mass_springs_step_sparse(&pre, f_ext, &u_prev, &u_cur, ours);
        assert_eq!(theirs, ours, "{mistake}: the step");
    }
}

/// The net, except for `pins-one-based`, which pins past the net's last
/// vertex: the single spring.
fn net_or_spring(mistake: Mistake) -> Scene {
    scene(match mistake {
        Mistake::PinsOneBased => "single-spring-horizontal",
        _ => "net",
    })
}

#[test]
fn every_line_the_slips_quote_is_in_the_function_they_name() {
    let page = read("docs/equations.md");
    let slips = page
        .split("## The handout's slips")
        .nth(1)
        .expect("the slips");
    let mut quoted = 0;
    for line in slips.lines().filter(|l| l.starts_with("**In the code:**")) {
        let spans = spans(line);
        for (k, file) in spans.iter().enumerate().filter(|(_, s)| s.ends_with(".rs")) {
            let (function, code) = (spans[k + 1], spans[k + 2]);
            let source = read(file);
            let named = format!("fn {function}");
            let bodies = source.match_indices(&named).map(|(start, _)| {
                let rest = &source[start..];
                &rest[..rest.find("\n}\n").unwrap_or(rest.len())]
            });
            let found = bodies.filter(|body| body.contains(code)).count();
            assert!(found > 0, "{file}: no fn {function} holds `{code}`");
            quoted += 1;
        }
    }
    assert!(quoted >= 8, "the slips quote {quoted} lines");
}

/// GitHub's anchor of a heading: lower case, punctuation dropped, spaces
/// as hyphens.
fn anchor(heading: &str) -> String {
    let kept = heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .collect::<String>();
    kept.replace(' ', "-")
}

#[test]
fn every_link_into_the_gallery_and_the_slips_names_a_heading() {
    let pages = [
        "README.md",
        "docs/README.md",
        "docs/equations.md",
        "docs/mistakes.md",
    ];
    let mut checked = 0;
    for page in pages {
        let text = read(page);
        for (target, fragment) in text.split("](").skip(1).filter_map(|rest| {
            let link = &rest[..rest.find(')')?];
            let (file, fragment) = link.split_once('#')?;
            Some((file.to_string(), fragment.to_string()))
        }) {
            let file = match target.as_str() {
                "" => Path::new(page).to_path_buf(),
                other => Path::new(page).parent().unwrap().join(other),
            };
            let name = file.file_name().unwrap().to_str().unwrap();
            if !["mistakes.md", "equations.md"].contains(&name) {
                continue;
            }
            let headings = read(file.to_str().unwrap());
            let anchors: Vec<String> = headings
                .lines()
                .filter_map(|l| l.strip_prefix('#'))
                .map(|l| anchor(l.trim_start_matches('#')))
                .collect();
            assert!(
                anchors.contains(&fragment),
                "{page}: no heading #{fragment} in {name}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} links checked");
}

#[test]
fn a_mistake_that_cannot_be_made_on_a_scene_is_refused() {
    let folder = temp_folder("mistakes-refused");
    let chain = data("horizontal-chain.json");
    let gif = folder.join("chain.gif");
    let output = masssprings(&[
        "render",
        &chain,
        "--mistake",
        "pins-one-based",
        "-o",
        gif.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("pinned vertex 11 is beyond the 11 vertices"));
    assert!(!gif.exists(), "nothing is written");
    let trace = folder.join("trace");
    let args = [
        "trace",
        &chain,
        "--mistake",
        "inertia-sign",
        "-o",
        trace.to_str().unwrap(),
    ];
    let output = masssprings(&args);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("not positive definite"),
        "{}",
        stderr(&output)
    );
    let output = masssprings(&["render", &chain, "--mistake", "no-such", "-o", "x.gif"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("mass-doubled"),
        "the names are listed"
    );
}

#[test]
fn render_says_when_the_mistaken_run_stops_being_finite() {
    let folder = temp_folder("mistakes-finite");
    let png = folder.join("spring.png");
    let spring = data("single-spring-horizontal.json");
    let args = [
        "render",
        &spring,
        "--mistake",
        "inertia-minus-prev",
        "--steps",
        "1500",
    ];
    let output = masssprings(&[&args[..], &["-o", png.to_str().unwrap()]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("infinite or NaN at step"),
        "{}",
        stdout(&output)
    );
    assert!(png.exists());
}
