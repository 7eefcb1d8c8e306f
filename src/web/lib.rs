//! masssprings in a browser: the library compiled to WebAssembly
//! (`wasm32-unknown-unknown`), behind a thin layer of plain `extern "C"`
//! functions over the module's linear memory.
//!
//! The page's script (`masssprings.mjs` beside this file wraps every
//! function below) speaks to the module in four ways:
//!
//! * **numbers** in and out: handles, `k`, `Δt`, a vertex, a time;
//! * **text in** (a file name, options as JSON): the script asks
//!   [`ms_input`] for room, writes the UTF-8 bytes there and calls the
//!   function that reads them;
//! * **files in**: with a file's name in the input, [`ms_file`] makes room
//!   for its bytes among the files held in memory, after checking its
//!   length against the input limit, and the script copies them there;
//! * **text out**: a function that answers in words (JSON, or what went
//!   wrong) leaves them in the output, [`ms_output`] and
//!   [`ms_output_len`]; [`ms_positions`] points at a simulation's own
//!   positions, `3n` numbers, read in place.
//!
//! A function returns `0` (or a handle, `≥ 1`) when it did its work, `-1`
//! when it did not, with the message in the output: the same message the
//! command line gives (`flag.obj:12: ...`). A panic (a bug) leaves its
//! message in the output too, before the module traps; the page then
//! starts a fresh module.
//!
//! Why not `wasm-bindgen`: it would generate this layer, but it brings a
//! command-line tool that must match its crate's version exactly, a
//! generated script to ship, and a dozen crates into the workspace; what
//! crosses here is numbers, a few strings and arrays of `f64`, which
//! `masssprings.mjs` carries in two small classes.
//!
//! Everything the module keeps lives in one [`State`] (this thread's: a
//! WebAssembly module runs on one).

mod answers;
mod state;

/// The viewer's own files that say what the page is told, compiled here
/// too, so that both of the page's backends send it the same scene and the
/// same words: the scene as the page draws it (`display_mesh.rs`, with the
/// first view of `facing.rs` and the point masses' size of the renderer's
/// `look.rs`), what the page's controls may ask and the names of how a
/// step is solved (`rules.rs`), and a step's record (`api.rs`). They use
/// only the library; the modules are laid out as in the program, so that
/// their paths (`super::super::draw`) mean the same here.
#[allow(dead_code)] // the look's colours and the other names are the program's
#[path = "../app"]
mod app {
    pub mod draw {
        pub mod look;
    }
    pub mod view {
        pub mod api;
        pub mod display_mesh;
        pub mod facing;
        pub mod rules;
    }
}

pub use state::State;

use std::cell::RefCell;

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
    /// The last answer: a cell of its own, so that a panic's message can be
    /// left there while the state is in use.
    static OUTPUT: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Runs `work` on the module's state (the first call also keeps panics'
/// messages).
fn with_state<R>(work: impl FnOnce(&mut State) -> R) -> R {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(keep_panic_messages);
    STATE.with(|state| work(&mut state.borrow_mut()))
}

/// Leaves `text` in the output.
fn set_output(text: String) {
    OUTPUT.with(|output| *output.borrow_mut() = text);
}

/// Runs `work` on the module's state: `0` when it did its work (its
/// answer, if any, in the output), `-1` when not (the message there).
fn answer(work: impl FnOnce(&mut State) -> Result<String, String>) -> i32 {
    let (text, code) = match with_state(work) {
        Ok(text) => (text, 0),
        Err(message) => (message, -1),
    };
    set_output(text);
    code
}

/// A handle from `work`, or `-1` with the message in the output.
fn handle(work: impl FnOnce(&mut State) -> Result<i32, String>) -> i32 {
    with_state(work).unwrap_or_else(|message| {
        set_output(message);
        -1
    })
}

/// A pointer from `work`, or null with the message in the output.
fn room(work: impl FnOnce(&mut State) -> Result<*mut u8, String>) -> *mut u8 {
    with_state(work).unwrap_or_else(|message| {
        set_output(message);
        std::ptr::null_mut()
    })
}

/// Keeps a panic's message in the output before the module traps.
fn keep_panic_messages() {
    std::panic::set_hook(Box::new(|info| {
        let message = format!("masssprings stopped on a bug: {info}");
        OUTPUT.with(|output| {
            if let Ok(mut output) = output.try_borrow_mut() {
                *output = message;
            }
        });
    }));
}

/// Sets the memory the module may use in all, `bytes` (the page's budget
/// for its tab); the limit every size is checked against is half of it.
/// Call it first. `-1` when the limit was decided already.
#[no_mangle]
pub extern "C" fn ms_set_budget(bytes: f64) -> i32 {
    answer(|_| state::set_budget(bytes))
}

/// Room for `length` bytes of text in (a name, JSON) for the next call;
/// null when `length` passes the input limit (the message in the output).
#[no_mangle]
pub extern "C" fn ms_input(length: u32) -> *mut u8 {
    room(|state| state.input_room(length))
}

/// The text the last call answered (UTF-8).
#[no_mangle]
pub extern "C" fn ms_output() -> *const u8 {
    OUTPUT.with(|output| output.borrow().as_ptr())
}

/// The length in bytes of [`ms_output`].
#[no_mangle]
pub extern "C" fn ms_output_len() -> u32 {
    OUTPUT.with(|output| output.borrow().len() as u32)
}

/// Forgets every file held in memory.
#[no_mangle]
pub extern "C" fn ms_files_clear() {
    with_state(State::clear_files);
}

/// Room for the `length` bytes of the file named in the input, checked
/// against the input limit before anything is allocated; null when
/// refused (the message, naming the file, in the output).
#[no_mangle]
pub extern "C" fn ms_file(length: f64) -> *mut u8 {
    room(|state| state.file_room(length))
}

/// Reads the scene whose JSON is named in the input from the files held in
/// memory: its handle, with the scene (`answers::SceneAnswer`) as JSON in
/// the output, or `-1`.
#[no_mangle]
pub extern "C" fn ms_scene_load() -> i32 {
    handle(|state| {
        let (handle, answer) = state.load_scene()?;
        set_output(answer);
        Ok(handle)
    })
}

/// Forgets scene `scene` (its simulations stay).
#[no_mangle]
pub extern "C" fn ms_scene_free(scene: i32) {
    with_state(|state| state.free_scene(scene));
}

/// A simulation of scene `scene`, at rest, solved as the options in the
/// input say (JSON, `answers::NewSimulation`): its handle, or `-1`.
#[no_mangle]
pub extern "C" fn ms_simulation_new(scene: i32) -> i32 {
    handle(|state| state.new_simulation(scene))
}

/// Forgets simulation `handle`.
#[no_mangle]
pub extern "C" fn ms_simulation_free(handle: i32) {
    with_state(|state| state.free_simulation(handle));
}

/// Advances simulation `handle` by `count` steps (one for the page; more
/// for a benchmark's loop without a call a step), answering the last
/// one's record (the viewer's `StepRecord`) as JSON.
#[no_mangle]
pub extern "C" fn ms_steps(handle: i32, count: u32) -> i32 {
    answer(|state| state.steps(handle, count))
}

/// The current positions of simulation `handle`, `3n` `f64` (x, y, z of
/// each vertex), in place: valid until the next call; null for no such
/// simulation.
#[no_mangle]
pub extern "C" fn ms_positions(handle: i32) -> *const f64 {
    with_state(|state| state.positions(handle, false))
}

/// The positions one step earlier, as [`ms_positions`].
#[no_mangle]
pub extern "C" fn ms_previous_positions(handle: i32) -> *const f64 {
    with_state(|state| state.positions(handle, true))
}

/// Answers what simulation `handle` is and how it runs
/// (`answers::SimulationAnswer`: steps, time, energy, the options) as
/// JSON.
#[no_mangle]
pub extern "C" fn ms_simulation(handle: i32) -> i32 {
    answer(|state| state.describe(handle))
}

/// New `k`, `Δt` and factor on the scene's masses (`Q` refactored when
/// one changed) and iteration budget, within the page's sliders' ranges.
#[no_mangle]
pub extern "C" fn ms_set_parameters(
    handle: i32,
    k: f64,
    delta_t: f64,
    mass_scale: f64,
    iterations: u32,
) -> i32 {
    answer(|state| state.set_parameters(handle, [k, delta_t, mass_scale], iterations))
}

/// Wind on (`1`) or off (`0`).
#[no_mangle]
pub extern "C" fn ms_set_wind(handle: i32, wind: u32) -> i32 {
    answer(|state| state.set_wind(handle, wind != 0))
}

/// How later steps are solved: the method and its rules in the input
/// (JSON, `answers::MethodSettings`).
#[no_mangle]
pub extern "C" fn ms_set_method(handle: i32) -> i32 {
    answer(|state| state.set_method(handle))
}

/// Back to rest, time 0, nothing dragged.
#[no_mangle]
pub extern "C" fn ms_reset(handle: i32) -> i32 {
    answer(|state| state.reset(handle))
}

/// Later steps solved as the simulation's solver solves them by default
/// (its method, budget and rules), or as the assignment when it has none:
/// what the viewer's reset returns to.
#[no_mangle]
pub extern "C" fn ms_solver_step(handle: i32) -> i32 {
    answer(|state| state.solver_step(handle))
}

/// Answers the names the page lists: `{"methods": [...], "solvers": [...]}`.
#[no_mangle]
pub extern "C" fn ms_names() -> i32 {
    answer(|_| Ok(answers::json(&answers::Names::new())))
}

/// Continues from a state: the input holds `U_prev` then `U_cur`, `6n`
/// little-endian `f64`, and what the methods carried as JSON after them;
/// they are `steps` steps after the start, at simulated time `time`.
#[no_mangle]
pub extern "C" fn ms_set_state(handle: i32, steps: f64, time: f64) -> i32 {
    answer(|state| state.set_state(handle, steps, time))
}

/// Starts dragging `vertex` (0-based) toward `(x, y, z)`.
#[no_mangle]
pub extern "C" fn ms_drag_start(handle: i32, vertex: u32, x: f64, y: f64, z: f64) -> i32 {
    answer(|state| state.drag_start(handle, vertex, [x, y, z]))
}

/// Moves the dragged vertex's target to `(x, y, z)`.
#[no_mangle]
pub extern "C" fn ms_drag_to(handle: i32, x: f64, y: f64, z: f64) -> i32 {
    answer(|state| state.drag_to(handle, [x, y, z]))
}

/// Lets go of the dragged vertex.
#[no_mangle]
pub extern "C" fn ms_drag_end(handle: i32) -> i32 {
    answer(|state| state.drag_end(handle))
}
