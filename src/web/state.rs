//! What the module keeps between calls, and the work of each export: the
//! files given, the scene read from them, the simulations (by handle),
//! and the room for the page's text in.

use crate::answers::{json, NewSimulation, SceneAnswer, SimulationAnswer, StepAnswer, StepSettings};
use crate::app::view::naming::options_named;
use masssprings::files::{max_input_bytes, InMemory, Source};
use masssprings::linalg::kernels::Kernels;
use masssprings::memory;
use masssprings::mesh::{load_scene_from, Scene, PNG_SIGNATURE};
use masssprings::sim::methods::Carried;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Simulation, Sparse, Start, StepControl, StepMethod};
use std::path::PathBuf;

/// The most iterations a step may take: a step must end within moments
/// (the page's stop ends a longer one by starting a fresh module).
pub const MAX_ITERATIONS: usize = 1000;

/// The module's state.
#[derive(Debug, Default)]
pub struct State {
    /// The page's text in for the next call (a name, JSON, a state).
    input: Vec<u8>,
    /// The files given.
    files: InMemory,
    /// The scene read last, and the JSON file it was read from.
    scene: Option<(Scene, PathBuf)>,
    /// The simulations; handle `h` is entry `h − 1`.
    simulations: Vec<Option<Simulation<Sparse>>>,
}

/// Sets the memory limit from the page's budget of `bytes`.
pub fn set_budget(bytes: f64) -> Result<String, String> {
    if !(bytes.is_finite() && bytes >= 1.0) {
        return Err(format!("a budget of {bytes} bytes is not a memory budget"));
    }
    let source = "half of the page's budget, from the memory of this device";
    match memory::set_budget(bytes as u64, source) {
        Ok(()) => Ok(String::new()),
        Err(limit) => Err(format!(
            "the memory limit is decided already: {} bytes ({})",
            limit.bytes, limit.source
        )),
    }
}

impl State {
    /// Room for `length` bytes of text in, at most the input limit.
    pub fn input_room(&mut self, length: u32) -> Result<*mut u8, String> {
        let max = max_input_bytes();
        if u64::from(length) > max {
            return Err(format!(
                "{length} bytes are more than the {max} the module reads at once (an eighth of \
                 the memory limit, see docs/reliability.md)"
            ));
        }
        self.input = vec![0; length as usize];
        Ok(self.input.as_mut_ptr())
    }

    /// The input, as text.
    fn input_text(&self) -> Result<&str, String> {
        std::str::from_utf8(&self.input).map_err(|e| format!("the input is not UTF-8: {e}"))
    }

    /// The input, as JSON of `T`.
    fn input_json<T: serde::de::DeserializeOwned>(&self) -> Result<T, String> {
        serde_json::from_str(self.input_text()?).map_err(|e| e.to_string())
    }

    /// Forgets the files given.
    pub fn clear_files(&mut self) {
        self.files = InMemory::new();
    }

    /// Room for the file named in the input, `length` bytes.
    pub fn file_room(&mut self, length: f64) -> Result<*mut u8, String> {
        let name = PathBuf::from(self.input_text()?);
        if !(length.is_finite() && length >= 0.0) {
            return Err(format!("{}: a length of {length} bytes", name.display()));
        }
        let room = self.files.reserve(&name, length as u64);
        room.map(<[u8]>::as_mut_ptr).map_err(|e| e.to_string())
    }

    /// Reads the scene named in the input from the files given (the
    /// simulations of the scene before are forgotten first, so that the new
    /// one has their memory).
    pub fn load_scene(&mut self) -> Result<String, String> {
        let path = PathBuf::from(self.input_text()?);
        self.simulations.clear();
        self.scene = None;
        let scene = load_scene_from(&self.files, &path).map_err(|e| e.to_string())?;
        let texture = self.texture(&scene);
        let answer = json(&SceneAnswer::of(&scene, texture));
        self.scene = Some((scene, path));
        Ok(answer)
    }

    /// The name of the scene's texture among the files given, checked as the
    /// command line checks it (a PNG's signature); `None` without one.
    fn texture(&self, scene: &Scene) -> Result<Option<String>, String> {
        let Some(path) = &scene.texture else {
            return Ok(None);
        };
        self.files
            .bytes_of_format(path, PNG_SIGNATURE, "PNG")
            .map(|_| Some(path.display().to_string()))
            .map_err(|e| format!("texture {e}"))
    }

    /// A new simulation of the scene, as the options in the input say.
    pub fn new_simulation(&mut self) -> Result<i32, String> {
        let wanted: NewSimulation = self.input_json()?;
        let (scene, path) = self.scene.as_ref().ok_or("no scene is loaded")?;
        let base = SimulationOptions {
            wind: wanted.wind,
            kernels: Kernels::Portable,
            ..SimulationOptions::default()
        };
        let options = options_named(base, &wanted.solver)?;
        let simulation = Simulation::<Sparse>::from_scene(scene, options).map_err(|error| {
            format!("{}: the precomputation failed: {error}", path.display())
        })?;
        self.simulations.push(Some(simulation));
        Ok(self.simulations.len() as i32)
    }

    /// Forgets simulation `handle`.
    pub fn free_simulation(&mut self, handle: i32) {
        if let Ok(slot) = self.slot(handle) {
            *slot = None;
        }
    }

    /// The entry of `handle`.
    fn slot(&mut self, handle: i32) -> Result<&mut Option<Simulation<Sparse>>, String> {
        usize::try_from(handle)
            .ok()
            .and_then(|h| h.checked_sub(1))
            .and_then(|index| self.simulations.get_mut(index))
            .ok_or_else(|| format!("there is no simulation {handle}"))
    }

    /// Simulation `handle`.
    fn simulation(&mut self, handle: i32) -> Result<&mut Simulation<Sparse>, String> {
        let slot = self.slot(handle)?;
        slot.as_mut()
            .ok_or_else(|| format!("simulation {handle} was freed"))
    }

    /// One step of simulation `handle`.
    pub fn step(&mut self, handle: i32) -> Result<String, String> {
        self.steps(handle, 1)
    }

    /// `count` steps of simulation `handle`, answering the last one's
    /// report.
    pub fn steps(&mut self, handle: i32, count: u32) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        let mut last = None;
        for _ in 0..count {
            last = Some(simulation.step().map_err(|e| e.to_string())?);
        }
        last.map_or(Ok(String::new()), |report| {
            Ok(json(&StepAnswer::of(report, simulation)))
        })
    }

    /// Where the positions of simulation `handle` are (the previous ones
    /// with `previous`); null for no such simulation.
    pub fn positions(&mut self, handle: i32, previous: bool) -> *const f64 {
        match self.simulation(handle) {
            Ok(s) if previous => s.previous_positions().as_flattened().as_ptr(),
            Ok(s) => s.positions().as_flattened().as_ptr(),
            Err(_) => std::ptr::null(),
        }
    }

    /// What simulation `handle` is now, as JSON.
    pub fn describe(&mut self, handle: i32) -> Result<String, String> {
        Ok(json(&SimulationAnswer::of(self.simulation(handle)?)))
    }

    /// New `[k, Δt, mass scale]` for simulation `handle`.
    pub fn set_parameters(&mut self, handle: i32, values: [f64; 3]) -> Result<String, String> {
        let [k, delta_t, mass_scale] = values;
        let simulation = self.simulation(handle)?;
        simulation
            .set_parameters(k, delta_t, mass_scale)
            .map(|()| String::new())
            .map_err(|e| e.to_string())
    }

    /// Wind on or off.
    pub fn set_wind(&mut self, handle: i32, wind: bool) -> Result<String, String> {
        self.simulation(handle)?.set_wind(wind);
        Ok(String::new())
    }

    /// How later steps of simulation `handle` are solved (the settings in
    /// the input): as the viewer's method picker, the budget and the
    /// stopping rules checked as the command line checks them.
    pub fn set_step(&mut self, handle: i32) -> Result<String, String> {
        let settings: StepSettings = self.input_json()?;
        let simulation = self.simulation(handle)?;
        let step = step_control(simulation.options().step, &settings)?;
        simulation
            .set_step(step)
            .map(|()| String::new())
            .map_err(|e| e.to_string())
    }

    /// Back to rest.
    pub fn reset(&mut self, handle: i32) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        simulation.reset().map_err(|e| e.to_string())?;
        Ok(String::new())
    }

    /// Continues simulation `handle` from the state in the input, `steps`
    /// steps after the start, at simulated time `time`.
    pub fn set_state(&mut self, handle: i32, steps: f64, time: f64) -> Result<String, String> {
        let (u_prev, u_cur, carried) = self.input_state(handle)?;
        if !(steps.is_finite() && steps >= 0.0 && steps.fract() == 0.0) {
            return Err(format!("{steps} steps: a step count is a whole number"));
        }
        if !(time.is_finite() && time >= 0.0) {
            return Err(format!("a simulated time of {time} s"));
        }
        let simulation = self.simulation(handle)?;
        simulation
            .set_state(&u_prev, &u_cur, steps as usize)
            .map_err(|e| e.to_string())?;
        if simulation.time() != time {
            // Δt changed on the way; otherwise the clock stays `steps · Δt`,
            // so that the wind's later times round as in the run continued
            simulation.set_time(time);
        }
        simulation.carry(carried);
        Ok(String::new())
    }

    /// `U_prev`, `U_cur` and what the methods carried, from the input.
    #[allow(clippy::type_complexity)]
    fn input_state(
        &mut self,
        handle: i32,
    ) -> Result<(Vec<[f64; 3]>, Vec<[f64; 3]>, Carried), String> {
        let n = self.simulation(handle)?.positions().len();
        let numbers = 6 * n * 8;
        if self.input.len() < numbers {
            return Err(format!("a state of {n} vertices needs {numbers} bytes of positions"));
        }
        let rows: Vec<[f64; 3]> = self.input[..numbers]
            .chunks_exact(24)
            .map(|row| std::array::from_fn(|c| le_f64(&row[8 * c..8 * c + 8])))
            .collect();
        let carried = std::str::from_utf8(&self.input[numbers..])
            .map_err(|e| e.to_string())
            .and_then(|text| serde_json::from_str(text).map_err(|e| e.to_string()))?;
        let (u_prev, u_cur) = rows.split_at(n);
        Ok((u_prev.to_vec(), u_cur.to_vec(), carried))
    }

    /// Starts dragging `vertex` of simulation `handle` toward `target`.
    pub fn drag_start(
        &mut self,
        handle: i32,
        vertex: u32,
        target: [f64; 3],
    ) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        let vertex = vertex as usize;
        if simulation.pinned().contains(&vertex) {
            return Err(format!("vertex {vertex} is pinned"));
        }
        check_target(target)?;
        simulation
            .start_drag(vertex, target)
            .map(|()| String::new())
            .map_err(|e| e.to_string())
    }

    /// Moves the dragged vertex's target.
    pub fn drag_to(&mut self, handle: i32, target: [f64; 3]) -> Result<String, String> {
        check_target(target)?;
        let simulation = self.simulation(handle)?;
        simulation
            .drag_to(target)
            .map(|()| String::new())
            .map_err(|e| e.to_string())
    }

    /// Lets go.
    pub fn drag_end(&mut self, handle: i32) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        simulation.end_drag().map_err(|e| e.to_string())?;
        Ok(String::new())
    }
}

/// A drag target must be finite.
fn check_target(target: [f64; 3]) -> Result<(), String> {
    match target.iter().all(|x| x.is_finite()) {
        true => Ok(()),
        false => Err(format!("the drag target {target:?} is not a point")),
    }
}

/// `current` changed as `settings` say: the method (L-BFGS's plain
/// iterations first kept while the method stays), the budget, the rules
/// (absent: none) and the start (absent: kept).
fn step_control(current: StepControl, settings: &StepSettings) -> Result<StepControl, String> {
    let method: StepMethod = match &settings.method {
        Some(name) => name.parse()?,
        None => current.method,
    };
    let start: Start = match &settings.start {
        Some(name) => name.parse()?,
        None => current.start,
    };
    let iterations = settings.iterations.unwrap_or(current.iterations);
    if !(1..=MAX_ITERATIONS).contains(&iterations) {
        return Err(format!(
            "{iterations} iterations: expected 1 to {MAX_ITERATIONS}"
        ));
    }
    let step = StepControl {
        method,
        iterations,
        tolerance: settings.tolerance,
        energy_tolerance: settings.energy_tolerance,
        at_least_plain: settings.at_least_plain,
        start,
        plain_first: current.plain_first && method == current.method,
        ..current
    };
    step.check_rules()?;
    Ok(step)
}

/// The `f64` of 8 little-endian bytes.
fn le_f64(bytes: &[u8]) -> f64 {
    f64::from_le_bytes(bytes.try_into().expect("8 bytes"))
}
