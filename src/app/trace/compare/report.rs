//! The report of `--compare`, as a table a student reads or as one JSON
//! object a program reads (`--json`), from the same findings:
//!
//! ```text
//! comparing OTHER with DIR (scene, step, iterations, ordering)   (text only)
//! legend, then one line per quantity: result, relative, tolerance, where
//! ignored: the student's .mtx files that are no quantity of this trace
//! first wrong quantity: …        diagnosis: …
//!
//! {"agree": false, "first": "y", "quantities": [{"name", "result", "relative",
//!  "tolerance", "where"}, …], "diagnosis": {"mistake": "gravity-sign" | null, "text": "…"}}
//! ```
//!
//! `"diagnosis"` is `null` when everything given agrees. The exit status
//! is the same either way: 1 when a quantity differs or none was given.

use super::diagnosis::Diagnosis;
use super::place::{Context, Place};
use crate::app::error::AppError;
use crate::app::trace::quantities::{Check, Quantity};
use std::path::Path;

/// What a comparison found for one quantity.
#[derive(Debug)]
pub enum Outcome {
    /// Not in the student's folder.
    NotGiven,
    /// Within the tolerance; the largest difference, if any, and a remark.
    Agrees(Option<Place>, String),
    /// Outside the tolerance (at `Place`), or the file could not be
    /// compared at all (the reason).
    Differs(Option<Place>, String),
    /// Allowed, but worth saying (another ordering `P`, another spring order).
    Note(String),
}

/// Everything the report says.
pub struct Report<'a> {
    pub heading: String,
    pub findings: Vec<(Quantity, Outcome)>,
    pub ignored: Vec<String>,
    pub diagnosis: Option<Diagnosis>,
    pub context: &'a Context,
    /// The trace's iterations (for the ignored files' line).
    pub iterations: usize,
}

/// What the columns of the table are.
const LEGEND: &str = "\
relative:  the largest |ours − yours| of the quantity divided by the scale named under \"where\"
           (|ours|, |yours|, or what the entry is held to); tolerance is the largest that agrees
where:     vertices, springs and pins count from 0 as in V, E and b (and Eigen); the file's row
           and column count from 1; at vertices the place shown is a free one unless only a pin differs

quantity  result     relative   tolerance  where";

/// One quantity's columns, as both reports give them.
struct Line {
    result: &'static str,
    relative: Option<f64>,
    /// `None`: any (an ordering), or not given.
    tolerance: Option<f64>,
    at: String,
}

impl Report<'_> {
    /// The quantity's line.
    fn line(&self, quantity: &Quantity, outcome: &Outcome) -> Line {
        let (result, place, remark) = match outcome {
            Outcome::NotGiven => ("not given", None, ""),
            Outcome::Agrees(place, remark) => ("agrees", place.as_ref(), remark.as_str()),
            Outcome::Differs(place, reason) => ("differs", place.as_ref(), reason.as_str()),
            Outcome::Note(remark) => ("note", None, remark.as_str()),
        };
        let place = place.filter(|p| p.relative() > 0.0); // no place for no difference
        let numeric = !matches!(quantity.spec.check, Check::Ordering | Check::Incidence);
        let relative = match (place, outcome) {
            (Some(place), _) => Some(place.relative()),
            (None, Outcome::Agrees(..)) if numeric => Some(0.0),
            _ => None,
        };
        let tolerance = match (outcome, quantity.spec.check) {
            (Outcome::NotGiven, _) | (_, Check::Ordering) => None,
            (_, Check::Entries { tolerance })
            | (_, Check::Factor { tolerance })
            | (_, Check::Sum { tolerance }) => Some(tolerance),
            (_, Check::Incidence) => Some(0.0),
        };
        let at = place.map(|p| self.context.describe(quantity.spec, p));
        let at = match (at, remark.is_empty()) {
            (Some(at), false) => format!("{at} ({remark})"),
            (Some(at), true) => at,
            (None, _) => remark.to_string(),
        };
        Line {
            result,
            relative,
            tolerance,
            at,
        }
    }

    /// The first quantity that differs, and where or why.
    fn first(&self) -> Option<(&Quantity, String)> {
        self.findings.iter().find_map(|(quantity, outcome)| {
            let Outcome::Differs(place, reason) = outcome else {
                return None;
            };
            let file = quantity.file_name();
            let at = match place {
                Some(place) => self.context.describe(quantity.spec, place),
                // the reason starts with the student's file: DIR/L.mtx
                None => match reason.split_once(&format!("{file}: ")) {
                    Some((folder, rest)) if folder.is_empty() || folder.ends_with('/') => {
                        rest.to_string()
                    }
                    _ => reason.clone(),
                },
            };
            Some((quantity, at))
        })
    }

    /// How many quantities were given, and how many differ.
    fn counts(&self) -> (usize, usize) {
        let given = self
            .findings
            .iter()
            .filter(|(_, o)| !matches!(o, Outcome::NotGiven));
        let differ = self
            .findings
            .iter()
            .filter(|(_, o)| matches!(o, Outcome::Differs(..)));
        (given.count(), differ.count())
    }

    /// The table a student reads.
    pub fn print_text(&self) {
        println!("{}\n\n{LEGEND}", self.heading);
        for (quantity, outcome) in &self.findings {
            let line = self.line(quantity, outcome);
            let result = match line.result {
                "differs" => "DIFFERS",
                other => other,
            };
            let relative = line.relative.map_or(String::new(), |r| match r {
                0.0 => "0".into(),
                r => format!("{r:.2e}"),
            });
            let tolerance = match (outcome, quantity.spec.check, line.tolerance) {
                (Outcome::NotGiven, ..) => String::new(),
                (_, Check::Ordering, _) => "any".into(),
                (_, _, Some(t)) if t > 0.0 => format!("{t:e}"),
                _ => "exact".into(),
            };
            let text = format!(
                "{:<9} {result:<10} {relative:<10} {tolerance:<10} {}",
                quantity.name(),
                line.at
            );
            println!("{}", text.trim_end());
        }
        if !self.ignored.is_empty() {
            println!(
                "\nignored (not a file of this trace of {} iteration(s)): {}",
                self.iterations,
                self.ignored.join(", ")
            );
        }
        let (given, _) = self.counts();
        match self.first() {
            Some((quantity, at)) => {
                println!(
                    "\nfirst wrong quantity: {} ({}): {at}",
                    quantity.name(),
                    quantity.file_name()
                );
            }
            None if given > 0 => println!("\nall {given} quantities given agree"),
            None => {}
        }
        if let Some(diagnosis) = &self.diagnosis {
            println!("diagnosis: {}", diagnosis.text);
        }
    }

    /// One JSON object.
    pub fn print_json(&self) {
        let quantities: Vec<serde_json::Value> = self
            .findings
            .iter()
            .map(|(quantity, outcome)| {
                let line = self.line(quantity, outcome);
                serde_json::json!({
                    "name": quantity.name(),
                    "result": line.result,
                    "relative": line.relative,
                    "tolerance": line.tolerance,
                    "where": line.at,
                })
            })
            .collect();
        let (given, differ) = self.counts();
        let diagnosis = self
            .diagnosis
            .as_ref()
            .map(|d| serde_json::json!({"mistake": d.mistake.map(|m| m.name()), "text": d.text}));
        let report = serde_json::json!({
            "agree": given > 0 && differ == 0,
            "first": self.first().map(|(quantity, _)| quantity.name()),
            "quantities": quantities,
            "diagnosis": diagnosis,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&report).expect("plain values serialise")
        );
    }

    /// The exit status: an error when anything differs or nothing was given.
    pub fn conclude(&self, theirs: &Path) -> Result<(), AppError> {
        let (given, wrong) = self.counts();
        if given == 0 {
            return Err(AppError::Failed(format!(
                "{} holds none of the files trace writes (A.mtx, r.mtx, M.mtx, …): nothing was compared",
                masssprings::files::shown(theirs)
            )));
        }
        match self.first() {
            None => Ok(()),
            Some((quantity, _)) => Err(AppError::Failed(format!(
                "{wrong} of the {given} quantities given differ; the first is {}",
                quantity.name()
            ))),
        }
    }
}

/// The `.mtx` files of `theirs` that are not quantities of this trace,
/// numbered ones by their runs.
pub fn ignored(theirs: &Path, all: &[Quantity]) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(theirs) else {
        return Vec::new();
    };
    let mut ignored: Vec<String> = entries
        .flatten()
        .map(|entry| masssprings::files::escaped(&entry.file_name().to_string_lossy()).into_owned())
        .filter(|name| name.ends_with(".mtx") && !all.iter().any(|q| q.file_name() == *name))
        .collect();
    ignored.sort();
    in_runs(&ignored)
}

/// `names` with each run of three or more numbered files of one quantity
/// (`b_3.mtx`, `b_4.mtx`, … `b_50.mtx`) written as its ends, `b_3.mtx …
/// b_50.mtx`: a student's trace of 50 iterations against ours of 2 is
/// three short runs, not 144 names.
fn in_runs(names: &[String]) -> Vec<String> {
    let mut numbered: std::collections::BTreeMap<&str, Vec<usize>> = Default::default();
    let mut listed = Vec::new();
    for name in names {
        let split = name
            .strip_suffix(".mtx")
            .and_then(|stem| stem.rsplit_once('_'));
        match split.and_then(|(quantity, n)| Some((quantity, n.parse::<usize>().ok()?))) {
            Some((quantity, n)) => numbered.entry(quantity).or_default().push(n),
            None => listed.push(name.clone()),
        }
    }
    for (quantity, mut numbers) in numbered {
        numbers.sort_unstable();
        for run in numbers.chunk_by(|a, b| b.checked_sub(*a) == Some(1)) {
            let name = |n: usize| format!("{quantity}_{n}.mtx");
            match run {
                [first, .., last] if run.len() >= 3 => {
                    listed.push(format!("{} … {}", name(*first), name(*last)))
                }
                _ => listed.extend(run.iter().map(|&n| name(n))),
            }
        }
    }
    listed
}

#[cfg(test)]
mod tests {
    use super::in_runs;

    #[test]
    fn numbered_files_are_listed_by_their_runs() {
        let mut names: Vec<String> = (3..=50).map(|n| format!("b_{n}.mtx")).collect();
        names.extend(["d_3.mtx", "d_4.mtx", "d_9.mtx", "notes.mtx", "x_y.mtx"].map(String::from));
        assert_eq!(
            in_runs(&names),
            [
                "notes.mtx",
                "x_y.mtx",
                "b_3.mtx … b_50.mtx",
                "d_3.mtx",
                "d_4.mtx",
                "d_9.mtx"
            ]
        );
    }
}
