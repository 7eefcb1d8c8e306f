//! A running simulation: the state `(U_prev, U_cur)`, simulated time,
//! forces, and pins that can change (dragging a vertex).
//!
//! Starts at rest (`U_prev = U_cur = V`, zero velocity) and advances one
//! step at a time, by the fast path ([`solve_step`](super::step::solve_step))
//! or the handout's functions as written ([`textbook`](super::textbook),
//! `SimulationOptions::textbook`). The state vectors are swapped, not
//! copied, and no step of the fast path allocates.

use super::backend::{LinearAlgebra, SparseFactorization};
use super::control::{Accuracy, Pins, Start, StepControl, StepMethod};
use super::engine::{Engine, Network};
use super::error::SimulationError;
use super::forces::{bounding_box_diagonal, external_forces, GRAVITY};
use super::methods::Carried;
use super::monitor::Observer;
use super::precomputation::{MassSpringSystem, DELTA_T};
use super::step::{StepReport, StepState};
use crate::linalg::kernels::{self, Kernels};
use crate::linalg::sparse::{Method, Ordering, SupernodeMerging};
use crate::linalg::threads;
use crate::linalg::Cancel;
use crate::mesh::Scene;
use std::fmt;
use std::str::FromStr;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// How a simulation runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulationOptions {
    /// Time step (the assignment: 1/30 s).
    pub delta_t: f64,
    /// Add the assignment viewer's wind to gravity.
    pub wind: bool,
    /// How each step is solved: the method, the iterations (the
    /// assignment: 50 plain local/global iterations) and the stopping
    /// rules.
    pub step: StepControl,
    /// Pins by the assignment's penalty, or as exact constraints.
    pub pins: Pins,
    /// The sparse backend's fill-reducing ordering (AMD, or the natural
    /// order).
    pub ordering: Ordering,
    /// The sparse backend's numeric factorization and solves (supernodal,
    /// or the textbook simplicial method).
    pub factorization: Method,
    /// The supernodal factorization's supernodes (by default those of at
    /// most three columns merged).
    pub supernodes: SupernodeMerging,
    /// Run the handout's functions as written ([`textbook`](super::textbook))
    /// instead of the fast path: plain iterations, penalty pins, the
    /// simplicial factor; `step` then only gives the iteration count.
    pub textbook: bool,
    /// Threads of the fast path's factorization, solves and plain
    /// iterations, kept for the whole simulation (default: the cores
    /// available, [`threads::available`]). The positions are the same bits
    /// on any number; `1` runs the single-threaded code. The textbook path
    /// and the dense backend run on one thread whatever this says, and a
    /// scene gets at most one thread per [`VERTICES_PER_THREAD`] vertices.
    pub threads: usize,
    /// The native kernels (AVX2, FMA where the CPU has them) or the
    /// portable loops, which compute what a WebAssembly build computes, to
    /// the bit ([`kernels`](crate::linalg::kernels)): the precomputation
    /// and every step run with this choice.
    pub kernels: Kernels,
}

impl SimulationOptions {
    /// With `textbook`, are the other options what the handout's step
    /// does (plain iterations from `U_cur`, no stopping rule, penalty
    /// pins)? Always `Ok` without it.
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] saying what the textbook path runs.
    pub fn check_textbook(&self) -> Result<(), SimulationError> {
        let step = &self.step;
        let plain = step.method == StepMethod::Plain && !step.has_stopping_rule();
        let handouts = plain && step.start == Start::Current && self.pins == Pins::Penalty;
        if self.textbook && !handouts {
            return Err(SimulationError::InvalidInput(
                "the textbook path runs the handout's step as written: plain iterations from U_cur, no stopping rule, penalty pins".into(),
            ));
        }
        Ok(())
    }
}

/// The ways of solving a step this crate is about, by name: what the
/// command line's `--textbook` and `--accuracy` select and the viewer's
/// "solve" picker offers. [`SimulationOptions::solved_by`] is the one rule
/// that turns a name into options, [`SimulationOptions::solver`] the way
/// back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Solver {
    /// The assignment's step on the fast path: 50 plain local/global
    /// iterations from `pᵗ`, penalty pins.
    Assignment,
    /// The same step by the handout's functions as written
    /// ([`textbook`](super::textbook)), dense or sparse as the backend is.
    Textbook,
    /// Every step solved to a named accuracy, as fast as the crate knows
    /// how ([`StepControl::for_accuracy`]).
    Accuracy(Accuracy),
}

impl Solver {
    /// Every solver, in the order the docs present them.
    pub const ALL: [Solver; 3] = [
        Solver::Assignment,
        Solver::Textbook,
        Solver::Accuracy(Accuracy::Assignment),
    ];

    /// Its name (the viewer's; the command line says `--textbook` and
    /// `--accuracy assignment`).
    pub fn name(self) -> &'static str {
        match self {
            Solver::Assignment => "assignment",
            Solver::Textbook => "textbook",
            Solver::Accuracy(Accuracy::Assignment) => "accuracy-assignment",
        }
    }
}

impl fmt::Display for Solver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Solver {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Solver::ALL
            .into_iter()
            .find(|solver| solver.name() == text)
            .ok_or_else(|| {
                format!(
                    "unknown solver '{text}' (expected assignment, textbook or accuracy-assignment)"
                )
            })
    }
}

impl SimulationOptions {
    /// These options solved by `solver`: its method, budget and rules
    /// (nothing else of the step's: Chebyshev's and the history's settings
    /// go back to their defaults), the handout's code or the fast path, and
    /// the assignment's penalty pins; the time step, wind, backend settings
    /// and [`StepControl::measure`] stay. What `--textbook` and `--accuracy`
    /// do before the other flags are applied on top.
    pub fn solved_by(self, solver: Solver) -> SimulationOptions {
        let step = match solver {
            Solver::Accuracy(accuracy) => StepControl::for_accuracy(accuracy),
            Solver::Assignment | Solver::Textbook => StepControl::default(),
        };
        SimulationOptions {
            step: StepControl {
                measure: self.step.measure,
                ..step
            },
            textbook: solver == Solver::Textbook,
            pins: Pins::Penalty,
            ..self
        }
    }

    /// The solver these options are, if any: the handout's code (whatever
    /// its iteration count), an accuracy's method and rules (whatever its
    /// budget: [`Accuracy::of`]), or the assignment's 50 plain iterations;
    /// `None` for anything else (another method, a stopping rule, exact
    /// pins, another start or count).
    pub fn solver(&self) -> Option<Solver> {
        if self.textbook {
            return Some(Solver::Textbook);
        }
        if self.pins != Pins::Penalty {
            return None;
        }
        if let Some(accuracy) = Accuracy::of(&self.step) {
            return Some(Solver::Accuracy(accuracy));
        }
        let assignment = SimulationOptions::default().solved_by(Solver::Assignment);
        let rules = |c: &StepControl| (c.method, c.start, c.iterations, c.plain_first);
        let no_rule = !self.step.has_stopping_rule();
        (no_rule && rules(&self.step) == rules(&assignment.step)).then_some(Solver::Assignment)
    }
}

impl Default for SimulationOptions {
    fn default() -> Self {
        SimulationOptions {
            delta_t: DELTA_T,
            wind: false,
            step: StepControl::default(),
            pins: Pins::Penalty,
            ordering: Ordering::default(),
            factorization: Method::default(),
            supernodes: SupernodeMerging::default(),
            textbook: false,
            threads: threads::available(),
            kernels: Kernels::Native,
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
    engine: Engine<B>,
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
    /// The simulated time and the step count when `Δt` last changed (0
    /// and 0 until it does): the time is that time plus `Δt` for each
    /// step since.
    clock: (f64, usize),
    /// The vertex being dragged, if any (an extra, last pin), and where.
    dragged: Option<(usize, [f64; 3])>,
    /// The scene's masses, before [`Simulation::set_parameters`] scales them.
    masses: Vec<f64>,
    /// The factor the scene's masses are multiplied by.
    mass_scale: f64,
    /// Once set, the step in progress stops between two iterations
    /// ([`Simulation::set_cancel`]).
    cancel: Option<Arc<AtomicBool>>,
}

impl<B: LinearAlgebra> Simulation<B> {
    /// Precomputes the system for rest positions `vertices` and starts at rest.
    ///
    /// # Errors
    /// As [`MassSpringSystem::new`](super::precomputation::MassSpringSystem::new);
    /// [`SimulationError::InvalidInput`] for `textbook` options with
    /// another method, a stopping rule or exact pins.
    pub fn new(
        vertices: &[[f64; 3]],
        springs: &[[usize; 2]],
        k: f64,
        masses: &[f64],
        pinned: &[usize],
        options: SimulationOptions,
    ) -> Result<Self, SimulationError> {
        Self::build(vertices, springs, k, masses, pinned, options, None)
    }

    /// The simulation of a loaded scene, starting at rest, whose
    /// precomputation stops once `cancel` is set, with
    /// [`SimulationError::Cancelled`] and nothing kept: the dense backend
    /// looks at the flag while it forms `AᵀA` and factors `Q`, minutes and
    /// gigabytes on a large scene. Its steps look at the same flag
    /// ([`Simulation::set_cancel`]), and so do the precomputations the
    /// handout's functions make again when `k`, `Δt`, the masses or the
    /// pins change.
    ///
    /// # Errors
    /// As [`Simulation::new`]; [`SimulationError::Cancelled`].
    pub fn from_scene_cancellable(
        scene: &Scene,
        options: SimulationOptions,
        cancel: Arc<AtomicBool>,
    ) -> Result<Self, SimulationError> {
        Self::build(
            &scene.vertices,
            &scene.springs,
            scene.k,
            &scene.masses,
            &scene.pinned,
            options,
            Some(cancel),
        )
    }

    /// [`Simulation::new`], stopped by `cancel` if given.
    fn build(
        vertices: &[[f64; 3]],
        springs: &[[usize; 2]],
        k: f64,
        masses: &[f64],
        pinned: &[usize],
        options: SimulationOptions,
        cancel: Option<Arc<AtomicBool>>,
    ) -> Result<Self, SimulationError> {
        let network = Network {
            vertices,
            springs,
            k,
            masses,
            pinned,
            delta_t: options.delta_t,
            cancel: Cancel::on(cancel.as_deref()),
        };
        let engine = kernels::with(options.kernels, || new_engine::<B>(&network, &options))?;
        let n = vertices.len();
        Ok(Simulation {
            engine,
            rest: vertices.to_vec(),
            pinned: pinned.to_vec(),
            u_prev: vertices.to_vec(),
            u_cur: vertices.to_vec(),
            u_next: vec![[0.0; 3]; n],
            f_ext: vec![[0.0; 3]; n],
            options,
            scale: bounding_box_diagonal(vertices),
            steps: 0,
            clock: (0.0, 0),
            dragged: None,
            masses: masses.to_vec(),
            mass_scale: 1.0,
            cancel,
        })
    }

    /// The simulation of a loaded scene, starting at rest.
    ///
    /// # Errors
    /// As [`Simulation::new`].
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
        let control = self.options.step;
        self.step_with(&control, None)
    }

    /// Advances one time step solved as `control` says, showing every
    /// iterate to `observer` (as `masssprings converge` does). On the
    /// textbook path only the handout's step runs.
    ///
    /// # Errors
    /// As [`Simulation::step`].
    pub fn step_with(
        &mut self,
        control: &StepControl,
        observer: Option<Observer<'_>>,
    ) -> Result<StepReport, SimulationError> {
        if let Engine::Fast { system, .. } = &mut self.engine {
            if multiplies_by_q(control.method) {
                system.hold_q();
            }
        }
        external_forces(
            &self.u_cur,
            self.time(),
            self.options.wind,
            self.scale,
            &mut self.f_ext,
        );
        let state = StepState {
            f_ext: &self.f_ext,
            u_prev: &self.u_prev,
            u_cur: &self.u_cur,
        };
        let cancel = self.cancel.as_ref();
        let report = kernels::with(self.options.kernels, || {
            self.engine
                .step(control, state, &mut self.u_next, observer, cancel)
        })?;
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

    /// Simulated time: the sum of every step's own `Δt` since the start
    /// (`steps · Δt` while `Δt` has not changed).
    pub fn time(&self) -> f64 {
        let (time, steps) = self.clock;
        time + self.steps.saturating_sub(steps) as f64 * self.options.delta_t
    }

    /// Says that the current state is at simulated time `time` (a state
    /// carried over from a simulation whose `Δt` changed on the way; see
    /// [`Simulation::set_state`]).
    pub fn set_time(&mut self, time: f64) {
        self.clock = (time, self.steps);
    }

    /// The precomputed system of the fast path (matrices, factorization);
    /// `None` on the textbook path. Its `Q` is released unless the method
    /// multiplies by it: read it through [`MassSpringSystem::q`].
    pub fn system(&self) -> Option<&MassSpringSystem<B>> {
        match &self.engine {
            Engine::Fast { system, .. } => Some(system),
            Engine::Textbook { .. } => None,
        }
    }

    /// The threads the steps run on: those of the fast path's sparse
    /// supernodal factorization ([`SimulationOptions::threads`]); 1 on the
    /// textbook path, with the dense backend or the simplicial method.
    pub fn threads(&self) -> usize {
        match &self.engine {
            Engine::Fast { system, .. } => B::threads(&system.prefactorization),
            Engine::Textbook { .. } => 1,
        }
    }

    /// What advances the simulation: the fast path or the handout's
    /// functions.
    pub fn engine(&self) -> &Engine<B> {
        &self.engine
    }

    /// Spring stiffness `k`.
    pub fn k(&self) -> f64 {
        self.engine.k()
    }

    /// What the simulation holds, in bytes (arrays' lengths), item by
    /// item: the engine's and the state.
    pub fn bytes(&self) -> Vec<(&'static str, usize)> {
        use std::mem::size_of_val as bytes;
        let mut items = self.engine.bytes();
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

    /// Lets another thread stop a step in progress: once `flag` is set, the
    /// step stops between two iterations and returns
    /// [`SimulationError::Cancelled`], the state left at the last completed
    /// step (the caller clears the flag for the next). Costs one relaxed
    /// load per iteration; `plain` then forgoes its loop in the factor's
    /// order, which does not look between iterations (the same bits, a few
    /// per cent slower). `None` (the default): steps cannot be cancelled.
    pub fn set_cancel(&mut self, flag: Option<Arc<AtomicBool>>) {
        self.cancel = flag;
    }

    /// The mechanical energy of the state: the kinetic
    /// `½ Σ mᵢ ‖(U_cur − U_prev)ᵢ / Δt‖²`, the springs'
    /// `½ k Σ (‖pᵢ − pⱼ‖ − rᵢⱼ)²` and gravity's `−Σ g·(pᵢ − Vᵢ)` (a force
    /// per vertex, [`GRAVITY`]); zero at rest. The pins' penalty and the
    /// wind are left out. Implicit Euler loses some of it every step, even
    /// solved exactly; a step solved less far loses more. `O(n + m)`.
    pub fn mechanical_energy(&self) -> f64 {
        let dt = self.options.delta_t;
        let mut energy = 0.0;
        for (((now, before), rest), &m) in self
            .u_cur
            .iter()
            .zip(&self.u_prev)
            .zip(&self.rest)
            .zip(&self.masses)
        {
            let v: [f64; 3] = std::array::from_fn(|c| (now[c] - before[c]) / dt);
            let lowered: f64 = (0..3).map(|c| GRAVITY[c] * (now[c] - rest[c])).sum();
            energy +=
                0.5 * m * self.mass_scale * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - lowered;
        }
        let length = |p: &[[f64; 3]], [i, j]: [usize; 2]| {
            (0..3)
                .map(|c| (p[i][c] - p[j][c]).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        let k = self.k();
        for &spring in self.engine.springs() {
            let stretch = length(&self.u_cur, spring) - length(&self.rest, spring);
            energy += 0.5 * k * stretch * stretch;
        }
        energy
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
        self.remake(k, delta_t, &masses, None)?;
        if delta_t != self.options.delta_t {
            self.set_time(self.time()); // the steps so far took the old Δt
        }
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
        self.options.step.iterations = iterations;
        self.engine.set_iterations(iterations);
    }

    /// Solves later steps as `step` says: method, budget, rules and start
    /// at once (nothing to refactor: every method uses the same `Q`).
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] (as
    /// [`SimulationOptions::check_textbook`]) when the simulation runs the
    /// handout's code and `step` is not its step; nothing changes then.
    pub fn set_step(&mut self, step: StepControl) -> Result<(), SimulationError> {
        let wanted = SimulationOptions {
            step,
            ..self.options
        };
        wanted.check_textbook()?;
        self.options.step = step;
        self.engine.set_iterations(step.iterations);
        Ok(())
    }

    /// Solves later steps by `method`, with `tolerance` (nothing to
    /// refactor: every method uses the same `Q`).
    pub fn set_method(&mut self, method: StepMethod, tolerance: Option<f64>) {
        self.options.step.method = method;
        self.options.step.tolerance = tolerance;
    }

    /// Stops later steps by the energy's progress (`None`: no such rule).
    pub fn set_energy_tolerance(&mut self, energy_tolerance: Option<f64>) {
        self.options.step.energy_tolerance = energy_tolerance;
    }

    /// Holds later steps to at least `multiple` plain iterations' worth of
    /// decrease (`None`: no such floor).
    pub fn set_at_least_plain(&mut self, multiple: Option<f64>) {
        self.options.step.at_least_plain = multiple;
    }

    /// Where later steps start their iterations.
    pub fn set_start(&mut self, start: Start) {
        self.options.step.start = start;
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
        self.clock = (0.0, 0);
        Ok(())
    }

    /// Continues from a saved state: `U_prev`, `U_cur` and the number of
    /// steps they are after the start (for the wind's clock: the time is
    /// `steps · Δt` until [`Simulation::set_time`] says otherwise).
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
        self.clock = (0.0, 0);
        Ok(())
    }

    /// What the step's methods carry from one step to the next besides
    /// the state (Chebyshev's `ρ`, Newton's damping; nothing on the
    /// textbook path): with [`Simulation::set_state`] and
    /// [`Simulation::carry`], a run continued elsewhere steps to the same
    /// bits.
    pub fn carried(&self) -> Carried {
        match &self.engine {
            Engine::Fast { workspace, .. } => workspace.carried(),
            Engine::Textbook { .. } => Carried::default(),
        }
    }

    /// Takes up what the methods of an earlier run carried
    /// ([`Simulation::carried`]).
    pub fn carry(&mut self, carried: Carried) {
        if let Engine::Fast { workspace, .. } = &mut self.engine {
            workspace.carry(carried);
        }
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
        let masses = self.scaled_masses();
        let (k, delta_t) = (self.k(), self.options.delta_t);
        self.remake(k, delta_t, &masses, Some((vertex, target)))?;
        self.dragged = Some((vertex, target));
        Ok(())
    }

    /// Moves the dragged vertex's target (the right-hand side only).
    ///
    /// # Errors
    /// None in practice; see [`MassSpringSystem::set_pin_targets`].
    pub fn drag_to(&mut self, target: [f64; 3]) -> Result<(), SimulationError> {
        if let Some((vertex, _)) = self.dragged {
            let mut targets = self.pin_rest_targets();
            targets.push(target);
            kernels::with(self.options.kernels, || {
                self.engine.set_pin_targets(&targets)
            })?;
            self.dragged = Some((vertex, target));
        }
        Ok(())
    }

    /// Lets go of the dragged vertex (restores the scene's pins).
    ///
    /// # Errors
    /// A factorization error.
    pub fn end_drag(&mut self) -> Result<(), SimulationError> {
        if self.dragged.take().is_some() {
            let masses = self.scaled_masses();
            let (k, delta_t) = (self.k(), self.options.delta_t);
            self.remake(k, delta_t, &masses, None)?;
        }
        Ok(())
    }

    /// The vertex being dragged.
    pub fn dragged(&self) -> Option<usize> {
        self.dragged.map(|(vertex, _)| vertex)
    }

    /// Rest positions of the scene's pins, `C V`.
    fn pin_rest_targets(&self) -> Vec<[f64; 3]> {
        self.pinned.iter().map(|&i| self.rest[i]).collect()
    }

    /// The scene's masses times the mass factor in force.
    fn scaled_masses(&self) -> Vec<f64> {
        self.masses.iter().map(|&m| m * self.mass_scale).collect()
    }

    /// The precomputation again for stiffness `k`, time step `delta_t`,
    /// masses `masses` and the scene's pins, plus `drag` (a vertex and its
    /// target) as the last pin.
    fn remake(
        &mut self,
        k: f64,
        delta_t: f64,
        masses: &[f64],
        drag: Option<(usize, [f64; 3])>,
    ) -> Result<(), SimulationError> {
        let mut pins = self.pinned.clone();
        let mut targets = self.pin_rest_targets();
        if let Some((vertex, target)) = drag.or(self.dragged) {
            pins.push(vertex);
            targets.push(target);
        }
        let springs = self.engine.springs().to_vec();
        let network = Network {
            vertices: &self.rest,
            springs: &springs,
            k,
            masses,
            pinned: &pins,
            delta_t,
            cancel: Cancel::on(self.cancel.as_deref()),
        };
        kernels::with(self.options.kernels, || {
            self.engine.remake(&network, &targets)
        })
    }
}

/// The engine `options` ask for: the handout's functions, or the fast path
/// (which releases `Q` when its method only solves with it).
fn new_engine<B: LinearAlgebra>(
    network: &Network<'_>,
    options: &SimulationOptions,
) -> Result<Engine<B>, SimulationError> {
    if options.textbook {
        options.check_textbook()?;
        return Engine::textbook(network, options.ordering, options.step.iterations);
    }
    let how = SparseFactorization {
        ordering: options.ordering,
        method: options.factorization,
        supernodes: options.supernodes,
        threads: threads_for(network.vertices.len(), options.threads),
    };
    let mut engine = Engine::fast(network, how, options.pins)?;
    if let Engine::Fast { system, .. } = &mut engine {
        if !multiplies_by_q(options.step.method) {
            system.release_q(); // the step only solves with Q
        }
    }
    Ok(engine)
}

/// Does a step by `method` multiply by `Q` (not only solve with its
/// factorization)? L-BFGS does, for its initial Hessian.
fn multiplies_by_q(method: StepMethod) -> bool {
    method == StepMethod::Lbfgs
}

/// Vertices a thread must have to pay for itself: waking a thread and
/// meeting it at each barrier of an iteration cost microseconds, while a
/// whole step of the 81-vertex net takes about 90 µs on one thread. When
/// two threads could step the net and the 11-vertex chain, they made their
/// steps slower, not faster; the 3,200-vertex flag's is faster on two.
pub const VERTICES_PER_THREAD: usize = 500;

/// The threads a scene of `n` vertices steps on: those asked, at most one
/// per [`VERTICES_PER_THREAD`] vertices, at least one.
fn threads_for(n: usize, asked: usize) -> usize {
    asked.min(n / VERTICES_PER_THREAD).max(1)
}
