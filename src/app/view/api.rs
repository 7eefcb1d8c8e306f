//! What the page and the server say to each other, besides the static files:
//!
//! | endpoint | answer |
//! |---|---|
//! | `GET /api/scene` | JSON [`DisplayMesh`](super::display_mesh::DisplayMesh): triangles, springs, pins, texture coordinates (once per scene: again when `scene_serial` changes) |
//! | `GET /api/frame[?since=S]` | binary [`Frame`]: the positions (of both simulations when comparing); `204` when serial `S` is still the latest |
//! | `GET /api/status` | JSON [`Status`]: steps, time, toggles, parameters, timings, the last steps' convergence and energies, the step in progress |
//! | `GET /api/image?…` | PNG: the frame drawn by the crate's own renderer, for a page without WebGL (`image.rs`) |
//! | `POST /api/command` | JSON [`Command`] in; the new [`Status`] out (`409` with `{"error"}` when refused; `202` when it waits for the step in progress, after which it is applied) |

use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// Steps kept in [`Status::history`] for the page's convergence plot.
pub const HISTORY_LENGTH: usize = 150;

/// A command of the page, as JSON: `{"command": "step"}`,
/// `{"command": "drag_start", "vertex": 12, "target": [x, y, z]}`.
///
/// The variants without data are written `Step {}` rather than `Step`:
/// serde refuses unknown fields only in struct variants, and a command with
/// a field it does not know is refused as a whole.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "command", rename_all = "snake_case", deny_unknown_fields)]
pub enum Command {
    /// Space: pause, then advance exactly one step.
    Step {},
    /// A: start or stop the real-time animation.
    ToggleAnimation {},
    /// L: show or hide the springs and point masses.
    ToggleSprings {},
    /// R: back to the state at load, paused: the rest shape, time 0, and
    /// the command line's settings (the scene's k, Δt and masses, wind,
    /// the first simulation's budget and rules as its solver has them).
    Reset {},
    /// Shift-R: back to the rest shape, time 0, every setting kept.
    Restart {},
    /// W: wind on or off.
    ToggleWind {},
    /// Start dragging `vertex` (0-based) toward `target`.
    DragStart { vertex: usize, target: [f64; 3] },
    /// Move the dragged vertex's target.
    DragTo { target: [f64; 3] },
    /// Let go.
    DragEnd {},
    /// New parameters: stiffness, time step, the factor on the scene's
    /// masses (these three change `Q`, which is refactored) and the
    /// local/global iterations per step.
    SetParameters {
        k: f64,
        delta_t: f64,
        mass_scale: f64,
        iterations: usize,
    },
    /// Switch to scene `scene` of [`Status::scenes`] (paused, at rest).
    LoadScene { scene: usize },
    /// Solve later steps by `method` (one of [`Status::methods`]), stopping
    /// at relative gradient `tolerance` (`null`: run every iteration) or
    /// at `energy_tolerance` (see `--energy-tolerance`; `null` or absent:
    /// no such rule), held back by `at_least_plain` (see
    /// `--at-least-plain`; `null` or absent: no floor). Nothing is
    /// refactored: every method uses the same `Q`. `start` (`current` or
    /// `inertial`, see `--start`) is kept when absent; so are the budget,
    /// the history window and, while the method stays, how it runs
    /// (L-BFGS's plain iterations first).
    SetMethod {
        method: String,
        tolerance: Option<f64>,
        #[serde(default)]
        energy_tolerance: Option<f64>,
        #[serde(default)]
        at_least_plain: Option<f64>,
        #[serde(default)]
        start: Option<String>,
    },
    /// Solve later steps by `solver` (one of [`Status::solvers`]: the
    /// assignment, the handout's code, the assignment's accuracy fast), as
    /// the command line's `--textbook` and `--accuracy` do, on `backend`
    /// (`sparse` or `dense`; absent: the viewer's). The simulation is
    /// precomputed again and goes on from where it is.
    SetSolver {
        solver: String,
        #[serde(default)]
        backend: Option<String>,
    },
    /// Run a second simulation of the scene beside the first, from where
    /// the first is, solved by `with` (a solver, or `converged`; `null`:
    /// stop comparing) on `backend`. Every later command acts on both,
    /// but the method, the solver and the iterations, which are the
    /// first's.
    Compare {
        with: Option<String>,
        #[serde(default)]
        backend: Option<String>,
    },
    /// Stop the step in progress between two iterations (the simulation
    /// stays at its last completed step), and the steps of commands sent
    /// before this one; pause.
    Cancel {},
}

impl Command {
    /// The command's name, as the page sends it.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Step {} => "step",
            Command::ToggleAnimation {} => "toggle_animation",
            Command::ToggleSprings {} => "toggle_springs",
            Command::Reset {} => "reset",
            Command::Restart {} => "restart",
            Command::ToggleWind {} => "toggle_wind",
            Command::DragStart { .. } => "drag_start",
            Command::DragTo { .. } => "drag_to",
            Command::DragEnd {} => "drag_end",
            Command::SetParameters { .. } => "set_parameters",
            Command::LoadScene { .. } => "load_scene",
            Command::SetMethod { .. } => "set_method",
            Command::SetSolver { .. } => "set_solver",
            Command::Compare { .. } => "compare",
            Command::Cancel {} => "cancel",
        }
    }

    /// Parses a command from the body of `POST /api/command`: one JSON
    /// object (serde would also take `["step"]`, which the page never sends).
    ///
    /// # Errors
    /// What is wrong with the body, for the `400` answer.
    pub fn from_json(body: &[u8]) -> Result<Command, String> {
        let value: serde_json::Value = serde_json::from_slice(body).map_err(|e| e.to_string())?;
        if !value.is_object() {
            return Err("a command is a JSON object such as {\"command\": \"step\"}".into());
        }
        serde_json::from_value(value).map_err(|e| e.to_string())
    }
}

/// The viewer's state, as `/api/status` and `/api/command` send it.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Status {
    /// The scene's name.
    pub scene: String,
    /// `"dense"` or `"sparse"`.
    pub backend: &'static str,
    /// Vertices.
    pub n: usize,
    /// Springs.
    pub springs: usize,
    /// Steps since the start or the last reset.
    pub steps: usize,
    /// Simulated time, in seconds: the sum of every step's own Δt.
    pub time: f64,
    pub animating: bool,
    pub wind: bool,
    /// Are springs and point masses drawn (key L)?
    pub show_springs: bool,
    /// Moving average of the time one step takes, in milliseconds.
    pub ms_per_step: f64,
    /// Steps over the last second (0 while paused).
    pub steps_per_second: f64,
    /// The vertex being dragged (0-based).
    pub dragged: Option<usize>,
    /// Why the animation stopped, if a step failed.
    pub error: Option<String>,
    /// Is a page showing the simulation (it asked for a frame within the
    /// last second)? The simulation runs only while `animating && watched`.
    pub watched: bool,
    /// Pages that asked for a frame within the last second.
    pub pages: usize,
    /// Spring stiffness `k`.
    pub k: f64,
    /// Time step `Δt`, seconds.
    pub delta_t: f64,
    /// The factor on the scene's masses.
    pub mass_scale: f64,
    /// The most iterations a step may take.
    pub iterations: usize,
    /// How each step is solved, and the methods there are.
    pub method: &'static str,
    pub methods: Vec<&'static str>,
    /// The solver the options are (`assignment`, `textbook`,
    /// `accuracy-assignment`), or `null` for another method or rules; the
    /// solvers there are; and which path and functions run a step.
    pub solver: Option<&'static str>,
    pub solvers: Vec<&'static str>,
    pub functions: String,
    /// Does L-BFGS start each step with plain iterations (as
    /// `--accuracy assignment` does)?
    pub plain_first: bool,
    /// The step or work in progress, and since when (milliseconds): filled
    /// in when the status is sent, so a page sees it during a long step.
    pub busy: Option<String>,
    pub busy_ms: Option<f64>,
    /// Commands waiting for the simulation thread.
    pub queued: usize,
    /// What happened that is not an error: a step cancelled, a command
    /// that waited for a step and was then refused (with why).
    pub note: Option<String>,
    /// The mechanical energy now (`Simulation::mechanical_energy`).
    pub energy: f64,
    /// The second simulation, when comparing.
    pub compare: Option<Compared>,
    /// The relative gradient a step stops at (`None`: every iteration).
    pub tolerance: Option<f64>,
    /// The energy tolerance (`--energy-tolerance`), if any.
    pub energy_tolerance: Option<f64>,
    /// The floor of `--at-least-plain`, if any.
    pub at_least_plain: Option<f64>,
    /// Where a step's iterations start (`current` or `inertial`).
    pub start: &'static str,
    /// How long the last rebuild and refactorization of `Q` took
    /// (milliseconds), after a parameter change or a drag; `None` before any.
    pub refactor_ms: Option<f64>,
    /// What the dense path would take for the scene shown (the memory
    /// rule's estimate, in words), and whether the rule allows it.
    pub dense_memory: String,
    pub dense_fits: bool,
    /// The frames given with `--frames`, when there are any.
    pub frames: Option<FramesGiven>,
    /// The scenes the page can switch to (names), and the one shown.
    pub scenes: Vec<String>,
    pub scene_index: usize,
    /// Changes whenever another scene is loaded: fetch `/api/scene` again.
    pub scene_serial: u32,
    /// The last steps, oldest first, for the convergence plot.
    pub history: VecDeque<StepRecord>,
}

/// The second simulation of a comparison.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Compared {
    /// Its solver (or `converged`; `null`: another method), backend,
    /// method and path, as for the first.
    pub solver: Option<&'static str>,
    pub backend: &'static str,
    pub method: &'static str,
    pub functions: String,
    /// Moving average of its step's time, milliseconds.
    pub ms_per_step: f64,
    pub iterations: usize,
    /// Its mechanical energy now.
    pub energy: f64,
    /// Has it run out of frames (a recording, `--frames`)?
    pub ended: bool,
    /// Its last steps, oldest first.
    pub history: VecDeque<StepRecord>,
}

/// The frames of `--frames`.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FramesGiven {
    /// The folder, as given.
    pub folder: String,
    /// Steps they hold (frames after the first, at rest).
    pub steps: usize,
    /// The scene they are of (the first of [`Status::scenes`]).
    pub scene: String,
}

/// What one step did, for the convergence plot.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct StepRecord {
    /// The step's number (since the start or the last reset).
    pub step: usize,
    /// Local/global iterations run.
    pub iterations: usize,
    /// `E(p⁰) − E(p)`: the energy the step took off (`null` when the step
    /// did not measure it: the textbook path).
    pub energy_decrease: Option<f64>,
    /// `‖∇E(p)‖ / ‖∇E(p⁰)‖` over the free vertices where the step stopped
    /// (`null` when not measured).
    pub relative_gradient: Option<f64>,
    /// Did the step stop on the tolerance (rather than on its iteration
    /// budget or a stalled line search)?
    pub converged: bool,
    /// Why it stopped: `iterations` (its budget), `tolerance`,
    /// `energy-tolerance`, `at-least-plain`, `stalled` (`Stop::name`).
    pub stop: &'static str,
    /// The mechanical energy after the step.
    pub energy: f64,
    /// How long the step took, milliseconds.
    pub ms: f64,
    /// In a comparison's history: the largest distance between a vertex
    /// of the two after the step (`null` elsewhere, and once a recording
    /// has run out of frames).
    pub distance: Option<f64>,
}

/// The latest positions, encoded once per step for every client:
///
/// ```text
/// offset  0  u32  n, the number of vertices
///         4  u32  serial: changes whenever the positions do
///         8  u32  steps (saturating)
///        12  f32  simulated time, seconds
///        16  f32 × 3n  x0 y0 z0 x1 y1 z1 …
///  16 + 12n  f32 × 3n  the second simulation's, when comparing
/// ```
///
/// All little-endian. The positions start at a multiple of 4 bytes, so the
/// page can view them as a `Float32Array` without copying.
#[derive(Debug)]
pub struct Frame {
    bytes: Vec<u8>,
    serial: u32,
}

/// Bytes before the positions.
pub const FRAME_HEADER_BYTES: usize = 16;

impl Frame {
    /// A frame for `sets` sets of `n` vertices (2 when comparing), all at
    /// the origin, serial 0.
    pub fn new(n: usize, sets: usize) -> Self {
        let mut frame = Frame {
            bytes: vec![0; FRAME_HEADER_BYTES + 12 * n * sets],
            serial: 0,
        };
        frame.bytes[..4].copy_from_slice(&(n as u32).to_le_bytes());
        frame
    }

    /// Overwrites the positions in place (no allocation) and moves the
    /// serial on.
    ///
    /// # Panics
    /// When the sets of `positions` are not as long as the frame was
    /// made for.
    pub fn write(&mut self, positions: &[&[[f64; 3]]], steps: usize, time: f64) {
        let values: usize = positions.iter().map(|set| 3 * set.len()).sum();
        assert_eq!(4 * values, self.bytes.len() - FRAME_HEADER_BYTES);
        self.serial = self.serial.wrapping_add(1);
        let steps = u32::try_from(steps).unwrap_or(u32::MAX);
        self.bytes[4..8].copy_from_slice(&self.serial.to_le_bytes());
        self.bytes[8..12].copy_from_slice(&steps.to_le_bytes());
        self.bytes[12..16].copy_from_slice(&(time as f32).to_le_bytes());
        let floats = positions.iter().flat_map(|set| set.iter().flatten());
        for (slot, &value) in self.bytes[FRAME_HEADER_BYTES..]
            .chunks_exact_mut(4)
            .zip(floats)
        {
            slot.copy_from_slice(&(value as f32).to_le_bytes());
        }
    }

    /// Changes whenever the positions do.
    pub fn serial(&self) -> u32 {
        self.serial
    }

    /// Sizes the frame for `sets` sets of `n` vertices (all at the
    /// origin until written), keeping its serial: a page that asks for the
    /// frame after serial `S` must never be told that `S` is the latest of
    /// another shape.
    pub fn reshape(&mut self, n: usize, sets: usize) {
        let serial = self.serial;
        *self = Frame::new(n, sets);
        self.serial = serial;
    }

    /// The encoded frame.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// The positions of set `set` (0: the first simulation), as `f64`.
    pub fn positions(&self, set: usize) -> Option<Vec<[f64; 3]>> {
        let n = u32::from_le_bytes(self.bytes[..4].try_into().expect("4 bytes")) as usize;
        let start = FRAME_HEADER_BYTES + 12 * n * set;
        let floats = self.bytes.get(start..start + 12 * n)?;
        let float = |at: &[u8]| f64::from(f32::from_le_bytes(at.try_into().expect("4 bytes")));
        let points = floats.chunks_exact(12);
        Some(
            points
                .map(|p| [float(&p[..4]), float(&p[4..8]), float(&p[8..])])
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_parse_from_the_pages_json() {
        let parse = |text: &str| Command::from_json(text.as_bytes());
        assert_eq!(parse(r#"{"command":"step"}"#).unwrap(), Command::Step {});
        assert!(parse(r#"{"command":"step","x":1}"#).is_err());
        assert_eq!(
            parse(r#"{"command":"drag_start","vertex":3,"target":[1,2,3]}"#).unwrap(),
            Command::DragStart {
                vertex: 3,
                target: [1.0, 2.0, 3.0]
            }
        );
        assert!(parse(r#"{"command":"explode"}"#).is_err());
        assert!(parse(r#"["step"]"#).is_err());
        assert!(parse(r#"{"command":"drag_to","target":[1,2]}"#).is_err());
        assert!(parse(r#"{"command":"drag_to","target":[1,2,3],"x":1}"#).is_err());
        assert!(parse(r#"{"command":"drag_start","vertex":-1,"target":[1,2,3]}"#).is_err());
        assert_eq!(
            parse(
                r#"{"command":"set_parameters","k":1,"delta_t":0.1,"mass_scale":2,"iterations":5}"#
            )
            .unwrap(),
            Command::SetParameters {
                k: 1.0,
                delta_t: 0.1,
                mass_scale: 2.0,
                iterations: 5
            }
        );
        assert!(parse(r#"{"command":"set_parameters","k":1}"#).is_err());
        assert_eq!(
            parse(r#"{"command":"set_method","method":"lbfgs","tolerance":null}"#).unwrap(),
            Command::SetMethod {
                method: "lbfgs".into(),
                tolerance: None,
                energy_tolerance: None,
                at_least_plain: None,
                start: None
            }
        );
        assert_eq!(
            parse(
                r#"{"command":"set_method","method":"plain","tolerance":0.5,"energy_tolerance":0.1,"at_least_plain":50,"start":"inertial"}"#
            )
            .unwrap(),
            Command::SetMethod {
                method: "plain".into(),
                tolerance: Some(0.5),
                energy_tolerance: Some(0.1),
                at_least_plain: Some(50.0),
                start: Some("inertial".into())
            }
        );
        assert_eq!(
            parse(r#"{"command":"load_scene","scene":2}"#).unwrap(),
            Command::LoadScene { scene: 2 }
        );
    }

    #[test]
    fn the_solving_commands_parse_from_the_pages_json() {
        let parse = |text: &str| Command::from_json(text.as_bytes());
        assert_eq!(
            parse(r#"{"command":"set_solver","solver":"textbook","backend":"dense"}"#).unwrap(),
            Command::SetSolver {
                solver: "textbook".into(),
                backend: Some("dense".into())
            }
        );
        assert_eq!(
            parse(r#"{"command":"compare","with":null}"#).unwrap(),
            Command::Compare {
                with: None,
                backend: None
            }
        );
        assert_eq!(
            parse(r#"{"command":"cancel"}"#).unwrap(),
            Command::Cancel {}
        );
        assert!(parse(r#"{"command":"cancel","now":true}"#).is_err());
        assert_eq!(Command::Cancel {}.name(), "cancel");
    }

    #[test]
    fn a_frame_is_a_header_and_little_endian_floats() {
        let mut frame = Frame::new(2, 1);
        frame.write(&[&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]], 7, 0.5);
        let bytes = frame.bytes();
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        let float = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        assert_eq!((word(0), word(4), word(8), float(12)), (2, 1, 7, 0.5));
        let positions: Vec<f32> = (0..6).map(|i| float(16 + 4 * i)).collect();
        assert_eq!(positions, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(frame.serial(), 1);
        assert_eq!(frame.positions(0).unwrap()[1], [4.0, 5.0, 6.0]);
        assert_eq!(frame.positions(1), None);
        let mut two = Frame::new(1, 2);
        two.write(&[&[[1.0, 2.0, 3.0]], &[[4.0, 5.0, 6.0]]], 1, 0.0);
        assert_eq!(two.positions(1).unwrap(), [[4.0, 5.0, 6.0]]);
    }
}
