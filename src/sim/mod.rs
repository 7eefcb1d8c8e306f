//! The assignment's mathematics: Fast Simulation of Mass-Spring Systems.
//!
//! | the handout's | here |
//! |---|---|
//! | `signed_incidence_matrix_dense/_sparse` | [`signed_incidence`] |
//! | `fast_mass_springs_precomputation_dense/_sparse` (r, M, A, C, Q, factor) | [`precomputation`] |
//! | `fast_mass_springs_step_dense/_sparse` (y, d, b, solve) | [`step`], [`local_step`] |
//! | the energy a step minimises, its gradient and Hessian | [`energy`], [`hessian`] |
//! | "more advanced stopping criteria": tolerances and faster methods | [`methods`] |
//! | gravity, wind | [`forces`] |
//! | dense or sparse matrices | [`backend`] |
//! | a running simulation (state, time, pins) | [`simulation`] |
//!
//! `docs/equations.md` maps every equation of the handout to the one place
//! that computes it.

pub mod backend;
pub mod energy;
pub mod exact_pins;
pub mod forces;
pub mod hessian;
pub mod local_step;
pub mod methods;
pub mod precomputation;
pub mod signed_incidence;
pub mod simulation;
pub mod spring_pass;
pub mod step;

pub use backend::{Dense, LinearAlgebra, Sparse};
pub use methods::{StepControl, StepMethod, Stop};
pub use precomputation::{MassSpringSystem, DELTA_T, PIN_WEIGHT};
pub use simulation::Simulation;
pub use step::{StepReport, ITERATIONS};

use crate::linalg::LinalgError;
use std::fmt;

/// What can go wrong in the simulation.
#[derive(Debug, Clone, PartialEq)]
pub enum SimulationError {
    /// Inputs that do not fit together (sizes, indices, masses).
    InvalidInput(String),
    /// The linear algebra failed, e.g. `Q` is not positive definite.
    Linalg(LinalgError),
    /// A step produced NaN or infinity, first at this vertex (0-based).
    NotFinite { vertex: usize },
    /// A step's energy or gradient overflowed (positions beyond what
    /// `f64` can square).
    EnergyNotFinite,
}

impl fmt::Display for SimulationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimulationError::InvalidInput(why) => write!(f, "invalid input: {why}"),
            SimulationError::Linalg(error) => write!(f, "{error}"),
            SimulationError::NotFinite { vertex } => write!(
                f,
                "the step produced a non-finite position (vertex {}, 1-based); the simulation stopped",
                vertex + 1
            ),
            SimulationError::EnergyNotFinite => write!(
                f,
                "the step's energy or gradient is not finite (positions too large to square in f64); the simulation stopped"
            ),
        }
    }
}

impl std::error::Error for SimulationError {}

impl From<LinalgError> for SimulationError {
    fn from(error: LinalgError) -> Self {
        SimulationError::Linalg(error)
    }
}
