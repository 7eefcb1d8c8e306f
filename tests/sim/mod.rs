//! The simulation layer: the assignment's mathematics, the textbook and fast steps, the reference trajectories, the iterations and their costs.

mod accuracy;
mod convergence;
mod fidelity;
mod mathematics;
mod memory;
mod mistakes;
mod no_allocation;
mod parameters;
mod textbook;
mod threads;
