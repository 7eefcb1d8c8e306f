//! The simulation thread: it owns the simulation (two, when comparing
//! solvers), steps it in real time (one step of Δt every Δt while
//! animating and a page is watching, see [`super::watchers`]), applies the
//! page's commands between steps ([`super::commands`]), and publishes what
//! the HTTP threads serve.
//!
//! ```text
//!  HTTP threads ──Message::Command──▶ simulation thread ──▶ Shared.frame  (positions, f32)
//!               ◀──reply (Ok/Err)────                   └─▶ Shared.status (steps, time, …)
//!  HTTP threads ──Shared.cancel (set)──▶ the step in progress stops between two iterations
//! ```
//!
//! Only this thread touches the simulations, so they need no lock; the
//! HTTP threads read the published copies under short-lived mutexes, and
//! during a long step they see it in [`Shared::busy`] and can stop it
//! through [`Shared::cancel`], which every simulation's step looks at
//! between its iterations (`Simulation::set_cancel`). A command that
//! arrives during a step waits for it (the page is answered at once that
//! it waits, [`super::routes`]) and is applied after it.

use super::api::{Command, Frame, FramesGiven, Status, HISTORY_LENGTH};
use super::display_mesh::display_mesh;
use super::recording::{Frames, RECORDING};
use super::rules::DragReach;
use super::solver::{self, Backend, Run};
use super::watchers::Watchers;
use crate::app::draw::texture::{read_png_file, Texture};
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::StepMethod;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

pub use super::rules::MAX_ITERATIONS;

/// The scene's PNG texture, read from the path the scene names; `None`
/// (with a warning) when it cannot be read or is not a PNG.
fn read_texture(scene: &Scene) -> Option<Vec<u8>> {
    let path = scene.texture.as_ref()?;
    match read_png_file(path) {
        Ok(bytes) => Some(bytes),
        Err(error) => {
            eprintln!("masssprings: warning: {error}; drawing without texture");
            None
        }
    }
}

/// How often the thread looks again whether a page has come back, while
/// animating with nobody watching.
const WATCH_POLL: Duration = Duration::from_millis(100);

/// What the HTTP threads publish and read.
pub struct Shared {
    /// The latest positions, encoded as `/api/frame` sends them.
    pub frame: Mutex<Frame>,
    /// The latest state, as `/api/status` sends it.
    pub status: Mutex<Status>,
    /// The scene shown: `/api/scene`, the texture, what `/api/image` draws.
    pub scene: Mutex<SceneAssets>,
    /// The pages that asked for frames lately.
    pub watchers: Mutex<Watchers>,
    /// Once set, the step in progress stops between two iterations
    /// (`Command::Cancel`, or the viewer stopping); the simulation thread
    /// clears it when it takes the cancel command.
    pub cancel: Arc<AtomicBool>,
    /// The work in progress (a step, a precomputation), if any.
    pub busy: Mutex<Option<Busy>>,
    /// Commands sent to the simulation thread and not yet taken.
    pub queued: AtomicUsize,
    /// Held while `/api/image` draws (one image at a time).
    pub drawing: Mutex<()>,
}

impl Shared {
    /// `mutex`, locked (no thread panics holding one of these).
    pub fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
        mutex.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Work in progress on the simulation thread.
#[derive(Debug, Clone)]
pub struct Busy {
    /// What: `step 12`, `precomputing the skirt`.
    pub what: String,
    pub since: Instant,
    /// How long such work took lately (a step: the time per step), when
    /// known: whether a command sent meanwhile waits for its end or is
    /// told at once that it waits (`routes`).
    pub expected: Option<Duration>,
}

/// What the page loads once per scene, and what the fallback renderer
/// draws with.
pub struct SceneAssets {
    /// `/api/scene`: the [`super::display_mesh::DisplayMesh`] as JSON.
    pub json: Arc<str>,
    /// `/texture.png`, when the scene has one that could be read.
    pub texture: Option<Arc<[u8]>>,
    /// The scene itself and its decoded texture (`/api/image`).
    pub scene: Arc<Scene>,
    pub decoded: Option<Arc<Texture>>,
}

impl SceneAssets {
    /// The display mesh and texture of `scene` on backend `backend`.
    pub fn of(scene: &Scene, backend: &'static str) -> SceneAssets {
        let texture = read_texture(scene);
        let mesh = display_mesh(scene, texture.is_some(), backend);
        let decoded = texture.as_ref().and_then(|bytes| {
            let cursor = std::io::Cursor::new(bytes.as_slice());
            Texture::decode_png(cursor, masssprings::memory::limit()).ok()
        });
        SceneAssets {
            json: serde_json::to_string(&mesh)
                .expect("plain data serialises")
                .into(),
            texture: texture.map(Into::into),
            scene: Arc::new(scene.clone()),
            decoded: decoded.map(Arc::new),
        }
    }
}

/// The answer to a command: `Err` carries the reason it was refused.
pub type Reply = Result<(), String>;

/// What the simulation thread receives.
pub enum Message {
    /// A command from the page, where to send the answer (the page may
    /// have been told already that it waits, and no longer listens), and a
    /// flag the thread sets when it takes the command.
    Command(Command, Sender<Reply>, Arc<AtomicBool>),
    /// Stop the thread (the program is shutting down).
    Quit,
}

/// One simulation shown: how it runs, on which backend, and how long its
/// steps take.
pub struct Shown {
    pub run: Box<dyn Run>,
    pub backend: Backend,
    /// Moving average of its step's time, milliseconds.
    pub ms_per_step: f64,
    /// Its state before the step in progress, kept while comparing, so
    /// that a step the other simulation could not finish is undone too.
    pub saved: Option<Saved>,
}

/// A state to go back to.
pub struct Saved {
    pub previous: Vec<[f64; 3]>,
    pub current: Vec<[f64; 3]>,
    pub steps: usize,
    pub time: f64,
}

impl Shown {
    pub fn new(run: Box<dyn Run>, backend: Backend) -> Shown {
        Shown {
            run,
            backend,
            ms_per_step: 0.0,
            saved: None,
        }
    }

    /// Counts one step that took `duration` in the moving average (about
    /// the last 10 steps).
    pub fn record_time(&mut self, duration: Duration) {
        let ms = 1e3 * duration.as_secs_f64();
        self.ms_per_step = match self.ms_per_step {
            0.0 => ms,
            average => 0.9 * average + 0.1 * ms,
        };
    }
}

/// The steps counted over the last second, for the overlay.
pub struct StepRate {
    window_start: Instant,
    window_steps: u32,
    pub steps_per_second: f64,
}

impl StepRate {
    pub fn new() -> Self {
        StepRate {
            window_start: Instant::now(),
            window_steps: 0,
            steps_per_second: 0.0,
        }
    }

    /// Counts one step.
    pub fn record(&mut self) {
        self.window_steps += 1;
        let elapsed = self.window_start.elapsed().as_secs_f64();
        if elapsed >= 1.0 {
            self.steps_per_second = f64::from(self.window_steps) / elapsed;
            self.window_start = Instant::now();
            self.window_steps = 0;
        }
    }

    /// Starts counting afresh, from 0 (when the animation starts or stops).
    pub fn restart(&mut self) {
        *self = StepRate::new();
    }
}

/// The simulations and the viewer state around them.
pub struct SimulationThread {
    pub(super) main: Shown,
    /// The second simulation, when comparing.
    pub(super) second: Option<Shown>,
    pub(super) scene: Arc<Scene>,
    pub(super) shared: Arc<Shared>,
    pub(super) animating: bool,
    pub(super) show_springs: bool,
    /// When the next real-time step is due.
    pub(super) next_step_at: Instant,
    pub(super) rate: StepRate,
    /// Why the animation stopped, when a step failed.
    pub(super) error: Option<String>,
    /// What happened that is not an error (a step cancelled, …).
    pub(super) note: Option<String>,
    /// Where a drag target may lie.
    pub(super) drag_reach: DragReach,
    /// The scene files the page may switch to, and the one shown.
    pub(super) scenes: Vec<PathBuf>,
    pub(super) scene_index: usize,
    /// The time the last rebuild and refactorization of `Q` took.
    pub(super) refactor: Option<Duration>,
    /// The backend of the command line, for the solvers without their own.
    pub(super) default_backend: Backend,
    /// The options of the command line: what reset returns to.
    pub(super) initial: SimulationOptions,
    /// A program's frames of the first scene (`--frames`), to compare with.
    pub(super) frames: Option<Arc<Frames>>,
}

/// What [`SimulationThread::new`] starts from.
pub struct Start {
    pub main: Shown,
    pub scene: Scene,
    pub scenes: Vec<PathBuf>,
    pub scene_index: usize,
    /// The command line's options.
    pub initial: SimulationOptions,
    /// `--frames`: shown beside the simulation from the start.
    pub frames: Option<Arc<Frames>>,
}

impl SimulationThread {
    /// Wraps the simulation of `start` (paused at rest; a cloth without
    /// its springs shown) and publishes its first frame.
    pub fn new(start: Start, shared: Arc<Shared>) -> Self {
        let drag_reach = DragReach::of(start.main.run.rest_positions());
        let show_springs = start.scene.faces.first().is_none_or(|face| face.len() < 3);
        let default_backend = start.main.backend;
        let mut thread = SimulationThread {
            main: start.main,
            second: None,
            scene: Arc::new(start.scene),
            shared,
            animating: false,
            show_springs,
            next_step_at: Instant::now(),
            rate: StepRate::new(),
            error: None,
            note: None,
            drag_reach,
            scenes: start.scenes,
            scene_index: start.scene_index,
            refactor: None,
            default_backend,
            initial: start.initial,
            frames: start.frames,
        };
        thread.publish_frame();
        thread.publish_scene_list();
        thread.publish_dense_need();
        if thread.frames.is_some() {
            if let Err(why) = thread.compare(Some(RECORDING), None) {
                thread.error = Some(why);
            }
        }
        thread.publish_status();
        thread
    }

    /// Is a page showing the simulation?
    fn watched(&self) -> bool {
        Shared::lock(&self.shared.watchers).count() > 0
    }

    /// Steps are due: animating, a page watching, and the time has come.
    fn running(&self) -> bool {
        self.animating && self.watched()
    }

    /// Runs until [`Message::Quit`] (or until every sender is gone).
    pub fn run(mut self, inbox: Receiver<Message>) {
        loop {
            let running = self.running();
            if running && Instant::now() >= self.next_step_at {
                self.real_time_step();
            } else if !running {
                // Paused, or nobody watching: no step is due; keep the
                // status's page count fresh, and start afresh when a page
                // comes back.
                self.next_step_at = Instant::now();
                self.publish_status();
            }
            let wait = if running {
                self.next_step_at.saturating_duration_since(Instant::now())
            } else {
                WATCH_POLL
            };
            let message = match inbox.recv_timeout(wait) {
                Ok(message) => message,
                Err(RecvTimeoutError::Timeout) => continue,
                Err(RecvTimeoutError::Disconnected) => return,
            };
            match message {
                Message::Quit => return,
                Message::Command(command, reply, taken) => {
                    taken.store(true, Ordering::SeqCst);
                    self.answer(command, &reply);
                }
            }
        }
    }

    /// Applies `command` and answers it; a page no longer waiting for the
    /// answer (it was told the command waits for a step) finds a refusal
    /// in the status's note.
    fn answer(&mut self, command: Command, reply: &Sender<Reply>) {
        self.shared.queued.fetch_sub(1, Ordering::SeqCst);
        let name = command.name();
        let result = self.apply(command);
        self.publish_status(); // before the answer, which sends the status
        if let Err(why) = &result {
            // Gone: the page was told the command waits; say why it failed.
            if reply.send(result.clone()).is_err() && self.note.as_deref() != Some(why) {
                self.note = Some(format!("{name}, sent during a step: refused: {why}"));
                self.publish_status();
            }
        } else {
            let _ = reply.send(result);
        }
    }

    /// The step due now; the next one is due Δt later. When steps take
    /// longer than Δt the animation slows down rather than piling up.
    fn real_time_step(&mut self) {
        let _ = self.step_once();
        let period = Duration::from_secs_f64(self.main.run.options().delta_t);
        self.next_step_at = (self.next_step_at + period).max(Instant::now());
        self.publish_status();
    }

    /// Every simulation shown: the first, then the second when comparing.
    pub(super) fn all_mut(&mut self) -> impl Iterator<Item = &mut Shown> {
        std::iter::once(&mut self.main).chain(self.second.as_mut())
    }

    /// Says what the thread is busy with (until [`Self::done`]), and how
    /// long such work takes, when known.
    pub(super) fn busy(&self, what: String, expected: Option<Duration>) {
        *Shared::lock(&self.shared.busy) = Some(Busy {
            what,
            since: Instant::now(),
            expected,
        });
    }

    pub(super) fn done(&self) {
        *Shared::lock(&self.shared.busy) = None;
    }

    pub(super) fn set_animating(&mut self, animating: bool) {
        if animating && !self.animating {
            self.next_step_at = Instant::now();
        }
        self.animating = animating;
        self.rate.restart();
    }

    /// The scene names the page lists, once.
    fn publish_scene_list(&self) {
        let mut status = Shared::lock(&self.shared.status);
        status.scenes = self.scenes.iter().map(|path| scene_name(path)).collect();
        status.methods = StepMethod::ALL.map(StepMethod::name).to_vec();
        status.solvers = solver::solver_names();
        status.history.reserve(HISTORY_LENGTH);
        status.frames = self.frames.as_ref().map(|frames| FramesGiven {
            folder: frames.folder.display().to_string(),
            steps: frames.positions.len() - 1,
            scene: scene_name(&self.scenes[0]),
        });
    }
}

/// The name the page shows for a scene file: its stem (`flag`).
pub fn scene_name(path: &std::path::Path) -> String {
    path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}
