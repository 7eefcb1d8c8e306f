//! The simulations the viewer shows, whatever their backend.
//!
//! The page can switch between the three ways of solving a step this crate
//! is about (`Solver`: the assignment, the handout's code, the
//! assignment's accuracy fast), the handout's code on dense or sparse
//! matrices, and run a second simulation beside the first. The backend is
//! a type parameter of [`Simulation`], so the simulation thread holds each
//! one as a [`Run`], the few things it asks of a simulation, and
//! [`build`] makes one on the [`Backend`] a choice needs, with the command
//! line's checks (the dense path's memory first).
//!
//! How a name becomes options is `SimulationOptions::solved_by`, the one
//! rule `--textbook` and `--accuracy` use too; nothing here repeats it.

use super::rules::functions;
pub use super::rules::{name_of, options_named, solver_names};
use crate::app::error::AppError;
use crate::app::limits::{check_precomputation, precomputation_failed};
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{
    Dense, LinearAlgebra, Simulation, SimulationError, Sparse, StepControl, StepReport,
};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// What the simulation thread asks of a simulation (each method is
/// `Simulation`'s own, see there).
pub trait Run: Send {
    fn step(&mut self) -> Result<StepReport, SimulationError>;
    fn positions(&self) -> &[[f64; 3]];
    fn previous_positions(&self) -> &[[f64; 3]];
    fn rest_positions(&self) -> &[[f64; 3]];
    fn pinned(&self) -> &[usize];
    fn steps(&self) -> usize;
    fn time(&self) -> f64;
    fn options(&self) -> &SimulationOptions;
    fn k(&self) -> f64;
    fn mass_scale(&self) -> f64;
    fn mechanical_energy(&self) -> f64;
    fn set_wind(&mut self, wind: bool);
    fn set_parameters(&mut self, k: f64, delta_t: f64, mass_scale: f64) -> Result<(), String>;
    fn set_step(&mut self, step: StepControl) -> Result<(), String>;
    fn set_state(&mut self, previous: &[[f64; 3]], current: &[[f64; 3]], steps: usize);
    fn set_time(&mut self, time: f64);
    fn reset(&mut self) -> Result<(), String>;
    fn start_drag(&mut self, vertex: usize, target: [f64; 3]) -> Result<(), String>;
    fn drag_to(&mut self, target: [f64; 3]) -> Result<(), String>;
    fn end_drag(&mut self) -> Result<(), String>;
    fn dragged(&self) -> Option<usize>;
    /// Has it run out of what it shows (a recording past its last frame)?
    fn past_its_end(&self) -> bool {
        false
    }
    /// Its solver's name for the status ([`name_of`]; `None`: the
    /// expert's own method and rules).
    fn solver_name(&self) -> Option<&'static str>;
    /// Which path and functions run its step, for the status.
    fn path(&self) -> String;
}

impl<B: LinearAlgebra> Run for Simulation<B>
where
    Simulation<B>: Send,
{
    fn step(&mut self) -> Result<StepReport, SimulationError> {
        Simulation::step(self)
    }
    fn positions(&self) -> &[[f64; 3]] {
        Simulation::positions(self)
    }
    fn previous_positions(&self) -> &[[f64; 3]] {
        Simulation::previous_positions(self)
    }
    fn rest_positions(&self) -> &[[f64; 3]] {
        Simulation::rest_positions(self)
    }
    fn pinned(&self) -> &[usize] {
        Simulation::pinned(self)
    }
    fn steps(&self) -> usize {
        Simulation::steps(self)
    }
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn options(&self) -> &SimulationOptions {
        Simulation::options(self)
    }
    fn k(&self) -> f64 {
        Simulation::k(self)
    }
    fn mass_scale(&self) -> f64 {
        Simulation::mass_scale(self)
    }
    fn mechanical_energy(&self) -> f64 {
        Simulation::mechanical_energy(self)
    }
    fn set_wind(&mut self, wind: bool) {
        Simulation::set_wind(self, wind);
    }
    fn set_parameters(&mut self, k: f64, delta_t: f64, mass_scale: f64) -> Result<(), String> {
        Simulation::set_parameters(self, k, delta_t, mass_scale).map_err(|e| e.to_string())
    }
    fn set_step(&mut self, step: StepControl) -> Result<(), String> {
        Simulation::set_step(self, step).map_err(|e| e.to_string())
    }
    fn set_state(&mut self, previous: &[[f64; 3]], current: &[[f64; 3]], steps: usize) {
        Simulation::set_state(self, previous, current, steps)
            .expect("a state of the same scene, finite");
    }
    fn set_time(&mut self, time: f64) {
        Simulation::set_time(self, time);
    }
    fn reset(&mut self) -> Result<(), String> {
        Simulation::reset(self).map_err(|e| e.to_string())
    }
    fn start_drag(&mut self, vertex: usize, target: [f64; 3]) -> Result<(), String> {
        Simulation::start_drag(self, vertex, target).map_err(|e| e.to_string())
    }
    fn drag_to(&mut self, target: [f64; 3]) -> Result<(), String> {
        Simulation::drag_to(self, target).map_err(|e| e.to_string())
    }
    fn end_drag(&mut self) -> Result<(), String> {
        Simulation::end_drag(self).map_err(|e| e.to_string())
    }
    fn dragged(&self) -> Option<usize> {
        Simulation::dragged(self)
    }
    fn solver_name(&self) -> Option<&'static str> {
        name_of(Simulation::options(self))
    }
    fn path(&self) -> String {
        functions(Simulation::options(self), Backend::of::<B>().name())
    }
}

/// The matrices a simulation runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    Sparse,
    Dense,
}

impl Backend {
    /// `"sparse"` or `"dense"`, as the status says it.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Sparse => Sparse::NAME,
            Backend::Dense => Dense::NAME,
        }
    }

    /// The backend `B` is.
    pub fn of<B: LinearAlgebra>() -> Backend {
        match B::NAME == Dense::NAME {
            true => Backend::Dense,
            false => Backend::Sparse,
        }
    }

    /// The backend named `name`.
    pub fn parse(name: &str) -> Result<Backend, String> {
        match name {
            "sparse" => Ok(Backend::Sparse),
            "dense" => Ok(Backend::Dense),
            _ => Err(format!(
                "unknown backend '{name}' (expected sparse or dense)"
            )),
        }
    }
}

/// Why [`build`] made no simulation.
#[derive(Debug, Clone, PartialEq)]
pub enum NotBuilt {
    /// Refused, and why (the command line's words).
    Refused(String),
    /// The cancel flag was set while it precomputed.
    Cancelled,
}

/// The simulation of `scene` (read from `path`) on `backend`, starting at
/// rest with `options`, refused as the command line refuses it (the dense
/// path's memory, `Q`'s overflow, a textbook run with other rules); its
/// precomputation and its steps stop when `cancel` is set.
pub fn build(
    scene: &Scene,
    path: &Path,
    backend: Backend,
    options: SimulationOptions,
    cancel: &Arc<AtomicBool>,
) -> Result<Box<dyn Run>, NotBuilt> {
    match backend {
        Backend::Sparse => made::<Sparse>(scene, path, options, cancel),
        Backend::Dense => made::<Dense>(scene, path, options, cancel),
    }
}

/// [`build`] on backend `B`.
fn made<B: LinearAlgebra + 'static>(
    scene: &Scene,
    path: &Path,
    options: SimulationOptions,
    cancel: &Arc<AtomicBool>,
) -> Result<Box<dyn Run>, NotBuilt>
where
    Simulation<B>: Send,
{
    let refused = |error: AppError| match error {
        AppError::Usage(why) | AppError::Failed(why) => NotBuilt::Refused(why),
    };
    check_precomputation::<B>(scene, path, options).map_err(refused)?;
    match Simulation::<B>::from_scene_cancellable(scene, options, Arc::clone(cancel)) {
        Ok(simulation) => Ok(Box::new(simulation)),
        Err(SimulationError::Cancelled) => Err(NotBuilt::Cancelled),
        Err(error) => Err(refused(precomputation_failed(path, &error))),
    }
}

/// Gives `to` (the same scene, just built) the state of `from`: its
/// positions, step count, wind, stiffness, time step and masses, so that
/// both go on from the same start.
pub fn carry_over(from: &dyn Run, to: &mut dyn Run) -> Result<(), String> {
    let (k, delta_t, mass_scale) = (from.k(), from.options().delta_t, from.mass_scale());
    if (to.k(), to.options().delta_t, to.mass_scale()) != (k, delta_t, mass_scale) {
        to.set_parameters(k, delta_t, mass_scale)?;
    }
    to.set_wind(from.options().wind);
    to.set_state(from.previous_positions(), from.positions(), from.steps());
    to.set_time(from.time());
    Ok(())
}
