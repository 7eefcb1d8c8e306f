// The viewer as a teaching instrument, in headless Chromium: the solve
// picker switches between the assignment, the handout's code (dense and
// sparse) and the assignment's accuracy fast, and the overlay says which
// functions run; "compare with" runs a second simulation beside the first
// or as a wireframe over it, with both in the plot, and a drag pulls both;
// the scene fills the free area between the panels on wide and tall
// windows; a long step can be stopped from the page and commands sent
// during it are answered at once; without WebGL the page shows the
// server's images with the same controls; touch orbits, zooms and pulls.
//
// Run with tests/browser/run.sh (after viewer.test.mjs). Screenshots go to
// target/browser/; compare.png and without-webgl.png are docs/viewer.md's
// (`bash docs/images/screenshots.sh` redraws them).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { Session, root, outputFolder, NO_WEBGL_FLAGS } from './harness.mjs';

const flag = path.join(root, 'data/flag.json');
const net = path.join(root, 'data/net.json');
const skirt = path.join(root, 'data/skirt.json');

let session; // the flag at 1400 × 900 with WebGL, shared by the first tests

before(async () => {
  session = await new Session().open(flag);
  await session.ready();
});

after(async () => {
  await session?.close();
});

/** Picks `value` in the select `id` and gives the keys back to the page. */
async function pick(page, id, value) {
  await page.selectOption(`#${id}`, value);
  await page.evaluate(() => document.activeElement.blur());
}

test('the solve picker switches between the assignment, the handout\'s code and the fast mode', async () => {
  const { page } = session;
  const stats = () => page.textContent('#stats');
  assert.match(await stats(), /solve: the assignment \(plain, 50 iterations\)/);
  assert.match(await stats(), /sim\/methods\/plain\.rs/);
  const choices = [
    ['textbook:sparse', 'textbook', 'sparse', /fast_mass_springs_step_sparse/],
    ['accuracy-assignment', 'accuracy-assignment', 'sparse', /plain_then_lbfgs\.rs/],
    ['assignment', 'assignment', 'sparse', /methods\/plain\.rs/],
  ];
  for (const [value, solver, backend, functions] of choices) {
    const before = (await session.status()).steps;
    await pick(page, 'solver', value);
    await session.waitForStatus((s) => s.solver === solver && s.backend === backend, value, 30000);
    await page.waitForFunction((text) => new RegExp(text).test(document.getElementById('stats').textContent),
      functions.source);
    await page.click('#step');
    await session.waitForStatus((s) => s.steps === before + 1, `a step by ${value}`, 30000);
  }
  // The expert's method picker beside it; the rules are the command line's.
  await pick(page, 'solver', 'textbook:sparse');
  await session.waitForStatus((s) => s.solver === 'textbook', 'the handout\'s code');
  await page.check('#start');
  await page.waitForFunction(() => /refused: set_method: .*the textbook path runs the handout's step/
    .test(document.getElementById('stats').textContent));
  assert.equal((await session.status()).start, 'current');
  await pick(page, 'solver', 'assignment');
  await session.waitForStatus((s) => s.solver === 'assignment', 'the assignment again');
  await pick(page, 'method', 'chebyshev');
  await session.waitForStatus((s) => s.method === 'chebyshev' && s.solver === null, 'Chebyshev, the expert\'s');
  await page.waitForFunction(() => document.getElementById('solver').value === ''); // the method below
  await pick(page, 'solver', 'assignment');
  await session.waitForStatus((s) => s.solver === 'assignment' && s.method === 'plain', 'the assignment');
});

test('the handout\'s dense code runs on a small scene', async () => {
  const small = await new Session().open(net);
  try {
    await small.page.waitForFunction(() => window.viewer.ready && window.viewer.framesDrawn > 0);
    await pick(small.page, 'solver', 'textbook:dense');
    await small.waitForStatus((s) => s.solver === 'textbook' && s.backend === 'dense', 'dense');
    await small.page.waitForFunction(() => /fast_mass_springs_step_dense \(dense Cholesky\)/
      .test(document.getElementById('stats').textContent));
    await small.page.click('#step');
    await small.waitForStatus((s) => s.steps === 1, 'a dense step');
  } finally {
    await small.close();
  }
});

test('compare with: a second simulation beside the first, both in the plot, drags and wind on both', async () => {
  const { page } = session;
  await session.command({ command: 'reset' });
  await pick(page, 'compare', 'accuracy-assignment');
  await session.waitForStatus((s) => s.compare && s.compare.solver === 'accuracy-assignment', 'the comparison');
  await page.waitForFunction(() => window.viewer.state.second !== null);
  await page.click('#wind');
  await session.waitForStatus((s) => s.wind, 'the wind');
  for (let step = 1; step <= 4; step++) {
    await page.click('#step');
    await session.waitForStatus((s) => s.steps === step, `step ${step}`, 30000);
  }
  const s = await session.status();
  assert.equal(s.compare.history.length, 4);
  for (const record of [...s.history, ...s.compare.history]) {
    assert.ok(record.energy_decrease > 0 && record.ms > 0, JSON.stringify(record));
  }
  await page.waitForFunction(() => window.viewer.state.frameSteps === 4);
  await page.keyboard.press('f');
  await page.waitForTimeout(300);
  // Beside: the two flags side by side, apart, both on the canvas.
  const [first, second] = [await session.projectedBox(0), await session.projectedBox(1)];
  assert.ok(second.left > first.left + 0.5 * (first.right - first.left), JSON.stringify({ first, second }));
  await page.screenshot({ path: path.join(outputFolder, 'compare-fast.png') });
  await page.waitForFunction(() => /compared with \(right\): fast: every step as low in energy as the assignment's/
    .test(document.getElementById('stats').textContent));
  const beside = await session.canvasContent();
  await pick(page, 'layout', 'overlay');
  await page.waitForTimeout(300);
  const over = await session.canvasContent();
  assert.notEqual(over.fingerprint, beside.fingerprint, 'drawn as a wireframe over the first');
  await pick(page, 'layout', 'beside');
  await dragTheCompared(page);
});

/** Shift-drags the compared flag's free corner: both simulations pull it
 *  to the same target. */
async function dragTheCompared(page) {
  await page.keyboard.press('f');
  await page.waitForTimeout(200);
  const corner = 3199;
  const start = await page.evaluate((v) => window.viewer.screenPositionOf(v, 1), corner);
  await page.keyboard.down('Shift');
  await page.mouse.move(start.x, start.y);
  await page.mouse.down();
  await session.waitForStatus((s) => s.dragged === corner, 'the drag to start');
  await page.mouse.move(start.x + 40, start.y - 80, { steps: 8 });
  await page.waitForTimeout(500);
  const stepped = (await session.status()).steps + 1;
  await session.command({ command: 'step' }); // the drag moves both, step by step
  await page.waitForFunction((n) => window.viewer.state.frameSteps === n, stepped);
  const [target, first, second] = await page.evaluate((v) => [window.viewer.state.dragTarget,
    Array.from(window.viewer.state.positions.subarray(3 * v, 3 * v + 3)),
    Array.from(window.viewer.state.second.subarray(3 * v, 3 * v + 3))], corner);
  await page.mouse.up();
  await page.keyboard.up('Shift');
  await session.waitForStatus((s) => s.dragged === null, 'the drag to end');
  for (const p of [first, second]) {
    const distance = Math.hypot(...p.map((x, k) => x - target[k]));
    assert.ok(distance < 0.05, `the corner is ${distance} from its target`);
  }
  await pick(page, 'compare', '');
  await session.waitForStatus((s) => s.compare === null, 'the comparison stopped');
  await session.command({ command: 'toggle_wind' });
}

test('the docs\' picture: the assignment beside steps solved to convergence', async () => {
  const { page } = session;
  await session.command({ command: 'reset' });
  await pick(page, 'compare', 'converged');
  await session.waitForStatus((s) => s.compare && s.compare.solver === 'converged' && !s.wind, 'the comparison');
  const steps = 12;
  for (let step = 1; step <= steps; step++) {
    const answer = await session.command({ command: 'step' });
    assert.ok(answer.status === 200 || answer.status === 202, JSON.stringify(answer));
    await session.waitForStatus((s) => s.steps === step, `step ${step}`, 30000);
  }
  await page.waitForFunction((n) => window.viewer.state.frameSteps === n && window.viewer.plotPoints === n, steps);
  await page.keyboard.press('f');
  await page.waitForTimeout(500);
  await page.screenshot({ path: path.join(outputFolder, 'compare.png') });
  // What the picture teaches: the assignment's steps leave energy behind
  // that the converged ones take off: its flag falls slower, as through
  // honey, on every step.
  const s = await session.status();
  s.history.forEach((record, i) => {
    assert.ok(record.energy > s.compare.history[i].energy, `step ${record.step}: ${JSON.stringify([record, s.compare.history[i]])}`);
  });
  await pick(page, 'compare', '');
  await session.waitForStatus((x) => x.compare === null, 'the comparison stopped');
});

test('at start and on F the scene fills the free area between the panels, on wide and tall windows', async () => {
  const { page } = session;
  for (const viewport of [{ width: 1400, height: 900 }, { width: 700, height: 1100 }, { width: 1600, height: 700 }]) {
    await page.setViewportSize(viewport);
    await page.reload();
    await session.ready();
    await page.waitForTimeout(300);
    await checkFraming(page, viewport, 'at start');
    await page.keyboard.press('f');
    await page.waitForTimeout(200);
    await checkFraming(page, viewport, 'on F');
  }
  await page.setViewportSize({ width: 1400, height: 900 });
  await page.reload();
  await session.ready();
});

/** Every vertex within the framed area, which no panel covers, and the
 *  scene spans most of its width or height. */
async function checkFraming(page, viewport, when) {
  const area = await page.evaluate(() => window.viewer.framedArea);
  const panels = await page.evaluate(() => ['overlay', 'controls', 'help']
    .map((id) => document.getElementById(id).getBoundingClientRect().toJSON()));
  const box = await session.projectedBox();
  const what = JSON.stringify({ viewport, when, area, box });
  const inside = box.left >= area.left - 1 && box.right <= area.left + area.width + 1
    && box.top >= area.top - 1 && box.bottom <= area.top + area.height + 1;
  assert.ok(inside, what);
  for (const panel of panels) {
    const overlaps = box.left < panel.right && box.right > panel.left && box.top < panel.bottom && box.bottom > panel.top;
    assert.ok(!overlaps, `${what} under ${JSON.stringify(panel)}`);
  }
  const fill = Math.max((box.right - box.left) / area.width, (box.bottom - box.top) / area.height);
  assert.ok(fill > 0.75, `fills ${fill.toFixed(2)}: ${what}`);
  assert.ok(area.width * area.height > 0.3 * viewport.width * viewport.height, `a small area: ${what}`);
}

test('touch: one finger orbits, two pinch to zoom, a long press pulls a vertex', async () => {
  const { page } = session;
  const client = await page.context().newCDPSession(page);
  await client.send('Emulation.setTouchEmulationEnabled', { enabled: true, maxTouchPoints: 2 });
  const touch = (type, points) => client.send('Input.dispatchTouchEvent', {
    type, touchPoints: points.map(([x, y], id) => ({ x, y, id })),
  });
  const cameraNow = () => page.evaluate(() => ({ ...window.viewer.camera, target: [...window.viewer.camera.target] }));
  const area = await page.evaluate(() => window.viewer.framedArea);
  const [cx, cy] = [area.left + area.width / 2, area.top + area.height / 2];
  let before = await cameraNow();
  await touch('touchStart', [[cx, cy]]);
  for (let i = 1; i <= 5; i++) await touch('touchMove', [[cx + 20 * i, cy]]);
  await touch('touchEnd', []);
  let after = await cameraNow();
  assert.ok(Math.abs(after.azimuth - before.azimuth) > 0.5, `orbit: ${before.azimuth} → ${after.azimuth}`);
  before = after;
  await touch('touchStart', [[cx - 50, cy], [cx + 50, cy]]);
  for (let i = 1; i <= 5; i++) await touch('touchMove', [[cx - 50 - 20 * i, cy], [cx + 50 + 20 * i, cy]]);
  await touch('touchEnd', []);
  after = await cameraNow();
  assert.ok(after.distance < 0.6 * before.distance, `pinch: ${before.distance} → ${after.distance}`);
  await page.keyboard.press('f');
  await page.waitForTimeout(200);
  const corner = await page.evaluate(() => window.viewer.screenPositionOf(3199));
  await touch('touchStart', [[corner.x, corner.y]]);
  await session.waitForStatus((s) => s.dragged === 3199, 'a long press to pull the corner', 5000);
  for (let i = 1; i <= 5; i++) await touch('touchMove', [[corner.x, corner.y - 15 * i]]);
  await page.waitForFunction(() => window.viewer.state.dragTarget !== null);
  await touch('touchEnd', []);
  await session.waitForStatus((s) => s.dragged === null, 'the pull to end');
  await client.send('Emulation.setTouchEmulationEnabled', { enabled: false });
});

test('a long step is answered at once, can be stopped from the page, and stays at the last step', async () => {
  const long = await new Session().open(skirt, { flags: ['--method', 'newton', '--iterations', '1000'] });
  try {
    const { page } = long;
    await long.ready();
    await page.click('#step');
    await page.waitForFunction(() => /step 1: [0-9.]+ s so far · ■ stop \(Esc\) cancels it/
      .test(document.getElementById('stats').textContent), null, { timeout: 30000 })
      .catch(async (error) => { throw new Error(`${error}: ${await page.textContent('#stats')}`); });
    assert.equal(await page.isEnabled('#stop'), true);
    // the step's own answer first (202 too), so that it cannot come after
    // the wind's and take its place as the last command answered
    await page.waitForFunction(() => window.viewer.lastCommand && window.viewer.lastCommand.command === 'step');
    await page.click('#wind');
    await page.waitForFunction(() => window.viewer.lastCommand && window.viewer.lastCommand.command === 'toggle_wind')
      .catch(async (error) => {
        throw new Error(`${error}: ${JSON.stringify(await page.evaluate(() => window.viewer.lastCommand))}`);
      });
    const answer = await page.evaluate(() => window.viewer.lastCommand);
    assert.equal(answer.status, 202, JSON.stringify(answer));
    // Answered, not held until the step ends (tests/app/viewer.rs times the
    // answer itself; here the page's own work is in the time too).
    assert.ok(answer.ms < 2000, `answered after ${answer.ms} ms`);
    await page.waitForFunction(() => /toggle_wind: waits for the step in progress/
      .test(document.getElementById('stats').textContent))
      .catch(async (error) => { throw new Error(`${error}: ${await page.textContent('#stats')}`); });
    const started = Date.now();
    await page.keyboard.press('Escape'); // or ■ stop
    const s = await long.waitForStatus((x) => x.busy === null, 'the cancelled step', 5000);
    assert.ok(Date.now() - started < 3000, `stopped after ${Date.now() - started} ms`);
    assert.equal(s.steps, 0, 'the simulation stays at its last completed step');
    assert.equal(s.wind, true, 'the wind waited for the step and then blew');
    await page.waitForFunction(() => /step 1 cancelled after [0-9.]+ s: the simulation stays at step 0/
      .test(document.getElementById('stats').textContent))
      .catch(async (error) => { throw new Error(`${error}: ${await page.textContent('#stats')}`); });
    assert.equal(await page.isEnabled('#stop'), false);
    assert.deepEqual(long.pageErrors, []);
  } finally {
    await long.close();
  }
});

test('without WebGL the page shows the frames the crate\'s renderer draws, with the same controls', async () => {
  const plain = await new Session().open(flag, { chromiumFlags: NO_WEBGL_FLAGS });
  try {
    const { page } = plain;
    await page.waitForFunction(() => window.viewer.ready && window.viewer.imagesDrawn > 0, null, { timeout: 30000 });
    assert.equal(await page.evaluate(() => window.viewer.fallback), true);
    const still = await plain.canvasContent();
    assert.ok(still.foreground > 0.03, `the image covers ${(100 * still.foreground).toFixed(1)}%`);
    const images = await page.evaluate(() => window.viewer.imagesDrawn);
    await page.click('#step');
    await plain.waitForStatus((s) => s.steps === 1, 'a step');
    await page.waitForFunction((n) => window.viewer.imagesDrawn > n && window.viewer.state.frameSteps === 1, images);
    const azimuth = await page.evaluate(() => window.viewer.camera.azimuth);
    const area = await page.evaluate(() => window.viewer.framedArea);
    await page.mouse.move(area.left + area.width / 2, area.top + area.height / 2);
    await page.mouse.down();
    await page.mouse.move(area.left + area.width / 2 + 120, area.top + area.height / 2, { steps: 6 });
    await page.mouse.up();
    await page.waitForTimeout(1500);
    assert.notEqual(await page.evaluate(() => window.viewer.camera.azimuth), azimuth);
    const turned = await plain.canvasContent();
    assert.notEqual(turned.fingerprint, still.fingerprint, 'a new image for the new camera');
    await page.screenshot({ path: path.join(outputFolder, 'without-webgl.png') });
    await page.keyboard.press('w');
    await plain.waitForStatus((s) => s.wind, 'the wind (key W)');
    assert.deepEqual(plain.pageErrors, []);
  } finally {
    await plain.close();
  }
});
