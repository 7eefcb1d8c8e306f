// The viewer in front of a class, in headless Chromium: the keys act
// whatever control has focus; Esc stops a step and the handout's dense
// setup (whose memory the page names before it starts, and which is given
// back); the plots have tick labels, units and both solvers' names, and
// never "Infinity"; large print on a projector's width; labels over the
// cloths; the camera frames a comparison as it settles, big enough to see
// from the back of a room, on a 1024 × 768 projector; every number has its
// unit and an explanation; reset returns to the scene as it loaded, and
// restart keeps the settings; on a phone the panels fold into a drawer and
// never overlap; a program's own frames (--frames) play beside ours.
//
// Run with tests/browser/run.sh (after the others). Screenshots go to
// target/browser/: projector.png and phone.png are docs/viewer.md's (`bash
// docs/images/screenshots.sh` redraws them).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { Session, root, outputFolder, writeFrames } from './harness.mjs';

const flag = path.join(root, 'data/flag.json');
const skirt = path.join(root, 'data/skirt.json');

/** Runs `body(session)` on a viewer of `scene` opened with `options`. */
async function withViewer(scene, options, body) {
  const session = await new Session().open(scene, options);
  try {
    await session.ready();
    await body(session);
    assert.deepEqual(session.pageErrors, []);
  } finally {
    await session.close();
  }
}

const stats = (page) => page.textContent('#stats');

/** Presses `key` and waits until the status says the step after `steps`
 *  is done. */
async function stepWith(session, key, steps) {
  await session.page.keyboard.press(key);
  return session.waitForStatus((s) => s.steps === steps + 1 && !s.busy, `a step by ${key}`, 30000);
}

test('the keys act whatever control has focus, but a text field', async () => {
  await withViewer(flag, {}, async (session) => {
    const { page } = session;
    // A slider moved with the keyboard: it keeps the focus.
    await page.focus('#iterations');
    await page.keyboard.press('ArrowLeft');
    await session.waitForStatus((s) => s.iterations === 49, 'the slider moved');
    let s = await stepWith(session, 'Space', 0);
    assert.equal(await page.evaluate(() => document.activeElement.id), 'iterations');
    // A picker: space steps, A plays, and no letter picks an option.
    await page.selectOption('#method', 'chebyshev');
    await session.waitForStatus((x) => x.method === 'chebyshev', 'Chebyshev');
    await page.focus('#method');
    s = await stepWith(session, 'Space', s.steps);
    await page.keyboard.press('a');
    await session.waitForStatus((x) => x.animating, 'A plays with the picker focused');
    await page.keyboard.press('a');
    s = await session.waitForStatus((x) => !x.animating, 'A pauses');
    assert.equal(await page.$eval('#method', (m) => m.value), 'chebyshev', 'A picked no option');
    // A button just clicked: space is one step, not a step and a click.
    await page.focus('#step');
    s = await stepWith(session, 'Space', s.steps);
    await page.waitForTimeout(500);
    assert.equal((await session.status()).steps, s.steps, 'one step for one press');
    // A checkbox: space steps and does not tick it.
    await page.focus('#start');
    await stepWith(session, 'Space', s.steps);
    assert.equal((await session.status()).start, 'current');
    // A text field takes its letters.
    await page.evaluate(() => {
      const field = document.createElement('input');
      field.id = 'typed';
      document.getElementById('controls').append(field);
    });
    await page.focus('#typed');
    await page.keyboard.type('a w');
    await page.waitForTimeout(500);
    s = await session.status();
    assert.equal(s.animating, false);
    assert.equal(s.wind, false);
    assert.equal(await page.$eval('#typed', (field) => field.value), 'a w');
    await session.command({ command: 'reset' });
  });
});

test('Esc stops a long step with the method picker focused', async () => {
  const flags = ['--method', 'newton', '--iterations', '1000'];
  await withViewer(skirt, { flags }, async (session) => {
    const { page } = session;
    await page.focus('#method');
    await page.keyboard.press('Space');
    await session.waitForStatus((s) => s.busy === 'step 1', 'the long step', 30000);
    await page.waitForTimeout(500);
    const pressed = Date.now();
    await page.keyboard.press('Escape');
    const s = await session.waitForStatus((x) => x.busy === null, 'the step stopped', 10000);
    assert.ok(Date.now() - pressed < 5000, `stopped after ${Date.now() - pressed} ms`);
    assert.equal(s.steps, 0);
    assert.equal(await page.evaluate(() => document.activeElement.id), 'method');
  });
});

test('the handout\'s dense setup says what it takes, stops on Esc, and gives its memory back', async () => {
  await withViewer(flag, {}, async (session) => {
    const { page } = session;
    const label = await page.$eval('#solver option[value="textbook:dense"]', (o) => [o.textContent, o.title]);
    assert.match(label[0], /^the handout's code, dense \([0-9.]+ GB\)$/);
    assert.match(label[1], /the dense path for n = 3,200 \(12,442 springs; five n × n matrices of f64\): [0-9.]+ GB/);
    const before = session.residentMegabytes();
    await page.selectOption('#solver', 'textbook:dense');
    await session.waitForStatus((s) => /^precomputing for textbook \(dense\): the dense path for n = 3,200 .*GB$/
      .test(s.busy || ''), 'the dense setup', 10000);
    await page.waitForFunction(() => /precomputing for textbook \(dense\).*GB: [0-9.]+ s so far · ■ stop \(Esc\)/
      .test(document.getElementById('stats').textContent));
    await page.waitForTimeout(1500);
    const during = session.residentMegabytes();
    const pressed = Date.now();
    await page.keyboard.press('Escape'); // the picker still has the focus
    const s = await session.waitForStatus((x) => x.busy === null, 'the setup stopped', 10000);
    assert.ok(Date.now() - pressed < 5000, `stopped after ${Date.now() - pressed} ms`);
    assert.equal(s.solver, 'assignment', 'nothing changed');
    assert.match(s.note, /precomputing for textbook \(dense\).*: cancelled after [0-9.]+ s; nothing changed/);
    await page.waitForFunction(() => document.getElementById('solver').value === 'assignment');
    await page.waitForTimeout(1000);
    const after = session.residentMegabytes();
    assert.ok(during > before + 50 && after < before + 50, `${before} MB, ${during} MB setting up, ${after} MB after`);
  });
});

/** No drawn or written number reads "Infinity" or "NaN". */
async function noNonsense(page) {
  const texts = [await stats(page), ...await page.evaluate(() => window.viewer.plotText)];
  for (const text of texts) assert.doesNotMatch(text, /Infinity|NaN|undefined|null/, text);
}

test('on a projector: large print, plots with ticks, units and both names, labels over the cloths', async () => {
  await withViewer(flag, { viewport: { width: 1024, height: 768 } }, async (session) => {
    const { page } = session;
    assert.equal(await page.evaluate(() => document.body.classList.contains('large')), true);
    const size = (selector) => page.$eval(selector, (e) => parseFloat(getComputedStyle(e).fontSize));
    for (const selector of ['#stats', '#controls', '#help']) assert.ok(await size(selector) >= 16, selector);
    await page.waitForFunction(() => window.viewer.plotText.includes('time per step (ms)'));
    assert.ok((await page.evaluate(() => window.viewer.plotText)).some((t) => t.startsWith('no steps yet')));
    await noNonsense(page);
    // A comparison at rest says so; after steps, both lines are named.
    await page.selectOption('#compare', 'converged');
    await session.waitForStatus((s) => s.compare && s.compare.solver === 'converged', 'the comparison', 30000);
    await page.waitForFunction(() => window.viewer.plotText.includes('energy above the lowest reached (J, log)'));
    await noNonsense(page);
    for (let step = 1; step <= 3; step++) {
      await session.command({ command: 'step' });
      await session.waitForStatus((s) => s.steps === step && !s.busy, `step ${step}`, 30000);
    }
    await page.waitForFunction(() => window.viewer.plotPoints === 3 && window.viewer.state.frameSteps === 3);
    const texts = await page.evaluate(() => window.viewer.plotText);
    for (const text of ['energy above the lowest reached (J, log)', 'time per step (ms)', 'step',
      'assignment (plain-50)', 'converged (L-BFGS)']) {
      assert.ok(texts.includes(text), `${text} in ${JSON.stringify(texts)}`);
    }
    assert.ok(texts.some((t) => /^10[⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+$|^1$/.test(t)), 'a power of ten on the energy axis');
    assert.ok(texts.includes('1') && texts.includes('3'), 'the steps along the bottom');
    await noNonsense(page);
    // Each cloth's label, above it.
    await page.waitForTimeout(300);
    for (const set of [0, 1]) {
      const label = await page.$eval(`#label-${set}`, (e) => ({ text: e.textContent, hidden: e.hidden,
        box: e.getBoundingClientRect().toJSON() }));
      const cloth = await session.projectedBox(set);
      assert.equal(label.hidden, false);
      assert.equal(label.text, ['assignment (plain-50)', 'converged (L-BFGS)'][set]);
      assert.ok(label.box.bottom <= cloth.top + 2, JSON.stringify({ label, cloth }));
      const middle = (label.box.left + label.box.right) / 2;
      assert.ok(middle > cloth.left - label.box.width && middle < cloth.right + label.box.width, JSON.stringify({ label, cloth }));
    }
    // The Aa button: small print and back.
    await page.click('#large');
    assert.equal(await size('#stats'), 12);
    await page.click('#large');
    assert.equal(await size('#stats'), 16);
  });
});

test('a comparison that settles fills at least 35% of a 1024 × 768 projector\'s height, without F', async () => {
  await withViewer(flag, { viewport: { width: 1024, height: 768 } }, async (session) => {
    const { page } = session;
    const facing = await page.evaluate(() => [window.viewer.camera.azimuth, window.viewer.state.scene.azimuth]);
    assert.equal(facing[0], facing[1], 'the first view faces the cloth as the server says');
    await page.selectOption('#compare', 'converged');
    await session.waitForStatus((s) => s.compare && s.compare.solver === 'converged', 'the comparison', 30000);
    const refits = await page.evaluate(() => window.viewer.refits);
    for (let step = 1; step <= 60; step++) {
      await session.command({ command: 'step' });
      await session.waitForStatus((s) => s.steps === step && !s.busy, `step ${step}`, 30000);
    }
    await page.waitForFunction((n) => window.viewer.refits > n && window.viewer.state.frameSteps === 60, refits);
    await page.waitForTimeout(300);
    const heights = [await session.projectedBox(0), await session.projectedBox(1)].map((b) => (b.bottom - b.top) / 768);
    for (const height of heights) assert.ok(height >= 0.35, `heights ${heights.map((h) => h.toFixed(2))} of the window`);
    assert.equal(await page.evaluate(() => window.viewer.fits), 0, 'F was not pressed');
    await page.screenshot({ path: path.join(outputFolder, 'projector.png') });
    // Moved by the user, the camera stays where it is put.
    const area = await page.evaluate(() => window.viewer.framedArea);
    await page.mouse.move(area.left + area.width / 2, area.top + area.height / 2);
    await page.mouse.down();
    await page.mouse.move(area.left + area.width / 2 + 60, area.top + area.height / 2, { steps: 4 });
    await page.mouse.up();
    const moved = await page.evaluate(() => ({ ...window.viewer.camera, target: [...window.viewer.camera.target] }));
    await page.selectOption('#compare', 'accuracy-assignment');
    await session.waitForStatus((s) => s.compare && s.compare.solver === 'accuracy-assignment', 'another', 30000);
    await page.waitForTimeout(500);
    const after = await page.evaluate(() => ({ ...window.viewer.camera, target: [...window.viewer.camera.target] }));
    assert.deepEqual([after.distance, after.azimuth, after.target], [moved.distance, moved.azimuth, moved.target]);
  });
});

test('every number has its unit and says what it is; the fast mode and the mass say what they keep', async () => {
  await withViewer(flag, {}, async (session) => {
    const { page } = session;
    for (let step = 1; step <= 3; step++) await stepWith(session, 'Space', step - 1);
    // Δt to 0.01 s: the time adds each step's own Δt.
    await page.evaluate(() => {
      const slider = document.getElementById('delta_t');
      slider.value = '0.01';
      slider.dispatchEvent(new Event('change'));
    });
    await session.waitForStatus((s) => s.delta_t === 0.01, 'Δt = 0.01 s');
    await stepWith(session, 'Space', 3);
    const s = await stepWith(session, 'Space', 4);
    assert.ok(Math.abs(s.time - (3 / 30 + 0.02)) < 1e-9, `t = ${s.time}`);
    await page.waitForFunction(() => /t 0\.12 s/.test(document.getElementById('stats').textContent));
    const text = await stats(page);
    for (const unit of [/k [0-9.e+]+ N\/m/, /Δt 0\.0100 s/, /energy -?[0-9.e+]+ J/, /[0-9.]+ ms\/step/,
      /[0-9.]+ steps\/s/, /relative gradient [0-9.]+/]) {
      assert.match(text, unit);
    }
    const untitled = await page.$$eval('#stats span', (spans) => spans.filter((e) => !e.title).map((e) => e.textContent));
    assert.deepEqual(untitled, []);
    const gradient = await page.$eval('#stats span[title*="stiff modes"]', (e) => e.textContent);
    assert.match(gradient, /relative gradient/);
    assert.match(await page.$eval('#k-value', (e) => e.textContent), /N\/m$/);
    assert.match(await page.$eval('#delta_t-value', (e) => e.textContent), / s$/);
    // The fast mode: what it keeps, what it does not.
    const fast = await page.$eval('#solver option[value="accuracy-assignment"]', (o) => [o.textContent, o.title]);
    assert.equal(fast[0], 'fast: the assignment\'s energy, not its motion');
    assert.match(fast[1], /no higher than the assignment's .*does not keep: the assignment's animation.*damps less/);
    await page.selectOption('#solver', 'accuracy-assignment');
    await session.waitForStatus((x) => x.solver === 'accuracy-assignment', 'the fast mode', 30000);
    await page.waitForFunction(() => /solve: fast: every step as low in energy as the assignment's, not its motion/
      .test(document.getElementById('stats').textContent));
    // The mass slider: why the sag does not change.
    assert.match(await page.textContent('#mass-hint'), /force on each vertex.*not m·g.*sag.*stays the same/);
    assert.equal(await page.isVisible('#mass-hint'), true);
  });
});

test('reset returns to the scene as it loaded and pauses; restart keeps the settings', async () => {
  await withViewer(flag, {}, async (session) => {
    const { page } = session;
    await page.evaluate(() => {
      const slider = document.getElementById('k');
      slider.value = String(Number(slider.value) - 1);
      slider.dispatchEvent(new Event('change'));
    });
    await session.waitForStatus((s) => Math.abs(s.k - 1e4) < 1e-6, 'k = 1e4');
    await page.keyboard.press('w');
    await page.keyboard.press('a');
    await session.waitForStatus((s) => s.animating && s.wind && s.steps > 2, 'playing in the wind');
    await page.keyboard.press('r');
    const s = await session.waitForStatus((x) => x.k === 1e5 && !x.animating && x.steps === 0 && !x.wind,
      'the scene as it loaded');
    assert.equal(s.delta_t, 1 / 30);
    assert.equal(s.mass_scale, 1);
    await page.waitForFunction(() => document.getElementById('k-value').textContent === '1.0e+5 N/m');
    await page.evaluate(() => {
      const slider = document.getElementById('k');
      slider.value = String(Number(slider.value) - 1);
      slider.dispatchEvent(new Event('change'));
    });
    await session.waitForStatus((x) => Math.abs(x.k - 1e4) < 1e-6, 'k = 1e4 again');
    await stepWith(session, 'Space', 0);
    await page.keyboard.press('Shift+R');
    const restarted = await session.waitForStatus((x) => x.steps === 0, 'the restart');
    assert.ok(Math.abs(restarted.k - 1e4) < 1e-6, 'restart keeps k');
  });
});

/** Do any two of the page's panels overlap? */
async function overlapping(page) {
  const panels = await page.evaluate(() => window.viewer.panels());
  const pairs = [];
  panels.forEach((a, i) => panels.slice(i + 1).forEach((b) => {
    if (a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom) pairs.push([a, b]);
  }));
  return pairs;
}

test('on a phone the panels fold into a drawer and never overlap, the cloth in the free area', async () => {
  await withViewer(flag, { viewport: { width: 390, height: 844 }, touch: true }, async (session) => {
    const { page } = session;
    assert.equal(await page.evaluate(() => document.body.className.includes('narrow')), true);
    assert.deepEqual(await overlapping(page), []);
    assert.equal(await page.isVisible('#plot'), false, 'folded into the drawer');
    for (let step = 1; step <= 20; step++) {
      await session.command({ command: 'step' });
      await session.waitForStatus((s) => s.steps === step && !s.busy, `step ${step}`, 30000);
    }
    await page.waitForFunction(() => window.viewer.state.frameSteps === 20);
    await page.waitForTimeout(500);
    const area = await page.evaluate(() => window.viewer.framedArea);
    const box = await session.projectedBox();
    assert.ok(box.left >= area.left - 1 && box.right <= area.left + area.width + 1
      && box.top >= area.top - 1 && box.bottom <= area.top + area.height + 1, JSON.stringify({ area, box }));
    await page.screenshot({ path: path.join(outputFolder, 'phone.png') });
    await page.tap('#drawer');
    await page.waitForFunction(() => document.body.classList.contains('drawer-open'));
    assert.equal(await page.isVisible('#plot'), true);
    assert.equal(await page.isVisible('#solver'), true);
    assert.deepEqual(await overlapping(page), []);
    await page.tap('#drawer');
    await page.waitForFunction(() => !document.body.classList.contains('drawer-open'));
  });
});

test('a program\'s own frames play beside ours, the distance between them in the plot', async () => {
  const folder = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'masssprings-frames-')), 'frames');
  writeFrames(flag, 12, folder);
  try {
    await withViewer(flag, { flags: ['--frames', folder] }, async (session) => {
      const { page } = session;
      let s = await session.status();
      assert.equal(s.compare.solver, 'frames');
      assert.deepEqual(s.frames, { folder, steps: 12, scene: 'flag' });
      await page.waitForFunction(() => document.getElementById('compare').value === 'frames');
      assert.match(await page.$eval('#compare option[value="frames"]', (o) => o.textContent), /your frames \(12 steps\)/);
      for (let step = 1; step <= 12; step++) s = await stepWith(session, 'Space', step - 1);
      assert.deepEqual(s.compare.history.map((r) => r.distance), new Array(12).fill(0));
      await page.waitForFunction(() => window.viewer.plotText.includes('distance to your frames: 0 m at every step, the same'));
      await page.waitForFunction(() => /distance now 0 m/.test(document.getElementById('stats').textContent));
      assert.equal(await page.$eval('#label-1', (e) => e.textContent), 'your frames');
      s = await stepWith(session, 'Space', 12);
      assert.equal(s.compare.ended, true);
      await page.waitForFunction(() => /your frames end at step 12/.test(document.getElementById('stats').textContent));
    });
  } finally {
    fs.rmSync(path.dirname(folder), { recursive: true, force: true });
  }
});
