// The viewer as a person uses it: `masssprings view data/flag.json` opened in
// headless Chromium (Debian's /usr/bin/chromium, driven by playwright-core).
// Checks that the page starts paused at rest and the canvas shows the
// textured flag, that the keys, the buttons, the sliders (a change of k
// refactors Q), the method picker and the scene picker change the
// simulation's state, that F fits and right-drag pans the camera, that
// shift-drag pulls a vertex, that the page loads nothing from elsewhere, and
// saves screenshots to target/browser/ (viewer.png and skirt.png are the
// ones in docs/viewer.md: `tests/browser/run.sh --update-screenshots` copies
// them to docs/images/).
//
// Run with tests/browser/run.sh (it builds the binary and installs what is
// missing); harness.mjs starts the viewer and the browser. teaching.test.mjs
// checks the solvers, the comparison, the framing, long steps, the page
// without WebGL and touch.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { Session, root, outputFolder } from './harness.mjs';

const session = new Session();
let page;
let url;
const status = () => session.status();
const waitForStatus = (condition, what, ms) => session.waitForStatus(condition, what, ms);
const canvasContent = () => session.canvasContent();

before(async () => {
  await session.open(path.join(root, 'data/flag.json'));
  ({ page, url } = session);
});

after(async () => {
  await session.close();
});

test('the page starts paused at rest and draws the textured flag on the canvas', async () => {
  await page.waitForFunction(() => window.viewer.ready && window.viewer.textureLoaded
    && window.viewer.framesReceived > 0 && window.viewer.framesDrawn > 0, null, { timeout: 20000 });
  await page.waitForTimeout(200); // the texture drawn too
  const { foreground } = await canvasContent();
  assert.ok(foreground > 0.01, `only ${(100 * foreground).toFixed(2)}% of the canvas differs from the background`);
  const overlay = await page.textContent('#stats');
  assert.match(overlay, /3,200 vertices · 12,442 springs/);
  assert.match(overlay, /paused at rest/);
  const s = await status();
  assert.equal(s.animating, false);
  assert.equal(s.steps, 0, 'nothing ran before anyone pressed play');
  assert.equal(s.watched, true, 'the page counts as watching');
  assert.equal(await page.textContent('#play'), '▶ play');
});

test('space advances exactly one step per press', async () => {
  const paused = await status();
  await page.keyboard.press('Space');
  await waitForStatus((s) => s.steps === paused.steps + 1 && !s.animating, 'one more step');
  await new Promise((resolve) => setTimeout(resolve, 300));
  assert.equal((await status()).steps, paused.steps + 1, 'no step while paused');
});

test('R resets to rest, W toggles the wind, A the animation', async () => {
  await page.keyboard.press('r');
  await waitForStatus((s) => s.steps === 0 && s.time === 0, 'the reset');
  const before = await status();
  await page.keyboard.press('w');
  await waitForStatus((s) => s.wind === !before.wind, 'the wind');
  await page.keyboard.press('a');
  await waitForStatus((s) => s.animating && s.steps > 2, 'the animation');
  await page.keyboard.press('a');
  await waitForStatus((s) => !s.animating, 'the pause');
});

test('L shows and hides the springs and point masses', async () => {
  const hidden = await status();
  assert.equal(hidden.show_springs, false, 'a cloth starts with its springs hidden');
  const without = await canvasContent();
  await page.keyboard.press('l');
  await waitForStatus((s) => s.show_springs, 'springs shown');
  await page.waitForTimeout(300);
  const withSprings = await canvasContent();
  await page.screenshot({ path: path.join(outputFolder, 'springs.png') });
  assert.notEqual(withSprings.fingerprint, without.fingerprint, 'the picture changed');
  await page.keyboard.press('l');
  await waitForStatus((s) => !s.show_springs, 'springs hidden');
});

test('shift-drag pulls the nearest vertex through the solver', async () => {
  // the corner is taken while the cloth is still (in the wind it moves
  // further than the pick's radius between finding it and pressing)
  await waitForStatus((s) => !s.animating, 'paused');
  const corner = 3199; // the free corner at the far end from the pole
  const start = await page.evaluate((v) => window.viewer.screenPositionOf(v), corner);
  const positionOf = (v) => page.evaluate((i) => Array.from(window.viewer.state.positions.subarray(3 * i, 3 * i + 3)), v);
  await page.keyboard.down('Shift');
  await page.mouse.move(start.x, start.y);
  await page.mouse.down();
  await waitForStatus((s) => s.dragged === corner, 'the drag to start');
  await page.keyboard.press('a'); // animate, so the solver moves the vertex
  await waitForStatus((s) => s.animating, 'the animation');
  await page.mouse.move(start.x + 60, start.y - 120, { steps: 10 });
  await page.waitForTimeout(1000);
  await page.screenshot({ path: path.join(outputFolder, 'drag.png') });
  const pulled = await positionOf(corner);
  const target = await page.evaluate(() => window.viewer.state.dragTarget);
  const distance = Math.hypot(...pulled.map((p, k) => p - target[k]));
  await page.mouse.up();
  await page.keyboard.up('Shift');
  await waitForStatus((s) => s.dragged === null, 'the drag to end');
  assert.ok(distance < 0.05, `the dragged vertex is ${distance} from its target`);
});

test('the buttons play, pause, step, toggle the wind and the springs', async () => {
  if ((await status()).animating) await page.click('#play');
  await waitForStatus((s) => !s.animating, 'paused');
  await page.click('#play');
  await waitForStatus((s) => s.animating && s.steps > 2, 'the animation');
  await page.waitForFunction(() => document.getElementById('play').textContent.includes('pause'));
  await page.click('#play');
  const paused = await waitForStatus((s) => !s.animating, 'the pause');
  await page.click('#step');
  await waitForStatus((s) => s.steps === paused.steps + 1, 'a step');
  await page.click('#wind');
  await waitForStatus((s) => s.wind !== paused.wind, 'the wind');
  await page.click('#wind');
  await page.click('#springs');
  await waitForStatus((s) => s.show_springs, 'springs shown');
  await page.click('#springs');
  await waitForStatus((s) => !s.show_springs, 'springs hidden');
  await page.click('#reset');
  await waitForStatus((s) => s.steps === 0, 'the reset');
});

test('a change of k with the slider refactors Q, and the overlay shows how long it took', async () => {
  const before = await status();
  await page.evaluate(() => {
    const slider = document.getElementById('k');
    slider.value = String(Number(slider.value) - 1); // ten times softer
    slider.dispatchEvent(new Event('input'));
    slider.dispatchEvent(new Event('change'));
  });
  const after = await waitForStatus((s) => s.refactor_ms !== null && Math.abs(s.k - before.k / 10) < 1e-6 * before.k,
    'k / 10 and a refactorization');
  assert.ok(after.refactor_ms > 0);
  assert.equal(after.delta_t, before.delta_t, 'only k changed');
  await page.waitForFunction(() => /Q rebuilt and refactored in [0-9.]+ ms/.test(document.getElementById('stats').textContent));
  await page.evaluate(() => {
    const slider = document.getElementById('iterations');
    slider.value = '20';
    slider.dispatchEvent(new Event('change'));
  });
  await waitForStatus((s) => s.iterations === 20, '20 iterations');
  await page.evaluate(() => {
    const slider = document.getElementById('iterations');
    slider.value = '50'; // the assignment's again
    slider.dispatchEvent(new Event('change'));
  });
  await waitForStatus((s) => s.iterations === 50 && s.solver === 'assignment', 'the assignment again');
});

test('the method picker and the convergence plot', async () => {
  try {
    await page.selectOption('#method', 'chebyshev');
    await waitForStatus((s) => s.method === 'chebyshev', 'Chebyshev');
    await page.waitForFunction(() => window.viewer.state.status.method === 'chebyshev');
    await page.check('#at_least_plain'); // the floor: at least plain-50's decrease
    await waitForStatus((s) => s.at_least_plain === 50, 'the floor of plain-50');
    await page.waitForFunction(() => document.getElementById('stats').textContent.includes('at least plain-50'));
    await page.evaluate(() => document.activeElement.blur()); // keys go to the page again
    await page.keyboard.press('m'); // the next method, keeping the floor
    await waitForStatus((s) => s.method === 'anderson' && s.at_least_plain === 50, 'Anderson');
    await page.check('#start'); // start each step from the momentum's prediction
    await waitForStatus((s) => s.start === 'inertial' && s.method === 'anderson', 'inertial start');
    await page.evaluate(() => document.activeElement.blur());
    const before = (await status()).steps;
    for (let i = 1; i <= 3; i++) {
      await page.click('#step');
      await waitForStatus((s) => s.steps === before + i, `step ${i}`, 30000);
    }
    await page.waitForFunction(() => window.viewer.plotPoints >= 3);
    const s = await status();
    const last = s.history.slice(-3);
    assert.ok(last.every((r) => r.iterations <= s.iterations && Number.isFinite(r.relative_gradient)),
      JSON.stringify(last));
    assert.ok(await page.isChecked('#start'));
  } finally {
    await page.uncheck('#at_least_plain');
    await waitForStatus((s) => s.at_least_plain === null, 'no floor again');
    await page.uncheck('#start');
    await waitForStatus((s) => s.start === 'current', 'the assignment\'s start again');
    await page.selectOption('#method', 'plain');
    await waitForStatus((s) => s.method === 'plain', 'plain again');
    await page.evaluate(() => document.activeElement.blur()); // keys go to the page again
  }
});

test('F fits the camera to the cloth; right-drag pans; the wheel zooms toward the cursor', async () => {
  const fits = await page.evaluate(() => window.viewer.fits);
  await page.keyboard.press('f');
  await page.waitForFunction((n) => window.viewer.fits === n + 1, fits);
  const fitted = await page.evaluate(() => ({ ...window.viewer.camera, target: [...window.viewer.camera.target] }));
  assert.equal(fitted.follow, true, 'F follows the cloth again');
  await page.mouse.move(700, 450);
  await page.mouse.down({ button: 'right' });
  await page.mouse.move(760, 470, { steps: 5 });
  await page.mouse.up({ button: 'right' });
  const panned = await page.evaluate(() => [...window.viewer.camera.target]);
  assert.ok(Math.hypot(...panned.map((t, k) => t - fitted.target[k])) > 1e-3, 'the target moved');
  assert.equal(await page.evaluate(() => window.viewer.camera.follow), false, 'a pan takes the camera');
  await page.mouse.move(600, 500);
  await page.mouse.wheel(0, -300);
  const zoomed = await page.evaluate(() => ({ distance: window.viewer.camera.distance, target: [...window.viewer.camera.target] }));
  assert.ok(zoomed.distance < fitted.distance, 'closer');
  await page.click('#fit');
  await page.waitForFunction((n) => window.viewer.fits === n + 2, fits);
  // Fitted: every vertex within the free area between the panels, and the
  // cloth spans most of its width or height (teaching.test.mjs measures
  // the framing on wide and tall windows).
  const area = await page.evaluate(() => window.viewer.framedArea);
  const box = await session.projectedBox();
  assert.ok(box.left >= area.left - 1 && box.right <= area.left + area.width + 1
    && box.top >= area.top - 1 && box.bottom <= area.top + area.height + 1, JSON.stringify({ box, area }));
  assert.ok(Math.max((box.right - box.left) / area.width, (box.bottom - box.top) / area.height) > 0.7,
    JSON.stringify({ box, area }));
});

test('? shows the help and Esc hides it', async () => {
  await page.keyboard.press('?');
  assert.equal(await page.isVisible('#help-overlay'), true);
  await page.keyboard.press('Escape');
  assert.equal(await page.isVisible('#help-overlay'), false);
});

test('the scene picker switches to the skirt and back', async () => {
  const options = await page.$$eval('#scene option', (o) => o.map((x) => x.textContent));
  assert.ok(options.includes('skirt') && options[0] === 'flag', options.join(', '));
  const loaded = await page.evaluate(() => window.viewer.scenesLoaded);
  await page.selectOption('#scene', { label: 'skirt' });
  await waitForStatus((s) => s.scene === 'skirt' && s.n === 9840 && s.steps === 0, 'the skirt', 20000);
  await page.waitForFunction((n) => window.viewer.scenesLoaded > n && window.viewer.textureLoaded
    && window.viewer.state.positions && window.viewer.state.positions.length === 3 * 9840, loaded, { timeout: 20000 });
  for (let step = 1; step <= 3; step++) {
    await page.click('#step');
    await waitForStatus((s) => s.steps === step, `skirt step ${step}`);
  }
  await page.waitForFunction(() => window.viewer.state.frameSteps === 3);
  await page.waitForTimeout(300);
  const { foreground } = await canvasContent();
  assert.ok(foreground > 0.03, `the skirt covers ${(100 * foreground).toFixed(1)}% of the canvas`);
  await page.screenshot({ path: path.join(outputFolder, 'skirt.png') });
  await page.selectOption('#scene', { label: 'flag' });
  await waitForStatus((s) => s.scene === 'flag' && s.n === 3200, 'the flag again', 20000);
  await page.waitForFunction(() => window.viewer.state.positions && window.viewer.state.positions.length === 3 * 3200
    && window.viewer.textureLoaded, null, { timeout: 20000 });
});

test('a screenshot of the flag in the wind is saved; nothing was loaded from elsewhere', async () => {
  // A picture that does not depend on the machine's speed: reset, wind on,
  // then four single steps (space).
  if ((await status()).animating) await page.keyboard.press('a');
  await waitForStatus((s) => !s.animating, 'the pause');
  await page.keyboard.press('r');
  const reset = await waitForStatus((s) => s.steps === 0, 'the reset');
  if (!reset.wind) await page.keyboard.press('w');
  await waitForStatus((s) => s.wind, 'the wind');
  for (let step = 1; step <= 4; step++) {
    await page.keyboard.press('Space');
    await waitForStatus((s) => s.steps === step, `step ${step}`);
  }
  await page.waitForFunction(() => window.viewer.state.frameSteps === 4);
  await page.keyboard.press('f');
  await page.waitForTimeout(200); // drawn
  const file = path.join(outputFolder, 'viewer.png');
  await page.screenshot({ path: file });
  assert.ok(fs.statSync(file).size > 10000);
  assert.deepEqual(session.foreignRequests, []);
  assert.deepEqual(session.pageErrors, []);
});
