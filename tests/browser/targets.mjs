// The figures of the viewer's targets in front of a class, measured in
// headless Chromium as a user drives the page, printed one per line:
//
// * after moving each slider and picker, how long space takes to step, and
//   Esc to stop a running step (the skirt, Newton's method, 1000
//   iterations);
// * how long Esc takes to stop the skirt's dense setup (the handout's dense
//   code), and the viewer's resident memory before, during and 2 s after;
// * at 1024 × 768, each cloth's height over the window's once a
//   comparison (beside) has settled, without F;
// * at 390 × 844 with touch, the area where two panels overlap, drawer
//   closed and open;
// * the distance between the flag and its own frames written by `simulate
//   --out`, and what the viewer says of frames of another scene.
//
//     bash tests/browser/run.sh --targets
//
// Not a test: the figures depend on the machine; the browser tests check
// the same behaviours with bounds that hold on a loaded one.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { Session, root, binary, writeFrames } from './harness.mjs';

const flag = path.join(root, 'data/flag.json');
const skirt = path.join(root, 'data/skirt.json');
const print = (what, figure) => console.log(`${what}: ${figure}`);

/** Milliseconds from `started` (now by default) until `condition(status)`
 *  holds, polled every 5 ms. */
async function until(session, condition, started = performance.now(), limit = 60000) {
  while (performance.now() - started < limit) {
    if (condition(await session.status())) return performance.now() - started;
    await new Promise((resolve) => setTimeout(resolve, 5));
  }
  throw new Error('not within the limit');
}

/** Each control a user moves, and how to move it from the keyboard. */
const MOVES = [
  ['#k', 'ArrowLeft'], ['#delta_t', 'ArrowRight'], ['#mass_scale', 'ArrowLeft'], ['#iterations', 'ArrowLeft'],
  ['#solver', 'accuracy-assignment'], ['#compare', 'assignment'], ['#layout', 'overlay'], ['#method', 'chebyshev'],
];

async function keysAfterEachControl() {
  const session = await new Session().open(flag);
  await session.ready();
  const { page } = session;
  const times = [];
  for (const [selector, move] of MOVES) {
    const before = await session.status();
    if (move.startsWith('Arrow')) {
      await page.focus(selector);
      await page.keyboard.press(move);
    } else {
      await page.selectOption(selector, move);
    }
    await until(session, (s) => !s.busy && s.queued === 0);
    await page.waitForTimeout(300);
    const steps = (await session.status()).steps;
    const pressed = performance.now();
    await page.keyboard.press('Space');
    times.push([selector, await until(session, (s) => s.steps === steps + 1 && !s.busy, pressed)]);
    if (before.solver !== null) await session.command({ command: 'set_solver', solver: 'assignment' });
  }
  print('space after moving a control, ms (flag, each control)',
    times.map(([s, t]) => `${s} ${t.toFixed(0)}`).join(', '));
  await session.close();
  const long = await new Session().open(skirt, { flags: ['--method', 'newton', '--iterations', '1000'] });
  await long.ready();
  const stops = [];
  for (const selector of ['#iterations', '#method', '#solver', '#compare']) {
    await long.page.focus(selector);
    await long.page.keyboard.press('Space');
    await until(long, (s) => s.busy && s.busy.startsWith('step'));
    await long.page.waitForTimeout(700);
    const pressed = performance.now();
    await long.page.keyboard.press('Escape');
    stops.push([selector, await until(long, (s) => s.busy === null, pressed)]);
  }
  print('Esc ends a running step after, ms (skirt, Newton, focus on)',
    stops.map(([s, t]) => `${s} ${t.toFixed(0)}`).join(', '));
  await long.close();
}

async function denseSetup() {
  const session = await new Session().open(skirt);
  await session.ready();
  const { page } = session;
  print('the page says before the skirt\'s dense setup', (await session.status()).dense_memory);
  const before = session.residentMegabytes();
  await page.selectOption('#solver', 'textbook:dense');
  await until(session, (s) => (s.busy || '').startsWith('precomputing'));
  await page.waitForTimeout(3000);
  const during = session.residentMegabytes();
  const pressed = performance.now();
  await page.keyboard.press('Escape');
  const stopped = await until(session, (s) => s.busy === null, pressed);
  await new Promise((resolve) => setTimeout(resolve, Math.max(0, 2000 - (performance.now() - pressed))));
  const after = session.residentMegabytes();
  print('skirt\'s dense setup stopped by Esc, ms', stopped.toFixed(0));
  print('resident memory before, 3 s into the setup, 2 s after Esc, MB',
    [before, during, after].map((m) => m.toFixed(0)).join(', '));
  await session.close();
}

async function projector() {
  const session = await new Session().open(flag, { viewport: { width: 1024, height: 768 } });
  await session.ready();
  await session.page.selectOption('#compare', 'converged');
  await until(session, (s) => s.compare && !s.busy);
  const refits = await session.page.evaluate(() => window.viewer.refits);
  for (let step = 1; step <= 60; step++) {
    await session.command({ command: 'step' });
    await until(session, (s) => s.steps === step && !s.busy);
  }
  await session.page.waitForFunction((n) => window.viewer.refits > n, refits);
  await session.page.waitForTimeout(300);
  const heights = [await session.projectedBox(0), await session.projectedBox(1)]
    .map((box) => ((box.bottom - box.top) / 768).toFixed(2));
  print('1024 × 768, flag beside converged after 60 steps, each cloth\'s height / window height (no F)',
    heights.join(', '));
  await session.close();
}

async function phone() {
  const session = await new Session().open(flag, { viewport: { width: 390, height: 844 }, touch: true });
  await session.ready();
  const overlap = async () => {
    const panels = await session.page.evaluate(() => window.viewer.panels());
    let area = 0;
    panels.forEach((a, i) => panels.slice(i + 1).forEach((b) => {
      area += Math.max(0, Math.min(a.right, b.right) - Math.max(a.left, b.left))
        * Math.max(0, Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top));
    }));
    return `${area.toFixed(0)} px² among ${panels.length} panels`;
  };
  const closed = await overlap();
  await session.page.tap('#drawer');
  await session.page.waitForTimeout(300);
  print('390 × 844 touch, panels overlapping, drawer closed / open', `${closed} / ${await overlap()}`);
  await session.close();
}

async function frames() {
  const base = fs.mkdtempSync(path.join(os.tmpdir(), 'masssprings-targets-'));
  const own = path.join(base, 'flag');
  const other = path.join(base, 'net');
  writeFrames(flag, 30, own);
  writeFrames(path.join(root, 'data/net.json'), 3, other);
  const session = await new Session().open(flag, { flags: ['--frames', own] });
  await session.ready();
  for (let step = 1; step <= 30; step++) {
    await session.command({ command: 'step' });
    await until(session, (s) => s.steps === step && !s.busy);
  }
  const distances = (await session.status()).compare.history.map((r) => r.distance);
  print('flag beside its own frames (simulate --out), largest distance over 30 steps, m', Math.max(...distances));
  await session.close();
  try {
    execFileSync(binary, ['view', flag, '--port', '0', '--frames', other], { stdio: ['ignore', 'ignore', 'pipe'] });
  } catch (error) {
    print('frames of the net with the flag', `exit ${error.status}: ${String(error.stderr).trim()}`);
  }
  fs.rmSync(base, { recursive: true, force: true });
}

await keysAfterEachControl();
await denseSetup();
await projector();
await phone();
await frames();
