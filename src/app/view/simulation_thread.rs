//! The simulation thread: it owns the [`Simulation`], steps it in real time
//! (one step of Δt = 1/30 s every 1/30 s while animating), applies the
//! page's commands between steps, and publishes what the HTTP threads serve.
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

use super::api::{Command, Frame, Status};
use masssprings::mesh::bounding_box::BoundingBox;
use masssprings::sim::{LinearAlgebra, Simulation, DELTA_T};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What the HTTP threads publish and read.
pub struct Shared {
    /// The latest positions, encoded as `/api/frame` sends them.
    pub frame: Mutex<Frame>,
    /// The latest state, as `/api/status` sends it.
    pub status: Mutex<Status>,
}

/// The answer to a command: `Err` carries the reason it was refused.
pub type Reply = Result<(), String>;

/// What the simulation thread receives.
pub enum Message {
    /// A command from the page, and where to send the answer.
    Command(Command, Sender<Reply>),
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
}

impl<B: LinearAlgebra> SimulationThread<B> {
    /// Wraps `simulation` (animating from the start, springs shown or not)
    /// and publishes its first frame.
    pub fn new(simulation: Simulation<B>, shared: Arc<Shared>, show_springs: bool) -> Self {
        let bounds = BoundingBox::of(simulation.rest_positions());
        let (center, diagonal) = (bounds.centre(), bounds.diagonal());
        let thread = SimulationThread {
            simulation,
            shared,
            animating: true,
            show_springs,
            next_step_at: Instant::now(),
            stats: StepStats::new(),
            error: None,
            center,
            reach: 10.0 * diagonal.max(1.0),
        };
        thread.publish_frame();
        thread.publish_status();
        thread
    }

    /// Runs until [`Message::Quit`] (or until every sender is gone).
    pub fn run(mut self, inbox: Receiver<Message>) {
        loop {
            if self.animating && Instant::now() >= self.next_step_at {
                self.real_time_step();
            }
            let message = if self.animating {
                let wait = self.next_step_at.saturating_duration_since(Instant::now());
                match inbox.recv_timeout(wait) {
                    Ok(message) => message,
                    Err(RecvTimeoutError::Timeout) => continue,
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            } else {
                match inbox.recv() {
                    Ok(message) => message,
                    Err(_) => return,
                }
            };
            match message {
                Message::Quit => return,
                Message::Command(command, reply) => {
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
        let period = Duration::from_secs_f64(DELTA_T);
        self.next_step_at = (self.next_step_at + period).max(Instant::now());
        self.publish_status();
    }

    /// One step, timed and published; a failure stops the animation.
    fn step_once(&mut self) -> Reply {
        let started = Instant::now();
        match self.simulation.step() {
            Ok(_) => {
                self.stats.record(started.elapsed());
                self.publish_frame();
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
            Command::DragEnd {} => self.simulation.end_drag().map_err(|e| e.to_string()),
        }
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
        self.simulation
            .start_drag(vertex, target)
            .map_err(|e| e.to_string())
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
    }
}
