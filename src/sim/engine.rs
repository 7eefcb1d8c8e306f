//! What advances a [`Simulation`](super::Simulation): the fast path or the
//! handout's functions as written.
//!
//! * [`Engine::Fast`]: the constant [`MassSpringSystem`] of the
//!   precomputation and the step's own [`StepWorkspace`]; every method,
//!   stopping rule and kind of pin ([`step`](super::step)).
//! * [`Engine::Textbook`]: the handout's precomputation and step
//!   ([`textbook`]), dense or sparse as the backend is:
//!   plain iterations, penalty pins, nothing measured. Changing the pins or
//!   the parameters redoes its precomputation, as the handout would.
//!
//! Source: the assignment's `main.cpp` (precompute once, step each frame).

use super::backend::{Dense, LinearAlgebra, Sparse, SparseFactorization};
use super::control::{Pins, StepControl, StepMethod, Stop};
use super::error::SimulationError;
use super::monitor::Observer;
use super::precomputation::MassSpringSystem;
use super::step::{solve_step, StepReport, StepState, StepWorkspace};
use super::textbook::{self, Precomputation};
use crate::linalg::sparse::Ordering;
use crate::linalg::Cancel;
use std::sync::atomic::{AtomicBool, Ordering as MemoryOrder};
use std::sync::Arc;

/// The network a simulation is made from.
#[derive(Debug, Clone, Copy)]
pub struct Network<'a> {
    /// Rest positions `V`.
    pub vertices: &'a [[f64; 3]],
    /// Springs `(i, j)`, 0-based.
    pub springs: &'a [[usize; 2]],
    /// Spring stiffness.
    pub k: f64,
    /// One mass per vertex.
    pub masses: &'a [f64],
    /// Pinned vertices, 0-based.
    pub pinned: &'a [usize],
    /// Time step.
    pub delta_t: f64,
    /// What stops its precomputation midway (the dense one takes minutes
    /// on a large scene); [`Cancel::NEVER`] for none.
    pub cancel: Cancel<'a>,
}

/// The fast path, or the handout's functions.
#[allow(clippy::large_enum_variant)] // one per simulation: its size does not matter
#[derive(Debug, Clone)]
pub enum Engine<B: LinearAlgebra> {
    /// The precomputed system and the step's work arrays.
    Fast {
        system: MassSpringSystem<B>,
        workspace: StepWorkspace,
    },
    /// The handout's precomputation (dense or sparse as `B` is), and the
    /// ordering its sparse factor uses.
    Textbook {
        handout: Handout,
        ordering: Ordering,
    },
}

/// The handout's precomputation, on the kind of matrix of the backend.
#[allow(clippy::large_enum_variant)] // one per simulation
#[derive(Debug, Clone)]
pub enum Handout {
    Sparse(Precomputation<Sparse>),
    Dense(Precomputation<Dense>),
}

impl<B: LinearAlgebra> Engine<B> {
    /// The fast path for `network`, `Q` ordered and factored as `how` says,
    /// pins as `pins` says.
    ///
    /// # Errors
    /// As the precomputation.
    pub fn fast(
        network: &Network<'_>,
        how: SparseFactorization,
        pins: Pins,
    ) -> Result<Self, SimulationError> {
        let Network {
            vertices,
            springs,
            k,
            masses,
            pinned,
            delta_t,
            cancel,
        } = *network;
        let mut system = MassSpringSystem::<B>::with_factorization(
            vertices, springs, k, masses, pinned, delta_t, how, cancel,
        )?;
        if pins == Pins::Exact {
            system.use_exact_pins(how)?;
        }
        let workspace = StepWorkspace::new(&system);
        Ok(Engine::Fast { system, workspace })
    }

    /// The handout's functions for `network` (sparse with `ordering`),
    /// running `iterations` per step.
    ///
    /// # Errors
    /// As the precomputation.
    pub fn textbook(
        network: &Network<'_>,
        ordering: Ordering,
        iterations: usize,
    ) -> Result<Self, SimulationError> {
        let mut handout = Handout::new::<B>(network, ordering)?;
        handout.set_iterations(iterations);
        Ok(Engine::Textbook { handout, ordering })
    }

    /// One step from `state` into `u_next`, solved as `control` says (the
    /// handout's functions take only its iteration count), stopped between
    /// two iterations once `cancel` is set.
    ///
    /// # Errors
    /// As [`solve_step`]; [`SimulationError::NotFinite`] and
    /// [`SimulationError::Cancelled`] on the textbook path too.
    pub fn step(
        &mut self,
        control: &StepControl,
        state: StepState<'_>,
        u_next: &mut [[f64; 3]],
        observer: Option<Observer<'_>>,
        cancel: Option<&Arc<AtomicBool>>,
    ) -> Result<StepReport, SimulationError> {
        match self {
            Engine::Fast { system, workspace } => {
                let cancel = cancel.map(|flag| &**flag);
                solve_step(system, workspace, control, state, u_next, observer, cancel)
            }
            Engine::Textbook { handout, .. } => handout.step(state, u_next, cancel),
        }
    }

    /// Local/global iterations per step, for the handout's functions (the
    /// fast path takes them from each step's control).
    pub fn set_iterations(&mut self, iterations: usize) {
        if let Engine::Textbook { handout, .. } = self {
            handout.set_iterations(iterations);
        }
    }

    /// What the engine holds, in bytes (arrays' lengths), item by item.
    pub fn bytes(&self) -> Vec<(&'static str, usize)> {
        match self {
            Engine::Fast { system, workspace } => {
                let mut items = system.bytes();
                items.extend(workspace.bytes());
                items
            }
            Engine::Textbook { handout, .. } => handout.bytes(),
        }
    }

    /// The springs `(i, j)`.
    pub fn springs(&self) -> &[[usize; 2]] {
        match self {
            Engine::Fast { system, .. } => &system.springs,
            Engine::Textbook { handout, .. } => handout.springs(),
        }
    }

    /// Spring stiffness `k`.
    pub fn k(&self) -> f64 {
        match self {
            Engine::Fast { system, .. } => system.k,
            Engine::Textbook { handout, .. } => handout.k(),
        }
    }

    /// Makes the precomputation again for `network` (new pins, stiffness,
    /// time step or masses), the pinned vertices held at `targets`: the
    /// fast path refactors on the analysis it has, the handout's functions
    /// start over.
    ///
    /// # Errors
    /// As the precomputation; the engine is then unchanged when the fast
    /// path could restore it.
    pub fn remake(
        &mut self,
        network: &Network<'_>,
        targets: &[[f64; 3]],
    ) -> Result<(), SimulationError> {
        match self {
            Engine::Fast { system, .. } => {
                let parameters = (system.k, system.delta_t) != (network.k, network.delta_t)
                    || system.m != network.masses;
                if parameters {
                    system.set_parameters(network.k, network.delta_t, network.masses)?;
                }
                if system.pinned != network.pinned || system.pin_targets != targets {
                    system.set_pins(network.pinned, targets)?;
                }
                Ok(())
            }
            Engine::Textbook { handout, ordering } => {
                let positive = |x: f64| x > 0.0 && x.is_finite();
                if !positive(network.k) || !positive(network.delta_t) {
                    return Err(SimulationError::InvalidInput(format!(
                        "k = {} and Δt = {} must be positive and finite",
                        network.k, network.delta_t
                    )));
                }
                let mut remade = Handout::new::<B>(network, *ordering)?;
                remade.set_iterations(handout.iterations());
                remade.move_pins(network.pinned, targets);
                *handout = remade;
                Ok(())
            }
        }
    }

    /// Moves the pinned vertices' targets (the right-hand side only).
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] when the number of targets is not
    /// the number of pins.
    pub fn set_pin_targets(&mut self, targets: &[[f64; 3]]) -> Result<(), SimulationError> {
        match self {
            Engine::Fast { system, .. } => system.set_pin_targets(targets),
            Engine::Textbook { handout, .. } => {
                let pinned = handout.pinned().to_vec();
                if pinned.len() != targets.len() {
                    return Err(SimulationError::InvalidInput(format!(
                        "{} targets for {} pinned vertices",
                        targets.len(),
                        pinned.len()
                    )));
                }
                handout.move_pins(&pinned, targets);
                Ok(())
            }
        }
    }
}

impl Handout {
    /// The handout's precomputation of `network`, dense when `B` is. The
    /// handout's functions take concrete matrices, not a backend, so the
    /// backend is told apart by its name (`LinearAlgebra::NAME`).
    fn new<B: LinearAlgebra>(
        network: &Network<'_>,
        ordering: Ordering,
    ) -> Result<Self, SimulationError> {
        let Network {
            vertices,
            springs,
            k,
            masses,
            pinned,
            delta_t,
            cancel,
        } = *network;
        // The handout's fast_mass_springs_precomputation_dense and _sparse
        // (with `ordering`), given up once `cancel` is set.
        Ok(if B::NAME == Dense::NAME {
            let how = SparseFactorization::default(); // the dense factor has one way
            Handout::Dense(textbook::precomputation::<Dense>(
                vertices, springs, k, masses, pinned, delta_t, how, cancel,
            )?)
        } else {
            let how = textbook::factored_as_eigen(ordering);
            Handout::Sparse(textbook::precomputation::<Sparse>(
                vertices, springs, k, masses, pinned, delta_t, how, cancel,
            )?)
        })
    }

    /// Iterations per step.
    pub fn set_iterations(&mut self, iterations: usize) {
        match self {
            Handout::Sparse(pre) => pre.iterations = iterations,
            Handout::Dense(pre) => pre.iterations = iterations,
        }
    }

    /// One step of the handout's `fast_mass_springs_step_*`, which looks at
    /// `cancel` between its iterations (`Precomputation::stop`).
    fn step(
        &mut self,
        state: StepState<'_>,
        u_next: &mut [[f64; 3]],
        cancel: Option<&Arc<AtomicBool>>,
    ) -> Result<StepReport, SimulationError> {
        let StepState {
            f_ext,
            u_prev,
            u_cur,
        } = state;
        let iterations = match self {
            Handout::Sparse(pre) => {
                pre.stop = cancel.cloned();
                textbook::fast_mass_springs_step_sparse(pre, f_ext, u_prev, u_cur, u_next);
                pre.iterations
            }
            Handout::Dense(pre) => {
                pre.stop = cancel.cloned();
                textbook::fast_mass_springs_step_dense(pre, f_ext, u_prev, u_cur, u_next);
                pre.iterations
            }
        };
        if cancel.is_some_and(|flag| flag.load(MemoryOrder::Relaxed)) {
            return Err(SimulationError::Cancelled); // u_next is not a step's end
        }
        if let Some(vertex) = u_next.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(SimulationError::NotFinite { vertex });
        }
        Ok(StepReport {
            method: StepMethod::Plain,
            iterations,
            stop: Stop::Iterations,
            energy_decrease: None,
            relative_gradient: None,
        })
    }

    /// Spring stiffness `k`.
    pub fn k(&self) -> f64 {
        match self {
            Handout::Sparse(pre) => pre.k,
            Handout::Dense(pre) => pre.k,
        }
    }

    /// Iterations per step.
    pub fn iterations(&self) -> usize {
        match self {
            Handout::Sparse(pre) => pre.iterations,
            Handout::Dense(pre) => pre.iterations,
        }
    }

    /// The springs `(i, j)`.
    pub fn springs(&self) -> &[[usize; 2]] {
        match self {
            Handout::Sparse(pre) => &pre.springs,
            Handout::Dense(pre) => &pre.springs,
        }
    }

    /// The pinned vertices.
    pub fn pinned(&self) -> &[usize] {
        match self {
            Handout::Sparse(pre) => &pre.pinned,
            Handout::Dense(pre) => &pre.pinned,
        }
    }

    /// Holds `pinned[p]` at `targets[p]`: the step reads `V` only as the
    /// pins' targets `C V`, so the pinned rows of `V` move (a drag).
    fn move_pins(&mut self, pinned: &[usize], targets: &[[f64; 3]]) {
        let v = match self {
            Handout::Sparse(pre) => &mut pre.V,
            Handout::Dense(pre) => &mut pre.V,
        };
        for (&c, &t) in pinned.iter().zip(targets) {
            v[c] = t;
        }
    }

    /// What the precomputation holds, in bytes (the matrices and the
    /// factor; an estimate for the dense one, `n²` values each).
    pub fn bytes(&self) -> Vec<(&'static str, usize)> {
        let (matrices, factor) = match self {
            Handout::Sparse(pre) => (
                [&pre.M, &pre.A, &pre.C, &pre.Q]
                    .map(Sparse::matrix_bytes)
                    .iter()
                    .sum(),
                Sparse::factorization_bytes(&pre.prefactorization),
            ),
            Handout::Dense(pre) => (
                [&pre.M, &pre.A, &pre.C, &pre.Q]
                    .map(Dense::matrix_bytes)
                    .iter()
                    .sum(),
                Dense::factorization_bytes(&pre.prefactorization),
            ),
        };
        vec![
            ("handout: M, A, C, Q", matrices),
            ("handout: factor of Q", factor),
        ]
    }
}
