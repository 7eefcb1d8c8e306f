// The WebAssembly module of masssprings (src/web/lib.rs), in JavaScript's
// words: the same calls in a browser's Web Worker and in node (the tests).
//
//   const module = await Masssprings.instantiate(wasmBytes);
//   module.setBudget(2 ** 30);                 // first: the memory the module may use
//   const scene = module.loadScene(files, 'flag.json');  // files: [{ name, bytes }]
//   const simulation = module.simulation(scene, { solver: 'assignment' });
//   simulation.step();                         // { iterations, stop, ... }
//   simulation.positions();                    // Float64Array, x y z per vertex
//
// A call that fails throws an Error whose message is the module's, the
// command line's words (`flag.obj:12: ...`). A bug in the module (a trap)
// throws too, with the panic's message, and the module is unusable after
// it: `module.broken` says so.

const encoder = new TextEncoder();
const decoder = new TextDecoder();

export class Masssprings {
  /** The module from the bytes of masssprings.wasm, or from it compiled
   *  (a WebAssembly.Module). */
  static async instantiate(wasm) {
    const made = await WebAssembly.instantiate(wasm, {});
    const instance = made instanceof WebAssembly.Instance ? made : made.instance;
    return new Masssprings(instance.exports);
  }

  constructor(exports) {
    this.exports = exports;
    this.broken = null;
  }

  /** The text the module answered last. */
  output() {
    const { ms_output, ms_output_len, memory } = this.exports;
    return decoder.decode(new Uint8Array(memory.buffer, ms_output(), ms_output_len()));
  }

  /** Calls export `name`: its result, or an Error with the module's message. */
  call(name, ...args) {
    if (this.broken) throw new Error(`the module stopped earlier: ${this.broken}`);
    let result;
    try {
      result = this.exports[name](...args);
    } catch (error) {
      if (!(error instanceof WebAssembly.RuntimeError)) throw error;
      this.broken = this.output() || String(error);
      throw new Error(this.broken);
    }
    if (result === -1 || result === 0n) throw new Error(this.output());
    return result;
  }

  /** Calls export `name` that answers in the output; returns it parsed
   *  (`null` for no answer). */
  answer(name, ...args) {
    this.call(name, ...args);
    const text = this.output();
    return text === '' ? null : JSON.parse(text);
  }

  /** Copies `bytes` into room the module made (`pointer` 0: refused). */
  fill(pointer, bytes) {
    if (pointer === 0) throw new Error(this.output());
    new Uint8Array(this.exports.memory.buffer, pointer, bytes.length).set(bytes);
  }

  /** Puts `text` (a string) or `bytes` in the module's input. */
  input(textOrBytes) {
    const bytes = typeof textOrBytes === 'string' ? encoder.encode(textOrBytes) : textOrBytes;
    this.fill(this.call('ms_input', bytes.length), bytes);
  }

  /** The memory the module may use in all, in bytes; call it first. */
  setBudget(bytes) {
    this.call('ms_set_budget', bytes);
  }

  /** Reads the scene `jsonName` from `files`, [{ name, bytes }] (bytes: a
   *  Uint8Array); returns it: { handle, mesh, texture, texture_problem }
   *  (src/web/answers.rs, SceneAnswer). */
  loadScene(files, jsonName) {
    this.exports.ms_files_clear();
    try {
      for (const { name, bytes } of files) {
        this.input(name);
        this.fill(this.exports.ms_file(bytes.length), bytes);
      }
      this.input(jsonName);
      const handle = this.call('ms_scene_load');
      return { handle, ...JSON.parse(this.output()) };
    } finally {
      this.exports.ms_files_clear();
    }
  }

  /** The names the page lists: { methods, solvers }. */
  names() {
    return this.answer('ms_names');
  }

  /** Forgets `scene` (its simulations stay). */
  freeScene(scene) {
    this.exports.ms_scene_free(scene.handle);
  }

  /** A simulation of `scene`, at rest: `options` as { solver: 'assignment'
   *  | 'textbook' | 'accuracy-assignment' | 'converged', wind }. */
  simulation(scene, options = {}) {
    this.input(JSON.stringify(options));
    return new Simulation(this, this.call('ms_simulation_new', scene.handle), scene.mesh.n);
  }
}

/** One simulation of the module, by its handle. */
export class Simulation {
  constructor(module, handle, n) {
    this.module = module;
    this.handle = handle;
    this.n = n;
  }

  /** One step: its record, as the viewer's status keeps it { step,
   *  iterations, energy_decrease, relative_gradient, converged, stop,
   *  energy, ms: 0, distance: null } (the caller times it). */
  step() {
    return this.steps(1);
  }

  /** `count` steps in one call; the last one's report. */
  steps(count) {
    return this.module.answer('ms_steps', this.handle, count);
  }

  /** The positions (x y z per vertex), copied out of the module's memory. */
  positions(previous = false) {
    const exports = this.module.exports;
    const pointer = previous ? exports.ms_previous_positions(this.handle) : exports.ms_positions(this.handle);
    if (pointer === 0) throw new Error(`there is no simulation ${this.handle}`);
    return new Float64Array(exports.memory.buffer, pointer, 3 * this.n).slice();
  }

  /** Where it is and how it runs (src/web/answers.rs, SimulationAnswer). */
  describe() {
    return this.module.answer('ms_simulation', this.handle);
  }

  /** New k, Δt, mass scale (Q refactored when one changed) and iteration budget. */
  setParameters(k, deltaT, massScale, iterations) {
    this.module.call('ms_set_parameters', this.handle, k, deltaT, massScale, iterations);
  }

  setWind(on) {
    this.module.call('ms_set_wind', this.handle, on ? 1 : 0);
  }

  /** { method, tolerance, energy_tolerance, at_least_plain, start }: the
   *  viewer's set_method. */
  setMethod(settings) {
    this.module.input(JSON.stringify(settings));
    this.module.call('ms_set_method', this.handle);
  }

  reset() {
    this.module.call('ms_reset', this.handle);
  }

  /** Later steps solved as its solver solves them by default (or the
   *  assignment when it has none). */
  solverStep() {
    this.module.call('ms_solver_step', this.handle);
  }

  /** Continues from `previous`, `current` (Float64Array, 3n each), `steps`
   *  steps after the start at simulated time `time`, with what the methods
   *  `carried` (describe()). */
  setState(previous, current, steps, time, carried) {
    const json = encoder.encode(JSON.stringify(carried));
    const bytes = new Uint8Array(8 * (previous.length + current.length) + json.length);
    const numbers = new Float64Array(previous.length + current.length);
    numbers.set(previous);
    numbers.set(current, previous.length);
    bytes.set(new Uint8Array(numbers.buffer));
    bytes.set(json, numbers.byteLength);
    this.module.input(bytes);
    this.module.call('ms_set_state', this.handle, steps, time);
  }

  dragStart(vertex, [x, y, z]) {
    this.module.call('ms_drag_start', this.handle, vertex, x, y, z);
  }

  dragTo([x, y, z]) {
    this.module.call('ms_drag_to', this.handle, x, y, z);
  }

  dragEnd() {
    this.module.call('ms_drag_end', this.handle);
  }

  free() {
    this.module.exports.ms_simulation_free(this.handle);
  }
}
