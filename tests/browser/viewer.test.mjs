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
// missing). Environment: MASSSPRINGS_BIN (the binary), CHROMIUM (the browser).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { createInterface } from 'node:readline';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const binary = process.env.MASSSPRINGS_BIN ?? path.join(root, 'target/debug/masssprings');
const outputFolder = path.join(root, 'target/browser');

// The launch flags of the machine notes: no sandbox (root), no GPU, and no
// background connections (the network is closed). WebGL runs on SwiftShader.
const CHROMIUM_FLAGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
];

let viewer; // the masssprings child process
let url; // http://127.0.0.1:PORT/
let browser;
let page;
const pageErrors = [];
const foreignRequests = [];

/** Starts `masssprings view SCENE --port 0` and reads the URL it prints. */
async function startViewer(scene) {
  const child = spawn(binary, ['view', scene, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  const lines = createInterface({ input: child.stdout });
  const firstLine = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error('no URL within 30 s')), 30000);
    lines.once('line', (line) => { clearTimeout(timer); resolve(line); });
    child.once('exit', (code) => reject(new Error(`viewer exited with ${code}`)));
  });
  assert.match(firstLine, /^http:\/\/127\.0\.0\.1:\d+\/$/);
  return { child, url: firstLine };
}

async function status() {
  const response = await fetch(`${url}api/status`);
  return response.json();
}

/** Polls `condition(status)` until it holds (or fails after `ms`). */
async function waitForStatus(condition, what, ms = 10000) {
  const deadline = Date.now() + ms;
  for (;;) {
    const s = await status();
    if (condition(s)) return s;
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${what}: ${JSON.stringify(s)}`);
    await new Promise((resolve) => setTimeout(resolve, 50));
  }
}

/** The share of canvas pixels that differ clearly from the background
 *  gradient of that row, and a cheap fingerprint of the image. */
async function canvasContent() {
  return page.evaluate(() => {
    const source = document.getElementById('view');
    const copy = document.createElement('canvas');
    copy.width = source.width;
    copy.height = source.height;
    const context = copy.getContext('2d');
    context.drawImage(source, 0, 0);
    const { data, width, height } = context.getImageData(0, 0, copy.width, copy.height);
    const { backgroundTop: top, backgroundBottom: bottom } = window.viewer.look;
    let foreground = 0;
    let fingerprint = 0;
    for (let y = 0; y < height; y++) {
      const h = 1 - (y + 0.5) / height; // 1 at the top row
      const expected = [0, 1, 2].map((k) => 255 * (bottom[k] + (top[k] - bottom[k]) * h));
      for (let x = 0; x < width; x++) {
        const i = 4 * (y * width + x);
        const far = [0, 1, 2].some((k) => Math.abs(data[i + k] - expected[k]) > 30);
        if (far) foreground++;
        fingerprint = (fingerprint * 31 + data[i] + 7 * data[i + 1] + 13 * data[i + 2]) % 1000000007;
      }
    }
    return { foreground: foreground / (width * height), fingerprint };
  });
}

let userDataDir; // Chromium's profile, removed when the tests are done

before(async () => {
  fs.mkdirSync(outputFolder, { recursive: true });
  ({ child: viewer, url } = await startViewer(path.join(root, 'data/flag.json')));
  userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'masssprings-chromium-'));
  browser = await chromium.launchPersistentContext(userDataDir, {
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: CHROMIUM_FLAGS,
    viewport: { width: 800, height: 450 },
  });
  page = browser.pages()[0] ?? await browser.newPage();
  page.on('pageerror', (error) => pageErrors.push(String(error)));
  page.on('console', (message) => { if (message.type() === 'error') pageErrors.push(message.text()); });
  page.on('request', (request) => {
    if (!request.url().startsWith(url) && !request.url().startsWith('data:')) foreignRequests.push(request.url());
  });
  await page.goto(url);
});

after(async () => {
  await browser?.close();
  if (userDataDir) fs.rmSync(userDataDir, { recursive: true, force: true });
  if (viewer && viewer.exitCode === null) {
    const exited = new Promise((resolve) => viewer.once('exit', resolve));
    viewer.kill('SIGINT');
    const timer = setTimeout(() => viewer.kill('SIGKILL'), 5000);
    await exited;
    clearTimeout(timer);
  }
});

test('the page starts paused at rest and draws the textured flag on the canvas', async () => {
  await page.waitForFunction(() => window.viewer.ready && window.viewer.textureLoaded
    && window.viewer.framesReceived > 0 && window.viewer.framesDrawn > 10, null, { timeout: 20000 });
  const { foreground } = await canvasContent();
  assert.ok(foreground > 0.01, `only ${(100 * foreground).toFixed(2)}% of the canvas differs from the background`);
  const overlay = await page.textContent('#stats');
  assert.match(overlay, /n 3200 · springs 12442/);
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
  await page.keyboard.press('a'); // animate, so the solver moves the vertex
  await waitForStatus((s) => s.animating, 'the animation');
  const corner = 3199; // the free corner at the far end from the pole
  const start = await page.evaluate((v) => window.viewer.screenPositionOf(v), corner);
  const positionOf = (v) => page.evaluate((i) => Array.from(window.viewer.state.positions.subarray(3 * i, 3 * i + 3)), v);
  await page.keyboard.down('Shift');
  await page.mouse.move(start.x, start.y);
  await page.mouse.down();
  await waitForStatus((s) => s.dragged === corner, 'the drag to start');
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
  assert.equal(fitted.autoFrame, false);
  await page.mouse.move(400, 225);
  await page.mouse.down({ button: 'right' });
  await page.mouse.move(460, 245, { steps: 5 });
  await page.mouse.up({ button: 'right' });
  const panned = await page.evaluate(() => [...window.viewer.camera.target]);
  assert.ok(Math.hypot(...panned.map((t, k) => t - fitted.target[k])) > 1e-3, 'the target moved');
  await page.mouse.move(200, 120);
  await page.mouse.wheel(0, -300);
  const zoomed = await page.evaluate(() => ({ distance: window.viewer.camera.distance, target: [...window.viewer.camera.target] }));
  assert.ok(zoomed.distance < fitted.distance, 'closer');
  await page.click('#fit');
  await page.waitForFunction((n) => window.viewer.fits === n + 2, fits);
  // Fitted: every vertex on the canvas, and the cloth spans most of its
  // width or height.
  const extent = await page.evaluate(() => {
    const canvas = document.getElementById('view');
    const xs = [];
    const ys = [];
    for (let i = 0; i < window.viewer.state.scene.n; i++) {
      const p = window.viewer.screenPositionOf(i);
      xs.push(p.x / canvas.clientWidth);
      ys.push(p.y / canvas.clientHeight);
    }
    return { left: Math.min(...xs), right: Math.max(...xs), top: Math.min(...ys), bottom: Math.max(...ys) };
  });
  assert.ok(extent.left >= 0 && extent.right <= 1 && extent.top >= 0 && extent.bottom <= 1, JSON.stringify(extent));
  assert.ok(Math.max(extent.right - extent.left, extent.bottom - extent.top) > 0.7, JSON.stringify(extent));
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
  assert.ok(foreground > 0.05, `the skirt covers ${(100 * foreground).toFixed(1)}% of the canvas`);
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
  assert.deepEqual(foreignRequests, []);
  assert.deepEqual(pageErrors, []);
});
