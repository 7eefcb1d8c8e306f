//! What the module keeps between calls, and the work of each export: the
//! room for the page's text in, the files given, the scenes read from them
//! and the simulations, each by handle.

use crate::answers::{
    json, step_record, MethodSettings, NewSimulation, SceneAnswer, SimulationAnswer,
};
use crate::app::view::rules::{check_parameters, method_step, name_of, options_named, DragReach};
use masssprings::files::{max_input_bytes, shown, InMemory, Source};
use masssprings::linalg::kernels::Kernels;
use masssprings::memory;
use masssprings::mesh::{load_scene_from, Scene, PNG_SIGNATURE};
use masssprings::sim::methods::Carried;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Simulation, SimulationError, Sparse, StepControl};
use std::path::PathBuf;

/// Things kept by handle: handle `h` is entry `h − 1` (`None` once freed).
#[derive(Debug)]
struct Handles<T>(Vec<Option<T>>);

impl<T> Default for Handles<T> {
    fn default() -> Self {
        Handles(Vec::new())
    }
}

impl<T> Handles<T> {
    /// Keeps `thing`; its handle.
    fn keep(&mut self, thing: T) -> i32 {
        self.0.push(Some(thing));
        self.0.len() as i32
    }

    /// The thing of `handle`, named `what` in the message when there is none.
    fn get(&mut self, handle: i32, what: &str) -> Result<&mut T, String> {
        usize::try_from(handle)
            .ok()
            .and_then(|h| h.checked_sub(1))
            .and_then(|index| self.0.get_mut(index))
            .and_then(Option::as_mut)
            .ok_or_else(|| format!("there is no {what} {handle}"))
    }

    /// Forgets the thing of `handle`, if any.
    fn free(&mut self, handle: i32) {
        if let Some(slot) = usize::try_from(handle)
            .ok()
            .and_then(|h| h.checked_sub(1))
            .and_then(|index| self.0.get_mut(index))
        {
            *slot = None;
        }
    }
}

/// The module's state.
#[derive(Debug, Default)]
pub struct State {
    /// The page's text in for the next call (a name, JSON, a state).
    input: Vec<u8>,
    /// The files given.
    files: InMemory,
    /// The scenes read, each with the JSON file it was read from.
    scenes: Handles<(Scene, PathBuf)>,
    simulations: Handles<Simulation<Sparse>>,
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

/// Nothing to answer.
fn done<E: ToString>(result: Result<(), E>) -> Result<String, String> {
    result.map(|()| String::new()).map_err(|e| e.to_string())
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

    /// Reads the scene named in the input from the files given: its handle,
    /// and its answer.
    pub fn load_scene(&mut self) -> Result<(i32, String), String> {
        let path = PathBuf::from(self.input_text()?);
        let scene = load_scene_from(&self.files, &path).map_err(|e| e.to_string())?;
        let answer = json(&SceneAnswer::of(&scene, self.texture(&scene)));
        Ok((self.scenes.keep((scene, path)), answer))
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

    /// Forgets scene `handle` (its simulations stay).
    pub fn free_scene(&mut self, handle: i32) {
        self.scenes.free(handle);
    }

    /// A new simulation of scene `scene`, as the options in the input say.
    pub fn new_simulation(&mut self, scene: i32) -> Result<i32, String> {
        let wanted: NewSimulation = self.input_json()?;
        let (scene, path) = self.scenes.get(scene, "scene")?;
        let base = SimulationOptions {
            wind: wanted.wind,
            kernels: Kernels::Portable,
            ..SimulationOptions::default()
        };
        let options = options_named(base, &wanted.solver)?;
        // named as the command line names it (`app::limits::precomputation_failed`)
        let simulation =
            Simulation::<Sparse>::from_scene(scene, options).map_err(|error| match error {
                SimulationError::QOverflow(why) => format!("{}: {why}", shown(path)),
                error => format!("{}: the precomputation failed: {error}", shown(path)),
            })?;
        Ok(self.simulations.keep(simulation))
    }

    /// Forgets simulation `handle`.
    pub fn free_simulation(&mut self, handle: i32) {
        self.simulations.free(handle);
    }

    /// Simulation `handle`.
    fn simulation(&mut self, handle: i32) -> Result<&mut Simulation<Sparse>, String> {
        self.simulations.get(handle, "simulation")
    }

    /// `count` steps of simulation `handle`, answering the last one's
    /// record.
    pub fn steps(&mut self, handle: i32, count: u32) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        let mut last = None;
        for _ in 0..count {
            last = Some(simulation.step().map_err(|e| e.to_string())?);
        }
        Ok(last.map_or(String::new(), |report| {
            json(&step_record(report, simulation))
        }))
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

    /// New `[k, Δt, mass scale]` (`Q` refactored when one changed) and
    /// iteration budget for simulation `handle`, within the sliders'
    /// ranges.
    pub fn set_parameters(
        &mut self,
        handle: i32,
        values: [f64; 3],
        iterations: u32,
    ) -> Result<String, String> {
        check_parameters(values, iterations as usize)?;
        let simulation = self.simulation(handle)?;
        let [k, delta_t, mass_scale] = values;
        let now = (simulation.k(), simulation.options().delta_t);
        if (now.0, now.1, simulation.mass_scale()) != (k, delta_t, mass_scale) {
            done(simulation.set_parameters(k, delta_t, mass_scale))?;
        }
        let step = StepControl {
            iterations: iterations as usize,
            ..simulation.options().step
        };
        done(simulation.set_step(step))
    }

    /// Wind on or off.
    pub fn set_wind(&mut self, handle: i32, wind: bool) -> Result<String, String> {
        self.simulation(handle)?.set_wind(wind);
        Ok(String::new())
    }

    /// Another method, tolerances, floor or start for later steps of
    /// simulation `handle` (the settings in the input), as the viewer's
    /// method picker and boxes ask.
    pub fn set_method(&mut self, handle: i32) -> Result<String, String> {
        let wanted: MethodSettings = self.input_json()?;
        let simulation = self.simulation(handle)?;
        let step = method_step(
            simulation.options().step,
            &wanted.method,
            [wanted.tolerance, wanted.energy_tolerance],
            wanted.at_least_plain,
            wanted.start.as_deref(),
        )?;
        simulation
            .set_step(step)
            .map(|()| String::new())
            .map_err(|why| format!("{why}; to change them, solve by another solver first"))
    }

    /// Back to rest.
    pub fn reset(&mut self, handle: i32) -> Result<String, String> {
        done(self.simulation(handle)?.reset())
    }

    /// Later steps of simulation `handle` as its solver's, or the
    /// assignment's.
    pub fn solver_step(&mut self, handle: i32) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        let initial = SimulationOptions::default();
        let step = match name_of(simulation.options()) {
            Some(name) => options_named(initial, name)?.step,
            None => initial.step,
        };
        done(simulation.set_step(step))
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
        done(simulation.set_state(&u_prev, &u_cur, steps as usize))?;
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
            return Err(format!(
                "a state of {n} vertices needs {numbers} bytes of positions"
            ));
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

    /// Starts dragging free `vertex` of simulation `handle` toward `target`.
    pub fn drag_start(
        &mut self,
        handle: i32,
        vertex: u32,
        target: [f64; 3],
    ) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        let vertex = vertex as usize;
        if vertex >= simulation.rest_positions().len() {
            return Err(format!("vertex {vertex} does not exist"));
        }
        if simulation.pinned().contains(&vertex) {
            return Err(format!("vertex {vertex} is pinned"));
        }
        DragReach::of(simulation.rest_positions()).check(target)?;
        done(simulation.start_drag(vertex, target))
    }

    /// Moves the dragged vertex's target.
    pub fn drag_to(&mut self, handle: i32, target: [f64; 3]) -> Result<String, String> {
        let simulation = self.simulation(handle)?;
        DragReach::of(simulation.rest_positions()).check(target)?;
        if simulation.dragged().is_none() {
            return Err("no vertex is being dragged".into());
        }
        done(simulation.drag_to(target))
    }

    /// Lets go.
    pub fn drag_end(&mut self, handle: i32) -> Result<String, String> {
        done(self.simulation(handle)?.end_drag())
    }
}

/// The `f64` of 8 little-endian bytes.
fn le_f64(bytes: &[u8]) -> f64 {
    f64::from_le_bytes(bytes.try_into().expect("8 bytes"))
}
