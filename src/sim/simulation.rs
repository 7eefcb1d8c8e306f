//! A running simulation: the state `(U_prev, U_cur)`, simulated time,
//! forces, and pins that can change (dragging a vertex).
//!
//! Starts at rest (`U_prev = U_cur = V`, zero velocity) and advances one
//! [`fast_mass_springs_step`](super::step::fast_mass_springs_step) at a time. The state vectors are swapped, not
//! copied, and no step allocates.

use super::backend::{LinearAlgebra, SparseFactorization};
use super::forces::{bounding_box_diagonal, external_forces};
use super::methods::{Observer, Start, StepControl, StepMethod, DEFAULT_WINDOW};
use super::precomputation::{fast_mass_springs_precomputation_with, MassSpringSystem, DELTA_T};
use super::step::{solve_step, StepReport, ITERATIONS};
use super::SimulationError;
use crate::linalg::sparse::{Method, Ordering};
use crate::mesh::Scene;

/// How a simulation runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulationOptions {
    /// Time step (the assignment: 1/30 s).
    pub delta_t: f64,
    /// Local/global iterations per step (the assignment: 50), or the most
    /// a step may take when there is a tolerance.
    pub iterations: usize,
    /// Add the assignment viewer's wind to gravity.
    pub wind: bool,
    /// How each step is solved (the assignment: plain local/global).
    pub method: StepMethod,
    /// Stop a step once its relative gradient is at most this.
    pub tolerance: Option<f64>,
    /// Stop a step once an iteration's energy decrease is at most this
    /// fraction of the step's decrease so far.
    pub energy_tolerance: Option<f64>,
    /// Let no rule stop a step before its energy has fallen by this many
    /// times the first plain iteration's decrease (with no other rule,
    /// stop there).
    pub at_least_plain: Option<f64>,
    /// Chebyshev's spectral radius (estimated when `None`).
    pub rho: Option<f64>,
    /// Chebyshev's relaxation of each plain step.
    pub relaxation: f64,
    /// Anderson's and L-BFGS's history window.
    pub window: usize,
    /// Where each step's iterations start.
    pub start: Start,
    /// Pins by the assignment's penalty, or as exact constraints.
    pub pins: Pins,
    /// The sparse backend's fill-reducing ordering (AMD, or the natural
    /// order of the textbook path).
    pub ordering: Ordering,
    /// The sparse backend's numeric factorization and solves (supernodal,
    /// or the textbook simplicial method).
    pub factorization: Method,
}

/// How pinned vertices are held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pins {
    /// The assignment's penalty `½ w ‖p_c − t_c‖²`, `w = 1e10`.
    #[default]
    Penalty,
    /// Removed from the unknowns ([`exact_pins`](super::exact_pins)).
    Exact,
}

impl std::str::FromStr for Pins {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        match text {
            "penalty" => Ok(Pins::Penalty),
            "exact" => Ok(Pins::Exact),
            _ => Err(format!("unknown pins '{text}' (expected penalty or exact)")),
        }
    }
}

impl SimulationOptions {
    /// The method and stopping rule of each step.
    pub fn step_control(&self) -> StepControl {
        StepControl {
            method: self.method,
            iterations: self.iterations,
            tolerance: self.tolerance,
            energy_tolerance: self.energy_tolerance,
            at_least_plain: self.at_least_plain,
            rho: self.rho,
            relaxation: self.relaxation,
            window: self.window,
            start: self.start,
        }
    }
}

impl Default for SimulationOptions {
    fn default() -> Self {
        SimulationOptions {
            delta_t: DELTA_T,
            iterations: ITERATIONS,
            wind: false,
            method: StepMethod::Plain,
            tolerance: None,
            energy_tolerance: None,
            at_least_plain: None,
            rho: None,
            relaxation: crate::sim::methods::chebyshev::DEFAULT_RELAXATION,
            window: DEFAULT_WINDOW,
            start: Start::Current,
            pins: Pins::Penalty,
            ordering: Ordering::default(),
            factorization: Method::default(),
        }
    }
}

/// A mass-spring network in motion, on the matrices of backend `B`.
///
/// # Examples
///
/// A single spring hanging from a pinned vertex, on the textbook sparse
/// path (natural order, simplicial Cholesky, plain substitutions):
///
/// ```
/// use masssprings::linalg::sparse::{Method, Ordering};
/// use masssprings::sim::simulation::SimulationOptions;
/// use masssprings::sim::{Simulation, Sparse};
///
/// let vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
/// let options = SimulationOptions {
///     ordering: Ordering::Natural,
///     factorization: Method::Simplicial,
///     ..SimulationOptions::default()
/// };
/// let mut simulation = Simulation::<Sparse>::new(&vertices, &[[0, 1]], 500.0, &[1.0, 1.0], &[0], options)?;
/// for _ in 0..10 {
///     simulation.step()?;
/// }
/// let [pinned, free] = [simulation.positions()[0], simulation.positions()[1]];
/// assert!(pinned.iter().all(|x| x.abs() < 1e-6)); // held by the penalty w
/// assert!(free[1] < 0.0); // the free end falls
/// assert!((simulation.time() - 10.0 / 30.0).abs() < 1e-12);
/// # Ok::<(), masssprings::sim::SimulationError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Simulation<B: LinearAlgebra> {
    system: MassSpringSystem<B>,
    rest: Vec<[f64; 3]>,
    pinned: Vec<usize>,
    u_prev: Vec<[f64; 3]>,
    u_cur: Vec<[f64; 3]>,
    u_next: Vec<[f64; 3]>,
    f_ext: Vec<[f64; 3]>,
    options: SimulationOptions,
    /// Diagonal of the rest shape's bounding box (the wind's length scale).
    scale: f64,
    steps: usize,
    /// The vertex being dragged, if any (an extra, last pin).
    dragged: Option<usize>,
    /// The scene's masses, before [`Simulation::set_parameters`] scales them.
    masses: Vec<f64>,
    /// The factor the scene's masses are multiplied by.
    mass_scale: f64,
}

impl<B: LinearAlgebra> Simulation<B> {
    /// Precomputes the system for rest positions `vertices` and starts at rest.
    ///
    /// # Errors
    /// As [`fast_mass_springs_precomputation`](super::precomputation::fast_mass_springs_precomputation).
    pub fn new(
        vertices: &[[f64; 3]],
        springs: &[[usize; 2]],
        k: f64,
        masses: &[f64],
        pinned: &[usize],
        options: SimulationOptions,
    ) -> Result<Self, SimulationError> {
        let how = SparseFactorization {
            ordering: options.ordering,
            method: options.factorization,
        };
        let mut system = fast_mass_springs_precomputation_with::<B>(
            vertices,
            springs,
            k,
            masses,
            pinned,
            options.delta_t,
            how,
        )?;
        if options.pins == Pins::Exact {
            system.use_exact_pins(how)?;
        }
        if !multiplies_by_q(options.method) {
            system.release_q(); // the step only solves with Q
        }
        let n = vertices.len();
        Ok(Simulation {
            system,
            rest: vertices.to_vec(),
            pinned: pinned.to_vec(),
            u_prev: vertices.to_vec(),
            u_cur: vertices.to_vec(),
            u_next: vec![[0.0; 3]; n],
            f_ext: vec![[0.0; 3]; n],
            options,
            scale: bounding_box_diagonal(vertices),
            steps: 0,
            dragged: None,
            masses: masses.to_vec(),
            mass_scale: 1.0,
        })
    }

    /// The simulation of a loaded scene, starting at rest.
    ///
    /// # Errors
    /// As [`fast_mass_springs_precomputation`](super::precomputation::fast_mass_springs_precomputation).
    pub fn from_scene(scene: &Scene, options: SimulationOptions) -> Result<Self, SimulationError> {
        Self::new(
            &scene.vertices,
            &scene.springs,
            scene.k,
            &scene.masses,
            &scene.pinned,
            options,
        )
    }

    /// Advances one time step.
    ///
    /// # Errors
    /// [`SimulationError::NotFinite`]; the state is then left as it was.
    pub fn step(&mut self) -> Result<StepReport, SimulationError> {
        let control = self.options.step_control();
        self.step_with(&control, None)
    }

    /// Advances one time step solved as `control` says, showing every
    /// iterate to `observer` (as `masssprings converge` does).
    ///
    /// # Errors
    /// As [`Simulation::step`].
    pub fn step_with(
        &mut self,
        control: &StepControl,
        observer: Option<Observer<'_>>,
    ) -> Result<StepReport, SimulationError> {
        if multiplies_by_q(control.method) {
            self.system.hold_q();
        }
        external_forces(
            &self.u_cur,
            self.time(),
            self.options.wind,
            self.scale,
            &mut self.f_ext,
        );
        let report = solve_step(
            &mut self.system,
            control,
            &self.f_ext,
            &self.u_prev,
            &self.u_cur,
            &mut self.u_next,
            observer,
        )?;
        std::mem::swap(&mut self.u_prev, &mut self.u_cur); // U_prev ← U_cur
        std::mem::swap(&mut self.u_cur, &mut self.u_next); // U_cur ← U
        self.steps += 1;
        Ok(report)
    }

    /// The current positions `U_cur`.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.u_cur
    }

    /// The positions one step earlier, `U_prev`.
    pub fn previous_positions(&self) -> &[[f64; 3]] {
        &self.u_prev
    }

    /// The rest positions `V`.
    pub fn rest_positions(&self) -> &[[f64; 3]] {
        &self.rest
    }

    /// The pinned vertices of the scene (not counting a dragged one).
    pub fn pinned(&self) -> &[usize] {
        &self.pinned
    }

    /// Steps taken since the start (or the last reset).
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Simulated time, `steps · Δt`.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.options.delta_t
    }

    /// The precomputed system (matrices, factorization). Its `Q` is
    /// released unless the method multiplies by it: read it through
    /// [`MassSpringSystem::q`].
    pub fn system(&self) -> &MassSpringSystem<B> {
        &self.system
    }

    /// What the simulation holds, in bytes (arrays' lengths), item by
    /// item: the system's ([`MassSpringSystem::bytes`]) and the state.
    pub fn bytes(&self) -> Vec<(&'static str, usize)> {
        use std::mem::size_of_val as bytes;
        let mut items = self.system.bytes();
        let state = [
            &self.rest,
            &self.u_prev,
            &self.u_cur,
            &self.u_next,
            &self.f_ext,
        ];
        items.push((
            "state: rest, previous, current, next positions, forces, masses",
            state.iter().map(|v| bytes(&v[..])).sum::<usize>()
                + bytes(&self.masses[..])
                + bytes(&self.pinned[..]),
        ));
        items
    }

    /// Is the wind blowing?
    pub fn wind(&self) -> bool {
        self.options.wind
    }

    /// Turns the wind on or off.
    pub fn set_wind(&mut self, wind: bool) {
        self.options.wind = wind;
    }

    /// Spring stiffness `k`, time step `Δt` and the factor on the scene's
    /// masses: changes `Q`'s values, so `Q` is refactored (numerically, on
    /// the pattern already analysed). The state is kept.
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] for values not positive and
    /// finite; a factorization error (the previous values then stay).
    pub fn set_parameters(
        &mut self,
        k: f64,
        delta_t: f64,
        mass_scale: f64,
    ) -> Result<(), SimulationError> {
        let masses: Vec<f64> = self.masses.iter().map(|&m| m * mass_scale).collect();
        self.system.set_parameters(k, delta_t, &masses)?;
        self.options.delta_t = delta_t;
        self.mass_scale = mass_scale;
        Ok(())
    }

    /// The factor on the scene's masses.
    pub fn mass_scale(&self) -> f64 {
        self.mass_scale
    }

    /// The options the simulation runs with.
    pub fn options(&self) -> &SimulationOptions {
        &self.options
    }

    /// Local/global iterations per step from the next step on.
    pub fn set_iterations(&mut self, iterations: usize) {
        self.options.iterations = iterations;
    }

    /// Solves later steps by `method`, with `tolerance` (nothing to
    /// refactor: every method uses the same `Q`).
    pub fn set_method(&mut self, method: StepMethod, tolerance: Option<f64>) {
        self.options.method = method;
        self.options.tolerance = tolerance;
    }

    /// Stops later steps by the energy's progress (`None`: no such rule).
    pub fn set_energy_tolerance(&mut self, energy_tolerance: Option<f64>) {
        self.options.energy_tolerance = energy_tolerance;
    }

    /// Holds later steps to at least `multiple` plain iterations' worth of
    /// decrease (`None`: no such floor).
    pub fn set_at_least_plain(&mut self, multiple: Option<f64>) {
        self.options.at_least_plain = multiple;
    }

    /// Where later steps start their iterations.
    pub fn set_start(&mut self, start: Start) {
        self.options.start = start;
    }

    /// Back to rest, time 0, nothing dragged.
    ///
    /// # Errors
    /// A factorization error when a drag had to be undone.
    pub fn reset(&mut self) -> Result<(), SimulationError> {
        self.end_drag()?;
        self.u_prev.copy_from_slice(&self.rest);
        self.u_cur.copy_from_slice(&self.rest);
        self.steps = 0;
        Ok(())
    }

    /// Continues from a saved state: `U_prev`, `U_cur` and the number of
    /// steps they are after the start (for the wind's clock).
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] when a state does not have one
    /// finite row per vertex.
    pub fn set_state(
        &mut self,
        u_prev: &[[f64; 3]],
        u_cur: &[[f64; 3]],
        steps: usize,
    ) -> Result<(), SimulationError> {
        let n = self.rest.len();
        for state in [u_prev, u_cur] {
            if state.len() != n || state.iter().flatten().any(|x| !x.is_finite()) {
                return Err(SimulationError::InvalidInput(format!(
                    "a state needs {n} finite positions, got {}",
                    state.len()
                )));
            }
        }
        self.u_prev.copy_from_slice(u_prev);
        self.u_cur.copy_from_slice(u_cur);
        self.steps = steps;
        Ok(())
    }

    /// Starts dragging `vertex` (0-based) toward `target`: it becomes an
    /// extra pin, which changes `Q`'s values and refactors it.
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] for a vertex out of range; a
    /// factorization error.
    pub fn start_drag(&mut self, vertex: usize, target: [f64; 3]) -> Result<(), SimulationError> {
        if vertex >= self.rest.len() {
            return Err(SimulationError::InvalidInput(format!(
                "vertex {vertex} is beyond the {} vertices",
                self.rest.len()
            )));
        }
        let mut pins = self.pinned.clone();
        pins.push(vertex);
        let mut targets = self.pin_rest_targets();
        targets.push(target);
        self.system.set_pins(&pins, &targets)?;
        self.dragged = Some(vertex);
        Ok(())
    }

    /// Moves the dragged vertex's target (the right-hand side only).
    ///
    /// # Errors
    /// None in practice; see [`MassSpringSystem::set_pin_targets`].
    pub fn drag_to(&mut self, target: [f64; 3]) -> Result<(), SimulationError> {
        if self.dragged.is_some() {
            let mut targets = self.pin_rest_targets();
            targets.push(target);
            self.system.set_pin_targets(&targets)?;
        }
        Ok(())
    }

    /// Lets go of the dragged vertex (restores the scene's pins).
    ///
    /// # Errors
    /// A factorization error.
    pub fn end_drag(&mut self) -> Result<(), SimulationError> {
        if self.dragged.take().is_some() {
            let targets = self.pin_rest_targets();
            self.system.set_pins(&self.pinned.clone(), &targets)?;
        }
        Ok(())
    }

    /// The vertex being dragged.
    pub fn dragged(&self) -> Option<usize> {
        self.dragged
    }

    /// Rest positions of the scene's pins, `C V`.
    fn pin_rest_targets(&self) -> Vec<[f64; 3]> {
        self.pinned.iter().map(|&i| self.rest[i]).collect()
    }
}

/// Does a step by `method` multiply by `Q` (not only solve with its
/// factorization)? L-BFGS does, for its initial Hessian.
fn multiplies_by_q(method: StepMethod) -> bool {
    method == StepMethod::Lbfgs
}
