//! The gallery of mistakes (`docs/mistakes.md`) and the handout's slips
//! (`docs/equations.md`), held to the gallery's entries
//! (`sim::mistakes::gallery`) and to the program, so that neither can drift:
//!
//! * the page's table is the entries (name, line, scene, symptom, first
//!   quantity), its index by symptom lists each mistake in the row of its
//!   entry, every mistake has its section, its picture (a GIF of at most
//!   300 KB) and the command that draws it, and the counts the pages quote
//!   are the gallery's;
//! * the figure each section quotes is measured on the picture's run (the
//!   mistake's scene from rest, the script's steps) and lies in the
//!   entry's range; `render --mistake NAME --json` prints it;
//! * for every entry, `trace --mistake` at step 3 and `trace --compare`
//!   name first the quantity the entry says and diagnose the mistake by
//!   name, and the mistake shows from the step the entry says, not before;
//! * a scene an entry says the mistake cannot show gives the handout's run;
//! * each mistake changes only its own line: a mistake of the step leaves
//!   the precomputation the handout's to the bit, a mistake of the
//!   precomputation alone leaves the step the handout's;
//! * every line of code the slips quote is in the function they name, and
//!   every link into the two pages names a heading there;
//! * a mistake that cannot be made on a scene is refused with a message.

use crate::cli;

use cli::{data, masssprings, stderr, stdout, temp_folder};
use masssprings::linalg::sparse::Ordering;
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::mistakes::figures::{Figures, Measuring};
use masssprings::sim::mistakes::precomputation::precomputation;
use masssprings::sim::mistakes::simulation::StudentSimulation;
use masssprings::sim::mistakes::step::step;
use masssprings::sim::mistakes::{Looks, Mistake, Part};
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

/// The backticked spans of a line, in order.
fn spans(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// The table rows under `heading` in `docs/mistakes.md`, as lines.
fn table(heading: &str) -> Vec<String> {
    let page = read("docs/mistakes.md");
    let section = page
        .split(heading)
        .nth(1)
        .unwrap_or_else(|| panic!("no {heading}"));
    let rows = section.lines().skip_while(|l| !l.starts_with('|')).skip(2);
    rows.take_while(|l| l.starts_with('|'))
        .map(str::to_string)
        .collect()
}

/// The row of the table "Every mistake" that the entry of `mistake` makes.
fn row(mistake: Mistake) -> String {
    let e = mistake.entry();
    format!(
        "| [`{0}`](#{0}) | `{1}` | `{2}` | {3} | `{4}` |",
        e.name, e.wrong, e.scene, e.symptom, e.first
    )
}

#[test]
fn the_gallerys_table_is_its_entries() {
    let expected: Vec<String> = Mistake::ALL.into_iter().map(row).collect();
    assert_eq!(
        table("## Every mistake"),
        expected,
        "docs/mistakes.md's table should read:\n{}",
        expected.join("\n")
    );
}

#[test]
fn every_mistake_has_its_section_its_picture_and_its_command() {
    let page = read("docs/mistakes.md");
    for mistake in Mistake::ALL {
        let e = mistake.entry();
        let name = e.name;
        let section = page
            .split(&format!("\n### {name}\n"))
            .nth(1)
            .unwrap_or_else(|| panic!("no section for {name}"));
        let section = section
            .split("\n## ")
            .next()
            .unwrap()
            .split("\n### ")
            .next()
            .unwrap();
        let section = section.replace('\n', " ");
        assert!(
            section.contains(&format!("(images/mistakes/{name}.gif)")),
            "{name}: picture"
        );
        assert!(
            section.contains(e.figure.quoted),
            "{name}: the figure `{}`",
            e.figure.quoted
        );
        let (steps, every) = gallery_steps(e.scene);
        let command = format!(
            "masssprings render data/{}.json --mistake {name} --steps {steps} --every {every} --size 480x180 -o {name}.gif",
            e.scene
        );
        assert!(section.contains(&command), "{name}: the command {command}");
        let picture = root().join(format!("docs/images/mistakes/{name}.gif"));
        let bytes = std::fs::metadata(&picture).map(|m| m.len());
        let bytes = bytes.unwrap_or_else(|_| panic!("{} is missing", picture.display()));
        assert!(
            bytes <= 300_000,
            "{name}.gif has {bytes} bytes, more than 300 KB"
        );
    }
    let script = read("docs/images/mistakes.sh");
    let rule = "if [ \"$scene\" = flag ]; then steps=60 every=2; else steps=90 every=3; fi";
    assert!(
        script.contains(rule),
        "mistakes.sh draws on the steps gallery_steps says"
    );
    assert!(page.contains("\n## Adding a mistake\n"), "the checklist");
}

/// The steps the script draws a scene's picture with: (steps, every).
fn gallery_steps(scene: &str) -> (usize, usize) {
    match scene {
        "flag" => (60, 2),
        _ => (90, 3),
    }
}

#[test]
fn the_index_by_symptom_lists_each_mistake_under_its_entrys_row() {
    let rows = table("## By symptom");
    assert_eq!(rows.len(), Looks::ALL.len(), "one row per symptom");
    for (line, looks) in rows.iter().zip(Looks::ALL) {
        let cells: Vec<&str> = line.split(" | ").collect();
        assert_eq!(cells[0].trim_start_matches("| "), looks.words(), "{line}");
        let listed: Vec<&str> = spans(cells[1]);
        let expected: Vec<&str> = Mistake::ALL
            .iter()
            .filter(|m| m.entry().looks == looks)
            .map(|m| m.name())
            .collect();
        assert_eq!(listed, expected, "the row `{}`", looks.words());
    }
}

/// A count in words, as the pages write it.
fn in_words(n: usize) -> String {
    let units = [
        "", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine",
    ];
    let teens = [
        "ten",
        "eleven",
        "twelve",
        "thirteen",
        "fourteen",
        "fifteen",
        "sixteen",
        "seventeen",
        "eighteen",
        "nineteen",
    ];
    let tens = ["", "", "twenty", "thirty", "forty"];
    match n {
        0..=9 => units[n].into(),
        10..=19 => teens[n - 10].into(),
        _ if n.is_multiple_of(10) => tens[n / 10].into(),
        _ => format!("{}-{}", tens[n / 10], units[n % 10]),
    }
}

/// The counts of mistakes `text` quotes in words ("twenty-four mistakes",
/// "fourteen usual mistakes").
fn counts_quoted(text: &str) -> Vec<String> {
    let text = text.to_lowercase().replace('\n', " ");
    let mut found = Vec::new();
    for n in 2..50 {
        let word = in_words(n);
        for suffix in [" mistakes", " usual mistakes", " common mistakes"] {
            let phrase = format!("{word}{suffix}");
            let quoted = text
                .match_indices(&phrase)
                .filter(|(at, _)| !text[..*at].ends_with(|c: char| c.is_alphabetic() || c == '-'));
            found.extend(quoted.map(|_| word.clone()));
        }
    }
    found
}

#[test]
fn the_counts_the_pages_quote_are_the_gallerys() {
    for page in ["docs/mistakes.md", "docs/README.md"] {
        let quoted = counts_quoted(&read(page));
        assert!(!quoted.is_empty(), "{page} quotes no count of mistakes");
        for word in quoted {
            assert_eq!(
                word,
                in_words(Mistake::COUNT),
                "{page} says {word} mistakes"
            );
        }
    }
    assert_eq!(
        counts_quoted("Twenty-four mistakes, not four mistakes"),
        ["four", "twenty-four"]
    );
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

/// The positions after each step of a run.
type Run = Vec<Vec<[f64; 3]>>;

/// The figures of `mistake` on `scene` against the handout's `run`.
fn figures(scene: &Scene, mistake: Mistake, run: &[Vec<[f64; 3]>]) -> Figures {
    let mut simulation = StudentSimulation::new(mistake, student(scene, mistake), false);
    let mut measuring = Measuring::new(&scene.vertices, &scene.pinned);
    for handout in run {
        simulation.step();
        measuring.observe(handout, simulation.positions());
    }
    measuring.finish()
}

#[test]
fn the_figure_each_section_quotes_is_measured_on_its_picture_s_run() {
    let mut runs: BTreeMap<&str, (Scene, Run)> = BTreeMap::new();
    let mut wrong = Vec::new();
    for mistake in Mistake::ALL {
        let e = mistake.entry();
        let (scene, run) = runs.entry(e.scene).or_insert_with(|| {
            let s = scene(e.scene);
            let run = handout_run(&s, gallery_steps(e.scene).0);
            (s, run)
        });
        let value = figures(scene, mistake, run).get(e.figure.measure);
        let [low, high] = e.figure.range;
        if !(low..=high).contains(&value) {
            wrong.push(format!(
                "{}: {} = {value}, not in [{low}, {high}]",
                e.name,
                e.figure.measure.name()
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn render_json_prints_the_figures_the_gallery_quotes() {
    let folder = temp_folder("mistakes-json");
    let png = folder.join("spring.png");
    let spring = data("single-spring-horizontal.json");
    let args = [
        "render",
        &spring,
        "--mistake",
        "velocity-lost",
        "--steps",
        "90",
        "--json",
    ];
    let output = masssprings(&[&args[..], &["-o", png.to_str().unwrap()]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let json: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(json["mistake"], "velocity-lost");
    assert_eq!(json["first"], "U_prev");
    let entry = Mistake::VelocityLost.entry();
    assert_eq!(json["quoted"]["measure"], entry.figure.measure.name());
    let value = json["quoted"]["value"].as_f64().unwrap();
    assert_eq!(value, json["figures"]["lowest"].as_f64().unwrap());
    assert!(
        (entry.figure.range[0]..=entry.figure.range[1]).contains(&value),
        "{value}"
    );
}

/// Runs `args`, which must succeed.
fn run_ok(args: &[&str]) {
    let output = masssprings(args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
}

/// `trace --compare --json ours theirs`.
fn compare(ours: &Path, theirs: &Path) -> serde_json::Value {
    let (ours, theirs) = (ours.to_str().unwrap(), theirs.to_str().unwrap());
    let output = masssprings(&["trace", "--compare", ours, theirs, "--json"]);
    serde_json::from_str(&stdout(&output)).unwrap_or_else(|e| panic!("{e}: {}", stderr(&output)))
}

#[test]
fn compare_names_first_the_quantity_of_the_entry_and_diagnoses_the_mistake() {
    let folder = temp_folder("mistakes-compare");
    let mut traced: BTreeMap<(String, usize), PathBuf> = BTreeMap::new();
    let mut wrong = Vec::new();
    for mistake in Mistake::ALL {
        let e = mistake.entry();
        let scene = data(&format!("{}.json", e.scene));
        let (from, _) = e.shows_from;
        // at step 3 (the gallery's names), at the step it shows from, and before it
        let steps = [Some(3), Some(from), from.checked_sub(1).filter(|&s| s > 0)];
        for step in steps.into_iter().flatten() {
            let ours = traced
                .entry((e.scene.to_string(), step))
                .or_insert_with(|| {
                    let ours = folder.join(format!("ours-{}-{step}", e.scene));
                    let step = step.to_string();
                    run_ok(&[
                        "trace",
                        &scene,
                        "--step",
                        &step,
                        "-o",
                        ours.to_str().unwrap(),
                    ]);
                    ours
                });
            let theirs = folder.join(format!("{}-{step}", e.name));
            let s = step.to_string();
            run_ok(&[
                "trace",
                &scene,
                "--step",
                &s,
                "--mistake",
                e.name,
                "-o",
                theirs.to_str().unwrap(),
            ]);
            let json = compare(ours, &theirs);
            let (first, diagnosed) = (&json["first"], &json["diagnosis"]["mistake"]);
            let ok = match step < from {
                true => json["agree"] == true,
                false if step == 3 => first == e.first && diagnosed == e.name,
                false => json["agree"] == false && diagnosed == e.name,
            };
            if !ok {
                wrong.push(format!(
                    "{} at step {step}: first {first}, diagnosis {}",
                    e.name, json["diagnosis"]
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn a_scene_an_entry_says_the_mistake_cannot_show_gives_the_handouts_run() {
    let folder = temp_folder("mistakes-invisible");
    for mistake in Mistake::ALL {
        let (scenes, why) = mistake.entry().invisible_on;
        for &name in scenes {
            let s = scene(name);
            let run = handout_run(&s, 10);
            let apart = figures(&s, mistake, &run).apart;
            assert!(apart < 1e-9, "{mistake} on {name} ({why}): {apart} m apart");
            if name == "skirt" {
                continue; // its trace is the flag's, four times over
            }
            // and --compare agrees, but for a-transposed's A
            let (ours, theirs) = (folder.join(name), folder.join(format!("{name}-{mistake}")));
            let json = data(&format!("{name}.json"));
            if !ours.exists() {
                run_ok(&["trace", &json, "-o", ours.to_str().unwrap()]);
            }
            run_ok(&[
                "trace",
                &json,
                "--mistake",
                mistake.name(),
                "-o",
                theirs.to_str().unwrap(),
            ]);
            let report = compare(&ours, &theirs);
            let differ: Vec<&str> = report["quantities"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|q| q["result"] == "differs")
                .map(|q| q["name"].as_str().unwrap())
                .collect();
            let expected: &[&str] = if mistake == Mistake::ATransposed {
                &["A"]
            } else {
                &[]
            };
            assert_eq!(differ, expected, "{mistake} on {name}");
        }
    }
}

#[test]
fn the_mistakes_of_the_inertial_term_hide_on_the_flag() {
    let flag = scene("flag");
    let run = handout_run(&flag, 30);
    for mistake in [
        Mistake::MassDoubled,
        Mistake::DtNotSquared,
        Mistake::DtSquaredMissingInY,
        Mistake::PrevCurSwapped,
        Mistake::InertiaMinusPrev,
        Mistake::InertiaSign,
        Mistake::InertiaHalfMissing,
    ] {
        let apart = figures(&flag, mistake, &run).apart;
        assert!(apart < 0.05, "{mistake} is {apart} from the handout's flag");
    }
    // inertia-half-missing moves as mass-doubled, on the chain too
    let chain = scene("horizontal-chain");
    let run = handout_run(&chain, 90);
    let [half, doubled] =
        [Mistake::InertiaHalfMissing, Mistake::MassDoubled].map(|m| figures(&chain, m, &run));
    assert!((half.lowest - doubled.lowest).abs() < 1e-6);
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

/// Whether the line of `mistake` is in the precomputation alone (its
/// entry's line names no term of the step's `y` or `b`).
fn in_the_precomputation_alone(mistake: Mistake) -> bool {
    let e = mistake.entry();
    e.part == Part::Precomputation && !e.wrong.contains(" y") && !e.wrong.contains("b =")
}

#[test]
fn each_mistake_changes_only_its_own_line() {
    let net = scene("net");
    let ours = handout(&net);
    for mistake in Mistake::ALL
        .into_iter()
        .filter(|m| m.entry().part != Part::Precomputation)
    {
        let theirs = student(&net, mistake);
        assert_eq!(theirs.Q, ours.Q, "{mistake}: Q");
        assert_eq!(
            (&theirs.A, &theirs.M, &theirs.C),
            (&ours.A, &ours.M, &ours.C)
        );
        assert_eq!(theirs.r, ours.r, "{mistake}: r");
    }
    let mut checked = 0;
    for mistake in Mistake::ALL
        .into_iter()
        .filter(|&m| in_the_precomputation_alone(m))
    {
        let scene = match mistake {
            Mistake::PinsOneBased => scene("single-spring-horizontal"), // the net's last pin + 1 is past its end
            Mistake::InertiaSign => continue, // not positive definite on the net
            _ => net.clone(),
        };
        let pre = student(&scene, mistake);
        let f_ext = vec![GRAVITY; pre.V.len()];
        let u_prev = pre.V.clone();
        let u_cur: Vec<[f64; 3]> = u_prev.iter().map(|p| [p[0], p[1] - 0.01, p[2]]).collect();
        let (mut theirs, mut ours) = (vec![[0.0; 3]; u_cur.len()], vec![[0.0; 3]; u_cur.len()]);
        step(mistake, &pre, &f_ext, &u_prev, &u_cur, &mut theirs);
        fast_mass_springs_step_sparse(&pre, &f_ext, &u_prev, &u_cur, &mut ours);
        assert_eq!(theirs, ours, "{mistake}: the step");
        checked += 1;
    }
    assert!(
        checked >= 6,
        "{checked} mistakes of the precomputation alone"
    );
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
