//! The frames `simulate --out` writes, and reading one back (for
//! `--resume`): `frame-NNNNNN.obj`, an OBJ whose first two lines say what
//! it is.
//!
//! ```text
//! # net — masssprings frame, step 12, exact positions
//! # masssprings run {"vertices":81,"k":500.0,"delta_t":0.03333333333333333,"masses":"fnv1a64:…","pins":"fnv1a64:…","options":{"--method":"chebyshev",…},"carried":{…}}
//! v 0.5 -0.25 0
//! …
//! ```
//!
//! * The first line names the scene, the step, and whether the positions
//!   are exact (each coordinate the shortest decimal that reads back to
//!   the same `f64`) or rounded (`--precision D`).
//! * The second, the run's record ([`RunRecord`]), holds what a run must
//!   share with the run it continues: the vertex count, `k`, `Δt`, a
//!   fingerprint of the masses and of the pins (64-bit FNV-1a of their
//!   bits), the flags that decide the step, and what the step's methods
//!   carry from one step to the next (`sim::methods::Carried`: Chebyshev's
//!   `ρ`, Newton's damping), as it was after this frame's step.
//!
//! This file knows the format only: [`parse_frame`] takes a frame's text to
//! its parts or to an error saying what is wrong on which line, for any
//! text at all (`fuzz/fuzz_targets/frame.rs`).

use masssprings::files::{fingerprint, number, FileError};
use masssprings::linalg::kernels::Kernels;
use masssprings::linalg::sparse::SupernodeMerging;
use masssprings::mesh::obj::parse_obj;
use masssprings::mesh::Scene;
use masssprings::sim::methods::chebyshev::{ESTIMATION_ITERATIONS, RHO_CAP};
use masssprings::sim::methods::newton::LARGEST_DAMPING;
use masssprings::sim::methods::Carried;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Accuracy, StepMethod};
use std::collections::BTreeMap;

/// `frame-NNNNNN.obj`, the name of the frame of `step`.
pub fn frame_name(step: usize) -> String {
    format!("frame-{step:06}.obj")
}

/// Is `name` a frame's name, `frame-NNNNNN.obj` (6 digits or more)?
pub fn is_frame_name(name: &str) -> bool {
    frame_step(name).is_some()
}

/// The step of the frame named `name` (`frame-000012.obj`: 12).
pub fn frame_step(name: &str) -> Option<usize> {
    let digits = name.strip_prefix("frame-")?.strip_suffix(".obj")?;
    if digits.len() < 6 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// The name and number of a numbered OBJ file, `frame-000012.obj` (a
/// frame of `simulate`) or any `NAME12.obj`: the part before the trailing
/// digits, and their value (`("frame-", 12)`, `("cloth_", 12)`); `None`
/// for another file.
pub fn numbered_obj(name: &str) -> Option<(&str, usize)> {
    let stem = name.strip_suffix(".obj")?;
    let digits = stem.bytes().rev().take_while(u8::is_ascii_digit).count();
    let (prefix, number) = stem.split_at(stem.len() - digits);
    Some((prefix, number.parse().ok()?))
}

/// The words between the scene's name and the step on a frame's first line.
const FRAME_MARK: &str = " — masssprings frame, step ";
/// The start of a frame's second line.
const RECORD_MARK: &str = "# masssprings run ";

/// The first line of a frame: the scene, the step, and whether its
/// positions are exact (`precision` `None`) or rounded to `precision`
/// digits after the point.
pub fn header(scene: &str, step: usize, precision: Option<usize>) -> String {
    match precision {
        None => format!("# {scene}{FRAME_MARK}{step}, exact positions"),
        Some(digits) => format!(
            "# {scene}{FRAME_MARK}{step}, positions rounded to {digits} digits after the point"
        ),
    }
}

/// What a run must share with the run it continues, and what its methods
/// carried after a frame's step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunRecord {
    /// The run the frame is of, when it replaced another run's frames:
    /// `masssprings-PID-START` of the process that started it (a resumed
    /// run keeps it), so that the frames of the two runs are told apart in
    /// one folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
    pub vertices: usize,
    pub k: f64,
    pub delta_t: f64,
    /// A fingerprint of the rest positions' bits
    /// (`masssprings::files::fingerprint`): the same scene moved, or
    /// reshaped, is another run.
    #[serde(default)]
    pub rest: Option<String>,
    /// A fingerprint of the springs (the pairs of vertices they join).
    #[serde(default)]
    pub springs: Option<String>,
    /// A fingerprint of the masses' bits.
    pub masses: String,
    /// A fingerprint of the pinned vertices, the same way.
    pub pins: String,
    /// Each flag that decides the step, and its value.
    pub options: BTreeMap<String, String>,
    /// What the methods carried after this frame's step.
    pub carried: Carried,
}

impl RunRecord {
    /// The record of a run of `scene` with `options` (`dense`: on the
    /// dense backend), before any step, not yet of a run.
    pub fn new(scene: &Scene, options: &SimulationOptions, dense: bool) -> RunRecord {
        let rest = scene.vertices.iter().flat_map(|v| v.map(f64::to_bits));
        let springs = scene.springs.iter().flat_map(|s| s.map(|i| i as u64));
        RunRecord {
            run: None,
            vertices: scene.vertices.len(),
            k: scene.k,
            delta_t: options.delta_t,
            rest: Some(fingerprint(rest)),
            springs: Some(fingerprint(springs)),
            masses: fingerprint(scene.masses.iter().map(|m| m.to_bits())),
            pins: fingerprint(scene.pinned.iter().map(|&p| p as u64)),
            options: option_values(options, dense),
            carried: Carried::default(),
        }
    }

    /// The frame's second line.
    pub fn line(&self) -> String {
        let json = serde_json::to_string(self).expect("plain values serialise");
        format!("{RECORD_MARK}{json}")
    }

    /// What differs between the run that wrote this record and `other`
    /// (which run it is, and what carries over from step to step, aside),
    /// one phrase each: empty when `other` continues the same run.
    pub fn differences(&self, other: &RunRecord) -> Vec<String> {
        let mut differ = Vec::new();
        let mut compare = |what: &str, ours: String, theirs: String| {
            if ours != theirs {
                differ.push(format!("{what} (the frames': {ours}; now: {theirs})"));
            }
        };
        let recorded =
            |fingerprint: &Option<String>| fingerprint.clone().unwrap_or("not recorded".into());
        compare(
            "vertices",
            self.vertices.to_string(),
            other.vertices.to_string(),
        );
        compare("k", number(self.k), number(other.k));
        compare("Δt", number(self.delta_t), number(other.delta_t));
        compare(
            "the rest positions (the scene moved or reshaped)",
            recorded(&self.rest),
            recorded(&other.rest),
        );
        compare(
            "the springs",
            recorded(&self.springs),
            recorded(&other.springs),
        );
        compare("the masses", self.masses.clone(), other.masses.clone());
        compare("the pins", self.pins.clone(), other.pins.clone());
        let flags = self.options.keys().chain(other.options.keys());
        let flags: std::collections::BTreeSet<&String> = flags.collect();
        for flag in flags {
            let value = |options: &BTreeMap<String, String>| {
                options.get(flag).cloned().unwrap_or("not used".into())
            };
            compare(flag, value(&self.options), value(&other.options));
        }
        differ
    }
}

/// Refuses what carries over that no run carries (a record edited by
/// hand): a `ρ` outside `[0, 0.995]`, more plain iterations recorded than
/// the estimate takes, a ratio or a damping that is negative, not finite,
/// or beyond what the damping ever grows to.
///
/// # Errors
/// A sentence naming the value and its range.
pub fn check_carried(carried: &Carried) -> Result<(), String> {
    let chebyshev = &carried.chebyshev;
    if let Some(rho) = chebyshev.rho.filter(|&rho| !(0.0..=RHO_CAP).contains(&rho)) {
        return Err(format!(
            "Chebyshev's ρ = {} is outside [0, {RHO_CAP}]",
            number(rho)
        ));
    }
    if chebyshev.recorded > ESTIMATION_ITERATIONS {
        return Err(format!(
            "{} plain iterations recorded toward ρ, more than the {ESTIMATION_ITERATIONS} the \
             estimate takes",
            chebyshev.recorded
        ));
    }
    let ratio = chebyshev.largest_ratio;
    if !(ratio.is_finite() && ratio >= 0.0) {
        return Err(format!(
            "the largest ratio {} is not a finite number ≥ 0",
            number(ratio)
        ));
    }
    let damping = carried.newton_damping;
    let most = 10.0 * LARGEST_DAMPING;
    if !(damping.is_finite() && (0.0..=most).contains(&damping)) {
        return Err(format!(
            "Newton's damping {} is outside [0, {most:e}]",
            number(damping)
        ));
    }
    Ok(())
}

/// The flags that decide a step of `options`, each with its value (those
/// of another method or backend left out).
fn option_values(options: &SimulationOptions, dense: bool) -> BTreeMap<String, String> {
    let step = &options.step;
    let shown = |value: Option<f64>| value.map_or("none".to_string(), number);
    let accuracy = Accuracy::of(step).map_or("none", Accuracy::name);
    let mut values = vec![
        ("--method", step.method.name().to_string()),
        ("--accuracy", accuracy.to_string()),
        ("--iterations", step.iterations.to_string()),
        ("--tolerance", shown(step.tolerance)),
        ("--energy-tolerance", shown(step.energy_tolerance)),
        ("--at-least-plain", shown(step.at_least_plain)),
        ("--start", step.start.name().to_string()),
        ("--pins", format!("{:?}", options.pins).to_lowercase()),
        ("--wind", options.wind.to_string()),
        ("--dense", dense.to_string()),
        ("--textbook", options.textbook.to_string()),
    ];
    match step.method {
        StepMethod::Chebyshev => {
            values.push(("--rho", shown(step.rho)));
            values.push(("--relaxation", step.relaxation.to_string()));
        }
        StepMethod::Anderson | StepMethod::Lbfgs => {
            values.push(("--window", step.window.to_string()));
        }
        StepMethod::Plain | StepMethod::Newton => {}
    }
    if !dense {
        let supernodes = match options.supernodes {
            SupernodeMerging::Small => "small",
            SupernodeMerging::Fundamental => "fundamental",
            SupernodeMerging::Relaxed => "relaxed",
        };
        values.push(("--ordering", options.ordering.name().to_string()));
        values.push(("--factorization", options.factorization.name().to_string()));
        values.push(("--supernodes", supernodes.to_string()));
    }
    if options.kernels != Kernels::Native {
        // recorded only when given, so that earlier runs' records still match
        values.push(("--kernels", options.kernels.name().to_string()));
    }
    values
        .into_iter()
        .map(|(flag, value)| (flag.to_string(), value))
        .collect()
}

/// A frame read back.
#[derive(Debug)]
pub struct Frame {
    /// The scene's name on its first line.
    pub scene: String,
    pub step: usize,
    /// Digits after the point of rounded positions; `None`: exact.
    pub precision: Option<usize>,
    /// Its second line, when it has one.
    pub record: Option<RunRecord>,
    pub positions: Vec<[f64; 3]>,
}

/// The parts of a frame's `text`.
///
/// # Errors
/// A [`FileError`] saying what is wrong, on its line: a first line that is
/// not a frame's, a record that cannot be read (line 2), or the OBJ
/// reader's error.
pub fn parse_frame(text: &str) -> Result<Frame, FileError> {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or("");
    let (scene, step, precision) = parse_header(first).ok_or_else(|| {
        FileError::invalid(format!(
            "`{}` is not the first line of a masssprings frame",
            shorten(first)
        ))
        .at_line(1)
    })?;
    let record = match lines.next().and_then(|line| line.strip_prefix(RECORD_MARK)) {
        None => None,
        Some(json) => Some(serde_json::from_str(json).map_err(|e| {
            FileError::invalid(format!("the run's record cannot be read: {e}")).at_line(2)
        })?),
    };
    let mesh = parse_obj(text)?;
    Ok(Frame {
        scene,
        step,
        precision,
        record,
        positions: mesh.vertices,
    })
}

/// The first two lines of a frame: what tells one written by `simulate`
/// (and which run it is of) without reading its positions.
#[derive(Debug)]
pub struct Head {
    pub step: usize,
    /// Its run record, when its second line is one that reads.
    pub record: Option<RunRecord>,
}

/// The [`Head`] of a frame whose text starts with `start`, if its first
/// line is a frame's.
pub fn parse_head(start: &str) -> Option<Head> {
    let mut lines = start.lines();
    let (_, step, _) = parse_header(lines.next()?)?;
    let record = lines
        .next()
        .and_then(|line| line.strip_prefix(RECORD_MARK))
        .and_then(|json| serde_json::from_str(json).ok());
    Some(Head { step, record })
}

/// The scene, step and precision of a frame's first line.
fn parse_header(line: &str) -> Option<(String, usize, Option<usize>)> {
    let (scene, rest) = line.strip_prefix("# ")?.rsplit_once(FRAME_MARK)?;
    let (step, how) = rest.split_once(", ")?;
    let step = step.parse().ok()?;
    let precision = match how {
        "exact positions" => None,
        _ => Some(
            how.strip_prefix("positions rounded to ")?
                .strip_suffix(" digits after the point")?
                .parse()
                .ok()?,
        ),
    };
    Some((scene.to_string(), step, precision))
}

/// At most 80 characters of `line`, for a message.
fn shorten(line: &str) -> String {
    match line.char_indices().nth(80) {
        Some((end, _)) => format!("{}…", &line[..end]),
        None => line.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two vertices, one spring: `k`, the masses and the pins as given.
    fn scene(k: f64, masses: &[f64], pinned: &[usize]) -> Scene {
        Scene {
            name: "two".into(),
            vertices: vec![[0.0; 3], [1.0, 0.0, 0.0]],
            faces: Vec::new(),
            texture_coords: Vec::new(),
            face_texture_coords: Vec::new(),
            springs: vec![[0, 1]],
            masses: masses.to_vec(),
            pinned: pinned.to_vec(),
            k,
            texture: None,
            obj: None,
        }
    }

    #[test]
    fn a_frame_reads_back_its_header_record_and_positions() {
        let options = SimulationOptions::default();
        let mut record = RunRecord::new(&scene(500.0, &[1.0, 0.5], &[0]), &options, false);
        record.run = Some("masssprings-1-2".into());
        record.carried.chebyshev.rho = Some(0.995);
        let text = format!(
            "{}\n{}\nv 0.1 0.2 0.3\nv 1 2 3\n",
            header("net", 12, None),
            record.line()
        );
        let frame = parse_frame(&text).unwrap();
        assert_eq!((frame.scene.as_str(), frame.step), ("net", 12));
        assert_eq!(frame.precision, None);
        assert_eq!(frame.record, Some(record.clone()));
        assert_eq!(frame.positions, vec![[0.1, 0.2, 0.3], [1.0, 2.0, 3.0]]);
        let rounded = format!("{}\nv 0 0 0\n", header("a — b", 3, Some(9)));
        let frame = parse_frame(&rounded).unwrap();
        assert_eq!((frame.scene.as_str(), frame.precision), ("a — b", Some(9)));
        assert!(frame.record.is_none());
    }

    #[test]
    fn what_no_run_carries_is_refused() {
        let mut carried = Carried::default();
        assert!(check_carried(&carried).is_ok());
        carried.chebyshev.rho = Some(0.995);
        carried.newton_damping = 1e-6;
        assert!(check_carried(&carried).is_ok());
        for (rho, damping, recorded, ratio) in [
            (Some(2.0), 0.0, 0, 0.0),
            (Some(-0.5), 0.0, 0, 0.0),
            (Some(f64::NAN), 0.0, 0, 0.0),
            (None, -1.0, 0, 0.0),
            (None, f64::INFINITY, 0, 0.0),
            (None, 0.0, 21, 0.0),
            (None, 0.0, 0, f64::NAN),
        ] {
            carried.chebyshev.rho = rho;
            carried.newton_damping = damping;
            carried.chebyshev.recorded = recorded;
            carried.chebyshev.largest_ratio = ratio;
            assert!(check_carried(&carried).is_err(), "{carried:?}");
        }
    }

    #[test]
    fn records_name_what_differs() {
        let options = SimulationOptions::default();
        let ours = RunRecord::new(&scene(500.0, &[1.0, 0.5], &[0]), &options, false);
        assert!(ours.differences(&ours).is_empty());
        let mut chebyshev = options;
        chebyshev.step.method = StepMethod::Chebyshev;
        let theirs = RunRecord::new(&scene(1e308, &[1.0, 0.25], &[1]), &chebyshev, false);
        let differ = ours.differences(&theirs).join("; ");
        for what in ["k (the frames': 500; now: 1e308)", "the masses", "the pins"] {
            assert!(differ.contains(what), "{differ}");
        }
        let mut moved = scene(500.0, &[1.0, 0.5], &[0]);
        moved.vertices[1][1] += 5.0;
        let rest = ours.differences(&RunRecord::new(&moved, &options, false));
        assert_eq!(rest.len(), 1, "{rest:?}");
        assert!(
            rest[0].starts_with("the rest positions (the scene moved"),
            "{rest:?}"
        );
        let mut other_run = ours.clone();
        other_run.run = Some("masssprings-3-4".into());
        assert!(
            ours.differences(&other_run).is_empty(),
            "which run is not a setting"
        );
        assert!(differ.contains("--method (the frames': plain; now: chebyshev)"));
        assert!(differ.contains("--rho (the frames': not used; now: none)"));
    }

    #[test]
    fn anything_that_is_not_a_frame_is_named_with_its_line() {
        for (text, line) in [
            ("", 1),
            ("v 0 0 0\n", 1),
            ("# net — masssprings frame, step -1, exact positions\n", 1),
            (
                "# net — masssprings frame, step 99999999999999999999999, exact positions\n",
                1,
            ),
            (
                "# n — masssprings frame, step 1, exact positions\n# masssprings run {",
                2,
            ),
            (
                "# n — masssprings frame, step 1, exact positions\nv 0 x 0\n",
                2,
            ),
        ] {
            let error = parse_frame(text).unwrap_err();
            assert_eq!(error.line(), Some(line), "{text:?}: {error}");
        }
        assert_eq!(frame_step("frame-000012.obj"), Some(12));
        assert_eq!(numbered_obj("frame-000012.obj"), Some(("frame-", 12)));
        assert_eq!(numbered_obj("7.obj"), Some(("", 7)));
        assert_eq!(numbered_obj("cloth.obj"), None);
        assert_eq!(numbered_obj("cloth12.png"), None);
        assert_eq!(frame_step("frame-12.obj"), None);
        assert_eq!(frame_step("frame-99999999999999999999999.obj"), None);
    }
}
