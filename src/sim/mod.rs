//! The assignment's mathematics: Fast Simulation of Mass-Spring Systems.
//!
//! Start at [`textbook`]: the handout's precomputation and step, written
//! out. The files below it, in the order they build on each other (each
//! uses only those listed before it):
//!
//! | file | what it holds |
//! |---|---|
//! | [`error`], [`control`] | what can go wrong; the words of a step (method, stopping rules, pins) |
//! | [`backend`] | dense or sparse matrices, one interface |
//! | [`signed_incidence`], [`forces`] | the handout's `A`; gravity and wind |
//! | [`local_step`] | `dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)/‖pᵢ − pⱼ‖`, one spring at a time ([`simd`]: four) |
//! | [`spring_blocks`] | the same with `Aᵀd`, shared among threads by blocks of rows |
//! | [`spring_pass`], [`energy`], [`hessian`] | the energy a step minimises, its gradient and Hessian |
//! | [`precomputation`], [`exact_pins`] | `r`, `M`, `A`, `C`, `Q` and its factor, constant: the fast path's `MassSpringSystem::new` |
//! | [`textbook`] | `fast_mass_springs_precomputation/step_{dense,sparse}` as the handout writes them |
//! | [`mistakes`] | the same, with one of the usual mistakes made on purpose (`render`/`trace --mistake`, the diagnosis of `trace --compare`) |
//! | [`global_step`], [`monitor`] | the fast path's iteration; stopping rules and observers |
//! | [`methods`] | plain and the four methods that accelerate it |
//! | [`step`] | one step on the fast path, with its own work arrays |
//! | [`engine`], [`simulation`] | a running simulation: time, state, forces, pins |
//!
//! `docs/equations.md` maps every equation of the handout to the function
//! that computes it on each path.

pub mod backend;
pub mod control;
pub mod energy;
pub mod engine;
pub mod error;
pub mod exact_pins;
pub mod forces;
pub mod global_step;
pub mod hessian;
pub mod local_step;
pub mod methods;
pub mod mistakes;
pub mod monitor;
pub mod precomputation;
pub mod signed_incidence;
pub mod simd;
pub mod simulation;
pub mod spring_blocks;
pub mod spring_pass;
pub mod step;
pub mod textbook;

pub use backend::{Dense, LinearAlgebra, Sparse};
pub use control::{Accuracy, Pins, Start, StepControl, StepMethod, Stop, ITERATIONS};
pub use error::SimulationError;
pub use precomputation::{MassSpringSystem, DELTA_T, PIN_WEIGHT};
pub use simulation::{Simulation, SimulationOptions, Solver, VERTICES_PER_THREAD};
pub use step::StepReport;
