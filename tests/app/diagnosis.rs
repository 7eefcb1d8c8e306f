//! `trace --compare --json` says what went wrong, for a student's solution
//! written by this test's own code (`common/student.rs`: another spring
//! order and orientation, dense matrices, another ordering and factor):
//!
//! * a correct solution agrees, from our state and from its own steps
//!   from rest: `"agree": true`, `"diagnosis": null`, exit 0;
//! * every mistake of the gallery, written by the student's code, is
//!   diagnosed by its name at step 3 (a mistake of the loop from the
//!   student's own steps, the others from our `U_prev` and `U_cur`);
//! * a mistake of the step is diagnosed by name from the student's own
//!   steps too, where their state already differs from ours;
//! * a quantity no mistake makes gets a hint that holds: a factor, a swap,
//!   the coefficients of its terms, a matrix written transposed.
//!
//! The scene is a small cloth of this test's own (6 × 5 vertices, Voronoi
//! masses, one edge pinned, not the last vertex), on which every mistake
//! shows and the student's dense matrices stay small.

use crate::cli;
use crate::common::student;

use cli::{compare_json, masssprings, stderr, temp_folder};
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::mistakes::{Mistake, Part};
use std::path::{Path, PathBuf};
use student::{small_cloth, Start, Student};

/// Our trace of `scene` at step 3, 2 iterations, into `folder/ours`.
fn trace(scene: &Path, folder: &Path) -> PathBuf {
    let ours = folder.join("ours");
    let output = masssprings(&[
        "trace",
        scene.to_str().unwrap(),
        "-o",
        ours.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    ours
}

struct Setting {
    _folder: cli::TempFolder,
    scene: Scene,
    ours: PathBuf,
    root: PathBuf,
}

fn setting(name: &str) -> Setting {
    let folder = temp_folder(name);
    let json = small_cloth(&folder);
    let scene = load_scene(&json).unwrap();
    let ours = trace(&json, &folder);
    let root = folder.to_path_buf();
    Setting {
        _folder: folder,
        scene,
        ours,
        root,
    }
}

#[test]
fn a_correct_solution_agrees_with_no_diagnosis() {
    let s = setting("diagnosis-correct");
    for (label, start) in [
        ("from-ours", Start::Ours(&s.ours)),
        ("own-run", Start::OwnRun),
    ] {
        let theirs = s.root.join(label);
        Student::new(&s.scene, None).write(start, 3, 2, &theirs);
        let (code, json) = compare_json(&s.ours, &theirs);
        assert_eq!(code, Some(0), "{label}: {json:#}");
        assert_eq!(json["agree"], true, "{label}: {json:#}");
        assert!(
            json["first"].is_null() && json["diagnosis"].is_null(),
            "{label}: {json:#}"
        );
        let quantities = json["quantities"].as_array().unwrap();
        assert_eq!(quantities.len(), 16);
        assert!(
            quantities
                .iter()
                .all(|q| ["agrees", "note"].contains(&q["result"].as_str().unwrap())),
            "{json:#}"
        );
    }
}

#[test]
fn every_mistake_of_the_gallery_is_diagnosed_by_name_at_step_3() {
    let s = setting("diagnosis-gallery");
    let mut missed = Vec::new();
    for mistake in Mistake::ALL {
        let name = mistake.name();
        let theirs = s.root.join(name);
        let start = match mistake.entry().part {
            Part::Loop => Start::OwnRun,
            _ => Start::Ours(&s.ours),
        };
        Student::new(&s.scene, Some(name)).write(start, 3, 2, &theirs);
        let (code, json) = compare_json(&s.ours, &theirs);
        assert_eq!(code, Some(1), "{name}: {json:#}");
        assert_eq!(json["agree"], false);
        if json["diagnosis"]["mistake"] != name {
            missed.push(format!(
                "{name}: first {}, diagnosis {}",
                json["first"], json["diagnosis"]
            ));
        }
    }
    assert!(missed.is_empty(), "{}", missed.join("\n"));
}

#[test]
fn a_mistake_of_the_step_is_named_from_the_students_own_steps_too() {
    let s = setting("diagnosis-own-run");
    for name in [
        "gravity-sign",
        "prev-cur-swapped",
        "d-against-a",
        "d-from-u-cur",
        "pins-not-in-b",
    ] {
        let theirs = s.root.join(name);
        Student::new(&s.scene, Some(name)).write(Start::OwnRun, 3, 2, &theirs);
        let (code, json) = compare_json(&s.ours, &theirs);
        assert_eq!(code, Some(1));
        let first = json["first"].as_str().unwrap();
        assert!(
            ["U_prev", "U_cur"].contains(&first),
            "{name}: the state differs first: {json:#}"
        );
        assert_eq!(json["diagnosis"]["mistake"], name, "{json:#}");
        let text = json["diagnosis"]["text"].as_str().unwrap();
        assert!(
            text.starts_with(&format!("your {first}"))
                && text.contains("your own steps' from rest"),
            "{text}"
        );
    }
}

#[test]
fn r_from_deformed_is_named_whichever_r_the_student_wrote() {
    let s = setting("diagnosis-r");
    for (label, step_r_written, first) in [("precomputed", false, "d_1"), ("step", true, "r")] {
        let theirs = s.root.join(label);
        let mut student = Student::new(&s.scene, Some("r-from-deformed"));
        student.step_r_written = step_r_written;
        student.write(Start::Ours(&s.ours), 3, 2, &theirs);
        let (_, json) = compare_json(&s.ours, &theirs);
        assert_eq!(json["first"], first, "{label}: {json:#}");
        assert_eq!(
            json["diagnosis"]["mistake"], "r-from-deformed",
            "{label}: {json:#}"
        );
    }
}

/// `value` with columns `a` and `b` swapped, written over `path`.
fn swap_columns(path: &Path, a: usize, b: usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    let rows: usize = lines[1].split_whitespace().next().unwrap().parse().unwrap();
    let (start_a, start_b) = (2 + a * rows, 2 + b * rows);
    for i in 0..rows {
        lines.swap(start_a + i, start_b + i);
    }
    std::fs::write(path, lines.join("\n") + "\n").unwrap();
}

/// A coordinate file written over by its transpose.
fn transpose_coordinate(path: &Path) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('%'));
    let swap = |line: &str| {
        let parts: Vec<&str> = line.split_whitespace().collect();
        let rest = parts[2..].join(" ");
        format!("{} {} {rest}", parts[1], parts[0])
    };
    let mut out = vec!["%%MatrixMarket matrix coordinate real general".to_string()];
    out.extend(lines.by_ref().map(swap));
    std::fs::write(path, out.join("\n") + "\n").unwrap();
}

#[test]
fn a_matrix_written_transposed_is_said_to_be() {
    let s = setting("diagnosis-transposed");
    let theirs = s.root.join("theirs");
    Student::new(&s.scene, None).write(Start::Ours(&s.ours), 3, 2, &theirs);
    transpose_coordinate(&theirs.join("C.mtx"));
    let (_, json) = compare_json(&s.ours, &theirs);
    assert_eq!(json["first"], "C");
    let text = json["diagnosis"]["text"].as_str().unwrap();
    assert!(
        text.contains("your C is the handout's transposed"),
        "{text}"
    );
    Student::new(&s.scene, None).write(Start::Ours(&s.ours), 3, 2, &theirs);
    transpose_coordinate(&theirs.join("L.mtx"));
    let (_, json) = compare_json(&s.ours, &theirs);
    assert_eq!(json["first"], "L");
    let text = json["diagnosis"]["text"].as_str().unwrap();
    assert!(text.contains("your L is upper triangular"), "{text}");
}

#[test]
fn a_quantity_no_mistake_makes_gets_a_hint_that_holds() {
    let s = setting("diagnosis-hints");
    let theirs = s.root.join("theirs");
    Student::new(&s.scene, None).write(Start::Ours(&s.ours), 3, 2, &theirs);
    // p_1 with x and z swapped: no mistake of the gallery, a swapped pair
    swap_columns(&theirs.join("p_1.mtx"), 0, 2);
    let (_, json) = compare_json(&s.ours, &theirs);
    assert_eq!(json["first"], "p_1");
    assert!(json["diagnosis"]["mistake"].is_null(), "{json:#}");
    let text = json["diagnosis"]["text"].as_str().unwrap();
    assert!(text.contains("columns x and z swapped"), "{text}");
    // y three times the handout's: a factor, named
    let student = Student::new(&s.scene, None);
    student.write(Start::Ours(&s.ours), 3, 2, &theirs);
    let y = std::fs::read_to_string(theirs.join("y.mtx")).unwrap();
    let tripled: Vec<String> = y
        .lines()
        .enumerate()
        .map(|(i, line)| match i {
            0 | 1 => line.to_string(),
            _ => format!("{:.16e}", 3.0 * line.trim().parse::<f64>().unwrap()),
        })
        .collect();
    std::fs::write(theirs.join("y.mtx"), tripled.join("\n") + "\n").unwrap();
    let (_, json) = compare_json(&s.ours, &theirs);
    let text = json["diagnosis"]["text"].as_str().unwrap();
    assert!(text.contains("times 3"), "{text}");
    // Q with its spring term doubled: the terms' coefficients
    let doubled = s.root.join("doubled");
    Student::new(&s.scene, Some("springs-doubled-in-q")).write(
        Start::Ours(&s.ours),
        3,
        2,
        &doubled,
    );
    let (_, json) = compare_json(&s.ours, &doubled);
    assert_eq!(json["first"], "Q");
    let text = json["diagnosis"]["text"].as_str().unwrap();
    let expected = "yours is Q = 2 k AᵀA + M/Δt² + w CᵀC (from your own inputs): k AᵀA has the \
                    coefficient 2 where the handout has 1";
    assert!(text.contains(expected), "{text}");
}
