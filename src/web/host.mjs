// The simulation's host when the page runs it itself: what the simulation
// thread of `masssprings view` does (src/app/view: simulation_thread.rs,
// commands.rs, stepping.rs, publish.rs), done in a Web Worker over the
// WebAssembly module, so that a step never freezes the page. It applies the
// page's commands (the viewer's, src/app/view/api.rs) and sends the page
// the scene, the frames and the status as the server's /api/ would. What
// the controls may ask and the words the page shows are the module's
// (src/app/view/rules.rs and display_mesh.rs, compiled into it); what is
// here is a server's part: which simulations are shown, real time, the
// histories and the timings.
//
// From the page (backend.js beside this file): { type: 'start', wasm (the
// module compiled), budget, dropped, restore }, { type: 'command', id,
// body, detached },
// { type: 'open', id, files }, { type: 'watching' }. To the page: 'scene',
// 'frame', 'status', 'busy' (work that may be long, with a snapshot to
// start again from when the page stops it), 'idle', 'answer', 'failed'.
import { Masssprings } from './masssprings.mjs';

/** Steps kept in each history for the page's plot (api.rs). */
const HISTORY_LENGTH = 150;
/** The simulation runs while the page asked for a frame this recently. */
const WATCHED_MS = 1000;
/** Work expected to take longer comes with a snapshot: Stop ends it by
 *  starting a fresh worker from there. */
const LONG_MS = 100;
/** The settings the page starts from, and reset returns to. */
const INITIAL = { deltaT: 1 / 30, wind: false };

let module = null;
let names = null;
const host = {
  scenes: [], // { name, json, files(): Promise<[{ name, bytes }]> }
  sceneIndex: 0,
  serial: 0,
  scene: null, // the module's scene: { handle, mesh, texture, texture_problem }
  sceneK: 0,
  texture: null, // the PNG's bytes
  main: null, // { sim, msPerStep, history }
  second: null,
  animating: false,
  showSprings: false,
  error: null,
  note: null,
  refactorMs: null,
  watchedAt: -Infinity,
  nextStepAt: 0,
  timer: null,
  rate: { start: 0, steps: 0, perSecond: 0 },
  frameSerial: 0,
};

const post = (message, transfer = []) => postMessage(message, transfer);

// ---------------------------------------------------------------------------
// The simulations shown.

function shown(sim) {
  return { sim, msPerStep: 0, history: [] };
}

function all() {
  return host.second ? [host.main, host.second] : [host.main];
}

/** A simulation of the scene shown, solved as `name` says (a solver,
 *  `converged`), going on from where `from` is (with its k, Δt, masses and
 *  wind), or at rest. */
function built(name, from = null) {
  const sim = module.simulation(host.scene, { solver: name });
  if (from) {
    const d = from.sim.describe();
    const own = sim.describe();
    sim.setParameters(d.k, d.delta_t, d.mass_scale, own.iterations);
    sim.setWind(d.wind);
    sim.setState(from.sim.positions(true), from.sim.positions(), d.steps, d.time, own.carried);
  }
  return sim;
}

/** Counts a step of `ms` in the moving average (about the last 10). */
function recordTime(one, ms) {
  one.msPerStep = one.msPerStep === 0 ? ms : 0.9 * one.msPerStep + 0.1 * ms;
}

function push(history, record) {
  if (history.length === HISTORY_LENGTH) history.shift();
  history.push(record);
}

/** The largest distance between a vertex of the two simulations. */
function distance(a, b) {
  let largest = 0;
  for (let i = 0; i < a.length; i += 3) {
    largest = Math.max(largest, Math.hypot(a[i] - b[i], a[i + 1] - b[i + 1], a[i + 2] - b[i + 2]));
  }
  return largest;
}

// ---------------------------------------------------------------------------
// What the page is sent.

/** The positions of every simulation shown (api.rs, Frame): u32 n, u32
 *  serial, u32 steps, f32 time, then 3n f32 per simulation. */
function publishFrame() {
  const d = host.main.sim.describe();
  const sets = all().map((one) => one.sim.positions());
  const n = sets[0].length / 3;
  const bytes = new ArrayBuffer(16 + 12 * n * sets.length);
  const header = new DataView(bytes, 0, 16);
  host.frameSerial = (host.frameSerial + 1) >>> 0;
  header.setUint32(0, n, true);
  header.setUint32(4, host.frameSerial, true);
  header.setUint32(8, Math.min(d.steps, 2 ** 32 - 1), true);
  header.setFloat32(12, d.time, true);
  sets.forEach((positions, set) => new Float32Array(bytes, 16 + 12 * n * set, 3 * n).set(positions));
  post({ type: 'frame', bytes }, [bytes]);
}

/** The status, as the server's /api/status says it (api.rs, Status). */
function status() {
  const d = host.main.sim.describe();
  const watched = performance.now() - host.watchedAt < WATCHED_MS;
  const { mesh } = host.scene;
  return {
    scene: host.scenes[host.sceneIndex].name,
    backend: d.backend,
    n: mesh.n,
    springs: mesh.springs.length / 2,
    steps: d.steps,
    time: d.time,
    animating: host.animating,
    wind: d.wind,
    show_springs: host.showSprings,
    ms_per_step: host.main.msPerStep,
    steps_per_second: host.rate.perSecond,
    dragged: d.dragged,
    error: host.error,
    watched,
    pages: watched ? 1 : 0,
    k: d.k,
    delta_t: d.delta_t,
    mass_scale: d.mass_scale,
    iterations: d.iterations,
    method: d.method,
    methods: names.methods,
    solver: d.solver,
    solvers: names.solvers,
    functions: d.functions,
    plain_first: d.plain_first,
    busy: null,
    busy_ms: null,
    queued: 0,
    note: host.note,
    energy: d.energy,
    compare: host.second ? compared(host.second) : null,
    tolerance: d.tolerance,
    energy_tolerance: d.energy_tolerance,
    at_least_plain: d.at_least_plain,
    start: d.start,
    refactor_ms: host.refactorMs,
    // The handout's dense code is not offered here (its five n × n
    // matrices are the server's to hold).
    dense_memory: '',
    dense_fits: false,
    frames: null,
    scenes: host.scenes.map((scene) => scene.name),
    scene_index: host.sceneIndex,
    scene_serial: host.serial,
    history: host.main.history,
  };
}

function compared(second) {
  const d = second.sim.describe();
  return {
    solver: d.solver, backend: d.backend, method: d.method, functions: d.functions,
    ms_per_step: second.msPerStep, iterations: d.iterations, energy: d.energy, ended: false,
    history: second.history,
  };
}

function publishStatus() {
  post({ type: 'status', status: status() });
}

function publishScene() {
  post({ type: 'scene', scene: host.scene.mesh, texture: host.texture, serial: host.serial });
}

/** Says that work which may be long starts (`what`, as the server's busy
 *  says it); `snapshot`: where a fresh worker would start again if the
 *  page stops it. */
function busy(what, long) {
  post({ type: 'busy', what, snapshot: long ? snapshot() : null });
}

function idle() {
  post({ type: 'idle' });
}

// ---------------------------------------------------------------------------
// Stepping (stepping.rs): every simulation shown, from the same state; a
// step one of them could not finish is undone in the other.

function stepOnce() {
  const number = host.main.sim.describe().steps + 1;
  const expected = Math.max(...all().map((one) => one.msPerStep));
  busy(`step ${number}`, expected === 0 || expected > LONG_MS);
  const saved = host.second ? all().map(save) : [];
  const reports = [];
  let failure = null;
  try {
    for (const one of all()) {
      const started = performance.now();
      reports.push({ one, record: one.sim.step(), ms: performance.now() - started });
    }
  } catch (error) {
    failure = error;
  } finally {
    idle();
  }
  if (failure) {
    saved.forEach(restore);
    setAnimating(false);
    host.error = `step ${number}: ${failure.message}`;
    throw new Error(host.error);
  }
  finishStep(reports);
}

function save(one) {
  const d = one.sim.describe();
  return { one, previous: one.sim.positions(true), current: one.sim.positions(), d };
}

/** Puts a simulation back where it was saved, if its step completed. */
function restore({ one, previous, current, d }) {
  if (one.sim.describe().steps !== d.steps) one.sim.setState(previous, current, d.steps, d.time, d.carried);
}

function finishStep(reports) {
  for (const { one, ms } of reports) recordTime(one, ms);
  countStep();
  host.note = null;
  publishFrame();
  const [first, second] = reports;
  push(host.main.history, { ...first.record, ms: first.ms });
  if (second) {
    const far = distance(host.main.sim.positions(), second.one.sim.positions());
    push(second.one.history, { ...second.record, ms: second.ms, distance: far });
  }
}

/** The steps over the last second, for the overlay. */
function countStep() {
  const now = performance.now();
  host.rate.steps += 1;
  if (now - host.rate.start >= 1000) {
    host.rate.perSecond = (1000 * host.rate.steps) / (now - host.rate.start);
    host.rate.start = now;
    host.rate.steps = 0;
  }
}

function setAnimating(animating) {
  if (animating && !host.animating) host.nextStepAt = performance.now();
  host.animating = animating;
  host.rate = { start: performance.now(), steps: 0, perSecond: 0 };
  schedule();
}

/** The next real-time step, when animating and watched: a step of Δt every
 *  Δt, or as fast as the steps go when they take longer. */
function schedule() {
  clearTimeout(host.timer);
  host.timer = null;
  if (!host.animating || performance.now() - host.watchedAt >= WATCHED_MS) return;
  host.timer = setTimeout(realTimeStep, Math.max(0, host.nextStepAt - performance.now()));
}

function realTimeStep() {
  host.timer = null;
  if (!host.animating) return;
  if (performance.now() - host.watchedAt >= WATCHED_MS) {
    publishStatus(); // nobody watching: paused until a page asks again
    return;
  }
  try {
    stepOnce();
  } catch (error) {
    // the status says why the animation stopped
  }
  const period = 1000 * host.main.sim.describe().delta_t;
  host.nextStepAt = Math.max(host.nextStepAt + period, performance.now());
  publishStatus();
  schedule();
}

// ---------------------------------------------------------------------------
// The commands (commands.rs): each acts on both simulations when comparing,
// but the method, the solver and the iteration budget, which are the
// first's.

/** `work`, which rebuilds and refactors Q, timed for the overlay. */
function refactored(work) {
  busy('rebuilding and refactoring Q', true);
  const started = performance.now();
  try {
    work();
  } finally {
    idle();
  }
  host.refactorMs = performance.now() - started;
}

const COMMANDS = {
  step() {
    setAnimating(false);
    stepOnce();
  },
  toggle_animation() {
    setAnimating(!host.animating);
  },
  toggle_springs() {
    host.showSprings = !host.showSprings;
  },
  reset,
  restart,
  toggle_wind() {
    const wind = !host.main.sim.describe().wind;
    all().forEach((one) => one.sim.setWind(wind));
  },
  drag_start({ vertex, target }) {
    // checked on the first (pinned, too far), then the same pin in both
    refactored(() => all().forEach((one) => one.sim.dragStart(vertex, target)));
  },
  drag_to({ target }) {
    all().forEach((one) => one.sim.dragTo(target));
  },
  drag_end() {
    refactored(() => all().forEach((one) => one.sim.dragEnd()));
  },
  set_parameters({ k, delta_t, mass_scale, iterations }) {
    const d = host.main.sim.describe();
    const apply = () => {
      host.main.sim.setParameters(k, delta_t, mass_scale, iterations);
      if (host.second) host.second.sim.setParameters(k, delta_t, mass_scale, host.second.sim.describe().iterations);
    };
    const changed = d.k !== k || d.delta_t !== delta_t || d.mass_scale !== mass_scale;
    if (changed) refactored(apply); else apply();
  },
  async load_scene({ scene }) {
    await loadScene(scene);
  },
  set_method(body) {
    const { method, tolerance = null, energy_tolerance = null, at_least_plain = null, start } = body;
    host.main.sim.setMethod({ method, tolerance, energy_tolerance, at_least_plain, ...(start ? { start } : {}) });
  },
  set_solver({ solver, backend }) {
    sparseOnly(backend);
    precomputing(`precomputing for ${solver} (sparse)`, () => {
      const sim = built(solver, host.main);
      host.main.sim.free();
      host.main = shown(sim);
    });
    host.refactorMs = null;
    publishFrame();
  },
  compare({ with: name, backend }) {
    if (name === null || name === undefined) {
      if (host.second) host.second.sim.free();
      host.second = null;
      publishFrame();
      return;
    }
    if (name === 'frames') throw new Error('your own frames need the program: masssprings view SCENE --frames DIR');
    sparseOnly(backend);
    precomputing(`precomputing for ${name} (sparse)`, () => {
      const sim = built(name, host.main);
      if (host.second) host.second.sim.free();
      host.second = shown(sim);
    });
    publishFrame();
  },
  cancel() {
    setAnimating(false);
  },
};

function sparseOnly(backend) {
  if (backend === 'dense') {
    throw new Error('the handout\'s dense code runs in the program only (masssprings view): '
      + 'its n × n matrices are too large for a page');
  }
}

/** Runs `build`, a precomputation, showing `what` as the work in progress. */
function precomputing(what, build) {
  busy(what, true);
  try {
    build();
  } finally {
    idle();
  }
}

/** Back to the scene as it loaded, paused: rest, time 0, the scene's k,
 *  Δt and masses, no wind, the first's budget and rules as its solver has
 *  them. */
function reset() {
  setAnimating(false);
  const changed = (sim) => {
    const d = sim.describe();
    return d.k !== host.sceneK || d.delta_t !== INITIAL.deltaT || d.mass_scale !== 1;
  };
  if (all().some((one) => changed(one.sim))) {
    refactored(() => all().forEach(({ sim }) => {
      if (changed(sim)) sim.setParameters(host.sceneK, INITIAL.deltaT, 1, sim.describe().iterations);
    }));
  }
  all().forEach((one) => one.sim.setWind(INITIAL.wind));
  host.main.sim.solverStep();
  restart();
}

/** Back to rest at time 0, every setting kept. */
function restart() {
  all().forEach((one) => one.sim.reset());
  host.error = null;
  host.note = null;
  publishFrame();
  all().forEach((one) => { one.history = []; });
}

// ---------------------------------------------------------------------------
// Scenes: the bundled ones (scenes/, listed in scenes/index.json) and those
// the user gives (their files, dropped or picked on the page).

async function fetched(name) {
  const response = await fetch(`scenes/${name}`);
  if (!response.ok) throw new Error(`scenes/${name}: ${response.status} ${response.statusText}`);
  return new Uint8Array(await response.arrayBuffer());
}

/** A bundled scene: its JSON, and the files the JSON names. */
function bundled(name) {
  const json = `${name}.json`;
  return {
    name,
    json,
    async files() {
      const text = await fetched(json);
      const named = JSON.parse(new TextDecoder().decode(text));
      const others = [named.obj, named.png].filter((file) => typeof file === 'string');
      return [{ name: json, bytes: text }, ...await Promise.all(others.map(async (file) => ({ name: file, bytes: await fetched(file) })))];
    },
  };
}

/** A scene of the user's files ([{ name, bytes }]): the one JSON among them. */
function given(files) {
  const jsons = files.filter((file) => file.name.toLowerCase().endsWith('.json'));
  if (jsons.length !== 1) {
    throw new Error(`give one scene: its .json with the .obj (and the .png) it names; ${jsons.length} .json files were given`);
  }
  const json = jsons[0].name;
  return { name: `${json.replace(/\.json$/i, '')} (yours)`, json, files: async () => files };
}

/** Loads scene `index` and makes every simulation shown again for it, paused
 *  at rest with the scene's own k, Δt and masses (solvers, budgets and wind
 *  carry over); on failure the scene shown stays. */
async function loadScene(index) {
  const entry = host.scenes[index];
  if (!entry) throw new Error(`there is no scene ${index}`);
  busy(`precomputing ${entry.name}`, true);
  let scene = null;
  let made = [];
  try {
    const files = await entry.files();
    scene = module.loadScene(files, entry.json);
    made = all().map((one) => remade(one, scene));
    const png = scene.texture && files.find((file) => file.name === scene.texture);
    host.texture = png ? png.bytes : null;
  } catch (error) {
    made.forEach((one) => one.sim.free());
    if (scene) module.freeScene(scene);
    throw error;
  } finally {
    idle();
  }
  all().forEach((one) => one.sim.free());
  module.freeScene(host.scene);
  [host.main, host.second = null] = made;
  showScene(scene, index);
}

/** A simulation of `scene` solved as `one` is, at rest. */
function remade(one, scene) {
  return shown(solvedAs(one.sim.describe(), scene));
}

/** A simulation of `scene`, at rest with the scene's own k, Δt and
 *  masses, solved as `d` (a simulation's description) says: by its solver,
 *  or by the expert's own method and rules; with its budget and wind. */
function solvedAs(d, scene) {
  const base = d.solver ?? (d.plain_first ? 'accuracy-assignment' : 'assignment');
  const sim = module.simulation(scene, { solver: base, wind: d.wind });
  if (d.solver === null) {
    sim.setMethod({
      method: d.method, tolerance: d.tolerance, energy_tolerance: d.energy_tolerance,
      at_least_plain: d.at_least_plain, start: d.start,
    });
  }
  const fresh = sim.describe();
  sim.setParameters(fresh.k, fresh.delta_t, fresh.mass_scale, d.iterations);
  return sim;
}

function showScene(scene, index) {
  host.scene = scene;
  host.sceneIndex = index;
  host.sceneK = host.main.sim.describe().k;
  host.serial = (host.serial + 1) >>> 0;
  host.refactorMs = null;
  host.showSprings = scene.mesh.triangles.length === 0;
  host.error = null;
  host.note = scene.texture_problem ? `${scene.texture_problem}; drawn without texture` : null;
  setAnimating(false);
  publishScene();
  publishFrame();
}

// ---------------------------------------------------------------------------
// Starting, and starting again from a snapshot when the page stopped work.

/** Where the page would start again: the scene, each simulation's state and
 *  settings, the histories. */
function snapshot() {
  return {
    sceneIndex: host.sceneIndex,
    serial: host.serial,
    showSprings: host.showSprings,
    refactorMs: host.refactorMs,
    shown: all().map((one) => ({
      d: one.sim.describe(),
      previous: one.sim.positions(true),
      current: one.sim.positions(),
      msPerStep: one.msPerStep,
      history: one.history,
    })),
  };
}

async function start({ wasm, budget, dropped, restore }) {
  module = await Masssprings.instantiate(wasm);
  module.setBudget(budget);
  names = module.names();
  const index = await (await fetch('scenes/index.json')).json();
  host.scenes = [...index.map(bundled), ...dropped.map(given)];
  if (restore) {
    await restored(restore);
  } else {
    await startWith(0);
  }
  host.watchedAt = performance.now();
  publishStatus();
}

/** The first scene, with the assignment's simulation. */
async function startWith(index) {
  const entry = host.scenes[index];
  const files = await entry.files();
  const scene = module.loadScene(files, entry.json);
  host.main = shown(module.simulation(scene, { solver: 'assignment' }));
  const png = scene.texture && files.find((file) => file.name === scene.texture);
  host.texture = png ? png.bytes : null;
  showScene(scene, index);
}

/** The state of `snapshot`, in this fresh worker. */
async function restored(saved) {
  await startWith(saved.sceneIndex);
  host.main.sim.free();
  const made = saved.shown.map(({ d, previous, current, msPerStep, history }) => {
    const sim = solvedAs(d, host.scene);
    sim.setParameters(d.k, d.delta_t, d.mass_scale, d.iterations);
    sim.setState(previous, current, d.steps, d.time, d.carried);
    return { sim, msPerStep, history };
  });
  [host.main, host.second = null] = made;
  host.serial = saved.serial;
  host.showSprings = saved.showSprings;
  host.refactorMs = saved.refactorMs;
  host.note = saved.note;
  publishScene();
  publishFrame();
}

// ---------------------------------------------------------------------------
// Messages.

async function answer(id, work, detached) {
  let reply;
  try {
    await work();
    reply = { code: 200, answer: status() };
  } catch (error) {
    reply = { code: 409, answer: { error: error.message } };
    if (detached) host.note = `${detached}, sent during a step: refused: ${error.message}`;
  }
  publishStatus();
  post({ type: 'answer', id, ...reply });
}

onmessage = async ({ data }) => {
  try {
    if (data.type === 'start') {
      await start(data);
    } else if (data.type === 'watching') {
      const resumed = performance.now() - host.watchedAt >= WATCHED_MS;
      host.watchedAt = performance.now();
      if (resumed && host.animating) {
        host.nextStepAt = performance.now();
        schedule();
      }
    } else if (data.type === 'command') {
      const { id, body, detached } = data;
      const apply = COMMANDS[body.command];
      if (!apply) {
        post({ type: 'answer', id, code: 400, answer: { error: `unknown command '${body.command}'` } });
        return;
      }
      await answer(id, () => apply(body), detached ? body.command : null);
    } else if (data.type === 'open') {
      await answer(data.id, async () => {
        const entry = given(data.files);
        const index = host.scenes.findIndex((scene) => scene.name === entry.name);
        host.scenes[index >= 0 ? index : host.scenes.length] = entry;
        const at = index >= 0 ? index : host.scenes.length - 1;
        try {
          await loadScene(at);
        } catch (error) {
          if (index < 0) host.scenes.splice(at, 1);
          throw error;
        }
      });
    }
  } catch (error) {
    post({ type: 'failed', message: error.message });
  }
};
