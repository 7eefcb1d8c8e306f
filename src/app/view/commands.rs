//! The page's commands, applied by the simulation thread between steps
//! (see [`Command`]): every one acts on both simulations when comparing,
//! but the method, the solver and the iteration budget, which are the
//! first's.

use super::api::Command;
use super::recording::{Recording, RECORDING};
use super::rules::{check_parameters, method_step, DragReach};
use super::simulation_thread::{scene_name, Reply, SceneAssets, Shared, Shown, SimulationThread};
use super::solver::{self, Backend, NotBuilt, Run};
use crate::app::error::AppError;
use crate::app::limits::dense_need;
use masssprings::memory::gigabytes;
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Solver, StepControl};
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Instant;

impl SimulationThread {
    /// Applies one command of the page.
    pub(super) fn apply(&mut self, command: Command) -> Reply {
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
            Command::Reset {} => self.reset(),
            Command::Restart {} => self.restart(),
            Command::ToggleWind {} => {
                let wind = !self.main.run.options().wind;
                self.all_mut().for_each(|shown| shown.run.set_wind(wind));
                Ok(())
            }
            Command::DragStart { vertex, target } => self.start_drag(vertex, target),
            Command::DragTo { target } => self.drag_to(target),
            Command::DragEnd {} => self.timed_refactor(|run| run.end_drag()),
            Command::SetParameters {
                k,
                delta_t,
                mass_scale,
                iterations,
            } => self.set_parameters([k, delta_t, mass_scale], iterations),
            Command::LoadScene { scene } => self.load_scene(scene),
            other => self.apply_solving(other),
        }
    }

    /// The commands about how steps are solved, and cancelling one.
    fn apply_solving(&mut self, command: Command) -> Reply {
        match command {
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
            Command::SetSolver { solver, backend } => self.set_solver(&solver, backend.as_deref()),
            Command::Compare { with, backend } => self.compare(with.as_deref(), backend.as_deref()),
            Command::Cancel {} => {
                // The steps of commands sent before this one were stopped
                // by the flag; the next ones run.
                self.shared.cancel.store(false, Ordering::SeqCst);
                self.set_animating(false);
                Ok(())
            }
            _ => unreachable!("apply handles the others"),
        }
    }

    /// Back to rest at time 0, every setting kept, running or not.
    fn restart(&mut self) -> Reply {
        for shown in self.all_mut() {
            shown.run.reset()?;
        }
        self.error = None;
        self.note = None;
        self.publish_frame();
        self.clear_history();
        Ok(())
    }

    /// Back to the state at load, paused: rest, time 0, and the command
    /// line's settings again (the scene's k, its Δt and masses, the wind,
    /// and the first simulation's budget and rules as its solver has
    /// them). What is shown and by which solvers stays.
    fn reset(&mut self) -> Reply {
        self.set_animating(false);
        let (k, delta_t, wind) = (self.scene.k, self.initial.delta_t, self.initial.wind);
        let changed =
            |run: &dyn Run| (run.k(), run.options().delta_t, run.mass_scale()) != (k, delta_t, 1.0);
        if self.all_mut().any(|shown| changed(shown.run.as_ref())) {
            self.timed_refactor(|run| match changed(run) {
                true => run.set_parameters(k, delta_t, 1.0),
                false => Ok(()),
            })?;
        }
        self.all_mut().for_each(|shown| shown.run.set_wind(wind));
        let step = match self.main.run.solver_name() {
            Some(name) => solver::options_named(self.initial, name)?.step,
            None => self.initial.step,
        };
        self.main.run.set_step(step)?;
        self.restart()
    }

    /// Another method, tolerances (the relative gradient's and the
    /// energy's), floor (`--at-least-plain`) or start for later steps of
    /// the first simulation; its budget and history window stay, and so
    /// does how the method runs (L-BFGS's plain start) while it stays.
    fn set_method(
        &mut self,
        method: &str,
        [tolerance, energy_tolerance]: [Option<f64>; 2],
        at_least_plain: Option<f64>,
        start: Option<&str>,
    ) -> Reply {
        let current = self.main.run.options().step;
        let step = method_step(
            current,
            method,
            [tolerance, energy_tolerance],
            at_least_plain,
            start,
        )?;
        self.main
            .run
            .set_step(step)
            .map_err(|why| format!("{why}; to change them, solve by another solver first"))
    }

    /// The backend of `name` (`None`: the command line's).
    fn backend(&self, name: Option<&str>) -> Result<Backend, String> {
        name.map_or(Ok(self.default_backend), Backend::parse)
    }

    /// Solves later steps of the first simulation by solver `name` on
    /// `backend`: precomputed again, from where it is.
    fn set_solver(&mut self, name: &str, backend: Option<&str>) -> Reply {
        let backend = self.backend(backend)?;
        name.parse::<Solver>()?;
        let options = solver::options_named(*self.main.run.options(), name)?;
        let run = self.built_from_main(name, backend, options)?;
        self.main = Shown::new(run, backend);
        self.refactor = None; // a new precomputation, not a refactorization
        self.publish_frame();
        Ok(())
    }

    /// Starts comparing with a second simulation solved by `with` on
    /// `backend`, from where the first is, or with the frames of
    /// `--frames` ([`RECORDING`], both from rest), or stops (`None`).
    pub(super) fn compare(&mut self, with: Option<&str>, backend: Option<&str>) -> Reply {
        let Some(name) = with else {
            self.second = None;
            self.reshape_frame();
            return Ok(());
        };
        let second = match name {
            RECORDING => self.recording()?,
            _ => {
                let backend = self.backend(backend)?;
                let options = solver::options_named(*self.main.run.options(), name)?;
                Shown::new(self.built_from_main(name, backend, options)?, backend)
            }
        };
        self.second = Some(second);
        self.reshape_frame();
        Shared::lock(&self.shared.status).compare = None; // a fresh history
        if name == RECORDING {
            self.restart()?; // the frames start at rest: both go from there
        }
        Ok(())
    }

    /// The frames of `--frames` played back beside the first simulation.
    fn recording(&mut self) -> Result<Shown, String> {
        let Some(frames) = self.frames.clone() else {
            return Err("no frames to compare with: start the viewer with --frames DIR".into());
        };
        if self.scene_index != 0 {
            let scene = scene_name(&self.scenes[0]);
            return Err(format!("the frames are of {scene}: switch to it first"));
        }
        let options = *self.main.run.options();
        let what = "precomputing the frames' scene, to measure their energy".to_string();
        let mirror = self.precomputing(what, |thread| {
            let path = &thread.scenes[0];
            solver::build(
                &thread.scene,
                path,
                Backend::Sparse,
                options,
                &thread.shared.cancel,
            )
        })?;
        let recording = Recording::new(frames, mirror);
        Ok(Shown::new(Box::new(recording), Backend::Sparse))
    }

    /// A simulation of the scene solved by `options` on `backend` (named
    /// `name` while it is precomputed), going on from where the first is.
    fn built_from_main(
        &mut self,
        name: &str,
        backend: Backend,
        options: SimulationOptions,
    ) -> Result<Box<dyn Run>, String> {
        let what = precomputing_for(name, backend, &self.scene);
        let mut run = self.precomputing(what, |thread| {
            let path = &thread.scenes[thread.scene_index];
            solver::build(&thread.scene, path, backend, options, &thread.shared.cancel)
        })?;
        solver::carry_over(self.main.run.as_ref(), run.as_mut())?;
        Ok(run)
    }

    /// Runs `build`, a precomputation, showing `what` as the work in
    /// progress; a cancelled one changes nothing but the note, which says
    /// so, and pauses.
    fn precomputing<T>(
        &mut self,
        what: String,
        build: impl FnOnce(&Self) -> Result<T, NotBuilt>,
    ) -> Result<T, String> {
        self.busy(what.clone(), None);
        let started = Instant::now();
        let built = build(self);
        self.done();
        built.map_err(|not_built| match not_built {
            NotBuilt::Refused(why) => why,
            NotBuilt::Cancelled => {
                let seconds = started.elapsed().as_secs_f64();
                let note = format!("{what}: cancelled after {seconds:.1} s; nothing changed");
                self.set_animating(false);
                self.note = Some(note.clone());
                note
            }
        })
    }

    /// The frame, sized for the simulations shown, with their positions.
    pub(super) fn reshape_frame(&self) {
        let sets = 1 + usize::from(self.second.is_some());
        Shared::lock(&self.shared.frame).reshape(self.scene.vertices.len(), sets);
        self.publish_frame();
    }

    /// `change` applied to every simulation (rebuilding and refactoring
    /// `Q`; the handout's dense code precomputes again, which the stop
    /// button stops), timed for the overlay.
    fn timed_refactor(&mut self, change: impl Fn(&mut dyn Run) -> Result<(), String>) -> Reply {
        self.busy("rebuilding and refactoring Q".into(), None);
        let started = Instant::now();
        let changed = self
            .all_mut()
            .try_for_each(|shown| change(shown.run.as_mut()));
        self.done();
        changed?;
        self.refactor = Some(started.elapsed());
        Ok(())
    }

    /// New k, Δt and mass scale for every simulation (refactoring `Q` only
    /// when one of them changed), and the first's iteration budget.
    fn set_parameters(&mut self, [k, delta_t, mass_scale]: [f64; 3], iterations: usize) -> Reply {
        check_parameters([k, delta_t, mass_scale], iterations)?;
        let run = &self.main.run;
        let current = (run.k(), run.options().delta_t, run.mass_scale());
        if current != (k, delta_t, mass_scale) {
            self.timed_refactor(|run| run.set_parameters(k, delta_t, mass_scale))?;
        }
        let step = StepControl {
            iterations,
            ..self.main.run.options().step
        };
        self.main.run.set_step(step)
    }

    /// Starts dragging a free vertex (a pinned one stays where it is).
    fn start_drag(&mut self, vertex: usize, target: [f64; 3]) -> Reply {
        self.check_target(target)?;
        if vertex >= self.main.run.rest_positions().len() {
            return Err(format!("vertex {vertex} does not exist"));
        }
        if self.main.run.pinned().contains(&vertex) {
            return Err(format!("vertex {vertex} is pinned"));
        }
        self.timed_refactor(|run| run.start_drag(vertex, target))
    }

    /// Moves the dragged vertex's target.
    fn drag_to(&mut self, target: [f64; 3]) -> Reply {
        self.check_target(target)?;
        if self.main.run.dragged().is_none() {
            return Err("no vertex is being dragged".into());
        }
        for shown in self.all_mut() {
            shown.run.drag_to(target)?;
        }
        Ok(())
    }

    /// A drag target must be finite and near the scene.
    fn check_target(&self, target: [f64; 3]) -> Reply {
        self.drag_reach.check(target)
    }

    /// Switches to scene `index`: loads it, precomputes every simulation
    /// shown, and starts paused at rest with the scene's own k, Δt and
    /// masses (solvers, iterations and wind carry over). On failure the
    /// current scene stays.
    fn load_scene(&mut self, index: usize) -> Reply {
        let path = self
            .scenes
            .get(index)
            .ok_or_else(|| format!("there is no scene {index}"))?
            .clone();
        let scene = crate::app::file_plan::load_scene(&path).map_err(|e| match e {
            AppError::Usage(why) | AppError::Failed(why) => why,
        })?;
        let what = format!("precomputing {}", scene_name(&path));
        let (main, second) = self.precomputing(what, |thread| thread.build_all(&scene, &path))?;
        self.main = main;
        self.second = second;
        self.scene_index = index;
        self.show_scene(scene);
        Ok(())
    }

    /// Every simulation shown, made again for `scene`, at rest (the frames
    /// of `--frames`, of another scene, are not shown with it).
    fn build_all(
        &self,
        scene: &Scene,
        path: &std::path::Path,
    ) -> Result<(Shown, Option<Shown>), NotBuilt> {
        let build = |shown: &Shown| -> Result<Shown, NotBuilt> {
            let current = shown.run.options();
            let options = SimulationOptions {
                // the user's choices carry over; Chebyshev's ρ is the old scene's
                step: StepControl {
                    rho: None,
                    ..current.step
                },
                ..*current
            };
            let run = solver::build(scene, path, shown.backend, options, &self.shared.cancel)?;
            Ok(Shown::new(run, shown.backend))
        };
        let simulated = self.second.as_ref();
        let simulated = simulated.filter(|second| second.run.solver_name() != Some(RECORDING));
        let second = simulated.map(build).transpose()?;
        Ok((build(&self.main)?, second))
    }

    /// Shows `scene`, just loaded: its assets, bounds, frame and status.
    fn show_scene(&mut self, scene: Scene) {
        self.refactor = None; // a new precomputation, not a refactorization
        self.drag_reach = DragReach::of(&scene.vertices);
        self.show_springs = scene.faces.first().is_none_or(|face| face.len() < 3);
        self.error = None;
        self.set_animating(false);
        *Shared::lock(&self.shared.scene) = SceneAssets::of(&scene, self.main.backend.name());
        self.scene = Arc::new(scene);
        self.reshape_frame();
        self.clear_history();
        self.publish_dense_need();
        let mut status = Shared::lock(&self.shared.status);
        status.scene.clone_from(&self.scene.name);
        status.n = self.scene.vertices.len();
        status.springs = self.scene.springs.len();
        status.scene_serial = status.scene_serial.wrapping_add(1);
    }
}

/// What the status says while the simulation solved by `name` on
/// `backend` is precomputed for `scene`: on the dense path, the memory it
/// takes, as the memory rule counts it (`limits::dense_need`).
fn precomputing_for(name: &str, backend: Backend, scene: &Scene) -> String {
    let what = format!("precomputing for {name} ({})", backend.name());
    match backend {
        Backend::Sparse => what,
        Backend::Dense => {
            let (bytes, need) = dense_need(scene);
            format!("{what}: {need}, {}", gigabytes(bytes))
        }
    }
}
