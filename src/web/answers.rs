//! What the module answers and reads as JSON: the scene, a step's report,
//! a simulation's state and options, and the options a page sends.

use masssprings::mesh::Scene;
use masssprings::sim::methods::Carried;
use masssprings::sim::{Sparse, StepReport};
use masssprings::sim::{Simulation, StepControl};
use serde::{Deserialize, Serialize};

/// A scene read from the files given: everything about it that does not
/// move, 0-based, arrays flattened.
#[derive(Debug, Serialize)]
pub struct SceneAnswer {
    /// The JSON file's stem (`flag`).
    pub name: String,
    /// Vertices.
    pub n: usize,
    /// The rest positions, `x y z` of each vertex.
    pub vertices: Vec<f64>,
    /// The springs, `i j` of each.
    pub springs: Vec<u32>,
    /// The pinned vertices.
    pub pinned: Vec<u32>,
    /// The corners of every face (2: the faces are springs).
    pub corners: usize,
    /// The faces' vertices, `corners` a face.
    pub faces: Vec<u32>,
    /// The OBJ's `vt`, `u v` of each.
    pub texture_coords: Vec<f64>,
    /// The faces' texture coordinates, `corners` a face; empty unless every
    /// corner has one.
    pub face_texture_coords: Vec<u32>,
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
        let indices = |list: &[usize]| list.iter().map(|&i| i as u32).collect::<Vec<u32>>();
        let (texture, texture_problem) = match texture {
            Ok(name) => (name, None),
            Err(problem) => (None, Some(problem)),
        };
        SceneAnswer {
            name: scene.name.clone(),
            n: scene.vertices.len(),
            vertices: scene.vertices.as_flattened().to_vec(),
            springs: indices(scene.springs.as_flattened()),
            pinned: indices(&scene.pinned),
            corners: scene.faces.first().map_or(0, Vec::len),
            faces: scene.faces.iter().flat_map(|face| indices(face)).collect(),
            texture_coords: scene.texture_coords.as_flattened().to_vec(),
            face_texture_coords: scene
                .face_texture_coords
                .iter()
                .flat_map(|face| indices(face))
                .collect(),
            texture,
            texture_problem,
        }
    }
}

/// The options of a new simulation.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NewSimulation {
    /// `assignment` (the default), `textbook` (the handout's sparse code)
    /// or `accuracy-assignment` (the fast mode): `Solver`'s names.
    #[serde(default = "assignment")]
    pub solver: String,
    /// The assignment viewer's wind.
    #[serde(default)]
    pub wind: bool,
}

fn assignment() -> String {
    "assignment".into()
}

/// How later steps are solved, as the page's method picker, sliders and
/// boxes say it (absent: kept as it is, but the tolerances, absent: none).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepSettings {
    /// `plain`, `chebyshev`, `anderson`, `lbfgs` or `newton`.
    pub method: Option<String>,
    pub iterations: Option<usize>,
    #[serde(default)]
    pub tolerance: Option<f64>,
    #[serde(default)]
    pub energy_tolerance: Option<f64>,
    #[serde(default)]
    pub at_least_plain: Option<f64>,
    /// `current` or `inertial`.
    pub start: Option<String>,
}

/// What one step did.
#[derive(Debug, Serialize)]
pub struct StepAnswer {
    pub method: &'static str,
    pub iterations: usize,
    /// Why it stopped (`Stop::name`: `iterations`, `tolerance`, ...).
    pub stop: &'static str,
    pub energy_decrease: Option<f64>,
    pub relative_gradient: Option<f64>,
}

impl From<StepReport> for StepAnswer {
    fn from(report: StepReport) -> StepAnswer {
        StepAnswer {
            method: report.method.name(),
            iterations: report.iterations,
            stop: report.stop.name(),
            energy_decrease: report.energy_decrease,
            relative_gradient: report.relative_gradient,
        }
    }
}

/// A simulation now: where it is and how it runs.
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
    /// The solver the options are (`null`: another method or rules).
    pub solver: Option<&'static str>,
    pub method: &'static str,
    pub iterations: usize,
    pub tolerance: Option<f64>,
    pub energy_tolerance: Option<f64>,
    pub at_least_plain: Option<f64>,
    pub start: &'static str,
    pub plain_first: bool,
    /// `fast` or `textbook` (the handout's functions as written).
    pub path: &'static str,
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
        let step: &StepControl = &options.step;
        SimulationAnswer {
            steps: simulation.steps(),
            time: simulation.time(),
            energy: simulation.mechanical_energy(),
            k: simulation.k(),
            delta_t: options.delta_t,
            mass_scale: simulation.mass_scale(),
            wind: options.wind,
            solver: options.solver().map(|solver| solver.name()),
            method: step.method.name(),
            iterations: step.iterations,
            tolerance: step.tolerance,
            energy_tolerance: step.energy_tolerance,
            at_least_plain: step.at_least_plain,
            start: step.start.name(),
            plain_first: step.plain_first,
            path: if options.textbook { "textbook" } else { "fast" },
            kernels: options.kernels.name(),
            dragged: simulation.dragged(),
            carried: simulation.carried(),
        }
    }
}

/// JSON of `value` (plain values always serialise).
pub fn json(value: &impl Serialize) -> String {
    serde_json::to_string(value).expect("plain values serialise")
}
