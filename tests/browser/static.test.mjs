// The viewer's page with the simulation in the page (the static build of
// src/web/build.sh), served by a static server and driven in headless
// Chromium: the flag falls, the controls act, the three solvers run, a
// vertex can be pulled, the user's own scene opens (and a bad one gets the
// command line's message), a long step stops at once and never freezes the
// page, and no request goes to the server's /api/.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { StaticSession, binary, outputFolder, root } from './harness.mjs';

let session;
let page;

const status = () => session.status();
const waitForStatus = (condition, what, ms) => session.waitForStatus(condition, what, ms);

/** Milliseconds from the page's request to the flag drawn, textured. */
let openedToDrawn;

before(async () => {
  session = new StaticSession();
  const opened = performance.now();
  await session.open();
  ({ page } = session);
  await session.ready();
  openedToDrawn = performance.now() - opened;
});

after(async () => {
  await session.close();
});

test('the served folder opens on the flag, paused at rest, drawn, without a request to /api/', async () => {
  const s = await status();
  assert.equal(s.scene, 'flag');
  assert.equal(s.steps, 0);
  assert.equal(s.animating, false);
  assert.deepEqual(s.scenes.slice(0, 5), ['flag', 'skirt', 'horizontal-chain', 'net', 'single-spring-horizontal']);
  assert.ok((await session.canvasContent()).foreground > 0.02, 'the cloth is drawn');
  assert.ok(openedToDrawn < 30000, `drawn after ${openedToDrawn} ms`);
  assert.ok(await page.isVisible('#open'), 'a user can open a scene of their own');
  assert.equal(await page.isVisible('#solver option[value="textbook:dense"]'), false);
  assert.deepEqual(session.requests.filter((request) => request.startsWith('/api/')), []);
  assert.deepEqual(session.foreignRequests, []);
});

test('play, step, wind and reset act on the simulation in the page', async () => {
  await page.keyboard.press('a');
  const playing = await waitForStatus((s) => s.animating && s.steps >= 5, 'the flag falling');
  assert.ok(playing.history.length >= 5, 'the plot has steps');
  assert.ok(playing.energy < 0, 'the flag has fallen');
  await page.click('#play');
  const paused = await waitForStatus((s) => !s.animating, 'paused');
  await page.keyboard.press('Space');
  await waitForStatus((s) => s.steps === paused.steps + 1 && !s.animating, 'one more step');
  await page.click('#wind');
  await waitForStatus((s) => s.wind, 'the wind');
  await page.keyboard.press('r');
  const reset = await waitForStatus((s) => s.steps === 0 && !s.wind, 'the reset');
  assert.equal(reset.time, 0);
  assert.ok(await page.evaluate(() => window.viewer.plotPoints) >= 0);
});

test('the sliders change k, Δt, the masses and the iterations', async () => {
  const moves = [['k', 4, 1e4], ['delta_t', 0.02, 0.02], ['mass_scale', 0.5, 10 ** 0.5], ['iterations', 20, 20]];
  for (const [name, position, value] of moves) {
    await page.evaluate(([id, at]) => {
      const input = document.getElementById(id);
      input.value = String(at);
      input.dispatchEvent(new Event('change'));
    }, [name, position]);
    await waitForStatus((s) => s[name] === value, name);
  }
  const s = await status();
  assert.deepEqual([s.k, s.delta_t, s.mass_scale, s.iterations], [1e4, 0.02, 10 ** 0.5, 20]);
  await page.waitForFunction(() => /Q rebuilt and refactored in [0-9.]+ ms/.test(document.getElementById('stats').textContent));
  const refused = await session.command({ command: 'set_parameters', k: -1, delta_t: 0.02, mass_scale: 1, iterations: 20 });
  assert.equal(refused.status, 409);
  assert.equal(refused.body.error, 'k = -1: expected a stiffness from 1e-6 to 1e12');
  await page.keyboard.press('r');
  await waitForStatus((t) => t.k === 1e5 && t.delta_t === 1 / 30 && t.mass_scale === 1 && t.iterations === 50, 'the reset');
});

test('the solve picker switches between the assignment, the handout\'s code and the fast mode', async () => {
  const expected = [
    ['textbook:sparse', 'textbook', 'fast_mass_springs_step_sparse'],
    ['accuracy-assignment', 'accuracy-assignment', 'plain_then_lbfgs'],
    ['assignment', 'assignment', 'methods/plain.rs'],
  ];
  for (const [choice, solver, runs] of expected) {
    await page.selectOption('#solver', choice);
    const before = await waitForStatus((s) => s.solver === solver && !s.busy, solver);
    assert.ok(before.functions.includes(runs), before.functions);
    await page.keyboard.press('Space');
    const after = await waitForStatus((s) => s.steps === before.steps + 1, `a step of ${solver}`);
    assert.ok(after.history.at(-1).iterations >= 1);
  }
  const dense = await session.command({ command: 'set_solver', solver: 'textbook', backend: 'dense' });
  assert.equal(dense.status, 409);
  assert.match(dense.body.error, /dense code runs in the program only/);
});

test('compare runs a second simulation beside the first', async () => {
  await page.selectOption('#compare', 'accuracy-assignment');
  await waitForStatus((s) => s.compare && s.compare.solver === 'accuracy-assignment', 'the comparison');
  await page.keyboard.press('Space');
  const s = await waitForStatus((t) => t.compare && t.compare.history.length === 1, 'a step of both');
  assert.ok(s.compare.history[0].distance > 0, 'they move apart');
  await page.waitForFunction(() => window.viewer.state.second !== null);
  await page.selectOption('#compare', '');
  await waitForStatus((t) => t.compare === null, 'one simulation again');
});

test('shift-drag pulls a vertex through the solver', async () => {
  const corner = 3199; // free, the flag's far corner
  const start = await page.evaluate((i) => window.viewer.screenPositionOf(i), corner);
  await page.keyboard.down('Shift');
  await page.mouse.move(start.x, start.y);
  await page.mouse.down();
  await waitForStatus((s) => s.dragged !== null, 'the drag to start');
  await page.mouse.move(start.x + 60, start.y - 120, { steps: 10 });
  await page.keyboard.press('Space');
  await waitForStatus((s) => s.steps >= 1 && s.dragged !== null, 'a step while pulling');
  await page.mouse.up();
  await page.keyboard.up('Shift');
  const s = await waitForStatus((t) => t.dragged === null, 'the drag to end');
  assert.ok(s.refactor_ms !== null, 'the drag refactored Q');
});

/** Writes `files` ({ name: text or bytes }) into a fresh folder; their
 *  paths. */
function written(files) {
  const folder = fs.mkdtempSync(path.join(os.tmpdir(), 'masssprings-static-'));
  return Object.entries(files).map(([name, text]) => {
    fs.writeFileSync(path.join(folder, name), text);
    return path.join(folder, name);
  });
}

test('a user\'s own scene opens; a bad one gets the command line\'s message on the page, a broken texture a word', async () => {
  const net = ['net.json', 'net.obj'].map((name) => path.join(root, 'data', name));
  await page.setInputFiles('#open-files', net);
  const opened = await waitForStatus((s) => s.scene === 'net (yours)' && s.n > 0, 'the user\'s net');
  assert.equal(opened.scene_index, opened.scenes.length - 1);
  await page.waitForFunction(() => window.viewer.state.scene && window.viewer.state.scene.n > 0
    && window.viewer.state.status.scene === 'net (yours)');
  const bad = written({ 'bad.json': '{"obj": "bad.obj", "k": 100, "b": [1]}', 'bad.obj': 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n' });
  const cli = spawnSync(binary, ['simulate', bad[0], '--steps', '1'], { cwd: path.dirname(bad[0]), encoding: 'utf8' });
  assert.equal(cli.status, 1, cli.stderr);
  await page.setInputFiles('#open-files', bad);
  await page.waitForFunction(() => window.viewer.lastOpen && !window.viewer.lastOpen.ok);
  const error = await page.evaluate(() => window.viewer.lastOpen.error);
  assert.match(error, /^bad\.obj:4: malformed face corner `x`/);
  assert.ok(cli.stderr.includes(error.replace(/^bad\.obj/, '')), `the command line said ${cli.stderr}`);
  await page.waitForFunction((message) => document.getElementById('stats').textContent.includes(message), error);
  const after = await status();
  assert.equal(after.scene, 'net (yours)', 'the scene shown stays');
  assert.equal(after.scenes.filter((name) => name.startsWith('bad')).length, 0, 'a bad scene is not listed');
  // a texture with a PNG's signature that the browser cannot decode
  const flag = fs.readFileSync(path.join(root, 'data/flag.json'), 'utf8');
  const signature = Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
  const broken = written({
    'broken.json': flag.replace('flag.png', 'broken.png'),
    'broken.png': Buffer.concat([signature, Buffer.from(' not a picture')]),
  });
  await page.setInputFiles('#open-files', [broken[0], path.join(root, 'data/flag.obj'), broken[1]]);
  await waitForStatus((s) => s.scene === 'broken (yours)', 'a scene whose PNG is broken');
  await page.waitForFunction(() => document.getElementById('stats').textContent.includes('cannot decode this PNG'));
  await page.selectOption('#scene', '0');
  await waitForStatus((s) => s.scene === 'flag', 'the flag again');
});

test('a long step never freezes the page, and Esc stops it within half a second', async (t) => {
  await page.selectOption('#scene', '1'); // the skirt
  await waitForStatus((s) => s.scene === 'skirt' && !s.busy, 'the skirt');
  await session.command({ command: 'set_method', method: 'newton', tolerance: null });
  await session.command({ command: 'set_parameters', k: 1e5, delta_t: 1 / 30, mass_scale: 1, iterations: 1000 });
  const before = await status();
  await page.keyboard.press('Space');
  await waitForStatus((s) => s.busy === `step ${before.steps + 1}`, 'the long step');
  const frames = await page.evaluate(() => new Promise((resolve) => {
    let count = 0;
    const started = performance.now();
    const count_ = () => {
      count += 1;
      if (performance.now() - started < 700) requestAnimationFrame(count_); else resolve(count);
    };
    requestAnimationFrame(count_);
  }));
  assert.ok(frames >= 7, `the page drew ${frames} frames in 0.7 s of the step`);
  // timed in the page, from the stop sent to its answer (the test's round
  // trips to a page busy drawing the skirt in software would add a few
  // hundred ms on a loaded machine)
  await page.evaluate(() => {
    const command = backend.command;
    backend.command = async (body) => {
      const started = performance.now();
      const answer = await command(body);
      if (body.command === 'cancel') window.stopAnsweredMs = performance.now() - started;
      return answer;
    };
  });
  await page.keyboard.press('Escape');
  const stopped = await waitForStatus((s) => s.busy === null, 'the stop', 5000);
  const ms = await page.evaluate(() => window.stopAnsweredMs);
  t.diagnostic(`stop answered in ${ms.toFixed(0)} ms; ${frames} frames drawn in 0.7 s of the step`);
  assert.ok(ms < 500, `stopped after ${ms.toFixed(0)} ms`);
  assert.equal(stopped.steps, before.steps);
  assert.match(stopped.note, /cancelled after [0-9.]+ s: the simulation stays at step/);
  await page.screenshot({ path: path.join(outputFolder, 'static-stopped.png') });
  // the fresh worker goes on from the state before the step
  const restarted = await waitForStatus((s) => s.method === 'newton' && s.iterations === 1000, 'the settings kept');
  assert.equal(restarted.scene, 'skirt');
  await session.command({ command: 'set_method', method: 'plain', tolerance: null });
  await session.command({ command: 'set_parameters', k: 1e5, delta_t: 1 / 30, mass_scale: 1, iterations: 50 });
  await page.keyboard.press('Space');
  await waitForStatus((s) => s.steps === before.steps + 1, 'a step after the stop');
  assert.deepEqual(session.requests.filter((request) => request.startsWith('/api/')), []);
  assert.deepEqual(session.pageErrors, []);
});
