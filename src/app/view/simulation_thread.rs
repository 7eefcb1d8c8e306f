//! The simulation thread: it owns the [`Simulation`], steps it in real time
//! (one step of Δt every Δt while animating and a page is watching, see
//! [`super::watchers`]), applies the page's commands between steps (keys,
//! drags, new parameters, another scene), and publishes what the HTTP
//! threads serve.
//!
//! ```text
//!  HTTP threads ──Message::Command──▶ simulation thread ──▶ Shared.frame  (positions, f32)
//!               ◀──reply (Ok/Err)────                   └─▶ Shared.status (steps, time, …)
//! ```
//!
//! Only this thread touches the simulation, so it needs no lock; the HTTP
//! threads read the published copies under two short-lived mutexes. A step
//! allocates nothing here either: the positions are written into the frame
//! buffer in place.

use super::api::{Command, Frame, Status, StepRecord, HISTORY_LENGTH};
use super::display_mesh::display_mesh;
use super::watchers::Watchers;
use crate::app::error::AppError;
use masssprings::mesh::bounding_box::BoundingBox;
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{LinearAlgebra, Simulation, StepMethod, StepReport, Stop};
use masssprings::sim::{Start, StepControl};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The most iterations a step of the viewer may take, from the command line
/// as from the page: a step must end within moments for the viewer to
/// answer and to stop.
pub const MAX_ITERATIONS: usize = 1000;

/// The scene's PNG texture, read from the path the scene names; `None`
/// (with a warning) when it cannot be read or is not a PNG.
fn read_texture(scene: &Scene) -> Option<Vec<u8>> {
    let path = scene.texture.as_ref()?;
    match crate::app::draw::texture::read_png_file(path) {
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
    /// The scene shown: `/api/scene` and the texture.
    pub scene: Mutex<SceneAssets>,
    /// The pages that asked for frames lately.
    pub watchers: Mutex<Watchers>,
}

/// What the page loads once per scene.
pub struct SceneAssets {
    /// `/api/scene`: the [`super::display_mesh::DisplayMesh`] as JSON.
    pub json: Arc<str>,
    /// `/texture.png`, when the scene has one that could be read.
    pub texture: Option<Arc<[u8]>>,
}

impl SceneAssets {
    /// The display mesh and texture of `scene` on backend `backend`.
    pub fn of(scene: &Scene, backend: &'static str) -> SceneAssets {
        let texture = read_texture(scene);
        let mesh = display_mesh(scene, texture.is_some(), backend);
        SceneAssets {
            json: serde_json::to_string(&mesh)
                .expect("plain data serialises")
                .into(),
            texture: texture.map(Into::into),
        }
    }
}

/// The answer to a command: `Err` carries the reason it was refused.
pub type Reply = Result<(), String>;

/// A command's fate, decided once: either the simulation thread takes it
/// (and applies and answers it), or the connection waiting for it gives up
/// first (and answers that it was not applied). So a command answered "not
/// applied" is never applied later, and one that is applied is answered.
#[derive(Debug, Default)]
pub struct Ticket(AtomicU8);

impl Ticket {
    const WAITING: u8 = 0;
    const TAKEN: u8 = 1;
    const ABANDONED: u8 = 2;

    /// The simulation thread's claim: true if the command is to be applied.
    pub fn take(&self) -> bool {
        self.settle(Ticket::TAKEN)
    }

    /// The connection's: true if the command will never be applied.
    pub fn abandon(&self) -> bool {
        self.settle(Ticket::ABANDONED)
    }

    fn settle(&self, to: u8) -> bool {
        self.0
            .compare_exchange(Ticket::WAITING, to, Ordering::SeqCst, Ordering::SeqCst)
            .is_ok()
    }
}

/// What the simulation thread receives.
pub enum Message {
    /// A command from the page, where to send the answer, and its ticket
    /// (applied only if the page is still waiting when its turn comes).
    Command(Command, Sender<Reply>, Arc<Ticket>),
    /// Stop the thread (the program is shutting down).
    Quit,
}

/// Step timings for the overlay: a moving average of the time per step
/// and the steps counted over the last second.
struct StepStats {
    ms_per_step: f64,
    window_start: Instant,
    window_steps: u32,
    steps_per_second: f64,
}

impl StepStats {
    fn new() -> Self {
        StepStats {
            ms_per_step: 0.0,
            window_start: Instant::now(),
            window_steps: 0,
            steps_per_second: 0.0,
        }
    }

    /// Counts one step that took `duration`.
    fn record(&mut self, duration: Duration) {
        let ms = 1e3 * duration.as_secs_f64();
        // An exponential moving average over about the last 10 steps.
        self.ms_per_step = if self.ms_per_step == 0.0 {
            ms
        } else {
            0.9 * self.ms_per_step + 0.1 * ms
        };
        self.window_steps += 1;
        let elapsed = self.window_start.elapsed().as_secs_f64();
        if elapsed >= 1.0 {
            self.steps_per_second = f64::from(self.window_steps) / elapsed;
            self.restart_window();
        }
    }

    /// Starts counting afresh (when the animation starts or stops).
    fn restart_window(&mut self) {
        self.window_start = Instant::now();
        self.window_steps = 0;
    }
}

/// The simulation and the viewer state around it.
pub struct SimulationThread<B: LinearAlgebra> {
    simulation: Simulation<B>,
    shared: Arc<Shared>,
    animating: bool,
    show_springs: bool,
    /// When the next real-time step is due.
    next_step_at: Instant,
    stats: StepStats,
    /// Why the animation stopped, when a step failed.
    error: Option<String>,
    /// A drag target must lie within this distance of `center` (a guard
    /// against targets that would blow the solve up).
    center: [f64; 3],
    reach: f64,
    /// The scene files the page may switch to, and the one shown.
    scenes: Vec<PathBuf>,
    scene_index: usize,
    /// The time the last rebuild and refactorization of `Q` took.
    refactor: Option<Duration>,
}

impl<B: LinearAlgebra> SimulationThread<B> {
    /// Wraps `simulation` of scene `scenes[scene_index]` (paused at rest,
    /// springs shown or not) and publishes its first frame.
    pub fn new(
        simulation: Simulation<B>,
        shared: Arc<Shared>,
        show_springs: bool,
        scenes: Vec<PathBuf>,
        scene_index: usize,
    ) -> Self {
        let bounds = BoundingBox::of(simulation.rest_positions());
        let (center, diagonal) = (bounds.centre(), bounds.diagonal());
        let thread = SimulationThread {
            simulation,
            shared,
            animating: false,
            show_springs,
            next_step_at: Instant::now(),
            stats: StepStats::new(),
            error: None,
            center,
            reach: 10.0 * diagonal.max(1.0),
            scenes,
            scene_index,
            refactor: None,
        };
        thread.publish_frame();
        thread.publish_scene_list();
        thread.publish_status();
        thread
    }

    /// Is a page showing the simulation?
    fn watched(&self) -> bool {
        self.shared
            .watchers
            .lock()
            .expect("no thread panics holding it")
            .count()
            > 0
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
                Message::Command(command, reply, ticket) => {
                    if !ticket.take() {
                        continue; // the page was answered "not applied" already
                    }
                    let result = self.apply(command);
                    self.publish_status();
                    // The page may have gone away meanwhile; nothing to do then.
                    let _ = reply.send(result);
                }
            }
        }
    }

    /// The step due now; the next one is due Δt later. When steps take
    /// longer than Δt the animation slows down rather than piling up.
    fn real_time_step(&mut self) {
        let _ = self.step_once();
        let period = Duration::from_secs_f64(self.simulation.options().delta_t);
        self.next_step_at = (self.next_step_at + period).max(Instant::now());
        self.publish_status();
    }

    /// One step, timed and published; a failure stops the animation.
    fn step_once(&mut self) -> Reply {
        let started = Instant::now();
        match self.simulation.step() {
            Ok(report) => {
                self.stats.record(started.elapsed());
                self.publish_frame();
                self.record_step(&report);
                Ok(())
            }
            Err(error) => {
                let message = format!("step {}: {error}", self.simulation.steps() + 1);
                self.set_animating(false);
                self.error = Some(message.clone());
                Err(message)
            }
        }
    }

    /// Applies one command of the page (see [`Command`]).
    fn apply(&mut self, command: Command) -> Reply {
        match command {
            Command::Step {} => {
                self.set_animating(false);
                self.step_once()
            }
            Command::ToggleAnimation {} => {
                self.set_animating(!self.animating);
                Ok(())
            }
            Command::ToggleSprings {} => {
                self.show_springs = !self.show_springs;
                Ok(())
            }
            Command::Reset {} => {
                self.simulation.reset().map_err(|e| e.to_string())?;
                self.error = None;
                self.publish_frame();
                self.clear_history();
                Ok(())
            }
            Command::ToggleWind {} => {
                self.simulation.set_wind(!self.simulation.wind());
                Ok(())
            }
            Command::DragStart { vertex, target } => self.start_drag(vertex, target),
            Command::DragTo { target } => {
                self.check_target(target)?;
                if self.simulation.dragged().is_none() {
                    return Err("no vertex is being dragged".into());
                }
                self.simulation.drag_to(target).map_err(|e| e.to_string())
            }
            Command::DragEnd {} => self.timed_refactor(|s| s.end_drag()),
            Command::SetParameters {
                k,
                delta_t,
                mass_scale,
                iterations,
            } => self.set_parameters(k, delta_t, mass_scale, iterations),
            Command::LoadScene { scene } => self.load_scene(scene),
            Command::SetMethod {
                method,
                tolerance,
                energy_tolerance,
                at_least_plain,
                start,
            } => self.set_method(
                &method,
                [tolerance, energy_tolerance],
                at_least_plain,
                start.as_deref(),
            ),
        }
    }

    /// Another method, tolerances (the relative gradient's and the
    /// energy's), floor (`--at-least-plain`) or start for later steps.
    fn set_method(
        &mut self,
        method: &str,
        [tolerance, energy_tolerance]: [Option<f64>; 2],
        at_least_plain: Option<f64>,
        start: Option<&str>,
    ) -> Reply {
        let method: StepMethod = method.parse()?;
        let rules = StepControl {
            tolerance,
            energy_tolerance,
            at_least_plain,
            ..StepControl::default()
        };
        rules.check_rules()?;
        let start: Option<Start> = start.map(str::parse).transpose()?;
        let current = self.simulation.options();
        let wanted = SimulationOptions {
            step: StepControl {
                method,
                start: start.unwrap_or(current.step.start),
                ..rules
            },
            ..*current
        };
        wanted.check_textbook().map_err(|e| e.to_string())?;
        self.simulation.set_method(method, tolerance);
        self.simulation.set_energy_tolerance(energy_tolerance);
        self.simulation.set_at_least_plain(at_least_plain);
        if let Some(start) = start {
            self.simulation.set_start(start);
        }
        Ok(())
    }

    /// `change`, which rebuilds and refactors `Q`, timed for the overlay.
    fn timed_refactor(
        &mut self,
        change: impl FnOnce(&mut Simulation<B>) -> Result<(), masssprings::sim::SimulationError>,
    ) -> Reply {
        let started = Instant::now();
        change(&mut self.simulation).map_err(|e| e.to_string())?;
        self.refactor = Some(started.elapsed());
        Ok(())
    }

    /// New k, Δt and mass scale (refactoring `Q` only when one of them
    /// changed) and iterations.
    fn set_parameters(
        &mut self,
        k: f64,
        delta_t: f64,
        mass_scale: f64,
        iterations: usize,
    ) -> Reply {
        let in_range = |x: f64, low: f64, high: f64| x.is_finite() && (low..=high).contains(&x);
        if !in_range(k, 1e-6, 1e12) {
            return Err(format!("k = {k}: expected a stiffness from 1e-6 to 1e12"));
        }
        if !in_range(delta_t, 1e-4, 1.0) {
            return Err(format!("Δt = {delta_t}: expected from 0.0001 to 1 s"));
        }
        if !in_range(mass_scale, 1e-3, 1e3) {
            return Err(format!(
                "mass scale {mass_scale}: expected from 0.001 to 1000"
            ));
        }
        if !(1..=MAX_ITERATIONS).contains(&iterations) {
            return Err(format!(
                "{iterations} iterations: expected from 1 to {}",
                MAX_ITERATIONS
            ));
        }
        let current = (
            self.simulation.k(),
            self.simulation.options().delta_t,
            self.simulation.mass_scale(),
        );
        if current != (k, delta_t, mass_scale) {
            self.timed_refactor(|s| s.set_parameters(k, delta_t, mass_scale))?;
        }
        self.simulation.set_iterations(iterations);
        Ok(())
    }

    /// Switches to scene `index`: loads it, precomputes, and starts paused
    /// at rest with the scene's own k, Δt and masses (iterations and wind
    /// carry over). On failure the current scene stays.
    fn load_scene(&mut self, index: usize) -> Reply {
        let path = self
            .scenes
            .get(index)
            .ok_or_else(|| format!("there is no scene {index}"))?
            .clone();
        let scene = crate::app::file_plan::load_scene(&path).map_err(|e| match e {
            AppError::Usage(why) | AppError::Failed(why) => why,
        })?;
        let current = self.simulation.options();
        let options = SimulationOptions {
            // the user's choices carry over; Chebyshev's ρ is the old scene's
            step: StepControl {
                rho: None,
                ..current.step
            },
            ..*current
        };
        // The command line's checks too: the dense path's memory first.
        let simulation =
            crate::app::limits::precompute::<B>(&scene, &path, options).map_err(|e| match e {
                AppError::Usage(why) | AppError::Failed(why) => why,
            })?;
        // A new scene is a new precomputation, not a refactorization.
        self.refactor = None;
        let assets = SceneAssets::of(&scene, B::NAME);
        let bounds = BoundingBox::of(&scene.vertices);
        self.center = bounds.centre();
        self.reach = 10.0 * bounds.diagonal().max(1.0);
        self.simulation = simulation;
        self.scene_index = index;
        self.show_springs = scene.faces.first().is_none_or(|face| face.len() < 3);
        self.error = None;
        self.set_animating(false);
        self.stats = StepStats::new();
        *self
            .shared
            .scene
            .lock()
            .expect("no thread panics holding it") = assets;
        *self
            .shared
            .frame
            .lock()
            .expect("no thread panics holding it") = Frame::new(scene.vertices.len());
        self.publish_frame();
        self.clear_history();
        let mut status = self
            .shared
            .status
            .lock()
            .expect("no thread panics holding it");
        status.scene.clone_from(&scene.name);
        status.n = scene.vertices.len();
        status.springs = scene.springs.len();
        status.scene_serial = status.scene_serial.wrapping_add(1);
        Ok(())
    }

    /// Appends what a step did to the status's history (in place: the
    /// history never grows beyond its capacity, so this does not allocate).
    fn record_step(&self, report: &StepReport) {
        let mut status = self
            .shared
            .status
            .lock()
            .expect("no thread panics holding it");
        if status.history.len() == HISTORY_LENGTH {
            status.history.pop_front();
        }
        status.history.push_back(StepRecord {
            step: self.simulation.steps(),
            iterations: report.iterations,
            energy_decrease: report.energy_decrease,
            relative_gradient: report.relative_gradient,
            converged: matches!(
                report.stop,
                Stop::Tolerance | Stop::EnergyTolerance | Stop::AtLeastPlain
            ),
        });
    }

    fn clear_history(&self) {
        let mut status = self
            .shared
            .status
            .lock()
            .expect("no thread panics holding it");
        status.history.clear();
    }

    /// The scene names the page lists, once.
    fn publish_scene_list(&self) {
        let mut status = self
            .shared
            .status
            .lock()
            .expect("no thread panics holding it");
        status.scenes = self.scenes.iter().map(|path| scene_name(path)).collect();
        status.methods = StepMethod::ALL.map(StepMethod::name).to_vec();
        status.history.reserve(HISTORY_LENGTH);
    }

    /// Starts dragging a free vertex (a pinned one stays where it is).
    fn start_drag(&mut self, vertex: usize, target: [f64; 3]) -> Reply {
        self.check_target(target)?;
        if vertex >= self.simulation.rest_positions().len() {
            return Err(format!("vertex {vertex} does not exist"));
        }
        if self.simulation.pinned().contains(&vertex) {
            return Err(format!("vertex {vertex} is pinned"));
        }
        self.timed_refactor(|s| s.start_drag(vertex, target))
    }

    /// A drag target must be finite and near the scene.
    fn check_target(&self, target: [f64; 3]) -> Reply {
        let distance = (0..3)
            .map(|axis| (target[axis] - self.center[axis]).powi(2))
            .sum::<f64>()
            .sqrt();
        if distance.is_finite() && distance <= self.reach {
            Ok(())
        } else {
            Err("the drag target is too far from the scene".into())
        }
    }

    fn set_animating(&mut self, animating: bool) {
        if animating && !self.animating {
            self.next_step_at = Instant::now();
        }
        self.animating = animating;
        self.stats.restart_window();
        self.stats.steps_per_second = 0.0;
    }

    /// Writes the current positions into the shared frame.
    fn publish_frame(&self) {
        let mut frame = self
            .shared
            .frame
            .lock()
            .expect("no thread panics holding it");
        frame.write(
            self.simulation.positions(),
            self.simulation.steps(),
            self.simulation.time(),
        );
    }

    /// Writes the current state into the shared status.
    fn publish_status(&self) {
        // Never hold the status while taking the watchers' lock.
        let pages = self
            .shared
            .watchers
            .lock()
            .expect("no thread panics holding it")
            .count();
        let mut status = self
            .shared
            .status
            .lock()
            .expect("no thread panics holding it");
        status.steps = self.simulation.steps();
        status.time = self.simulation.time();
        status.animating = self.animating;
        status.wind = self.simulation.wind();
        status.show_springs = self.show_springs;
        status.ms_per_step = self.stats.ms_per_step;
        status.steps_per_second = self.stats.steps_per_second;
        status.dragged = self.simulation.dragged();
        if status.error != self.error {
            status.error.clone_from(&self.error);
        }
        status.pages = pages;
        status.watched = pages > 0;
        status.k = self.simulation.k();
        status.delta_t = self.simulation.options().delta_t;
        status.mass_scale = self.simulation.mass_scale();
        status.iterations = self.simulation.options().step.iterations;
        status.method = self.simulation.options().step.method.name();
        status.tolerance = self.simulation.options().step.tolerance;
        status.energy_tolerance = self.simulation.options().step.energy_tolerance;
        status.at_least_plain = self.simulation.options().step.at_least_plain;
        status.start = self.simulation.options().step.start.name();
        status.refactor_ms = self.refactor.map(|d| 1e3 * d.as_secs_f64());
        status.scene_index = self.scene_index;
    }
}

/// The name the page shows for a scene file: its stem (`flag`).
fn scene_name(path: &std::path::Path) -> String {
    path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}
