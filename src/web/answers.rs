//! What the module answers and reads as JSON: the scene as the page draws
//! it, a step's record, a simulation's part of the viewer's status, and the
//! settings a page sends. The names are those of the viewer's HTTP API
//! (`src/app/view/api.rs`, whose step record is used as it is), so that the
//! page reads either backend alike.

use crate::app::view::api::StepRecord;
use crate::app::view::display_mesh::{display_mesh, DisplayMesh};
use crate::app::view::rules::{converged, functions, name_of, solver_names};
use masssprings::mesh::Scene;
use masssprings::sim::methods::Carried;
use masssprings::sim::{Simulation, Sparse, StepMethod, StepReport};
use serde::{Deserialize, Serialize};

/// The backend the module runs on.
pub const BACKEND: &str = "sparse";

/// A scene read from the files given.
#[derive(Debug, Serialize)]
pub struct SceneAnswer {
    /// What the page draws (the viewer's `/api/scene`); textured when the
    /// texture is readable.
    pub mesh: DisplayMesh,
    /// The texture's name among the files given, when the scene names one
    /// that starts as a PNG does (the page decodes it).
    pub texture: Option<String>,
    /// Why the texture the scene names cannot be used, in the command
    /// line's words (the scene is drawn without it).
    pub texture_problem: Option<String>,
}

impl SceneAnswer {
    /// The answer for `scene`, with its texture's name or problem.
    pub fn of(scene: &Scene, texture: Result<Option<String>, String>) -> SceneAnswer {
        let (texture, texture_problem) = match texture {
            Ok(name) => (name, None),
            Err(problem) => (None, Some(problem)),
        };
        SceneAnswer {
            mesh: display_mesh(scene, texture.is_some(), BACKEND),
            texture,
            texture_problem,
        }
    }
}

/// The options of a new simulation.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NewSimulation {
    /// `assignment` (the default), `textbook` (the handout's sparse code),
    /// `accuracy-assignment` (the fast mode) or `converged`: the viewer's
    /// names.
    #[serde(default = "assignment")]
    pub solver: String,
    /// The assignment viewer's wind.
    #[serde(default)]
    pub wind: bool,
}

fn assignment() -> String {
    "assignment".into()
}

/// How later steps are solved, as the page's method picker and boxes ask
/// it (the viewer's `set_method`: the rules absent are none, the start
/// absent is kept).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MethodSettings {
    /// `plain`, `chebyshev`, `anderson`, `lbfgs` or `newton`.
    pub method: String,
    #[serde(default)]
    pub tolerance: Option<f64>,
    #[serde(default)]
    pub energy_tolerance: Option<f64>,
    #[serde(default)]
    pub at_least_plain: Option<f64>,
    /// `current` or `inertial`.
    #[serde(default)]
    pub start: Option<String>,
}

/// What one step did, `report`, a step `simulation` just took: the
/// viewer's record of it, but its time (`ms`, which the page's worker
/// measures around the call) and the distance to a second simulation
/// (which the worker measures when comparing).
pub fn step_record(report: StepReport, simulation: &Simulation<Sparse>) -> StepRecord {
    StepRecord {
        step: simulation.steps(),
        iterations: report.iterations,
        energy_decrease: report.energy_decrease,
        relative_gradient: report.relative_gradient,
        converged: converged(report.stop),
        stop: report.stop.name(),
        energy: simulation.mechanical_energy(),
        ms: 0.0,
        distance: None,
    }
}

/// A simulation now: its part of the viewer's status, and what the page
/// needs to continue it elsewhere.
#[derive(Debug, Serialize)]
pub struct SimulationAnswer {
    pub steps: usize,
    /// Simulated time, seconds.
    pub time: f64,
    /// The mechanical energy (`Simulation::mechanical_energy`).
    pub energy: f64,
    pub k: f64,
    pub delta_t: f64,
    pub mass_scale: f64,
    pub wind: bool,
    pub backend: &'static str,
    /// Its solver's name (`null`: the expert's own method and rules).
    pub solver: Option<&'static str>,
    /// Which path and functions run its step.
    pub functions: String,
    pub method: &'static str,
    pub iterations: usize,
    pub tolerance: Option<f64>,
    pub energy_tolerance: Option<f64>,
    pub at_least_plain: Option<f64>,
    pub start: &'static str,
    pub plain_first: bool,
    /// `native` or `portable` (always `portable` in WebAssembly).
    pub kernels: &'static str,
    pub dragged: Option<usize>,
    /// What the methods carry from one step to the next (for
    /// `ms_set_state`).
    pub carried: Carried,
}

impl SimulationAnswer {
    /// The answer for `simulation`.
    pub fn of(simulation: &Simulation<Sparse>) -> SimulationAnswer {
        let options = simulation.options();
        let step = &options.step;
        SimulationAnswer {
            steps: simulation.steps(),
            time: simulation.time(),
            energy: simulation.mechanical_energy(),
            k: simulation.k(),
            delta_t: options.delta_t,
            mass_scale: simulation.mass_scale(),
            wind: options.wind,
            backend: BACKEND,
            solver: name_of(options),
            functions: functions(options, BACKEND),
            method: step.method.name(),
            iterations: step.iterations,
            tolerance: step.tolerance,
            energy_tolerance: step.energy_tolerance,
            at_least_plain: step.at_least_plain,
            start: step.start.name(),
            plain_first: step.plain_first,
            kernels: options.kernels.name(),
            dragged: simulation.dragged(),
            carried: simulation.carried(),
        }
    }
}

/// The names the page lists in its pickers.
#[derive(Debug, Serialize)]
pub struct Names {
    /// Every method (`StepMethod::ALL`).
    pub methods: Vec<&'static str>,
    /// Every solver (`Solver::ALL`).
    pub solvers: Vec<&'static str>,
}

impl Names {
    pub fn new() -> Names {
        Names {
            methods: StepMethod::ALL.map(StepMethod::name).to_vec(),
            solvers: solver_names(),
        }
    }
}

/// JSON of `value` (plain values always serialise).
pub fn json(value: &impl Serialize) -> String {
    serde_json::to_string(value).expect("plain values serialise")
}
