// The figures of the page that runs the simulation itself (the static
// build), measured in headless Chromium as a user opens and plays it,
// printed one per line:
//
// * from opening the served page to the flag drawn, textured (ms, each of
//   ROUNDS fresh browsers);
// * the step of the flag and of the skirt in the page (the worker's time
//   around each step, the status's history: median of 100 steps, played
//   in real time) beside the native program's with the portable kernels
//   on one thread, as the page's worker runs (`simulate --kernels portable
//   --threads 1 --json`, the median of 100 steps), in
//   ROUNDS interleaved rounds, and their ratio;
// * the steps a second the flag plays at (the status, after 5 s of play).
//
//     bash tests/browser/run.sh --static-targets [ROUNDS]
//
// Not a test: the figures depend on the machine (measure on a quiet one).
import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { StaticSession, binary, root } from './harness.mjs';

const rounds = Number(process.argv[2] ?? 3);
const print = (what, figure) => console.log(`${what}: ${figure}`);
const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  const middle = sorted.length >> 1;
  return sorted.length % 2 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2;
};
const SCENES = { flag: 0, skirt: 1 };

/** A fresh browser on the page: ms from opening to the flag drawn. */
async function opened() {
  const session = new StaticSession();
  const started = performance.now();
  await session.open();
  await session.ready();
  return { session, ms: performance.now() - started };
}

/** The page's median step of 100 of `scene`, played in real time; and the
 *  steps a second it played at. */
async function pageStep(session, scene) {
  if (SCENES[scene] !== 0) {
    await session.page.selectOption('#scene', String(SCENES[scene]));
    await session.waitForStatus((s) => s.scene === scene && !s.busy, scene, 60000);
  }
  await session.page.keyboard.press('a');
  const played = await session.waitForStatus((s) => s.steps >= 101, '101 steps', 120000);
  await session.page.keyboard.press('a');
  const times = played.history.slice(-100).map((record) => record.ms);
  return { ms: median(times), rate: played.steps_per_second };
}

function nativeStep(scene) {
  const output = execFileSync(binary, ['simulate', path.join(root, 'data', `${scene}.json`), '--steps', '100',
    '--kernels', 'portable', '--threads', '1', '--json'], { encoding: 'utf8' });
  return 1000 * JSON.parse(output).step_median_s;
}

const openings = [];
const figures = { flag: { page: [], native: [] }, skirt: { page: [], native: [] } };
const rates = [];
for (let round = 0; round < rounds; round += 1) {
  const { session, ms } = await opened();
  openings.push(ms);
  for (const scene of Object.keys(figures)) {
    const { ms: step, rate } = await pageStep(session, scene);
    figures[scene].page.push(step);
    if (scene === 'flag') rates.push(rate);
    figures[scene].native.push(nativeStep(scene));
  }
  await session.close();
}
print('opening the page to the flag drawn, ms (target ≤ 3000)', `${median(openings).toFixed(0)} (${openings.map((ms) => ms.toFixed(0)).join(', ')})`);
for (const [scene, { page, native }] of Object.entries(figures)) {
  const ratios = page.map((ms, i) => ms / native[i]);
  print(`${scene}: step in the page, ms (median of 100, median of ${rounds} rounds)`, median(page).toFixed(1));
  print(`${scene}: step native, portable kernels, ms`, median(native).toFixed(1));
  print(`${scene}: page / native portable (each round's; target ≤ 2.5 for the flag)`,
    `${median(ratios).toFixed(2)} (${ratios.map((r) => r.toFixed(2)).join(', ')})`);
}
print('flag: steps a second while playing (target ≥ 15; real time is 30)', `${median(rates).toFixed(1)} (${rates.map((r) => r.toFixed(1)).join(', ')})`);
