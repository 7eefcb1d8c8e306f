//! What `converge` was asked to do, parsed from its flags once: the scene,
//! the step or steps, the methods and their control, the outputs, and the
//! canonical simulation every method is compared along.

use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Accuracy, StepControl, StepMethod};
use std::path::PathBuf;

/// A parsed `converge` command line.
pub(crate) struct Request {
    pub(super) scene: PathBuf,
    pub(super) step: usize,
    pub(super) methods: Vec<StepMethod>,
    pub(super) control: StepControl,
    pub(super) csv: Option<PathBuf>,
    pub(super) plot: Option<PathBuf>,
    /// `--steps S`: instead of one step, steps 1…S, medians only.
    pub(super) over_steps: Option<usize>,
    /// The canonical simulation: plain, 50 iterations, the pins and the
    /// factorization given.
    pub(crate) canonical: SimulationOptions,
    /// `--accuracy A` (with `--steps`): the accuracy's settings against the
    /// assignment's, over whole animations.
    pub(super) accuracy: Option<Accuracy>,
    /// `--oracle FILE.png` (with `--accuracy`): the accuracy's cost against
    /// an oracle's, instead of the comparison.
    pub(super) oracle: Option<PathBuf>,
    /// `--motion FILE.png` (with `--accuracy`): how much three runs move.
    pub(super) motion: Option<PathBuf>,
}

/// Plain iterations whose energies are the yardsticks.
pub(super) const YARDSTICKS: [usize; 2] = [50, 200];
