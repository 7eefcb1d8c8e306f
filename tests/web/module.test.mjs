// The WebAssembly module of the page (src/web), run by node as a browser's
// worker runs it: the same bits as the native program with the portable
// kernels (to 1e-12 with the wind, whose cos and sin each platform's math
// library rounds), the command line's messages for bad files, the memory
// rule with the page's budget, and a run continued in a fresh module. Run
// by tests/web/run.sh, which builds the module and the program first.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync, spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { Masssprings } from '../../src/web/masssprings.mjs';

const root = new URL('../..', import.meta.url).pathname;
const wasm = readFileSync(process.env.MASSSPRINGS_WASM ?? join(root, 'target/web/masssprings.wasm'));
const program = process.env.MASSSPRINGS_BIN ?? join(root, 'target/debug/masssprings');
const GB = 2 ** 30;

/** A fresh module with a budget of `budget` bytes. */
async function module(budget = GB) {
  const masssprings = await Masssprings.instantiate(wasm);
  masssprings.setBudget(budget);
  return masssprings;
}

/** The files of scene `json` in `folder` as the page gives them: the JSON
 *  and the files it names. */
function sceneFiles(folder, json) {
  const text = readFileSync(join(folder, json));
  const { obj, png } = JSON.parse(text);
  const named = [obj, png].filter(Boolean);
  return [{ name: json, bytes: text }, ...named.map((name) => ({ name, bytes: readFileSync(join(folder, name)) }))];
}

/** A temporary folder, removed after `work(folder)`. */
function inTemporaryFolder(work) {
  const folder = mkdtempSync(join(tmpdir(), 'masssprings-web-'));
  try {
    return work(folder);
  } finally {
    rmSync(folder, { recursive: true, force: true });
  }
}

/** The positions of the last frame `simulate` wrote into `folder`. */
function lastFrame(folder) {
  const frames = readdirSync(folder).filter((name) => /^frame-\d+\.obj$/.test(name)).sort();
  const text = readFileSync(join(folder, frames.at(-1)), 'utf8');
  return text.split('\n').filter((line) => line.startsWith('v ')).flatMap((line) => line.split(' ').slice(1).map(Number));
}

test('100 steps of the flag give the bits of simulate --kernels portable', async () => {
  const masssprings = await module();
  const scene = masssprings.loadScene(sceneFiles(join(root, 'data'), 'flag.json'), 'flag.json');
  const simulation = masssprings.simulation(scene, { solver: 'assignment' });
  simulation.steps(100);
  const page = simulation.positions();
  const native = inTemporaryFolder((folder) => {
    const out = join(folder, 'frames');
    execFileSync(program, ['simulate', join(root, 'data/flag.json'), '--steps', '100', '--every', '100',
      '--kernels', 'portable', '--out', out, '--json']);
    return lastFrame(out);
  });
  assert.equal(page.length, native.length);
  // The frames are written in the shortest decimal that reads back to the
  // same f64, so equal numbers here are equal bits.
  const differing = [...page].findIndex((x, i) => x !== native[i] || Object.is(x, -0) !== Object.is(native[i], -0));
  assert.equal(differing, -1, `coordinate ${differing}: page ${page[differing]}, native ${native[differing]}`);
  assert.ok(Math.min(...page.filter((_, i) => i % 3 === 1)) < 0, 'the flag has fallen');
});

test('with the wind, 100 steps agree to 1e-12 relative: its cos and sin are each platform\'s', async () => {
  const masssprings = await module();
  const scene = masssprings.loadScene(sceneFiles(join(root, 'data'), 'flag.json'), 'flag.json');
  const simulation = masssprings.simulation(scene, { solver: 'assignment', wind: true });
  simulation.steps(100);
  const page = simulation.positions();
  const native = inTemporaryFolder((folder) => {
    const out = join(folder, 'frames');
    execFileSync(program, ['simulate', join(root, 'data/flag.json'), '--steps', '100', '--every', '100',
      '--kernels', 'portable', '--wind', '--out', out, '--json']);
    return lastFrame(out);
  });
  const relative = page.map((x, i) => Math.abs(x - native[i]) / Math.max(1, Math.abs(native[i])));
  const largest = Math.max(...relative);
  assert.ok(largest <= 1e-12, `differ by ${largest} relative`);
});

test('a bad file gets the message the command line gives', async () => {
  const masssprings = await module();
  const cases = [
    ['bad.json', '{"obj": "bad.obj", "k": 100, "b": [1]}', 'bad.obj', 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n'],
    ['bad.json', '{"obj": "bad.obj", "k": -1, "b": [1]}', 'bad.obj', 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n'],
    ['bad.json', '{"obj": "bad.obj",\n "k": 100, "b": [4]}', 'bad.obj', 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n'],
  ];
  for (const [json, jsonText, obj, objText] of cases) {
    const cli = inTemporaryFolder((folder) => {
      writeFileSync(join(folder, json), jsonText);
      writeFileSync(join(folder, obj), objText);
      const run = spawnSync(program, ['simulate', json, '--steps', '1'], { cwd: folder, encoding: 'utf8' });
      assert.equal(run.status, 1, run.stderr);
      return run.stderr;
    });
    const files = [{ name: json, bytes: Buffer.from(jsonText) }, { name: obj, bytes: Buffer.from(objText) }];
    assert.throws(() => masssprings.loadScene(files, json), (error) => {
      assert.ok(/^bad\.(json|obj)(:\d+)?: /.test(error.message), error.message);
      assert.ok(cli.includes(error.message), `the command line said ${cli}, the page ${error.message}`);
      return true;
    });
  }
  // a Q that would overflow is refused when the simulation is made, as the
  // command line refuses it
  const hostile = join(root, 'tests/hostile');
  const overflow = masssprings.loadScene(sceneFiles(hostile, 'k-1e308.json'), 'k-1e308.json');
  const run = spawnSync(program, ['simulate', 'k-1e308.json', '--steps', '1'], { cwd: hostile, encoding: 'utf8' });
  assert.throws(() => masssprings.simulation(overflow), (error) => {
    assert.match(error.message, /^k-1e308\.json: k = 1e308 overflows Q/);
    assert.ok(run.stderr.includes(error.message), `the command line said ${run.stderr}`);
    return true;
  });
  const missing = [{ name: 'lone.json', bytes: Buffer.from('{"obj": "mesh.obj", "k": 1, "b": []}') }];
  assert.throws(() => masssprings.loadScene(missing, 'lone.json'), /^Error: mesh\.obj: cannot read the file/);
});

test('a texture that is not a PNG is named, and the scene loads without it', async () => {
  const masssprings = await module();
  const files = sceneFiles(join(root, 'data'), 'flag.json').map((file) =>
    file.name === 'flag.png' ? { name: 'flag.png', bytes: Buffer.from('not a picture') } : file);
  const scene = masssprings.loadScene(files, 'flag.json');
  assert.equal(scene.texture, null);
  assert.equal(scene.texture_problem, 'texture flag.png: this is not a PNG file (it does not start with the PNG signature)');
  assert.equal(scene.mesh.n, 3200);
  assert.equal(scene.mesh.texture, null);
  assert.equal(masssprings.loadScene(sceneFiles(join(root, 'data'), 'flag.json'), 'flag.json').mesh.texture, '/texture.png');
});

test('the page\'s budget refuses a scene too large for it, with the figures, before allocating it', async () => {
  // 24 MB in all: the limit is 12 MB, files up to 1.5 MB are read, and the
  // skirt's springs are estimated at more than 12 MB.
  const masssprings = await module(24e6);
  assert.throws(() => masssprings.loadScene(sceneFiles(join(root, 'data'), 'skirt.json'), 'skirt.json'), (error) => {
    assert.match(error.message, /^skirt\.obj: .* springs .* would need 0\.0\d\d GB; the limit here is 0\.012 GB \(half of the page's budget/);
    return true;
  });
  // a file beyond an eighth of the limit gets no room at all
  masssprings.input('huge.obj');
  assert.equal(masssprings.exports.ms_file(2e6), 0);
  assert.match(masssprings.output(), /^huge\.obj: the file is larger than 1500000 bytes, the most read here/);
  // the flag fits
  const flag = masssprings.loadScene(sceneFiles(join(root, 'data'), 'flag.json'), 'flag.json');
  masssprings.simulation(flag).step();
});

test('a run continued in a fresh module, from the state and what the methods carried, gives the same bits', async () => {
  const files = sceneFiles(join(root, 'data'), 'flag.json');
  const whole = await module();
  const run = whole.simulation(whole.loadScene(files, 'flag.json'), { solver: 'accuracy-assignment', wind: true });
  run.steps(20);
  const { carried, time } = run.describe();
  const [previous, current] = [run.positions(true), run.positions()];
  run.steps(10);
  const fresh = await module();
  const continued = fresh.simulation(fresh.loadScene(files, 'flag.json'), { solver: 'accuracy-assignment', wind: true });
  continued.setState(previous, current, 20, time, carried);
  continued.steps(10);
  assert.deepEqual(continued.positions(), run.positions());
  assert.equal(continued.describe().time, run.describe().time);
});

test('each solver steps, and the settings change as the page asks', async () => {
  const masssprings = await module();
  const scene = masssprings.loadScene(sceneFiles(join(root, 'data'), 'flag.json'), 'flag.json');
  const expected = {
    assignment: ['fast path: sim/step.rs solve_step → sim/methods/plain.rs (supernodal sparse Cholesky)', 50],
    textbook: ['the handout\'s code as written: sim/textbook.rs, fast_mass_springs_step_sparse (simplicial sparse Cholesky)', 50],
    'accuracy-assignment': ['fast path: sim/step.rs solve_step → sim/methods/plain_then_lbfgs.rs (supernodal sparse Cholesky)', 20],
    converged: ['fast path: sim/step.rs solve_step → sim/methods/lbfgs.rs (supernodal sparse Cholesky)', 200],
  };
  for (const [solver, [functions, iterations]] of Object.entries(expected)) {
    const simulation = masssprings.simulation(scene, { solver });
    const report = simulation.step();
    const state = simulation.describe();
    assert.deepEqual([state.solver, state.functions, state.iterations], [solver, functions, iterations]);
    assert.ok(report.iterations >= 1, JSON.stringify(report));
    assert.ok(simulation.positions().every(Number.isFinite));
    simulation.free();
  }
  const simulation = masssprings.simulation(scene);
  simulation.setParameters(2e5, 1 / 60, 2, 30);
  simulation.setWind(true);
  simulation.setMethod({ method: 'chebyshev', tolerance: 1e-3 });
  const state = simulation.describe();
  assert.deepEqual([state.k, state.delta_t, state.mass_scale, state.wind, state.method, state.iterations, state.tolerance, state.solver],
    [2e5, 1 / 60, 2, true, 'chebyshev', 30, 1e-3, null]);
  // the page's rules, as the viewer's server checks them (src/app/view/rules.rs)
  assert.throws(() => simulation.setMethod({ method: 'plain', tolerance: 2 }), /^Error: tolerance 2: expected between 0 and 1$/);
  assert.throws(() => simulation.setParameters(-1, 1 / 30, 1, 50), /^Error: k = -1: expected a stiffness from 1e-6 to 1e12$/);
  assert.throws(() => simulation.setParameters(1e5, 1 / 30, 1, 1001), /^Error: 1001 iterations: expected from 1 to 1000$/);
  assert.throws(() => simulation.dragStart(0, [0, 0, 0]), /^Error: vertex 0 is pinned$/);
  assert.throws(() => simulation.dragStart(3199, [1e6, 0, 0]), /^Error: the drag target is too far from the scene$/);
  assert.throws(() => simulation.dragTo([0, 0, 1]), /^Error: no vertex is being dragged$/);
  simulation.dragStart(3199, [0, 0, 1]);
  simulation.dragTo([0.1, 0, 1]);
  simulation.step();
  assert.equal(simulation.describe().dragged, 3199);
  simulation.dragEnd();
  simulation.reset();
  assert.equal(simulation.describe().steps, 0);
  const textbook = masssprings.simulation(scene, { solver: 'textbook' });
  assert.throws(() => textbook.setMethod({ method: 'lbfgs' }),
    /textbook path runs the handout's step as written.*; to change them, solve by another solver first$/);
});
