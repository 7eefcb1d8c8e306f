//! What can go wrong in the simulation.
//!
//! A leaf of the simulation's layers: every other file may report these,
//! and this one uses none of them.

use crate::linalg::LinalgError;
use std::fmt;

/// What can go wrong in the simulation.
#[derive(Debug, Clone, PartialEq)]
pub enum SimulationError {
    /// Inputs that do not fit together (sizes, indices, masses).
    InvalidInput(String),
    /// The linear algebra failed, e.g. `Q` is not positive definite.
    Linalg(LinalgError),
    /// `Q = k AᵀA + M/Δt² + w CᵀC` would overflow `f64` on its diagonal:
    /// which quantity, at which vertex, and the largest value that fits
    /// (`precomputation::check_q_fits`).
    QOverflow(String),
    /// A step produced NaN or infinity, first at this vertex (0-based).
    NotFinite { vertex: usize },
    /// A step's energy or gradient overflowed (positions beyond what
    /// `f64` can square).
    EnergyNotFinite,
    /// The step was asked to stop between two iterations
    /// ([`Simulation::set_cancel`](super::Simulation::set_cancel)); the state
    /// is left at the last completed step. Or the precomputation was asked
    /// to stop ([`Simulation::from_scene_cancellable`](super::Simulation::from_scene_cancellable)):
    /// there is no simulation.
    Cancelled,
}

impl fmt::Display for SimulationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimulationError::InvalidInput(why) => write!(f, "invalid input: {why}"),
            SimulationError::Linalg(error) => write!(f, "{error}"),
            SimulationError::QOverflow(why) => f.write_str(why),
            SimulationError::NotFinite { vertex } => write!(
                f,
                "the step produced a non-finite position (vertex {}, 1-based); the simulation stopped",
                vertex + 1
            ),
            SimulationError::EnergyNotFinite => write!(
                f,
                "the step's energy or gradient is not finite (positions too large to square in f64); the simulation stopped"
            ),
            SimulationError::Cancelled => write!(
                f,
                "cancelled before it was done; the simulation stays as it was"
            ),
        }
    }
}

impl std::error::Error for SimulationError {}

impl From<LinalgError> for SimulationError {
    /// A cancelled operation is a cancelled simulation, whatever was
    /// cancelled; every other error stays the linear algebra's.
    fn from(error: LinalgError) -> Self {
        match error {
            LinalgError::Cancelled => SimulationError::Cancelled,
            error => SimulationError::Linalg(error),
        }
    }
}
