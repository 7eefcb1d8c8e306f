// The figures of the page's targets that need no browser, one per line:
//
// * the size of masssprings.wasm, plain and gzipped;
// * for the flag and the skirt, the median step of 100 in the WebAssembly
//   module (node's V8, Chromium's engine) beside the native program's on one
//   thread, as the module runs, with the portable kernels (`simulate
//   --kernels portable --threads 1 --json`, whose
//   step_median_s times each step alone) and with the native ones, in
//   ROUNDS interleaved rounds (default 3), and their ratio; and the steps a
//   second the module keeps up.
//
//     bash tests/web/run.sh --targets [ROUNDS]
//
// Not a test: the figures depend on the machine (measure on a quiet one).
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { gzipSync } from 'node:zlib';
import { Masssprings } from '../../src/web/masssprings.mjs';

const root = new URL('../..', import.meta.url).pathname;
const wasmPath = process.env.MASSSPRINGS_WASM ?? join(root, 'target/web/masssprings.wasm');
const program = process.env.MASSSPRINGS_BIN ?? join(root, 'target/release/masssprings');
const rounds = Number(process.argv[2] ?? 3);
const STEPS = 100;
const wasm = readFileSync(wasmPath);
const print = (what, figure) => console.log(`${what}: ${figure}`);
const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  const middle = sorted.length >> 1;
  return sorted.length % 2 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2;
};

/** The median step of the module on `scene`, milliseconds. */
async function moduleStep(scene) {
  const masssprings = await Masssprings.instantiate(wasm);
  masssprings.setBudget(2 ** 31);
  const folder = join(root, 'data');
  const json = readFileSync(join(folder, `${scene}.json`));
  const { obj, png } = JSON.parse(json);
  const files = [{ name: `${scene}.json`, bytes: json }, { name: obj, bytes: readFileSync(join(folder, obj)) }];
  if (png) files.push({ name: png, bytes: readFileSync(join(folder, png)) });
  const loaded = masssprings.loadScene(files, `${scene}.json`);
  const simulation = masssprings.simulation(loaded, { solver: 'assignment' });
  const times = [];
  for (let step = 0; step < STEPS; step += 1) {
    const started = performance.now();
    simulation.step();
    times.push(performance.now() - started);
  }
  return median(times);
}

/** The native program's median step on `scene` with `kernels`, ms. */
function nativeStep(scene, kernels) {
  const output = execFileSync(program, ['simulate', join(root, 'data', `${scene}.json`), '--steps', String(STEPS),
    '--kernels', kernels, '--threads', '1', '--json'], { encoding: 'utf8' });
  return 1000 * JSON.parse(output).step_median_s;
}

print('masssprings.wasm, bytes', `${wasm.length} (${(wasm.length / 1e6).toFixed(2)} MB; target ≤ 1 MB)`);
const gzipped = gzipSync(wasm, { level: 9 }).length;
print('masssprings.wasm gzipped, bytes', `${gzipped} (${(gzipped / 1e3).toFixed(0)} KB; target ≤ 400 KB)`);
for (const scene of ['flag', 'skirt']) {
  const figures = { module: [], portable: [], native: [] };
  for (let round = 0; round < rounds; round += 1) {
    figures.module.push(await moduleStep(scene));
    figures.portable.push(nativeStep(scene, 'portable'));
    figures.native.push(nativeStep(scene, 'native'));
  }
  const [module, portable, native] = [figures.module, figures.portable, figures.native].map(median);
  const ratios = figures.module.map((m, i) => m / figures.portable[i]);
  print(`${scene}: step in the module (node), ms, median of ${rounds} rounds' medians of ${STEPS}`, module.toFixed(1));
  print(`${scene}: step native, portable kernels, ms`, portable.toFixed(1));
  print(`${scene}: step native, native kernels, ms`, native.toFixed(1));
  print(`${scene}: module / native portable (each round's; target ≤ 2.5)`,
    `${median(ratios).toFixed(2)} (${ratios.map((r) => r.toFixed(2)).join(', ')})`);
  print(`${scene}: steps a second the module keeps up (target ≥ 15 for the flag)`, (1000 / module).toFixed(0));
}
